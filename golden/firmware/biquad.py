"""Second-order IIR section of the firmware (band-pass and notch filters), bit-true.

Direct form I with Q28 coefficients and ``Y_FRAC`` fraction bits on the output, once per control period:

    acc = b0 * (x << Y_FRAC) + b1 * (x1 << Y_FRAC) + b2 * (x2 << Y_FRAC) - a1 * y1 - a2 * y2
    y   = sat(round_shr(acc, 28), 32)
    x2, x1, y2, y1 = x1, x, y1, y

``x`` in current LSB (|x| < 2^20), ``y`` in current LSB * 2^Y_FRAC. Coefficients |b|, |a| < 2^30 (the
int32 range of Q28 values below 4); with |y| < 2^31 every product is below 2^61 and the sum of five
fits int64. ``round_shr`` rounds half up (``(acc + 2^27) >> 28``).

Host side: :func:`bandpass` and :func:`notch` discretise the continuous prototypes by the bilinear
transform **prewarped at the centre frequency**, so that the discrete centre is exactly ``f0`` (a plain
bilinear transform moves a 1000 Hz centre at 10 kHz to about 970 Hz; docs/methods.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from golden.fixed import round_shr, sat, to_fixed

COEF_FRAC = 28
"""Fraction bits of the coefficients."""
Y_FRAC = 4
"""Fraction bits of the output (and of the feedback state)."""
_COEF_LIMIT = 1 << 30


@dataclass(frozen=True)
class BiquadCoef:
    """``b0, b1, b2, a1, a2`` in Q28 (``a0`` = 1)."""

    b0: int
    b1: int
    b2: int
    a1: int
    a2: int


@dataclass(frozen=True, slots=True)
class BiquadState:
    """Last two inputs (current LSB) and outputs (Q ``Y_FRAC``)."""

    x1: int = 0
    x2: int = 0
    y1: int = 0
    y2: int = 0


def biquad_step(s: BiquadState, x: int, c: BiquadCoef) -> BiquadState:
    """One period; the new output is the returned state's ``y1``.

    C: ``int64_t acc = (int64_t)b0 * ((int64_t)x << Y) + ... - (int64_t)a1 * y1 - (int64_t)a2 * y2;``
    with the shifts of the inputs as products by ``1 << Y_FRAC`` (a left shift of a negative is undefined),
    ``y = sat32((acc + (1 << 27)) >> 28)``."""
    f = 1 << Y_FRAC
    acc = c.b0 * (x * f) + c.b1 * (s.x1 * f) + c.b2 * (s.x2 * f) - c.a1 * s.y1 - c.a2 * s.y2
    y = sat(round_shr(acc, COEF_FRAC), 32)
    return BiquadState(x, s.x1, y, s.y1)


def _quantise(b: tuple[float, float, float], a: tuple[float, float, float]) -> BiquadCoef:
    vals = [v / a[0] for v in (*b, a[1], a[2])]
    q = [to_fixed(v, COEF_FRAC) for v in vals]
    if any(abs(v) >= _COEF_LIMIT for v in q):
        raise ValueError(f"biquad coefficients {vals} outside +-4")
    return BiquadCoef(*q)


def _prewarp(f0: float, bw: float, f_s: float) -> tuple[float, float, float]:
    if not (f_s > 0 and 0 < f0 < f_s / 2 and bw > 0):
        raise ValueError(f"filter centre {f0} Hz must lie in 0..{f_s / 2} Hz (f_s = {f_s} Hz) "
                         f"and its bandwidth {bw} Hz must be positive")
    w0, wg = 2 * math.pi * f0, 2 * math.pi * bw
    k = w0 / math.tan(w0 / (2 * f_s))
    return w0, wg, k


def bandpass(f0: float, bw: float, f_s: float) -> BiquadCoef:
    """Tap et al. 2023, eq. (13): ``G(s) = w_g s / (s^2 + w_g s + w_0^2)`` (centre ``f0``, -3 dB
    bandwidth ``bw``), bilinear with ``s = k (z - 1)/(z + 1)``, ``k = w_0 / tan(w_0 T / 2)``."""
    w0, wg, k = _prewarp(f0, bw, f_s)
    c = _quantise((wg * k, 0.0, -wg * k), (k * k + wg * k + w0 * w0, 2 * (w0 * w0 - k * k),
                                           k * k - wg * k + w0 * w0))
    if c.b0 == 0:
        raise ValueError(f"a band-pass of {bw:g} Hz at {f0:g} Hz is narrower than its coefficients resolve "
                         f"(2^-{COEF_FRAC} at f_s = {f_s:g} Hz): its gain rounds to 0")
    return c


def notch(f0: float, bw: float, f_s: float) -> BiquadCoef:
    """The notch of the current feedback (Tap et al. 2023, Sec. II-C, Fig. 7): ``(s^2 + w_0^2) /
    (s^2 + w_b s + w_0^2)`` (= 1 - band-pass), stop band ``bw``, prewarped at ``f0``."""
    w0, wb, k = _prewarp(f0, bw, f_s)
    num = k * k + w0 * w0
    return _quantise((num, 2 * (w0 * w0 - k * k), num), (k * k + wb * k + w0 * w0, 2 * (w0 * w0 - k * k),
                                                         k * k - wb * k + w0 * w0))


def response(c: BiquadCoef, f: float, f_s: float) -> complex:
    """Frequency response of the quantised section at ``f`` [Hz] (host side: design and tests)."""
    z = complex(math.cos(2 * math.pi * f / f_s), -math.sin(2 * math.pi * f / f_s))  # z^-1
    s = 2.0 ** -COEF_FRAC
    return (c.b0 + c.b1 * z + c.b2 * z * z) * s / (1 + (c.a1 * z + c.a2 * z * z) * s)
