"""``hfi compare``: the four systems side by side (docs/compare.md).

Each system runs on its own paper's motor from its sweep spec ``sweeps/compare_<id>.toml``: start-up, a
speed ramp to a plateau, a load ramp, 0.6 s of steady state measured. The specs set 1 p.u. to the motor's
rated speed and torque (``golden.motors``, ``rated``; tests/test_compare.py holds them to it) and scale the
profiles to 0, 10 % and 50 % speed and 0-2 p.u. load, 20 seeds and initial angles per point.

The sweeps run on one Dask cluster (hfi.sweep, cached: a second call only reports). The report goes to
``OUT`` (default ``out/compare``): ``report.md`` with the tables, ``angle_vs_load.png`` (the headline
figure), ``lock_loss.png``, and ``results.csv`` (one row per point and system).
"""

from __future__ import annotations

import copy
import csv
import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from golden.firmware.estimator import METHODS
from golden.scenario import parse_scenario
from hfi.sweep import Spec, load_spec, sweep

ROOT = Path(__file__).resolve().parent.parent
SYSTEMS = ("002", "000", "001", "003")
"""The compared systems: ``sweeps/compare_<id>.toml`` (the seed papers' numbers)."""
LOCK_LOSS = "lost lock or tripped"


def spec_path(system: str) -> Path:
    return ROOT / "sweeps" / f"compare_{system}.toml"


@dataclass(frozen=True)
class Point:
    """One (system, speed, load) point over its seeds: ``n`` runs, ``lost`` of them unlocked or tripped,
    and over the locked ones the median and worst RMS and the worst peak of the angle error [deg el]."""

    system: str
    speed_pu: float
    load_pu: float
    n: int
    lost: int
    failed: int
    rms_median: float
    rms_worst: float
    peak_worst: float
    estimator: str
    """The slot in charge in the measured window: ``low``, ``high`` or ``both`` (over the locked runs)."""


def label(spec: Spec) -> str:
    """``002: sqw_bangbang + rfo, benevieri2023_table1``: the estimators and the motor of the base scenario."""
    sc = parse_scenario(copy.deepcopy(spec.base), str(spec.scenario))
    est = sc.estimator
    names = " + ".join(n for n in (est.low, est.high) if n in METHODS)
    return f"{spec.name.removeprefix('compare_')}: {names}, {spec.base['motor']['preset']}"


def summarize(system: str, rows: list[dict]) -> list[Point]:
    """The rows of one system's sweep, grouped by (speed, load)."""
    groups: dict[tuple[float, float], list[dict]] = {}
    for r in rows:
        groups.setdefault((r["reference.speed.scale"], r["load.torque.scale"]), []).append(r)
    out = []
    for (speed, load), rs in sorted(groups.items()):
        ok = [r for r in rs if not r["error"]]
        locked = [r for r in ok if r["locked"] and r.get("faults.code") == "none"]
        rms = [r["win0.err_rms_deg"] for r in locked]
        shares = [r["win0.high_share"] for r in locked]
        slot = "-" if not shares else "low" if max(shares) == 0 else "high" if min(shares) == 1 else "both"
        nan = float("nan")
        out.append(Point(system, speed, load, len(rs), len(ok) - len(locked), len(rs) - len(ok),
                         float(np.median(rms)) if rms else nan, max(rms, default=nan),
                         max((r["win0.err_peak_deg"] for r in locked), default=nan), slot))
    return out


def figure(points: list[Point], labels: dict[str, str], path: Path) -> None:
    """Angle error against load, one panel per speed, one line per system (median RMS, bars to the worst
    peak); a cross where some runs lost lock, with the share."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    speeds = sorted({p.speed_pu for p in points})
    fig, axes = plt.subplots(1, len(speeds), figsize=(4.2 * len(speeds), 4.2), sharey=True, squeeze=False)
    for ax, speed in zip(axes[0], speeds):
        for k, system in enumerate(labels):
            ps = sorted((p for p in points if p.system == system and p.speed_pu == speed), key=lambda p: p.load_pu)
            if not ps:
                continue
            x = np.array([p.load_pu for p in ps]) + (k - 1.5) * 0.03
            med = np.array([p.rms_median for p in ps])
            peak = np.array([p.peak_worst for p in ps])
            line, = ax.plot(x, med, "o-", label=labels[system])
            ax.vlines(x, med, peak, color=line.get_color(), alpha=0.5)
            for xi, p in zip(x, ps):
                if p.lost:
                    ax.plot(xi, 0.3, "x", color=line.get_color(), markersize=9)
                    ax.annotate(f"{100 * p.lost / p.n:.0f}%", (xi, 0.3), textcoords="offset points",
                                xytext=(0, 6 + 9 * k), ha="center", fontsize=7, color=line.get_color())
        ax.set_title(f"{100 * speed:.0f} % of rated speed")
        ax.set_xlabel("load [p.u. of rated torque]")
        ax.set_yscale("log")
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("angle error [deg el]: median RMS (dot), worst peak (bar)\n"
                          "x: share of seeds that lost lock or tripped")
    axes[0][-1].legend(fontsize=7, loc="upper right")
    fig.suptitle("Four sensorless systems on their own motors, same platform, plant and inverter models", fontsize=10)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _fmt(x: float) -> str:
    return "-" if math.isnan(x) else f"{x:.2f}"


def report(points: list[Point], labels: dict[str, str], seeds: int, out: Path) -> str:
    lines = ["# Four sensorless systems side by side", "",
             f"`hfi compare` ({seeds} seeds and initial angles per point; docs/compare.md says how). Angle error "
             "in electrical degrees over 0.6-1.3 s after the load ramp ended, on the runs that kept lock "
             "(`locked` and no fault); `lost`: runs that lost lock or tripped.", "",
             "![angle error against load](angle_vs_load.png)", ""]
    for system, name in labels.items():
        lines += [f"## {name}", "", "| speed | load | runs | lost | RMS median | RMS worst | peak worst | estimator |",
                  "|---|---|---|---|---|---|---|---|"]
        for p in (p for p in points if p.system == system):
            lines.append(f"| {100 * p.speed_pu:.0f} % | {p.load_pu:g} p.u. | {p.n} | {p.lost}"
                         f"{f' (+{p.failed} failed)' if p.failed else ''} | {_fmt(p.rms_median)} | "
                         f"{_fmt(p.rms_worst)} | {_fmt(p.peak_worst)} | {p.estimator} |")
        lines.append("")
    text = "\n".join(lines)
    (out / "report.md").write_text(text)
    with open(out / "results.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["system", "speed_pu", "load_pu", "runs", "lost", "failed", "rms_median_deg", "rms_worst_deg",
                    "peak_worst_deg", "estimator"])
        for p in points:
            w.writerow([p.system, p.speed_pu, p.load_pu, p.n, p.lost, p.failed, p.rms_median, p.rms_worst,
                        p.peak_worst, p.estimator])
    return text


def compare(out: Path, systems: tuple[str, ...] = SYSTEMS, seeds: int | None = None, scheduler: str | None = None,
            workers: int | None = None, progress: bool = True, log=print) -> list[Point]:
    """Run (or read from the cache) every system's sweep and write the report; return its points."""
    from hfi.sweep import _client

    specs = {}
    for s in systems:
        spec = load_spec(spec_path(s))
        specs[s] = replace(spec, seeds=seeds) if seeds else spec
    client, cluster = _client(scheduler, workers, dashboard=True)
    try:
        if client.dashboard_link:
            log(f"dashboard: {client.dashboard_link}")
        points = []
        for s, spec in specs.items():
            rows = sweep(spec, ROOT / "out" / "sweep" / spec.name, progress=progress, log=log, client=client)
            points += summarize(s, rows)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    labels = {s: label(spec) for s, spec in specs.items()}
    out.mkdir(parents=True, exist_ok=True)
    figure(points, labels, out / "angle_vs_load.png")
    report(points, labels, max(spec.seeds or 1 for spec in specs.values()), out)
    log(f"wrote {out}/report.md, angle_vs_load.png, results.csv")
    return points

