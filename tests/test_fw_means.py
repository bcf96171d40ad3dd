"""Tests of the per-window means (golden/firmware/means.py; docs/spec.md 5.2): C division, truncating
toward zero. The random check uses math.trunc of the float quotient (exact here: |sum| < 2^31 and
n < 2^16 keep any non-integer quotient at least 1/n away from an integer, far above float rounding)."""

from __future__ import annotations

import math
import random
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from golden.firmware.means import window_means  # noqa: E402


@pytest.mark.parametrize(
    "sum_id, sum_iq, n, expected",
    [
        (-7, 7, 2, (-3, 3)),  # truncation toward zero, not floor (-4)
        (-1, 1, 200, (0, 0)),
        (-399, 399, 200, (-1, 1)),
        (-400, 401, 200, (-2, 2)),
        (123, -456, 0, (0, 0)),  # empty window
        (0, 0, 0, (0, 0)),
        (-(2**31), 2**31 - 1, 1, (-(2**31), 2**31 - 1)),
        # -2147483648 / 65535 = -32768.50001 -> -32768; 2147483647 / 65535 = 32768.49999 -> 32768
        (-(2**31), 2**31 - 1, 65535, (-32768, 32768)),
        (-6553500, 6553500, 200, (-32767, 32767)),  # -/+32767.5 -> -/+32767
    ],
)
def test_window_means_hand(sum_id, sum_iq, n, expected):
    assert window_means(sum_id, sum_iq, n) == expected


def test_window_means_random():
    seed = 8675309
    rng = random.Random(seed)
    for _ in range(10_000):
        n = rng.choice([0, rng.randint(1, 400), rng.randint(1, 65535)])
        a = rng.randint(-(2**31), 2**31 - 1)
        b = rng.randint(-32768, 32767) * max(n, 1) + rng.randint(-n, n)
        b = max(-(2**31), min(2**31 - 1, b))
        i_d, i_q = window_means(a, b, n)
        if n == 0:
            assert (i_d, i_q) == (0, 0), f"seed {seed}"
            continue
        assert (i_d, i_q) == (math.trunc(a / n), math.trunc(b / n)), f"seed {seed}: {a} {b} {n}"
        for s, q in ((a, i_d), (b, i_q)):  # C: s == q n + r with |r| < n and r of the sign of s
            r = s - q * n
            assert abs(r) < n and (r == 0 or (r > 0) == (s > 0)), f"seed {seed}"
