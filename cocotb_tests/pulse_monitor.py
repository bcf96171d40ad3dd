"""Helpers shared by the block testbenches: the seeded random generator, whole-cycle waits, a monitor
of a one-bit pulse output (tb_adc_scale.py, tb_park.py, tb_demodulator.py, tb_overcurrent.py,
tb_diff_cic.py) and the overlapping start/done sequence of a fixed-latency pipeline (tb_adc_scale.py,
tb_park.py)."""

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


async def run_pipelined(dut, vectors, spacings, garbage, label: str, latency: int, drive, check) -> None:
    """One operation of a fixed-latency pipeline per vector: vector k starts in cycle ``sum(spacings[:k])``
    (``drive(1, v)``), ``drive(0, garbage[k])`` in the cycle after it (inputs that must not be sampled), and
    ``check(k, f"{label} {k}", v)`` reads the result ``latency`` cycles after the start; a :class:`HighMonitor`
    checks that ``done`` is high in exactly those cycles. Starts at the current falling edge, ends at one."""
    events: dict[int, list] = {}

    def at(cycle, fn):
        events.setdefault(cycle, []).append(fn)

    cycle = 0
    starts = []
    for k, v in enumerate(vectors):
        starts.append(cycle)
        at(cycle, lambda v=v: drive(1, v))
        at(cycle + 1, lambda g=garbage[k]: drive(0, g))
        at(cycle + latency, lambda k=k, v=v: check(k, f"{label} {k}", v))
        cycle += int(spacings[k])
    expected_high = {c + latency for c in starts}
    mon = HighMonitor(dut, get_sim_time(unit="ns"))
    now = 0
    for c in sorted(events):        # same-cycle events: the checks read registered outputs only
        if c > now:
            await cycles(c - now)
            now = c
        for fn in events[c]:
            fn()
    await cycles(latency + 2)      # ends at a falling edge, the last done over
    high = mon.stop()
    assert high == expected_high, (
        f"{label}: done high in unexpected cycles {sorted(high - expected_high)[:10]}, "
        f"missing in {sorted(expected_high - high)[:10]} (cycles from the first start)")
