"""hfi_dsp safety in hardware (issue 4 item 4, spec 3.8): the overcurrent comparator switches every
gate off exactly D_GATE ticks (440 ns, within 2 µs) after the sampling instant and latches FAULT.OC until
FAULT_CLEAR, and WIN_FAULT shows it by the boundary rule of spec 3.7 (both sides of a boundary); the watchdog turns
the gates off after WDT_PERIODS windows without a commit; the STO and DESAT pins remove every gate 3
clocks after the pin, latch their fault (FAULT_CLEAR ignored while the pin is held) and the gates come
back only from the carrier bottom after a re-arm; SAFETY_LOCK freezes DEAD_TICKS/OC_LIMIT/WDT_PERIODS.
The block-level clock-by-clock check of the safety logic is cocotb_tests/test_safety.py; the formal
proof of the gate generator is in tests/test_prove.py; the dead-time floor in
cocotb_tests/test_gate_gen.py."""

from __future__ import annotations

import pytest

from golden import regmap as rm
from hdl_runner import TB_DIR, core_rtl_files, rtl_sources, run_cocotb

TRIP_INDEX = 777
"""Conversion that carries the overcurrent (in window 3, 777 OS samples after reset)."""
OC_LIMIT = 8000
BOUNDARY_TRIP_INDEX = 4 * 202 + 50
"""overcurrent_window_boundary: the OS sample at phase 5000 of period 4 (202 samples per period at OS_TICKS = 100,
OS_MIN = 40 and H = 10088 or 10090: phases 0 .. 20100)."""
BOUNDARY_CASES = {
    # H/2 = 5045: t_s + D_FAULT (45 at the defaults) is the boundary tick ending window 3 itself
    "at": {"HFI_HALF": 10090, "HFI_BOUNDARY_OFFSET": 0},
    # H/2 = 5044: one tick after it
    "after": {"HFI_HALF": 10088, "HFI_BOUNDARY_OFFSET": 1},
}


@pytest.mark.parametrize("testcase, extra", [
    *[pytest.param(name, {}, id=name) for name in ("overcurrent_trip_latch_and_clear", "watchdog_turns_gates_off",
                                                   "sto_safe_torque_off", "desat_driver_fault",
                                                   "safety_lock_freezes_registers")],
    *[pytest.param("overcurrent_window_boundary", {**env, "HFI_TRIP_INDEX": BOUNDARY_TRIP_INDEX},
                   id=f"overcurrent_window_boundary-{side}") for side, env in BOUNDARY_CASES.items()],
])
def test_dsp_safety(tmp_path, testcase, extra):
    bits = 12
    mid = 1 << (bits - 1)
    over = mid + 600                    # i_a = 600 * 16 = 9600 LSB > OC_LIMIT
    assert (over - mid) << (16 - bits) > OC_LIMIT
    build = tmp_path / "build"
    build.mkdir(parents=True)
    env = {"HFI_TRIP_INDEX": TRIP_INDEX, "HFI_OC_LIMIT": OC_LIMIT, "HFI_ADC_BITS": bits, **extra,
           "COCOTB_TEST_FILTER": testcase}
    codes = [(mid << 16) | mid] * 5000
    if testcase.startswith("overcurrent"):
        codes[env["HFI_TRIP_INDEX"]] = (over << 16) | mid
    (build / "codes.hex").write_text("".join(f"{c:08x}\n" for c in codes))
    assert rm.OS_TICKS_VALUE_RESET == 100
    run_cocotb(sim="verilator", toplevel="tb_hfi_dsp",
               sources=[*rtl_sources(*core_rtl_files()), TB_DIR / "hdl" / "adc_model.v",
                        TB_DIR / "hdl" / "tb_hfi_dsp.v"],
               tb_module="tb_dsp_safety", build_dir=build, parameters={"ADC_BITS": bits},
               env=env, build_args=["--timing"], expect_tests=1)
