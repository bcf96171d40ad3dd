"""pytest entry of the hfi_demodulator cocotb tests (rtl/hfi_demodulator.v, spec 3.4)."""

from __future__ import annotations

import pytest

import hdl_runner


@pytest.mark.parametrize("sim", hdl_runner.SIMULATORS)
def test_demodulator(sim, tmp_path):
    hdl_runner.run_cocotb(sim=sim, toplevel="hfi_demodulator",
                          sources=hdl_runner.rtl_sources("hfi_demodulator.v"),
                          tb_module="tb_demodulator", build_dir=tmp_path / "build", expect_tests=3)
