"""cocotb side of the hfi_dsp safety tests (see test_dsp_safety.py): overcurrent trip and watchdog.

The ADC model returns mid-scale codes (0 A) except for one conversion (index HFI_TRIP_INDEX) whose
phase-a current exceeds OC_LIMIT. Gate edges and sampling instants come from the Verilog recorders.
"""

from __future__ import annotations

import os

import cocotb
import numpy as np
from cocotb.triggers import ClockCycles, RisingEdge, with_timeout

from axil_driver import AxiLiteMaster
from golden import regmap as rm
from tb_dsp_replay import CONVST_LATENCY, GATE_LATENCY

H = rm.PWM_HALF_VALUE_RESET
P = 2 * H
TRIP_BUDGET = 200
"""Issue 4: all gates off within 2 us (200 clocks at 100 MHz) of the sampling instant."""


def s(addr_name: str) -> int:
    return rm.REGISTERS[addr_name]["addr"]


async def start(dut):
    axi = AxiLiteMaster(dut, "s_axil", dut.clk)
    dut.flush.value = 0
    dut.rst.value = 1
    await ClockCycles(dut.clk, 20)
    dut.rst.value = 0
    return axi


async def status(axi) -> dict:
    value, resp = await axi.read(s("STATUS"))
    assert resp == 0
    return rm.unpack("STATUS", value)


async def commit(axi, v_h: int) -> None:
    await axi.write(s("V_H"), rm.pack("V_H", VALUE=v_h))
    await axi.write(s("COMMIT"), rm.pack("COMMIT", GO=1))


def records(dut_flush_done=True):
    gates = np.loadtxt("gates.txt", dtype=np.int64, ndmin=2)
    convst = np.loadtxt("convst.txt", dtype=np.int64, ndmin=1) - CONVST_LATENCY   # sampling ticks
    return gates, convst


async def wait_tick(dut, tick: int) -> None:
    now = int(dut.tick.value)
    assert tick >= now, f"tick {tick} already passed ({now})"
    await ClockCycles(dut.clk, tick - now)


@cocotb.test()
async def overcurrent_trip_latch_and_clear(dut):
    trip_index = int(os.environ["HFI_TRIP_INDEX"])
    axi = await start(dut)
    await axi.write(s("OC_LIMIT"), rm.pack("OC_LIMIT", VALUE=int(os.environ["HFI_OC_LIMIT"])))
    await axi.write(s("IRQ_ENABLE"), rm.pack("IRQ_ENABLE", WINDOW=1))
    await axi.write(s("CTRL"), rm.pack("CTRL", ENABLE=1, INJ_EN=1))
    await commit(axi, 3000)
    await with_timeout(RisingEdge(dut.irq), 2 * P * 10, "ns")    # window -1 ends
    await axi.write(s("IRQ_STATUS"), rm.pack("IRQ_STATUS", WINDOW=1))
    await wait_tick(dut, P + 100)                   # ENABLE applies at the bottom of period 1
    st = await status(axi)
    assert st["OUTPUTS_ON"] == 1 and st["FAULT_OC"] == 0, st
    # run past the trip sample (index trip_index, about trip_index * OS_TICKS ticks after reset)
    await wait_tick(dut, trip_index * 100 + 2000)
    st = await status(axi)
    assert st["FAULT_OC"] == 1 and st["OUTPUTS_ON"] == 0, f"no overcurrent fault latched: {st}"
    assert int(dut.gate.value) == 0, "gates on after the trip"
    # stays latched across windows; a FAULT_CLEAR releases it at the next bottom
    await ClockCycles(dut.clk, 3 * P)
    assert (await status(axi))["FAULT_OC"] == 1 and int(dut.gate.value) == 0
    await axi.write(s("CTRL"), rm.pack("CTRL", ENABLE=1, INJ_EN=1, FAULT_CLEAR=1))
    clear_tick = int(dut.tick.value)
    assert (await status(axi))["FAULT_OC"] == 0
    await ClockCycles(dut.clk, 2 * P)
    assert (await status(axi))["OUTPUTS_ON"] == 1
    dut.flush.value = 1
    await ClockCycles(dut.clk, 2)

    gates, convst = records()
    t_trip = int(convst[trip_index])
    on_before = gates[gates[:, 0] <= t_trip]
    assert on_before.size and on_before[-1, 1] != 0, "gates were not switching before the trip sample"
    off = gates[(gates[:, 0] > t_trip) & (gates[:, 1] == 0)]
    assert off.size, "gates never went off after the trip sample"
    t_off = int(off[0, 0])                          # first cycle with all gates off
    latency = t_off - t_trip
    cocotb.log.info(f"overcurrent: sample at tick {t_trip}, all gates off in cycle {t_off}: "
                    f"{latency} clocks = {latency * 10} ns after the sampling instant")
    assert latency <= TRIP_BUDGET, f"trip took {latency} clocks > {TRIP_BUDGET}"
    # no gate turned on between the trip and the clear
    between = gates[(gates[:, 0] > t_off) & (gates[:, 0] <= clear_tick)]
    assert not between.size, f"gate activity while the fault was latched: {between[:5]}"
    # after the clear the gates resume at a carrier bottom (plus the dead time)
    resumed = gates[gates[:, 0] > clear_tick]
    assert resumed.size, "gates did not resume after FAULT_CLEAR"
    dead = rm.DEAD_TICKS_VALUE_RESET
    first_on = int(resumed[0, 0]) - GATE_LATENCY    # golden tick of the first turn-on
    assert (first_on - dead) % P == 0, f"gates resumed at tick {first_on}, not a bottom + dead time"


@cocotb.test()
async def watchdog_turns_gates_off(dut):
    periods = 3
    axi = await start(dut)
    await axi.write(s("WDT_PERIODS"), rm.pack("WDT_PERIODS", VALUE=periods))
    await axi.write(s("OC_LIMIT"), rm.pack("OC_LIMIT", VALUE=32767))
    await axi.write(s("CTRL"), rm.pack("CTRL", ENABLE=1, INJ_EN=1))
    await commit(axi, 3000)                         # committed at the boundary of window 0
    boundary = [k * P + H // 2 for k in range(8)]
    # keep committing until window 2, then stop: boundaries 3, 4, 5 find no commit
    for k in (1, 2):
        await wait_tick(dut, boundary[k] - 1000)
        await commit(axi, 3000)
    await wait_tick(dut, boundary[3 + periods - 1] - 5)
    st = await status(axi)
    assert st["FAULT_WDT"] == 0 and st["OUTPUTS_ON"] == 1, f"watchdog fired early: {st}"
    await wait_tick(dut, boundary[3 + periods - 1] + 10)
    st = await status(axi)
    assert st["FAULT_WDT"] == 1 and st["OUTPUTS_ON"] == 0, f"watchdog did not fire: {st}"
    late, _ = await axi.read(s("LATE_COUNT"))
    assert late == periods, f"LATE_COUNT {late}, expected {periods} (the boundaries without a commit)"
    dut.flush.value = 1
    await ClockCycles(dut.clk, 2)
    gates, _ = records()
    t_fire = boundary[3 + periods - 1]
    off = gates[(gates[:, 0] > t_fire - 1) & (gates[:, 1] == 0)]
    # the boundary counts the missed window (1 clock), the fault latches (1 clock), then GATE_LATENCY
    assert off.size and int(off[0, 0]) - t_fire == 2 + GATE_LATENCY, f"gates not off right after the watchdog: {off[:3]}"
    cocotb.log.info(f"watchdog: fault at boundary tick {t_fire}, gates off in cycle {int(off[0, 0])}")
