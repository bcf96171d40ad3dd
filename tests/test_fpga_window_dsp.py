"""Tests of the one-call window data path (golden/fpga/window_dsp.py, docs/spec.md 3.1, 3.2, 3.4).

window_dsp must return exactly what the chain of the public, checking functions returns:
adc_to_current (both channels) -> clarke -> park -> demodulate of the kept samples. It is compared with
that chain on random windows (each window has its own seed, printed on failure), including the extreme
codes 0 and 2^B-1, negative offsets, gains up to 65535, extreme SIN/COS, one-sample windows (where the
skipped-saturation bounds are tight) and blanking masks.
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from golden.fpga.adc_scale import adc_to_current  # noqa: E402
from golden.fpga.cordic import cw_angle_step, demod_weight, sincos_q15  # noqa: E402
from golden.fpga.demodulator import WindowResult, demodulate  # noqa: E402
from golden.fpga.park import clarke, park  # noqa: E402
from golden.fpga.window_dsp import window_dsp  # noqa: E402

BASE_SEED = 20240611
N_WINDOWS = 10_000
HALF = 10000
OS_W = np.asarray(demod_weight(np.minimum(np.arange(200) * 100, 2 * HALF - np.arange(200) * 100), HALF,
                               cw_angle_step(HALF)), dtype=np.int64)
"""The weights of the 200 oversampled instants of a 5 kHz period (carrier counter 0..H..0)."""


def chain(adc_a, adc_b, bits, off_a, off_b, gain_a, gain_b, s, c, w, keep=None):
    """The reference: the public functions, one after the other."""
    i_a = adc_to_current(np.asarray(adc_a), bits, off_a, gain_a)
    i_b = adc_to_current(np.asarray(adc_b), bits, off_b, gain_b)
    i_al, i_be = clarke(i_a, i_b)
    i_d, i_q = park(i_al, i_be, s, c)
    if keep is None:
        return demodulate(i_d, i_q, w), i_d, i_q
    return demodulate(i_d[keep], i_q[keep], np.asarray(w)[keep]), i_d, i_q


def _codes(rng, n, bits):
    """Codes of one channel: uniform, near mid-scale, or pinned to the extremes."""
    top = (1 << bits) - 1
    kind = rng.integers(4)
    if kind == 0:
        x = rng.integers(0, top + 1, n)
    elif kind == 1:
        mid, spread = 1 << (bits - 1), max(1, top // 16)
        x = np.clip(rng.integers(mid - spread, mid + spread + 1, n), 0, top)
    elif kind == 2:
        x = rng.choice(np.array([0, top]), n)
    else:
        x = rng.integers(0, top + 1, n)
        x[rng.random(n) < 0.2] = 0
        x[rng.random(n) < 0.2] = top
    return x


def _window(seed):
    """Arguments of one random window."""
    rng = np.random.default_rng(seed)
    bits = int(rng.choice([12, 12, 16, rng.integers(1, 17)]))
    n = int(rng.choice([200, 200, 1, rng.integers(0, 260)]))
    a, b = _codes(rng, n, bits), _codes(rng, n, bits)
    layout = rng.integers(3)
    if layout == 0:                                     # int32 column views, as the plant returns
        adc = np.zeros((n, 3), dtype=np.int32)
        adc[:, 0], adc[:, 1] = a, b
        adc_a, adc_b = adc[:, 0], adc[:, 1]
    elif layout == 1:
        adc_a, adc_b = a.astype(np.int64), b.astype(np.int64)
    else:
        adc_a, adc_b = a.astype(np.uint16), b.astype(np.uint16)

    def offset():
        return int(rng.choice([0, -32768, 32767, rng.integers(-300, 301), rng.integers(-32768, 32768)]))

    def gain():
        return int(rng.choice([16384, 65535, 0, rng.integers(12000, 20000), rng.integers(0, 65536)]))

    if rng.random() < 0.5:
        s, c = (int(v) for v in sincos_q15(int(rng.integers(0, 1 << 32))))
    else:
        s, c = (int(rng.choice([-32768, 32767, 0, rng.integers(-32768, 32768)])) for _ in range(2))
    if n == 200 and rng.random() < 0.5:
        w = OS_W.copy()
    else:
        w = rng.choice(np.array([-32768, 32767, 0, *rng.integers(-32768, 32768, 4)]), n).astype(np.int64)
    keep = None
    if rng.random() < 0.4:
        keep = rng.random(n) < rng.choice([0.0, 0.8, 1.0, rng.random()])
    return (adc_a, adc_b, bits, offset(), offset(), gain(), gain(), s, c, w), keep


def _check_equal(args, keep, seed):
    got, d, q = window_dsp(*args, keep=keep)
    want, want_d, want_q = chain(*args, keep=keep)
    assert got == want, f"seed {seed}: {got} != {want}"
    assert d.dtype == np.int64 and q.dtype == np.int64, f"seed {seed}"
    assert np.array_equal(d, want_d) and np.array_equal(q, want_q), f"seed {seed}: Park currents differ"
    assert all(type(v) is int for v in dataclasses.astuple(got)), f"seed {seed}"


def test_equals_public_chain_on_random_windows():
    for k in range(N_WINDOWS):
        seed = BASE_SEED + k
        args, keep = _window(seed)
        _check_equal(args, keep, seed)


def test_saturation_thresholds_with_single_samples():
    # bits 16, gain 1.0, offset 0: current = code - 32768 exactly, so one-sample windows put i_a and
    # i_b anywhere; sweep i_a + 2 i_b across the Clarke saturation thresholds and the Park magnitude
    # across 2^30 (where a wrongly skipped saturation would show).
    one = np.ones(1, dtype=np.int64)
    seed = -1
    for s_target in (*range(-56770, -56740), *range(56740, 56770)):
        i_a = int(np.clip(s_target, -32768, 32767))
        i_b = (s_target - i_a) // 2
        for extra in (0, 1):
            a = np.array([i_a + 32768], dtype=np.int64)
            b = np.array([min(i_b + extra, 32767) + 32768], dtype=np.int64)
            _check_equal((a, b, 16, 0, 0, 16384, 16384, 0, 32767, one), None, seed)
    for i_a in (-32768, -32767, -32766, 32767, 32766):
        for s, c in ((0, -32768), (-32768, 0), (-32768, -32768), (32767, 32767), (23170, 23170),
                     (-23170, 23170), (0, 32767)):
            for i_b in (-32768, -16384, 0, 16384, 32767):
                a = np.array([i_a + 32768], dtype=np.int64)
                b = np.array([i_b + 32768], dtype=np.int64)
                _check_equal((a, b, 16, 0, 0, 16384, 16384, s, c, one), None, seed)


def test_typical_window_values():
    # 200 samples near mid-scale with the real weight pattern: no stage saturates (the fast path)
    rng = np.random.default_rng(BASE_SEED)
    adc = rng.integers(1900, 2200, (200, 3)).astype(np.int32)
    args = (adc[:, 0], adc[:, 1], 12, -37, 41, 16500, 16200, 12345, -23456, OS_W)
    _check_equal(args, None, BASE_SEED)
    _check_equal(args, rng.random(200) < 0.8, BASE_SEED)


def test_empty_window_and_all_blanked():
    e = np.zeros(0, dtype=np.int32)
    r, d, q = window_dsp(e, e, 12, 0, 0, 16384, 16384, 0, 32767, np.zeros(0, dtype=np.int64))
    assert r == WindowResult(0, 0, 0, 0, 0, 0) and d.size == 0 and q.size == 0
    codes = np.full(200, 2100, dtype=np.int64)
    r, d, q = window_dsp(codes, codes, 12, 0, 0, 16384, 16384, 0, 32767, OS_W, keep=np.zeros(200, bool))
    assert r == WindowResult(0, 0, 0, 0, 0, 0) and d.size == 200


def test_bad_codes_name_channel_and_value():
    good = np.full(8, 2048, dtype=np.int32)
    w = np.zeros(8, dtype=np.int64)
    bad = good.copy()
    bad[3] = 4096
    with pytest.raises(ValueError, match=r"adc_b\[3\] = 4096 is outside 0\.\.4095.*channel b"):
        window_dsp(good, bad, 12, 0, 0, 16384, 16384, 0, 32767, w)
    bad[3], bad[5] = 2048, -1
    with pytest.raises(ValueError, match=r"adc_a\[5\] = -1 .*channel a"):
        window_dsp(bad, good, 12, 0, 0, 16384, 16384, 0, 32767, w)
    with pytest.raises(ValueError, match=r"adc_a\[0\] = 65535"):
        window_dsp(np.full(8, 65535, dtype=np.uint16), good, 12, 0, 0, 16384, 16384, 0, 32767, w)
    # a code that is garbage although blanked is still reported: the ADC cannot produce it
    bad[5] = 5000
    with pytest.raises(ValueError, match=r"adc_a\[5\] = 5000"):
        window_dsp(bad, good, 12, 0, 0, 16384, 16384, 0, 32767, w, keep=np.arange(8) != 5)


def test_bad_arguments():
    c = np.full(4, 2048, dtype=np.int64)
    w = np.zeros(4, dtype=np.int64)
    with pytest.raises(ValueError, match="one length"):
        window_dsp(c, c[:3], 12, 0, 0, 16384, 16384, 0, 32767, w)
    with pytest.raises(ValueError, match="one length"):
        window_dsp(c, c, 12, 0, 0, 16384, 16384, 0, 32767, w[:3])
    with pytest.raises(ValueError, match="1-D"):
        window_dsp(c.reshape(2, 2), c.reshape(2, 2), 12, 0, 0, 16384, 16384, 0, 32767, w)
    with pytest.raises(TypeError):
        window_dsp(c.astype(float), c, 12, 0, 0, 16384, 16384, 0, 32767, w)
    with pytest.raises(ValueError, match=r"w\[2\] = 32768"):
        window_dsp(c, c, 12, 0, 0, 16384, 16384, 0, 32767, np.array([0, 0, 32768, 0]))
    with pytest.raises(ValueError, match="bits"):
        window_dsp(c, c, 17, 0, 0, 16384, 16384, 0, 32767, w)
    with pytest.raises(ValueError, match="offset_b"):
        window_dsp(c, c, 12, 0, 32768, 16384, 16384, 0, 32767, w)
    with pytest.raises(ValueError, match="gain_a"):
        window_dsp(c, c, 12, 0, 0, 65536, 16384, 0, 32767, w)
    with pytest.raises(ValueError, match="cos_q15"):
        window_dsp(c, c, 12, 0, 0, 16384, 16384, 0, 32768, w)
    with pytest.raises(ValueError, match="sin_q15"):
        window_dsp(c, c, 12, 0, 0, 16384, 16384, -32769, 0, w)
    with pytest.raises(TypeError, match="keep"):
        window_dsp(c, c, 12, 0, 0, 16384, 16384, 0, 32767, w, keep=np.ones(4, dtype=np.int64))
    with pytest.raises(ValueError, match="keep"):
        window_dsp(c, c, 12, 0, 0, 16384, 16384, 0, 32767, w, keep=np.ones(3, dtype=bool))
