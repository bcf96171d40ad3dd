"""Tests of the PLL (golden/firmware/pll.py; docs/spec.md 5.2).

The step and ramp responses are compared with the closed-form solution of the same difference equation
in real numbers, x_n = x_p(n) + A^n (x_0 - x_p(0)) (numpy float, matrix powers), with Kp = kp/2^16 and
Ki = ki/2^24. The integer PLL equals that real system plus a disturbance d_n in (-2, 0] added to omega
(the two floors of step 3; the integrator itself is exact), so the deviation is bounded by
2 * sum |h| with h the impulse response from that disturbance: the tolerance is this bound, not a guess.
"""

from __future__ import annotations

import math
import random
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from golden.firmware.pll import PllState, pll_gains, pll_step  # noqa: E402

TURN = 1 << 32
KP, KI = 2621, 6711  # hand-checked below (paper Table II at 5 kHz)


def swrap(x: float) -> float:
    """Signed residue of x modulo 2^32 (float or int), in [-2^31, 2^31)."""
    return (x + 2**31) % TURN - 2**31


def test_pll_gains_paper():
    # k_p T = 200/5000 = 0.04; 0.04 * 65536 = 2621.44 -> 2621
    # k_i T^2 = 10000/25e6 = 4e-4; 4e-4 * 16777216 = 6710.89 -> 6711
    assert pll_gains(200.0, 10000.0, 5000.0) == (2621, 6711)
    with pytest.raises(ValueError):
        pll_gains(200.0, 10000.0, 0.0)
    with pytest.raises(ValueError):
        pll_gains(-1.0, 10000.0, 5000.0)
    with pytest.raises(ValueError):
        pll_gains(200.0, 1e20, 5000.0)


def test_pll_first_steps_by_hand():
    s = PllState()
    # e = 1000; integ = 6711000; omega = floor(2621000/65536 = 39.99) + floor(6711000/2^24 = 0.4) = 39
    s = pll_step(s, 1000, KP, KI)
    assert (s.theta, s.integ, s.omega) == (39, 6711000, 39)
    # e = 961; integ = 6711000 + 961*6711 = 13160271; kp e = 2518781 -> 38 (38.43);
    # 13160271 / 2^24 = 0.78 -> 0; omega = 38, theta = 77
    s = pll_step(s, 1000, KP, KI)
    assert (s.theta, s.integ, s.omega) == (77, 13160271, 38)
    # e = -77 (theta_hat = 0): integ = 13160271 - 516747 = 12643524; kp e = -201817 -> floor(-3.08) = -4;
    # omega = -4 + 0 = -4; theta = 73
    s = pll_step(s, 0, KP, KI)
    assert (s.theta, s.integ, s.omega) == (73, 12643524, -4)


def test_pll_wrap_by_hand():
    # theta just below 2^32, theta_hat just above 0: e = 2^20 + 10 = 1048586 (short way, through 2^32)
    # integ = 1048586 * 6711 = 7037060646 -> /2^24 = 419.44 -> 419
    # kp e = 2748343906 -> /2^16 = 41936.40 -> 41936; omega = 42355; theta = 2^32 - 10 + 42355 - 2^32
    s = pll_step(PllState(TURN - 10, 0, 0), 1 << 20, KP, KI)
    assert (s.theta, s.integ, s.omega) == (42345, 7037060646, 42355)
    # the other way: theta = 10, theta_hat = 2^32 - 10 -> e = -20; integ = -134220 -> floor(-0.008) = -1;
    # kp e = -52420 -> floor(-0.7999) = -1; omega = -2; theta = 8
    s = pll_step(PllState(10, 0, 0), TURN - 10, KP, KI)
    assert (s.theta, s.integ, s.omega) == (8, -134220, -2)
    # half a turn is -2^31 (wrap to s32): integ = -2^31 * 6711 = -14411762761728 (/2^24 = -859008 exactly);
    # kp e / 2^16 = -2^15 * 2621 = -85884928; omega = -86743936; theta = 2^32 - 86743936 = 4208223360
    s = pll_step(PllState(0, 0, 0), 1 << 31, KP, KI)
    assert (s.theta, s.integ, s.omega) == (4208223360, -14411762761728, -86743936)


def test_pll_saturations():
    # integrator saturates at the int64 limits, omega at the s32 limits
    s = pll_step(PllState(0, 2**63 - 5, 0), 1 << 30, KP, KI)
    assert s.integ == 2**63 - 1
    assert s.omega == 2**31 - 1
    assert s.theta == 2**31 - 1
    s = pll_step(PllState(0, -(2**63) + 5, 0), 3 << 30, KP, KI)
    assert s.integ == -(2**63)
    assert s.omega == -(2**31)
    assert s.theta == 2**31


# ---- closed form of the same difference equation in real numbers ---------------------------------
def _matrices(kp: int, ki: int):
    """State s_n = (theta_n, I_{n-1}) before period n, I in angle LSB per period (integ / 2^24).
    I_n = I_{n-1} + Ki (r_n - theta_n); theta_{n+1} = theta_n + Kp (r_n - theta_n) + I_n."""
    Kp, Ki = kp / 2**16, ki / 2**24
    A = np.array([[1.0 - Kp - Ki, 1.0], [-Ki, 1.0]])
    return A, Kp, Ki


def closed_form(kp, ki, r0, v, theta0, n_steps):
    """theta_n, omega_n, I_n (n = 0..n_steps-1) for r_n = r0 + v n from theta_0 = theta0, I_{-1} = 0.
    Particular solution of a ramp: theta = r, I = v (type 2: zero error); homogeneous part A^n."""
    A, Kp, Ki = _matrices(kp, ki)
    d0 = np.array([theta0 - r0, 0.0 - v])
    th, om, integ = [], [], []
    for n in range(n_steps):
        dev = np.linalg.matrix_power(A, n) @ d0
        theta_n = r0 + v * n + dev[0]
        i_prev = v + dev[1]
        e = r0 + v * n - theta_n
        i_n = i_prev + Ki * e
        th.append(theta_n)
        om.append(Kp * e + i_n)
        integ.append(i_n)
    return np.array(th), np.array(om), np.array(integ)


def disturbance_bounds(kp, ki, n_steps):
    """2 * sum |h| for theta, omega and I, h the response to a unit disturbance added to omega at n = 0."""
    A, Kp, Ki = _matrices(kp, ki)
    x = np.zeros(2)  # deviation (theta, I_prev)
    ht, ho, hi = [], [], []
    for n in range(n_steps):
        e = -x[0]
        i_n = x[1] + Ki * e
        om = Kp * e + i_n + (1.0 if n == 0 else 0.0)
        ht.append(x[0])
        ho.append(om)
        hi.append(i_n)
        x = np.array([x[0] + om, i_n])
    return tuple(2.0 * float(np.sum(np.abs(h))) for h in (ht, ho, hi))


def run_int(kp, ki, r0, v, theta0, n_steps):
    s = PllState(theta0 % TURN, 0, 0)
    th, om, integ = [], [], []
    for n in range(n_steps):
        th.append(s.theta)
        s = pll_step(s, (r0 + v * n) % TURN, kp, ki)
        om.append(s.omega)
        integ.append(s.integ)
    return np.array(th, dtype=float), np.array(om, dtype=float), np.array(integ, dtype=float) / 2**24


@pytest.mark.parametrize("kp, ki", [(KP, KI), pll_gains(400.0, 40000.0, 5000.0), pll_gains(50.0, 2000.0, 5000.0)])
@pytest.mark.parametrize(
    "r0, v, theta0",
    [
        (1 << 28, 0, 0),  # step of 22.5 deg
        (-(1 << 29), 0, 0),  # negative step of 45 deg
        (0, 27342611, 0),  # ramp at 200 rad/s
        (1 << 27, -3_000_000, 0),  # step and negative ramp
        (TURN - 1000, 100_000, 0),  # short-way step through the 2^32 boundary, then a ramp
    ],
)
def test_pll_matches_closed_form(kp, ki, r0, v, theta0):
    n = 1500
    th_i, om_i, in_i = run_int(kp, ki, r0, v, theta0, n)
    # the real system sees the same shortest-way error: unwrap r0 relative to theta0
    r0u = theta0 + swrap(r0 - theta0)
    th_f, om_f, in_f = closed_form(kp, ki, r0u, v, theta0, n)
    bt, bo, bi = disturbance_bounds(kp, ki, 4000)
    dth = np.abs([swrap(a - b) for a, b in zip(th_i, th_f)])
    assert dth.max() <= bt + 1e-3, (dth.max(), bt)
    assert np.abs(om_i - om_f).max() <= bo + 1e-3, (np.abs(om_i - om_f).max(), bo)
    assert np.abs(in_i - in_f).max() <= bi + 1e-3
    # the bound itself is small: 74 LSB of 2^32 (paper gains), 263 for the slow (50, 2000) loop
    assert bt < 300


def test_pll_ramp_zero_steady_state_error():
    """Type 2: a constant-speed ramp is tracked with e == 0 exactly, omega == speed, after settling.

    From omega = 0 the loop pulls in up to 2^28 per period (1/16 turn; 1960 rad/s at 5 kHz) with the
    paper gains; beyond that (e.g. 3 * 2^27) it slips cycles, which is the real loop, not a wrap bug."""
    seed = 7
    rng = random.Random(seed)
    speeds = [0, 1, -1, 7, 1000, 27342611, -27342611, 1 << 28, -(1 << 28)]
    speeds += [rng.randint(-(1 << 27), 1 << 27) for _ in range(10)]
    for v in speeds:
        for th0 in (0, 123_456_789, TURN - 5):
            s = PllState()
            r = th0
            for n in range(5000):
                e = swrap(r - s.theta)
                if n >= 3500:  # the last 1-LSB error can take ~2800 periods (ki e = 6711 per period, Q24)
                    assert e == 0, f"seed {seed}: v {v} th0 {th0} n {n} e {e}"
                    assert s.omega == v and (s.integ >> 24) == v, f"seed {seed}: v {v}"
                s = pll_step(s, r, KP, KI)
                r = (r + v) % TURN


def test_pll_wrap_translation_invariance():
    """Adding a constant c (mod 2^32) to theta_hat and theta adds c to theta and changes nothing else,
    also when the trajectories cross the 2^32 boundary many times (v = 2^29: every 8 periods)."""
    seed = 99
    rng = random.Random(seed)
    for _ in range(20):
        c = rng.randrange(TURN)
        v = rng.choice([1 << 29, -(1 << 29), rng.randint(-(1 << 30), 1 << 30)])
        a, b = PllState(), PllState(c, 0, 0)
        r = rng.randrange(TURN)
        for _n in range(300):
            a = pll_step(a, r, KP, KI)
            b = pll_step(b, (r + c) % TURN, KP, KI)
            assert b.theta == (a.theta + c) % TURN and (b.integ, b.omega) == (a.integ, a.omega), f"seed {seed}"
            assert 0 <= a.theta < TURN
            r = (r + v + rng.randint(-1000, 1000)) % TURN


def test_pll_step_random_against_float():
    """One step from random states against a float re-derivation (math.remainder for the wrap, float
    products); the two floors of omega make it lie in (ref - 2, ref]."""
    seed = 314159
    rng = random.Random(seed)
    for _ in range(10_000):
        theta = rng.randrange(TURN)
        th_hat = rng.randrange(TURN)
        integ = rng.randint(-(1 << 45), 1 << 45)
        kp = rng.randrange(1 << rng.randint(1, 31))
        ki = rng.randrange(1 << rng.randint(1, 31))
        s = pll_step(PllState(theta, integ, 0), th_hat, kp, ki)
        e = int(math.remainder(th_hat - theta, TURN))  # in [-2^31, 2^31], exact in float
        if abs(e) == 2**31:
            e = -(2**31)
        integ_ref = integ + ki * e
        assert s.integ == integ_ref, f"seed {seed}"  # |integ| < 2^63: exact, no saturation
        om_ref = kp * e / 2**16 + integ_ref / 2**24
        if abs(om_ref) < 2**31 - 4:
            assert om_ref - 2 - 1e-3 < s.omega <= om_ref + 1e-3, f"seed {seed}: {s.omega} vs {om_ref}"
        else:
            assert abs(s.omega) >= 2**31 - 6 and (s.omega > 0) == (om_ref > 0), f"seed {seed}"
        assert s.theta == (theta + s.omega) % TURN, f"seed {seed}"
