"""HLS kernel hfi_overcurrent (hls/src/hfi_overcurrent.cpp) against golden.fpga.overcurrent.over_limit (spec 3.7),
native C simulation, on the RTL testbench's vectors (golden.testvectors.overcurrent: the directed corner cases
and random ones; the seed is ``HFI_SEED`` if set, else a fresh one, printed)."""

from __future__ import annotations

import numpy as np

from golden.fpga.overcurrent import over_limit
from golden.testvectors.overcurrent import DIRECTED, random_vectors
from hfi import hls_build

N_RANDOM = 100_000


def _hls(i_a, i_b, limit) -> np.ndarray:
    ffi, lib = hls_build.csim()
    a, b = (np.ascontiguousarray(x, dtype=np.int16) for x in (i_a, i_b))
    lim = np.ascontiguousarray(limit, dtype=np.uint16)
    trip = np.zeros(len(a), dtype=np.uint8)
    lib.csim_overcurrent(len(a), ffi.from_buffer("int16_t[]", a), ffi.from_buffer("int16_t[]", b),
                         ffi.from_buffer("uint16_t[]", lim), ffi.from_buffer("uint8_t[]", trip))
    return trip.astype(bool)


def test_directed():
    i_a, i_b, limit, expected = (np.array(c, dtype=np.int64) for c in zip(*DIRECTED))
    assert (over_limit(i_a, i_b, limit) == expected.astype(bool)).all(), "golden disagrees with the corner cases"
    assert (_hls(i_a, i_b, limit) == expected.astype(bool)).all()


def test_random(seed):
    _, i_a, i_b, limit = random_vectors(np.random.default_rng(seed), N_RANDOM)
    exp = over_limit(i_a, i_b, limit)
    got = _hls(i_a, i_b, limit)
    bad = np.flatnonzero(got != exp)
    assert bad.size == 0, (f"{bad.size} mismatches (HFI_SEED={seed}), first (i_a, i_b, limit) = "
                           f"{(i_a[bad[0]], i_b[bad[0]], limit[bad[0]])}: HLS {got[bad[0]]}, golden {exp[bad[0]]}")
    print(f"{N_RANDOM} random vectors, {int(exp.sum())} trips")
