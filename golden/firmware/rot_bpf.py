"""Estimator ``rot_bpf``: the 000 method (Tap et al., IEEE Access 2023, Sec. II-B..E, Figs. 5-6).

The FPGA injects the rotating vector ``V_H e^{j phi}`` in the stationary frame (eq. (9); ``CTRL.INJ_ROT``,
docs/spec.md 3.5) and reports the phase of each window (``INJ_PHASE``). Once per control period:

1. ``i_al, i_be = inv_park(i_d, i_q, sin, cos)``: the window-mean current in the stationary frame;
2. ``(s, c)``: sin/cos of the injection phase at the window centre, ``phi = INJ_PHASE - INJ_STEP / 4``
   (three quarters of the window ran on ``INJ_PHASE``, the first quarter on the phase before), formed
   from the supervisor's sin/cos of ``INJ_PHASE`` (``Measurement.inj_sin/inj_cos``) turned by the
   constant ``-INJ_STEP / 4`` (``q_cos, q_sin``: its cos/sin, Q15): ``c = round_shr(C qc - S qs, 15)``,
   ``s = round_shr(S qc + C qs, 15)``;
3. positive-HF frame (eq. (12)): ``x = i e^{-j phi}``: ``x_d = sat(round_shr(i_al c + i_be s, 15), 21)``,
   ``x_q = sat(round_shr(i_be c - i_al s, 15), 21)`` (the band-pass's input range; real currents are s16);
4. the band-pass of eq. (13) at ``2 f_h`` on both components (:mod:`golden.firmware.biquad`; the negative
   sequence sits at ``-2 (f_h - f_e)`` in this frame and a real filter passes both signs), output ``y``
   with ``Y_FRAC`` fraction bits;
5. negative-HF frame (eq. (15)): ``z = y e^{+j 2 phi}`` with ``s2 = round_shr(2 s c, 15)``,
   ``c2 = round_shr(c c - s s, 15)``: ``z_d = sat(round_shr(y_d c2 - y_q s2, 15), Z_BITS)``,
   ``z_q = sat(round_shr(y_d s2 + y_q c2, 15), Z_BITS)``;
6. N-sample average (eq. (16)) as a moving sum over the last ``n_avg`` periods (ring buffer): the ``1/N``
   is left out, only the angle of the sum is used;
7. ``(psi, mag) = vector_angle(sat(sum_d, 29), sat(sum_q, 29))``: ``psi = 2 theta + offset`` with
   ``offset = +-pi/2`` by the sign of the saliency (docs/methods.md derives it); the PLL error is eq. (17)
   normalised: ``err = shr(wrap(psi - offset - 2 pll.theta, 32), 1)``, the electrical angle error
   ``theta - theta_pll`` taken the short way round modulo half a turn (the HF response cannot tell
   ``theta`` from ``theta + pi``; polarity detection does). Its slope is 1 whatever the injection
   amplitude, saliency and filter gain, which eq. (17)'s ``|i| sin 2(theta - theta_hat)`` is not. With the
   cross-saturation table (``xs_angle``, off when empty; beyond the paper) ``psi`` is taken less
   :func:`cross_saturation_turn` at the window-mean ``i_q``: the turn of the negative sequence that the machine's
   cross-saturation gives with the estimate on the d-axis (docs/methods.md, "Cross-saturation");
8. tracking, by ``tracking``: ``TRACK_PLL`` (the paper's, Fig. 6): ``pll = pll_step(pll, uwrap(pll.theta +
   err), kp, ki)`` (:mod:`golden.firmware.pll`), ``omega = pll.omega``, the tracked angle ``pll.theta``;
   ``TRACK_OBSERVER`` (beyond the paper): the motion observer with the torque feed-forward
   (:mod:`golden.firmware.motion`: ``motion_step(self, err, i_d, i_q, p)``), the tracked angle ``theta_o``.
   The error of step 7 is taken against the tracked angle. The PLL lags an acceleration by ``alpha / k_i``
   (11.6 deg in the 0 -> 100 r/min step under load), and with 31 periods of loop delay it cannot be made
   faster; the observer predicts the acceleration from the current (docs/methods.md);
9. delay compensation (eqs. (18)-(19) and the digital loop): ``theta = uwrap(tracked +
   shr(omega * k_delay, 16), 32)``. ``k_delay`` (Q16 periods) is computed on the host from the discrete
   filters: the band-pass phase at ``2(f_h - f_e)`` fitted by a straight line over the speed range (the
   paper's first-order fit), the moving average's ``(N - 1)/2`` periods, and the one period from the PLL's
   prediction to the window the angle is used in (``golden.control_config.rot_bpf_params``).

``sync(theta, omega)`` (taking over from the high-speed slot; the injection restarts with the next
commit): filters and sums cleared, the PLL and the observer set so that the next outputs continue from
``theta`` at ``omega``, and for ``n_hold`` periods the error is ignored (the filters fill). ``turn(delta)``
turns the PLL and the observer; the filters carry ``2 theta``, which the half turn of polarity detection
does not change.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from golden.firmware.biquad import BiquadCoef, BiquadState, biquad_step
from golden.firmware.estimator import METHOD_ROT_BPF, Estimator, Measurement, inv_park
from golden.firmware.motion import motion_step, motion_sync
from golden.firmware.mtpa import check_odd_table, odd_lookup
from golden.firmware.pll import PllState, pll_step
from golden.firmware.vector import vector_angle
from golden.fixed import round_shr, sat, shr, uwrap, wrap

N_MAX = 32
"""Longest moving average (ring buffer length)."""
X_BITS = 21
"""Width of a positive-frame sample (the band-pass's input range, golden.firmware.biquad)."""
Z_BITS = 26
"""Width of a negative-frame sample (so that the sum of N_MAX fits s32)."""
TRACK_PLL, TRACK_OBSERVER = 0, 1
"""``RotParams.tracking``: the paper's PLL, or the motion observer with the torque feed-forward."""


@dataclass(frozen=True)
class RotParams:
    """Integers of the estimator (host side: :func:`golden.control_config.rot_bpf_params`).

    ``q_cos, q_sin``: cos/sin of ``-INJ_STEP / 4`` (Q15); ``bpf``: the band-pass; ``n_avg`` in 1..N_MAX;
    ``offset``: u32 binary angle of the negative-sequence phase at ``theta = 0`` (``2^30`` for
    ``L_q > L_d``, ``3 * 2^30`` otherwise); ``pll_kp`` Q16, ``pll_ki`` Q24; ``k_delay`` Q16 periods
    (|k_delay| < 2^24); ``n_hold`` periods after ``sync``; ``tracking`` ``TRACK_PLL`` or ``TRACK_OBSERVER``;
    ``c1, c2, c3, c_t, c_r`` the motion observer's gains (:mod:`golden.firmware.motion`; 0 with the PLL);
    ``i_d`` the d-current it asks for while in charge [current LSB, <= 0]; ``xs_shift``, ``xs_angle``: the
    cross-saturation table (0..20, 0 or 2..MTPA_LEN s16 values in 2^16 binary angle of the negative sequence; empty:
    off) and ``xs_len`` its length (derived)."""

    q_cos: int
    q_sin: int
    bpf: BiquadCoef
    n_avg: int
    offset: int
    pll_kp: int
    pll_ki: int
    k_delay: int
    n_hold: int
    tracking: int = TRACK_PLL
    c1: int = 0
    c2: int = 0
    c3: int = 0
    c_t: int = 0
    c_r: int = 0
    i_d: int = 0
    xs_shift: int = 0
    xs_angle: tuple = ()
    xs_len: int = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        check_odd_table(self.xs_shift, self.xs_angle, "the cross-saturation table")
        object.__setattr__(self, "xs_len", len(self.xs_angle))


def cross_saturation_turn(p: RotParams, i_q: int) -> int:
    """``sign(i_q) a0(|i_q|) 2^16``: the turn of the negative sequence [binary angle, int] that the machine's
    cross-saturation gives at the q current ``i_q`` with the estimate on the d-axis (the table's value, looked up and
    interpolated by :func:`golden.firmware.mtpa.odd_lookup`), 0 without a table."""
    return odd_lookup(i_q, p.xs_shift, p.xs_angle) << 16


class RotatingBpf(Estimator):
    """Rotating injection, one band-pass, N-sample average and PLL (see the module docstring)."""

    METHOD = METHOD_ROT_BPF
    PARAMS = "rot"

    def __init__(self, p: RotParams):
        self.p = p
        self.bd = BiquadState()
        self.bq = BiquadState()
        self.buf_d = [0] * N_MAX
        self.buf_q = [0] * N_MAX
        self.idx = 0
        self.sum_d = self.sum_q = 0
        self.mag = 0
        self.err = 0
        self.hold = 0
        self.pll = PllState(0, 0, 0)
        self.theta_o = 0                   # the motion observer (TRACK_OBSERVER)
        self.w = 0
        self.z = 0
        self.theta = 0
        self.omega = 0

    @property
    def i_d(self) -> int:
        """Estimator.i_d: ``estimator.rot_bpf.i_d_min`` (0, Tap et al.'s, on a magnet motor; a reluctance
        machine's magnetizing current, whose saliency appears only once its ribs saturate). A parameter, no
        state: C ``fw_rot_i_d``."""
        return self.p.i_d

    def step(self, m: Measurement) -> None:
        p = self.p
        i_al, i_be = inv_park(m.i_d, m.i_q, m.sin, m.cos)
        c = round_shr(m.inj_cos * p.q_cos - m.inj_sin * p.q_sin, 15)     # phi = INJ_PHASE - INJ_STEP/4
        s = round_shr(m.inj_sin * p.q_cos + m.inj_cos * p.q_sin, 15)
        x_d = sat(round_shr(i_al * c + i_be * s, 15), X_BITS)              # eq. (12): e^{-j phi}
        x_q = sat(round_shr(i_be * c - i_al * s, 15), X_BITS)
        self.bd = biquad_step(self.bd, x_d, p.bpf)                        # eq. (13)
        self.bq = biquad_step(self.bq, x_q, p.bpf)
        y_d, y_q = self.bd.y1, self.bq.y1
        s2, c2 = round_shr(2 * s * c, 15), round_shr(c * c - s * s, 15)
        z_d = sat(round_shr(y_d * c2 - y_q * s2, 15), Z_BITS)             # eq. (15): e^{+j 2 phi}
        z_q = sat(round_shr(y_d * s2 + y_q * c2, 15), Z_BITS)
        k = self.idx                                                      # eq. (16): moving sum
        self.sum_d += z_d - self.buf_d[k]
        self.sum_q += z_q - self.buf_q[k]
        self.buf_d[k], self.buf_q[k] = z_d, z_q
        self.idx = k + 1 if k + 1 < p.n_avg else 0
        psi, self.mag = vector_angle(sat(self.sum_d, 29), sat(self.sum_q, 29))
        observer = p.tracking == TRACK_OBSERVER
        tracked = self.theta_o if observer else self.pll.theta
        if self.hold > 0:
            self.hold -= 1
            self.err = 0
        else:                                                             # eq. (17), normalised
            self.err = shr(wrap(psi - p.offset - cross_saturation_turn(p, m.i_q) - 2 * tracked, 32), 1)
        if observer:
            motion_step(self, self.err, m.i_d, m.i_q, p)
            tracked = self.theta_o
        else:
            self.pll = pll_step(self.pll, uwrap(self.pll.theta + self.err, 32), p.pll_kp, p.pll_ki)
            self.omega = self.pll.omega
            tracked = self.pll.theta
        self.theta = uwrap(tracked + shr(self.omega * p.k_delay, 16), 32)   # eqs. (18)-(19)

    def turn(self, delta: int) -> None:
        self.turn_pll(delta)
        self.theta_o = uwrap(self.theta_o + delta, 32)

    def sync(self, theta: int, omega: int) -> None:
        p = self.p
        self.bd = BiquadState()
        self.bq = BiquadState()
        self.buf_d = [0] * N_MAX
        self.buf_q = [0] * N_MAX
        self.idx = self.sum_d = self.sum_q = self.mag = self.err = 0
        tracked = uwrap(theta - shr(omega * p.k_delay, 16), 32)
        self.pll = PllState(tracked, omega << 24, omega)
        motion_sync(self, tracked, omega)
        self.theta, self.omega = theta, omega
        self.hold = p.n_hold
