#!/usr/bin/env python3
"""The order of the firmware's last code group (link.ld ``/* 003 */``) for the 16 KiB direct-mapped instruction cache.

The 000 and 002 steps fit the cache with the groups before it (tests/test_fw_layout.py); the 003 step executes about
17 KiB of code per period, so some of its lines must share cache lines with the shared group's, and which ones decides
how many are refilled every period (docs/soc.md, "The instruction cache"). This tool measures and chooses:

1. builds the image (its link map, ``out/firmware/hfi_fw.map``) and runs the 003 drive on the rtl backend with the
   program-counter profile (scripts/fw_profile.py), two stretches (:data:`STRETCHES`):
   ``scenarios/varatharajan2020_torquestep.toml`` at its own 10 kHz (start-up, RUN and the 2 p.u. torque step at
   0.8 s) and the fusion band of ``varatharajan2020_speedrange.toml`` (0.53-0.59 s, where APP runs): CPU clocks per
   period of every instruction word in each (until 2026-11-30 the drive's step did not fit its period, and the tool
   ran a copy slowed to 2 kHz, whose start-up and cache use differ from the real drive's; until 2026-12-01 it
   weighed the torque step alone, where APP never runs, so APP's lines were placed blindly);
2. takes the input sections from the first one of the ``/* 003 */`` group to the end of ``.text`` (the 003 method's
   functions and the code no step runs: start-up, sync, turn, the flying start, the library's division) and searches
   their order (moves of one section and swaps of two, from the present order and from ``--restarts`` shuffled ones,
   fixed seed) for the least sum of both stretches' :func:`conflict_cost` and the :func:`eviction_cost` of the first
   step in RUN (:data:`ENTRIES`: its lines the start-up modes evicted since the boot's warm-up), with ``.text`` no
   longer than it was;
3. prints the order with each section's address and cache offset; ``--write`` puts it into link.ld's ``003`` group,
   builds and profiles again, and keeps it only if the measured refills (summed over the stretches and the entry
   step) are fewer (the cost ranks orders only roughly: docs/soc.md, "The 003 group's order"); otherwise link.ld is put back.

    python scripts/fw_layout.py [--duration 1.0] [--restarts 8] [--seed 1] [--weights W...] [--write]

``--weights`` (one per stretch, then one per entry step; default all 1) weighs each number in the cost and in the
keep test: the step whose clocks are nearest the budget can count more (2026-12-01: the fusion band).
"""

from __future__ import annotations

import argparse
import dataclasses
import random
import re
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from hfi import soc_platform  # noqa: E402
from hfi.rtl_backend import FW_OUT, RtlBackendError, build_firmware  # noqa: E402
from golden.scenario import load_scenario  # noqa: E402

sys.path.insert(0, str(ROOT / "scripts"))
import fw_profile  # noqa: E402

LINK_LD = ROOT / "firmware" / "link.ld"
LINE_BYTES = 32
"""Bytes per instruction-cache line (docs/soc.md)."""
SETS = soc_platform.CPU_ICACHE_BYTES // LINE_BYTES
LINE_CLOCKS = 8.0
"""A line that runs every period takes at least this many clocks (8 instructions): a line's clocks per period over
it, at most 1, stands for the share of periods in which the line runs."""
FUNCTION_ALIGN = 64
"""-falign-functions of the default image (firmware/Makefile); the library's and the unlikely sections keep 4."""
SECTION_RE = re.compile(r"^ (\.text[\w.]*)(?:\s+(0x[0-9a-f]+)\s+(0x[0-9a-f]+)\s+(\S+))?\s*$")
NEXT_RE = re.compile(r"^\s+(0x[0-9a-f]+)\s+(0x[0-9a-f]+)\s+(\S+)")


@dataclass(frozen=True)
class Section:
    """One input section of ``.text`` in the link map: its name, where it was, its size, the object it came from."""

    name: str
    addr: int
    size: int
    source: str

    @property
    def align(self) -> int:
        """Its alignment: the function alignment for the C sections that had it, else a word."""
        aligned = self.addr % FUNCTION_ALIGN == 0
        return FUNCTION_ALIGN if aligned and "libgcc" not in self.source and ".unlikely." not in self.name else 4

    def link_line(self) -> str:
        """Its line in link.ld."""
        if "libgcc" in self.source:
            obj = re.search(r"\((\w+\.o)\)", self.source)
            if obj is None:
                raise ValueError(f"cannot name the library object of {self.name} ({self.source})")
            return f"*libgcc.a:{obj.group(1)}(.text .text.*)"
        return f"*({self.name})"


def map_sections(path: Path) -> list[Section]:
    """The non-empty ``.text*`` input sections of the link map ``path``, by address."""
    lines = path.read_text().splitlines()
    out = []
    for i, line in enumerate(lines):
        m = SECTION_RE.match(line)
        if not m:
            continue
        name, addr, size, src = m.groups()
        if addr is None:
            nxt = NEXT_RE.match(lines[i + 1]) if i + 1 < len(lines) else None
            if nxt is None:
                continue
            addr, size, src = nxt.groups()
        if int(size, 16):
            out.append(Section(name, int(addr, 16), int(size, 16), src))
    return sorted(out, key=lambda s: s.addr)


def place(order: list[Section], start: int) -> tuple[list[int], int]:
    """Addresses of ``order`` laid out from ``start`` with each section's alignment, and the end."""
    addrs, a = [], start
    for s in order:
        a = -(-a // s.align) * s.align
        addrs.append(a)
        a += s.size
    return addrs, a


def line_clocks(sections: list[Section], addrs: list[int], clocks: np.ndarray) -> dict[int, float]:
    """Clocks per period of every cache line that runs, for ``sections`` placed at ``addrs`` (``clocks``: per
    instruction word of the profiled image, indexed by its offset in the RAM / 4)."""
    out: dict[int, float] = {}
    base = soc_platform.RAM_BASE
    for s, a in zip(sections, addrs):
        w = clocks[(s.addr - base) // 4:(s.addr - base + s.size) // 4]
        for k in np.flatnonzero(w):
            line = (a + 4 * int(k)) // LINE_BYTES
            out[line] = out.get(line, 0.0) + float(w[k])
    return out


def conflict_cost(lines: dict[int, float]) -> float:
    """Expected refills per period: in every cache set, the shares of the lines that run in it (clocks over
    :data:`LINE_CLOCKS`, at most 1) less the largest one (a direct-mapped set keeps one line; a pair that both run
    every period costs 1, a line that runs every period against one that runs in half of them 0.5)."""
    sets: dict[int, list[float]] = {}
    for line, c in lines.items():
        sets.setdefault(line % SETS, []).append(min(1.0, c / LINE_CLOCKS))
    return sum(sum(v) - max(v) for v in sets.values() if len(v) > 1)


def eviction_cost(before: dict[int, float], step: dict[int, float]) -> float:
    """Expected refills of a step whose lines did not run in the stretch ``before`` it (lines -> clocks, as
    :func:`line_clocks`): each such line of ``step`` (its share, as in :func:`conflict_cost`) whose cache set a line
    of ``before`` used (the start-up modes evict the RUN path's code, warmed at boot, before the first step in RUN)."""
    used = {line % SETS for line in before}
    return sum(min(1.0, c / LINE_CLOCKS) for line, c in step.items() if line not in before and line % SETS in used)


def search(head: list[Section], tail: list[Section], profiles: list[np.ndarray], restarts: int, seed: int,
           entries: list[tuple[np.ndarray, np.ndarray]] = (), progress: bool = True,
           weights: tuple[float, ...] | None = None) -> tuple[list[Section], float, float]:
    """The order of ``tail`` (placed from its first section's address, after the fixed ``head``) with the least
    (``weights``-weighted: one per profile, then one per entry; default all 1) sum
    over ``profiles`` (clocks per period of every instruction word, one array per profiled stretch) of
    :func:`conflict_cost` plus, for each of ``entries`` (the stretch before a step and the step), the step's
    :func:`eviction_cost`, found by moving one section, or swapping two, at a time until no such change lowers it (a
    swap keeps the sections between them in place where a move shifts them all), from the present order
    and ``restarts`` shuffled ones; never longer than the present. Returns the order, its cost and the present's."""
    arrays = list(profiles) + [a for pair in entries for a in pair]
    weights = tuple(weights) if weights is not None else (1.0,) * (len(profiles) + len(entries))
    if len(weights) != len(profiles) + len(entries):
        raise ValueError(f"{len(weights)} weights for {len(profiles)} stretches and {len(entries)} entry steps")
    fixed = [line_clocks(head, [s.addr for s in head], clocks) for clocks in arrays]
    start = tail[0].addr
    _, end0 = place(tail, start)

    def cost(order: list[Section]) -> tuple[float, int]:
        addrs, end = place(order, start)
        maps = []
        for clocks, lines0 in zip(arrays, fixed):
            lines = dict(lines0)
            for line, c in line_clocks(order, addrs, clocks).items():
                lines[line] = lines.get(line, 0.0) + c
            maps.append(lines)
        total = sum(w * conflict_cost(m) for w, m in zip(weights, maps[:len(profiles)]))
        rest = maps[len(profiles):]
        total += sum(weights[len(profiles) + k] * eviction_cost(rest[2 * k], rest[2 * k + 1])
                     for k in range(len(entries)))
        return total, end

    c0, _ = cost(tail)
    rng = random.Random(seed)
    best, best_cost = list(tail), c0
    for r in range(restarts + 1):
        cur = list(tail) if r == 0 else rng.sample(tail, len(tail))
        cc, _ = cost(cur)
        improved = True
        while improved:
            improved = False
            for i in range(len(cur)):
                for j in range(len(cur)):
                    if i == j:
                        continue
                    for swap in (False, True):
                        if swap and j < i:
                            continue
                        cand = list(cur)
                        if swap:
                            cand[i], cand[j] = cand[j], cand[i]
                        else:
                            cand.insert(j, cand.pop(i))
                        c, end = cost(cand)
                        if c < cc - 1e-9 and end <= end0:
                            cur, cc, improved = cand, c, True
        if cc < best_cost:
            best, best_cost = cur, cc
        if progress:
            print(f"fw_layout: start {r} of {restarts}: cost {cc:.1f} (best {best_cost:.1f}, present {c0:.1f})",
                  flush=True)
    return best, best_cost, c0


def group_bounds(text: str) -> tuple[int, int]:
    """Character range of the ``/* 003 */`` group's section lines in link.ld (up to the catch-all line)."""
    start = text.index("        /* 003 */\n") + len("        /* 003 */\n")
    return start, text.index("        *(.text .text.*)", start)


def first_listed(text: str, sections: list[Section]) -> Section:
    """The first section of the ``/* 003 */`` group that the image has."""
    a, b = group_bounds(text)
    by_line = {s.link_line(): s for s in sections}
    for line in text[a:b].splitlines():
        if line.strip() in by_line:
            return by_line[line.strip()]
    raise ValueError("link.ld: no section of the /* 003 */ group is in the image")


STRETCHES = ((ROOT / "scenarios" / "varatharajan2020_torquestep.toml", 0.0, None),
             (ROOT / "scenarios" / "varatharajan2020_speedrange.toml", 0.53, 0.59))
"""The stretches of the 003 drive whose steps the 003 group's order is chosen for, each (scenario, from, to) in
simulated seconds (``None``: ``--duration``): the torque step (start-up, RUN at standstill, the 2 p.u. step: the low
speed estimator alone) and the speed range's fusion band (both estimators, APP and the fusion weight's divide;
docs/soc.md, "The fusion band")."""
ENTRIES = ((ROOT / "scenarios" / "varatharajan2020_torquestep.toml", 0.01, 0.25),)
"""Single steps whose code the steps before them evicted, each (scenario, from, at): the step at ``at`` s against
the stretch from ``from`` (after the boot's warm-up) to ``at``: the torque step's first step in RUN."""


def profile(duration: float) -> tuple[list[np.ndarray], list[float], list[tuple[np.ndarray, np.ndarray]]]:
    """Build the image and profile every stretch of :data:`STRETCHES` (its ``to`` ``None`` -> ``duration``) and
    every step of :data:`ENTRIES`: per stretch, CPU clocks per period of every instruction word and
    instruction-cache lines refilled per period (an entry's step: its refills, one number after the stretches'); per
    entry, the clocks of the stretch before it and of the step."""
    build_firmware()
    clocks, refills, entries = [], [], []
    for path, t0, t1 in STRETCHES:
        sc = dataclasses.replace(load_scenario(path), duration=t1 if t1 is not None else duration)
        prof, n, res = fw_profile.profile_stretch(sc, t0)
        clocks.append(prof["cycles"] / n)
        refills.append(float(prof["fetch"].sum()) / (LINE_BYTES // 4) / n)
        print(f"fw_layout: {sc.name} from {t0:g} s to {sc.duration:g} s, {n} periods at {sc.pwm.f_sw:.0f} Hz: step "
              f"{res.soc['fw_cycles_mean']:.0f} CPU clocks mean, {res.soc['fw_cycles_max']} worst over the whole run, "
              f"{refills[-1]:.1f} lines refilled per period in the stretch", flush=True)
    for path, t0, t1 in ENTRIES:
        sc = load_scenario(path)
        before, n, _ = fw_profile.profile_stretch(dataclasses.replace(sc, duration=t1), t0)
        step, m, res = fw_profile.profile_stretch(dataclasses.replace(sc, duration=t1 + 1.0 / sc.pwm.f_sw), t1)
        entries.append((before["cycles"] / n, step["cycles"] / m))
        refills.append(float(step["fetch"].sum()) / (LINE_BYTES // 4) / m)
        print(f"fw_layout: {sc.name}, the step at {t1:g} s: {refills[-1]:.1f} lines refilled", flush=True)
    return clocks, refills, entries


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--duration", type=float, default=1.0, help="simulated seconds profiled (default 1.0)")
    ap.add_argument("--restarts", type=int, default=8, help="shuffled starting orders (default 8)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--weights", type=float, nargs="+", default=None, metavar="W",
                    help="one weight per stretch, then per entry step (default all 1)")
    ap.add_argument("--write", action="store_true",
                    help="write the order into link.ld's 003 group, measure it, and keep it only if it refills fewer "
                         "lines than the present order")
    args = ap.parse_args(argv)
    if args.weights is not None and (len(args.weights) != len(STRETCHES) + len(ENTRIES) or min(args.weights) < 0):
        print(f"fw_layout: --weights takes {len(STRETCHES) + len(ENTRIES)} numbers >= 0 (the stretches, then the entry "
              "steps)", file=sys.stderr)
        return 1
    if not args.duration > 0 or args.restarts < 0:
        print("fw_layout: --duration must be > 0 and --restarts >= 0", file=sys.stderr)
        return 1
    try:
        clocks, refills0, entries = profile(args.duration)
        sections = map_sections(FW_OUT / "hfi_fw.map")
        text = LINK_LD.read_text()
        first = first_listed(text, sections)
        head = [s for s in sections if s.addr < first.addr]
        tail = [s for s in sections if s.addr >= first.addr]
        order, cost, cost0 = search(head, tail, clocks, args.restarts, args.seed, entries, weights=args.weights)
        addrs, end = place(order, first.addr)
        print(f"{'section':40s} {'address':>8s} {'cache':>6s} {'clocks/period':>13s}")
        for s, a in zip(order, addrs):
            w0 = (s.addr - soc_platform.RAM_BASE) // 4
            c = float(sum(k[w0:w0 + s.size // 4].sum() for k in clocks))
            print(f"{s.name + (' ' + s.source.split('/')[-1] if 'libgcc' in s.source else ''):40s} {a:8x} "
                  f"{a % soc_platform.CPU_ICACHE_BYTES:6x} {c:13.1f}")
        print(f"fw_layout: expected refills per period {cost:.1f} (present order {cost0:.1f}), .text ends at {end:#x}")
        if args.write:
            a, b = group_bounds(text)
            LINK_LD.write_text(text[:a] + "".join(f"        {s.link_line()}\n" for s in order) + text[b:])
            try:
                _, refills, _ = profile(args.duration)
            except (RtlBackendError, ValueError, OSError):
                LINK_LD.write_text(text)
                raise
            was, now = " + ".join(f"{r:.1f}" for r in refills0), " + ".join(f"{r:.1f}" for r in refills)
            w = args.weights or (1.0,) * len(refills)
            if sum(a * r for a, r in zip(w, refills)) < sum(a * r for a, r in zip(w, refills0)):
                print(f"fw_layout: kept in {LINK_LD.relative_to(ROOT)}: {was} -> {now} lines refilled per period "
                      "(one number per stretch)")
            else:
                LINK_LD.write_text(text)
                build_firmware()
                print(f"fw_layout: not kept ({now} lines refilled per period, the present order {was}); "
                      f"{LINK_LD.relative_to(ROOT)} unchanged")
    except (RtlBackendError, ValueError, OSError) as exc:
        print(f"fw_layout: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
