"""Clarke and Park transforms of the sampled phase currents, bit-true.

docs/spec.md, section 3.2 (amplitude-invariant Clarke, as the plant):

* Clarke: ``i_alpha = i_a``, ``i_beta = sat(round_shr((i_a + 2*i_b) * 18919, 15), 16)`` with
  18919 = round(2^15/sqrt(3)) (``i_a + 2*i_b`` s18, times u15 -> s33).
* Park onto the estimated frame (``SIN``, ``COS`` of the angle committed for the window, Q1.15):
  ``i_d = sat(round_shr(i_alpha*COS + i_beta*SIN, 15), 16)``,
  ``i_q = sat(round_shr(i_beta*COS - i_alpha*SIN, 15), 16)`` (s16 x s16 -> s31, sum s32).
  ``i_q`` is the ``i_q^`` of Benevieri et al. 2023, eq. (19); ``i_d`` feeds ``GAMMA_D``.

All currents are s16 with 2^15 = ``I_FS``. Inputs outside s16 raise ValueError: they cannot come
from the s16 ports of the hardware.
"""

from __future__ import annotations

import numpy as np

from golden.fixed import round_shr, sat

INV_SQRT3_Q15 = 18919
"""round(2^15 / sqrt(3)), the Clarke coefficient (u15)."""

_S16_MIN, _S16_MAX = -(1 << 15), (1 << 15) - 1


def _as_s16(x, name: str):
    """Validate an s16 int or integer numpy array; return a Python int or an int64 array."""
    if isinstance(x, np.ndarray):
        if x.dtype.kind not in "iu":
            raise TypeError(f"{name} must be an integer array, got dtype {x.dtype}")
        if x.size and (int(x.min()) < _S16_MIN or int(x.max()) > _S16_MAX):
            idx = np.flatnonzero((x < _S16_MIN) | (x > _S16_MAX))[0]
            raise ValueError(f"{name}[{idx}] = {int(x.flat[idx])} is not an s16 value")
        return x.astype(np.int64)
    if isinstance(x, (bool, np.bool_)) or not isinstance(x, (int, np.integer)):
        raise TypeError(f"{name} must be an int or an integer numpy array, got {type(x).__name__}")
    if not _S16_MIN <= x <= _S16_MAX:
        raise ValueError(f"{name} = {x} is not an s16 value")
    return int(x)


def clarke(i_a, i_b):
    """Clarke transform of the two measured phase currents (spec 3.2).

    Parameters
    ----------
    i_a, i_b : int or numpy.ndarray of int
        Phase currents, s16 (2^15 = ``I_FS``); arrays broadcast.

    Returns
    -------
    (i_alpha, i_beta)
        s16: ``i_alpha = i_a`` (a copy for arrays), ``i_beta = sat(round_shr((i_a + 2 i_b)*18919, 15), 16)``.

    Raises
    ------
    ValueError
        If a current is outside s16.
    """
    a = _as_s16(i_a, "i_a")
    b = _as_s16(i_b, "i_b")
    i_beta = sat(round_shr((a + 2 * b) * INV_SQRT3_Q15, 15), 16)   # s18 x u15 -> s33
    if isinstance(i_beta, np.ndarray):
        return np.broadcast_to(a, i_beta.shape).astype(np.int64), i_beta
    return a, i_beta


def park(i_alpha, i_beta, sin_q15, cos_q15):
    """Park transform onto the estimated rotor frame (spec 3.2).

    Parameters
    ----------
    i_alpha, i_beta : int or numpy.ndarray of int
        Stationary-frame currents, s16.
    sin_q15, cos_q15 : int or numpy.ndarray of int
        ``SIN``, ``COS`` of the estimated angle, s16 Q1.15 (32767 ~ 1). Arrays broadcast.

    Returns
    -------
    (i_d, i_q)
        s16: ``sat(round_shr(i_alpha*COS + i_beta*SIN, 15), 16)`` and
        ``sat(round_shr(i_beta*COS - i_alpha*SIN, 15), 16)``.

    Raises
    ------
    ValueError
        If an input is outside s16.
    """
    al = _as_s16(i_alpha, "i_alpha")
    be = _as_s16(i_beta, "i_beta")
    s = _as_s16(sin_q15, "sin_q15")
    c = _as_s16(cos_q15, "cos_q15")
    i_d = sat(round_shr(al * c + be * s, 15), 16)     # s16 x s16 -> s31, sum s32
    i_q = sat(round_shr(be * c - al * s, 15), 16)
    return i_d, i_q
