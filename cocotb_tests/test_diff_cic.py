"""pytest entry of the hfi_diff_cic cocotb tests (rtl/hfi_diff_cic.v: differencing, envelope, CIC, spec 3.9)."""

from __future__ import annotations

import pytest

import hdl_runner


@pytest.mark.parametrize("sim", hdl_runner.SIMULATORS)
def test_diff_cic(sim, tmp_path):
    hdl_runner.run_cocotb(sim=sim, toplevel="hfi_diff_cic", sources=hdl_runner.rtl_sources("hfi_diff_cic.v"),
                          tb_module="tb_diff_cic", build_dir=tmp_path / "build", expect_tests=3)
