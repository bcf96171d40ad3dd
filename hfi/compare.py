"""``hfi compare``: the four systems side by side (docs/compare.md).

Each system runs on its own paper's motor from its sweep spec ``sweeps/compare_<id>.toml``: start-up, a
speed ramp to a plateau, a load ramp, 0.6 s of steady state measured. The specs set 1 p.u. to the motor's
rated speed and torque (``golden.motors``, ``rated``; tests/test_compare.py holds them to it) and scale the
profiles to 0, 10 % and 50 % speed and 0-2 p.u. load, 20 seeds and initial angles per point.

Then the sensitivity study (:data:`SENSITIVITY`, 10 seeds per change). The sweeps run on one Dask cluster
(hfi.sweep, cached: a second call only reports). The report goes to ``OUT`` (default ``out/compare``):
``report.md`` with the tables, ``angle_vs_load.png`` (the headline figure), ``sensitivity.png``,
``results.csv`` (one row per point and system), ``costs.json`` (each system's firmware clocks per step on
the rtl backend, hfi.costs) and ``resources.json`` (the FPGA resources its own blocks add, hfi.resources).
"""

from __future__ import annotations

import copy
import csv
import json
import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from golden import motors
from golden.firmware.estimator import METHODS
from golden.scenario import parse_scenario
from hfi.sweep import Axis, Spec, load_spec, scaled, sweep

ROOT = Path(__file__).resolve().parent.parent
SYSTEMS = ("002", "000", "001", "001r", "003")
"""The compared systems: ``sweeps/compare_<id>.toml`` (the seed papers' numbers; ``001r`` is the 001 system
with the rotor flux observer above 300 r/min, the engineering fix of its speed range)."""
SENSITIVITY = {
    "model_error.R_s": ("values", (0.8, 1.2)),
    "model_error.L_d": ("values", (0.8, 1.2)),
    "model_error.L_q": ("values", (0.8, 1.2)),
    "model_error.psi_f": ("values", (0.8, 1.2)),
    "sensors.noise_rms": ("scale", (3.0,)),
    "pwm.dead_time": ("scale", (2.0,)),
    "inverter.V_dc": ("scale", (1.1,)),
    "faults": ("values", ([{"kind": "dc_link", "factor": 0.8, "at": "0 s"}],)),
}
"""The sensitivity study: each change alone (``one_at_a_time``) at 10 % speed and rated load: the
controller's motor data +-20 % (``[model_error]``), three times the sensor noise, twice the dead time, a DC
link 10 % higher (the controller set for it) and 20 % lower than the controller assumes (a sag from the
start, ``[[faults]] dc_link``: the drives measure no DC-link voltage)."""
SENSITIVITY_OWN = {
    "003": {"estimator.hfo_proj.map_scale_d": ("values", (0.9, 1.1)),
            "estimator.hfo_proj.map_scale_q": ("values", (0.9, 1.1))},
}
"""Changes of one system only, after the common ones: the 003 method's flux maps (its controller's tables, which
``[model_error]``'s L and psi_f factors do not reach) +-10 % off, each axis alone."""
SENSITIVITY_SKIP = ("001r",)
"""Systems the sensitivity study leaves out: 001r is 001 below its hand-over, where the study runs."""
SENSITIVITY_POINT = (0.1, 1.0)
"""(speed, load) of the sensitivity study, p.u.: a point every system holds."""


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
    speed_ripple: float
    """Median over the locked runs of half the peak-to-peak speed [r/min]."""
    torque_ripple: float
    """Median over the locked runs of the torque's standard deviation, p.u. of rated torque."""
    cu_ripple: float
    """Median over the locked runs of the copper loss beyond the mean current's (injection, PWM and control
    ripple: hfi.ripple), p.u. of the rated copper loss ``1.5 R_s I_rated^2``."""
    audible_db: float
    """Median over the locked runs of the A-weighted torque variation (hfi.ripple), dB re 1 % of rated torque."""
    crb_deg: float
    """Median Cramér-Rao standard deviation of one control window's samples (hfi.crb; standstill only)."""
    err_std_deg: float
    """Median standard deviation of the angle error (its noise, without the bias)."""
    tau_c_ms: float
    """Median correlation time of the angle error."""
    efficiency: float
    """Median ``crb^2 T_w / (err_std^2 tau_c)``: 1 uses all the information of the samples."""
    estimator: str
    """The slot in charge in the measured window: ``low``, ``high`` or ``both`` (over the locked runs)."""


def label(spec: Spec) -> str:
    """``002: sqw_bangbang + rfo, benevieri2023_table1``: the estimators and the motor of the base scenario."""
    sc = parse_scenario(copy.deepcopy(spec.base), str(spec.scenario))
    est = sc.estimator
    names = " + ".join(n for n in (est.low, est.high) if n in METHODS)
    return f"{spec.name.removeprefix('compare_')}: {names}, {spec.base['motor']['preset']}"


def rated(spec: Spec) -> tuple[float, float]:
    """The rated torque [N*m] and rated copper loss ``1.5 R_s I_rated^2`` [W] of a spec's motor (golden.motors:
    the p.u. bases of the comparison)."""
    m = motors.preset(spec.base["motor"]["preset"])
    return m["rated"]["torque"], 1.5 * m["R_s"] * m["rated"]["current_peak"] ** 2


AUDIBLE_REF = 0.01
"""Reference of the acoustic proxy's decibels: 1 % of the motor's rated torque."""


def kept(row: dict) -> bool:
    """A run that ran and was not lost: ``locked`` and no fault trip."""
    return bool(row["locked"]) and row.get("faults.code") == "none"


def _db(x: float) -> float:
    """``20 log10 x``; -inf for 0, nan for nan."""
    return 20 * math.log10(x) if x > 0 else -math.inf if x == 0 else math.nan


def summarize(system: str, rows: list[dict], rated_nm: float = 1.0, rated_cu_w: float = 1.0) -> list[Point]:
    """The rows of one system's sweep, grouped by (speed, load); ``rated_nm`` the motor's rated torque,
    ``rated_cu_w`` its rated copper loss."""
    groups: dict[tuple[float, float], list[dict]] = {}
    for r in rows:
        groups.setdefault((r["reference.speed.scale"], r["load.torque.scale"]), []).append(r)
    out = []
    for (speed, load), rs in sorted(groups.items()):
        ok = [r for r in rs if not r["error"]]
        locked = [r for r in ok if kept(r)]
        rms = [r["win0.err_rms_deg"] for r in locked]
        shares = [r["win0.high_share"] for r in locked]
        slot = "-" if not shares else "low" if max(shares) == 0 else "high" if min(shares) == 1 else "both"
        nan = float("nan")

        def median(key: str, scale: float = 1.0) -> float:
            have = [r[key] for r in locked if r.get(key) is not None and not math.isnan(r[key])]
            return float(np.median(have)) / scale if have else nan

        out.append(Point(system, speed, load, len(rs), len(ok) - len(locked), len(rs) - len(ok),
                         median("win0.err_rms_deg"), max(rms, default=nan),
                         max((r["win0.err_peak_deg"] for r in locked), default=nan),
                         median("win0.speed_ripple_rpm"), median("win0.torque_std_nm", rated_nm),
                         median("win0.cu_ripple_w", rated_cu_w),
                         _db(median("win0.torque_audible_nm", AUDIBLE_REF * rated_nm)),
                         *(median(f"win0.{k}") for k in ("crb_window_deg", "err_std_deg", "tau_c_ms", "efficiency")),
                         slot))
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
            x = np.array([p.load_pu for p in ps]) + (k - (len(labels) - 1) / 2) * 0.03
            med = np.array([p.rms_median for p in ps])
            peak = np.array([p.peak_worst for p in ps])
            line, = ax.plot(x, med, "o-", color=f"C{k}", label=labels[system])
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


def ripple_figure(points: list[Point], labels: dict[str, str], path: Path) -> None:
    """Ripple copper loss (top) and audible torque (bottom) against load, one column per speed, one line per
    system (medians over the locked runs)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    speeds = sorted({p.speed_pu for p in points})
    fig, axes = plt.subplots(2, len(speeds), figsize=(4.2 * len(speeds), 6.6), sharey="row", squeeze=False)
    for col, speed in enumerate(speeds):
        for k, system in enumerate(labels):
            ps = sorted((p for p in points if p.system == system and p.speed_pu == speed), key=lambda p: p.load_pu)
            if ps:
                x = [p.load_pu for p in ps]
                axes[0][col].plot(x, [100 * p.cu_ripple for p in ps], "o-", color=f"C{k}", label=labels[system])
                axes[1][col].plot(x, [p.audible_db for p in ps], "o-", color=f"C{k}")
        axes[0][col].set_title(f"{100 * speed:.0f} % of rated speed")
        axes[0][col].set_yscale("log")
        axes[1][col].set_xlabel("load [p.u. of rated torque]")
        for ax in axes[:, col]:
            ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("ripple copper loss\n[% of rated copper loss]")
    axes[1][0].set_ylabel("audible torque, A-weighted\n[dB re 1 % of rated torque]")
    axes[0][-1].legend(fontsize=7)
    fig.suptitle("What the estimation costs: copper loss beyond the mean current, and the audible torque", fontsize=10)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _fmt(x: float) -> str:
    return "-" if math.isnan(x) else f"{x:.2f}"


def headline(points: list[Point], labels: dict[str, str], cost: dict[str, tuple[str, str]] | None = None) -> list[str]:
    """The headline table: per system, the angle error and the acoustic proxy at standstill under rated load,
    the share of runs lost over the whole grid, and the ripple copper loss there; with ``cost`` (system ->
    (firmware, FPGA) texts, measured by hfi.costs and hfi.resources) two more columns."""
    extra = (" firmware in RUN [CPU clocks worst / period] | own FPGA blocks [xc7] |", "---|---|") if cost else ("", "")
    lines = ["| system | angle error, standstill, 1 p.u. [deg RMS median / peak worst] | runs lost (all points) | "
             "audible torque, standstill, 1 p.u. [dB re 1 % rated] | ripple copper loss, standstill, 1 p.u. "
             "[% rated copper loss] |" + extra[0], "|---|---|---|---|---|" + extra[1]]
    for system, name in labels.items():
        mine = [p for p in points if p.system == system]
        at = next((p for p in mine if p.speed_pu == 0 and p.load_pu == 1), None)
        n, lost = sum(p.n for p in mine), sum(p.lost + p.failed for p in mine)
        nan = float("nan")
        more = " {} | {} |".format(*cost.get(system, ("-", "-"))) if cost else ""
        lines.append(f"| {name} | {_fmt(at.rms_median if at else nan)} / {_fmt(at.peak_worst if at else nan)} | "
                     f"{lost} of {n} | {_fmt(at.audible_db if at else nan)} | "
                     f"{_fmt(100 * at.cu_ripple if at else nan)} |" + more)
    return lines


def bound_table(points: list[Point], labels: dict[str, str]) -> list[str]:
    """The standstill points' angle noise against the Cramér-Rao bound of their samples (hfi.crb)."""
    lines = ["## Angle noise against the Cramér-Rao bound (standstill)", "",
             "The information about the rotor angle in the ADC samples each system takes, given the voltages it "
             "applied and the sensor noise (hfi/crb.py): `CRB/window` is the smallest standard deviation of an "
             "unbiased angle estimate from one control window's samples; `noise` the standard deviation of the "
             "estimator's error (its mean, the bias, is in the RMS above), `tau_c` its correlation time; "
             "`efficiency` = CRB² T_w / (noise² tau_c): the share of the samples' information the estimator uses "
             "(medians over the seeds).", "",
             "| system | load | CRB/window [deg] | noise [deg] | tau_c [ms] | efficiency [%] |", "|---|---|---|---|---|---|"]
    for system, name in labels.items():
        for p in (p for p in points if p.system == system and p.speed_pu == 0 and not math.isnan(p.crb_deg)):
            lines.append(f"| {name} | {p.load_pu:g} p.u. | {p.crb_deg:.3f} | {p.err_std_deg:.3f} | "
                         f"{_fmt(p.tau_c_ms)} | {100 * p.efficiency:.2g} |")
    return lines


def report(points: list[Point], labels: dict[str, str], seeds: int, out: Path,
           cost: dict[str, tuple[str, str]] | None = None) -> str:
    lines = ["# Four sensorless systems side by side", "",
             f"`hfi compare` ({seeds} seeds and initial angles per point; docs/compare.md says how). Angle error "
             "in electrical degrees over 0.6-1.3 s after the load ramp ended, on the runs that kept lock "
             "(`locked` and no fault); `lost`: runs that lost lock or tripped. Ripple copper loss: the copper "
             "loss beyond that of the mean rotor-frame current (injection, PWM and control ripple), in % of the "
             "motor's rated copper loss; audible torque: the A-weighted RMS of the torque's variation, dB re "
             "1 % of rated torque (hfi/ripple.py).", "", *headline(points, labels, cost), "",
             "![angle error against load](angle_vs_load.png)", "",
             "![ripple copper loss and audible torque against load](ripple_vs_load.png)", "",
             *bound_table(points, labels), ""]
    for system, name in labels.items():
        lines += [f"## {name}", "", "| speed | load | runs | lost | RMS median | RMS worst | peak worst | speed ripple "
                  "[r/min] | torque ripple [% rated] | ripple Cu loss [% rated] | audible [dB] | estimator |",
                  "|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for p in (p for p in points if p.system == system):
            lines.append(f"| {100 * p.speed_pu:.0f} % | {p.load_pu:g} p.u. | {p.n} | {p.lost}"
                         f"{f' (+{p.failed} failed)' if p.failed else ''} | {_fmt(p.rms_median)} | "
                         f"{_fmt(p.rms_worst)} | {_fmt(p.peak_worst)} | {_fmt(p.speed_ripple)} | "
                         f"{_fmt(100 * p.torque_ripple)} | {_fmt(100 * p.cu_ripple)} | {_fmt(p.audible_db)} | "
                         f"{p.estimator} |")
        lines.append("")
    text = "\n".join(lines)
    (out / "report.md").write_text(text)
    with open(out / "results.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["system", "speed_pu", "load_pu", "runs", "lost", "failed", "rms_median_deg", "rms_worst_deg",
                    "peak_worst_deg", "speed_ripple_rpm", "torque_ripple_pu", "cu_ripple_pu", "audible_db",
                    "crb_window_deg", "err_std_deg", "tau_c_ms", "efficiency", "estimator"])
        for p in points:
            w.writerow([p.system, p.speed_pu, p.load_pu, p.n, p.lost, p.failed, p.rms_median, p.rms_worst,
                        p.peak_worst, p.speed_ripple, p.torque_ripple, p.cu_ripple, p.audible_db, p.crb_deg,
                        p.err_std_deg, p.tau_c_ms, p.efficiency, p.estimator])
    return text


def changes(system: str) -> dict:
    """The sensitivity study's changes of ``system``: SENSITIVITY, then its SENSITIVITY_OWN."""
    return {**SENSITIVITY, **SENSITIVITY_OWN.get(system, {})}


def change_labels(system: str) -> list[str]:
    """``nominal`` and the label of each change of ``system`` (as :func:`change_of` names a row's)."""
    return ["nominal"] + [_fault_label(v) if k == "faults" else f"{k.rpartition('.')[2]} x{v:g}"
                          for k, (_, vs) in changes(system).items() for v in vs]


def sensitivity_spec(spec: Spec) -> Spec:
    """The sensitivity study on a system's comparison spec (``compare_<system>``): its base and ``[set]``, at
    SENSITIVITY_POINT, each of the system's :func:`changes` alone."""
    base = copy.deepcopy(spec.base)
    for key, factor in zip(("reference.speed", "load.torque"), SENSITIVITY_POINT):
        table, _, name = key.partition(".")
        base[table][name] = scaled(base[table][name], factor, key)
    axes = tuple(Axis(k, kind, items) for k, (kind, items) in changes(spec.name.removeprefix("compare_")).items())
    return replace(spec, name=spec.name.replace("compare_", "sensitivity_"), design="one_at_a_time", axes=axes,
                   base=base)


def _fault_label(faults: list[dict]) -> str:
    return " + ".join(f"V_dc x{f['factor']:g} (sag)" if f["kind"] == "dc_link" else f["kind"] for f in faults)


def change_of(row: dict) -> str:
    """The sensitivity change a row ran with (``nominal`` for the base point), e.g. ``L_d x0.8``."""
    every = {k: v for own in SENSITIVITY_OWN.values() for k, v in own.items()}
    for key, (kind, _) in {**SENSITIVITY, **every}.items():
        name = key.rpartition(".")[2]
        if key == "faults" and row.get(key) is not None:
            return _fault_label(json.loads(row[key]))
        if kind == "values" and row.get(key) is not None:
            return f"{name} x{row[key]:g}"
        if kind == "scale" and row.get(f"{key}.scale") is not None:
            return f"{name} x{row[f'{key}.scale']:g}"
    return "nominal"


def sensitivity_figure(rows: dict[str, list[dict]], labels: dict[str, str], path: Path) -> list[tuple]:
    """Median RMS angle error of each change and system (x where runs were lost); returns the table
    ``(system, change, runs, lost, failed, rms median, peak worst)``."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    order = [ch for system in rows for ch in change_labels(system)]
    changes_all = sorted(set(order), key=order.index)
    table = []
    fig, ax = plt.subplots(figsize=(12, 4.2))
    for j, (system, rs) in enumerate(rows.items()):
        k = list(labels).index(system)              # the system's colour in every figure
        xs, ys = [], []
        for i, ch in enumerate(changes_all):
            if ch not in change_labels(system):
                continue
            mine = [r for r in rs if change_of(r) == ch]
            ran = [r for r in mine if not r["error"]]
            good = [r for r in ran if kept(r)]
            rms = float(np.median([r["win0.err_rms_deg"] for r in good])) if good else float("nan")
            peak = max((r["win0.err_peak_deg"] for r in good), default=float("nan"))
            table.append((system, ch, len(mine), len(ran) - len(good), len(mine) - len(ran), rms, peak))
            xs.append(i + (j - (len(rows) - 1) / 2) * 0.12)
            ys.append(rms)
            if len(good) < len(mine):
                ax.plot(xs[-1], 0.3, "x", color=f"C{k}", markersize=9)
        ax.plot(xs, ys, "o", color=f"C{k}", label=labels[system])
    ax.set_xticks(range(len(changes_all)), changes_all, rotation=30, ha="right", fontsize=8)
    ax.set_yscale("log")
    ax.set_ylabel("median RMS angle error [deg el]\nx: some runs lost lock or tripped")
    ax.set_title(f"Sensitivity at {100 * SENSITIVITY_POINT[0]:.0f} % speed, {SENSITIVITY_POINT[1]:g} p.u. load: "
                 "each change alone", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return table


def compare(out: Path, systems: tuple[str, ...] = SYSTEMS, seeds: int | None = None, scheduler: str | None = None,
            workers: int | None = None, progress: bool = True, log=print, firmware_cost: bool = True) -> list[Point]:
    """Run (or read from the cache) every system's sweep and write the report; return its points. With
    ``firmware_cost``, also the firmware's clocks per step on the rtl backend (hfi.costs)."""
    from hfi.sweep import start_client

    specs = {}
    for s in systems:
        spec = load_spec(spec_path(s))
        specs[s] = replace(spec, seeds=seeds) if seeds else spec
    client, cluster = start_client(scheduler, workers, dashboard=True)
    try:
        if client.dashboard_link:
            log(f"dashboard: {client.dashboard_link}")
        points, sens = [], {}
        for s, spec in specs.items():
            rows = sweep(spec, ROOT / "out" / "sweep" / spec.name, progress=progress, log=log, client=client)
            points += summarize(s, rows, *rated(spec))
        for s, spec in specs.items():
            if s in SENSITIVITY_SKIP:
                continue
            study = sensitivity_spec(replace(spec, seeds=min(spec.seeds or 1, 10)))
            sens[s] = sweep(study, ROOT / "out" / "sweep" / study.name, progress=progress, log=log, client=client)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    labels = {s: label(spec) for s, spec in specs.items()}
    out.mkdir(parents=True, exist_ok=True)
    figure(points, labels, out / "angle_vs_load.png")
    ripple_figure(points, labels, out / "ripple_vs_load.png")
    table = sensitivity_figure(sens, labels, out / "sensitivity.png")
    cost_lines, cost = [], None
    if firmware_cost:
        from hfi import costs, resources

        bases = {s: spec.base for s, spec in specs.items()}
        fw = costs.costs(bases, out / "costs.json", log=log)
        scenarios = {s: parse_scenario(copy.deepcopy(b), f"{s} base scenario") for s, b in bases.items()}
        base, hw = resources.resources(scenarios, out / "resources.json", log=log)
        cost_lines = ["", *costs.table(fw, labels), "", *resources.table(base, hw, labels)]
        cost = {c.system: (costs.worst_of_period(c), resources.summary(r)) for c, r in zip(fw, hw)}
    text = report(points, labels, max(spec.seeds or 1 for spec in specs.values()), out, cost)
    lines = ["", "## Sensitivity", "", f"Each change alone at {100 * SENSITIVITY_POINT[0]:.0f} % speed and "
             f"{SENSITIVITY_POINT[1]:g} p.u. load (`hfi.compare.SENSITIVITY`).", "",
             "![sensitivity](sensitivity.png)", "",
             "| system | change | runs | lost | RMS median | peak worst |", "|---|---|---|---|---|---|"]
    lines += [f"| {s} | {ch} | {n} | {lost}{f' (+{failed} failed)' if failed else ''} | {_fmt(rms)} | {_fmt(peak)} |"
              for s, ch, n, lost, failed, rms, peak in table]
    lines += cost_lines
    (out / "report.md").write_text(text + "\n".join(lines) + "\n")
    log(f"wrote {out}/report.md, angle_vs_load.png, ripple_vs_load.png, sensitivity.png, results.csv"
        + (", costs.json, resources.json" if firmware_cost else ""))
    return points

