"""Tests of the CORDIC model (golden/fpga/cordic.py, docs/spec.md section 3.3).

Expected values come from the spec's formulas evaluated by hand or with math (never from the model):
the arctangent table, the gain, sin/cos at the quadrant points in Q1.15, an accuracy bound derived from
the iteration count, and the demodulation weight of Benevieri et al. 2023, eq. (19).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from golden.fpga import cordic  # noqa: E402
from golden.fpga.cordic import (  # noqa: E402
    atan_table,
    cordic_gain_inverse,
    cordic_sincos,
    cw_angle_step,
    demod_weight,
    sincos_q15,
    to_q15,
    x0,
)

TURN = 1 << 32
DEG = {0: 0, 45: 1 << 29, 90: 1 << 30, 180: 1 << 31, 270: 3 << 30}  # exact binary angles


# ---- constants --------------------------------------------------------------------------------------
def test_atan_table_first_and_last_entries():
    t = atan_table(32)
    assert len(t) == 32
    assert t[0] == 536870912 == 1 << 29                      # atan(1) = pi/4 = 1/8 turn, exactly
    # atan(0.5) * 2^32 / 2pi = 316933405.617 -> 316933406; atan(0.25) -> 167458907.371 -> 167458907
    assert t[1] == round(math.atan(0.5) * TURN / (2 * math.pi)) == 316933406
    assert t[2] == 167458907
    assert t[3] == 85004756                                   # 85004756.117
    # tail: atan(2^-i) ~ 2^-i, so ATAN[i] ~ 2^(32-i) / 2pi: 2/pi = 0.64 -> 1, 1/pi = 0.32 -> 0
    assert t[29] == 1 and t[30] == 1 and t[31] == 0
    assert atan_table(5) == t[:5]


def test_gain_and_x0():
    assert cordic_gain_inverse(1) == pytest.approx(1 / math.sqrt(2), rel=1e-15)
    assert cordic_gain_inverse(2) == pytest.approx(1 / math.sqrt(2 * 1.25), rel=1e-15)
    assert cordic_gain_inverse(32) == pytest.approx(0.6072529350088812561694, rel=1e-14)
    # K_32 * 2^30 = 652032874.4 -> 652032874; K_1 * 2^6 = 45.25 -> 45 (WIDTH = 8)
    assert x0(32, 32) == 652032874
    assert x0(32, 16) == 652032874            # K_16 differs from K_32 by 2^-33 relative only
    assert x0(8, 1) == 45


# ---- sin / cos --------------------------------------------------------------------------------------
# Q1.15 of the exact values: +1 -> 32768 saturates to 32767, -1 -> -32768, sin(45 deg) * 2^15 =
# 23170.475 -> 23170 (nearest). With 32 iterations the raw results are within a few Q2.30 LSB of the
# exact values, far from any rounding boundary, so these are the only possible outputs.
Q15_32 = {0: (0, 32767), 45: (23170, 23170), 90: (32767, 0), 180: (0, -32768), 270: (-32768, 0)}


@pytest.mark.parametrize("deg", sorted(Q15_32))
def test_sincos_q15_quadrant_points_32_iterations(deg):
    assert sincos_q15(DEG[deg], 32, 32) == Q15_32[deg]
    assert sincos_q15(np.array([DEG[deg]], dtype=np.int64), 32, 32)[0].tolist() == [Q15_32[deg][0]]


# With the firmware's 16 iterations the residual angle is up to ATAN[15] = 2^-15 rad = 1 LSB of
# Q1.15, so the zeros come out as +-1 and sin(45 deg) as 23171 (23170.475 + 0.53): all within the
# 1.5 LSB bound of test_accuracy_vs_math. Pinned as the bit-exact firmware values.
Q15_16 = {0: (-1, 32767), 45: (23171, 23170), 90: (32767, 1), 180: (1, -32768), 270: (-32768, -1)}


@pytest.mark.parametrize("deg", sorted(Q15_16))
def test_sincos_q15_quadrant_points_firmware(deg):
    assert sincos_q15(DEG[deg]) == Q15_16[deg]
    s, c = Q15_16[deg]
    assert abs(s - math.sin(math.radians(deg)) * 32768) < 1.5
    assert abs(c - math.cos(math.radians(deg)) * 32768) < 1.5


def test_raw_outputs_near_unit_circle():
    # Q2.30: 1.0 = 2^30. 32 iterations: error of a few LSB of 2^-30.
    s, c = cordic_sincos(0)
    assert abs(s) <= 16 and abs(c - (1 << 30)) <= 16
    s, c = cordic_sincos(1 << 31)           # folded: z = 0, outputs negated
    assert abs(s) <= 16 and abs(c + (1 << 30)) <= 16
    s, c = cordic_sincos(0, width=16, iterations=16)   # Q2.14: 1.0 = 16384
    assert abs(s) <= 16 and abs(c - 16384) <= 16


def _bound_q15(width: int, iterations: int) -> float:
    """Error bound of the Q1.15 output against sin/cos * 2^15 (clipped to s16), in LSB.

    0.5 (final rounding) + residual angle after N iterations, |z_N| <= atan(2^-(N-1)) rad, plus
    N * 2 pi / 2^32 for the rounding of the table entries (|d sin| <= |d angle|) + truncation of the
    N shifts, < 1 LSB of Q2.(W-2) per iteration and coordinate, amplified by at most 1.65 (the CORDIC
    gain) on both coordinates: (4N + 2) LSB of Q2.(W-2) = (4N + 2) * 2^(17-W) LSB of Q1.15.
    """
    angle = math.atan(2.0 ** -(iterations - 1)) + iterations * 2 * math.pi / TURN
    return 0.5 + 32768 * angle + (4 * iterations + 2) * 2.0 ** (17 - width)


@pytest.mark.parametrize("width,iterations", [(32, 32), (32, 16), (24, 24), (20, 16), (32, 8)])
def test_accuracy_vs_math(width, iterations):
    rng = np.random.default_rng(20230)
    a = rng.integers(0, TURN, size=100_000, dtype=np.int64)
    a[:8] = [0, (1 << 30) - 1, 1 << 30, (1 << 31) - 1, 1 << 31, (3 << 30) - 1, 3 << 30, TURN - 1]
    theta = a * (2 * np.pi / TURN)
    s, c = sincos_q15(a, width, iterations)
    assert s.dtype == np.int64 and c.dtype == np.int64
    ref_s = np.clip(np.sin(theta) * 32768, -32768, 32767)
    ref_c = np.clip(np.cos(theta) * 32768, -32768, 32767)
    err = max(float(np.abs(s - ref_s).max()), float(np.abs(c - ref_c).max()))
    assert err < _bound_q15(width, iterations)
    if (width, iterations) == (32, 32):
        # 32 iterations are round-to-nearest Q1.15 up to a few 2^-30: |err| <= 0.5 + 0.001
        assert err < 0.501
    if (width, iterations) == (32, 16):
        assert err < 1.51   # the firmware's sin/cos: 0.5 rounding + 1 LSB residual angle


def test_vectorised_equals_scalar():
    rng = np.random.default_rng(7)
    a = rng.integers(0, TURN, size=300, dtype=np.int64)
    a[:8] = [0, (1 << 30) - 1, 1 << 30, (1 << 31) - 1, 1 << 31, (3 << 30) - 1, 3 << 30, TURN - 1]
    for width, iterations in [(32, 32), (32, 16), (8, 8), (17, 5)]:
        vs, vc = cordic_sincos(a, width, iterations)
        for k, ak in enumerate(a.tolist()):
            ss, sc = cordic_sincos(ak, width, iterations)
            assert type(ss) is int and type(sc) is int
            assert (ss, sc) == (int(vs[k]), int(vc[k]))
    # other integer dtypes and shapes are accepted as int64
    vs, vc = cordic_sincos(a[:12].astype(np.uint32).reshape(3, 4))
    assert vs.shape == (3, 4) and vs.dtype == np.int64
    assert vs.ravel().tolist() == cordic_sincos(a[:12])[0].tolist()


def test_parameter_validation():
    with pytest.raises(ValueError, match="width"):
        cordic_sincos(0, width=7, iterations=7)
    with pytest.raises(ValueError, match="width"):
        cordic_sincos(0, width=33)
    with pytest.raises(ValueError, match="iterations"):
        cordic_sincos(0, iterations=0)
    with pytest.raises(ValueError, match="iterations"):
        cordic_sincos(0, width=16, iterations=17)
    with pytest.raises(ValueError, match="u32"):
        cordic_sincos(-1)
    with pytest.raises(ValueError, match="u32"):
        cordic_sincos(TURN)
    with pytest.raises(ValueError, match=r"angle\[2\]"):
        cordic_sincos(np.array([0, 5, TURN], dtype=np.int64))
    with pytest.raises(TypeError):
        cordic_sincos(np.array([0.0, 1.0]))
    with pytest.raises(TypeError):
        cordic_sincos(1.5)
    with pytest.raises(ValueError, match="iterations"):
        atan_table(0)
    with pytest.raises(ValueError, match="iterations"):
        cordic_gain_inverse(33)
    with pytest.raises(ValueError, match="iterations"):
        x0(12, 13)
    with pytest.raises(ValueError, match="WIDTH >= 17"):
        to_q15(0, 16)
    with pytest.raises(ValueError, match="WIDTH >= 17"):
        sincos_q15(0, width=16, iterations=16)
    with pytest.raises(ValueError, match="s20"):
        to_q15(1 << 19, 20)


def test_to_q15_rounding():
    # WIDTH = 32: round_shr by 15, half up, then s16 saturation
    assert to_q15(1 << 30, 32) == 32767                 # +1.0 saturates
    assert to_q15(-(1 << 30), 32) == -32768
    assert to_q15(16384, 32) == 1                       # +0.5 LSB -> up
    assert to_q15(-16384, 32) == 0                      # -0.5 LSB -> up (half up)
    assert to_q15(-16385, 32) == -1
    assert to_q15(12345, 17) == 12345                   # WIDTH = 17: no shift
    assert to_q15(np.array([16383, 16384], dtype=np.int64), 32).tolist() == [0, 1]


# ---- demodulation weight ----------------------------------------------------------------------------
def test_cw_angle_step_hand_values():
    assert cw_angle_step(10000) == 107374        # 2^30 / 10000 = 107374.18
    assert cw_angle_step(4) == 1 << 28           # exact
    assert cw_angle_step(6) == 178956971         # 178956970.67
    assert cw_angle_step(65534) == 16385         # 16384.50002: just above the tie
    assert cw_angle_step(65532) == 16385         # 16385.00006
    for h in (3, 2, 0, 65535, 65536, -4):
        with pytest.raises(ValueError, match="half"):
            cw_angle_step(h)


H = 10000
STEP = 107374


def test_demod_weight_hand_points():
    # c = 0: a = H*step = 2^30 - 1824 (a quarter turn less 2.7 urad): sin = 1 - 4e-12 -> 32768 -> 32767
    assert demod_weight(0, H, STEP) == 32767
    # c = H/2: a = 0 exactly, sin = 0
    assert demod_weight(H // 2, H, STEP) == 0
    # c = H: a = -(2^30 - 1824): sin = -(1 - 4e-12); raw y is within a few LSB of -2^30, and
    # round_shr(-2^30 + e, 15) = -32768 for -16384 <= e < 16384: -32768 exactly, no saturation.
    # (The +1 side saturates to 32767, hence the 1-LSB asymmetry between the bottom and the top.)
    assert demod_weight(H, H, STEP) == -32768
    # quarter points: cw = -1/2 -> sin(pi/4) = 23170.475 -> 23170; cw = +1/2 -> -23170
    assert demod_weight(H // 4, H, STEP) == 23170
    assert demod_weight(3 * H // 4, H, STEP) == -23170


def test_demod_weight_smallest_carrier():
    # H = 4, step = 2^28: a = (4 - 2c) * 2^28 = 90, 45, 0, -45, -90 deg exactly
    assert [demod_weight(c, 4, 1 << 28) for c in range(5)] == [32767, 23170, 0, -23170, -32768]


def test_demod_weight_symmetry_and_accuracy():
    c = np.arange(H + 1, dtype=np.int64)
    w = demod_weight(c, H, STEP)
    assert w.dtype == np.int64
    # w(c) = -w(H - c) within 1 LSB (the angle is exactly odd in c, the CORDIC nearly)
    assert np.abs(w + w[::-1]).max() <= 1
    # against sin(-cw pi/2), cw = 2c/H - 1 (eq. (15)): 0.5 rounding + angle error of the rounded step
    # |H - 2c| * |step - 2^30/H| <= H/2 binary units + 32-iteration CORDIC error (< 0.001 LSB)
    ref = np.clip(np.sin(-(2 * c / H - 1) * np.pi / 2) * 32768, -32768, 32767)
    bound = 0.5 + 32768 * 2 * math.pi * (H / 2) / TURN + 0.001
    assert np.abs(w - ref).max() <= bound
    # monotone decreasing from the bottom (c = 0) to the top (c = H)
    assert np.all(np.diff(w) <= 0)
    # scalar == vector
    for k in (0, 1, 2499, 5000, 7777, 9999, 10000):
        assert demod_weight(k, H, STEP) == int(w[k])


def test_demod_weight_validation():
    with pytest.raises(ValueError, match="counter"):
        demod_weight(-1, H, STEP)
    with pytest.raises(ValueError, match=r"counter\[1\]"):
        demod_weight(np.array([0, H + 1]), H, STEP)
    with pytest.raises(ValueError, match="even"):
        demod_weight(0, 9999, STEP)
    with pytest.raises(ValueError, match="step"):
        demod_weight(0, H, -1)
    with pytest.raises(ValueError, match="step"):
        demod_weight(0, H, TURN)
    with pytest.raises(ValueError, match="WIDTH >= 17"):
        demod_weight(0, H, STEP, width=16, iterations=16)


def test_module_constants():
    assert cordic.ANGLE_BITS == 32
    assert (cordic.HALF_MIN, cordic.HALF_MAX) == (4, 65534)
