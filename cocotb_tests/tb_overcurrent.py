"""cocotb testbench of rtl/hfi_overcurrent.v (run by cocotb_tests/test_overcurrent.py, not by pytest).

Reference: golden.fpga.overcurrent.over_limit (spec 3.7): a valid sample trips if ``|i_a|``, ``|i_b|`` or
``|i_c|`` exceeds ``OC_LIMIT`` (u16), with ``i_c = -i_a - i_b`` formed exactly. ``trip`` is a one-cycle pulse in
the cycle after the sample. Vectors: golden.testvectors.overcurrent (shared with the HLS kernel's test).

Inputs are driven at falling edges, outputs read at falling edges (the DUT is posedge-only).
"""

from __future__ import annotations

import os

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, Timer
from pulse_monitor import seeded_rng

from golden.fpga.overcurrent import over_limit
from golden.testvectors import overcurrent as vectors

PERIOD_NS = 10


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


@cocotb.test()
async def random_vectors(dut):
    """HFI_RANDOM_N random samples, one per cycle, each trip compared with the reference."""
    rng = seeded_rng()
    n = int(os.environ["HFI_RANDOM_N"])
    valid, i_a, i_b, limit = vectors.random_vectors(rng, n)
    expected = (valid.astype(bool) & over_limit(i_a, i_b, limit)).astype(int).tolist()
    valid, i_a, i_b, limit = (a.tolist() for a in (valid, i_a, i_b, limit))
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
            exp = expected[prev]
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
    for idx, (a, b, lim, exp) in enumerate(vectors.DIRECTED):
        assert int(over_limit(np.int64(a), np.int64(b), lim)) == exp, f"directed case {idx}: golden disagrees"
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
