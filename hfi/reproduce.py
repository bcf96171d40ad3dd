"""Reproduce the results of Benevieri et al. 2023 (Figs. 6-25) on the golden closed loop (``hfi paper``).

Writes ``<out>/metrics.json`` (one entry per figure group of :mod:`hfi.paper_groups`: our numbers, the
paper's, the criterion and whether it passes) and one plot per group beside it.
"""

from __future__ import annotations

import json
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from hfi.paper import ROOT, RPM  # noqa: E402
from hfi.paper_groups import GROUPS  # noqa: E402

DEFAULT_OUT = ROOT / "out" / "paper"


def _run(name: str, short: bool):
    t0 = time.perf_counter()
    out = GROUPS[name](short)
    return name, out, time.perf_counter() - t0


def plot_gamma(results: dict, path: Path, title: str) -> None:
    fig, axes = plt.subplots(1, len(results), figsize=(5 * len(results), 3.6), squeeze=False)
    for ax, (label, res) in zip(axes[0], results.items()):
        if res.windows["mode"][0] != 5:    # closed-loop runs are not gamma sweeps
            ax.set_visible(False)
            continue
        err = res.angle_error_deg()
        g = res.windows["gamma"]
        ax.plot(err, g, ".", ms=1.5, label="gamma (golden)")
        k = np.max(np.abs(g)) if len(g) else 1.0
        x = np.linspace(-180, 180, 361)
        fit = np.polyfit(np.sin(np.radians(2 * err)), g, 1)[0]
        ax.plot(x, fit * np.sin(np.radians(2 * x)), "r", lw=1, label="K sin(2 err)")
        ax.set_xlim(-180, 180)
        ax.set_ylim(-1.3 * k, 1.3 * k)
        ax.set_xlabel("angle error θ − θ̂ [deg el.]")
        ax.set_ylabel("γ [current LSB × samples]")
        ax.set_title(label)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_runs(results: dict, path: Path, title: str) -> None:
    n = len(results)
    fig, axes = plt.subplots(2, n, figsize=(4.8 * n, 5.2), squeeze=False, sharex="col")
    for i, (label, res) in enumerate(results.items()):
        scale = res.scales.speed_mech(RPM)
        ax = axes[0][i]
        ax.plot(res.t, res.windows["speed_ref"] / scale, label="reference")
        ax.plot(res.t, res.windows["omega_m"] / RPM, lw=0.8, label="measured (plant)")
        ax.set_ylabel("speed [r/min]")
        ax.set_title(label, fontsize=9)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
        ax = axes[1][i]
        ax.plot(res.t, res.angle_error_deg(), lw=0.6)
        ax.set_ylabel("θ − θ̂ [deg el.]")
        ax.set_xlabel("t [s]")
        ax.set_ylim(-180, 180)
        ax.grid(alpha=0.3)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def reproduce(names: list[str], short: bool = False, jobs: int = 2, out: Path = DEFAULT_OUT) -> bool:
    """Run the figure groups ``names`` (all if empty) on ``jobs`` processes, write the metrics and plots
    into ``out`` (merged into an existing metrics.json when only some groups run), print one line per
    group; True if every group passes. ValueError for an unknown group or ``jobs`` < 1."""
    unknown = [n for n in names if n not in GROUPS]
    if unknown:
        raise ValueError(f"unknown group(s) {', '.join(unknown)} (known: {', '.join(GROUPS)})")
    if jobs < 1:
        raise ValueError(f"--jobs must be >= 1, not {jobs}")
    only = bool(names)
    names = names or list(GROUPS)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    metrics_path = out / "metrics.json"
    metrics = json.loads(metrics_path.read_text()) if metrics_path.exists() and only else {}
    t0 = time.perf_counter()
    with ProcessPoolExecutor(max_workers=jobs) as pool:
        futures = [pool.submit(_run, n, short) for n in names]
        for fut in futures:
            name, res, wall = fut.result()
            results = res.pop("_results")
            res["wall_s"] = round(wall, 1)
            metrics[name] = res
            if name in ("fig6_7", "fig8_9"):
                plot_gamma(results, out / f"{name}.png", f"{name}: γ vs angle error, fixed θ̂, rotor turned")
            if name != "fig6_7":
                runs = {k: v for k, v in results.items() if v.windows["mode"][0] != 5}
                if name == "random_starts":
                    runs = dict(list(runs.items())[:4])
                if runs:
                    plot_runs(runs, out / f"{name}_runs.png", name)
            print(f"{name:14s} {'PASS' if res['pass'] else 'FAIL'}  ({wall:.0f} s)  {res['criteria']}", flush=True)
    metrics_path.write_text(json.dumps(metrics, indent=2) + "\n")
    passed = sum(1 for n in names if metrics[n]["pass"])
    print(f"{passed}/{len(names)} groups pass; {metrics_path} ({time.perf_counter() - t0:.0f} s)")
    return passed == len(names)
