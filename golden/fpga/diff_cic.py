"""Sample differencing, envelope by sample-rate conversion and CIC interpolation, bit-true (docs/spec.md
3.9; Xue et al. 2022, Sec. 3.1-3.2, eqs. (7)-(8), Figs. 3, 4 and 8).

The 001 method injects a square wave on the estimated d-axis whose sign holds for a whole PWM period and
flips at every carrier bottom (``CTRL.INJ_PER``, a square wave at f_sw / 2, eq. (3)). The HF current is
then a triangle with its vertices at the carrier bottoms, where the PWM ripple is zero too. Once per
PWM period the block takes the stationary-frame current of the sample at the carrier bottom (``phi = 0``,
which every ADC mode samples) and:

1. **rate** (``CIC_M``, clamped to 1..``M_MAX``): if it differs from the one in use, the delay line and
   the integrators are cleared and it becomes the one in use (a rate change restarts the filter);
2. **difference** (eq. (7), without its factor 1/2): ``d = i - p`` per component (s17), ``p`` the
   previous bottom sample; it is the change of the current over the period that just ended, in which the
   injection was ``+V_H`` or ``-V_H`` on d-hat and the fundamental changed little;
3. **envelope** (Fig. 4, the sample-rate conversion R = 1/2): only the differences across a period with
   ``+V_H`` (``plus``) are kept: ``e = d`` then, else ``e`` holds. So ``e`` is the position quadrature
   signal of eq. (6) at f_sw / 2, held for two periods. Pairing the difference with the injection's sign
   is what makes the loop lock at theta and not a quarter turn off; the first sample after reset only
   fills ``p``;
4. **CIC interpolation** (eq. (8), one stage, on the held envelope at the PWM rate: the equivalent form
   of Fig. 8): comb ``c = e - x[M-1]`` with the delay line ``x`` (``x[0]`` the newest), then ``x``
   shifts in ``e`` and the integrator ``y = wrap(y + c, Y_BITS)``. The output ``q = y`` is the sum of the
   last ``M`` held values (gain ``M``): with ``M = 2`` a linear interpolation between the envelope's
   samples, one period late (a zero-stuffed input would give a zero-order hold instead).

The integrator is a ``Y_BITS`` two's-complement accumulator, as a CIC's is; here, with the comb first and
both cleared together, it always holds the exact sum of the last ``M`` held values (the entries before a
reset or a rate change count as 0), at most ``M_MAX (2^16 - 1) < 2^20``: it never wraps. A rate change
keeps ``p`` and ``e``. At the window boundary the window results latch ``CIC_QA, CIC_QB = q`` and
``ENV_A, ENV_B = e`` (each sign-extended to 32 bits).
"""

from __future__ import annotations

from golden.fixed import wrap
from golden.fpga.checks import int_param

M_MAX = 16
"""Largest comb delay (the delay line's length); ``CIC_M`` above it is used as ``M_MAX``, 0 as 1."""
D_BITS = 17
"""Width of a difference and of the held envelope (the difference of two s16 samples)."""
Y_BITS = 21
"""Width of the integrator: the sum of ``M_MAX`` values of ``D_BITS`` bits fits."""

_S16_MIN, _S16_MAX = -(1 << 15), (1 << 15) - 1


def cic_m(reg: int) -> int:
    """The comb delay in use for a ``CIC_M`` register value (u8): 0 as 1, above ``M_MAX`` as ``M_MAX``."""
    reg = int_param(reg, 0, 255, "CIC_M (u8)")
    return min(max(reg, 1), M_MAX)


class DiffCic:
    """The block's state after reset: no previous sample, everything 0, no comb delay in use."""

    def __init__(self) -> None:
        self.valid = False
        self.p = [0, 0]
        self.e = [0, 0]
        self.x = [[0] * M_MAX, [0] * M_MAX]
        self.y = [0, 0]
        self.m = 0

    def step(self, i_alpha: int, i_beta: int, plus: bool, cic_m_reg: int) -> tuple[int, int, int, int]:
        """One carrier-bottom sample: returns ``(q_a, q_b, e_a, e_b)``.

        ``i_alpha, i_beta``: s16 current of the sample (spec 3.2); ``plus``: the period that ended at this
        sample ran the period square wave with ``+V_H``; ``cic_m_reg``: the ``CIC_M`` register (u8).
        Raises ValueError on a current outside s16 or a register outside u8."""
        m = cic_m(cic_m_reg)
        i_alpha = int_param(i_alpha, _S16_MIN, _S16_MAX, "i_alpha (s16)")
        i_beta = int_param(i_beta, _S16_MIN, _S16_MAX, "i_beta (s16)")
        if m != self.m:                                   # 1. a rate change restarts the filter
            self.m = m
            self.x = [[0] * M_MAX, [0] * M_MAX]
            self.y = [0, 0]
        for k, i in enumerate((i_alpha, i_beta)):
            if self.valid and plus:                       # 2., 3. eq. (7) across a + period, held
                self.e[k] = i - self.p[k]
            self.p[k] = i
            x = self.x[k]                                 # 4. eq. (8): comb, then integrator
            c = self.e[k] - x[m - 1]
            x.insert(0, self.e[k])
            x.pop()
            self.y[k] = wrap(self.y[k] + c, Y_BITS)
        self.valid = True
        return self.y[0], self.y[1], self.e[0], self.e[1]
