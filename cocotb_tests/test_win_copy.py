"""pytest side of the tests of hfi_win_copy (the CPU-clock copy of hfi_dsp's window-result registers):
cocotb_tests/tb_win_copy.py on both simulators, through the wrapper cocotb_tests/hdl/tb_win_copy.v (hfi_win_copy
in s_clk with hfi_soc's reset synchronizer, a source register pair in m_clk driven by the testbench).

hfi_win_copy includes ``regs/hfi_regs_map.vh`` (its mask HFI_WINDOW_COPY_WORDS): found through the include path
rtl/ that hdl_runner.run_cocotb gives every build.

Random counts: HFI_RANDOM_N reads per clock pair of random_clock_ratios (3 fixed pairs and HFI_WINCOPY_PAIRS
random ones, tb_win_copy.N_PAIRS by default), a tenth of it (at least 20) per setup of the reset tests;
``HFI_RANDOM_N`` overrides the defaults below.
"""

from __future__ import annotations

import pytest

import hdl_runner

N_TESTS = 4  # cocotb tests in tb_win_copy.py
RANDOM_N = {"verilator": 3000, "icarus": 3000}
RTL_FILES = ("hfi_cdc_sync.v", "hfi_win_copy.v")


@pytest.mark.parametrize("sim", hdl_runner.SIMULATORS)
def test_win_copy(sim, tmp_path):
    hdl_runner.run_cocotb(
        sim=sim, toplevel="tb_win_copy",
        sources=[*hdl_runner.rtl_sources(*RTL_FILES), hdl_runner.TB_DIR / "hdl" / "tb_win_copy.v"],
        tb_module="tb_win_copy", build_dir=tmp_path / "build", expect_tests=N_TESTS,
        random_n=RANDOM_N[sim])
