"""Firmware control task and supervisor (golden/firmware/supervisor.py; docs/spec.md 5.2).

Synthetic window results (golden.fpga.demodulator.WindowResult) drive Firmware.step. The controllers
are chosen so that every output can be computed by hand:

* current and speed PIs with unit proportional gain and no integral (kp = 2^16, sp = 16, ki = 0):
  u = clamp(shr(65536 * e, 16), -limit, limit) = clamp(ref - meas, -limit, limit);
* PLL gains 0: e is multiplied by 0, so integ = omega = 0 and the PLL angle stays where it is; the
  filtered speed is then 0 too (F = 0 + shr((0 - 0) * A, 16) = 0);
* window means c_div(SUM, N) truncate toward zero.

The expected sin/cos are golden.fpga.cordic.sincos_q15 of the expected angle (an independent block
with its own tests).
"""

from __future__ import annotations

import dataclasses

import pytest

from golden.firmware.pi import PiParams
from golden.firmware.estimator import METHOD_SQW_BANGBANG
from golden.firmware.pll import PllState
from golden.firmware.sqw_bangbang import SqwParams
from golden.firmware.supervisor import (MODE_CATCH, MODE_CONVERGE, MODE_DONE, MODE_FAULT, MODE_FIXED, MODE_IDENT, MODE_NAMES,
                                        MODE_POL_NEG, MODE_POL_POS, MODE_RELAX, MODE_RUN, Firmware, FirmwareParams,
                                        Outputs)
from golden.fpga.cordic import sincos_q15
from golden.fpga.demodulator import WindowResult

TURN = 1 << 32
HALF_TURN = 1 << 31
K_BB = 1000
V_H = 5851
I_PULSE = 300
I_TRIP = 1000
UNIT_PI = PiParams(kp=1 << 16, sp=16, ki=0, si=16, limit=2000)     # u = clamp(ref - meas, +-2000)


def params(k_bb: int = K_BB, **kw) -> FirmwareParams:
    """The square-wave estimator alone (PLL gains 0) with unit current PIs."""
    base = dict(low=METHOD_SQW_BANGBANG, high=0, sqw=SqwParams(k_bb, 0, 0), rfo=None, speed_lp=2425,
                speed_pi=UNIT_PI, id_pi=UNIT_PI, iq_pi=UNIT_PI, v_h=V_H, i_pulse=I_PULSE, n_converge=3,
                n_pulse=4, n_settle=1, i_trip=I_TRIP, fixed_angle=None)
    base.update(kw)
    return FirmwareParams(**base)


def firmware(p: FirmwareParams, theta_hat: int = 0) -> Firmware:
    """A firmware whose low-speed estimator (and so the angle in use) starts at ``theta_hat``."""
    fw = Firmware(p)
    fw.slots[0].theta = fw.est_theta[0] = fw.theta_hat = theta_hat
    return fw


def win(gamma=0, gamma_d=0, sum_id=0, sum_iq=0, n=10, wsum=0) -> WindowResult:
    return WindowResult(gamma=gamma, gamma_d=gamma_d, sum_id=sum_id, sum_iq=sum_iq, wsum=wsum, n_samples=n)


def test_mode_constants():
    assert (MODE_CONVERGE, MODE_POL_POS, MODE_POL_NEG, MODE_RELAX, MODE_RUN, MODE_FIXED, MODE_FAULT, MODE_IDENT,
            MODE_DONE, MODE_CATCH) == tuple(range(10))
    assert MODE_NAMES == ("CONVERGE", "POL_POS", "POL_NEG", "RELAX", "RUN", "FIXED", "FAULT", "IDENT", "DONE", "CATCH")


# ---- start-up sequence -------------------------------------------------------------------------------
# n_converge 3, n_pulse 4, n_settle 1. The window counter n is incremented first in each step and reset
# to 0 on a mode change; the step that changes the mode returns the references of its branch:
#   step  n  mode before -> after   returned i_d*
#    1    1  CONVERGE               0
#    2    2  CONVERGE               0
#    3    3  CONVERGE -> POL_POS    +I_p     (n >= 3; CONVERGE's last step starts the pulse: both pulses
#                                            last n_pulse = 4 windows)
#    4    1  POL_POS                +I_p
#    5    2  POL_POS                +I_p     (n > n_settle: gamma_d summed into pol_pos)
#    6    3  POL_POS                +I_p     (summed)
#    7    4  POL_POS -> POL_NEG     -I_p     (summed; n >= 4: POL_POS returns -I_p on its last step)
#    8    1  POL_NEG                -I_p
#    9    2  POL_NEG                -I_p     (summed into pol_neg)
#   10    3  POL_NEG                -I_p     (summed)
#   11    4  POL_NEG -> RELAX        0       (summed; polarity decision)
#   12    1  RELAX -> RUN            0       (n >= n_settle = 1; then RUN: the speed PI runs this step)
#   13    1  RUN                     0
# RUN: i_q* = clamp(speed_ref - omega_f, +-2000) = 123 - 0 = 123 (unit speed PI, omega_f = 0).
SEQ_MODES = [MODE_CONVERGE, MODE_CONVERGE, MODE_POL_POS, MODE_POL_POS, MODE_POL_POS, MODE_POL_POS,
             MODE_POL_NEG, MODE_POL_NEG, MODE_POL_NEG, MODE_POL_NEG, MODE_RELAX, MODE_RUN, MODE_RUN]
SEQ_ID_REF = [0, 0, I_PULSE, I_PULSE, I_PULSE, I_PULSE, -I_PULSE, -I_PULSE, -I_PULSE, -I_PULSE, 0, 0, 0]
SEQ_IQ_REF = [0] * 11 + [123, 123]


def test_startup_sequence_modes_and_references():
    fw = Firmware(params())
    assert fw.mode == MODE_CONVERGE and fw.theta_hat == 0
    modes, id_refs, iq_refs = [], [], []
    s0, c0 = sincos_q15(0)
    for k in range(13):
        o = fw.step(win(), speed_ref=123)
        modes.append(fw.mode)
        id_refs.append(o.i_d_ref)
        iq_refs.append(o.i_q_ref)
        assert (fw.i_d_ref, fw.i_q_ref) == (o.i_d_ref, o.i_q_ref), k
        # unit current PIs, window means 0: V_D = i_d*, V_Q = i_q*; theta_hat stays 0 (gamma = 0)
        assert o == Outputs(v_d=o.i_d_ref, v_q=o.i_q_ref, v_h=V_H, sin=s0, cos=c0, enable=1,
                            i_d_ref=o.i_d_ref, i_q_ref=o.i_q_ref), k
    assert [MODE_NAMES[m] for m in modes] == [MODE_NAMES[m] for m in SEQ_MODES]
    assert id_refs == SEQ_ID_REF
    assert iq_refs == SEQ_IQ_REF
    assert (fw.pol_pos, fw.pol_neg, fw.flipped, fw.theta_hat) == (0, 0, 0, 0)


def test_current_pi_sees_the_window_means():
    # CONVERGE, i_d* = i_q* = 0; SUM_ID = -509, SUM_IQ = 1234, N = 10:
    # means c_div(-509, 10) = -50 (truncated toward zero), c_div(1234, 10) = 123;
    # V_D = clamp(0 - (-50)) = 50, V_Q = clamp(0 - 123) = -123.
    fw = Firmware(params())
    o = fw.step(win(sum_id=-509, sum_iq=1234), speed_ref=0)
    assert (fw.i_d, fw.i_q) == (-50, 123)
    assert (o.v_d, o.v_q) == (50, -123)
    # N = 0: means 0
    o = fw.step(win(sum_id=5000, sum_iq=5000, n=0), speed_ref=0)
    assert (fw.i_d, fw.i_q, o.v_d, o.v_q) == (0, 0, 0, 0)


def run_polarity(theta0: int, gd_pos, gd_neg):
    """Steps 1..11 of the start-up with gamma = 0; gd_pos / gd_neg: gamma_d of steps 5-7 / 9-11.

    The other windows carry large gamma_d values that must not be summed."""
    fw = firmware(params(), theta0)
    gd = [10**6, -10**6, 10**6, 777_777] + list(gd_pos) + [-888_888] + list(gd_neg)
    outs = [fw.step(win(gamma_d=g), speed_ref=0) for g in gd]
    return fw, outs


@pytest.mark.parametrize("theta0", [0x12345678, 0x90000000, 0, 0x7FFFFFFF])
def test_polarity_flip_when_negative_pulse_responds_more(theta0):
    # pol_pos = 10 + 20 + 30 = 60; pol_neg = 11 + 21 + 31 = 63 > 60: theta_hat += 2^31 (mod 2^32) at
    # step 11, flipped = 1; the PLL angle (0: gains 0) is turned too, to 2^31.
    # e.g. 0x12345678 -> 0x92345678; 0x90000000 -> 0x10000000; 0x7FFFFFFF -> 0xFFFFFFFF.
    fw, outs = run_polarity(theta0, [10, 20, 30], [11, 21, 31])
    expected = {0x12345678: 0x92345678, 0x90000000: 0x10000000, 0: 0x80000000,
                0x7FFFFFFF: 0xFFFFFFFF}[theta0]
    assert (fw.pol_pos, fw.pol_neg) == (60, 63)
    assert fw.flipped == 1
    assert fw.theta_hat == expected
    assert fw.slots[0].pll == PllState(HALF_TURN, 0, 0)
    assert fw.mode == MODE_RELAX
    # outputs: the angle before the decision in steps 1..10, the turned one from step 11 on
    assert all((o.sin, o.cos) == sincos_q15(theta0) for o in outs[:10])
    assert (outs[10].sin, outs[10].cos) == sincos_q15(expected)
    # stays turned afterwards (gamma = 0)
    o = fw.step(win(), speed_ref=0)
    assert fw.theta_hat == expected and fw.mode == MODE_RUN and fw.flipped == 1
    assert (o.sin, o.cos) == sincos_q15(expected)


@pytest.mark.parametrize("gd_pos, gd_neg, pos, neg", [
    ([10, 20, 30], [10, 20, 29], 60, 59),        # positive pulse larger: no flip
    ([10, 20, 30], [30, 20, 10], 60, 60),        # equal: no flip (strict comparison)
    ([-5, -5, -5], [-6, -6, -6], -15, -18),      # negative sums: -15 > -18, no flip
])
def test_polarity_no_flip(gd_pos, gd_neg, pos, neg):
    fw, outs = run_polarity(0x12345678, gd_pos, gd_neg)
    assert (fw.pol_pos, fw.pol_neg) == (pos, neg)
    assert fw.flipped == 0
    assert fw.theta_hat == 0x12345678
    assert fw.slots[0].pll == PllState(0, 0, 0)
    assert fw.mode == MODE_RELAX
    assert all((o.sin, o.cos) == sincos_q15(0x12345678) for o in outs)


def test_polarity_flip_with_negative_sums():
    # pol_pos = -30, pol_neg = -3 > -30: flip
    fw, _ = run_polarity(0x00000001, [-10, -10, -10], [-1, -1, -1])
    assert (fw.pol_pos, fw.pol_neg, fw.flipped, fw.theta_hat) == (-30, -3, 1, 0x80000001)


# ---- bang-bang sign convention -----------------------------------------------------------------------
def test_bangbang_sign_convention():
    # n_converge large: stays in CONVERGE (estimator running, references 0). K_BB = 1000.
    # theta_hat: 0 -(+5)-> 1000 -(+1)-> 2000 -(-1)-> 1000 -(0)-> 1000 -(-7)-> 0
    #   -(-1)-> 2^32 - 1000 = 4_294_966_296 -(-2^31)-> 4_294_965_296 -(+2^31-1)-> 4_294_966_296
    #   -(+3)-> 0 (wraps) -(0)-> 0
    fw = Firmware(params(n_converge=1000))
    gammas = [5, 1, -1, 0, -7, -1, -(1 << 31), (1 << 31) - 1, 3, 0]
    expected = [1000, 2000, 1000, 1000, 0, 4_294_966_296, 4_294_965_296, 4_294_966_296, 0, 0]
    got = []
    for g, th in zip(gammas, expected):
        o = fw.step(win(gamma=g), speed_ref=0)
        got.append(fw.theta_hat)
        assert (o.sin, o.cos) == sincos_q15(th)
        assert fw.mode == MODE_CONVERGE
    assert got == expected


def test_bangbang_wraps_at_the_top():
    # theta_hat = 2^32 - 10, gamma > 0: 2^32 - 10 + 1000 - 2^32 = 990
    fw = firmware(params(n_converge=1000), TURN - 10)
    fw.step(win(gamma=1), speed_ref=0)
    assert fw.theta_hat == 990


def test_bangbang_paper_step():
    # K_BB = 27_344_161 (spec 5.2, 200 rad/s at 5 kHz): two steps up, one down from 0 -> 27_344_161
    fw = Firmware(params(n_converge=1000, k_bb=27_344_161))
    for g in (100, 100, -100):
        fw.step(win(gamma=g), speed_ref=0)
    assert fw.theta_hat == 27_344_161


# ---- software overcurrent ----------------------------------------------------------------------------
FAULT_OUT = Outputs(v_d=0, v_q=0, v_h=0, sin=0, cos=32767, enable=0, i_d_ref=0, i_q_ref=0)


@pytest.mark.parametrize("sum_id, sum_iq", [
    (10_010, 0),      # i_d mean c_div(10010, 10) = 1001 > 1000
    (-10_019, 0),     # c_div(-10019, 10) = -1001 (toward zero from -1001.9), |.| > 1000
    (0, 10_010),      # i_q mean 1001
    (0, -10_010),     # i_q mean -1001
])
def test_software_overcurrent_trips_and_latches(sum_id, sum_iq):
    fw = firmware(params(), 0x40000000)
    fw.step(win(gamma=5), speed_ref=0)                     # theta_hat 0x40000000 + 1000
    o = fw.step(win(gamma=5, sum_id=sum_id, sum_iq=sum_iq), speed_ref=0)
    assert fw.mode == MODE_FAULT
    assert o == FAULT_OUT
    assert o.enable == 0 and (o.v_d, o.v_q, o.v_h) == (0, 0, 0)
    # the tripping window does not move theta_hat (the estimator is skipped in FAULT)
    assert fw.theta_hat == 0x40000000 + 1000
    # stays in FAULT with normal windows, estimator frozen, integrators cleared
    for g in (5, -5, 0, 7):
        o = fw.step(win(gamma=g), speed_ref=500)
        assert fw.mode == MODE_FAULT and o == FAULT_OUT
        assert fw.theta_hat == 0x40000000 + 1000
        assert (fw.id_int, fw.iq_int, fw.i_d_ref, fw.i_q_ref) == (0, 0, 0, 0)


@pytest.mark.parametrize("sum_id, sum_iq", [(10_000, 0), (-10_009, 0), (0, 10_009), (10_009, -10_009)])
def test_software_overcurrent_boundary_does_not_trip(sum_id, sum_iq):
    # means 1000, -1000 (c_div(-10009, 10) = -1000), 1000: |mean| = i_trip is not beyond the limit
    fw = Firmware(params())
    o = fw.step(win(sum_id=sum_id, sum_iq=sum_iq), speed_ref=0)
    assert fw.mode == MODE_CONVERGE and o.enable == 1


def test_software_overcurrent_in_run_and_fixed():
    fw = Firmware(params())
    for _ in range(12):
        fw.step(win(), speed_ref=0)
    assert fw.mode == MODE_RUN
    assert fw.step(win(sum_iq=-20_000), speed_ref=0) == FAULT_OUT and fw.mode == MODE_FAULT
    fw = Firmware(params(fixed_angle=123))
    assert fw.step(win(sum_id=20_000), speed_ref=0) == FAULT_OUT and fw.mode == MODE_FAULT
    assert fw.step(win(), speed_ref=0) == FAULT_OUT and fw.mode == MODE_FAULT


# ---- fixed-angle mode --------------------------------------------------------------------------------
@pytest.mark.parametrize("angle, theta", [(0x40000000, 0x40000000), (0, 0), (-1, 0xFFFFFFFF),
                                          (TURN + 5, 5)])
def test_fixed_angle_mode(angle, theta):
    fw = Firmware(params(fixed_angle=angle))
    assert fw.mode == MODE_FIXED and fw.theta_hat == theta
    s, c = sincos_q15(theta)
    for g, gd in ((10**6, 5), (-10**6, -5), (0, 0), (1, 10**6)):
        # SUM_ID = -505, SUM_IQ = 300, N = 10: means -50, 30; references 0:
        # V_D = clamp(0 - (-50)) = 50, V_Q = clamp(0 - 30) = -30
        o = fw.step(win(gamma=g, gamma_d=gd, sum_id=-505, sum_iq=300), speed_ref=999)
        assert fw.mode == MODE_FIXED
        assert fw.theta_hat == theta
        assert o == Outputs(v_d=50, v_q=-30, v_h=V_H, sin=s, cos=c, enable=1, i_d_ref=0, i_q_ref=0)
        assert fw.slots[0].pll == PllState(0, 0, 0)      # estimator off
    assert fw.flipped == 0 and fw.pol_pos == 0 and fw.pol_neg == 0


# ---- sin/cos outputs ---------------------------------------------------------------------------------
@pytest.mark.parametrize("theta0", [0, 0x20000000, 0x40000000, 0x80000000, 0xC0000000, 0xFFFFFC18,
                                    0x2AAAAAAB, 0xDEADBEEF])
def test_sin_cos_follow_theta_hat(theta0):
    # CONVERGE, gamma > 0: theta_hat = theta0 + 1000 (mod 2^32); then gamma < 0: back to theta0
    fw = firmware(params(n_converge=1000), theta0)
    o = fw.step(win(gamma=1), speed_ref=0)
    t1 = (theta0 + 1000) % TURN
    assert fw.theta_hat == t1 and (o.sin, o.cos) == sincos_q15(t1)
    o = fw.step(win(gamma=-1), speed_ref=0)
    assert fw.theta_hat == theta0 and (o.sin, o.cos) == sincos_q15(theta0)


def test_params_are_frozen():
    p = params()
    with pytest.raises(dataclasses.FrozenInstanceError):
        p.low = 2   # type: ignore[misc]
