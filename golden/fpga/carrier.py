"""Up/down PWM carrier: counter, periods, integration windows and injection sign, in clock ticks.

docs/spec.md, section 2.1 (Benevieri et al. 2023, Sec. II-B, eqs. (14)-(15)). One tick is one FPGA
clock. ``H = PWM_HALF`` is the carrier half period and ``P = 2H`` the PWM period. Period ``k`` starts
at tick ``k*P`` at the carrier bottom; within a period the phase is ``phi = t mod P`` and the counter is
``c = phi`` on the rising half (``phi < H``) and ``c = P - phi`` on the falling half, so ``c`` runs
0 -> H -> 0 (the convention of ``golden/openloop.py``). The normalised carrier is ``cw = 2c/H - 1``.

Integration window ``k`` starts at the carrier rising zero crossing of period ``k``
(``phi = H/2``, the cw interrupt) and holds the instants ``[k*P + H/2, (k+1)*P + H/2)``.

Every function takes the *effective* half period (even, 4..65534); :func:`effective_half` turns a
``PWM_HALF`` register value into it. Ticks and phases are Python ints or int64 numpy arrays.
"""

from __future__ import annotations

import numpy as np

U16_MAX = 0xFFFF
HALF_MIN = 4
"""Smallest half period [ticks] the carrier functions accept (the arithmetic's domain)."""
REGISTER_HALF_MIN = 512
"""Smallest carrier half period [ticks] the hardware runs (``PWM_HALF`` below it is raised to it):
the RTL needs a period longer than its sample pipeline and ``IRQ_LATENCY`` (docs/rtl.md)."""


def effective_half(pwm_half_register: int) -> int:
    """The carrier half period the hardware uses for a ``PWM_HALF`` register value (spec 2.1).

    ``H`` must be even and at least 4. The hardware's safe behaviour for a bad register value is to
    clear its LSB (an odd value ``2n+1`` runs as ``2n``) and to use ``REGISTER_HALF_MIN`` (512) for
    anything smaller, so the carrier always has an integer quarter point ``H/2`` and a period longer
    than the RTL's sample pipeline and interrupt latency.

    Parameters
    ----------
    pwm_half_register : int
        ``PWM_HALF`` register value, u16 (0..65535).

    Returns
    -------
    int
        Effective half period ``H``: even, 512..65534.

    Raises
    ------
    ValueError
        If the value is not an integer in 0..65535 (not representable in the u16 register).
    """
    reg = _as_int(pwm_half_register, "PWM_HALF")
    if not 0 <= reg <= U16_MAX:
        raise ValueError(f"PWM_HALF = {reg} is not a u16 register value (0..65535)")
    return max(reg & ~1, REGISTER_HALF_MIN)


def check_half(half: int) -> int:
    """Validate an effective half period (even, 4..65534) and return it as an int.

    Raises
    ------
    ValueError
        If ``half`` is odd, below 4 or above 65534 (use :func:`effective_half` on register values).
    """
    h = _as_int(half, "half period")
    if not HALF_MIN <= h <= U16_MAX or h & 1:
        raise ValueError(f"half period {h} must be even and in {HALF_MIN}..{U16_MAX - 1} ticks "
                         "(use effective_half() on a PWM_HALF register value)")
    return h


def counter(phase, half: int):
    """Carrier counter ``c`` at a phase within the period (spec 2.1).

    ``c = phi`` on the rising half (``phi < H``), ``c = P - phi`` on the falling half; ``c = 0`` at the
    bottom (``phi = 0``) and ``c = H`` at the top (``phi = H``). The normalised carrier of Benevieri
    et al. 2023, eq. (15), is ``cw = 2c/H - 1``.

    Parameters
    ----------
    phase : int or ndarray of int64
        Phase ``phi`` in ``[0, 2H)`` [ticks] (see :func:`phase_of`).
    half : int
        Effective half period ``H`` [ticks].

    Returns
    -------
    int or ndarray of int64
        Counter value in ``0..H``, same kind as ``phase``.

    Raises
    ------
    ValueError
        If a phase lies outside ``[0, 2H)`` or ``half`` is not a valid half period.
    """
    h = check_half(half)
    period = 2 * h
    if isinstance(phase, np.ndarray):
        if phase.dtype.kind not in "iu":
            raise ValueError(f"phases must be integers, got dtype {phase.dtype}")
        ph = phase.astype(np.int64)
        if ph.size and (ph.min() < 0 or ph.max() >= period):
            raise ValueError(f"phases must lie in [0, {period}), got {ph.min()}..{ph.max()}")
        return np.where(ph < h, ph, period - ph)
    ph = _as_int(phase, "phase")
    if not 0 <= ph < period:
        raise ValueError(f"phase {ph} must lie in [0, {period})")
    return ph if ph < h else period - ph


def phase_of(tick, half: int):
    """Phase ``phi = t mod P`` of a tick within its period, in ``[0, 2H)`` (also for negative ticks)."""
    return tick % (2 * check_half(half))


def period_start(k, half: int):
    """First tick of period ``k``: ``k*P``, the carrier bottom."""
    return k * (2 * check_half(half))


def window_start(k, half: int):
    """First tick of integration window ``k``: ``k*P + H/2``, the carrier rising zero crossing.

    This is the window boundary / cw interrupt of spec 2.1 (Benevieri et al. 2023, Sec. II-B: the
    integrator is reset on the rising zero crossing of the carrier).
    """
    h = check_half(half)
    return k * (2 * h) + h // 2


def window_of(tick, half: int):
    """Index of the integration window holding ``tick``: ``floor((t - H/2) / P)``.

    Window ``k`` holds ``[window_start(k), window_start(k + 1))``; ticks before ``H/2`` belong to
    window -1.
    """
    h = check_half(half)
    return (tick - h // 2) // (2 * h)


def injection_sign(rising: bool) -> int:
    """Sign of the d-axis injection ``v_dh = V_h * -sign(d cw/dt)`` for a carrier half.

    Benevieri et al. 2023, eq. (14); spec 2.1: -1 on the rising half (compares latched at the bottom),
    +1 on the falling half (compares latched at the top).
    """
    return -1 if rising else 1


def _as_int(value, name: str) -> int:
    """``value`` as a Python int; ValueError for non-integers (bools, floats, strings)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{name} must be an integer, got {value!r}")
    return int(value)
