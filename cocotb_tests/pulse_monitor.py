"""Pulse monitor shared by the start/done testbenches (tb_adc_scale.py, tb_park.py)."""

from __future__ import annotations

import cocotb
from cocotb.triggers import FallingEdge, RisingEdge
from cocotb.utils import get_sim_time

PERIOD_NS = 10
"""Clock period of the testbenches [ns]."""


class HighMonitor:
    """Records the cycles in which ``done`` is 1, relative to ``t0`` (the falling edge of cycle 0), from
    its value changes (no per-cycle callback)."""

    def __init__(self, dut, t0_ns: float):
        self.t0 = t0_ns
        self.intervals: list[list] = []
        self._task = cocotb.start_soon(self._run(dut))

    async def _run(self, dut):
        while True:
            await RisingEdge(dut.done)
            self.intervals.append([get_sim_time(unit="ns"), None])
            await FallingEdge(dut.done)
            self.intervals[-1][1] = get_sim_time(unit="ns")

    def stop(self) -> set[int]:
        """Stop monitoring; the set of cycles with done = 1 (high in cycle c: rose at or before the
        posedge t0 + c*P - P/2 that starts it, fell after)."""
        self._task.cancel()
        out = set()
        for rise, fall in self.intervals:
            assert fall is not None, "done still high at the end of the sequence"
            first = round((rise - self.t0 + PERIOD_NS / 2) / PERIOD_NS)
            last = round((fall - self.t0 + PERIOD_NS / 2) / PERIOD_NS) - 1
            out.update(range(first, last + 1))
        return out
