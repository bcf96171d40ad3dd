"""Input vectors of the differencing + envelope + CIC tests (golden.fpga.diff_cic.DiffCic, spec 3.9).

Used by cocotb_tests/tb_diff_cic.py (RTL, which adds the cycle timing and the resets). A step is a tuple
``(i_alpha, i_beta, plus, cic_m)`` of Python ints (``plus`` 0/1, ``cic_m`` the u8 CIC_M register), the
arguments of one ``DiffCic.step``.
"""

from __future__ import annotations

import numpy as np

EXTREMES = (-32768, -32767, -1, 0, 1, 32766, 32767)
S16_MIN, S16_MAX = -32768, 32767
RATE_SEQUENCE = (2, 5, 16, 1, 0, 255)
"""CIC_M values of the directed rate changes (clamped M 2, 5, 16, 1, 1, 16: 1 -> 0 is no change)."""


def _currents(rng: np.random.Generator, n: int) -> np.ndarray:
    """``n`` s16 samples of one component: uniform (40 %), the extremes -32768 / 32767 (20 %), any of
    :data:`EXTREMES` (10 %), otherwise a random walk of small steps (a real current's carrier ripple)."""
    walk = np.clip(np.cumsum(rng.integers(-600, 601, n)) + int(rng.integers(-20000, 20001)), S16_MIN, S16_MAX)
    x = walk.astype(np.int64)
    r = rng.random(n)
    uni = r < 0.4
    x[uni] = rng.integers(S16_MIN, S16_MAX + 1, uni.sum())
    ends = (r >= 0.4) & (r < 0.6)
    x[ends] = rng.choice(np.array([S16_MIN, S16_MAX]), ends.sum())
    ext = (r >= 0.6) & (r < 0.7)
    x[ext] = rng.choice(np.array(EXTREMES), ext.sum())
    return x


def _plus(rng: np.random.Generator, n: int) -> np.ndarray:
    """``plus`` flags: runs of the system's alternation (the period square wave, random phase), of random
    flags, of all 1 and of all 0."""
    out = np.zeros(n, dtype=np.int64)
    k = 0
    while k < n:
        length = min(n - k, int(rng.integers(1, 400)))
        mode = rng.choice(4, p=[0.6, 0.25, 0.1, 0.05])
        if mode == 0:
            out[k:k + length] = (np.arange(length) + int(rng.integers(0, 2))) % 2
        elif mode == 1:
            out[k:k + length] = rng.integers(0, 2, length)
        elif mode == 2:
            out[k:k + length] = 1
        k += length
    return out


def _cic_m(rng: np.random.Generator, n: int) -> np.ndarray:
    """The CIC_M register per step: mostly 2, changed at random steps to 2 (60 %), to any u8 value (28 %:
    mostly M clamped to 16) or to a value of 0, 1 and 14..20 (12 %: clamping edges, and writes that leave the
    clamped M unchanged: 0 <-> 1, 16 <-> 17..255). A 2 is changed about once in 150 steps, any other value
    once in 50, so that 2 holds about four fifths of the steps with a small spread even in the 10 000 steps of
    an Icarus run (with one rate for both, 2's share fell below 40 % for some seeds)."""
    out = np.empty(n, dtype=np.int64)
    reg = 2
    u = rng.random(n)
    for k in range(n):
        if u[k] < (1 / 150 if reg == 2 else 1 / 50):
            r = rng.random()
            if r < 0.6:
                reg = 2
            elif r < 0.88:
                reg = int(rng.integers(0, 256))
            else:
                reg = int(rng.choice(np.array([0, 1, 14, 15, 16, 17, 18, 20])))
        out[k] = reg
    return out


def random_steps(rng: np.random.Generator, n: int) -> list[tuple[int, int, int, int]]:
    """``n`` random steps: currents from :func:`_currents`, ``plus`` from :func:`_plus`, CIC_M from
    :func:`_cic_m`."""
    cols = [_currents(rng, n), _currents(rng, n), _plus(rng, n), _cic_m(rng, n)]
    return [tuple(r) for r in np.stack(cols, axis=1).tolist()]


def full_scale_runs(cic_m: int = 16, repeats: int = 6, hold: int = 40) -> list[tuple[int, int, int, int]]:
    """The largest integrator values and comb steps: ``repeats`` times, ``hold`` steps with the envelope at
    +65535 (alpha) / -65535 (beta) (the current alternating -32768 / 32767, plus only on the rising step),
    then ``hold`` steps with the signs swapped: q reaches +-M * 65535 (+-1048560 at M = 16, 16 LSB inside
    s21) and every comb output of a swing is +-131070 (s18 full scale)."""
    steps = []
    for _ in range(repeats):
        for up in (True, False):
            for k in range(2 * hold):
                rising = k % 2 == 1
                a = S16_MAX if rising == up else S16_MIN
                b = S16_MIN if rising == up else S16_MAX
                steps.append((a, b, int(rising), cic_m))
    return steps


def alternating_extremes(cic_m: int, n: int) -> list[tuple[int, int, int, int]]:
    """``n`` steps of the currents alternating -32768 / 32767 with plus = 1 on every step: the envelope
    alternates +-65535 (comb outputs +-131070 for an odd M)."""
    return [((S16_MIN, S16_MAX)[k % 2], (S16_MAX, S16_MIN)[k % 2], 1, cic_m) for k in range(n)]


def rate_changes(rng: np.random.Generator, per_rate: int = 24) -> list[tuple[int, int, int, int]]:
    """``per_rate`` steps at each CIC_M of :data:`RATE_SEQUENCE`, then at 17, 16, 3, 3 (again, after the
    same value: no restart), with alternating plus and full-range currents."""
    steps = []
    for reg in RATE_SEQUENCE + (17, 16, 3):
        a = _currents(rng, per_rate).tolist()
        b = _currents(rng, per_rate).tolist()
        steps += [(a[k], b[k], k % 2, reg) for k in range(per_rate)]
    return steps


def plus_zero_runs(rng: np.random.Generator, cic_m: int = 5, runs: int = 6, length: int = 30
                   ) -> list[tuple[int, int, int, int]]:
    """Runs of ``length`` steps with plus = 0 (the envelope holds, q settles at M * e), each after a few
    steps with plus = 1 that set a new envelope; random full-range currents."""
    steps = []
    for _ in range(runs):
        n_set = int(rng.integers(1, 4))
        a = _currents(rng, n_set + length).tolist()
        b = _currents(rng, n_set + length).tolist()
        steps += [(a[k], b[k], int(k < n_set), cic_m) for k in range(n_set + length)]
    return steps
