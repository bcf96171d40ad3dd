"""Tests of the ADC offset and scale (golden/fpga/adc_scale.py, docs/spec.md section 3.1).

i = sat(round_shr(((code - 2^(B-1)) * 2^(16-B) - ADC_OFFSET) * ADC_GAIN, 14), 16); every expected value
below is that formula worked out by hand.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from golden.fpga.adc_scale import GAIN_ONE, adc_to_current  # noqa: E402


def test_gain_one_constant():
    assert GAIN_ONE == 16384


@pytest.mark.parametrize("code,expected", [
    (2048, 0),          # mid-scale = 0 A
    (2049, 16),         # 1 code = 2^(16-12) = 16 current LSB
    (2047, -16),
    (4095, 32752),      # 2047 * 16
    (0, -32768),        # -2048 * 16
])
def test_12bit_unity_gain(code, expected):
    assert adc_to_current(code, 12, 0, 16384) == expected


def test_12bit_gain_two_saturates():
    assert adc_to_current(4095, 12, 0, 32768) == 32767      # 2 * 32752 = 65504 -> s16 max
    assert adc_to_current(0, 12, 0, 32768) == -32768        # -65536 -> s16 min
    assert adc_to_current(2050, 12, 0, 32768) == 64         # 2 * 32


def test_12bit_gain_rounding():
    # 32752 * 16385 = 32752 * 2^14 + 32752; (+ 8192) >> 14 = 32752 + (40944 >> 14) = 32752 + 2
    assert adc_to_current(4095, 12, 0, 16385) == 32754
    # 16 * 65535 = 1048560; (+ 8192) >> 14 = 1056752 / 16384 = 64.499 -> 64
    assert adc_to_current(2049, 12, 0, 65535) == 64
    assert adc_to_current(4095, 12, 0, 0) == 0


@pytest.mark.parametrize("offset,expected", [
    (-1, 1),    # (1 * 8192 + 8192) >> 14 = 1     (+0.5 -> 1, half up)
    (1, 0),     # (-8192 + 8192) >> 14 = 0        (-0.5 -> 0, half up)
    (-3, 2),    # (24576 + 8192) >> 14 = 2        (+1.5 -> 2)
    (3, -1),    # (-24576 + 8192) >> 14 = -1      (-1.5 -> -1)
])
def test_half_up_rounding_at_gain_one_half(offset, expected):
    assert adc_to_current(2048, 12, offset, 8192) == expected


def test_negative_and_positive_offset():
    assert adc_to_current(2048, 12, -100, 16384) == 100          # x - offset = 0 + 100
    assert adc_to_current(0, 12, -100, 16384) == -32668          # -32768 + 100
    assert adc_to_current(4095, 12, 100, 16384) == 32652         # 32752 - 100
    assert adc_to_current(4095, 12, -100, 16384) == 32767        # 32852 saturates
    assert adc_to_current(0, 12, 100, 16384) == -32768           # -32868 saturates


def test_16bit():
    assert adc_to_current(0, 16, 0, 16384) == -32768
    assert adc_to_current(32768, 16, 0, 16384) == 0
    assert adc_to_current(65535, 16, 0, 16384) == 32767
    assert adc_to_current(0, 16, 32767, 16384) == -32768        # -65535 saturates
    assert adc_to_current(65535, 16, -32768, 16384) == 32767    # +65535 saturates
    # (40000 - 32768 - 1000) * 20000 = 124640000; / 16384 = 7607.42 -> 7607
    assert adc_to_current(40000, 16, 1000, 20000) == 7607


def test_1bit():
    assert adc_to_current(0, 1, 0, 16384) == -32768
    assert adc_to_current(1, 1, 0, 16384) == 0


def test_array_input():
    codes = np.array([0, 2047, 2048, 2049, 4095], dtype=np.int64)
    out = adc_to_current(codes, 12, 0, 16384)
    assert isinstance(out, np.ndarray) and out.dtype == np.int64
    assert out.tolist() == [-32768, -16, 0, 16, 32752]
    assert adc_to_current(codes.astype(np.uint16), 12, 0, 16384).tolist() == out.tolist()
    assert type(adc_to_current(np.int64(2049), 12, 0, 16384)) is int


def test_bad_codes_are_reported():
    for code in (-1, 4096, 65535):
        with pytest.raises(ValueError, match="ADC code"):
            adc_to_current(code, 12, 0, 16384)
    with pytest.raises(ValueError, match=r"code\[2\] = 4096"):
        adc_to_current(np.array([0, 4095, 4096, 5000]), 12, 0, 16384)
    with pytest.raises(ValueError, match="ADC code"):
        adc_to_current(65536, 16, 0, 16384)
    with pytest.raises(TypeError):
        adc_to_current(np.array([1.0, 2.0]), 12, 0, 16384)
    with pytest.raises(TypeError):
        adc_to_current(2048.0, 12, 0, 16384)


def test_bad_parameters():
    for bits in (0, 17, -12):
        with pytest.raises(ValueError, match="bits"):
            adc_to_current(0, bits, 0, 16384)
    for offset in (32768, -32769):
        with pytest.raises(ValueError, match="ADC_OFFSET"):
            adc_to_current(0, 12, offset, 16384)
    for gain in (-1, 65536):
        with pytest.raises(ValueError, match="ADC_GAIN"):
            adc_to_current(0, 12, 0, gain)
    with pytest.raises(ValueError, match="bits"):
        adc_to_current(0, 12.0, 0, 16384)
