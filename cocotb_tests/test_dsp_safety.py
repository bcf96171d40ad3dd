"""hfi_dsp safety in hardware (issue 4 item 4, spec 3.8): the overcurrent comparator switches every
gate off exactly D_GATE ticks (440 ns, within 2 µs) after the sampling instant and latches FAULT.OC until
FAULT_CLEAR, and WIN_FAULT shows it by the boundary rule of spec 3.7 (both sides of a boundary); the watchdog turns
the gates off after WDT_PERIODS windows without a commit; the STO and DESAT pins remove every gate 3
clocks after the pin, latch their fault (FAULT_CLEAR ignored while the pin is held) and the gates come
back only from the carrier bottom after a re-arm; SAFETY_LOCK freezes DEAD_TICKS/OC_LIMIT/WDT_PERIODS;
WIN_ADC flags a current lane whose every conversion of a window returned one raw code (spec 3.13).
The block-level clock-by-clock check of the safety logic is cocotb_tests/test_safety.py; the formal
proof of the gate generator is in tests/test_prove.py; the dead-time floor in
cocotb_tests/test_gate_gen.py."""

from __future__ import annotations

import numpy as np
import pytest

from golden import regmap as rm
from golden.fpga.adc_trigger import MODE_DS, MODE_OS, window_sample_ticks
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

FROZEN_SEED = 20261129
"""frozen_adc_channels: the seed of the ADC model's noise on the current lanes."""
FROZEN_NOISE = 4
"""The noise of a live lane: mid-scale + -4 .. +4 codes."""
FROZEN_DS = (7, 9)
"""frozen_adc_channels: windows 7 to 9 in DS (CTRL.ADC_MODE = 1, two conversions: carrier top, then bottom)."""
FROZEN_OS_TICKS_LATE = 60000
"""From window 10 on (OS again): OS_TICKS > P - OS_MIN, so each window holds one conversion (the bottom)."""
FROZEN_CASES = {
    # H/2 = 5000 on the OS grid: the conversion at the boundary tick is the first of the new window
    "on_grid": {"HFI_HALF": 10000},
    # H/2 = 5020: the conversion 20 ticks before the boundary arrives after it (L_ADC = 38), the next is 80 after
    "off_grid": {"HFI_HALF": 10040},
}
# Per window, the codes of lane A and of lane B: "noise" (a live channel), ("const", c) every conversion c,
# ("first", c) the first conversion c + 1 and the rest c (a stuck stretch that starts at the window's second
# conversion), ("last", c) the last conversion c - 1 and the rest c, ("split", c) the first half c, the rest c + 5.
# With each window, the WIN_ADC that the rule of spec 3.13 gives ({FROZEN_A, FROZEN_B}).
MID = 1 << 11
CA, CA2, CB, CX, CY = MID + 37, MID - 51, MID - 23, MID + 300, MID - 300
FROZEN_PLAN = {
    -1: ("noise", "noise", (0, 0)),
    0: ("noise", "noise", (0, 0)),
    1: (("const", CA), "noise", (1, 0)),        # A stuck from the first conversion of window 1 (at/after its start)
    2: (("const", CA), ("first", CB), (1, 0)),  # B stuck from the second conversion of window 2
    3: (("const", CA), ("const", CB), (1, 1)),
    4: (("first", CA), ("last", CB), (0, 0)),   # A: window 4's first differs (not in window 3); B: its last
    5: (("const", CA2), ("const", CB), (1, 1)),  # B: window 4's last conversion is not in window 5
    6: (("split", CA2), "noise", (0, 0)),
    7: (("const", CX), ("const", CY), (1, 1)),  # DS: top and bottom equal
    8: (("const", CX), ("last", CY), (1, 0)),   # DS: B's two differ
    9: (("last", CX), ("const", CY), (0, 1)),
    10: (("const", CX), ("const", CY), (0, 0)),  # one conversion per window: never frozen
    11: (("const", CX), ("const", CY), (0, 0)),
}


def frozen_lane(kind, n: int, rng: np.random.Generator) -> list[int]:
    """The codes of one lane for the n conversions of a window (FROZEN_PLAN's kinds)."""
    if kind == "noise":
        codes = [int(c) for c in MID + rng.integers(-FROZEN_NOISE, FROZEN_NOISE + 1, n)]
        if n >= 2 and len(set(codes)) == 1:
            codes[-1] += 1                      # a live channel: never one code for a whole window
        return codes
    what, c = kind
    return {"const": [c] * n, "first": [c + 1] + [c] * (n - 1), "last": [c] * (n - 1) + [c - 1],
            "split": [c] * (n // 2) + [c + 5] * (n - n // 2)}[what]


def frozen_codes(half: int) -> list[int]:
    """frozen_adc_channels' conversions, one "C A B" word each in conversion order (the sampling instants of
    spec 2.3 per window: OS_TICKS = 100 up to window 6, DS in FROZEN_DS, OS_TICKS_LATE after; the dc-link lane C
    constant, it is not checked)."""
    rng = np.random.default_rng(FROZEN_SEED)
    words = []
    for k, (kind_a, kind_b, _) in sorted(FROZEN_PLAN.items()):
        mode = MODE_DS if FROZEN_DS[0] <= k <= FROZEN_DS[1] else MODE_OS
        os_ticks = FROZEN_OS_TICKS_LATE if k > FROZEN_DS[1] else rm.OS_TICKS_VALUE_RESET
        n = int(np.count_nonzero(window_sample_ticks(k, mode, half, os_ticks) >= 0))   # window -1: from tick 0
        words += [(3000 << 32) | (a << 16) | b
                  for a, b in zip(frozen_lane(kind_a, n, rng), frozen_lane(kind_b, n, rng), strict=True)]
    return words


@pytest.mark.parametrize("testcase, extra", [
    *[pytest.param(name, {}, id=name) for name in ("overcurrent_trip_latch_and_clear", "watchdog_turns_gates_off",
                                                   "sto_safe_torque_off", "desat_driver_fault",
                                                   "safety_lock_freezes_registers")],
    *[pytest.param("overcurrent_window_boundary", {**env, "HFI_TRIP_INDEX": BOUNDARY_TRIP_INDEX},
                   id=f"overcurrent_window_boundary-{side}") for side, env in BOUNDARY_CASES.items()],
    *[pytest.param("frozen_adc_channels", env, id=f"frozen_adc_channels-{grid}") for grid, env in FROZEN_CASES.items()],
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
    if testcase == "frozen_adc_channels":
        assert MID == mid
        codes = frozen_codes(env["HFI_HALF"])
        env.update({"HFI_FROZEN_DS": f"{FROZEN_DS[0]},{FROZEN_DS[1]}", "HFI_FROZEN_OS_TICKS": FROZEN_OS_TICKS_LATE,
                    "HFI_FROZEN_EXPECT": ";".join(f"{k}:{a}{b}" for k, (_, _, (a, b)) in FROZEN_PLAN.items())})
    (build / "codes.hex").write_text("".join(f"{c:012x}\n" for c in codes))
    assert rm.OS_TICKS_VALUE_RESET == 100
    run_cocotb(sim="verilator", toplevel="tb_hfi_dsp",
               sources=[*rtl_sources(*core_rtl_files()), TB_DIR / "hdl" / "adc_model.v",
                        TB_DIR / "hdl" / "tb_hfi_dsp.v"],
               tb_module="tb_dsp_safety", build_dir=build, parameters={"ADC_BITS": bits},
               env=env, build_args=["--timing"], expect_tests=1)
