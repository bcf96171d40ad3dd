"""ADC trigger of docs/spec.md section 2.3 (golden/fpga/adc_trigger.py): OS / DS instants per period and
per integration window, blanking after switching instants."""

from __future__ import annotations

import numpy as np
import pytest

from golden.fpga.adc_trigger import (MODE_DS, MODE_OS, MODE_OS_BLANK, blank_mask, sample_phases,
                                     window_sample_ticks)

H = 10000
OS = 100


def test_mode_constants():
    assert (MODE_OS, MODE_DS, MODE_OS_BLANK) == (0, 1, 2)


def test_os_phases_default():
    ph = sample_phases(MODE_OS, H, OS)
    assert ph.dtype == np.int64
    assert len(ph) == 200
    assert ph.tolist() == list(range(0, 20000, 100))


def test_os_blank_and_reserved_mode_use_the_os_phases():
    expected = list(range(0, 20000, 100))
    assert sample_phases(MODE_OS_BLANK, H, OS).tolist() == expected
    assert sample_phases(3, H, OS).tolist() == expected


def test_ds_phases_are_bottom_and_top():
    assert sample_phases(MODE_DS, H, OS).tolist() == [0, 10000]


def test_os_ticks_not_dividing_the_period_restart_every_period():
    ph = sample_phases(MODE_OS, H, 300)
    assert len(ph) == 67                      # ceil(20000 / 300)
    assert ph.tolist() == list(range(0, 19801, 300))
    assert ph[-1] == 19800
    # the next period starts again at phase 0: the gap across the period start is 200, not 300
    ticks = np.concatenate([window_sample_ticks(0, MODE_OS, H, 300), window_sample_ticks(1, MODE_OS, H, 300)])
    gaps = np.diff(ticks)
    assert set(gaps.tolist()) == {300, 200}
    assert 40000 in ticks.tolist() and 20000 in ticks.tolist()


def test_window_zero_os_ticks():
    t = window_sample_ticks(0, MODE_OS, H, OS)
    assert t.dtype == np.int64
    assert len(t) == 200
    assert t.tolist() == list(range(5000, 24901, 100))


def test_window_zero_ds_ticks():
    assert window_sample_ticks(0, MODE_DS, H, OS).tolist() == [10000, 20000]


def test_window_ticks_with_os_300():
    t = window_sample_ticks(0, MODE_OS, H, 300)
    # period 0: 5100 .. 19800 (50 instants); period 1: 20000 .. 24800 (17 instants)
    assert t.tolist() == list(range(5100, 19801, 300)) + list(range(20000, 24801, 300))
    assert len(t) == 67


def test_window_ticks_other_windows_are_shifted_copies():
    t0 = window_sample_ticks(0, MODE_OS, H, OS)
    assert window_sample_ticks(3, MODE_OS, H, OS).tolist() == (t0 + 60000).tolist()
    assert window_sample_ticks(-1, MODE_OS, H, OS).tolist() == (t0 - 20000).tolist()


@pytest.mark.parametrize("kwargs, match", [
    (dict(mode=4, half=H, os_ticks=OS), "ADC_MODE"),
    (dict(mode=-1, half=H, os_ticks=OS), "ADC_MODE"),
    (dict(mode=MODE_OS, half=H, os_ticks=0), "OS_TICKS"),
    (dict(mode=MODE_OS, half=H, os_ticks=65536), "OS_TICKS"),
    (dict(mode=MODE_DS, half=H, os_ticks=0), "OS_TICKS"),
    (dict(mode=MODE_OS, half=10001, os_ticks=OS), "half period"),
])
def test_sample_phases_validation(kwargs, match):
    with pytest.raises(ValueError, match=match):
        sample_phases(**kwargs)


def test_blank_mask_hand_cases():
    sw = np.array([1000, 5000])
    t = np.array([999, 1000, 1001, 1999, 2000, 4999, 5000, 5999, 6000, 0])
    dropped = blank_mask(t, sw, 1000)
    # 999: before any switch; 1000: at t_s (t - t_s = 0 < 1000) dropped; 1999: 999 after; 2000: exactly
    # BLANK_TICKS after -> kept; 5000 / 5999 after the second switch dropped; 6000 kept; 0 kept
    assert dropped.tolist() == [False, True, True, True, False, False, True, True, False, False]


def test_blank_mask_unsorted_and_duplicate_switch_ticks():
    sw = np.array([5000, 1000, 1000, 4500])
    t = np.array([1500, 4400, 4500, 5400, 5600])
    # 5400: 900 after 4500 (dropped) and 400 after 5000; 5600: 600 after 5000 -> dropped
    assert blank_mask(t, sw, 1000).tolist() == [True, False, True, True, True]
    # blank 500: 1500 is exactly 500 after 1000 -> kept; 4500 at t_s; 5400 400 after 5000; 5600 kept
    assert blank_mask(t, sw, 500).tolist() == [False, False, True, True, False]


def test_blank_zero_keeps_everything():
    t = np.arange(0, 20000, 100)
    assert not blank_mask(t, np.array([0, 100, 5000]), 0).any()


def test_blank_mask_no_switches_keeps_everything_and_keeps_shape():
    t = np.arange(12).reshape(3, 4)
    out = blank_mask(t, np.array([], dtype=np.int64), 1000)
    assert out.shape == (3, 4) and not out.any()


def test_blank_mask_validation():
    with pytest.raises(ValueError, match="BLANK_TICKS"):
        blank_mask(np.array([0]), np.array([0]), -1)
    with pytest.raises(ValueError, match="BLANK_TICKS"):
        blank_mask(np.array([0]), np.array([0]), 65536)
    with pytest.raises(ValueError, match="integers"):
        blank_mask(np.array([0.5]), np.array([0]), 10)


def test_os_ticks_below_the_pipeline_minimum_use_os_min():
    """docs/spec.md 2.3: OS_TICKS < ITERATIONS + 8 (40 by default) is used as 40, 0 included."""
    from golden.fpga.adc_trigger import effective_os_ticks
    assert effective_os_ticks(0) == 40 and effective_os_ticks(39) == 40 and effective_os_ticks(100) == 100
    assert effective_os_ticks(10, iterations=16) == 24
    with pytest.raises(ValueError):
        effective_os_ticks(70000)
