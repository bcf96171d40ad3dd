"""Tests of the first-order speed filter (golden/firmware/lowpass.py; docs/spec.md 5.2).

The step response is compared with the closed form X (1 - (1 - a/2^16)^n). The floor of each step
makes F lag by delta in (-1, 0] Q16 LSB per step, so |F/2^16 - closed form| < 1/a output LSB.
"""

from __future__ import annotations

import random
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from golden.firmware.lowpass import lowpass_coef, lowpass_out, lowpass_step  # noqa: E402

I64_MIN, I64_MAX = -(2**63), 2**63 - 1


def test_lowpass_coef_by_hand():
    # 2 pi 30 / 5000 = 0.03769911; e^-x = 1 - x + x^2/2 - x^3/6 + x^4/24 = 0.96300265;
    # (1 - 0.96300265) * 65536 = 2424.66 -> 2425
    assert lowpass_coef(30.0, 5000.0) == 2425
    assert lowpass_coef(0.0, 5000.0) == 0
    # f_c -> infinity: 1 - e^-inf = 1 -> 65536 (pass-through)
    assert lowpass_coef(1e9, 5000.0) == 65536
    with pytest.raises(ValueError):
        lowpass_coef(30.0, 0.0)
    with pytest.raises(ValueError):
        lowpass_coef(-1.0, 5000.0)


def test_lowpass_hand_steps():
    # F = 0, x = 1000, a = 2425: (1000 << 16) * 2425 >> 16 = 2425000; out = floor(37.003) = 37
    F = lowpass_step(0, 1000, 2425)
    assert F == 2425000 and lowpass_out(F) == 37
    # (65536000 - 2425000) * 2425 = 153044175000; / 65536 = 2335268.78 -> 2335268; F = 4760268 -> 72
    F = lowpass_step(F, 1000, 2425)
    assert F == 4760268 and lowpass_out(F) == 72
    # negative, floored: F = 5, x = -3, a = 101: d = -196613; d a = -19857913; / 65536 = -303.008 -> -304
    F = lowpass_step(5, -3, 101)
    assert F == -299 and lowpass_out(F) == -1
    # a = 0 holds the state
    assert lowpass_step(123456789, -5000, 0) == 123456789


@pytest.mark.parametrize("a", [1, 100, 2425, 30000, 65535, 65536])
@pytest.mark.parametrize("X", [1000, -1000, 123456, 27342611, 2**31 - 1, -(2**31)])
def test_lowpass_step_response_closed_form(a, X):
    alpha = a / 65536
    F = 0
    n_steps = 3000 if a >= 100 else 300
    for n in range(1, n_steps + 1):
        F = lowpass_step(F, X, a)
        ref = X * (1.0 - (1.0 - alpha) ** n)
        tol = 1.0 / a + abs(X) * 1e-12  # float rounding of the reference
        assert -tol <= F / 65536 - ref <= 1e-9 + abs(X) * 1e-12, (n, F / 65536, ref)
        out = lowpass_out(F)
        assert ref - 1 - tol <= out <= ref + abs(X) * 1e-12, (n, out, ref)
    if a >= 2425:
        assert lowpass_out(F) in (X - 1, X)  # settled (within the flooring)


def test_lowpass_passthrough_random():
    seed = 4242
    rng = random.Random(seed)
    for _ in range(10_000):
        F = rng.randint(-(2**47), 2**47 - 1)
        x = rng.randint(-(2**31), 2**31 - 1)
        F2 = lowpass_step(F, x, 65536)
        assert F2 == x * 65536 and lowpass_out(F2) == x, f"seed {seed}"


def c_form(F: int, x: int, a: int) -> int:
    """The split product the C must use (lowpass.py docstring), with int64 range checks on every value."""
    d = x * 65536 - F
    q = d >> 16
    r = d & 0xFFFF
    for v in (d, q, r, q * a, r * a, q * a + ((r * a) >> 16), F + q * a + ((r * a) >> 16)):
        assert I64_MIN <= v <= I64_MAX
    return F + q * a + ((r * a) >> 16)


def test_lowpass_random_against_float_and_c_form():
    """10^4 random (F, x, a): float reference within one Q16 LSB, the new F between F and x << 16, and
    the overflow-free C form equal; the extremes show that the direct int64 product would overflow."""
    seed = 271828
    rng = random.Random(seed)
    overflow_seen = False
    for i in range(10_000):
        if i < 4:  # the extremes
            x = (2**31 - 1, -(2**31))[i % 2]
            F = -x * 65536 if i < 2 else (-(2**31) if x > 0 else 2**31 - 1) * 65536
            a = 65536
        else:
            x = rng.randint(-(2**31), 2**31 - 1)
            F = rng.randint(-(2**31), 2**31 - 1) * 65536 + rng.randrange(65536)
            a = rng.choice([65536, rng.randint(0, 65536), rng.randint(0, 4096)])
        F2 = lowpass_step(F, x, a)
        ref = F + (x * 65536.0 - F) * (a / 65536.0)
        assert ref - 1 - abs(ref) * 1e-15 <= F2 <= ref + abs(ref) * 1e-15 + 1e-9, f"seed {seed}"
        lo, hi = sorted((F, x * 65536))
        assert lo <= F2 <= hi, f"seed {seed}"
        assert c_form(F, x, a) == F2, f"seed {seed}: F {F} x {x} a {a}"
        overflow_seen |= not I64_MIN <= (x * 65536 - F) * a <= I64_MAX
    assert overflow_seen
