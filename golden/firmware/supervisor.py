"""The firmware's control task, run once per PWM period on the window interrupt (docs/spec.md, 5).

One call of :meth:`Firmware.step` is one interrupt: it reads the latched window results, runs the
estimator (bang-bang + PLL + speed filter), the supervisor state machine (start-up with polarity
detection, then speed control), the current controllers, and returns the register values the
firmware writes (shadow registers, committed at the next window boundary, and ``CTRL``).

Every operation is integer arithmetic from :mod:`golden.fixed` and the function modules beside this
one; the C firmware performs the same calls in the same order.

States (``MODE_*``):

``CONVERGE``  injection on, current references 0, estimator running: θ̂ settles on the ±d axis.
``POL_POS``   i_d* = +I_p; after ``n_settle`` windows γ_d is summed (HF d-current response).
``POL_NEG``   i_d* = −I_p, summed the same way. A larger response means a smaller incremental
              inductance, i.e. saturation, i.e. the magnet's north: if the −I_p sum is the larger,
              θ̂ (and the PLL) are turned by half a turn (polarity detection by d-axis saturation,
              the method the paper cites as [23], [30]).
``RELAX``     i_d* = 0 for ``n_settle`` windows.
``RUN``       speed PI on the filtered PLL speed -> i_q*, i_d* = 0.
``FIXED``     open-loop test (paper Sec. IV-A): θ̂ fixed, estimator off, current references 0
              (the current loops keep the back-EMF from driving current, PITFALLS 10).
``FAULT``     outputs disabled (software overcurrent on the window means).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from golden.firmware.bangbang import bangbang_step
from golden.firmware.lowpass import lowpass_out, lowpass_step
from golden.firmware.means import window_means
from golden.firmware.pi import PiParams, pi_step
from golden.firmware.pll import PllState, pll_step
from golden.fixed import uwrap, wrap
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
    k_bb : int
        Bang-bang step [binary angle per period].
    pll_kp, pll_ki : int
        PLL gains (Q16, Q24).
    speed_lp : int
        Speed-filter coefficient (Q16).
    speed_pi, id_pi, iq_pi : PiParams
        Speed PI (speed LSB -> current LSB) and current PIs (current LSB -> voltage LSB).
    v_h : int
        Injection amplitude [voltage LSB].
    i_pulse : int
        Polarity-test d-current [current LSB].
    n_converge, n_pulse, n_settle : int
        Window counts of the start-up states.
    i_trip : int
        Software overcurrent limit on the window means [current LSB].
    fixed_angle : int or None
        Binary angle for the open-loop test; None for normal operation.
    """

    k_bb: int
    pll_kp: int
    pll_ki: int
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


@dataclass
class Firmware:
    """State of the firmware's control task (see the module docstring)."""

    p: FirmwareParams
    mode: int = MODE_CONVERGE
    n: int = 0                       # windows spent in the present mode
    theta_hat: int = 0               # u32 estimated electrical angle
    pll: PllState = field(default_factory=lambda: PllState(0, 0, 0))
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
    active: int = 0                  # estimator slot in charge: 0 low-speed, 1 high-speed
    est_theta: list = field(default_factory=lambda: [0, 0])   # each slot's angle output (u32)
    est_omega: list = field(default_factory=lambda: [0, 0])   # each slot's speed output (s32)

    def __post_init__(self) -> None:
        if self.p.fixed_angle is not None:
            self.mode = MODE_FIXED
            self.theta_hat = uwrap(self.p.fixed_angle, 32)

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
            # Benevieri et al. 2023, Fig. 1: bang-bang on gamma, integrated to theta_hat; PLL -> speed
            self.theta_hat = bangbang_step(self.theta_hat, win.gamma, p.k_bb)
            self.pll = pll_step(self.pll, self.theta_hat, p.pll_kp, p.pll_ki)
            self.speed_f = lowpass_step(self.speed_f, self.pll.omega, p.speed_lp)
            i_d_ref, i_q_ref = self._supervise(win)
            if self.mode == MODE_RUN:
                i_q_ref, self.speed_int = pi_step(self.speed_int, speed_ref, self.omega_f, p.speed_pi)
        self.i_d_ref, self.i_q_ref = i_d_ref, i_q_ref
        if self.mode == MODE_FAULT:
            self.id_int = self.iq_int = 0
            return Outputs(0, 0, 0, 0, 32767, 0)
        v_d, self.id_int = pi_step(self.id_int, i_d_ref, i_d, p.id_pi)
        v_q, self.iq_int = pi_step(self.iq_int, i_q_ref, i_q, p.iq_pi)
        s, c = sincos_q15(self.theta_hat)
        return Outputs(v_d, v_q, p.v_h, s, c, 1, i_d_ref, i_q_ref)

    def _supervise(self, win: WindowResult) -> tuple[int, int]:
        """Start-up state machine; returns (i_d*, i_q*) before the speed loop."""
        p = self.p
        if self.mode == MODE_CONVERGE:
            if self.n >= p.n_converge:
                self._next(MODE_POL_POS)
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
                    self.theta_hat = uwrap(self.theta_hat + HALF_TURN, 32)
                    self.pll = PllState(uwrap(self.pll.theta + HALF_TURN, 32), self.pll.integ, self.pll.omega)
                    self.flipped = 1
                self._next(MODE_RELAX)
                return 0, 0
            return -p.i_pulse, 0
        if self.mode == MODE_RELAX:
            if self.n >= p.n_settle:
                self._next(MODE_RUN)
            return 0, 0
        return 0, 0

    def angle_error(self, theta_true: int) -> int:
        """wrap(theta - theta_hat, 32) for diagnostics."""
        return wrap(theta_true - self.theta_hat, 32)
