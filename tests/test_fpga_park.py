"""Tests of the Clarke and Park transforms (golden/fpga/park.py, docs/spec.md section 3.2).

Expected values are the spec's formulas worked by hand: round_shr(x, 15) = floor((x + 16384) / 32768).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from golden.fpga.cordic import sincos_q15  # noqa: E402
from golden.fpga.park import INV_SQRT3_Q15, clarke, park  # noqa: E402


def test_inv_sqrt3_constant():
    assert INV_SQRT3_Q15 == round(2 ** 15 / math.sqrt(3)) == 18919   # 18918.58


@pytest.mark.parametrize("i_a,i_b,i_beta", [
    (1000, 0, 577),         # 18919000 / 32768 = 577.36
    (-1000, 0, -577),       # -577.36
    (0, 1000, 1155),        # 2000 * 18919 / 32768 = 1154.72
    (1000, -500, 0),        # i_a + 2 i_b = 0 (i_c = -500)
    (16384, 0, 9460),       # 16384 * 18919 / 2^15 = 9459.5 exactly: half up -> 9460
    (-16384, 0, -9459),     # -9459.5 -> -9459 (half up)
    (0, 8660, 10000),       # theta = 90 deg, I = 10000: 17320 * 18919 / 32768 = 9999.9
    (32767, 32767, 32767),  # 98301 * 18919 / 32768 = 56755 -> saturates
    (-32768, -32768, -32768),
])
def test_clarke_hand_cases(i_a, i_b, i_beta):
    assert clarke(i_a, i_b) == (i_a, i_beta)


def test_clarke_array_and_broadcast():
    al, be = clarke(np.array([1000, -1000, 16384]), np.array([0, 0, 0]))
    assert al.tolist() == [1000, -1000, 16384] and be.tolist() == [577, -577, 9460]
    al, be = clarke(1000, np.array([0, -500]))
    assert al.tolist() == [1000, 1000] and be.tolist() == [577, 0]
    assert al.dtype == np.int64 and be.dtype == np.int64


@pytest.mark.parametrize("i_al,i_d", [
    # COS = 32767: round_shr(i * 32767, 15) = i + floor((16384 - i) / 32768)
    (1000, 1000), (20000, 19999), (-20000, -19999), (16384, 16384), (16385, 16384),
    (-16383, -16383), (-16384, -16383), (0, 0), (32767, 32766), (-32768, -32767),
])
def test_park_theta_zero(i_al, i_d):
    # theta = 0: SIN = 0, COS = 32767 (Q1.15 of cos 0, saturated): i_d ~ i_alpha, i_q ~ i_beta
    assert park(i_al, 0, 0, 32767) == (i_d, 0)
    assert park(0, i_al, 0, 32767) == (0, i_d)


def test_park_theta_90_and_180():
    # SIN = 32767, COS = 0: i_d = round_shr(i_beta*32767), i_q = round_shr(-i_alpha*32767)
    assert park(1000, 20000, 32767, 0) == (19999, -1000)
    assert park(20000, 0, 32767, 0) == (0, -19999)      # -20000 + floor(36384/32768)
    # COS = -32768 (exactly -1): i_d = -i_alpha exactly, i_q = -i_beta; -(-32768) saturates
    assert park(1234, -567, 0, -32768) == (-1234, 567)
    assert park(-32768, -32768, 0, -32768) == (32767, 32767)


def test_park_45_degrees():
    # SIN = COS = 23170: i_d = (1000 + 2000) * 23170 = 69510000 -> 2121.26 + 0.5 -> 2121
    #                     i_q = (2000 - 1000) * 23170 = 23170000 -> 707.09 + 0.5 -> 707
    assert park(1000, 2000, 23170, 23170) == (2121, 707)


def test_park_saturation_at_extremes():
    # i_d = 2 * 2^30 / 2^15 = 65536 -> 32767; i_q = 2^30 - 2^30 = 0
    assert park(-32768, -32768, -32768, -32768) == (32767, 0)
    # i_d = 2 * 32767^2 -> 65532 -> 32767
    assert park(32767, 32767, 32767, 32767) == (32767, 0)
    # i_d = 32767^2 - 32768*32767 = -32767 -> -1; i_q = -32767 * 65535 -> -65533 -> -32768
    assert park(32767, -32768, 32767, 32767) == (-1, -32768)
    d, q = park(np.array([-32768, 32767]), np.array([-32768, -32768]), np.array([-32768, 32767]),
                np.array([-32768, 32767]))
    assert d.tolist() == [32767, -1] and q.tolist() == [0, -32768]


def test_balanced_three_phase_gives_constant_dq():
    # i_a = I cos(theta), i_b = I cos(theta - 2pi/3) rounded to s16, SIN/COS of theta from the
    # firmware CORDIC: in the rotor frame i_d = I, i_q = 0.
    current = 10000
    a = np.arange(4096, dtype=np.int64) * ((1 << 32) // 4096)     # one turn, binary angles
    theta = a * (2 * np.pi / 2 ** 32)
    i_a = np.round(current * np.cos(theta)).astype(np.int64)
    i_b = np.round(current * np.cos(theta - 2 * np.pi / 3)).astype(np.int64)
    i_al, i_be = clarke(i_a, i_b)
    s, c = sincos_q15(a)
    i_d, i_q = park(i_al, i_be, s, c)
    # Against the float transforms of the same integer inputs: 0.5 (Park rounding) + the i_beta error
    # (0.5 rounding + |i_a + 2 i_b| * |18919/2^15 - 1/sqrt(3)|, |i_a + 2 i_b| <= sqrt(3) I + 1.5).
    beta_f = (i_a + 2 * i_b) / math.sqrt(3)
    err_beta = 0.5 + (math.sqrt(3) * current + 1.5) * abs(18919 / 2 ** 15 - 1 / math.sqrt(3))
    assert np.abs(i_be - beta_f).max() <= err_beta
    ref_d = (i_a * c + beta_f * s) / 32768
    ref_q = (beta_f * c - i_a * s) / 32768
    assert np.abs(i_d - ref_d).max() <= 0.5 + err_beta
    assert np.abs(i_q - ref_q).max() <= 0.5 + err_beta
    # Constant dq: measured within 1 LSB of (I, 0) over the whole turn for this data set (the
    # worst-case analysis with the 1.5-LSB input rounding and the 16-iteration SIN/COS gives < 3 LSB).
    assert np.abs(i_d - current).max() <= 1
    assert np.abs(i_q).max() <= 1


def test_validation():
    with pytest.raises(ValueError, match="i_a"):
        clarke(32768, 0)
    with pytest.raises(ValueError, match=r"i_b\[1\]"):
        clarke(0, np.array([0, -32769]))
    with pytest.raises(ValueError, match="cos_q15"):
        park(0, 0, 0, 32768)
    with pytest.raises(ValueError, match="sin_q15"):
        park(0, 0, -32769, 0)
    with pytest.raises(TypeError):
        park(0.5, 0, 0, 32767)
    with pytest.raises(TypeError):
        clarke(np.array([1.0]), 0)
