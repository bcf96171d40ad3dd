"""First-order speed filter (docs/spec.md 5.2): ``F += ((x << 16) - F) * A / 2^16`` (floored).

State ``F`` is the filtered value in Q16 (int64); the output is ``shr(F, 16)``. ``A`` (Q16, 0..65536)
is ``1 - exp(-2 pi f_c T)``, so the step response is ``1 - (1 - A/2^16)^n`` up to the flooring (which
makes F lag the exact response by less than 2^16/A Q16 LSB, i.e. less than 1/A output LSB).
"""

from __future__ import annotations

import math

from golden.fixed import shr, to_fixed


def lowpass_step(F: int, x: int, a: int) -> int:
    """One filter period: returns ``F + shr(((x << 16) - F) * a, 16)``.

    ``F`` int64 Q16 state with shr(F, 16) in the s32 range, ``x`` s32 input, ``a`` Q16 in 0..65536.
    The new F stays between F and x << 16 (so in the same range).

    C: the product ``d * a`` with ``d = (int64_t)x * 65536 - F`` can reach 2^48 * 2^16 = 2^64 and
    overflow int64, so the C must form it split (exactly equal for every integer d, since
    d = q 2^16 + r with 0 <= r < 2^16 gives floor(d a / 2^16) = q a + floor(r a / 2^16)):

        int64_t d = (int64_t)x * 65536 - F;        // |d| < 2^48 ((int64_t)x << 16 is UB for x < 0)
        int64_t q = d >> 16;                       // arithmetic shift (GCC), |q| <= 2^32
        int64_t r = d & 0xFFFF;                    // 0 <= r < 2^16
        F += q * a + ((r * a) >> 16);              // |q a| <= 2^48, r a < 2^32

    (``a`` as int32_t.) The plain ``(d * a) >> 16`` is identical only while |d| * a < 2^63.
    """
    return F + shr(((x << 16) - F) * a, 16)


def lowpass_out(F: int) -> int:
    """Filter output ``shr(F, 16)`` (s32). C: ``(int32_t)(F >> 16)``."""
    return shr(F, 16)


def lowpass_coef(f_c: float, f_sw: float) -> int:
    """Host-side: ``A = to_fixed(1 - exp(-2 pi f_c / f_sw), 16)`` (Q16; 30 Hz at 5 kHz gives 2425).

    Raises ValueError unless f_c >= 0 and f_sw > 0.
    """
    if not f_sw > 0 or not f_c >= 0:
        raise ValueError(f"need f_c >= 0 and f_sw > 0 (got {f_c}, {f_sw})")
    return to_fixed(1.0 - math.exp(-2.0 * math.pi * f_c / f_sw), 16)
