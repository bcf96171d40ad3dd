"""Per-window means of the demodulator sums (docs/spec.md 5.2): ``i = c_div(SUM, N)``, 0 if N == 0."""

from __future__ import annotations

from golden.fixed import c_div


def window_means(sum_id: int, sum_iq: int, n: int) -> tuple[int, int]:
    """``(c_div(sum_id, n), c_div(sum_iq, n))``, or ``(0, 0)`` if ``n == 0``.

    ``sum_id``, ``sum_iq`` s32 (``SUM_ID``, ``SUM_IQ``), ``n`` u16 (``N_SAMPLES``). The quotients
    truncate toward zero (C ``/``) and fit s32 (|sum / n| <= |sum|); they are s16 whenever the sums are
    not saturated (each sample is s16).

    C: ``int32_t n32 = n; i_d = n32 ? sum_id / n32 : 0; i_q = n32 ? sum_iq / n32 : 0;`` (RV32IM ``div``;
    n is never negative, so INT32_MIN / -1 cannot occur).
    """
    if n == 0:
        return 0, 0
    return c_div(sum_id, n), c_div(sum_iq, n)
