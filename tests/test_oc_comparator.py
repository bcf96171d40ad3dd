"""The hardware overcurrent comparator in the closed loop (docs/spec.md 3.7, golden.fpga.overcurrent): the golden
and hls backends model it bit for bit (the rtl backend has the RTL itself: tests/test_rtl_identity.py).

The run: the default drive (``fullload_start``) with ``control.oc_limit`` below its start-up's polarity pulses
(2.2 A), so a sample trips during the start-up. Expected values come from the samples themselves (their scaled
currents against the limit, recomputed here with the ADC scaling, independently of the loop's bookkeeping) and
from the two delays of golden.fpga.overcurrent, measured on the RTL (cocotb_tests/tb_dsp_safety.py)."""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

from golden.closedloop import ClosedLoop
from golden.fpga.adc_scale import adc_to_current
from golden.fpga.overcurrent import fault_delay, gate_off_delay
from golden.firmware.protection import FAULT_HARDWARE
from golden.scenario import ScenarioError, load_scenario, parse_scenario

ROOT = Path(__file__).resolve().parents[1]
LIMIT_A = 1.5
"""The comparator's limit of the run [A]: below the 2.2 A polarity pulses of the default start-up."""


def tripping_scenario(duration: str = "0.08 s"):
    data = tomllib.loads((ROOT / "scenarios" / "fullload_start.toml").read_text())
    data["scenario"]["duration"] = duration
    data["control"]["oc_limit"] = f"{LIMIT_A} A"
    return parse_scenario(data, source=f"fullload_start.toml + control.oc_limit = {LIMIT_A} A")


@pytest.fixture(scope="module")
def golden_run():
    return ClosedLoop(tripping_scenario()).run(progress=False)


def _first_over(res) -> int:
    """The sampling instant of the first sample whose scaled |i_a|, |i_b| or |i_a + i_b| exceeds the limit."""
    hw = res.hw
    for t, a, b in zip(res.samples["tick"], res.samples["adc_a"], res.samples["adc_b"]):
        i_a = adc_to_current(int(a), hw.adc_bits, hw.adc_offset[0], hw.adc_gain[0])
        i_b = adc_to_current(int(b), hw.adc_bits, hw.adc_offset[1], hw.adc_gain[1])
        if max(abs(i_a), abs(i_b), abs(i_a + i_b)) > hw.oc_limit:
            return int(t)
    raise AssertionError("no sample beyond the limit: the run does not trip")


def test_the_limit_reaches_the_register(golden_run):
    assert golden_run.hw.oc_limit == golden_run.scales.current(LIMIT_A) < 32767


def test_gates_off_from_the_trip_and_for_good(golden_run):
    """All gates off at the tripping sample's instant + the gate delay, and no edge after it."""
    t_s = _first_over(golden_run)
    ticks, masks = golden_run.edges["tick"], golden_run.edges["mask"]
    before = masks[ticks < t_s + gate_off_delay(golden_run.hw.adc_bits)]
    assert before.size and before[-1] != 0, "the gates were not on before the trip"
    after = ticks >= t_s + gate_off_delay(golden_run.hw.adc_bits)
    assert ticks[after].tolist() == [t_s + gate_off_delay(golden_run.hw.adc_bits)] and masks[after].tolist() == [0]
    assert (golden_run.windows["tick"] > ticks[after][0]).sum() >= 10, "too short to see the gates stay off"


def test_the_firmware_sees_it_in_the_window_of_its_boundary(golden_run):
    """WIN_FAULT.OC from the first window whose boundary is at or after the instant + the fault delay: the firmware
    trips `hardware` in that window's step, not before."""
    t_s = _first_over(golden_run)
    end = golden_run.windows["tick"]                      # each window's closing boundary
    k = int(np.flatnonzero(end >= t_s + fault_delay(golden_run.hw.adc_bits))[0])
    fault = golden_run.windows["fault"]
    assert (fault[:k] != FAULT_HARDWARE).all() and fault[k] == FAULT_HARDWARE


def test_hls_identical(golden_run):
    from hfi.hls_backend import HlsClosedLoop

    hls = HlsClosedLoop(tripping_scenario()).run(progress=False)
    for group in ("windows", "samples", "edges", "writes"):
        a, b = getattr(golden_run, group), getattr(hls, group)
        bad = [k for k in a if not np.array_equal(a[k], b[k])]
        assert not bad, f"{group}: columns differ: {bad}"


def test_a_limit_beyond_the_sensors_is_refused():
    data = tomllib.loads((ROOT / "scenarios" / "fullload_start.toml").read_text())
    data["control"]["oc_limit"] = "20 A"
    with pytest.raises(ScenarioError, match=r"control.oc_limit.*not below the current sensors' range"):
        parse_scenario(data, source="test")


def test_without_the_key_the_register_keeps_its_reset_value():
    from golden.control_config import hardware_config
    from golden.regmap import OC_LIMIT_VALUE_RESET

    assert hardware_config(load_scenario(ROOT / "scenarios" / "fullload_start.toml")).oc_limit == OC_LIMIT_VALUE_RESET


def test_a_hardware_trip_is_not_restarted():
    """With `[protection] restarts = 1` the firmware restarts after its own checks' faults, never after `hardware`:
    the latch holds the gates off (docs/faults.md); the run ends in FAULT with that code and no edge after the
    kill."""
    from golden.firmware.supervisor import MODE_FAULT

    data = tomllib.loads((ROOT / "scenarios" / "fullload_start.toml").read_text())
    data["scenario"]["duration"] = "0.12 s"
    data["control"]["oc_limit"] = f"{LIMIT_A} A"
    data["protection"] = {"restarts": 1, "restart_delay": "10 ms"}
    res = ClosedLoop(parse_scenario(data, source="restarts after a hardware trip")).run(progress=False)
    trip = int(np.flatnonzero(res.windows["fault"] == FAULT_HARDWARE)[0])
    assert res.t[-1] - res.t[trip] > 0.03                   # three restart delays after the trip
    assert (res.windows["mode"][trip:] == MODE_FAULT).all() and (res.windows["fault"][trip:] == FAULT_HARDWARE).all()
    assert res.edges["mask"][-1] == 0
