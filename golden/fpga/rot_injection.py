"""Rotating-injection phase generator, bit-true (docs/spec.md 3.5, ``CTRL.INJ_ROT``).

Tap et al. 2023, eq. (9): ``u_alpha_beta^hf = U_hf (cos(omega_hf t), sin(omega_hf t))`` in the stationary
frame. The hardware holds one phase per PWM period:

* a u32 phase accumulator ``P``, 0 after reset;
* at every window boundary, after the boundary's register updates: if the rotating injection is on
  (``CTRL.INJ_EN`` and ``CTRL.INJ_ROT``), the compare sets computed at this boundary use ``phi = P``
  and ``P`` becomes ``P + INJ_STEP`` (mod 2^32); otherwise they use no rotating term and ``P``
  becomes 0. At the next boundary ``INJ_PHASE`` latches ``phi`` (0 while off): read with the window
  results, it is the phase of the window that just ended (its last three quarters; the first quarter
  ran on the previous phase);
* the modulator adds ``V_H (C, S)`` with ``(S, C) = sincos_q15(phi)`` (the firmware's sin/cos, spec 5.2:
  WIDTH 32, 16 iterations) to ``(v_alpha, v_beta)`` of both halves (``golden.fpga.modulator.compares``).

One phase per period (not per half period): the injection is a staircase of ``2^32 / INJ_STEP`` steps
per turn, as an MCU that adds eq. (9) to its 10 kHz current-controller output makes it; the RTL then
computes one sin/cos per period, in the period before it is needed.
"""

from __future__ import annotations

from golden.fpga.cordic import sincos_q15

_U32 = 0xFFFFFFFF


def inj_step(f_inj: float, f_sw: float) -> int:
    """``INJ_STEP`` for an injection frequency ``f_inj`` [Hz] at the PWM frequency ``f_sw`` [Hz]:
    ``round(f_inj / f_sw * 2^32) mod 2^32`` (negative frequencies rotate backwards).

    Raises ValueError unless ``|f_inj| < f_sw / 2`` (at or above half the phase update rate the
    staircase no longer rotates the way ``f_inj`` says)."""
    if not f_sw > 0:
        raise ValueError(f"f_sw must be positive, got {f_sw!r}")
    if not abs(f_inj) < f_sw / 2:
        raise ValueError(f"injection frequency {f_inj} Hz must be below f_sw / 2 = {f_sw / 2} Hz "
                         "(the phase advances once per PWM period)")
    return round(f_inj / f_sw * 2**32) & _U32


class RotatingInjection:
    """The phase accumulator ``P`` (0 after reset)."""

    def __init__(self) -> None:
        self.acc = 0

    def boundary(self, on: bool, step: int) -> tuple[int, tuple[int, int] | None]:
        """One window boundary: returns ``(phi, rot)`` with ``rot = (C, S)`` for
        ``compares(..., rot=rot)``, or ``(0, None)`` while the rotating injection is off (``phi`` is what
        ``INJ_PHASE`` reads after the window that starts here).
        ``step``: ``INJ_STEP`` (u32)."""
        if not 0 <= step <= _U32:
            raise ValueError(f"INJ_STEP = {step} is outside 0..2^32-1")
        if not on:
            self.acc = 0
            return 0, None
        phi = self.acc
        self.acc = (phi + step) & _U32
        s, c = sincos_q15(phi)
        return phi, (c, s)
