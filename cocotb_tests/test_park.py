"""pytest entry of the hfi_park cocotb tests (rtl/hfi_park.v: Clarke + Park, spec 3.2)."""

from __future__ import annotations

import pytest

import hdl_runner


@pytest.mark.parametrize("sim", hdl_runner.SIMULATORS)
def test_park(sim, tmp_path):
    hdl_runner.run_cocotb(sim=sim, toplevel="hfi_park", sources=hdl_runner.rtl_sources("hfi_mul18.v", "hfi_park.v"),
                          tb_module="tb_park", build_dir=tmp_path / "build", expect_tests=2)
