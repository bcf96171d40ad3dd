#!/usr/bin/env python3
"""The figure of ``sweeps/startup_2000.toml`` (docs/sweep.md "Measured"): the 002 start-up and rated-load step at
standstill over 100 random drives x 20 seeds. One panel per drawn parameter: the angle error (RMS over the
window, electrical) of each run that kept the rotor against the parameter, and the share of runs lost (not
locked, or a fault) in four equal bins of its range. Reads the sweep's table; run ``hfi sweep
sweeps/startup_2000.toml`` first.

With ``--variant TABLE`` (repeatable: the same sweep with ``hfi sweep --set``, named by its folder's ``+KEY=VALUE``
suffix), the last panel sets the
share of runs lost against the dead time of each beside the base's, with each one's count of runs lost and median
angle error of the runs kept.

    python scripts/startup_2000_figure.py [--table out/sweep/startup_2000/results.parquet] [--variant TABLE]...
                                          [--out docs/figures/startup_2000.png]
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
    """Not locked (the error passed 60 deg after start-up) or tripped: the comparison's rule (hfi.compare.kept)."""
    from hfi.compare import kept
    return not kept(row)


def loss_rate(x: np.ndarray, gone: np.ndarray, edges: np.ndarray) -> list[float]:
    """The share of runs lost [%] in each bin of ``x`` between ``edges`` (the last bin closed)."""
    idx = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, len(edges) - 2)
    return [100 * gone[idx == b].mean() if (idx == b).any() else 0.0 for b in range(len(edges) - 1)]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--table", default=str(ROOT / "out" / "sweep" / "startup_2000" / "results.parquet"))
    ap.add_argument("--base-label", default="speed loop 4 Hz (the base)", help="the base table's name in the last panel")
    ap.add_argument("--variant", action="append", default=[], metavar="TABLE",
                    help="the same sweep on another drive (hfi sweep --set), drawn beside the base in the last panel")
    ap.add_argument("--out", default=str(ROOT / "docs" / "figures" / "startup_2000.png"))
    args = ap.parse_args(argv)
    if not os.path.exists(args.table):
        print(f"startup_2000_figure: {args.table} not found: run `hfi sweep sweeps/startup_2000.toml` first",
              file=sys.stderr)
        return 2
    missing = [f for f in args.variant if not os.path.exists(f)]
    if missing:
        print(f"startup_2000_figure: --variant {missing[0]}: not found (run hfi sweep ... --set first)", file=sys.stderr)
        return 2
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import pyarrow.parquet as pq

    from hfi.report import save_figure

    rows = pq.read_table(args.table).to_pylist()
    variants = [(Path(f).parent.name.partition("+")[2].replace("+", ", ") or Path(f).parent.name, pq.read_table(f).to_pylist())
                for f in args.variant]
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
        rate = loss_rate(x, gone, edges)
        share.bar((edges[:-1] + edges[1:]) / 2, rate, width=0.8 * (edges[1] - edges[0]), color="tab:red", alpha=0.25)
        share.set_ylabel("runs lost [%]", color="tab:red")
        share.set_ylim(0, max(5.0, 1.2 * max(rate)))
    last = axes.flat[-1]
    tables = [(args.base_label, rows)] + variants
    edges = np.linspace(0.5, 1.5, BINS + 1)
    width = 0.8 * (edges[1] - edges[0]) / len(tables)
    top = 0.0
    for k, (name, rs) in enumerate(tables):
        x = np.array([r["pwm.dead_time.scale"] for r in rs], dtype=float)
        g = np.array([lost(r) for r in rs])
        rate = loss_rate(x, g, edges)
        ok = [r for r in rs if not lost(r)]
        stats = f"{g.sum()} lost, kept {np.median([r['win0.err_rms_deg'] for r in ok]):.2f} deg"
        last.bar(edges[:-1] + (k + 0.5) * width + 0.1 * (edges[1] - edges[0]), rate, width=width, label=f"{name}: {stats}")
        top = max(top, max(rate))
    last.set_xlabel("dead time (x 4 us)")
    last.set_ylabel("runs lost [%]")
    last.set_ylim(0, 1.9 * top + 1)                     # room for the legend above the bars
    last.legend(fontsize=7, loc="upper left")
    last.set_title("the same 2000 runs, each drive", fontsize=9)
    kept = err[~gone]
    fig.suptitle(f"002 start-up and rated load at standstill (fullload_start, 0.4-0.6 s) over {len(rows)} random runs\n"
                 f"{gone.sum()} lost; kept: RMS angle error median {np.median(kept):.2f}, 95th percentile "
                 f"{np.percentile(kept, 95):.2f}, worst {kept.max():.2f} deg")
    print(save_figure(fig, os.path.dirname(args.out), os.path.basename(args.out), top=0.93))
    return 0


if __name__ == "__main__":
    sys.exit(main())
