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

``CONVERGE``  low-speed estimator in charge, current references 0: theta_hat settles on the +-d axis.
              Its last window already asks for +I_p, so both polarity pulses last ``n_pulse`` windows.
``POL_POS``   i_d* = +I_p; after ``n_settle`` windows gamma_d is summed (HF d-current response).
``POL_NEG``   i_d* = -I_p, summed the same way. A larger response means a smaller incremental
              inductance, i.e. saturation, i.e. the magnet's north: if the -I_p sum is the larger,
              the low-speed estimator is turned by half a turn (polarity detection by d-axis
              saturation, the method the paper cites as [23], [30]).
``RELAX``     i_d* = 0 for ``n_settle`` windows; at its end the high-speed estimator (if any) is
              synchronised to the low-speed one's angle and speed.
``RUN``       speed PI on the filtered speed of the estimator in charge -> i_q*, i_d* as that estimator
              asks (``Estimator.i_d``: 0, or the rotor flux observer's minimum current). Hand-over
              (Benevieri et al. 2023, Sec. IV-F): above ``w_up`` (|filtered speed|) the high-speed
              estimator takes charge, below ``w_down`` the low-speed one again. Bumpless: taking charge
              upwards, the angle in use keeps its value and the difference to the new estimator decays
              by ``merge`` (Q16) per period; downwards, the low-speed estimator continues from the angle
              and speed in use (``sync``). The injection follows the estimator in charge.
``FIXED``     open-loop test (paper Sec. IV-A): theta_hat fixed, injection on, estimators off, current references 0
              (the current loops keep the back-EMF from driving current).
``FAULT``     outputs disabled (software overcurrent on the window means).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from golden.firmware.estimator import BY_ID, INJ_SQW_D, SLOT_HIGH, SLOT_LOW, Measurement, window_voltage
from golden.firmware.lowpass import lowpass_out, lowpass_step
from golden.firmware.means import window_means
from golden.firmware.methods import CLASSES
from golden.firmware.pi import PiParams, pi_step
from golden.firmware.rfo import RfoParams
from golden.firmware.sqw_bangbang import SqwParams
from golden.fixed import shr, uwrap, wrap
from golden.fpga.cordic import sincos_q15
from golden.fpga.demodulator import WindowResult

MODE_CONVERGE, MODE_POL_POS, MODE_POL_NEG, MODE_RELAX, MODE_RUN, MODE_FIXED, MODE_FAULT = range(7)
MODE_NAMES = ("CONVERGE", "POL_POS", "POL_NEG", "RELAX", "RUN", "FIXED", "FAULT")

HALF_TURN = 1 << 31


@dataclass(frozen=True)
class FirmwareParams:
    """Integer parameters of the firmware (computed on the host by :mod:`golden.control_config`).

    Attributes
    ----------
    low, high : int
        Method ids of the estimator slots (``golden.firmware.estimator.METHOD_*``); ``high`` 0: none.
    sqw, rfo : SqwParams or None, RfoParams or None
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
    fixed_angle : int or None
        Binary angle for the open-loop test; None for normal operation.
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
    act: list = field(default_factory=lambda: [RESET_OUTPUTS, RESET_OUTPUTS])  # outputs of steps k-2, k-1
    prev: Outputs = RESET_OUTPUTS    # outputs of step k-3 (active in the window before)
    slots: list = field(init=False)

    def __post_init__(self) -> None:
        p = self.p
        self.slots = [None if m == 0 else CLASSES[m](getattr(p, CLASSES[m].PARAMS)) for m in (p.low, p.high)]
        if p.fixed_angle is not None:
            self.mode = MODE_FIXED
            self.theta_hat = uwrap(p.fixed_angle, 32)

    @property
    def omega_f(self) -> int:
        """Filtered speed estimate [binary angle per period]."""
        return lowpass_out(self.speed_f)

    def _next(self, mode: int) -> None:
        self.mode, self.n = mode, 0

    def step(self, win: WindowResult, speed_ref: int) -> Outputs:
        """One interrupt: window results in, register writes out."""
        p = self.p
        self.i_d, self.i_q = i_d, i_q = window_means(win.sum_id, win.sum_iq, win.n_samples)
        self.n += 1
        if self.mode != MODE_FAULT and (abs(i_d) > p.i_trip or abs(i_q) > p.i_trip):
            self._next(MODE_FAULT)
        if self.mode in (MODE_FIXED, MODE_FAULT):
            i_d_ref = i_q_ref = 0
        else:
            now, before = self.act[0], self.prev               # register sets active in this window and before
            m = Measurement(win, i_d, i_q, now.sin, now.cos, *window_voltage(now, before))
            self._estimate(m)
            if self.active == SLOT_HIGH:
                self.offset -= shr(self.offset * p.merge, 16)
            self.speed_f = lowpass_step(self.speed_f, self.est_omega[self.active], p.speed_lp)
            i_d_ref, i_q_ref = self._supervise(win)
            if self.mode == MODE_RUN:
                self._hand_over()
                i_d_ref = self.slots[self.active].i_d
                i_q_ref, self.speed_int = pi_step(self.speed_int, speed_ref, self.omega_f, p.speed_pi)
            self.theta_hat = self._angle()
        self.i_d_ref, self.i_q_ref = i_d_ref, i_q_ref
        if self.mode == MODE_FAULT:
            self.id_int = self.iq_int = 0
            out = RESET_OUTPUTS
        else:
            v_d, self.id_int = pi_step(self.id_int, i_d_ref, i_d, p.id_pi)
            v_q, self.iq_int = pi_step(self.iq_int, i_q_ref, i_q, p.iq_pi)
            s, c = sincos_q15(self.theta_hat)
            inj = self.mode == MODE_FIXED or BY_ID[self.slots[self.active].METHOD].injection == INJ_SQW_D
            out = Outputs(v_d, v_q, p.v_h if inj else 0, s, c, 1, i_d_ref, i_q_ref)
        self.prev = self.act[0]
        self.act = [self.act[1], out]
        return out

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

    def _hand_over(self) -> None:
        """Benevieri et al. 2023, Sec. IV-F: switch slots at w_up / w_down (hysteresis), bumpless."""
        p, hi = self.p, self.slots[SLOT_HIGH]
        if hi is None:
            return
        w = abs(self.omega_f)
        if self.active == SLOT_LOW and w > p.w_up:
            self.active = SLOT_HIGH
            self.offset = wrap(self.est_theta[SLOT_LOW] - self.est_theta[SLOT_HIGH], 32)
        elif self.active == SLOT_HIGH and w < p.w_down:
            theta = self._angle()
            self.active = SLOT_LOW
            lo = self.slots[SLOT_LOW]
            lo.sync(theta, self.est_omega[SLOT_HIGH])
            self.est_theta[SLOT_LOW], self.est_omega[SLOT_LOW] = lo.theta, lo.omega

    def _supervise(self, win: WindowResult) -> tuple[int, int]:
        """Start-up state machine; returns (i_d*, i_q*) before the speed loop."""
        p = self.p
        if self.mode == MODE_CONVERGE:
            if self.n >= p.n_converge:
                self._next(MODE_POL_POS)
                return p.i_pulse, 0
            return 0, 0
        if self.mode == MODE_POL_POS:
            if self.n > p.n_settle:
                self.pol_pos += win.gamma_d
            if self.n >= p.n_pulse:
                self._next(MODE_POL_NEG)
                return -p.i_pulse, 0
            return p.i_pulse, 0
        if self.mode == MODE_POL_NEG:
            if self.n > p.n_settle:
                self.pol_neg += win.gamma_d
            if self.n >= p.n_pulse:
                if self.pol_neg > self.pol_pos:   # the -d direction saturates: theta_hat is off by pi
                    lo = self.slots[SLOT_LOW]
                    lo.turn(HALF_TURN)
                    self.est_theta[SLOT_LOW] = lo.theta
                    self.flipped = 1
                self._next(MODE_RELAX)
                return 0, 0
            return -p.i_pulse, 0
        if self.mode == MODE_RELAX:
            if self.n >= p.n_settle:
                self._next(MODE_RUN)
                hi = self.slots[SLOT_HIGH]
                if hi is not None:
                    hi.sync(self.est_theta[SLOT_LOW], self.est_omega[SLOT_LOW])
                    self.est_theta[SLOT_HIGH], self.est_omega[SLOT_HIGH] = hi.theta, hi.omega
        return 0, 0

    def angle_error(self, theta_true: int) -> int:
        """wrap(theta - theta_hat, 32) for diagnostics."""
        return wrap(theta_true - self.theta_hat, 32)
