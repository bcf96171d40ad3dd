"""The paper's figure groups: run, reduce to numbers, compare with the paper (Benevieri et al. 2023).

Each ``group_*`` function takes ``short`` (the test-suite length) and returns
``{"ours": {...}, "paper": {...}, "pass": bool, "criteria": str}`` plus the results it ran under
``"_results"`` (for plots; not written to JSON). ``hfi paper`` (:mod:`hfi.reproduce`) runs the full versions
and writes ``out/paper/metrics.json``; ``tests/test_paper.py`` runs the short ones and asserts the same
criteria.

Configurations compared where the paper's own one fails in our model:
``paper``   4 µs dead time uncompensated (the paper's bench);
``project`` the same with the dead-time compensation of docs/spec.md 3.6 (the default scenario).
"""

from __future__ import annotations

import numpy as np

from hfi import paper

PAPER_CFG = {"control": {"dead_time_comp": "off"}}
PROJECT_CFG: dict = {}
SPEED_BW_T3 = "12 Hz"
"""Speed-loop crossover of the Table III runs. Swept over 6-18 Hz (seed 1, load rise 0.2 s), 12 and 14 Hz
are the settings at which the angle holds through both the application and the release of 10 N*m at 50
and 250 r/min, test and full lengths (slower loops let the speed overshoot after the release beyond what
the bang-bang gain tracks, K_bb = 477 r/min). 250 r/min holds with margin (peak errors 28-47 deg over
seeds 1-4); 50 r/min under 10 N*m is marginal in our model (peak errors 37-45 deg; with seed 2 the full-length
application loses the angle)."""
LOAD_RISE_T3 = 0.2
LOCK_DEG = 60.0
"""Angle error beyond which the estimator counts as having lost the rotor (it then slips by 180°)."""


def _fits(res) -> dict:
    return paper.gamma_fit(res, skip=0.02)


def group_fig6_7(short: bool) -> dict:
    dur = 0.55 if short else 1.05
    os_ = paper.run(paper.gamma_sweep("OS", dur))
    ds = paper.run(paper.gamma_sweep("DS", dur))
    f_os, f_ds = _fits(os_), _fits(ds)
    ok = f_os["r2"] >= 0.95 and abs(f_os["delta_deg"]) <= 3.0 and f_ds["r2"] < 0.8
    return {"ours": {"OS": f_os, "DS": f_ds},
            "paper": {"OS": "follows K sin(2 err) with a small zero-crossing offset (Fig. 7)",
                      "DS": "does not follow the ideal curve (Fig. 6)"},
            "criteria": "OS R^2 >= 0.95 and |offset| <= 3 deg; DS R^2 < 0.8",
            "pass": bool(ok), "_results": {"OS": os_, "DS": ds}}


def group_fig8_9(short: bool) -> dict:
    dur = 0.55 if short else 1.05
    os_ = paper.run(paper.gamma_sweep("OS", dur))
    bl = paper.run(paper.gamma_sweep("OS_BLANK", dur))
    f_os, f_bl = _fits(os_), _fits(bl)
    # closed loop under full load: where blanking's non-zero weight sum lets i_q leak into gamma
    kw = dict(duration=1.0, t_load=0.2, t50=0.4, t250=2.0) if short else dict(duration=2.4)
    cl_os = paper.run(paper.speed_steps("blank_ref_os", 2.0, **kw))
    cl_bl = paper.run(paper.speed_steps("blank_closed", 2.0, control={"adc_mode": "OS_BLANK"}, **kw))
    t_end = kw["duration"]
    s_os, s_bl = paper.segment_stats(cl_os, 0.15, t_end), paper.segment_stats(cl_bl, 0.15, t_end)
    os_locked, bl_locked = paper.locked(cl_os, 0.15, LOCK_DEG), paper.locked(cl_bl, 0.15, LOCK_DEG)
    return {"ours": {"open_loop": {"OS": f_os, "OS_BLANK": f_bl},
                     "closed_loop_full_load": {"OS": s_os, "OS_BLANK": s_bl, "OS_locked": os_locked,
                                               "OS_BLANK_locked": bl_locked}},
            "paper": {"OS_BLANK": "worse than plain OS (Fig. 9 vs Fig. 7); not used"},
            "criteria": "closed loop under full load: OS holds the angle, OS_BLANK loses it (more than "
                        f"{LOCK_DEG:g} deg); the open-loop fits (no fundamental current, nothing to leak) "
                        "are reported",
            "pass": bool(os_locked and not bl_locked),
            "_results": {"OS": os_, "OS_BLANK": bl, "closed_OS_BLANK": cl_bl}}


def group_fig11(short: bool) -> dict:
    """OS -> DS at 250 r/min, swept over the sensor noise: DS (one sample at each carrier peak) loses the
    angle above a noise level that OS (1 µs oversampling) still tolerates (docs/spec.md, "Decisions")."""
    t_sw, dur = (0.8, 1.2) if short else (1.0, 1.6)
    noises = (30, 100) if short else (30, 60, 100, 150)
    out, results, threshold = {}, {}, None
    for mA in noises:
        sens = {"sensors": {"noise_rms": f"{mA} mA"}}
        res = paper.run(paper.ds_switch(t_switch=t_sw, duration=dur, **sens))
        before, after = paper.segment_stats(res, t_sw - 0.2, t_sw), paper.segment_stats(res, t_sw, dur)
        lost = after["err_peak_deg"] > 90.0
        out[f"{mA}mA"] = {"OS_before_switch": before, "DS_after_switch": after, "DS_lost": lost,
                          "OS_locked": before["err_peak_deg"] < LOCK_DEG}
        results[f"{mA} mA"] = res
        if lost and threshold is None and out[f"{mA}mA"]["OS_locked"]:
            threshold = mA
    out["DS_loses_from_noise_mA"] = threshold
    return {"ours": out,
            "paper": {"result": "angle estimation lost after switching from OS to DS at 250 r/min (Fig. 11)"},
            "criteria": "at some sensor noise level OS holds the angle and DS, switched in at 250 r/min, loses "
                        "it (report the threshold; the default scenario's noise is 30 mA)",
            "pass": threshold is not None, "_results": results}


def _speed_steps_group(name: str, load: float, short: bool) -> dict:
    if short:
        kw = dict(duration=1.3, t_load=0.2, t50=0.35, t250=0.8)
        segs = {"standstill": (0.15, 0.35), "50rpm": (0.5, 0.8), "250rpm": (1.0, 1.3)}
    else:
        kw = dict(duration=2.4)
        segs = {"standstill": (0.15, 0.8), "50rpm": (1.0, 1.6), "250rpm": (1.9, 2.4)}
    out, results, ok = {}, {}, True
    for cfg_name, cfg in (("paper_config", PAPER_CFG), ("project_config", PROJECT_CFG)):
        res = paper.run(paper.speed_steps(f"{name}_{cfg_name}", load, **kw, **cfg))
        stats = {seg: paper.segment_stats(res, *span) for seg, span in segs.items()}
        stats["locked"] = paper.locked(res, 0.15, LOCK_DEG)
        stats["polarity_flipped"] = res.flipped
        out[cfg_name] = stats
        results[cfg_name] = res
    proj = out["project_config"]
    ok = proj["locked"] and proj["50rpm"]["speed_ripple_rpm"] <= 20.0
    return {"ours": out,
            "paper": {"50rpm_speed_ripple_rpm": 20.0, "locked": True,
                      "dead_time": "4 us, uncompensated"},
            "criteria": "project configuration locked at all times and speed ripple at 50 r/min <= +-20 r/min",
            "pass": bool(ok), "_results": results}


def group_fig12_14(short: bool) -> dict:
    return _speed_steps_group("noload", 0.0, short)


def group_fig15_17(short: bool) -> dict:
    return _speed_steps_group("fullload", 2.0, short)


def group_fig18_23(short: bool) -> dict:
    out, results = {}, {}
    for rpm in (50, 250):
        if short:
            sc = paper.experiment(f"load_steps_{rpm}rpm", {
                "scenario": {"duration": 1.1},
                "load": {"torque": [[0.0, 0.0], [0.5, 0.0], [0.5, 2.0], [0.8, 2.0], [0.8, 0.0]]},
                "reference": {"speed": [[0.0, "0 rpm"], [0.2, "0 rpm"], [0.35, f"{rpm} rpm"]]}})
            t_on = 0.5
        else:
            sc = paper.load_steps(rpm)
            t_on = 0.8
        res = paper.run(sc)
        out[f"{rpm}rpm"] = {"load_on": paper.segment_stats(res, t_on, t_on + 0.3),
                            "locked": paper.locked(res, 0.15, LOCK_DEG)}
        results[f"{rpm}rpm"] = res
    ok = all(v["locked"] for v in out.values())
    return {"ours": out, "paper": {"result": "full-load step and release at 50 and 250 r/min without losing "
                                              "the angle (Figs. 18-23)"},
            "criteria": "locked through both load steps", "pass": bool(ok), "_results": results}


def group_fig24_25(short: bool) -> dict:
    out, results = {}, {}
    dur = 1.4 if short else 2.0
    for load in (0.0, 2.0):
        res = paper.run(paper.sine_reference(load, amp_rpm=25.0, duration=dur))
        g = paper.sine_gain(res, 5.0, 0.8)
        out[f"{load:g}Nm"] = {**g, "locked": paper.locked(res, 0.15, LOCK_DEG)}
        results[f"{load:g}Nm"] = res
    ok = all(v["gain"] >= 1 / np.sqrt(2) and v["locked"] for v in out.values())
    return {"ours": out, "paper": {"speed_loop_bandwidth_hz": 5.0},
            "criteria": "closed-loop speed gain at 5 Hz >= -3 dB (bandwidth >= 5 Hz), locked",
            "pass": bool(ok), "_results": results}


def group_random_starts(short: bool) -> dict:
    rng = np.random.default_rng(2023)
    n = 4 if short else 20
    angles = rng.uniform(0.0, 360.0, n)
    rows, results = [], {}
    for i, ang in enumerate(angles):
        res = paper.run(paper.random_start(float(ang), seed=100 + i, duration=0.9 if short else 1.0))
        end = res.t >= res.t[-1] - 0.1
        row = {"theta_m0_deg": round(float(ang), 1), "flipped": res.flipped,
               "locked": paper.locked(res, 0.15, LOCK_DEG),
               "final_speed_rpm": round(float(np.mean(res.windows["omega_m"][end]) / paper.RPM), 1)}
        row["ok"] = bool(row["locked"] and abs(row["final_speed_rpm"] - 50.0) < 25.0)
        rows.append(row)
        results[f"start_{i}"] = res
    ok = all(r["ok"] for r in rows)
    return {"ours": {"starts": rows, "successes": sum(r["ok"] for r in rows), "total": n},
            "paper": {"result": "polarity detected ([23], [30]); starts under full load"},
            "criteria": "every start: polarity right (never > 60 deg error) and 50 r/min reached under 2 N*m",
            "pass": bool(ok), "_results": results}


def group_table3(short: bool) -> dict:
    """Second motor (Table III, 10 N*m): full-load application and removal at 250 and 50 r/min
    (paper Figs. 33-36). The load machine's torque rises in LOAD_RISE_T3 = 0.2 s (a torque-controlled commercial
    drive behind a Modbus reference cannot step 10 N*m faster)."""
    motor = {"motor": {"preset": "benevieri2023_table3"},
             "control": {"i_max": "6.5 A", "i_trip": "11 A", "speed_bw": SPEED_BW_T3}}
    out, results = {}, {}
    for rpm in ((250,) if short else (250, 50)):
        # release 0.6 s after the application, once the speed has recovered
        kw = dict(duration=1.5, t_on=0.5, t_off=1.1) if short else dict(duration=2.2, t_on=0.8, t_off=1.4)
        res = paper.run(paper.load_steps(rpm, load_nm=10.0, rise=LOAD_RISE_T3, **kw, **motor))
        t_on = kw["t_on"]
        err = np.abs(res.angle_error_deg())
        applied = (res.t >= 0.15) & (res.t < kw["t_off"])
        out[f"{rpm}rpm"] = {"load_on": paper.segment_stats(res, t_on, t_on + 0.3),
                            "locked_through_application": bool(np.all(err[applied] < LOCK_DEG)),
                            "locked_through_release": paper.locked(res, 0.15, LOCK_DEG),
                            "peak_speed_after_release_rpm": round(float(
                                np.max(res.windows["omega_m"][res.t >= kw["t_off"]]) / paper.RPM), 1)}
        results[f"{rpm}rpm"] = res
    ok = all(v["locked_through_application"] and v["locked_through_release"] for v in out.values())
    return {"ours": out, "paper": {"motor": "Table III, 10 N*m",
                                   "result": "full-load steps at 250 and 50 r/min handled (Figs. 33-36)"},
            "criteria": "locked through the application and the release of 10 N*m",
            "pass": bool(ok),
            "_results": results}


GROUPS = {
    "fig6_7": group_fig6_7,
    "fig8_9": group_fig8_9,
    "fig11": group_fig11,
    "fig12_14": group_fig12_14,
    "fig15_17": group_fig15_17,
    "fig18_23": group_fig18_23,
    "fig24_25": group_fig24_25,
    "random_starts": group_random_starts,
    "table3": group_table3,
}
