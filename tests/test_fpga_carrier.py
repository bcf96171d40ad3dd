"""Carrier of docs/spec.md section 2.1 (golden/fpga/carrier.py): counter, windows, effective half,
injection sign (Benevieri et al. 2023, eqs. (14)-(15))."""

from __future__ import annotations

import numpy as np
import pytest

from golden.fpga.carrier import (counter, effective_half, injection_sign, period_start, phase_of,
                                 window_of, window_start)

H = 10000


@pytest.mark.parametrize("phase, expected", [
    (0, 0),            # carrier bottom
    (1, 1),            # rising: c = phi
    (H - 1, H - 1),
    (H, H),            # carrier top: falling half starts, c = 2H - H
    (H + 1, H - 1),    # falling: c = 2H - phi
    (2 * H - 1, 1),
])
def test_counter_scalar(phase, expected):
    assert counter(phase, H) == expected


def test_counter_array_matches_the_same_points():
    phases = np.array([0, 1, H - 1, H, H + 1, 2 * H - 1], dtype=np.int64)
    out = counter(phases, H)
    assert out.dtype == np.int64
    assert out.tolist() == [0, 1, 9999, 10000, 9999, 1]


@pytest.mark.parametrize("phase", [-1, 2 * H, 3 * H])
def test_counter_rejects_phases_outside_the_period(phase):
    with pytest.raises(ValueError, match="phase"):
        counter(phase, H)
    with pytest.raises(ValueError, match="phases"):
        counter(np.array([0, phase], dtype=np.int64), H)


@pytest.mark.parametrize("half", [3, 2, 10001, 65536, 0])
def test_functions_reject_invalid_half(half):
    with pytest.raises(ValueError, match="half period"):
        counter(0, half)
    with pytest.raises(ValueError, match="half period"):
        window_start(0, half)


def test_phase_and_period_start():
    assert phase_of(0, H) == 0
    assert phase_of(2 * H - 1, H) == 2 * H - 1
    assert phase_of(2 * H, H) == 0
    assert phase_of(5 * 2 * H + 1234, H) == 1234
    assert phase_of(-1, H) == 2 * H - 1
    assert phase_of(np.array([20000, 20001, 39999]), H).tolist() == [0, 1, 19999]
    assert period_start(0, H) == 0
    assert period_start(3, H) == 60000
    assert period_start(-1, H) == -20000


def test_window_boundaries_at_the_rising_zero_crossing():
    assert window_start(0, H) == 5000           # H/2: counter at H/2 on the rising half, cw = 0
    assert counter(phase_of(window_start(0, H), H), H) == H // 2
    assert window_start(1, H) == 25000
    assert window_start(-1, H) == -15000
    assert window_of(H // 2 - 1, H) == -1       # 4999: last tick of window -1
    assert window_of(H // 2, H) == 0            # 5000: first tick of window 0
    assert window_of(24999, H) == 0
    assert window_of(25000, H) == 1
    assert window_of(-15000, H) == -1
    assert window_of(-15001, H) == -2
    ticks = np.array([4999, 5000, 24999, 25000], dtype=np.int64)
    assert window_of(ticks, H).tolist() == [-1, 0, 0, 1]


@pytest.mark.parametrize("register, expected", [
    (10000, 10000),
    (10001, 10000),   # odd: LSB cleared
    (514, 514),
    (513, 512),
    (512, 512),
    (511, 512),       # too small: REGISTER_HALF_MIN
    (4, 512),
    (0, 512),
    (65535, 65534),
    (65534, 65534),
])
def test_effective_half(register, expected):
    assert effective_half(register) == expected


@pytest.mark.parametrize("register", [-1, 65536, 1.5, True])
def test_effective_half_rejects_non_u16(register):
    with pytest.raises(ValueError, match="PWM_HALF"):
        effective_half(register)


def test_injection_sign_eq14():
    # v_dh = V_h * -sign(d cw / dt): the carrier rises -> -V_h, falls -> +V_h
    assert injection_sign(True) == -1
    assert injection_sign(False) == 1
