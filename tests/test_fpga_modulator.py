"""Modulator of docs/spec.md section 3.5 (golden/fpga/modulator.py): inverse Park, inverse Clarke,
min-max zero sequence and compares, with the square-wave injection of Benevieri et al. 2023, eq. (14).

Expected values are derived by hand in the comments (floor(x / 32768) written out with the multiples of
32768 that bracket x) or from the analytical duty formula, never from the function under test."""

from __future__ import annotations

import math

import numpy as np
import pytest

from golden.fpga.modulator import SIGN_BOTTOM, SIGN_TOP, SQRT3_HALF_Q15, compares

H = 10000
COS0, SIN0 = 32767, 0           # theta_hat = 0 in Q1.15
V_H = 5851                      # to_fixed(100 V / 560 V, 15) = round(5851.43)


def test_constants():
    assert SQRT3_HALF_Q15 == 28378 == round(2 ** 15 * math.sqrt(3) / 2)
    assert (SIGN_BOTTOM, SIGN_TOP) == (-1, 1)


@pytest.mark.parametrize("half", [4, 10000, 65534])
@pytest.mark.parametrize("sin_cos", [(0, 32767), (32767, 0), (-23170, 23170), (-32768, -32768)])
@pytest.mark.parametrize("sign", [-1, 1])
def test_zero_voltage_gives_half_duty(half, sin_cos, sign):
    s, c = sin_cos
    assert compares(0, 0, 0, s, c, half, sign) == (half // 2,) * 3


def test_pure_injection_bottom_latch_by_hand():
    # theta_hat = 0 (SIN = 0, COS = 32767), V_D = V_Q = 0, V_H = 5851, rising half (sign -1):
    # vd = 0 + (-1)(5851) = -5851, vq = 0
    # v_alpha = round_shr(-5851*32767 - 0, 15): -5851*32767 = -191_719_717; +16384 = -191_703_333;
    #           -5851*32768 = -191_725_568 <= x < -5850*32768 = -191_692_800  ->  v_alpha = -5851
    # v_beta  = round_shr(-5851*0 + 0*32767, 15) = round_shr(0, 15) = 0
    # v_a = -5851
    # v_b = round_shr(5851*16384 + 0*28378, 15): 95_862_784 + 16384 = 95_879_168 = 2926*32768  ->  2926
    # v_c = round_shr(5851*16384 - 0*28378, 15) = 2926
    # off = shr(2926 + (-5851), 1) = floor(-2925 / 2) = -1463
    # v_a' = -5851 + 1463 = -4388, v_b' = v_c' = 2926 + 1463 = 4389
    # cmp_a = 5000 + round_shr(-4388*10000, 15): -43_880_000 + 16384 = -43_863_616;
    #         -1339*32768 = -43_876_352 <= x < -1338*32768 = -43_843_584  ->  5000 - 1339 = 3661
    # cmp_b = 5000 + round_shr(4389*10000, 15): 43_890_000 + 16384 = 43_906_384;
    #         1339*32768 = 43_876_352 <= x < 1340*32768 = 43_909_120  ->  5000 + 1339 = 6339
    vd = 0 + (-1) * V_H
    v_al = (vd * COS0 - 0 * SIN0 + 16384) // 32768
    v_be = (vd * SIN0 + 0 * COS0 + 16384) // 32768
    assert (v_al, v_be) == (-5851, 0)
    v_b = (-v_al * 16384 + v_be * 28378 + 16384) // 32768
    v_c = (-v_al * 16384 - v_be * 28378 + 16384) // 32768
    assert (v_b, v_c) == (2926, 2926)
    off = (max(v_al, v_b, v_c) + min(v_al, v_b, v_c)) // 2
    assert off == -1463
    assert [v_al - off, v_b - off, v_c - off] == [-4388, 4389, 4389]
    assert compares(0, 0, V_H, SIN0, COS0, H, SIGN_BOTTOM) == (3661, 6339, 6339)


def test_pure_injection_top_latch_by_hand():
    # sign +1: vd = 5851; v_alpha = round_shr(191_719_717, 15): 191_736_101 in [5851*32768, 5852*32768)
    # -> 5851; v_beta = 0; v_b = v_c = round_shr(-5851*16384, 15): -95_846_400 = -2925*32768 -> -2925
    # off = shr(5851 - 2925, 1) = 1463; v' = (4388, -4388, -4388)
    # cmp_a = 5000 + round_shr(43_880_000, 15): 43_896_384 in [1339*32768, 1340*32768) -> 6339
    # cmp_b = 5000 + round_shr(-43_880_000, 15): -43_863_616 in [-1339*32768, -1338*32768) -> 3661
    assert compares(0, 0, V_H, SIN0, COS0, H, SIGN_TOP) == (6339, 3661, 3661)


@pytest.mark.parametrize("sign", [-1, 1])
def test_injection_line_voltage_matches_the_analytical_duty(sign):
    # At theta_hat = 0: v_alpha = vd = sign*V_H, v_beta = 0, so v_a = vd and v_b = v_c = -vd/2:
    # v_ab = 1.5*vd. The zero sequence cancels in a line voltage and duty = 1/2 + v'/V_dc with
    # 2^15 = V_dc, so (cmp_a - cmp_b)/H = v_ab/V_dc = 1.5*sign*V_H/2^15.
    a, b, c = compares(0, 0, V_H, SIN0, COS0, H, sign)
    assert b == c
    ideal = 1.5 * sign * V_H / 32768 * H          # 2678.37 ticks
    assert abs((a - b) - ideal) <= 1
    # and the physical 1.5*100 V/560 V, within the V_H quantisation (0.43 LSB = 0.2 tick) + 1 tick
    assert abs((a - b) - 1.5 * sign * 100.0 / 560.0 * H) <= 1.2


def test_injection_line_voltage_sweep():
    # Error budget of cmp_a - cmp_b against 1.5*vd*H/2^15 over the linear range (|v'| = 0.75 V_H
    # <= 2^14, V_H <= 21845): v_alpha = round(vd*32767/32768) is off by <= 0.5 + |vd|/32768 < 1.17 LSB,
    # v_b = round(-v_alpha/2) by <= 0.5 LSB, so v_a - v_b by < 1.5*1.17 + 0.5 = 2.25 LSB = 0.69 tick;
    # each compare rounds by <= 0.5 tick: total < 1.69 tick.
    for v_h in range(0, 21846, 7):
        for sign in (-1, 1):
            a, b, c = compares(0, 0, v_h, SIN0, COS0, H, sign)
            assert abs((a - b) - 1.5 * sign * v_h / 32768 * H) < 1.69, (v_h, sign)
            assert abs(a + b - H) <= 1            # min-max offset: the two levels centred on H/2


def test_min_max_offset_extends_the_linear_range():
    # V_D = 18000 (0.549 V_dc) at theta_hat = 0, sign +1, no injection: without the zero sequence
    # leg a would need duty 1/2 + 17999/32768 = 1.049 (clipped); with it the legs stay linear.
    # v_alpha = round_shr(18000*32767, 15): 589_822_384 in [17999*32768, 18000*32768) -> 17999
    # v_beta = 0; v_b = v_c = round_shr(-17999*16384, 15): -294_879_232 = -8999*32768 -> -8999
    # off = shr(17999 - 8999, 1) = 4500; v' = (13499, -13499, -13499)
    # cmp_a = 5000 + round_shr(134_990_000, 15): 135_006_384 in [4120*32768, 4121*32768) -> 9120
    # cmp_b = 5000 + round_shr(-134_990_000, 15): -134_973_616 in [-4120*32768, -4119*32768) -> 880
    assert compares(18000, 0, 0, SIN0, COS0, H, SIGN_TOP) == (9120, 880, 880)


def test_overmodulation_clamps_per_leg():
    # V_D = V_Q = 32767 at theta_hat = 0 (|v| = 1.41 V_dc), no injection:
    # v_alpha = v_beta = round_shr(32767*32767, 15): 1_073_692_673 in [32766*32768, 32767*32768) -> 32766
    # v_b = round_shr(32766*(28378 - 16384), 15) = round_shr(392_995_404, 15):
    #       393_011_788 in [11993*32768 = 392_986_624, 11994*32768) -> 11993
    # v_c = round_shr(-32766*44762, 15) = round_shr(-1_466_671_692, 15): -1_466_655_308 in
    #       [-44759*32768 = -1_466_662_912, -44758*32768) -> -44759
    # off = shr(32766 - 44759, 1) = floor(-11993/2) = -5997; v' = (38763, 17990, -38762)
    # unclamped: 5000 + 11830 = 16830, 5000 + 5490 = 10490, 5000 - 11829 = -6829 -> clamped to 0..H
    assert compares(32767, 32767, 0, SIN0, COS0, H, SIGN_TOP) == (H, H, 0)
    # the most negative register values clamp the other way for leg a
    a, _, _ = compares(-32768, 0, 32767, SIN0, COS0, H, SIGN_BOTTOM)
    assert a == 0


def test_symmetry_negating_the_voltages_mirrors_the_compares():
    # cmp(-v) + cmp(v) = H exactly in real arithmetic; round-half-up and the floor of the offset
    # break it by at most a few voltage LSB (< 32768/H = 3.3 LSB = 1 tick at H = 10000).
    for i in range(72):
        th = 2 * math.pi * i / 72 + 0.01
        s, c = round(32767 * math.sin(th)), round(32767 * math.cos(th))
        for v_d, v_q, v_h in ((3000, -7000, 0), (-12001, 4321, 5851), (16000, 9999, 2000), (1, -1, 1)):
            for sign in (-1, 1):
                p = compares(v_d, v_q, v_h, s, c, H, sign)
                n = compares(-v_d, -v_q, v_h, s, c, H, -sign)
                assert all(abs(x + y - H) <= 1 for x, y in zip(p, n)), (i, v_d, v_q, v_h, sign, p, n)


def test_numpy_integers_are_accepted():
    assert compares(np.int64(0), np.int16(0), np.int32(V_H), np.int64(SIN0), np.int64(COS0),
                    np.int64(H), np.int64(-1)) == (3661, 6339, 6339)


@pytest.mark.parametrize("args, match", [
    ((32768, 0, 0, 0, 32767, H, 1), "V_D"),
    ((-32769, 0, 0, 0, 32767, H, 1), "V_D"),
    ((0, 32768, 0, 0, 32767, H, 1), "V_Q"),
    ((0, 0, -1, 0, 32767, H, 1), "V_H"),
    ((0, 0, 32768, 0, 32767, H, 1), "V_H"),
    ((0, 0, 0, 32768, 0, H, 1), "SIN"),
    ((0, 0, 0, 0, -32769, H, 1), "COS"),
    ((0, 0, 0, 0, 32767, 10001, 1), "even"),
    ((0, 0, 0, 0, 32767, 2, 1), "half period"),
    ((0, 0, 0, 0, 32767, 65536, 1), "half period"),
    ((0, 0, 0, 0, 32767, H, 0), "sign"),
    ((0, 0, 0, 0, 32767, H, 2), "sign"),
    ((0.0, 0, 0, 0, 32767, H, 1), "integer"),
    ((0, 0, 0, 0, 32767, H, True), "integer"),
])
def test_validation(args, match):
    with pytest.raises(ValueError, match=match):
        compares(*args)
