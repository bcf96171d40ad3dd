"""Test vectors of the ADC trigger (golden/fpga/adc_trigger.py), shared by cocotb_tests/tb_adc_trigger.py
and tests/test_hls_adc_trigger.py: register draws, switch-event pulses and the ``OS_MIN`` sweep."""

from __future__ import annotations

import numpy as np

OS_MIN_SWEEP = (40, 7)
"""``OS_MIN`` synthesis parameters of the RTL sweep (cocotb_tests/test_adc_trigger.py): the default
(32 CORDIC iterations + 8) and a small value (many samples per period)."""


def random_half_reg(rng: np.random.Generator) -> int:
    """``PWM_HALF`` of one run: mostly short periods (512..699), sometimes anything in 0..1599."""
    return int(rng.integers(512, 700)) if rng.random() < 0.8 else int(rng.integers(0, 1600))


def random_os(rng: np.random.Generator, os_min: int, h: int) -> int:
    """An ``OS_TICKS`` register value for half period ``h``: 0, at or below ``OS_MIN`` (runs as
    ``OS_MIN``), 1..2 samples per period, a divisor of 2H, or mostly not dividing 2H."""
    r = rng.random()
    if r < 0.1:
        return 0
    if r < 0.2:
        return int(rng.integers(1, os_min + 1))          # below / at OS_MIN: runs as OS_MIN
    if r < 0.25:
        return min(int(rng.choice([2 * h - os_min, 2 * h - os_min + 1, 2 * h, 65535])), 65535)  # 1..2 samples
    if r < 0.35:
        return int(rng.choice([d for d in range(os_min, 400) if (2 * h) % d == 0] or [os_min]))
    return int(rng.integers(os_min, 200))                # mostly not dividing P


def random_blank(rng: np.random.Generator, h: int) -> int:
    """A ``BLANK_TICKS`` register value: 0 (nothing dropped), 1, 2, 65535, or 1..H-1."""
    r = rng.random()
    if r < 0.1:
        return 0
    if r < 0.15:
        return int(rng.choice([1, 2, 65535]))
    return int(rng.integers(1, h))


def random_switch_pulses(rng: np.random.Generator, h: int, end: int) -> list[tuple[int, int]]:
    """Switch events in ticks ``[0, end - 4)``: ``(first tick, length)`` pulses of 1..3 consecutive
    event ticks, exponentially spaced (mean ``h/3``)."""
    pulses = []
    t = int(rng.integers(0, 50))
    while t < end - 4:
        n = int(rng.integers(1, 4))
        pulses.append((t, n))
        t += n + int(rng.exponential(h / 3)) + 1
    return pulses
