"""The part every cocotb bench of an iterative unit shares (tb_cordic.py, tb_vector.py, tb_flux_lut.py): the seed
and random count from the environment (``HFI_SEED``, ``HFI_RANDOM_N``: hdl_runner sets them), the clock cycles
counted from sample point to sample point, and the start/done protocol's flags (``busy``, ``done``) checked
cycle by cycle. A bench subclasses it and adds its unit's inputs, outputs and golden model."""

from __future__ import annotations

import os

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, Timer


class UnitBench:
    """``dut``: the toplevel (clock, reset, the unit's inputs); ``unit``: the instance whose ``busy`` and ``done``
    are checked (the toplevel itself by default); ``period_ns``: the clock period; ``info``: added to the log line
    that names the seed."""

    def __init__(self, dut, period_ns: int, unit=None, info: str = ""):
        self.dut = dut
        self.unit = dut if unit is None else unit
        self.period_ns = period_ns
        self.seed = int(os.environ["HFI_SEED"])
        self.random_n = int(os.environ["HFI_RANDOM_N"])
        self.rng = np.random.default_rng(self.seed)
        self.cycle = 0  # sample points since the bench started
        self._timers: dict[int, Timer] = {}
        cocotb.log.info(f"HFI_SEED={self.seed} HFI_RANDOM_N={self.random_n} {info}".rstrip())

    async def power_up(self, idle) -> None:
        """Start the clock, hold the reset while ``idle()`` drives the inputs to rest, then move to the first
        sample point (1 ns after a falling edge: never at an edge), release the reset after two cycles, and
        check the unit idle one cycle later."""
        dut = self.dut
        Clock(dut.clk, self.period_ns, unit="ns", impl="gpi").start()
        dut.rst.value = 1
        idle()
        await FallingEdge(dut.clk)
        await Timer(1, unit="ns")  # the first sample point
        await self.cycles(2)
        dut.rst.value = 0
        await self.cycles(1)
        self.expect_idle("after reset")

    async def cycles(self, n: int) -> None:
        """Advance ``n`` >= 1 clock cycles (from one sample point to another)."""
        t = self._timers.get(n)
        if t is None:
            t = self._timers[n] = Timer(n * self.period_ns, unit="ns")
        await t
        self.cycle += n

    def flags(self) -> tuple[int, int]:
        return int(self.unit.busy.value), int(self.unit.done.value)

    def expect_flags(self, busy: int, done: int, what: str) -> None:
        got = self.flags()
        assert got == (busy, done), f"cycle {self.cycle}, {what}: (busy, done) = {got}, expected {(busy, done)}"

    def expect_idle(self, what: str) -> None:
        self.expect_flags(0, 0, what)

    async def start_then_reset(self, k: int, start, release, what: str) -> None:
        """A start (``start()`` drives its inputs), then a reset ``k`` cycles after the start cycle (``k = 0``: in
        it; ``release()`` drops the start after its cycle), the unit busy up to the reset; then idle right after
        the reset is released."""
        start()
        if k == 0:
            self.dut.rst.value = 1
        await self.cycles(1)
        release()
        if k:
            if k > 1:
                await self.cycles(k - 1)
            self.expect_flags(1, 0, f"{what}: busy before the reset")
            self.dut.rst.value = 1
            await self.cycles(1)
        self.dut.rst.value = 0
        self.expect_idle(f"{what}: right after the reset")
