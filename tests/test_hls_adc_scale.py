"""HLS kernel hfi_adc_scale (hls/src/hfi_adc_scale.cpp) against golden.fpga.adc_scale.adc_to_current
(spec 3.1), native C simulation.

Vectors: golden/testvectors/adc_scale.py, the same directed and random vectors as the RTL testbench
cocotb_tests/tb_adc_scale.py, at the same ADC resolutions. Random inputs use
``numpy.random.default_rng(seed + k)``; the seed is ``HFI_SEED`` if set, else a fresh one, and is printed.
"""

from __future__ import annotations

import numpy as np
import pytest

from golden.fpga.adc_scale import adc_to_current
from golden.testvectors import adc_scale as testvectors
from hfi import hls_build

BITS = (1, 8, 12, 14, 16)          # cocotb_tests/test_adc_scale.py sweep
DEFAULT_BITS = 12
N_RANDOM = {12: 100_000}           # random vectors per resolution (default resolution: the most)
N_RANDOM_SWEEP = 20_000


def _hls(bits: int, code: np.ndarray, offset: np.ndarray, gain: np.ndarray) -> np.ndarray:
    """hfi_adc_scale of every (code, offset, gain) row, through csim_adc_scale."""
    ffi, lib = hls_build.csim()
    code = np.ascontiguousarray(code, dtype=np.uint16)
    offset = np.ascontiguousarray(offset, dtype=np.int16)
    gain = np.ascontiguousarray(gain, dtype=np.uint16)
    out = np.empty(len(code), dtype=np.int16)
    lib.csim_adc_scale(len(code), bits, ffi.from_buffer("uint16_t[]", code), ffi.from_buffer("int16_t[]", offset),
                       ffi.from_buffer("uint16_t[]", gain), ffi.from_buffer("int16_t[]", out))
    return out.astype(np.int64)


def _check(vectors: np.ndarray, bits: int, label: str) -> int:
    """Both channels of every vector (code, offset, gain columns 0/2/4 and 1/3/5) against the golden
    adc_to_current; returns the number of saturated results."""
    code = np.concatenate([vectors[:, 0], vectors[:, 1]])
    offset = np.concatenate([vectors[:, 2], vectors[:, 3]])
    gain = np.concatenate([vectors[:, 4], vectors[:, 5]])
    got = _hls(bits, code, offset, gain)
    exp = np.array([adc_to_current(c, bits, o, g) for c, o, g in zip(code.tolist(), offset.tolist(), gain.tolist())],
                   dtype=np.int64)
    bad = np.flatnonzero(got != exp)
    assert bad.size == 0, (f"{label}, ADC_BITS={bits}: {bad.size} mismatches, first (code, offset, gain) = "
                           f"{(code[bad[0]], offset[bad[0]], gain[bad[0]])}: HLS {got[bad[0]]}, golden {exp[bad[0]]}")
    return int(np.count_nonzero((exp == -32768) | (exp == 32767)))


@pytest.mark.parametrize("bits", BITS)
def test_directed(bits):
    sat = _check(testvectors.directed_vectors(bits), bits, "directed")
    assert sat > 0, "the directed vectors never saturate"


@pytest.mark.parametrize("bits", BITS)
def test_random(bits, seed):
    rng = np.random.default_rng(seed + bits)
    n = N_RANDOM.get(bits, N_RANDOM_SWEEP)
    sat = _check(testvectors.random_vectors(rng, n, bits), bits, f"random (HFI_SEED={seed})")
    print(f"ADC_BITS={bits}: {n} random vectors (x 2 channels), {sat} saturated results")
    assert sat > 0
