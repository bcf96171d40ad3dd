#!/usr/bin/env python3
"""Synthesis and timing of ONE module of the hfi_dsp IP, out of context.

Reuses the flow of ``scripts/synth_report.py`` (imported, not copied): ``synth_xilinx -family xc7`` for
LUT / FF / DSP counts, ``synth_ecp5`` + ``nextpnr-ecp5`` (LFE5U-25F, CABGA256, speed 6, out of context,
``--freq 100``) for the post-route Fmax of ``clk``. Only the module's own file and the rtl/hfi_*.v files
it instantiates (recursively) are read, so modules being edited elsewhere do not disturb the run.
Outputs go to ``out/synth_module/<module>[_<params>]/`` (separate directories: runs can go in parallel).

Usage: ``python scripts/synth_module.py carrier [-P NAME=VALUE ...] [--seed 1] [--skip-pnr] [--xc7-only] [--json]``
(module name with or without the ``hfi_`` prefix). Prints one table row:
``module  xc7 LUT  xc7 FF  xc7 DSP  ecp5 LUT4  ecp5 FF  ecp5 DSP  Fmax MHz`` (``--xc7-only``: the ECP5 flow is
skipped, its columns are ``-``; ``hfi compare`` measures the methods' build options so, hfi/resources.py).
"""

from __future__ import annotations

import argparse
import json
import re
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import synth_report as sr  # noqa: E402  (after the path set-up)

INST_RE = re.compile(r"^\s*(hfi_\w+)\s*(?:#\s*\(|\w+\s*\()", re.M)


def module_files(top: str, rtl_dir: str = "rtl") -> list[str]:
    """<rtl_dir>/<top>.v and the hfi_*.v files it instantiates, recursively (paths relative to ROOT)."""
    seen: list[str] = []
    todo = [top]
    while todo:
        name = todo.pop()
        path = sr.ROOT / rtl_dir / f"{name}.v"
        rel = path.relative_to(sr.ROOT).as_posix()
        if rel in seen:
            continue
        if not path.exists():
            raise SystemExit(f"synth_module: {rel} not found")
        seen.append(rel)
        text = re.sub(r"//.*", "", path.read_text())
        todo += [m for m in INST_RE.findall(text) if m != name and (sr.ROOT / rtl_dir / f"{m}.v").exists()]
    return seen


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("module", help="module name, e.g. carrier or hfi_carrier")
    ap.add_argument("-P", "--param", action="append", default=[], metavar="NAME=VALUE",
                    help="override a parameter of the module (repeatable)")
    ap.add_argument("--seed", type=int, default=1, help="nextpnr placement seed")
    ap.add_argument("--skip-pnr", action="store_true", help="synthesis counts only (no Fmax)")
    ap.add_argument("--xc7-only", action="store_true", help="the Xilinx 7-series counts only (no ECP5 flow)")
    ap.add_argument("--rtl-dir", default="rtl",
                    help="source directory relative to the repo root (e.g. a snapshot for a baseline)")
    ap.add_argument("--tag", default="", help="suffix of the output directory")
    ap.add_argument("--json", action="store_true", help="also print the result as JSON")
    args = ap.parse_args(argv)
    top = args.module if args.module.startswith("hfi_") else f"hfi_{args.module}"
    params: dict[str, str] = {}
    for p in args.param:
        if not re.fullmatch(r"[A-Z_][A-Z0-9_]*=\d+", p):
            ap.error(f"--param {p!r}: expected NAME=VALUE with an integer value")
        k, v = p.split("=")
        params[k] = v
    tag = top + "".join(f"_{k}{v}" for k, v in params.items()) + (f"_{args.tag}" if args.tag else "")
    sr.OUT = Path("out/synth_module") / tag          # synth_report's functions write to sr.OUT
    (sr.ROOT / sr.OUT).mkdir(parents=True, exist_ok=True)
    files = module_files(top, args.rtl_dir)
    print(f"{top}: {' '.join(files)}", flush=True)
    t0 = time.perf_counter()
    x = sr.xc7(top, files, params)
    e = {"lut4": "-", "ff": "-", "dsp": "-", "lutram": "-", "fmax_mhz": None}
    if not args.xc7_only:
        try:
            e = sr.ecp5(top, files, params, args.seed, args.skip_pnr)
        except SystemExit as exc:                   # a purely combinational module has no clock to time
            if "no clock" not in str(exc):
                raise
            print("  (no clocked path: Fmax not applicable)")
            e = sr.ecp5(top, files, params, args.seed, True)
    res = {"module": top, "parameters": params, "files": files,
           "xc7": {k: x[k] for k in ("lut", "ff", "dsp", "bram", "srl", "lutram")},
           "ecp5": None if args.xc7_only else {k: e[k] for k in ("lut4", "ff", "dsp", "lutram", "fmax_mhz")}}
    (sr.ROOT / sr.OUT / "module_report.json").write_text(json.dumps(res, indent=2) + "\n")
    fmax = "-" if e["fmax_mhz"] is None else f"{e['fmax_mhz']:.1f}"
    print(f"\n{top}: {time.perf_counter() - t0:.0f} s, {sr.OUT}/module_report.json")
    print(f"{'module':<20}{'xc7 LUT':>8}{'FF':>6}{'DSP':>5}{'ecp5 LUT4':>10}{'FF':>6}{'DSP':>5}{'Fmax MHz':>10}")
    print(f"{top:<20}{x['lut']:>8}{x['ff']:>6}{x['dsp']:>5}{e['lut4']:>10}{e['ff']:>6}{e['dsp']:>5}{fmax:>10}")
    if args.json:
        print(json.dumps(res))
    return 0


if __name__ == "__main__":
    sys.exit(main())
