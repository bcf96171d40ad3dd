"""Maximum-torque-per-ampere current references from a table (Tap et al. 2023, eqs. (3)-(4), Fig. 3).

The speed PI's output is the current magnitude ``i_s`` (signed by the torque's direction); the table
holds, on a uniform grid of step ``2^shift`` current LSB starting at 0, the d-current (<= 0) and the
q-current magnitude of the MTPA point of each magnitude. Look-up with linear interpolation:

    i_s = min(i_s, (len - 1) << shift),  k = min(i_s >> shift, len - 2),  f = i_s - (k << shift)
    i_d = t_d[k] + shr((t_d[k+1] - t_d[k]) * f, shift)       (the same for i_q)

``i_s`` >= 0 (the caller passes the magnitude, up to 2^31); beyond the last point the last point's
currents (the speed PI's limit is the table's end). 2 to MTPA_LEN s16 values, ``shift`` 0..20.

Host side: :func:`mtpa_table` from the nominal motor data. In the plant's frame (d = magnet axis) the
torque is ``1.5 p (psi_f i_q + (L_d - L_q) i_d i_q)``; the paper's eq. (4) is the same optimum written in
its own frame (d on the high-inductance axis, magnet on -q; docs/methods.md). With ``dL = L_q - L_d > 0``
and the magnitude ``i_s`` fixed, ``dT/di_d = 0`` gives
``i_d = (psi_f - sqrt(psi_f^2 + 8 dL^2 i_s^2)) / (4 dL)`` and ``i_q = sqrt(i_s^2 - i_d^2)``.
"""

from __future__ import annotations

import math

from golden.fixed import shr, to_fixed

MTPA_LEN = 33
"""Most points of a table (32 segments)."""


def mtpa_lookup(i_s: int, shift: int, t_d: tuple, t_q: tuple) -> tuple[int, int]:
    """``(i_d, |i_q|)`` for the magnitude ``i_s`` >= 0 (module docstring)."""
    i_s = min(i_s, (len(t_d) - 1) << shift)
    k = min(i_s >> shift, len(t_d) - 2)
    f = i_s - (k << shift)
    return (t_d[k] + shr((t_d[k + 1] - t_d[k]) * f, shift),
            t_q[k] + shr((t_q[k + 1] - t_q[k]) * f, shift))


def check_odd_table(shift: int, table: tuple, what: str) -> None:
    """A table over ``|i_q|`` on this module's grid (the estimators' cross-saturation tables): ``shift`` 0..20 and 0
    (off) or 2..MTPA_LEN s16 values; ValueError naming ``what`` otherwise."""
    if not (0 <= shift <= 20 and len(table) in (0, *range(2, MTPA_LEN + 1)) and all(-32768 <= v <= 32767 for v in table)):
        raise ValueError(f"{what}: xs_shift {shift}, the table's length {len(table)} or a value out of range "
                         f"(0..20; 0 or 2..{MTPA_LEN}; s16)")


def odd_lookup(i_q: int, shift: int, table: tuple) -> int:
    """``sign(i_q) t(|i_q|)``: a table over ``|i_q|`` (:func:`mtpa_lookup`'s look-up and interpolation) extended to
    an odd function of ``i_q``, as a machine's cross-saturation is; 0 for an empty table."""
    if not table:
        return 0
    t = mtpa_lookup(abs(i_q), shift, table, table)[0]
    return -t if i_q < 0 else t


def mtpa_point(i_s: float, psi_f: float, L_d: float, L_q: float) -> tuple[float, float]:
    """The MTPA split ``(i_d, i_q)`` [A] of a current magnitude ``i_s`` >= 0 [A] (module docstring);
    ``(0, i_s)`` for a machine without reluctance torque (``L_q <= L_d``: the optimum is i_d = 0 or the
    magnet torque alone dominates; this platform does not field-weaken by MTPA)."""
    dl = L_q - L_d
    if dl <= 0:
        return 0.0, i_s
    i_d = (psi_f - math.sqrt(psi_f * psi_f + 8 * dl * dl * i_s * i_s)) / (4 * dl)
    return i_d, math.sqrt(max(i_s * i_s - i_d * i_d, 0.0))


def table_grid(i_max: int, points: int, what: str) -> tuple[int, int]:
    """``(shift, n)``: the fewest points ``n`` (at most ``points``) of a power-of-two step ``2^shift`` [current
    LSB] from 0 that cover ``0..i_max`` (the grid of :func:`mtpa_lookup`). Raises ValueError for ``i_max``
    outside 1..32767, naming ``what``."""
    if not 1 <= i_max <= 32767:
        raise ValueError(f"{what}: current limit {i_max} LSB outside 1..32767")
    shift = 0
    while (i_max + (1 << shift) - 1) >> shift > points - 1:
        shift += 1
    return shift, ((i_max + (1 << shift) - 1) >> shift) + 1


def mtpa_table(i_max: int, i_lsb: float, psi_f: float, L_d: float, L_q: float
               ) -> tuple[int, tuple[int, ...], tuple[int, ...]]:
    """``(shift, t_d, t_q)`` covering 0..``i_max`` [current LSB] with the fewest points of a power-of-two
    step (at most MTPA_LEN). Raises ValueError for ``i_max`` outside 1..32767."""
    shift, n = table_grid(i_max, MTPA_LEN, "MTPA table")
    pts = [mtpa_point(min(k << shift, 32767) * i_lsb, psi_f, L_d, L_q) for k in range(n)]
    t_d = tuple(max(to_fixed(d / i_lsb, 0), -32768) for d, _ in pts)
    t_q = tuple(min(to_fixed(q / i_lsb, 0), 32767) for _, q in pts)
    return shift, t_d, t_q
