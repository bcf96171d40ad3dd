"""cocotb testbench for smoke_counter.v (run by cocotb_tests/test_smoke_toolchain.py, not by pytest).

The runner passes the expected counter width in SMOKE_WIDTH so the parameter override is checked too.
"""

import os
import random

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, FallingEdge


async def _reset(dut):
    Clock(dut.clk, 10, unit="ns").start()
    dut.rst.value = 1
    dut.en.value = 0
    await ClockCycles(dut.clk, 2, rising=True)
    await FallingEdge(dut.clk)
    assert dut.count.value.to_unsigned() == 0, f"count after reset: {dut.count.value}"
    dut.rst.value = 0


@cocotb.test()
async def counts_exactly(dut):
    """37 enabled cycles -> 37; 5 disabled cycles hold it; a sync reset clears it in one cycle."""
    width = int(os.environ["SMOKE_WIDTH"])
    assert len(dut.count) == width, f"WIDTH parameter not applied: {len(dut.count)} != {width}"
    await _reset(dut)

    dut.en.value = 1
    await ClockCycles(dut.clk, 37, rising=False)  # 37 rising edges with en=1, then sample at falling
    assert dut.count.value.to_unsigned() == 37

    dut.en.value = 0
    await ClockCycles(dut.clk, 5, rising=False)
    assert dut.count.value.to_unsigned() == 37

    dut.rst.value = 1
    dut.en.value = 1  # reset wins over enable
    await FallingEdge(dut.clk)
    assert dut.count.value.to_unsigned() == 0


@cocotb.test()
async def matches_model_with_wraparound(dut):
    """300 cycles of random en/rst against a Python model, including wrap-around at 2**WIDTH."""
    width = len(dut.count)
    rng = random.Random(1234)
    await _reset(dut)
    model = 0
    wraps = 0
    for cycle in range(300):
        en = int(rng.random() < 0.9)
        rst = int(rng.random() < 0.01)
        dut.en.value = en
        dut.rst.value = rst
        await FallingEdge(dut.clk)
        if rst:
            model = 0
        elif en:
            model = (model + 1) % (1 << width)
            wraps += model == 0
        got = dut.count.value.to_unsigned()
        assert got == model, f"cycle {cycle}: count={got}, expected {model}"
    assert wraps >= 1, "the test never exercised wrap-around"
