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
   until the CIC holds envelopes of the new injection) and while ``mag < q_min``;
3. the Luenberger observer (eqs. (9)-(12), with the torque feed-forward written as the motion equation
   means it: ``d omega/dt = n_p T_e / J + ...``; eq. (9) as printed multiplies ``T_e`` by the error),
   the gains ``K1 = a^3 J``, ``K2 = 3 a^2 J``, ``K3 = 3 a J`` divided by ``J`` (the poles at ``-a``):

   * ``z = sat(z + c1 e, 64)``                    (Q24 binary angle per period^2; ``c1 = a^3 T^3``)
   * ``w = sat(w + z + c2 e + ff, 64)``           (Q24 binary angle per period; ``c2 = 3 a^2 T^2``)
   * ``omega = sat(shr(w, 24), 32)``
   * ``theta_o = uwrap(theta_o + omega + shr(c3 e, 16), 32)``   (``c3 = 3 a T``, Q16)

   with ``ff = c_t i_q + shr(c_r i_d i_q, 16)`` (``i_d, i_q``: the window means saturated to s16; ``c_t,
   c_r``: ``n_p T_e / J`` per current LSB and per LSB^2, Q24 and Q40), 0 when ``c_t = c_r = 0``;
4. delay compensation: ``theta = uwrap(theta_o + shr(omega * k_delay, 16), 32)``, ``k_delay`` (Q16
   periods) from the implemented timing (``golden.control_config.sqw_cic_delay``: the CIC output's age
   plus the time to the middle of the window the angle is used in; docs/methods.md derives it).

``sync(theta, omega)``: the observer continues from ``theta`` at ``omega`` (``z = 0``) and ignores the
error for ``n_hold`` periods; ``turn(delta)`` turns both angles.
"""

from __future__ import annotations

from dataclasses import dataclass

from golden.firmware.estimator import METHOD_SQW_CIC, Estimator, Measurement
from golden.firmware.vector import vector_angle
from golden.fixed import sat, shr, uwrap, wrap


@dataclass(frozen=True)
class CicParams:
    """Integers of the estimator (host side: :func:`golden.control_config.sqw_cic_params`); see the module
    docstring for each one's scale. ``q_min``: the smallest ``mag`` of ``vector_angle`` that gives an
    angle; ``n_hold``: periods without error after a restart."""

    g: int
    c1: int
    c2: int
    c3: int
    c_t: int
    c_r: int
    k_delay: int
    q_min: int
    n_hold: int


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

    def step(self, m: Measurement) -> None:
        p = self.p
        psi, self.mag = vector_angle(sat(m.win.cic_qa, 29), sat(m.win.cic_qb, 29))
        if self.hold > 0:
            self.hold -= 1
            e = 0
        elif self.mag < p.q_min:
            e = 0
        else:                                             # Fig. 10, scaled to slope 1
            e = sat(shr(p.g * wrap(psi - self.theta_o, 32), 16), 32)
        self.err = e
        i_d, i_q = sat(m.i_d, 16), sat(m.i_q, 16)
        ff = p.c_t * i_q + shr(p.c_r * (i_d * i_q), 16)   # n_p T_e / J: the torque feed-forward
        self.z = sat(self.z + p.c1 * e, 64)               # eqs. (9)-(12): poles at -a
        self.w = sat(self.w + self.z + p.c2 * e + ff, 64)
        self.omega = sat(shr(self.w, 24), 32)
        self.theta_o = uwrap(self.theta_o + self.omega + shr(p.c3 * e, 16), 32)
        self.theta = uwrap(self.theta_o + shr(self.omega * p.k_delay, 16), 32)

    def turn(self, delta: int) -> None:
        self.theta_o = uwrap(self.theta_o + delta, 32)
        self.theta = uwrap(self.theta + delta, 32)

    def sync(self, theta: int, omega: int) -> None:
        p = self.p
        self.theta_o = uwrap(theta - shr(omega * p.k_delay, 16), 32)
        self.w = omega << 24
        self.z = 0
        self.hold = p.n_hold
        self.theta, self.omega = theta, omega
