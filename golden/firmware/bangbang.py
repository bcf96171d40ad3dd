"""Bang-bang angle estimator (docs/spec.md 5.2; Benevieri et al. 2023, Sec. II-B and Fig. 1).

Sign convention: err = theta - theta_hat, and the demodulated signal is gamma = +K sin(2 err) with
K > 0 (L_d < L_q). gamma > 0 means the estimate lags, so theta_hat advances by one fixed step K_BB;
gamma < 0 retards it; gamma == 0 leaves it unchanged.
"""

from __future__ import annotations

import math

from golden.fixed import to_fixed, uwrap


def bangbang_step(theta_hat: int, gamma: int, k_bb: int) -> int:
    """One bang-bang update of the u32 binary angle ``theta_hat`` from the window result ``gamma`` (s32).

    Returns ``uwrap(theta_hat + k_bb, 32)`` if gamma > 0, ``uwrap(theta_hat - k_bb, 32)`` if gamma < 0,
    ``theta_hat`` if gamma == 0.

    C: ``uint32_t theta_hat, k_bb; int32_t gamma;``
    ``if (gamma > 0) theta_hat += k_bb; else if (gamma < 0) theta_hat -= k_bb;``
    (unsigned add/subtract wrap modulo 2^32 by definition in C).
    """
    if gamma > 0:
        return uwrap(theta_hat + k_bb, 32)
    if gamma < 0:
        return uwrap(theta_hat - k_bb, 32)
    return theta_hat


def k_bb_raw(k_bb_rad_s: float, f_sw: float) -> int:
    """Host-side: K_BB as a u32 binary angle per PWM period, ``to_fixed(K_bb * T / (2 pi), 32)``.

    ``K_bb`` is the estimator speed in electrical rad/s, T = 1/f_sw. 200 rad/s at 5 kHz gives
    0.04 rad per period = 27 342 611 (2^32 = one electrical turn).
    Raises ValueError unless 0 <= result < 2^31 (a step of half a turn or more is meaningless).
    """
    if not f_sw > 0:
        raise ValueError(f"f_sw {f_sw} must be > 0")
    raw = to_fixed(k_bb_rad_s / f_sw / (2.0 * math.pi), 32)
    if not 0 <= raw < (1 << 31):
        raise ValueError(f"K_BB {raw} out of range 0..2^31-1 (K_bb {k_bb_rad_s} rad/s, f_sw {f_sw} Hz)")
    return uwrap(raw, 32)
