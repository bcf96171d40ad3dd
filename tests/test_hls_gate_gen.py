"""HLS gate generator kernels (hls/src/hfi_gate_gen.cpp) against golden/fpga/gate_generator.py (C simulation).

* effective_dead over every u16 register value and several DEAD_MIN;
* whole runs of the carrier + ideal switch + hfi_gate_tick (csim_gate_gen_carrier_run) against the golden
  GateGenerator: the runs of cocotb_tests/tb_gate_gen.py (golden/testvectors/gate_gen.py: random compares
  with 0, H, > H and pulses of s shorter than / equal to D, enable toggles at bottoms and inside half
  periods, kill pulses, DEAD_TICKS changes while disabled) for both DEAD_MIN of the RTL sweep, plus runs
  at the default H = 10000; golden's edges (take_edges) are expanded to a mask per tick and compared
  with the kernel's mask at every tick, the switching instants (take_switch_ticks) with the ticks where
  s changes;
* hfi_gate_advance over random segments (lengths around D, 1, long) equals the same ticks of
  hfi_gate_tick: mask of the first tick, on_at of each leg and the state after the segment.
Seed: ``HFI_SEED`` if set, else a fresh one, printed.
"""

from __future__ import annotations

import numpy as np
import pytest

from golden.fpga.gate_generator import effective_dead_ticks
from golden.testvectors.gate_gen import (DEAD_MIN_SWEEP, golden_edges, new_stats, plan_run, random_dead_reg,
                                         random_half_reg)
from hfi.hls_build import csim

RUN_TICKS = 400_000
"""Ticks of random runs per DEAD_MIN."""
N_SEGMENTS = 100_000

ffi, lib = csim()


def ptr(ctype: str, arr: np.ndarray):
    return ffi.cast(ctype, ffi.from_buffer(arr))


@pytest.mark.parametrize("dead_min", [50, 3, 1, 65535])
def test_effective_dead_every_register(dead_min):
    regs = np.arange(1 << 16, dtype=np.uint16)
    mins = np.full(regs.size, dead_min, dtype=np.uint16)
    out = np.zeros_like(regs)
    lib.csim_gate_gen_effective_dead(regs.size, ptr("uint16_t *", regs), ptr("uint16_t *", mins), ptr("uint16_t *", out))
    want = np.array([effective_dead_ticks(int(r), dead_min) for r in regs], dtype=np.uint16)
    np.testing.assert_array_equal(out, want)


def mask_per_tick(ticks: np.ndarray, masks: np.ndarray, n: int) -> np.ndarray:
    """Golden edges (mask after each edge tick, from mask 0) expanded to the mask of every tick."""
    idx = np.searchsorted(ticks, np.arange(n), side="right") - 1
    return np.where(idx >= 0, masks[np.maximum(idx, 0)], 0) if ticks.size else np.zeros(n, dtype=np.int64)


def check_run(run, dead_min: int) -> int:
    """The run through the kernels and through golden; returns the number of edges compared and of
    switching instants at most D ticks after the previous one (pulses that must never turn on)."""
    n = run.end
    cmps = np.array([c for _, _, c in run.halves], dtype=np.uint16).ravel()
    en = run.en_per_tick()
    dead = run.dead_per_tick(dead_min)
    s, mask = np.zeros(n, np.uint8), np.zeros(n, np.uint8)
    lib.csim_gate_gen_carrier_run(run.n_halves, run.h, ptr("uint16_t *", cmps), ptr("uint8_t *", en),
                                  ptr("uint16_t *", dead), ptr("uint8_t *", s), ptr("uint8_t *", mask))
    ticks, masks, sw = golden_edges(run, dead_min)
    want = mask_per_tick(ticks, masks, n)
    bad = np.flatnonzero(mask != want)
    assert bad.size == 0, (f"tick {bad[0]}: HLS mask {mask[bad[0]]:#08b}, golden {want[bad[0]]:#08b} (H={run.h}, "
                           f"DEAD_TICKS={run.dead_reg}, DEAD_MIN={dead_min}, halves {run.halves[:4]}..., "
                           f"enable changes {run.en_changes})")
    sw_hls = np.flatnonzero(np.diff(s, prepend=np.uint8(0)) != 0)
    np.testing.assert_array_equal(sw_hls, np.unique(sw), err_msg="switching instants")
    return ticks.size, int(np.sum(np.diff(sw_hls) <= dead[sw_hls[1:]])) if sw_hls.size > 1 else 0


@pytest.mark.parametrize("dead_min", DEAD_MIN_SWEEP)
def test_runs(seed, dead_min):
    rng = np.random.default_rng(seed + dead_min)
    stats = new_stats()
    ticks = edges = 0
    while ticks < RUN_TICKS:
        h_reg = random_half_reg(rng)
        dead_reg = random_dead_reg(rng, h_reg, dead_min)
        p_en_mid = 0.0 if rng.random() < 0.6 else 0.2
        run = plan_run(rng, h_reg, dead_reg, dead_min, int(rng.integers(6, 40)), 0.25, 0.1, p_en_mid, stats)
        e, short = check_run(run, dead_min)
        edges += e
        stats["sw_gaps_le_D"] += short
        ticks += run.end
    print(f"{ticks} ticks, {edges} gate edges; {stats}")
    assert stats["kills"] > 0 and stats["cmp_gt_H"] > 0 and stats["cmp_0"] > 0 and stats["en_mid_half"] > 0
    assert stats["sw_gaps_le_D"] > 0


def test_runs_default_half(seed):
    """H = 10000 (5 kHz), D = 400 (4 us): a few periods with enable toggles and kills."""
    rng = np.random.default_rng(seed + 7)
    for _ in range(3):
        run = plan_run(rng, 10000, 400, 50, int(rng.integers(4, 7)), 0.5, 0.2, 0.2, new_stats())
        check_run(run, 50)


def tick_reference(s, en, dead, lens):
    """The segments expanded to ticks through hfi_gate_tick: per-tick masks and states."""
    n = int(lens.sum())
    rep = lambda a, dt: np.ascontiguousarray(np.repeat(a, lens), dtype=dt)  # noqa: E731
    st, et, dt_ = rep(s, np.uint8), rep(en, np.uint8), rep(dead, np.uint16)
    mask, el = np.zeros(n, np.uint8), np.zeros(3 * n, np.uint16)
    lib.csim_gate_gen_run(n, ptr("uint8_t *", st), ptr("uint8_t *", et), ptr("uint16_t *", dt_),
                          ptr("uint8_t *", mask), ptr("uint16_t *", el))
    return mask, el.reshape(n, 3)


def test_advance_equals_ticks(seed):
    rng = np.random.default_rng(seed + 11)
    k = N_SEGMENTS
    dead = np.where(rng.random(k) < 0.999, rng.integers(1, 60, k), rng.integers(1, 65536, k)).astype(np.uint16)
    # s and en mostly unchanged from the previous segment (no restart: the closed form's long runs)
    s = rng.integers(0, 8, k).astype(np.uint8)
    keep = rng.random(k) < 0.5
    for i in np.flatnonzero(keep)[np.flatnonzero(keep) > 0]:
        s[i] = s[i - 1]
    en = (rng.random(k) < 0.85).astype(np.uint8)
    kind = rng.integers(0, 4, k)
    near = np.maximum(dead.astype(np.int64) + rng.integers(-2, 3, k), 1)
    lens = np.select([kind == 0, kind == 1, kind == 2], [np.ones(k, np.int64), near, rng.integers(1, 200, k)],
                     rng.integers(1, 3 * dead.astype(np.int64) + 2)).astype(np.uint32)
    lens[rng.random(k) < 0.0005] = 70_000                   # beyond the el saturation at 65535
    mask_first, on_at, el = np.zeros(k, np.uint8), np.zeros(3 * k, np.uint32), np.zeros(3 * k, np.uint16)
    lib.csim_gate_gen_advance(k, ptr("uint8_t *", s), ptr("uint8_t *", en), ptr("uint16_t *", dead),
                              ptr("uint32_t *", lens), ptr("uint8_t *", mask_first), ptr("uint32_t *", on_at),
                              ptr("uint16_t *", el))
    mask_t, el_t = tick_reference(s, en, dead, lens)
    starts = np.concatenate([[0], np.cumsum(lens.astype(np.int64))[:-1]])
    ends = starts + lens - 1
    np.testing.assert_array_equal(mask_first, mask_t[starts], err_msg="mask of the first tick")
    np.testing.assert_array_equal(el.reshape(k, 3), el_t[ends], err_msg="state after the segment")
    seg = np.repeat(np.arange(k), lens)
    on_at = on_at.reshape(k, 3)
    for x in range(3):
        on_ticks = np.flatnonzero(mask_t & (3 << (2 * x)))
        first = np.full(k, -1, dtype=np.int64)
        segs, idx = np.unique(seg[on_ticks], return_index=True)
        first[segs] = on_ticks[idx]
        want = np.where(first >= 0, first - starts, lens)
        np.testing.assert_array_equal(on_at[:, x], want, err_msg=f"on_at of leg {x}")
        # once on, the leg stays on to the end of the segment (the closed form's assumption)
        on_count = np.bincount(seg[on_ticks], minlength=k)
        np.testing.assert_array_equal(on_count, lens - want, err_msg=f"leg {x} not on to the segment's end")
    print(f"{k} segments, {int(lens.sum())} ticks")
