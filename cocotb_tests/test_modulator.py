"""cocotb tests of rtl/hfi_modulator.v (with its hfi_deadtime_comp) against the golden compare chain.

The testbench is cocotb_tests/tb_modulator.py; it draws HFI_RANDOM_N random start vectors (100 000
under Verilator, 2 000 under Icarus by default) and runs the directed cases (register extremes,
over-modulation, min-max ties, reset values, reset in mid-operation, start while busy / held high).
"""

from __future__ import annotations

import pytest

import hdl_runner


@pytest.mark.parametrize("sim", hdl_runner.SIMULATORS)
def test_modulator(sim, tmp_path):
    hdl_runner.run_cocotb(sim=sim, toplevel="hfi_modulator",
                          sources=hdl_runner.rtl_sources("hfi_modulator.v", "hfi_mul18.v", "hfi_deadtime_comp.v",
                                                           "hfi_fcs_mpc.v"),
                          tb_module="tb_modulator", build_dir=tmp_path / "build", expect_tests=7)
