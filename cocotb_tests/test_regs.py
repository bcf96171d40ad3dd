"""pytest side of the hfi_regs tests (AXI4-Lite register block): cocotb_tests/tb_regs.py on both
simulators, at the default ADDR_BITS = 8 and at ADDR_BITS = 12 (upper address bits must not alias).

Random transaction counts: 20 000 (Verilator) / 2 000 (Icarus) at the default point, a tenth of that
at ADDR_BITS = 12 (``HFI_RANDOM_N`` overrides both).
"""

from __future__ import annotations

import pytest

import hdl_runner

N_TESTS = 11  # cocotb tests in tb_regs.py
RANDOM_N = {"verilator": 20_000, "icarus": 2_000}


@pytest.mark.parametrize("addr_bits", [8, 12])
@pytest.mark.parametrize("sim", hdl_runner.SIMULATORS)
def test_regs(sim, addr_bits, tmp_path):
    n = RANDOM_N[sim] if addr_bits == 8 else RANDOM_N[sim] // 10
    hdl_runner.run_cocotb(sim=sim, toplevel="hfi_regs", sources=hdl_runner.rtl_sources("hfi_regs.v"),
                          tb_module="tb_regs", build_dir=tmp_path / "build",
                          parameters={"ADDR_BITS": addr_bits}, expect_tests=N_TESTS, random_n=n)
