"""The FPGA build options (docs/rtl.md "Build options") on the SoC: one Verilated hfi_soc with every option left
out (ROT_INJ, DIFF_CIC, FCS_MPC, FLUX_LUT = 0: the 002 system's, which the rtl backend simulates for the default
scenario), one with every block in, and one without the accelerators (ACC = 0, with its own firmware image). The
firmware reads CAPS before it starts: a scenario whose method needs a missing block is refused with the missing bits
on the UART and the gates never on; a method that needs none runs on that build exactly as on the full one (the
options change nothing else), and so does the SoC without the accelerators."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from golden import accmap, regmap
from golden.build_options import OPTIONS
from golden.closedloop import WINDOW_FIELDS
from golden.scenario import load_scenario
from hfi.rtl_backend import EVERY_BLOCK, RtlBackendError, RtlClosedLoop, build_sim

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
    """The options left out change nothing else, not even the firmware's clocks; the Tang Nano 20K's SoC, without
    the accelerators and the fixed-point unit (``ACC = 0``, ``CFU = 0``), with its own image (``make -C firmware
    ACC=0 CFU=0``: the firmware's own sin/cos, vector angle and flux-map look-up, fw_fx.h's plain C) gives every
    window column equal too, in more clocks."""
    sc = short("fullload_start.toml", 0.05)
    full = RtlClosedLoop(sc).run(progress=False, workdir=tmp_path, options=EVERY_BLOCK)
    slim = RtlClosedLoop(sc).run(progress=False, workdir=tmp_path)        # the scenario's system: 002 needs none
    no_acc = RtlClosedLoop(sc).run(progress=False, workdir=tmp_path, acc=False, cfu=False)
    assert full.soc["left_out"] == []
    assert slim.soc["left_out"] == no_acc.soc["left_out"] == list(OPTIONS)
    for col in WINDOW_FIELDS:
        assert np.array_equal(full.windows[col], slim.windows[col]), col
        assert np.array_equal(full.windows[col], no_acc.windows[col]), col
    assert full.soc["fw_cycles_max"] == slim.soc["fw_cycles_max"] < no_acc.soc["fw_cycles_max"]



def _syrm_with_table():
    """The first run of the 002-on-SyRM sweep with the square wave's cross-saturation table on, 2 ms."""
    import hfi.sweep as sw
    from golden.scenario import parse_scenario

    job = sw.jobs(sw.load_spec(ROOT / "sweeps" / "cross_002_on_003.toml"), "test")[0]
    sw._set(job.tree, "estimator.sqw_bangbang.cross_saturation", "on")
    return dataclasses.replace(parse_scenario(job.tree, "cross_002_on_003"), duration=0.002)


@pytest.mark.parametrize("what", ["probe", "xs"])
def test_the_image_without_accelerators_refuses_the_probe_and_the_tables(tmp_path, what):
    """The image without the accelerators has no room for the flying start's probe nor the cross-saturation look-up
    (firmware/Makefile FW_NO_PROBE, FW_NO_XS): a scenario that asks for one (scenarios/flying_start.toml, catch_probe
    50 mA; the 002 method on the SyRM with its table) is refused with the line, the gates never on."""
    sc = short("flying_start.toml", 0.002) if what == "probe" else _syrm_with_table()
    with pytest.raises(RtlBackendError) as e:
        RtlClosedLoop(sc).run(progress=False, workdir=tmp_path, acc=False, cfu=False)
    text = str(e.value)
    assert "tick 0" in text
    assert "hfi_fw: not in this image: protection.catch_probe, estimator.*.cross_saturation; gates stay off\n" in text


def test_unknown_or_bad_options_are_refused():
    with pytest.raises(RtlBackendError, match="build option CIC=0: expected one of ROT_INJ, DIFF_CIC, FCS_MPC, FLUX_LUT"):
        build_sim(options={"CIC": 0})
    with pytest.raises(RtlBackendError, match="build option ROT_INJ=2"):
        build_sim(options={"ROT_INJ": 2})


def test_the_suite_builds_without_the_profile_guided_training(monkeypatch, tmp_path):
    """The default scenario's system is built profile-guided (an instrumented build, the training run, a second
    compile); with HFI_SIM_PGO=0 (`make test`) a plain build beside it (``<variant>_plain``), unless the profile-guided
    one is up to date, which then serves. The compiler and the training are recorded here, not run."""
    from hfi import rtl_backend

    calls = []

    def fake_run(cmd, what, cwd=ROOT):
        calls.append(what)
        if "-o" in cmd:                                  # a Verilator build: its library and object directory
            Path(cmd[cmd.index("--Mdir") + 1]).mkdir(parents=True, exist_ok=True)
            Path(cmd[cmd.index("-o") + 1]).write_bytes(b"lib")

    monkeypatch.setattr(rtl_backend, "_run", fake_run)
    monkeypatch.setattr(rtl_backend, "OUT_SIM", tmp_path)
    monkeypatch.setenv("HFI_SIM_PGO", "0")
    plain = build_sim(options=NONE)
    assert plain.parent.name.endswith("_plain") and calls == ["Verilator build of hfi_soc"]
    monkeypatch.delenv("HFI_SIM_PGO")
    calls.clear()
    guided = build_sim(options=NONE)
    assert guided.parent.name == plain.parent.name.removesuffix("_plain")
    assert calls == ["Verilator build of hfi_soc", "training run of the profile-guided build",
                     "Verilator build of hfi_soc"]
    monkeypatch.setenv("HFI_SIM_PGO", "0")
    calls.clear()
    assert build_sim(options=NONE) == guided and calls == []          # up to date: it serves
    assert build_sim(options=EVERY_BLOCK).parent.name == "fast" and calls == ["Verilator build of hfi_soc"]
