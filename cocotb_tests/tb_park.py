"""cocotb testbench of rtl/hfi_park.v (run by cocotb_tests/test_park.py, not by pytest).

Reference: golden.fpga.park.clarke then golden.fpga.park.park (spec 3.2).

Timing checked on every transform: ``done`` is 1 exactly ``LATENCY`` cycles after ``start``, with
``i_d``, ``i_q`` and the Clarke outputs ``i_alpha``, ``i_beta`` equal to the golden values (``i_alpha`` where
the next start is at least ``LATENCY`` cycles later: it is held until the next start), and a monitor of ``done``'s value changes checks that it is
high in exactly those cycles (no spurious, lost or stretched pulses). Inputs are sampled in the start cycle only: the cycle after each start
drives random other inputs (a register change right after the sample). Starts come every 5..12 cycles
(5 is the documented minimum spacing), so transforms overlap in the pipeline.

Inputs are driven and outputs read at falling edges (the DUT is posedge-only); idle stretches are
skipped with one Timer each (the clock runs in the simulator).
"""

from __future__ import annotations

import os

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge

from pulse_monitor import cycles, run_pipelined, seeded_rng
from golden.fpga.park import clarke, park
from golden.testvectors import park as testvectors

PERIOD_NS = 10
LATENCY = 7             # rtl/hfi_park.v localparam LATENCY
MIN_SPACING = 5         # minimum start spacing of the RTL (documented in its header)


def _drive(dut, start: int, v) -> None:
    i_a, i_b, s, c = v
    dut.start.value = start
    dut.i_a.value = i_a
    dut.i_b.value = i_b
    dut.sin_q15.value = s
    dut.cos_q15.value = c


def _outputs(dut) -> tuple[int, int]:
    return dut.i_d.value.to_signed(), dut.i_q.value.to_signed()


def _golden(v) -> tuple[int, int]:
    i_a, i_b, s, c = v
    i_alpha, i_beta = clarke(i_a, i_b)
    return park(i_alpha, i_beta, s, c)


def _check_idle(dut, what: str) -> None:
    assert int(dut.done.value) == 0, f"done = 1 {what}"


def _check_result(dut, idx, v, alpha_held: bool) -> None:
    """The done cycle of transform ``idx``: done, i_d and i_q, and the Clarke currents of the same transform
    (i_beta always; i_alpha only if no start came within LATENCY cycles after this one's: the RTL header's
    'held until the next start')."""
    assert int(dut.done.value) == 1, f"vector {idx} {v}: done = 0 {LATENCY} cycles after start"
    got = _outputs(dut)
    exp = _golden(v)
    assert got == exp, (f"vector {idx}: (i_a, i_b, sin_q15, cos_q15) = {v}: RTL (i_d, i_q) = {got}, "
                        f"golden {exp}")
    i_alpha, i_beta = clarke(v[0], v[1])
    got_ab = dut.i_alpha.value.to_signed(), dut.i_beta.value.to_signed()
    assert got_ab[1] == i_beta and (not alpha_held or got_ab[0] == i_alpha), (
        f"vector {idx}: (i_a, i_b) = {v[:2]}: RTL (i_alpha, i_beta) = {got_ab}, golden {(i_alpha, i_beta)}")


async def _start(dut):
    """Clock, idle inputs, two reset cycles; returns at a falling edge with rst released."""
    Clock(dut.clk, PERIOD_NS, unit="ns").start()
    dut.rst.value = 1
    _drive(dut, 0, (0, 0, 0, 0))
    await FallingEdge(dut.clk)
    await FallingEdge(dut.clk)
    dut.rst.value = 0
    _check_idle(dut, "after reset")
    assert _outputs(dut) == (0, 0), f"outputs after reset: {_outputs(dut)}"


async def run_vectors(dut, vectors, spacings, garbage, label: str) -> None:
    """Start one transform per vector (vector k at cycle sum(spacings[:k])), check every result and
    its timing (``done`` high exactly in the start cycles + LATENCY); ``garbage[k]`` is driven in
    the cycle after start k (start = 0). Starts at the current falling edge, ends at one."""
    held = [k == len(vectors) - 1 or spacings[k] >= LATENCY for k in range(len(vectors))]
    await run_pipelined(dut, vectors, spacings, garbage, label, LATENCY, lambda start, v: _drive(dut, start, v),
                        lambda k, idx, v: _check_result(dut, idx, v, held[k]))


def _rows(arr) -> list[tuple]:
    """Vectors of golden.testvectors.park (an (n, 4) array) as tuples of Python ints."""
    return [tuple(r) for r in arr.tolist()]


@cocotb.test()
async def random_vectors(dut):
    """HFI_RANDOM_N random transforms, overlapping, each compared with the golden model."""
    rng = seeded_rng()
    n = int(os.environ["HFI_RANDOM_N"])
    vectors = _rows(testvectors.random_vectors(rng, n))
    garbage = _rows(testvectors.random_vectors(rng, n))
    spacing = rng.integers(MIN_SPACING, 13, n)
    spacing[rng.random(n) < 0.5] = MIN_SPACING          # many back-to-back starts
    await _start(dut)
    await run_vectors(dut, vectors, spacing, garbage, "random")
    exp = [_golden(v) for v in vectors]
    sat = sum(abs(x) >= 32767 for e in exp for x in e)
    cocotb.log.info("%d transforms, %d saturated or full-scale outputs", n, sat)


@cocotb.test()
async def directed(dut):
    """Extremes of every input (saturating i_beta, i_d and i_q; sums at 2^31), timing, held outputs,
    reset in every cycle of a transform in flight."""
    await _start(dut)
    vectors = _rows(testvectors.directed_vectors())
    zero = (0, 0, 0, 0)
    for spacing in (MIN_SPACING, LATENCY + 3):
        await run_vectors(dut, vectors, [spacing] * len(vectors), [zero] * len(vectors),
                          f"directed (spacing {spacing})")
    results = [e for v in vectors for e in _golden(v)]
    assert -32768 in results and 32767 in results, "the directed vectors never saturate"

    # Outputs are held after done, whatever the inputs do.
    full = (-32768, -32768, -32768, -32768)
    other = (1234, -4321, 30000, -20000)
    exp = _golden(full)
    _drive(dut, 1, full)
    await cycles(1)
    _drive(dut, 0, other)
    await cycles(LATENCY + 10)
    assert _outputs(dut) == exp, f"outputs not held: {_outputs(dut)}, golden {exp}"

    # Reset in every cycle of a transform in flight: no done, outputs cleared, then a clean restart.
    for rst_at in range(1, LATENCY):                    # rst sampled at the end of cycle S + rst_at
        _drive(dut, 1, full)
        await cycles(1)
        _drive(dut, 0, other)
        if rst_at > 1:
            await cycles(rst_at - 1)
        dut.rst.value = 1
        await cycles(1)
        dut.rst.value = 0
        assert _outputs(dut) == (0, 0), f"reset {rst_at} cycles after start: outputs {_outputs(dut)}"
        for _ in range(LATENCY + 2):
            _check_idle(dut, f"after a reset {rst_at} cycles after start")
            await cycles(1)
        await run_vectors(dut, [other], [1], [full], f"restart after reset at {rst_at}")

    # A start during reset is ignored.
    dut.rst.value = 1
    _drive(dut, 1, full)
    await cycles(1)
    dut.rst.value = 0
    _drive(dut, 0, zero)
    for _ in range(LATENCY + 2):
        _check_idle(dut, "after a start during reset")
        await cycles(1)
