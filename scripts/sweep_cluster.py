#!/usr/bin/env python3
"""A sweep through a scheduler address: starts a Dask scheduler and worker processes on this machine (Dask's
own ``dask scheduler`` and ``dask worker`` commands, as on a cluster), runs ``hfi sweep SPEC --scheduler
ADDRESS`` against them and stops them.

It shows the cluster path of ``hfi sweep`` on one machine: the sweep connects to an address, as it would to
a scheduler on another host, instead of starting its own local cluster (docs/sweep.md "Measured").

    python scripts/sweep_cluster.py SPEC [--workers N] [--out DIR] [--set KEY=VALUE]... [--quiet]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from hfi.cli import main as hfi_main  # noqa: E402

START_TIMEOUT_S = 60.0


def _dask(*args: str, log: Path) -> subprocess.Popen:
    """``dask ARGS...`` from this venv, its output in ``log`` (the processes' own logs, kept for a failure)."""
    dask = Path(sys.executable).with_name("dask")
    with open(log, "w") as f:
        return subprocess.Popen([str(dask), *args], stdout=f, stderr=subprocess.STDOUT, cwd=ROOT,
                                env={**os.environ, "OPENBLAS_NUM_THREADS": "1"})


def _wait_for(what: str, ready, procs: list[subprocess.Popen], logs: list[Path]) -> None:
    deadline = time.monotonic() + START_TIMEOUT_S
    while not ready():
        dead = [log for p, log in zip(procs, logs) if p.poll() is not None]
        if dead or time.monotonic() > deadline:
            tail = "\n".join(log.read_text()[-2000:] for log in (dead or logs))
            raise RuntimeError(f"{what} did not start within {START_TIMEOUT_S:.0f} s:\n{tail}")
        time.sleep(0.2)


def _address(sched_file: Path) -> str | None:
    """The scheduler's address from its file, once the file is there and whole (it is not written atomically)."""
    try:
        return json.loads(sched_file.read_text())["address"]
    except (OSError, ValueError, KeyError):
        return None


def start(workers: int, directory: Path) -> tuple[str, list[subprocess.Popen]]:
    """A scheduler on 127.0.0.1 (a free port) and ``workers`` single-threaded worker processes; returns the
    scheduler's address once every worker has joined, and the processes to stop."""
    sched_file = directory / "scheduler.json"
    logs = [directory / "scheduler.log", directory / "workers.log"]
    procs = [_dask("scheduler", "--host", "127.0.0.1", "--port", "0", "--dashboard-address", ":0",
                   "--scheduler-file", str(sched_file), log=logs[0])]
    try:
        _wait_for("the scheduler", lambda: _address(sched_file) is not None, procs, logs[:1])
        address = _address(sched_file)
        procs.append(_dask("worker", address, "--nworkers", str(workers), "--nthreads", "1",
                           "--local-directory", str(directory), log=logs[1]))
        from distributed import Client
        with Client(address, timeout=START_TIMEOUT_S) as client:
            _wait_for(f"{workers} workers", lambda: len(client.scheduler_info()["workers"]) >= workers, procs, logs)
    except BaseException:
        stop(procs)
        raise
    return address, procs


def stop(procs: list[subprocess.Popen]) -> None:
    """Stops the workers first, then the scheduler."""
    for p in reversed(procs):
        p.terminate()
        try:
            p.wait(timeout=30)
        except subprocess.TimeoutExpired:
            p.kill()
            p.wait()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("spec", metavar="SPEC", help="sweep spec (TOML, docs/sweep.md)")
    ap.add_argument("--workers", type=int, default=os.cpu_count() or 1, help="worker processes (default: all cores)")
    ap.add_argument("--out", metavar="DIR", help="output directory (default out/sweep/<name>_cluster)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="as hfi sweep's --set")
    ap.add_argument("--quiet", action="store_true", help="no progress bar")
    args = ap.parse_args(argv)
    if args.workers < 1:
        ap.error(f"--workers must be >= 1, got {args.workers}")
    out = args.out
    if out is None:
        from hfi.sweep import SweepError, load_spec, parse_set
        try:
            out = str(ROOT / "out" / "sweep" / f"{load_spec(args.spec, parse_set(args.set)).name}_cluster")
        except (SweepError, ValueError) as exc:
            print(f"sweep_cluster: {exc}", file=sys.stderr)
            return 2
    with tempfile.TemporaryDirectory(prefix="hfi-dask-") as tmp:
        t0 = time.monotonic()
        try:
            address, procs = start(args.workers, Path(tmp))
        except RuntimeError as exc:
            print(f"sweep_cluster: {exc}", file=sys.stderr)
            return 2
        print(f"sweep_cluster: scheduler {address}, {args.workers} worker processes "
              f"({time.monotonic() - t0:.1f} s to start)", flush=True)
        try:
            argv = (["sweep", args.spec, "--scheduler", address, "--out", out] + [f"--set={x}" for x in args.set]
                    + (["--quiet"] if args.quiet else []))
            return hfi_main(argv)
        finally:
            stop(procs)


if __name__ == "__main__":
    sys.exit(main())
