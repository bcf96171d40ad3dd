"""Scenario format: unit parsing, mapping into the plant tree, validation messages, examples, CLI."""

from __future__ import annotations

import copy
import math
import re
import subprocess
import sys
from pathlib import Path

import pytest

from golden.scenario import SCHEMA, ScenarioError, _plant_defaults, load_scenario, main, parse_scenario
from golden.units import UNITS, UnitError, format_quantity, parse_quantity

ROOT = Path(__file__).resolve().parents[1]

STUB_PRESETS = {
    "stub_linear": {"R_s": 2.5, "mag": {"kind": 0, "psi_f": 0.1, "L_d": 4e-3, "L_q": 8e-3},
                    "mech": {"pole_pairs": 3, "J": 1e-3}},
    "stub_algebraic": {"mag": {"kind": 2, "a_d0": 150.0, "a_q0": 100.0, "S": 4}},
}
MINIMAL = {"scenario": {"name": "t", "duration": "10 ms"}}


def scenario(extra: dict | None = None, **kwargs):
    """Parse MINIMAL updated with ``extra`` (merged section by section)."""
    data = copy.deepcopy(MINIMAL)
    for section, table in (extra or {}).items():
        if isinstance(table, dict) and isinstance(data.get(section), dict):
            data[section].update(table)
        else:
            data[section] = table
    return parse_scenario(data, presets=STUB_PRESETS, **kwargs)


def problems(extra: dict) -> list[str]:
    """The problems reported for MINIMAL updated with ``extra``."""
    with pytest.raises(ScenarioError) as info:
        scenario(extra)
    return info.value.problems


def example_presets() -> dict:
    """The installed presets, which the example scenarios name."""
    from golden.motors import PRESETS
    return PRESETS


# ---- units ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("text, dimension, expected", [
    ("5.59 mH", "inductance", 5.59e-3),
    ("4 us", "time", 4e-6),
    ("4 \u00b5s", "time", 4e-6),           # micro sign
    ("4 \u03bcs", "time", 4e-6),           # Greek mu
    ("4us", "time", 4e-6),
    ("250 rpm", "speed", 250 * (2 * math.pi / 60)),
    ("250 r/min", "speed", 250 * (2 * math.pi / 60)),
    ("-50 rpm", "speed", -50 * (2 * math.pi / 60)),
    ("3 rad/s", "speed", 3.0),
    ("90 deg", "angle", 90 * (math.pi / 180)),
    ("1.5 N*m", "torque", 1.5),
    ("1.5 N\u00b7m", "torque", 1.5),
    ("20 mN*m", "torque", 0.02),
    ("4e-3 kg*m^2", "inertia", 4e-3),
    ("40 kg*cm^2", "inertia", 4e-3),
    ("1e-4 N*m*s/rad", "viscous_friction", 1e-4),
    ("10 kHz", "frequency", 1e4),
    ("100 MHz", "frequency", 1e8),
    ("0.2 ohm", "resistance", 0.2),
    ("0.2 \u03a9", "resistance", 0.2),     # Greek capital omega
    ("0.2 \u2126", "resistance", 0.2),     # ohm sign
    ("20 mohm", "resistance", 0.02),
    ("147 mWb", "flux", 0.147),
    ("560 V", "voltage", 560.0),
    ("2 A", "current", 2.0),
    ("1 nF", "capacitance", 1e-9),
    ("30 %", "dimensionless", 0.3),
    ("0.25", "time", 0.25),
    (".5 ms", "time", 5e-4),
])
def test_parse_quantity_exact(text, dimension, expected):
    assert parse_quantity(text, dimension) == expected


def test_bare_numbers_are_si():
    assert parse_quantity(3, "voltage") == 3.0
    assert isinstance(parse_quantity(3, "voltage"), float)
    assert parse_quantity(5.59e-3, "inductance") == 5.59e-3


@pytest.mark.parametrize("value, message", [
    ("5.59 mV", "motor.L_d: '5.59 mV' is a voltage, expected an inductance (H, mH, uH)"),
    ("5.59 mh", "motor.L_d: unknown unit 'mh' in '5.59 mh', expected an inductance (H, mH, uH)"),
    ("mH", "motor.L_d: 'mH' is not a quantity, expected '<number> <unit>' for an inductance "
           "(H, mH, uH)"),
    (True, "motor.L_d: expected an inductance (H, mH, uH) as a number or a '<number> <unit>' "
           "string, got a boolean"),
    ([1], "motor.L_d: expected an inductance (H, mH, uH) as a number or a '<number> <unit>' "
          "string, got an array"),
    (float("inf"), "motor.L_d: inf is not a finite number"),
    ("1e999 H", "motor.L_d: '1e999 H' is out of range"),
    (10**400, f"motor.L_d: {10**400!r} is out of range"),
])
def test_parse_quantity_errors(value, message):
    with pytest.raises(UnitError) as info:
        parse_quantity(value, "inductance", "motor.L_d")
    assert str(info.value) == message


def test_unit_table_dimensions():
    assert UNITS["mH"].dimension == "inductance" and UNITS["mH"].exponent == -3
    assert UNITS["ms"].dimension == "time"
    assert UNITS["kHz"].exponent == 3
    assert UNITS["rpm"].factor == 2 * math.pi / 60


@pytest.mark.parametrize("value, symbol, text", [
    (4e-6, "s", "4 us"), (5e3, "Hz", "5 kHz"), (1e8, "Hz", "100 MHz"), (0.05, "s", "50 ms"),
    (323.3162, "V", "323.316 V"), (0.0, "V", "0 V"), (-2e-3, "A", "-2 mA"),
])
def test_format_quantity(value, symbol, text):
    assert format_quantity(value, symbol) == text


# ---- mapping into the plant tree ------------------------------------------------------------------
def test_minimal_scenario_defaults():
    sc = scenario()
    assert (sc.name, sc.description, sc.duration, sc.seed) == ("t", "", 0.01, 1)
    assert (sc.pwm.f_sw, sc.pwm.dead_time, sc.pwm.tick_hz) == (5e3, 4e-6, 100e6)
    assert (sc.injection.V_h, sc.injection.theta_hat, sc.injection.v_d, sc.injection.v_q) == \
        (100.0, 0.0, 0.0, 0.0)
    assert sc.reference_speed == []
    assert sc.output.dir == "out/t"
    assert sc.preset is None
    assert sc.plant == _plant_defaults.default_params()
    assert sc.plant["mech"]["imposed_speed"] == 0
    assert sc.plant["load"] == {"t": [], "v": [], "puls_freq": 0.0, "puls_depth": 0.0}


def test_preset_then_overrides():
    sc = scenario({"motor": {"preset": "stub_linear", "R_s": "3.2 ohm",
                             "magnetic": {"L_q": "9 mH", "model": "dsat", "dsat_a": 0.2}}})
    assert sc.preset == "stub_linear"
    assert sc.plant["R_s"] == 3.2
    assert sc.plant["mag"]["L_d"] == 4e-3          # from the preset
    assert sc.plant["mag"]["L_q"] == 9e-3          # overridden
    assert sc.plant["mag"]["kind"] == 1
    assert sc.plant["mag"]["dsat_a"] == 0.2
    assert sc.plant["mech"]["pole_pairs"] == 3
    assert sc.plant["mech"]["J"] == 1e-3
    assert sc.plant["mech"]["B"] == 1e-4           # plant default, not in the preset


def test_plant_fields_from_every_section():
    sc = scenario({
        "scenario": {"seed": 2**64 - 1},
        "motor": {"pole_pairs": 5},
        "mechanics": {"J": "40 kg*cm^2", "B": 0.001, "T_c": "10 mN*m", "w_stick": "1 rpm"},
        "inverter": {"V_dc": "300 V", "R_dc": "0.1 ohm", "ripple_amp": "3 V", "ripple_freq": "100 Hz",
                     "v_sw": "1 V", "r_sw": "10 mohm", "v_diode": "0.8 V", "r_diode": "5 mohm",
                     "C_node": "1 nF"},
        "pwm": {"tick_hz": "50 MHz"},
        "sensors": {"gain": 1.02, "offset": ["10 mA", 0, "-5 mA"], "noise_rms": "3 mA",
                    "bandwidth": "200 kHz", "ring_amp": "0.5 A", "ring_freq": "20 MHz",
                    "ring_tau": "100 ns", "ring_cross": "20 %", "adc_bits": 12, "adc_range": "8 A",
                        "vdc_range": "1 kV", "vdc_gain": 0.98, "vdc_noise": "0.5 V"},
        "load": {"initial": {"theta_m": "90 deg", "omega_m": "-60 rpm"}},
        "simulation": {"max_substep": "1 us"},
    })
    p = sc.plant
    assert sc.seed == p["seed"] == 2**64 - 1
    assert p["mech"] == {"pole_pairs": 5, "J": 4e-3, "B": 0.001, "T_c": 0.01,
                         "w_stick": 2 * math.pi / 60, "imposed_speed": 0}
    assert p["inv"] == {"V_dc": 300.0, "R_dc": 0.1, "ripple_amp": 3.0, "ripple_freq": 100.0,
                        "v_sw": 1.0, "r_sw": 0.01, "v_diode": 0.8, "r_diode": 0.005, "C_node": 1e-9}
    assert p["tick_hz"] == sc.pwm.tick_hz == 50e6
    assert p["sens"] == {"gain": [1.02, 1.02, 1.02], "offset": [0.01, 0.0, -0.005],
                         "noise_rms": 0.003, "bandwidth_hz": 2e5, "ring_amp": 0.5,
                         "ring_freq": 2e7, "ring_tau": 1e-7, "ring_cross": 0.2, "adc_bits": 12,
                         "adc_range": 8.0, "vdc_range": 1000.0, "vdc_gain": 0.98, "vdc_noise_rms": 0.5}
    assert p["theta_m0"] == 90 * (math.pi / 180)
    assert p["omega_m0"] == -60 * (2 * math.pi / 60)
    assert p["max_substep_ticks"] == 50


def test_torque_profile_round_trip():
    sc = scenario({"load": {"torque": [["0 s", "0 N*m"], ["0.1 s", "0 N*m"], ["0.1 s", "2 N*m"],
                                       [0.3, 1.5]],
                            "pulsation": {"freq": "30 Hz", "depth": 0.3}}})
    assert sc.plant["load"] == {"t": [0.0, 0.1, 0.1, 0.3], "v": [0.0, 0.0, 2.0, 1.5],
                                "puls_freq": 30.0, "puls_depth": 0.3}
    assert sc.plant["speed"] == {"t": [], "v": [], "puls_freq": 0.0, "puls_depth": 0.0}
    assert sc.plant["mech"]["imposed_speed"] == 0


def test_imposed_speed_profile_round_trip():
    sc = scenario({"load": {"mode": "speed", "speed": [["0 s", "0 rpm"], ["1 s", "50 rpm"]],
                            "pulsation": {"freq": "5 Hz", "depth": "10 %"}}})
    assert sc.plant["mech"]["imposed_speed"] == 1
    assert sc.plant["speed"] == {"t": [0.0, 1.0], "v": [0.0, 50 * (2 * math.pi / 60)],
                                 "puls_freq": 5.0, "puls_depth": 0.1}
    assert sc.plant["load"]["t"] == []


def test_non_plant_settings():
    sc = scenario({"pwm": {"f_sw": "10 kHz", "dead_time": "2 us"},
                   "injection": {"V_h": "50 V", "theta_hat": "90 deg", "v_d": "10 V", "v_q": -20},
                   "reference": {"speed": [["0 s", "0 rpm"], ["0.5 s", "250 rpm"]]},
                   "output": {"dir": "results/run1"}})
    assert (sc.pwm.f_sw, sc.pwm.dead_time) == (1e4, 2e-6)
    assert (sc.injection.V_h, sc.injection.theta_hat, sc.injection.v_d, sc.injection.v_q) == \
        (50.0, math.pi / 2, 10.0, -20.0)
    assert sc.reference_speed == [(0.0, 0.0), (0.5, 250 * (2 * math.pi / 60))]
    assert sc.output.dir == "results/run1"


@pytest.mark.parametrize("max_substep, tick_hz, ticks", [
    ("0.25 us", "100 MHz", 25), ("15 ns", "100 MHz", 1), ("1 us", "1 MHz", 1), ("2.5 us", "10 MHz", 25),
])
def test_max_substep_ticks(max_substep, tick_hz, ticks):
    sc = scenario({"simulation": {"max_substep": max_substep}, "pwm": {"tick_hz": tick_hz}})
    assert sc.plant["max_substep_ticks"] == ticks


def test_plant_tree_has_exactly_the_default_keys():
    sc = scenario({"motor": {"preset": "stub_algebraic"}})
    defaults = _plant_defaults.default_params()
    assert sc.plant.keys() == defaults.keys()
    for key, value in defaults.items():
        if isinstance(value, dict):
            assert sc.plant[key].keys() == value.keys(), key


# ---- validation -----------------------------------------------------------------------------------
@pytest.mark.parametrize("extra, expected", [
    # unknown sections and keys, with suggestions
    ({"motr": {}}, "motr: unknown section (did you mean 'motor'?)"),
    ({"name": "x"}, "name: unknown top-level key (did you mean 'scenario.name'?)"),
    ({"scenario": {"nmae": "x"}}, "scenario.nmae: unknown key (did you mean 'name'?)"),
    ({"motor": {"rs": 1}}, "motor.rs: unknown key (did you mean 'R_s'?)"),
    ({"motor": {"L_d": "5 mH"}}, "motor.L_d: unknown key (did you mean 'motor.magnetic.L_d'?)"),
    ({"pwm": {"zzz": 1}}, "pwm.zzz: unknown key (valid: f_sw, dead_time, tick_hz)"),
    # wrong types
    ({"motor": {"pole_pairs": 4.0}}, "motor.pole_pairs: expected an integer, got a number (4.0)"),
    ({"motor": {"pole_pairs": "4"}}, "motor.pole_pairs: expected an integer, got a string ('4')"),
    ({"scenario": {"name": 3}}, "scenario.name: expected a string, got an integer"),
    ({"motor": {"magnetic": 3}}, "motor.magnetic: expected a table, got an integer"),
    ({"motor": {"magnetic": {"a_dd": float("nan")}}}, "motor.magnetic.a_dd: nan is not a finite number"),
    ({"motor": {"magnetic": {"a_d0": "1 A"}}},
     "motor.magnetic.a_d0: expected a bare number in SI units, got a string ('1 A')"),
    ({"mechanics": {"B": True}},
     "mechanics.B: expected a viscous friction coefficient (N*m*s/rad) as a number or a "
     "'<number> <unit>' string, got a boolean"),
    # wrong units
    ({"motor": {"magnetic": {"L_d": "5.59 mV"}}},
     "motor.magnetic.L_d: '5.59 mV' is a voltage, expected an inductance (H, mH, uH)"),
    ({"pwm": {"dead_time": "4 uH"}},
     "pwm.dead_time: '4 uH' is an inductance, expected a time (s, ms, us, ns)"),
    ({"load": {"initial": {"omega_m": "50 Hz"}}},
     "load.initial.omega_m: '50 Hz' is a frequency, expected a mechanical speed (rad/s, rpm, r/min)"),
    # ranges
    ({"scenario": {"duration": 0}}, "scenario.duration: must be > 0, got 0"),
    ({"scenario": {"duration": "-1 ms"}}, "scenario.duration: must be > 0, got '-1 ms'"),
    ({"motor": {"R_s": "0 ohm"}}, "motor.R_s: must be > 0, got '0 ohm'"),
    ({"motor": {"magnetic": {"L_d": "0 mH"}}}, "motor.magnetic.L_d: must be > 0, got '0 mH'"),
    ({"motor": {"magnetic": {"L_q": "-1 mH"}}}, "motor.magnetic.L_q: must be > 0, got '-1 mH'"),
    ({"motor": {"magnetic": {"dsat_S": 3}}},
     "motor.magnetic.dsat_S: must be an even integer in 2..16 (the plant's range), got 3"),
    ({"motor": {"magnetic": {"dsat_S": 18}}},
     "motor.magnetic.dsat_S: must be an even integer in 2..16 (the plant's range), got 18"),
    ({"sensors": {"ring_cross": -0.1}}, "sensors.ring_cross: must be >= 0, got -0.1"),
    ({"mechanics": {"J": 0}}, "mechanics.J: must be > 0, got 0"),
    ({"inverter": {"V_dc": "-560 V"}}, "inverter.V_dc: must be > 0, got '-560 V'"),
    ({"pwm": {"f_sw": "0 kHz"}}, "pwm.f_sw: must be > 0, got '0 kHz'"),
    ({"sensors": {"adc_bits": 0}}, "sensors.adc_bits: must be between 1 and 24, got 0"),
    ({"sensors": {"adc_bits": 25}}, "sensors.adc_bits: must be between 1 and 24, got 25"),
    ({"sensors": {"gain": 0}}, "sensors.gain: must be > 0, got 0"),
    ({"sensors": {"gain": [1, 1, -1]}}, "sensors.gain[2]: must be > 0, got -1"),
    ({"sensors": {"offset": [0, 0]}},
     "sensors.offset: expected 3 values (phases a, b, c) or a single value, got 2"),
    ({"sensors": {"noise_rms": "-1 mA"}}, "sensors.noise_rms: must be >= 0, got '-1 mA'"),
    ({"scenario": {"seed": -1}}, "scenario.seed: must be between 0 and 18446744073709551615, got -1"),
    ({"scenario": {"seed": 2**64}},
     f"scenario.seed: must be between 0 and 18446744073709551615, got {2**64}"),
    ({"scenario": {"seed": 1.0}}, "scenario.seed: expected an integer, got a number (1.0)"),
    ({"scenario": {"name": "my run"}},
     "scenario.name: must be a non-empty name of letters, digits, '_', '-' and '.', got 'my run'"),
    ({"load": {"mode": "torq"}},
     "load.mode: 'torq' is not one of 'torque', 'speed' (did you mean 'torque'?)"),
    # profiles
    ({"load": {"torque": [["0 s", "1 N*m"], ["1 s"]]}},
     "load.torque[1]: expected a [time, value] pair, got an array of length 1"),
    ({"load": {"torque": [["0 s", "1 N*m"], 2]}},
     "load.torque[1]: expected a [time, value] pair, got an integer"),
    ({"load": {"torque": "1 N*m"}}, "load.torque: expected an array of [time, value] pairs, got a string"),
    ({"load": {"torque": [["0 s", "1 N*m"], ["1 s", "1 rpm"]]}},
     "load.torque[1][1]: '1 rpm' is a mechanical speed, expected a torque (N*m, mN*m)"),
    ({"reference": {"speed": [["1 s", 0], ["0.5 s", 0]]}},
     "reference.speed[1]: time '0.5 s' is before the previous point's time '1 s' "
     "(times must be non-decreasing)"),
    # presets and required keys
    ({"motor": {"preset": "stub_linaer"}},
     "motor.preset: unknown preset 'stub_linaer' (did you mean 'stub_linear'? valid presets: "
     "stub_algebraic, stub_linear)"),
])
def test_field_errors(extra, expected):
    assert expected in problems(extra)


def test_missing_required():
    with pytest.raises(ScenarioError) as info:
        parse_scenario({}, presets=STUB_PRESETS)
    assert info.value.problems == ["scenario.name: missing (required)",
                                   "scenario.duration: missing (required)"]


def test_dead_time_names_both_numbers():
    assert problems({"pwm": {"f_sw": "10 kHz", "dead_time": "50 us"}}) == [
        "pwm.dead_time: 50 us must be shorter than half the PWM period (50 us at pwm.f_sw = 10 kHz)"]


def test_a_duration_beyond_the_memory_of_a_run_is_refused():
    """Found by probing the command (2026-11-30): 1e12 s passed the check and failed allocating 35 PiB; 1e300 s gave
    numpy's "Maximum allowed size exceeded" without the key. MAX_WINDOWS PWM periods are accepted, one more is not."""
    assert problems({"scenario": {"duration": "1e12 s"}, "pwm": {"f_sw": "5 kHz"}}) == [
        "scenario.duration: 1e+12 s is 5e+15 PWM periods at pwm.f_sw = 5 kHz, more than 2000000 "
        "(golden.scenario.MAX_WINDOWS: a run keeps every window in memory); split it"]
    scenario({"scenario": {"duration": "400 s"}, "pwm": {"f_sw": "5 kHz"}})          # exactly MAX_WINDOWS: accepted
    assert problems({"scenario": {"duration": "400.001 s"}, "pwm": {"f_sw": "5 kHz"}})[0].startswith(
        "scenario.duration: 400.001 s is 2e+06 PWM periods")


def test_max_substep_shorter_than_a_tick():
    assert problems({"simulation": {"max_substep": "5 ns", "max_substep_commutation": 1e-9}}) == [
        "simulation.max_substep: 5 ns is shorter than one tick (10 ns at pwm.tick_hz = 100 MHz)",
        "simulation.max_substep_commutation: 1 ns is shorter than one tick (10 ns at "
        "pwm.tick_hz = 100 MHz)"]


def test_max_substep_commutation_ticks():
    sc = scenario({"simulation": {"max_substep_commutation": "50 ns"}})
    assert sc.plant["max_substep_commutation_ticks"] == 5


def test_load_mode_profiles():
    assert problems({"load": {"mode": "speed"}}) == [
        "load.speed: missing (required when load.mode = 'speed')"]
    assert problems({"load": {"speed": [[0, 1]]}}) == ["load.speed: not used when load.mode = 'torque'"]


def test_magnetic_model_needs():
    assert problems({"motor": {"magnetic": {"model": "algebraic"}}}) == [
        "motor.magnetic.a_d0: must be > 0 for model 'algebraic', got 0.0",
        "motor.magnetic.a_q0: must be > 0 for model 'algebraic', got 0.0"]
    assert scenario({"motor": {"preset": "stub_algebraic"}}).plant["mag"]["kind"] == 2
    assert problems({"motor": {"magnetic": {"model": "dsat", "psi_f": 0}}}) == [
        "motor.magnetic.psi_f: must be > 0 for model 'dsat', got 0.0"]
    assert problems({"motor": {"magnetic": {"model": "table"}}}) == [
        "motor.magnetic.model: 'table' is not supported in scenario files yet "
        "(use a preset that provides the tables)"]


def test_injection_modulation_limit():
    msgs = problems({"injection": {"V_h": "300 V", "v_d": "30 V"}})
    assert msgs == ["injection.V_h: injection plus fundamental reach 330 V (hypot(|v_d| + V_h, v_q)), "
                    "above the linear modulation limit V_dc/sqrt(3) = 323.316 V (inverter.V_dc = 560 V)"]


def test_all_problems_reported_at_once():
    with pytest.raises(ScenarioError) as info:
        scenario({"motor": {"R_s": -1, "magnetic": {"L_q": "1 V"}}, "sensors": {"adc_bits": 99},
                  "pwm": {"dead_time": "1 s"}, "bogus": {}})
    err = info.value
    assert [p.split(":")[0] for p in err.problems] == [
        "motor.R_s", "motor.magnetic.L_q", "sensors.adc_bits", "bogus", "pwm.dead_time"]
    assert isinstance(err, ValueError)
    assert str(err).startswith("<dict>: 5 problems:\n  motor.R_s: must be > 0, got -1\n")


def test_invalid_field_does_not_cascade():
    """A bad f_sw is reported once, not again as a dead-time conflict against the default."""
    assert problems({"pwm": {"f_sw": "1 V", "dead_time": "200 us"}}) == [
        "pwm.f_sw: '1 V' is a voltage, expected a frequency (Hz, kHz, MHz)"]


# ---- files ----------------------------------------------------------------------------------------
def test_toml_syntax_error_names_file_and_line(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text('[scenario]\nname = "x"\nduration = 5 ms\n')
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    message = str(info.value)
    assert message.startswith(f"{path}: 1 problem:\n  TOML syntax error: ")
    assert "line 3" in message


def test_load_scenario_from_file(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text('[scenario]\nname = "file"\nduration = "0.2 s"\n'
                    '[motor]\npreset = "stub_linear"\n[motor.magnetic]\nL_d = "5 mH"\n',
                    encoding="utf-8")
    sc = load_scenario(path, presets=STUB_PRESETS)
    assert (sc.name, sc.duration, sc.source) == ("file", 0.2, str(path))
    assert sc.plant["mag"]["L_d"] == 5e-3


EXAMPLES = sorted((ROOT / "scenarios").glob("*.toml"))


def test_required_examples_exist():
    names = {p.stem for p in EXAMPLES}
    assert "openloop_injection" in names
    assert {"load_step", "imposed_speed"} <= names


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_examples_load(path):
    sc = load_scenario(path, presets=example_presets())
    assert sc.name == path.stem
    assert sc.duration > 0


def test_example_modes():
    presets = example_presets()
    step = load_scenario(ROOT / "scenarios" / "load_step.toml", presets=presets)
    assert step.plant["load"]["v"] == [0.0, 0.0, 2.0]
    assert step.plant["load"]["puls_depth"] == 0.3
    imposed = load_scenario(ROOT / "scenarios" / "imposed_speed.toml", presets=presets)
    assert imposed.plant["mech"]["imposed_speed"] == 1
    assert imposed.plant["speed"]["v"] == [-50 * (2 * math.pi / 60), 50 * (2 * math.pi / 60)]


def test_docs_list_every_key():
    text = (ROOT / "docs" / "scenario.md").read_text(encoding="utf-8")
    for section, fields in SCHEMA.items():
        if not section:
            continue
        heading = re.search(rf"^#+ `\[{re.escape(section)}\]`$", text, re.MULTILINE)
        assert heading, f"docs/scenario.md has no heading for [{section}]"
        body = text[heading.end():].split("\n#", 1)[0]
        for key, spec in fields.items():
            if spec.kind != "table":
                assert f"| `{key}` |" in body, f"[{section}] {key} is not documented"


# ---- command line ---------------------------------------------------------------------------------
def run_cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "golden.scenario", *args], cwd=ROOT,
                          capture_output=True, text=True, timeout=60)


def test_cli_ok(tmp_path):
    path = tmp_path / "ok.toml"
    path.write_text('[scenario]\nname = "ok"\nduration = "50 ms"\n')
    result = run_cli("check", str(path))
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout == (f"{path}: ok (ok: 50 ms, motor default (linear), torque load (0 points), "
                             "f_sw 5 kHz, dead time 4 us, V_h 100 V)\n")


def test_cli_errors_exit_1_without_traceback(tmp_path):
    good = tmp_path / "good.toml"
    good.write_text('[scenario]\nname = "good"\nduration = 1\n')
    bad = tmp_path / "bad.toml"
    bad.write_text('[scenario]\nname = "bad"\nduration = 1\n[motor.magnetic]\nL_d = "5.59 mV"\n')
    broken = tmp_path / "broken.toml"
    broken.write_text("[scenario\n")
    missing = tmp_path / "missing.toml"
    result = run_cli("check", str(good), str(bad), str(broken), str(missing))
    assert result.returncode == 1
    out = result.stdout
    assert f"{good}: ok (" in out
    assert (f"{bad}: 1 problem:\n  motor.magnetic.L_d: '5.59 mV' is a voltage, "
            "expected an inductance (H, mH, uH)\n") in out
    assert f"{broken}: 1 problem:\n  TOML syntax error: " in out
    assert f"{missing}: cannot read: No such file or directory" in out
    assert "Traceback" not in out + result.stderr


def test_main_returns_status(tmp_path, capsys):
    path = tmp_path / "ok.toml"
    path.write_text('[scenario]\nname = "ok"\nduration = 1\n')
    assert main(["check", str(path)]) == 0
    assert main(["check", str(tmp_path / "nope.toml")]) == 1
    assert capsys.readouterr().out.count("\n") == 2


def test_the_fcs_mpc_law_and_its_estimator_go_together():
    """fcs_mpc needs an estimator that observes the stator flux, alone in its slot; hfo_proj needs the law;
    the law refuses a polarity test (it ignores its pulses) and OS_BLANK (it drops the top samples)."""
    got = problems({"control": {"law": "fcs_mpc", "polarity": "none"}, "estimator": {"low": "sqw_bangbang"}})
    assert any(p.startswith("control.law: fcs_mpc needs an estimator that observes the stator flux") for p in got)
    got = problems({"control": {"polarity": "none"}, "estimator": {"low": "hfo_proj"}})
    assert any(p.startswith("estimator.low: hfo_proj runs with the direct-vector control law") for p in got)
    got = problems({"control": {"law": "fcs_mpc"}, "estimator": {"low": "hfo_proj"}})
    assert any(p.startswith("control.polarity: fcs_mpc runs without a polarity test") for p in got)
    got = problems({"control": {"law": "fcs_mpc", "polarity": "none", "adc_mode": "OS_BLANK"},
                    "estimator": {"low": "hfo_proj"}})
    assert any(p.startswith("control.adc_mode: fcs_mpc needs the carrier-top samples") for p in got)
    sc = scenario({"control": {"law": "fcs_mpc", "polarity": "none", "adc_mode": "DS"}, "estimator": {"low": "hfo_proj"}})
    assert sc.control.law == "fcs_mpc" and sc.estimator.low == "hfo_proj"


def test_the_hand_over_watchdog_keys():
    """estimator.watchdog_*: refused without a high slot (nothing to compare with), outside 0..180 deg, below 0
    rpm and beyond 10 s; on, they become the firmware's binary angle, speed LSB and periods."""
    got = problems({"control": {}, "estimator": {"watchdog_angle": "35 deg"}})
    assert any(p.startswith("estimator.watchdog_angle: the hand-over's watchdog compares the two slots' angles")
               for p in got)
    for key, value in (("watchdog_angle", "180 deg"), ("watchdog_angle", "-1 deg"), ("watchdog_speed", "-1 rpm"),
                       ("watchdog_hold", "11 s")):
        got = problems({"control": {}, "estimator": {"high": "rfo", key: value}})
        assert any(p.startswith(f"estimator.{key}") for p in got), (key, got)
    from golden.control_config import firmware_params
    sc = scenario({"control": {}, "estimator": {"high": "rfo", "watchdog_angle": "45 deg", "watchdog_speed": "100 rpm",
                                                "watchdog_hold": "50 ms"}})
    p = firmware_params(sc)
    pp, f_sw = sc.plant["mech"]["pole_pairs"], sc.pwm.f_sw
    assert (p.wd_delta, p.wd_hold) == (2**29, round(0.05 * f_sw))
    assert p.wd_speed == round(100 / 60 * pp / f_sw * 2**32)
    assert firmware_params(scenario({"control": {}, "estimator": {"high": "rfo"}})).wd_delta == 0   # off by default


def test_the_flying_start_needs_a_high_speed_estimator_and_the_foc_law():
    """protection.catch_time > 0 is refused without estimator.high (nothing could catch the rotor) and under the
    fcs_mpc law (the catch holds the currents at zero with the current PIs); with both it becomes catch_n periods."""
    got = problems({"control": {}, "protection": {"catch_time": "40 ms"}})
    assert any(p.startswith("protection.catch_time: the flying start needs a high-speed estimator") for p in got)
    got = problems({"control": {"law": "fcs_mpc", "polarity": "none", "adc_mode": "DS"},
                    "estimator": {"low": "hfo_proj"}, "protection": {"catch_time": "40 ms"}})
    assert any(p.startswith("protection.catch_time: the flying start holds the currents at zero") for p in got)
    got = problems({"control": {}, "protection": {"catch_time": "-1 ms"}})
    assert any(p.startswith("protection.catch_time") for p in got)
    from golden.control_config import protection_params
    sc = scenario({"control": {}, "estimator": {"high": "rfo"}, "protection": {"catch_time": "40 ms"}})
    assert protection_params(sc).catch_n == round(0.04 * sc.pwm.f_sw)
    off = scenario({"control": {}, "estimator": {"high": "rfo"}, "protection": {"catch_time": "40 ms", "checks": "off"}})
    assert protection_params(off).catch_n == round(0.04 * off.pwm.f_sw)      # no check: it stays with the checks off
