"""The FPGA build options (docs/rtl.md "Build options") on the SoC: one Verilated hfi_soc with every option left
out (ROT_INJ, DIFF_CIC, FCS_MPC, FLUX_LUT = 0). The firmware reads CAPS before it starts: a scenario whose method
needs a missing block is refused with the missing bits on the UART and the gates never on; a method that needs
none runs on that build exactly as on the full one (the options change nothing else)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from golden import accmap, regmap
from golden.build_options import OPTIONS
from golden.closedloop import WINDOW_FIELDS
from golden.scenario import load_scenario
from hfi.rtl_backend import RtlBackendError, RtlClosedLoop, build_sim

ROOT = Path(__file__).resolve().parents[1]
NONE = {name: 0 for name in OPTIONS}
"""Every option left out."""


def short(name: str, seconds: float):
    return dataclasses.replace(load_scenario(ROOT / "scenarios" / name), duration=seconds)


@pytest.mark.parametrize("scenario,dsp,acc", [
    ("tap2023_fullload.toml", regmap.CAPS_ROT_INJ_MASK, 0),
    ("xue2022_noload.toml", regmap.CAPS_DIFF_CIC_MASK, 0),
    ("varatharajan2020_torquestep.toml", regmap.CAPS_FCS_MPC_MASK, accmap.CAPS_FLUX_LUT_MASK),
])
def test_a_method_without_its_blocks_is_refused(tmp_path, scenario, dsp, acc):
    with pytest.raises(RtlBackendError) as e:
        RtlClosedLoop(short(scenario, 0.002)).run(progress=False, workdir=tmp_path, options=NONE)
    text = str(e.value)
    assert "tick 0" in text and "gates stay off" in text
    assert f"hfi_fw: build lacks the method's blocks: CAPS {dsp}, ACC CAPS {acc}; gates stay off\n" in text


def test_a_method_that_needs_none_runs_as_on_the_full_build(tmp_path):
    sc = short("fullload_start.toml", 0.05)
    full = RtlClosedLoop(sc).run(progress=False, workdir=tmp_path)
    slim = RtlClosedLoop(sc).run(progress=False, workdir=tmp_path, options=NONE)
    for col in WINDOW_FIELDS:
        assert np.array_equal(full.windows[col], slim.windows[col]), col
    assert full.soc["fw_cycles_max"] == slim.soc["fw_cycles_max"]


def test_unknown_or_bad_options_are_refused():
    with pytest.raises(RtlBackendError, match="build option CIC=0: expected one of ROT_INJ, DIFF_CIC, FCS_MPC, FLUX_LUT"):
        build_sim(options={"CIC": 0})
    with pytest.raises(RtlBackendError, match="build option ROT_INJ=2"):
        build_sim(options={"ROT_INJ": 2})
