"""Fixed-point helpers shared by every bit-true model (docs/spec.md, "Arithmetic rules").

Values are plain Python ints or numpy int64 arrays holding raw two's-complement integers. Each helper
names one operation that the RTL and the firmware C perform in exactly the same way:

* ``shr`` is an arithmetic right shift (floor division by 2^n), as Verilog ``>>>`` on a signed value
  and GCC's ``>>`` on a signed int (GCC documents it as arithmetic).
* ``round_shr`` rounds half up: ``(x + 2^(n-1)) >> n``.
* ``sat`` saturates to a signed width; ``usat`` to an unsigned width.
* ``wrap`` reduces to a signed width modulo 2^bits (binary angles only: they are meant to wrap).
* ``c_div`` divides truncating toward zero, as C's ``/`` on ints.

Every helper accepts a Python int or an int64 numpy array and returns the same kind.
"""

from __future__ import annotations

import math

import numpy as np


def _check_bits(bits: int) -> None:
    if not 1 <= bits <= 64:
        raise ValueError(f"width {bits} must be in 1..64")


def smin(bits: int) -> int:
    """Smallest signed value of a width."""
    return -(1 << (bits - 1))


def smax(bits: int) -> int:
    """Largest signed value of a width."""
    return (1 << (bits - 1)) - 1


def sat(x, bits: int):
    """Saturate to the signed range of ``bits`` bits."""
    if type(x) is int and type(bits) is int and 0 < bits <= 64:     # fast path: plain Python int
        hi = (1 << (bits - 1)) - 1
        if x > hi:
            return hi
        return -1 - hi if x < -1 - hi else x
    _check_bits(bits)
    if isinstance(x, np.ndarray):
        if x.dtype == np.int64:                      # same values as np.clip, a third of its cost
            return np.minimum(np.maximum(x, smin(bits)), smax(bits))
        return np.clip(x, smin(bits), smax(bits))
    return min(max(x, smin(bits)), smax(bits))


def usat(x, bits: int):
    """Saturate to the unsigned range of ``bits`` bits."""
    if type(x) is int and type(bits) is int and 0 < bits <= 64:     # fast path: plain Python int
        if x < 0:
            return 0
        hi = (1 << bits) - 1
        return hi if x > hi else x
    _check_bits(bits)
    if isinstance(x, np.ndarray):
        if x.dtype == np.int64 and bits < 64:       # (2^64 - 1 is no int64 operand)
            return np.minimum(np.maximum(x, 0), (1 << bits) - 1)
        return np.clip(x, 0, (1 << bits) - 1)
    return min(max(x, 0), (1 << bits) - 1)


def wrap(x, bits: int):
    """Two's-complement wrap to a signed width (for binary angles and their differences)."""
    if type(x) is int and type(bits) is int and 0 < bits <= 64:     # fast path: plain Python int
        half = 1 << (bits - 1)
        return ((x + half) & ((half << 1) - 1)) - half
    _check_bits(bits)
    half = 1 << (bits - 1)
    if isinstance(x, np.ndarray):
        if bits == 64:
            return x.astype(np.int64)
        return ((x + half) & ((1 << bits) - 1)) - half
    return ((x + half) & ((1 << bits) - 1)) - half


def uwrap(x, bits: int):
    """Wrap to an unsigned width (modulo 2^bits)."""
    if type(x) is int and type(bits) is int and 0 < bits <= 64:     # fast path: plain Python int
        return x & ((1 << bits) - 1)
    _check_bits(bits)
    return x & ((1 << bits) - 1)


def shr(x, n: int):
    """Arithmetic shift right by ``n`` >= 0 bits (floor of x / 2^n)."""
    if n >= 0:                                       # plain ints and int64 arrays alike: one compare
        return x >> n
    raise ValueError(f"shift {n} must be >= 0")


def round_shr(x, n: int):
    """Shift right by ``n`` >= 0 bits, rounding half up: (x + 2^(n-1)) >> n."""
    if n > 0:
        return (x + (1 << (n - 1))) >> n
    if n < 0:
        raise ValueError(f"shift {n} must be >= 0")
    return x


def c_div(a, b):
    """Integer division truncating toward zero (C semantics); ``b`` must not be 0."""
    if type(a) is int and type(b) is int and b:      # fast path: plain Python ints
        q = abs(a) // abs(b)
        return -q if (a < 0) != (b < 0) else q
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a = np.asarray(a, dtype=np.int64)
        b = np.asarray(b, dtype=np.int64)
        if np.any(b == 0):
            raise ZeroDivisionError("c_div by zero")
        q = np.abs(a) // np.abs(b)
        return np.where((a < 0) != (b < 0), -q, q)
    if b == 0:
        raise ZeroDivisionError("c_div by zero")
    q = abs(a) // abs(b)
    return -q if (a < 0) != (b < 0) else q


def to_fixed(value: float, frac_bits: int, bits: int | None = None) -> int:
    """Nearest integer to ``value * 2^frac_bits`` (half away from zero), saturated to ``bits`` if given.

    For configuration constants computed from physical parameters (gains, scales), never in a datapath. A value
    whose scaled magnitude is not finite (infinite, NaN, or beyond a float: a scenario value of 1e153 Hz) is a
    ValueError, which the callers name with the scenario keys it came from (control_config._named).
    """
    scaled = abs(value) * (1 << frac_bits)
    if not math.isfinite(scaled):
        raise ValueError(f"{value!r} times 2^{frac_bits} is not a finite number: no fixed-point constant holds it")
    raw = int(np.floor(scaled + 0.5))
    raw = -raw if value < 0 else raw
    return raw if bits is None else sat(raw, bits)
