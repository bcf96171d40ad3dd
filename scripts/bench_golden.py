#!/usr/bin/env python3
"""Benchmark of the golden closed loop: simulated seconds per wall second on one core.

Runs the default scenario (``scenarios/fullload_start.toml``) for ``--duration`` simulated seconds
(default: the whole scenario), prints the time split between the C plant and the Python models, and
ends with ``realtime_factor: X`` (simulated / wall time; >= 1 means faster than real time).

    python scripts/bench_golden.py [--duration 1.0] [--scenario FILE]
"""

from __future__ import annotations

import argparse
import os
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from golden.closedloop import ClosedLoop  # noqa: E402
from golden.scenario import ScenarioError, load_scenario  # noqa: E402
from hfi.argtypes import positive_finite  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenario", default=os.path.join(HERE, "..", "scenarios", "fullload_start.toml"))
    ap.add_argument("--duration", type=positive_finite, help="simulated seconds (default: the scenario's)")
    args = ap.parse_args(argv)
    try:
        sc = load_scenario(args.scenario)
    except (ScenarioError, OSError) as exc:
        print(f"bench_golden: {exc}", file=sys.stderr)
        return 1
    if args.duration is not None:
        sc.duration = args.duration
    cl = ClosedLoop(sc)
    plant_time = [0.0]
    run = cl.plant.run

    def timed_run(*a, **k):
        t0 = time.perf_counter()
        try:
            return run(*a, **k)
        finally:
            plant_time[0] += time.perf_counter() - t0

    cl.plant.run = timed_run
    res = cl.run(progress=False)
    sim = float(res.t[-1])
    wall = res.wall_s
    n = len(res.t)
    print(f"scenario {sc.name}: {sim:.3f} s simulated, {n} PWM windows, {wall:.2f} s wall")
    print(f"per window: {wall / n * 1e6:.1f} us total, plant {plant_time[0] / n * 1e6:.1f} us, "
          f"Python models {(wall - plant_time[0]) / n * 1e6:.1f} us (window = {1e6 / sc.pwm.f_sw:.0f} us)")
    print(f"realtime_factor: {sim / wall:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
