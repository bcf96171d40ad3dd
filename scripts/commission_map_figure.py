#!/usr/bin/env python3
"""The saturation map's error at each of its 15 points on the four PM motors (docs/commissioning.md, "The map and
the inverter's error"): reduced with the ideal inverter's HF gains and with the model of the inverter
(golden/hf_gain.py) from the same run, the hls backend.

    python scripts/commission_map_figure.py [--out docs/figures/commission_map_error.png]

Prints each motor's largest error both ways.
"""

from __future__ import annotations

import argparse
import os
import sys

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import golden.commission as commission  # noqa: E402
from golden.plant.fluxmap import incremental_inductance, psi_from_current  # noqa: E402
from golden.scenario import parse_scenario  # noqa: E402
from hfi.backends import run as run_backend  # noqa: E402
from hfi.commission import run_scenario_dict  # noqa: E402

MOTORS = (("002 Table I", "fullload_start"), ("002 Table III", "bench2_loadsteps"), ("001 IPMSM", "xue2022_noload"),
          ("000 PMaSynRM", "tap2023_step"))


def map_errors(sc, prog, ident, theta, iterations: int) -> np.ndarray:
    """(points x 2) relative errors of L_dd, L_qq against the plant's with ``iterations`` passes of the model."""
    res = commission.reduce(prog, ident, sc, commission.settings(sc), theta, map_iterations=iterations)
    mag = sc.plant["mag"]
    out = []
    for i_d, i_q, L in res.map:
        t = incremental_inductance(mag, *psi_from_current(mag, i_d, i_q))
        out.append((L[0, 0] / t[0, 0] - 1.0, L[1, 1] / t[1, 1] - 1.0))
    return np.array(out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="docs/figures/commission_map_error.png")
    args = ap.parse_args(argv)
    fig, axs = plt.subplots(1, len(MOTORS), figsize=(14, 3.6), sharey=True)
    for ax, (title, name) in zip(axs, MOTORS):
        path = f"scenarios/{name}.toml"
        sc = parse_scenario(run_scenario_dict(path), path)
        prog = commission.build_program(sc, commission.settings(sc))
        run = run_backend(sc, "hls", progress=False)
        ideal = map_errors(sc, prog, run.ident, run.windows["theta_hat"], 0)
        model = map_errors(sc, prog, run.ident, run.windows["theta_hat"], commission.MAP_ITERATIONS)
        k = np.arange(len(ideal))
        for n, (key, mark) in enumerate((("L_dd", "o"), ("L_qq", "s"))):
            ax.plot(k, 100 * ideal[:, n], mark, mfc="none", color="C1", label=f"{key}, ideal inverter")
            ax.plot(k, 100 * model[:, n], mark, color="C0", label=f"{key}, inverter model")
        ax.axhspan(-5, 5, color="0.9", zorder=0)
        ax.set_title(f"{title}: max {100 * np.abs(ideal).max():.1f} % -> {100 * np.abs(model).max():.1f} %",
                     fontsize=9)
        ax.set_xlabel("map point (i_d fastest, then i_q)")
        print(f"{title}: largest error {100 * np.abs(ideal).max():.2f} % with the ideal gains, "
              f"{100 * np.abs(model).max():.2f} % with the inverter model")
    axs[0].set_ylabel("map error against the plant [%]")
    axs[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
