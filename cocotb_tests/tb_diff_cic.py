"""cocotb testbench of rtl/hfi_diff_cic.v (run by cocotb_tests/test_diff_cic.py, not by pytest).

Reference: golden.fpga.diff_cic.DiffCic (spec 3.9), one ``step`` per ``in_valid`` with the same inputs.

A test is a list of timed items (see :class:`Seq`): steps (``in_valid`` with i_alpha, i_beta, plus,
cic_m) and resets, each a number of cycles after the previous item. Every step is checked ``LATENCY``
cycles after its in_valid: ``out_valid`` = 1 and (q_a, q_b, e_a, e_b) equal to the golden step's
result; one cycle earlier the outputs must still hold the previous step's result (0 after a reset). A
monitor records every cycle in which ``out_valid`` is high, which must be exactly the set of step cycles
+ ``LATENCY`` (no spurious, lost or stretched pulses). The cycle after each item drives in_valid = 0
with random other inputs (i_alpha, i_beta, plus and cic_m are sampled in the in_valid cycle only).
A reset aborts the steps in flight (no out_valid for them) and restarts the golden model (DiffCic()).

Steps come every MIN_SPACING..6 cycles (MIN_SPACING = 2, the RTL's documented minimum), much closer
than in the system (one step per PWM period, >= 64 cycles), so that 100 000 steps run in seconds.

Inputs are driven and outputs read at falling edges (the DUT is posedge-only); idle stretches are
skipped with one Timer each (the clock runs in the simulator).
"""

from __future__ import annotations

import os

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge
from cocotb.utils import get_sim_time

from golden.fpga.diff_cic import M_MAX, Y_BITS, DiffCic, cic_m
from golden.testvectors import diff_cic as testvectors
from pulse_monitor import HighMonitor, cycles, seeded_rng

PERIOD_NS = 10
LATENCY = 4             # rtl/hfi_diff_cic.v localparam LATENCY (in_valid -> out_valid)
MIN_SPACING = 2         # minimum in_valid spacing of the RTL (documented in its header)
OUT_NAMES = ("q_a", "q_b", "e_a", "e_b")
ZERO = (0, 0, 0, 0)


def _outputs(dut) -> tuple[int, int, int, int]:
    return (dut.q_a.value.to_signed(), dut.q_b.value.to_signed(), dut.e_a.value.to_signed(),
            dut.e_b.value.to_signed())


class Seq:
    """A timed stimulus with its golden results: items appended in time order, each ``gap`` cycles after
    the previous one.

    * ``step(gap, i_alpha, i_beta, plus, cic_m)``: an in_valid strobe (``gap`` >= MIN_SPACING after the
      previous step, >= 1 after a reset);
    * ``reset(gap, cycles, strobe)``: ``rst`` high for ``cycles`` cycles, optionally with in_valid and
      random inputs in them (ignored); steps whose in_valid is fewer than LATENCY cycles before the
      reset's first cycle are aborted.
    """

    def __init__(self, rng, model: DiffCic | None = None, out: tuple = ZERO):
        self.rng = rng
        self.model = model or DiffCic()
        self.cycle = 0
        self.last_step = -100
        self.drive: dict[int, dict] = {}        # cycle -> signal values
        self.checks: dict[int, list] = {}       # cycle -> [(label, expected out_valid, expected outputs)]
        self.expected_high: set[int] = set()
        self.out = out                          # outputs of the last completed step (golden)
        self.results: list[tuple] = []          # golden result of every step (aborted ones included)
        self.n_steps = 0
        self.n_aborted = 0
        self.n_resets = 0

    def _at(self, gap: int) -> dict:
        self.cycle += gap
        return self.drive.setdefault(self.cycle, {})

    def step(self, gap: int, i_alpha: int, i_beta: int, plus: int, cic_m_reg: int, label: str = "") -> None:
        assert gap >= 1 and self.cycle + gap - self.last_step >= MIN_SPACING, "steps closer than MIN_SPACING"
        d = self._at(gap)
        assert "rst" not in d
        d.update(in_valid=1, i_alpha=i_alpha, i_beta=i_beta, plus=plus, cic_m=cic_m_reg)
        exp = self.model.step(i_alpha, i_beta, bool(plus), cic_m_reg)
        name = f"step {self.n_steps} at cycle {self.cycle} {label}"
        info = f"(i_alpha, i_beta, plus, cic_m) = {(i_alpha, i_beta, plus, cic_m_reg)}"
        self.checks.setdefault(self.cycle + LATENCY - 1, []).append((f"{name} (held before)", 0, self.out))
        self.checks.setdefault(self.cycle + LATENCY, []).append((f"{name} {info}", 1, exp))
        self.expected_high.add(self.cycle + LATENCY)
        self.out = exp
        self.results.append(exp)
        self.last_step = self.cycle
        self.n_steps += 1

    def reset(self, gap: int, cycles: int, strobe: bool = False) -> None:
        assert gap >= 1 and cycles >= 1
        first = self.cycle + gap
        # rst sampled in cycle `first`: what was registered before stays visible in that cycle, every
        # later check (of a step in flight, or its hold check) and out_valid pulse is gone.
        aborted = {c for c in self.expected_high if c > first}
        self.n_aborted += len(aborted)
        self.expected_high -= aborted
        self.checks = {c: v for c, v in self.checks.items() if c <= first}
        junk = self.rng.integers(-32768, 32768, (cycles, 2)).tolist()
        for k in range(cycles):
            d = self._at(gap if k == 0 else 1)
            d["rst"] = 1
            if strobe:                          # an in_valid during reset is ignored
                d.update(in_valid=1, i_alpha=junk[k][0], i_beta=junk[k][1], plus=1, cic_m=k % 256)
        self.checks.setdefault(self.cycle + 1, []).append((f"reset ending at cycle {self.cycle}", 0, ZERO))
        self.model = DiffCic()
        self.out = ZERO
        self.last_step = self.cycle - MIN_SPACING + 1   # the next step may come in the cycle after rst
        self.n_resets += 1

    async def run(self, dut, label: str) -> None:
        """Drive the items from the current falling edge (cycle 0), check every step and the out_valid
        pulse set; ends at a falling edge, with the outputs of the last step held."""
        rng = self.rng
        end = max(list(self.drive) + list(self.checks)) + 2
        for c in sorted(self.drive):            # the cycle after an item: idle, random other inputs
            if c + 1 not in self.drive:
                self.drive[c + 1] = {"idle": True}
        n_idle = sum(1 for v in self.drive.values() if "idle" in v)
        junk = iter(np.stack([rng.integers(-32768, 32768, n_idle), rng.integers(-32768, 32768, n_idle),
                              rng.integers(0, 2, n_idle), rng.integers(0, 256, n_idle)], axis=1).tolist())
        t0 = get_sim_time(unit="ns")
        mon = HighMonitor(dut, t0, "out_valid")
        events = sorted(set(self.drive) | set(self.checks))
        now = 0
        for c in events:
            if c > now:
                await cycles(c - now)
                now = c
            for name, valid, exp in self.checks.get(c, ()):
                got = _outputs(dut)
                assert int(dut.out_valid.value) == valid, f"{label}: {name}: out_valid = {1 - valid}"
                assert got == exp, (f"{label}: {name}: RTL {dict(zip(OUT_NAMES, got))}, "
                                    f"golden {dict(zip(OUT_NAMES, exp))}")
            d = self.drive.get(c)
            if d is None:
                continue
            if "idle" in d:
                j = next(junk)
                dut.in_valid.value = 0
                dut.rst.value = 0
                dut.i_alpha.value = j[0]
                dut.i_beta.value = j[1]
                dut.plus.value = j[2]
                dut.cic_m.value = j[3]
                continue
            dut.rst.value = d.get("rst", 0)
            dut.in_valid.value = d.get("in_valid", 0)
            if "i_alpha" in d:
                dut.i_alpha.value = d["i_alpha"]
                dut.i_beta.value = d["i_beta"]
                dut.plus.value = d["plus"]
                dut.cic_m.value = d["cic_m"]
        if end > now:
            await cycles(end - now)
        high = mon.stop()
        assert high == self.expected_high, (
            f"{label}: out_valid high in unexpected cycles {sorted(high - self.expected_high)[:10]}, "
            f"missing in {sorted(self.expected_high - high)[:10]} (cycles from the sequence start)")
        assert _outputs(dut) == self.out, f"{label}: outputs at the end {_outputs(dut)}, golden {self.out}"


async def _start(dut):
    """Clock, idle inputs, two reset cycles; returns at a falling edge with rst released."""
    Clock(dut.clk, PERIOD_NS, unit="ns").start()
    dut.rst.value = 1
    for name in ("in_valid", "i_alpha", "i_beta", "plus", "cic_m"):
        getattr(dut, name).value = 0
    await FallingEdge(dut.clk)
    await FallingEdge(dut.clk)
    dut.rst.value = 0
    assert _outputs(dut) == ZERO and int(dut.out_valid.value) == 0, "outputs not cleared by reset"


def _gaps(rng, n: int) -> list[int]:
    """Step spacings: MIN_SPACING (back to back, 50 %) or MIN_SPACING + 1 .. 6."""
    g = rng.integers(MIN_SPACING + 1, 7, n)
    g[rng.random(n) < 0.5] = MIN_SPACING
    return g.tolist()


def _add(seq: Seq, steps, gaps, label: str = "") -> list[tuple]:
    """Append ``steps`` with ``gaps``; returns their golden results."""
    first = len(seq.results)
    for k, (st, g) in enumerate(zip(steps, gaps)):
        seq.step(g, *st, label=f"{label} {k}")
    return seq.results[first:]


def _rate_changes(steps: list) -> tuple[list[int], int]:
    """The effective rate of each step and how often it changes."""
    ms = [cic_m(s[3]) for s in steps]
    return ms, sum(1 for a, b in zip(ms, ms[1:]) if a != b)


def _rate_coverage(steps: list, n: int) -> bool:
    """Whether ``steps`` change the effective rate more than ``n // 1000`` times with 2 kept in more than 40 % of
    them (the random test's coverage)."""
    ms, restarts = _rate_changes(steps)
    return restarts > n // 1000 and ms.count(2) > 0.4 * len(ms)


@cocotb.test()
async def random_steps(dut):
    """HFI_RANDOM_N random steps (currents with many -32768 / 32767, random plus, CIC_M mostly 2 with
    random u8 writes at random steps), and on until they change the rate more than HFI_RANDOM_N / 1000 times
    with 2 in more than 40 % of them, at most 20 times as long (at the 2 000 steps of Icarus in `make test` 91
    of 3 000 seeds changed it twice or less: the check, per run, failed 3 % of correct runs); every output of
    every step compared with the golden model."""
    rng = seeded_rng()
    n = int(os.environ["HFI_RANDOM_N"])
    steps = testvectors.random_steps(rng, n)
    while not _rate_coverage(steps, n) and len(steps) < 20 * n:
        steps += testvectors.random_steps(rng, max(n // 4, 1))
    await _start(dut)
    seq = Seq(rng)
    res = _add(seq, steps, _gaps(rng, len(steps)), "(random)")
    await seq.run(dut, "random")
    _, restarts = _rate_changes(steps)
    writes = sum(1 for a, b in zip(steps, steps[1:]) if a[3] != b[3])
    ext = sum(1 for s in steps for i in s[:2] if i in (-32768, 32767))
    cocotb.log.info("%d steps, %d CIC_M writes (%d rate changes), %d extreme currents, max |q| %d, "
                    "max |e| %d", len(steps), writes, restarts, ext, max(abs(x) for r in res for x in r[:2]),
                    max(abs(x) for r in res for x in r[2:]))
    assert _rate_coverage(steps, n), "the random CIC_M does not change as intended"


@cocotb.test()
async def full_scale(dut):
    """Full-scale inputs at M = 16: the envelope held at +-65535 for 40 steps then swapped (q reaches
    +-1048560, 16 LSB inside s21; comb outputs +-131070), then long runs of alternating extremes with
    plus = 1 at M = 16, 15 and 1. In this comb-first form the wrapping integrator always holds the exact
    moving sum (which lies in s21), so its wrap never changes a value: checked against the unwrapped sum
    of the last M envelopes."""
    rng = seeded_rng()
    await _start(dut)
    seq = Seq(rng)
    runs = [("full-scale swing M = 16", testvectors.full_scale_runs(16)),
            ("full-scale swing M = 15", testvectors.full_scale_runs(15, repeats=2)),
            ("alternating extremes M = 16", testvectors.alternating_extremes(16, 3000)),
            ("alternating extremes M = 15", testvectors.alternating_extremes(15, 3000)),
            ("alternating extremes M = 1", testvectors.alternating_extremes(1, 200)),
            ("full-scale swing M = 16 again", testvectors.full_scale_runs(16, repeats=2))]
    for name, steps in runs:
        res = _add(seq, steps, _gaps(rng, len(steps)), f"({name})")
        m = cic_m(steps[0][3])
        # The unwrapped moving sum of the last M envelopes (each run starts with a rate change or at
        # M = 16 after the same M: compare only from the M-th step of the run on).
        for k in range(m - 1, len(res)):
            for ch in (0, 1):
                true_sum = sum(res[j][2 + ch] for j in range(k - m + 1, k + 1))
                assert res[k][ch] == true_sum, (name, k, ch, res[k][ch], true_sum)
    allq = [x for r in seq.results for x in r[:2]]
    lim = M_MAX * 65535
    assert max(allq) == lim and min(allq) == -lim and lim < 1 << (Y_BITS - 1), (max(allq), min(allq))
    await seq.run(dut, "full scale")


@cocotb.test()
async def directed(dut):
    """First steps after reset (the first only fills p), rate changes 2 -> 5 -> 16 -> 1 -> 0 -> 255 -> 17
    -> 16 -> 3 (outputs right after each), plus = 0 runs (the envelope holds), CIC_M writes between
    steps, reset in the middle of a run, reset in every cycle of a step in flight, in_valid during reset,
    outputs held for long idle stretches."""
    rng = seeded_rng()
    await _start(dut)
    seq = Seq(rng)

    # The first step after reset only fills p (plus = 1, yet e = 0 and q = 0); the second differences.
    r = _add(seq, [(-32768, 32767, 1, 2), (32767, -32768, 1, 2), (0, 0, 1, 2), (100, -100, 0, 2)],
             [1, 3, 2, 2], "(first steps)")
    assert r[0] == ZERO and r[1] == (65535, -65535, 65535, -65535) and r[2][2:] == (-32767, 32768), r
    assert r[3][2:] == r[2][2:], r

    # Rate changes with the outputs right after each: the change step restarts the filter.
    steps = testvectors.rate_changes(rng)
    res = _add(seq, steps, _gaps(rng, len(steps)), "(rate changes)")
    for k in range(1, len(steps)):
        if cic_m(steps[k][3]) != cic_m(steps[k - 1][3]):
            assert res[k][:2] == res[k][2:], ("q after a rate change is the new e alone", k, res[k])

    # plus = 0 runs: e holds, q settles at M * e.
    steps = testvectors.plus_zero_runs(rng, cic_m=5)
    res = _add(seq, steps, _gaps(rng, len(steps)), "(plus = 0 runs)")
    held = [k for k in range(1, len(steps)) if not steps[k][2]]
    assert all(res[k][2:] == res[k - 1][2:] for k in held)
    assert sum(1 for k in held if res[k][:2] == (5 * res[k][2], 5 * res[k][3])) > 50

    # Reset in the middle of a run (rst for 1 and 3 cycles, the second with in_valid held high in it),
    # then the first steps again.
    for n_rst, strobe in ((1, False), (3, True)):
        _add(seq, testvectors.rate_changes(rng, per_rate=5)[:20], _gaps(rng, 20), "(before a reset)")
        seq.reset(LATENCY + 3, n_rst, strobe)
        r = _add(seq, [(1000, -1000, 1, 7), (-1000, 1000, 1, 7), (5, 5, 1, 7)], [1, 2, 5], "(after a reset)")
        assert r[0] == ZERO and r[1] == (-2000, 2000, -2000, 2000), r

    # Reset in every cycle of a step in flight (and in its in_valid cycle): no out_valid for it, outputs
    # 0, the next step is the first after reset.
    for rst_at in range(0, LATENCY + 2):
        _add(seq, [(1234, -4321, 1, 3), (-30000, 30000, 1, 3)], [6, 3], f"(rst {rst_at} after the next)")
        if rst_at == 0:
            seq.reset(MIN_SPACING, 1, strobe=False)
            seq.drive[seq.cycle].update(in_valid=1, i_alpha=7, i_beta=7, plus=1, cic_m=9)
        else:
            seq.reset(rst_at, 1)
        r = _add(seq, [(10, 20, 1, 3), (20, 10, 1, 3)], [1, 2], f"(after a reset {rst_at} after a step)")
        assert r == [ZERO, (10, -10, 10, -10)], r

    # CIC_M changes between steps without a step (only the in_valid cycle's value counts: the idle
    # cycles of Seq drive random cic_m anyway), a long idle stretch (outputs held).
    _add(seq, [(500, 600, 1, 4)] * 3 + [(-500, -600, 1, 4)], [3, 2, 2, 2], "(held)")
    await seq.run(dut, "directed")
    held_out = seq.out
    dut.cic_m.value = 200
    dut.i_alpha.value = 32767
    await cycles(300)
    assert _outputs(dut) == held_out and int(dut.out_valid.value) == 0, "outputs not held when idle"
    cocotb.log.info("directed: %d steps, %d aborted by %d resets", seq.n_steps, seq.n_aborted, seq.n_resets)
