"""FCS-MPC vector choice, bit-true (Varatharajan et al. 2020, eqs. (15), (30)-(32); docs/spec.md 3.10).

The firmware of the 003 method computes the deadbeat voltage ``v*`` of eq. (14) and writes it as the
usual ``V_D, V_Q`` with the angle's ``SIN, COS``; in the direct-vector mode the modulator does not
modulate it: it applies, for a whole period, the one inverter state whose voltage is nearest to ``v*``
(eq. (15): the Euclidean distance is the same in every frame, so it is evaluated in the stationary frame
on the modulator's ``v_alpha, v_beta``), under the hard constraint of eqs. (31)-(32).

Fixed point (voltages in voltage LSB, ``2^15 = V_dc``):

* the six active states in the order ``0b001, 0b011, 0b010, 0b110, 0b100, 0b101`` (bit 0 = phase a) have the
  voltage ``(2/3) V_dc`` at ``0, 60, ..., 300`` degrees: ``(VX_j, VY_j)`` = the rounded ``21845.33 (cos,
  sin)``, ``K_j = VX_j^2 + VY_j^2``;
* squared distance less ``|v*|^2``: ``d_j = K_j - 2 (v_alpha VX_j + v_beta VY_j)``, ``d_0 = 0`` for the
  zero vector;
* eq. (30) for each active state in the estimated frame: ``vd_j = round_shr(VX_j COS + VY_j SIN, 15)``,
  ``vq_j = round_shr(VY_j COS - VX_j SIN, 15)``, ``p_j = round_shr(A1 vq_j - A2 vd_j, 12)`` (``A1, A2``
  s16 Q12: the inductance ratios of eq. (30), computed by the firmware from the incremental inductances);
* with ``CONSTRAIN`` (the firmware's ``n > N_max`` of eq. (31)) a state is eligible only if it is active
  and ``|p_j| > PHI_MIN`` (eq. (32)); if none is, the constraint is dropped (documented safe behaviour:
  a threshold above every vector's strength must not stop the inverter); without it every state is;
* the choice is the eligible state of least ``d`` (the zero vector first, then ``j = 1..6``, the first
  of equal ones); the zero vector is ``000`` or ``111``, the one with fewer legs to switch from the
  state applied now (``111`` if two or three legs are high).

Ranges: ``v_alpha, v_beta`` s18 (the modulator's), so ``d_j`` fits s36; ``p_j`` s17.
"""

from __future__ import annotations

from golden.fixed import round_shr
from golden.fpga.checks import int_param

ACTIVE_STATES = (0b001, 0b011, 0b010, 0b110, 0b100, 0b101)
"""The six active states in angle order 0, 60, ..., 300 deg; bit 0 = phase a, bit 1 = b, bit 2 = c."""
VX = (21845, 10923, -10923, -21845, -10923, 10923)
"""Alpha components of the active vectors [voltage LSB]: round(2^15 * 2/3 * cos(60 deg * j))."""
VY = (0, 18919, 18919, 0, -18919, -18919)
"""Beta components: round(2^15 * 2/3 * sin(60 deg * j))."""
K = tuple(x * x + y * y for x, y in zip(VX, VY))
"""Squared magnitudes of the rounded active vectors."""



def state_voltage(state: int) -> tuple[int, int]:
    """``(v_alpha, v_beta)`` [voltage LSB] of an inverter state (0..7, bit 0 = phase a): ``(VX_j, VY_j)``
    of an active state, ``(0, 0)`` of ``000`` and ``111`` (the firmware's model of what it applied)."""
    if state in (0, 7):
        return 0, 0
    j = ACTIVE_STATES.index(state)
    return VX[j], VY[j]


_S18 = (-(1 << 17), (1 << 17) - 1)
_S16 = (-(1 << 15), (1 << 15) - 1)


def choose_vector(v_al: int, v_be: int, sin_q15: int, cos_q15: int, a1: int, a2: int, phi_min: int,
                  constrain: bool, state_now: int) -> tuple[int, int]:
    """``(state, p)``: the inverter state to apply for the next period (3 bits, bit 0 = phase a) and the
    ``p_j`` of eq. (30) of that state (0 for a zero vector).

    ``v_al, v_be``: s18 (the modulator's inverse Park of ``V_D, V_Q``); ``sin_q15, cos_q15``: the estimated
    angle (s16 Q1.15); ``a1, a2``: s16 Q12; ``phi_min``: u16 [voltage LSB]; ``constrain``: eq. (31)'s
    ``n > N_max``; ``state_now``: the state applied now (0..7). Raises ValueError outside these ranges."""
    v_al = int_param(v_al, *_S18, "v_alpha (s18)")
    v_be = int_param(v_be, *_S18, "v_beta (s18)")
    s = int_param(sin_q15, *_S16, "SIN (s16)")
    c = int_param(cos_q15, *_S16, "COS (s16)")
    a1 = int_param(a1, *_S16, "A1 (s16 Q12)")
    a2 = int_param(a2, *_S16, "A2 (s16 Q12)")
    phi_min = int_param(phi_min, 0, (1 << 16) - 1, "PHI_MIN (u16)")
    state_now = int_param(state_now, 0, 7, "state (0..7)")
    p = []
    for x, y in zip(VX, VY):                                   # eq. (30) in the estimated frame
        vd = round_shr(x * c + y * s, 15)
        vq = round_shr(y * c - x * s, 15)
        p.append(round_shr(a1 * vq - a2 * vd, 12))
    eligible = [abs(pj) > phi_min for pj in p] if constrain else [True] * 6
    zero_ok = not constrain or not any(eligible)
    if not any(eligible):                                      # no vector is strong enough: unconstrained
        eligible = [True] * 6
    best, best_d = None, 0 if zero_ok else None                # None: the zero vector (d_0 = 0)
    for j in range(6):
        if not eligible[j]:
            continue
        d = K[j] - 2 * (v_al * VX[j] + v_be * VY[j])           # eq. (15), less |v*|^2
        if best_d is None or d < best_d:
            best, best_d = j, d
    if best is None:
        return (0b111 if bin(state_now).count("1") >= 2 else 0b000), 0
    return ACTIVE_STATES[best], p[best]
