"""cocotb testbench of rtl/hfi_cordic.v against golden/fpga/cordic.py (run by test_cordic.py, not by pytest).

Environment (set by test_cordic.py through hdl_runner.run_cocotb): ``HFI_SEED``, ``HFI_RANDOM_N``,
``HFI_CORDIC_WIDTH``, ``HFI_CORDIC_ITERATIONS`` (the parameters the DUT was built with) and, for the
Verilator sweep, ``HFI_CORDIC_INSTANCE``: the toplevel is then the wrapper ``hfi_cordic_sweep`` (all
sweep points on shared clk/rst/start/angle inputs) and the outputs are read from that instance.

Timing of the bench: inputs are written and outputs read 1 ns after each falling clock edge ("sample
point" of a cycle), never at an edge, so the C clock (``impl="gpi"``) and plain ``Timer`` waits are
race-free and the simulator runs the cycles between two checks without Python. A start written at
the sample point of cycle ``t`` is taken by the rising edge that ends cycle ``t``; ``done`` must be
read as 1 at the sample point of cycle ``t + LATENCY`` (LATENCY = ITERATIONS + 2) and 0 one cycle
before. Every result is compared with the golden model (``sincos_q15``, ``demod_weight``).
"""

from __future__ import annotations

import os

import cocotb
import numpy as np

from golden.fpga.cordic import cw_angle_step, demod_weight, sincos_q15
from golden.testvectors import cordic as testvectors
from golden.testvectors.cordic import U32, Q
from unit_bench import UnitBench

PERIOD_NS = 10


class Bench(UnitBench):
    """Clock, reset and the start/done protocol of one hfi_cordic instance."""

    def __init__(self, dut):
        name = os.environ.get("HFI_CORDIC_INSTANCE")
        self.inst = getattr(dut, name) if name else dut  # the hfi_cordic under test: outputs
        self.width = int(os.environ["HFI_CORDIC_WIDTH"])
        self.iterations = int(os.environ["HFI_CORDIC_ITERATIONS"])
        self.latency = self.iterations + 2
        # dut: the toplevel (clk, rst, start, angle)
        super().__init__(dut, PERIOD_NS, self.inst,
                         f"WIDTH={self.width} ITERATIONS={self.iterations} LATENCY={self.latency}")

    async def setup(self) -> None:
        dut = self.dut
        assert len(self.inst.sin_q15) == 16 and len(self.inst.cos_q15) == 16 and len(dut.angle) == 32
        def idle():
            dut.start.value = 0
            dut.angle.value = 0

        await self.power_up(idle)
        self.expect_outputs(0, 0, "after reset (reset value of sin_q15, cos_q15)")

    # ---- observations --------------------------------------------------------------------------------
    def outputs(self) -> tuple[int, int]:
        return self.inst.sin_q15.value.to_signed(), self.inst.cos_q15.value.to_signed()

    def expect_outputs(self, sin: int, cos: int, what: str) -> None:
        got = self.outputs()
        assert got == (sin, cos), f"cycle {self.cycle}, {what}: (sin_q15, cos_q15) = RTL {got}, golden {(sin, cos)}"

    # ---- one computation with a full cycle-by-cycle protocol check -----------------------------------
    async def one_checked(self, angle: int, label: str) -> tuple[int, int]:
        """Start ``angle`` now (start was low), check busy/done in every cycle; returns the result."""
        dut = self.dut
        prev = self.outputs()
        dut.angle.value = angle
        dut.start.value = 1
        self.expect_flags(0, 0, f"{label}: start cycle")
        await self.cycles(1)
        dut.start.value = 0
        dut.angle.value = angle ^ 0xDEADBEEF  # the angle is sampled in the start cycle only
        for k in range(1, self.latency):
            self.expect_flags(1, 0, f"{label}: {k} cycles after start")
            self.expect_outputs(*prev, f"{label}: outputs held while busy, {k} cycles after start")
            await self.cycles(1)
        self.expect_flags(0, 1, f"{label}: done cycle = start + LATENCY ({self.latency})")
        result = self.outputs()
        await self.cycles(1)
        self.expect_idle(f"{label}: cycle after done (done is a one-cycle pulse)")
        self.expect_outputs(*result, f"{label}: outputs held after done")
        return result

    # ---- a stream of computations (random protocol: back to back, gaps, start held while busy) -------
    async def stream(self, angles, exp_sin, exp_cos, label: str) -> None:
        """Run every angle; compare each result with the golden (exp_sin[k], exp_cos[k]).

        Per vector, at random: the start in the done cycle of the previous one (back to back) or
        1..3 idle cycles later; start held high with a garbage angle while busy (must be ignored).
        Checks busy/done one cycle after the start, one cycle before done and in the done cycle, and
        that the previous outputs are held until the done cycle.
        """
        dut = self.dut
        n = len(angles)
        angles = [int(a) for a in angles]
        exp_sin = [int(v) for v in exp_sin]
        exp_cos = [int(v) for v in exp_cos]
        gaps = self.rng.choice(np.array([0, 0, 0, 0, 0, 1, 1, 2, 3]), size=n).tolist()
        hold = (self.rng.random(n) < 0.5).tolist()
        garbage = self.rng.integers(0, U32, size=n, dtype=np.int64).tolist()
        mid = self.latency - 2  # cycles from start + 1 to done - 1 (>= 1)
        start, angle, busy, done = dut.start, dut.angle, self.inst.busy, self.inst.done
        sin_h, cos_h = self.inst.sin_q15, self.inst.cos_q15
        prev = self.outputs()
        for k in range(n):
            if gaps[k]:
                start.value = 0
                await self.cycles(gaps[k])
                if int(busy.value) or int(done.value):
                    self.expect_idle(f"{label} vector {k}: idle gap of {gaps[k]} cycles before the start")
            a = angles[k]
            angle.value = a
            start.value = 1
            await self.cycles(1)
            if not int(busy.value) or int(done.value):
                self.expect_flags(1, 0, f"{label} vector {k} (angle {a:#010x}): cycle after start")
            if hold[k]:
                angle.value = garbage[k]  # start stays high: a start while busy is ignored
            else:
                start.value = 0
            await self.cycles(mid)
            if not int(busy.value) or int(done.value):
                self.expect_flags(1, 0, f"{label} vector {k} (angle {a:#010x}): cycle before done")
            got = (sin_h.value.to_signed(), cos_h.value.to_signed())
            if got != prev:
                assert False, (f"{label} vector {k} (angle {a:#010x}): outputs not held until done: "
                               f"{got}, previous result {prev}")
            await self.cycles(1)
            if int(busy.value) or not int(done.value):
                self.expect_flags(0, 1, f"{label} vector {k} (angle {a:#010x}): done cycle = start + "
                                        f"LATENCY ({self.latency})")
            got = (sin_h.value.to_signed(), cos_h.value.to_signed())
            want = (exp_sin[k], exp_cos[k])
            if got != want:
                assert False, (f"{label} vector {k}: angle {a} ({a:#010x}), WIDTH={self.width} "
                               f"ITERATIONS={self.iterations}: (sin_q15, cos_q15) RTL {got}, golden {want}")
            prev = got
        start.value = 0
        await self.cycles(1)
        self.expect_idle(f"{label}: after the last vector")

    async def stream_golden(self, angles, label: str) -> None:
        """:meth:`stream` with the golden ``sincos_q15`` of the angles."""
        arr = np.asarray([int(a) for a in angles], dtype=np.int64)
        s, c = sincos_q15(arr, self.width, self.iterations)
        await self.stream(arr.tolist(), s.tolist(), c.tolist(), label)


# ---- tests --------------------------------------------------------------------------------------------
@cocotb.test()
async def directed(dut):
    """Directed angles (quadrant points, fold boundaries, saturation), each with a cycle-by-cycle
    protocol check, then again as a back-to-back stream."""
    tb = Bench(dut)
    await tb.setup()
    angles = testvectors.directed_angles()
    sat_angles, n_pos, n_neg = testvectors.saturating_angles(tb.width, tb.iterations)
    cocotb.log.info(f"saturation: {n_pos} near-axis angles round to +32768, {n_neg} to -32769; "
                    f"testing {len(sat_angles)}")
    if (tb.width, tb.iterations) == (32, 32):
        assert n_pos > 0, "no angle exercising the +32768 -> 32767 saturation was found"
    angles += sat_angles
    arr = np.asarray(angles, dtype=np.int64)
    exp_s, exp_c = sincos_q15(arr, tb.width, tb.iterations)
    for k, a in enumerate(angles):
        got = await tb.one_checked(a, f"directed angle {a:#010x}")
        want = (int(exp_s[k]), int(exp_c[k]))
        assert got == want, (f"directed angle {a} ({a:#010x}), WIDTH={tb.width} ITERATIONS={tb.iterations}: "
                             f"(sin_q15, cos_q15) RTL {got}, golden {want}")
    await tb.stream_golden(angles, "directed stream")


@cocotb.test()
async def random_angles(dut):
    """HFI_RANDOM_N random u32 angles, random protocol (back to back, gaps, start held while busy)."""
    tb = Bench(dut)
    await tb.setup()
    await tb.stream_golden(testvectors.random_angles(tb.rng, tb.random_n), "random angle")


@cocotb.test()
async def demodulation_weights(dut):
    """Weight angles uwrap((H - 2c) * CW_ANGLE_STEP, 32) against golden demod_weight: H = 10000 at
    c = 0, H/2, H, then random even H in 512..65534 and c in 0..H (HFI_RANDOM_N / 5 of them)."""
    tb = Bench(dut)
    await tb.setup()
    cases = testvectors.demod_cases(tb.rng, max(200, tb.random_n // 5))
    angles, exp_w, exp_c = [], [], []
    for h, c in cases:
        a = testvectors.demod_case(h, c)
        angles.append(a)
        exp_w.append(demod_weight(c, h, cw_angle_step(h), tb.width, tb.iterations))
        exp_c.append(sincos_q15(a, tb.width, tb.iterations)[1])
    for k, (h, c) in enumerate(cases[:3]):
        got = await tb.one_checked(angles[k], f"weight H={h} c={c}")
        assert got[0] == exp_w[k], (f"weight H={h} c={c} (angle {angles[k]:#010x}): RTL {got[0]}, "
                                    f"golden demod_weight {exp_w[k]}")
    if (tb.width, tb.iterations) == (32, 32):  # spec 3.3: +32767 at the bottom, 0 at c = H/2, -32768 at the top
        assert exp_w[:3] == [32767, 0, -32768], f"golden weights at H = {testvectors.WEIGHT_H}: {exp_w[:3]}"
    await tb.stream(angles, exp_w, exp_c, "demodulation weight")


@cocotb.test()
async def reset_mid_operation(dut):
    """A reset in every cycle of a computation (from the start cycle on) aborts it: busy and done
    drop, no done follows, outputs go to 0; the next start works."""
    tb = Bench(dut)
    await tb.setup()
    angles = tb.rng.integers(0, U32, size=tb.latency + 1, dtype=np.int64).tolist()
    angles[0] = Q // 2  # 45 deg: nonzero outputs, so the reset value is visible
    await tb.stream_golden(angles[:1], "before reset")
    for k in range(tb.latency):  # reset asserted k cycles after the start cycle (k = 0: together)
        def start(a=angles[k + 1]):
            tb.dut.angle.value = a
            tb.dut.start.value = 1

        def release():
            tb.dut.start.value = 0

        await tb.start_then_reset(k, start, release, f"reset {k} cycles after the start")
        tb.expect_outputs(0, 0, f"reset {k} cycles after the start: reset outputs")
        for j in range(tb.latency + 2):
            await tb.cycles(1)
            tb.expect_idle(f"reset {k} cycles after the start: {j + 1} cycles after the reset "
                           "(the aborted computation must not finish)")
            tb.expect_outputs(0, 0, f"reset {k} cycles after the start: outputs stay 0")
        await tb.stream_golden([angles[k + 1]], f"after reset k={k}")


@cocotb.test()
async def start_while_busy(dut):
    """Starts with other angles in every busy cycle are ignored: one done, the first angle's result."""
    tb = Bench(dut)
    await tb.setup()
    dut = tb.dut
    for trial in range(4):
        a, *others = tb.rng.integers(0, U32, size=tb.latency, dtype=np.int64).tolist()
        want = tuple(int(v) for v in sincos_q15(a, tb.width, tb.iterations))
        dut.angle.value = a
        dut.start.value = 1
        await tb.cycles(1)
        for k in range(1, tb.latency):
            tb.expect_flags(1, 0, f"trial {trial}: {k} cycles after start, start held with other angles")
            dut.angle.value = others[k - 1]  # start stays 1
            await tb.cycles(1)
        dut.start.value = 0
        tb.expect_flags(0, 1, f"trial {trial}: done cycle")
        tb.expect_outputs(*want, f"trial {trial}: angle {a:#010x}")
        for j in range(tb.latency + 2):
            await tb.cycles(1)
            tb.expect_idle(f"trial {trial}: {j + 1} cycles after done (ignored starts must not run)")
        tb.expect_outputs(*want, f"trial {trial}: outputs held")
    # start in the cycle after done (not in the done cycle) and in the done cycle, checked per cycle
    b, c = tb.rng.integers(0, U32, size=2, dtype=np.int64).tolist()
    got = await tb.one_checked(b, "start after idle")  # returns one cycle after done: start now
    assert got == tuple(int(v) for v in sincos_q15(b, tb.width, tb.iterations))
    got = await tb.one_checked(c, "start in the cycle after done")
    assert got == tuple(int(v) for v in sincos_q15(c, tb.width, tb.iterations))
