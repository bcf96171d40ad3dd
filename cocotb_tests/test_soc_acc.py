"""pytest side of the SoC accelerator tests: cocotb_tests/tb_soc_acc.py on both simulators, through the wrapper
cocotb_tests/hdl/tb_soc_acc_ram.v (rtl/hfi_soc_acc.v with hfi_cordic and hfi_flux_lut, and hfi_ram on its
data port holding the 003 scenario's flux-map tables: a $readmemh image written here). Random counts:
sine/cosine angles HFI_RANDOM_N (2000 under Verilator, 500 under Icarus), look-ups a tenth of that (at
least 50): the units' own tests cover their ranges."""

from __future__ import annotations

import pytest

import hdl_runner
from tb_soc_acc import RAM_AW, ram_image

N_TESTS = 3  # cocotb tests in tb_soc_acc.py
RANDOM_N = {"verilator": 2000, "icarus": 500}
RTL_FILES = ("hfi_soc_acc.v", "hfi_cordic.v", "hfi_vector.v", "hfi_flux_lut.v", "hfi_ram.v")


@pytest.mark.parametrize("sim", hdl_runner.SIMULATORS)
def test_soc_acc(sim, tmp_path):
    build = tmp_path / "build"
    build.mkdir(parents=True)
    image = build / "ram_init.hex"
    image.write_text("".join(f"{w:08x}\n" for w in ram_image()))
    hdl_runner.run_cocotb(
        sim=sim, toplevel="tb_soc_acc_ram",
        sources=[*hdl_runner.rtl_sources(*RTL_FILES), hdl_runner.TB_DIR / "hdl" / "tb_soc_acc_ram.v"],
        tb_module="tb_soc_acc", build_dir=build, parameters={"RAM_AW": RAM_AW, "RAM_INIT": f'"{image}"'},
        expect_tests=N_TESTS, random_n=RANDOM_N[sim])
