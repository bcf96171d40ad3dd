"""PI controller with conditional-integration anti-windup (docs/spec.md 5.2): speed and both currents.

Per call, in this order (the C must keep it; ``clamp(x, lo, hi) = min(max(x, lo), hi)``):

1. ``e    = sat(ref - meas, 32)``                                 error, s32
2. ``prop = shr(kp * e, sp)``                                     proportional term, int64
3. ``cand = clamp(integ + ki * e, -(limit << si), limit << si)``  candidate integrator, Q``si``, int64
4. ``u_unclamped = prop + shr(cand, si)``                         int64
5. if ``u_unclamped > limit and e > 0`` or ``u_unclamped < -limit and e < 0``:
   ``integ_new = integ`` (frozen: do not integrate further into saturation);
   else ``integ_new = cand``
6. ``u = clamp(prop + shr(integ_new, si), -limit, limit)``        output, s32, |u| <= limit

The integrator therefore stops as soon as integrating would push the output further into the limit, and
it integrates again as soon as the error reverses sign (or the output is back inside the limit): the
output leaves the limit the period the error changes sign, without first unwinding a stored excess.

C ranges (``int32_t kp, ki, limit; int64_t integ``; 0 <= kp, ki, limit <= 2^31 - 1; sp, si 0..31;
|integ| <= limit << si < 2^62 if it starts there): ``ref - meas`` in int64 then clamped to s32;
``(int64_t)kp * e`` and ``(int64_t)ki * e`` < 2^62; ``integ + ki e`` < 2^63; ``(int64_t)limit << si``
< 2^62; every sum below stays < 2^63. No overflow anywhere; right shifts arithmetic (GCC).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from golden.fixed import sat, shr, to_fixed

_S32_MAX = (1 << 31) - 1


@dataclass(slots=True, frozen=True)
class PiParams:
    """PI parameters: ``kp`` (Q``sp``) and ``ki`` (Q``si``) gains in output LSB per input LSB
    (``ki`` per call), ints 0..2^31-1; ``sp``, ``si`` shift counts 0..31; ``limit`` the symmetric
    output limit, 1..2^31-1. Raises ValueError otherwise. ``lim_i = limit << si`` is derived."""

    kp: int
    sp: int
    ki: int
    si: int
    limit: int
    lim_i: int = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        for name in ("kp", "sp", "ki", "si", "limit"):
            v = getattr(self, name)
            if not isinstance(v, int) or isinstance(v, bool):
                raise ValueError(f"{name} must be an int, got {v!r}")
        if not 0 <= self.kp <= _S32_MAX:
            raise ValueError(f"kp {self.kp} out of range 0..2^31-1")
        if not 0 <= self.ki <= _S32_MAX:
            raise ValueError(f"ki {self.ki} out of range 0..2^31-1")
        if not 0 <= self.sp <= 31:
            raise ValueError(f"sp {self.sp} out of range 0..31")
        if not 0 <= self.si <= 31:
            raise ValueError(f"si {self.si} out of range 0..31")
        if not 1 <= self.limit <= _S32_MAX:
            raise ValueError(f"limit {self.limit} out of range 1..2^31-1")
        object.__setattr__(self, "lim_i", self.limit << self.si)


def pi_step(integ: int, ref: int, meas: int, p: PiParams) -> tuple[int, int]:
    """One PI call: returns ``(u, integ_new)``; see the module docstring for the exact order.

    ``integ`` int64 Q``si`` state (|integ| <= limit << si), ``ref``, ``meas`` s32, ``u`` s32 with
    |u| <= limit.
    """
    e = sat(ref - meas, 32)
    prop = shr(p.kp * e, p.sp)
    lim_i = p.lim_i                      # >= 0, so clamp(x, -lim_i, lim_i) is the two tests below
    cand = integ + p.ki * e
    if cand > lim_i:
        cand = lim_i
    elif cand < -lim_i:
        cand = -lim_i
    si = p.si
    u_unclamped = prop + shr(cand, si)
    limit = p.limit
    if (u_unclamped > limit and e > 0) or (u_unclamped < -limit and e < 0):
        integ_new = integ
    else:
        integ_new = cand
    u = prop + shr(integ_new, si)
    if u > limit:
        u = limit
    elif u < -limit:
        u = -limit
    return u, integ_new


def pi_gains(kp_phys: float, ki_phys: float, out_per_in: float, f_sw: float,
             sp: int = 16, si: int = 16) -> tuple[int, int]:
    """Host-side: ``kp = to_fixed(kp_phys * out_per_in, sp)``, ``ki = to_fixed(ki_phys * out_per_in / f_sw, si)``.

    ``kp_phys`` (output unit per input unit) and ``ki_phys`` (the same per second) are the physical
    gains of ``u = kp_phys e + ki_phys int e dt``; the PI runs at ``f_sw``. ``out_per_in`` converts
    them to output LSB per input LSB: (physical value of one input LSB) / (physical value of one
    output LSB). Example, current loop (input i_d or i_q: 1 LSB = I_FS / 2^15 = 12.5 A / 32768;
    output V_D or V_Q: 1 LSB = V_dc / 2^15 = 560 V / 32768): out_per_in = 12.5 / 560, and
    kp_phys = 10 V/A gives kp = to_fixed(10 * 12.5 / 560, 16) = 14629 (0.2232 V LSB per A LSB).
    Raises ValueError if a result is outside 0..2^31-1 or f_sw <= 0.
    """
    if not f_sw > 0:
        raise ValueError(f"f_sw {f_sw} must be > 0")
    kp = to_fixed(kp_phys * out_per_in, sp)
    ki = to_fixed(ki_phys * out_per_in / f_sw, si)
    for name, v in (("kp", kp), ("ki", ki)):
        if not 0 <= v <= _S32_MAX:
            raise ValueError(f"{name} {v} out of range 0..2^31-1")
    return kp, ki
