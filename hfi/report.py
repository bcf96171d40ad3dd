"""Outputs of a closed-loop run: ``trace.npz``, ``metrics.json`` and plots (the main job's report)."""

from __future__ import annotations

import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from golden.closedloop import ClosedLoopResult  # noqa: E402
from golden.firmware.protection import FAULT_NAMES  # noqa: E402
from golden.firmware.supervisor import MODE_FAULT, MODE_NAMES, MODE_RUN  # noqa: E402
from golden.scenario import Scenario  # noqa: E402
from hfi.paper import RPM  # noqa: E402

SETTLE_S = 0.3
"""A segment's statistics start this long after the last reference or load change (docs/metrics.md)."""

LOCK_DEG = 60.0
"""``locked``: the angle error stays below this after the start-up (beyond it the estimator slips a pole)."""

RUNAWAY_RPM, RUNAWAY_S = 300.0, 0.05
"""``faults.runaway_gates_on``: the true speed more than RUNAWAY_RPM from the reference for RUNAWAY_S in a row
while the firmware is not in FAULT (a shorter excursion is a transient the drive recovers from or trips on)."""

ZOOM_S = 0.02
"""Span of the zoomed panel of ``angles.png`` [s]."""

SLOT_NAMES = ("low", "high")
"""Values of the ``est`` column: the low-speed estimator slot (0) or the high-speed one (1) in charge."""


def profile_changes(times, values) -> list[float]:
    """When a profile (points ``(times[i], values[i])``, piecewise linear) stops changing: the end time of
    every step or ramp between two points of different value."""
    return [float(t1) for t1, v0, v1 in zip(times[1:], values[:-1], values[1:]) if v1 != v0]


def load_changes(sc: Scenario) -> list[float]:
    """The load changes of the scenario: ends of the steps and ramps of the load torque profile (or of
    the imposed speed in ``load.mode = "speed"``); the pulsation is not a change."""
    profile = sc.plant["speed" if sc.plant["mech"]["imposed_speed"] else "load"]
    return profile_changes(profile["t"], profile["v"])


def plateaus(res: ClosedLoopResult) -> list[tuple[int, int]]:
    """Window index ranges ``[start, stop)`` over which the speed reference is constant."""
    ref = res.windows["speed_ref"]
    edges = [0, *(np.nonzero(ref[1:] != ref[:-1])[0] + 1), len(ref)]
    return list(zip(edges[:-1], edges[1:]))


def segments(sc: Scenario, res: ClosedLoopResult, t_run: float) -> list[dict]:
    """One entry per reference plateau with a settled part (docs/metrics.md): the statistics over the
    windows from SETTLE_S after the latest of the plateau's start, the start of RUN mode and the load
    changes up to the plateau's end, to the plateau's end."""
    w, t = res.windows, res.t
    changes = load_changes(sc)
    out = []
    for start, stop in plateaus(res):
        t_start, t_end = float(t[start]), float(t[stop - 1])
        settled_from = max([t_start, t_run] + [c for c in changes if c <= t_end]) + SETTLE_S
        first = start + int(np.searchsorted(t[start:stop], settled_from - 1e-12))
        if first >= stop:
            continue
        sel = slice(first, stop)
        err = res.angle_error_deg()[sel]
        err_b = res.angle_error_deg(quarters=3)[sel]
        rpm = w["omega_m"][sel] / RPM
        out.append({
            "plateau": [round(t_start, 5), round(t_end, 5)],
            "t": [round(float(t[first]), 5), round(t_end, 5)],
            "speed_ref_rpm": round(float(w["speed_ref"][start] / res.scales.speed_mech(RPM)), 2),
            "speed_mean_rpm": round(float(np.mean(rpm)), 2),
            "speed_ripple_rpm": round(float(0.5 * (np.max(rpm) - np.min(rpm))), 2),
            "err_rms_deg": round(float(np.sqrt(np.mean(err ** 2))), 2),
            "err_peak_deg": round(float(np.max(np.abs(err))), 2),
            "err_peak_bottom_deg": round(float(np.max(np.abs(err_b))), 2),
            "estimators": [SLOT_NAMES[k] for k in np.unique(w["est"][sel])],
        })
    return out


def estimator_switches(res: ClosedLoopResult) -> list[dict]:
    """Every change of the ``est`` column: its time (end of the first window with the new value), the
    slot taking over, and the measured and estimated (filtered PLL) speeds in that window."""
    w, t = res.windows, res.t
    est = w["est"]
    return [{"t_s": round(float(t[k]), 5), "to": SLOT_NAMES[int(est[k])],
             "speed_rpm": round(float(w["omega_m"][k] / RPM), 2),
             "speed_est_rpm": round(float(w["omega_f"][k] / res.scales.speed_mech(RPM)), 2)}
            for k in np.nonzero(est[1:] != est[:-1])[0] + 1]


def longest_run(flags: np.ndarray) -> int:
    """The longest stretch of consecutive True entries."""
    edges = np.diff(np.concatenate([[0], flags.astype(np.int8), [0]]))
    return int(np.max(np.flatnonzero(edges == -1) - np.flatnonzero(edges == 1), initial=0))


def fault_metrics(sc: Scenario, res: ClosedLoopResult) -> dict:
    """The firmware's fault and, with injected faults, what followed the first onset (docs/metrics.md)."""
    w, t = res.windows, res.t
    trip = np.flatnonzero(w["mode"] == MODE_FAULT)
    out = {"code": FAULT_NAMES[int(w["fault"][trip[0]])] if len(trip) else "none",
           "at_s": round(float(t[trip[0]]), 4) if len(trip) else None,
           "injected": [{"kind": f.kind, "at_s": f.at} for f in sc.faults]}
    if not sc.faults:
        return out
    t0 = sc.faults[0].at
    after = t >= t0
    speed = w["omega_m"] / RPM
    ref = w["speed_ref"] / res.scales.speed_mech(RPM)
    k0 = int(np.argmax(after)) if after.any() else len(t) - 1
    gates_on = w["mode"] != MODE_FAULT
    lost = np.flatnonzero(after & gates_on & (np.abs(res.angle_error_deg()) > LOCK_DEG))
    t_lost = float(t[lost[0]]) if len(lost) else None
    t_trip = float(t[trip[0]]) if len(trip) and t[trip[0]] >= t0 else None
    out.update({
        "lock_lost_s": None if t_lost is None else round(t_lost, 4),
        "lock_detect_ms": None if t_lost is None or t_trip is None else round((t_trip - t_lost) * 1e3, 2),
        "detect_ms": round((float(t[trip[0]]) - t0) * 1e3, 2) if len(trip) and t[trip[0]] >= t0 else None,
        "peak_current_a": round(float(np.max(np.hypot(w["i_d_true"], w["i_q_true"])[after], initial=0.0)), 3),
        "speed_excursion_rpm": round(float(np.max(np.abs(speed[after] - speed[k0]), initial=0.0)), 1),
        "runaway_gates_on": longest_run(after & gates_on & (np.abs(speed - ref) > RUNAWAY_RPM))
        >= RUNAWAY_S * res.scales.f_sw})
    return out


def vdc_volts(sc: Scenario, res: ClosedLoopResult) -> np.ndarray | None:
    """The dc link as the drive measured it per window (``VDC``, docs/spec.md 3.12, read with an ideal divider
    as the firmware does) [V]; None without a dc-link channel."""
    sens = sc.plant["sens"]
    return res.windows["vdc"] * (sens["vdc_range"] / 2 ** sens["adc_bits"]) if sens["vdc_range"] else None


def dc_link_metrics(sc: Scenario, res: ClosedLoopResult) -> dict | None:
    """:func:`vdc_volts`' smallest, mean and largest value over the run [V]; None without a dc-link channel."""
    volts = vdc_volts(sc, res)
    if volts is None:
        return None
    return {"min_v": round(float(volts.min()), 2), "mean_v": round(float(volts.mean()), 2),
            "max_v": round(float(volts.max()), 2)}


def metrics_of(sc: Scenario, res: ClosedLoopResult) -> dict:
    """Angle error, speed, estimator and timing numbers of a closed-loop run (docs/metrics.md)."""
    w = res.windows
    run = np.nonzero(w["mode"] == MODE_RUN)[0]
    t_run = float(res.t[run[0]]) if len(run) else float(res.t[-1])
    err = res.angle_error_deg()
    err_b = res.angle_error_deg(quarters=3)
    after = res.t >= t_run
    switches = estimator_switches(res)
    return {
        "scenario": sc.name,
        "backend": res.backend,
        "duration_s": round(float(res.t[-1]), 4),
        "windows": int(len(res.t)),
        "samples": int(len(res.samples["tick"])),
        "final_mode": MODE_NAMES[int(w["mode"][-1])],
        "run_from_s": round(t_run, 4),
        "polarity_flipped": int(res.flipped),
        "angle_error_after_start": {
            "rms_deg": round(float(np.sqrt(np.mean(err[after] ** 2))), 2) if after.any() else None,
            "peak_deg": round(float(np.max(np.abs(err[after]))), 2) if after.any() else None},
        "angle_error_at_bottom": {
            "rms_deg": round(float(np.sqrt(np.mean(err_b[after] ** 2))), 2) if after.any() else None,
            "peak_deg": round(float(np.max(np.abs(err_b[after]))), 2) if after.any() else None},
        "locked": bool(np.all(np.abs(err[after]) < LOCK_DEG)),
        "segments": segments(sc, res, t_run),
        "estimator_switches": len(switches),
        "estimator_switch_events": switches,
        "faults": fault_metrics(sc, res),
        "dc_link": dc_link_metrics(sc, res),
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
    vdc = vdc_volts(sc, res)
    fig, axes = plt.subplots(4 if vdc is None else 5, 1, figsize=(10, 9 if vdc is None else 11), sharex=True)
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
    if vdc is not None:
        axes[4].plot(t, vdc, lw=0.6, label="VDC (measured)")
        axes[4].axhline(sc.plant["inv"]["V_dc"], color="k", lw=0.6, ls=":", label="nominal")
        axes[4].set_ylabel("dc link [V]")
    axes[-1].set_xlabel("t [s]")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper left") if ax.get_legend_handles_labels()[0] else None
    fig.suptitle(f"{sc.name}: {res.backend} closed loop")
    files.append(save_figure(fig, out_dir, "closed_loop.png"))
    files.append(plot_angles(sc, res, out_dir))

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
    files.append(save_figure(fig, out_dir, "phase_current.png"))
    return files


def angle_deg(a: np.ndarray) -> np.ndarray:
    """u32 binary angles (2^32 = one turn) in degrees, 0..360."""
    return a.astype(np.int64) % 2**32 * (360.0 / 2**32)


def est_spans(res: ClosedLoopResult) -> list[tuple[float, float]]:
    """Time spans [s] in which the high-speed estimator is in charge (``est == 1``), window by window:
    each span runs from the start of its first window to the end of its last."""
    high = np.concatenate([[False], res.windows["est"] == 1, [False]]).astype(np.int8)
    starts, stops = np.nonzero(np.diff(high) == 1)[0], np.nonzero(np.diff(high) == -1)[0]
    period = 1.0 / res.scales.f_sw
    return [(float(res.t[a]) - period, float(res.t[b - 1])) for a, b in zip(starts, stops)]


def plot_angles(sc: Scenario, res: ClosedLoopResult, out_dir: str) -> str:
    """``angles.png``: the true electrical angle, the HF (low-speed) and the high-speed estimators'
    angles, and each one's error, with the spans where the high-speed estimator is in charge shaded
    (as Figs. 29-31 of Benevieri et al. 2023: true angle, HF estimate, RFO estimate); the third panel
    zooms on ZOOM_S around the first estimator switch (the end of the run if there is none)."""
    w, t = res.windows, res.t
    switch = np.nonzero(w["est"][1:] != w["est"][:-1])[0]
    center = t[switch[0] + 1] if len(switch) else t[-1] - ZOOM_S / 2
    zoom = (t >= center - ZOOM_S / 2) & (t <= center + ZOOM_S / 2)
    fig, axes = plt.subplots(3, 1, figsize=(10, 9))
    for ax, sel in ((axes[0], slice(None)), (axes[2], zoom)):
        ax.plot(t[sel], angle_deg(w["theta_e"][sel]), lw=0.8, label="θ (true, plant)")
        ax.plot(t[sel], angle_deg(w["theta_lo"][sel]), lw=0.8, label="θ̂ low-speed slot (HF estimator)")
        ax.plot(t[sel], angle_deg(w["theta_hi"][sel]), lw=0.8, label="θ̂ high-speed slot")
        ax.set(ylabel="electrical angle [deg]", ylim=(0, 360))
    axes[1].plot(t, res.angle_error_deg("theta_lo"), lw=0.6, label="θ − θ̂ low-speed slot")
    axes[1].plot(t, res.angle_error_deg("theta_hi"), lw=0.6, label="θ − θ̂ high-speed slot")
    axes[1].set(ylabel="angle error [deg el.]", ylim=(-180, 180), xlabel="t [s]")
    axes[2].set(xlabel="t [s]", title=f"{ZOOM_S * 1e3:g} ms around the first estimator switch" if len(switch)
                else f"last {ZOOM_S * 1e3:g} ms (no estimator switch)")
    for ax in axes:
        for k, (a, b) in enumerate(est_spans(res)):
            ax.axvspan(a, b, color="0.85", zorder=0, label="high-speed estimator in charge" if k == 0 else None)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper left")
    axes[2].set_xlim(float(t[zoom][0]), float(t[zoom][-1]))
    fig.suptitle(f"{sc.name}: {res.backend} closed loop, estimated angles")
    return save_figure(fig, out_dir, "angles.png")


def save_figure(fig, out_dir: str, name: str, top: float = 1.0) -> str:
    """Lay out (the axes below ``top``, a fraction of the height: room for a suptitle), save as ``out_dir/name``
    (110 dpi) and close ``fig``; returns the path."""
    path = os.path.join(out_dir, name)
    fig.tight_layout(rect=(0, 0, 1, top))
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

