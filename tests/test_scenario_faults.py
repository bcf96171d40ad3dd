"""``[[faults]]`` in scenario files (docs/scenario.md, docs/faults.md): conversion to the plant's
``struct fault`` list and the errors for bad entries."""

from __future__ import annotations

import pytest

from golden.plant import Plant
from golden.plant.binding import ffi
from golden.scenario import FAULT_KIND_IDS, FAULTS, ScenarioError, parse_scenario

KIND = ffi.typeof("enum fault_kind").relements


def scenario(*faults: dict, **tables) -> dict:
    return {"scenario": {"name": "f", "duration": "1 s"}, "motor": {"preset": "benevieri2023_table1"},
            "sensors": {"adc_bits": 12}, **tables, "faults": list(faults)}


def test_every_kind_becomes_its_plant_fault_in_onset_order():
    sc = parse_scenario(scenario(
        {"kind": "rotor_blocked", "at": "0.9 s"},
        {"kind": "sensor_offset", "at": "0.1 s", "phase": "b", "offset": "50 mA", "drift": "2 A/s"},
        {"kind": "sensor_gain", "at": "0.2 s", "phase": "a", "gain": 0.9},
        {"kind": "adc_stuck", "at": "0.3 s", "phase": "c", "code": 4095},
        {"kind": "adc_lane_dead", "at": "0.35 s", "phase": "a"},
        {"kind": "phase_open", "at": "0.4 s", "phase": "c"},
        {"kind": "switch_open", "at": "0.5 s", "switch": "b_lo"},
        {"kind": "dc_link", "at": "0.6 s", "factor": 0.7, "tau": "20 ms"},
        {"kind": "load_step", "at": "0.7 s", "torque": "-4 N*m", "until": "0.8 s"}))
    got = [(f["kind"], f["channel"], f["tick"], f["value"], f["rate"]) for f in sc.plant["faults"]]
    assert [f["until"] for f in sc.plant["faults"]] == [0] * 7 + [80_000_000, 0]
    assert got == [
        (KIND["FAULT_SENSOR_OFFSET"], 1, 10_000_000, 0.05, 2.0),
        (KIND["FAULT_SENSOR_GAIN"], 0, 20_000_000, 0.9, 0.0),
        (KIND["FAULT_ADC_STUCK"], 2, 30_000_000, 4095.0, 0.0),
        (KIND["FAULT_ADC_STUCK"], 0, 35_000_000, 0.0, 0.0),
        (KIND["FAULT_PHASE_OPEN"], 2, 40_000_000, 0.0, 0.0),
        (KIND["FAULT_SWITCH_OPEN"], 3, 50_000_000, 0.0, 0.0),
        (KIND["FAULT_DC_LINK"], 0, 60_000_000, 0.7, 0.02),
        (KIND["FAULT_LOAD_STEP"], 0, 70_000_000, -4.0, 0.0),
        (KIND["FAULT_ROTOR_BLOCKED"], 0, 90_000_000, 0.0, 0.0)]
    assert [f.kind for f in sc.faults][:2] == ["sensor_offset", "sensor_gain"]
    Plant(sc.plant)                                           # the plant accepts the list
    assert set(FAULT_KIND_IDS) == set(KIND) and {v[0] for v in FAULTS.values()} == set(KIND)


def test_no_faults_is_an_empty_list():
    data = scenario()
    del data["faults"]
    assert parse_scenario(data).plant["faults"] == [] and parse_scenario(data).faults == ()


@pytest.mark.parametrize("entry, message", [
    ({"at": "0.1 s"}, "faults[0].kind: missing"),
    ({"kind": "sensor_ofset", "at": "0.1 s"}, "did you mean 'sensor_offset'"),
    ({"kind": "phase_open", "phase": "a"}, "faults[0].at: missing"),
    ({"kind": "phase_open", "at": "0.1 s"}, "faults[0].phase: missing"),
    ({"kind": "phase_open", "at": "0.1 s", "phase": "d"}, "'d' is not one of 'a', 'b', 'c'"),
    ({"kind": "phase_open", "at": "0.1 s", "phase": "a", "gain": 2}, "faults[0].gain: not a key of fault kind"),
    ({"kind": "dc_link", "at": "0.1 s", "factor": 2.5}, "faults[0].factor: must be between"),
    ({"kind": "adc_stuck", "at": "0.1 s", "phase": "a", "code": 4096}, "not a code of a 12-bit ADC"),
    ({"kind": "rotor_blocked", "at": "1 s"}, "not before the end of the run"),
    ({"kind": "load_step", "at": "0.1 s", "torque": "2 V"}, "faults[0].torque"),
    ("phase_open", "faults[0]: expected a table"),
    ({"kind": "rotor_blocked", "at": "0.5 s", "until": "0.5 s"}, "faults[0].until: 500 ms is not after"),
])
def test_bad_entries_name_their_path(entry, message):
    with pytest.raises(ScenarioError, match=message.replace("[", r"\[").replace("]", r"\]")):
        parse_scenario(scenario(entry))


def test_two_open_phases_and_a_load_step_on_an_imposed_speed_are_refused():
    with pytest.raises(ScenarioError, match="at most one phase can be open"):
        parse_scenario(scenario({"kind": "phase_open", "at": "0.1 s", "phase": "a"},
                                {"kind": "phase_open", "at": "0.2 s", "phase": "b"}))
    with pytest.raises(ScenarioError, match="a load step needs load.mode"):
        parse_scenario(scenario({"kind": "load_step", "at": "0.1 s", "torque": "1 N*m"},
                                load={"mode": "speed", "speed": [["0 s", "0 rpm"]]}))
