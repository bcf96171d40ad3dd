#!/usr/bin/env python3
"""Lock losses over random seeds and initial rotor angles (issue 14): every scenario given, N seeds each,
on one backend (default hls, the fastest). Prints one line per run (seed, initial angle, locked, estimator
switches, worst plateau speed error) and the count of lock losses; exit status 1 if any run lost lock.

Usage: scripts/seed_sweep.py SCENARIO.toml... [--seeds 10] [--backend hls]
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from golden.scenario import load_scenario  # noqa: E402
from hfi.backends import run  # noqa: E402
from hfi.report import metrics_of  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scenarios", nargs="+")
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--backend", default="hls")
    args = ap.parse_args()
    losses = 0
    for path in args.scenarios:
        base = load_scenario(path)
        rng = np.random.default_rng(base.seed)
        for k in range(args.seeds):
            seed, theta = base.seed + 1000 + k, float(rng.uniform(0, 2 * math.pi / base.plant["mech"]["pole_pairs"]))
            plant = dict(base.plant, seed=seed, theta_m0=theta)
            sc = dataclasses.replace(base, seed=seed, plant=plant)
            m = metrics_of(sc, run(sc, args.backend, progress=False))
            worst = max((abs(s["speed_mean_rpm"] - s["speed_ref_rpm"]) for s in m["segments"]), default=0.0)
            losses += not m["locked"]
            print(f"{base.name} seed {seed} theta_m0 {math.degrees(theta):6.1f} deg: locked {m['locked']}, "
                  f"switches {m['estimator_switches']}, "
                  f"worst plateau speed error {worst:.1f} rpm", flush=True)
    print(f"lock losses: {losses}")
    return 1 if losses else 0


if __name__ == "__main__":
    sys.exit(main())
