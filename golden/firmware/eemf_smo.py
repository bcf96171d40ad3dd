"""Estimator ``eemf_smo``: the extended-EMF sliding-mode observer of the 000 method (Tap et al. 2023,
Sec. II-F, eqs. (20)-(22)), the high-speed slot.

The model of eq. (20) in the plant's frame (d = magnet axis; the paper's ``L_q`` is our ``L_d``, the
axis that carries the magnet; docs/methods.md), in the stationary frame with an observer inductance
``L_o``:

    L_o di/dt = v - R i - w (L_o - L_q) J i - e,      J = [[0, 1], [-1, 0]],
    e = E (-sin theta, cos theta) + (radial terms),   E = w (psi_f + (L_d - L_q) i_d)     (eq. (21))

``L_o = L_d`` is the paper's form (its cross term needs the estimated speed); ``L_o = L_q`` (the default)
is the active-flux form, exact without a cross term: the stator flux is ``L_q i + (psi_f + (L_d - L_q)
i_d) e^{j theta}``, so ``e`` is the derivative of that second vector. Its tangential part has the same
magnitude ``E``; a change of ``i_d`` adds a radial part. docs/methods.md shows why the default is not the
paper's form.

A current observer with the same model is driven by the sliding-mode term ``z = z_max sat(i_hat - i /
Phi)`` (a boundary layer ``Phi = z_max / k_lin`` instead of the sign function, so the term is linear
near the surface and does not chatter at the 10 kHz rate); ``z`` then equals ``e`` on average, a
first-order low-pass (``a_lpf``) takes the switching ripple out, and eq. (22) gives the angle:
``theta = atan2(-e_al, e_be)`` (a half turn more when the speed is negative, where ``E < 0``). A PLL
gives the speed (the paper's "filtered derivative"), and the angle handed to the FOC is advanced by the
observer's, the filter's and the loop's delays (``k_delay``, host side).

Fixed point, once per control period (``i`` in current LSB, ``i_hat`` Q8 current LSB, ``v`` and ``z`` in
voltage LSB, ``e_f`` Q8 voltage LSB):

1. ``i_al, i_be = inv_park(i_d, i_q, sin, cos)``;
2. ``z = clamp(shr(sat(i_hat - (i << 8), 32) * k_lin, 16), -z_max, z_max)`` per component;
3. ``g = shr(pll.omega * c_x, 32)`` (Q16 fraction per period of the cross term), then with the old
   ``i_hat``: ``d_al = shr(c_v sat(v_al - z_al, 32), 8) - shr(c_r i_hat_al, 16) - shr(g i_hat_be, 16)``,
   ``d_be = shr(c_v sat(v_be - z_be, 32), 8) - shr(c_r i_hat_be, 16) + shr(g i_hat_al, 16)``,
   ``i_hat = sat(i_hat + d, 32)``;
4. the low-pass whose cut-off follows the speed (the paper's "variable band-pass frequency", Sec. II-F):
   ``a = clamp(shr(|w_i| * c_a, 24), a_min, a_max)`` (Q16; ``c_a`` = ratio of the cut-off to the
   electrical speed times 2 pi 2^8; ``w_i = shr(pll.integ, 24)`` is the PLL integrator's speed, smoother
   than its output), then ``e_f += shr(a ((z << 8) - e_f), 16)`` per component. The
   injection's 500 Hz current, which the isotropic model cannot explain, leaves ``z`` with a 500 Hz
   part as large as the EEMF at 300 r/min; a fixed 1 kHz filter passed it and the PLL followed it;
5. ``(ang, mag) = vector_angle(sat(e_f_al, 29), sat(e_f_be, 29))``, the EEMF's own angle (eq. (22): it
   leads ``theta`` by a quarter turn when turning forwards and lags it backwards); ``ang = pll.theta``
   (no error: the PLL coasts at its speed) while ``mag < e_min``, where the EEMF is too small for an
   angle (standstill and low speed, while the low-speed slot is in charge);
6. ``pll = pll_step(pll, ang, kp, ki)``: the PLL follows the EEMF vector, whose rotation is continuous
   through a speed reversal; the direction ``dir`` becomes +1 when ``w_i > w_dir`` and -1 when
   ``w_i < -w_dir`` (hysteresis, on the integrator's speed of step 4), and ``theta = uwrap(pll.theta - dir 2^30 + shr(omega * k_delay,
   16) + dir lag0, 32)``: ``lag0`` and ``k_delay`` are the constant and the slope of the observer's and the
   filter's lag fitted over the speed range (host side). (Taking the sign of the estimated speed into the PLL's input instead flips the input by a
   half turn at every sign change of a noisy speed, and each flip kicks the speed: it did not settle.)

``c_v = T / L_o`` [current LSB per voltage LSB] Q16, ``c_r = T R / L_o`` Q16, ``c_x = 2 pi (L_o - L_q) / L_o``
Q16 (signed; 0 for ``L_o = L_q``), ``k_lin`` Q16 [voltage LSB per Q8 current LSB]; all |.| < 2^24;
``z_max`` in 0..2^15-1; ``c_a`` in 0..2^16; ``0 <= a_min <= a_max <= 2^16``; ``lag0`` u32; ``|k_delay| < 2^24``.
"""

from __future__ import annotations

from dataclasses import dataclass

from golden.firmware.estimator import METHOD_EEMF_SMO, Estimator, Measurement, inv_park
from golden.firmware.pll import PllState, pll_step
from golden.firmware.vector import vector_angle
from golden.fixed import sat, shr, uwrap

I_FRAC = 8
"""Fraction bits of the observer's current and of the filtered EEMF."""
QUARTER = 1 << 30
"""A quarter turn (binary angle): the EEMF leads the rotor angle by it when turning forwards."""


@dataclass(frozen=True)
class SmoParams:
    """Integers of the observer (host side: :func:`golden.control_config.eemf_smo_params`); see the
    module docstring for each one's scale. ``e_min`` [Q8 voltage LSB]: the smallest EEMF that gives an
    angle; ``w_dir`` [speed LSB]: the speed beyond which the direction is taken; ``i_d`` is the
    d-current it asks for while in charge."""

    c_v: int
    c_r: int
    c_x: int
    k_lin: int
    z_max: int
    c_a: int
    a_min: int
    a_max: int
    lag0: int
    pll_kp: int
    pll_ki: int
    k_delay: int
    e_min: int
    w_dir: int
    i_d: int = 0


def _clamp(x: int, lim: int) -> int:
    return lim if x > lim else -lim if x < -lim else x


class EemfSmo(Estimator):
    """The EEMF sliding-mode observer with a PLL (see the module docstring)."""

    METHOD = METHOD_EEMF_SMO
    PARAMS = "smo"

    def __init__(self, p: SmoParams):
        self.p = p
        self.ih_al = self.ih_be = 0
        self.ef_al = self.ef_be = 0
        self.mag = 0
        self.dir = 1
        self.pll = PllState(0, 0, 0)
        self.theta = 0
        self.omega = 0
        self.i_d = p.i_d

    def step(self, m: Measurement) -> None:
        p = self.p
        i_al, i_be = inv_park(m.i_d, m.i_q, m.sin, m.cos)
        z_al = _clamp(shr(sat(self.ih_al - (i_al << I_FRAC), 32) * p.k_lin, 16), p.z_max)
        z_be = _clamp(shr(sat(self.ih_be - (i_be << I_FRAC), 32) * p.k_lin, 16), p.z_max)
        g = shr(self.pll.omega * p.c_x, 32)
        # Tap et al. 2023, eq. (20) in the plant's frame with L_o, driven by the sliding-mode term z
        d_al = shr(p.c_v * sat(m.v_al - z_al, 32), 16 - I_FRAC) - shr(p.c_r * self.ih_al, 16) - shr(g * self.ih_be, 16)
        d_be = shr(p.c_v * sat(m.v_be - z_be, 32), 16 - I_FRAC) - shr(p.c_r * self.ih_be, 16) + shr(g * self.ih_al, 16)
        self.ih_al = sat(self.ih_al + d_al, 32)
        self.ih_be = sat(self.ih_be + d_be, 32)
        w_i = shr(self.pll.integ, 24)
        a = min(max(shr(abs(w_i) * p.c_a, 24), p.a_min), p.a_max)
        self.ef_al += shr(a * ((z_al << I_FRAC) - self.ef_al), 16)
        self.ef_be += shr(a * ((z_be << I_FRAC) - self.ef_be), 16)
        ang, self.mag = vector_angle(sat(self.ef_al, 29), sat(self.ef_be, 29))    # eq. (22)
        if self.mag < p.e_min:
            ang = self.pll.theta
        self.pll = pll_step(self.pll, ang, p.pll_kp, p.pll_ki)
        self.omega = self.pll.omega
        if w_i > p.w_dir:
            self.dir = 1
        elif w_i < -p.w_dir:
            self.dir = -1
        self.theta = uwrap(self.pll.theta + self.dir * (p.lag0 - QUARTER) + shr(self.omega * p.k_delay, 16), 32)

    def turn(self, delta: int) -> None:
        self.turn_pll(delta)

    def sync(self, theta: int, omega: int) -> None:
        """The PLL continues from ``theta`` at ``omega`` (the direction from the sign of ``omega``, forwards
        at 0); the current and EMF estimates keep running (the observer runs in parallel)."""
        self.dir = -1 if omega < 0 else 1
        self.pll = PllState(uwrap(theta - self.dir * (self.p.lag0 - QUARTER) - shr(omega * self.p.k_delay, 16), 32),
                            omega << 24, omega)
        self.theta, self.omega = theta, omega
