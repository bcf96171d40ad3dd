"""cocotb testbench of rtl/hfi_deadtime_comp.v (run by cocotb_tests/test_deadtime_comp.py).

Every result is compared with ``compensate(...)`` of golden/fpga/deadtime_comp.py for one compare set.
Random vectors: ``numpy.random.default_rng(HFI_SEED)``, ``HFI_RANDOM_N`` of them, from
golden/testvectors/deadtime_comp.py (shared with tests/test_hls_deadtime_comp.py): the modulator's
register draws (full ranges and extremes, DTC_GAIN = 0 for half, RECIP_H nominal mostly
and any u32 sometimes) with a random sign and random compares in 0..H (extremes 0, 1, H/2, H-1, H
included). The module runs back to back (a start in the done cycle); the registers that are sampled
(compares, sign) change right after every start, and the held ones change (to the next vector's
values) in the done cycle, when the module no longer reads them (``chain`` = 0). Directed: the chained
start (``chain`` = 1: the second set, sign -1, starts by itself in the done cycle, as hfi_modulator uses it), extremes, leg a's predicted
current placed exactly around the RTL's saturation bound (+-2^23, +-2^24), start while busy, reset in
mid-operation.
"""

from __future__ import annotations

import os

import numpy as np

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles

from golden.fixed import round_shr
from golden.fpga.deadtime_comp import compensate, phase_current
from golden.testvectors.deadtime_comp import HELD, SAMPLED, corner_vectors, draw, saturation_vectors
from tb_modulator import CLOCK_NS, cycles, seed_and_count

LATENCY = 39
"""hfi_deadtime_comp: start in cycle 0, done and the results in cycle LATENCY (its header)."""

OUTS = ("cmp_a", "cmp_b", "cmp_c")


def golden(r: dict) -> tuple[int, int, int]:
    sign = 1 if r["sign_top"] else -1
    return tuple(int(c) for c in compensate((r["cmp_a_in"], r["cmp_b_in"], r["cmp_c_in"]), sign, r["half"],
                                            r["dead"], r["gain"], r["i_d_ref"], r["i_q_ref"], r["hf_amp"],
                                            r["sin_q15"], r["cos_q15"], r["recip_h"]))


def fmt(r: dict) -> str:
    return "{" + ", ".join(f"{k}={r[k]}" for k in HELD + SAMPLED) + "}"


def apply(dut, r: dict, names):
    for k in names:
        getattr(dut, k).value = r[k]


def check(dut, expected, what: str, r: dict):
    got = tuple(getattr(dut, k).value.to_unsigned() for k in OUTS)
    if got != expected:
        diff = ", ".join(f"{k}: RTL {g} golden {e}" for k, g, e in zip(OUTS, got, expected) if g != e)
        raise AssertionError(f"{what}: {diff}; inputs {fmt(r)}")


async def clock_and_reset(dut):
    Clock(dut.clk, CLOCK_NS, unit="ns").start()
    dut.start.value = 0
    dut.chain.value = 0
    for k in HELD + SAMPLED:
        getattr(dut, k).value = 0
    dut.half.value = 1000
    dut.rst.value = 1
    await ClockCycles(dut.clk, 3, rising=False)      # from here on, every action at a falling edge
    dut.rst.value = 0


async def run_vectors(dut, vecs, label, busy_start_at=None):
    """Back to back; `busy_start_at` (cycle) adds a start pulse while busy to every vector."""
    apply(dut, vecs[0], HELD + SAMPLED)
    dut.start.value = 1
    for i, r in enumerate(vecs):
        expected = golden(r)
        await cycles(1)                                  # cycle 1
        dut.start.value = 0
        nxt = vecs[i + 1] if i + 1 < len(vecs) else None
        if nxt is not None:
            apply(dut, nxt, SAMPLED)                     # sampled inputs: already taken
        t = 1
        if busy_start_at is not None:
            await cycles(busy_start_at - t)
            dut.start.value = 1                          # ignored: busy
            await cycles(1)
            dut.start.value = 0
            t = busy_start_at + 1
        await cycles(LATENCY - 1 - t)
        if int(dut.done.value) != 0 or int(dut.busy.value) != 1:
            raise AssertionError(f"{label} {i}: cycle {LATENCY - 1}: done={dut.done.value} busy={dut.busy.value}")
        await cycles(1)                                  # cycle LATENCY
        if int(dut.done.value) != 1 or int(dut.busy.value) != 0:
            raise AssertionError(f"{label} {i}: cycle {LATENCY}: done={dut.done.value} busy={dut.busy.value}")
        check(dut, expected, f"{label} {i}", r)
        if nxt is not None:
            apply(dut, nxt, HELD)
            dut.start.value = 1


@cocotb.test()
async def random_vectors(dut):
    """HFI_RANDOM_N random compare sets, back to back, against compensate()."""
    seed, count = seed_and_count()
    rng = np.random.default_rng(seed)
    vecs = draw(rng, count)
    await clock_and_reset(dut)
    await run_vectors(dut, vecs, "random vector")


@cocotb.test()
async def corner_cases(dut):
    """Extremes: compares 0 / H, full-scale currents and angles, RECIP_H 0 / 2^32-1, D 1 / 65535, gain
    1 / 65535, both signs; and DTC_GAIN = 0 (identity)."""
    vecs = corner_vectors(np.random.default_rng(int(os.environ["HFI_SEED"]) + 3))
    await clock_and_reset(dut)
    await run_vectors(dut, vecs, "corner vector")


@cocotb.test()
async def saturation_boundary(dut):
    """i_x around the saturation bound of the RTL (see saturation_vectors)."""
    vecs = saturation_vectors()
    exact = sum(1 for r in vecs if abs(phase_current(0, r["i_d_ref"] - round_shr(
        r["hf_amp"] * (2 * r["cmp_a_in"] - r["half"]) * r["recip_h"], 32), 0, 0, 32767)) in
        (2**23 - 1, 2**23, 2**24 - 1, 2**24))
    assert exact >= 8, f"saturation vectors missed their targets ({exact})"
    await clock_and_reset(dut)
    await run_vectors(dut, vecs, "saturation vector")


@cocotb.test()
async def start_while_busy(dut):
    """A start pulse in any busy cycle is ignored (the result and the timing are those of the first)."""
    rng = np.random.default_rng(int(os.environ["HFI_SEED"]) + 4)
    await clock_and_reset(dut)
    for k in (1, 2, 17, LATENCY - 2):
        await run_vectors(dut, draw(rng, 3), f"start in busy cycle {k}, vector", busy_start_at=k)
        await cycles(1)


@cocotb.test()
async def reset_mid_operation(dut):
    """A reset while busy abandons the computation (no done); the next start computes correctly."""
    rng = np.random.default_rng(int(os.environ["HFI_SEED"]) + 5)
    await clock_and_reset(dut)
    for k in (1, 5, 20, 34, LATENCY - 1):
        vecs = draw(rng, 2)
        apply(dut, vecs[0], HELD + SAMPLED)
        dut.start.value = 1
        await cycles(1)
        dut.start.value = 0
        await cycles(k - 1)
        dut.rst.value = 1
        await cycles(1)
        dut.rst.value = 0
        for cyc in range(LATENCY + 2):
            assert int(dut.done.value) == 0 and int(dut.busy.value) == 0, f"done/busy {cyc} cycles after reset"
            await cycles(1)
        await run_vectors(dut, vecs[1:], f"vector after reset in cycle {k}")


@cocotb.test()
async def chained_start(dut):
    """chain = 1 with a start: in its done cycle the unit starts again by itself with sign -1 and the compares
    present in that cycle (the held inputs unchanged), done LATENCY cycles later; then it stays idle. Each
    result against compensate()."""
    rng = np.random.default_rng(int(os.environ["HFI_SEED"]) + 6)
    await clock_and_reset(dut)
    for i in range(20):
        first = dict(draw(rng, 1)[0], sign_top=1)
        second = dict(first, sign_top=0, **{k: int(rng.integers(0, first["half"] + 1))      # in 0..H
                                            for k in ("cmp_a_in", "cmp_b_in", "cmp_c_in")})
        apply(dut, first, HELD + SAMPLED)
        dut.chain.value = 1
        dut.start.value = 1
        await cycles(1)
        dut.start.value = 0
        dut.chain.value = int(rng.integers(0, 2))             # sampled with the start only
        dut.sign_top.value = int(rng.integers(0, 2))          # the chained start takes sign -1 whatever this is
        await cycles(LATENCY - 2)
        apply(dut, second, ("cmp_a_in", "cmp_b_in", "cmp_c_in"))   # present in the done cycle
        await cycles(1)
        assert int(dut.done.value) == 1, f"chain {i}: no done in cycle {LATENCY}"
        check(dut, golden(first), f"chain {i}, first set", first)
        await cycles(LATENCY)
        assert int(dut.done.value) == 1, f"chain {i}: the chained set is not done {LATENCY} cycles later"
        check(dut, golden(second), f"chain {i}, chained set", second)
        for _ in range(LATENCY + 2):
            await cycles(1)
            assert int(dut.done.value) == 0 and int(dut.busy.value) == 0, f"chain {i}: a third start"
