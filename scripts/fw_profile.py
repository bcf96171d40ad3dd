#!/usr/bin/env python3
"""Where the firmware's CPU clocks go: a program-counter profile of the ``rtl`` co-simulation.

Runs a scenario on the Verilated hfi_soc built with the profile (sim/soc_sim.h, ``SOC_PROF_*``): every
CPU clock counts to the instruction in the core's last pipeline stage (a stall counts to the instruction
that retired before it), every instruction-bus beat to the word it refills. Maps the counts to the
firmware's functions (``nm`` of out/firmware/hfi_fw.elf) and prints, per function, CPU clocks per control
period, their share of the handler's clocks, and instruction-cache lines refilled per period (8 beats
each), largest first; then the data cache's refills per period by data object. The start-up, the idle loop and
the UART log (``IDLE``: firmware/src/main.c) are shown apart. ``--lines FUNC`` (repeatable) then splits one
function's clocks by source line (the DWARF line table of ``objdump -l``: an inlined helper's statements count
to the helper's own line), largest first, with the line's text.

    python scripts/fw_profile.py [--scenario FILE] [--duration 0.1] [--from T] [--top 25] [--f-sw HZ] [--lines FUNC]...

``--from T`` profiles only the periods after ``T`` simulated seconds (a stretch of a run, e.g. the 003 drive's
fusion band): the scenario runs twice, to ``T`` and to ``--duration``, and the first run's counts are subtracted
(the co-simulation is deterministic: both runs are the same up to ``T``).

``--f-sw`` runs the scenario at another switching frequency (everything else as written): a slower copy
measures a step that overruns the scenario's own period (the co-simulation stops then).
"""

from __future__ import annotations

import argparse
import dataclasses
import linecache
import os
import re
import shutil
import subprocess
import sys

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import numpy as np  # noqa: E402

from golden.scenario import ScenarioError, load_scenario  # noqa: E402
from hfi import soc_platform  # noqa: E402
from hfi.rtl_backend import FW_OUT, RtlBackendError, RtlClosedLoop  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
LINE_WORDS = 8
"""Words per instruction-cache line (32 bytes; docs/soc.md)."""
IDLE = ("main", "run", "show_mode", "uart_puts", "uart_putu")
"""The firmware's start-up, idle loop and log (firmware/src/main.c): outside the control step."""


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


LOCATION_RE = re.compile(r"^(/\S+?):(\d+)(?: \(discriminator \d+\))?$")
INSN_RE = re.compile(r"^\s+([0-9a-f]+):\t")


def parse_line_table(listing: str) -> dict[int, tuple[str, int]]:
    """Instruction address -> (source file, line) from an ``objdump -d -l`` listing: each instruction takes
    the location printed last before it (instructions before any location are left out)."""
    where, out = None, {}
    for text in listing.splitlines():
        m = LOCATION_RE.match(text)
        if m:
            where = (m.group(1), int(m.group(2)))
            continue
        m = INSN_RE.match(text)
        if m and where is not None:
            out[int(m.group(1), 16)] = where
    return out


def line_clocks(table: dict[int, tuple[str, int]], cycles, base: int, n_win: int) -> list[tuple[str, int, float, int]]:
    """(file, line, CPU clocks per period, instructions) per source line of ``table``, largest first."""
    acc: dict[tuple[str, int], list] = {}
    for addr, where in table.items():
        row = acc.setdefault(where, [0, 0])
        row[0] += int(cycles[(addr - base) // 4])
        row[1] += 1
    return sorted(((f, ln, c / n_win, k) for (f, ln), (c, k) in acc.items()), key=lambda r: (-r[2], r[0], r[1]))


def print_lines(elf: str, name: str, start: int, end: int, cycles, base: int, n_win: int, top: int) -> None:
    """The clocks of function ``name`` (``start``..``end``) by source line, at most ``top`` lines."""
    objdump = shutil.which("riscv64-unknown-elf-objdump") or "riscv64-unknown-elf-objdump"
    listing = subprocess.run([objdump, "-d", "-l", f"--start-address={start:#x}", f"--stop-address={end:#x}", elf],
                             capture_output=True, text=True, check=True).stdout
    rows = line_clocks(parse_line_table(listing), cycles, base, n_win)
    total = sum(r[2] for r in rows)
    print(f"{name}: {total:.1f} clocks per period by source line (the largest {min(top, len(rows))} of {len(rows)})")
    print(f"{'clocks/period':>13s} {'insns':>5s}  line")
    for f, ln, c, k in rows[:top]:
        print(f"{c:13.1f} {k:5d}  {os.path.basename(f)}:{ln}  {linecache.getline(f, ln).strip()[:100]}")


def data_objects(elf: str, chunk: int = 512) -> list[tuple[int, int, str]]:
    """(start, end, name) of the data the step reads through the data cache: the data symbols of ``elf``
    (``nm`` types d, b, r and their globals), the large ones (the configuration block) cut into ``chunk``-byte
    pieces named ``name+0xOFFSET``, and ``stack`` from the end of .bss to the end of the RAM."""
    nm = shutil.which("riscv64-unknown-elf-nm") or "riscv64-unknown-elf-nm"
    out = subprocess.run([nm, "-S", "-n", elf], capture_output=True, text=True, check=True).stdout
    objs, bss_end = [], None
    for line in out.splitlines():
        parts = line.split()
        if len(parts) == 4 and parts[2] in "dDbBrR":
            start, size = int(parts[0], 16), int(parts[1], 16)
            for off in range(0, size, chunk) if size > chunk else [0]:
                name = f"{parts[3]}+0x{off:x}" if size > chunk else parts[3]
                objs.append((start + off, start + min(size, off + chunk), name))
        elif parts[-1] == "_bss_end":
            bss_end = int(parts[0], 16)
    if bss_end is not None:
        objs.append((bss_end, soc_platform.RAM_BASE + soc_platform.RAM_BYTES, "stack"))
    return sorted(objs)


def profile_stretch(sc, start: float = 0.0) -> tuple[dict, int, object]:
    """The program-counter profile (``cycles``, ``fetch``: counts per instruction word, int64) of the periods of
    ``sc`` after ``start`` simulated seconds, their number and the whole run's result: with ``start`` > 0 the
    scenario runs twice, to ``start`` and to its end, and the first run's counts are subtracted (ValueError if the
    firmware image changed between the two runs)."""
    loop = RtlClosedLoop(sc)
    res = loop.run(progress=False, profile=True)
    prof = {k: v.astype(np.int64) for k, v in loop.profile.items()}
    n_win = len(res.t)
    if start > 0:
        image = (FW_OUT / "hfi_fw.elf").read_bytes()
        head = RtlClosedLoop(dataclasses.replace(sc, duration=start))
        n_win -= len(head.run(progress=False, profile=True).t)
        if (FW_OUT / "hfi_fw.elf").read_bytes() != image:
            raise ValueError("the firmware image changed between the two runs of --from (sources edited?): run again")
        prof = {k: v - head.profile[k].astype(np.int64) for k, v in prof.items()}
    return prof, n_win, res


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenario", default=os.path.join(HERE, "..", "scenarios", "fullload_start.toml"))
    ap.add_argument("--duration", type=float, default=0.1, help="simulated seconds (default 0.1)")
    ap.add_argument("--from", dest="start", type=float, default=0.0,
                    help="profile only the periods after this many simulated seconds (default 0)")
    ap.add_argument("--top", type=int, default=25, help="functions listed (default 25)")
    ap.add_argument("--f-sw", type=float, default=None,
                    help="switching frequency in Hz instead of the scenario's (a slower copy of a step that overruns)")
    ap.add_argument("--lines", action="append", default=[], metavar="FUNC",
                    help="split this function's clocks by source line (repeatable)")
    args = ap.parse_args(argv)
    if not args.duration > 0 or args.top < 1 or (args.f_sw is not None and not args.f_sw > 0):
        print("fw_profile: --duration and --f-sw must be > 0 and --top >= 1", file=sys.stderr)
        return 1
    if not 0 <= args.start < args.duration:
        print(f"fw_profile: --from must be in [0, --duration) (got {args.start} s, --duration {args.duration} s)",
              file=sys.stderr)
        return 1
    try:
        sc = dataclasses.replace(load_scenario(args.scenario), duration=args.duration)
        if args.f_sw is not None:
            sc = dataclasses.replace(sc, pwm=dataclasses.replace(sc.pwm, f_sw=args.f_sw))
        prof, n_win, res = profile_stretch(sc, args.start)
    except (ScenarioError, RtlBackendError, ValueError, OSError) as exc:
        print(f"fw_profile: {exc}", file=sys.stderr)
        return 1
    cycles, fetch = prof["cycles"], prof["fetch"]
    base = soc_platform.RAM_BASE
    elf = str(FW_OUT / "hfi_fw.elf")
    symbols = functions(elf)
    spans = {name: (start, end) for start, end, name in symbols}
    unknown = [f for f in args.lines if f not in spans]
    if unknown:
        print(f"fw_profile: no function {', '.join(unknown)} in {elf}", file=sys.stderr)
        return 1
    rows = []
    for start, end, name in symbols:
        a, b = (start - base) // 4, max((end - base) // 4, (start - base) // 4 + 1)
        c, f = int(cycles[a:b].sum()), int(fetch[a:b].sum())
        if c or f:
            rows.append((name, c / n_win, f / LINE_WORDS / n_win, end - start))
    idle = sum(r[1] for r in rows if r[0] in IDLE)
    busy = sum(r[1] for r in rows) - idle
    soc = res.soc
    span = f" after {args.start} s" if args.start > 0 else ""
    print(f"scenario {sc.name}: {n_win} periods{span}; firmware step (handler) {soc['fw_cycles_mean']} CPU clocks mean, "
          f"{soc['fw_cycles_max']} worst; profiled outside the idle loop: {busy:.0f} per period")
    print(f"{'function':28s} {'clocks/period':>13s} {'share':>7s} {'lines/period':>12s} {'bytes':>6s}")
    for name, c, f, size in sorted((r for r in rows if r[0] not in IDLE), key=lambda r: -r[1])[:args.top]:
        print(f"{name:28s} {c:13.1f} {100 * c / busy:6.1f}% {f:12.1f} {size:6d}")
    lines = sum(r[2] for r in rows if r[0] not in IDLE)
    print(f"{'(the step)':28s} {busy:13.1f} {100.0:6.1f}% {lines:12.1f}")
    print(f"{'start-up, idle loop, log':28s} {idle:13.1f}")
    dfetch = prof["dfetch"]
    drows = []
    for start, end, name in data_objects(str(FW_OUT / "hfi_fw.elf")):
        a, b = (start - base) // 4, max((end - base) // 4, (start - base) // 4 + 1)
        f = int(dfetch[a:b].sum())
        if f:
            drows.append((name, f / LINE_WORDS / n_win, start - base, end - start))
    print(f"data cache ({soc_platform.CPU_DCACHE_BYTES} bytes, direct-mapped): lines refilled per period, by object")
    print(f"{'object':28s} {'lines/period':>12s} {'cache offset':>12s} {'bytes':>6s}")
    for name, f, at, size in sorted(drows, key=lambda r: -r[1])[:args.top]:
        print(f"{name:28s} {f:12.1f} {f'0x{at % soc_platform.CPU_DCACHE_BYTES:03x}':>12s} {size:6d}")
    print(f"{'(all)':28s} {sum(r[1] for r in drows):12.1f}")
    for name in args.lines:
        print_lines(elf, name, *spans[name], cycles, base, n_win, args.top)
    return 0


if __name__ == "__main__":
    sys.exit(main())
