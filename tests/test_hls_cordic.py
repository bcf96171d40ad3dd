"""HLS CORDIC kernels (hls/include/hfi_cordic_impl.h, hls/src/hfi_cordic.cpp) against golden.fpga.cordic
(spec 3.3), native C simulation: hfi_cordic_sincos<WIDTH, ITERATIONS> (raw and Q1.15) at every
(WIDTH, ITERATIONS) point of the RTL sweep, hfi_to_q15<WIDTH> at every WIDTH 17..32, hfi_sincos_q15 (the
firmware's (32, 16)) and hfi_demod_weight over every counter of several H.

Angles and weight cases: golden/testvectors/cordic.py, as the RTL testbench cocotb_tests/tb_cordic.py.
Random inputs use ``numpy.random.default_rng(seed + k)``; the seed is ``HFI_SEED`` if set, else a fresh
one, and is printed.
"""

from __future__ import annotations

import numpy as np
import pytest

from golden.fpga.cordic import cordic_sincos, cw_angle_step, demod_weight, sincos_q15, to_q15
from golden.testvectors import cordic as testvectors
from hfi import hls_build

DEFAULT = (32, 32)
N_RANDOM_DEFAULT = 100_000
N_RANDOM_SWEEP = 20_000
N_RANDOM_Q15 = 20_000              # per WIDTH
N_WEIGHT_CASES = 5_000             # random (H, c) cases of the RTL testbench
WEIGHT_HALVES = (4, 512, 10000, 65534)


def _first_bad(got: np.ndarray, exp: np.ndarray, inputs: np.ndarray, what: str) -> None:
    bad = np.flatnonzero(got != exp)
    assert bad.size == 0, (f"{what}: {bad.size} mismatches, first input {inputs[bad[0]]}: HLS {got[bad[0]]}, "
                           f"golden {exp[bad[0]]}")


def _hls_sincos(width: int, iterations: int, angle: np.ndarray):
    """(sin_raw, cos_raw, sin_q15, cos_q15) of hfi_cordic_sincos<width, iterations> + hfi_to_q15<width>."""
    ffi, lib = hls_build.csim()
    a = np.ascontiguousarray(angle, dtype=np.uint32)
    n = len(a)
    sr, cr = np.empty(n, np.int32), np.empty(n, np.int32)
    sq, cq = np.empty(n, np.int16), np.empty(n, np.int16)
    rc = lib.csim_cordic_sincos(width, iterations, n, ffi.from_buffer("uint32_t[]", a),
                                ffi.from_buffer("int32_t[]", sr), ffi.from_buffer("int32_t[]", cr),
                                ffi.from_buffer("int16_t[]", sq), ffi.from_buffer("int16_t[]", cq))
    assert rc == 0, f"(WIDTH, ITERATIONS) = {(width, iterations)} is not instantiated in hls/csim/csim_cordic.cpp"
    return tuple(x.astype(np.int64) for x in (sr, cr, sq, cq))


def _check_sincos(width: int, iterations: int, angle: np.ndarray, label: str) -> None:
    got = _hls_sincos(width, iterations, angle)
    s_raw, c_raw = cordic_sincos(angle, width, iterations)
    s_q, c_q = sincos_q15(angle, width, iterations)
    for name, g, e in zip(("sin_raw", "cos_raw", "sin_q15", "cos_q15"), got, (s_raw, c_raw, s_q, c_q)):
        _first_bad(g, e, angle, f"{label} (WIDTH, ITERATIONS) = {(width, iterations)}: {name}")


def test_instantiated_points():
    """The C-sim library instantiates exactly the RTL sweep points, and refuses another point."""
    ffi, lib = hls_build.csim()
    w, n = ffi.new("int[64]"), ffi.new("int[64]")
    count = lib.csim_cordic_points(64, w, n)
    assert sorted((w[k], n[k]) for k in range(count)) == list(testvectors.SWEEP_POINTS)
    assert DEFAULT in testvectors.SWEEP_POINTS
    assert lib.csim_cordic_sincos(25, 13, 0, ffi.NULL, ffi.NULL, ffi.NULL, ffi.NULL, ffi.NULL) == -1


@pytest.mark.parametrize("width, iterations", testvectors.SWEEP_POINTS)
def test_sincos_directed(width, iterations):
    """Quadrant points, fold boundaries and the angles whose Q1.15 result saturates."""
    sat, n_pos, _ = testvectors.saturating_angles(width, iterations)
    angle = np.array(testvectors.directed_angles() + sat, dtype=np.int64)
    _check_sincos(width, iterations, angle, "directed")
    if (width, iterations) == DEFAULT:
        assert n_pos > 0, "no angle exercising the +32768 -> 32767 saturation was found"


@pytest.mark.parametrize("width, iterations", testvectors.SWEEP_POINTS)
def test_sincos_random(width, iterations, seed):
    rng = np.random.default_rng(seed + 100 * width + iterations)
    n = N_RANDOM_DEFAULT if (width, iterations) == DEFAULT else N_RANDOM_SWEEP
    _check_sincos(width, iterations, testvectors.random_angles(rng, n), f"random (HFI_SEED={seed})")


def test_to_q15(seed):
    """hfi_to_q15<WIDTH> for WIDTH 17..32: the extremes of sWIDTH, the rounding ties and random values."""
    ffi, lib = hls_build.csim()
    rng = np.random.default_rng(seed + 1)
    for width in range(17, 33):
        lo, hi = -(1 << (width - 1)), (1 << (width - 1)) - 1
        sh = width - 17
        ties = [(k << sh) + (1 << sh >> 1) for k in (-2, -1, 0, 1, 32766, 32767, -32768, -32769)] if sh else []
        special = np.array([lo, lo + 1, -1, 0, 1, hi - 1, hi] + [t for t in ties if lo <= t <= hi], dtype=np.int64)
        v = np.concatenate([special, rng.integers(lo, hi, N_RANDOM_Q15, endpoint=True, dtype=np.int64)])
        v32 = np.ascontiguousarray(v, dtype=np.int32)
        out = np.empty(len(v), dtype=np.int16)
        assert lib.csim_cordic_to_q15(width, len(v), ffi.from_buffer("int32_t[]", v32),
                                      ffi.from_buffer("int16_t[]", out)) == 0
        _first_bad(out.astype(np.int64), to_q15(v, width), v, f"to_q15 WIDTH={width}")
    assert lib.csim_cordic_to_q15(16, 0, ffi.NULL, ffi.NULL) == -1


def test_sincos_q15(seed):
    """hfi_sincos_q15 (the firmware's (32, 16)) against golden sincos_q15 with its defaults."""
    ffi, lib = hls_build.csim()
    rng = np.random.default_rng(seed + 2)
    angle = np.concatenate([np.array(testvectors.directed_angles(), dtype=np.int64),
                            testvectors.random_angles(rng, N_RANDOM_DEFAULT)])
    a = np.ascontiguousarray(angle, dtype=np.uint32)
    s, c = np.empty(len(a), np.int16), np.empty(len(a), np.int16)
    lib.csim_cordic_sincos_q15(len(a), ffi.from_buffer("uint32_t[]", a), ffi.from_buffer("int16_t[]", s),
                               ffi.from_buffer("int16_t[]", c))
    exp_s, exp_c = sincos_q15(angle)
    _first_bad(s.astype(np.int64), exp_s, angle, "sincos_q15 sin")
    _first_bad(c.astype(np.int64), exp_c, angle, "sincos_q15 cos")


def _hls_weight(counter, half, step) -> np.ndarray:
    ffi, lib = hls_build.csim()
    c = np.ascontiguousarray(counter, dtype=np.uint16)
    h = np.ascontiguousarray(half, dtype=np.uint16)
    st = np.ascontiguousarray(step, dtype=np.uint32)
    w = np.empty(len(c), dtype=np.int16)
    lib.csim_cordic_demod_weight(len(c), ffi.from_buffer("uint16_t[]", c), ffi.from_buffer("uint16_t[]", h),
                                 ffi.from_buffer("uint32_t[]", st), ffi.from_buffer("int16_t[]", w))
    return w.astype(np.int64)


def test_demod_weight_all_counters(seed):
    """Every counter 0..H of several H (and one random even H), with CW_ANGLE_STEP = round(2^30 / H) and
    with a random u32 step; spec 3.3's example at H = 10000."""
    rng = np.random.default_rng(seed + 3)
    halves = WEIGHT_HALVES + (2 * int(rng.integers(2, 32768)),)
    for half in halves:
        counter = np.arange(half + 1, dtype=np.int64)
        for step in (cw_angle_step(half), int(rng.integers(0, 1 << 32))):
            got = _hls_weight(counter, np.full(half + 1, half), np.full(half + 1, step))
            _first_bad(got, demod_weight(counter, half, step), counter, f"demod_weight H={half} step={step}")
            if half == testvectors.WEIGHT_H and step == cw_angle_step(half):
                assert got[[0, half // 2, half]].tolist() == [32767, 0, -32768]


def test_demod_weight_cases(seed):
    """The RTL testbench's weight cases: random even H with a random counter, and the ends of H."""
    rng = np.random.default_rng(seed + 4)
    cases = np.array(testvectors.demod_cases(rng, N_WEIGHT_CASES), dtype=np.int64)
    step = np.array([cw_angle_step(int(h)) for h in cases[:, 0]], dtype=np.int64)
    got = _hls_weight(cases[:, 1], cases[:, 0], step)
    exp = np.array([demod_weight(int(c), int(h), int(s)) for (h, c), s in zip(cases, step)], dtype=np.int64)
    _first_bad(got, exp, cases, "demod_weight (H, c)")
