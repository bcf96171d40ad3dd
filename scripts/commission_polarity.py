"""Self-commissioning: the rotor angle and the magnet polarity found at standstill from random initial angles.

For each scenario (the PM motors), ``N`` random initial rotor angles: the commissioning program's probe, scan
and polarity steps on the golden closed loop (the rest of the program cut off), and the angle the firmware
found against the plant's. The polarity is right when the error is within +-90 deg. Prints one line per run
and a summary; exit status 1 if a polarity is wrong.

    python scripts/commission_polarity.py [--n 20] [--seed 1] [SCENARIO ...]
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from hfi.commission import standstill_angle  # noqa: E402

PM_SCENARIOS = ("scenarios/fullload_start.toml", "scenarios/bench2_loadsteps.toml", "scenarios/xue2022_noload.toml",
                "scenarios/tap2023_step.toml")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scenarios", nargs="*", default=list(PM_SCENARIOS))
    ap.add_argument("--n", type=int, default=20, help="random initial angles per scenario (default 20)")
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    wrong = 0
    for path in args.scenarios:
        errs = []
        for theta in rng.uniform(0.0, 360.0, args.n):
            found, true = standstill_angle(path, float(theta))
            err = (found - true + 180.0) % 360.0 - 180.0
            errs.append(err)
            print(f"{Path(path).stem:28s} theta_m0 {theta:7.2f} deg: found {found:7.2f}, true {true:7.2f}, "
                  f"error {err:+7.2f} deg", flush=True)
        errs = np.array(errs)
        bad = int((np.abs(errs) > 90.0).sum())
        wrong += bad
        ok = np.abs(errs) <= 90.0
        print(f"== {Path(path).stem}: polarity right in {args.n - bad} of {args.n}; angle error RMS "
              f"{math.sqrt(float(np.mean(errs[ok] ** 2))) if ok.any() else math.nan:.2f} deg, largest "
              f"{float(np.max(np.abs(errs[ok]))) if ok.any() else math.nan:.2f} deg", flush=True)
    return 1 if wrong else 0


if __name__ == "__main__":
    sys.exit(main())
