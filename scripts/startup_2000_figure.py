#!/usr/bin/env python3
"""The figure of ``sweeps/startup_2000.toml`` (docs/sweep.md "Measured"): the 002 start-up and rated-load step at
standstill over 100 random drives x 20 seeds. One panel per drawn parameter: the angle error (RMS over the
window, electrical) of each run that kept the rotor against the parameter, and the share of runs lost (not
locked, or a fault) in four equal bins of its range. Reads the sweep's table; run ``hfi sweep
sweeps/startup_2000.toml`` first.

    python scripts/startup_2000_figure.py [--table out/sweep/startup_2000/results.parquet] [--out docs/figures/startup_2000.png]
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
PARAMETERS = (("sensors.noise_rms.scale", "sensor noise (x 30 mA)"), ("pwm.dead_time.scale", "dead time (x 4 us)"),
              ("inverter.V_dc.scale", "DC link (x 560 V)"), ("model_error.R_s", "controller's R_s (factor)"),
              ("model_error.L_d", "controller's L_d (factor)"), ("model_error.L_q", "controller's L_q (factor)"),
              ("model_error.psi_f", "controller's psi_f (factor)"))
BINS = 4


def lost(row: dict) -> bool:
    """Not locked (the error passed 60 deg after start-up) or ended in a fault: the comparison's rule."""
    return bool(row["error"]) or not row["locked"] or row["final_mode"] != "RUN"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--table", default=str(ROOT / "out" / "sweep" / "startup_2000" / "results.parquet"))
    ap.add_argument("--out", default=str(ROOT / "docs" / "figures" / "startup_2000.png"))
    args = ap.parse_args(argv)
    if not os.path.exists(args.table):
        print(f"startup_2000_figure: {args.table} not found: run `hfi sweep sweeps/startup_2000.toml` first",
              file=sys.stderr)
        return 2
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import pyarrow.parquet as pq

    from hfi.report import save_figure

    rows = pq.read_table(args.table).to_pylist()
    gone = np.array([lost(r) for r in rows])
    err = np.array([np.nan if lost(r) else r["win0.err_rms_deg"] for r in rows])
    fig, axes = plt.subplots(2, 4, figsize=(14, 6.5))
    for ax, (key, label) in zip(axes.flat, PARAMETERS):
        x = np.array([r[key] for r in rows], dtype=float)
        ax.plot(x[~gone], err[~gone], ".", ms=2, color="tab:blue", alpha=0.4)
        ax.set_xlabel(label)
        ax.set_ylabel("angle error RMS [deg el]", color="tab:blue")
        share = ax.twinx()
        edges = np.linspace(x.min(), x.max(), BINS + 1)
        idx = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, BINS - 1)
        rate = [100 * gone[idx == b].mean() if (idx == b).any() else 0 for b in range(BINS)]
        share.bar((edges[:-1] + edges[1:]) / 2, rate, width=0.8 * (edges[1] - edges[0]), color="tab:red", alpha=0.25)
        share.set_ylabel("runs lost [%]", color="tab:red")
        share.set_ylim(0, max(5.0, 1.2 * max(rate)))
    summary = axes.flat[-1]
    summary.axis("off")
    kept = err[~gone]
    summary.text(0.02, 0.95, f"{len(rows)} runs: 100 drives x 20 seeds\nlost: {gone.sum()} ({100 * gone.mean():.1f} %)\n"
                 f"kept, RMS angle error:\n  median {np.median(kept):.2f} deg\n  95th percentile "
                 f"{np.percentile(kept, 95):.2f} deg\n  worst {kept.max():.2f} deg", va="top", family="monospace")
    fig.suptitle("002 start-up and rated load at standstill (fullload_start, 0.4-0.6 s) over random drives")
    print(save_figure(fig, os.path.dirname(args.out), os.path.basename(args.out), top=0.95))
    return 0


if __name__ == "__main__":
    sys.exit(main())
