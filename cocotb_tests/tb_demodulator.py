"""cocotb testbench of rtl/hfi_demodulator.v (run by cocotb_tests/test_demodulator.py, not by pytest).

Reference: golden.fpga.demodulator.demodulate (spec 3.4) of each window's accepted samples.

A test is a list of timed items (see :class:`Seq`): samples (``valid``, with a ``keep`` flag), latch
strobes and resets, each a number of cycles after the previous item. A latch closes the window of all
accepted samples before it; a sample in the same cycle as a latch (gap 0 after it) is the first sample
of the new window, as the spec says. Every latch is checked ``LATENCY`` cycles later: ``latched`` = 1
and all six outputs equal to the golden window result; a monitor records every cycle in which
``latched`` is high, which must be exactly the set of latch cycles + ``LATENCY`` (no spurious, lost or
stretched pulses). Cycles after a sample that carry no item drive ``valid = 0`` with random data
(ignored), blanked samples (``keep = 0``) carry random data too.

Inputs are driven and outputs read at falling edges (the DUT is posedge-only); idle stretches are
skipped with one Timer each (the clock runs in the simulator).
"""

from __future__ import annotations

import os

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, RisingEdge
from cocotb.utils import get_sim_time

from golden.fpga.demodulator import demodulate
from pulse_monitor import cycles, seeded_rng
from golden.testvectors import demodulator as testvectors

PERIOD_NS = 10
LATENCY = 2             # rtl/hfi_demodulator.v localparam LATENCY (latch -> latched)
OUT_NAMES = ("gamma", "gamma_d", "sum_id", "sum_iq", "wsum", "n_samples")


def _outputs(dut) -> tuple[int, ...]:
    return (dut.gamma.value.to_signed(), dut.gamma_d.value.to_signed(), dut.sum_id.value.to_signed(),
            dut.sum_iq.value.to_signed(), dut.wsum.value.to_signed(), dut.n_samples.value.to_unsigned())


def _golden(window) -> tuple[int, ...]:
    """Golden WindowResult of a list of accepted (i_d, i_q, w) samples, as the output tuple."""
    if window:
        d, q, w = (np.array(col, dtype=np.int64) for col in zip(*window))
    else:
        d = q = w = np.zeros(0, dtype=np.int64)
    r = demodulate(d, q, w)
    return r.gamma, r.gamma_d, r.sum_id, r.sum_iq, r.wsum, r.n_samples


class LatchedMonitor:
    """Records the cycles (relative to ``t0``, the falling edge of cycle 0) in which ``latched`` is 1."""

    def __init__(self, dut, t0_ns: float):
        self.t0 = t0_ns
        self.intervals: list[tuple[float, float | None]] = []
        self._task = cocotb.start_soon(self._run(dut))

    async def _run(self, dut):
        while True:
            await RisingEdge(dut.latched)
            self.intervals.append((get_sim_time(unit="ns"), None))
            await FallingEdge(dut.latched)
            self.intervals[-1] = (self.intervals[-1][0], get_sim_time(unit="ns"))

    def high_cycles(self) -> set[int]:
        """Cycle c is high if latched rose at or before its posedge (t0 + c*P - P/2) and fell after."""
        out = set()
        for rise, fall in self.intervals:
            assert fall is not None, "latched still high at the end of the test"
            first = round((rise - self.t0 + PERIOD_NS / 2) / PERIOD_NS)
            last = round((fall - self.t0 + PERIOD_NS / 2) / PERIOD_NS) - 1
            out.update(range(first, last + 1))
        return out


class Seq:
    """A timed stimulus: items appended in time order, each ``gap`` cycles after the previous one.

    * ``sample(gap, keep, i_d, i_q, w)``: a valid strobe (``gap`` 0 only right after a latch: the same
      cycle, first sample of the new window);
    * ``latch(gap)``: a window-boundary strobe (``gap`` >= 1);
    * ``reset(gap, cycles)``: ``rst`` high for ``cycles`` cycles (the window restarts after it; no
      latch may be pending, i.e. the previous latch is at least ``LATENCY`` cycles earlier).
    """

    def __init__(self, rng):
        self.rng = rng
        self.cycle = 0
        self.drive: dict[int, dict] = {}        # cycle -> signal values
        self.checks: dict[int, list] = {}       # cycle -> [(label, expected outputs or None)]
        self.expected_high: set[int] = set()
        self.window: list[tuple[int, int, int]] = []
        self.n_latches = 0
        self.n_samples = 0
        self.last = None                        # kind of the previous item
        self.last_latch = -10

    def _at(self, gap: int) -> dict:
        self.cycle += gap
        return self.drive.setdefault(self.cycle, {})

    def sample(self, gap: int, keep: int, i_d: int, i_q: int, w: int) -> None:
        assert gap >= 1 or (gap == 0 and self.last == "latch"), "gap 0 only for a sample in a latch cycle"
        d = self._at(gap)
        d.update(valid=1, keep=keep, i_d=i_d, i_q=i_q, w=w)
        self.n_samples += 1
        if keep:
            self.window.append((i_d, i_q, w))
        self.last = "sample"

    def latch(self, gap: int, label: str = "") -> None:
        assert gap >= 1
        self._at(gap)["latch"] = 1
        exp = _golden(self.window)
        self.window = []
        at = self.cycle + LATENCY
        self.checks.setdefault(at, []).append((f"latch {self.n_latches} at cycle {self.cycle} {label}", exp))
        self.expected_high.add(at)
        self.n_latches += 1
        self.last = "latch"
        self.last_latch = self.cycle

    def reset(self, gap: int, cycles: int) -> None:
        assert gap >= 1 and self.cycle + gap >= self.last_latch + LATENCY
        for k in range(cycles):
            self._at(gap if k == 0 else 1)["rst"] = 1
        self.window = []
        self.checks.setdefault(self.cycle + 1, []).append((f"reset ending at cycle {self.cycle}", (0,) * 6))
        self.last = "reset"

    async def run(self, dut, label: str) -> None:
        """Drive the items from the current falling edge (cycle 0), check every latch, then the
        ``latched`` pulse set; ends at a falling edge."""
        end = max(list(self.drive) + list(self.checks)) + LATENCY + 2
        rng = self.rng
        # Cycles after an item without one of their own: idle, with random data on the sample inputs.
        for c in sorted(self.drive):
            if c + 1 not in self.drive:
                self.drive[c + 1] = {"idle": True}
        n_idle = sum(1 for v in self.drive.values() if "idle" in v)
        junk = iter(rng.integers(-32768, 32768, (n_idle, 4)).tolist())
        t0 = get_sim_time(unit="ns")
        mon = LatchedMonitor(dut, t0)
        events = sorted(set(self.drive) | set(self.checks))
        now = 0
        for c in events:
            if c > now:
                await cycles(c - now)
                now = c
            for name, exp in self.checks.get(c, ()):
                got = _outputs(dut)
                if not name.startswith("reset"):
                    got_l = int(dut.latched.value)
                    assert got_l == 1, f"{label}: {name}: latched = 0 {LATENCY} cycles after the latch"
                assert got == exp, (f"{label}: {name}: RTL {dict(zip(OUT_NAMES, got))}, "
                                    f"golden {dict(zip(OUT_NAMES, exp))}")
            d = self.drive.get(c)
            if d is None:
                continue
            if "idle" in d:
                j = next(junk)
                dut.valid.value = 0
                dut.keep.value = j[0] & 1
                dut.i_d.value = j[1]
                dut.i_q.value = j[2]
                dut.w.value = j[3]
                dut.latch.value = 0
                dut.rst.value = 0
                continue
            dut.rst.value = d.get("rst", 0)
            dut.latch.value = d.get("latch", 0)
            dut.valid.value = d.get("valid", 0)
            if "i_d" in d:
                dut.keep.value = d["keep"]
                dut.i_d.value = d["i_d"]
                dut.i_q.value = d["i_q"]
                dut.w.value = d["w"]
        if end > now:
            await cycles(end - now)
        mon._task.cancel()
        high = mon.high_cycles()
        assert high == self.expected_high, (
            f"{label}: latched high in unexpected cycles {sorted(high - self.expected_high)[:10]}, "
            f"missing in {sorted(self.expected_high - high)[:10]}")


async def _start(dut):
    """Clock, idle inputs, two reset cycles; returns at a falling edge with rst released."""
    Clock(dut.clk, PERIOD_NS, unit="ns").start()
    dut.rst.value = 1
    for name in ("valid", "keep", "i_d", "i_q", "w", "latch"):
        getattr(dut, name).value = 0
    await FallingEdge(dut.clk)
    await FallingEdge(dut.clk)
    dut.rst.value = 0
    assert _outputs(dut) == (0,) * 6 and int(dut.latched.value) == 0, "outputs not cleared by reset"


def _gap(rng) -> int:
    """Cycles between items: mostly 1..3 (1 = back to back), sometimes longer (the system's 40+)."""
    r = rng.random()
    if r < 0.35:
        return 1
    if r < 0.7:
        return 2
    if r < 0.95:
        return int(rng.integers(3, 8))
    return int(rng.integers(8, 60))


@cocotb.test()
async def random_windows(dut):
    """Random windows of 0..300 samples with random keep flags and gaps until HFI_RANDOM_N accepted
    samples, latches alone or in the cycle of the next window's first sample."""
    rng = seeded_rng()
    n_target = int(os.environ["HFI_RANDOM_N"])
    await _start(dut)
    windows = testvectors.random_windows(rng, n_target)
    seq = Seq(rng)
    coincide = False
    for k, (keep, d, q, w) in enumerate(windows):
        for j in range(len(keep)):
            gap = 0 if (j == 0 and coincide) else _gap(rng)
            seq.sample(gap, keep[j], d[j], q[j], w[j])
        seq.latch(_gap(rng), f"(window {k}, {len(keep)} samples)")
        coincide = rng.random() < 0.3
    await seq.run(dut, "random")
    cocotb.log.info("%d windows, %d samples (%d accepted), %d latched, %d empty windows",
                    len(windows), seq.n_samples, sum(sum(win[0]) for win in windows), seq.n_latches,
                    sum(1 for win in windows if not win[0]))


async def _constant_window(dut, n: int, keep: int, i_d: int, i_q: int, w: int, latch_first: bool) -> None:
    """n back-to-back samples of one value (valid held high; one Timer), the first one in a latch cycle
    if ``latch_first``; returns at the falling edge after the last sample with valid = 0."""
    dut.valid.value = 1
    dut.keep.value = keep
    dut.i_d.value = i_d
    dut.i_q.value = i_q
    dut.w.value = w
    dut.latch.value = 1 if latch_first else 0
    await cycles(1)
    dut.latch.value = 0
    if n > 1:
        await cycles(n - 1)
    dut.valid.value = 0


async def _latch_and_check(dut, exp, label: str) -> None:
    """Latch in this cycle (no sample), check latched and the outputs LATENCY cycles later."""
    dut.latch.value = 1
    await cycles(1)
    dut.latch.value = 0
    for k in range(1, LATENCY):
        assert int(dut.latched.value) == 0, f"{label}: latched = 1 {k} cycles after the latch"
        await cycles(1)
    assert int(dut.latched.value) == 1, f"{label}: latched = 0 {LATENCY} cycles after the latch"
    got = _outputs(dut)
    assert got == exp, f"{label}: RTL {dict(zip(OUT_NAMES, got))}, golden {dict(zip(OUT_NAMES, exp))}"
    await cycles(1)
    assert int(dut.latched.value) == 0, f"{label}: latched longer than one cycle"


@cocotb.test()
async def long_windows(dut):
    """Windows at the specified maximum: 65534 samples of the largest products (+2^30 each, then
    -32767*32768 each); a window of 70000 small samples: N_SAMPLES saturates at 65535 while the sums
    go on (the accumulators stay far from their range)."""
    await _start(dut)
    for n, keep, i_d, i_q, w in testvectors.long_windows():
        await _constant_window(dut, n, keep, i_d, i_q, w, latch_first=False)
        exp = _golden([(i_d, i_q, w)] * n if keep else [])
        if n > 65535:
            assert exp[5] == 65535 and exp[2] == i_d * n, exp
        await _latch_and_check(dut, exp, f"{n} x (i_d, i_q, w) = {(i_d, i_q, w)}, keep {keep}")


# Timing of golden.testvectors.demodulator.directed_events(): the gap (cycles) before each event (0: a
# sample in the cycle of the preceding latch, the first sample of the new window; LATENCY before the
# second reset: no latch in flight), and the length of each reset (cycles).
DIRECTED_GAPS = (1, 1, 1, 1, 1, 0, 1, 0, 1, 1, 0, 1, 1, 1, 1, 2, 2, 2, 2, 2, 1, 1, 2, 1, LATENCY, 1)
DIRECTED_RESET_CYCLES = (1, 3)


@cocotb.test()
async def directed(dut):
    """Latch and valid in the same cycle, latch right after a sample (the product still in the
    pipeline), consecutive latches (empty windows), blanked samples in latch cycles, reset mid-window
    and reset with a latch in flight."""
    rng = seeded_rng()
    await _start(dut)
    seq = Seq(rng)
    events = testvectors.directed_events()
    assert len(events) == len(DIRECTED_GAPS), (len(events), len(DIRECTED_GAPS))
    reset_cycles = iter(DIRECTED_RESET_CYCLES)
    for ev, gap in zip(events, DIRECTED_GAPS):
        if ev[0] == "sample":
            seq.sample(gap, *ev[1:])
        elif ev[0] == "latch":
            seq.latch(gap, ev[1])
        else:
            seq.reset(gap, next(reset_cycles))
    await seq.run(dut, "directed")

    # Reset with a latch in flight: no latched pulse, outputs cleared.
    for rst_after in range(0, LATENCY):
        for _ in range(3):
            dut.valid.value = 1
            dut.keep.value = 1
            dut.i_d.value = 1000
            dut.i_q.value = -2000
            dut.w.value = 3000
            await cycles(1)
        dut.valid.value = 0
        dut.latch.value = 1
        await cycles(1)
        dut.latch.value = 0
        if rst_after:
            await cycles(rst_after)
        dut.rst.value = 1
        await cycles(1)
        dut.rst.value = 0
        for _ in range(LATENCY + 1):
            assert int(dut.latched.value) == 0, f"latched after a reset {rst_after} cycles after a latch"
            assert _outputs(dut) == (0,) * 6, f"outputs after a reset: {_outputs(dut)}"
            await cycles(1)
        await _latch_and_check(dut, _golden([]), f"empty window after the reset {rst_after} after a latch")
