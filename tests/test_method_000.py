"""The 000 method's golden blocks (Tap et al. 2023) against independent references.

* the band-pass and notch sections (golden.firmware.biquad): their quantised responses against the
  analog prototypes of eq. (13) and Sec. II-C, the integer filter against its own response;
* ``rot_bpf`` on window means of the ideal HF current of a salient machine (eqs. (8)-(11), written out
  here in floating point), standing and turning, for both signs of the saliency;
* ``eemf_smo`` on the steady state of the dq model of eq. (1), forwards and backwards;
* the MTPA table (eq. (4)) against a numerical torque maximum; the delay fit against eq. (18).
"""

from __future__ import annotations

import cmath
import math
from dataclasses import replace
from pathlib import Path

import pytest

import hfi.sweep as sw
from golden.control_config import (dc_link_limits, eemf_smo_params, firmware_params, rot_bpf_delay,
                                   rot_bpf_params, rot_cross_saturation_table, rot_hf_current)
from golden.firmware import biquad
from golden.firmware.biquad import BiquadState, biquad_step
from golden.firmware.eemf_smo import EemfSmo
from golden.firmware.estimator import Measurement
from golden.firmware.mtpa import mtpa_lookup, mtpa_table
from golden.firmware.rot_bpf import TRACK_OBSERVER, TRACK_PLL, RotatingBpf, cross_saturation_turn
from golden.firmware.supervisor import MODE_CONVERGE, Firmware
from golden.fixed import wrap
from golden.fpga.cordic import sincos_q15
from golden.fpga.demodulator import WindowResult
from golden.scenario import load_scenario, parse_scenario

F_S = 10e3
ROOT = Path(__file__).resolve().parents[1]
SCENARIO = ROOT / "scenarios" / "tap2023_fullload.toml"
TURN = 2**32


def deg(binary: int) -> float:
    return wrap(binary, 32) * 360.0 / TURN


# ---- filters -----------------------------------------------------------------------------------------------
def test_bandpass_centre_is_exact_and_bandwidth_is_eq13():
    c = biquad.bandpass(1000.0, 164.0, F_S)
    h0 = biquad.response(c, 1000.0, F_S)
    assert abs(h0 - 1) < 1e-6                                   # prewarped: unity gain, zero phase at f0
    mid = math.sqrt(1000.0**2 + 82.0**2)                        # -3 dB edges of the analog prototype:
    for f in (mid - 82.0, mid + 82.0):                          # f+ - f- = bandwidth, f+ f- = f0^2
        assert abs(biquad.response(c, f, F_S)) == pytest.approx(math.sqrt(0.5), abs=0.03)   # warped a little


def test_a_bandpass_narrower_than_its_coefficients_resolve_is_refused():
    """b0 = w_g k / (k^2 + w_g k + w_0^2) (eq. (13), bilinear, prewarped) rounds to 0 below half an LSB of the
    Q(COEF_FRAC) coefficients: such a filter passes nothing (and the delay fit divided by its zero gain)."""
    w0 = 2 * math.pi * 1000.0
    k = w0 / math.tan(w0 / (2 * F_S))
    half_lsb = 2.0 ** -(biquad.COEF_FRAC + 1)
    bw_edge = half_lsb * (k * k + w0 * w0) / (k * (1 - half_lsb)) / (2 * math.pi)   # b0(bw_edge) = half an LSB
    assert biquad.bandpass(1000.0, bw_edge * 1.01, F_S).b0 == 1
    with pytest.raises(ValueError, match=r"a band-pass of .* Hz at 1000 Hz is narrower than its coefficients resolve"):
        biquad.bandpass(1000.0, bw_edge * 0.99, F_S)


def test_plain_bilinear_would_move_the_centre():
    """docs/methods.md: without prewarping the 1000 Hz centre lands near 970 Hz at 10 kHz."""
    f_plain = F_S / math.pi * math.atan(math.pi * 1000.0 / F_S)
    assert 968 < f_plain < 972


def test_notch_rejects_the_injection_and_passes_dc():
    c = biquad.notch(500.0, 400.0, F_S)
    assert abs(biquad.response(c, 500.0, F_S)) < 1e-4
    assert abs(biquad.response(c, 0.0, F_S) - 1) < 1e-6
    assert abs(biquad.response(c, 60.0, F_S)) > 0.97            # a 60 Hz fundamental passes


@pytest.mark.parametrize("kind, f", [("bandpass", 1000.0), ("bandpass", 500.0), ("notch", 200.0), ("notch", 900.0)])
def test_integer_section_follows_its_response(kind, f):
    c = biquad.bandpass(1000.0, 164.0, F_S) if kind == "bandpass" else biquad.notch(500.0, 400.0, F_S)
    h = biquad.response(c, f, F_S)
    s, amp = BiquadState(), 20000.0
    out = []
    for k in range(4000):
        s = biquad_step(s, round(amp * math.cos(2 * math.pi * f * k / F_S)), c)
        if k >= 3000:
            out.append((s.y1 / 2**biquad.Y_FRAC, k))
    # least-squares phasor of the output over the last 1000 samples
    z = sum(y * cmath.exp(-2j * math.pi * f * k / F_S) for y, k in out) * 2 / len(out)
    assert abs(z) == pytest.approx(amp * abs(h), rel=2e-3, abs=2.0)
    if abs(h) > 0.05:
        assert cmath.phase(z / h) == pytest.approx(0.0, abs=2e-3)


# ---- rot_bpf on the ideal HF response ------------------------------------------------------------------------
def hf_current(theta: float, phi: float, v: float, w_h: float, l_d: float, l_q: float, r: float = 5.9) -> complex:
    """Stationary HF current of a salient machine to the voltage v e^{j phi}, steady state of eq. (8) with
    the stator resistance (speed neglected). In the rotor frame u = v e^{j(phi - theta)}, and each axis
    answers its real sinusoid with its admittance Y = 1 / (R + j w_h L): i_d = Re(Y_d u), i_q = Im(Y_q u),
    i.e. i_dq = (Y_d + Y_q)/2 u + (conj Y_d - conj Y_q)/2 conj(u); back in the stationary frame the second
    term is the negative sequence at 2 theta - phi (eqs. (10)-(11) for R = 0)."""
    y_d, y_q = 1 / complex(r, w_h * l_d), 1 / complex(r, w_h * l_q)
    return v * ((y_d + y_q) / 2 * cmath.exp(1j * phi)
                + (y_d.conjugate() - y_q.conjugate()) / 2 * cmath.exp(1j * (2 * theta - phi)))


def run_rot(p, theta_of_k, l_d, l_q, n=1500, i_lsb=5 / 32768, i_fund=lambda k: 0):
    """Steps a RotatingBpf on window means of the ideal response (plus ``i_fund(k)`` LSB on the q component,
    slow enough for the band-pass to remove and read by the motion observer's feed-forward); returns the
    estimator and the list of (k, theta output)."""
    est = RotatingBpf(p)
    step = 214_748_365                                          # 500 Hz at 10 kHz
    out = []
    for k in range(n):
        inj_phase = (k * step) % TURN
        phi = (inj_phase - step / 4) / TURN * 2 * math.pi       # the centre of window k
        i = hf_current(theta_of_k(k), phi, 28.0, 2 * math.pi * 500, l_d, l_q) / i_lsb
        s, c = sincos_q15(inj_phase)
        win = WindowResult(0, 0, 0, 0, 0, 1, inj_phase)
        est.step(Measurement(win, round(i.real), round(i.imag) + i_fund(k), 0, 32767, 0, 0, s, c))
        out.append((k, est.theta))
    return est, out


def run_more(est: RotatingBpf, theta: float, n: int, start: int = 3000) -> None:
    """``n`` more windows of the standing rotor at ``theta`` (continuing the injection phase of run_rot)."""
    step = 214_748_365
    for k in range(start, start + n):
        inj_phase = (k * step) % TURN
        phi = (inj_phase - step / 4) / TURN * 2 * math.pi
        i = hf_current(theta, phi, 28.0, 2 * math.pi * 500, 0.067, 0.182) / (5 / 32768)
        s, c = sincos_q15(inj_phase)
        est.step(Measurement(WindowResult(0, 0, 0, 0, 0, 1, inj_phase), round(i.real), round(i.imag), 0, 32767,
                             0, 0, s, c))


def rot_params(l_d: float, l_q: float, tracking: str = "pll"):
    """The scenario's rot_bpf integers for these inductances, tracking with the paper's PLL or the observer."""
    sc = load_scenario(SCENARIO)
    sc.plant["mag"]["L_d"], sc.plant["mag"]["L_q"] = l_d, l_q
    sc.estimator.params["rot_bpf"]["tracking"] = tracking
    p = rot_bpf_params(sc)
    assert p.tracking == (TRACK_OBSERVER if tracking == "observer" else TRACK_PLL)
    return p


@pytest.mark.parametrize("l_d, l_q", [(0.067, 0.182), (0.182, 0.067)])
@pytest.mark.parametrize("theta_deg", [0.0, 37.0, 90.0, 133.0, 222.0, 301.0])
def test_rot_bpf_finds_the_angle_at_standstill(l_d, l_q, theta_deg):
    """Standing rotor: theta_hat = theta modulo half a turn, within 0.1 deg (eq. (17)'s sign from the
    saliency: with the other sign the loop would settle 90 deg off)."""
    p = rot_params(l_d, l_q)
    th = math.radians(theta_deg)
    est, out = run_rot(p, lambda k: th, l_d, l_q, n=3000)
    e = (deg(round(th / (2 * math.pi) * TURN) - est.theta) + 90) % 180 - 90
    assert abs(e) < 0.1


@pytest.mark.parametrize("l_d, l_q", [(0.067, 0.182), (0.182, 0.067)])
@pytest.mark.parametrize("theta_deg", [0.0, 133.0, 301.0])
def test_rot_bpf_observer_finds_the_angle_at_standstill(l_d, l_q, theta_deg):
    """The motion observer in place of the PLL (8 Hz, the scenario's): theta_hat = theta modulo half a turn
    within 0.1 deg at standstill."""
    p = rot_params(l_d, l_q, "observer")
    th = math.radians(theta_deg)
    est, _ = run_rot(p, lambda k: th, l_d, l_q, n=6000)
    e = (deg(round(th / (2 * math.pi) * TURN) - est.theta) + 90) % 180 - 90
    assert abs(e) < 0.1


def test_rot_bpf_observer_follows_the_acceleration_it_is_told():
    """The rotor at standstill starts to accelerate in window 3000: the current rises to 3000 LSB over 500
    windows (50 ms, a slew limit as the scenarios') and the acceleration with it, to 157 rad/s^2 (electrical;
    about 250 r/min after the 1500 windows at 2 pole pairs). With the feed-forward telling the observer that
    acceleration (c_t i_q = alpha T^2 in Q24 binary angle, c_r = 0) the output for the window after next
    stays within 0.5 deg of the true angle over the 1500 windows after the onset; the observer without it
    (c_t = 0) must find the acceleration through its delayed error (more than 1 deg), the paper's PLL
    (100 1/s, 2500 1/s^2) lags by up to alpha / k_i = 3.6 deg (more than 2 deg)."""
    alpha, i_q, k0, n_ramp, n = 157.0, 3000, 3000, 500, 1500
    acc_q24 = alpha / F_S**2 / (2 * math.pi) * TURN * 2**24     # binary angle per period^2, Q24
    current = [0] * k0 + [round(i_q * min(k / n_ramp, 1.0)) for k in range(n + 3)]
    theta, w = [0.3], 0.0                                       # rad and rad per period, electrical
    for i in current[:-1]:                                      # the acceleration of each window's current
        w += alpha / F_S**2 * i / i_q
        theta.append(theta[-1] + w)
    obs = replace(rot_params(0.067, 0.182, "observer"), c_t=round(acc_q24 / i_q), c_r=0)
    errors = {}
    for name, p in (("told", obs), ("untold", replace(obs, c_t=0)), ("pll", rot_params(0.067, 0.182))):
        _, out = run_rot(p, lambda k: theta[k], 0.067, 0.182, n=k0 + n, i_fund=lambda k: current[k])
        errors[name] = max(abs((deg(round(theta[k + 2] / (2 * math.pi) * TURN) - th) + 90) % 180 - 90)
                           for k, th in out[k0:])
    assert errors["told"] < 0.5 and errors["untold"] > 1.0 and errors["pll"] > 2.0, errors


@pytest.mark.parametrize("turn_deg", [10.0, -10.0])
def test_rot_bpf_error_has_the_sign_of_theta_minus_estimate(turn_deg):
    """The normalised eq. (17): with the PLL held (gains 0) after it has locked, turning the rotor by
    +-10 deg gives an error of +-10 deg once the filters have settled."""
    p = rot_params(0.067, 0.182)
    est, _ = run_rot(p, lambda k: 0.5, 0.067, 0.182, n=3000)
    est.p = replace(p, pll_kp=0, pll_ki=0)
    est.pll = replace(est.pll, omega=0, integ=0)
    run_more(est, 0.5 + math.radians(turn_deg), 300)
    assert deg(est.err) == pytest.approx(turn_deg, abs=0.3)


@pytest.mark.parametrize("rpm", [15.0, 100.0, 300.0, -300.0])
def test_rot_bpf_compensates_its_delays_when_turning(rpm):
    """Constant speed: the output for the window after next equals the true angle there within 0.3 deg
    at 15-300 r/min (the band-pass phase of eqs. (18)-(19), the average and the loop's periods)."""
    p = replace(rot_params(0.067, 0.182), pll_kp=3277, pll_ki=10486)   # 500 1/s, 105 000 1/s^2: damping 1
    w = rpm / 60 * 2 * 2 * math.pi / F_S                      # electrical rad per period, 2 pole pairs
    est, out = run_rot(p, lambda k: 0.3 + w * k, 0.067, 0.182, n=4000)
    errs = [(deg(round((0.3 + w * (k + 2)) / (2 * math.pi) * TURN) - th) + 90) % 180 - 90 for k, th in out[-500:]]
    assert max(abs(e) for e in errs) < 0.2


def test_delay_fit_matches_eq18():
    """The host's band-pass delay against the paper's eq. (18), 2 dtheta = atan((w^2 - w0^2) / (w_g w)) with
    w = 2 (w_h - w_e), at the switch-over speed (10 Hz electrical), evaluated at the analog frequency the
    prewarped bilinear transform maps 2 (f_h - f_e) to (w_a = k tan(w T / 2), k = w0 / tan(w0 T / 2));
    the plain continuous formula is 7 % lower there."""
    c = biquad.bandpass(1000.0, 164.0, F_S)
    d = rot_bpf_delay(c, 500.0, 1, F_S, 10.0) - 1             # periods, N = 1: the band-pass alone
    w0, wg = 2 * math.pi * 1000, 2 * math.pi * 164
    w = 2 * 2 * math.pi * (500 - 10)
    k = w0 / math.tan(w0 / (2 * F_S))
    w_a = k * math.tan(w / (2 * F_S))
    lag = -math.atan((w_a * w_a - w0 * w0) / (wg * w_a)) / 2    # rad of theta at 10 Hz
    assert d * 2 * math.pi * 10 / F_S == pytest.approx(lag, rel=0.01)


# ---- eemf_smo on the dq model ------------------------------------------------------------------------------------
@pytest.mark.parametrize("rpm", [300.0, -300.0, 1000.0, 3000.0])
def test_eemf_smo_tracks_the_model(rpm):
    """Steady state of eq. (1) (MTPA-like currents i_d = -1 A, i_q = 1.5 A, exact window means of a
    rotating vector neglected): after 0.3 s the angle for the window after next is within 2 deg."""
    sc = load_scenario(SCENARIO)
    p = eemf_smo_params(sc)
    i_lsb, v_lsb = 5 / 32768, 350 / 32768
    l_d, l_q, psi, r = 0.067, 0.182, 0.096, 5.9
    w = rpm * 2 * math.pi / 60 * 2
    i_d, i_q = -1.0, 1.5
    v = complex(r * i_d - w * l_q * i_q, r * i_q + w * (l_d * i_d + psi))
    est = EemfSmo(p)
    th0, t = 0.3, 1 / F_S
    est.sync(round((th0 + 2 * w * t) / (2 * math.pi) * TURN) % TURN, round(w * t / (2 * math.pi) * TURN))
    est.ih_al, est.ih_be = (round(x / i_lsb) << 8 for x in
                            ((i_d * math.cos(th0) - i_q * math.sin(th0)), (i_d * math.sin(th0) + i_q * math.cos(th0))))
    for k in range(3000):
        th = th0 + w * t * k
        r_ = cmath.exp(1j * th)
        vab = v * r_
        s, c = sincos_q15(round(th / (2 * math.pi) * TURN) % TURN)
        est.step(Measurement(None, round(i_d / i_lsb), round(i_q / i_lsb), s, c, round(vab.real / v_lsb),
                             round(vab.imag / v_lsb)))
    e = deg(round((th0 + w * t * 3001) / (2 * math.pi) * TURN) - est.theta)
    assert abs(e) < 2.0


# ---- MTPA --------------------------------------------------------------------------------------------------------
def test_mtpa_table_is_the_torque_maximum():
    """Each table point maximises 1.5 p (psi_f i_q + (L_d - L_q) i_d i_q) on its current circle (a 0.5 deg
    search), and the interpolated split has the commanded magnitude within 1 %."""
    psi, l_d, l_q, i_lsb = 0.096, 0.067, 0.182, 5 / 32768
    shift, t_d, t_q = mtpa_table(20972, i_lsb, psi, l_d, l_q)      # 3.2 A
    for k in range(1, len(t_d)):
        i_s = math.hypot(t_d[k], t_q[k]) * i_lsb
        best = max((psi * i_s * math.sin(a) + (l_d - l_q) * i_s * i_s * math.cos(a) * math.sin(a), a)
                   for a in (math.radians(x / 2) for x in range(180, 361)))[1]
        assert math.degrees(math.atan2(t_q[k], t_d[k])) == pytest.approx(math.degrees(best), abs=0.5)
    for i_s in (1000, 7777, 15000, 20972):
        d, q = mtpa_lookup(i_s, shift, t_d, t_q)
        assert math.hypot(d, q) == pytest.approx(i_s, rel=0.01)


def test_firmware_params_of_the_scenario():
    """The scenario's integers: rotating injection, pilot polarity, MTPA, notch and a 1 kHz speed loop."""
    p = firmware_params(load_scenario(SCENARIO))
    assert (p.inj_rot, p.pol_mode, p.speed_div) == (1, 1, 10)
    assert p.notch is not None and len(p.mtpa_id) >= 2
    w = 2 * math.pi * 500
    d_r = math.atan(5.9 / (w * 0.067)) + math.atan(5.9 / (w * 0.182))       # 2.2 deg: R's share
    assert p.rot.offset == (1 << 30) - round(d_r / (2 * math.pi) * TURN)    # L_q > L_d: +pi/2 (docs/methods.md)


@pytest.mark.parametrize("amps", [0.0, 0.3])
def test_rot_bpf_asks_for_its_magnetizing_current(amps):
    """``estimator.rot_bpf.i_d_min`` (default 0, the paper's): the d-current the supervisor asks for while the method
    is in charge, before RUN too on a reluctance machine (no polarity test: CONVERGE asks for the estimator's
    d-current), whose saliency appears only with it (sweeps/cross_000_on_003.toml, docs/compare.md)."""
    job = sw.jobs(sw.load_spec(ROOT / "sweeps" / "cross_000_on_003.toml"), "test")[0]
    sw._set(job.tree, "estimator.rot_bpf.i_d_min", f"{amps} A")
    sc = parse_scenario(job.tree, "cross_000_on_003")
    expected = -round(amps * 2**15 / sc.plant["sens"]["adc_range"])      # the current LSB: adc_range / 2^15
    assert rot_bpf_params(sc).i_d == RotatingBpf(rot_bpf_params(sc)).i_d == expected
    fw = Firmware(firmware_params(sc))
    link = dc_link_limits(sc)                                              # the nominal link: no dc-link trip
    fw.step(WindowResult(0, 0, 0, 0, 0, 1, 0, 0, 0, vdc=(link["vdc_lo"] + link["vdc_hi"]) // 2), speed_ref=0)
    assert (fw.mode, fw.i_d_ref) == (MODE_CONVERGE, expected)     # (Outputs.i_d_ref adds the HF current's prediction)


def test_rot_bpf_on_a_map_takes_the_incremental_inductances():
    """On the SyRM at its 0.3 A the negative sequence's resistance share (the offset) and the positive-sequence
    current the dead-time compensation adds (Tap et al. 2023, eq. (11)) take the incremental inductances at that
    current, from the algebraic model's own Jacobian (golden.saturation_fit), not the defaults' 5.59 / 6.26 mH of
    the map's parameter dict."""
    from golden.saturation_fit import fluxes, jacobian

    job = sw.jobs(sw.load_spec(ROOT / "sweeps" / "cross_000_on_003.toml"), "test")[0]
    sc = parse_scenario(job.tree, "cross_000_on_003")
    mag = sc.plant["mag"]
    g_dd, _, g_qq = jacobian(mag, *fluxes(mag, -0.3, 0.0))
    l_d, l_q = 1 / float(g_dd), 1 / float(g_qq)
    w, r = 2 * math.pi * 500, sc.plant["R_s"]
    d_r = math.atan(r / (w * l_d)) + math.atan(r / (w * l_q))                # 1.2 deg, not the defaults' 27
    assert rot_bpf_params(sc).offset == (1 << 30) - round(d_r / (2 * math.pi) * TURN)
    i_lsb = sc.plant["sens"]["adc_range"] / 2**15
    assert rot_hf_current(sc) == round(21.6 * 0.5 * (l_d + l_q) / (w * l_d * l_q) / i_lsb)   # 50 mA


def _syrm_xs(**settings):
    """The first point of the 000-on-SyRM sweep with the cross-saturation table on and ``settings`` (dotted keys)."""
    job = sw.jobs(sw.load_spec(ROOT / "sweeps" / "cross_000_on_003.toml"), "test")[0]
    sw._set(job.tree, "estimator.rot_bpf.cross_saturation", "on")
    for key, value in settings.items():
        sw._set(job.tree, key, value)
    return parse_scenario(job.tree, "cross_000_on_003")


def test_rot_cross_saturation_table_is_the_plants_turn():
    """The table against an independent computation: the plant's own magnetic model (the C plant's ``mag_eval``,
    not golden.saturation_fit's Python) at the operating point the drive asks for, which for a magnet-free machine's
    MTPA is ``i_d = -|i_q|`` in closed form (at least the 0.3 A): the argument of the negative sequence's coefficient
    ``(g_dd - g_qq)/2 + j g_dq`` less its value without the cross term, in 2^16 binary angle."""
    from golden.plant.binding import mag_eval
    from golden.plant.fluxmap import psi_from_current

    sc = _syrm_xs()
    shift, table = rot_cross_saturation_table(sc)
    lsb = sc.plant["sens"]["adc_range"] / 2**15
    expected = []
    for k in range(len(table)):
        q = (k << shift) * lsb
        psi = psi_from_current(sc.plant["mag"], min(-q, -0.3), q)
        _, _, g_dd, g_dq, _, g_qq = mag_eval(sc.plant["mag"], psi[0], psi[1])
        s = 1 if g_dd >= g_qq else -1                                      # the SyRM: L_d < L_q, s = 1
        expected.append(round(math.atan2(2 * s * g_dq, s * (g_dd - g_qq)) / (2 * math.pi) * 2**16))
    assert table[0] == 0 and list(table) == expected
    assert min(table) < -1000                     # 5.5 deg of the sequence's phase: worth correcting


def test_rot_cross_saturation_turns_the_error_by_the_table():
    """The estimator takes ``sign(i_q) a0(|i_q|) 2^16`` off the sequence's phase (half of it off the angle error):
    the table (0, 1000) on a grid of 16 LSB gives 500 at |i_q| = 8 (linear interpolation), so the error of the
    same window moves by -+(500 << 15) against the estimator without a table."""
    base = rot_params(0.067, 0.182)
    xs = replace(base, xs_shift=4, xs_angle=(0, 1000))
    assert (cross_saturation_turn(xs, 8), cross_saturation_turn(xs, -8), cross_saturation_turn(base, 8)) == \
        (500 << 16, -(500 << 16), 0)
    for i_q in (8, -8):
        errs = []
        for p in (base, xs):
            est = RotatingBpf(p)
            est.step(Measurement(WindowResult(0, 0, 0, 0, 0, 1, 0), 300, i_q, 0, 32767, 0, 0, 0, 32767))
            errs.append(est.err)
        assert wrap(errs[1] - errs[0], 31) == (-(500 << 15) if i_q > 0 else 500 << 15)


def test_rot_cross_saturation_refuses_a_linear_model():
    sc = load_scenario(SCENARIO)
    sc.estimator.params["rot_bpf"]["cross_saturation"] = "on"
    with pytest.raises(ValueError, match="estimator.rot_bpf.cross_saturation"):
        rot_bpf_params(sc)
