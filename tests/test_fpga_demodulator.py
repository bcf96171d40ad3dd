"""Tests of the demodulator and window sums (golden/fpga/demodulator.py, docs/spec.md section 3.4).

GAMMA = sat(shr(sum i_q*w, 15), 32) (Benevieri et al. 2023, eq. (19)), GAMMA_D likewise with i_d, the
plain sums saturated to s32, N_SAMPLES saturated at 65535. Expected values are worked out by hand.
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from golden.fpga.cordic import cw_angle_step, demod_weight  # noqa: E402
from golden.fpga.demodulator import WindowResult, demodulate  # noqa: E402

S32_MAX, S32_MIN = 2 ** 31 - 1, -(2 ** 31)


def _arr(*v):
    return np.array(v, dtype=np.int64)


def test_four_sample_window():
    i_d = _arr(10, 20, -30, 40)
    i_q = _arr(100, -200, 300, -400)
    w = _arr(32767, -32768, 16384, 0)
    r = demodulate(i_d, i_q, w)
    # acc_q = 3276700 + 6553600 + 4915200 + 0 = 14745500 = 450*32768 - 100 -> floor: 449
    # acc_d = 327670 - 655360 - 491520 + 0 = -819210 = -25*32768 - 10 -> floor: -26
    assert r == WindowResult(gamma=449, gamma_d=-26, sum_id=40, sum_iq=-200, wsum=16383, n_samples=4)
    assert all(type(v) is int for v in dataclasses.astuple(r))


def test_ds_two_sample_window():
    # DS mode: the window [H/2, P + H/2) holds the top (c = H, w = -1) then the bottom (c = 0, w = +1)
    half = 10000
    step = cw_angle_step(half)
    w_top, w_bottom = demod_weight(half, half, step), demod_weight(0, half, step)
    assert (w_top, w_bottom) == (-32768, 32767)
    iq_top, iq_bottom = -700, 500
    r = demodulate(_arr(300, 300), _arr(iq_top, iq_bottom), _arr(w_top, w_bottom))
    # (500*32767 + (-700)*(-32768)) >> 15 = (16383500 + 22937600) >> 15 = 39321100 >> 15 = 1199
    assert r.gamma == (iq_bottom * 32767 + iq_top * (-32768)) >> 15 == 1199
    # acc_d = 300 * (-32768 + 32767) = -300 -> floor(-300 / 32768) = -1
    assert r.gamma_d == -1
    assert (r.sum_id, r.sum_iq, r.wsum, r.n_samples) == (600, -200, -1, 2)


@pytest.mark.parametrize("i_q,w,gamma", [
    (-1, 1, -1),            # -1 / 2^15 floors to -1, not 0
    (1, 1, 0),
    (-1, 32767, -1),        # -32767 -> -1
    (1, 32767, 0),          # 32767 -> 0
    (-1, -32768, 1),        # 32768 -> 1 exactly
    (1, -32768, -1),        # -32768 -> -1 exactly
])
def test_floor_rounding(i_q, w, gamma):
    r = demodulate(_arr(0), _arr(i_q), _arr(w))
    assert r.gamma == gamma


def test_floor_rounding_of_negative_sums():
    # acc = -32768 - 1 = -32769 -> -2 (floor), although the mean product is tiny
    r = demodulate(_arr(0, 0), _arr(-1, -1), _arr(32767, 2))
    assert r.gamma == -2


def test_saturation_beyond_s32():
    n = 70000                                           # > 2^16 samples
    i_d = np.full(n, 32767, dtype=np.int64)
    i_q = np.full(n, -32768, dtype=np.int64)
    w = np.full(n, -32768, dtype=np.int64)
    r = demodulate(i_d, i_q, w)
    # acc_q = 70000 * 2^30 (< 2^47) -> 70000 * 2^15 = 2293760000 > 2^31 - 1
    assert r.gamma == S32_MAX
    # acc_d = -70000 * 32767 * 2^15 -> -2293690000 < -2^31
    assert r.gamma_d == S32_MIN
    assert r.sum_id == S32_MAX                          # 2293690000
    assert r.sum_iq == S32_MIN                          # -2293760000
    assert r.wsum == S32_MIN
    assert r.n_samples == 65535


def test_gamma_saturation_boundary():
    # 65535 samples of 2^30: 65535 * 2^15 = 2147450880 fits s32; 65536 samples: 2^31 saturates
    r = demodulate(np.zeros(65535, np.int64), np.full(65535, -32768, np.int64),
                   np.full(65535, -32768, np.int64))
    assert (r.gamma, r.n_samples) == (2147450880, 65535)
    r = demodulate(np.zeros(65536, np.int64), np.full(65536, -32768, np.int64),
                   np.full(65536, -32768, np.int64))
    assert (r.gamma, r.n_samples) == (S32_MAX, 65535)


def test_accumulation_continues_after_count_saturates():
    n = 70000
    r = demodulate(np.zeros(n, np.int64), np.full(n, -1, np.int64), np.full(n, -32768, np.int64))
    # acc_q = 70000 * 32768 -> 70000: all samples counted in the sums, N_SAMPLES stops at 65535
    assert (r.gamma, r.sum_iq, r.wsum, r.n_samples) == (70000, -70000, S32_MIN, 65535)


def test_accumulator_beyond_s48_is_rejected():
    # 2^17 - 1 extreme samples: acc = 2^47 - 2^30 fits s48; 2^17 samples: acc = 2^47 does not
    n = 2 ** 17
    r = demodulate(np.zeros(n - 1, np.int64), np.full(n - 1, -32768, np.int64),
                   np.full(n - 1, -32768, np.int64))
    assert r.gamma == S32_MAX
    with pytest.raises(ValueError, match="s48"):
        demodulate(np.zeros(n, np.int64), np.full(n, -32768, np.int64), np.full(n, -32768, np.int64))


def test_empty_window():
    zero = WindowResult(0, 0, 0, 0, 0, 0)
    e = np.zeros(0, dtype=np.int64)
    assert demodulate(e, e, e) == zero
    assert demodulate([], [], []) == zero


def test_result_is_frozen():
    r = demodulate(_arr(1), _arr(2), _arr(3))
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.gamma = 5


def test_validation():
    with pytest.raises(ValueError, match="one length"):
        demodulate(_arr(1, 2), _arr(1), _arr(1, 2))
    with pytest.raises(ValueError, match="1-D"):
        demodulate(np.zeros((2, 2), np.int64), np.zeros((2, 2), np.int64), np.zeros((2, 2), np.int64))
    with pytest.raises(ValueError, match=r"w\[1\] = 32768"):
        demodulate(_arr(0, 0), _arr(0, 0), _arr(0, 32768))
    with pytest.raises(ValueError, match="i_q"):
        demodulate(_arr(0), _arr(-32769), _arr(0))
    with pytest.raises(TypeError):
        demodulate(np.array([0.5]), _arr(0), _arr(0))
