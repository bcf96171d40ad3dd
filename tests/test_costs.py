"""hfi/costs.py: the firmware cost of the compared systems (``hfi compare``'s section), with a stand-in for the rtl
backend: the slower copy on an overrun, the error of a failed run, the cache, the table's numbers."""

from __future__ import annotations

import copy
import json
import math
import tomllib
from pathlib import Path

from golden.scenario import parse_scenario
from hfi import costs, soc_platform
from hfi.backends import BackendError

ROOT = Path(__file__).resolve().parents[1]
BASE = tomllib.loads((ROOT / "scenarios" / "tap2023_fullload.toml").read_text())
SOC = {"fw_cycles_run_mean": 3991.4, "fw_cycles_run_max": 4280, "fw_cycles_mean": 3500.0, "fw_cycles_max": 4300}


def scenario():
    return parse_scenario(copy.deepcopy(BASE), "tap2023_fullload.toml")


class Backend:
    """Answers each run with ``answers`` in turn (a dict: the soc; an exception: raised), and keeps the runs."""

    def __init__(self, *answers):
        self.answers, self.runs = list(answers), []

    def __call__(self, sc):
        self.runs.append(sc)
        a = self.answers.pop(0)
        if isinstance(a, Exception):
            raise a
        return a


def test_measured_in_its_own_scenario():
    sc = scenario()
    b = Backend(SOC)
    c = costs.measure("000", sc, b)
    assert [r.duration for r in b.runs] == [costs.DURATION] and b.runs[0].pwm.f_sw == sc.pwm.f_sw == 10e3
    # 100 MHz tick / 2 = 50 MHz CPU clock: 5000 clocks per 100 us
    assert c.period_clocks == round(sc.pwm.tick_hz / soc_platform.CPU_CLOCK_DIVIDER / 10e3) == 5000
    assert (c.run_mean, c.run_max, c.mean, c.max, c.measured_f_sw, c.error) == (3991.4, 4280, 3500.0, 4300, 10e3, "")
    assert c.share(c.run_max) == 4280 / 5000


def test_an_overrun_is_measured_on_a_slower_copy():
    b = Backend(BackendError(f"co-simulation stopped: its control step takes {costs.OVERRUN}"), SOC)
    c = costs.measure("003", scenario(), b)
    assert [r.pwm.f_sw for r in b.runs] == [10e3, 5e3]
    assert c.measured_f_sw == 5e3 and c.f_sw == 10e3 and c.period_clocks == 5000 and c.run_max == 4280
    line = costs.table([c], {"003": "003 (Varatharajan 2020)"})[-1]
    assert line == ("| 003 (Varatharajan 2020) | 5000 | 3991 / 4280 | 80 % / 86 % | 3500 / 4300 | "
                    "5 kHz (its 10 kHz overruns) |")


def test_other_errors_are_reported_not_retried():
    b = Backend(BackendError("verilator is not on PATH\nmore"))
    c = costs.measure("002", scenario(), b)
    assert len(b.runs) == 1 and c.error == "verilator is not on PATH" and math.isnan(c.measured_f_sw)
    assert costs.table([c], {})[-1] == "| 002 | 5000 | not measured: verilator is not on PATH | - | - | - |"


def test_every_copy_overruns():
    b = Backend(*[BackendError(costs.OVERRUN)] * len(costs.SLOWER))
    c = costs.measure("003", scenario(), b)
    assert [r.pwm.f_sw for r in b.runs] == [10e3 / k for k in costs.SLOWER] and c.error == costs.OVERRUN


def test_no_step_in_run():
    c = costs.measure("000", scenario(), Backend(dict(SOC, fw_cycles_run_mean=None, fw_cycles_run_max=None)))
    assert costs.table([c], {})[-1] == "| 000 | 5000 | - | - | 3500 / 4300 | 10 kHz |"


def test_the_cache(tmp_path):
    cache = tmp_path / "costs.json"
    b = Backend(SOC, dict(SOC, fw_cycles_run_max=4000))
    first = costs.costs({"000": BASE}, cache, log=lambda *_: None, run=b)
    again = costs.costs({"000": BASE}, cache, log=lambda *_: None, run=b)
    assert len(b.runs) == 1 and first == again and json.loads(cache.read_text())["000"]["cost"]["run_max"] == 4280
    changed = copy.deepcopy(BASE)
    changed["scenario"]["seed"] = 12345
    third = costs.costs({"000": changed}, cache, log=lambda *_: None, run=b)
    assert len(b.runs) == 2 and third[0].run_max == 4000


def test_the_key_follows_the_firmware(tmp_path, monkeypatch):
    (tmp_path / "firmware").mkdir()
    src = tmp_path / "firmware" / "a.c"
    src.write_text("int a;")
    monkeypatch.setattr(costs, "ROOT", tmp_path)
    monkeypatch.setattr(costs, "SOURCES", ("firmware",))
    before = costs.source_digest("x")
    src.write_text("int b;")
    assert costs.source_digest("x") != before and costs.source_digest("x") != costs.source_digest("y")


def test_the_key_follows_the_core(tmp_path, monkeypatch):
    """Another soft core (its branch prediction or caches) measures other clocks: the cache key changes."""
    from hfi import rtl_backend

    core = tmp_path / "VexRiscv_X.v"
    core.write_text("module VexRiscv (); endmodule")
    monkeypatch.setattr(rtl_backend, "cpu_source", lambda: core)
    before = costs.source_digest("x")
    core.write_text("module VexRiscv (); /* another predictor */ endmodule")
    assert costs.source_digest("x") != before
