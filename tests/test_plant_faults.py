"""Faults of the C plant (``struct fault``, docs/faults.md) against analytical results.

Each expected value comes from a formula of the fault's definition in plant_api.h, computed here.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from golden.plant import Plant, PlantError, default_params, merge
from golden.plant.binding import ffi

TICK = 100e6
_KIND = ffi.typeof("enum fault_kind").relements
SENSOR_OFFSET, SENSOR_GAIN, ADC_STUCK, PHASE_OPEN, SWITCH_OPEN, DC_LINK, LOAD_STEP, ROTOR_BLOCKED = (
    _KIND[f"FAULT_{name}"] for name in ("SENSOR_OFFSET", "SENSOR_GAIN", "ADC_STUCK", "PHASE_OPEN", "SWITCH_OPEN",
                                        "DC_LINK", "LOAD_STEP", "ROTOR_BLOCKED"))


def fault(kind: int, t: float, channel: int = 0, value: float = 0.0, rate: float = 0.0, until: float = 0.0) -> dict:
    return {"kind": kind, "channel": channel, "tick": round(t * TICK), "value": value, "rate": rate,
            "until": round(until * TICK)}


def plant(*faults: dict, **over) -> Plant:
    return Plant(merge(default_params(), {**over, "faults": list(faults)}))


def code(current: float, bits: int = 16, full_range: float = 10.0) -> int:
    """The ADC code of a current (docs/plant.md, "Sensors and ADC")."""
    full = 2 ** bits
    return min(max(math.floor(current * full / (2 * full_range) + full / 2 + 0.5), 0), full - 1)


def test_sensor_offset_step_and_drift_add_to_the_reading():
    p = plant(fault(SENSOR_OFFSET, 1e-3, channel=1, value=0.5, rate=20.0))
    p.advance(round(0.5e-3 * TICK))
    assert p.sample()[1][1] == 0.0                           # no current, no offset yet
    p.advance(round(3e-3 * TICK))
    adc, analog = p.sample()
    assert analog[1] == pytest.approx(0.5 + 20.0 * 2e-3, abs=1e-12)
    assert adc[1] == code(0.54) and analog[0] == analog[2] == 0.0


def test_sensor_gain_scales_and_adc_stuck_forces_the_code():
    v = [30.0, -15.0, -15.0]                                  # a dc current along phase a (rotor locked)
    base = {"mech": {"imposed_speed": 1}}
    healthy, faulty = plant(**base), plant(fault(SENSOR_GAIN, 0.0, channel=0, value=0.8),
                                           fault(ADC_STUCK, 0.0, channel=2, value=1234), **base)
    for p in (healthy, faulty):
        p.set_voltage(v)
        p.advance(round(5e-3 * TICK))
    (adc_h, ana_h), (adc_f, ana_f) = healthy.sample(), faulty.sample()
    assert ana_h[0] > 1.0
    assert ana_f[0] == pytest.approx(0.8 * ana_h[0], rel=1e-15)
    assert adc_f[2] == 1234 and adc_h[2] != 1234 and ana_f[2] == ana_h[2]


def test_open_phase_carries_no_current_and_the_others_are_opposite():
    """A rotating voltage on the locked rotor: after phase b opens, i_b decays with OPEN_PHASE_TAU
    (10 us) and i_a = -i_c (Kirchhoff at the floating star)."""
    p = plant(fault(PHASE_OPEN, 2e-3, channel=1), mech={"imposed_speed": 1})
    for k in range(60):
        th = 2 * math.pi * 50 * k * 1e-4
        p.set_voltage([40 * math.cos(th - 2 * math.pi * j / 3) for j in range(3)])
        p.advance(round((k + 1) * 1e-4 * TICK))
        s = p.state()
        if s["t"] > 2.2e-3:
            assert abs(s["i_abc"][1]) < 1e-6
            assert s["i_abc"][0] == pytest.approx(-s["i_abc"][2], abs=1e-9)
    assert abs(s["i_abc"][0]) > 0.5                          # current still flows in a and c


def test_open_switch_leaves_the_leg_to_its_diodes():
    """a_hi dead: the commanded a_hi + b_lo + c_lo drives no current through a (it would be V_dc over
    the winding); the node of a sits on the low diode or the capacitance, never on the positive rail."""
    mask = 0b101001                                           # a_hi, b_lo, c_lo
    p = plant(fault(SWITCH_OPEN, 0.0, channel=0), mech={"imposed_speed": 1})
    p.set_gates(mask)
    p.advance(round(1e-3 * TICK))
    s = p.state()
    assert s["gates"] == mask                                 # the commanded mask is reported
    assert abs(s["i_abc"][0]) < 1e-9 and s["v_node"][0] < 1.0
    healthy = plant(mech={"imposed_speed": 1})
    healthy.set_gates(mask)
    healthy.advance(round(1e-3 * TICK))
    assert healthy.state()["i_abc"][0] > 1.0


@pytest.mark.parametrize("tau", [0.0, 5e-3])
def test_dc_link_falls_to_its_factor(tau):
    p = plant(fault(DC_LINK, 1e-3, value=0.7, rate=tau), inv={"V_dc": 500.0}, mech={"imposed_speed": 1})
    p.set_gates(0b011001)                                     # legs conduct: the state reports the bus
    p.advance(round(1e-3 * TICK) - 1)
    assert p.state()["v_dc"] == 500.0
    p.advance(round(6e-3 * TICK))
    expected = 500.0 * (0.7 + 0.3 * math.exp(-5e-3 / tau)) if tau else 350.0
    assert p.state()["v_dc"] == pytest.approx(expected, rel=1e-12)


def test_load_step_decelerates_and_a_blocked_rotor_stops():
    """No torque (no magnet, no current): J d omega/dt = -T_load; blocked: omega = 0, theta held."""
    J, T_step = 4.0e-3, 2.0
    p = plant(fault(LOAD_STEP, 1e-3, value=T_step), omega_m0=10.0,
              mech={"B": 0.0, "T_c": 0.0, "J": J}, mag={"psi_f": 0.0})
    p.advance(round(1e-3 * TICK))
    w0 = p.state()["omega_m"]
    p.advance(round(2e-3 * TICK))
    assert p.state()["omega_m"] == pytest.approx(w0 - T_step / J * 1e-3, rel=1e-6)
    b = plant(fault(ROTOR_BLOCKED, 1e-3), omega_m0=10.0)
    b.advance(round(1e-3 * TICK))
    theta = b.state()["theta_m"]
    b.advance(round(3e-3 * TICK))
    assert b.state()["omega_m"] == 0.0 and b.state()["theta_m"] == theta


def test_faults_do_not_change_a_run_before_their_onset():
    """Bit-identical samples up to the onset: the fault list alone changes nothing."""
    noisy = {"sens": {"noise_rms": 0.05}}
    a, b = plant(**noisy), plant(fault(SENSOR_OFFSET, 5e-3, value=1.0), **noisy)
    for p in (a, b):
        p.set_voltage([20.0, -10.0, -10.0])
    ticks = np.arange(1, 40) * 100
    ra = a.run([], ticks, volts=np.zeros((0, 3)), analog=True)
    rb = b.run([], ticks, volts=np.zeros((0, 3)), analog=True)
    assert np.array_equal(ra["adc"], rb["adc"]) and np.array_equal(ra["analog"], rb["analog"])


@pytest.mark.parametrize("bad, message", [
    (fault(max(_KIND.values()) + 1, 0.0), "is not a fault"),
    (fault(ADC_STUCK, 0.0, value=70000), "stuck code"),
    (fault(SWITCH_OPEN, 0.0, channel=6), "channel must be in 0..5"),
    (fault(DC_LINK, 0.0, value=2.5), "dc-link factor"),
    (fault(SENSOR_GAIN, 0.0, value=-1.0), "gain factor"),
])
def test_bad_faults_are_refused(bad, message):
    with pytest.raises(PlantError, match=message):
        plant(bad)


def test_a_fault_clears_at_its_end():
    """A load step from 1 to 2 ms decelerates only then; an open phase from 1 to 2 ms lets the current
    back into its phase after it; a drift ends with its fault."""
    J, T_step = 4.0e-3, 2.0
    p = plant(fault(LOAD_STEP, 1e-3, value=T_step, until=2e-3), omega_m0=10.0,
              mech={"B": 0.0, "T_c": 0.0, "J": J}, mag={"psi_f": 0.0})
    p.advance(round(3e-3 * TICK))
    assert p.state()["omega_m"] == pytest.approx(10.0 - T_step / J * 1e-3, rel=1e-9)
    q = plant(fault(PHASE_OPEN, 1e-3, channel=0, until=2e-3), mech={"imposed_speed": 1})
    q.set_voltage([30.0, -15.0, -15.0])
    q.advance(round(1.9e-3 * TICK))
    assert abs(q.state()["i_abc"][0]) < 1e-6
    q.advance(round(3e-3 * TICK))
    assert q.state()["i_abc"][0] > 0.1
    r = plant(fault(SENSOR_OFFSET, 1e-3, channel=2, value=0.1, rate=50.0, until=2e-3))
    r.advance(round(1.5e-3 * TICK))
    assert r.sample()[1][2] == pytest.approx(0.1 + 50.0 * 0.5e-3, abs=1e-12)
    r.advance(round(2e-3 * TICK))
    assert r.sample()[1][2] == 0.0
    with pytest.raises(PlantError, match="until must be 0"):
        plant(fault(LOAD_STEP, 2e-3, until=1e-3))


def test_fault_order_and_one_open_phase():
    with pytest.raises(PlantError, match="not before the previous"):
        plant(fault(LOAD_STEP, 2e-3), fault(LOAD_STEP, 1e-3))
    with pytest.raises(PlantError, match="at most one phase"):
        plant(fault(PHASE_OPEN, 1e-3, channel=0), fault(PHASE_OPEN, 2e-3, channel=2))
