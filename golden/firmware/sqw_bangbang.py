"""Estimator ``sqw_bangbang``: the 002 method's angle estimator (Benevieri et al. 2023, Sec. II-B, Fig. 1).

The FPGA injects the square wave +-V_h on the estimated d-axis at the switching frequency and
demodulates i_q_hat into gamma (eq. (19)); here, once per period: the bang-bang step on gamma,
integrated to the angle, and the type-2 PLL on that angle for the speed (docs/spec.md 5.2).

* with the cross-saturation table (``xs_gamma``, off when empty): ``gamma = sat(gamma - sign(i_q) g0, 32)``,
  ``g0`` the table's value at ``|i_q|`` (the window-mean q current in the estimated frame; the look-up and
  interpolation of :func:`golden.firmware.mtpa.mtpa_lookup` on its grid of step ``2^xs_shift``): the response
  across d_hat that the machine's cross-saturation gives *on* the d-axis, where the estimator should settle
  (docs/methods.md, "Cross-saturation");
* ``theta = bangbang_step(theta, gamma, k_bb)`` (:mod:`golden.firmware.bangbang`), then
  ``pll = pll_step(pll, theta, kp, ki)`` (:mod:`golden.firmware.pll`); outputs ``theta`` and ``pll.omega``.
* ``sync(theta, omega)`` (taking over from the high-speed slot): the angle becomes ``theta``, the PLL
  ``(uwrap(theta + omega), omega << 24, omega)`` (its prediction for the next step and its integrator at
  that speed), and for ``SYNC_HOLD`` steps gamma is ignored and the angle advances by the PLL speed: the
  injection written by the step of the hand-over is active only from the window after next, so the
  next window carries no HF response.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from golden.firmware.bangbang import bangbang_step
from golden.firmware.estimator import METHOD_SQW_BANGBANG, Estimator, Measurement
from golden.firmware.mtpa import check_odd_table, odd_lookup
from golden.firmware.pll import PllState, pll_step
from golden.fixed import sat, uwrap

SYNC_HOLD = 1
"""Steps after ``sync`` whose gamma is ignored (the window without injection)."""


@dataclass(frozen=True)
class SqwParams:
    """``k_bb`` bang-bang step [binary angle per period] (u32, < 2^31); ``pll_kp`` Q16, ``pll_ki`` Q24; ``i_d``
    the d-current it asks for while in charge [current LSB, <= 0]: 0 on a magnet motor, a magnetizing current on
    a reluctance machine, whose saliency appears only once its ribs saturate (docs/methods.md); ``xs_shift``,
    ``xs_gamma``: the cross-saturation table (0..20, 0 or 2..MTPA_LEN s16 values; empty: off) and ``xs_len``
    its length (derived)."""

    k_bb: int
    pll_kp: int
    pll_ki: int
    i_d: int = 0
    xs_shift: int = 0
    xs_gamma: tuple = ()
    xs_len: int = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        check_odd_table(self.xs_shift, self.xs_gamma, "the cross-saturation table")
        object.__setattr__(self, "xs_len", len(self.xs_gamma))


def cross_saturation_gamma(p: SqwParams, i_q: int) -> int:
    """``sign(i_q) g0(|i_q|)``: the table's response across d_hat at the q current ``i_q`` (s32), 0 without a table."""
    return odd_lookup(i_q, p.xs_shift, p.xs_gamma)


class SquareWaveBangBang(Estimator):
    """Bang-bang on gamma + PLL (see the module docstring)."""

    METHOD = METHOD_SQW_BANGBANG
    PARAMS = "sqw"

    def __init__(self, p: SqwParams):
        self.p = p
        self.theta = 0
        self.pll = PllState(0, 0, 0)
        self.omega = 0
        self.hold = 0
        self.i_d = p.i_d

    def step(self, m: Measurement) -> None:
        p = self.p
        if self.hold > 0:
            self.hold -= 1
            self.theta = uwrap(self.theta + self.pll.omega, 32)
        else:
            # Benevieri et al. 2023, Fig. 1: bang-bang on gamma, integrated to theta_hat; PLL -> speed
            gamma = sat(m.win.gamma - cross_saturation_gamma(p, m.i_q), 32)
            self.theta = bangbang_step(self.theta, gamma, p.k_bb)
        self.pll = pll_step(self.pll, self.theta, p.pll_kp, p.pll_ki)
        self.omega = self.pll.omega

    def turn(self, delta: int) -> None:
        self.turn_pll(delta)

    def sync(self, theta: int, omega: int) -> None:
        self.theta = theta
        self.pll = PllState(uwrap(theta + omega, 32), omega << 24, omega)
        self.omega = omega
        self.hold = SYNC_HOLD
