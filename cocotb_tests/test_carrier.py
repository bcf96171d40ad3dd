"""pytest entry for the carrier (rtl/hfi_carrier.v) against golden/fpga/carrier.py and the weight angle
of golden/fpga/cordic.demod_weight; the cocotb coroutines are in tb_carrier.py."""

from __future__ import annotations

import pytest

import hdl_runner


@pytest.mark.parametrize("sim", hdl_runner.SIMULATORS)
def test_carrier(sim, tmp_path):
    hdl_runner.run_cocotb(sim=sim, toplevel="hfi_carrier", sources=hdl_runner.rtl_sources("hfi_carrier.v"),
                          tb_module="tb_carrier", build_dir=tmp_path / "build", expect_tests=5)
