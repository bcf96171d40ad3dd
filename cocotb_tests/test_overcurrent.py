"""pytest entry of the hfi_overcurrent cocotb tests (rtl/hfi_overcurrent.v, spec 3.7)."""

from __future__ import annotations

import pytest

import hdl_runner


@pytest.mark.parametrize("sim", hdl_runner.SIMULATORS)
def test_overcurrent(sim, tmp_path):
    hdl_runner.run_cocotb(sim=sim, toplevel="hfi_overcurrent",
                          sources=hdl_runner.rtl_sources("hfi_overcurrent.v"),
                          tb_module="tb_overcurrent", build_dir=tmp_path / "build", expect_tests=2)
