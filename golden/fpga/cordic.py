"""Rotation-mode CORDIC on binary angles: sin/cos, the demodulation weight and the firmware's sin/cos.

docs/spec.md, section 3.3. Parameters ``WIDTH`` (data width, 8..32, default 32) and ``ITERATIONS``
(1..WIDTH, default 32: the paper's 32 bits / 32 clocks).

* The input angle ``a`` is a ``u32`` binary angle (2^32 = one turn). Fold: if its top two bits are
  ``01`` or ``10`` (90 deg ... 270 deg) the rotation uses ``a - 2^31`` and the results are negated;
  otherwise it uses ``a`` read as ``s32``. The folded angle ``z`` (s32) lies in ``[-2^30, 2^30)``.
* ``x0 = round(K_N * 2^(WIDTH-2))`` with ``K_N = prod 1/sqrt(1 + 2^-2i)``, ``y0 = 0``.
* Iteration ``i = 0 .. ITERATIONS-1``: ``d = +1 if z >= 0 else -1``; ``x' = x - d*shr(y, i)``,
  ``y' = y + d*shr(x, i)``, ``z' = z - d*ATAN[i]`` with ``ATAN[i] = round(atan(2^-i) * 2^32 / 2pi)``.
* Outputs ``cos = x``, ``sin = y`` in Q2.(WIDTH-2); in Q1.15: ``sat(round_shr(v, WIDTH-17), 16)``.
* Demodulation weight (Benevieri et al. 2023, eq. (19)): for a sample at carrier counter ``c``,
  ``a = wrap((H - 2c) * CW_ANGLE_STEP, 32)`` with ``CW_ANGLE_STEP = round(2^30 / H)``, i.e.
  ``a ~ -cw * 2^30`` = ``-cw * pi/2`` with ``cw = 2c/H - 1`` (eq. (15)), and ``w = sin(a)`` in Q1.15.
* The firmware's sin/cos of the estimated angle use ``WIDTH = 32``, ``ITERATIONS = 16`` (spec 5.2).

Widths: the folded angle and ``z`` stay inside ``[-2^30, 2^30]`` (s32); ``|x|, |y|`` stay below
``K_N * prod sqrt(1 + 2^-2i) * 2^(WIDTH-2)`` plus the truncation errors, i.e. about ``2^(WIDTH-2)``:
Q2.(WIDTH-2) in sWIDTH never overflows. ``(H - 2c) * CW_ANGLE_STEP`` is at most ``65534 * (2^32-1)``
in magnitude (s49) before the wrap.

Every datapath function takes a Python int (returns Python ints) or an integer numpy array (returns
int64 arrays, loop over the iterations, vector over the samples).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from golden.fixed import round_shr, sat, shr, to_fixed, uwrap, wrap
from golden.fpga.checks import int_or_array, int_param

ANGLE_BITS = 32
"""Width of the binary angle (u32, 2^32 = one turn)."""
WIDTH_MIN, WIDTH_MAX = 8, 32
"""Supported range of the ``WIDTH`` parameter."""
U32_MAX = (1 << 32) - 1
HALF_MIN, HALF_MAX = 4, 65534
"""Range of the effective carrier half period ``H`` (even; spec 2.1, u16 ``PWM_HALF``)."""


# ---- parameter and input checks ---------------------------------------------------------------------
def _check_range(x, lo: int, hi: int, name: str, what: str) -> None:
    """ValueError naming the first value of ``x`` (int or array) outside ``lo..hi``."""
    if isinstance(x, np.ndarray):
        bad = (x < lo) | (x > hi)
        if np.any(bad):
            idx = np.flatnonzero(bad)[0]
            raise ValueError(f"{name}[{idx}] = {int(x.flat[idx])} is not {what} ({lo}..{hi})")
    elif not lo <= x <= hi:
        raise ValueError(f"{name} = {x} is not {what} ({lo}..{hi})")


def _check_width_iterations(width, iterations) -> tuple[int, int]:
    width = int_param(width, WIDTH_MIN, WIDTH_MAX, "width")
    iterations = int_param(iterations, 1, width, "iterations")
    return width, iterations


def _check_half(half) -> int:
    half = int_param(half, HALF_MIN, HALF_MAX, "half (H, carrier half period)")
    if half & 1:
        raise ValueError(f"half (H, carrier half period) = {half} must be even (spec 2.1)")
    return half


# ---- constants (host side) --------------------------------------------------------------------------
@functools.lru_cache(maxsize=None)
def _atan_table(iterations: int) -> tuple[int, ...]:
    return tuple(to_fixed(math.atan(2.0 ** -i) / (2.0 * math.pi), ANGLE_BITS)
                 for i in range(iterations))


def atan_table(iterations: int) -> list[int]:
    """Arctangent table of the CORDIC in binary angle units (spec 3.3).

    ``ATAN[i] = round(atan(2^-i) * 2^32 / (2*pi))``, nearest (the values are never within 0.01 of a
    tie, so the double-precision evaluation is exact). ``ATAN[0] = 2^29`` (45 deg).

    Parameters
    ----------
    iterations : int
        Number of entries, 1..32.

    Returns
    -------
    list of int
        ``ATAN[0 .. iterations-1]``, each a non-negative s32 (entries from ``i = 31`` on are 0).

    Raises
    ------
    ValueError
        If ``iterations`` is not an int in 1..32.
    """
    iterations = int_param(iterations, 1, ANGLE_BITS, "iterations")
    return list(_atan_table(iterations))


def cordic_gain_inverse(iterations: int) -> float:
    """Inverse CORDIC gain ``K_N = prod_{i<N} 1/sqrt(1 + 2^-2i)`` (spec 3.3).

    Parameters
    ----------
    iterations : int
        Number of iterations ``N``, 1..32.

    Returns
    -------
    float
        ``K_N`` (0.70710678... for N = 1, 0.60725293... for large N).

    Raises
    ------
    ValueError
        If ``iterations`` is not an int in 1..32.
    """
    iterations = int_param(iterations, 1, ANGLE_BITS, "iterations")
    k = 1.0
    for i in range(iterations):
        k /= math.sqrt(1.0 + 2.0 ** (-2 * i))
    return k


@functools.lru_cache(maxsize=None)
def _x0(width: int, iterations: int) -> int:
    return to_fixed(cordic_gain_inverse(iterations), width - 2)


def x0(width: int, iterations: int) -> int:
    """Start value ``x0 = round(K_N * 2^(WIDTH-2))`` of the rotation (spec 3.3).

    Computed once on the host with :func:`golden.fixed.to_fixed` (nearest; the exact value is never
    within 0.002 of a tie for any supported ``(WIDTH, ITERATIONS)``, so the double evaluation is exact).

    Parameters
    ----------
    width : int
        Data width ``WIDTH``, 8..32.
    iterations : int
        ``ITERATIONS``, 1..width.

    Returns
    -------
    int
        ``x0`` in Q2.(WIDTH-2) (e.g. 652032874 for WIDTH = 32, ITERATIONS = 32).

    Raises
    ------
    ValueError
        If ``width`` or ``iterations`` is out of range.
    """
    width, iterations = _check_width_iterations(width, iterations)
    return _x0(width, iterations)


def cw_angle_step(half: int) -> int:
    """``CW_ANGLE_STEP = round(2^30 / H)``, the u32 register of the demodulation weight (spec 3.3).

    Exact integer arithmetic: ``(2^31 // H + 1) // 2`` = ``floor(2^30/H + 1/2)`` (a tie would need
    ``2^31/H`` odd, impossible for an even ``H <= 65534``).

    Parameters
    ----------
    half : int
        Effective carrier half period ``H`` [ticks]: even, 4..65534 (spec 2.1).

    Returns
    -------
    int
        The step, so that ``H * step ~ 2^30`` (a quarter turn, ``-cw*pi/2`` at the carrier bottom).

    Raises
    ------
    ValueError
        If ``half`` is not an even int in 4..65534.
    """
    half = _check_half(half)
    return ((1 << 31) // half + 1) // 2


# ---- datapath ---------------------------------------------------------------------------------------
def cordic_sincos(angle, width: int = 32, iterations: int = 32):
    """Sine and cosine of a u32 binary angle by rotation-mode CORDIC, raw Q2.(WIDTH-2) (spec 3.3).

    Parameters
    ----------
    angle : int or numpy.ndarray of int
        Binary angle, u32 (0..2^32-1, 2^32 = one turn). Use ``golden.fixed.uwrap(a, 32)`` on a
        signed angle first.
    width : int, optional
        Data width ``WIDTH`` of ``x, y``, 8..32 (default 32).
    iterations : int, optional
        ``ITERATIONS``, 1..width (default 32).

    Returns
    -------
    (sin_raw, cos_raw)
        ``y`` and ``x`` after the iterations, Q2.(WIDTH-2) (``2^(WIDTH-2)`` = 1.0): Python ints for
        an int angle, int64 arrays of the angle's shape for an array.

    Raises
    ------
    ValueError
        If an angle is outside 0..2^32-1 or ``width`` / ``iterations`` is out of range.
    TypeError
        If ``angle`` is neither an int nor an integer numpy array.
    """
    width, iterations = _check_width_iterations(width, iterations)
    a = int_or_array(angle, "angle", as_int64=True)
    _check_range(a, 0, U32_MAX, "angle", "a u32 binary angle")
    table = _atan_table(iterations)
    start = _x0(width, iterations)
    quadrant = shr(a, ANGLE_BITS - 2)  # top two bits
    if isinstance(a, np.ndarray):
        fold = (quadrant == 1) | (quadrant == 2)
        z = np.where(fold, a - (1 << 31), wrap(a, ANGLE_BITS))
        x = np.full_like(z, start)
        y = np.zeros_like(z)
        for i in range(iterations):
            d = (z >> 63) | 1           # +1 where z >= 0, -1 where z < 0 (int64 sign)
            x, y = x - d * shr(y, i), y + d * shr(x, i)
            z = z - d * table[i]
        return np.where(fold, -y, y), np.where(fold, -x, x)
    return _rotate_int(a, table, start)


def _rotate_int(a: int, table: tuple[int, ...], start: int) -> tuple[int, int]:
    """The rotation of :func:`cordic_sincos` for one Python-int angle in 0..2^32-1 (checked by the caller):
    ``(sin_raw, cos_raw)``. ``>>`` on a Python int is ``shr`` (floor), and each ``d`` branch is the
    iteration's ``x - d*shr(y, i), y + d*shr(x, i), z - d*ATAN[i]``."""
    fold = (1 << 30) <= a < (3 << 30)                 # top two bits 01 or 10
    z = a - (1 << 31) if fold else wrap(a, ANGLE_BITS)
    x, y = start, 0
    for i, atan in enumerate(table):
        if z >= 0:
            x, y, z = x - (y >> i), y + (x >> i), z - atan
        else:
            x, y, z = x + (y >> i), y - (x >> i), z + atan
    return (-y, -x) if fold else (y, x)


def to_q15(v_raw, width: int):
    """Q2.(WIDTH-2) CORDIC output -> s16 Q1.15: ``sat(round_shr(v, WIDTH - 17), 16)`` (spec 3.3).

    Parameters
    ----------
    v_raw : int or numpy.ndarray of int
        CORDIC output, sWIDTH Q2.(WIDTH-2).
    width : int
        ``WIDTH``, 17..32: the spec's conversion is a right shift by ``WIDTH - 17`` (undefined for a
        narrower CORDIC).

    Returns
    -------
    int or numpy.ndarray
        s16 Q1.15 (+1.0 saturates to 32767).

    Raises
    ------
    ValueError
        If ``width`` is not in 17..32 or a value is outside sWIDTH.
    TypeError
        If ``v_raw`` is neither an int nor an integer numpy array.
    """
    width = int_param(width, 17, WIDTH_MAX, "width (Q1.15 conversion needs WIDTH >= 17)")
    v = int_or_array(v_raw, "v_raw", as_int64=True)
    _check_range(v, -(1 << (width - 1)), (1 << (width - 1)) - 1, "v_raw", f"an s{width} value")
    return sat(round_shr(v, width - 17), 16)


def sincos_q15(angle, width: int = 32, iterations: int = 16):
    """Sine and cosine of a u32 binary angle in s16 Q1.15 (spec 3.3 and 5.2, firmware sin/cos of theta).

    Parameters
    ----------
    angle : int or numpy.ndarray of int
        Binary angle, u32.
    width : int, optional
        ``WIDTH``, 17..32 (default 32, the firmware's).
    iterations : int, optional
        ``ITERATIONS``, 1..width (default 16, the firmware's).

    Returns
    -------
    (sin_q15, cos_q15)
        s16 Q1.15 (the ``SIN`` and ``COS`` registers), ints or int64 arrays.

    Raises
    ------
    ValueError
        As :func:`cordic_sincos` and :func:`to_q15`.
    """
    if type(angle) is int and 0 <= angle <= U32_MAX:   # one plain int (the firmware's angle, every window)
        width, table, start = _q15_rotation(width, iterations)
        s, c = _rotate_int(angle, table, start)
        n = width - 17
        return sat(round_shr(s, n), 16), sat(round_shr(c, n), 16)   # to_q15 (|s|, |c| < 2^(WIDTH-1))
    width = int_param(width, 17, WIDTH_MAX, "width (Q1.15 conversion needs WIDTH >= 17)")
    s, c = cordic_sincos(angle, width, iterations)
    return to_q15(s, width), to_q15(c, width)


@functools.lru_cache(maxsize=None, typed=True)
def _q15_rotation(width, iterations) -> tuple[int, tuple[int, ...], int]:
    """``(WIDTH, ATAN table, x0)`` of :func:`sincos_q15`, checked once per parameter pair (an exception is not
    cached: a bad pair raises every time)."""
    width = int_param(width, 17, WIDTH_MAX, "width (Q1.15 conversion needs WIDTH >= 17)")
    width, iterations = _check_width_iterations(width, iterations)
    return width, _atan_table(iterations), _x0(width, iterations)


def demod_weight(counter, half: int, step: int, width: int = 32, iterations: int = 32):
    """Demodulation weight ``w = sin(-cw * pi/2)`` in s16 Q1.15 for carrier counter values (spec 3.3).

    ``a = wrap((H - 2c) * CW_ANGLE_STEP, 32)`` read as a u32 binary angle (``a ~ -cw * 2^30``, with
    ``cw = 2c/H - 1``, Benevieri et al. 2023, eq. (15)), ``w = to_q15(sin(a))``: the weight of
    ``eps = i_q * sin(-cw*pi/2)``, Benevieri et al. 2023, eq. (19). +1 (32767) at the carrier bottom
    (``c = 0``), 0 at the zero crossing (``c = H/2``), -1 at the top (``c = H``).

    Parameters
    ----------
    counter : int or numpy.ndarray of int
        Carrier counter ``c`` of the sampling instant, 0..H (spec 2.1).
    half : int
        Effective carrier half period ``H``: even, 4..65534.
    step : int
        ``CW_ANGLE_STEP`` register, u32 (normally :func:`cw_angle_step` of ``half``).
    width : int, optional
        CORDIC ``WIDTH``, 17..32 (default 32).
    iterations : int, optional
        CORDIC ``ITERATIONS``, 1..width (default 32).

    Returns
    -------
    int or numpy.ndarray
        ``w``, s16 Q1.15.

    Raises
    ------
    ValueError
        If a counter is outside 0..H, ``half`` is not even in 4..65534, ``step`` is not u32, or the
        CORDIC parameters are out of range.
    """
    half = _check_half(half)
    step = int_param(step, 0, U32_MAX, "step (CW_ANGLE_STEP, u32)")
    c = int_or_array(counter, "counter", as_int64=True)
    _check_range(c, 0, half, "counter", "a carrier counter value")
    # (H - 2c) is s17, times a u32 step: s49 before the wrap to the 32-bit binary angle.
    a = uwrap(wrap((half - 2 * c) * step, ANGLE_BITS), ANGLE_BITS)
    return sincos_q15(a, width, iterations)[0]
