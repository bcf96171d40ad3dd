#!/usr/bin/env python3
"""The smallest injection amplitude that keeps lock (issue 16): every scenario given, at each amplitude
(``injection.V_h``, the rotating vector's radius; the dead-time compensation's HF current follows it),
for N seeds and random initial rotor angles. Prints one line per amplitude and scenario (lock losses,
worst plateau angle error RMS) and the smallest amplitude without a loss in any scenario.

Usage: scripts/injection_sweep.py SCENARIO.toml... --volts 28 20 14 10 [--seeds 3] [--backend golden]
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
from hfi.argtypes import positive_finite, positive_int  # noqa: E402
from hfi.backends import run  # noqa: E402
from hfi.cli import run_script  # noqa: E402
from hfi.report import metrics_of  # noqa: E402


def main() -> int:
    return run_script("injection_sweep", sweep)


def sweep() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scenarios", nargs="+")
    ap.add_argument("--volts", type=positive_finite, nargs="+", required=True, help="amplitudes to try [V]")
    ap.add_argument("--seeds", type=positive_int, default=3)
    ap.add_argument("--backend", default="golden")
    args = ap.parse_args()
    ok_all = []
    for volts in sorted(args.volts, reverse=True):
        lost_any = False
        for path in args.scenarios:
            base = load_scenario(path)
            base = dataclasses.replace(base, injection=dataclasses.replace(base.injection, V_h=volts))
            rng = np.random.default_rng(base.seed)
            lost, worst = 0, 0.0
            for k in range(args.seeds):
                seed = base.seed + 2000 + k
                theta = float(rng.uniform(0, 2 * math.pi / base.plant["mech"]["pole_pairs"]))
                sc = dataclasses.replace(base, seed=seed, plant=dict(base.plant, seed=seed, theta_m0=theta))
                m = metrics_of(sc, run(sc, args.backend, progress=False))
                lost += not m["locked"]
                worst = max([worst] + [s["err_rms_deg"] for s in m["segments"]])
            lost_any |= lost > 0
            print(f"{volts:5.1f} V  {base.name}: lock lost in {lost} of {args.seeds}, worst plateau RMS {worst:.2f} deg",
                  flush=True)
        if not lost_any:
            ok_all.append(volts)
    print(f"smallest amplitude without a lock loss: {min(ok_all):g} V" if ok_all else "every amplitude lost lock")
    return 0


if __name__ == "__main__":
    sys.exit(main())
