"""Host-side configuration: physical controller settings -> register values and firmware integers.

Everything the FPGA registers and the firmware need is computed here once, from the scenario's
``[control]``, ``[pwm]``, ``[inverter]`` and ``[sensors]`` settings and the motor's nominal data
(as a user tunes a drive from the data sheet: the plant's saturation, friction and sensor errors
are not known to the controller). Scales (docs/spec.md, section 3):

* current: 1 LSB = ``I_FS / 2^15`` with ``I_FS`` the ADC range;
* voltage: 1 LSB = ``V_dc / 2^15`` (nominal dc link);
* speed: 1 LSB = one binary-angle unit (2^-32 turn) per PWM period, electrical.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from golden.firmware.bangbang import k_bb_raw
from golden.firmware.estimator import METHOD_RFO, METHOD_SQW_BANGBANG
from golden.firmware.lowpass import lowpass_coef
from golden.firmware.pi import PiParams, pi_gains
from golden.firmware.pll import pll_gains
from golden.firmware.rfo import FLUX_FRAC, RfoParams
from golden.firmware.sqw_bangbang import SqwParams
from golden.firmware.supervisor import FirmwareParams
from golden.scenario import HIGH_ESTIMATORS, LOW_ESTIMATORS
from golden.fixed import to_fixed
from golden.fpga.adc_trigger import MODE_DS, MODE_OS, MODE_OS_BLANK, effective_os_ticks
from golden.fpga.cordic import cw_angle_step
from golden.fpga.deadtime_comp import recip_half
from golden.scenario import Scenario

ADC_MODE = {"OS": MODE_OS, "DS": MODE_DS, "OS_BLANK": MODE_OS_BLANK}


@dataclass(frozen=True)
class Scales:
    """Physical value of one LSB of each format."""

    i_lsb: float      # A
    v_lsb: float      # V
    w_lsb: float      # rad/s electrical
    f_sw: float
    pole_pairs: int

    def current(self, amps: float) -> int:
        return to_fixed(amps / self.i_lsb, 0)

    def voltage(self, volts: float) -> int:
        return to_fixed(volts / self.v_lsb, 0)

    def speed_mech(self, omega_m: float) -> int:
        """Mechanical rad/s -> electrical binary angle per period."""
        return to_fixed(omega_m * self.pole_pairs / self.w_lsb, 0)


@dataclass(frozen=True)
class HardwareConfig:
    """Register values written once at start-up (docs/registers.md)."""

    pwm_half: int
    dead_ticks: int
    os_ticks: int
    blank_ticks: int
    cw_angle_step: int
    adc_mode: int
    adc_bits: int
    dtc_gain: int = 0            # dead-time compensation (0: off), ticks per current LSB, Q8
    hf_amp: int = 0              # predicted HF d-current amplitude [current LSB]
    recip_h: int = 0             # round(2^32 / H)
    adc_offset: tuple[int, int] = (0, 0)
    adc_gain: tuple[int, int] = (16384, 16384)
    inj_rot: int = 0             # CTRL.INJ_ROT: 1 = rotating injection (golden.fpga.rot_injection)
    inj_step: int = 0            # INJ_STEP: its phase advance per PWM period (u32 binary angle)


def scales(sc: Scenario) -> Scales:
    f_sw = sc.pwm.f_sw
    return Scales(i_lsb=sc.plant["sens"]["adc_range"] / 2**15, v_lsb=sc.plant["inv"]["V_dc"] / 2**15,
                  w_lsb=2 * math.pi * f_sw / 2**32, f_sw=f_sw, pole_pairs=int(sc.plant["mech"]["pole_pairs"]))


def hardware_config(sc: Scenario) -> HardwareConfig:
    tick_hz, ctl = sc.pwm.tick_hz, sc.control
    half = round(tick_hz / (2 * sc.pwm.f_sw))
    sc_ = scales(sc)
    dead = round(sc.pwm.dead_time * tick_hz)
    mag = sc.plant["mag"]
    # eq. (17): the HF d-current is a triangle of amplitude V_h / (4 f_sw L_d)
    hf_amp = min(sc_.current(sc.injection.V_h / (4 * sc.pwm.f_sw * mag["L_d"])), 32767)
    dtc_gain = min(to_fixed(dead / max(sc_.current(ctl.dtc_zone), 1), 8), 65535) if ctl.dead_time_comp == "on" else 0
    return HardwareConfig(
        dtc_gain=dtc_gain, hf_amp=hf_amp, recip_h=recip_half(half),
        pwm_half=half, dead_ticks=round(sc.pwm.dead_time * tick_hz),
        os_ticks=effective_os_ticks(min(round(ctl.sample_interval * tick_hz), 0xFFFF)), blank_ticks=round(ctl.blank * tick_hz),
        cw_angle_step=cw_angle_step(half), adc_mode=ADC_MODE[ctl.adc_mode],
        adc_bits=int(sc.plant["sens"]["adc_bits"]))


def firmware_params(sc: Scenario) -> FirmwareParams:
    """Firmware integers from the control settings and the motor's nominal data.

    Current PIs: technical optimum on the nominal L and R (k_p = L·ω_c, k_i = R·ω_c, ω_c = 2π·current_bw).
    Speed PI: k_p = J·ω_s / (K_t·p) [A per electrical rad/s], integral zero at ω_s/4 (ω_s = 2π·speed_bw),
    with K_t = 1.5·p·ψ_f.
    """
    ctl, sc_ = sc.control, scales(sc)
    f_sw = sc.pwm.f_sw
    mag, mech = sc.plant["mag"], sc.plant["mech"]
    L = 0.5 * (mag["L_d"] + mag["L_q"])
    w_c = 2 * math.pi * ctl.current_bw
    v_lim = min(sc_.voltage(ctl.v_max), 32767)
    kp, ki = pi_gains(L * w_c, sc.plant["R_s"] * w_c, sc_.i_lsb / sc_.v_lsb, f_sw, sp=16, si=16)
    cur_pi = PiParams(kp, 16, ki, 16, v_lim)
    p = int(mech["pole_pairs"])
    k_t = 1.5 * p * mag["psi_f"]
    w_s = 2 * math.pi * ctl.speed_bw
    kp_w = mech["J"] * w_s / (k_t * p)
    kp_s, ki_s = pi_gains(kp_w, kp_w * w_s / 4, sc_.w_lsb / sc_.i_lsb, f_sw, sp=24, si=31)
    speed_pi = PiParams(kp_s, 24, ki_s, 31, sc_.current(ctl.i_max))
    fixed = to_fixed(ctl.theta_hat / (2 * math.pi), 32) % 2**32 if ctl.mode == "fixed_angle" else None
    est = sc.estimator
    low, high = LOW_ESTIMATORS[est.low], HIGH_ESTIMATORS[est.high]
    methods = {low, high}
    return FirmwareParams(
        low=low, high=high,
        sqw=sqw_params(sc) if METHOD_SQW_BANGBANG in methods else None,
        rfo=rfo_params(sc) if METHOD_RFO in methods else None,
        speed_lp=lowpass_coef(ctl.speed_filter, f_sw), speed_pi=speed_pi, id_pi=cur_pi, iq_pi=cur_pi,
        v_h=sc_.voltage(sc.injection.V_h), i_pulse=sc_.current(ctl.i_pulse),
        n_converge=round(ctl.converge * f_sw), n_pulse=round(ctl.pulse * f_sw), n_settle=round(ctl.settle * f_sw),
        i_trip=sc_.current(ctl.i_trip),
        w_up=sc_.speed_mech(est.handover_up), w_down=sc_.speed_mech(est.handover_down),
        merge=lowpass_coef(1.0 / (2 * math.pi * est.merge_time), f_sw), fixed_angle=fixed)


def sqw_params(sc: Scenario) -> SqwParams:
    """``estimator.sqw_bangbang``: bang-bang step and PLL gains (Benevieri et al. 2023, Table II)."""
    t, f_sw = sc.estimator.params["sqw_bangbang"], sc.pwm.f_sw
    kp, ki = pll_gains(t["pll_kp"], t["pll_ki"], f_sw)
    return SqwParams(k_bb=k_bb_raw(t["K_bb"], f_sw), pll_kp=kp, pll_ki=ki)


def rfo_params(sc: Scenario) -> RfoParams:
    """``estimator.rfo`` and the motor's nominal data: the flux-observer integers (golden.firmware.rfo).

    Flux LSB = v_lsb T / 2^FLUX_FRAC; ``r_s`` = R_s i_lsb / v_lsb (Q16); ``l_s`` = L_q i_lsb / flux LSB
    (Q16); ``k_c = 1 - exp(-2 pi flux_bw T)`` (Q16); ``i_d = -i_d_min`` [current LSB]. Raises ValueError when a value leaves its range.
    """
    t, sc_ = sc.estimator.params["rfo"], scales(sc)
    f_sw = sc.pwm.f_sw
    flux_lsb = sc_.v_lsb / f_sw / 2**FLUX_FRAC
    mag = sc.plant["mag"]
    kp, ki = pll_gains(t["pll_kp"], t["pll_ki"], f_sw)
    p = RfoParams(r_s=to_fixed(sc.plant["R_s"] * sc_.i_lsb / sc_.v_lsb, 16),
                  l_s=to_fixed(mag["L_q"] * sc_.i_lsb / flux_lsb, 16),
                  psi_f=to_fixed(mag["psi_f"] / flux_lsb, 0),
                  k_c=lowpass_coef(t["flux_bw"], f_sw), pll_kp=kp, pll_ki=ki, i_d=-sc_.current(t["i_d_min"]))
    for name, value, hi in (("r_s", p.r_s, 2**31 - 1), ("l_s", p.l_s, 2**31 - 1), ("psi_f", p.psi_f, 2**27)):
        if not 0 <= value <= hi:
            raise ValueError(f"rotor flux observer: {name} = {value} outside 0..{hi} (motor data and scales "
                             f"of scenario {sc.name})")
    return p
