"""Fault checks of the firmware (golden/firmware/protection.py, docs/faults.md) against the motor equations
and the filter's closed form, and the supervisor's reaction. The C twin: tests/test_fw_c.py."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from golden.control_config import firmware_params, protection_params, scales
from golden.firmware.pi import PiParams
from golden.firmware.protection import (FAULT_LOCK_LOSS, FAULT_NONE, FAULT_OVERLOAD, FAULT_OVERSPEED,
                                        FAULT_HF_RESPONSE, FAULT_TRACKING, SLIP_AGREE, SLIP_TRIP, ProtParams,
                                        emf_residual, hf_learn, protect_step, slip_check)
from golden.firmware.sqw_bangbang import SqwParams
from golden.firmware.supervisor import MODE_CONVERGE, MODE_FAULT, MODE_RUN, Firmware, FirmwareParams, Outputs
from golden.fpga.cordic import sincos_q15
from golden.fpga.demodulator import WindowResult
from golden.scenario import load_scenario

# Table I motor in the formats of scenarios/fullload_start.toml (12.5 A, 560 V, 5 kHz)
R, L_D, L_Q, PSI_F = 3.0, 5.59e-3, 6.26e-3, 0.147
I_LSB, V_LSB, F_SW = 12.5 / 2**15, 560 / 2**15, 5e3
W_LSB = 2 * math.pi * F_SW / 2**32
FLUX = 2 * math.pi * F_SW / V_LSB                         # flux LSB per V*s
P = ProtParams(r=round(R * I_LSB / V_LSB * 2**16), ld=round(L_D * I_LSB * FLUX * 2**16),
               lq=round(L_Q * I_LSB * FLUX * 2**16), psi_f=round(PSI_F * FLUX))


def level(e: tuple[int, int]) -> int:
    """|e_d| + |e_q| of one period's residual."""
    return abs(e[0]) + abs(e[1])


def steady_voltage(omega: float, i_d: float, i_q: float) -> tuple[int, int]:
    """v_d, v_q [LSB] of the steady-state stator equation at electrical speed omega [rad/s]."""
    v_d = R * i_d - omega * L_Q * i_q
    v_q = R * i_q + omega * (PSI_F + L_D * i_d)
    return round(v_d / V_LSB), round(v_q / V_LSB)


@pytest.mark.parametrize("rpm, i_d, i_q", [(0, 0.0, 2.27), (50, -0.5, 2.0), (250, 0.3, -2.2), (-1000, 0.0, 1.0)])
def test_residual_vanishes_on_the_motor_equation_and_measures_a_speed_error(rpm, i_d, i_q):
    omega = rpm * math.pi / 30 * 4
    v_d, v_q = steady_voltage(omega, i_d, i_q)
    args = (round(i_d / I_LSB), round(i_q / I_LSB), round(omega / W_LSB))
    assert level(emf_residual(P, v_d, v_q, *args)) <= 3              # rounding of the LSB conversions
    # a speed estimate 100 r/min low leaves (delta omega) psi_d in e_q and (delta omega) L_q i_q in e_d
    d_omega = 100 * math.pi / 30 * 4
    lagging = (*args[:2], round((omega - d_omega) / W_LSB))
    want = d_omega * ((PSI_F + L_D * i_d) + L_Q * abs(i_q)) / V_LSB
    assert level(emf_residual(P, v_d, v_q, *lagging)) == pytest.approx(want, abs=4)


def test_lock_check_fires_when_the_filter_crosses_the_limit_and_the_limit_grows_with_speed():
    """A constant residual x through the shift filter (2^k periods): 1 - (1 - 2^-k)^n of x (floored, so within
    a period)."""
    k, tol, x = 5, 1000, 3000
    p = replace(P, emf_k=k, emf_tol=tol)
    st = Firmware(_params())
    n = next(j for j in range(1, 1000) if x * (1 - (1 - 2.0**-k) ** j) > tol + 1)
    codes = [protect_step(st, p, 0, x, 0, 0, 0, 0, 0, 0, False) for _ in range(n + 1)]   # i = 0, omega = 0: |v_q|
    first = codes.index(FAULT_LOCK_LOSS)               # step first + 1: the closed form's step n, or one later
    assert first in (n - 1, n) and codes[:first] == [FAULT_NONE] * first, (n, codes)
    # at speed w the limit is emf_tol + shr(|w| psi_rel, 32): v_q = x + the back-EMF of w leaves e_q = x
    w = 2**26
    p_rel = replace(p, psi_rel=-(-(x - tol + 1) * 2**32 // w))
    v_q = x + ((w * P.psi_f) >> 32)
    st = Firmware(_params())
    assert emf_residual(p_rel, 0, v_q, 0, 0, w) == (0, x)
    assert FAULT_LOCK_LOSS not in [protect_step(st, p_rel, 0, v_q, 0, 0, 0, 0, w, 0, False) for _ in range(3 * n)]


def test_lock_check_filters_the_signed_components():
    """A residual that alternates in sign (an L di/dt the steady-state model leaves out, a current ripple) averages
    away in the signed filters and never trips; the same magnitude held in one direction trips."""
    k, tol, x = 5, 1000, 3000
    p = replace(P, emf_k=k, emf_tol=tol)
    st = Firmware(_params())
    codes = [protect_step(st, p, 0, x if j % 2 else -x, 0, 0, 0, 0, 0, 0, False) for j in range(2000)]
    assert FAULT_LOCK_LOSS not in codes and abs(st.emf_q) <= x >> (k - 1)
    st = Firmware(_params())
    assert FAULT_LOCK_LOSS in [protect_step(st, p, x, 0, 0, 0, 0, 0, 0, 0, False) for _ in range(200)]


def test_sensor_check_learns_the_level_and_trips_on_the_filtered_deviation():
    """hf_learn: ref += (g - ref) >> k from 0; in RUN |GAMMA_D - ref| through the same filter against
    floor(ref * tol / 2^16); a window without the whole square wave (None) zeroes the filter."""
    k, tol, g = 2, 5898, 1_000_000                   # 9 % of the level
    p = replace(P, hf_k=k, hf_tol=tol)
    st = Firmware(_params())
    ref = 0
    for _ in range(100):
        hf_learn(st, p, g)
        ref += (g - ref) >> k
    assert st.hf_ref == ref and g - 4 <= ref <= g    # the floored filter stops within 2^k of the level
    limit = (ref * tol) >> 16
    step = lambda hf: protect_step(st, p, 0, 0, 0, 0, 0, 0, 0, 0, False, hf)   # noqa: E731
    # a constant deviation of exactly the limit: the filter climbs to within 2^k of it, never above
    assert [step(ref + limit) for _ in range(60)] == [FAULT_NONE] * 60 and limit - 2**k < st.hf_f <= limit
    assert step(ref - 8 * limit) == FAULT_HF_RESPONSE     # a deviation of either sign: one period crosses it
    assert step(None) == FAULT_NONE and st.hf_f == 0
    # off (hf_tol 0) or no level learned: nothing
    assert protect_step(Firmware(_params()), replace(p, hf_tol=0), 0, 0, 0, 0, 0, 0, 0, 0, False, 0) == FAULT_NONE
    fresh = Firmware(_params())
    assert protect_step(fresh, p, 0, 0, 0, 0, 0, 0, 0, 0, False, 10**6) == FAULT_NONE and fresh.hf_f == 0


def test_tracking_overload_and_overspeed():
    p = replace(P, track_k=0, track_tol=100, ovl_n=5, w_max=1000)
    st = Firmware(_params())
    assert protect_step(st, p, 0, 0, 0, 0, 60, -40, 0, 0, False) == FAULT_NONE      # |60| + |-40| = 100: not above
    assert protect_step(st, p, 0, 0, 0, 0, 60, -41, 0, 0, False) == FAULT_TRACKING
    st = Firmware(_params())
    codes = [protect_step(st, p, 0, 0, 0, 0, 0, 0, 0, 0, True) for _ in range(5)]
    assert codes == [FAULT_NONE] * 4 + [FAULT_OVERLOAD]
    protect_step(st, p, 0, 0, 0, 0, 0, 0, 0, 0, False)
    assert st.ovl_n == 0                                             # a period off the limit restarts the count
    assert protect_step(st, p, 0, 0, 0, 0, 0, 0, -1001, 0, True) == FAULT_OVERSPEED  # first in the order
    assert protect_step(st, p, 0, 0, 0, 0, 0, 0, -1000, 0, True) == FAULT_NONE
    # at the limit with the speed error grown by more than ovl_w since the limit was reached, ovl_m periods
    p = replace(p, ovl_n=0, ovl_w=300, ovl_m=3, w_max=0)
    st = Firmware(_params())
    assert protect_step(st, p, 0, 0, 0, 0, 0, 0, 50, 100, True) == FAULT_NONE       # the limit: e0 = 50
    assert st.e0 == 50
    codes = [protect_step(st, p, 0, 0, 0, 0, 0, 0, w, 100, True) for w in (-250, -251, -252, -253)]
    assert codes == [FAULT_NONE] * 3 + [FAULT_OVERLOAD]              # 350 - 50 = 300: not above; then 3 periods
    st = Firmware(_params())
    protect_step(st, p, 0, 0, 0, 0, 0, 0, 50, 100, True)
    codes = [protect_step(st, p, 0, 0, 0, 0, 0, 0, w, 100, limit)
             for w, limit in ((-251, True), (-252, True), (-253, False), (-254, True), (-255, True), (-256, True))]
    assert codes == [FAULT_NONE] * 6 and st.e0 == 354                # off the limit: e0 taken anew
    st = Firmware(_params())
    codes = [protect_step(st, p, 0, 0, 0, 0, 0, 0, w, 100, True) for w in (-500, -300, -100, 0, 50)]
    assert FAULT_OVERLOAD not in codes                                # the error shrinks: a reference step


def _params(**kw) -> FirmwareParams:
    pi = PiParams(kp=1 << 16, sp=16, ki=1 << 10, si=16, limit=2000)
    base = dict(low=1, high=0, sqw=SqwParams(27_342_611, 2621, 6711), rfo=None, speed_lp=2425, speed_pi=pi,
                id_pi=pi, iq_pi=pi, v_h=5851, i_pulse=300, n_converge=3, n_pulse=4, n_settle=1, i_trip=1000)
    base.update(kw)
    return FirmwareParams(**base)


def _running(p: FirmwareParams, speed: int) -> Firmware:
    fw = Firmware(p)
    fw.mode, fw.speed_f, fw.est_omega = MODE_RUN, speed << 16, [speed, 0]
    return fw


@pytest.mark.parametrize("speed, asc", [(10_000, 0), (-30_000, 1)])
def test_a_fault_in_run_stops_the_outputs_or_shorts_the_motor(speed, asc):
    """A tracking fault in RUN: FAULT with its code; below w_asc the gates off (the reset outputs), above it
    zero voltage with the outputs on (the active short circuit), kept in the following periods."""
    p = _params(prot=ProtParams(track_k=0, track_tol=10, w_asc=20_000))
    fw = _running(p, speed)
    fw.i_d_ref = 500                                                 # the last reference; the mean is 0
    out = fw.step(WindowResult(gamma=0, gamma_d=0, sum_id=0, sum_iq=0, wsum=0, n_samples=10), speed)
    assert (fw.mode, fw.fault, fw.asc) == (MODE_FAULT, FAULT_TRACKING, asc)
    want = Outputs(0, 0, 0, *sincos_q15(fw.theta_hat), 1) if asc else Outputs(0, 0, 0, 0, 32767, 0)
    assert out == want
    later = fw.step(WindowResult(gamma=0, gamma_d=0, sum_id=0, sum_iq=0, wsum=0, n_samples=10), speed)
    assert later.enable == asc and (later.v_d, later.v_q, later.v_h) == (0, 0, 0)


def test_restart_after_the_delay_at_most_restarts_times():
    """A fault with restarts = 2, restart_n = 3: the tripping period and three more in FAULT, then CONVERGE with
    every state as at
    power-up (the estimator's too) but the fault code, the count and the output history; after the second
    restart's fault, FAULT holds."""
    p = _params(prot=ProtParams(track_k=0, track_tol=10, restarts=2, restart_n=3))
    fw = _running(p, 1000)
    win = WindowResult(gamma=0, gamma_d=0, sum_id=0, sum_iq=0, wsum=0, n_samples=10)
    modes = []
    for k in range(40):
        if fw.mode == MODE_RUN:
            fw.i_d_ref = 500                                         # the tracking check fires in RUN
        fw.step(win, 0)
        modes.append(fw.mode)
    first = modes.index(MODE_FAULT)
    assert modes[first:first + 5] == [MODE_FAULT] * 4 + [MODE_CONVERGE]
    assert fw.restarts == 2 and fw.fault == FAULT_TRACKING and modes[-1] == MODE_FAULT
    assert modes.count(MODE_CONVERGE) == 2 * (p.n_converge - 1)     # two start-ups (CONVERGE leaves at n_converge)
    fresh = _running(p, 1000)
    fw2 = _running(p, 1000)
    fw2.i_d_ref = 500
    fw2.step(win, 0)                                                 # trips
    for _ in range(4):
        fw2.step(win, 0)                                             # the fourth: restart, then CONVERGE's first step
    ref = Firmware(p)
    ref.step(win, 0)
    assert (fw2.mode, fw2.n, fw2.speed_f, fw2.slots[0].pll, fw2.restarts) == (ref.mode, ref.n, ref.speed_f,
                                                                             ref.slots[0].pll, 1)
    assert fresh.restarts == 0


def test_protection_params_of_the_default_scenario():
    """The integers from the scenario's motor and formats (docs/faults.md defaults)."""
    sc = load_scenario("scenarios/fullload_start.toml")
    s, p = scales(sc), protection_params(sc)
    flux = 2 * math.pi * s.f_sw / s.v_lsb
    assert (p.r, p.ld, p.lq, p.psi_f) == (round(R * s.i_lsb / s.v_lsb * 2**16), round(L_D * s.i_lsb * flux * 2**16),
                                          round(L_Q * s.i_lsb * flux * 2**16), round(PSI_F * flux))
    assert p.emf_tol == round(0.06 * 560 / s.v_lsb) and p.psi_rel == round(0.25 * PSI_F * flux)
    assert p.track_tol == round(3.0 / s.i_lsb) and p.ovl_n == round(0.5 * 5e3)
    assert (p.emf_k, p.track_k) == (5, 7)                             # 25 -> 32 and 100 -> 128 periods
    assert (p.ovl_w, p.ovl_m) == (round(100 * math.pi / 30 * 4 / s.w_lsb), round(0.02 * 5e3))
    assert p.w_max == round((2 * 250 + 500) * math.pi / 30 * 4 / s.w_lsb)
    assert p.w_asc == round(560 / (math.sqrt(3) * 4 * PSI_F) * 4 / s.w_lsb)
    assert firmware_params(sc).prot == p
    off = replace(sc, protection=replace(sc.protection, checks="off"))
    assert protection_params(off) == ProtParams()
    flying = replace(off, protection=replace(off.protection, catch_time=0.04, catch_probe=0.05))   # the probe stays
    assert protection_params(flying) == ProtParams(catch_n=200, probe_min=round(0.05 / s.i_lsb), psi_f=p.psi_f)


def test_the_load_check_reads_the_motion_equation():
    """The overload check's load part: ``a = shr(ld_ct i_q + shr(ld_cr i_d i_q, 16), 24) - d omega`` per period
    through the shift filter. With ``ld_ct`` = 1.5 speed LSB per period per current LSB (Q24), no reluctance term and
    no filter (k = 0): the first period takes the speed only; a rotor that speeds up by 40 LSB a period under 100
    current LSB (150 of torque's acceleration) leaves 110 to a load; one that slows down by 40 brakes against 190,
    beyond a limit of 150."""
    p = replace(P, ld_ct=3 << 23, ld_cr=0, ld_k=0, ld_max=150)
    st = Firmware(_params())
    step = lambda w, i_d, i_q: protect_step(st, p, 0, 0, i_d, i_q, 0, 0, w, w, False)   # noqa: E731
    assert step(5000, 0, 100) == FAULT_NONE and (st.ld_w, st.ld_n, st.ld_f) == (5000, 1, 150)   # at the limit
    assert step(5040, 0, 100) == FAULT_NONE and (st.ld_w, st.ld_f) == (5040, 110)
    assert step(5000, 0, 100) == FAULT_OVERLOAD and (st.ld_w, st.ld_f) == (5000, 190)
    assert step(5000, 0, -100) == FAULT_NONE and st.ld_f == -150
    assert step(5000, 0, -101) == FAULT_OVERLOAD and st.ld_f == -152                # floor(-151.5)
    assert step(5000, 0, 40000) == FAULT_OVERLOAD and st.ld_f == (3 * 32767) >> 1    # i_q saturated to s16
    # the reluctance term: ld_cr = 1 (Q40) per LSB^2 gives i_d i_q; with -10 and 12: -120
    pr = replace(p, ld_ct=0, ld_cr=1 << 40)
    st2 = Firmware(_params())
    assert protect_step(st2, pr, 0, 0, -10, 12, 0, 0, 7, 7, False) == FAULT_NONE and st2.ld_f == -120
    # filtered (k = 2): a constant 200 from 0 reaches 200 (1 - (3/4)^n), floored: beyond 150 after 5 periods
    st3 = Firmware(_params())
    p3 = replace(p, ld_ct=2 << 24, ld_k=2)
    codes = [protect_step(st3, p3, 0, 0, 0, 100, 0, 0, 0, 0, False) for _ in range(5)]
    assert codes == [FAULT_NONE] * 4 + [FAULT_OVERLOAD]
    assert protect_step(Firmware(_params()), replace(p, ld_max=0), 0, 0, 0, 30000, 0, 0, 0, 0, False) == FAULT_NONE


def test_load_limits_from_the_scenario():
    """The load part's integers for the default scenario: the motion equation's ``n_p T_e / J`` of the Table I
    motor (J = 4e-3 kg m^2, 4 pole pairs) in binary angle per period^2, and the limit: the acceleration
    of its MTPA torque at i_max = 3 A (closed form) times 1.4, 20 ms -> 128 periods; off with ``load_max = 0``."""
    sc = load_scenario("scenarios/fullload_start.toml")
    s, p = scales(sc), protection_params(sc)
    acc = 4 * 1.5 * 4 / 4e-3 / F_SW**2 * 2**32 / (2 * math.pi)
    assert p.ld_ct == pytest.approx(acc * PSI_F * s.i_lsb * 2**24, abs=1)
    assert p.ld_cr == pytest.approx(acc * (L_D - L_Q) * s.i_lsb**2 * 2**40, abs=1)
    dl = L_Q - L_D
    i_d = (PSI_F - math.sqrt(PSI_F**2 + 8 * dl**2 * 3.0**2)) / (4 * dl)          # MTPA on |i| = 3 A
    i_q = math.sqrt(3.0**2 - i_d**2)
    t_max = 1.5 * 4 * (PSI_F * i_q - dl * i_d * i_q)
    assert p.ld_max == pytest.approx(1.4 * 4 * t_max / 4e-3 / F_SW**2 * 2**32 / (2 * math.pi), abs=1)
    assert p.ld_k == 7
    off = replace(sc, protection=replace(sc.protection, load_max=0.0))
    assert (protection_params(off).ld_ct, protection_params(off).ld_max) == (0, 0)
    tiny = replace(sc, protection=replace(sc.protection, load_max=1e-9))          # would round to "off"
    with pytest.raises(ValueError, match="protection.load_max: the limit rounds to 0"):
        protection_params(tiny)
    feather = replace(sc, plant={**sc.plant, "mech": {**sc.plant["mech"], "J": 1e-12}})   # gains beyond the C range
    with pytest.raises(ValueError, match="protection.load_max: the torque's gain ld_ct"):
        protection_params(feather)


class _SlipState:
    slip_left = 0


@pytest.mark.parametrize("after", [1, 4, 5, 9])
def test_the_slip_check_trips_only_within_its_time_of_an_agreement(after):
    """Agreement (within 45 deg, both speeds above slip_w, one sign) arms the check for slip_n = 5 periods: a gap
    beyond 90 deg ``after`` periods later trips while armed (1..4 periods after), not at 5 or later."""
    p, st = ProtParams(slip_w=1000, slip_n=5), _SlipState()
    assert slip_check(st, p, True, SLIP_AGREE - 1, 1001, 1200) == FAULT_NONE and st.slip_left == 5
    for _ in range(after - 1):
        assert slip_check(st, p, True, SLIP_AGREE, 1001, 1200) == FAULT_NONE     # 45 deg: no agreement, no trip
    want = FAULT_LOCK_LOSS if after < 5 else FAULT_NONE
    assert slip_check(st, p, True, -SLIP_TRIP - 1, 1001, 1200) == want and st.slip_left == max(5 - after, 0)


@pytest.mark.parametrize("low, w_f, w_hi", [(True, 1000, 1200), (True, 1200, 1000), (True, -1200, 1200),
                                            (True, 0, 0), (False, 1200, 1200)])
def test_the_slip_check_is_not_armed_by_slow_opposite_or_high_slot_periods(low, w_f, w_hi):
    """No agreement arms it with a speed at or below slip_w, speeds of opposite signs, or the high slot in charge
    (which disarms it): the gap of half a turn that follows does not trip."""
    p, st = ProtParams(slip_w=1000, slip_n=5), _SlipState()
    assert slip_check(st, p, low, 0, w_f, w_hi) == FAULT_NONE and st.slip_left == 0
    assert slip_check(st, p, True, -2**31, 1200, 1200) == FAULT_NONE


def test_the_slip_check_is_off_without_its_speed():
    st = _SlipState()
    st.slip_left = 3
    assert slip_check(st, ProtParams(slip_w=0, slip_n=5), True, 2**31 - 1, 1200, 1200) == FAULT_NONE
    assert st.slip_left == 3


def test_slip_limits_from_the_scenario():
    """With the rotor flux observer beside the HF estimator (fullrange_noload): the speed where p omega psi_f equals
    V_dc t_d f_sw (560 V, 4 us, 5 kHz: 11.2 V) and 5 ms = 25 periods; none on the default drive (no high slot)."""
    sc = load_scenario("scenarios/fullrange_noload.toml")
    s, p = scales(sc), protection_params(sc)
    assert (p.slip_w, p.slip_n) == (round(560 * 4e-6 * 5e3 / PSI_F / s.w_lsb), 25)
    default = protection_params(load_scenario("scenarios/fullload_start.toml"))
    assert (default.slip_w, default.slip_n) == (0, 0)
    off = replace(sc, protection=replace(sc.protection, slip_speed=0.0))
    assert (protection_params(off).slip_w, protection_params(off).slip_n) == (0, 0)


def test_the_soc_status_register_names_the_modes_and_faults_in_order():
    """rtl/regs/hfi_soc.rdl, FW_STATUS: its field descriptions list the supervisor's modes and the fault codes
    as golden numbers them (the firmware writes st.mode and st.fault there)."""
    import re
    from pathlib import Path
    from golden.firmware.protection import FAULT_NAMES
    from golden.firmware.supervisor import MODE_NAMES
    rdl = " ".join((Path(__file__).resolve().parents[1] / "rtl/regs/hfi_soc.rdl").read_text().split())
    modes = ", ".join(f"{k} {name}" for k, name in enumerate(MODE_NAMES))
    faults = ", ".join(f"{k} {name}" for k, name in enumerate(FAULT_NAMES))
    assert f"Supervisor mode: {modes}." in rdl
    assert re.search(rf"last fault: {re.escape(faults)}\.", rdl), faults


@pytest.mark.parametrize("status", [0x1, 0x2, 0x10, 0x20])
def test_a_hardware_trip_is_the_firmwares_fault_too(status):
    """A fault latch of STATUS (the hardware turned the gates off): FAULT with code hardware in any mode, before
    the software overcurrent; the outputs reset."""
    from golden.firmware.protection import FAULT_HARDWARE
    fw = _running(_params(), 1000)
    win = WindowResult(gamma=0, gamma_d=0, sum_id=5000, sum_iq=0, wsum=0, n_samples=1, status=status)
    assert fw.step(win, 0) == Outputs(0, 0, 0, 0, 32767, 0)          # |i_d| = 5000 > i_trip as well
    assert (fw.mode, fw.fault) == (MODE_FAULT, FAULT_HARDWARE)
