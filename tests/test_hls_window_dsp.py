"""HLS kernel hfi_window_dsp (hls/src/hfi_window_dsp.cpp) against golden.fpga.window_dsp.window_dsp
(ADC scale -> Clarke -> Park -> demodulator of one window; spec 3.1, 3.2, 3.4), native C simulation.

Random windows of 0..HFI_WINDOW_MAX samples: ADC codes, offsets and gains from the ADC vectors of
golden/testvectors/adc_scale.py (codes at 0 and full scale, saturating offsets and gains), SIN/COS from
golden/testvectors/park.py, random keep masks (all, none, partial); directed windows at n = 0 and
n = HFI_WINDOW_MAX at full scale. Both the latched result and every sample's i_d, i_q are compared.
Random inputs use ``numpy.random.default_rng(seed)``; the seed is ``HFI_SEED`` if set, else a fresh
one, and is printed. The kernel's time per sample is measured by scripts/bench_hls.py (`make bench`).
"""

from __future__ import annotations

import numpy as np

from golden.fpga.adc_scale import GAIN_ONE
from golden.fpga.cordic import cw_angle_step, demod_weight
from golden.fpga.window_dsp import window_dsp
from golden.testvectors import adc_scale as adc_vectors
from golden.testvectors import park as park_vectors
from hfi import hls_build

WINDOW_MAX = 3277                  # HFI_WINDOW_MAX of hls/include/hfi_window_dsp.h
N_WINDOWS = 300
OUT_NAMES = ("gamma", "gamma_d", "sum_id", "sum_iq", "wsum", "n_samples")


def _arrays(adc_a, adc_b, w, keep):
    return (np.ascontiguousarray(adc_a, dtype=np.uint16), np.ascontiguousarray(adc_b, dtype=np.uint16),
            np.ascontiguousarray(w, dtype=np.int16), np.ascontiguousarray(keep, dtype=np.uint8))


def _hls(win: dict):
    """(result tuple, i_d, i_q) of hfi_window_dsp through csim_window_dsp."""
    ffi, lib = hls_build.csim()
    a, b, w, keep = _arrays(win["adc_a"], win["adc_b"], win["w"], win["keep"])
    n = len(a)
    i_d, i_q = np.empty(n, np.int16), np.empty(n, np.int16)
    res = np.empty(6, np.int32)
    rc = lib.csim_window_dsp(n, ffi.from_buffer("uint16_t[]", a), ffi.from_buffer("uint16_t[]", b),
                             ffi.from_buffer("int16_t[]", w), ffi.from_buffer("uint8_t[]", keep), win["bits"],
                             win["offset_a"], win["offset_b"], win["gain_a"], win["gain_b"], win["sin"], win["cos"],
                             ffi.from_buffer("int16_t[]", i_d), ffi.from_buffer("int16_t[]", i_q),
                             ffi.from_buffer("int32_t[]", res))
    assert rc == 0
    return tuple(int(v) for v in res), i_d.astype(np.int64), i_q.astype(np.int64)


def _golden(win: dict):
    r, i_d, i_q = window_dsp(win["adc_a"], win["adc_b"], win["bits"], win["offset_a"], win["offset_b"],
                             win["gain_a"], win["gain_b"], win["sin"], win["cos"], win["w"],
                             np.asarray(win["keep"], dtype=bool))
    return (r.gamma, r.gamma_d, r.sum_id, r.sum_iq, r.wsum, r.n_samples), i_d, i_q


def _check(win: dict, label: str) -> tuple:
    got, exp = _hls(win), _golden(win)
    regs = {k: v for k, v in win.items() if np.isscalar(v)}
    assert got[0] == exp[0], (f"{label} {regs}: HLS {dict(zip(OUT_NAMES, got[0]))}, "
                              f"golden {dict(zip(OUT_NAMES, exp[0]))}")
    for name, g, e in (("i_d", got[1], exp[1]), ("i_q", got[2], exp[2])):
        bad = np.flatnonzero(g != e)
        assert bad.size == 0, (f"{label} {regs}: {name}[{bad[0]}] HLS {g[bad[0]]}, golden {e[bad[0]]} "
                               f"(codes {win['adc_a'][bad[0]]}, {win['adc_b'][bad[0]]})")
    return exp


def _random_window(rng: np.random.Generator) -> dict:
    """One random window (see the module docstring)."""
    r = rng.random()
    n = 0 if r < 0.05 else WINDOW_MAX if r < 0.1 else 200 if r < 0.3 else int(rng.integers(1, WINDOW_MAX + 1))
    bits = 12 if rng.random() < 0.4 else int(rng.integers(1, 17))
    adc = adc_vectors.random_vectors(rng, max(n, 1), bits)
    top = (1 << bits) - 1
    mode = rng.random()
    if mode < 0.05:                                     # every code at full scale
        adc[:, 0], adc[:, 1] = top, 0
    if mode > 0.8:                                      # realistic registers: small offsets, gains near 1.0
        adc[0, 2:4] = rng.integers(-200, 201, 2)
        adc[0, 4:6] = rng.integers(GAIN_ONE - 800, GAIN_ONE + 801, 2)
    sin_cos = park_vectors.random_vectors(rng, 1)[0, 2:4]
    if rng.random() < 0.5:                              # the weights of a carrier half period
        half = 2 * int(rng.integers(2, 32768))
        w = demod_weight(rng.integers(0, half + 1, n), half, cw_angle_step(half))
    else:
        w = rng.integers(-32768, 32768, n)
    p_keep = rng.choice(np.array([1.0, 0.9, 0.5, 0.0]))
    return dict(adc_a=adc[:n, 0], adc_b=adc[:n, 1], bits=bits, offset_a=int(adc[0, 2]), offset_b=int(adc[0, 3]),
                gain_a=int(adc[0, 4]), gain_b=int(adc[0, 5]), sin=int(sin_cos[0]), cos=int(sin_cos[1]),
                w=np.asarray(w, dtype=np.int64), keep=rng.random(n) < p_keep)


def test_random_windows(seed):
    rng = np.random.default_rng(seed)
    samples = sat = 0
    for k in range(N_WINDOWS):
        win = _random_window(rng)
        _, i_d, i_q = _check(win, f"random window {k} (HFI_SEED={seed})")
        samples += len(i_d)
        sat += int(np.count_nonzero(np.isin(np.concatenate([i_d, i_q]), (-32768, 32767))))
    print(f"{N_WINDOWS} windows, {samples} samples, {sat} saturated Park outputs")
    assert sat > 0


def test_directed_windows():
    """n = 0; n = HFI_WINDOW_MAX at full scale with saturating offsets and gains (every sample kept), and
    with every sample blanked."""
    empty = dict(adc_a=np.zeros(0, np.int64), adc_b=np.zeros(0, np.int64), bits=12, offset_a=0, offset_b=0,
                 gain_a=GAIN_ONE, gain_b=GAIN_ONE, sin=0, cos=32767, w=np.zeros(0, np.int64), keep=np.zeros(0, bool))
    assert _check(empty, "n = 0")[0] == (0, 0, 0, 0, 0, 0)
    n = WINDOW_MAX
    for bits in (1, 12, 16):
        top = (1 << bits) - 1
        full = dict(adc_a=np.full(n, top), adc_b=np.zeros(n, np.int64), bits=bits, offset_a=-32768, offset_b=32767,
                    gain_a=65535, gain_b=65535, sin=-32768, cos=-32768, w=np.full(n, -32768), keep=np.ones(n, bool))
        exp = _check(full, f"full scale, n = {n}, ADC_BITS={bits}")
        assert exp[0][5] == n
        full["keep"] = np.zeros(n, bool)
        assert _check(full, f"full scale, n = {n}, all blanked, ADC_BITS={bits}")[0] == (0, 0, 0, 0, 0, 0)
