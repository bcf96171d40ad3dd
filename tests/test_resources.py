"""hfi/resources.py: the FPGA resources of the compared systems (``hfi compare``'s section) with a stand-in for the
synthesis: which options each system's methods need, the differences to the shared base, the cache, the table;
and golden/build_options.py: the options are the CAPS fields, the methods name only those."""

from __future__ import annotations

import copy
import json
import re
from pathlib import Path

import pytest

from golden import accmap, build_options, regmap
from golden.firmware.estimator import METHODS
from golden.scenario import parse_scenario
from hfi import compare, resources
from hfi.sweep import load_spec

ROOT = Path(__file__).resolve().parents[1]


def systems():
    return {s: parse_scenario(copy.deepcopy(load_spec(compare.spec_path(s)).base), s) for s in compare.SYSTEMS}


class Synth:
    """Counts as a function of the options: every option adds its own amount, so the differences are known."""

    ADD = {"ROT_INJ": (482, 175, 0, 0), "DIFF_CIC": (129, 360, 0, 0), "FCS_MPC": (372, 477, 1, 0),
           "FLUX_LUT": (5089, 3230, 4, 1)}
    BASE = {"hfi_dsp": (4748, 4118, 6, 0), "hfi_soc_acc": (1284, 606, 4, 0)}

    def __init__(self):
        self.runs = []

    def __call__(self, top, params):
        self.runs.append((top, dict(params)))
        counts = list(self.BASE[top])
        for name, on in params.items():
            counts = [c + on * a for c, a in zip(counts, self.ADD[name])]
        return dict(zip(resources.COUNTS, counts))


def test_each_system_needs_its_methods_options():
    assert {s: resources.options(sc) for s, sc in systems().items()} == {
        "002": (), "000": ("ROT_INJ",), "001": ("DIFF_CIC",), "001r": ("DIFF_CIC",), "003": ("FCS_MPC", "FLUX_LUT")}


def test_added_to_the_base_and_cached(tmp_path):
    cache, synth = tmp_path / "resources.json", Synth()
    base, items = resources.resources(systems(), cache, log=lambda _: None, synth=synth, key=lambda: "k1")
    assert base == {"hfi_dsp": dict(zip(resources.COUNTS, Synth.BASE["hfi_dsp"])),
                    "hfi_soc_acc": dict(zip(resources.COUNTS, Synth.BASE["hfi_soc_acc"]))}
    by = {r.system: r for r in items}
    assert by["002"].added == {}
    assert by["000"].added == {"hfi_dsp": {"lut": 482, "ff": 175, "dsp": 0, "bram": 0}}
    assert by["003"].added == {"hfi_dsp": {"lut": 372, "ff": 477, "dsp": 1, "bram": 0},
                               "hfi_soc_acc": {"lut": 5089, "ff": 3230, "dsp": 4, "bram": 1}}
    # one run per distinct module and option set: two bases, three hfi_dsp variants, one accelerator variant
    assert len(synth.runs) == 6
    assert ("hfi_dsp", {"ROT_INJ": 0, "DIFF_CIC": 0, "FCS_MPC": 1}) in synth.runs
    # a second call reads the cache; a changed RTL (another key) synthesizes again
    again = Synth()
    assert resources.resources(systems(), cache, log=lambda _: None, synth=again, key=lambda: "k1")[1] == items
    assert again.runs == []
    resources.resources(systems(), cache, log=lambda _: None, synth=again, key=lambda: "k2")
    assert len(again.runs) == 6 and json.loads(cache.read_text())["key"] == "k2"


def test_table_lines(tmp_path):
    base, items = resources.resources(systems(), tmp_path / "r.json", log=lambda _: None, synth=Synth(),
                                      key=lambda: "k")
    lines = resources.table(base, items, {"003": "003 (Varatharajan 2020)"})
    assert "- shared `hfi_dsp` (every option out): 4748 LUT, 4118 FF, 6 DSP, 0 BRAM" in lines
    assert lines[-1] == ("| 003 (Varatharajan 2020) | `FCS_MPC`, `FLUX_LUT` | +372 LUT, +477 FF, +1 DSP | "
                         "+5089 LUT, +3230 FF, +4 DSP, +1 BRAM |")
    assert "| 002 | none | +0 | +0 |" in lines


def test_options_are_the_caps_fields_and_the_verilog_parameters():
    assert build_options.DSP_OPTIONS == ("ROT_INJ", "DIFF_CIC", "FCS_MPC")
    assert build_options.ACC_OPTIONS == ("FLUX_LUT",)
    assert build_options.caps_masks(["ROT_INJ", "FCS_MPC", "FLUX_LUT"]) == (
        regmap.CAPS_ROT_INJ_MASK | regmap.CAPS_FCS_MPC_MASK, accmap.CAPS_FLUX_LUT_MASK)
    with pytest.raises(ValueError, match="unknown build option 'CIC'"):
        build_options.caps_masks(["CIC"])
    for top, names in resources.TOPS.items():
        header = (ROOT / "rtl" / f"{top}.v").read_text().split(") (", 1)[0]
        assert {n for n in names} <= set(re.findall(r"parameter (\w+) = 1\b", header)), top
    # every method names known options only, and the firmware's tables are generated from them
    for m in METHODS.values():
        build_options.caps_masks(m.hardware)
    text = (ROOT / "firmware" / "src" / "fw_methods.h").read_text()
    assert "#define FW_METHOD_DSP_CAPS {[3] = 0x1u, [5] = 0x2u, [6] = 0x4u}" in text
    assert "#define FW_METHOD_ACC_CAPS {[6] = 0x1u}" in text


def test_headline_cells(tmp_path):
    """The headline's columns for the firmware and the FPGA blocks (hfi.compare.headline)."""
    from hfi import costs

    _, items = resources.resources(systems(), tmp_path / "r.json", log=lambda _: None, synth=Synth(), key=lambda: "k")
    by = {r.system: resources.summary(r) for r in items}
    assert by["002"] == "none (the shared base)"
    assert by["000"] == "ROT_INJ: +482 LUT, +175 FF"
    assert by["003"] == "FCS_MPC, FLUX_LUT: +5461 LUT, +3707 FF, +5 DSP, +1 BRAM"
    c = costs.Cost("003", 10e3, 5e3, 5000, 8715.0, 9108, 8000.0, 9200)
    assert costs.worst_of_period(c) == "9108 / 5000 (at 5 kHz)"
    assert costs.worst_of_period(costs.Cost("003", 10e3, float("nan"), 5000, error="x")) == "not measured"
    lines = compare.headline([], {"002": "002", "003": "003"}, {"003": ("9108 / 5000 (at 5 kHz)", by["003"])})
    assert lines[0].endswith("| firmware in RUN [CPU clocks worst / period] | own FPGA blocks [xc7] |")
    assert lines[2].endswith("| - | - |") and lines[3].endswith(f"| 9108 / 5000 (at 5 kHz) | {by['003']} |")
    assert compare.headline([], {"002": "002"})[0].endswith("[% rated copper loss] |")
