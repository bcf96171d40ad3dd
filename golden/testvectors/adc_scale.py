"""Input vectors of the ADC offset-and-scale tests (golden.fpga.adc_scale.adc_to_current, spec 3.1).

Used by cocotb_tests/tb_adc_scale.py (RTL) and tests/test_hls_adc_scale.py (HLS C simulation). A vector
is a row ``(code_a, code_b, offset_a, offset_b, gain_a, gain_b)`` of an (n, 6) int64 array.
"""

from __future__ import annotations

import numpy as np

COLUMNS = ("code_a", "code_b", "offset_a", "offset_b", "gain_a", "gain_b")
OFFSET_EXTREMES = (-32768, -32767, -1, 0, 1, 32766, 32767)
GAIN_EXTREMES = (0, 1, 16383, 16384, 16385, 32768, 65534, 65535)


def directed_vectors(bits: int) -> np.ndarray:
    """Full-scale, mid-scale and zero codes (phase b the complement of phase a) x extreme offsets
    (phase b: ``-1 - offset_a``) x extreme gains (phase b: ``65535 - gain_a``), 5 x 5 x up to 4 rows."""
    top = (1 << bits) - 1
    rows = []
    for code in sorted({0, top, top // 2, (top + 1) // 2}):
        for off in (-32768, -1, 0, 1, 32767):
            for gain in (0, 1, 16384, 32768, 65535):
                rows.append((code, top - code, off, -1 - off, gain, 65535 - gain))
    return np.array(rows, dtype=np.int64)


def random_vectors(rng: np.random.Generator, n: int, bits: int) -> np.ndarray:
    """``n`` random vectors: uniform codes with 15 % at 0, 1, mid-scale, top - 1 and top; offsets uniform
    s16, 30 % small (+-200), 10 % extreme; gains uniform u16, 30 % near 1.0 (+-800), 10 % extreme."""
    top = (1 << bits) - 1
    cols = []
    for _ in range(2):                                  # codes a, b
        c = rng.integers(0, top + 1, n)
        sel = rng.random(n) < 0.15
        c[sel] = rng.choice(np.array([0, 1, top // 2, top // 2 + 1, max(top - 1, 0), top]), sel.sum())
        cols.append(c)
    for _ in range(2):                                  # offsets a, b (s16)
        o = rng.integers(-32768, 32768, n)
        small = rng.random(n) < 0.3
        o[small] = rng.integers(-200, 201, small.sum())
        ext = rng.random(n) < 0.1
        o[ext] = rng.choice(np.array(OFFSET_EXTREMES), ext.sum())
        cols.append(o)
    for _ in range(2):                                  # gains a, b (u16 Q2.14)
        g = rng.integers(0, 65536, n)
        near = rng.random(n) < 0.3
        g[near] = rng.integers(16384 - 800, 16384 + 801, near.sum())
        ext = rng.random(n) < 0.1
        g[ext] = rng.choice(np.array(GAIN_EXTREMES), ext.sum())
        cols.append(g)
    return np.stack(cols, axis=1).astype(np.int64)
