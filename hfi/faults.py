"""``hfi faults``: the fault matrix of the 002 drive (docs/faults.md).

Every fault of :data:`FAULTS` is injected into the plant of the default scenario (Table I motor, the
paper's control) at :data:`ONSET_S`, in RUN at each speed of :data:`SPEEDS_RPM`, without load and at
rated load, on the golden closed loop. For each run the firmware's reaction is taken from the trace
(:func:`hfi.report.fault_metrics`) and judged:

``detected``  the firmware tripped after the onset (its code and the time to detect);
``harmless``  it did not trip, and nothing happened that a trip should prevent: no runaway with the gates
              on, the current within ``control.i_trip``, the speed within :data:`HARMLESS_RPM` of its
              value at the onset;
``MISSED``    anything else.

The restart part (:func:`run_restart`): every fault again, lasting :data:`TRANSIENT_S` only, at
:data:`RESTART_RPM` with and without load, with ``[protection] restarts = 1`` after :data:`RESTART_DELAY_S`:
does the drive trip, start again once the fault has cleared (CONVERGE, the polarity test, RUN) and hold its
reference locked at the end? Each cell twice: the paper's drive (the restart is a standstill start) and with the
flying start (the rotor flux observer as the high-speed estimator, ``[protection] catch_time`` =
:data:`CATCH_S` and its probe :data:`CATCH_PROBE`: the restart first catches a rotor the load has spun up while the
drive coasted).

Outputs in ``--out`` (default ``out/faults``): ``matrix.json`` (one object per run), ``restart.json``,
``matrix.md`` (the tables of docs/faults.md) and one figure per run in ``fig/``. Progress on stderr, one line
per run.
"""

from __future__ import annotations

import copy
import json
import os
import sys
import time
import tomllib
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from golden.closedloop import ClosedLoop
from golden.firmware.supervisor import MODE_FAULT
from golden.scenario import parse_scenario
from hfi.paper import BASE, RPM

ONSET_S = 0.8
"""Fault onset: in RUN, 0.3 s after the speed reached its plateau."""
DURATION_S = 1.6
"""End of each run (0.8 s after the onset: the overload check needs 0.5 s at the current limit)."""
DURATION_SHORT_S = 1.0
SPEEDS_RPM = (0.0, 50.0, 250.0)
RATED_NM = 2.0
"""Rated torque of the Table I motor (the default scenario's full load)."""
ZOOM_S = 0.15
"""The right-hand panels of a run's figure: this long after the onset (and 20 ms before)."""
TRANSIENT_S = 0.05
"""The restart part: each fault lasts this long (``until`` = onset + TRANSIENT_S)."""
RESTART_RPM = 50.0
RESTART_DELAY_S = 0.2
"""``[protection] restart_delay`` of the restart part (the firmware's safe state lasts this long)."""
RESTART_EXTRA_S = 1.0
"""The restart part's runs last this much longer than the matrix's: a flying start brakes a rotor the rated
(active) load has spun to about -1000 r/min with 0.65 N*m to spare (0.6 s), then hands over to the HF estimator."""
CATCH_S = 0.04
"""``[protection] catch_time`` of the flying start (30 ms is the least that works on the Table I motor: the speed
filter has not settled after 20 ms, and the overload check then sees the speed error grow)."""
CATCH_PROBE = "50 mA"
"""``[protection] catch_probe`` of the flying start: its short-circuit probe finds a rotor above about 1000 r/min on
the Table I motor (scenarios/flying_start.toml, docs/faults.md)."""
RELOCK_DEG = 15.0
RELOCK_RPM = 10.0
"""A restart holds when, over the last RELOCK_WINDOW_S of the run, the drive is in RUN, the angle error's RMS is
within RELOCK_DEG (healthy: about 5 deg) and the mean speed within RELOCK_RPM of the reference."""
RELOCK_WINDOW_S = 0.1
HARMLESS_RPM = 100.0
"""An undetected fault is harmless if the speed stays within this of its value at the onset (and no runaway,
no overcurrent)."""

FAULTS: dict[str, dict] = {
    "none": {},
    "sensor offset 0.5 A (a)": {"kind": "sensor_offset", "phase": "a", "offset": "0.5 A"},
    "sensor drift 5 A/s (a)": {"kind": "sensor_offset", "phase": "a", "drift": "5 A/s"},
    "sensor gain x0.7 (a)": {"kind": "sensor_gain", "phase": "a", "gain": 0.7},
    "ADC stuck at +1.3 A (a)": {"kind": "adc_stuck", "phase": "a", "code": 2475},
    "ADC lane dead (b)": {"kind": "adc_lane_dead", "phase": "b"},
    "ADC lane dead (dc link)": {"kind": "adc_lane_dead", "phase": "dc"},
    "phase open (a)": {"kind": "phase_open", "phase": "a"},
    "switch open (a high)": {"kind": "switch_open", "switch": "a_hi"},
    "dc-link sag -30 %": {"kind": "dc_link", "factor": 0.7},
    "dc-link loss (20 ms)": {"kind": "dc_link", "factor": 0.0, "tau": "20 ms"},
    "dc-link surge +40 %": {"kind": "dc_link", "factor": 1.4},
    "load impact +2x rated": {"kind": "load_step", "torque": f"{2 * RATED_NM} N*m"},
    "rotor blocked": {"kind": "rotor_blocked"},
    "load drives at -3x rated": {"kind": "load_step", "torque": f"{-3 * RATED_NM} N*m"},
}
"""Matrix rows: name -> the ``[[faults]]`` entry without ``at`` (``{}``: the healthy reference)."""


def scenario(fault: dict, rpm: float, loaded: bool, duration: float, restart: bool = False, flying: bool = False):
    """The default scenario with the load from 0.2 s, the speed ramp 0.3-0.5 s and ``fault`` at ONSET_S, on the 002
    system as issue 14 completed it: the rotor flux observer beside the HF estimator (``estimator.high``; its
    hand-over at 350 r/min lies above every speed of the matrix, and the slip check compares the two). ``restart``:
    the fault lasting TRANSIENT_S, one restart RESTART_DELAY_S after a trip; ``flying``: with the flying start
    (``catch_time`` CATCH_S and its probe)."""
    data = tomllib.loads(BASE.read_text())
    data["scenario"].update(duration=f"{duration} s", name="fault_matrix")
    data.setdefault("estimator", {}).update(high="rfo")
    torque = RATED_NM if loaded else 0.0
    data["load"]["torque"] = [["0 s", "0 N*m"], ["0.2 s", "0 N*m"], ["0.2 s", f"{torque} N*m"]]
    data["reference"]["speed"] = [["0 s", "0 rpm"], ["0.3 s", "0 rpm"], ["0.5 s", f"{rpm} rpm"]]
    if fault:
        data["faults"] = [dict(copy.deepcopy(fault), at=f"{ONSET_S} s")]
        if restart:
            data["faults"][0]["until"] = f"{ONSET_S + TRANSIENT_S} s"
    if restart:
        data.setdefault("protection", {}).update(restarts=1, restart_delay=f"{RESTART_DELAY_S} s")
    if flying:
        data.setdefault("protection", {}).update(catch_time=f"{CATCH_S} s", catch_probe=CATCH_PROBE)
    return parse_scenario(data, source=f"fault matrix ({BASE.name})")


def run_one(job: tuple) -> dict:
    """One matrix cell: run, judge, plot; returns its row of matrix.json."""
    name, rpm, loaded, duration, fig_dir = job
    from hfi.report import fault_metrics
    sc = scenario(FAULTS[name], rpm, loaded, duration)
    t0 = time.perf_counter()
    res = ClosedLoop(sc).run(progress=False)
    m = fault_metrics(sc, res)
    i_trip = sc.control.i_trip
    tripped = m["code"] != "none" and m["at_s"] is not None and m["at_s"] >= ONSET_S
    if not sc.faults:
        verdict = "healthy" if m["code"] == "none" else "FALSE TRIP"
    elif tripped:
        verdict = "detected"
    elif (not m["runaway_gates_on"] and m["peak_current_a"] <= i_trip
          and m["speed_excursion_rpm"] <= HARMLESS_RPM):
        verdict = "harmless"
    else:
        verdict = "MISSED"
    row = {"fault": name, "speed_rpm": rpm, "load": "rated" if loaded else "none", "verdict": verdict,
           "code": m["code"], "detect_ms": m.get("detect_ms"), "lock_detect_ms": m.get("lock_detect_ms"),
           "lock_lost": m.get("lock_lost_s") is not None,
           "reaction": reaction(res) if tripped else "-",
           "peak_current_a": m.get("peak_current_a"), "speed_excursion_rpm": m.get("speed_excursion_rpm"),
           "runaway_gates_on": m.get("runaway_gates_on", False), "wall_s": round(time.perf_counter() - t0, 1)}
    row["figure"] = plot_row(res, row, fig_dir)
    return row


def run_restart(job: tuple) -> dict:
    """One cell of the restart part: the fault for TRANSIENT_S, one restart allowed; returns its row of
    restart.json: the first trip's code and time, the restart's time (the first window out of FAULT), a second
    trip's code, and whether the drive holds its reference locked at the end (RELOCK_*)."""
    from golden.firmware.protection import FAULT_NAMES
    from golden.firmware.supervisor import MODE_RUN
    from hfi.report import fault_metrics
    name, loaded, flying, duration, fig_dir = job
    sc = scenario(FAULTS[name], RESTART_RPM, loaded, duration, restart=True, flying=flying)
    t0 = time.perf_counter()
    res = ClosedLoop(sc).run(progress=False)
    w, t = res.windows, res.t
    mode = w["mode"]
    after = t >= ONSET_S
    trips = np.flatnonzero(after & (mode == MODE_FAULT) & (np.roll(mode, 1) != MODE_FAULT))
    first = int(trips[0]) if len(trips) else None
    restart = None
    if first is not None:
        back = np.flatnonzero((np.arange(len(t)) > first) & (mode != MODE_FAULT))
        restart = int(back[0]) if len(back) else None
    second = next((int(k) for k in trips if restart is not None and k > restart), None)
    end = t >= t[-1] - RELOCK_WINDOW_S
    err = res.angle_error_deg()[end]
    speed = float(np.mean(w["omega_m"][end])) / RPM
    locked = bool((mode[end] == MODE_RUN).all() and np.sqrt(np.mean(err ** 2)) <= RELOCK_DEG
                  and abs(speed - RESTART_RPM) <= RELOCK_RPM)
    row = {"fault": name, "load": "rated" if loaded else "none", "start": "flying" if flying else "standstill",
           "code": FAULT_NAMES[w["fault"][first]] if first is not None else "none",
           "trip_s": None if first is None else round(float(t[first]), 4),
           "restart_s": None if restart is None else round(float(t[restart]), 4),
           "second_code": FAULT_NAMES[w["fault"][second]] if second is not None else "none",
           "end_speed_rpm": round(speed, 1), "end_angle_rms_deg": round(float(np.sqrt(np.mean(err ** 2))), 2),
           "extreme_speed_rpm": round(float(w["omega_m"][after][np.argmax(np.abs(w["omega_m"][after]))]) / RPM, 1),
           "peak_current_a": round(fault_metrics(sc, res)["peak_current_a"], 2),
           "locked_at_end": locked, "wall_s": round(time.perf_counter() - t0, 1)}
    row["figure"] = plot_restart(res, row, fig_dir)
    return row


def plot_restart(res, row: dict, fig_dir: str) -> str:
    """Speed (true, reference, estimated), angle error and current amplitude of one run of the restart part,
    with the fault's span, the trip and the restart marked."""
    from hfi.report import plt, save_figure
    w, t = res.windows, res.t
    fig, axes = plt.subplots(3, 1, figsize=(10, 7), sharex=True)
    axes[0].plot(t, w["speed_ref"] / res.scales.speed_mech(RPM), label="reference")
    axes[0].plot(t, w["omega_m"] / RPM, lw=0.8, label="true (plant)")
    axes[0].plot(t, w["omega_f"] / res.scales.speed_mech(RPM), lw=0.6, label="estimated")
    axes[0].set_ylabel("speed [r/min]")
    axes[1].plot(t, res.angle_error_deg(), lw=0.6)
    axes[1].set_ylabel("angle error [deg el.]")
    axes[2].plot(t, np.hypot(w["i_d_true"], w["i_q_true"]), lw=0.6, label="|i| (plant)")
    axes[2].set(ylabel="[A]", xlabel="t [s]")
    for ax in axes:
        ax.axvspan(ONSET_S, ONSET_S + TRANSIENT_S, color="r", alpha=0.15, label="fault")
        for key, style, what in (("trip_s", "--", f"trip: {row['code']}"), ("restart_s", ":", "restart")):
            if row[key] is not None:
                ax.axvline(row[key], color="k", ls=style, lw=0.8, label=what)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7, loc="upper left")
    fig.suptitle(f"restart ({row['start']} start): {row['fault']} for {TRANSIENT_S * 1e3:g} ms, {RESTART_RPM:g} r/min, "
                 f"load {row['load']}: {'locked' if row['locked_at_end'] else 'NOT locked'} at the end")
    slug = "".join(c if c.isalnum() else "_" for c in f"restart_{row['fault']}_{row['load']}_{row['start']}")
    return save_figure(fig, fig_dir, f"{slug}.png")


def restart_table(rows: list[dict]) -> str:
    """The markdown table of the restart part and its summary line."""
    lines = [f"| fault ({TRANSIENT_S * 1e3:g} ms) | load | start | trip | at [s] | restart at [s] | second trip | "
             "extreme speed [r/min] | peak current [A] | speed at the end [r/min] | "
             "angle error RMS at the end [deg] | locked at the end |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['fault']} | {r['load']} | {r['start']} | {r['code']} | {r['trip_s'] or '-'} | "
                     f"{r['restart_s'] or '-'} | {r['second_code']} | {r['extreme_speed_rpm']} | "
                     f"{r['peak_current_a']} | {r['end_speed_rpm']} | {r['end_angle_rms_deg']} | "
                     f"{'yes' if r['locked_at_end'] else 'NO'} |")
    parts = []
    for start in ("standstill", "flying"):
        sel = [r for r in rows if r["start"] == start]
        tripped = [r for r in sel if r["code"] != "none"]
        held = sum(r["locked_at_end"] for r in tripped)
        quiet = sum(r["locked_at_end"] for r in sel if r["code"] == "none")
        if sel:
            parts.append(f"{start} start: {len(sel)} transient faults at {RESTART_RPM:g} r/min, "
                         f"{len(tripped)} tripped, {held} of them locked again at the end after the restart; "
                         f"{quiet} of {len(sel) - len(tripped)} that did not trip locked")
    return "\n".join(lines) + "\n\n" + "; ".join(parts) + "\n"


def reaction(res) -> str:
    """The safe state the firmware chose: the outputs it wrote at the trip enabled (zero voltage: the active
    short circuit) or not (the gates off: coast)."""
    trip = int(np.flatnonzero(res.windows["mode"] == MODE_FAULT)[0])
    return "short circuit" if res.writes["enable"][trip] else "coast"


def plot_row(res, row: dict, fig_dir: str) -> str:
    """Speed (true, reference, estimated) and current amplitude of one run: the whole run on the left, the
    ZOOM_S after the onset on the right; the onset and the trip marked."""
    from hfi.report import plt, save_figure
    w, t = res.windows, res.t
    trip = np.flatnonzero(w["mode"] == MODE_FAULT)
    zoom = (t >= ONSET_S - 0.02) & (t <= ONSET_S + ZOOM_S)
    fig, axes = plt.subplots(2, 2, figsize=(11, 5.5), sharex="col", gridspec_kw={"width_ratios": (3, 2)})
    for col, sel in enumerate((slice(None), zoom)):
        ax_w, ax_i = axes[0, col], axes[1, col]
        ax_w.plot(t[sel], w["speed_ref"][sel] / res.scales.speed_mech(RPM), label="reference")
        ax_w.plot(t[sel], w["omega_m"][sel] / RPM, lw=0.8, label="true (plant)")
        ax_w.plot(t[sel], w["omega_f"][sel] / res.scales.speed_mech(RPM), lw=0.6, label="estimated")
        ax_i.plot(t[sel], np.hypot(w["i_d_true"], w["i_q_true"])[sel], lw=0.6, label="|i| (plant)")
        ax_w.set_ylabel("speed [r/min]")
        ax_i.set(ylabel="[A]", xlabel="t [s]")
        for ax in (ax_w, ax_i):
            ax.axvline(ONSET_S, color="r", lw=0.8, label="fault onset")
            if len(trip):
                ax.axvline(t[trip[0]], color="k", ls="--", lw=0.8, label=f"trip: {row['code']}")
            ax.grid(alpha=0.3)
        ax_w.legend(fontsize=7, loc="upper left")
    axes[0, 1].set_title(f"{ZOOM_S * 1e3:g} ms after the onset", fontsize=9)
    fig.suptitle(f"{row['fault']}, {row['speed_rpm']:g} r/min, load {row['load']}: {row['verdict']}")
    slug = "".join(c if c.isalnum() else "_" for c in f"{row['fault']}_{row['speed_rpm']:g}_{row['load']}")
    return save_figure(fig, fig_dir, f"{slug}.png")


def table(rows: list[dict]) -> str:
    """The markdown table of docs/faults.md and the summary line."""
    lines = ["| fault | r/min | load | verdict | code | detect [ms] | lock lost -> trip [ms] | reaction | "
             "peak current [A] | speed excursion [r/min] | runaway, gates on |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['fault']} | {r['speed_rpm']:g} | {r['load']} | {r['verdict']} | {r['code']} | "
                     f"{'-' if r['detect_ms'] is None else r['detect_ms']} | "
                     f"{'-' if r['lock_detect_ms'] is None else r['lock_detect_ms']} | {r['reaction']} | "
                     f"{r['peak_current_a'] or '-'} | "
                     f"{'-' if r['speed_excursion_rpm'] is None else r['speed_excursion_rpm']} | "
                     f"{'yes' if r['runaway_gates_on'] else 'no'} |")
    return "\n".join(lines) + "\n\n" + summary(rows) + "\n"


def summary(rows: list[dict]) -> str:
    faulty = [r for r in rows if r["fault"] != "none"]
    count = {v: sum(r["verdict"] == v for r in faulty) for v in ("detected", "harmless", "MISSED")}
    times = [r["detect_ms"] for r in faulty if r["detect_ms"] is not None]
    false = sum(r["verdict"] == "FALSE TRIP" for r in rows)
    lock = [r["lock_detect_ms"] for r in faulty if r["lock_detect_ms"] is not None]
    undetected_lock = sum(r["lock_lost"] and r["lock_detect_ms"] is None for r in faulty)
    return (f"{len(faulty)} faulty runs: {count['detected']} detected, {count['harmless']} harmless, "
            f"{count['MISSED']} missed; {sum(r['runaway_gates_on'] for r in faulty)} runaways with the gates on; "
            f"{false} false trips in {len(rows) - len(faulty)} healthy runs; detection "
            f"{min(times, default=0):g}..{max(times, default=0):g} ms after the onset; lock lost in "
            f"{len(lock) + undetected_lock} runs, tripped {min(lock, default=0):g}..{max(lock, default=0):g} ms "
            f"after, {undetected_lock} never")


def main(short: bool = False, jobs: int = 2, out: Path = Path("out/faults"), only: str = "") -> int:
    """Run the matrix; exit status 1 if a fault was missed, a run with the gates on ran away or a healthy run
    tripped."""
    names = [n for n in FAULTS if not only or n in only.split(",")]
    unknown = [n for n in only.split(",") if n and n not in FAULTS]
    if unknown:
        raise ValueError(f"unknown fault rows {unknown} (rows: {', '.join(FAULTS)})")
    fig_dir = str(out / "fig")
    os.makedirs(fig_dir, exist_ok=True)
    duration = DURATION_SHORT_S if short else DURATION_S
    cells = [(n, rpm, loaded, duration, fig_dir) for n in names for rpm in SPEEDS_RPM for loaded in (False, True)]
    rows = []
    with ProcessPoolExecutor(max_workers=max(jobs, 1)) as pool:
        for k, row in enumerate(pool.map(run_one, cells)):
            rows.append(row)
            print(f"[{k + 1}/{len(cells)}] {row['fault']}, {row['speed_rpm']:g} r/min, {row['load']}: "
                  f"{row['verdict']} ({row['code']}, {row['detect_ms']} ms), {row['wall_s']} s", file=sys.stderr,
                  flush=True)
    jobs_r = [(n, loaded, flying, duration + RESTART_EXTRA_S, fig_dir) for n in names if FAULTS[n]
              for loaded in (False, True) for flying in (False, True)]
    restart_rows = []
    with ProcessPoolExecutor(max_workers=max(jobs, 1)) as pool:
        for k, row in enumerate(pool.map(run_restart, jobs_r)):
            restart_rows.append(row)
            print(f"[restart {k + 1}/{len(jobs_r)}] {row['fault']}, {row['load']}, {row['start']} start: "
                  f"{row['code']} -> restart {row['restart_s']} s -> {row['second_code']}, "
                  f"locked at the end: {row['locked_at_end']}, {row['wall_s']} s", file=sys.stderr, flush=True)
    (out / "matrix.json").write_text(json.dumps(rows, indent=1) + "\n")
    (out / "restart.json").write_text(json.dumps(restart_rows, indent=1) + "\n")
    (out / "matrix.md").write_text(table(rows) + "\n" + restart_table(restart_rows))
    print(summary(rows))
    print(restart_table(restart_rows).splitlines()[-1])
    bad = [r for r in rows if r["verdict"] in ("MISSED", "FALSE TRIP") or r["runaway_gates_on"]]
    return 1 if bad else 0
