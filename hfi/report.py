"""Outputs of a closed-loop run: ``trace.npz``, ``metrics.json`` and plots (the main job's report)."""

from __future__ import annotations

import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from golden.closedloop import ClosedLoopResult  # noqa: E402
from golden.firmware.supervisor import MODE_NAMES, MODE_RUN  # noqa: E402
from golden.scenario import Scenario  # noqa: E402
from hfi.paper import RPM, segment_stats  # noqa: E402

PLATEAU_MIN_S = 0.2
"""Shortest constant stretch of the speed reference reported as a segment."""


def plateaus(res: ClosedLoopResult, t_run: float) -> list[tuple[float, float]]:
    """Stretches (after ``t_run``) where the speed reference is constant, each minus its first quarter."""
    ref = res.windows["speed_ref"]
    t = res.t
    out, start = [], 0
    for k in range(1, len(ref) + 1):
        if k == len(ref) or ref[k] != ref[start]:
            t0, t1 = max(t[start], t_run), t[k - 1]
            if t1 - t0 >= PLATEAU_MIN_S:
                out.append((t0 + 0.25 * (t1 - t0), t1))
            start = k
    return out


def metrics_of(sc: Scenario, res: ClosedLoopResult) -> dict:
    """Angle error, speed and timing numbers of a closed-loop run."""
    w = res.windows
    run = np.nonzero(w["mode"] == MODE_RUN)[0]
    t_run = float(res.t[run[0]]) if len(run) else float(res.t[-1])
    err = res.angle_error_deg()
    after = res.t >= t_run
    segs = []
    for t0, t1 in plateaus(res, t_run):
        s = segment_stats(res, t0, t1)
        s["speed_ref_rpm"] = round(float(w["speed_ref"][np.searchsorted(res.t, t0)] / res.scales.speed_mech(RPM)), 2)
        segs.append(s)
    return {
        "scenario": sc.name,
        "duration_s": round(float(res.t[-1]), 4),
        "windows": int(len(res.t)),
        "samples": int(len(res.samples["tick"])),
        "final_mode": MODE_NAMES[int(w["mode"][-1])],
        "run_from_s": round(t_run, 4),
        "polarity_flipped": int(res.flipped),
        "angle_error_after_start": {
            "rms_deg": round(float(np.sqrt(np.mean(err[after] ** 2))), 2) if after.any() else None,
            "peak_deg": round(float(np.max(np.abs(err[after]))), 2) if after.any() else None},
        "locked": bool(np.all(np.abs(err[after]) < 60.0)),
        "segments": segs,
        "backend": res.backend,
        "late_commits": 0 if res.soc is None else res.soc["late_commits"],
        "wall_s": round(res.wall_s, 2),
        "realtime_factor": round(float(res.t[-1]) / res.wall_s, 3),
        **({} if res.soc is None else {"soc": {k: v for k, v in res.soc.items() if k != "uart_log"}}),
        **({} if res.plant_wall_s is None else {"plant_wall_s": round(res.plant_wall_s, 3)}),
    }


def write_trace(path: str, res: ClosedLoopResult) -> None:
    """Per-window columns (``win_*``), per-sample ADC codes (``sample_*``), gate edges (``edge_*``) and
    the firmware's register writes per window (``write_*``) in one npz."""
    arrays = {f"win_{k}": v for k, v in res.windows.items()}
    arrays.update({f"sample_{k}": v for k, v in res.samples.items()})
    arrays.update({f"edge_{k}": v for k, v in res.edges.items()})
    arrays.update({f"write_{k}": v for k, v in res.writes.items()})
    arrays["tick_hz"] = np.array(res.tick_hz)
    np.savez_compressed(path, **arrays)


def plot(sc: Scenario, res: ClosedLoopResult, out_dir: str) -> list[str]:
    w = res.windows
    t = res.t
    files = []
    fig, axes = plt.subplots(4, 1, figsize=(10, 9), sharex=True)
    axes[0].plot(t, w["speed_ref"] / res.scales.speed_mech(RPM), label="reference")
    axes[0].plot(t, w["omega_m"] / RPM, lw=0.8, label="measured (plant)")
    axes[0].plot(t, w["omega_f"] / res.scales.speed_mech(RPM), lw=0.6, alpha=0.7, label="estimated (PLL, filtered)")
    axes[0].set_ylabel("speed [r/min]")
    axes[1].plot(t, res.angle_error_deg(), lw=0.6)
    axes[1].set_ylabel("θ − θ̂ [deg el.]")
    axes[2].plot(t, w["gamma"], lw=0.5)
    axes[2].set_ylabel("γ (GAMMA)")
    i_lsb = res.scales.i_lsb
    axes[3].plot(t, w["i_q"] * i_lsb, lw=0.6, label="i_q̂ (window mean)")
    axes[3].plot(t, w["i_d"] * i_lsb, lw=0.6, label="i_d̂ (window mean)")
    axes[3].plot(t, w["load_torque"], lw=0.8, label="load torque [N·m]")
    axes[3].set_ylabel("[A], [N·m]")
    axes[3].set_xlabel("t [s]")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper left") if ax.get_legend_handles_labels()[0] else None
    fig.suptitle(f"{sc.name}: golden closed loop")
    files.append(_save(fig, out_dir, "closed_loop.png"))

    bits = res.hw.adc_bits
    amps = (res.samples["adc_a"].astype(float) - 2 ** (bits - 1)) * (2 * sc.plant["sens"]["adc_range"] / 2 ** bits)
    ts = res.samples["tick"] / res.tick_hz
    fig, axes = plt.subplots(2, 1, figsize=(10, 6))
    step = max(1, len(ts) // 200000)
    axes[0].plot(ts[::step], amps[::step], lw=0.3)
    axes[0].set(ylabel="i_a (ADC) [A]", title="phase current a, whole run")
    last = ts >= ts[-1] - 0.002
    axes[1].plot(ts[last] * 1e3, amps[last], ".-", ms=2, lw=0.4)
    axes[1].set(xlabel="t [ms]", ylabel="i_a (ADC) [A]", title="last 2 ms (1 µs samples)")
    for ax in axes:
        ax.grid(alpha=0.3)
    files.append(_save(fig, out_dir, "phase_current.png"))
    return files


def _save(fig, out_dir: str, name: str) -> str:
    path = os.path.join(out_dir, name)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def write_all(sc: Scenario, res: ClosedLoopResult, out_dir: str) -> tuple[dict, list[str]]:
    """Write trace, metrics and plots; return the metrics and the files written."""
    os.makedirs(out_dir, exist_ok=True)
    trace = os.path.join(out_dir, "trace.npz")
    write_trace(trace, res)
    metrics = metrics_of(sc, res)
    mpath = os.path.join(out_dir, "metrics.json")
    with open(mpath, "w") as fh:
        json.dump(metrics, fh, indent=2)
    return metrics, [trace, mpath] + plot(sc, res, out_dir)

