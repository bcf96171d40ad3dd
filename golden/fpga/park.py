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

:func:`clarke` and :func:`park` check their arguments; :func:`clarke_kernel` and :func:`park_kernel`
(broadcasting) are their unchecked int64 array forms, the same integers; :mod:`golden.fpga.window_dsp`
runs :func:`clarke_kernel` and :func:`park_stacked_kernel` (one matrix product for i_d and i_q).
"""

from __future__ import annotations

import numpy as np

from golden.fixed import round_shr, sat

INV_SQRT3_Q15 = 18919
"""round(2^15 / sqrt(3)), the Clarke coefficient (u15)."""

_S16_MIN, _S16_MAX = -(1 << 15), (1 << 15) - 1


def _as_s16(x, name: str):
    """Validate an s16 int or integer numpy array; return a Python int or an int64 array (the argument
    itself, not a copy, if it already is one: the kernels never write into their inputs)."""
    if isinstance(x, np.ndarray):
        if x.dtype.kind not in "iu":
            raise TypeError(f"{name} must be an integer array, got dtype {x.dtype}")
        if x.size and (int(x.min()) < _S16_MIN or int(x.max()) > _S16_MAX):
            idx = np.flatnonzero((x < _S16_MIN) | (x > _S16_MAX))[0]
            raise ValueError(f"{name}[{idx}] = {int(x.flat[idx])} is not an s16 value")
        return x if x.dtype == np.int64 else x.astype(np.int64)
    if isinstance(x, (bool, np.bool_)) or not isinstance(x, (int, np.integer)):
        raise TypeError(f"{name} must be an int or an integer numpy array, got {type(x).__name__}")
    if not _S16_MIN <= x <= _S16_MAX:
        raise ValueError(f"{name} = {x} is not an s16 value")
    return int(x)


def _scalar(x) -> bool:
    """A Python int or a 0-d array (the kernels need at least one array of at least one dimension)."""
    return type(x) is int or x.ndim == 0


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
    if _scalar(a) and _scalar(b):
        i_beta = sat(round_shr((a + 2 * b) * INV_SQRT3_Q15, 15), 16)   # s18 x u15 -> s33
        return (a if type(a) is int else a.copy()), i_beta
    i_beta = clarke_kernel(a, b)
    return np.broadcast_to(a, i_beta.shape).astype(np.int64), i_beta


def clarke_kernel(i_a, i_b, *, out: np.ndarray | None = None, saturate: bool = True) -> np.ndarray:
    """Unchecked array form of :func:`clarke`: ``i_beta = sat(((i_a + i_b + i_b) * 18919 + 2^14) >> 15, 16)``.

    ``i_a``, ``i_b``: s16 values (checked by the caller) as int64 arrays or Python ints, at least one
    an array; they broadcast and are not modified. ``i_alpha`` is ``i_a`` itself (no copy is made).
    ``out``: optional int64 array of the broadcast shape to write ``i_beta`` into (returned).
    ``saturate=False`` skips the saturation, exact only if every ``i_a + 2 i_b`` lies in
    ``-56755..56753`` (where the rounded product stays in s16; the caller's bounds say so).
    Five numpy operations (seven with saturation), all in place after the first.
    """
    t = np.add(i_a, i_b, out=out, dtype=np.int64)      # s18 after the second add
    t += i_b
    t *= INV_SQRT3_Q15                                  # x u15 -> s33
    t += 1 << 14
    t >>= 15
    if saturate:
        np.maximum(t, _S16_MIN, out=t)
        np.minimum(t, _S16_MAX, out=t)
    return t


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
    if _scalar(al) and _scalar(be) and _scalar(s) and _scalar(c):
        i_d = sat(round_shr(al * c + be * s, 15), 16)     # s16 x s16 -> s31, sum s32
        i_q = sat(round_shr(be * c - al * s, 15), 16)
        return i_d, i_q
    return park_kernel(al, be, s, c)


def park_kernel(i_alpha, i_beta, sin_q15, cos_q15, *, saturate: bool = True):
    """Unchecked array form of :func:`park`: ``(i_d, i_q)`` as new int64 arrays.

    Arguments: s16 values (checked by the caller) as int64 arrays or Python ints, at least one an
    array; they broadcast and are not modified. ``saturate=False`` skips the saturation to s16, exact
    if neither ``i_alpha*COS + i_beta*SIN`` nor ``i_beta*COS - i_alpha*SIN`` reaches ``2^30 - 2^14``
    in magnitude (see :func:`park_needs_saturation`).
    """
    i_d = i_alpha * cos_q15 + i_beta * sin_q15          # s16 x s16 -> s31, sum s32
    i_d += 1 << 14
    i_d >>= 15
    i_q = i_beta * cos_q15 - i_alpha * sin_q15
    i_q += 1 << 14
    i_q >>= 15
    if saturate:
        for x in (i_d, i_q):
            np.maximum(x, _S16_MIN, out=x)
            np.minimum(x, _S16_MAX, out=x)
    return i_d, i_q


def park_stacked_kernel(i_ab: np.ndarray, sin_q15: int, cos_q15: int, *, out: np.ndarray | None = None,
                        saturate: bool = True) -> np.ndarray:
    """Park transform of stacked currents by one matrix product: ``[i_d; i_q]``, a (2, n) int64 array.

    ``i_ab`` is an int64 array of shape (2, n), rows ``i_alpha`` and ``i_beta`` (s16, checked by the
    caller, not modified); ``sin_q15``, ``cos_q15`` Python ints, s16 (checked by the caller). Bit-equal
    to :func:`park_kernel` row by row: ``[[COS, SIN], [-SIN, COS]] @ i_ab`` forms exactly
    ``i_alpha*COS + i_beta*SIN`` and ``-i_alpha*SIN + i_beta*COS`` (int64 matmul is exact here: each
    product is below 2^31 in magnitude, each sum of two below 2^32), then ``+ 2^14``, ``>> 15`` and
    the saturation (skipped with ``saturate=False``, under the condition of :func:`park_kernel`).
    ``out``: optional C-contiguous int64 (2, n) array, not overlapping ``i_ab``, to write into
    (returned). Three numpy operations (five with saturation).
    """
    r = np.matmul(np.array(((cos_q15, sin_q15), (-sin_q15, cos_q15)), dtype=np.int64), i_ab, out=out)
    r += 1 << 14
    r >>= 15
    if saturate:
        np.maximum(r, _S16_MIN, out=r)
        np.minimum(r, _S16_MAX, out=r)
    return r


def park_needs_saturation(alpha_max: int, beta_max: int, sin_q15: int, cos_q15: int) -> bool:
    """Whether Park outputs may leave s16 when ``|i_alpha| <= alpha_max`` and ``|i_beta| <= beta_max``.

    Bounds each sum of products by ``alpha_max*|COS| + beta_max*|SIN|`` (resp. with the roles of the
    currents swapped) and applies the rounding shift to +/- that bound; conservative (True may be
    returned when no sample saturates), never wrong in the other direction. Arguments unchecked ints.
    """
    ac, as_ = abs(cos_q15), abs(sin_q15)
    bound = max(alpha_max * ac + beta_max * as_, beta_max * ac + alpha_max * as_)
    return (bound + (1 << 14)) >> 15 > _S16_MAX or (-bound + (1 << 14)) >> 15 < _S16_MIN
