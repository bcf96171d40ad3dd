"""Physical and hardware limits of scenario values (golden/limits.py, docs/scenario.md "Physical and
hardware limits"): one violating scenario per check, the expected limit computed here from its fact."""

from __future__ import annotations

import copy
import math
import tomllib
from pathlib import Path

import pytest

from golden.fpga.adc_trigger import OS_MIN_DEFAULT
from golden.fpga.carrier import REGISTER_HALF_MIN
from golden.fpga.gate_generator import DEAD_MIN_DEFAULT
from golden.motors import PRESETS
from golden.regmap import OS_TICKS_VALUE_WIDTH, PWM_HALF_VALUE_WIDTH
from golden.scenario import ScenarioError, load_scenario, parse_scenario
from golden.units import format_quantity as fq

ROOT = Path(__file__).resolve().parents[1]
SCENARIOS = sorted((ROOT / "scenarios").glob("*.toml"))
TICK = 100e6                                    # the spec's tick (docs/soc.md)
F_SW = 5e3                                      # the scenario default
BASE = {"scenario": {"name": "limits", "duration": "10 ms"},
        "motor": {"preset": "benevieri2023_table1"}, "control": {}}
"""A closed-loop scenario on the defaults (adc_range 10 A, V_dc 560 V, 4 pole pairs, 100 MHz, 5 kHz)."""


def merged(base: dict, extra: dict) -> dict:
    data = copy.deepcopy(base)
    for section, table in extra.items():
        node = data
        for key in section.split("."):
            node = node.setdefault(key, {})
        node.update(table)
    return data


def problem(extra: dict, path: str, base: dict = BASE) -> str:
    """The problem reported at ``path`` (the only one there)."""
    with pytest.raises(ScenarioError) as info:
        parse_scenario(merged(base, extra))
    found = [p for p in info.value.problems if p.startswith(path + ": ")]
    assert len(found) == 1, info.value.problems
    return found[0]


def accepted(extra: dict, base: dict = BASE):
    return parse_scenario(merged(base, extra))


def preset_file(name: str) -> dict:
    with open(ROOT / "scenarios" / name, "rb") as file:
        return tomllib.load(file)


@pytest.mark.parametrize("path", SCENARIOS, ids=lambda p: p.name)
def test_every_scenario_file_still_loads(path):
    load_scenario(path)


def test_the_defaults_are_within_every_limit():
    accepted({})


# ---- clock and PWM --------------------------------------------------------------------------------
@pytest.mark.parametrize("tick", ["33 MHz", "99 MHz", "120 MHz"])
def test_tick_outside_the_hardware_clocks(tick):
    msg = problem({"pwm": {"tick_hz": tick}}, "pwm.tick_hz")
    assert fq(TICK, "Hz") in msg and fq(1.1 * TICK, "Hz") in msg          # spec tick, +10 % timing target
    assert "timing" in msg


def test_tick_of_the_tang_nano_is_accepted():
    assert accepted({"pwm": {"tick_hz": "100.286 MHz"}}).pwm.tick_hz == 100.286e6


def test_tick_is_free_in_the_open_loop_study():
    data = copy.deepcopy(BASE)
    del data["control"]
    assert parse_scenario(merged(data, {"pwm": {"tick_hz": "50 MHz"}})).pwm.tick_hz == 50e6


@pytest.mark.parametrize("f_sw", ["500 Hz", "100 kHz"])
def test_f_sw_half_period_in_the_carrier_register(f_sw):
    msg = problem({"pwm": {"f_sw": f_sw, "dead_time": "1 us"}}, "pwm.f_sw")
    half_max = 2**PWM_HALF_VALUE_WIDTH - 1
    assert fq(TICK / (2 * half_max), "Hz") in msg and fq(TICK / (2 * REGISTER_HALF_MIN), "Hz") in msg
    assert f"{REGISTER_HALF_MIN}..{half_max}" in msg


def test_f_sw_at_the_edges_is_accepted():
    accepted({"pwm": {"f_sw": TICK / (2 * REGISTER_HALF_MIN), "dead_time": "1 us"}})
    accepted({"pwm": {"f_sw": TICK / (2 * (2**PWM_HALF_VALUE_WIDTH - 1))}})


def test_openloop_needs_a_whole_half_period():
    data = copy.deepcopy(BASE)
    del data["control"]
    msg = problem({"pwm": {"f_sw": "3 kHz"}}, "pwm.f_sw", base=data)
    assert f"{TICK / (2 * 3e3):.6g} ticks" in msg and "whole number" in msg


def test_dead_time_below_dead_min():
    msg = problem({"pwm": {"dead_time": "0.2 us"}}, "pwm.dead_time")
    assert f"DEAD_MIN = {DEAD_MIN_DEFAULT} ticks" in msg and fq(DEAD_MIN_DEFAULT / TICK, "s") in msg
    assert "20 ticks" in msg


# ---- sampling -------------------------------------------------------------------------------------
def test_sample_interval_below_os_min():
    msg = problem({"control": {"sample_interval": "10 ns"}}, "control.sample_interval")
    assert f"OS_MIN = {OS_MIN_DEFAULT} ticks" in msg and fq(OS_MIN_DEFAULT / TICK, "s") in msg


def test_sample_interval_leaves_a_sample_on_each_carrier_half():
    half = round(TICK / (2 * F_SW))
    limit = (half - OS_MIN_DEFAULT) / TICK
    accepted({"control": {"sample_interval": limit}})
    msg = problem({"control": {"sample_interval": limit + 1 / TICK}}, "control.sample_interval")
    assert fq(limit, "s") in msg and "falling half" in msg


def test_sample_interval_in_the_os_ticks_register():
    msg = problem({"control": {"sample_interval": "1 ms"}, "pwm": {"f_sw": "1 kHz"}}, "control.sample_interval")
    assert f"{2**OS_TICKS_VALUE_WIDTH - 1} ticks" in msg


def test_blank_in_its_register():
    msg = problem({"control": {"blank": "1 ms"}}, "control.blank")
    assert "100000 ticks" in msg and "65535 ticks" in msg


def test_adc_bits_of_the_adc_interface():
    msg = problem({"sensors": {"adc_bits": 18}}, "sensors.adc_bits")
    assert "at most 16" in msg
    data = copy.deepcopy(BASE)
    del data["control"]
    parse_scenario(merged(data, {"sensors": {"adc_bits": 18}}))          # the plant alone models 24 bits


# ---- currents -------------------------------------------------------------------------------------
def test_trip_above_the_sensor_range():
    msg = problem({"sensors": {"adc_range": "12.5 A"}, "control": {"i_trip": "1000 A"}}, "control.i_trip")
    assert fq(1000, "A") in msg and fq(12.5, "A") in msg and "never fire" in msg


@pytest.mark.parametrize("extra, path", [
    ({"control": {"i_max": "6 A"}}, "control.i_max"),
    ({"control": {"i_pulse": "7 A"}}, "control.i_pulse"),
    ({"estimator": {"high": "rfo", "rfo": {"i_d_min": "6.5 A"}}}, "estimator.rfo.i_d_min"),
    ({"estimator": {"sqw_bangbang": {"i_d_min": "6 A"}}}, "estimator.sqw_bangbang.i_d_min"),
    ({"estimator": {"low": "sqw_cic", "sqw_cic": {"i_d_min": "6 A"}}}, "estimator.sqw_cic.i_d_min"),
    ({"estimator": {"low": "rot_bpf", "rot_bpf": {"i_d_min": "6 A"}}}, "estimator.rot_bpf.i_d_min"),
])
def test_currents_below_the_trip(extra, path):
    msg = problem(extra, path)
    assert fq(6.0, "A") in msg and "control.i_trip" in msg           # the default trip


def test_pulse_is_free_without_the_current_polarity_test():
    accepted({"control": {"i_pulse": "7 A", "polarity": "pilot"}})


@pytest.mark.parametrize("value", ["10 A", "2.7e304 A"])
def test_pulse_within_the_sensor_range_without_the_current_polarity_test(value):
    """Unused with another polarity method, but still turned into the firmware's parameter: 2.7e304 A (found by
    tests/test_scenario_fuzz.py) overflowed the conversion with a traceback; refused at the sensors' range (10 A)."""
    msg = problem({"control": {"i_pulse": value, "polarity": "pilot"}}, "control.i_pulse")
    assert "sensors.adc_range = " + fq(10.0, "A") in msg and "no sample could measure it" in msg


def test_dtc_zone_within_the_range():
    msg = problem({"control": {"dead_time_comp": "on", "dtc_zone": "11 A"}}, "control.dtc_zone")
    assert fq(10.0, "A") in msg


def test_dtc_zone_the_gain_register_can_express():
    msg = problem({"control": {"dead_time_comp": "on", "dtc_zone": "0.2 mA"}}, "control.dtc_zone")
    dead_ticks = round(4e-6 * TICK)
    least = dead_ticks * 256 / 65535 * (10.0 / 2**15)
    assert fq(least, "A") in msg and f"{dead_ticks} ticks" in msg
    accepted({"control": {"dead_time_comp": "on", "dtc_zone": 2 * least}})


def test_square_wave_current_within_the_range():
    L_d = PRESETS["benevieri2023_table1"]["mag"]["L_d"]
    amp = 300 / (4 * F_SW * L_d)
    msg = problem({"injection": {"V_h": "300 V"}, "sensors": {"adc_range": "2 A"},
                   "control": {"i_trip": "1.5 A", "i_max": "1 A", "i_pulse": "1 A"}}, "injection.V_h")
    assert fq(amp, "A") in msg and fq(2.0, "A") in msg


def test_rotating_injection_current_within_the_range():
    base = preset_file("tap2023_step.toml")
    mag = load_scenario(ROOT / "scenarios" / "tap2023_step.toml").plant["mag"]
    assert base["injection"]["V_h"] == "28 V" and base["sensors"]["adc_range"] == "5 A"
    amp = 28 * 0.5 * (mag["L_d"] + mag["L_q"]) / (2 * math.pi * 5 * mag["L_d"] * mag["L_q"])
    assert amp >= 5.0
    msg = problem({"estimator.rot_bpf": {"f_inj": "5 Hz"}}, "injection.V_h", base=base)
    assert fq(amp, "A") in msg and fq(5.0, "A") in msg


# ---- voltages -------------------------------------------------------------------------------------
def test_v_max_within_the_linear_range():
    msg = problem({"control": {"v_max": "400 V"}}, "control.v_max")
    assert fq(560 / math.sqrt(3), "V") in msg and "V_dc/sqrt(3)" in msg
    accepted({"control": {"v_max": 560 / math.sqrt(3)}})


def test_pilot_voltage_within_the_linear_range():
    msg = problem({"control": {"polarity": "pilot", "v_pilot": "400 V"}}, "control.v_pilot")
    assert fq(560 / math.sqrt(3), "V") in msg


def test_smo_limit_within_the_voltage_format():
    base = preset_file("tap2023_step.toml")
    msg = problem({"estimator.eemf_smo": {"z_max": "400 V"}}, "estimator.eemf_smo.z_max", base=base)
    assert fq(350.0, "V") in msg                                          # the file's V_dc


def test_phi_min_within_its_u16():
    base = preset_file("varatharajan2020_torquestep.toml")
    msg = problem({"estimator.hfo_proj": {"phi_min": "2 kV"}}, "estimator.hfo_proj.phi_min", base=base)
    assert fq(65535 * 540 / 2**15, "V") in msg


def test_error_limit_below_half_a_turn():
    base = preset_file("varatharajan2020_torquestep.toml")
    msg = problem({"estimator.hfo_proj": {"eps_max": "180 deg"}}, "estimator.hfo_proj.eps_max", base=base)
    assert "below 180 deg" in msg
    accepted({"estimator.hfo_proj": {"eps_max": "179 deg"}}, base=base)


# ---- rates and speeds -----------------------------------------------------------------------------
def test_speed_rate_at_most_the_pwm_rate():
    msg = problem({"control": {"speed_rate": "10 kHz"}}, "control.speed_rate")
    assert fq(F_SW, "Hz") in msg


def test_current_slew_at_least_one_lsb_per_period():
    msg = problem({"control": {"current_slew": "0.1 A/s"}}, "control.current_slew")
    assert fq(10.0 / 2**15 * F_SW, "A/s") in msg


def test_rotating_injection_below_half_the_pwm_rate():
    base = preset_file("tap2023_step.toml")
    msg = problem({"estimator.rot_bpf": {"f_inj": "6 kHz"}}, "estimator.rot_bpf.f_inj", base=base)
    assert fq(10e3 / 2, "Hz") in msg                                      # the file's f_sw = 10 kHz


def test_sensor_lag_at_most_one_period():
    base = preset_file("varatharajan2020_torquestep.toml")
    msg = problem({"estimator.hfo_proj": {"i_lag": "1 ms"}}, "estimator.hfo_proj.i_lag", base=base)
    assert fq(1 / 10e3, "s") in msg


def test_reference_speed_in_the_speed_format():
    limit_rpm = F_SW / 2 / 4 * 60                 # f_sw / 2 electrical, 4 pole pairs
    msg = problem({"reference": {"speed": [["0 s", "0 rpm"], ["1 s", "40000 rpm"]]}}, "reference.speed[1][1]")
    assert f"{limit_rpm:g} rpm" in msg
    accepted({"reference": {"speed": [["0 s", "0 rpm"], ["1 s", f"{0.99 * limit_rpm} rpm"]]}})


def test_handover_speed_in_the_speed_format():
    limit_rpm = F_SW / 2 / 4 * 60
    msg = problem({"estimator": {"high": "rfo", "handover_up": "40000 rpm"}}, "estimator.handover_up")
    assert f"{limit_rpm:g} rpm" in msg


# ---- the dc-link channel (docs/scenario.md, sensors.vdc_range, protection.undervoltage/overvoltage) ----------
def test_dc_link_channel_defaults_to_twice_the_link_and_its_limits_follow():
    """Absent vdc_range: 2 x V_dc (560 V here); the check's codes are the limits times V_dc in codes of the
    channel (2^12 / 1120 V per volt at the SoC's 12 bits), for 0.6 ms = 3 periods at 5 kHz."""
    from golden.control_config import protection_params
    sc = accepted({"sensors": {"adc_bits": 12}})
    assert sc.plant["sens"]["vdc_range"] == 2 * 560.0
    p = protection_params(sc)
    assert (p.vdc_lo, p.vdc_hi, p.vdc_n) == (round(0.75 * 560 * 4096 / 1120), round(1.25 * 560 * 4096 / 1120), 3)
    assert (p.vdc_lo, p.vdc_hi) == (1536, 2560)
    off = protection_params(accepted({"sensors": {"adc_bits": 12, "vdc_range": "0 V"}}))
    assert (off.vdc_lo, off.vdc_hi, off.vdc_n) == (0, 0, 0)


def test_dc_link_channel_must_hold_the_overvoltage_limit():
    msg = problem({"sensors": {"vdc_range": "600 V"}}, "sensors.vdc_range")
    assert f"is not above protection.overvoltage x inverter.V_dc = {fq(1.25 * 560, 'V')}" in msg
    assert "would read full scale" in msg
    msg = problem({"sensors": {"vdc_range": "650 V"}, "protection": {"overvoltage": 1.2}}, "sensors.vdc_range")
    assert f"protection.overvoltage x inverter.V_dc = {fq(1.2 * 560, 'V')}" in msg


def test_dc_link_limits_are_checked():
    assert "must be between 0 and 1" in problem({"protection": {"undervoltage": 1.0}}, "protection.undervoltage")
    assert "must be > 1" in problem({"protection": {"overvoltage": 1.0}}, "protection.overvoltage")
    # a band of 2 codes at 12 bits over 1120 V (4 LSB = 1.09 V): refused
    msg = problem({"sensors": {"adc_bits": 12}, "protection": {"undervoltage": 0.999, "overvoltage": 1.0005}},
                  "protection.overvoltage")
    assert f"below 4 LSB of the dc-link channel ({fq(4 * 1120 / 4096, 'V')})" in msg
