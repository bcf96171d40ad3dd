"""cocotb tests of rtl/hfi_deadtime_comp.v against golden/fpga/deadtime_comp.py ``compensate``.

The testbench is cocotb_tests/tb_deadtime_comp.py: HFI_RANDOM_N random compare sets (``hdl_runner.random_count``:
100 000 under Verilator, 10 000 under Icarus in ``make deep``) and the directed cases (extremes, i_x around the RTL's
saturation bound, start while busy, reset in mid-operation).
"""

from __future__ import annotations

import pytest

import hdl_runner


@pytest.mark.parametrize("sim", hdl_runner.SIMULATORS)
def test_deadtime_comp(sim, tmp_path):
    hdl_runner.run_cocotb(sim=sim, toplevel="hfi_deadtime_comp",
                          sources=hdl_runner.rtl_sources("hfi_mul18.v", "hfi_deadtime_comp.v"),
                          tb_module="tb_deadtime_comp", build_dir=tmp_path / "build", expect_tests=6)
