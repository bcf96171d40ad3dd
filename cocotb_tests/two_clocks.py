"""Two unrelated clocks for the clock-domain crossing testbenches (tb_cdc_bus.py, tb_win_copy.py): random clock pairs,
a bench base class with the clocks, the seeds and the error collection.

Clocks are cocotb GPI clocks with even periods in ps (50 % duty). :meth:`TwoClockBench.start_clocks` stops both
right after a falling edge and restarts them with new periods and first rising edges, so a test walks through
clock pairs between its traffic.
"""

from __future__ import annotations

import math
import os
from collections import Counter

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.simtime import get_sim_time
from cocotb.triggers import FallingEdge, Timer

PERIOD_MIN_PS = 3_000
PERIOD_MAX_PS = 97_000
RATIO_MAX = 30.0
"""Random clock pairs: periods 3..97 ns (even ps), period ratio Ts/Tm from 1/30 to 30."""
RESET_SLOW_CLOCKS = 20
"""rst is held for at least this many clocks of the slower clock (hfi_soc's contract)."""


def now() -> int:
    """Simulation time in ps."""
    return int(round(get_sim_time("ps")))


def clock_pairs(rng, n: int) -> list[tuple[int, int, int, int]]:
    """n random (Ts, Tm, first s edge, first m edge) in ps: one pair of equal periods and one of periods
    2..40 ps apart, the rest with log(Ts/Tm) stratified over [-log 30, log 30] (so both extremes and ratios
    near 1 occur); random phases; shuffled."""
    def even(x: float) -> int:
        return max(PERIOD_MIN_PS, int(round(x / 2)) * 2)

    pairs = []
    t = even(rng.integers(PERIOD_MIN_PS, PERIOD_MAX_PS))
    pairs.append((t, t))
    t = even(rng.integers(PERIOD_MIN_PS, PERIOD_MAX_PS - 40))
    pairs.append((t, t + 2 * int(rng.integers(1, 21))))
    k = max(0, n - len(pairs))
    for i in range(k):
        u = (i + rng.random()) / k
        ratio = RATIO_MAX ** (2 * u - 1)              # Ts / Tm
        r = max(ratio, 1 / ratio)
        slow = even(rng.integers(math.ceil(PERIOD_MIN_PS * r), PERIOD_MAX_PS + 1))
        fast = even(slow / r)
        pairs.append((slow, fast) if ratio >= 1 else (fast, slow))
    order = rng.permutation(len(pairs))
    return [(ts, tm, int(rng.integers(0, ts)), int(rng.integers(0, tm)))
            for ts, tm in (pairs[i] for i in order)][:n]


class TwoClockBench:
    """The clocks ``s_clk`` and ``m_clk`` of a wrapper, the test's seeds and its error messages.

    ``HFI_SEED`` and ``HFI_RANDOM_N`` come from the environment (hdl_runner sets them); ``pairs_env`` names the
    variable that overrides ``n_pairs`` (the random clock pairs of the test). Three random streams per test,
    ``numpy.random.SeedSequence([HFI_SEED, test_id])``: :attr:`rng` (traffic), :attr:`rng_aux` (the other side's
    model) and :attr:`rng_clk` (clock pairs)."""

    def __init__(self, dut, name: str, test_id: int, pairs_env: str, n_pairs: int):
        self.dut = dut
        self.name = name
        self.seed = int(os.environ["HFI_SEED"])
        self.n_random = int(os.environ["HFI_RANDOM_N"])
        self.n_pairs = int(os.environ.get(pairs_env, n_pairs))
        streams = np.random.SeedSequence([self.seed, test_id]).spawn(3)
        self.rng, self.rng_aux, self.rng_clk = (np.random.default_rng(s) for s in streams)
        cocotb.log.info(f"{name}: HFI_SEED={self.seed} HFI_RANDOM_N={self.n_random}")
        self.errors: list[str] = []
        self.where = ""               # the clock pair or setup, for messages
        self.current = None           # the access in flight, for messages (None or "": none)
        self.clk_s = self.clk_m = None
        self.ts = self.tm = None
        self.phase = (0, 0)
        self.stats = Counter()

    # ------------------------------------------------------------------ messages
    def fail(self, text: str) -> str:
        clocks = f"Ts={self.ts} ps, Tm={self.tm} ps, first edges s@{self.phase[0]} m@{self.phase[1]} ps"
        cur = f", {self.current}" if self.current else ""
        return f"{self.name} [{self.where}{cur}; {clocks}] t={now()} ps (HFI_SEED={self.seed}): {text}"

    def error(self, text: str) -> None:
        """An error found by a background monitor; the test raises the first one (check_errors)."""
        self.errors.append(self.fail(text))

    def check_errors(self) -> None:
        assert not self.errors, self.errors[0] + (f" (and {len(self.errors) - 1} more)"
                                                   if len(self.errors) > 1 else "")

    # ------------------------------------------------------------------ clocks
    async def stop_clocks(self) -> None:
        """Stop both clocks right after a falling edge (both then low)."""
        if self.clk_s is not None:
            await FallingEdge(self.dut.s_clk)
            self.clk_s.stop()
        if self.clk_m is not None:
            await FallingEdge(self.dut.m_clk)
            self.clk_m.stop()
        self.clk_s = self.clk_m = None

    async def start_clocks(self, ts: int, tm: int, off_s: int, off_m: int) -> None:
        """Stop the clocks, then restart them with periods ts, tm (even ps): first rising edges off_s, off_m ps
        after the stop."""
        assert ts % 2 == 0 and tm % 2 == 0 and ts >= 2 and tm >= 2
        await self.stop_clocks()
        t = now()
        self.ts, self.tm = ts, tm
        self.phase = (t + off_s, t + off_m)
        self.clk_s = Clock(self.dut.s_clk, ts, unit="ps", impl="gpi")
        self.clk_m = Clock(self.dut.m_clk, tm, unit="ps", impl="gpi")
        elapsed = 0
        for off, clk in sorted([(off_s, self.clk_s), (off_m, self.clk_m)], key=lambda x: x[0]):
            if off > elapsed:
                await Timer(off - elapsed, unit="ps")
                elapsed = off
            clk.start(start_high=True)
