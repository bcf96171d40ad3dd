"""pytest entry for the safety logic (rtl/hfi_safety.v with its synchronizers rtl/hfi_cdc_sync.v)
against the golden golden/fpga/safety.py, clock by clock and bit for bit; the cocotb coroutines are in
tb_safety.py.

Clocks per random run: HFI_RANDOM_N (default here 100 000 under Verilator, 50 000 under Icarus;
about 5 s each).
"""

from __future__ import annotations

import pytest

import hdl_runner

N_TESTS = 4  # cocotb tests in tb_safety.py
RANDOM_CLOCKS = {"verilator": 100_000, "icarus": 50_000}


@pytest.mark.parametrize("sim", hdl_runner.SIMULATORS)
def test_safety(sim, tmp_path):
    hdl_runner.run_cocotb(sim=sim, toplevel="hfi_safety",
                          sources=hdl_runner.rtl_sources("hfi_cdc_sync.v", "hfi_safety.v"),
                          tb_module="tb_safety", build_dir=tmp_path / "build", expect_tests=N_TESTS,
                          random_n=RANDOM_CLOCKS[sim])
