#!/usr/bin/env python3
"""Where the firmware's CPU clocks go: a program-counter profile of the ``rtl`` co-simulation.

Runs a scenario on the Verilated hfi_soc built with the profile (sim/soc_sim.h, ``SOC_PROF_*``): every
CPU clock counts to the instruction in the core's last pipeline stage (a stall counts to the instruction
that retired before it), every instruction-bus beat to the word it refills. Maps the counts to the
firmware's functions (``nm`` of out/firmware/hfi_fw.elf) and prints, per function, CPU clocks per control
period, their share of the handler's clocks, and instruction-cache lines refilled per period (8 beats
each), largest first. The idle loop (``main``) is shown apart.

    python scripts/fw_profile.py [--scenario FILE] [--duration 0.1] [--top 25]
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import shutil
import subprocess
import sys

import numpy as np

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from golden.scenario import ScenarioError, load_scenario  # noqa: E402
from hfi import soc_platform  # noqa: E402
from hfi.rtl_backend import FW_OUT, RtlBackendError, RtlClosedLoop  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
LINE_WORDS = 8
"""Words per instruction-cache line (32 bytes; docs/soc.md)."""


def functions(elf: str) -> list[tuple[int, int, str]]:
    """(start, end, name) of the code symbols of ``elf``, by address (end: the next symbol's start when
    ``nm`` gives no size)."""
    nm = shutil.which("riscv64-unknown-elf-nm") or "riscv64-unknown-elf-nm"
    out = subprocess.run([nm, "-S", "-n", elf], capture_output=True, text=True, check=True).stdout
    syms = []
    for line in out.splitlines():
        parts = line.split()
        if len(parts) == 4 and parts[2] in "tTW":
            start = int(parts[0], 16)
            syms.append((start, start + int(parts[1], 16), parts[3]))
        elif len(parts) == 3 and parts[1] in "tT":
            syms.append((int(parts[0], 16), -1, parts[2]))
    syms.sort()
    return [(a, b if b >= 0 else (syms[i + 1][0] if i + 1 < len(syms) else a + 4), n)
            for i, (a, b, n) in enumerate(syms)]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenario", default=os.path.join(HERE, "..", "scenarios", "fullload_start.toml"))
    ap.add_argument("--duration", type=float, default=0.1, help="simulated seconds (default 0.1)")
    ap.add_argument("--top", type=int, default=25, help="functions listed (default 25)")
    args = ap.parse_args(argv)
    if not args.duration > 0 or args.top < 1:
        print("fw_profile: --duration must be > 0 and --top >= 1", file=sys.stderr)
        return 1
    try:
        sc = dataclasses.replace(load_scenario(args.scenario), duration=args.duration)
        loop = RtlClosedLoop(sc)
        res = loop.run(progress=False, profile=True)
    except (ScenarioError, RtlBackendError, ValueError) as exc:
        print(f"fw_profile: {exc}", file=sys.stderr)
        return 1
    cycles, fetch = loop.profile["cycles"], loop.profile["fetch"]
    n_win = len(res.t)
    base = soc_platform.RAM_BASE
    rows = []
    for start, end, name in functions(str(FW_OUT / "hfi_fw.elf")):
        a, b = (start - base) // 4, max((end - base) // 4, (start - base) // 4 + 1)
        c, f = int(cycles[a:b].sum()), int(fetch[a:b].sum())
        if c or f:
            rows.append((name, c / n_win, f / LINE_WORDS / n_win, end - start))
    idle = sum(r[1] for r in rows if r[0] == "main")
    busy = sum(r[1] for r in rows) - idle
    soc = res.soc
    print(f"scenario {sc.name}: {n_win} periods; firmware step (handler) {soc['fw_cycles_mean']} CPU clocks mean, "
          f"{soc['fw_cycles_max']} worst; profiled outside the idle loop: {busy:.0f} per period")
    print(f"{'function':28s} {'clocks/period':>13s} {'share':>7s} {'lines/period':>12s} {'bytes':>6s}")
    for name, c, f, size in sorted((r for r in rows if r[0] != "main"), key=lambda r: -r[1])[:args.top]:
        print(f"{name:28s} {c:13.1f} {100 * c / busy:6.1f}% {f:12.1f} {size:6d}")
    lines = sum(r[2] for r in rows if r[0] != "main")
    print(f"{'(all but main)':28s} {busy:13.1f} {100.0:6.1f}% {lines:12.1f}")
    print(f"{'main (idle loop)':28s} {idle:13.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
