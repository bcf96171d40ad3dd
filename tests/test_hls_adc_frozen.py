"""HLS kernel hfi_adc_frozen (hls/src/hfi_adc_frozen.cpp) against golden.fpga.adc_frozen.frozen_lanes (spec 3.13),
native C simulation: windows of 0..300 conversions, each lane constant, constant but for one conversion (first,
middle, last) or random; the seed is ``HFI_SEED`` if set, else a fresh one, printed."""

from __future__ import annotations

import numpy as np

from golden.fpga.adc_frozen import frozen_lanes
from hfi import hls_build

N_WINDOWS = 20_000


def _hls(a: np.ndarray, b: np.ndarray) -> int:
    ffi, lib = hls_build.csim()
    a, b = (np.ascontiguousarray(x, dtype=np.uint16) for x in (a, b))
    return int(lib.csim_adc_frozen(ffi.from_buffer("uint16_t[]", a), ffi.from_buffer("uint16_t[]", b), len(a)))


def _lane(rng, n: int) -> np.ndarray:
    kind = rng.integers(0, 4)
    code = rng.integers(0, 65536)
    lane = np.full(n, code, dtype=np.int64)
    if kind == 1 and n:                                  # one conversion differs, by one code, anywhere
        lane[rng.choice([0, n // 2, n - 1])] = (code + rng.choice([-1, 1])) % 65536
    elif kind == 2:                                      # live: noise around a code
        lane = (code + rng.integers(-3, 4, n)) % 65536
    return lane


def test_directed():
    cases = [([], [], 0), ([5], [5], 0), ([5, 5], [5, 6], 1), ([7, 8], [9, 9], 2), ([0] * 200, [65535] * 200, 3),
             ([1] * 199 + [2], [3] * 200, 2), ([2] + [1] * 199, [4] * 200, 2)]
    for a, b, expected in cases:
        assert frozen_lanes(np.array(a, dtype=np.int64), np.array(b, dtype=np.int64)) == expected, (a[:3], b[:3])
        assert _hls(np.array(a), np.array(b)) == expected


def test_random(seed):
    rng = np.random.default_rng(seed)
    counts = [0, 0, 0, 0]
    for _ in range(N_WINDOWS):
        n = int(rng.choice([0, 1, 2, 3, int(rng.integers(4, 301))]))
        a, b = _lane(rng, n), _lane(rng, n)
        exp = frozen_lanes(a, b)
        assert _hls(a, b) == exp, f"HFI_SEED={seed}: n={n}, a={a[:4]}..., b={b[:4]}...: HLS {_hls(a, b)}, golden {exp}"
        counts[exp] += 1
    print(f"{N_WINDOWS} windows, WIN_ADC 0 / A / B / both: {counts}")
    assert min(counts) > N_WINDOWS // 20
