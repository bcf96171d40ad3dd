"""The flying start's short-circuit probe (golden/firmware/catch_probe.py, docs/faults.md "The flying start"): its
estimate against closed forms, the C twin against golden on random vectors, and a rotor too fast for the
current-control catch alone, caught with it, identical on the hls backend and on the soft core."""

from __future__ import annotations

import dataclasses
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from golden.closedloop import ClosedLoop
from golden.firmware.catch_probe import PROBE_END, PROBE_GAP, probe_angles, probe_estimate
from golden.firmware.protection import FAULT_NAMES, FAULT_OVERCURRENT
from golden.firmware.supervisor import MODE_CATCH, MODE_FAULT, MODE_RUN
from golden.fixed import wrap
from golden.scenario import ScenarioError, parse_scenario

ROOT = Path(__file__).resolve().parents[1]
TURN = 2**32


def coasting(rpm: float, probe: str = "50 mA", duration: float = 0.1):
    """scenarios/flying_start.toml (the Table I motor switched on while it coasts, reference 100 r/min) at ``rpm``,
    with ``protection.catch_probe`` = ``probe``."""
    data = tomllib.loads((ROOT / "scenarios" / "flying_start.toml").read_text())
    data["load"]["initial"]["omega_m"] = f"{rpm} rpm"
    data["protection"]["catch_probe"] = probe
    return dataclasses.replace(parse_scenario(data, source=f"flying start at {rpm} r/min"), duration=duration)


def test_estimate_against_the_closed_form():
    """Two current vectors along -e, the second turned by the back-EMF's advance: the advance within the resolution
    of the integer vectoring CORDIC on vectors of that length (4 / length rad), its sign the direction of rotation, and the rotor's angle the back-EMF's less a
    quarter turn in that direction; currents below the limit, or no advance, find nothing."""
    for theta_deg, adv_deg, mag in [(10.0, 30.0, 300), (200.0, -50.0, 120), (300.0, 144.0, 2000), (91.0, -2.5, 60)]:
        e1 = math.radians(theta_deg + (90.0 if adv_deg > 0 else -90.0))      # e leads the flux by 90 deg in its sense
        e2 = e1 + math.radians(adv_deg)
        d1 = (round(-mag * math.cos(e1)), round(-mag * math.sin(e1)))
        d2 = (round(-mag * math.cos(e2)), round(-mag * math.sin(e2)))
        found, theta, delta = probe_estimate(*d1, *d2, i_min=mag // 2)
        assert found == 1
        a1, a2 = (math.atan2(y, x) / (2 * math.pi) * TURN for x, y in (d1, d2))   # the rounded vectors' angles
        tol = 4 / mag / (2 * math.pi) * TURN
        assert abs(delta - wrap(round(a2 - a1), 32)) < tol
        assert abs(delta - adv_deg / 360 * TURN) < 2 * tol                  # and about the advance given
        want = a2 + TURN / 2 - math.copysign(TURN / 4, adv_deg)             # at pulse 2
        assert abs(wrap(theta - round(want) % TURN, 32)) < tol
        omega, theta_a, theta_b = probe_angles(theta, delta)
        assert omega == int(delta / PROBE_GAP)                              # c_div: towards zero
        assert abs(wrap(theta_a - theta, 32) - 5 * delta / (3 * PROBE_GAP)) <= 1
        assert abs(wrap(theta_b - theta, 32) - 8 * delta / (3 * PROBE_GAP)) <= 1
        assert probe_estimate(*d1, *d2, i_min=mag + mag // 10) == (0, 0, 0)
    assert probe_estimate(100, 0, 100, 0, 10) == (0, 0, 0)


def test_c_twin_is_identical_on_random_vectors(seed):
    """fw_probe_estimate and fw_probe_angles (control.c) == golden on 20 000 random pulse currents (small, large,
    beyond the vector angle's +-2^28, where both saturate) and limits."""
    from hfi.fw_c import load
    ffi, lib = load()
    rng = np.random.default_rng(seed)
    theta_c, delta_c, omega_c = ffi.new("uint32_t *"), ffi.new("int32_t *"), ffi.new("int32_t *")
    a_c, b_c = ffi.new("uint32_t *"), ffi.new("uint32_t *")
    for _ in range(20_000):
        scale = int(rng.choice([100, 10_000, 1 << 28, (1 << 31) - 1]))    # the last saturated to +-2^28
        d = [int(x) for x in rng.integers(-scale, scale + 1, 4)]
        i_min = int(rng.choice([0, 1, 50, 5000, int(rng.integers(0, 1 << 20))]))
        want = probe_estimate(*d, i_min)
        got = lib.fw_probe_estimate(*d, i_min, theta_c, delta_c)
        assert (got, theta_c[0], delta_c[0]) == want, (d, i_min)
        theta, delta = int(rng.integers(0, TURN)), int(rng.integers(-(1 << 31), 1 << 31))
        lib.fw_probe_angles(theta, delta, omega_c, a_c, b_c)
        assert (omega_c[0], a_c[0], b_c[0]) == probe_angles(theta, delta)


def test_a_rotor_at_2500_rpm_is_caught_with_the_probe_and_trips_without():
    """The Table I motor coasting at 2500 r/min (2.5 times what the current-control catch holds): with the probe the
    speed it finds is within 5 % of the plant's, the first window under current control within 10 deg, and the
    drive is in RUN on the observer after catch_time, without a fault, within 8 deg over the last 20 ms; without
    the probe the catch's first windows at zero voltage drive the short-circuit current and it trips on
    overcurrent within 5 ms (golden, docs/faults.md)."""
    res = ClosedLoop(coasting(2500.0)).run(progress=False)
    w, err = res.windows, res.angle_error_deg()
    k = PROBE_END - 1                                           # the window whose step hands over to the catch
    found = w["omega_hi"][k] / res.scales.speed_mech(math.pi / 30)
    true = w["omega_m"][k] * 30 / math.pi
    assert abs(found / true - 1) < 0.05, (found, true)
    assert abs(err[k + 2]) < 10.0                               # the first window with the gates on after the probe
    assert MODE_FAULT not in w["mode"] and w["mode"][0] == MODE_CATCH and w["mode"][-1] == MODE_RUN
    assert np.max(np.abs(err[res.t > res.t[-1] - 0.02])) < 8.0
    plain = ClosedLoop(coasting(2500.0, probe="0 A", duration=0.01)).run(progress=False)
    trip = np.flatnonzero(plain.windows["mode"] == MODE_FAULT)
    assert len(trip) and plain.t[trip[0]] < 0.005
    assert FAULT_NAMES[plain.windows["fault"][trip[0]]] == FAULT_NAMES[FAULT_OVERCURRENT]


@pytest.mark.parametrize("rpm", [2500.0, -3500.0])
def test_hls_is_identical_with_the_probe(rpm):
    """The probe, its hand-over to the catch and RUN on the hls backend (the host build of the C firmware): every
    window column equal to golden over 0.06 s."""
    from hfi.hls_backend import HlsClosedLoop
    sc = coasting(rpm, duration=0.06)
    gold, hls = ClosedLoop(sc).run(progress=False), HlsClosedLoop(sc).run(progress=False)
    for k in gold.windows:
        assert np.array_equal(gold.windows[k], hls.windows[k]), k


def test_the_probe_needs_the_flying_start_and_a_limit_below_the_trip():
    data = tomllib.loads((ROOT / "scenarios" / "flying_start.toml").read_text())
    data["protection"] = {"catch_probe": "50 mA"}
    with pytest.raises(ScenarioError, match="protection.catch_probe: the short-circuit probe"):
        parse_scenario(data, source="test")
    data["protection"] = {"catch_time": "40 ms", "catch_probe": "6 A"}      # control.i_trip: 6 A (the default)
    with pytest.raises(ScenarioError, match="protection.catch_probe: 6 A is not below control.i_trip"):
        parse_scenario(data, source="test")
