"""cocotb testbench of rtl/hfi_adc_scale.v (run by cocotb_tests/test_adc_scale.py, not by pytest).

Reference: golden.fpga.adc_scale.adc_to_current (spec 3.1), channel by channel. The ADC resolution
comes from the ``HFI_ADC_BITS`` environment variable (the runner sets it with the parameter).

Timing checked on every conversion: ``done`` is 1 exactly ``LATENCY`` cycles after ``start``, with both
outputs equal to the golden values, and a monitor of ``done``'s value changes checks that it is high in
exactly those cycles (no spurious, lost or stretched pulses). Inputs are sampled in the start cycle only: the cycle after each start
drives random other inputs. Starts come every 2..9 cycles (2 is the documented minimum spacing), so
conversions overlap in the pipeline.

Inputs are driven at falling edges and outputs read at falling edges (the DUT is posedge-only); idle
stretches are skipped with one Timer each (the clock runs in the simulator).
"""

from __future__ import annotations

import os

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge

from pulse_monitor import cycles, run_pipelined
from golden.fpga.adc_scale import adc_to_current
from golden.testvectors import adc_scale as testvectors

PERIOD_NS = 10
LATENCY = 4             # rtl/hfi_adc_scale.v localparam LATENCY
MIN_SPACING = 2         # minimum start spacing of the RTL (documented in its header)


def _bits() -> int:
    return int(os.environ["HFI_ADC_BITS"])


def _rng():
    seed = int(os.environ["HFI_SEED"])
    cocotb.log.info("HFI_SEED=%d HFI_RANDOM_N=%s ADC_BITS=%d", seed, os.environ["HFI_RANDOM_N"], _bits())
    return np.random.default_rng(seed)


async def _start(dut):
    """Clock, idle inputs, two reset cycles; returns at a falling edge with rst released."""
    Clock(dut.clk, PERIOD_NS, unit="ns").start()
    dut.rst.value = 1
    _drive(dut, 0, (0, 0, 0, 0, 0, 0))
    await FallingEdge(dut.clk)
    await FallingEdge(dut.clk)
    dut.rst.value = 0
    _check_idle(dut, "after reset")
    assert _outputs(dut) == (0, 0), f"outputs after reset: {_outputs(dut)}"


def _drive(dut, start: int, v) -> None:
    code_a, code_b, offset_a, offset_b, gain_a, gain_b = v
    dut.start.value = start
    dut.code_a.value = code_a
    dut.code_b.value = code_b
    dut.offset_a.value = offset_a
    dut.offset_b.value = offset_b
    dut.gain_a.value = gain_a
    dut.gain_b.value = gain_b


def _outputs(dut) -> tuple[int, int]:
    return dut.i_a.value.to_signed(), dut.i_b.value.to_signed()


def _check_idle(dut, what: str) -> None:
    got = int(dut.done.value)
    assert got == 0, f"done = 1 {what}"


def _golden(v, bits: int) -> tuple[int, int]:
    code_a, code_b, offset_a, offset_b, gain_a, gain_b = v
    return adc_to_current(code_a, bits, offset_a, gain_a), adc_to_current(code_b, bits, offset_b, gain_b)


def _check_result(dut, idx, v, bits: int) -> None:
    got_done = int(dut.done.value)
    assert got_done == 1, f"vector {idx} {v}: done = 0 {LATENCY} cycles after start"
    got = _outputs(dut)
    exp = _golden(v, bits)
    assert got == exp, (f"vector {idx}: (code_a, code_b, offset_a, offset_b, gain_a, gain_b) = {v}, "
                        f"ADC_BITS={bits}: RTL (i_a, i_b) = {got}, golden {exp}")


async def run_vectors(dut, vectors, spacings, garbage, label: str) -> None:
    """Start one conversion per vector (vector k at cycle sum(spacings[:k])), check every result and
    its timing (``done`` high exactly in the start cycles + LATENCY); ``garbage[k]`` is driven in
    the cycle after start k (start = 0). Starts at the current falling edge, ends at one."""
    bits = _bits()
    await run_pipelined(dut, vectors, spacings, garbage, label, LATENCY, lambda start, v: _drive(dut, start, v),
                        lambda k, idx, v: _check_result(dut, idx, v, bits))


def _rows(arr) -> list[tuple]:
    """Vectors of golden.testvectors.adc_scale (an (n, 6) array) as tuples of Python ints."""
    return [tuple(r) for r in arr.tolist()]


@cocotb.test()
async def random_vectors(dut):
    """HFI_RANDOM_N random conversions, overlapping, each compared with the golden model."""
    rng = _rng()
    bits = _bits()
    assert len(dut.code_a) == bits, f"ADC_BITS parameter not applied: {len(dut.code_a)} != {bits}"
    n = int(os.environ["HFI_RANDOM_N"])
    vectors = _rows(testvectors.random_vectors(rng, n, bits))
    garbage = _rows(testvectors.random_vectors(rng, n, bits))
    spacing = rng.integers(MIN_SPACING, 10, n)
    spacing[rng.random(n) < 0.5] = MIN_SPACING          # many back-to-back starts
    await _start(dut)
    await run_vectors(dut, vectors, spacing, garbage, "random")
    exp = [_golden(v, bits) for v in vectors]
    sat = sum(abs(x) >= 32767 for e in exp for x in e)
    cocotb.log.info("%d conversions, %d saturated or full-scale outputs", n, sat)


@cocotb.test()
async def directed(dut):
    """Full-scale codes, extreme offsets and gains, saturation, reset mid-conversion, timing."""
    bits = _bits()
    top = (1 << bits) - 1
    await _start(dut)
    vectors = _rows(testvectors.directed_vectors(bits))
    zero = (0, 0, 0, 0, 0, 0)
    for spacing in (MIN_SPACING, LATENCY + 3):          # back to back and one at a time
        await run_vectors(dut, vectors, [spacing] * len(vectors), [zero] * len(vectors),
                          f"directed (spacing {spacing})")
    sats = [e for v in vectors for e in _golden(v, bits) if e in (-32768, 32767)]
    assert sats, "the directed vectors never saturate"

    # Outputs are held after done, whatever the inputs do.
    full = (top, 0, -32768, 32767, 65535, 65535)
    exp = _golden(full, bits)
    _drive(dut, 1, full)
    await cycles(1)
    _drive(dut, 0, zero)
    await cycles(LATENCY + 10)
    assert _outputs(dut) == exp, f"outputs not held: {_outputs(dut)}, golden {exp}"

    # Reset in every cycle of a conversion in flight: no done, outputs cleared, then a clean restart.
    for rst_at in range(1, LATENCY):                    # rst sampled at the end of cycle S + rst_at
        _drive(dut, 1, full)
        await cycles(1)
        _drive(dut, 0, zero)
        if rst_at > 1:
            await cycles(rst_at - 1)
        dut.rst.value = 1
        await cycles(1)
        dut.rst.value = 0
        assert _outputs(dut) == (0, 0), f"reset {rst_at} cycles after start: outputs {_outputs(dut)}"
        for _ in range(LATENCY + 2):
            _check_idle(dut, f"after a reset {rst_at} cycles after start")
            await cycles(1)
        probe = (top // 3, top, 123, -45, 20000, 1000)
        await run_vectors(dut, [probe], [1], [full], f"restart after reset at {rst_at}")
        # Restore a non-zero output for the next reset.
        _drive(dut, 1, full)
        await cycles(1)
        _drive(dut, 0, zero)
        await cycles(LATENCY + 2)

    # A start during reset is ignored.
    dut.rst.value = 1
    _drive(dut, 1, full)
    await cycles(1)
    dut.rst.value = 0
    _drive(dut, 0, zero)
    for _ in range(LATENCY + 2):
        _check_idle(dut, "after a start during reset")
        await cycles(1)
