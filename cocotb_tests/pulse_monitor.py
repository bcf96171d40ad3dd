"""Helpers shared by the block testbenches: the seeded random generator, whole-cycle waits and a monitor
of a one-bit pulse output (tb_adc_scale.py, tb_park.py, tb_demodulator.py, tb_overcurrent.py,
tb_diff_cic.py)."""

from __future__ import annotations

import os

import cocotb
import numpy as np
from cocotb.triggers import FallingEdge, RisingEdge, Timer
from cocotb.utils import get_sim_time

PERIOD_NS = 10
"""Clock period of the testbenches [ns]."""


def seeded_rng() -> np.random.Generator:
    """The random generator of a test run: seeded with ``HFI_SEED`` (set by cocotb_tests/hdl_runner.py,
    logged with ``HFI_RANDOM_N``)."""
    seed = int(os.environ["HFI_SEED"])
    cocotb.log.info("HFI_SEED=%d HFI_RANDOM_N=%s", seed, os.environ["HFI_RANDOM_N"])
    return np.random.default_rng(seed)


async def cycles(n: int) -> None:
    """Advance ``n`` clock cycles (falling edge to falling edge; never mixed with edge triggers, whose
    order against a Timer expiring at the same instant is not defined)."""
    await Timer(n * PERIOD_NS, unit="ns")


class HighMonitor:
    """Records the cycles in which the one-bit output ``signal`` (default ``done``) is 1, relative to ``t0``
    (the falling edge of cycle 0), from its value changes (no per-cycle callback)."""

    def __init__(self, dut, t0_ns: float, signal: str = "done"):
        self.t0 = t0_ns
        self.signal = signal
        self.intervals: list[list] = []
        self._task = cocotb.start_soon(self._run(getattr(dut, signal)))

    async def _run(self, sig):
        while True:
            await RisingEdge(sig)
            self.intervals.append([get_sim_time(unit="ns"), None])
            await FallingEdge(sig)
            self.intervals[-1][1] = get_sim_time(unit="ns")

    def stop(self) -> set[int]:
        """Stop monitoring; the set of cycles with the signal at 1 (high in cycle c: rose at or before the
        posedge t0 + c*P - P/2 that starts it, fell after)."""
        self._task.cancel()
        out = set()
        for rise, fall in self.intervals:
            assert fall is not None, f"{self.signal} still high at the end of the sequence"
            first = round((rise - self.t0 + PERIOD_NS / 2) / PERIOD_NS)
            last = round((fall - self.t0 + PERIOD_NS / 2) / PERIOD_NS) - 1
            out.update(range(first, last + 1))
        return out
