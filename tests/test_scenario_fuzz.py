"""Bad scenario values never end in a traceback (docs/scenario.md, "Errors"): every key of the schema, in three
closed-loop scenarios (the 002, 000 and 001 drives), set to values no drive has (zero, negative, 2^70, 1e+-30,
NaN, infinities, the wrong type, the scenario's own value scaled by 1e-9..1e9) and, with Hypothesis, to arbitrary
numbers, strings with any of the unit table's symbols, booleans and lists. What ``hfi check`` does with each
(golden.scenario.parse_scenario, then hfi.cli.check_scenario: the plant, the register values, the firmware's
integers) either accepts it or raises a ValueError, the one-line error of the command line; nothing else. The
default scenario's accepted cases also run 1 ms on golden, with the same rule.

The 003 drive is left out: its flux tables take a second per scenario (its keys are parsed by the same code)."""

from __future__ import annotations

import copy
import dataclasses
import math
import os
import re
import tomllib
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from golden.closedloop import ClosedLoop
from golden.scenario import SCHEMA, parse_scenario
from golden.units import UNITS
from hfi.cli import check_scenario, main

ROOT = Path(__file__).resolve().parents[1]
FILES = ("fullload_start.toml", "tap2023_fullload.toml", "xue2022_noload.toml")
BASES = {name: tomllib.loads((ROOT / "scenarios" / name).read_text()) for name in FILES}
KEYS = sorted(f"{section}.{key}" for section, keys in SCHEMA.items() if section
              for key, field in keys.items() if field.kind != "table")
"""Every value key of the schema (dotted path), whether a scenario file has it or not."""
EXTREMES = (0, -1, 1, 2**70, -2**70, 1e30, -1e30, 1e-30, math.nan, math.inf, -math.inf, True, "abc", "", [], {},
            [1, 2])
FACTORS = (1e-9, 1e-3, 0.1, 10, 1e3, 1e9, -1)


def with_value(base: dict, path: str, value) -> dict:
    """A copy of the scenario tree ``base`` with ``path`` set to ``value`` (tables created on the way)."""
    data = copy.deepcopy(base)
    *tables, key = path.split(".")
    node = data
    for t in tables:
        node = node.setdefault(t, {})
        if not isinstance(node, dict):          # a key of the file is a value where the schema has a table
            return data
    node[key] = value
    return data


def own_value(base: dict, path: str):
    node = base
    for part in path.split("."):
        if not isinstance(node, dict) or part not in node:
            return None
        node = node[part]
    return node


def scaled(value) -> list:
    """``value`` times :data:`FACTORS`: a number, or the number of a quantity string with its unit."""
    if isinstance(value, bool):
        return []
    if isinstance(value, (int, float)):
        return [type(value)(value * f) for f in FACTORS]
    if isinstance(value, str):
        number, _, unit = value.partition(" ")
        try:
            x = float(number)
        except ValueError:
            return []
        return [f"{x * f:g} {unit}".strip() for f in FACTORS]
    return []


def outcome(data: dict, run_s: float = 0.0) -> str:
    """``"ok"`` or ``"refused"``; any exception but a ValueError propagates (the test's failure). ``run_s`` > 0:
    an accepted scenario also runs that long on the golden backend (a diverging plant stops with a PlantError)."""
    try:
        sc = parse_scenario(data, source="fuzz")
        check_scenario(sc)
        if run_s > 0 and sc.control is not None:
            ClosedLoop(dataclasses.replace(sc, duration=run_s)).run(progress=False)
    except ValueError:
        return "refused"
    return "ok"


@pytest.mark.parametrize("name", FILES)
def test_every_key_with_extreme_values(name):
    """The default scenario's accepted cases also run 1 ms (5 windows) on golden: values the parser cannot call
    absurd (a dc-link resistance of 1e30 ohm) make the plant diverge, which stops the run with PLANT_NOT_FINITE's
    message instead of turning a NaN into ADC codes."""
    base = BASES[name]
    run_s = 1e-3 if name == "fullload_start.toml" else 0.0
    counts = {"ok": 0, "refused": 0}
    for path in KEYS:
        for value in EXTREMES + tuple(scaled(own_value(base, path))):
            counts[outcome(with_value(base, path, value), run_s)] += 1
    print(name, counts)
    assert counts["refused"] > counts["ok"] > 0     # the values are mostly bad, and the harmless ones pass


UNIT_SYMBOLS = sorted(UNITS)
values = st.one_of(
    st.integers(min_value=-2**80, max_value=2**80),
    st.floats(allow_nan=True, allow_infinity=True),
    st.booleans(),
    st.text(max_size=12),
    st.builds(lambda x, u: f"{x!r} {u}", st.floats(allow_nan=True, allow_infinity=True), st.sampled_from(UNIT_SYMBOLS)),
    st.lists(st.floats(allow_nan=True), max_size=3),
)


FUZZ_EXAMPLES = int(os.environ.get("FUZZ_SCENARIO_EXAMPLES") or 300)
"""Arbitrary values tried: 300 in ``make test``, the same ones every run (derandomized); ``make fuzz`` sets
``FUZZ_SCENARIO_EXAMPLES`` (100 000, about 5 minutes) and searches anew each run (2026-12-01: 220 000 examples found
six values that crashed with a traceback, each a test below)."""


@settings(max_examples=FUZZ_EXAMPLES, derandomize="FUZZ_SCENARIO_EXAMPLES" not in os.environ, database=None,
          deadline=None, suppress_health_check=list(HealthCheck))
@given(name=st.sampled_from(FILES), path=st.sampled_from(KEYS), value=values)
def test_arbitrary_values_are_accepted_or_refused(name, path, value):
    outcome(with_value(BASES[name], path, value))


def test_check_refuses_what_a_run_would_with_the_key(tmp_path, capsys):
    """A current-loop bandwidth whose PI gain needs more than the firmware's 31 bits: ``hfi check`` says so in one
    line that names the key, as ``hfi run`` would."""
    text = (ROOT / "scenarios" / "fullload_start.toml").read_text()
    assert 'current_bw = "150 Hz"' in text
    path = tmp_path / "wide.toml"
    path.write_text(text.replace('current_bw = "150 Hz"', 'current_bw = "150 MHz"'))
    assert main(["check", str(path)]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert err.startswith(f"{path}: control.current_bw (the current PIs' gains, with L = ")
    assert "out of range 0..2^31-1" in err


@pytest.mark.parametrize("path, value, key", [
    ("control.speed_bw", 1.3966812486703196e+153, "control.speed_bw and speed_rate (the speed PI's gains"),
    ("control.i_pulse", 2.7430620343968443e+304, "control.i_pulse: "),
    ("estimator.rot_bpf.observer_bw", 8.982391602669073e+105, "estimator rot_bpf: a gain is beyond a float"),
    ("control.sample_interval", 1.797693134862316e+300, "control.sample_interval: "),
    ("simulation.max_substep", 1.7976931330646225e+300, "simulation.max_substep: "),
    ("model_error.L_d", 5e-324, "model_error.L_d: "),
])
def test_values_found_by_the_fuzz_are_refused_with_their_key(path, value, key):
    """Values the arbitrary-value search found (2026-12-01) that overflowed a float with a traceback (OverflowError):
    the speed PI's gain from a speed bandwidth of 1.4e153 Hz (golden.fixed.to_fixed now refuses a value whose scaled
    magnitude is not finite), the polarity pulse of the 000 drive, unused with its pilot polarity but still
    converted (golden/limits.py: below the sensors' range), the 000 motion observer's (a T)^3 at 9e105 Hz
    (control_config.motion_gains), a sample interval and a plant substep of 1.8e300 s in ticks (limits._ticks,
    scenario._to_ticks), and a model-error factor of 5e-324 that divided by zero (factors within 0.01..100)."""
    name = "tap2023_fullload.toml" if path.startswith(("control.i_pulse", "estimator")) else "fullload_start.toml"
    with pytest.raises(ValueError, match=re.escape(key)):
        sc = parse_scenario(with_value(BASES[name], path, value), source="fuzz")
        check_scenario(sc)
