"""Dead-time compensation from the predicted phase-current sign at each switching instant, bit-true.

Not in the paper (which ran 4 µs uncompensated on purpose): the project's engineering fix for the
dead-time disturbance of the injection at low fundamental current (docs/spec.md, 3.7; PITFALLS 3).

During the dead time after the ideal switch signal ``s`` of a leg changes, both switches are off and the
phase current's sign decides the node: a positive current (out of the leg) holds it low, a negative
one high. So, with ``D`` the dead time, the node stays high ``D`` ticks too long when ``s`` falls with
``i < 0`` (rising carrier half), and rises ``D`` ticks too late when ``s`` rises with ``i > 0``
(falling half). The compensation moves that one edge by up to ``D``:

* rising half (``sign = -1``): ``cmp' = cmp + min(c, 0)``; falling half (``sign = +1``):
  ``cmp' = cmp + max(c, 0)``; with ``c = clamp(shr(i_x · DTC_GAIN, 8), -D, D)`` (``DTC_GAIN`` u16,
  ticks per current LSB in Q8: a linear zone around zero current, where the node capacitance
  already softens the transition), and ``cmp'`` clamped to ``0..H``;
* ``i_x`` is the current predicted at the edge: the firmware's current references ``I_D_REF``,
  ``I_Q_REF`` plus the square-wave HF d-current ``-HF_AMP · cw_edge`` (eq. (17): the current is a
  triangle in phase with ``-cw``), with ``cw_edge = (2·cmp − H)/H``, rotated to the phase with the
  active ``SIN``/``COS``: ``hf = round_shr(HF_AMP · (2·cmp − H) · RECIP_H, 32)`` with
  ``RECIP_H = round(2^32 / H)`` (a multiply instead of a division), ``i_d = I_D_REF − hf``, then
  inverse Park and Clarke as the modulator (``round_shr(·, 15)``) and ``i_x`` of the leg.
"""

from __future__ import annotations

from golden.fixed import round_shr, shr
from golden.fpga.modulator import SQRT3_HALF_Q15


def recip_half(half: int) -> int:
    """``RECIP_H = round(2^32 / H)``, a u32 register (H >= 4)."""
    if half < 4 or half & 1:
        raise ValueError(f"half period {half} must be even and >= 4")
    return ((1 << 33) // half + 1) // 2


def phase_current(leg: int, i_d: int, i_q: int, sin_q15: int, cos_q15: int) -> int:
    """Phase ``leg`` (0, 1, 2) current from dq with the Q1.15 sin/cos: inverse Park, inverse Clarke."""
    i_al = round_shr(i_d * cos_q15 - i_q * sin_q15, 15)
    if leg == 0:
        return i_al
    i_be = round_shr(i_d * sin_q15 + i_q * cos_q15, 15)
    b_part = i_be * SQRT3_HALF_Q15
    return round_shr(-i_al * 16384 + (b_part if leg == 1 else -b_part), 15)


def compensate(cmps, sign: int, half: int, dead: int, gain: int, i_d_ref: int, i_q_ref: int,
               hf_amp: int, sin_q15: int, cos_q15: int, recip_h: int) -> tuple[int, int, int]:
    """Compensated compare values of one half period (see the module docstring)."""
    if sign not in (-1, 1):
        raise ValueError(f"sign {sign} must be -1 (rising half) or +1 (falling half)")
    if not 0 <= gain <= 0xFFFF or not 0 <= hf_amp <= 0x7FFF:
        raise ValueError(f"DTC_GAIN {gain} must be u16 and HF_AMP {hf_amp} u15")
    out = []
    for leg in range(3):
        cmp = int(cmps[leg])
        hf = round_shr(hf_amp * (2 * cmp - half) * recip_h, 32)
        i_x = phase_current(leg, i_d_ref - hf, i_q_ref, sin_q15, cos_q15)
        c = max(-dead, min(dead, shr(i_x * gain, 8)))
        cmp += min(c, 0) if sign < 0 else max(c, 0)
        out.append(max(0, min(half, cmp)))
    return out[0], out[1], out[2]
