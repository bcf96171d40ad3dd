#!/usr/bin/env python3
"""Lock losses over random seeds and initial rotor angles (issue 14): every scenario given, N seeds each,
on one backend (default hls, the fastest). Prints one line per run (seed, initial angle, locked, estimator
switches, the firmware's first fault code, worst plateau speed error) and the count of lock losses and of
runs with a fault; exit status 1 if any run lost lock or tripped, 2 on an input it cannot run (one line).

Usage: scripts/seed_sweep.py SCENARIO.toml... [--seeds 10] [--backend hls] [--window T0 T1]...

``--window T0 T1`` (repeatable) adds the peak and RMS of the angle error at the carrier bottom
(``angle_error_at_bottom``, docs/metrics.md) over ``[T0, T1)`` seconds of each run, and their worst over the
seeds at the end.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from golden.firmware.protection import FAULT_NAMES  # noqa: E402
from golden.scenario import load_scenario  # noqa: E402
from hfi.argtypes import positive_int  # noqa: E402
from hfi.backends import run  # noqa: E402
from hfi.cli import run_script  # noqa: E402
from hfi.report import metrics_of  # noqa: E402


def main() -> int:
    return run_script("seed_sweep", sweep)


def sweep() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scenarios", nargs="+")
    ap.add_argument("--seeds", type=positive_int, default=10)
    ap.add_argument("--backend", default="hls")
    ap.add_argument("--window", nargs=2, type=float, action="append", default=[], metavar=("T0", "T1"))
    args = ap.parse_args()
    losses = trips = 0
    worst = {tuple(w): [0.0, 0.0] for w in args.window}
    for path in args.scenarios:
        base = load_scenario(path)
        rng = np.random.default_rng(base.seed)
        for k in range(args.seeds):
            seed, theta = base.seed + 1000 + k, float(rng.uniform(0, 2 * math.pi / base.plant["mech"]["pole_pairs"]))
            plant = dict(base.plant, seed=seed, theta_m0=theta)
            sc = dataclasses.replace(base, seed=seed, plant=plant)
            res = run(sc, args.backend, progress=False)
            m = metrics_of(sc, res)
            speed_err = max((abs(s["speed_mean_rpm"] - s["speed_ref_rpm"]) for s in m["segments"]), default=0.0)
            losses += not m["locked"]
            codes = res.windows["fault"][res.windows["fault"] != 0]
            fault = FAULT_NAMES[int(codes[0])] if len(codes) else "none"
            trips += fault != "none"
            extra = ""
            for (t0, t1), acc in worst.items():
                sel = (res.t >= t0) & (res.t < t1)
                err = res.angle_error_deg(quarters=3)[sel]
                peak, rms = float(np.max(np.abs(err))), float(np.sqrt(np.mean(err ** 2)))
                acc[0], acc[1] = max(acc[0], peak), max(acc[1], rms)
                extra += f", [{t0:g}, {t1:g}) s: peak {peak:.2f} RMS {rms:.2f} deg"
            print(f"{base.name} seed {seed} theta_m0 {math.degrees(theta):6.1f} deg: locked {m['locked']}, "
                  f"switches {m['estimator_switches']}, fault {fault}, "
                  f"worst plateau speed error {speed_err:.1f} rpm{extra}", flush=True)
    for (t0, t1), (peak, rms) in worst.items():
        print(f"[{t0:g}, {t1:g}) s over all runs: worst peak {peak:.2f} deg, worst RMS {rms:.2f} deg")
    print(f"lock losses: {losses}, runs with a fault: {trips}")
    return 1 if losses or trips else 0


if __name__ == "__main__":
    sys.exit(main())
