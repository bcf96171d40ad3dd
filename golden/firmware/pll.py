"""Type-2 PLL on the bang-bang angle (docs/spec.md 5.2): smooths theta_hat and yields the speed.

Per PWM period, in this order (the C must keep it):

1. ``e     = wrap(theta_hat - theta, 32)``            angle error, s32 (shortest way round)
2. ``integ = sat(integ + ki * e, 64)``                integrator, Q24 binary angle per period, int64
3. ``omega = sat(shr(kp * e, 16) + shr(integ, 24), 32)``  speed, s32 binary angle per period
4. ``theta = uwrap(theta + omega, 32)``               u32 binary angle

so the omega of step 3 already contains this period's integration, and theta is advanced by it for the
next period. With Kp = kp/2^16 and Ki = ki/2^24 this is the discrete form of ``omega = k_p e + k_i
int e``, ``d theta/dt = omega`` (KP = k_p T, KI = k_i T^2): zero steady-state error to a constant-speed
ramp, where integ settles so that shr(integ, 24) equals the speed.
"""

from __future__ import annotations

from dataclasses import dataclass

from golden.fixed import sat, shr, to_fixed, uwrap, wrap

_S32_MAX = (1 << 31) - 1


@dataclass(slots=True)
class PllState:
    """PLL state: ``theta`` u32 binary angle, ``integ`` int64 Q24 (angle per period), ``omega`` s32
    (binary angle per period; the output of the last step, 1 LSB = f_sw * 2 pi / 2^32 rad/s)."""

    theta: int = 0
    integ: int = 0
    omega: int = 0


def pll_step(state: PllState, theta_hat: int, kp: int, ki: int) -> PllState:
    """One PLL period; returns a new state (``state`` is not modified).

    ``theta_hat`` u32, ``kp`` Q16 and ``ki`` Q24 gains in 0..2^31-1 (from :func:`pll_gains`).

    C (``uint32_t theta, theta_hat; int64_t integ; int32_t omega, e; int32_t kp, ki``):

    * ``e = (int32_t)(theta_hat - theta);``
    * ``p = (int64_t)ki * e`` (|p| < 2^62), then the **saturating** int64 add
      ``integ = sat(integ + p, 64)`` (e.g. ``__builtin_add_overflow`` and INT64_MAX/INT64_MIN on
      overflow; a plain add is undefined behaviour on overflow);
    * ``s = (((int64_t)kp * e) >> 16) + (integ >> 24)`` (|s| < 2^47 + 2^39, no overflow), then
      ``omega = s > INT32_MAX ? INT32_MAX : s < INT32_MIN ? INT32_MIN : (int32_t)s;``
    * ``theta += (uint32_t)omega;`` (wrapping unsigned add).
    """
    theta = state.theta
    e = wrap(theta_hat - theta, 32)
    integ = sat(state.integ + ki * e, 64)
    omega = sat(shr(kp * e, 16) + shr(integ, 24), 32)
    return PllState(uwrap(theta + omega, 32), integ, omega)


def pll_gains(k_p: float, k_i: float, f_sw: float) -> tuple[int, int]:
    """Host-side: ``(kp, ki) = (to_fixed(k_p T, 16), to_fixed(k_i T^2, 24))``, T = 1/f_sw.

    ``k_p`` in 1/s, ``k_i`` in 1/s^2 (continuous loop omega = k_p e + k_i int e). The paper's
    (Table II) k_p = 200, k_i = 10000 at 5 kHz give (2621, 6711).
    Raises ValueError unless both are in 0..2^31-1 (the range the C products assume).
    """
    if not f_sw > 0:
        raise ValueError(f"f_sw {f_sw} must be > 0")
    t = 1.0 / f_sw
    kp = to_fixed(k_p * t, 16)
    ki = to_fixed(k_i * t * t, 24)
    for name, v in (("kp", kp), ("ki", ki)):
        if not 0 <= v <= _S32_MAX:
            raise ValueError(f"{name} {v} out of range 0..2^31-1")
    return kp, ki
