"""Estimator ``rfo``: the rotor flux observer of the 002 system's medium/high-speed range (Sec. IV-F).

Benevieri et al. 2023 hand over to the rotor flux observer of their ref. [10] (Choi, Nam, Bobtsov,
Pyrkin, Ortega, TPEL 2017), which builds on the gradient flux observer of Ortega et al. (IEEE TCST 2011):
the stator flux ``x`` obeys ``dx/dt = v - R i`` in the stationary frame, and for a PMSM the rotor flux
``eta = x - L i`` has the known magnitude ``psi_f``; the observer integrates the voltage model and
corrects ``x`` along ``eta`` so that ``|eta|`` returns to that magnitude. We use ``L = L_q``: the *active
flux* ``x - L_q i = A (cos theta, sin theta)``, ``A = psi_f + (L_d - L_q) i_d``, lies on the d-axis for
any current (Boldea et al., "Active flux concept for motion-sensorless unified AC drives", IEEE TPEL
2008), so no anisotropy costs angle, and its magnitude ``A`` is known from the d-current (``i_d`` of the
window, in the frame the drive used: the difference from the true frame's is second order in the angle
error). A normalised correction:

    x <- x + T (v - R i) + k_c (A - |eta|) / |eta| * eta        (per control period)

The magnitude's ``(L_d - L_q) i_d`` term matters on a salient machine: on the 000 PMaSynRM (``L_d - L_q =
-115 mH``) ``A`` is 0.21 Wb at ``i_d = -1 A`` against ``psi_f`` = 0.096 Wb, and a correction towards
``psi_f`` leaves a tangential flux error, ``k (A - psi_f) / (omega A)`` rad, 50 deg while braking at 600
r/min (docs/faults.md, "The flying start of the 000 drive").

``k_c`` (0..1) is the fraction of a radial flux error removed per period. Where the paper leaves the
observer's tuning open, docs/methods.md says what was chosen and why.

Fixed point, once per control period, inputs of :class:`~golden.firmware.estimator.Measurement`
(window means in the frame active during the window, and the voltage references active then):

1. ``i_al, i_be = inv_park(i_d, i_q, sin, cos)`` (:func:`golden.firmware.estimator.inv_park`); the
   voltage ``v_al, v_be`` is the window mean the supervisor measures (:func:`~golden.firmware.estimator.window_voltage`);
2. ``dx = (v << F) - shr(r_s * i, 16 - F)`` per component (flux LSB: ``v_lsb T / 2^F``, ``F = FLUX_FRAC``);
3. ``eta = sat(x + shr(dx, 1) - shr(l_s * i, 16), 29)``: the rotor flux at the middle of the window
   (the window means are the currents there), saturated to +-2^28;
4. ``(ang, mag) = vector_angle(eta)`` (:mod:`golden.firmware.vector`);
5. ``A = active_flux(p, i_d)`` (``psi_f + shr(l_dq i_d, 16)`` within ``1..2^27``) and
   ``q = clamp(c_div((A - mag) << 16, max(mag, 1)), -2^17, 2^17)``; the correction rate follows the
   speed, ``k = clamp((|sat(shr(pll.integ, 24), 32)| * k_r) >> 32, k_min, k_c)`` (the PLL integrator's
   speed of the previous period: ``k`` is ``flux_ratio`` times the electrical angle per period, between
   ``flux_bw_min`` and ``flux_bw``), and ``k = k_c`` until the first ``sync`` (``synced = 0``: the flux
   is unknown, as in a flying start, where the observer acquires a spinning rotor from zero flux and zero
   speed: at ``k_min`` its PLL ran off the wrong way on the Table I motor at 900 r/min, docs/faults.md);
   ``g = shr(k * q, 16)``, ``x = sat(x + dx + shr(eta * g, 16), 32)`` per component. A fixed rate was
   either too slow for low current at 1500-3500 r/min (20 Hz: the observer and the current loop oscillated
   and tripped, no load) or too fast under load near the hand-over (50 Hz: 9 deg RMS at 355 r/min with
   +-2 N*m steps against 5 deg); docs/methods.md;
6. ``pll = pll_step(pll, ang, kp, ki)``; outputs ``omega = pll.omega`` and
   ``theta = uwrap(ang + 2 * sat(shr(pll.integ, 24), 32), 32)``: the angle in the middle of the window after
   next, where the outputs of this step are active (docs/spec.md 2.2), advanced by the PLL *integrator's*
   speed. Advancing by ``omega``, which holds ``kp * e``, fed the observer's angle back with a lead of
   ``1 + 2 kp T`` (1.4 at the default 1000 1/s and 5 kHz): at low current (no load at 1500-3500 r/min,
   4 us dead time) the current loop and the observer oscillated at about 140 Hz and tripped
   (docs/methods.md, "The rotor flux observer at low current").

Ranges: ``|v| < 2^15``, ``|i| < 2^31``; ``r_s`` (Q16 voltage LSB per current LSB) and ``l_s`` (Q16 flux LSB
per current LSB) in 0..2^31-1, so the products fit int64; ``psi_f`` in 1..2^27; ``l_dq`` (Q16 flux LSB per
current LSB, signed) in -2^31+1..2^31-1; ``k_c`` and ``k_min`` Q16 in 0..65536; ``k_r`` in 0..2^31-1.
"""

from __future__ import annotations

from dataclasses import dataclass

from golden.firmware.estimator import METHOD_RFO, Estimator, Measurement, inv_park
from golden.firmware.flux_lut import FLUX_FRAC
from golden.firmware.pll import PllState, pll_step
from golden.firmware.vector import vector_angle
from golden.fixed import c_div, round_shr, sat, shr, uwrap
from golden.fpga.cordic import sincos_q15

Q_LIMIT = 1 << 17
"""Limit of the relative flux error ``(A - |eta|) / |eta|`` in Q16 (a ratio of 2)."""
A_MAX = 1 << 27
"""The largest active-flux magnitude [flux LSB] (the range of ``psi_f``)."""


@dataclass(frozen=True)
class RfoParams:
    """Integers of the observer (host side: :func:`golden.control_config.firmware_params`).

    ``r_s`` Q16 [voltage LSB per current LSB]; ``l_s`` Q16 [flux LSB per current LSB] of L_q;
    ``psi_f`` [flux LSB]; ``k_c`` and ``k_min`` Q16 correction per period, the largest and the smallest;
    ``k_r`` the correction per binary angle of speed per period, Q48 (``k = k_r |w| >> 32`` is Q16);
    ``pll_kp`` Q16, ``pll_ki`` Q24; ``i_d``
    the d-current reference while in charge [current LSB] (<= 0, docs/methods.md); ``l_dq`` Q16 [flux LSB per
    current LSB] of ``L_d - L_q`` (signed; 0: the magnitude is ``psi_f`` at every current).
    """

    r_s: int
    l_s: int
    psi_f: int
    k_c: int
    k_min: int
    k_r: int
    pll_kp: int
    pll_ki: int
    i_d: int = 0
    l_dq: int = 0


def active_flux(p: RfoParams, i_d: int) -> int:
    """The active flux's magnitude ``psi_f + (L_d - L_q) i_d`` [flux LSB] at the d-current ``i_d`` [current LSB],
    within ``1..A_MAX`` (a reluctance machine's active flux vanishes at a positive d-current: the observer needs
    a magnitude to aim at)."""
    a = p.psi_f + shr(p.l_dq * i_d, 16)
    return 1 if a < 1 else A_MAX if a > A_MAX else a


class RotorFluxObserver(Estimator):
    """The gradient (active-)flux observer with a CORDIC angle and a PLL (see the module docstring)."""

    METHOD = METHOD_RFO
    PARAMS = "rfo"

    def __init__(self, p: RfoParams):
        self.p = p
        self.x_al = self.x_be = 0
        self.i_al = self.i_be = 0
        self.a_mag = 0
        self.mag = 0
        self.pll = PllState(0, 0, 0)
        self.theta = 0
        self.omega = 0
        self.i_d = p.i_d
        self.synced = 0

    def step(self, m: Measurement) -> None:
        p = self.p
        i_al, i_be = inv_park(m.i_d, m.i_q, m.sin, m.cos)
        v_al, v_be = m.v_al, m.v_be
        self.i_al, self.i_be = i_al, i_be
        dx_al = (v_al << FLUX_FRAC) - shr(p.r_s * i_al, 16 - FLUX_FRAC)      # T (v - R i)
        dx_be = (v_be << FLUX_FRAC) - shr(p.r_s * i_be, 16 - FLUX_FRAC)
        eta_al = sat(self.x_al + shr(dx_al, 1) - shr(p.l_s * i_al, 16), 29)  # x - L_q i, mid-window
        eta_be = sat(self.x_be + shr(dx_be, 1) - shr(p.l_s * i_be, 16), 29)
        ang, mag = vector_angle(eta_al, eta_be)
        self.mag = mag
        # Ortega et al. 2011: correction along eta towards |eta| = A (normalised gradient), A the active flux
        self.a_mag = active_flux(p, m.i_d)
        q = c_div((self.a_mag - mag) << 16, mag if mag > 0 else 1)
        q = Q_LIMIT if q > Q_LIMIT else -Q_LIMIT if q < -Q_LIMIT else q
        k = min(max((abs(sat(shr(self.pll.integ, 24), 32)) * p.k_r) >> 32, p.k_min), p.k_c) if self.synced else p.k_c
        g = shr(k * q, 16)
        self.x_al = sat(self.x_al + dx_al + shr(eta_al * g, 16), 32)
        self.x_be = sat(self.x_be + dx_be + shr(eta_be * g, 16), 32)
        self.pll = pll_step(self.pll, ang, p.pll_kp, p.pll_ki)
        self.omega = self.pll.omega
        self.theta = uwrap(ang + 2 * sat(shr(self.pll.integ, 24), 32), 32)

    def turn(self, delta: int) -> None:
        s, c = sincos_q15(uwrap(delta, 32))
        self.x_al, self.x_be = (sat(round_shr(self.x_al * c - self.x_be * s, 15), 32),
                                sat(round_shr(self.x_al * s + self.x_be * c, 15), 32))
        self.pll = PllState(uwrap(self.pll.theta + delta, 32), self.pll.integ, self.pll.omega)
        self.theta = uwrap(self.theta + delta, 32)

    def sync(self, theta: int, omega: int) -> None:
        """Start the flux at the angle ``theta - 2 omega`` (the middle of the last window) with the magnitude
        the last step aimed at (the active flux at that window's d-current; 0 before the first step), plus
        ``L_q i`` of the last currents; the PLL at that angle's next prediction and speed."""
        p = self.p
        mid = uwrap(theta - 2 * omega, 32)
        s, c = sincos_q15(mid)
        self.x_al = sat(round_shr(self.a_mag * c, 15) + shr(p.l_s * self.i_al, 16), 32)
        self.x_be = sat(round_shr(self.a_mag * s, 15) + shr(p.l_s * self.i_be, 16), 32)
        self.pll = PllState(uwrap(mid + omega, 32), omega << 24, omega)
        self.theta, self.omega = theta, omega
        self.synced = 1
