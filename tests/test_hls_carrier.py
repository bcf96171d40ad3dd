"""HLS carrier kernel (hls/src/hfi_carrier.cpp) against golden/fpga/carrier.py, bit for bit (C simulation).

effective_half over every u16 register value; the counter over every phase of the directed and random
half periods of golden/testvectors/carrier.py (the draws of cocotb_tests/tb_carrier.py); hfi_carrier_tick
over whole tick sequences from reset with a new half period at every bottom (random, 512 floor, the
default H = 10000 and full scale 65534), phase, counter and strobes checked at every tick.
Seed: ``HFI_SEED`` if set, else a fresh one, printed.
"""

from __future__ import annotations

import numpy as np

from golden.fpga.carrier import counter, effective_half
from golden.testvectors.carrier import DIRECTED_HALF_REGS, random_half_reg
from hfi.hls_build import csim

N_PERIODS = 300
"""Random periods of the tick sequence (each 1024..2798 ticks)."""

ffi, lib = csim()


def ptr(ctype: str, arr: np.ndarray):
    return ffi.cast(ctype, ffi.from_buffer(arr))


def test_effective_half_every_register():
    regs = np.arange(1 << 16, dtype=np.uint16)
    out = np.zeros_like(regs)
    lib.csim_carrier_effective_half(regs.size, ptr("uint16_t *", regs), ptr("uint16_t *", out))
    want = np.array([effective_half(int(r)) for r in regs], dtype=np.uint16)
    np.testing.assert_array_equal(out, want)


def test_counter_every_phase(seed):
    rng = np.random.default_rng(seed)
    halves = {effective_half(r) for r in DIRECTED_HALF_REGS} | {effective_half(random_half_reg(rng))
                                                                  for _ in range(50)}
    for h in sorted(halves):
        phase = np.arange(2 * h, dtype=np.uint32)
        half = np.full(phase.size, h, dtype=np.uint16)
        out = np.zeros(phase.size, dtype=np.uint16)
        lib.csim_carrier_counter(phase.size, ptr("uint32_t *", phase), ptr("uint16_t *", half),
                                 ptr("uint16_t *", out))
        np.testing.assert_array_equal(out, counter(phase.astype(np.int64), h), err_msg=f"H={h}")


def test_tick_sequence(seed):
    """Whole periods from reset, H changing at bottoms: phase, counter, rising/bottom/top/boundary per tick."""
    rng = np.random.default_rng(seed + 1)
    regs = [random_half_reg(rng) for _ in range(N_PERIODS)] + [10000, 10000, 65535, 511]
    regs = [regs[i] for i in rng.permutation(len(regs))]
    halves = [effective_half(r) for r in regs]
    phase_want = np.concatenate([np.arange(2 * h, dtype=np.int64) for h in halves])
    half_t = np.concatenate([np.full(2 * h, h, dtype=np.uint16) for h in halves])
    n = phase_want.size
    phase, cnt, flags = np.zeros(n, np.uint32), np.zeros(n, np.uint16), np.zeros(n, np.uint8)
    lib.csim_carrier_run(n, ptr("uint16_t *", half_t), ptr("uint32_t *", phase), ptr("uint16_t *", cnt),
                         ptr("uint8_t *", flags))
    h64 = half_t.astype(np.int64)
    np.testing.assert_array_equal(phase, phase_want)
    np.testing.assert_array_equal(cnt, np.where(phase_want < h64, phase_want, 2 * h64 - phase_want))
    want_flags = ((phase_want < h64) * 1 | (phase_want == 0) * 2 | (phase_want == h64) * 4
                  | (phase_want == h64 // 2) * 8)
    np.testing.assert_array_equal(flags, want_flags)
    for h in {512, 10000, 65534}:                 # golden counter on the directed periods as well
        sel = half_t == h
        np.testing.assert_array_equal(cnt[sel], counter(phase_want[sel], h))
    print(f"{n} ticks, {len(halves)} periods")
