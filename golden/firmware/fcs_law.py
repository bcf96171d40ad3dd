"""Control law ``fcs_mpc``: deadbeat FCS-MPC on the observed stator flux (Varatharajan et al. 2020, Sec. II-C).

The current-loop *law* of the firmware is ``foc_pwm`` (current PIs, the modulator's PWM) or this one
(``[control] law``, docs/methods.md): the supervisor's start-up, speed loop and estimator slots stay as
they are; with ``fcs_mpc`` the speed PI's output (a current magnitude, signed by the torque's direction)
becomes a flux reference, and the firmware writes the deadbeat voltage of eq. (14) as ``V_D, V_Q`` with the
angle's ``SIN, COS``; the hardware's direct-vector mode (``CTRL.DIRECT``, spec 3.10) applies the nearest
inverter state (eq. (15)) under the constraint of eqs. (31)-(32), whose coefficients the estimator gives.
The estimator in charge must observe the stator flux (``MethodInfo.flux``).

Timing (spec 2, 3.10): the step after window ``k`` reads the flux at the carrier top of that window (the
estimator's ``psi``, top ``k``) and ``VECTOR``, the state applied from top ``k`` to ``k + 1``; the state
applied from ``k + 1`` to ``k + 2`` was chosen from the previous step's outputs; the state chosen from this
step's outputs is applied from top ``k + 2`` to ``k + 3``. So eq. (13)'s one-step prediction becomes two,
with the two known states, in the stationary frame (no ``w J lambda`` terms: the flux is not rotated while
it is predicted), and eq. (14) aims at the reference at top ``k + 3``:

    r        = shr(r_f * i, 16)                        (i = TOP_I, the drop R_s i T per component)
    psi2     = psi + a(before, VECTOR) + a(VECTOR, next) - 2 r
                    (a: golden.firmware.applied_flux with the dead time, at the current i; ``before``: the
                     previous step's VECTOR; ``next``: VECTOR.NEXT, the state the hardware chose from the
                     previous outputs (committed at this window boundary) with VECTOR as the state applied
                     before, reported by the hardware rather than recomputed: the firmware needs no copy
                     of the choice)
    ref      = inv_park(psi_d*, psi_q*) at theta + shr(omega, 1)      (the end of the applied period)
    v*       = round_shr(ref - psi2, 8) + shr(r_v * i, 16)            (eq. (14), stationary frame)
    V_D, V_Q = park(v*) at theta, both shifted right together until each fits +-v_lim (the direction is
               kept: the nearest vector to a far reference is the one closest in angle)

Flux reference from the torque demand (Sec. II-C, II-D): a table over the current magnitude ``|i_s|``
(:func:`golden.firmware.mtpa.mtpa_lookup`'s grid and interpolation) of the MTPA point's flux, its
low-inductance (d) component at least ``flux_min`` in magnitude (the paper's minimum flux on its q axis,
our d: it saturates the ribs, so the machine is salient at no load, and it excites the fundamental model):
``psi_d* = t_d(|i_s|) <= 0``, ``psi_q* = sgn(i_s) t_q(|i_s|)``.
"""

from __future__ import annotations

from dataclasses import dataclass

from golden.firmware.applied_flux import applied_flux
from golden.firmware.estimator import inv_park, park
from golden.firmware.flux_lut import FLUX_FRAC
from golden.firmware.mtpa import mtpa_lookup
from golden.fixed import round_shr, sat, shr, uwrap
from golden.fpga.cordic import sincos_q15

LAW_FOC_PWM, LAW_FCS_MPC = 0, 1
"""Current-loop laws (``[control] law``)."""


@dataclass(frozen=True)
class FcsParams:
    """Integers of the law (host side: :func:`golden.control_config.fcs_params`): ``r_f`` = ``R_s`` as flux
    per period per current LSB (Q16), ``r_v`` = ``R_s`` as voltage LSB per current LSB (Q16), ``dt_f``, ``vth_f`` =
    ``V_dc t_d``, ``V_th T`` [flux units] (:mod:`golden.firmware.applied_flux`); the flux
    reference table (``shift``, ``t_d``, ``t_q``; flux units, ``t_d`` <= 0); ``phi_min``: ``FCS_CTRL.PHI_MIN``
    [voltage LSB]; ``v_lim``: the largest ``|V_D|``, ``|V_Q|`` written (1..32767, the host checks it)."""

    r_f: int
    r_v: int
    dt_f: int
    vth_f: int
    shift: int
    t_d: tuple
    t_q: tuple
    phi_min: int
    v_lim: int


def flux_reference(p: FcsParams, i_s: int) -> tuple[int, int]:
    """``(psi_d*, psi_q*)`` [flux units] for the signed current command ``i_s`` (module docstring)."""
    d, q = mtpa_lookup(abs(i_s), p.shift, p.t_d, p.t_q)
    return d, (-q if i_s < 0 else q)


def deadbeat_voltage(p: FcsParams, psi_al: int, psi_be: int, i_al: int, i_be: int, before: int, vector: int,
                     nxt: int, theta: int, omega: int, i_s: int) -> tuple[int, int]:
    """``(V_D, V_Q)`` of eq. (14) for the angle ``theta`` (module docstring). ``before``, ``vector``, ``nxt``:
    the states applied before top ``k``, from it, and from top ``k + 1`` (``VECTOR.NEXT``)."""
    a1a, a1b = applied_flux(before, vector, i_al, i_be, p.dt_f, p.vth_f)
    a2a, a2b = applied_flux(vector, nxt, i_al, i_be, p.dt_f, p.vth_f)
    r_a, r_b = shr(p.r_f * i_al, 16), shr(p.r_f * i_be, 16)
    p2a = psi_al + a1a + a2a - 2 * r_a
    p2b = psi_be + a1b + a2b - 2 * r_b
    d_ref, q_ref = flux_reference(p, i_s)
    s, c = sincos_q15(uwrap(theta + shr(omega, 1), 32))
    ref_a, ref_b = inv_park(d_ref, q_ref, s, c)
    v_a = sat(round_shr(ref_a - p2a, FLUX_FRAC) + shr(p.r_v * i_al, 16), 32)
    v_b = sat(round_shr(ref_b - p2b, FLUX_FRAC) + shr(p.r_v * i_be, 16), 32)
    s, c = sincos_q15(theta)
    v_d, v_q = park(v_a, v_b, s, c)
    while abs(v_d) > p.v_lim or abs(v_q) > p.v_lim:
        v_d, v_q = shr(v_d, 1), shr(v_q, 1)
    return v_d, v_q
