"""hfi_dsp safety in hardware (issue 4 item 4): the overcurrent comparator switches every gate off
within 2 µs of the sampling instant and latches FAULT.OC until FAULT_CLEAR; the watchdog turns the
gates off after WDT_PERIODS windows without a commit. The formal proof of the gate generator is in
tests/test_prove.py; the dead-time floor in cocotb_tests/test_gate_gen.py."""

from __future__ import annotations

import pytest

from golden import regmap as rm
from hdl_runner import TB_DIR, rtl_sources, run_cocotb
from test_dsp_replay import RTL_FILES

TRIP_INDEX = 777
"""Conversion that carries the overcurrent (in window 3, 777 OS samples after reset)."""
OC_LIMIT = 8000


@pytest.mark.parametrize("testcase", ["overcurrent_trip_latch_and_clear", "watchdog_turns_gates_off"])
def test_dsp_safety(tmp_path, testcase):
    bits = 12
    mid = 1 << (bits - 1)
    over = mid + 600                    # i_a = 600 * 16 = 9600 LSB > OC_LIMIT
    assert (over - mid) << (16 - bits) > OC_LIMIT
    build = tmp_path / "build"
    build.mkdir(parents=True)
    codes = [(mid << 16) | mid] * 5000
    if testcase.startswith("overcurrent"):
        codes[TRIP_INDEX] = (over << 16) | mid
    (build / "codes.hex").write_text("".join(f"{c:08x}\n" for c in codes))
    assert rm.OS_TICKS_VALUE_RESET == 100
    run_cocotb(sim="verilator", toplevel="tb_hfi_dsp",
               sources=[*rtl_sources(*RTL_FILES), TB_DIR / "hdl" / "adc_model.v", TB_DIR / "hdl" / "tb_hfi_dsp.v"],
               tb_module="tb_dsp_safety", build_dir=build, parameters={"ADC_BITS": bits},
               env={"HFI_TRIP_INDEX": TRIP_INDEX, "HFI_OC_LIMIT": OC_LIMIT, "COCOTB_TEST_FILTER": testcase},
               build_args=["--timing"], expect_tests=1)
