"""The firmware's control task, run once per PWM period on the window interrupt (docs/spec.md, 5).

One call of :meth:`Firmware.step` is one interrupt: it reads the latched window results, steps the
estimators through their plug-in interface (:mod:`golden.firmware.estimator`; docs/methods.md), runs
the supervisor state machine (start-up with polarity detection, then speed control with the hand-over
between the low-speed and the high-speed estimator), the speed filter and PI, the current controllers,
and returns the register values the firmware writes (shadow registers, committed at the next window
boundary, and ``CTRL``). The supervisor never reads an estimator's internals: it calls ``step``,
``turn`` and ``sync`` and reads ``theta`` and ``omega``.

Every operation is integer arithmetic from :mod:`golden.fixed` and the function modules beside this
one; the C firmware performs the same calls in the same order.

States (``MODE_*``):

``CATCH``     the flying start (``prot.catch_n`` > 0, a high-speed estimator in the high slot): every start, at
              power-up and after each automatic restart, begins here. The high-speed estimator is in charge and
              steps, no injection, i_q* = 0 and i_d* = 0; in the second half of the catch, when the speed is
              then at or above ``w_down``, i_d* is the estimator's (``Estimator.i_d``, as in RUN: its step at
              the start of RUN disturbed the 000 drive's EEMF observer; at rest it would be a torque pulse in
              a direction the estimator does not know), under current control in its frame: the current PIs'
              voltage is then the back-EMF of a spinning rotor, from which the estimator takes angle and speed.
              The high-speed estimator acquires from its power-up state (the rotor flux observer at its
              fastest flux correction until its first ``sync``). After ``catch_n`` windows: ``|omega_f| >=
              w_down`` -> RUN with the high-speed estimator in charge, ``sync``ed to its own angle and speed
              (the speed PI from zero torque; the overspeed check's limit raised by the caught speed until the
              hand-over down, golden.firmware.protection); slower -> CONVERGE, the standstill
              start (the speed filter cleared, the low slot in charge). A rotor an active load has spun up
              while the drive coasted is thus braked back under control instead of tripping the standstill
              start (docs/faults.md). With ``prot.probe_min`` the catch begins with the short-circuit probe
              (:mod:`golden.firmware.catch_probe`: two zero-voltage pulses of one period, the estimators not
              stepped, the steps' outputs the probe's); when it finds the rotor, the high slot is synced to its
              angle and speed, the speed filter set to that speed and the q current PI's integrator to the
              back-EMF's voltage, and the catch goes on from there; else as without it.
``CONVERGE``  low-speed estimator in charge, current references 0: theta_hat settles on the +-d axis.
              Its last window already asks for +I_p, so both polarity pulses last ``n_pulse`` windows.
              Without a polarity test (``POL_NONE``, a reluctance machine) i_d* is the estimator's
              ``Estimator.i_d`` here and in RELAX: the magnetizing current whose saturation makes the saliency.
``POL_POS``   i_d* = +I_p; after ``n_settle`` windows gamma_d is summed (HF d-current response).
``POL_NEG``   i_d* = -I_p, summed the same way. A larger response means a smaller incremental
              inductance, i.e. saturation, i.e. the magnet's north: if the -I_p sum is the larger,
              the low-speed estimator is turned by half a turn (polarity detection by d-axis
              saturation, the method the paper cites as [23], [30]).
              With ``pol_mode = POL_PILOT`` (Tap et al. 2023, Sec. II-D) the two pulses are pilot
              *voltages* +-V_p on d_hat for ``n_pulse`` windows each, current control off; each state
              starts with ``n_settle`` windows of current control to zero; no injection and the
              estimators not stepped in both states. The d-current of each pulse's last window is
              compared: the larger is the saturating direction, the magnet's north.
``RELAX``     i_d* = 0 for ``n_settle`` windows; at its end the high-speed estimator (if any) is
              synchronised to the low-speed one's angle and speed.
``RUN``       speed PI on the filtered speed of the estimator in charge, every ``speed_div`` periods (with
              the load observer on, :mod:`golden.firmware.load_observer`: P control plus its load current) ->
              i_q*, i_d* as that estimator asks (``Estimator.i_d``: 0, or the rotor flux observer's
              minimum current); with an MTPA table the PI output is the current magnitude and the table
              gives (i_d*, |i_q*|), i_d* the smaller of the table's and the estimator's. Hand-over
              (Benevieri et al. 2023, Sec. IV-F): above ``w_up`` (|filtered speed|) the high-speed
              estimator takes charge, below ``w_down`` the low-speed one again. Bumpless: taking charge
              upwards, the angle in use keeps its value and the difference to the new estimator decays
              by ``merge`` (Q16) per period; downwards, the low-speed estimator continues from the angle
              and speed in use (``sync``). The injection follows the estimator in charge.
``FIXED``     open-loop test (paper Sec. IV-A): theta_hat fixed, injection on, estimators off, current references 0
              (the current loops keep the back-EMF from driving current).
``IDENT``     self-commissioning (``FirmwareParams.ident``): the identification program runs instead of the
              start-up (:mod:`golden.firmware.ident`); a probe or scan without HF response trips with ``FAULT_IDENT``.
``DONE``      the program has ended: gates off to the end of the run.
``FAULT``     a fault was found (``fault``: the code of :mod:`golden.firmware.protection`): the software
              overcurrent on the window means in any mode, or one of the RUN checks. Safe state: gates off
              (coast), or, when ``|omega_f|`` was above ``prot.w_asc`` at the fault and the law is
              ``LAW_FOC_PWM``, the active short circuit (zero voltage with the outputs enabled: the
              modulator keeps every leg at half duty, the line-to-line voltages at zero). ``prot.restart_n``
              periods after the tripping one the firmware starts again from CONVERGE (every state as at
              power-up, the polarity test again), at most ``prot.restarts`` times; then FAULT holds to the
              end of the run (docs/faults.md). Never after ``FAULT_HARDWARE``: the hardware's latch holds
              the gates off until someone acknowledges it (``CTRL.FAULT_CLEAR``; decision 2026-11-29:
              an overcurrent the comparator saw, a watchdog, STO or DESAT is not retried automatically).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from golden.firmware.biquad import Y_FRAC, BiquadCoef, BiquadState, biquad_step
from golden.firmware.catch_probe import PROBE_END, PROBE_GAP, probe_angles, probe_enable, probe_estimate
from golden.firmware.dc_feedforward import dc_feedforward
from golden.firmware.eemf_smo import SmoParams
from golden.firmware.fcs_law import LAW_FCS_MPC, LAW_FOC_PWM, FcsParams, deadbeat_voltage
from golden.firmware.hfo_proj import HfoParams
from golden.firmware.ident import Ident, IdentParams
from golden.firmware.estimator import (BY_ID, INJ_NONE, INJ_SQW_D, SLOT_HIGH, SLOT_LOW, Measurement,
                                       injection_voltage, park, window_voltage)
from golden.firmware.load_observer import I_FRAC, LoadObsParams, load_obs_step
from golden.firmware.lowpass import lowpass_out, lowpass_step
from golden.firmware.means import window_means
from golden.firmware.methods import CLASSES
from golden.firmware.mtpa import mtpa_lookup
from golden.firmware.pi import PiParams, pi_step
from golden.firmware.protection import (FAULT_HARDWARE, FAULT_IDENT, FAULT_NONE, FAULT_OVERCURRENT, ProtParams,
                                       dc_link_check, frozen_check, hf_learn, protect_step, slip_check)
from golden.firmware.rfo import RfoParams
from golden.firmware.rot_bpf import RotParams
from golden.firmware.sqw_bangbang import SqwParams
from golden.firmware.sqw_cic import CicParams
from golden.fixed import round_shr, sat, shr, uwrap, wrap
from golden.fpga.cordic import sincos_q15
from golden.fpga.fcs_mpc import state_voltage
from golden.fpga.demodulator import WindowResult

(MODE_CONVERGE, MODE_POL_POS, MODE_POL_NEG, MODE_RELAX, MODE_RUN, MODE_FIXED, MODE_FAULT, MODE_IDENT, MODE_DONE,
 MODE_CATCH) = range(10)
MODE_NAMES = ("CONVERGE", "POL_POS", "POL_NEG", "RELAX", "RUN", "FIXED", "FAULT", "IDENT", "DONE", "CATCH")

POL_CURRENT, POL_PILOT, POL_NONE = 0, 1, 2
"""Polarity detection: d-current pulses with the HF response (002), pilot voltages (000, Sec. II-D), or
none (a reluctance machine is pi-periodic: CONVERGE goes straight to RELAX)."""

HALF_TURN = 1 << 31
S32_MAX = (1 << 31) - 1
NOTCH_BITS = 21
"""Input width of the feedback notch (golden.firmware.biquad's input range)."""


@dataclass(frozen=True)
class FirmwareParams:
    """Integer parameters of the firmware (computed on the host by :mod:`golden.control_config`).

    Attributes
    ----------
    low, high : int
        Method ids of the estimator slots (``golden.firmware.estimator.METHOD_*``); ``high`` 0: none.
    sqw, rfo, rot, smo, cic : SqwParams, RfoParams, RotParams, SmoParams, CicParams or None
        Each method's own parameters (None when no slot uses it); one field per method.
    speed_lp : int
        Speed-filter coefficient (Q16).
    speed_pi, id_pi, iq_pi : PiParams
        Speed PI (speed LSB -> current LSB) and current PIs (current LSB -> voltage LSB).
    v_h : int
        Injection amplitude [voltage LSB] while an injecting estimator is in charge.
    i_pulse : int
        Polarity-test d-current [current LSB].
    n_converge, n_pulse, n_settle : int
        Window counts of the start-up states.
    i_trip : int
        Software overcurrent limit on the window means [current LSB].
    w_up, w_down : int
        Hand-over speeds on the filtered speed [speed LSB], 0 <= w_down <= w_up.
    merge : int
        Per-period decay of the hand-over angle offset (Q16, 0..65536).
    wd_delta, wd_speed, wd_hold : int
        The hand-over's watchdog (docs/methods.md, "The watchdog"; ``wd_delta = 0``: off): with the low slot
        in charge in RUN, when ``max(|omega_f|, |high slot's omega|) > wd_speed`` [speed LSB] and the two slots'
        angles differ by more than ``wd_delta`` [binary angle, 0..2^31], the high slot takes charge at its own
        angle and keeps it for ``wd_hold`` periods. With it on, the hand-over speeds compare that larger speed,
        and an upward hand-over whose offset exceeds ``wd_delta`` takes the high slot's angle too.
    fixed_angle : int or None
        Binary angle for the open-loop test; None for normal operation.
    inj_rot, inj_cd, inj_sd : int
        1 when the hardware's injection rotates (``CTRL.INJ_ROT``), and cos/sin of ``INJ_STEP`` (Q15):
        the supervisor then gives the estimators sin/cos of ``INJ_PHASE`` and adds the injection's window
        mean to the measured voltage (:func:`~golden.firmware.estimator.injection_voltage`, saturated to
        s32; ``v_h`` in 0..2^15 in this mode).
    inj_c2, inj_s2 : int
        cos/sin of ``2 INJ_STEP`` (Q15): from ``INJ_PHASE`` of a window to the phase of the window the
        outputs are active in.
    hf_dtc : int
        Rotating injection: the amplitude of its HF current [current LSB, 0..2^15], which the firmware
        adds to the current references it writes for the dead-time compensation (:meth:`Firmware._dtc_refs`).
    pol_mode, v_pilot : int
        ``POL_CURRENT`` or ``POL_PILOT``; the pilot voltage [voltage LSB].
    mtpa_shift, mtpa_id, mtpa_iq : int, tuple, tuple
        MTPA table (:mod:`golden.firmware.mtpa`; empty: off).
    notch : BiquadCoef or None
        Notch on the d and q current feedback of the current PIs (Tap et al. 2023, Sec. II-C); None: off.
    speed_div : int
        The speed PI runs every ``speed_div`` periods (its gains computed for that period).
    lobs : LoadObsParams
        The load-torque observer of the speed loop (:mod:`golden.firmware.load_observer`; ``g = 0``: off),
        stepped with the speed PI; its load current is added to the PI's output.
    i_slew : int
        Largest change of the current command per period [current LSB] (0: no limit): the HF estimators
        take a current step's transient for position signal (docs/methods.md).
    law, fcs : int, FcsParams or None
        The current-loop law: ``LAW_FOC_PWM`` (current PIs) or ``LAW_FCS_MPC`` (:mod:`golden.firmware.fcs_law`,
        with its parameters; the speed PI's output indexes its flux table, ``mtpa_*`` unused).
    hfo : HfoParams or None
        The ``hfo_proj`` estimator's parameters.
    prot : ProtParams
        Limits of the fault checks (:mod:`golden.firmware.protection`; all zero: every check off).
    ff_nom, ff_lo, ff_hi : int
        The dc-link voltage feed-forward (:mod:`golden.firmware.dc_feedforward`): the nominal link and the
        limits its measurement is clamped to, in codes of the dc-link channel; ``ff_nom = 0``: off.
    ident : IdentParams or None
        The self-commissioning program (:mod:`golden.firmware.ident`): the firmware runs it from power-up
        (``MODE_IDENT``) instead of the start-up; None: normal operation.
    """

    low: int
    high: int
    sqw: SqwParams | None
    rfo: RfoParams | None
    speed_lp: int
    speed_pi: PiParams
    id_pi: PiParams
    iq_pi: PiParams
    v_h: int
    i_pulse: int
    n_converge: int
    n_pulse: int
    n_settle: int
    i_trip: int
    w_up: int = 0
    w_down: int = 0
    merge: int = 0
    fixed_angle: int | None = None
    rot: RotParams | None = None
    smo: SmoParams | None = None
    cic: CicParams | None = None
    inj_rot: int = 0
    inj_cd: int = 32767
    inj_sd: int = 0
    inj_c2: int = 32767
    inj_s2: int = 0
    hf_dtc: int = 0
    pol_mode: int = POL_CURRENT
    v_pilot: int = 0
    mtpa_shift: int = 0
    mtpa_id: tuple = ()
    mtpa_iq: tuple = ()
    notch: BiquadCoef | None = None
    speed_div: int = 1
    i_slew: int = 0
    law: int = LAW_FOC_PWM
    fcs: FcsParams | None = None
    hfo: HfoParams | None = None
    prot: ProtParams = ProtParams()
    lobs: LoadObsParams = LoadObsParams()
    ff_nom: int = 0
    ff_lo: int = 0
    ff_hi: int = 0
    ident: IdentParams | None = None
    wd_delta: int = 0
    wd_speed: int = 0
    wd_hold: int = 0


@dataclass(frozen=True)
class Outputs:
    """Register values written by one interrupt (shadow registers and CTRL)."""

    v_d: int
    v_q: int
    v_h: int
    sin: int
    cos: int
    enable: int
    i_d_ref: int = 0
    i_q_ref: int = 0
    fcs_a1: int = 0                  # FCS_A.A1, s16 Q12 (direct-vector mode, spec 3.10)
    fcs_a2: int = 0                  # FCS_A.A2, s16 Q12
    fcs_phi_min: int = 0             # FCS_CTRL.PHI_MIN, u16
    fcs_constrain: int = 0           # FCS_CTRL.CONSTRAIN


RESET_OUTPUTS = Outputs(v_d=0, v_q=0, v_h=0, sin=0, cos=32767, enable=0)
"""Register reset values (docs/registers.md): what is active before the first commit."""


@dataclass
class Firmware:
    """State of the firmware's control task (see the module docstring)."""

    p: FirmwareParams
    mode: int = MODE_CONVERGE
    n: int = 0                       # windows spent in the present mode
    theta_hat: int = 0               # u32 angle in use (sin/cos written for the window after next)
    speed_f: int = 0                 # Q16 state of the speed filter
    speed_int: int = 0
    id_int: int = 0
    iq_int: int = 0
    pol_pos: int = 0
    pol_neg: int = 0
    flipped: int = 0
    i_d: int = 0                     # window means (diagnostics)
    i_q: int = 0
    i_d_ref: int = 0
    i_q_ref: int = 0
    active: int = SLOT_LOW           # estimator slot in charge
    est_theta: list = field(default_factory=lambda: [0, 0])   # each slot's angle output (u32)
    est_omega: list = field(default_factory=lambda: [0, 0])   # each slot's speed output (s32)
    offset: int = 0                  # s32 hand-over angle offset (angle in use - high slot's angle)
    speed_cnt: int = 0               # periods since the last speed-PI step (0..speed_div-1)
    i_s_ref: int = 0                 # speed-PI output, held between its steps
    i_s_cmd: int = 0                 # the current command: i_s_ref through the slew limit
    lobs_w: int = 0                  # load observer: speed (Q16) and load current (Q32)
    lobs_i: int = 0
    nd: BiquadState = field(default_factory=BiquadState)   # notch states of the d and q feedback
    nq: BiquadState = field(default_factory=BiquadState)
    act: list = field(default_factory=lambda: [RESET_OUTPUTS, RESET_OUTPUTS])  # outputs of steps k-2, k-1
    prev: Outputs = RESET_OUTPUTS    # outputs of step k-3 (active in the window before)
    vec_before: int = 0              # fcs_mpc: VECTOR of the previous step (the state before this one's)
    fault: int = FAULT_NONE          # fault code (golden.firmware.protection), set with MODE_FAULT
    asc: int = 0                     # 1: the safe state is the active short circuit
    emf_d: int = 0                   # protection filters and overload counts (golden.firmware.protection)
    emf_q: int = 0
    track_f: int = 0
    ovl_n: int = 0
    ovl_e: int = 0
    e0: int = 0
    ld_w: int = 0                    # overload check's load part: the last filtered speed, whether it holds one,
    ld_n: int = 0                    # and the filtered load acceleration
    ld_f: int = 0
    w_catch: int = 0                 # a flying start's caught speed (overspeed counts from it to the hand-over down)
    hf_ref: int = 0                  # HF response check: learned GAMMA_D and the filtered deviation from it
    hf_f: int = 0
    vdc_lo_n: int = 0                # dc-link check: periods in a row below / above its limits
    vdc_hi_n: int = 0
    frz_a: int = 0                   # sensor check: periods in a row with lane A / B frozen
    frz_b: int = 0
    probe: int = 0                   # flying-start probe (golden.firmware.catch_probe): 0 on, 1 found, -1 off this start
    pr_x0: int = 0                   # its gates-off window means (the sensors' offsets), pulse 1's mean less them,
    pr_y0: int = 0                   # the angle found and the advance
    pr_x1: int = 0
    pr_y1: int = 0
    pr_theta: int = 0
    pr_delta: int = 0
    restarts: int = 0                # automatic restarts done
    wd_n: int = 0                    # the hand-over's watchdog: periods its hand-over still holds
    slip_left: int = 0               # the slip check (golden.firmware.protection.slip_check): periods still armed
    ident: Ident | None = None       # the identification program's executor (FirmwareParams.ident)
    slots: list = field(init=False)

    def __post_init__(self) -> None:
        p = self.p
        self.slots = [None if m == 0 else CLASSES[m](getattr(p, CLASSES[m].PARAMS)) for m in (p.low, p.high)]
        if p.ident is not None:
            self.mode, self.ident = MODE_IDENT, Ident(p.ident)
        elif p.fixed_angle is not None:
            self.mode = MODE_FIXED
            self.theta_hat = uwrap(p.fixed_angle, 32)
        elif p.prot.catch_n > 0 and self.slots[SLOT_HIGH] is not None:
            self.mode, self.active = MODE_CATCH, SLOT_HIGH

    @property
    def omega_f(self) -> int:
        """Filtered speed estimate [binary angle per period]."""
        return lowpass_out(self.speed_f)

    def _next(self, mode: int) -> None:
        self.mode, self.n = mode, 0

    def _restart(self) -> None:
        """Every state as at power-up, except the fault code, the restart count and the output history (the
        registers the hardware still holds)."""
        keep = (self.fault, self.restarts + 1, self.act, self.prev)
        self.__init__(self.p)
        self.fault, self.restarts, self.act, self.prev = keep

    def _trip(self, code: int) -> None:
        """Enter FAULT with ``code``; choose the safe state (module docstring)."""
        p = self.p
        self.fault = code
        self.asc = int(p.prot.w_asc > 0 and abs(self.omega_f) > p.prot.w_asc and p.law == LAW_FOC_PWM)
        self._next(MODE_FAULT)

    def step(self, win: WindowResult, speed_ref: int) -> Outputs:
        """One interrupt: window results in, register writes out."""
        p = self.p
        if (self.mode == MODE_FAULT and self.restarts < p.prot.restarts and self.n >= p.prot.restart_n
                and self.fault != FAULT_HARDWARE):
            self._restart()
        self.i_d, self.i_q = i_d, i_q = window_means(win.sum_id, win.sum_iq, win.n_samples)
        self.n += 1
        i_d_prev, i_q_prev = self.i_d_ref, self.i_q_ref       # the references of the last period
        if self.mode != MODE_FAULT and win.status != 0:
            self._trip(FAULT_HARDWARE)
        elif self.mode != MODE_FAULT and (abs(i_d) > p.i_trip or abs(i_q) > p.i_trip):
            self._trip(FAULT_OVERCURRENT)
        if self.mode != MODE_FAULT and (dc := dc_link_check(self, p.prot, win.vdc)) != FAULT_NONE:
            self._trip(dc)
        if self.mode in (MODE_IDENT, MODE_DONE):
            out = self._ident_outputs(win, i_d, i_q) if self.mode == MODE_IDENT else RESET_OUTPUTS
            self.prev = self.act[0]
            self.act = [self.act[1], out]
            return out
        if self.mode == MODE_CATCH and p.prot.probe_min and self.probe >= 0 and self.n < PROBE_END:
            out = self._probe(i_d, i_q)
            if out is not None:
                return self._emit(out, win)
        pilot = None
        s_inj, c_inj = sincos_q15(win.inj_phase) if p.inj_rot else (0, 32767)
        if self.mode in (MODE_FIXED, MODE_FAULT):
            i_d_ref = i_q_ref = 0
        else:
            now, before = self.act[0], self.prev               # register sets active in this window and before
            v_al, v_be = window_voltage(now, before)
            if p.inj_rot:
                a, b = injection_voltage(now.v_h, before.v_h, s_inj, c_inj, p.inj_cd, p.inj_sd)
                v_al, v_be = sat(v_al + a, 32), sat(v_be + b, 32)
            m = Measurement(win, i_d, i_q, now.sin, now.cos, v_al, v_be, s_inj, c_inj)
            hf = win.gamma_d if self._square_wave_on(now, before) else None
            if self.mode == MODE_CONVERGE and hf is not None:
                hf_learn(self, p.prot, hf)
            if not self._frozen():
                self._estimate(m)
            if self.active == SLOT_HIGH:
                self.offset -= shr(self.offset * p.merge, 16)
            self.speed_f = lowpass_step(self.speed_f, self.est_omega[self.active], p.speed_lp)
            i_d_ref, i_q_ref, pilot = self._supervise(win)
            if self.mode == MODE_RUN:
                slip = self._hand_over()
                i_d_ref, i_q_ref = self._run_refs(speed_ref)
                fcs = p.law == LAW_FCS_MPC and p.prot.emf_tol != 0      # only the lock check reads it
                v_d, v_q = self._applied_dq(win, now) if fcs else (now.v_d, now.v_q)
                frozen = frozen_check(self, p.prot, win.frozen, win.n_samples)   # the sensor first: the cause
                code = protect_step(self, p.prot, v_d, v_q, i_d, i_q, i_d_prev, i_q_prev, self.omega_f,
                                    speed_ref, abs(self.i_s_ref) >= p.speed_pi.limit, hf)
                code = code if code != FAULT_NONE else slip
                if frozen != FAULT_NONE or code != FAULT_NONE:
                    self._trip(frozen if frozen != FAULT_NONE else code)
            self.theta_hat = self._angle()
        self.i_d_ref, self.i_q_ref = i_d_ref, i_q_ref
        i_d_f, i_q_f = self._feedback(i_d, i_q)
        if self.mode == MODE_FAULT:
            self.id_int = self.iq_int = 0
            out = Outputs(0, 0, 0, *sincos_q15(self.theta_hat), 1) if self.asc else RESET_OUTPUTS
        elif p.law == LAW_FCS_MPC:
            out = self._fcs_outputs(win, i_q_ref)
        else:
            if pilot is None:
                v_d, self.id_int = pi_step(self.id_int, i_d_ref, i_d_f, p.id_pi)
                v_q, self.iq_int = pi_step(self.iq_int, i_q_ref, i_q_f, p.iq_pi)
            else:                                              # pilot voltage: current control off
                v_d, v_q, self.id_int, self.iq_int = pilot, 0, 0, 0
            s, c = sincos_q15(self.theta_hat)
            v_h = p.v_h if self._injecting() else 0
            r_d, r_q = self._dtc_refs(i_d_ref, i_q_ref, v_h, s_inj, c_inj, s, c)
            out = Outputs(v_d, v_q, v_h, s, c, 1, r_d, r_q)
        return self._emit(out, win)

    def _emit(self, out: Outputs, win: WindowResult) -> Outputs:
        """The step's outputs into the history of the register sets (the voltages applied: the estimators' and
        checks'), then through the dc-link feed-forward when it is on."""
        p = self.p
        self.prev = self.act[0]
        self.act = [self.act[1], out]
        if p.ff_nom and p.law == LAW_FOC_PWM:
            out = dc_feedforward(out, win.vdc, p.ff_nom, p.ff_lo, p.ff_hi)
        return out

    def _probe(self, i_d: int, i_q: int) -> Outputs | None:
        """Steps 1 .. PROBE_END - 1 of the flying start's probe (golden.firmware.catch_probe): the stator frame, zero
        voltage, the pulses' enables; at the last the estimate, and if found the back-EMF's voltage in the frame of
        the window after next. None
        (the current-control catch instead, from this step on) when the gates were on in window 0 (a restart from
        the active short circuit: no clean offsets)."""
        p, n = self.p, self.n
        if n == 1:
            if self.act[0].enable or self.act[1].enable:
                self.probe = -1
                return None
            self.pr_x0, self.pr_y0 = i_d, i_q
        elif n == 2:
            self.pr_x1, self.pr_y1 = sat(i_d - self.pr_x0, 32), sat(i_q - self.pr_y0, 32)
        elif n == PROBE_GAP + 2:
            found, theta, delta = probe_estimate(self.pr_x1, self.pr_y1, sat(i_d - self.pr_x0, 32),
                                                 sat(i_q - self.pr_y0, 32), p.prot.probe_min)
            self.probe = 1 if found else -1
            if found:
                self.pr_theta, self.pr_delta = theta, delta
                omega, theta_a, _ = probe_angles(theta, delta)
                self.theta_hat = theta_a                   # the angle whose sin/cos this step writes
                s, c = sincos_q15(theta_a)
                return Outputs(0, self._back_emf(omega), 0, s, c, 0)
        return Outputs(0, 0, 0, 0, 32767, probe_enable(n))

    def _back_emf(self, omega: int) -> int:
        """The q voltage that cancels the back-EMF at ``omega`` (``shr(omega psi_f, 32)``, protection's units),
        within the current PI's limit."""
        lim = self.p.iq_pi.limit
        return min(max(shr(omega * self.p.prot.psi_f, 32), -lim), lim)

    def _ident_outputs(self, win: WindowResult, i_d: int, i_q: int) -> Outputs:
        """``MODE_IDENT``: one window of the identification program (:mod:`golden.firmware.ident`); gates off
        at its end (``MODE_DONE``) or when a probe or the scan saw no HF response (``FAULT_IDENT``)."""
        idn = self.ident
        idn.measure(i_d, i_q, win.gamma_d, win.gamma, self.act[0], self.prev)
        if idn.failed:
            self._trip(FAULT_IDENT)
            return RESET_OUTPUTS
        if idn.done:
            self._next(MODE_DONE)
            return RESET_OUTPUTS
        v_d, v_q, v_h, self.theta_hat, self.i_d_ref, self.i_q_ref = idn.refs(i_d, i_q, self)
        s, c = sincos_q15(self.theta_hat)
        return Outputs(v_d, v_q, v_h, s, c, 1, self.i_d_ref, self.i_q_ref)

    def _fcs_outputs(self, win: WindowResult, i_s: int) -> Outputs:
        """The ``fcs_mpc`` law (:mod:`golden.firmware.fcs_law`): the deadbeat voltage for the angle in use
        and the estimator's flux, its constraint coefficients; ``i_s`` the current command (the speed PI's
        output in RUN, 0 before)."""
        p, est = self.p, self.slots[self.active]
        v_d, v_q = deadbeat_voltage(p.fcs, est.psi_al, est.psi_be, win.top_ia, win.top_ib, self.vec_before,
                                    win.vector, win.vector_next, self.theta_hat, est.omega, i_s)
        self.vec_before = win.vector
        s, c = sincos_q15(self.theta_hat)
        return Outputs(v_d, v_q, 0, s, c, 1, 0, 0, est.fcs_a1, est.fcs_a2, p.fcs.phi_min, est.constrain)

    def _applied_dq(self, win: WindowResult, now: Outputs) -> tuple[int, int]:
        """Under the ``fcs_mpc`` law, the voltage the inverter applied in the window, in the frame active in it
        (the lock check's ``v``): the state chosen at the window's carrier top (``VECTOR``) for its last three
        quarters, the one before (``vec_before``) for its first, at the nominal link (``state_voltage``)."""
        a0, b0 = state_voltage(self.vec_before)
        a1, b1 = state_voltage(win.vector)
        return park(shr(a0 + 3 * a1, 2), shr(b0 + 3 * b1, 2), now.sin, now.cos)

    def _dtc_refs(self, i_d_ref: int, i_q_ref: int, v_h: int, s_i: int, c_i: int, s: int, c: int) -> tuple[int, int]:
        """The currents written to I_D_REF / I_Q_REF, which only the dead-time compensation reads: the
        references, plus, while the rotating injection is on, its predicted HF current in the window the
        outputs are active in (phase ``INJ_PHASE + 2 INJ_STEP``: ``(s_i, c_i)`` of ``INJ_PHASE`` turned by
        ``(inj_s2, inj_c2)``; the positive sequence lags the voltage by a quarter turn: ``hf_dtc (sin,
        -cos)`` in the stationary frame), turned into the frame ``(s, c)``. Without it the compensation
        guesses the sign of the HF current wrong around zero fundamental current: 7.6 deg of angle bias at
        standstill on the Table 1 motor (docs/methods.md). All roundings ``round_shr(., 15)``; the results
        saturated to s32."""
        p = self.p
        if not p.inj_rot or v_h == 0:
            return i_d_ref, i_q_ref
        s_n, c_n = round_shr(s_i * p.inj_c2 + c_i * p.inj_s2, 15), round_shr(c_i * p.inj_c2 - s_i * p.inj_s2, 15)
        h_al, h_be = round_shr(p.hf_dtc * s_n, 15), -round_shr(p.hf_dtc * c_n, 15)
        return (sat(i_d_ref + round_shr(h_al * c + h_be * s, 15), 32),
                sat(i_q_ref + round_shr(h_be * c - h_al * s, 15), 32))

    def _frozen(self) -> bool:
        """Pilot-voltage polarity detection: the estimators are not stepped from the first window without
        injection to the end of RELAX (the pulses, the gaps, and the decay of the last pulse under current
        control); at the start of RUN the low slot restarts by ``sync`` at its own angle (its filters
        would otherwise take the pulses' current transients for HF response, _relax)."""
        return self.p.pol_mode == POL_PILOT and self.mode in (MODE_POL_POS, MODE_POL_NEG, MODE_RELAX)

    def _sync(self, slot: int, theta: int, omega: int) -> None:
        """``sync`` a slot's estimator and take its outputs."""
        est = self.slots[slot]
        est.sync(theta, omega)
        self.est_theta[slot], self.est_omega[slot] = est.theta, est.omega

    def _square_wave_on(self, now: Outputs, before: Outputs) -> bool:
        """The square wave on d_hat (INJ_SQW_D) was on for the whole window: the estimator in charge injects
        it, and the register sets active in the window and in the one before both have ``V_H != 0``."""
        return (BY_ID[self.slots[self.active].METHOD].injection == INJ_SQW_D
                and now.v_h != 0 and before.v_h != 0)

    def _injecting(self) -> bool:
        """Whether the outputs of this step carry the injection."""
        if self.mode == MODE_FIXED:
            return True
        if self.p.pol_mode == POL_PILOT and self.mode in (MODE_POL_POS, MODE_POL_NEG):
            return False
        return BY_ID[self.slots[self.active].METHOD].injection != INJ_NONE

    def _feedback(self, i_d: int, i_q: int) -> tuple[int, int]:
        """The current PIs' feedback: the window means, through the notch when there is one (its input
        saturated to its range, +-2^20: beyond i_trip in every real configuration)."""
        if self.p.notch is None:
            return i_d, i_q
        self.nd = biquad_step(self.nd, sat(i_d, NOTCH_BITS), self.p.notch)
        self.nq = biquad_step(self.nq, sat(i_q, NOTCH_BITS), self.p.notch)
        return round_shr(self.nd.y1, Y_FRAC), round_shr(self.nq.y1, Y_FRAC)

    def _run_refs(self, speed_ref: int) -> tuple[int, int]:
        """RUN: the speed PI every ``speed_div`` periods, the slew limit (``i_slew``; the clamp is done in
        s64, ``i_slew`` <= 2^30), then MTPA (if a table is given)."""
        p = self.p
        if self.speed_cnt == 0:
            u, self.speed_int = pi_step(self.speed_int, speed_ref, self.omega_f, p.speed_pi)
            if p.lobs.g != 0:
                lim = p.speed_pi.limit
                self.lobs_w, self.lobs_i = load_obs_step(self.lobs_w, self.lobs_i, self.omega_f, self.i_s_cmd,
                                                         p.lobs, lim)
                u = min(max(u + shr(self.lobs_i, I_FRAC), -lim), lim)
            self.i_s_ref = u
        self.speed_cnt = self.speed_cnt + 1 if self.speed_cnt + 1 < p.speed_div else 0
        if p.i_slew > 0:
            self.i_s_cmd = min(max(self.i_s_ref, self.i_s_cmd - p.i_slew), self.i_s_cmd + p.i_slew)
        else:
            self.i_s_cmd = self.i_s_ref
        i_d_est = self.slots[self.active].i_d
        if not p.mtpa_id:
            return i_d_est, self.i_s_cmd
        i_d, i_q = mtpa_lookup(abs(self.i_s_cmd), p.mtpa_shift, p.mtpa_id, p.mtpa_iq)
        return min(i_d, i_d_est), (-i_q if self.i_s_cmd < 0 else i_q)

    def _estimate(self, m: Measurement) -> None:
        """Step the low-speed slot while it is in charge, the high-speed slot always (in parallel)."""
        for slot, est in enumerate(self.slots):
            if est is not None and (slot == SLOT_HIGH or self.active == SLOT_LOW):
                est.step(m)
                self.est_theta[slot], self.est_omega[slot] = est.theta, est.omega

    def _angle(self) -> int:
        """The angle in use: the low slot's, or the high slot's plus the hand-over offset."""
        if self.active == SLOT_LOW:
            return self.est_theta[SLOT_LOW]
        return uwrap(self.est_theta[SLOT_HIGH] + self.offset, 32)

    def _hand_over(self) -> int:
        """Benevieri et al. 2023, Sec. IV-F: switch slots at w_up / w_down (hysteresis), bumpless; with the
        watchdog on (``wd_delta``), also when the two slots' angles disagree (FirmwareParams, docs/methods.md).
        Before, the slip check (golden.firmware.protection.slip_check) on the slots as they are; returns its code."""
        p, hi = self.p, self.slots[SLOT_HIGH]
        if hi is None:
            return FAULT_NONE
        gap = wrap(self.est_theta[SLOT_LOW] - self.est_theta[SLOT_HIGH], 32)
        slip = slip_check(self, p.prot, self.active == SLOT_LOW, gap, self.omega_f, self.est_omega[SLOT_HIGH])
        w = abs(self.omega_f)
        if p.wd_delta:
            if self.wd_n > 0:
                self.wd_n -= 1
                return slip
            w = max(w, abs(self.est_omega[SLOT_HIGH]))
        if self.active == SLOT_LOW:
            wrong = p.wd_delta and abs(gap) > p.wd_delta
            if w > p.w_up:
                self.active, self.offset = SLOT_HIGH, 0 if wrong else gap
            elif wrong and w > p.wd_speed:
                self.active, self.offset, self.wd_n = SLOT_HIGH, 0, p.wd_hold
        elif w < p.w_down:
            theta = self._angle()
            self.active, self.w_catch = SLOT_LOW, 0           # a flying start's raised speed limit ends here
            self._sync(SLOT_LOW, theta, self.est_omega[SLOT_HIGH])
        return slip

    def _supervise(self, win: WindowResult) -> tuple[int, int, int | None]:
        """Start-up state machine; returns (i_d*, i_q*, pilot voltage or None) before the speed loop."""
        if self.mode == MODE_CATCH:
            self._catch()
            spinning = 2 * self.n > self.p.prot.catch_n and abs(self.omega_f) >= self.p.w_down
            return (self.slots[self.active].i_d if spinning else 0), 0, None
        if self.p.pol_mode == POL_PILOT:
            return self._supervise_pilot()
        p = self.p
        if p.pol_mode == POL_NONE:
            if self.mode == MODE_CONVERGE and self.n >= p.n_converge:
                self._next(MODE_RELAX)
            self._relax()
            return self.slots[self.active].i_d, 0, None     # a reluctance machine: magnetized as the estimator asks
        if self.mode == MODE_CONVERGE:
            if self.n >= p.n_converge:
                self._next(MODE_POL_POS)
                return p.i_pulse, 0, None
            return 0, 0, None
        if self.mode == MODE_POL_POS:
            if self.n > p.n_settle:
                self.pol_pos += win.gamma_d
            if self.n >= p.n_pulse:
                self._next(MODE_POL_NEG)
                return -p.i_pulse, 0, None
            return p.i_pulse, 0, None
        if self.mode == MODE_POL_NEG:
            if self.n > p.n_settle:
                self.pol_neg += win.gamma_d
            if self.n >= p.n_pulse:
                self._decide_polarity()
                self._next(MODE_RELAX)
                return 0, 0, None
            return -p.i_pulse, 0, None
        self._relax()
        return 0, 0, None

    def _supervise_pilot(self) -> tuple[int, int, int | None]:
        """Tap et al. 2023, Sec. II-D: pilot voltages +-V_p on d_hat, each after ``n_settle`` windows of
        current control to zero without injection (the HF current and the first pulse decay); the
        d-current of each pulse's last window, measured at the next state's first window (two periods
        after the step that wrote the pulse), decides."""
        p = self.p
        if self.mode == MODE_CONVERGE:
            if self.n >= p.n_converge:
                self._next(MODE_POL_POS)
            return 0, 0, None
        if self.mode in (MODE_POL_POS, MODE_POL_NEG):
            if self.n == 1 and self.mode == MODE_POL_NEG:
                self.pol_pos = self.i_d
            if self.n >= p.n_settle + p.n_pulse:
                self._next(MODE_POL_NEG if self.mode == MODE_POL_POS else MODE_RELAX)
                return 0, 0, None
            v = p.v_pilot if self.mode == MODE_POL_POS else -p.v_pilot
            return 0, 0, (v if self.n >= p.n_settle else None)
        if self.mode == MODE_RELAX and self.n == 1:
            self.pol_neg = -self.i_d
            self._decide_polarity()
        self._relax()
        return 0, 0, None

    def _catch(self) -> None:
        """CATCH (the module docstring): after ``catch_n`` windows, RUN on the high slot or the standstill start. At
        window PROBE_END a probe that found the rotor starts the current-control catch from it: the high slot synced
        to the probe's angle and speed, the speed filter at that speed, the q current PI's integrator at the
        back-EMF's voltage (its first window then applies that voltage, not the short circuit)."""
        p = self.p
        if self.probe == 1 and self.n == PROBE_END:
            omega, _, theta_b = probe_angles(self.pr_theta, self.pr_delta)
            self.probe = -1
            self.speed_f = omega << 16
            self._sync(SLOT_HIGH, theta_b, omega)
            self.id_int, self.iq_int = 0, self._back_emf(omega) << p.iq_pi.si
        if self.n < p.prot.catch_n:
            return
        if abs(self.omega_f) >= p.w_down:
            self.w_catch = min(abs(self.omega_f), S32_MAX)
            self._next(MODE_RUN)
            self._sync(SLOT_HIGH, self.est_theta[SLOT_HIGH], self.est_omega[SLOT_HIGH])
        else:
            self.active, self.speed_f = SLOT_LOW, 0
            self._next(MODE_CONVERGE)

    def _decide_polarity(self) -> None:
        """The larger response is the magnet's north: if it is the -d_hat one, turn the low slot."""
        if self.pol_neg > self.pol_pos:
            lo = self.slots[SLOT_LOW]
            lo.turn(HALF_TURN)
            self.est_theta[SLOT_LOW] = lo.theta
            self.flipped = 1

    def _relax(self) -> None:
        """RELAX: after ``n_settle`` windows, RUN (after pilot pulses the low slot restarts at its own
        angle, :meth:`_frozen`); the high slot starts from the low slot's angle."""
        if self.mode == MODE_RELAX and self.n >= self.p.n_settle:
            self._next(MODE_RUN)
            if self.p.pol_mode == POL_PILOT:
                self._sync(SLOT_LOW, self.est_theta[SLOT_LOW], 0)
            if self.slots[SLOT_HIGH] is not None:
                self._sync(SLOT_HIGH, self.est_theta[SLOT_LOW], self.est_omega[SLOT_LOW])

    def angle_error(self, theta_true: int) -> int:
        """wrap(theta - theta_hat, 32) for diagnostics."""
        return wrap(theta_true - self.theta_hat, 32)
