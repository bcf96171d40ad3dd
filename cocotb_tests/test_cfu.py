"""pytest side of the fixed-point instruction unit's tests: cocotb_tests/tb_cfu.py on rtl/hfi_cfu.v, both
simulators (HFI_RANDOM_N random instructions: ``hdl_runner.random_count``, the suite's or ``make deep``'s depth)."""

from __future__ import annotations

import pytest

import hdl_runner

N_TESTS = 3  # cocotb tests in tb_cfu.py


@pytest.mark.parametrize("sim", hdl_runner.SIMULATORS)
def test_cfu(sim, tmp_path):
    hdl_runner.run_cocotb(sim=sim, toplevel="hfi_cfu", sources=hdl_runner.rtl_sources("hfi_cfu.v"),
                          tb_module="tb_cfu", build_dir=tmp_path / "build", expect_tests=N_TESTS)
