"""Input vectors of the demodulator tests (golden.fpga.demodulator.demodulate, spec 3.4).

Used by cocotb_tests/tb_demodulator.py (RTL, which adds the cycle timing) and
tests/test_hls_demodulator.py (HLS C simulation). A window is a tuple ``(keep, i_d, i_q, w)`` of equal
length lists (``keep`` 0/1: 0 = blanked, the sample does not enter the sums); an event is
``("sample", keep, i_d, i_q, w)``, ``("latch", label)`` (window boundary: latch the sums of the kept
samples since the previous latch or reset, then clear) or ``("reset",)`` (clear without a latch).
"""

from __future__ import annotations

import numpy as np

EXTREME = np.array([-32768, -32767, -1, 0, 1, 32766, 32767])
BIG = (-32768, -32768, -32768)
"""(i_d, i_q, w) of the largest product, +2^30."""
LONG_N = 65534
"""Samples of the longest specified window (fewer than 65535, spec 3.4)."""


def window_values(rng: np.random.Generator, n: int) -> list[list[int]]:
    """``[i_d, i_q, w]`` of one window's ``n`` samples, from one of five distributions: products at the
    extremes, every product +-2^30, extremes and small values mixed, realistic (small currents,
    full-range weights), uniform s16."""
    mode = rng.integers(0, 5)
    if mode == 0:       # products at the extremes: +-32768 * -32768 and neighbours
        vals = rng.choice(np.array([-32768, 32767]), (3, n))
    elif mode == 1:     # every product +2^30 (the largest), or its negative
        sign = rng.choice(np.array([-32768, 32767]))
        vals = np.array([[-32768] * n, [-32768] * n, [sign] * n])
    elif mode == 2:     # extremes and small values mixed
        vals = rng.choice(EXTREME, (3, n))
    elif mode == 3:     # realistic: small currents, full-range weights
        vals = np.vstack([rng.integers(-2000, 2001, (2, n)), rng.integers(-32768, 32768, (1, n))])
    else:               # uniform s16
        vals = rng.integers(-32768, 32768, (3, n))
    return vals.reshape(3, n).tolist()


def random_windows(rng: np.random.Generator, n_accepted: int) -> list[tuple[list[int], ...]]:
    """Random windows until at least ``n_accepted`` kept samples: lengths 0 (5 %), 1 (3 %) or uniform
    0..300; keep probability 1.0, 0.9, 0.5 or 0.0 per window; values from :func:`window_values`."""
    windows = []
    accepted = 0
    while accepted < n_accepted:
        r = rng.random()
        length = 0 if r < 0.05 else 1 if r < 0.08 else int(rng.integers(0, 301))
        p_keep = rng.choice(np.array([1.0, 0.9, 0.5, 0.0]), p=[0.3, 0.5, 0.15, 0.05])
        keep = (rng.random(length) < p_keep).astype(int).tolist()
        i_d, i_q, w = window_values(rng, length)
        windows.append((keep, i_d, i_q, w))
        accepted += sum(keep)
    return windows


def directed_events() -> list[tuple]:
    """Empty and consecutive windows, a window of one full-scale product, blanked samples, reset mid-window,
    an empty window after a reset (the RTL testbench places some samples in latch cycles)."""
    ev = [("latch", "(empty window right after reset)"), ("latch", "(consecutive latch)"),
          ("latch", "(consecutive latch)"),
          ("sample", 1, *BIG), ("latch", "(sample in the cycle before)"),
          ("sample", 1, 100, -200, 300), ("latch", "(sample in the latch cycle before)"),
          ("sample", 1, *BIG), ("sample", 1, 32767, -32768, 32767), ("latch", "(back-to-back samples then latch)"),
          ("sample", 0, *BIG), ("sample", 1, 5, 6, 7), ("sample", 0, *BIG), ("latch", "(blanked samples around)"),
          ("latch", "(empty window after a blanked latch-cycle sample)")]
    ev += [("sample", 1, -32768 + j, 32767 - j, -32768) for j in range(5)]
    ev += [("reset",),                                  # the 5 samples are dropped
           ("sample", 1, 11, 22, 33), ("latch", "(after a reset mid-window)"),
           ("sample", 1, *BIG), ("reset",), ("latch", "(first cycle after a reset)")]
    return ev


def long_windows() -> list[tuple[int, int, int, int, int]]:
    """Constant windows ``(n, keep, i_d, i_q, w)``: 65534 largest products (+2^30 each), 65534 products
    -32767*32768, 1000 blanked full-scale samples, 70000 small samples (N_SAMPLES saturates at 65535)."""
    return [(LONG_N, 1, -32768, -32768, -32768), (LONG_N, 1, 32767, 32767, -32768),
            (1000, 0, -32768, -32768, -32768), (70000, 1, 3, -2, 1)]
