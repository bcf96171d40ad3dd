"""cocotb side of the hfi_dsp safety tests (see test_dsp_safety.py): overcurrent trip, watchdog,
the STO and DESAT pins (spec 3.8), the register lock (SAFETY_LOCK) and the frozen ADC channels (WIN_ADC, spec 3.13).

The ADC model returns mid-scale codes (0 A) except for one conversion (index HFI_TRIP_INDEX) whose
phase-a current exceeds OC_LIMIT (frozen_adc_channels: the noisy and stuck codes of test_dsp_safety.py's
FROZEN_PLAN). Gate edges and sampling instants come from the Verilog recorders.
Cycle numbering: "cycle k" is the clock period in which the testbench's ``tick`` reads k (gates.txt
records "k mask" when the pins show ``mask`` in cycle k and something else in cycle k - 1). A pin
driven by the testbench at the falling edge inside cycle k is first sampled by the rising edge that
ends cycle k; the spec's 3-clock latency then means: all gate pins 0 from cycle k + 3 on.
Every test that runs windows also runs tb_hfi_dsp's window-copy check (tb_dsp_replay.window_copy_check, checked at
its end): no register of golden.regmap.WINDOW_COPY (WIN_FAULT and WIN_ADC among them, which change here) changes
in the clock of a window_tog flip or the 64 after it, and window_tog flipped at least once.
"""

from __future__ import annotations

import functools
import os

import cocotb
import numpy as np
from cocotb.triggers import ClockCycles, FallingEdge, ReadOnly, RisingEdge, current_gpi_trigger, with_timeout

from dsp_bench import start as bench_start
from golden import regmap as rm
from golden.fpga.adc_frozen import frozen_lanes
from golden.fpga.carrier import window_of
from golden.fpga.overcurrent import fault_delay, gate_off_delay
from golden.regmap import WIN_ADC_FROZEN_A_MASK, WIN_ADC_FROZEN_B_MASK
from tb_dsp_replay import CONVST_LATENCY, GATE_LATENCY, WINDOW_COPY_MASK, window_copy_check

H = rm.PWM_HALF_VALUE_RESET
P = 2 * H
TRIP_BUDGET = 200
"""Issue 4: all gates off within 2 us (200 clocks at 100 MHz) of the sampling instant."""
ADC_BITS = int(os.environ["HFI_ADC_BITS"])
"""The ADC resolution test_dsp_safety.py builds tb_hfi_dsp with (its ADC_BITS parameter; 12 there)."""
IRQ_LATENCY = 400
"""hfi_dsp's default IRQ_LATENCY: WINDOW_COUNT and WIN_FAULT take window k's values this many ticks after its
boundary (hfi/soc_platform.py has the same)."""
READ_MARGIN = 20
"""Ticks after that copy at which the testbench reads a window's WIN_FAULT (the bus read takes a few clocks)."""


D_FAULT = fault_delay(ADC_BITS)
"""Ticks from a tripping sample's sampling instant t_s to the first tick STATUS.FAULT_OC reads 1: WIN_FAULT.OC of
window k (boundary tick B = (k+1)*P + H/2) is 1 iff t_s + D_FAULT <= B (golden.fpga.overcurrent, where the pipeline
is counted: the sample strobe, hfi_adc_if, hfi_adc_scale, hfi_overcurrent's register, hfi_safety's latch)."""
D_GATE = gate_off_delay(ADC_BITS)
"""Ticks from t_s to the first tick the plant sees all gates off (golden ticks: the pins' clock minus GATE_LATENCY, as
tb_dsp_replay aligns the gate edges; the kill clears the gate output register directly, bypassing the gate
generator's register that GATE_LATENCY counts: D_FAULT - 1)."""
FAULT_TO_GATES_OFF = 1
"""Clocks from a latched fault (kill) to all gate pins 0: the gate output register (hfi_safety)."""
TICK_TO_CYCLE = GATE_LATENCY - 2
"""Tick t of the carrier is testbench cycle t + TICK_TO_CYCLE (the registered timing reset): the pin
latency less the gate generator's and the output register."""


def s(addr_name: str) -> int:
    return rm.REGISTERS[addr_name]["addr"]


async def start(dut):
    """dsp_bench.start with tb_hfi_dsp's window-copy check on (its counters restart with the reset)."""
    dut.win_copy_mask.value = WINDOW_COPY_MASK
    return await bench_start(dut)


def window_copy_checked(test):
    """The test, then tb_hfi_dsp's window-copy check over all of it."""
    @functools.wraps(test)
    async def run(dut):
        await test(dut)
        flips, hold_min = window_copy_check(dut, where=f"{test.__name__}: ")
        cocotb.log.info(f"window copy: {flips} window_tog flips; the fewest clocks from one to the next change of a "
                        f"copied register: {hold_min}")
    return run


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


def boundary(k: int, half: int = H) -> int:
    """The boundary tick that ends window k (spec 2.1: window k = [k*P + H/2, (k+1)*P + H/2))."""
    return (k + 1) * 2 * half + half // 2


async def window_fault(dut, axi, k: int, half: int = H, name: str = "WIN_FAULT") -> int:
    """WIN_FAULT (or another window result, ``name``) as the firmware reads it for window k: after its copy
    (IRQ_LATENCY after the boundary, with WINDOW_COUNT = k + 2: window -1 is the first) and before the next
    boundary."""
    await wait_tick(dut, boundary(k, half) + IRQ_LATENCY + READ_MARGIN)
    count, resp = await axi.read(s("WINDOW_COUNT"))
    assert resp == 0 and count == k + 2, f"window {k}: WINDOW_COUNT {count}"
    value, resp = await axi.read(s(name))
    assert resp == 0 and int(dut.tick.value) < boundary(k + 1, half), f"window {k}: read of {name} too late"
    return value


def expect_window_faults(reads: dict[int, int], t_trip: int, clear: int | None = None, half: int = H) -> None:
    """The rule of spec 3.7 on the WIN_FAULT reads {window: value}: OC is 1 in window k iff t_trip + D_FAULT <= the
    boundary tick of k (and the clear, STATUS.FAULT_OC 0 from about tick ``clear``, came after that boundary);
    the other bits 0 (no watchdog, STO or DESAT fault)."""
    for k, value in sorted(reads.items()):
        b = boundary(k, half)
        oc = int(t_trip + D_FAULT <= b and (clear is None or b < clear))
        assert value == rm.pack("WIN_FAULT", OC=oc), \
            f"window {k} (boundary {b}, trip sample {t_trip} + D_FAULT {D_FAULT}): WIN_FAULT {value:#x}, OC {oc}"


@cocotb.test()
@window_copy_checked
async def overcurrent_trip_latch_and_clear(dut):
    """The sample of conversion HFI_TRIP_INDEX (tick 77 700, window 3) trips: all gates off exactly D_GATE ticks
    after its sampling instant, STATUS.FAULT_OC latched; WIN_FAULT.OC is 0 in windows 0 to 2, 1 from window 3 (the
    boundary rule, spec 3.7) while the fault is latched, and 0 again from the first window whose boundary follows
    the FAULT_CLEAR; WIN_FAULT changes IRQ_LATENCY after a boundary, not at it."""
    trip_index = int(os.environ["HFI_TRIP_INDEX"])
    axi = await start(dut)
    await axi.write(s("OC_LIMIT"), rm.pack("OC_LIMIT", VALUE=int(os.environ["HFI_OC_LIMIT"])))
    await axi.write(s("IRQ_ENABLE"), rm.pack("IRQ_ENABLE", WINDOW=1))
    await axi.write(s("CTRL"), rm.pack("CTRL", ENABLE=1, INJ_EN=1))
    await commit(axi, 3000)
    await with_timeout(RisingEdge(dut.irq), 2 * P * 10, "ns")    # window -1 ends
    await axi.write(s("IRQ_STATUS"), rm.pack("IRQ_STATUS", WINDOW=1))
    assert await axi.read(s("WIN_FAULT")) == (0, 0), "WIN_FAULT of window -1"
    await wait_tick(dut, P + 100)                   # ENABLE applies at the bottom of period 1
    st = await status(axi)
    assert st["OUTPUTS_ON"] == 1 and st["FAULT_OC"] == 0, st
    trip_window = (trip_index * 100 - H // 2) // P  # the window of the trip sample (about trip_index * OS_TICKS)
    assert trip_window == 3 and boundary(trip_window - 1) + IRQ_LATENCY + 300 < trip_index * 100, trip_window
    reads = {k: await window_fault(dut, axi, k) for k in range(trip_window)}
    # run past the trip sample (index trip_index, about trip_index * OS_TICKS ticks after reset)
    await wait_tick(dut, trip_index * 100 + 2000)
    st = await status(axi)
    assert st["FAULT_OC"] == 1 and st["OUTPUTS_ON"] == 0, f"no overcurrent fault latched: {st}"
    assert int(dut.gate.value) == 0, "gates on after the trip"
    # after the boundary that ends the trip window, before the copy: WIN_FAULT still shows the window before
    await wait_tick(dut, boundary(trip_window) + IRQ_LATENCY // 2)
    assert (await status(axi))["FAULT_OC"] == 1
    assert await axi.read(s("WIN_FAULT")) == (0, 0), "WIN_FAULT changed before IRQ_LATENCY after the boundary"
    # stays latched across windows (STATUS and every window's WIN_FAULT)
    for k in range(trip_window, trip_window + 3):
        reads[k] = await window_fault(dut, axi, k)
    assert (await status(axi))["FAULT_OC"] == 1 and int(dut.gate.value) == 0
    # FAULT_CLEAR in mid-window: STATUS clears at once, WIN_FAULT keeps the last window's 1 until its next copy
    clear_window = trip_window + 3
    await wait_tick(dut, boundary(clear_window - 1) + P // 2)
    await axi.write(s("CTRL"), rm.pack("CTRL", ENABLE=1, INJ_EN=1, FAULT_CLEAR=1))
    clear_tick = int(dut.tick.value)
    assert (await status(axi))["FAULT_OC"] == 0
    assert await axi.read(s("WIN_FAULT")) == (rm.pack("WIN_FAULT", OC=1), 0), "WIN_FAULT before the next copy"
    for k in range(clear_window, clear_window + 2):
        reads[k] = await window_fault(dut, axi, k)
    assert (await status(axi))["OUTPUTS_ON"] == 1
    dut.flush.value = 1
    await ClockCycles(dut.clk, 2)

    gates, convst = records()
    t_trip = int(convst[trip_index])
    on_before = gates[gates[:, 0] <= t_trip]
    assert on_before.size and on_before[-1, 1] != 0, "gates were not switching before the trip sample"
    off = gates[(gates[:, 0] > t_trip) & (gates[:, 1] == 0)]
    assert off.size, "gates never went off after the trip sample"
    t_off = int(off[0, 0]) - GATE_LATENCY           # golden tick of the first tick with all gates off
    latency = t_off - t_trip
    cocotb.log.info(f"overcurrent: sample at tick {t_trip}, all gates off from tick {t_off}: {latency} ticks = "
                    f"{latency * 10} ns after the sampling instant (D_GATE {D_GATE}, D_FAULT {D_FAULT})")
    assert latency == D_GATE, f"trip took {latency} ticks, D_GATE = {D_GATE}"
    assert D_GATE <= TRIP_BUDGET, f"D_GATE {D_GATE} ticks > the 2 us budget ({TRIP_BUDGET} ticks)"
    # the gates were on (some mask) up to the tick before: the trip cut them, not a switching edge
    assert gates[gates[:, 0] - GATE_LATENCY < t_off][-1, 1] != 0
    expect_window_faults(reads, t_trip, clear_tick)
    assert [reads[k] >> rm.WIN_FAULT_OC_LSB & 1 for k in sorted(reads)] == [0, 0, 0, 1, 1, 1, 0, 0], reads
    # no gate turned on between the trip and the clear
    between = gates[(gates[:, 0] > off[0, 0]) & (gates[:, 0] <= clear_tick)]
    assert not between.size, f"gate activity while the fault was latched: {between[:5]}"
    # after the clear the gates resume at a carrier bottom (plus the dead time)
    resumed = gates[gates[:, 0] > clear_tick]
    assert resumed.size, "gates did not resume after FAULT_CLEAR"
    dead = rm.DEAD_TICKS_VALUE_RESET
    first_on = int(resumed[0, 0]) - GATE_LATENCY    # golden tick of the first turn-on
    assert (first_on - dead) % P == 0, f"gates resumed at tick {first_on}, not a bottom + dead time"


@cocotb.test()
@window_copy_checked
async def overcurrent_window_boundary(dut):
    """The boundary rule of WIN_FAULT (spec 3.7) on both sides: PWM_HALF (HFI_HALF, set while the timing is held)
    puts the boundary tick B that ends window 3 at phase H/2 = 5000 + D_FAULT - HFI_BOUNDARY_OFFSET, and the
    over-limit conversion HFI_TRIP_INDEX is the OS sample at phase 5000 of period 4, so t_s + D_FAULT = B +
    HFI_BOUNDARY_OFFSET: offset 0, STATUS.FAULT_OC reads 1 from the boundary tick itself and window 3's
    WIN_FAULT.OC is 1; offset 1, one tick later, and the fault first shows in window 4. Gates off D_GATE ticks
    after t_s in both."""
    trip_index = int(os.environ["HFI_TRIP_INDEX"])
    half = int(os.environ["HFI_HALF"])
    offset = int(os.environ["HFI_BOUNDARY_OFFSET"])
    dut.hold.value = 1                              # configure before tick 0 (hfi_dsp's run = 0)
    axi = await start(dut)
    for name, value in (("PWM_HALF", half), ("CW_ANGLE_STEP", round(2**30 / half)),
                        ("RECIP_H", round(2**32 / half)), ("OC_LIMIT", int(os.environ["HFI_OC_LIMIT"]))):
        await axi.write(s(name), rm.pack(name, VALUE=value))
    await axi.write(s("CTRL"), rm.pack("CTRL", ENABLE=1, INJ_EN=1))
    await commit(axi, 3000)                         # committed at the first boundary
    await ClockCycles(dut.clk, 20)                  # the carrier's H*STEP product (docs/rtl.md)
    assert int(dut.tick.value) == 0, "the timing ran while held"
    dut.hold.value = 0
    k = 3                                           # the window whose end the trip straddles
    reads = {j: await window_fault(dut, axi, j, half) for j in range(k - 1, k + 2)}
    st = await status(axi)
    assert st["FAULT_OC"] == 1 and st["OUTPUTS_ON"] == 0, f"no overcurrent fault latched: {st}"
    dut.flush.value = 1
    await ClockCycles(dut.clk, 2)

    gates, convst = records()
    t_trip = int(convst[trip_index])
    assert t_trip + D_FAULT - boundary(k, half) == offset, \
        f"trip sample at tick {t_trip}: t_s + D_FAULT - B = {t_trip + D_FAULT - boundary(k, half)}, not {offset}"
    off = gates[(gates[:, 0] > t_trip) & (gates[:, 1] == 0)]
    assert off.size, "gates never went off after the trip sample"
    assert gates[gates[:, 0] <= t_trip][-1, 1] != 0, "gates were not switching before the trip sample"
    assert int(off[0, 0]) - GATE_LATENCY - t_trip == D_GATE, f"gates off in cycle {off[0, 0]}, trip sample {t_trip}"
    expect_window_faults(reads, t_trip, half=half)
    assert [reads[j] for j in sorted(reads)] == [0, int(offset <= 0), 1], reads
    cocotb.log.info(f"window boundary: H {half}, trip sample at tick {t_trip}, t_s + D_FAULT = B(window {k}) + "
                    f"{offset}: WIN_FAULT of windows {k - 1}..{k + 1} = {[reads[j] for j in sorted(reads)]}")


# ---------------------------------------------------------------------- frozen ADC channels (spec 3.13)
def frozen_rule(convst: np.ndarray, half: int) -> dict[int, tuple[int, int]]:
    """WIN_ADC (spec 3.13) by the golden model (golden.fpga.adc_frozen.frozen_lanes of each window's conversions,
    golden.fpga.carrier.window_of of their sampling ticks), from the sampling instants the testbench recorded and
    the codes the ADC model returned (codes.hex, in conversion order): {window: (FROZEN_A, FROZEN_B)}."""
    with open("codes.hex") as f:
        words = [int(line, 16) for line in f.read().split()]
    assert len(words) >= convst.size, f"{convst.size} conversions, codes.hex has {len(words)}"
    mask = (1 << ADC_BITS) - 1
    lanes = np.array([[w >> 16 & mask, w & mask] for w in words[:convst.size]], dtype=np.int64).reshape(-1, 2)
    window = window_of(convst, half)                 # the ticks before the first boundary are window -1
    flags = {}
    for k in np.unique(window):
        word = frozen_lanes(lanes[window == k, 0], lanes[window == k, 1])
        flags[int(k)] = (int(bool(word & WIN_ADC_FROZEN_A_MASK)), int(bool(word & WIN_ADC_FROZEN_B_MASK)))
    return flags


@cocotb.test()
@window_copy_checked
async def frozen_adc_channels(dut):
    """WIN_ADC (spec 3.13) per window: the ADC model returns noise (mid-scale + -4 codes) on both current lanes
    except where test_dsp_safety.py's FROZEN_PLAN holds one code: from the first or the second conversion of a
    window, to the last or the one before it, in OS (200 conversions per window), in DS (windows HFI_FROZEN_DS:
    the carrier top and bottom) and with one conversion per window (OS_TICKS = HFI_FROZEN_OS_TICKS). PWM_HALF
    (HFI_HALF, set while the timing is held) puts the boundary on the OS grid (the conversion at the boundary tick
    is the first of the new window) or 20 ticks after a conversion (whose codes arrive after the boundary). Each
    window's read equals the rule computed here from the recorded sampling instants and the codes, and that equals
    the plan's intent (HFI_FROZEN_EXPECT); the copy comes IRQ_LATENCY after the boundary, not at it."""
    half = int(os.environ["HFI_HALF"])
    ds_first, ds_last = (int(k) for k in os.environ["HFI_FROZEN_DS"].split(","))
    plan = (e.split(":") for e in os.environ["HFI_FROZEN_EXPECT"].split(";"))
    intent = {int(k): (int(v[0]), int(v[1])) for k, v in plan}
    dut.hold.value = 1                              # configure before tick 0 (hfi_dsp's run = 0)
    axi = await start(dut)
    for name, value in (("PWM_HALF", half), ("CW_ANGLE_STEP", round(2**30 / half)), ("RECIP_H", round(2**32 / half))):
        await axi.write(s(name), rm.pack(name, VALUE=value))
    await ClockCycles(dut.clk, 20)                  # the carrier's H*STEP product (docs/rtl.md)
    assert await axi.read(s("WIN_ADC")) == (0, 0), "WIN_ADC after reset"
    dut.hold.value = 0
    reads = {}
    for k in sorted(intent):
        if k == 3:                                  # between the boundary and the copy: still window 2's
            await wait_tick(dut, boundary(k, half) + IRQ_LATENCY // 2)
            assert await axi.read(s("WIN_ADC")) == (reads[k - 1], 0), "WIN_ADC changed before the copy"
        reads[k] = await window_fault(dut, axi, k, half, "WIN_ADC")
        if k == ds_first - 2:                       # in window ds_first - 1: DS from its end (spec 2.2)
            await axi.write(s("CTRL"), rm.pack("CTRL", ADC_MODE=1))
        if k == ds_last - 1:                        # in window ds_last, before its bottom: OS, one per period
            await axi.write(s("OS_TICKS"), rm.pack("OS_TICKS", VALUE=int(os.environ["HFI_FROZEN_OS_TICKS"])))
            await axi.write(s("CTRL"), rm.pack("CTRL", ADC_MODE=0))
            assert int(dut.tick.value) < (ds_last + 1) * 2 * half, "OS_TICKS written after the bottom"
    dut.flush.value = 1
    await ClockCycles(dut.clk, 2)

    _, convst = records()
    rule = frozen_rule(convst, half)
    got = {k: (v >> rm.WIN_ADC_FROZEN_A_LSB & 1, v >> rm.WIN_ADC_FROZEN_B_LSB & 1) for k, v in reads.items()}
    assert all(v == rm.pack("WIN_ADC", FROZEN_A=a, FROZEN_B=b) for v, (a, b) in zip(reads.values(), got.values()))
    per_window = {k: int(np.count_nonzero((convst - half // 2) // (2 * half) == k)) for k in sorted(reads)}
    cocotb.log.info(f"frozen ADC channels, H {half}: conversions per window {per_window}, WIN_ADC {got}")
    for k in sorted(reads):
        assert got[k] == rule[k], f"window {k} ({per_window[k]} conversions): WIN_ADC (A, B) {got[k]}, rule {rule[k]}"
        assert rule[k] == intent[k], f"window {k}: the rule gives {rule[k]}, the plan meant {intent[k]}"
    assert per_window[ds_first] == per_window[ds_last] == 2 and per_window[ds_last + 1] == 1, per_window
    # the conversions next to the boundary between windows 3 and 4 (the grid of the case)
    b = boundary(3, half)
    on_grid = (half // 2) % rm.OS_TICKS_VALUE_RESET == 0
    last, first = convst[convst < b][-1], convst[convst >= b][0]
    assert (last - b, first - b) == ((-100, 0) if on_grid else (-20, 80)), f"B {b}: conversions at {last}, {first}"


@cocotb.test()
@window_copy_checked
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
    # the boundary counts the missed window (1 clock), the fault latches (1 clock), then the kill clears
    # the gate output register directly (1 clock; hfi_safety, spec 3.8: fault latch -> gates off in
    # the next clock, no longer through the gate generator's register)
    assert off.size and int(off[0, 0]) - t_fire == TICK_TO_CYCLE + 2 + FAULT_TO_GATES_OFF, \
        f"gates not off right after the watchdog: {off[:3]} (boundary tick {t_fire})"
    cocotb.log.info(f"watchdog: fault at boundary tick {t_fire}, gates off in cycle {int(off[0, 0])}")


# ---------------------------------------------------------------------- STO / DESAT (spec 3.8)
PIN_TO_GATES_OFF = 3
"""Clocks from the pin (sampled at the end of its cycle) to all gate pins 0: two synchronizer flops
and the gate output register (docs/spec.md 3.8)."""
PINS = {"sto": ("FAULT_STO", "STO_ACTIVE"), "desat": ("FAULT_DESAT", "DESAT_ACTIVE")}


async def sample(dut) -> tuple[int, int, int]:
    """The next cycle's (tick, gate, drive_allowed), read in ReadOnly after its rising edge."""
    await RisingEdge(dut.clk)
    await ReadOnly()
    return int(dut.tick.value), int(dut.gate.value), int(dut.drive_allowed.value)


async def drive_pin(dut, pin: str, value: int) -> int:
    """Set a safety pin at the falling edge inside the current cycle; returns that cycle's tick."""
    if not isinstance(current_gpi_trigger(), ReadOnly):
        await ReadOnly()
    tick = int(dut.tick.value)
    await FallingEdge(dut.clk)
    getattr(dut, pin).value = value
    return tick


async def wait_phase(dut, phase: int) -> None:
    """Advance to the next cycle whose tick is ``phase`` (mod P) - a point well away from bottoms."""
    now = int(dut.tick.value)
    target = now - now % P + phase
    if target <= now + 5:
        target += P
    await wait_tick(dut, target)


async def pin_fault_case(dut, pin: str) -> None:
    fault_f, active_f = PINS[pin]
    other_fault = PINS["desat" if pin == "sto" else "sto"][0]
    rng = np.random.default_rng(int(os.environ["HFI_SEED"]))
    axi = await start(dut)
    ctrl = rm.pack("CTRL", ENABLE=1, INJ_EN=1)
    ctrl_clear = rm.pack("CTRL", ENABLE=1, INJ_EN=1, FAULT_CLEAR=1)
    await axi.write(s("CTRL"), ctrl)
    await commit(axi, 3000)
    await wait_tick(dut, P + 100)                   # ENABLE applies at the bottom of period 1
    st = await status(axi)
    assert st["OUTPUTS_ON"] == 1 and st[fault_f] == 0 and st[active_f] == 0, st
    assert int(dut.drive_allowed.value) == 1

    # ---- the pin at a random instant while the gates switch ----------------------------------------
    await ClockCycles(dut.clk, int(rng.integers(1, 2 * P)))
    while True:
        tick, gate, allowed = await sample(dut)
        if gate != 0 and allowed == 1:
            break
    k = await drive_pin(dut, pin, 1)
    assert k == tick
    seen = [await sample(dut) for _ in range(8)]    # cycles k + 1 .. k + 8
    assert [t for t, _, _ in seen] == list(range(k + 1, k + 9))
    for t, g, a in seen:
        if t - k >= PIN_TO_GATES_OFF:
            assert g == 0, f"{pin} raised in cycle {k}: gate pins {g:#08b} in cycle {t} (> {PIN_TO_GATES_OFF} clocks)"
        # drive_allowed follows the synchronized pin (2 clocks), combinationally
        assert a == int(t - k < 2), f"{pin} raised in cycle {k}: drive_allowed {a} in cycle {t}"
    cocotb.log.info(f"{pin}: raised in cycle {k} (gates {gate:#08b}), pins after: {[(t, g) for t, g, _ in seen]}")
    st = await status(axi)
    assert st[fault_f] == 1 and st[active_f] == 1 and st["OUTPUTS_ON"] == 0, f"{pin} held: {st}"
    assert st[other_fault] == 0 and st["FAULT_OC"] == 0 and st["FAULT_WDT"] == 0, f"{pin} held: {st}"

    # ---- FAULT_CLEAR while the pin is held: stays latched, gates off -------------------------------
    await ClockCycles(dut.clk, int(rng.integers(1, P)))
    await axi.write(s("CTRL"), ctrl_clear)
    st = await status(axi)
    assert st[fault_f] == 1 and st[active_f] == 1 and st["OUTPUTS_ON"] == 0, f"clear while {pin} held: {st}"
    await ClockCycles(dut.clk, 2 * P)               # two carrier bottoms with ENABLE = 1
    await ReadOnly()
    assert int(dut.gate.value) == 0 and int(dut.drive_allowed.value) == 0
    st = await status(axi)
    assert st[fault_f] == 1 and st["OUTPUTS_ON"] == 0, f"{pin} held, 2 periods after the clear: {st}"

    # ---- release: still latched until the firmware re-arms -----------------------------------------
    await RisingEdge(dut.clk)
    release = await drive_pin(dut, pin, 0)
    await ClockCycles(dut.clk, 5)
    st = await status(axi)
    assert st[fault_f] == 1 and st[active_f] == 0 and st["OUTPUTS_ON"] == 0, f"{pin} released: {st}"
    await ClockCycles(dut.clk, P)
    await ReadOnly()
    assert int(dut.gate.value) == 0 and int(dut.drive_allowed.value) == 0, f"{pin} released, not re-armed"

    # ---- re-arm: FAULT_CLEAR in mid-period; gates back from the next bottom on ---------------------
    await wait_phase(dut, P // 2)
    await axi.write(s("CTRL"), ctrl_clear)
    clear_tick = int(dut.tick.value)
    st = await status(axi)
    assert st[fault_f] == 0 and st[active_f] == 0, f"{pin} re-armed: {st}"
    assert int(dut.drive_allowed.value) == 1
    bottom = (clear_tick // P + 1) * P              # the first bottom after the clear
    await wait_tick(dut, bottom - 10)
    assert (await status(axi))["OUTPUTS_ON"] == 0, "OUTPUTS_ON before the bottom after the re-arm"
    await wait_tick(dut, bottom + P)
    st = await status(axi)
    assert st["OUTPUTS_ON"] == 1 and st[fault_f] == 0, f"{pin}: outputs not back after the re-arm: {st}"
    dut.flush.value = 1
    await ClockCycles(dut.clk, 2)

    gates, _ = records()
    t_off = k + PIN_TO_GATES_OFF
    before = gates[gates[:, 0] <= t_off]
    assert before.size and before[-1, 1] == 0, f"gates not off in cycle {t_off}: {before[-3:]}"
    assert (gates[(gates[:, 0] > k - 2 * P) & (gates[:, 0] <= k), 1] != 0).any(), "gates were not switching"
    between = gates[(gates[:, 0] > t_off) & (gates[:, 0] <= clear_tick)]
    assert not between.size, f"gate activity while {pin} was held or latched: {between[:5]}"
    resumed = gates[gates[:, 0] > clear_tick]
    assert resumed.size, f"gates did not resume after the re-arm (clear in cycle {clear_tick})"
    dead = rm.DEAD_TICKS_VALUE_RESET
    first_on = int(resumed[0, 0]) - GATE_LATENCY    # golden tick of the first turn-on
    assert first_on - dead == bottom, (f"{pin}: gates resumed at tick {first_on}, expected the bottom {bottom} "
                                       f"after the clear (cycle {clear_tick}) + dead time {dead}")
    cocotb.log.info(f"{pin}: raised in cycle {k}, released in {release}, re-armed in {clear_tick}, "
                    f"gates back at tick {first_on} = bottom {bottom} + {dead}")


@cocotb.test()
@window_copy_checked
async def sto_safe_torque_off(dut):
    await pin_fault_case(dut, "sto")


@cocotb.test()
@window_copy_checked
async def desat_driver_fault(dut):
    await pin_fault_case(dut, "desat")


# ---------------------------------------------------------------------- SAFETY_LOCK
@cocotb.test()
async def safety_lock_freezes_registers(dut):       # runs no window: no window-copy check
    """After SAFETY_LOCK.LOCK = 1 writes to the LOCKED_BY registers answer SLVERR and change nothing
    (full and partial byte strobes); the lock cannot be cleared by software; other registers stay
    writable."""
    rng = np.random.default_rng(int(os.environ["HFI_SEED"]))
    axi = await start(dut)
    locked = list(dict.fromkeys(reg for reg, _field in rm.LOCKED_BY))
    (lock_reg, lock_field), = set(rm.LOCKED_BY.values())
    assert locked, "LOCKED_BY is empty"

    async def read(name):
        value, resp = await axi.read(s(name))
        assert resp == 0, f"read {name}: RRESP {resp}"
        return value

    # writable before the lock (values the gate generator and the watchdog accept)
    config = {"DEAD_TICKS": 420, "OC_LIMIT": 30000, "WDT_PERIODS": 0}
    for name in locked:
        v = config.get(name, 0x1234)
        assert await axi.write(s(name), rm.pack(name, VALUE=v)) == 0, f"{name} before the lock"
        assert await read(name) == v
    # lock at a random moment
    await ClockCycles(dut.clk, int(rng.integers(1, 1000)))
    assert await axi.write(s(lock_reg), rm.pack(lock_reg, **{lock_field: 1})) == 0
    assert rm.unpack(lock_reg, await read(lock_reg))[lock_field] == 1
    for name in locked:
        before = await read(name)
        for data, strb in [(0xFFFFFFFF, 0xF), (0, 0xF), (0x0000FFFF, 0x1), (0x0000FFFF, 0x2), (0xABCD, 0x0),
                           (int(rng.integers(0, 1 << 32)), int(rng.integers(1, 16)))]:
            assert await axi.write(s(name), data, strb) == 2, f"write {name} <= {data:#x} strb {strb:#x} while locked"
            assert await read(name) == before, f"{name} changed while locked"
    # software cannot unlock
    for data in (0, 0xFFFFFFFE):
        assert await axi.write(s(lock_reg), data) == 0
        assert rm.unpack(lock_reg, await read(lock_reg))[lock_field] == 1
    assert await axi.write(s(locked[0]), 0) == 2
    # other registers still writable
    for name, value in (("SPEED_REF", int(rng.integers(0, 1 << 32))), ("BLANK_TICKS", rm.pack("BLANK_TICKS", VALUE=77)),
                        ("IRQ_ENABLE", rm.pack("IRQ_ENABLE", WINDOW=1)),
                        ("I_REF", rm.pack("I_REF", I_D=-123, I_Q=456)),
                        ("CTRL", rm.pack("CTRL", ENABLE=1, INJ_EN=1))):
        assert name not in locked
        assert await axi.write(s(name), value) == 0, f"{name} not writable after the lock"
        assert await read(name) == value, f"{name} read back"
    assert (await status(axi))["FAULT_OC"] == 0
