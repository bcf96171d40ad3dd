"""The 003 method (Varatharajan et al. 2020): golden pieces against independent references.

* the firmware's flux LUT against the plant's own magnetic model (the map it is made from);
* the applied-voltage model against the leg-voltage definition of the dead time;
* the low-speed projection: the gain of the error per applied vector, on the plant's map at 2 p.u., with
  and without the correction for the position-error-induced inductance change (the cause of the lock
  losses the issue reports);
* the deadbeat law against a float re-statement of eq. (14) in the stationary frame;
* the closed loop of scenarios/varatharajan2020_torquestep.toml against the issue's numbers.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from golden.control_config import firmware_params, flux_lsb, scales
from golden.firmware.applied_flux import applied_flux
from golden.firmware.fcs_law import deadbeat_voltage, flux_reference
from golden.firmware.flux_lut import FLUX_FRAC, LutPoint, lut_flux, lut_point, unwarp
from golden.firmware.hfo_proj import projection_coefficients
from golden.fpga.fcs_mpc import state_voltage
from golden.motors import preset
from golden.plant.fluxmap import incremental_inductance, psi_from_current
from golden.scenario import load_scenario

ROOT = Path(__file__).resolve().parents[1]
SCENARIO = ROOT / "scenarios" / "varatharajan2020_torquestep.toml"


@pytest.fixture(scope="module")
def setup():
    sc = load_scenario(SCENARIO)
    return sc, firmware_params(sc), scales(sc), flux_lsb(sc), preset("varatharajan2020_syrm")["mag"]


def _rot(a: float, b: float, ang: float) -> np.ndarray:
    """Stationary -> the frame at ``ang``."""
    return np.array([a * math.cos(ang) + b * math.sin(ang), b * math.cos(ang) - a * math.sin(ang)])


def test_lut_equals_the_map_at_the_grid_points(setup):
    """At a grid point the look-up returns the table's value, which is the plant's map rounded to the
    table's unit (``2^f_shift`` flux units)."""
    _, fp, sc_, fl, mag = setup
    lut = fp.hfo.lut
    rng = np.random.default_rng(3)
    for _ in range(40):
        c, r = int(rng.integers(0, lut.n_d - 1)), int(rng.integers(0, lut.n_q - 1))
        i_d, i_q = unwarp(c << lut.shift, lut.knee, lut.coarse), unwarp(r << lut.shift, lut.knee, lut.coarse)
        lam = lut_flux(lut, -i_d, i_q)
        psi = psi_from_current(mag, -i_d * sc_.i_lsb, i_q * sc_.i_lsb)
        fs = lut.f_shift
        assert lam == (-(round(-psi[0] / fl / 2**fs) << fs) if i_d else 0, round(psi[1] / fl / 2**fs) << fs)


def test_lut_between_the_points_within_the_estimator_budget(setup):
    """Between the points (bilinear, warped grid) the flux is within 1 % of the map or 4 mV*s (the torque
    the flux reference gives within 1 %; 4 mV*s, 0.4 % of the rated flux, is the 0.5 A grid's worst case
    beyond the knee, where the cross-saturation bends the q flux at a 3 A kick from 8 A) and the
    incremental inductances within 10 % (they set only the gain of the low-speed error, whose change of the
    current model is the map's own secant: a gain 10 % off moves the PLL's bandwidth by 10 %, no bias);
    beyond the grid the flux is extrapolated linearly, within 10 % of the map's change from the grid's edge
    (the map keeps saturating out there)."""
    _, fp, sc_, fl, mag = setup
    lut = fp.hfo.lut
    cell = (1 << lut.shift) * sc_.i_lsb / fl
    from golden.flux_tables import mtpa_point
    rng = np.random.default_rng(5)
    for _ in range(300):
        # the operating envelope: an MTPA point (with the flux floor's -0.44 A at no load) of up to 8 A
        # (the current limit), plus one vector's ripple, up to 3 A in any direction
        i_d, i_q, *_ = mtpa_point(mag, rng.uniform(0.0, 8.0), 2)
        kick = rng.uniform(0, 3.0) * np.exp(1j * rng.uniform(0, 2 * math.pi))
        i_d, i_q = min(i_d, -0.44) + kick.real, i_q + kick.imag
        if abs(i_d) < 0.25 or abs(i_q) > 4.5:  # the ribs' knee inside the first cell; beyond the q grid
            continue
        pt = lut_point(lut, round(i_d / sc_.i_lsb), round(i_q / sc_.i_lsb))
        psi = psi_from_current(mag, i_d, i_q)
        l = incremental_inductance(mag, *psi)
        tol = max(4e-3, 0.01 * math.hypot(*psi))
        assert abs(pt.lam_d * fl - psi[0]) < tol and abs(pt.lam_q * fl - psi[1]) < tol
        assert abs(pt.l_d / cell / l[0, 0] - 1) < 0.1 and abs(pt.l_q / cell / l[1, 1] - 1) < 0.1
        assert abs(pt.l_dq / cell - l[0, 1]) < 0.1 * math.sqrt(l[0, 0] * l[1, 1])
    edge = psi_from_current(mag, -10.0, 1.0)[0]
    for i_d in (-11.0, -12.0):
        lam = lut_flux(lut, round(i_d / sc_.i_lsb), round(1.0 / sc_.i_lsb))[0] * fl
        true = psi_from_current(mag, i_d, 1.0)[0]
        assert abs(lam - true) < 0.10 * abs(true - edge)


def test_lut_is_odd_in_each_current(setup):
    _, fp, *_ = setup
    lut = fp.hfo.lut
    for i_d, i_q in ((-3000, 1500), (200, -40), (-9000, -4000), (0, 700)):
        p, m = lut_point(lut, i_d, i_q), lut_point(lut, -i_d, i_q)
        assert (m.lam_d, m.lam_q, m.l_d, m.l_q, m.l_dq) == (-p.lam_d, p.lam_q, p.l_d, p.l_q, -p.l_dq)


def test_applied_flux_dead_time_of_one_leg(setup):
    """One leg switching: the ideal state's flux, and, when the leg's current holds the old level through
    the dead time, V_dc t_d less along that leg's axis (2/3 of it in alpha/beta); nothing otherwise."""
    _, fp, *_ = setup
    dt_f = fp.hfo.dt_f
    for leg, axis in ((0, 0.0), (1, 2 * math.pi / 3), (2, -2 * math.pi / 3)):
        i_dir = np.array([math.cos(axis), math.sin(axis)]) * 1000          # current out of this leg
        for sign in (1, -1):
            ia, ib = (int(round(v)) for v in sign * i_dir)
            on = applied_flux(0, 1 << leg, ia, ib, dt_f, 0)
            off = applied_flux(1 << leg, 0, ia, ib, dt_f, 0)
            ideal = np.array(state_voltage(1 << leg)) * 2**FLUX_FRAC
            loss = 2 / 3 * dt_f * np.array([math.cos(axis), math.sin(axis)])
            # turning on with the current flowing out: the lower diode holds the leg low for t_d
            assert np.allclose(on, ideal - (loss if sign > 0 else 0), atol=1.5)
            # turning off with the current flowing in: the upper diode holds it high for t_d
            assert np.allclose(off, (loss if sign < 0 else 0) + np.zeros(2), atol=1.5)


def _gains(mag, lut, sc_, fl, l_shift, i_true, err_deg, corrected):
    """The low-speed error over the true position error, per active vector (in the rotor frame at 0, 60,
    ..., 300 deg), for the plant's map as the motor and the golden projection coefficients at the
    estimated-frame current; None where the strength is below 10 % of a vector's."""
    err = math.radians(err_deg)
    lt = incremental_inductance(mag, *psi_from_current(mag, *i_true))
    i_hat = _rot(*i_true, -err)                       # the estimated frame lags by err
    pt = lut_point(lut, round(i_hat[0] / sc_.i_lsb), round(i_hat[1] / sc_.i_lsb))
    if not corrected:
        pt = LutPoint(pt.lam_d, pt.lam_q, pt.l_d, pt.l_q, pt.l_dq, 0, 0, 0)
    a1, a2 = (a / 4096 for a in projection_coefficients(pt, l_shift))
    cell = (1 << lut.shift) * sc_.i_lsb / fl
    out = []
    for k in range(6):
        dpsi = 0.036 * np.array([math.cos(k * math.pi / 3), math.sin(k * math.pi / 3)])
        di = np.linalg.solve(lt, dpsi)
        dpsi_h, di_h = _rot(*dpsi, -err), _rot(*di, -err)
        l_hat = np.array([[pt.l_d, pt.l_dq], [pt.l_dq, pt.l_q]]) / cell
        e = dpsi_h - l_hat @ di_h
        s = a1 * dpsi_h[1] - a2 * dpsi_h[0]
        out.append(e[0] / s / err if abs(s) > 0.0036 else None)
    return out


@pytest.mark.parametrize("i_true", [(-2.86, 1.55), (-5.45, 2.5)])
def test_low_speed_gain_per_vector_with_the_inductance_correction(setup, i_true):
    """PITFALLS 1: at rated and 2 p.u. load, with 3 deg of position error, eq. (28)-(30) as printed give
    an error gain of the wrong sign for some applied vectors (the lock losses after the 2 p.u. step); with
    the derivative of the table's inductance along the rotation (golden.firmware.hfo_proj step 3) every
    strong vector's gain is between 0.8 and 1.3."""
    _, fp, sc_, fl, mag = setup
    for err in (3.0, -3.0):
        plain = [g for g in _gains(mag, fp.hfo.lut, sc_, fl, fp.hfo.lut.l_shift, i_true, err, False) if g is not None]
        fixed = [g for g in _gains(mag, fp.hfo.lut, sc_, fl, fp.hfo.lut.l_shift, i_true, err, True) if g is not None]
        assert min(plain) < 0 or max(plain) > 2.0
        assert len(fixed) >= 4 and all(0.8 < g < 1.3 for g in fixed)


def test_deadbeat_voltage_is_eq14_in_the_stationary_frame(setup):
    """Two known states ahead (zero vectors here), then the voltage that brings the flux to the reference
    at the end of the applied period: (ref - psi - 2 (flux of the zero states: R i T each, and the
    threshold drops)) / T + R i, Park-transformed to the angle written."""
    sc, fp, sc_, fl, mag = setup
    p = fp.fcs
    rng = np.random.default_rng(9)
    for _ in range(50):
        theta = int(rng.integers(0, 2**32))
        omega = int(rng.integers(-2**23, 2**23))
        i_s = int(rng.integers(-16000, 16000))
        psi = rng.uniform(-0.9, 0.9, 2)
        i_ab = rng.integers(-8000, 8000, 2)
        v_d, v_q = deadbeat_voltage(p, round(psi[0] / fl), round(psi[1] / fl), int(i_ab[0]), int(i_ab[1]), 0, 0,
                                    0, theta, omega, i_s)
        d_ref, q_ref = flux_reference(p, i_s)
        end = (theta + omega / 2) / 2**32 * 2 * math.pi
        ref = np.array([d_ref * math.cos(end) - q_ref * math.sin(end), d_ref * math.sin(end) + q_ref * math.cos(end)])
        zero = np.array(applied_flux(0, 0, int(i_ab[0]), int(i_ab[1]), p.dt_f, p.vth_f), float)
        r_f = p.r_f / 65536 * i_ab
        v_star = (ref - psi / fl - 2 * zero + 2 * r_f) / 2**FLUX_FRAC + p.r_v / 65536 * i_ab
        th = theta / 2**32 * 2 * math.pi
        want = _rot(*v_star, th)
        while max(abs(want)) > p.v_lim:
            want = want / 2
        # the Q1.15 sine and cosine of the two rotations: 2^-15 of the reference's flux, in voltage LSB
        tol = 3 + 2 * math.hypot(d_ref, q_ref) / 2**15 / 2**FLUX_FRAC
        assert abs(v_d - want[0]) <= tol and abs(v_q - want[1]) <= tol


@pytest.fixture(scope="module")
def torquestep():
    from hfi.backends import run
    from hfi.report import metrics_of
    sc = load_scenario(SCENARIO)
    res = run(sc, "golden", progress=False)
    return sc, res, metrics_of(sc, res)


def test_torquestep_holds_lock_through_the_2pu_step(torquestep):
    """The 0 -> 2 p.u. load step at standstill (paper Fig. 8a, speed poles at 2 pi 2.5 rad/s), issue 18's
    numbers: lock held; the position error's peak over the step's transient (the 0.3 s after it, while
    the speed sags and recovers) within 5 deg el; its RMS in the steady state after it (1.1 s to the end)
    within 1 deg; the speed back at standstill (the last 0.5 s within 10 r/min)."""
    sc, res, m = torquestep
    assert m["locked"] and m["final_mode"] == "RUN"
    err = res.angle_error_deg(quarters=3)
    step = (res.t >= 0.8) & (res.t < 1.1)
    assert np.max(np.abs(err[step])) <= 5.0
    steady = res.t >= 1.1
    assert np.sqrt(np.mean(err[steady] ** 2)) <= 1.0
    late = res.t >= sc.duration - 0.5
    assert abs(np.mean(res.windows["omega_m"][late]) * 30 / math.pi) < 10.0


def _run(name: str, backend: str):
    from hfi.backends import run
    from hfi.report import metrics_of
    sc = load_scenario(ROOT / "scenarios" / f"varatharajan2020_{name}.toml")
    res = run(sc, backend, progress=False)
    return sc, res, metrics_of(sc, res)


@pytest.mark.long
def test_speedrange_is_seamless():
    """0 -> 1500 -> -1500 r/min through the fusion both ways (issue 18): lock held, the position error's
    peak from the start of RUN within 10 deg el, both rated-speed plateaus settled within 1 %; the hls backend
    gives every window column of the golden run (the whole scenario: the fusion and the high-speed observer)."""
    _, res, m = _run("speedrange", "golden")
    _, hls, _ = _run("speedrange", "hls")
    for name, col in res.windows.items():
        np.testing.assert_array_equal(hls.windows[name], col, err_msg=name)
    assert m["locked"] and m["angle_error_at_bottom"]["peak_deg"] <= 10.0
    plateaus = [s for s in m["segments"] if abs(s["speed_ref_rpm"]) > 1000]
    assert len(plateaus) == 2
    for s in plateaus:
        assert abs(s["speed_mean_rpm"] - s["speed_ref_rpm"]) <= 0.01 * abs(s["speed_ref_rpm"])


def test_tracking_holds_lock():
    """The 1.5 Hz speed reference (+-100 r/min at standstill and at 750 r/min) under the 1.5 Hz load
    (issue 18: tracking at 1.5 Hz with lock held); the low-speed and the fundamental model both had charge
    (the speed crosses the fusion band). On the hls backend, bit-identical to golden (test_speedrange_is_seamless,
    tests/test_hls_identity.py) and 7 times faster."""
    sc, res, m = _run("tracking", "hls")
    assert m["locked"] and m["final_mode"] == "RUN"
    rpm = np.abs(res.windows["omega_m"]) * 30 / math.pi
    assert rpm.min() < 50 and rpm.max() > 600
