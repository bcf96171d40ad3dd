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

:func:`adc_to_current` checks its arguments; :func:`adc_to_current_kernel` is the unchecked int64 array
form (the same integers) that :mod:`golden.fpga.window_dsp` runs once per window.
"""

from __future__ import annotations

import numpy as np

from golden.fixed import round_shr, sat
from golden.fpga.checks import int_or_array, int_param

GAIN_ONE = 1 << 14
"""``ADC_GAIN`` value of a gain of 1.0 (Q2.14)."""


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
    bits = int_param(bits, 1, 16, "bits (ADC resolution)")
    offset = int_param(offset, -(1 << 15), (1 << 15) - 1, "offset (ADC_OFFSET, s16)")
    gain = int_param(gain, 0, (1 << 16) - 1, "gain (ADC_GAIN, u16 Q2.14)")
    c = int_or_array(code, "code")
    top = (1 << bits) - 1
    if not isinstance(c, np.ndarray) or c.ndim == 0:       # an int (or a 0-d array): the formula itself
        if not 0 <= c <= top:
            if isinstance(c, np.ndarray):
                raise ValueError(f"ADC code[0] = {int(c)} is outside 0..{top} of a {bits}-bit converter")
            raise ValueError(f"ADC code {c} is outside 0..{top} of a {bits}-bit converter")
        if isinstance(c, np.ndarray):
            c = c.astype(np.int64)
        x = (c - (1 << (bits - 1))) * (1 << (16 - bits))        # left-aligned, s16
        return sat(round_shr((x - offset) * gain, 14), 16)      # s17 x u16 -> s33, then s16
    if c.size == 0:
        return np.zeros(c.shape, dtype=np.int64)
    lo, hi = int(c.min()), int(c.max())
    if lo < 0 or hi > top:
        idx = np.flatnonzero((c < 0) | (c > top))[0]
        raise ValueError(f"ADC code[{idx}] = {int(c.flat[idx])} is outside 0..{top} of a "
                         f"{bits}-bit converter")
    return adc_to_current_kernel(c, bits, offset, gain,
                                 saturate=adc_needs_saturation(lo, hi, bits, offset, gain))


def adc_affine(bits: int, offset: int, gain: int) -> tuple[int, int]:
    """``(m, k)`` with ``(x - ADC_OFFSET) * ADC_GAIN + 2^13 == code * m + k`` for every code (spec 3.1).

    ``x = (code - 2^(B-1)) * 2^(16-B) = code * 2^(16-B) - 2^15``, hence ``m = ADC_GAIN * 2^(16-B)``
    (u31) and ``k = 2^13 - (2^15 + ADC_OFFSET) * ADC_GAIN``: the rounded scaling is
    ``(code * m + k) >> 14``, an exact integer identity (no rounding is moved). ``m >= 0``, so the
    result is non-decreasing in the code. Arguments unchecked.
    """
    return gain << (16 - bits), (1 << 13) - ((1 << 15) + offset) * gain


def adc_needs_saturation(code_min: int, code_max: int, bits: int, offset: int, gain: int) -> bool:
    """Whether some code in ``code_min..code_max`` scales outside s16 (so the final ``sat`` can act).

    The scaling is non-decreasing in the code, so only the two ends need checking. Arguments unchecked.
    """
    m, k = adc_affine(bits, offset, gain)
    return (code_min * m + k) >> 14 < -(1 << 15) or (code_max * m + k) >> 14 > (1 << 15) - 1


def adc_to_current_kernel(code: np.ndarray, bits: int, offset: int, gain: int, *,
                          out: np.ndarray | None = None, saturate: bool = True) -> np.ndarray:
    """Unchecked array form of :func:`adc_to_current`: ``sat(((code * m + k) >> 14), 16)``, int64.

    ``code`` is an integer array (any integer dtype, e.g. an int32 column view of the plant's ADC
    output; it is not modified) whose values the caller has checked to be in ``0..2^bits-1``;
    ``bits``, ``offset``, ``gain`` are checked Python ints (see :func:`adc_affine` for ``m``, ``k``).
    ``out``: optional int64 array of ``code``'s shape to write into (returned). ``saturate=False``
    skips the final saturation, which is exact only if no code can leave s16
    (:func:`adc_needs_saturation` of the codes' min and max is False). Four numpy operations, three
    without saturation; no conversion copy. Products: ``code * m < 2^16 * 2^31``, exact in int64.
    """
    m, k = adc_affine(bits, offset, gain)
    r = np.multiply(code, m, out=out, dtype=np.int64)
    r += k
    r >>= 14
    if saturate:
        np.maximum(r, -(1 << 15), out=r)
        np.minimum(r, (1 << 15) - 1, out=r)
    return r
