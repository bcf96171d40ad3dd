#!/usr/bin/env python3
"""The test suite's wall time, and the same time on the reference machine: `make suite-time`.

The project asks for `make test` within 15 minutes on 2 cores (docs/testing.md). This machine's speed drifts by
the hour and dropped by a factor of 2 over the project's life with no code changed, so a wall time alone says
little about the suite. This script measures the machine beside the suite with the plant benchmark
(`scripts/bench_plant.py`'s batch API: C, one core, the realtime factor; the suite's CPU time has followed it, see
docs/testing.md), before and after, and prints

    suite: wall W, CPU C; machine: plant X (before) .. Y (after); at the reference speed R: W * mean(X, Y) / R

where R is hfi.machine_speed.REFERENCE_PLANT_X, the plant benchmark of the machine on which the targets were set. The
suite is the README's command itself, `make test` (its setup step a no-op once done: run `make setup` first), with
``PYTEST_JOBS`` and ``PYTEST_ARGS`` from ``--jobs`` and the arguments after ``--``. ``--wall SECONDS`` normalises a
time measured elsewhere (CI's) with the calibration taken now, and runs no suite.

Usage: scripts/suite_time.py [--jobs N] [--wall SECONDS] [-- PYTEST_ARGS...]
"""

from __future__ import annotations

import argparse
import os
import resource
import shlex
import subprocess
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(ROOT))

import bench_plant  # noqa: E402

from golden.scenario import load_scenario  # noqa: E402
from hfi.argtypes import positive_finite, positive_int  # noqa: E402
from hfi.machine_speed import REFERENCE_PLANT_X, slowdown  # noqa: E402

TARGET_S = 15 * 60
"""`make test` within 15 minutes on 2 cores."""
CALIBRATION_S = 2.0
"""Simulated seconds of one plant benchmark run (about a second of wall time at the reference speed)."""


def machine_speed(runs: int = 3) -> float:
    """The plant benchmark's realtime factor, the best of ``runs`` (scripts/bench_plant.py, batch API)."""
    scn = load_scenario(ROOT / "scenarios" / "openloop_injection.toml")
    return max(bench_plant.bench_batch(scn, CALIBRATION_S) for _ in range(runs))


def jobs(text: str) -> str:
    """``auto`` or a count >= 1 (argparse type)."""
    return text if text == "auto" else str(positive_int(text))


def clock(seconds: float) -> str:
    """``MM:SS``."""
    m, s = divmod(round(seconds), 60)
    return f"{m}:{s:02d}"


def run_suite(jobs: str, pytest_args: list[str]) -> tuple[int, float, float]:
    """``(exit status, wall s, CPU s)`` of `make test` (Makefile, target test)."""
    cmd = ["make", "-C", str(ROOT), "test", f"PYTEST_JOBS={jobs}", f"PYTEST_ARGS={shlex.join(pytest_args)}"]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    rc = subprocess.call(cmd)
    wall = time.monotonic() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return rc, wall, cpu


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--jobs", type=jobs, default="auto", help="pytest-xdist workers (as PYTEST_JOBS; default auto)")
    ap.add_argument("--wall", type=positive_finite, metavar="SECONDS",
                    help="normalise this wall time (measured elsewhere) instead of running the suite")
    ap.add_argument("pytest_args", nargs="*", help="passed to pytest after `--`")
    args = ap.parse_args()
    print("machine speed before (plant benchmark, best of 3) ...", flush=True)
    x0 = machine_speed()
    print(f"  plant {x0:.2f}x real time (reference {REFERENCE_PLANT_X:g}x)", flush=True)
    if args.wall is not None:
        rc, wall, cpu, x1 = 0, args.wall, None, x0
    else:
        rc, wall, cpu = run_suite(args.jobs, args.pytest_args)
        print("machine speed after ...", flush=True)
        x1 = machine_speed()
        print(f"  plant {x1:.2f}x real time", flush=True)
    slow = slowdown(0.5 * (x0 + x1))
    scaled = wall / slow
    cpu_text = f", CPU {clock(cpu)}" if cpu is not None else ""
    print(f"suite: wall {clock(wall)}{cpu_text}" + (f", make test exit status {rc}" if rc else ""))
    print(f"machine: plant {x0:.2f}x .. {x1:.2f}x real time, {slow:.2f} times slower than the "
          f"reference ({REFERENCE_PLANT_X:g}x)")
    print(f"at the reference speed: {clock(scaled)} (target {clock(TARGET_S)}: "
          f"{'met' if scaled <= TARGET_S else 'not met'})")
    print(f"suite_time_ratio: {scaled / TARGET_S:.3f}")
    return rc


if __name__ == "__main__":
    sys.exit(main())
