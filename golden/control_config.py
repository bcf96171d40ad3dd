"""Host-side configuration: physical controller settings -> register values and firmware integers.

Everything the FPGA registers and the firmware need is computed here once, from the scenario's
``[control]``, ``[pwm]``, ``[inverter]`` and ``[sensors]`` settings and the motor data the controller
knows (:func:`controller_motor`): the ``[model]`` table when the scenario has one (the values ``hfi
commission`` measured), else the plant's nominal data (as a user tunes a drive from the data sheet: the
plant's saturation, friction and sensor errors are not known to the controller). Scales (docs/spec.md,
section 3):

* current: 1 LSB = ``I_FS / 2^15`` with ``I_FS`` the ADC range;
* voltage: 1 LSB = ``V_dc / 2^15`` (nominal dc link);
* speed: 1 LSB = one binary-angle unit (2^-32 turn) per PWM period, electrical.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from golden.firmware import biquad
from golden.firmware.bangbang import k_bb_raw
from golden.firmware.eemf_smo import I_FRAC, SmoParams
from golden.firmware.estimator import (BY_ID, INJ_ROT, INJ_SQW_P, METHOD_EEMF_SMO, METHOD_HFO_PROJ, METHOD_RFO,
                                      METHOD_ROT_BPF, METHOD_SQW_BANGBANG, METHOD_SQW_CIC)
from golden.firmware.fcs_law import LAW_FCS_MPC, LAW_FOC_PWM, FcsParams
from golden.firmware.flux_lut import FLUX_FRAC
from golden.firmware.hfo_proj import HfoParams
from golden.firmware.lowpass import lowpass_coef
from golden.firmware.mtpa import mtpa_table
from golden.firmware.pi import PiParams, pi_gains
from golden.firmware.pll import pll_gains
from golden.firmware.protection import ProtParams
from golden.firmware.rfo import RfoParams
from golden.firmware.load_observer import LoadObsParams
from golden.firmware.rot_bpf import TRACK_OBSERVER, TRACK_PLL, RotParams
from golden.firmware.sqw_bangbang import SqwParams
from golden.firmware.sqw_cic import CicParams
from golden.firmware.supervisor import POL_CURRENT, POL_NONE, POL_PILOT, FirmwareParams
from golden.flux_tables import flux_lut, flux_reference_table, hf_inductances, nominal_motor
from golden.scenario import HIGH_ESTIMATORS, LOW_ESTIMATORS
from golden.fixed import sat, shr, to_fixed, uwrap, wrap
from golden.fpga.adc_trigger import MODE_DS, MODE_OS, MODE_OS_BLANK, effective_os_ticks
from golden.fpga.cordic import cw_angle_step, sincos_q15
from golden.fpga.deadtime_comp import recip_half
from golden.fpga.rot_injection import inj_step
from golden.plant import defaults as plant_defaults
from golden.plant.binding import MAG_KINDS, PlantError
from golden.regmap import OC_LIMIT_VALUE_RESET
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
    angle_period_deg: float = 360.0
    """The period of the machine in the electrical angle: 180 deg for a reluctance machine (no magnet: the
    d axis and its opposite look alike, so angle errors are reported modulo 180 deg), 360 otherwise."""

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
    inj_per: int = 0             # CTRL.INJ_PER: 1 = the square wave's sign holds a PWM period (spec 3.5)
    direct: int = 0              # CTRL.DIRECT: 1 = direct-vector mode, the FCS-MPC choice (spec 3.10)
    cic_m: int = 2               # CIC_M: comb delay of the CIC interpolator (golden.fpga.diff_cic)
    oc_limit: int = OC_LIMIT_VALUE_RESET  # OC_LIMIT: the hardware comparator's limit [current LSB] (spec 3.7)


@dataclass(frozen=True)
class ControllerMotor:
    """The motor data the controller is tuned from (:func:`controller_motor`), SI units.

    ``mag`` is a magnetic model dict of the plant's layout (``golden.plant.defaults``; the functions of
    golden.flux_tables and golden.plant.fluxmap take it). ``pole_pairs`` is always the scenario's (the name
    plate's). ``B``, ``T_c``: the friction of the model (the controller's tunings do not use them yet).
    """

    R_s: float
    mag: dict
    J: float
    pole_pairs: int
    B: float = 0.0
    T_c: float = 0.0


def linear_mag(L_d: float, L_q: float, psi_f: float) -> dict:
    """A complete linear magnetic model dict (``MAG_KINDS["linear"]``, the plant's layout) of the given
    inductances [H] and magnet flux [V*s]."""
    mag = plant_defaults.default_params()["mag"]
    mag.update(kind=MAG_KINDS["linear"], L_d=L_d, L_q=L_q, psi_f=psi_f)
    return mag


def algebraic_mag(coefficients: dict, psi_f: float) -> dict:
    """A complete algebraic magnetic model dict (``MAG_KINDS["algebraic"]``, golden.saturation_fit) of the given
    coefficients and exponents (``[model.saturation]``) and magnet flux [V*s]."""
    mag = plant_defaults.default_params()["mag"]
    mag.update(kind=MAG_KINDS["algebraic"], psi_f=psi_f, **coefficients)
    return mag


def controller_motor(sc: Scenario) -> ControllerMotor:
    """What the controller knows of its motor: the scenario's ``[model]`` table (``sc.model``, written by
    ``hfi commission``) as a linear magnetic model (the algebraic one of ``[model.saturation]`` when the table has
    it: a reluctance machine's), or, without it, the plant's own ``R_s``, ``mag`` and
    ``mech`` data (``mag`` is then the plant's dict itself, so the firmware's parameters are those of a
    drive tuned from the data sheet, unchanged from before ``[model]`` existed).

    With ``[model]`` the 003 method's flux maps (:func:`hfo_proj_params`' ``flux_lut``, :func:`fcs_params`'
    ``flux_reference_table``) are sampled from that model. ``pole_pairs`` is always the scenario's (``motor.pole_pairs`` or the preset's)."""
    mech = sc.plant["mech"]
    p = int(mech["pole_pairs"])
    m = sc.model
    if m is None:
        cm = ControllerMotor(R_s=sc.plant["R_s"], mag=sc.plant["mag"], J=mech["J"], pole_pairs=p,
                             B=mech["B"], T_c=mech["T_c"])
    else:
        mag = linear_mag(m.L_d, m.L_q, m.psi_f) if m.saturation is None else algebraic_mag(m.saturation, m.psi_f)
        cm = ControllerMotor(R_s=m.R_s, mag=mag, J=m.J, pole_pairs=p, B=m.B, T_c=m.T_c)
    e = sc.model_error
    if e is None:
        return cm
    # [model_error]: a deliberately wrong controller (robustness studies). On a flux-map model (the 003 preset)
    # the L factors change the nominal L_d, L_q only; its tables have estimator.hfo_proj.map_scale_d/q.
    mag = dict(cm.mag, L_d=cm.mag["L_d"] * e.L_d, L_q=cm.mag["L_q"] * e.L_q, psi_f=cm.mag["psi_f"] * e.psi_f)
    return replace(cm, R_s=cm.R_s * e.R_s, J=cm.J * e.J, mag=mag)


def scales(sc: Scenario) -> Scales:
    f_sw = sc.pwm.f_sw
    return Scales(i_lsb=sc.plant["sens"]["adc_range"] / 2**15, v_lsb=sc.plant["inv"]["V_dc"] / 2**15,
                  w_lsb=2 * math.pi * f_sw / 2**32, f_sw=f_sw, pole_pairs=int(sc.plant["mech"]["pole_pairs"]),
                  angle_period_deg=180.0 if sc.plant["mag"]["psi_f"] == 0 else 360.0)


def _beyond_float(exc: ArithmeticError) -> ValueError:
    """The net under the keyed checks (golden/limits.py, :func:`_named`, :func:`motion_gains`): a scenario value that
    no check names overflows a float or divides by zero while the registers or the firmware's integers are computed
    (tests/test_scenario_fuzz.py searches for them); one line instead of a traceback."""
    return ValueError(f"a scenario value is beyond the range the register values and the firmware's parameters are "
                      f"computed in ({exc})")


def hardware_config(sc: Scenario) -> HardwareConfig:
    """The hfi_dsp start-up register values of ``sc`` (a value beyond a float on the way: :func:`_beyond_float`)."""
    try:
        return _hardware_config(sc)
    except (OverflowError, ZeroDivisionError) as exc:
        raise _beyond_float(exc) from exc


def _hardware_config(sc: Scenario) -> HardwareConfig:
    tick_hz, ctl = sc.pwm.tick_hz, sc.control
    half = round(tick_hz / (2 * sc.pwm.f_sw))
    sc_ = scales(sc)
    dead = round(sc.pwm.dead_time * tick_hz)
    mag = controller_motor(sc).mag
    rot = rotating_injection(sc)
    # eq. (17): the HF d-current is a triangle of amplitude V_h / (4 f_sw L_d); the rotating injection's
    # current is predicted by the firmware instead (FirmwareParams.hf_dtc), so HF_AMP is 0 then
    direct = int(ctl.law == "fcs_mpc")
    # self-commissioning: no HF prediction (the amplitude is the program's, the inductance not yet known)
    ident = sc.control is not None and sc.control.mode == "commission"
    # the d inductance: the model's parameter (linear, dsat: at zero current), or for a model without one (algebraic,
    # table: a reluctance machine's) the nominal motor's, as the current PIs take it (the parameter dict's L_d is
    # then the defaults', 5.59 mH, whatever the machine)
    L_d = (mag["L_d"] if mag["kind"] in (MAG_KINDS["linear"], MAG_KINDS["dsat"])
           else nominal_motor(mag, controller_motor(sc).pole_pairs, 0.5 * ctl.i_max)["L_d"])
    hf_amp = 0 if rot or period_injection(sc) or direct or ident else min(sc_.current(sc.injection.V_h / (4 * sc.pwm.f_sw * L_d)), 32767)
    dtc_gain = min(to_fixed(dead / max(sc_.current(ctl.dtc_zone), 1), 8), 65535) if ctl.dead_time_comp == "on" else 0
    per = period_injection(sc)
    return HardwareConfig(
        inj_rot=int(rot), inj_step=injection_step(sc),
        inj_per=int(per), direct=direct, cic_m=sc.estimator.params["sqw_cic"]["cic_m"] if per else 2,
        dtc_gain=dtc_gain, hf_amp=hf_amp, recip_h=recip_half(half),
        pwm_half=half, dead_ticks=round(sc.pwm.dead_time * tick_hz),
        os_ticks=effective_os_ticks(min(round(ctl.sample_interval * tick_hz), 0xFFFF)), blank_ticks=round(ctl.blank * tick_hz),
        cw_angle_step=cw_angle_step(half), adc_mode=ADC_MODE[ctl.adc_mode],
        adc_bits=int(sc.plant["sens"]["adc_bits"]),
        oc_limit=OC_LIMIT_VALUE_RESET if ctl.oc_limit is None else sc_.current(ctl.oc_limit))


def injection_step(sc: Scenario) -> int:
    """``INJ_STEP`` of the scenario: the rotating injection's phase step (0 when no slot injects it)."""
    return inj_step(sc.estimator.params["rot_bpf"]["f_inj"], sc.pwm.f_sw) if rotating_injection(sc) else 0


def rotating_injection(sc: Scenario) -> bool:
    """Whether a slot's method injects the rotating vector (then ``CTRL.INJ_ROT`` is set at start-up)."""
    est = sc.estimator
    if sc.control is None or est is None:
        return False
    return any(BY_ID[m].injection == INJ_ROT for m in (LOW_ESTIMATORS[est.low], HIGH_ESTIMATORS[est.high]) if m)


def period_injection(sc: Scenario) -> bool:
    """Whether a slot's method injects the square wave that holds for a PWM period (``CTRL.INJ_PER``)."""
    est = sc.estimator
    if sc.control is None or est is None:
        return False
    return any(BY_ID[m].injection == INJ_SQW_P for m in (LOW_ESTIMATORS[est.low], HIGH_ESTIMATORS[est.high]) if m)


def rot_hf_current(sc: Scenario) -> int:
    """Tap et al. 2023, eq. (11): the positive-sequence HF current ``V_h L_0 / (w_h L_d L_q)`` [current LSB]
    of the rotating injection, which the firmware adds to the dead-time compensation's current."""
    sc_, t = scales(sc), sc.estimator.params["rot_bpf"]
    l_d, l_q = hf_inductances(controller_motor(sc).mag, -t["i_d_min"])
    w_h = 2 * math.pi * t["f_inj"]
    return min(sc_.current(sc.injection.V_h * 0.5 * (l_d + l_q) / (w_h * l_d * l_q)), 32767)


def _named(keys: str, make, *args):
    """``make(*args)`` (the gains of a PI, a PLL, the bang-bang step); a ValueError it raises (a gain beyond the
    firmware's 31 bits) names the scenario keys the value comes from, so ``hfi check`` and ``hfi run`` say which
    key to change."""
    try:
        return make(*args)
    except ValueError as exc:
        raise ValueError(f"{keys}: {exc}") from exc


def _at_least_one_lsb(key: str, value: float, unit: str, lsb: float, source: str) -> None:
    """A limit that rounds to 0 LSB would stop its controller: refuse it with the scale's LSB."""
    if round(value / lsb) < 1:
        raise ValueError(f"{key} = {value:g} {unit} is below one LSB of its scale ({lsb:.4g} {unit}, {source})")


def firmware_params(sc: Scenario) -> FirmwareParams:
    """Firmware integers from the control settings and the controller's motor data (:func:`controller_motor`).

    Current PIs: technical optimum on the nominal L and R (k_p = L·ω_c, k_i = R·ω_c, ω_c = 2π·current_bw).
    Speed PI: k_p = J·ω_s / (K_t·p) [A per electrical rad/s], integral zero at ω_s/4 (ω_s = 2π·speed_bw),
    with K_t = 1.5·p·ψ_f. A magnetic model the controller's tables cannot invert (the MTPA point, the flux tables)
    is reported with its source (a PlantError, a ValueError: one line on the command line); so is a value that
    overflows a float on the way (a ValueError), where no check names its key.
    """
    try:
        return _firmware_params(sc)
    except PlantError as exc:
        source = ("[model.saturation]" if sc.model is not None and sc.model.saturation is not None
                  else "[model]" if sc.model is not None else "the motor's magnetic model")
        raise PlantError(f"{source}: the controller's tables cannot invert it: {exc}") from exc
    except (OverflowError, ZeroDivisionError) as exc:
        raise _beyond_float(exc) from exc


def _firmware_params(sc: Scenario) -> FirmwareParams:
    """:func:`firmware_params` without the report of the model's source."""
    ctl, sc_ = sc.control, scales(sc)
    f_sw = sc.pwm.f_sw
    cm = controller_motor(sc)
    p = cm.pole_pairs
    mag = nominal_motor(cm.mag, cm.pole_pairs, 0.5 * ctl.i_max)
    L = 0.5 * (mag["L_d"] + mag["L_q"])
    w_c = 2 * math.pi * ctl.current_bw
    _at_least_one_lsb("control.v_max", ctl.v_max, "V", sc_.v_lsb, "inverter.V_dc / 2^15")
    _at_least_one_lsb("control.i_max", ctl.i_max, "A", sc_.i_lsb, "from sensors.adc_range")
    v_lim = min(sc_.voltage(ctl.v_max), 32767)
    kp, ki = _named(f"control.current_bw (the current PIs' gains, with L = {L:.4g} H and R_s = {cm.R_s:.4g} ohm)",
                    pi_gains, L * w_c, cm.R_s * w_c, sc_.i_lsb / sc_.v_lsb, f_sw, 16, 16)
    cur_pi = PiParams(kp, 16, ki, 16, v_lim)
    k_t = mag["k_t"]
    w_s = 2 * math.pi * ctl.speed_bw
    kp_w = cm.J * w_s / (k_t * p)
    speed_div = max(round(f_sw / ctl.speed_rate), 1) if ctl.speed_rate > 0 else 1
    lobs = load_observer_params(sc, k_t, speed_div)
    # with the load observer the speed controller is P only: the observer's load current is its integral action
    ki_w = 0.0 if lobs.g else kp_w * w_s / 4
    kp_s, ki_s = _named(f"control.speed_bw and speed_rate (the speed PI's gains, with J = {cm.J:.4g} kg m^2 and "
                        f"k_t = {k_t:.4g} N m/A)",
                        pi_gains, kp_w, ki_w, sc_.w_lsb / sc_.i_lsb, f_sw / speed_div, 24, 31)
    speed_pi = PiParams(kp_s, 24, ki_s, 31, sc_.current(ctl.i_max))
    fixed = to_fixed(ctl.theta_hat / (2 * math.pi), 32) % 2**32 if ctl.mode == "fixed_angle" else None
    est = sc.estimator
    low, high = LOW_ESTIMATORS[est.low], HIGH_ESTIMATORS[est.high]
    methods = {low, high}
    rot = rotating_injection(sc)
    step = injection_step(sc)
    inj_sd, inj_cd = sincos_q15(step)
    inj_s2, inj_c2 = sincos_q15(2 * step % 2**32)
    mtpa = (mtpa_table(sc_.current(ctl.i_max), sc_.i_lsb, mag["psi_f"], mag["L_d"], mag["L_q"])
            if ctl.mtpa == "on" else (0, (), ()))
    notch = (_named("control.notch_freq, notch_width", biquad.notch, ctl.notch_freq, ctl.notch_width, f_sw)
             if ctl.notch_freq > 0 else None)
    return FirmwareParams(
        low=low, high=high,
        sqw=sqw_params(sc) if METHOD_SQW_BANGBANG in methods else None,
        rfo=rfo_params(sc) if METHOD_RFO in methods else None,
        speed_lp=lowpass_coef(ctl.speed_filter, f_sw), speed_pi=speed_pi, id_pi=cur_pi, iq_pi=cur_pi,
        v_h=sc_.voltage(sc.injection.V_h), i_pulse=sc_.current(ctl.i_pulse),
        n_converge=round(ctl.converge * f_sw), n_pulse=round(ctl.pulse * f_sw), n_settle=round(ctl.settle * f_sw),
        i_trip=sc_.current(ctl.i_trip),
        w_up=sc_.speed_mech(est.handover_up), w_down=sc_.speed_mech(est.handover_down),
        merge=lowpass_coef(1.0 / (2 * math.pi * est.merge_time), f_sw), fixed_angle=fixed,
        wd_delta=round(est.watchdog_angle / (2 * math.pi) * 2**32), wd_speed=sc_.speed_mech(est.watchdog_speed),
        wd_hold=round(est.watchdog_hold * f_sw),
        rot=rot_bpf_params(sc) if METHOD_ROT_BPF in methods else None,
        smo=eemf_smo_params(sc) if METHOD_EEMF_SMO in methods else None,
        cic=sqw_cic_params(sc) if METHOD_SQW_CIC in methods else None,
        inj_rot=int(rot), inj_cd=inj_cd, inj_sd=inj_sd, inj_c2=inj_c2, inj_s2=inj_s2,
        hf_dtc=rot_hf_current(sc) if rot else 0,
        pol_mode={"current": POL_CURRENT, "pilot": POL_PILOT, "none": POL_NONE}[ctl.polarity],
        v_pilot=min(sc_.voltage(ctl.v_pilot), 32767),
        mtpa_shift=mtpa[0], mtpa_id=mtpa[1], mtpa_iq=mtpa[2], notch=notch, speed_div=speed_div,
        i_slew=max(sc_.current(ctl.current_slew / f_sw), 1) if ctl.current_slew > 0 else 0,
        law=LAW_FCS_MPC if ctl.law == "fcs_mpc" else LAW_FOC_PWM,
        fcs=fcs_params(sc) if ctl.law == "fcs_mpc" else None,
        hfo=hfo_proj_params(sc) if METHOD_HFO_PROJ in methods else None,
        prot=protection_params(sc), lobs=lobs, **dc_feedforward_params(sc), ident=ident_params(sc))


def dc_feedforward_params(sc: Scenario) -> dict:
    """``ff_nom``, ``ff_lo``, ``ff_hi`` of the dc-link voltage feed-forward (golden.firmware.dc_feedforward):
    the nominal ``inverter.V_dc`` and ``protection.undervoltage`` / ``overvoltage`` times it, in codes of the
    dc-link channel (as :func:`dc_link_limits`, whether or not the dc-link check is on); all 0 unless
    ``control.dc_feedforward = "on"`` under the ``foc_pwm`` law. Raises ValueError without a dc-link channel."""
    if sc.control.dc_feedforward != "on" or sc.control.law != "foc_pwm":
        return {"ff_nom": 0, "ff_lo": 0, "ff_hi": 0}
    pr, sens, v_dc = sc.protection, sc.plant["sens"], sc.plant["inv"]["V_dc"]
    if not sens["vdc_range"]:
        raise ValueError("control.dc_feedforward = \"on\" needs the dc-link measurement (sensors.vdc_range > 0)")
    codes = 2 ** sens["adc_bits"] / sens["vdc_range"]
    return {"ff_nom": round(v_dc * codes), "ff_lo": max(round(pr.undervoltage * v_dc * codes), 1),
            "ff_hi": round(pr.overvoltage * v_dc * codes)}


def load_observer_params(sc: Scenario, k_t: float, speed_div: int) -> LoadObsParams:
    """``control.load_observer`` (Hz; 0: off): the load-torque observer's integers (golden.firmware.load_observer)
    for the controller's motor (torque per ampere ``k_t`` of its nominal model, ``J``, pole pairs) and the speed
    loop's step ``T_s = speed_div / f_sw``: ``g = (k_t p / J) T_s i_lsb / w_lsb`` (Q16), both poles at
    ``-w_o``: ``l1 = 2 w_o T_s`` (Q24), ``l2g = (w_o T_s)^2 / g`` (Q40). Raises ValueError when an integer
    leaves its range (docs/scenario.md)."""
    f_o = sc.control.load_observer
    if f_o <= 0:
        return LoadObsParams()
    sc_, cm = scales(sc), controller_motor(sc)
    t_s = speed_div / sc.pwm.f_sw
    g = k_t * cm.pole_pairs / cm.J * t_s * sc_.i_lsb / sc_.w_lsb
    w_t = 2 * math.pi * f_o * t_s
    p = LoadObsParams(g=to_fixed(g, 16), l1=to_fixed(2 * w_t, 24), l2g=to_fixed(w_t * w_t / g, 40))
    for name, v in (("g", p.g), ("l1", p.l1), ("l2g", p.l2g)):
        if not 0 < v < 1 << 31:
            raise ValueError(f"control.load_observer: {name} = {v} is outside 1..2^31-1 (the observer at "
                             f"{f_o:g} Hz with this motor's J, torque constant and speed-loop rate; docs/scenario.md)")
    return p


def ident_params(sc: Scenario):
    """The identification program (golden.commission) when ``control.mode = "commission"``, else None."""
    if sc.control.mode != "commission":
        return None
    from golden.commission import build_program, settings      # golden.commission imports this module
    return build_program(sc, settings(sc)).params


LOCK_EMF_SHARE = 0.06
"""Default ``protection.lock_emf``: this share of V_dc (34 V at 560 V, 21 V at 350 V). Healthy runs stay below
10 V on the Table I motor, 13 V through the 000 method's speed reversal at 350 V (docs/faults.md)."""
TRACK_SHARE = 1.0
"""Default ``protection.track_current``: this share of ``control.i_max`` (near the voltage limit at 5000 r/min the
Table I drive's current loop swings by 2 A of 3 A with the angle still within 6 deg: docs/faults.md)."""
SPEED_MAX_MARGIN = 2.0, 500 * math.pi / 30
"""Default ``protection.speed_max``: factor on the largest reference speed, plus this [rad/s mechanical] (a
full-load step at standstill on the Table I motor dips to -160 r/min before the speed loop catches it)."""


def protection_params(sc: Scenario) -> ProtParams:
    """The fault checks' integers (golden.firmware.protection) from ``[protection]``, the controller's nominal
    motor (:func:`~golden.flux_tables.nominal_motor` of :func:`controller_motor` at half ``i_max``) and the formats. Defaults of absent keys:
    ``lock_emf`` LOCK_EMF_SHARE * V_dc; ``track_current`` TRACK_SHARE * i_max; ``speed_max`` from
    SPEED_MAX_MARGIN; ``asc_speed`` the speed whose back-EMF amplitude ``p omega psi_f`` reaches V_dc/sqrt(3),
    above which a coasting motor charges the dc link through the diodes (0, never, without a magnet).
    ``lock_emf_rel`` is a share of the nominal flux (psi_f, or L_q i_max without a magnet). Under the ``fcs_mpc``
    law the tracking check is off (the law tracks a flux, not a current per axis: there is no current reference);
    the lock check takes the voltage of the states the inverter applied. ``checks = "off"``: every limit 0 (the
    flying start, ``catch_time`` and ``catch_probe`` with the magnet flux it needs, is no check: it stays)."""
    pr, ctl, sc_ = sc.protection, sc.control, scales(sc)
    catch_n = round(pr.catch_time * sc_.f_sw)
    cm = controller_motor(sc)
    mag = nominal_motor(cm.mag, cm.pole_pairs, 0.5 * ctl.i_max)
    flux = 2 * math.pi * sc_.f_sw / sc_.v_lsb          # flux LSB per V*s (golden.firmware.protection)
    probe_min = sc_.current(pr.catch_probe) if catch_n else 0
    if pr.checks == "off":
        return ProtParams(catch_n=catch_n, probe_min=probe_min,
                          psi_f=to_fixed(mag["psi_f"] * flux, 0) if probe_min else 0)
    v_dc = sc.plant["inv"]["V_dc"]
    ref = max((abs(v) for _, v in sc.reference_speed), default=0.0)
    speed_max = pr.speed_max if pr.speed_max is not None else SPEED_MAX_MARGIN[0] * ref + SPEED_MAX_MARGIN[1]
    if pr.asc_speed is not None:
        asc = pr.asc_speed
    else:
        asc = v_dc / (math.sqrt(3) * sc_.pole_pairs * mag["psi_f"]) if mag["psi_f"] > 0 else 0.0
    psi_nom = mag["psi_f"] if mag["psi_f"] > 0 else mag["L_q"] * ctl.i_max   # the back-EMF per speed
    shift = lambda tau: filter_shift(tau, sc_.f_sw)   # noqa: E731
    return ProtParams(
        r=to_fixed(cm.R_s * sc_.i_lsb / sc_.v_lsb, 16),
        ld=to_fixed(mag["L_d"] * sc_.i_lsb * flux, 16), lq=to_fixed(mag["L_q"] * sc_.i_lsb * flux, 16),
        psi_f=to_fixed(mag["psi_f"] * flux, 0),
        emf_k=shift(pr.lock_time),
        emf_tol=sc_.voltage(pr.lock_emf if pr.lock_emf is not None else LOCK_EMF_SHARE * v_dc),
        psi_rel=to_fixed(pr.lock_emf_rel * psi_nom * flux, 0),
        track_k=shift(pr.track_time),
        track_tol=0 if ctl.law == "fcs_mpc" else sc_.current(pr.track_current if pr.track_current is not None
                                                             else TRACK_SHARE * ctl.i_max),
        ovl_n=round(pr.overload_time * sc_.f_sw), ovl_w=min(sc_.speed_mech(pr.overload_speed), 2**31 - 1),
        ovl_m=round(pr.overload_speed_time * sc_.f_sw),
        w_max=min(sc_.speed_mech(speed_max), 2**31 - 1), w_asc=min(sc_.speed_mech(asc), 2**31 - 1),
        restarts=pr.restarts, restart_n=max(round(pr.restart_delay * sc_.f_sw), 1),
        catch_n=catch_n, probe_min=probe_min,
        hf_k=shift(pr.hf_time), hf_tol=to_fixed(pr.hf_response, 16),
        frz_n=round(pr.frozen_time * sc_.f_sw), frz_min=pr.frozen_samples,
        **slip_limits(sc, mag["psi_f"]), **dc_link_limits(sc), **load_limits(sc))


def filter_shift(tau: float, f_sw: float) -> int:
    """The shift ``k`` (0..30) of a first-order filter ``f += shr(x - f, k)`` run once per period whose time
    constant ``2^k / f_sw`` is nearest to ``tau`` [s] in the logarithm."""
    return min(max(round(math.log2(tau * f_sw)), 0), 30)


def load_limits(sc: Scenario) -> dict:
    """``ld_ct``, ``ld_cr``, ``ld_k``, ``ld_max`` of the overload check's load part (golden.firmware.protection): the
    torque's acceleration per current (:func:`torque_acceleration` of the controller's nominal motor at half
    ``i_max``, as the other checks), the filter ``load_time`` and the limit ``load_max`` times the acceleration of
    the largest torque that model gives at ``control.i_max`` (its MTPA point, :func:`max_torque`), in speed LSB
    per period (0: off)."""
    pr = sc.protection
    if pr.load_max <= 0:
        return {"ld_ct": 0, "ld_cr": 0, "ld_k": 0, "ld_max": 0}
    cm = controller_motor(sc)
    mag = nominal_motor(cm.mag, cm.pole_pairs, 0.5 * sc.control.i_max)
    c_t, c_r = torque_acceleration(sc, mag)
    a_max = cm.pole_pairs * max_torque(mag, cm.pole_pairs, sc.control.i_max) / cm.J / sc.pwm.f_sw**2
    ld_max = min(to_fixed(pr.load_max * a_max * 2**32 / (2 * math.pi), 0), 2**31 - 1)
    why = (f"with this motor's J = {cm.J:.4g} kg m^2, its torque at control.i_max and pwm.f_sw "
           "(docs/scenario.md; load_max = 0 turns the check off)")
    for name, v, lim in (("ld_ct", c_t, MOTION_LIMITS["c_t"]), ("ld_cr", c_r, MOTION_LIMITS["c_r"])):
        if not -lim <= v < lim:
            raise ValueError(f"protection.load_max: the torque's gain {name} = {v} is outside the range the "
                             f"firmware's products hold, {why}")
    if ld_max < 1:
        raise ValueError(f"protection.load_max: the limit rounds to 0 speed LSB per period (the check would be "
                         f"off), {why}")
    return {"ld_ct": c_t, "ld_cr": c_r, "ld_k": filter_shift(pr.load_time, sc.pwm.f_sw), "ld_max": ld_max}


def max_torque(mag: dict, pole_pairs: int, i_max: float) -> float:
    """The largest torque ``1.5 p (psi_f i_q + (L_d - L_q) i_d i_q)`` of the nominal constants of ``mag`` on the
    circle ``|i| = i_max`` [N m] (the MTPA point; 1001 current angles from q towards -d and +d: either sign of
    saliency, where golden.firmware.mtpa.mtpa_point takes i_d = 0 for L_q <= L_d)."""
    best = 0.0
    for k in range(1001):
        beta = (k / 1000 - 0.5) * math.pi             # i_d = -i sin(beta), i_q = i cos(beta)
        i_d, i_q = -i_max * math.sin(beta), i_max * math.cos(beta)
        best = max(best, 1.5 * pole_pairs * (mag["psi_f"] * i_q + (mag["L_d"] - mag["L_q"]) * i_d * i_q))
    return best


def slip_limits(sc: Scenario, psi_f: float) -> dict:
    """``slip_w``, ``slip_n`` of the slip check (golden.firmware.protection.slip_check): only with a high slot
    (``estimator.high``) and a magnet (``psi_f`` > 0, the controller's nominal flux); the speed
    ``protection.slip_speed``, absent: the one at which the back-EMF ``p omega psi_f`` equals the inverter's
    dead-time voltage ``V_dc t_d f_sw`` (182 r/min on the Table I drive; below it the model-based observer's angle
    is no reference; 0: off), armed for ``slip_time`` (at least one period)."""
    pr = sc.protection
    if sc.estimator.high == "none" or psi_f <= 0:
        return {"slip_w": 0, "slip_n": 0}
    sc_ = scales(sc)
    if pr.slip_speed is not None:
        speed = pr.slip_speed
    else:
        speed = sc.plant["inv"]["V_dc"] * sc.pwm.dead_time * sc.pwm.f_sw / (sc_.pole_pairs * psi_f)
    w = min(sc_.speed_mech(speed), 2**31 - 1)
    return {"slip_w": w, "slip_n": min(max(round(pr.slip_time * sc_.f_sw), 1), 2**31 - 1) if w else 0}


def dc_link_limits(sc: Scenario) -> dict:
    """``vdc_lo``, ``vdc_hi``, ``vdc_n`` of the dc-link check: ``protection.undervoltage`` and ``overvoltage``
    times the nominal ``inverter.V_dc`` in codes of the dc-link channel (``2^B / sensors.vdc_range`` per volt,
    an ideal divider: its gain error is the sensor's), for ``dc_link_time`` (at least one period); all 0
    without a channel (``vdc_range = 0``)."""
    pr, sens, v_dc = sc.protection, sc.plant["sens"], sc.plant["inv"]["V_dc"]
    if not sens["vdc_range"]:
        return {"vdc_lo": 0, "vdc_hi": 0, "vdc_n": 0}
    codes = 2 ** sens["adc_bits"] / sens["vdc_range"]
    return {"vdc_lo": round(pr.undervoltage * v_dc * codes), "vdc_hi": round(pr.overvoltage * v_dc * codes),
            "vdc_n": max(round(pr.dc_link_time * sc.pwm.f_sw), 1)}


def flux_lsb(sc: Scenario) -> float:
    """The firmware's flux unit [V*s]: ``v_lsb T / 2^FLUX_FRAC`` (golden.firmware.flux_lut)."""
    return scales(sc).v_lsb / sc.pwm.f_sw / 2**FLUX_FRAC


def dead_time_flux(sc: Scenario) -> int:
    """``V_dc t_d`` in flux units (golden.firmware.applied_flux): ``2^(15 + FLUX_FRAC)`` times the dead time
    the hardware applies (``DEAD_TICKS``) over the period."""
    hw = hardware_config(sc)
    return to_fixed(2**15 * hw.dead_ticks / (2 * hw.pwm_half), FLUX_FRAC)


def resistance_per_lsb(sc: Scenario) -> float:
    """The 003 firmware's resistance: the controller's ``R_s`` (:func:`controller_motor`) plus the inverter's
    on-resistance ``[control] inv_r_drop``, in voltage LSB per current LSB (the law's ``r_v``; times
    ``2^FLUX_FRAC`` the flux per period, ``r_f``)."""
    sc_ = scales(sc)
    return (controller_motor(sc).R_s + sc.control.inv_r_drop) * sc_.i_lsb / sc_.v_lsb


def threshold_flux(sc: Scenario) -> int:
    """``V_th T`` in flux units: the inverter's threshold drop ``[control] inv_v_drop`` over one period."""
    return to_fixed(sc.control.inv_v_drop / scales(sc).v_lsb, FLUX_FRAC)


def fcs_params(sc: Scenario) -> FcsParams:
    """The ``fcs_mpc`` law's integers (golden.firmware.fcs_law): ``R_s`` as flux and as voltage per current
    LSB, the flux reference table over ``0..i_max`` from the controller's map (:func:`controller_motor`: the
    plant's, or the model of ``[model]``) with ``control.flux_min``, and the constraint's threshold
    ``estimator.hfo_proj.phi_min``."""
    ctl, sc_, cm = sc.control, scales(sc), controller_motor(sc)
    r = resistance_per_lsb(sc)
    shift, t_d, t_q = flux_reference_table(cm.mag, cm.pole_pairs, sc_.i_lsb,
                                           flux_lsb(sc), sc_.current(ctl.i_max), ctl.flux_min)
    if not t_d or max(map(abs, t_d + t_q)) >= 1 << 30:
        raise ValueError(f"fcs_mpc: the flux reference table leaves +-2^30 flux units (scenario {sc.name})")
    return FcsParams(r_f=to_fixed(r * 2**FLUX_FRAC, 16), r_v=to_fixed(r, 16), dt_f=dead_time_flux(sc),
                     vth_f=threshold_flux(sc), shift=shift, t_d=t_d, t_q=t_q,
                     phi_min=min(sc_.voltage(sc.estimator.params["hfo_proj"]["phi_min"]), 65535), v_lim=32767)


def hfo_proj_params(sc: Scenario) -> HfoParams:
    """``estimator.hfo_proj``: the 003 estimator's integers (golden.firmware.hfo_proj). The flux LUT from the
    controller's map (:func:`controller_motor`: the plant's, or the model of ``[model]``, linear or
    ``[model.saturation]``; times ``map_scale_d/q``); ``g``, ``w_g`` as electrical speeds; the PLL's poles at
    ``-Omega`` (eq. (40): ``k_p = 2 Omega``, ``k_i = Omega^2``)."""
    t, sc_, f_sw = sc.estimator.params["hfo_proj"], scales(sc), sc.pwm.f_sw
    T = 1.0 / f_sw
    lut = flux_lut(controller_motor(sc).mag, sc_.i_lsb, flux_lsb(sc), t["lut_step"], t["lut_knee"], t["lut_coarse"],
                   t["lut_max_d"], t["lut_max_q"], t["map_scale_d"], t["map_scale_q"])
    omega = 2 * math.pi * t["pll_bw"]
    kp, ki = _named("estimator.hfo_proj.pll_bw", pll_gains, 2 * omega, omega * omega, f_sw)
    return HfoParams(lut=lut, c_lag=min(to_fixed(t["i_lag"] * f_sw, 16), 1 << 16),
                     r_f=to_fixed(resistance_per_lsb(sc) * 2**FLUX_FRAC, 16),
                     dt_f=dead_time_flux(sc), vth_f=threshold_flux(sc),
                     c_g=to_fixed(2 * math.pi * t["g"] * T, 16),
                     phi_min=min(sc_.voltage(t["phi_min"]), 65535),
                     s_knee=min(max(to_fixed(t["phi_knee"] / sc_.v_lsb, FLUX_FRAC), 1), 1 << 23), n_max=t["n_max"],
                     g_b=to_fixed(t["g"] * T, 32), wg_b=max(to_fixed(t["w_g"] * T, 32), 1), kp=kp, ki=ki,
                     k_delay=to_fixed(1.5, 16), eps_max=to_fixed(t["eps_max"] / (2 * math.pi), 32),
                     hold=int(t["hold"] == "on"))


def sqw_params(sc: Scenario) -> SqwParams:
    """``estimator.sqw_bangbang``: bang-bang step and PLL gains (Benevieri et al. 2023, Table II); ``i_d =
    -i_d_min`` [current LSB]; with ``cross_saturation = "on"`` the table of :func:`cross_saturation_table`."""
    t, f_sw = sc.estimator.params["sqw_bangbang"], sc.pwm.f_sw
    kp, ki = _named("estimator.sqw_bangbang.pll_kp, pll_ki", pll_gains, t["pll_kp"], t["pll_ki"], f_sw)
    shift, table = cross_saturation_table(sc) if t["cross_saturation"] == "on" else (0, ())
    return SqwParams(k_bb=_named("estimator.sqw_bangbang.K_bb", k_bb_raw, t["K_bb"], f_sw), pll_kp=kp, pll_ki=ki,
                     i_d=-scales(sc).current(t["i_d_min"]), xs_shift=shift, xs_gamma=table)


def _cross_saturation_grid(sc: Scenario, method: str) -> tuple[int, list[tuple[float, float, float]]]:
    """``(shift, [(g_dd, g_dq, g_qq), ...])``: the inverse incremental inductance matrix (1/H) of the controller's
    algebraic model (:func:`golden.saturation_fit.jacobian` at its fluxes) along the current references the drive asks
    for, on the grid of the MTPA table over ``|i_q|`` from 0 to ``control.i_max``, for the tables of
    ``estimator.<method>.cross_saturation`` (docs/methods.md, "Cross-saturation").

    At ``|i_q| = q``: ``i_d`` the smaller of ``-estimator.<method>.i_d_min`` and, with ``control.mtpa = "on"``, the
    MTPA point's whose q current is ``q`` (:func:`golden.firmware.mtpa.mtpa_point` on the nominal motor, as the MTPA
    table). Raises ValueError (naming the key) without an algebraic model: a linear one has no cross-saturation to
    take out."""
    from golden.firmware.mtpa import MTPA_LEN, mtpa_point, table_grid
    from golden.saturation_fit import fluxes, jacobian

    key = f"estimator.{method}.cross_saturation"
    cm = controller_motor(sc)
    if cm.mag["kind"] != MAG_KINDS["algebraic"]:
        raise ValueError(f"{key} = \"on\" needs a controller model with cross-saturation: the motor preset's or "
                         f"[model.saturation]'s algebraic model (this one is linear: nothing to take out)")
    ctl, sc_ = sc.control, scales(sc)
    i_d_min = sc.estimator.params[method]["i_d_min"]
    nom = nominal_motor(cm.mag, cm.pole_pairs, 0.5 * ctl.i_max)

    def i_d_at(q: float) -> float:
        """The d-current reference [A] at the q current ``q`` >= 0 [A] (docstring)."""
        if ctl.mtpa != "on":
            return -i_d_min
        lo, hi = q, 4.0 * q + 1e-9                  # the MTPA magnitude whose q current is q, by bisection
        while mtpa_point(hi, nom["psi_f"], nom["L_d"], nom["L_q"])[1] < q:
            hi *= 2.0
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if mtpa_point(mid, nom["psi_f"], nom["L_d"], nom["L_q"])[1] < q else (lo, mid)
        return min(mtpa_point(hi, nom["psi_f"], nom["L_d"], nom["L_q"])[0], -i_d_min)

    shift, n = table_grid(min(sc_.current(ctl.i_max), 32767), MTPA_LEN, "cross-saturation table")
    grid = []
    for k in range(n):
        q = min(k << shift, 32767) * sc_.i_lsb
        psi_d, psi_q = fluxes(cm.mag, i_d_at(q), q)
        grid.append(tuple(float(g) for g in jacobian(cm.mag, psi_d, psi_q)))
    return shift, grid


def cross_saturation_table(sc: Scenario) -> tuple[int, tuple[int, ...]]:
    """``(xs_shift, xs_gamma)``: the response across d_hat (``GAMMA``) that the controller's magnetic model gives with
    d_hat *on* the d-axis, at the current references the drive asks for (:func:`_cross_saturation_grid`): the inverse
    incremental inductance across the axes ``Gamma_dq`` times the hardware's HF gain for the square wave
    (:func:`golden.hf_gain.hf_response`: ``GAMMA_D`` of 1 H at ``V_H``, with the sensors' lag), rounded, within s16.
    The table holds ``gain * Gamma_dq``: on the d-axis the cross term reads as a ``GAMMA`` of that sign (checked in
    closed loop on the 003 SyRM, 2026-12-02: with the opposite sign the offset doubles and the rotor is lost at rated
    load)."""
    from golden.hf_gain import hf_response, sensor_bandwidth

    shift, grid = _cross_saturation_grid(sc, "sqw_bangbang")
    sc_ = scales(sc)
    v_h = min(sc_.voltage(sc.injection.V_h), 32767)
    gain = hf_response(hardware_config(sc), sc_, sc.pwm.tick_hz, v_h, 0, 32767, sensor_bw=sensor_bandwidth(sc))[0]
    return shift, tuple(sat(to_fixed(gain * g_dq, 0), 16) for _, g_dq, _ in grid)


def rot_cross_saturation_table(sc: Scenario) -> tuple[int, tuple[int, ...]]:
    """``(xs_shift, xs_angle)``: the turn of the rotating injection's negative sequence that the controller's model's
    cross-saturation gives with the estimate *on* the d-axis, at the current references the drive asks for
    (:func:`_cross_saturation_grid`), in units of ``2^16`` binary angle of that sequence's phase (twice the
    electrical angle), within s16. With the inverse incremental inductance matrix ``Gamma`` the HF current of the
    rotating vector ``z`` is ``(g_dd + g_qq)/2 z + ((g_dd - g_qq)/2 + j g_dq) conj(z)`` in the rotor frame, so the
    negative sequence's phase is ``2 theta + arg((g_dd - g_qq)/2 + j g_dq)``; the table holds that argument less its
    value without the cross term (0 or pi: the saliency's sign, in ``offset``), ``atan2(2 s g_dq, s (g_dd - g_qq))``
    with ``s`` the sign of ``g_dd - g_qq`` (docs/methods.md, "Cross-saturation")."""
    shift, grid = _cross_saturation_grid(sc, "rot_bpf")
    table = []
    for g_dd, g_dq, g_qq in grid:
        s = 1.0 if g_dd >= g_qq else -1.0
        turn = math.atan2(2 * s * g_dq, s * (g_dd - g_qq)) / (2 * math.pi)
        table.append(sat(to_fixed(turn, 16), 16))
    return shift, tuple(table)


def cic_cross_saturation_table(sc: Scenario) -> tuple[int, tuple[int, ...]]:
    """``(xs_shift, xs_angle)``: the angle of the square wave's envelope against the d-axis that the controller's
    model's cross-saturation gives with the estimate *on* the d-axis, at the current references the drive asks for
    (:func:`_cross_saturation_grid`), in units of ``2^16`` binary angle (electrical), within s16. The square wave on
    d moves the current by ``Gamma`` times the voltage: along ``(g_dd, g_dq)`` in the rotor frame, so the envelope
    points ``atan2(g_dq, g_dd)`` off d, and the observer, which settles where the envelope's angle equals its own,
    settles there less the table (docs/methods.md, "Cross-saturation")."""
    shift, grid = _cross_saturation_grid(sc, "sqw_cic")
    return shift, tuple(sat(to_fixed(math.atan2(g_dq, g_dd) / (2 * math.pi), 16), 16) for g_dd, g_dq, _ in grid)


def rfo_params(sc: Scenario) -> RfoParams:
    """``estimator.rfo`` and the motor's nominal data: the flux-observer integers (golden.firmware.rfo).

    Flux LSB = v_lsb T / 2^FLUX_FRAC; ``r_s`` = R_s i_lsb / v_lsb (Q16); ``l_s`` = L_q i_lsb / flux LSB
    (Q16); ``l_dq`` = (L_d - L_q) i_lsb / flux LSB (Q16, signed: the active flux's magnitude follows i_d);
    ``k_c = 1 - exp(-2 pi flux_bw T)`` and ``k_min`` likewise of ``flux_bw_min`` (Q16); ``k_r =
    flux_ratio 2 pi 2^16`` (so that ``k_r |w| >> 32`` is ``flux_ratio`` times the electrical angle per period,
    Q16); ``i_d = -i_d_min`` [current LSB]. Raises ValueError when a value leaves its range.
    """
    t, sc_ = sc.estimator.params["rfo"], scales(sc)
    f_sw = sc.pwm.f_sw
    f_lsb = flux_lsb(sc)
    cm = controller_motor(sc)
    mag = cm.mag
    kp, ki = _named("estimator.rfo.pll_kp, pll_ki", pll_gains, t["pll_kp"], t["pll_ki"], f_sw)
    p = RfoParams(r_s=to_fixed(cm.R_s * sc_.i_lsb / sc_.v_lsb, 16),
                  l_s=to_fixed(mag["L_q"] * sc_.i_lsb / f_lsb, 16),
                  psi_f=to_fixed(mag["psi_f"] / f_lsb, 0),
                  k_c=lowpass_coef(t["flux_bw"], f_sw), k_min=lowpass_coef(t["flux_bw_min"], f_sw),
                  k_r=to_fixed(t["flux_ratio"] * 2 * math.pi, 16), pll_kp=kp, pll_ki=ki, i_d=-sc_.current(t["i_d_min"]),
                  l_dq=to_fixed((mag["L_d"] - mag["L_q"]) * sc_.i_lsb / f_lsb, 16))
    for name, value, lo, hi in (("r_s", p.r_s, 0, 2**31 - 1), ("l_s", p.l_s, 0, 2**31 - 1),
                                ("psi_f", p.psi_f, 0, 2**27), ("k_r", p.k_r, 0, 2**31 - 1),
                                ("l_dq", p.l_dq, -2**31 + 1, 2**31 - 1)):
        if not lo <= value <= hi:
            raise ValueError(f"rotor flux observer: {name} = {value} outside {lo}..{hi} (motor data and scales "
                             f"of scenario {sc.name})")
    return p


def rot_bpf_delay(bpf: biquad.BiquadCoef, f_inj: float, n_avg: int, f_sw: float, f_e_max: float) -> float:
    """Delay [periods] from the electrical speed to the angle lag of ``rot_bpf`` (Tap et al. 2023, eqs.
    (18)-(19)), plus one period (the PLL's prediction is for the next window, the angle is used in the one
    after): the negative sequence passes the band-pass at ``-2 (f_inj - f_e)`` in the positive frame, where
    the filter's phase is minus its phase ``atan((w_0^2 - w^2) / (w_g w))`` at ``+2 (f_inj - f_e)``, so
    the angle lags by half of that phase (eq. (18) with its sign); that phase, evaluated on the quantised
    discrete filter at 41 speeds in ``0..f_e_max``, is fitted by a straight line through 0 (the paper fits
    a first-order polynomial); the moving average over N periods of a phasor at ``2 f_e`` lags ``theta`` by
    ``(N - 1) / 2`` periods."""
    ref = biquad.response(bpf, 2 * f_inj, f_sw)
    num = den = 0.0
    for k in range(1, 41):
        f_e = f_e_max * k / 40
        # at the negative frequency -2 (f_inj - f_e) a real filter's phase is minus its phase at +2 (f_inj - f_e)
        h = biquad.response(bpf, 2 * (f_inj - f_e), f_sw) / ref
        lag = math.atan2(h.imag, h.real) / 2                                              # rad of theta
        w = 2 * math.pi * f_e / f_sw                                                      # rad per period
        num, den = num + lag * w, den + w * w
    return num / den + (n_avg - 1) / 2 + 1


def rot_bpf_params(sc: Scenario) -> RotParams:
    """``estimator.rot_bpf``: the 000 method's integers (golden.firmware.rot_bpf); with ``cross_saturation = "on"``
    the table of :func:`rot_cross_saturation_table`."""
    t, f_sw = sc.estimator.params["rot_bpf"], sc.pwm.f_sw
    cm = controller_motor(sc)
    mag, p = cm.mag, cm.pole_pairs
    step = injection_step(sc)
    q_sin, q_cos = sincos_q15(uwrap(-shr(wrap(step, 32), 2), 32))     # -INJ_STEP / 4
    bpf = _named("estimator.rot_bpf.f_inj, bpf_width", biquad.bandpass, 2 * t["f_inj"], t["bpf_width"], f_sw)
    kp, ki = _named("estimator.rot_bpf.pll_kp, pll_ki", pll_gains, t["pll_kp"], t["pll_ki"], f_sw)
    f_e_max = sc.estimator.handover_up * p / (2 * math.pi)
    delay = rot_bpf_delay(bpf, t["f_inj"], t["n_avg"], f_sw, max(f_e_max, 1.0))
    # the negative sequence's phase: +-pi/2 by the saliency's sign (docs/methods.md), less the stator
    # resistance's share, which eqs. (8)-(11) neglect: arg 1/((R + j w L_d)(R + j w L_q)) + pi
    w_h, r = 2 * math.pi * t["f_inj"], cm.R_s
    l_d, l_q = hf_inductances(mag, -t["i_d_min"])          # at the magnetizing current on a map
    d_r = math.atan(r / (w_h * l_d)) + math.atan(r / (w_h * l_q))
    offset = (2**30 if l_q > l_d else 3 * 2**30) - to_fixed(d_r / (2 * math.pi), 32)
    observer = t["tracking"] == "observer"
    gains = motion_gains(sc, t["observer_bw"], True, "rot_bpf") if observer else {}
    shift, table = rot_cross_saturation_table(sc) if t["cross_saturation"] == "on" else (0, ())
    return RotParams(q_cos=q_cos, q_sin=q_sin, bpf=bpf, n_avg=t["n_avg"], offset=offset % 2**32, pll_kp=kp, pll_ki=ki,
                     k_delay=to_fixed(delay, 16), n_hold=round(t["hold"] * f_sw),
                     tracking=TRACK_OBSERVER if observer else TRACK_PLL, i_d=-scales(sc).current(t["i_d_min"]),
                     xs_shift=shift, xs_angle=table, **gains)


MOTION_LIMITS = {"c_t": 1 << 46, "c_r": 1 << 32}
"""The ranges of the motion observer's feed-forward gains that the C products rely on (control.h, struct
fw_cic_params and fw_rot_params); the other gains: any s32."""


def motion_gains(sc: Scenario, observer_bw: float, torque_ff: bool, method: str) -> dict:
    """The motion observer's integers (golden.firmware.motion) for the poles at ``-a``, ``a = 2 pi
    observer_bw``: ``c1 = a^3 T^3``, ``c2 = 3 a^2 T^2`` (Q24 binary angle per binary angle), ``c3 = 3 a T``
    (Q16); the torque feed-forward ``n_p T_e / J`` with ``T_e = 1.5 n_p (psi_f i_q + (L_d - L_q) i_d i_q)``
    of the controller's nominal motor (:func:`~golden.flux_tables.nominal_motor` at half ``i_max``, as the overload
    check's load part: a linear model's own constants, a map's apparent inductances; until 2026-12-02 a map's
    defaults' 5.59 / 6.26 mH were read, which left the 003 SyRM's feed-forward about 700 times too small):
    ``c_t`` per current LSB (Q24 binary angle per
    period^2), ``c_r`` per LSB^2 (Q40); both 0 without ``torque_ff``. Raises ValueError (naming ``method``)
    when a gain leaves the range the firmware's integers hold."""
    T = 1.0 / sc.pwm.f_sw
    a = 2 * math.pi * observer_bw
    why = "observer_bw, the motor's saliency or its J out of the range the firmware's integers hold"
    cm = controller_motor(sc)
    nom = nominal_motor(cm.mag, cm.pole_pairs, 0.5 * sc.control.i_max)   # a map's apparent L_d, L_q
    try:
        c_t, c_r = torque_acceleration(sc, nom) if torque_ff else (0, 0)
        g = {"c1": to_fixed((a * T) ** 3, 24), "c2": to_fixed(3 * (a * T) ** 2, 24), "c3": to_fixed(3 * a * T, 16),
             "c_t": c_t, "c_r": c_r}
    except (OverflowError, ValueError) as exc:     # (a T)^3 beyond a float: tests/test_scenario_fuzz.py, 2026-12-01
        raise ValueError(f"estimator {method}: a gain is beyond a float ({exc}; a T = {a * T:.3g}): {why}") from None
    for name, v in g.items():
        lim = MOTION_LIMITS.get(name, 1 << 31)
        if not -lim <= v < lim:
            raise ValueError(f"estimator {method}: {name} = {v} is outside +-{lim} ({why})")
    return g


def torque_acceleration(sc: Scenario, mag: dict) -> tuple[int, int]:
    """``n_p T_e / J`` with ``T_e = 1.5 n_p (psi_f i_q + (L_d - L_q) i_d i_q)`` of the constants ``mag`` of the
    controller's motor (:func:`controller_motor`: its J and pole pairs) in binary angle per period^2: per current
    LSB (Q24) and per LSB^2 (Q40); the motion observer's feed-forward and the overload check's load part."""
    sc_, T = scales(sc), 1.0 / sc.pwm.f_sw
    cm = controller_motor(sc)
    p = cm.pole_pairs
    turn = 2**32 / (2 * math.pi)                                 # binary angle per radian
    acc = p * 1.5 * p / cm.J * T * T * turn                 # n_p T_e / J per (N*m / 1.5 n_p) per period^2
    return to_fixed(acc * mag["psi_f"] * sc_.i_lsb, 24), to_fixed(acc * (mag["L_d"] - mag["L_q"]) * sc_.i_lsb**2, 40)


def sqw_cic_delay(cic_m: int, l_d: float, l_q: float) -> float:
    """The delay compensation of ``sqw_cic`` [PWM periods] for the comb delay ``cic_m`` and the motor's
    nominal inductances (docs/methods.md, "The 001 method", derives it; the steady state at constant speed
    on an ideal inverter confirms it).

    Window ``k`` runs from ``k P + P/4`` to ``(k+1) P + P/4`` (a window boundary is the carrier's rising zero
    crossing); the firmware steps at its end. The envelope formed at that step is the current change over
    period ``k`` (carrier bottom to bottom), centred at ``k P + P/2``: 0.75 periods before the step, and it is
    held for two periods (0.75 or 1.75 old, 1.25 on average). The CIC adds the last ``M`` held values: their
    mean age is ``a = 1.25 + (M - 1)/2``. The observer, whose steady-state error is zero at constant speed,
    settles where the angle of the CIC output equals its own angle before its step; after the step its angle
    is its prediction for the next step, one period on; the outputs are used in window ``k + 2``, whose middle
    is 1.5 periods after the step. If the injection pointed at the rotor's angle of the envelope's time, that
    gives ``a + 1.5 - 1``. It does not quite: the modulator takes a committed angle at the next carrier top,
    a quarter period after the window boundary, so each period's injection runs half on the angle aimed at
    the middle of one window and half on the next one's, a quarter period behind the period's middle. The
    envelope's angle follows the injection's in part: ``psi = theta_inj + s (theta - theta_inj)``, ``s = 1 -
    L_d/L_q`` (eq. (6)), and the observer then settles ``(1 - s) / 4 / s`` periods late unless ``k_delay``
    carries ``(1 - s) / 4 = L_d / (4 L_q)`` more. In all: ``k_delay = a + 0.5 + L_d / (4 L_q)`` (2.37 on the
    Table 1 motor at the paper's ``M = 2``; the paper compensates 3.5)."""
    return 1.25 + (cic_m - 1) / 2 + 0.5 + l_d / (4 * l_q)


def sqw_cic_params(sc: Scenario) -> CicParams:
    """``estimator.sqw_cic`` and the motor's nominal data: the 001 method's integers (golden.firmware.sqw_cic).

    ``g = L_q / (L_q - L_d)`` (Q16): the inverse slope of the angle of the quadrature signal against the
    angle error, with the inductances the square wave meets (:func:`~golden.flux_tables.hf_inductances` at
    ``-i_d_min``: on a map the incremental ones at the magnetizing current); observer poles at ``-a``, ``a = 2 pi observer_bw``: ``c1 = a^3 T^3``, ``c2 = 3 a^2 T^2``
    (Q24 binary angle per binary angle), ``c3 = 3 a T`` (Q16); torque feed-forward ``n_p T_e / J`` with
    ``T_e = 1.5 n_p (psi_f i_q + (L_d - L_q) i_d i_q)``: ``c_t`` per current LSB (Q24 binary angle per
    period^2), ``c_r`` per LSB^2 (Q40); ``q_min``: the ``vector_angle`` magnitude of ``cic_m`` envelope
    values of ``q_min`` each; ``i_d = -i_d_min`` [current LSB]. Raises ValueError on a motor without saliency."""
    t, sc_, f_sw = sc.estimator.params["sqw_cic"], scales(sc), sc.pwm.f_sw
    l_d, l_q = hf_inductances(controller_motor(sc).mag, -t["i_d_min"])   # at the magnetizing current on a map
    if l_q == l_d:
        raise ValueError("estimator sqw_cic needs a salient motor (L_d != L_q): the envelope carries no angle")
    gains = motion_gains(sc, t["observer_bw"], t["torque_ff"] == "on", "sqw_cic")
    shift, table = cic_cross_saturation_table(sc) if t["cross_saturation"] == "on" else (0, ())
    p_ = CicParams(g=to_fixed(l_q / (l_q - l_d), 16), **gains,
                   k_delay=to_fixed(sqw_cic_delay(t["cic_m"], l_d, l_q), 16),
                   q_min=t["cic_m"] * sc_.current(t["q_min"]), n_hold=round(t["hold"] * f_sw),
                   i_d=-sc_.current(t["i_d_min"]), xs_shift=shift, xs_angle=table)
    for name in ("g", "k_delay", "q_min", "n_hold", "i_d"):       # the ranges of struct fw_cic_params (control.h)
        v = getattr(p_, name)
        if not -(1 << 31) <= v < 1 << 31:
            raise ValueError(f"estimator sqw_cic: {name} = {v} is outside the s32 range the firmware holds")
    return p_


def eemf_smo_params(sc: Scenario) -> SmoParams:
    """``estimator.eemf_smo`` and the motor's nominal data: the observer's integers (golden.firmware.eemf_smo).

    The observer's inductance ``L_o`` is ``L_q`` (``model = "Lq"``, default: no speed-dependent cross
    term) or ``L_d`` (``model = "Ld"``: the paper's eq. (20), whose cross term is ``w (L_d - L_q) J i``);
    docs/methods.md says why. ``c_v = T / L_o`` (current LSB per voltage LSB), ``c_r = T R / L_o``,
    ``c_x = 2 pi (L_o - L_q) / L_o``; the linear gain ``k_lin`` puts the observer's error pole at
    ``obs_pole`` (``1 - c_r - c_v k = pole``); the low-pass cut-off ``lpf_ratio`` times the electrical
    speed between ``lpf_min`` and ``lpf_max``. ``lag0`` and ``k_delay`` [periods]: :func:`eemf_smo_lag`
    and one period from the PLL's prediction to the window of use."""
    t, sc_, f_sw = sc.estimator.params["eemf_smo"], scales(sc), sc.pwm.f_sw
    cm, T = controller_motor(sc), 1.0 / f_sw
    mag = cm.mag
    l_o = mag["L_q"] if t["model"] == "Lq" else mag["L_d"]
    dl = (l_o - mag["L_q"]) / l_o
    c_v = T / l_o * sc_.v_lsb / sc_.i_lsb                       # current LSB per voltage LSB per period
    c_r = T * cm.R_s / l_o
    k = (1 - c_r - t["obs_pole"]) / c_v                         # voltage LSB per current LSB
    kp, ki = _named("estimator.eemf_smo.pll_kp, pll_ki", pll_gains, t["pll_kp"], t["pll_ki"], f_sw)
    pp = cm.pole_pairs
    f_e_max = sc.plant["rated"]["speed_rpm"] / 60 * pp if "rated" in sc.plant else 100.0
    f_e_min = sc.estimator.handover_down * pp / (2 * math.pi)
    c_a = to_fixed(t["lpf_ratio"] * 2 * math.pi * 2**8, 0)
    a_min, a_max = lowpass_coef(t["lpf_min"], f_sw), lowpass_coef(t["lpf_max"], f_sw)
    lag0, slope = eemf_smo_lag(t["obs_pole"], dl, c_a, a_min, a_max, f_sw, max(f_e_min, 1.0), max(f_e_max, 2.0))
    p = SmoParams(c_v=to_fixed(c_v, 16), c_r=to_fixed(c_r, 16), c_x=to_fixed(2 * math.pi * dl, 16),
                  k_lin=to_fixed(k / 2**I_FRAC, 16), z_max=min(sc_.voltage(t["z_max"]), 32767),
                  c_a=c_a, a_min=a_min, a_max=a_max, lag0=to_fixed(lag0 / (2 * math.pi), 32),
                  pll_kp=kp, pll_ki=ki, k_delay=to_fixed(slope + 1, 16), e_min=sc_.voltage(t["e_min"]) << I_FRAC,
                  w_dir=sc_.speed_mech(t["dir_speed"]), i_d=-sc_.current(t["i_d_min"]))
    for name in ("c_v", "c_r", "c_x", "k_lin"):
        if not abs(getattr(p, name)) < 2**24:
            raise ValueError(f"EEMF observer: {name} = {getattr(p, name)} outside +-2^24 (motor data and "
                             f"scales of scenario {sc.name})")
    return p


def eemf_smo_lag(pole: float, dl: float, c_a: int, a_min: int, a_max: int, f_sw: float, f_e_min: float,
                 f_e_max: float) -> tuple[float, float]:
    """Lag of the EEMF estimate of ``eemf_smo`` behind the true EEMF, fitted as ``lag0 + slope x`` (rad,
    ``x`` the electrical angle per period) by least squares over 41 speeds in ``f_e_min..f_e_max``; returns
    ``(lag0, slope)`` (rad, periods). In the observer's linear zone the current error obeys
    ``eps' = (pole + j g) eps + c_v e`` with ``g = x dl``, ``dl = (L_o - L_q) / L_o`` (the cross term of
    eq. (20), ``J`` acting as ``-j``; 0 for ``L_o = L_q``), so ``z / e = (1 - pole) q / (1 - (pole + j g) q)``
    with ``q = e^{-j x}``; then the low-pass ``a / (1 - (1 - a) q)`` with the speed-dependent ``a`` of the
    firmware. The cut-off in proportion to the speed makes the filter's lag nearly constant
    (``atan(1 / ratio)``); the paper's cross term (``L_o = L_d``) adds ``-dl / (1 - pole)`` periods,
    3.4 on the Table 1 PMaSynRM at pole 0.5."""
    xs, ys = [], []
    for k in range(41):
        f_e = f_e_min + (f_e_max - f_e_min) * k / 40
        x = 2 * math.pi * f_e / f_sw
        w_bin = round(f_e / f_sw * 2**32)
        a = min(max((w_bin * c_a) >> 24, a_min), a_max) / 65536
        q = complex(math.cos(x), -math.sin(x))
        h = (1 - pole) * q / (1 - complex(pole, x * dl) * q) * a / (1 - (1 - a) * q)
        xs.append(x)
        ys.append(-math.atan2(h.imag, h.real))
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    return my - slope * mx, slope
