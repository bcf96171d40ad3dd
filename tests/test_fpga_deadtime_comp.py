"""Dead-time compensation (golden/fpga/deadtime_comp.py; rules in its module docstring).

Expected values are derived by hand in the comments: round_shr(x, 15) = floor((x + 16384) / 32768),
written out with the multiples of 32768 that bracket x + 16384; never from the function under test.
"""

from __future__ import annotations

import pytest

from golden.fpga.deadtime_comp import compensate, phase_current, recip_half

H = 10000
DEAD = 400
SIN0, COS0 = 0, 32767                # theta = 0 in Q1.15
RECIP = 429497                       # round(2^32 / 10000), see test_recip_half_default


# ---- RECIP_H -----------------------------------------------------------------------------------------
def test_recip_half_default():
    # 2^32 = 4_294_967_296; / 10000 = 429_496.7296 -> nearest 429_497
    assert recip_half(10000) == 429497


@pytest.mark.parametrize("half, expected", [
    (4, 1073741824),        # 2^32 / 4 = 2^30 exactly
    (6, 715827883),         # 4_294_967_296 / 6 = 715_827_882.67 -> 715_827_883
    (8, 536870912),         # 2^29 exactly
    (10, 429496730),        # 429_496_729.6 -> 429_496_730
    (5000, 858993),         # 858_993.4592 -> 858_993
    (65534, 65538),         # 65534 * 65538 = 65536^2 - 4 = 4_294_967_292: 65538 + 4/65534 -> 65538
])
def test_recip_half_values(half, expected):
    assert recip_half(half) == expected


@pytest.mark.parametrize("half", [3, 5, 9999, 10001, 2, 1, 0, -2, -10000])
def test_recip_half_rejects_odd_or_small(half):
    with pytest.raises(ValueError):
        recip_half(half)


# ---- phase current -----------------------------------------------------------------------------------
def test_phase_current_d_axis_at_theta_0():
    # i_d = 1000, i_q = 0, SIN 0, COS 32767:
    # i_alpha = round_shr(1000*32767 - 0, 15): 32_767_000 + 16_384 = 32_783_384;
    #   1000*32768 = 32_768_000 <= 32_783_384 < 1001*32768 = 32_800_768 -> 1000
    # i_beta = round_shr(1000*0 + 0*32767, 15) = 0
    # leg b = round_shr(-1000*16384 + 0, 15): -16_384_000 + 16_384 = -16_367_616;
    #   -500*32768 = -16_384_000 <= -16_367_616 < -499*32768 = -16_351_232 -> -500; leg c the same.
    assert phase_current(0, 1000, 0, SIN0, COS0) == 1000
    assert phase_current(1, 1000, 0, SIN0, COS0) == -500
    assert phase_current(2, 1000, 0, SIN0, COS0) == -500


def test_phase_current_negative_d_axis_at_theta_0():
    # i_d = -1000: i_alpha = round_shr(-32_767_000, 15): -32_767_000 + 16_384 = -32_750_616;
    #   -1000*32768 = -32_768_000 <= -32_750_616 < -999*32768 = -32_735_232 -> -1000
    # leg b = round_shr(+1000*16384, 15): 16_384_000 + 16_384 = 16_400_384;
    #   500*32768 = 16_384_000 <= 16_400_384 < 501*32768 = 16_416_768 -> 500; leg c the same.
    assert [phase_current(leg, -1000, 0, SIN0, COS0) for leg in range(3)] == [-1000, 500, 500]


def test_phase_current_q_axis_at_theta_0():
    # i_d = 0, i_q = 1000: i_alpha = round_shr(0 - 1000*0, 15) = 0;
    # i_beta = round_shr(0 + 1000*32767, 15) = 1000 (as i_alpha above)
    # leg b = round_shr(0 + 1000*28378, 15): 28_378_000 + 16_384 = 28_394_384;
    #   866*32768 = 28_377_088 <= 28_394_384 < 867*32768 = 28_409_856 -> 866
    # leg c = round_shr(-28_378_000, 15): -28_378_000 + 16_384 = -28_361_616;
    #   -866*32768 = -28_377_088 <= -28_361_616 < -865*32768 = -28_344_320 -> -866
    assert [phase_current(leg, 0, 1000, SIN0, COS0) for leg in range(3)] == [0, 866, -866]


def test_phase_current_d_axis_at_theta_90():
    # SIN 32767, COS 0 (theta = 90 deg), i_d = 1000: i_alpha = round_shr(1000*0 - 0*32767, 15) = 0,
    # i_beta = round_shr(1000*32767 + 0, 15) = 1000 -> legs 0, 866, -866 as in the q-axis case above.
    assert [phase_current(leg, 1000, 0, 32767, 0) for leg in range(3)] == [0, 866, -866]


def test_phase_current_small_values_round_half_up():
    # i_d = -10 at theta 0: i_alpha = round_shr(-327_670, 15): -327_670 + 16_384 = -311_286;
    #   -10*32768 = -327_680 <= -311_286 < -9*32768 = -294_912 -> -10
    # leg b = round_shr(10*16384, 15) = floor((163_840 + 16_384) / 32768) = floor(5.5) = 5
    assert [phase_current(leg, -10, 0, SIN0, COS0) for leg in range(3)] == [-10, 5, 5]
    # i_d = +10: i_alpha = floor((327_670 + 16_384) / 32768) = floor(10.49) = 10;
    # leg b = floor((-163_840 + 16_384) / 32768) = floor(-4.5) = -5
    assert [phase_current(leg, 10, 0, SIN0, COS0) for leg in range(3)] == [10, -5, -5]


# ---- compensation ------------------------------------------------------------------------------------
def comp(cmps, sign, *, gain=256, i_d=0, i_q=0, hf_amp=0, sin=SIN0, cos=COS0, half=H, dead=DEAD,
         recip=RECIP):
    return compensate(cmps, sign, half, dead, gain, i_d, i_q, hf_amp, sin, cos, recip)


@pytest.mark.parametrize("sign", [-1, 1])
@pytest.mark.parametrize("i_d, i_q", [(-20000, 0), (20000, 0), (0, 15000), (-3000, -3000)])
def test_gain_zero_leaves_compares_unchanged(sign, i_d, i_q):
    # c = clamp(shr(i * 0, 8), -D, D) = 0 for every leg
    cmps = (1234, 5000, 8766)
    assert comp(cmps, sign, gain=0, i_d=i_d, i_q=i_q, hf_amp=3000) == cmps


def test_rising_half_negative_current_reduces_by_dead():
    # hf_amp 0 -> hf = 0; i_d = -1000, theta 0: leg currents (-1000, 500, 500) (see above).
    # gain 256 (1 tick per LSB): c = clamp(shr(i*256, 8), -400, 400) = (-400, 400, 400).
    # rising (sign -1): cmp + min(c, 0) -> (5000 - 400, 5000, 5000)
    assert comp((5000, 5000, 5000), -1, i_d=-1000) == (4600, 5000, 5000)


def test_falling_half_positive_current_increases_by_dead():
    # i_d = -1000: c = (-400, 400, 400); falling (+1): cmp + max(c, 0) -> (5000, 5400, 5400)
    assert comp((5000, 5000, 5000), 1, i_d=-1000) == (5000, 5400, 5400)
    # i_d = +1000: currents (1000, -500, -500), c = (400, -400, -400) -> (5400, 5000, 5000)
    assert comp((5000, 5000, 5000), 1, i_d=1000) == (5400, 5000, 5000)


def test_opposite_signs_leave_compares_unchanged():
    # rising half with positive currents and falling half with negative currents: no change.
    # i_d = +1000: c = (400, -400, -400): rising moves only b, c (negative) by -400; leg a unchanged.
    assert comp((5000, 5000, 5000), -1, i_d=1000) == (5000, 4600, 4600)
    # i_q = 1000 at theta 0: currents (0, 866, -866), gain 256: c = (0, 400, -400)
    # rising: (5000, 5000, 4600); falling: (5000, 5400, 5000)
    assert comp((5000, 5000, 5000), -1, i_q=1000) == (5000, 5000, 4600)
    assert comp((5000, 5000, 5000), 1, i_q=1000) == (5000, 5400, 5000)


def test_compensation_clamped_to_0_h():
    # rising, i_d = -1000 (leg a c = -400): compare 100 -> -300 -> 0; compare 0 stays 0
    assert comp((100, 0, 0), -1, i_d=-1000) == (0, 0, 0)
    # falling, i_d = -1000 (legs b, c: c = +400): 9800 -> 10200 -> 10000; 10000 stays 10000
    assert comp((0, 9800, 10000), 1, i_d=-1000) == (0, 10000, 10000)
    # exactly at the bounds: 400 - 400 = 0, 9600 + 400 = 10000
    assert comp((400, 9600, 9600), -1, i_d=-1000) == (0, 9600, 9600)
    assert comp((400, 9600, 9600), 1, i_d=-1000) == (400, 10000, 10000)


def test_linear_zone_small_current():
    # i_d = -10 at theta 0: currents (-10, 5, 5) (see test_phase_current_small_values_round_half_up).
    # gain 300 (1.171875 ticks per LSB, Q8): leg a shr(-3000, 8) = floor(-11.72) = -12;
    # legs b, c shr(1500, 8) = floor(5.86) = 5. All inside +-400.
    # rising: (5000 - 12, 5000, 5000); falling: (5000, 5005, 5005)
    assert comp((5000, 5000, 5000), -1, gain=300, i_d=-10) == (4988, 5000, 5000)
    assert comp((5000, 5000, 5000), 1, gain=300, i_d=-10) == (5000, 5005, 5005)


def test_linear_zone_edge_of_clamp():
    # dead 12, gain 300, i_d = -10: leg a c = clamp(-12, -12, 12) = -12 (just inside);
    # dead 11: clamp(-12, -11, 11) = -11
    assert comp((5000, 5000, 5000), -1, gain=300, i_d=-10, dead=12) == (4988, 5000, 5000)
    assert comp((5000, 5000, 5000), -1, gain=300, i_d=-10, dead=11) == (4989, 5000, 5000)


def test_hf_prediction_from_the_compare():
    # hf_amp 1000, refs 0, theta 0, gain 256, dead 400, H 10000, RECIP 429497.
    # leg a, compare 7500: 2*7500 - 10000 = 5000; hf = round_shr(1000*5000*429497, 32):
    #   1000*5000*429497 = 2_147_485_000_000; + 2^31 = 2_149_632_483_648;
    #   500*2^32 = 2_147_483_648_000 <= 2_149_632_483_648 < 501*2^32 = 2_151_778_615_296 -> hf = 500
    #   i_d = 0 - 500 = -500 -> leg a current round_shr(-500*32767, 15):
    #   -16_383_500 + 16_384 = -16_367_116; -500*32768 = -16_384_000 <= . < -499*32768 -> -500
    #   c = clamp(shr(-500*256, 8), -400, 400) = -400: rising -> 7100
    # legs b, c, compare 5000: 2*5000 - 10000 = 0 -> hf = 0 -> i_d = 0 -> current 0 -> unchanged
    assert comp((7500, 5000, 5000), -1, hf_amp=1000) == (7100, 5000, 5000)
    # falling: leg a c = -400 -> max(-400, 0) = 0 -> unchanged
    assert comp((7500, 5000, 5000), 1, hf_amp=1000) == (7500, 5000, 5000)


def test_hf_prediction_small_in_linear_zone():
    # hf_amp 1000, leg a compare 2500: 2*2500 - 10000 = -5000; hf = round_shr(-2_147_485_000_000, 32):
    #   -2_147_485_000_000 + 2_147_483_648 = -2_145_337_516_352;
    #   -500*2^32 = -2_147_483_648_000 <= . < -499*2^32 = -2_143_188_680_704 -> hf = -500
    #   i_d = 0 - (-500) = 500 -> leg a current round_shr(500*32767, 15):
    #   16_383_500 + 16_384 = 16_399_884; 500*32768 = 16_384_000 <= . < 501*32768 -> 500
    #   gain 2 (2/256 tick per LSB): shr(500*2, 8) = floor(3.906) = 3; falling -> 2503
    # legs b, c compare 5000: 0 current -> unchanged
    assert comp((2500, 5000, 5000), 1, gain=2, hf_amp=1000) == (2503, 5000, 5000)
    assert comp((2500, 5000, 5000), -1, gain=2, hf_amp=1000) == (2500, 5000, 5000)


@pytest.mark.parametrize("sign", [0, 2, -2, 3])
def test_bad_sign_raises(sign):
    with pytest.raises(ValueError):
        comp((5000, 5000, 5000), sign)


@pytest.mark.parametrize("gain", [-1, 0x10000, 1 << 20])
def test_bad_gain_raises(gain):
    with pytest.raises(ValueError):
        comp((5000, 5000, 5000), 1, gain=gain)


@pytest.mark.parametrize("hf_amp", [-1, 0x8000])
def test_bad_hf_amp_raises(hf_amp):
    with pytest.raises(ValueError):
        comp((5000, 5000, 5000), 1, hf_amp=hf_amp)


def test_gain_and_hf_amp_bounds_accepted():
    # 0xFFFF and 0x7FFF are valid register values; with zero currents and hf_amp at a 50 % compare
    # (2*cmp - H = 0) nothing moves.
    assert comp((5000, 5000, 5000), 1, gain=0xFFFF, hf_amp=0x7FFF) == (5000, 5000, 5000)
