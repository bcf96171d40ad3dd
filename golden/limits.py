"""Physical and hardware limits of scenario values (issue 19, item 6).

:func:`check_limits` refuses, with a message that names the value, the limit and the reason, every
scenario value that no real drive built from this design has: a trip current the current sensors
cannot measure, a sampling interval shorter than the ADC's conversion, a tick clock the hardware is
not built for, a switching frequency whose half period does not fit the carrier register, and every
value that ``golden/control_config.py`` would otherwise silently clamp, saturate or wrap when it turns
the scenario into register values and firmware integers. docs/scenario.md, "Physical and hardware
limits", lists every check with its limit and reason.

The hardware limits (registers, tick clock, ADC width) apply to the closed loop only (a scenario with
a ``[control]`` table): only there do the values become register values of the FPGA design. The
open-loop injection study (``golden/openloop.py``) drives the plant with an ideal float PWM at any
clock; it has its own condition (an integer carrier half period), checked here as well.

This module does not import :mod:`golden.scenario` (which calls it): ``reader`` is its ``_Reader``
(``get(path)``, ``error(path, message)``, ``values``, ``invalid``, ``has_table(section)``) and
``plant`` the complete plant parameter tree it built.
"""

from __future__ import annotations

import math

from golden.firmware.estimator import INJ_ROT, INJ_SQW_D, METHODS
from golden.fixed import to_fixed
from golden.fpga.adc_trigger import OS_MIN_DEFAULT
from golden.fpga.carrier import REGISTER_HALF_MIN
from golden.fpga.gate_generator import DEAD_MIN_DEFAULT
from golden.regmap import (BLANK_TICKS_VALUE_WIDTH, DEAD_TICKS_VALUE_WIDTH, DTC_GAIN_VALUE_WIDTH,
                           OS_TICKS_VALUE_WIDTH, PWM_HALF_VALUE_WIDTH)
from golden.units import format_quantity

TICK_HZ_MIN = 100e6
"""Slowest tick clock [Hz]. docs/soc.md: "The 100 MHz DSP clock is fixed by the spec (10 ns gate
resolution, 1 us sampling grid)"; both boards make at least 100 MHz (docs/boards.md: ULX3S 100 MHz,
Tang Nano 20K 100.286 MHz). The CPU runs at tick / CPU_CLOCK_DIVIDER (hfi/soc_platform.py: 2, 50 MHz),
the clock the firmware's cycle budget is measured and sized at (docs/soc.md, "Firmware budget": the
worst step already takes 27.5 % of a 200 us period at 50 MHz): a slower tick slows the CPU with it."""

TICK_HZ_MAX = 110e6
"""Fastest tick clock [Hz]. docs/rtl.md, "Timing": the tick clock is constrained at 100 MHz and the
design's timing target is a post-route Fmax of 110 MHz (10 % slack); no build is verified to close
above it (docs/boards.md: the ULX3S board build does not even reach 110 MHz at every seed)."""

HALF_MAX = (1 << PWM_HALF_VALUE_WIDTH) - 1
"""Largest carrier half period [ticks]: ``PWM_HALF`` is u16 (docs/registers.md, golden.regmap)."""

HALF_MIN = REGISTER_HALF_MIN
"""Smallest carrier half period [ticks]: the hardware runs a smaller ``PWM_HALF`` as 512 (docs/spec.md
2.1, golden.fpga.carrier.REGISTER_HALF_MIN: the period must exceed the sample pipeline and
IRQ_LATENCY). sim/plant_loop.cpp's PlantLoop::check (256..65535) is looser."""

ADC_BITS_MAX = 16
"""Widest ADC code: rtl/hfi_adc_if.v refuses ``ADC_BITS`` outside 1..16 at elaboration, the ADC code
is ``uB`` with B <= 16 (docs/spec.md 3, left-aligned to s16 by adc_scale, 3.1) and sim/plant_loop.cpp's
PlantLoop::check accepts 1..16 (the plant alone models up to 24 bits: open loop only)."""

CURRENT_FS_LSB = 1 << 15
"""The current format's full scale: 2^15 LSB = ``sensors.adc_range`` (docs/spec.md 3)."""

VOLTAGE_FS_LSB = 1 << 15
"""The voltage format's full scale: 2^15 LSB = ``inverter.V_dc`` (docs/spec.md 3)."""


def _q(value: float, unit: str) -> str:
    return format_quantity(value, unit)


def _n(count: int) -> str:
    """``"1 tick"``, ``"20 ticks"``."""
    return f"{count} tick{'' if count == 1 else 's'}"


def _plant_value(reader, path: str, value: float) -> float | None:
    """A plant value (from the scenario, the preset or the defaults), None when the scenario's was invalid."""
    return None if path in reader.invalid else value


def check_limits(reader, plant: dict) -> None:
    """Report every scenario value outside what the hardware and the physics allow.

    Parameters
    ----------
    reader : golden.scenario._Reader
        The scenario's converted values; problems are recorded with ``reader.error(path, message)``.
    plant : dict
        The complete plant parameter tree (``tick_hz``, ``sens``, ``inv``, ``mag``, ``mech``).
    """
    if not reader.has_table("control"):
        _check_openloop_half(reader, plant)
        return
    tick = _check_tick(reader, plant)
    if tick is not None:
        _check_pwm(reader, tick)
        _check_sampling(reader, tick)
    _check_adc_bits(reader, plant)
    i_range = _plant_value(reader, "sensors.adc_range", plant["sens"]["adc_range"])
    if i_range is not None:
        _check_currents(reader, plant, i_range, tick)
    v_dc = _plant_value(reader, "inverter.V_dc", plant["inv"]["V_dc"])
    if v_dc is not None:
        _check_voltages(reader, v_dc)
        _check_dc_link(reader, plant, v_dc)
    _check_rates(reader, plant)


# ---- open loop ------------------------------------------------------------------------------------
def _check_openloop_half(reader, plant: dict) -> None:
    """golden.openloop.PwmConfig.half: the open-loop PWM needs ``tick_hz / (2 f_sw)`` an integer >= 2."""
    f_sw, tick = reader.get("pwm.f_sw"), _plant_value(reader, "pwm.tick_hz", plant["tick_hz"])
    if f_sw is None or tick is None:
        return
    half = tick / (2 * f_sw)
    if abs(half - round(half)) > 1e-9 * half or round(half) < 2:
        reader.error("pwm.f_sw", f"{_q(f_sw, 'Hz')} gives a carrier half period of {half:.6g} ticks at "
                                 f"pwm.tick_hz = {_q(tick, 'Hz')}: the open-loop PWM (golden/openloop.py) "
                                 f"needs a whole number of ticks, at least 2 (f_sw = tick_hz / (2 n))")


# ---- clock and PWM --------------------------------------------------------------------------------
def _check_tick(reader, plant: dict) -> float | None:
    """The tick clock in the range the hardware is built and timed for; None if it is not."""
    tick = _plant_value(reader, "pwm.tick_hz", plant["tick_hz"])
    if tick is None:
        return None
    if TICK_HZ_MIN * (1 - 1e-9) <= tick <= TICK_HZ_MAX * (1 + 1e-9):
        return tick
    reader.error("pwm.tick_hz",
                 f"{_q(tick, 'Hz')} is outside the tick clocks the hardware supports, "
                 f"{_q(TICK_HZ_MIN, 'Hz')} to {_q(TICK_HZ_MAX, 'Hz')}: the spec fixes the tick at 100 MHz "
                 f"(the boards make 100 and 100.286 MHz, the CPU runs at half of it and its firmware "
                 f"budget is sized at 50 MHz), and the RTL's timing target is 110 MHz "
                 f"(docs/rtl.md, \"Timing\")")
    return None


def _ticks(seconds: float, tick: float) -> int | float:
    """A duration as control_config.py turns it into a register value: rounded to whole ticks; ``inf`` when the
    product is beyond a float (1.8e300 s: found by tests/test_scenario_fuzz.py), which every register check refuses."""
    ticks = seconds * tick
    return round(ticks) if math.isfinite(ticks) else math.inf


def _check_pwm(reader, tick: float) -> None:
    """The carrier half period in the PWM_HALF register, the dead time between DEAD_MIN and its register."""
    clock = f"pwm.tick_hz = {_q(tick, 'Hz')}"
    f_sw = reader.get("pwm.f_sw")
    if f_sw is not None:
        f_lo, f_hi = tick / (2 * HALF_MAX), tick / (2 * HALF_MIN)
        if not f_lo * (1 - 1e-9) <= f_sw <= f_hi * (1 + 1e-9):
            reader.error("pwm.f_sw",
                         f"{_q(f_sw, 'Hz')} gives a carrier half period of {tick / (2 * f_sw):.6g} ticks at "
                         f"{clock}, outside {HALF_MIN}..{HALF_MAX} (PWM_HALF is u16, and the hardware runs "
                         f"a half period below {HALF_MIN} as {HALF_MIN}: docs/spec.md 2.1): f_sw must be "
                         f"between {_q(f_lo, 'Hz')} and {_q(f_hi, 'Hz')} at this clock")
    dead = reader.get("pwm.dead_time")
    if dead is None:
        return
    ticks = _ticks(dead, tick)
    if ticks < DEAD_MIN_DEFAULT:
        reader.error("pwm.dead_time",
                     f"{_q(dead, 's')} is {_n(ticks)} at {clock}, below the gate generator's floor "
                     f"DEAD_MIN = {DEAD_MIN_DEFAULT} ticks ({_q(DEAD_MIN_DEFAULT / tick, 's')}), a synthesis "
                     f"parameter: the hardware would apply {_q(DEAD_MIN_DEFAULT / tick, 's')} "
                     f"(docs/spec.md 2.4)")
    elif ticks >= 1 << DEAD_TICKS_VALUE_WIDTH:
        reader.error("pwm.dead_time",
                     f"{_q(dead, 's')} is {_n(ticks)} at {clock}, more than the DEAD_TICKS register "
                     f"holds ({(1 << DEAD_TICKS_VALUE_WIDTH) - 1} ticks, u16)")


def _check_sampling(reader, tick: float) -> None:
    """OS_TICKS between OS_MIN and what leaves a sample on each carrier half; BLANK_TICKS in its register."""
    clock = f"pwm.tick_hz = {_q(tick, 'Hz')}"
    interval = reader.get("control.sample_interval")
    if interval is not None:
        os_ticks = _ticks(interval, tick)
        f_sw = reader.get("pwm.f_sw")
        half = round(tick / (2 * f_sw)) if f_sw is not None and "pwm.f_sw" not in reader.invalid else None
        if os_ticks < OS_MIN_DEFAULT:
            reader.error("control.sample_interval",
                         f"{_q(interval, 's')} is {_n(os_ticks)} at {clock}, below the hardware's shortest "
                         f"sampling interval OS_MIN = {OS_MIN_DEFAULT} ticks ({_q(OS_MIN_DEFAULT / tick, 's')}): "
                         f"the serial ADC's conversion and read-out cycle (38 clocks for 12 bits, "
                         f"rtl/hfi_adc_if.v) and the CORDIC's 32 clocks + 8 must end before the next sample; "
                         f"the hardware would sample every OS_MIN (docs/spec.md 2.3)")
        elif os_ticks >= 1 << OS_TICKS_VALUE_WIDTH:
            reader.error("control.sample_interval",
                         f"{_q(interval, 's')} is {_n(os_ticks)} at {clock}, more than the OS_TICKS "
                         f"register holds ({(1 << OS_TICKS_VALUE_WIDTH) - 1} ticks, u16)")
        elif half is not None and os_ticks > half - OS_MIN_DEFAULT:
            # OS samples at phases m*OS_TICKS <= 2H - OS_MIN (spec 2.3): with OS_TICKS <= H - OS_MIN the
            # falling half [H, 2H) holds one as well as the rising half (phase 0); the demodulator's
            # weights have opposite signs on the two halves (spec 3.3-3.4)
            limit = (half - OS_MIN_DEFAULT) / tick
            reader.error("control.sample_interval",
                         f"{_q(interval, 's')} ({os_ticks} ticks) is longer than the carrier half period "
                         f"minus OS_MIN, {_q(limit, 's')} ({half} - {OS_MIN_DEFAULT} ticks at "
                         f"pwm.f_sw = {_q(f_sw, 'Hz')}, {clock}): the falling half of the carrier would hold "
                         f"no sample (samples at m*OS_TICKS up to 2H - OS_MIN, docs/spec.md 2.3), and the "
                         f"demodulation needs both halves")
    blank = reader.get("control.blank")
    if blank is not None and _ticks(blank, tick) >= 1 << BLANK_TICKS_VALUE_WIDTH:
        reader.error("control.blank",
                     f"{_q(blank, 's')} is {_n(_ticks(blank, tick))} at {clock}, more than the BLANK_TICKS "
                     f"register holds ({(1 << BLANK_TICKS_VALUE_WIDTH) - 1} ticks, u16)")


def _check_adc_bits(reader, plant: dict) -> None:
    bits = _plant_value(reader, "sensors.adc_bits", plant["sens"]["adc_bits"])
    if bits is not None and bits > ADC_BITS_MAX:
        reader.error("sensors.adc_bits",
                     f"{bits} bits is more than the closed loop's ADC interface reads: at most "
                     f"{ADC_BITS_MAX} (rtl/hfi_adc_if.v ADC_BITS 1..16; the ADC code is uB with B <= 16, "
                     f"left-aligned to s16, docs/spec.md 3 and 3.1)")


# ---- currents -------------------------------------------------------------------------------------
def _methods(reader) -> list:
    """The estimator methods of the two slots (MethodInfo), those that are valid."""
    return [METHODS[name] for name in (reader.get("estimator.low"), reader.get("estimator.high"))
            if name in METHODS]


def _check_currents(reader, plant: dict, i_range: float, tick: float | None) -> None:
    """Currents against the sensor range, and the controller's currents below the trip."""
    rng = f"sensors.adc_range = {_q(i_range, 'A')}"
    i_lsb = i_range / CURRENT_FS_LSB
    trip = reader.get("control.i_trip")
    if trip is not None and trip >= i_range:
        reader.error("control.i_trip",
                     f"{_q(trip, 'A')} is not below the current sensors' range {rng}: the measured "
                     f"currents saturate at +-adc_range (2^15 LSB, docs/spec.md 3), so the firmware's "
                     f"trip on the window means could never fire")
        trip = None
    oc = reader.get("control.oc_limit")
    if oc is not None and oc >= i_range:
        reader.error("control.oc_limit",
                     f"{_q(oc, 'A')} is not below the current sensors' range {rng}: the hardware comparator "
                     f"(OC_LIMIT, docs/spec.md 3.7) compares the scaled samples, which saturate at +-adc_range; "
                     f"leave the key out for the register's reset value (full scale)")
    probe = reader.get("protection.catch_probe")
    if probe and probe >= (trip if trip is not None else i_range):
        reader.error("protection.catch_probe",
                     f"{_q(probe, 'A')} is not below {'control.i_trip' if trip is not None else rng}: a pulse whose "
                     f"window mean reached it would have tripped the drive (or saturated the sensors) first, so "
                     f"the flying start's probe could never find the rotor")
    if trip is not None:
        why = f"below control.i_trip = {_q(trip, 'A')}, or the drive trips on its own command"
        i_max = reader.get("control.i_max")
        if i_max is not None and i_max >= trip:
            reader.error("control.i_max", f"{_q(i_max, 'A')} (the speed PI's current limit) must be {why}")
        i_pulse = reader.get("control.i_pulse")
        if reader.get("control.polarity") == "current" and i_pulse is not None and i_pulse >= trip:
            reader.error("control.i_pulse", f"{_q(i_pulse, 'A')} (the polarity test's d-current) must be {why}")
        for method in _methods(reader):
            path = f"estimator.{method.name}.i_d_min"
            try:
                i_d = reader.get(path)
            except KeyError:        # the method keeps no d-current of its own
                continue
            if i_d is not None and i_d >= trip:
                reader.error(path, f"{_q(i_d, 'A')} (the d-current kept while {method.name} is in charge) "
                                   f"must be {why}")
    i_pulse = reader.get("control.i_pulse")
    checked = trip is not None and reader.get("control.polarity") == "current"      # against the trip, above
    if i_pulse is not None and i_pulse >= i_range and not checked:
        # found by tests/test_scenario_fuzz.py (2026-12-01): with another polarity method the value is unused, but the
        # firmware's parameter is still made from it, and 2.7e304 A overflowed the conversion (a traceback)
        reader.error("control.i_pulse", f"{_q(i_pulse, 'A')} (the polarity test's d-current) is not below the current "
                                        f"sensors' range {rng}: no sample could measure it")
    if reader.get("control.dead_time_comp") == "on":
        _check_dtc_zone(reader, i_range, i_lsb, tick)
    _check_hf_current(reader, plant, i_range)


def _check_dtc_zone(reader, i_range: float, i_lsb: float, tick: float | None) -> None:
    """control_config: DTC_GAIN = min(to_fixed(DEAD_TICKS / max(zone LSB, 1), 8), 65535) (u16 Q8)."""
    zone = reader.get("control.dtc_zone")
    if zone is None:
        return
    if zone >= i_range:
        reader.error("control.dtc_zone",
                     f"{_q(zone, 'A')} is not below the current sensors' range sensors.adc_range = "
                     f"{_q(i_range, 'A')}: the compensation would never reach the full dead time "
                     f"(docs/spec.md 3.6)")
        return
    dead = reader.get("pwm.dead_time")
    if tick is None or dead is None:
        return
    dead_ticks = _ticks(dead, tick)
    gain_max = (1 << DTC_GAIN_VALUE_WIDTH) - 1
    zone_lsb = to_fixed(zone / i_lsb, 0)
    if zone_lsb < 1 or to_fixed(dead_ticks / max(zone_lsb, 1), 8) > gain_max:
        least = max(dead_ticks * 256 / gain_max, 0.5) * i_lsb
        reader.error("control.dtc_zone",
                     f"{_q(zone, 'A')} is below {_q(least, 'A')}, the smallest zone DTC_GAIN (u16 Q8, "
                     f"ticks per current LSB) can express for the dead time of {dead_ticks} ticks "
                     f"(pwm.dead_time = {_q(dead, 's')}): DEAD_TICKS * 2^8 / {gain_max} current LSB, and at "
                     f"least half an LSB (1 LSB = sensors.adc_range / 2^15 = {_q(i_lsb, 'A')}); "
                     f"control_config.py would saturate the gain")


def _check_hf_current(reader, plant: dict, i_range: float) -> None:
    """The injection's predicted HF current (HF_AMP, the rotating injection's hf_dtc) within the range."""
    v_h = reader.get("injection.V_h")
    f_sw = reader.get("pwm.f_sw")
    mag = plant["mag"]
    if v_h is None or f_sw is None or any(f"motor.magnetic.{k}" in reader.invalid for k in ("L_d", "L_q")):
        return
    kinds = {m.injection for m in _methods(reader)}
    rng = f"sensors.adc_range = {_q(i_range, 'A')}"
    if INJ_SQW_D in kinds and reader.get("control.law") != "fcs_mpc":
        # control_config.hardware_config, eq. (17): a triangle of amplitude V_h / (4 f_sw L_d)
        amp = v_h / (4 * f_sw * mag["L_d"])
        if amp >= i_range:
            reader.error("injection.V_h",
                         f"{_q(v_h, 'V')} drives an HF d-current of {_q(amp, 'A')} (V_h / (4 f_sw L_d), "
                         f"L_d = {_q(mag['L_d'], 'H')}, f_sw = {_q(f_sw, 'Hz')}), not below the current "
                         f"sensors' range {rng}: the samples saturate (HF_AMP is a u15 of 2^15 = adc_range)")
    if INJ_ROT in kinds:
        f_inj = reader.get("estimator.rot_bpf.f_inj")
        if f_inj is None:
            return
        # control_config.rot_hf_current, Tap et al. 2023 eq. (11): V_h L_0 / (w_h L_d L_q)
        amp = v_h * 0.5 * (mag["L_d"] + mag["L_q"]) / (2 * math.pi * f_inj * mag["L_d"] * mag["L_q"])
        if amp >= i_range:
            reader.error("injection.V_h",
                         f"{_q(v_h, 'V')} at estimator.rot_bpf.f_inj = {_q(f_inj, 'Hz')} drives an HF current "
                         f"of {_q(amp, 'A')} (V_h L_0 / (w_h L_d L_q), Tap et al. 2023 eq. (11)), not below the "
                         f"current sensors' range {rng}: the samples saturate")


# ---- voltages -------------------------------------------------------------------------------------
def _check_voltages(reader, v_dc: float) -> None:
    """Voltage limits within the inverter's linear range V_dc/sqrt(3); voltages within their formats."""
    linear = v_dc / math.sqrt(3)
    why = (f"the inverter's linear modulation limit V_dc/sqrt(3) = {_q(linear, 'V')} "
           f"(inverter.V_dc = {_q(v_dc, 'V')}): beyond it the modulator cannot apply the voltage")
    v_max = reader.get("control.v_max")
    if v_max is not None and v_max > linear * (1 + 1e-12):
        reader.error("control.v_max", f"{_q(v_max, 'V')} (the current PIs' limit per axis) is above {why}")
    v_pilot = reader.get("control.v_pilot")
    if reader.get("control.polarity") == "pilot" and v_pilot is not None and v_pilot > linear * (1 + 1e-12):
        reader.error("control.v_pilot", f"{_q(v_pilot, 'V')} (the polarity test's pilot voltage) is above {why}")
    names = {m.name for m in _methods(reader)}
    z_max = reader.get("estimator.eemf_smo.z_max")
    if "eemf_smo" in names and z_max is not None and z_max >= v_dc:
        reader.error("estimator.eemf_smo.z_max",
                     f"{_q(z_max, 'V')} is not below inverter.V_dc = {_q(v_dc, 'V')}, the voltage format's "
                     f"full scale (2^15 LSB, docs/spec.md 3): control_config.py would saturate it")
    phi_min = reader.get("estimator.hfo_proj.phi_min")
    if "hfo_proj" in names and phi_min is not None and phi_min * VOLTAGE_FS_LSB / v_dc > 65535:
        reader.error("estimator.hfo_proj.phi_min",
                     f"{_q(phi_min, 'V')} is above {_q(65535 * v_dc / VOLTAGE_FS_LSB, 'V')}, what its u16 "
                     f"firmware value holds (65535 voltage LSB of V_dc / 2^15, inverter.V_dc = "
                     f"{_q(v_dc, 'V')}): control_config.py would saturate it")


# ---- dc-link channel ------------------------------------------------------------------------------
def _check_dc_link(reader, plant: dict, v_dc: float) -> None:
    """The dc-link channel reads the nominal link and the overvoltage limit below its full scale, and its
    LSB resolves the under- and overvoltage limits (the check would otherwise never or always fire)."""
    full = _plant_value(reader, "sensors.vdc_range", plant["sens"]["vdc_range"])
    under, over = reader.get("protection.undervoltage"), reader.get("protection.overvoltage")
    if reader.get("control.dc_feedforward") == "on" and full == 0:
        reader.error("control.dc_feedforward", "\"on\" needs the dc-link measurement, and sensors.vdc_range is "
                                               "0 V (no channel): give the channel's full scale or turn it off")
    if not full or under is None or over is None:  # no channel (0 V: the check is off), or an invalid limit
        return
    gain = plant["sens"]["vdc_gain"]
    if over * v_dc * gain >= full:
        reader.error("sensors.vdc_range", f"{_q(full, 'V')} is not above protection.overvoltage x inverter.V_dc = "
                                          f"{_q(over * v_dc, 'V')} (times sensors.vdc_gain = {gain:g}): the "
                                          f"dc-link channel would read full scale there")
    bits = plant["sens"]["adc_bits"]
    if (over - under) * v_dc < 4 * full / 2**bits:
        reader.error("protection.overvoltage", f"the band from protection.undervoltage to overvoltage is below "
                                               f"4 LSB of the dc-link channel ({_q(4 * full / 2**bits, 'V')})")


# ---- rates and speeds -----------------------------------------------------------------------------
def _check_rates(reader, plant: dict) -> None:
    """Values per PWM period that control_config.py would clamp, and speeds the s32 speed format holds."""
    f_sw = reader.get("pwm.f_sw")
    if f_sw is None:
        return
    per = f"pwm.f_sw = {_q(f_sw, 'Hz')}"
    rate = reader.get("control.speed_rate")
    if rate is not None and rate > f_sw * (1 + 1e-12):
        reader.error("control.speed_rate",
                     f"{_q(rate, 'Hz')} is above {per}: the speed PI runs at most once per PWM period "
                     f"(control_config.py would run it every period)")
    i_range = _plant_value(reader, "sensors.adc_range", plant["sens"]["adc_range"])
    slew = reader.get("control.current_slew")
    if i_range is not None and slew is not None and slew > 0:
        least = i_range / CURRENT_FS_LSB * f_sw
        if to_fixed(slew / f_sw / (i_range / CURRENT_FS_LSB), 0) < 1:
            reader.error("control.current_slew",
                         f"{_q(slew, 'A/s')} is less than one current LSB per PWM period, {_q(least, 'A/s')} "
                         f"(sensors.adc_range / 2^15 times {per}): control_config.py would use that instead")
    names = {m.name for m in _methods(reader)}
    f_inj = reader.get("estimator.rot_bpf.f_inj")
    if "rot_bpf" in names and f_inj is not None and not f_inj < f_sw / 2:
        reader.error("estimator.rot_bpf.f_inj",
                     f"{_q(f_inj, 'Hz')} is not below f_sw / 2 = {_q(f_sw / 2, 'Hz')} ({per}): the injection's "
                     f"phase advances once per PWM period (golden/fpga/rot_injection.py, INJ_STEP)")
    lag = reader.get("estimator.hfo_proj.i_lag")
    if "hfo_proj" in names and lag is not None and lag * f_sw > 1 + 1e-12:
        reader.error("estimator.hfo_proj.i_lag",
                     f"{_q(lag, 's')} is longer than one PWM period, {_q(1 / f_sw, 's')} ({per}): the top "
                     f"samples are corrected by at most one period (control_config.py would clamp it)")
    _check_speeds(reader, plant, f_sw)


def _check_speeds(reader, plant: dict, f_sw: float) -> None:
    """Speeds in the firmware's s32 format, binary angle (2^32 = one electrical turn) per PWM period:
    |f_e| < f_sw / 2 (docs/spec.md 3; control_config.Scales.speed_mech)."""
    pp = _plant_value(reader, "motor.pole_pairs", plant["mech"]["pole_pairs"])
    if pp is None:
        return
    limit = math.pi * f_sw / pp                        # mechanical rad/s at f_e = f_sw / 2
    why = (f"the largest speed the firmware's s32 speed format holds: half an electrical turn per PWM "
           f"period, f_sw / 2 electrical (pwm.f_sw = {_q(f_sw, 'Hz')}, motor.pole_pairs = {pp}; "
           f"docs/spec.md 3)")
    rpm = 30 / math.pi
    for i, (_, w) in enumerate(reader.get("reference.speed") or []):
        if abs(w) >= limit:
            reader.error(f"reference.speed[{i}][1]", f"{abs(w) * rpm:g} rpm is not below {limit * rpm:g} rpm, {why}")
            break
    if reader.get("estimator.high") not in (None, "none"):
        for key in ("estimator.handover_up", "estimator.handover_down", "estimator.watchdog_speed",
                    "protection.slip_speed"):
            w = reader.get(key)
            if w is not None and w >= limit:
                reader.error(key, f"{w * rpm:g} rpm is not below {limit * rpm:g} rpm, {why}")
