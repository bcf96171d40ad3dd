"""HLS kernels hfi_clarke and hfi_park (hls/src/hfi_park.cpp) against golden.fpga.park.clarke and
golden.fpga.park.park (spec 3.2), native C simulation.

Vectors: golden/testvectors/park.py, the same directed and random ``(i_a, i_b, SIN, COS)`` vectors as the
RTL testbench cocotb_tests/tb_park.py. Each vector is checked three ways: Clarke alone, Park of the
Clarke outputs (the RTL's chain) and Park of ``(i_a, i_b)`` read as ``(i_alpha, i_beta)`` (any s16
pair, e.g. the sums at 2^31). Random inputs use ``numpy.random.default_rng(seed)``; the seed is
``HFI_SEED`` if set, else a fresh one, and is printed.
"""

from __future__ import annotations

import numpy as np

from golden.fpga.park import clarke, park
from golden.testvectors import park as testvectors
from hfi import hls_build

N_RANDOM = 100_000


def _s16(x) -> np.ndarray:
    return np.ascontiguousarray(x, dtype=np.int16)


def _buf(ffi, a: np.ndarray):
    return ffi.from_buffer("int16_t[]", a)


def _hls_clarke(i_a, i_b):
    ffi, lib = hls_build.csim()
    i_a, i_b = _s16(i_a), _s16(i_b)
    al, be = np.empty_like(i_a), np.empty_like(i_a)
    lib.csim_park_clarke(len(i_a), _buf(ffi, i_a), _buf(ffi, i_b), _buf(ffi, al), _buf(ffi, be))
    return al.astype(np.int64), be.astype(np.int64)


def _hls_park(i_alpha, i_beta, s, c):
    ffi, lib = hls_build.csim()
    al, be, s, c = _s16(i_alpha), _s16(i_beta), _s16(s), _s16(c)
    d, q = np.empty_like(al), np.empty_like(al)
    lib.csim_park(len(al), _buf(ffi, al), _buf(ffi, be), _buf(ffi, s), _buf(ffi, c), _buf(ffi, d), _buf(ffi, q))
    return d.astype(np.int64), q.astype(np.int64)


def _assert_equal(got: np.ndarray, exp: np.ndarray, vectors: np.ndarray, what: str) -> None:
    bad = np.flatnonzero(got != exp)
    assert bad.size == 0, (f"{what}: {bad.size} mismatches, first (i_a, i_b, SIN, COS) = {tuple(vectors[bad[0]])}: "
                           f"HLS {got[bad[0]]}, golden {exp[bad[0]]}")


def _check(vectors: np.ndarray, label: str) -> int:
    """The three checks of the module docstring; returns the number of saturated golden outputs."""
    i_a, i_b, s, c = (vectors[:, k].copy() for k in range(4))
    al, be = _hls_clarke(i_a, i_b)
    exp_al, exp_be = clarke(i_a, i_b)
    _assert_equal(al, exp_al, vectors, f"{label}: clarke i_alpha")
    _assert_equal(be, exp_be, vectors, f"{label}: clarke i_beta")
    sat = 0
    for what, (x, y) in (("park(clarke)", (exp_al, exp_be)), ("park(i_a, i_b)", (i_a, i_b))):
        d, q = _hls_park(x, y, s, c)
        exp_d, exp_q = park(x, y, s, c)
        _assert_equal(d, exp_d, vectors, f"{label}: {what} i_d")
        _assert_equal(q, exp_q, vectors, f"{label}: {what} i_q")
        sat += int(np.count_nonzero(np.isin(np.concatenate([exp_d, exp_q]), (-32768, 32767))))
    return sat + int(np.count_nonzero(np.isin(exp_be, (-32768, 32767))))


def test_directed():
    assert _check(testvectors.directed_vectors(), "directed") > 0, "the directed vectors never saturate"


def test_random(seed):
    rng = np.random.default_rng(seed)
    sat = _check(testvectors.random_vectors(rng, N_RANDOM), f"random (HFI_SEED={seed})")
    print(f"{N_RANDOM} random vectors, {sat} saturated or full-scale results")
