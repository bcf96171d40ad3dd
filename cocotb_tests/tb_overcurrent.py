"""cocotb testbench of rtl/hfi_overcurrent.v (run by cocotb_tests/test_overcurrent.py, not by pytest).

Reference: :func:`overcurrent_ref`, spec 3.7 written as a pure function (there is no golden module):
a valid sample trips if ``|i_a|``, ``|i_b|`` or ``|i_c|`` exceeds ``OC_LIMIT`` (u16), with
``i_c = -i_a - i_b`` formed exactly. ``trip`` is a one-cycle pulse in the cycle after the sample.

Inputs are driven at falling edges, outputs read at falling edges (the DUT is posedge-only).
"""

from __future__ import annotations

import os

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, Timer
from pulse_monitor import seeded_rng

PERIOD_NS = 10


def overcurrent_ref(i_a: int, i_b: int, limit: int) -> bool:
    """Spec 3.7: ``|i_a| > limit or |i_b| > limit or |i_c| > limit`` with ``i_c = -i_a - i_b`` (exact)."""
    i_c = -i_a - i_b
    return abs(i_a) > limit or abs(i_b) > limit or abs(i_c) > limit


async def _start(dut):
    """Clock, idle inputs, two reset cycles; returns at a falling edge with rst released."""
    Clock(dut.clk, PERIOD_NS, unit="ns").start()
    dut.rst.value = 1
    dut.valid.value = 0
    dut.i_a.value = 0
    dut.i_b.value = 0
    dut.limit.value = 0x7FFF
    await FallingEdge(dut.clk)
    await FallingEdge(dut.clk)
    assert int(dut.trip.value) == 0, "trip not cleared by reset"
    dut.rst.value = 0


def _random_vectors(rng, n: int):
    """(valid, i_a, i_b, limit) arrays: full-range currents and limits, limits near the currents'
    magnitudes (both sides of every compare), extremes (-32768, 32767, i_c = 65536) and small values."""
    kind = rng.integers(0, 5, n)
    i_a = rng.integers(-32768, 32768, n)
    i_b = rng.integers(-32768, 32768, n)
    small = kind == 1                                   # small currents, small limits
    i_a[small] = rng.integers(-40, 41, small.sum())
    i_b[small] = rng.integers(-40, 41, small.sum())
    ext = kind == 2                                     # extreme currents
    choices = np.array([-32768, -32767, -1, 0, 1, 32766, 32767])
    i_a[ext] = rng.choice(choices, ext.sum())
    i_b[ext] = rng.choice(choices, ext.sum())
    mag = np.maximum(np.maximum(np.abs(i_a), np.abs(i_b)), np.abs(i_a + i_b))
    limit = rng.integers(0, 65536, n)                   # kind 0: uniform u16 limit
    near = kind >= 1                                    # limit = largest magnitude + {-2..1}
    limit[near] = np.clip(mag[near] + rng.integers(-2, 2, near.sum()), 0, 65535)
    big = kind == 4                                     # limit >= 32768: only i_c can trip
    limit[big] = rng.integers(32768, 65536, big.sum())
    i_a[big & (rng.random(n) < 0.5)] = -32768
    valid = (rng.random(n) < 0.8).astype(np.int64)
    return valid, i_a, i_b, limit


@cocotb.test()
async def random_vectors(dut):
    """HFI_RANDOM_N random samples, one per cycle, each trip compared with the reference."""
    rng = seeded_rng()
    n = int(os.environ["HFI_RANDOM_N"])
    valid, i_a, i_b, limit = (a.tolist() for a in _random_vectors(rng, n))
    await _start(dut)
    trips = 0
    prev = None
    step = Timer(PERIOD_NS, unit="ns")
    for k in range(n + 1):
        if k < n:
            dut.valid.value = valid[k]
            dut.i_a.value = i_a[k]
            dut.i_b.value = i_b[k]
            dut.limit.value = limit[k]
        else:
            dut.valid.value = 0
        if prev is not None:
            got = int(dut.trip.value)
            exp = int(valid[prev] and overcurrent_ref(i_a[prev], i_b[prev], limit[prev]))
            trips += exp
            assert got == exp, (f"vector {prev}: valid={valid[prev]} i_a={i_a[prev]} i_b={i_b[prev]} "
                                f"limit={limit[prev]}: RTL trip={got}, reference {exp}")
        prev = k
        await step
    got = int(dut.trip.value)
    assert got == 0, f"trip={got} one cycle after the last vector (valid=0)"
    cocotb.log.info("%d vectors, %d trips", n, trips)
    assert 0.1 * n < trips < 0.9 * n or n < 100, f"unbalanced vectors: {trips} trips of {n}"


@cocotb.test()
async def directed(dut):
    """Corner cases: full scale, -32768, i_c = 65536 and -65534, limits 0 / 32767 / >= 32768 / 65535,
    valid = 0 never trips, pulse length, reset."""
    await _start(dut)
    cases = [
        # (i_a, i_b, limit, expected)
        (0, 0, 0, 0), (1, -1, 0, 1), (0, 0, 65535, 0),
        (-32768, 0, 32767, 1),                  # |i_a| = 32768 > any limit < 32768
        (0, -32768, 32767, 1),
        (16384, 16384, 32767, 1),               # i_c = -32768
        (16384, 16383, 32767, 0),               # i_c = -32767
        (32767, 0, 32767, 0), (32767, 0, 32766, 1), (0, 32767, 32766, 1),
        (-32768, -32768, 65535, 1),             # i_c = 65536 > 65535
        (-32768, -32768, 32768, 1), (-32768, 0, 32768, 0),
        (32767, 32767, 65535, 0), (32767, 32767, 65534, 0),   # i_c = -65534
        (32767, 32767, 65533, 1),
        (-32768, -32767, 65535, 0), (-32768, -32767, 65534, 1),  # i_c = 65535
        (100, -300, 200, 1), (100, -300, 300, 0), (100, -200, 200, 0), (-100, 300, 299, 1),
        (150, 150, 299, 1), (150, 150, 300, 0),            # only i_c = -300 can trip
        (20000, 20000, 39999, 1), (20000, 20000, 40000, 0),
    ]
    for idx, (a, b, lim, exp) in enumerate(cases):
        assert int(overcurrent_ref(a, b, lim)) == exp, f"directed case {idx}: reference disagrees"
        for valid in (1, 0):
            dut.valid.value = valid
            dut.i_a.value = a
            dut.i_b.value = b
            dut.limit.value = lim
            await FallingEdge(dut.clk)
            got = int(dut.trip.value)
            assert got == exp * valid, (f"directed case {idx}: valid={valid} i_a={a} i_b={b} limit={lim}: "
                                        f"RTL trip={got}, reference {exp * valid}")
    # Consecutive tripping samples: one pulse per sample; it ends the cycle after the last one.
    dut.i_a.value = -32768
    dut.i_b.value = 0
    dut.limit.value = 0
    dut.valid.value = 1
    for _ in range(3):
        await FallingEdge(dut.clk)
        assert int(dut.trip.value) == 1, "trip missing during consecutive tripping samples"
    dut.valid.value = 0
    await FallingEdge(dut.clk)
    assert int(dut.trip.value) == 0, "trip held after the last tripping sample"
    # Reset wins over a tripping sample.
    dut.valid.value = 1
    dut.rst.value = 1
    await FallingEdge(dut.clk)
    assert int(dut.trip.value) == 0, "trip during reset"
    dut.rst.value = 0
    await FallingEdge(dut.clk)
    assert int(dut.trip.value) == 1, "no trip after reset release"
    dut.valid.value = 0
    await FallingEdge(dut.clk)
    assert int(dut.trip.value) == 0
