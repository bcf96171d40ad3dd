"""The ``hfi`` command: run, check and list what the platform does.

    hfi run [FILE] [--backend golden|rtl|hls] [--out DIR] [--quiet] [--fst FILE --fst-window T0 T1] [--every-block]
    hfi check FILE...
    hfi methods
    hfi paper [--short] [--only GROUPS] [--jobs N] [--out DIR]
    hfi bench
    hfi faults [--short] [--only ROWS] [--jobs N] [--out DIR]
    hfi sweep SPEC [--scheduler ADDRESS] [--workers N] [--out DIR] [--set KEY=VALUE]... [--quiet]
    hfi compare [--seeds N] [--systems IDS] [--scheduler ADDRESS] [--workers N] [--out DIR] [--no-cost] [--quiet]

Every error is one line on stderr and exit status 1 (no traceback).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

from golden.firmware.estimator import INJ_NONE, INJ_ROT, INJ_SQW_D, INJ_SQW_P, METHODS, SLOT_HIGH, SLOT_LOW
from golden.scenario import ScenarioError, load_scenario
from hfi import backends
from hfi.argtypes import positive_int
from hfi.machine_speed import slowdown
from hfi.paper import BASE as DEFAULT_SCENARIO
from hfi.paper import ROOT
from hfi.paper_groups import GROUPS

ERRORS = (ValueError, OSError, backends.BackendError)
"""What a command reports as one line (ScenarioError and PlantError are ValueErrors)."""

BENCH_TARGETS = {"bench_plant.py": ("the plant alone, x real time", None),
                 "bench_golden.py": ("golden backend, x real time", 1.0),
                 "bench_rtl.py": ("rtl backend, M clocks/s", 5.0),
                 "bench_hls.py": ("hls backend, x real time", 10.0)}
"""``hfi bench``: the benchmarks of ``scripts/``, in this order (as ``make bench``), each with what its last line
(``name: value``) measures and the issue's target (issue 21; None: no target, the plant is the hls backend's bound)."""

BENCH_SCRIPTS = tuple(BENCH_TARGETS)

SLOT_NAMES = {SLOT_LOW: "low", SLOT_HIGH: "high"}
INJECTION_NAMES = {INJ_NONE: "none", INJ_SQW_D: "square wave on d_hat at f_sw",
                   INJ_ROT: "vector rotating at f_inj in the stationary frame",
                   INJ_SQW_P: "square wave on d_hat at f_sw/2 (sign held a PWM period)"}


class _Parser(argparse.ArgumentParser):
    """argparse with usage errors as one line and exit status 1."""

    def error(self, message: str):
        print(f"{self.prog}: {message} (see {self.prog} --help)", file=sys.stderr)
        sys.exit(1)


def one_line(exc: BaseException) -> str:
    """The message of ``exc`` on one line (a ScenarioError's problems joined by "; ")."""
    if isinstance(exc, ScenarioError):
        return f"{exc.source}: " + "; ".join(exc.problems)
    if isinstance(exc, OSError) and exc.strerror:
        return f"{exc.filename}: {exc.strerror}" if exc.filename else exc.strerror
    return " ".join(str(exc).split()) or type(exc).__name__


def cmd_run(args) -> int:
    from hfi.run import run_file   # imports matplotlib and the open-loop study: only when needed
    out = run_file(args.file, backend=args.backend, out_dir=args.out, progress=not args.quiet,
                   fst=args.fst, fst_window=tuple(args.fst_window), every_block=args.every_block)
    sys.stderr.write("".join(f"[fw] {line}\n" for line in out.uart_log.splitlines()))
    print(json.dumps(out.metrics, indent=2))
    print("wrote", ", ".join(out.files))
    return 0


def check_scenario(sc) -> None:
    """What a closed-loop run derives from the scenario ``sc`` before its first step: the plant, the register values
    and the firmware's integers (a gain beyond 31 bits, a filter its coefficients cannot resolve); raises the
    ValueError a run would raise, so ``hfi check`` refuses what ``hfi run`` would."""
    from golden.control_config import firmware_params, hardware_config
    from golden.plant import Plant

    if sc.control is not None:
        Plant(sc.plant)
        hardware_config(sc)
        firmware_params(sc)


def cmd_check(args) -> int:
    status = 0
    for name in args.files:
        try:
            sc = load_scenario(name)
            check_scenario(sc)
        except ERRORS as exc:
            text = one_line(exc)
            print(text if text.startswith(f"{name}:") else f"{name}: {text}", file=sys.stderr)
            status = 1
        else:
            kind = "closed loop" if sc.control is not None else "open-loop study"
            print(f"{name}: ok ({sc.summary()}; {kind})")
    return status


def method_lines() -> list[str]:
    """One line per estimator of :data:`golden.firmware.estimator.METHODS`."""
    return [f"{m.name}: {m.paper}; slots {', '.join(SLOT_NAMES[s] for s in m.slots)}; "
            f"injection {INJECTION_NAMES[m.injection]}; backends {', '.join(m.backends)}"
            for m in METHODS.values()]


def cmd_methods(args) -> int:
    print("\n".join(method_lines()))
    return 0


def selection(text: str | None, option: str) -> list[str] | None:
    """The names of a comma-separated ``--only``/``--systems`` value (None: the option not given, everything); a value
    that names nothing (``""``, ``","``) is refused rather than read as everything or nothing."""
    if text is None:
        return None
    names = [n.strip() for n in text.split(",") if n.strip()]
    if not names:
        raise ValueError(f"{option} {text!r} names nothing (leave the option out for all)")
    return names


def cmd_paper(args) -> int:
    from hfi.reproduce import reproduce
    names = selection(args.only, "--only") or []
    return 0 if reproduce(names, short=args.short, jobs=args.jobs, out=Path(args.out)) else 1


def cmd_faults(args) -> int:
    from hfi.faults import main as fault_matrix   # imports matplotlib: only when needed
    only = selection(args.only, "--only")
    return fault_matrix(short=args.short, jobs=args.jobs, out=Path(args.out), only=",".join(only or []))


def cmd_commission(args) -> int:
    from hfi.commission import CommissionError, commission   # imports matplotlib: only when needed
    path = Path(args.file)
    out = Path(args.out) if args.out else ROOT / "out" / (path.stem + "_commission")
    try:
        commission(path, out, progress=not args.quiet, backend=args.backend)
    except CommissionError as exc:
        print(f"hfi commission: {exc}", file=sys.stderr)
        return 1
    print(f"wrote {out}/commission.json, commissioned.toml and the figures", flush=True)
    return 0


def cmd_sweep(args) -> int:
    from hfi.sweep import SweepError, load_spec, parse_set, sweep   # imports Dask only when needed
    try:
        spec = load_spec(args.spec, parse_set(args.set))
    except SweepError as exc:
        print(f"hfi sweep: {exc}", file=sys.stderr)
        return 1
    out = Path(args.out) if args.out else ROOT / "out" / "sweep" / spec.name
    rows = sweep(spec, out, scheduler=args.scheduler, workers=args.workers, progress=not args.quiet)
    return 1 if any(r["error"] for r in rows) else 0


def cmd_compare(args) -> int:
    from hfi.compare import SYSTEMS, compare   # imports Dask and matplotlib only when needed
    systems = tuple(selection(args.systems, "--systems") or SYSTEMS)
    bad = [s for s in systems if s not in SYSTEMS]
    if bad:
        raise ValueError(f"--systems: unknown {', '.join(bad)} (valid: {', '.join(SYSTEMS)})")
    compare(Path(args.out), systems, seeds=args.seeds, scheduler=args.scheduler, workers=args.workers,
            progress=not args.quiet, firmware_cost=not args.no_cost)
    return 0


def cmd_bench(args) -> int:
    results = {}
    for name in BENCH_SCRIPTS:
        script = ROOT / "scripts" / name
        if not script.is_file():
            raise OSError(2, "benchmark not found (hfi bench needs the source tree)", str(script))
        print(f"== {name}", flush=True)
        proc = subprocess.Popen([sys.executable, str(script)], env=dict(os.environ, OPENBLAS_NUM_THREADS="1"),
                                stdout=subprocess.PIPE, text=True, bufsize=1)
        last = ""
        for line in proc.stdout:                  # echoed as it comes; the last line is the measurement
            print(line, end="", flush=True)
            last = line.strip() or last
        if proc.wait() != 0:
            print(f"hfi bench: {name} failed (exit status {proc.returncode})", file=sys.stderr)
            return 1
        results[name] = float(last.rpartition(":")[2])
    slow = slowdown(results["bench_plant.py"])
    print(f"== summary (issue 21's targets; this machine {slow:.2f} times slower than the reference by the plant "
          f"benchmark: the last column scales to it, docs/testing.md)")
    for name, value in results.items():
        what, target = BENCH_TARGETS[name]
        if target is None:
            print(f"{what:32s} {value:8.3f}")
            continue
        print(f"{what:32s} {value:8.3f}  target >= {target:g}: {'met' if value >= target else 'NOT met':7s}"
              f"  at the reference speed {value * slow:8.3f}: {'met' if value * slow >= target else 'NOT met'}")
    return 0


def parser() -> argparse.ArgumentParser:
    ap = _Parser(prog="hfi", description="Sensorless HFI motor-control platform: simulate scenarios on the "
                 "golden model, the RTL SoC or the HLS kernels; check scenario files; list the estimators; "
                 "reproduce the paper; benchmark.",
                 epilog="Docs: README.md, docs/scenario.md (scenario files), docs/metrics.md (metrics.json).")
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND", parser_class=_Parser)

    p = sub.add_parser("run", help="simulate a scenario file and write trace, metrics and plots",
                       description="Simulate FILE and write trace.npz, metrics.json (docs/metrics.md) and plots "
                       "into --out or the scenario's output.dir. A scenario with a [control] table runs the "
                       "closed loop on --backend; one without runs the open-loop injection study.")
    p.add_argument("file", metavar="FILE", nargs="?", default=str(DEFAULT_SCENARIO),
                   help="scenario file (TOML, docs/scenario.md; default: the default scenario "
                        "scenarios/fullload_start.toml)")
    p.add_argument("--backend", default=None,
                   help=f"closed-loop backend: {'; '.join(f'{b.name}: {b.description}' for b in backends.BACKENDS.values())} "
                        "(default: $BACKEND or rtl)")
    p.add_argument("--out", metavar="DIR", help="output directory (default: the scenario's output.dir)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--fst", metavar="FILE", help="rtl backend: write an FST waveform of the SoC to FILE")
    p.add_argument("--fst-window", nargs=2, type=float, metavar=("T0", "T1"), default=(0.0, 0.002),
                   help="time span of the waveform [s] (default 0 0.002; T0 within the run, an end beyond it is "
                        "the run's end)")
    p.add_argument("--every-block", action="store_true",
                   help="rtl backend: simulate the FPGA build with every optional block in (the boards' bitstreams) "
                        "instead of the scenario's system (only the blocks its methods need, docs/rtl.md "
                        "\"Build options\")")
    p.set_defaults(func=cmd_run)

    p = sub.add_parser("check", help="validate scenario files (exit 1 if any is invalid)",
                       description="Validate scenario files: one line per file, 'ok' with a summary on stdout "
                       "or every problem on stderr; exit status 1 if any file is invalid or unreadable. A closed "
                       "loop is checked as far as a run takes it before its first step: the plant, the register "
                       "values and the firmware's integers (a 003 scenario's flux tables take about a second).")
    p.add_argument("files", nargs="+", metavar="FILE")
    p.set_defaults(func=cmd_check)

    p = sub.add_parser("methods", help="list the estimators and the backends that run them",
                       description="One line per estimator (golden.firmware.estimator.METHODS): its scenario "
                       "name, paper, estimator slots, injection while in charge, and the backends that run it.")
    p.set_defaults(func=cmd_methods)

    p = sub.add_parser("paper", help="reproduce the paper's figure groups (out/paper)",
                       description="Run the figure groups of Benevieri et al. 2023 on the golden closed loop and "
                       "write metrics.json and plots; exit status 1 if a group fails its criterion.")
    p.add_argument("--short", action="store_true", help="test-suite lengths")
    p.add_argument("--only", metavar="GROUPS",
                   help=f"comma-separated groups (default: all: {', '.join(GROUPS)})")
    p.add_argument("--jobs", type=positive_int, default=2, help="parallel processes (default 2)")
    p.add_argument("--out", default=str(ROOT / "out" / "paper"), metavar="DIR",
                   help="output directory (default out/paper)")
    p.set_defaults(func=cmd_paper)

    p = sub.add_parser("faults", help="the fault matrix of the 002 drive (out/faults, docs/faults.md)",
                       description="Inject each fault of hfi.faults.FAULTS at 0.8 s into the default scenario at "
                       "0, 50 and 250 r/min, without load and at rated load, on the golden closed loop; then each "
                       "fault for 50 ms with one restart allowed (the restart part); write matrix.json, "
                       "restart.json, matrix.md and a figure per run; exit status 1 if a fault was missed, a run "
                       "ran away with the gates on or a healthy run tripped.")
    p.add_argument("--short", action="store_true", help="1 s runs instead of 1.6 s (the overload check needs 0.5 s "
                   "at the current limit: a blocked rotor may then go undetected)")
    p.add_argument("--only", metavar="ROWS", help="comma-separated row names (default: all)")
    p.add_argument("--jobs", type=positive_int, default=2, help="parallel processes (default 2)")
    p.add_argument("--out", default=str(ROOT / "out" / "faults"), metavar="DIR", help="output directory "
                   "(default out/faults)")
    p.set_defaults(func=cmd_faults)

    p = sub.add_parser("commission", help="the drive measures its motor and tunes itself (docs/commissioning.md)",
                       description="Run the self-commissioning program on the plant of FILE (motor at rest, no "
                       "load profile; the shaft held during the inductance map unless commission.lock = off): "
                       "R_s, L_d, L_q and their map, the magnet polarity and psi_f, J and friction; compare each "
                       "with the plant's truth; write commission.json, commissioned.toml (the scenario with "
                       "the measured [model] and the tuned V_h and hand-over speeds) and figures.")
    p.add_argument("file", metavar="FILE", nargs="?", default=str(DEFAULT_SCENARIO),
                   help="scenario file (default: the default scenario)")
    p.add_argument("--backend", default="golden", choices=("golden", "hls", "rtl"), metavar="BACKEND",
                   help="golden (default), hls (the same results, native) or rtl (the same again: the commissioning "
                        "firmware image on the soft core of the Verilated SoC with 128 KiB RAM; about 10 minutes)")
    p.add_argument("--out", metavar="DIR", help="output directory (default out/<FILE stem>_commission)")
    p.add_argument("--quiet", action="store_true", help="no progress output")
    p.set_defaults(func=cmd_commission)

    p = sub.add_parser("sweep", help="run a grid or random design over scenario parameters on Dask (docs/sweep.md)",
                       description="Expand SPEC (a [sweep] table naming a base scenario, and [params] to vary) "
                       "into runs, run those not cached yet on a Dask cluster (a local one by default), and "
                       "write results.parquet: one row per run with its parameters, seed and metrics, or its "
                       "error. Exit status 1 if any run failed.")
    p.add_argument("spec", metavar="SPEC", help="sweep spec (TOML, docs/sweep.md)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler (default: a local cluster "
                   "with one single-threaded worker process per core)")
    p.add_argument("--workers", type=positive_int, metavar="N", help="local cluster's worker processes (default: the cores)")
    p.add_argument("--out", metavar="DIR", help="output directory (default out/sweep/<name>, with --set "
                   "out/sweep/<name>+KEY=VALUE...)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="one more [set] value for every "
                   "run (a TOML value, or text: --set control.speed_bw='12 Hz'); repeatable")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=cmd_sweep)

    p = sub.add_parser("compare", help="the four systems side by side: angle error and lock against load and "
                       "speed (out/compare, docs/compare.md)",
                       description="Run sweeps/compare_<id>.toml for each system on one Dask cluster (cached: a "
                       "second call only reports), measure each system's firmware clocks per step on the rtl "
                       "backend (cached likewise), and write report.md, angle_vs_load.png, ripple_vs_load.png, "
                       "sensitivity.png, results.csv and costs.json.")
    p.add_argument("--seeds", type=positive_int, metavar="N", help="seeds per point (default: the specs' 20)")
    p.add_argument("--systems", metavar="IDS", help="comma-separated systems (default: all, hfi.compare.SYSTEMS)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler (default: a local cluster)")
    p.add_argument("--workers", type=positive_int, metavar="N", help="local cluster's worker processes (default: the cores)")
    p.add_argument("--out", default=str(ROOT / "out" / "compare"), metavar="DIR", help="output directory "
                   "(default out/compare)")
    p.add_argument("--no-cost", action="store_true", help="leave out the firmware and FPGA cost (the rtl "
                   "co-simulations and the syntheses, about 5 minutes the first time; cached)")
    p.add_argument("--quiet", action="store_true", help="no progress bars")
    p.set_defaults(func=cmd_compare)

    p = sub.add_parser("bench", help="run the plant and closed-loop benchmarks",
                       description=f"Run {', '.join(f'scripts/{s}' for s in BENCH_SCRIPTS)} in turn; stop at "
                       "the first that fails.")
    p.set_defaults(func=cmd_bench)
    return ap


def run_script(prog: str, body) -> int:
    """A script's entry point: ``body()``'s exit status, or 2 with one line ``prog: message`` for what a command
    reports as one line (:data:`ERRORS`: a scenario file, a value its run refuses, a backend)."""
    try:
        return body()
    except ERRORS as exc:
        print(f"{prog}: {one_line(exc)}", file=sys.stderr)
        return 2


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``hfi`` console script; returns the exit status."""
    args = parser().parse_args(argv)
    try:
        return args.func(args)
    except ERRORS as exc:
        print(f"hfi {args.command}: {one_line(exc)}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
