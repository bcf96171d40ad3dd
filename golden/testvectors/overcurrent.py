"""Test vectors of the overcurrent comparator (spec 3.7), shared by the RTL testbench
(cocotb_tests/tb_overcurrent.py) and the HLS kernel's test (tests/test_hls_overcurrent.py)."""

from __future__ import annotations

import numpy as np

DIRECTED = [
    # (i_a, i_b, limit, expected)
    (0, 0, 0, 0), (1, -1, 0, 1), (0, 0, 65535, 0),
    (-32768, 0, 32767, 1),                  # |i_a| = 32768 > any limit < 32768
    (0, -32768, 32767, 1),
    (16384, 16384, 32767, 1),               # i_c = -32768
    (16384, 16383, 32767, 0),               # i_c = -32767
    (32767, 0, 32767, 0), (32767, 0, 32766, 1), (0, 32767, 32766, 1),
    (-32768, -32768, 65535, 1),             # i_c = 65536 > 65535
    (-32768, -32768, 32768, 1), (-32768, 0, 32768, 0),
    (32767, 32767, 65535, 0), (32767, 32767, 65534, 0),   # i_c = -65534
    (32767, 32767, 65533, 1),
    (-32768, -32767, 65535, 0), (-32768, -32767, 65534, 1),  # i_c = 65535
    (100, -300, 200, 1), (100, -300, 300, 0), (100, -200, 200, 0), (-100, 300, 299, 1),
    (150, 150, 299, 1), (150, 150, 300, 0),            # only i_c = -300 can trip
    (20000, 20000, 39999, 1), (20000, 20000, 40000, 0),
]
"""Corner cases: full scale, -32768, i_c = 65536 and -65534, limits 0 / 32767 / >= 32768 / 65535."""


def random_vectors(rng, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(valid, i_a, i_b, limit) int64 arrays: full-range currents and limits, limits near the currents'
    magnitudes (both sides of every compare), extremes (-32768, 32767, i_c = 65536) and small values."""
    kind = rng.integers(0, 5, n)
    i_a = rng.integers(-32768, 32768, n)
    i_b = rng.integers(-32768, 32768, n)
    small = kind == 1                                   # small currents, small limits
    i_a[small] = rng.integers(-40, 41, small.sum())
    i_b[small] = rng.integers(-40, 41, small.sum())
    ext = kind == 2                                     # extreme currents
    choices = np.array([-32768, -32767, -1, 0, 1, 32766, 32767])
    i_a[ext] = rng.choice(choices, ext.sum())
    i_b[ext] = rng.choice(choices, ext.sum())
    mag = np.maximum(np.maximum(np.abs(i_a), np.abs(i_b)), np.abs(i_a + i_b))
    limit = rng.integers(0, 65536, n)                   # kind 0: uniform u16 limit
    near = kind >= 1                                    # limit = largest magnitude + {-2..1}
    limit[near] = np.clip(mag[near] + rng.integers(-2, 2, near.sum()), 0, 65535)
    big = kind == 4                                     # limit >= 32768: only i_c can trip
    limit[big] = rng.integers(32768, 65536, big.sum())
    i_a[big & (rng.random(n) < 0.5)] = -32768
    valid = (rng.random(n) < 0.8).astype(np.int64)
    return valid, i_a, i_b, limit
