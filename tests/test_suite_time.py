"""scripts/suite_time.py (docs/testing.md): the suite's wall time scaled to the reference machine's speed, and its
arguments. The calibration is replaced by a fixed speed so that the arithmetic is exact."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def suite_time():
    spec = importlib.util.spec_from_file_location("suite_time", ROOT / "scripts" / "suite_time.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_a_measured_wall_time_is_scaled_to_the_reference_speed(suite_time, monkeypatch, capsys):
    """900 s on a machine at half the reference speed take 450 s at the reference speed: half the 15 minutes."""
    monkeypatch.setattr(suite_time, "machine_speed", lambda: 0.5 * suite_time.REFERENCE_PLANT_X)
    monkeypatch.setattr("sys.argv", ["suite_time.py", "--wall", "900"])
    assert suite_time.main() == 0
    out = capsys.readouterr().out.splitlines()
    assert out[-4:] == ["suite: wall 15:00",
                        "machine: plant 3.20x .. 3.20x real time, 2.00 times slower than the reference (6.4x)",
                        "at the reference speed: 7:30 (target 15:00: met)",
                        "suite_time_ratio: 0.500"]


@pytest.mark.parametrize("argv, message", [(["--wall", "-3"], "expected a finite number > 0"),
                                           (["--wall", "nan"], "expected a finite number > 0"),
                                           (["--jobs", "0"], "expected an integer >= 1"),
                                           (["--jobs", "two"], "is not an integer")])
def test_bad_arguments_are_refused_in_one_line(suite_time, monkeypatch, capsys, argv, message):
    monkeypatch.setattr("sys.argv", ["suite_time.py", *argv])
    with pytest.raises(SystemExit) as exc:
        suite_time.main()
    assert exc.value.code == 2 and message in capsys.readouterr().err


@pytest.mark.parametrize("plant_x", [0.0, -1.0, float("nan")])
def test_a_plant_benchmark_that_is_no_speed_is_refused(plant_x):
    from hfi.machine_speed import slowdown

    with pytest.raises(ValueError, match="expected a realtime factor > 0"):
        slowdown(plant_x)
