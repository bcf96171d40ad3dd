"""One integration window through the FPGA data path in one call: ADC scale -> Clarke -> Park -> demodulator.

docs/spec.md, sections 3.1, 3.2 and 3.4. :func:`window_dsp` is bit-equal to the chain of the public,
checking functions (tests/test_fpga_window_dsp.py compares them on random windows)::

    i_a = adc_to_current(adc_a, bits, offset_a, gain_a)
    i_b = adc_to_current(adc_b, bits, offset_b, gain_b)
    i_alpha, i_beta = clarke(i_a, i_b)
    i_d, i_q = park(i_alpha, i_beta, sin_q15, cos_q15)
    result = demodulate(i_d[keep], i_q[keep], w[keep])        # keep: all samples if None

but validates its inputs once (the ADC codes by one min/max per channel) and then runs the unchecked
kernels on int64 arrays, without the per-stage checks and conversion copies of the chain: it is what
the closed loop calls once per PWM window. The ADC scaling is a look-up of each code in the table of
every code's current (:func:`scale_table`, the kernel's own values, made once per register setting):
one numpy operation per channel instead of three to five.

The codes' min and max also bound every intermediate value (each stage is monotone or bounded by the
magnitudes of its inputs), so a saturation that provably cannot act on this window is skipped. A
skipped saturation would have returned its input unchanged: the result is the same integers.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from golden.fixed import sat
from golden.fpga.adc_scale import adc_to_current_kernel
from golden.fpga.checks import int_param
from golden.fpga.demodulator import WindowResult, latch_window
from golden.fpga.park import INV_SQRT3_Q15, clarke_kernel, park_needs_saturation, park_stacked_kernel

_S16_MIN, _S16_MAX = -(1 << 15), (1 << 15) - 1


def _int_array(x, name: str) -> np.ndarray:
    a = np.asarray(x)
    if a.dtype.kind not in "iu":
        raise TypeError(f"{name} must be an integer array, got dtype {a.dtype}")
    if a.ndim != 1:
        raise ValueError(f"{name} must be 1-D (one window's samples), got shape {a.shape}")
    return a


def _adc_range(code: np.ndarray, ch: str, bits: int) -> tuple[int, int]:
    """(min, max) of one channel's codes; ValueError naming the channel and the first bad code."""
    top = (1 << bits) - 1
    lo, hi = int(code.min()), int(code.max())
    if lo < 0 or hi > top:
        idx = int(np.flatnonzero((code < 0) | (code > top))[0])
        raise ValueError(f"ADC code adc_{ch}[{idx}] = {int(code[idx])} is outside 0..{top} of a "
                         f"{bits}-bit converter (channel {ch})")
    return lo, hi


@lru_cache(maxsize=64)
def scale_table(bits: int, offset: int, gain: int) -> np.ndarray:
    """The current of every code ``0..2^bits-1`` (``adc_to_current_kernel``, saturated), int64, read-only: the ADC
    scaling of a window is a look-up in it. Arguments checked by the caller."""
    table = adc_to_current_kernel(np.arange(1 << bits, dtype=np.int64), bits, offset, gain)
    table.flags.writeable = False
    return table


def _clarke_beta(s: int) -> int:
    """Unsaturated ``i_beta`` for ``s = i_a + 2 i_b`` (monotone non-decreasing in ``s``)."""
    return (s * INV_SQRT3_Q15 + (1 << 14)) >> 15


def window_dsp(adc_a, adc_b, bits: int, offset_a: int, offset_b: int, gain_a: int, gain_b: int,
               sin_q15: int, cos_q15: int, w, keep=None) -> tuple[WindowResult, np.ndarray, np.ndarray]:
    """ADC codes of one window -> latched window result, and the Park currents of every sample.

    Parameters
    ----------
    adc_a, adc_b : numpy.ndarray of int
        1-D, one length ``n``: the window's ADC codes of phases a and b, ``0..2^bits-1`` (any integer
        dtype; e.g. the int32 columns of the plant's ADC output, used without a conversion copy).
    bits : int
        ADC resolution ``B``, 1..16.
    offset_a, offset_b : int
        ``ADC_OFFSET`` of each channel, s16.
    gain_a, gain_b : int
        ``ADC_GAIN`` of each channel, u16 Q2.14.
    sin_q15, cos_q15 : int
        ``SIN``, ``COS`` of the angle active for the window, s16 Q1.15.
    w : numpy.ndarray of int
        1-D, length ``n``: the demodulation weights of the samples, s16 Q1.15.
    keep : numpy.ndarray of bool, optional
        1-D, length ``n``: the samples that enter the demodulator (``OS_BLANK``: False for the blanked
        ones). Applied after Park; None keeps every sample.

    Returns
    -------
    (WindowResult, i_d, i_q)
        The window's latched results (:func:`golden.fpga.demodulator.demodulate` of the kept samples)
        and the Park currents ``i_d``, ``i_q`` of all ``n`` samples (blanked ones included), s16 as
        int64 arrays (two rows of one new array, views that the caller owns).

    Raises
    ------
    ValueError
        If an ADC code is outside ``0..2^bits-1`` (the message names the channel, the index and the
        code), a register is not an int in its format, ``w`` is not s16, or the arrays are not 1-D
        of one length.
    TypeError
        If an array does not hold integers (``keep``: booleans).
    """
    bits = int_param(bits, 1, 16, "bits (ADC resolution)")
    offset_a = int_param(offset_a, _S16_MIN, _S16_MAX, "offset_a (ADC_OFFSET, s16)")
    offset_b = int_param(offset_b, _S16_MIN, _S16_MAX, "offset_b (ADC_OFFSET, s16)")
    gain_a = int_param(gain_a, 0, (1 << 16) - 1, "gain_a (ADC_GAIN, u16 Q2.14)")
    gain_b = int_param(gain_b, 0, (1 << 16) - 1, "gain_b (ADC_GAIN, u16 Q2.14)")
    s = int_param(sin_q15, _S16_MIN, _S16_MAX, "sin_q15 (SIN, s16 Q1.15)")
    c = int_param(cos_q15, _S16_MIN, _S16_MAX, "cos_q15 (COS, s16 Q1.15)")
    ca = _int_array(adc_a, "adc_a")
    cb = _int_array(adc_b, "adc_b")
    ww = _int_array(w, "w")
    n = len(ca)
    if not len(cb) == len(ww) == n:
        raise ValueError(f"adc_a, adc_b and w must have one length, got {n}, {len(cb)}, {len(ww)}")
    if keep is not None:
        keep = np.asarray(keep)
        if keep.dtype != np.bool_:
            raise TypeError(f"keep must be a boolean array, got dtype {keep.dtype}")
        if keep.shape != (n,):
            raise ValueError(f"keep must have shape ({n},), got {keep.shape}")
    if n == 0:
        empty = np.zeros(0, dtype=np.int64)
        return latch_window(0, 0, 0, 0, 0, 0), empty, empty.copy()
    if ww.dtype != np.int16 and (int(ww.min()) < _S16_MIN or int(ww.max()) > _S16_MAX):
        idx = int(np.flatnonzero((ww < _S16_MIN) | (ww > _S16_MAX))[0])
        raise ValueError(f"w[{idx}] = {int(ww[idx])} is not an s16 value")
    lo_a, hi_a = _adc_range(ca, "a", bits)
    lo_b, hi_b = _adc_range(cb, "b", bits)

    # ADC scale (spec 3.1) by the tables, phase a straight into row 0 of the stacked [i_alpha; i_beta]
    # (i_alpha = i_a). The scaling is non-decreasing in the code: the min and max codes give the exact range.
    # Rows: i_alpha, i_beta, then i_d, i_q (Park) and w, so that one dot product with w and one sum
    # per row give every demodulator sum (the unused i_alpha, i_beta rows are not reduced).
    t_a, t_b = scale_table(bits, offset_a, gain_a), scale_table(bits, offset_b, gain_b)
    buf = np.empty((5, n), dtype=np.int64)
    i_ab, dqw = buf[:2], buf[2:]
    t_a.take(ca, out=buf[0], mode="clip")          # every code is in range (checked): clip changes none
    i_b = t_b.take(cb, mode="clip")
    ia_lo, ia_hi, ib_lo, ib_hi = int(t_a[lo_a]), int(t_a[hi_a]), int(t_b[lo_b]), int(t_b[hi_b])

    # Clarke (spec 3.2) into row 1: i_beta is monotone in i_a + 2 i_b, which lies in
    # [ia_lo + 2 ib_lo, ia_hi + 2 ib_hi] (a superset of the window's values).
    be_lo, be_hi = _clarke_beta(ia_lo + 2 * ib_lo), _clarke_beta(ia_hi + 2 * ib_hi)
    clarke_kernel(buf[0], i_b, out=buf[1], saturate=be_lo < _S16_MIN or be_hi > _S16_MAX)
    be_lo, be_hi = sat(be_lo, 16), sat(be_hi, 16)

    # Park (spec 3.2) into rows 2, 3 by one matrix product; saturation only if the magnitude bound
    # of the window's currents allows it.
    park_stacked_kernel(i_ab, s, c, out=buf[2:4], saturate=park_needs_saturation(
        max(-ia_lo, ia_hi), max(-be_lo, be_hi), s, c))
    buf[4] = ww

    # Demodulator (spec 3.4) on the kept samples: [i_d; i_q; w] @ w and the row sums, exact in int64.
    if keep is not None:
        dqw = dqw.compress(keep, axis=1)
    acc_d, acc_q, _ = (dqw @ dqw[2]).tolist()
    sum_d, sum_q, wsum = dqw.sum(axis=1).tolist()
    return latch_window(acc_q, acc_d, sum_d, sum_q, wsum, dqw.shape[1]), buf[2], buf[3]
