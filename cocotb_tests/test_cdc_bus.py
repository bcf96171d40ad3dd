"""pytest side of the clock-domain crossing tests: cocotb_tests/tb_cdc_bus.py on both simulators, through
the wrapper cocotb_tests/hdl/tb_cdc_bus.v (hfi_cdc_bus between two clocks with hfi_soc's reset
synchronizers, and three hfi_cdc_sync on a third clock).

Random counts: HFI_RANDOM_N bus accesses per clock pair (random_clock_ratios: N_PAIRS pairs, overridden by
HFI_CDC_PAIRS) and per directed test; ``HFI_RANDOM_N`` overrides the defaults below.
"""

from __future__ import annotations

import pytest

import hdl_runner

N_TESTS = 7  # cocotb tests in tb_cdc_bus.py
RANDOM_N = {"verilator": 250, "icarus": 250}
RTL_FILES = ("hfi_cdc_sync.v", "hfi_cdc_bus.v")


@pytest.mark.parametrize("sim", hdl_runner.SIMULATORS)
def test_cdc_bus(sim, tmp_path):
    hdl_runner.run_cocotb(
        sim=sim, toplevel="tb_cdc_bus",
        sources=[*hdl_runner.rtl_sources(*RTL_FILES), hdl_runner.TB_DIR / "hdl" / "tb_cdc_bus.v"],
        tb_module="tb_cdc_bus", build_dir=tmp_path / "build", expect_tests=N_TESTS,
        random_n=RANDOM_N[sim])
