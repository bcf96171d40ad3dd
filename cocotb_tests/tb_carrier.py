"""cocotb testbench for rtl/hfi_carrier.v (run by cocotb_tests/test_carrier.py).

Every tick is compared with the golden carrier (``golden.fpga.carrier``: ``effective_half``,
``counter``; strobes and phase of spec 2.1; register draws from golden/testvectors/carrier.py, shared with
tests/test_hls_carrier.py) and the weight angle of ``golden.fpga.cordic.demod_weight``
(``a = uwrap(wrap((H - 2c)*STEP, 32), 32)``; the resulting weights are also checked against
``demod_weight`` itself, vectorised). The register-application rule of the RTL (docs/rtl.md: a write
takes effect at the first bottom at least 20 clocks after it) is modelled cycle by cycle and tested
directly at the boundary (bottom at w + 19 vs w + 20).

Convention: inputs are driven at the falling edge of cycle t ("the value present in cycle t"); at
that falling edge the outputs show the registered state of tick t.
"""

from __future__ import annotations

import os

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, FallingEdge

from golden.fixed import uwrap, wrap
from golden.fpga.carrier import counter as golden_counter
from golden.fpga.carrier import effective_half
from golden.fpga.cordic import cw_angle_step, demod_weight, sincos_q15
from golden.testvectors.carrier import DIRECTED_HALF_REGS, random_half_reg, random_step

MUL_CYCLES = 17          # load + 16 add cycles of the serial multiplier (rtl/hfi_carrier.v)
APPLY_DELAY = 20         # a write in cycle w is used from the first bottom at tick >= w + 20
                         # (the input registers, the product, one pipeline stage into the ready triple)


def golden_angle(c: int, half: int, step: int) -> int:
    """The weight angle of golden.fpga.cordic.demod_weight (its ``a = ...`` line) for counter c."""
    return uwrap(wrap((half - 2 * c) * step, 32), 32)


class CarrierModel:
    """Cycle model of hfi_carrier: golden carrier per tick plus the documented register rule.

    The register rule is modelled as the RTL documents it: the inputs are registered first (the pair
    of the cycle before is what the rest sees), the serial multiplier restarts whenever
    the (effective H, STEP) inputs differ from its operands (or on the rising edge of rst) and
    completes 17 cycles later; one cycle after that the pair is the ready pair (a pipeline stage); a
    bottom takes the ready pair.
    """

    def __init__(self):
        self.ops = None            # operands of the product in progress
        self.cnt = 0
        self.busy = False
        self.ready = None          # the ready (H, STEP): completed one cycle before the last load
        self.loading = None        # completed in the previous cycle: ready at the end of this one
        self.in_q = None           # the register inputs of the previous cycle (the RTL's x_h, x_s)
        self.prev_pair = None      # in_q of the previous cycle (the pair taken under rst)
        self.rst_q = 0
        self.phase = None          # carrier state of the current tick (None: unknown)
        self.half = None
        self.step = None
        self.hs_ok = False         # is H*STEP of (half, step) known to the RTL (angle checkable)?

    def expected(self):
        """Expected outputs of the current tick (dict), or None while unknown."""
        if self.phase is None:
            return None
        h, ph = self.half, self.phase
        c = int(golden_counter(ph, h))
        return {
            "phase": ph, "half": h, "counter": c, "rising": int(ph < h), "at_bottom": int(ph == 0),
            "at_top": int(ph == h), "at_zc": int(ph == h // 2),
            "cw_angle": golden_angle(c, h, self.step) if self.hs_ok else None,
        }

    def clock(self, rst: int, pwm_half: int, step: int) -> None:
        """Advance one clock edge with the inputs present in the current cycle."""
        pair = self.in_q           # the inputs of the cycle before (None in the first cycle)
        self.in_q = (effective_half(pwm_half), step)
        # carrier (uses the ready pair as it was during this cycle)
        if rst:   # the pair of the previous cycle (the RTL's operand registers; unknown in cycle 0)
            if self.prev_pair is None:
                self.phase = None
            else:
                self.phase, self.half, self.step = 0, self.prev_pair[0], self.prev_pair[1]
        elif self.phase is not None:
            if self.phase >= 2 * self.half - 1:
                self.phase = 0
                self.half, self.step = self.ready
                self.hs_ok = True
            else:
                self.phase += 1
        # serial multiplier
        completed = None
        if pair != self.ops or (rst and not self.rst_q):
            self.ops, self.cnt, self.busy = pair, 0, True
        elif self.busy:
            if self.cnt == MUL_CYCLES - 2:
                self.busy = False
                completed = self.ops
            else:
                self.cnt += 1
        self.rst_q = rst
        # hs follows the ready triple when it matches the pair in use (the RTL's hs_n rule,
        # evaluated with the ready triple of this cycle)
        if rst or self.phase is not None:
            if self.ready is not None and self.ready == (self.half, self.step):
                self.hs_ok = True
            elif rst:
                self.hs_ok = False
        if self.loading is not None:
            self.ready = self.loading
        self.loading = completed
        self.prev_pair = pair


class Bench:
    """Drives the DUT at falling edges, checks every tick against the model."""

    def __init__(self, dut, rng):
        self.dut = dut
        self.rng = rng
        self.model = CarrierModel()
        self.rst = 1
        self.pwm_half = 1000
        self.step = cw_angle_step(1000)
        self.tick = None           # tick number of the current cycle (None before the first reset)
        self.checked = 0
        self.angles = []           # (counter, half, step, rtl angle) for the demod_weight cross-check
        self.sigs = {n: getattr(dut, n) for n in
                     ("phase", "half", "counter", "rising", "at_bottom", "at_top", "at_zc", "cw_angle")}

    def drive(self):
        self.dut.rst.value = self.rst
        self.dut.pwm_half_reg.value = self.pwm_half
        self.dut.cw_step_reg.value = self.step

    async def cycle(self, check=True):
        """At the falling edge of the current cycle: check outputs, drive inputs, advance the model."""
        await FallingEdge(self.dut.clk)
        exp = self.model.expected()
        self.last_exp = exp
        if check and exp is not None:
            got = {n: int(s.value) for n, s in self.sigs.items() if exp[n] is not None}
            self.last_got = got
            for name, want in exp.items():
                if want is not None and got[name] != want:
                    raise AssertionError(
                        f"tick {self.tick}: {name} RTL={got[name]} golden={want} "
                        f"(H={exp['half']}, phase={exp['phase']}, STEP={self.model.step}, "
                        f"PWM_HALF reg={self.pwm_half}, CW_ANGLE_STEP reg={self.step})")
            if exp["cw_angle"] is not None and len(self.angles) < 200_000:
                self.angles.append((exp["counter"], exp["half"], self.model.step, got["cw_angle"]))
            self.checked += 1
        self.drive()
        self.model.clock(self.rst, self.pwm_half, self.step)
        self.tick = 0 if self.rst else (None if self.tick is None else self.tick + 1)

    def check_weights(self):
        """Cross-check the collected RTL angles with golden demod_weight (vectorised per (H, STEP))."""
        if not self.angles:
            return 0
        arr = np.array(self.angles, dtype=np.int64)
        n = 0
        for (h, s) in {(int(a[1]), int(a[2])) for a in arr[:, :]}:
            sel = arr[(arr[:, 1] == h) & (arr[:, 2] == s)]
            want = demod_weight(sel[:, 0], h, s)
            got = sincos_q15(sel[:, 3], 32, 32)[0]
            bad = np.nonzero(want != got)[0]
            if bad.size:
                i = bad[0]
                raise AssertionError(f"weight of c={sel[i, 0]} H={h} STEP={s}: from RTL angle {sel[i, 3]} "
                                     f"-> {got[i]}, golden demod_weight {want[i]}")
            n += sel.shape[0]
        return n


async def start(dut, rst_cycles=20, pwm_half=1000, step=None, first=True):
    """Start the clock (``first``) and reset the DUT for ``rst_cycles``; a fresh Bench/model."""
    seed = int(os.environ["HFI_SEED"])
    if first:
        cocotb.log.info(f"HFI_SEED={seed} HFI_RANDOM_N={os.environ['HFI_RANDOM_N']}")
        Clock(dut.clk, 10, unit="ns").start()
    b = Bench(dut, np.random.default_rng(seed))
    b.pwm_half = pwm_half
    b.step = cw_angle_step(effective_half(pwm_half)) if step is None else step
    b.rst = 1
    for _ in range(rst_cycles):
        await b.cycle()
    b.rst = 0
    return b


MIN_NEW_HALVES = 3
"""Bottoms that take a new PWM_HALF in random_registers (its coverage goal)."""


@cocotb.test()
async def random_registers(dut):
    """HFI_RANDOM_N ticks with random PWM_HALF / CW_ANGLE_STEP writes (single and bursts) and resets, and on until
    at least MIN_NEW_HALVES bottoms have taken a new H (a seed that drew long periods sees few bottoms in
    HFI_RANDOM_N ticks: seed 3626610211 saw 2), at most 20 times as long."""
    n = int(os.environ["HFI_RANDOM_N"])
    b = await start(dut)
    rng = b.rng
    burst = []                                   # cycles until the next write of a burst
    bottoms_changed = 0
    last_half = None
    while (b.checked < n or bottoms_changed < MIN_NEW_HALVES) and b.checked < 20 * n:
        if burst:
            burst[0] -= 1
            if burst[0] == 0:
                burst.pop(0)
                if rng.random() < 0.7:
                    b.pwm_half = random_half_reg(rng)
                if rng.random() < 0.7:
                    b.step = random_step(rng, b.pwm_half)
        elif rng.random() < 1 / 900:
            # a write burst: 1..3 writes, spaced 1..40 cycles (some never apply)
            k = int(rng.integers(1, 4))
            burst = [1] + [int(rng.integers(1, 41)) for _ in range(k - 1)]
        if b.rst:
            b.rst = int(rng.random() > 1 / 20)    # reset held a random number of cycles (>= 20 here)
        elif b.tick is not None and b.tick > 50 and rng.random() < 1 / 40_000:
            b.rst = 1
            for _ in range(APPLY_DELAY):         # long enough for the product (>= 19 cycles)
                await b.cycle()
        await b.cycle()
        exp = b.model.expected()
        if exp and exp["at_bottom"] and exp["half"] != last_half:
            bottoms_changed += 1
            last_half = exp["half"]
    nw = b.check_weights()
    cocotb.log.info(f"{b.checked} ticks checked, {bottoms_changed} bottoms with a new H, "
                    f"{nw} weights cross-checked with demod_weight")
    assert bottoms_changed >= MIN_NEW_HALVES, "too few register changes applied: the test did not exercise them"


@cocotb.test()
async def apply_rule_boundary(dut):
    """A write in cycle w applies at a bottom at tick w + 20, not at w + 19 (docs/rtl.md rule)."""
    cases = ((APPLY_DELAY, True), (APPLY_DELAY - 1, False), (APPLY_DELAY + 5, True), (1, False))
    for i, (delay, applies) in enumerate(cases):
        b = await start(dut, pwm_half=600, first=i == 0)       # H = 600, P = 1200
        old = (600, b.step)
        # run to the cycle w such that the next bottom is at w + delay
        while not (b.model.phase is not None and b.model.phase == 2 * 600 - delay):
            await b.cycle()
        b.pwm_half, b.step = 700, 0x12345679     # present from this cycle (w) on
        for _ in range(delay + 1):               # cycles w .. w + delay (the bottom)
            await b.cycle()
        assert b.last_exp["at_bottom"] == 1 and b.tick is not None, b.last_exp
        got = (b.last_got["half"], b.last_got["cw_angle"])
        want_pair = (700, 0x12345679) if applies else old
        want = (want_pair[0], golden_angle(0, *want_pair))
        assert got == want, f"write {delay} cycles before a bottom: RTL (half, angle)={got}, expected {want}"
        for _ in range(2 * 700 + 10):            # and the next period runs with the new values anyway
            await b.cycle()
        assert int(b.dut.half.value) == 700


@cocotb.test()
async def short_reset(dut):
    """rst of 1..20 cycles: phase/half/strobes right from tick 0, cw_angle from tick max(0, 20 - n)."""
    rng = np.random.default_rng(int(os.environ["HFI_SEED"]))
    for i, n_rst in enumerate((1, 2, 5, 19, 20)):
        h_reg = int(rng.integers(512, 2000))
        step = int(rng.integers(0, 1 << 32))
        # run some cycles with other register values first, so the multiplier holds another product
        b = await start(dut, rst_cycles=20, pwm_half=3000, step=0xDEADBEEF, first=i == 0)
        for _ in range(30):
            await b.cycle()
        b.pwm_half, b.step = h_reg, step
        b.rst = 1
        for _ in range(n_rst):
            await b.cycle()
        b.rst = 0
        first_ok = max(0, APPLY_DELAY - n_rst)
        for t in range(2 * effective_half(h_reg) + 40):
            exp = b.model.expected()
            assert b.tick == t
            if t >= first_ok:
                assert exp["cw_angle"] is not None, f"reset of {n_rst} cycles: angle not valid at tick {t}"
            await b.cycle()


@cocotb.test()
async def full_scale(dut):
    """PWM_HALF = 65535 (H = 65534), STEP = 2^32 - 1: check around bottom, zero crossing, top, end."""
    b = await start(dut, pwm_half=0xFFFF, step=0xFFFFFFFF)
    h = 65534
    marks = [0, h // 2 - 2, h - 2, 2 * h - 3, 2 * h + 3]
    for m in marks:
        if m - 2 > b.tick:                       # fast-forward without per-tick Python
            skip = m - 2 - b.tick
            await ClockCycles(b.dut.clk, skip, rising=False)
            for _ in range(skip):                # advance the model (inputs constant)
                b.model.clock(0, b.pwm_half, b.step)
            b.tick += skip
        for _ in range(5):
            await b.cycle()
    assert b.checked >= 25


@cocotb.test()
async def multiplier_full_range(dut):
    """The serial H*STEP product over the whole register range: random (PWM_HALF, STEP) pairs, each
    loaded by a reset of 18..22 cycles; ticks 0..3 are checked (angle = H*STEP - 2c*STEP)."""
    rng = np.random.default_rng(int(os.environ["HFI_SEED"]) + 1)
    n_pairs = max(20, int(os.environ["HFI_RANDOM_N"]) // 500)
    b = None
    for i in range(n_pairs):
        h_reg = int(rng.integers(0, 1 << 16)) if i % 4 else int(rng.choice(DIRECTED_HALF_REGS))
        step = int(rng.integers(0, 1 << 32)) if i % 3 else int(rng.choice([0xFFFFFFFF, 0x80000000, 1]))
        b = await start(dut, rst_cycles=int(rng.integers(APPLY_DELAY, APPLY_DELAY + 5)), pwm_half=h_reg,
                        step=step, first=i == 0)
        for _ in range(4):
            await b.cycle()
        assert b.checked >= 4 and b.last_exp["cw_angle"] is not None
    cocotb.log.info(f"{n_pairs} products checked")
