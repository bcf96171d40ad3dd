"""Load-torque observer of the speed loop: the integral action of a P speed controller, from the motion
equation. A shared supervisor block (``control.load_observer``), any method; C twin ``fw_lobs_step`` in
``firmware/src/control.c``.

The rotor obeys ``J d omega/dt = K_t i - T_L``. A second-order Luenberger observer on the filtered speed
estimate ``omega`` (binary angle per period, the speed PI's own input) with the current command ``i_cmd``
(current LSB, the command of the step before) estimates the load as a current ``i_l = T_L / K_t``; the speed
controller adds it to its proportional output (its integral gain is 0 when the observer is on). Once per
speed-loop step:

* ``e = sat(omega - shr(w, 16), 32)``
* ``w = sat(w + g sat(i_cmd - shr(i_l, 32), 32) + shr(l1 e, 8), 64)``    (``w``: the observer's speed, Q16)
* ``i_l = clamp(i_l - shr(l2g e, 8), -(limit << 32), limit << 32)``   (Q32 current LSB; ``limit``: the speed
  PI's)
* output ``shr(i_l, 32)``

with ``g`` the speed change per current LSB in one speed-loop step (Q16), and the two poles at ``-w_o``
(``w_o = 2 pi load_observer``): ``l1 = 2 w_o T_s`` (Q24), ``l2g = (w_o T_s)^2 / g`` (Q40). A load step is
answered at the observer's bandwidth whatever the speed loop's; after it the speed returns without the slow
tail of a PI whose integral zero sits a quarter of the crossover below it (docs/methods.md: the 003 torque
step, the Table III load steps). Host side: ``golden.control_config.load_observer_params``.
"""

from __future__ import annotations

from dataclasses import dataclass

from golden.fixed import sat, shr

W_FRAC, I_FRAC = 16, 32
"""Fraction bits of the observer's speed ``w`` and load current ``i_l``."""


@dataclass(frozen=True)
class LoadObsParams:
    """``g`` Q16 (0 < g < 2^31; 0: the observer is off), ``l1`` Q24 (0 <= l1 < 2^31), ``l2g`` Q40
    (0 <= l2g < 2^31): module docstring."""

    g: int = 0
    l1: int = 0
    l2g: int = 0


def load_obs_step(w: int, i_l: int, omega: int, i_cmd: int, p: LoadObsParams, limit: int) -> tuple[int, int]:
    """One speed-loop step: ``(w, i_l)`` from the filtered speed ``omega`` and the last current command
    ``i_cmd`` (s32), with the speed PI's ``limit`` (0..2^31-1; |i_l| <= limit << 32 on entry)."""
    e = sat(omega - shr(w, W_FRAC), 32)
    w = sat(w + p.g * sat(i_cmd - shr(i_l, I_FRAC), 32) + shr(p.l1 * e, 8), 64)
    lim = limit << I_FRAC
    i_l = min(max(i_l - shr(p.l2g * e, 8), -lim), lim)
    return w, i_l
