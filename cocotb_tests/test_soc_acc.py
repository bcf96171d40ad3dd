"""pytest side of the SoC accelerator tests: cocotb_tests/tb_soc_acc.py on both simulators (rtl/hfi_soc_acc.v
with hfi_cordic and hfi_flux_lut). Random counts: sine/cosine angles HFI_RANDOM_N (2000 under Verilator,
500 under Icarus), look-ups a tenth of that (at least 50): the units' own tests cover their ranges."""

from __future__ import annotations

import pytest

import hdl_runner

N_TESTS = 3  # cocotb tests in tb_soc_acc.py
RANDOM_N = {"verilator": 2000, "icarus": 500}
RTL_FILES = ("hfi_soc_acc.v", "hfi_cordic.v", "hfi_flux_lut.v")


@pytest.mark.parametrize("sim", hdl_runner.SIMULATORS)
def test_soc_acc(sim, tmp_path):
    hdl_runner.run_cocotb(
        sim=sim, toplevel="hfi_soc_acc", sources=hdl_runner.rtl_sources(*RTL_FILES), tb_module="tb_soc_acc",
        build_dir=tmp_path / "build", expect_tests=N_TESTS, random_n=RANDOM_N[sim])
