"""Input vectors of the CORDIC tests (golden.fpga.cordic: cordic_sincos, sincos_q15, demod_weight, spec 3.3).

Used by cocotb_tests/tb_cordic.py (RTL) and tests/test_hls_cordic.py (HLS C simulation): angles are u32
binary angles (int64 values), weight cases ``(H, c)`` pairs of an effective half period and a carrier
counter value.
"""

from __future__ import annotations

import numpy as np

from golden.fixed import round_shr, uwrap
from golden.fpga.cordic import cordic_sincos, cw_angle_step

U32 = 1 << 32
Q = 1 << 30  # a quarter turn

SWEEP_POINTS = tuple(sorted({(w, n) for w in (17, 18, 24, 32) for n in (1, 8, 16, w)}))
"""(WIDTH, ITERATIONS) points of the RTL sweep (cocotb_tests/test_cordic.py: Verilator {17, 18, 24, 32} x
{1, 8, 16, WIDTH}, which holds the Icarus points (32, 32), (17, 17), (24, 8))."""

WEIGHT_H = 10000
"""The half period of the spec's weight example (spec 3.3: +32767, 0, -32768 at c = 0, H/2, H)."""


def directed_angles() -> list[int]:
    """0, +-1, the quadrant points +-1 and +-2, the fold boundaries (top bits 00|01, 01|10, 10|11, 11|00),
    45 deg multiples, 2^32 - 1."""
    out = []
    for base in (0, Q, 2 * Q, 3 * Q, U32):
        for d in (-2, -1, 0, 1, 2):
            a = base + d
            if 0 <= a < U32:
                out.append(a)
    out += [Q // 2 + k * Q for k in range(4)]              # 45, 135, 225, 315 deg
    out += [U32 - 1, 1 << 31, (1 << 31) - 1, (1 << 31) + 1, 0x7FFFFFFF, 0x80000000, 0xFFFFFFFF]
    return list(dict.fromkeys(out))                        # unique, in order


def saturating_angles(width: int, iterations: int, per_kind: int = 4) -> tuple[list[int], int, int]:
    """Angles near the axes whose golden Q1.15 sin or cos needs saturation (round_shr gives +32768 or
    -32769 before sat). Returns (angles, number of positive, number of negative cases found)."""
    k = np.arange(0, 4096, dtype=np.int64)
    cand = np.concatenate([(base + sgn * k) % U32 for base in (0, Q, 2 * Q, 3 * Q) for sgn in (1, -1)])
    cand = np.unique(cand)
    s_raw, c_raw = cordic_sincos(cand, width, iterations)
    picked, n_pos, n_neg = [], 0, 0
    for raw in (s_raw, c_raw):
        pre = round_shr(raw, width - 17)
        pos, neg = cand[pre > 32767], cand[pre < -32768]
        n_pos += len(pos)
        n_neg += len(neg)
        picked += pos[:per_kind].tolist() + neg[:per_kind].tolist()
    return list(dict.fromkeys(picked)), n_pos, n_neg


def random_angles(rng: np.random.Generator, n: int) -> np.ndarray:
    """``n`` uniform u32 angles (int64 array)."""
    return rng.integers(0, U32, size=n, dtype=np.int64)


def demod_case(half: int, counter: int) -> int:
    """The weight angle uwrap((H - 2c) * CW_ANGLE_STEP, 32) of spec 3.3 (the carrier's cw_angle)."""
    return uwrap((half - 2 * counter) * cw_angle_step(half), 32)


def demod_cases(rng: np.random.Generator, n: int) -> list[tuple[int, int]]:
    """Weight cases ``(H, c)``: first H = 10000 at c = 0, H/2, H; then ``n`` random even H in 512..65534
    with a uniform c in 0..H; then the ends of H = 65534 and H = 512."""
    cases = [(WEIGHT_H, 0), (WEIGHT_H, WEIGHT_H // 2), (WEIGHT_H, WEIGHT_H)]
    halves = 2 * rng.integers(256, 32768, size=n)             # even, 512..65534
    cases += [(int(h), int(rng.integers(0, h + 1))) for h in halves]
    cases += [(65534, 0), (65534, 32767), (65534, 65534), (512, 0), (512, 256), (512, 512), (512, 1)]
    return cases
