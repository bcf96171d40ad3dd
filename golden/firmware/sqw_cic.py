"""Estimator ``sqw_cic``: the 001 method (Xue et al., Electronics 2022, Sec. 3, Figs. 2 and 10).

The FPGA injects a square wave on the estimated d-axis whose sign holds for a whole PWM period
(``CTRL.INJ_PER``: f_sw / 2, 500 Hz at 1 kHz, eq. (3)), differences the carrier-bottom samples, keeps the
differences across the ``+V_H`` periods as the envelope and interpolates it to the PWM rate with a
single-stage CIC (eqs. (7)-(8), Figs. 4 and 8; ``golden.fpga.diff_cic``). Its output ``q = (CIC_QA,
CIC_QB)`` is the position quadrature signal of eq. (6): with the estimate right it points along the
rotor's d-axis. Once per control period:

1. normalisation: ``(psi, mag) = vector_angle(sat(q_a, 29), sat(q_b, 29))``, the angle of ``q``;
2. the quadrature PLL's error (Fig. 10), scaled to slope 1: ``e = sat(shr(g * wrap(psi - theta_o, 32),
   16), 32)`` with ``theta_o`` the observer's angle and ``g = L_q / (L_q - L_d)`` (Q16). Eq. (6) gives
   ``q e^{-j theta_hat} ~ L_avg - L_dif e^{j 2 (theta - theta_hat)}``, whose angle is ``(1 - L_d/L_q)``
   times the angle error for small errors, not the error itself; 0 while ``hold > 0`` (after a restart,
   until the CIC holds envelopes of the new injection) and while ``mag < q_min``. With the cross-saturation table
   (``xs_angle``, off when empty; beyond the paper) ``psi`` is taken less ``odd_lookup(i_q) 2^16``
   (:func:`golden.firmware.mtpa.odd_lookup` at the window-mean ``i_q``): the angle of the envelope that the
   machine's cross-saturation gives with the estimate on the d-axis (docs/methods.md, "Cross-saturation");
3. the Luenberger observer of eqs. (9)-(12) with the torque feed-forward, poles at ``-a``
   (:mod:`golden.firmware.motion`: ``motion_step(self, e, i_d, i_q, p)`` on ``theta_o, w, z, omega``);
4. delay compensation: ``theta = uwrap(theta_o + shr(omega * k_delay, 16), 32)``, ``k_delay`` (Q16
   periods) from the implemented timing (``golden.control_config.sqw_cic_delay``: the CIC output's age
   plus the time to the middle of the window the angle is used in; docs/methods.md derives it).

``sync(theta, omega)``: the observer continues from ``theta`` at ``omega`` (``z = 0``) and ignores the
error for ``n_hold`` periods; ``turn(delta)`` turns both angles. ``i_d``: the d-current it asks for while in
charge (``estimator.sqw_cic.i_d_min``; 0, the paper's, on a magnet motor; a magnetizing current on a reluctance
machine, whose saliency appears only once its ribs saturate, as for ``sqw_bangbang``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from golden.firmware.estimator import METHOD_SQW_CIC, Estimator, Measurement
from golden.firmware.mtpa import check_odd_table, odd_lookup
from golden.firmware.motion import motion_step, motion_sync
from golden.firmware.vector import vector_angle
from golden.fixed import sat, shr, uwrap, wrap


@dataclass(frozen=True)
class CicParams:
    """Integers of the estimator (host side: :func:`golden.control_config.sqw_cic_params`); see the module
    docstring for each one's scale. ``q_min``: the smallest ``mag`` of ``vector_angle`` that gives an
    angle; ``n_hold``: periods without error after a restart; ``i_d``: the d-current it asks for while in charge
    [current LSB, <= 0]; ``xs_shift``, ``xs_angle``: the cross-saturation table (0..20, 0 or 2..MTPA_LEN s16 values
    in 2^16 binary angle; empty: off) and ``xs_len`` its length (derived)."""

    g: int
    c1: int
    c2: int
    c3: int
    c_t: int
    c_r: int
    k_delay: int
    q_min: int
    n_hold: int
    i_d: int = 0
    xs_shift: int = 0
    xs_angle: tuple = ()
    xs_len: int = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        check_odd_table(self.xs_shift, self.xs_angle, "the cross-saturation table")
        object.__setattr__(self, "xs_len", len(self.xs_angle))


class SquareWaveCic(Estimator):
    """Quadrature PLL error on the CIC-interpolated envelope and a Luenberger observer (module docstring)."""

    METHOD = METHOD_SQW_CIC
    PARAMS = "cic"

    def __init__(self, p: CicParams):
        self.p = p
        self.theta_o = 0
        self.w = 0
        self.z = 0
        self.hold = 0
        self.err = 0
        self.mag = 0
        self.theta = 0
        self.omega = 0

    @property
    def i_d(self) -> int:
        """Estimator.i_d: ``estimator.sqw_cic.i_d_min`` (a parameter, no state: C ``fw_cic_i_d``)."""
        return self.p.i_d

    def step(self, m: Measurement) -> None:
        p = self.p
        psi, self.mag = vector_angle(sat(m.win.cic_qa, 29), sat(m.win.cic_qb, 29))
        if self.hold > 0:
            self.hold -= 1
            e = 0
        elif self.mag < p.q_min:
            e = 0
        else:                                             # Fig. 10, scaled to slope 1
            e = sat(shr(p.g * wrap(psi - (odd_lookup(m.i_q, p.xs_shift, p.xs_angle) << 16) - self.theta_o, 32),
                        16), 32)
        self.err = e
        motion_step(self, e, m.i_d, m.i_q, p)             # eqs. (9)-(12): poles at -a, torque feed-forward
        self.theta = uwrap(self.theta_o + shr(self.omega * p.k_delay, 16), 32)

    def turn(self, delta: int) -> None:
        self.theta_o = uwrap(self.theta_o + delta, 32)
        self.theta = uwrap(self.theta + delta, 32)

    def sync(self, theta: int, omega: int) -> None:
        p = self.p
        motion_sync(self, theta - shr(omega * p.k_delay, 16), omega)
        self.hold = p.n_hold
        self.theta = theta
