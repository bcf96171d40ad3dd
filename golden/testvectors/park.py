"""Input vectors of the Clarke + Park tests (golden.fpga.park.clarke, golden.fpga.park.park, spec 3.2).

Used by cocotb_tests/tb_park.py (RTL) and tests/test_hls_park.py (HLS C simulation). A vector is a row
``(i_a, i_b, sin_q15, cos_q15)`` of an (n, 4) int64 array.
"""

from __future__ import annotations

import math

import numpy as np

EXTREMES = (-32768, -32767, -1, 0, 1, 32766, 32767)


def directed_vectors() -> np.ndarray:
    """Every combination of the ends -32768, -1, 0, 32767 of the four inputs (saturating i_beta, i_d and
    i_q; Park sums at 2^31), plus a few named cases."""
    ends = (-32768, -1, 0, 32767)
    rows = [(a, b, s, c) for a in ends for b in ends for s in ends for c in ends]
    rows += [(-32768, -32768, -32768, -32768), (32767, 32767, 32767, 32767), (-32768, -32768, 32767, 32767),
             (10000, -5000, 23170, 23170), (-1, -1, -1, -1), (1, 0, 0, 32767)]
    return np.array(rows, dtype=np.int64)


def random_vectors(rng: np.random.Generator, n: int) -> np.ndarray:
    """``n`` random vectors: currents uniform s16, 20 % small (+-300), 15 % extreme; (SIN, COS) uniform s16
    pairs or (50 %) rounded points of the unit circle (the firmware's), 10 % extreme."""
    cols = []
    for _ in range(2):                                  # currents
        x = rng.integers(-32768, 32768, n)
        small = rng.random(n) < 0.2
        x[small] = rng.integers(-300, 301, small.sum())
        ext = rng.random(n) < 0.15
        x[ext] = rng.choice(np.array(EXTREMES), ext.sum())
        cols.append(x)
    s = rng.integers(-32768, 32768, n)
    c = rng.integers(-32768, 32768, n)
    unit = rng.random(n) < 0.5
    th = rng.random(unit.sum()) * 2 * math.pi
    s[unit] = np.clip(np.round(np.sin(th) * 32768), -32768, 32767).astype(np.int64)
    c[unit] = np.clip(np.round(np.cos(th) * 32768), -32768, 32767).astype(np.int64)
    ext = rng.random(n) < 0.1
    s[ext] = rng.choice(np.array(EXTREMES), ext.sum())
    c[ext] = rng.choice(np.array(EXTREMES), ext.sum())
    cols += [s, c]
    return np.stack(cols, axis=1).astype(np.int64)
