"""Tests of the PI controller (golden/firmware/pi.py; docs/spec.md 5.2).

Sequences are hand-computed (shown in the comments). The random check compares with an exact rational
re-derivation (fractions.Fraction, no floors): the two floors of the integer PI make u lie in
[clamp(u_real - 2), clamp(u_real)].
"""

from __future__ import annotations

import random
import sys
from fractions import Fraction
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from golden.firmware.pi import PiParams, pi_gains, pi_step  # noqa: E402

S32_MAX = 2**31 - 1


def run(p: PiParams, integ: int, seq):
    """Apply (ref, meas) pairs; return [(u, integ_new), ...]."""
    out = []
    for ref, meas in seq:
        u, integ = pi_step(integ, ref, meas, p)
        out.append((u, integ))
    return out


def test_pi_three_steps_by_hand():
    p = PiParams(kp=3, sp=1, ki=5, si=2, limit=100)  # integrator limit 400
    got = run(p, 0, [(10, 0), (10, 3), (0, 5), (-20, 0), (0, 1)])
    assert got == [
        (27, 50),  # e 10: prop 30>>1 = 15; cand 50; 15 + (50>>2 = 12) = 27
        (31, 85),  # e 7: prop 21>>1 = 10; cand 85; 10 + 21 = 31
        (7, 60),  # e -5: prop floor(-15/2) = -8; cand 60; -8 + 15 = 7
        (-40, -40),  # e -20: prop -30; cand -40; -30 + (-40>>2 = -10) = -40
        (-14, -45),  # e -1: prop floor(-1.5) = -2; cand -45; -2 + floor(-11.25) = -14
    ]


def test_pi_positive_saturation_anti_windup():
    p = PiParams(kp=1, sp=0, ki=1, si=0, limit=10)  # integrator limit 10
    got = run(p, 0, [(3, 0), (3, 0), (8, 0), (8, 0), (20, 0), (0, 2)])
    assert got == [
        (6, 3),  # e 3: 3 + 3
        (9, 6),  # e 3: 3 + 6
        (10, 6),  # e 8: cand 14 -> 10, unclamped 18 > 10 and e > 0: frozen at 6; u = clamp(8 + 6) = 10
        (10, 6),  # same
        (10, 6),  # e 20: unclamped 30: frozen
        (2, 4),  # e -2 reverses: cand 4 integrates; u = -2 + 4 = 2 at once
    ]
    # a merely clamped integrator (no conditional integration) would sit at 10 and give -2 + 8 = 6 here
    # a long push into the limit keeps the integrator frozen
    u, integ = 0, 6
    for _ in range(100):
        u, integ = pi_step(integ, 50, 0, p)
        assert (u, integ) == (10, 6)


def test_pi_negative_saturation_anti_windup():
    p = PiParams(kp=1, sp=0, ki=1, si=0, limit=10)
    got = run(p, 0, [(-12, 0), (0, 3), (0, 3), (0, 3), (0, 15), (1, 0)])
    assert got == [
        (-10, 0),  # e -12: cand -12 -> -10, unclamped -22 < -10 and e < 0: frozen at 0; u = clamp(-12) = -10
        (-6, -3),  # e -3: -3 - 3
        (-9, -6),  # e -3: -3 - 6
        (-9, -6),  # e -3: cand -9, unclamped -12 < -10: frozen; u = -3 - 6 = -9 (inside the limit)
        (-10, -6),  # e -15: frozen; u = clamp(-21) = -10
        (-4, -5),  # e +1 reverses: cand -5; u = 1 - 5 = -4
    ]


def test_pi_saturation_with_shifts():
    p = PiParams(kp=5, sp=2, ki=7, si=4, limit=20)  # integrator limit 320
    got = run(p, 300, [(3, 0), (0, 1)])
    assert got == [
        (20, 300),  # e 3: prop 15>>2 = 3; cand 321 -> 320; unclamped 3 + 20 = 23 > 20: frozen 300;
        #              u = clamp(3 + (300>>4 = 18)) = 20
        (16, 293),  # e -1: prop floor(-5/4) = -2; cand 293; -2 + floor(18.31) = 16
    ]


def test_pi_limit_clamp_and_error_saturation():
    big = PiParams(kp=S32_MAX, sp=0, ki=S32_MAX, si=31, limit=S32_MAX)
    # e = sat(2^31 - 1 + 2^31, 32) = 2^31 - 1; prop = (2^31-1)^2 = 4611686014132420609;
    # cand = the same (< limit << 31 = 4611686016279904256); frozen; u = limit
    assert pi_step(0, S32_MAX, -(2**31), big) == (S32_MAX, 0)
    # e = -2^31: prop = -(2^31-1) 2^31 = -(limit << 31) exactly; frozen; u = -limit (not -2^31)
    assert pi_step(0, -(2**31), S32_MAX, big) == (-S32_MAX, 0)
    p = PiParams(kp=1000, sp=0, ki=0, si=0, limit=500)
    assert pi_step(0, 7, 0, p) == (500, 0)
    assert pi_step(0, -7, 0, p) == (-500, 0)
    assert pi_step(0, 0, 0, p) == (0, 0)


@pytest.mark.parametrize(
    "kw",
    [
        dict(kp=-1),
        dict(ki=-1),
        dict(kp=2**31),
        dict(ki=2**31),
        dict(sp=-1),
        dict(sp=32),
        dict(si=-1),
        dict(si=32),
        dict(limit=0),
        dict(limit=-5),
        dict(limit=2**31),
        dict(kp=1.0),
        dict(limit=10.5),
        dict(si=True),
        dict(sp="3"),
    ],
)
def test_pi_params_validation(kw):
    args = dict(kp=1, sp=0, ki=1, si=0, limit=10)
    args.update(kw)
    with pytest.raises(ValueError):
        PiParams(**args)


def test_pi_params_bounds_accepted():
    PiParams(kp=0, sp=0, ki=0, si=0, limit=1)
    PiParams(kp=S32_MAX, sp=31, ki=S32_MAX, si=31, limit=S32_MAX)


def test_pi_gains_by_hand():
    # current loop: out_per_in = (12.5 A / 2^15) / (560 V / 2^15) = 12.5/560 = 0.0223214;
    # kp_phys 10 V/A -> 0.223214 * 65536 = 14628.57 -> 14629
    # ki_phys 1000 V/(A s) at 5 kHz -> 0.0223214 * 1000 / 5000 * 65536 = 292.57 -> 293
    assert pi_gains(10.0, 1000.0, 12.5 / 560.0, 5000.0) == (14629, 293)
    # other shifts: 0.223214 * 2^8 = 57.14 -> 57; 0.00446429 * 2^20 = 4681.14 -> 4681
    assert pi_gains(10.0, 1000.0, 12.5 / 560.0, 5000.0, sp=8, si=20) == (57, 4681)
    with pytest.raises(ValueError):
        pi_gains(-1.0, 1000.0, 1.0, 5000.0)
    with pytest.raises(ValueError):
        pi_gains(1.0, 1000.0, 1.0, 0.0)
    with pytest.raises(ValueError):
        pi_gains(1e6, 0.0, 1.0, 5000.0)  # 1e6 * 2^16 > 2^31 - 1


def _clamp(x, lo, hi):
    return lo if x < lo else hi if x > hi else x


def test_pi_random_against_exact_rational():
    seed = 1618033
    rng = random.Random(seed)
    frozen_seen = integrated_seen = saturated_seen = 0
    for _ in range(10_000):
        limit = rng.choice([rng.randint(1, 100), rng.randint(1, 32767), rng.randint(1, S32_MAX)])
        sp, si = rng.randint(0, 31), rng.randint(0, 31)
        kp = rng.randrange(1 << rng.randint(1, 31))
        ki = rng.randrange(1 << rng.randint(1, 31))
        p = PiParams(kp=kp, sp=sp, ki=ki, si=si, limit=limit)
        lim_i = limit * 2**si
        integ = rng.randint(-lim_i, lim_i)
        ref = rng.randint(-(2**31), S32_MAX)
        meas = rng.choice([rng.randint(-(2**31), S32_MAX), ref + rng.randint(-1000, 1000)])
        meas = _clamp(meas, -(2**31), S32_MAX)
        u, integ_new = pi_step(integ, ref, meas, p)
        msg = f"seed {seed}: {p} integ {integ} ref {ref} meas {meas} -> {u} {integ_new}"

        e = _clamp(ref - meas, -(2**31), S32_MAX)
        cand = Fraction(_clamp(integ + ki * e, -lim_i, lim_i))
        prop_r = Fraction(kp * e, 2**sp)
        assert abs(u) <= limit and abs(integ_new) <= lim_i, msg
        assert integ_new in (integ, cand), msg
        u_real = prop_r + Fraction(integ_new, 2**si)
        assert _clamp(u_real - 2, -limit, limit) <= u <= _clamp(u_real, -limit, limit), msg
        assert u > u_real - 2 or u == limit, msg
        unclamped_real = prop_r + cand / 2**si  # the integer value lies in (this - 2, this]
        if integ_new != cand:  # frozen: the unclamped output was beyond the limit in e's direction
            frozen_seen += 1
            assert (e > 0 and unclamped_real > limit) or (e < 0 and unclamped_real - 2 < -limit), msg
        elif cand != integ:
            integrated_seen += 1
            assert not (e > 0 and unclamped_real - 2 >= limit) and not (e < 0 and unclamped_real < -limit), msg
        saturated_seen += abs(u) == limit
    assert frozen_seen > 100 and integrated_seen > 100 and saturated_seen > 100, (
        frozen_seen, integrated_seen, saturated_seen)
