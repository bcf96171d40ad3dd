"""ADC offset and scale: offset-binary ADC codes -> s16 phase currents, bit-true.

docs/spec.md, section 3.1. For a ``B``-bit offset-binary code (``B <= 16``, mid-scale = 0 A):

1. ``x = (code - 2^(B-1)) * 2^(16-B)``: left-aligned, s16;
2. ``i = sat(round_shr((x - ADC_OFFSET) * ADC_GAIN, 14), 16)`` with ``ADC_OFFSET`` s16 (current LSB)
   and ``ADC_GAIN`` u16 Q2.14 (16384 = 1.0).

Widths: ``x - ADC_OFFSET`` is s17, the product s17 x u16 -> s33, the result s16 (2^15 = ``I_FS``, the
ADC range). Two sensors, phases a and b (the paper's two LEMs); ``i_c = -i_a - i_b`` (s17) is formed
only by the overcurrent check (spec 3.6), not here.

A code outside ``0..2^B-1`` is not a value the ADC can produce: it is reported (ValueError), never
wrapped or clipped, so that a broken sensor model or interface cannot hide behind the scaling.
"""

from __future__ import annotations

import numpy as np

from golden.fixed import round_shr, sat

GAIN_ONE = 1 << 14
"""``ADC_GAIN`` value of a gain of 1.0 (Q2.14)."""


def _as_int_or_array(x, name: str):
    """A Python int for an integer scalar, an int64 array for an integer numpy array; else TypeError."""
    if isinstance(x, np.ndarray):
        if x.dtype.kind not in "iu":
            raise TypeError(f"{name} must be an integer array, got dtype {x.dtype}")
        if x.dtype == np.uint64 and x.size and int(x.max()) > np.iinfo(np.int64).max:
            raise ValueError(f"{name} holds values above the int64 range")
        return x.astype(np.int64)
    if isinstance(x, (bool, np.bool_)) or not isinstance(x, (int, np.integer)):
        raise TypeError(f"{name} must be an int or an integer numpy array, got {type(x).__name__}")
    return int(x)


def _check_param(value, lo: int, hi: int, name: str) -> int:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{name} must be an int, got {type(value).__name__}")
    value = int(value)
    if not lo <= value <= hi:
        raise ValueError(f"{name} = {value} must be in {lo}..{hi}")
    return value


def adc_to_current(code, bits: int, offset: int, gain: int):
    """Phase current (s16) from an offset-binary ADC code (spec 3.1).

    Parameters
    ----------
    code : int or numpy.ndarray of int
        ADC code(s), ``0..2^bits-1`` (offset binary, mid-scale ``2^(bits-1)`` = 0 A).
    bits : int
        ADC resolution ``B``, 1..16 (12 by default in the project).
    offset : int
        ``ADC_OFFSET`` register, s16, in current LSB (subtracted after left alignment).
    gain : int
        ``ADC_GAIN`` register, u16 Q2.14 (16384 = 1.0, 32768 = 2.0).

    Returns
    -------
    int or numpy.ndarray
        Phase current, s16 (2^15 = ``I_FS``); an int for an int code, an int64 array for an array.

    Raises
    ------
    ValueError
        If a code is outside ``0..2^bits-1``, ``bits`` is not in 1..16, ``offset`` is not s16 or
        ``gain`` is not u16.
    TypeError
        If ``code`` is neither an int nor an integer numpy array.

    Examples
    --------
    >>> adc_to_current(4095, 12, 0, 16384)   # (4095 - 2048) * 16 = 32752
    32752
    """
    bits = _check_param(bits, 1, 16, "bits (ADC resolution)")
    offset = _check_param(offset, -(1 << 15), (1 << 15) - 1, "offset (ADC_OFFSET, s16)")
    gain = _check_param(gain, 0, (1 << 16) - 1, "gain (ADC_GAIN, u16 Q2.14)")
    c = _as_int_or_array(code, "code")
    top = (1 << bits) - 1
    if isinstance(c, np.ndarray):
        bad = (c < 0) | (c > top)
        if np.any(bad):
            idx = np.flatnonzero(bad)[0]
            raise ValueError(f"ADC code[{idx}] = {int(c.flat[idx])} is outside 0..{top} of a "
                             f"{bits}-bit converter")
    elif not 0 <= c <= top:
        raise ValueError(f"ADC code {c} is outside 0..{top} of a {bits}-bit converter")
    x = (c - (1 << (bits - 1))) * (1 << (16 - bits))        # left-aligned, s16
    return sat(round_shr((x - offset) * gain, 14), 16)      # s17 x u16 -> s33, then s16
