"""Test vectors of the carrier (golden/fpga/carrier.py), shared by cocotb_tests/tb_carrier.py and
tests/test_hls_carrier.py: ``PWM_HALF`` / ``CW_ANGLE_STEP`` register draws and directed values."""

from __future__ import annotations

import numpy as np

from golden.fpga.carrier import effective_half
from golden.fpga.cordic import cw_angle_step

DIRECTED_HALF_REGS = (0, 1, 2, 510, 511, 512, 513, 514, 515, 1000, 10000, 10001, 32767, 32768, 65533, 65534, 65535)
"""``PWM_HALF`` values at the edges of effective_half (the 512 floor, odd values, full scale)."""


def random_half_reg(rng: np.random.Generator) -> int:
    """A ``PWM_HALF`` register value: mostly 512..1399 (short periods), 10 % below the 512 floor, 5 %
    right at it; odd values (run with the LSB cleared) as often as even ones."""
    r = rng.random()
    if r < 0.1:
        return int(rng.integers(0, 512))          # below the floor: runs as 512
    if r < 0.15:
        return int(rng.choice([511, 512, 513, 514]))
    return int(rng.integers(512, 1400))


def random_step(rng: np.random.Generator, pwm_half: int) -> int:
    """A ``CW_ANGLE_STEP`` register value: the nominal step of ``pwm_half`` (40 %), an extreme (10 %),
    any u32 (50 %)."""
    r = rng.random()
    if r < 0.4:
        return cw_angle_step(effective_half(pwm_half))
    if r < 0.5:
        return int(rng.choice([0, 1, 0xFFFFFFFF, 0x80000000, 0x7FFFFFFF]))
    return int(rng.integers(0, 1 << 32))
