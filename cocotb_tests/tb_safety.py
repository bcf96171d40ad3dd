"""cocotb testbench of rtl/hfi_safety.v (run by cocotb_tests/test_safety.py, not by pytest).

Reference: ``golden.fpga.safety.SafetyLogic``, one ``step`` per clock. Phase: the inputs of clock t are
driven at the falling edge inside clock t (so the rising edge that ends clock t samples them); in
ReadOnly of the same time step every combinational output (``sto_s``, ``desat_s``, ``kill``,
``enable``, ``outputs_on``, ``drive_allowed``) and the registered latches (``fault_*``) are compared
with the model's outputs of clock t, and the ``gate`` register with the model's ``gate`` of clock
t - 1 (the register loaded at the end of the clock before). Every output, every clock.

Start: the latches, the enable and the gate register have no initial value (X in Icarus), the
synchronizers start at 0; the bench holds ``rst`` with STO/DESAT low for two clocks before comparing,
which puts the RTL in the state of a fresh ``SafetyLogic``.
"""

from __future__ import annotations

import os

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, ReadOnly

from golden.fpga.safety import SafetyInputs, SafetyLogic

INPUTS = ("rst", "sto", "desat", "oc_trip", "wdt_expired", "fault_clear", "ctrl_enable", "at_bottom", "gate_in")
COMB = ("sto_s", "desat_s", "fault_oc", "fault_wdt", "fault_sto", "fault_desat", "kill", "enable",
        "outputs_on", "drive_allowed")


class Bench:
    def __init__(self, dut, name: str):
        self.dut = dut
        self.seed = int(os.environ["HFI_SEED"])
        self.n = int(os.environ["HFI_RANDOM_N"])
        self.rng = np.random.default_rng(self.seed)
        cocotb.log.info(f"{name}: HFI_SEED={self.seed} HFI_RANDOM_N={self.n}")
        self.in_sigs = [getattr(dut, n) for n in INPUTS]
        self.out_sigs = [(n, getattr(dut, n)) for n in COMB]
        self.fall = FallingEdge(dut.clk)
        self.ro = ReadOnly()
        self.model = SafetyLogic()
        self.clock = 0           # clocks compared since start()
        self.history: list[tuple] = []
        self.last = None         # outputs of the last clock
        self.pin_now = 0         # gate pins of the last clock stepped

    async def start(self):
        dut = self.dut
        Clock(dut.clk, 10, unit="ns").start()
        for sig in self.in_sigs:
            sig.value = 0
        dut.rst.value = 1
        for _ in range(3):        # two rising edges with rst, STO and DESAT low
            await self.fall
        self.model = SafetyLogic()   # from here on the RTL is in the state of a fresh model

    async def quiesce(self):
        """Idle clocks until the synchronizers are empty, then a reset clock."""
        for _ in range(3):
            await self.step(SafetyInputs())
        await self.step(SafetyInputs(rst=1))

    async def step(self, x: SafetyInputs):
        """One clock: drive ``x`` (we are at the falling edge inside the clock), compare in ReadOnly,
        step the model, wait for the next falling edge. Returns the model's outputs of the clock."""
        for sig, name in zip(self.in_sigs, INPUTS):
            sig.value = getattr(x, name)
        gate_reg = self.model.gate
        self.pin_now = gate_reg   # the gate pins in this clock (checked against the RTL below)
        await self.ro
        exp = self.model.step(x)
        self.history.append((self.clock, x))
        if len(self.history) > 8:
            self.history.pop(0)
        got_gate = self.dut.gate.value
        if not got_gate.is_resolvable or int(got_gate) != gate_reg:
            self._fail("gate (register)", got_gate, gate_reg)
        for name, sig in self.out_sigs:
            v = sig.value
            e = getattr(exp, name)
            if not v.is_resolvable or int(v) != e:
                self._fail(name, v, e)
        self.clock += 1
        self.last = exp
        await self.fall
        return exp

    def _fail(self, name, got, exp):
        hist = "\n  ".join(f"clock {c}: {x}" for c, x in self.history)
        raise AssertionError(f"clock {self.clock}: {name} RTL {got}, golden {exp} (HFI_SEED={self.seed}); "
                             f"inputs of the last clocks:\n  {hist}")

# ---------------------------------------------------------------------- random stimulus
class Stimulus:
    """Random inputs biased towards the interesting cases: STO/DESAT pulses of 1..5 clocks and held
    levels, FAULT_CLEAR during and right after STO/DESAT, CTRL.ENABLE toggles at and next to carrier
    bottoms, oc_trip pulses, wdt_expired levels, resets; ``stats`` counts what occurred."""

    def __init__(self, rng):
        self.rng = rng
        self.t = 0
        self.period = 20
        self.next_bottom = 0
        self.left = {"sto": 0, "desat": 0, "wdt_expired": 0, "rst": 0}   # clocks a level stays 1
        self.quiet = {"sto": 0, "desat": 0}                                  # clocks since release
        self.ctrl_enable = 0
        self.gate_in = 0
        self.clear_at: set[int] = set()
        self.stats: dict[str, int] = {}
        self.u = rng.random((4096, 12))
        self.k = 4096

    def count(self, what: str) -> None:
        self.stats[what] = self.stats.get(what, 0) + 1

    def _u(self):
        if self.k == len(self.u):
            self.u = self.rng.random(self.u.shape)
            self.k = 0
        row = self.u[self.k]
        self.k += 1
        return row

    def next(self) -> SafetyInputs:
        u = self._u()
        rng, t = self.rng, self.t
        # carrier bottoms: a new random period now and then
        at_bottom = int(t == self.next_bottom)
        if at_bottom:
            if u[0] < 0.05:
                self.period = int(rng.integers(4, 80))
            self.next_bottom = t + self.period
        # CTRL.ENABLE: toggles mostly at, just before or just after a bottom
        near = min(abs(self.next_bottom - t), t - (self.next_bottom - self.period))
        if (near <= 1 and u[1] < 0.08) or u[1] < 0.002:
            self.ctrl_enable ^= 1
            self.count("enable toggle at bottom" if at_bottom else "enable toggle")
        # STO and DESAT: 1..5-clock pulses or held levels
        pins = {}
        for i, (pin, p) in enumerate((("sto", 0.004), ("desat", 0.002))):
            if self.left[pin] == 0 and u[2 + i] < p:
                if rng.random() < 0.6:
                    self.left[pin] = int(rng.integers(1, 6))
                    self.count(f"{pin} pulse {self.left[pin]}")
                else:
                    self.left[pin] = int(rng.integers(6, 400))
                    self.count(f"{pin} held")
                    # clears during the held level
                    for _ in range(int(rng.integers(0, 4))):
                        self.clear_at.add(t + int(rng.integers(0, self.left[pin] + 3)))
                # clears right after the release (around the synchronizer delay) and later
                end = t + self.left[pin]
                for d in rng.choice([0, 1, 2, 3, 4, 5, 10, 50], size=int(rng.integers(0, 3))):
                    self.clear_at.add(end + int(d))
            pins[pin] = int(self.left[pin] > 0)
            if self.left[pin]:
                self.left[pin] -= 1
        # oc_trip: one-clock pulses; wdt_expired: a level of 1..30 clocks
        oc = int(u[4] < 0.002)
        if oc:
            self.count("oc_trip")
        if self.left["wdt_expired"] == 0 and u[5] < 0.001:
            self.left["wdt_expired"] = int(rng.integers(1, 31))
            self.count("wdt level")
        wdt = int(self.left["wdt_expired"] > 0)
        if wdt:
            self.left["wdt_expired"] -= 1
        # FAULT_CLEAR: scheduled ones plus random pulses
        clear = int(t in self.clear_at or u[6] < 0.004)
        self.clear_at.discard(t)
        if clear:
            self.count("fault_clear")
        # rst: rare, 1..3 clocks
        if self.left["rst"] == 0 and u[7] < 0.0005:
            self.left["rst"] = int(rng.integers(1, 4))
            self.count("rst")
        rst = int(self.left["rst"] > 0)
        if rst:
            self.left["rst"] -= 1
        # gate_in: changes now and then (the full 6-bit range, not only legal masks)
        if u[8] < 0.15:
            self.gate_in = int(rng.integers(0, 64))
        self.t += 1
        return SafetyInputs(rst=rst, sto=pins["sto"], desat=pins["desat"], oc_trip=oc, wdt_expired=wdt,
                            fault_clear=clear, ctrl_enable=self.ctrl_enable, at_bottom=at_bottom,
                            gate_in=self.gate_in)


@cocotb.test()
async def random_sequence(dut):
    """HFI_RANDOM_N clocks of biased random inputs, every output compared every clock."""
    b = Bench(dut, "random_sequence")
    await b.start()
    st = Stimulus(b.rng)
    seen = dict(clear_while_sto_s=0, clear_rearm_sto=0, clear_rearm_desat=0, enable_at_bottom=0,
                gate_kill_edges=0, outputs_on=0)
    prev = None
    for _ in range(b.n):
        x = st.next()
        before = (b.model.fault_sto, b.model.fault_desat)
        o = await b.step(x)
        if x.fault_clear and o.sto_s:
            seen["clear_while_sto_s"] += 1
        if x.fault_clear and not x.rst and before[0] and not o.sto_s and not b.model.fault_sto:
            seen["clear_rearm_sto"] += 1
        if x.fault_clear and not x.rst and before[1] and not o.desat_s and not b.model.fault_desat:
            seen["clear_rearm_desat"] += 1
        if x.at_bottom and o.enable and not (prev and prev.enable):
            seen["enable_at_bottom"] += 1
        if o.kill and not (prev and prev.kill) and x.gate_in:
            seen["gate_kill_edges"] += 1
        seen["outputs_on"] += o.outputs_on
        prev = o
    cocotb.log.info(f"random_sequence: {b.clock} clocks compared; stimulus {dict(sorted(st.stats.items()))}; "
                    f"seen {seen}")
    needed = [f"sto pulse {k}" for k in range(1, 6)] + [f"desat pulse {k}" for k in range(1, 6)] + [
        "sto held", "desat held", "oc_trip", "wdt level", "enable toggle at bottom", "rst"]
    if b.n >= 40_000:                       # (shorter runs may miss a rare case)
        missing = [k for k in needed if not st.stats.get(k)] + [k for k, v in seen.items() if not v]
        assert not missing, f"cases that did not occur: {missing}"


@cocotb.test()
async def sto_pin_to_gates_off(dut):
    """STO pin raised in clock T: gate pins still on in T + 2, all 0 from T + 3; drive_allowed 0 from
    T + 2; the same for DESAT; for several phases of the pin after the enabling bottom."""
    b = Bench(dut, "sto_pin_to_gates_off")
    await b.start()
    for pin in ("sto", "desat"):
        for lead in (0, 1, 3, 7):
            await b.quiesce()
            await b.step(SafetyInputs(ctrl_enable=1, at_bottom=1, gate_in=0x25))   # enabled at a bottom
            for _ in range(lead):
                await b.step(SafetyInputs(ctrl_enable=1, gate_in=0x25))
            pins, outs = [], []                 # clocks T .. T + 5, the pin high from clock T
            for _ in range(6):
                outs.append(await b.step(SafetyInputs(ctrl_enable=1, gate_in=0x25, **{pin: 1})))
                pins.append(b.pin_now)
            what = f"{pin} (lead {lead})"
            assert pins == [0x25, 0x25, 0x25, 0, 0, 0], f"{what}: gate pins in clocks T..T+5: {pins}"
            assert [o.drive_allowed for o in outs] == [1, 1, 0, 0, 0, 0], f"{what}: drive_allowed"
            assert [getattr(o, f"{pin}_s") for o in outs] == [0, 0, 1, 1, 1, 1], f"{what}: {pin}_s"
            assert [getattr(o, f"fault_{pin}") for o in outs] == [0, 0, 0, 1, 1, 1], f"{what}: latch"
            assert [o.enable for o in outs] == [1, 1, 0, 0, 0, 0], f"{what}: enable"


@cocotb.test()
async def clear_while_sto_held_is_ignored(dut):
    """FAULT_CLEAR while STO (or DESAT) is held, also in the clocks the synchronized pin is still 1
    after the release: latched, gates off; after the release the latch stays until a clear."""
    b = Bench(dut, "clear_while_sto_held_is_ignored")
    await b.start()
    for pin in ("sto", "desat"):
        await b.quiesce()
        await b.step(SafetyInputs(ctrl_enable=1, at_bottom=1, gate_in=0x12))
        for k in range(40):      # held 40 clocks, a clear every 7 clocks
            o = await b.step(SafetyInputs(ctrl_enable=1, gate_in=0x12, fault_clear=int(k % 7 == 6), **{pin: 1}))
            if k >= 3:
                assert getattr(o, f"fault_{pin}") == 1 and o.kill == 1, f"{pin} held, clock {k}"
            if k >= 3:
                assert b.pin_now == 0, f"{pin} held, clock {k}: gate pins {b.pin_now:#x}"
        # released: the synchronized pin is still 1 for 2 clocks; a clear in each of them is ignored
        for k in range(2):
            o = await b.step(SafetyInputs(ctrl_enable=1, gate_in=0x12, fault_clear=1))
            assert getattr(o, f"{pin}_s") == 1 and b.pin_now == 0
        for k in range(20):
            o = await b.step(SafetyInputs(ctrl_enable=1, gate_in=0x12))
            assert getattr(o, f"fault_{pin}") == 1 and getattr(o, f"{pin}_s") == 0 and o.kill == 1
            assert o.drive_allowed == 0 and b.pin_now == 0
        o = await b.step(SafetyInputs(ctrl_enable=1, gate_in=0x12, fault_clear=1))   # the re-arm
        o = await b.step(SafetyInputs(ctrl_enable=1, gate_in=0x12))
        assert getattr(o, f"fault_{pin}") == 0 and o.kill == 0 and o.drive_allowed == 1


@cocotb.test()
async def clear_after_release_rearms_at_next_bottom(dut):
    """Pin high in clocks 19..31 (carrier period 16, bottoms at multiples of 16, ENABLE held), released,
    FAULT_CLEAR in clock 48 + phase: kill drops the clock after the clear, ``enable`` (and so the gate
    generator) comes back only at the bottom 64. A gate generator stand-in (gate_in = mask while
    enable was 1 the clock before) shows the gate pins back in clock 66."""
    b = Bench(dut, "clear_after_release_rearms_at_next_bottom")
    await b.start()
    period = 16
    bottom = 4 * period         # the first bottom after the clear
    for pin in ("sto", "desat"):
        for clear_phase in (1, 5, 14, 15):
            await b.quiesce()
            clear_clock = 3 * period + clear_phase
            en_prev = 0
            log = []
            for t in range(6 * period):
                x = SafetyInputs(
                    ctrl_enable=1, at_bottom=int(t % period == 0), **{pin: int(period + 3 <= t < 2 * period)},
                    fault_clear=int(t == clear_clock), gate_in=0x2D if en_prev else 0)
                o = await b.step(x)
                en_prev = o.enable
                log.append((t, o.kill, o.enable, o.outputs_on, b.pin_now))
            what = f"{pin}, clear in clock {clear_clock}"
            for t, kill, en, on, pins in log:
                exp = int(period + 5 <= t <= clear_clock)
                assert kill == exp, f"{what}: kill {kill} in clock {t}, expected {exp}"
                exp = int(t < period + 5 or t >= bottom)
                assert en == exp, f"{what}: enable {en} in clock {t}, expected {exp}"
                exp = int(1 <= t <= period + 5 or t >= bottom + 1)
                assert on == exp, f"{what}: outputs_on {on} in clock {t}, expected {exp}"
                exp = 0x2D if (2 <= t <= period + 5 or t >= bottom + 2) else 0
                assert pins == exp, f"{what}: gate pins {pins:#x} in clock {t}, expected {exp:#x}"
