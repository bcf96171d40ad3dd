"""Test vectors of the dead-time gate generator (golden/fpga/gate_generator.py), shared by
cocotb_tests/tb_gate_gen.py and tests/test_hls_gate_gen.py.

A run is a reset followed by ``n_halves`` carrier half periods of ``H`` ticks (:func:`plan_run`): the
compares latched at the start of each half (uniform, 0, H, above H, pulses of s shorter than / equal to
/ one longer than D), enable toggles at bottoms, kill pulses and enable toggles inside half periods, and
DEAD_TICKS changes while the outputs are disabled. :func:`golden_edges` replays a run on the golden
``GateGenerator`` (``add_half`` per half, split into pieces at the enable changes; ``set_enabled``) and
returns its gate edges and switching instants.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from golden.fpga.carrier import effective_half
from golden.fpga.gate_generator import GateGenerator, effective_dead_ticks

DEAD_MIN_SWEEP = (50, 3)
"""``DEAD_MIN`` synthesis parameters of the RTL sweep (cocotb_tests/test_gate_gen.py)."""


def new_stats() -> dict[str, int]:
    """Coverage counters filled by :func:`random_cmps` and :func:`plan_run`."""
    return {"sw_gaps_le_D": 0, "cmp_0": 0, "cmp_H": 0, "cmp_gt_H": 0, "dead_clamped": 0, "kills": 0,
            "en_mid_half": 0, "resets_while_on": 0}


def random_half_reg(rng: np.random.Generator) -> int:
    """``PWM_HALF`` of a run: mostly 512..600, sometimes anything in 0..1499 (runs as 512 below it)."""
    return int(rng.integers(512, 601)) if rng.random() < 0.7 else int(rng.integers(0, 1500))


def random_dead_reg(rng: np.random.Generator, h_reg: int, dead_min: int) -> int:
    """``DEAD_TICKS`` of a run: at or below ``DEAD_MIN`` (clamped), a few times it, or up to H/2."""
    r = rng.random()
    if r < 0.25:
        return int(rng.integers(0, dead_min + 1))
    if r < 0.5:
        return int(rng.integers(dead_min, 4 * dead_min + 10))
    return int(rng.integers(0, max(effective_half(h_reg) // 2, dead_min + 2)))


def random_cmps(rng: np.random.Generator, h: int, dead: int, stats: dict[str, int]) -> list[int]:
    """Compares of one half period: uniform, corners (0, H, > H) and short pulses (<= D) mixed."""
    out = []
    for _ in range(3):
        r = rng.random()
        if r < 0.08:
            v = 0
        elif r < 0.16:
            v = h
        elif r < 0.20:
            v = int(rng.integers(h + 1, 65536))            # above H: runs as H
        elif r < 0.40:
            v = int(rng.integers(1, dead + 2))             # short high pulse (<= D or D + 1)
        elif r < 0.55:
            v = h - int(rng.integers(0, dead + 2))         # short low pulse
        else:
            v = int(rng.integers(0, h + 1))
        out.append(max(0, v))
        stats["cmp_0"] += v == 0
        stats["cmp_H"] += v == h
        stats["cmp_gt_H"] += v > h
    return out


def pieces(start: int, h: int, rising: bool, cmps, splits):
    """Split the half [start, start + h) at ``splits`` into add_half pieces with the same ideal signal."""
    bounds = [start] + sorted(s for s in splits if start < s < start + h) + [start + h]
    out = []
    for p0, p1 in zip(bounds[:-1], bounds[1:]):
        if rising:      # s = 1 on [start, start + cmp)
            pc = [min(max(start + c - p0, 0), p1 - p0) for c in cmps]
        else:           # s = 1 on [start + h - cmp, start + h)
            pc = [min(max(p1 - (start + h - c), 0), p1 - p0) for c in cmps]
        out.append((p0, p1 - p0, rising, pc))
    return out


@dataclass
class Run:
    """One planned run (ticks count from tick 0, the first bottom after the reset)."""

    h: int                                  # effective half period
    dead_reg: int                           # DEAD_TICKS during the reset
    n_halves: int
    en0: int                                # enable during the reset and tick 0
    halves: list = field(default_factory=list)      # (latch tick, rising, compares as drawn)
    cmp_writes: list = field(default_factory=list)  # tick at which a bench writes the compares of half i >= 1
    events: list = field(default_factory=list)      # (tick, "enable" | "kill", new level), sorted
    en_changes: list = field(default_factory=list)  # (tick, enable & ~kill) at every change, from (0, en0)
    dead_changes: list = field(default_factory=list)  # (tick, DEAD_TICKS) written while disabled

    @property
    def end(self) -> int:
        return self.n_halves * self.h

    def en_per_tick(self) -> np.ndarray:
        """enable & ~kill of every tick (uint8)."""
        en = np.zeros(self.end, dtype=np.uint8)
        for (t, v), (t_next, _) in zip(self.en_changes, self.en_changes[1:] + [(self.end, None)]):
            en[t:t_next] = v
        return en

    def dead_per_tick(self, dead_min: int) -> np.ndarray:
        """Effective dead time of every tick (uint16)."""
        dead = np.full(self.end, effective_dead_ticks(self.dead_reg, dead_min), dtype=np.uint16)
        for t, reg in self.dead_changes:
            dead[t:] = effective_dead_ticks(reg, dead_min)
        return dead


def plan_run(rng: np.random.Generator, h_reg: int, dead_reg: int, dead_min: int, n_halves: int, p_en: float,
             p_kill: float, p_en_mid: float, stats: dict[str, int]) -> Run:
    """A random run: compares per half, enable toggles at bottoms (probability ``p_en``), inside each
    half at most one of a kill pulse (>= 2 ticks, ``p_kill``) or an enable toggle (``p_en_mid``), both
    >= 2 ticks from the half's ends (the golden model's pieces must be >= 2 ticks long); DEAD_TICKS
    changes one tick after a disable that lasts >= 4 ticks (the golden model fixes D when it schedules a
    turn-on, the RTL reads it live: identical while no turn-on is pending)."""
    h = effective_half(h_reg)
    dead = effective_dead_ticks(dead_reg, dead_min)
    stats["dead_clamped"] += dead_reg < dead_min
    run = Run(h=h, dead_reg=dead_reg, n_halves=n_halves, en0=int(rng.random() < 0.7))
    run.halves.append((0, True, random_cmps(rng, h, dead, stats)))
    events = []
    for i in range(1, n_halves):
        t_latch = i * h
        rising = i % 2 == 0
        run.halves.append((t_latch, rising, random_cmps(rng, h, dead, stats)))
        # written at a random tick before the latch; a bottom set may be written in the latch tick itself,
        # a top set at the latest one tick before it (rtl/hfi_gate_gen.v registers ct >= H the tick before)
        run.cmp_writes.append(t_latch - int(rng.integers(0 if rising else 1, h)))
        if rising and rng.random() < p_en:
            events.append((t_latch, "toggle", None))
    for i in range(n_halves):
        t0 = i * h
        r = rng.random()
        if r < p_kill:
            k1 = t0 + int(rng.integers(2, h - 4))
            k2 = min(k1 + int(rng.integers(2, 2 * dead + 4)), t0 + h - 2)
            events += [(k1, "kill", 1), (k2, "kill", 0)]
            stats["kills"] += 1
        elif r < p_kill + p_en_mid:
            events.append((t0 + int(rng.integers(2, h - 1)), "toggle", None))
            stats["en_mid_half"] += 1
    events.sort(key=lambda e: e[0])
    enable, kill = run.en0, 0
    run.en_changes = [(0, run.en0)]
    for t, kind, val in events:
        if kind == "toggle":
            enable ^= 1
            run.events.append((t, "enable", enable))
        else:
            kill = val
            run.events.append((t, "kill", kill))
        eff = enable & (1 - kill)
        if eff != run.en_changes[-1][1]:
            run.en_changes.append((t, eff))
    for (t, v), (t_next, _) in zip(run.en_changes, run.en_changes[1:] + [(run.end, None)]):
        if v == 0 and t_next - t >= 4 and rng.random() < 0.5:
            reg = int(rng.integers(0, 3 * dead_min + 200))
            run.dead_changes.append((t + 1, reg))
            stats["dead_clamped"] += reg < dead_min
    return run


def golden_edges(run: Run, dead_min: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The run on the golden GateGenerator: (edge ticks, masks after them, switching instants)."""
    gen = GateGenerator(run.dead_reg, dead_min)
    en_at = dict(run.en_changes)
    splits = sorted(en_at)
    dq = sorted(run.dead_changes)
    for start, rising, c in run.halves:
        cg = [min(x, run.h) for x in c]           # a compare above H runs as H
        for p0, plen, prising, pc in pieces(start, run.h, rising, cg, splits):
            while dq and dq[0][0] <= p0:          # D written while disabled: used from the next enable
                gen.dead = effective_dead_ticks(dq.pop(0)[1], dead_min)
            if p0 in en_at:
                gen.set_enabled(p0, bool(en_at[p0]))
            gen.add_half(p0, plen, prising, pc)
    ticks, masks = gen.take_edges(run.end)
    return ticks, masks, gen.take_switch_ticks(run.end)
