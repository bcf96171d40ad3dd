"""``hfi commission FILE``: the drive measures its motor and tunes itself (docs/commissioning.md).

The scenario gives the plant (motor, inverter, sensors) and the drive's settings; the application's load
profile, speed reference and faults are left out: commissioning runs with the motor at rest and free (the
shaft held during the inductance map when ``commission.lock = "on"``). The run is itself a scenario
(``control.mode = "commission"``, written to ``commission_run.toml``); the firmware runs the identification
program (golden.firmware.ident), the host reduces its sums (golden.commission), compares every value with
the plant's truth and writes:

* ``commission.json``: for each quantity ``measured``, ``truth``, ``rel_error``, plus the tuning;
* ``commissioned.toml``: the scenario with the measured ``[model]``, the tuned ``injection.V_h`` and the
  hand-over speeds, which every other command takes;
* ``commission_scan.png``, ``commission_map.png``, ``commission_lf.png`` (when the stage lf ran),
  ``commission_spin.png``, ``commission_saturation.png`` (a reluctance machine).
"""

from __future__ import annotations

import copy
import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import tomli_w

from golden.commission import (PROBE_DEAD_TIMES, SCAN_BIAS_SHARE, build_program, frame_speed, reduce, settings,
                               spin_speed)
from golden.firmware.estimator import INJ_NONE, METHODS
from golden.firmware.ident import IdentParams
from golden.control_config import scales
from golden.plant.fluxmap import incremental_inductance, psi_from_current
from golden.saturation_fit import EXPONENT_NAMES, fluxes, jacobian
from golden.scenario import load_scenario, parse_scenario, read_toml

HANDOVER_EMF = 2.0
"""Hand-over speed: the back-EMF is this many times the dead time's voltage ``t_d f_sw V_dc`` (the 002 paper's
350 r/min on its Table I motor is 1.9 times; the rule gives 355 r/min there, 157 r/min on the Table III motor
and 669 r/min on the 000 motor, whose scenarios hand over at 350 and 380 r/min: a heuristic of one paper's
case). Written only for a scenario with a high-speed estimator."""
HANDOVER_DOWN = 300 / 350
"""Hand-over down speed as a share of the up speed (the 002 paper's 300 and 350 r/min)."""
STANDSTILL_STAGES = ("probe", "scan", "polarity")
"""The stages that find the rotor angle and the magnet's polarity at standstill."""
SNR_MIN_SALIENCY = 2.0
"""Below this SNR of the saliency signal at the largest HF amplitude an HF method is refused."""


def run_scenario_dict(path: str | Path) -> dict:
    """The commissioning run's scenario tree from the scenario file ``path`` (module docstring)."""
    raw = read_toml(path)
    sc0 = parse_scenario(raw, str(path))
    d = copy.deepcopy(raw)
    for key in ("faults", "reference"):
        d.pop(key, None)
    d["load"] = {k: v for k, v in d.get("load", {}).items() if k == "initial"}
    ctl = d.setdefault("control", {})
    ctl.update(mode="commission", law="foc_pwm", adc_mode="OS", polarity="current")
    ctl.pop("switch_to_ds_at", None)
    d["estimator"] = {"low": "sqw_bangbang", "high": "none"}
    com = d.setdefault("commission", {})
    if "speed" not in com:                       # from the application's reference, which the run leaves out
        com["speed"] = f"{spin_speed(sc0.reference_speed) * 30 / math.pi:.6g} rpm"
    d["scenario"]["name"] = sc0.name + "_commission"
    sc1 = parse_scenario(d, str(path))
    prog = build_program(sc1, settings(sc1))
    d["scenario"]["duration"] = f"{prog.duration:.6g} s"
    if prog.lock:
        d["faults"] = [{"kind": "rotor_blocked", "at": f"{prog.lock[0]:.9g} s", "until": f"{prog.lock[1]:.9g} s"}]
    return d


def standstill_angle(path: str, theta_m_deg: float) -> tuple[float, float]:
    """``(found, true)`` electrical angles [deg] after the standstill stages (STANDSTILL_STAGES, the rest of the
    program cut off) of the scenario file ``path`` from the initial rotor angle ``theta_m_deg`` [deg mechanical]:
    the angle the firmware found and the plant's at the end."""
    from golden.closedloop import ClosedLoop
    from golden.control_config import firmware_params
    from golden.firmware.supervisor import Firmware
    d = run_scenario_dict(path)
    d["load"].setdefault("initial", {})["theta_m"] = f"{theta_m_deg} deg"
    sc = parse_scenario(d, path)
    prog = build_program(sc, settings(sc))
    n = sum(1 for s in prog.steps if s.stage in STANDSTILL_STAGES)
    p = prog.params
    cut = IdentParams(*(getattr(p, f.name)[:n] for f in dataclasses.fields(p) if f.name.startswith("s_")),
                      **{f.name: getattr(p, f.name) for f in dataclasses.fields(p)
                         if f.init and not f.name.startswith("s_")})
    d["scenario"]["duration"] = f"{(sum(cut.s_n) + 4) / sc.pwm.f_sw:.6g} s"
    sc = parse_scenario(d, path)                                      # (the shaft lock from the polarity test on)
    cl = ClosedLoop(sc)
    cl.fw = Firmware(dataclasses.replace(firmware_params(sc), ident=cut))
    run = cl.run(progress=False)
    true = run.windows["theta_e"][-1] / 2**32 * 360.0
    return cl.fw.ident.theta_r / 2**32 * 360.0, true


def truth(sc, bias: float = 0.0) -> dict:
    """The plant's values the measurements are compared with; ``bias`` [A]: the scan's bias current (a reluctance
    machine's, golden.commission.SCAN_BIAS_SHARE): its L_d is the incremental one with the bias on d, its L_q with
    the bias on q."""
    mag, mech, inv = sc.plant["mag"], sc.plant["mech"], sc.plant["inv"]
    L_d = incremental_inductance(mag, *psi_from_current(mag, bias, 0.0))[0, 0]
    L_q = incremental_inductance(mag, *psi_from_current(mag, 0.0, bias))[1, 1]
    return {"R_s": sc.plant["R_s"], "R_path": sc.plant["R_s"] + 0.5 * (inv["r_sw"] + inv["r_diode"]),
            "L_d": float(L_d), "L_q": float(L_q), "psi_f": mag["psi_f"], "J": mech["J"],
            "B": mech["B"], "T_c": mech["T_c"]}


def tuning(sc, res) -> dict:
    """The controller's settings from the measurements: the HF amplitude for ``commission.snr`` (the
    saliency signal of one window over its noise, both measured by the scan, the signal growing with the
    amplitude), but at least PROBE_DEAD_TIMES times the dead time's voltage (and 1 % of V_dc), the hand-over
    speeds (HANDOVER_EMF), and whether an HF method can run at all. The floor (decision, 2026-11-29): the 001
    motor at 1 kHz, whose scan windows average 1000 samples, got 5.4 V from the signal-to-noise rule, 2.5 times
    the dead time's 2.2 V, and its drive lost the angle and tripped; 8.8 and 13.2 V lost it at 300 r/min, 17.6 V
    (8 times) ran its scenario within 0.2 deg of the hand-tuned 20 V (docs/commissioning.md)."""
    sc_, v_dc = scales(sc), sc.plant["inv"]["V_dc"]
    per_volt = res.scan["g_sal"] / res.scan["v_hf"]
    sigma = res.scan["sigma"]
    v_max = settings(sc).hf_voltage_max
    v_dt = sc.pwm.dead_time * sc_.f_sw * v_dc
    v_min = max(PROBE_DEAD_TIMES * v_dt, 0.01 * v_dc)
    v_h = min(max(sc.commission.snr * sigma / per_volt, v_min), v_max) if per_volt > 0 else v_max
    out = {"V_h": v_h, "snr_at_V_h": per_volt * v_h / sigma if sigma > 0 else math.inf,
           "hf_possible": bool(per_volt * v_max / max(sigma, 1e-12) >= SNR_MIN_SALIENCY)}
    psi_f = res.values.get("psi_f", 0.0)
    if psi_f > 0:
        w_up = HANDOVER_EMF * v_dt / (sc_.pole_pairs * psi_f)
        out.update(handover_up=w_up, handover_down=HANDOVER_DOWN * w_up)
    return out


SATURATION_CHECK = ((0.5, 0.0), (0.0, 0.5), (2.0, 0.0), (0.0, 2.0), (-3.0, 1.25), (3.0, 3.0), (6.0, 6.0))
"""Currents [A] at which ``commission.json`` compares the fitted saturation model's flux linkages with the plant's."""


def saturation_check(sc, model: dict) -> list:
    """The fitted saturation model's flux linkages against the plant's at :data:`SATURATION_CHECK` (the rated
    current's MTPA point of the 003 SyRM, -2.9 / 1.6 A, lies between them)."""
    out = []
    for i_d, i_q in SATURATION_CHECK:
        fit = [float(v) for v in fluxes(model, i_d, i_q)]
        true = [float(v) for v in psi_from_current(sc.plant["mag"], i_d, i_q)]
        out.append({"i_d": i_d, "i_q": i_q, "psi": fit, "truth": true,
                    "rel_error": math.hypot(fit[0] - true[0], fit[1] - true[1]) / math.hypot(*true)})
    return out


def commissioned_scenario(path: str | Path, res, tune: dict) -> dict:
    """The scenario file's tree with the measured ``[model]`` and the tuned settings."""
    d = read_toml(path)
    v = res.values
    d["model"] = {"R_s": f"{v['R_s']:.6g} ohm", "L_d": f"{v['L_d']:.6g} H", "L_q": f"{v['L_q']:.6g} H",
                  "psi_f": f"{v.get('psi_f', 0.0):.6g} Wb", "J": f"{v['J']:.6g} kg*m^2",
                  "B": f"{max(v['B'], 0.0):.6g} N*m*s/rad", "T_c": f"{max(v['T_c'], 0.0):.6g} N*m"}
    if res.saturation is not None:                # a reluctance machine's fitted saturation model (SI numbers)
        d["model"]["saturation"] = {k: (int(v) if k in EXPONENT_NAMES else float(f"{v:.6g}"))
                                    for k, v in res.saturation.items()}
    d.setdefault("injection", {})["V_h"] = f"{tune['V_h']:.4g} V"
    if "handover_up" in tune and d.get("estimator", {}).get("high", "none") != "none":   # a hand-over to tune
        est = d["estimator"]
        est["handover_up"] = f"{tune['handover_up'] * 30 / math.pi:.4g} rpm"
        est["handover_down"] = f"{tune['handover_down'] * 30 / math.pi:.4g} rpm"
    d["scenario"]["name"] = d["scenario"]["name"] + "_commissioned"
    d.setdefault("output", {})["dir"] = f"out/{d['scenario']['name']}"
    return d


def commission(path: str | Path, out: Path, progress: bool = True, backend: str = "golden") -> dict:
    """Run the commissioning of the scenario file ``path`` on ``backend`` (any of hfi.backends: the golden model,
    the hls loop, or the rtl co-simulation with the commissioning image on a SoC of ``soc_platform.IDENT_RAM_BYTES``;
    bit-identical); returns the summary."""
    from hfi.backends import run as run_backend
    d = run_scenario_dict(path)
    sc = parse_scenario(d, str(path))
    out.mkdir(parents=True, exist_ok=True)
    (out / "commission_run.toml").write_text(tomli_w.dumps(d))
    cs = settings(sc)
    prog = build_program(sc, cs)
    if progress:
        print(f"{sc.name}: {prog.params.n_steps} steps, {prog.duration:.2f} s simulated"
              + (f", shaft held {prog.lock[0]:.2f}-{prog.lock[1]:.2f} s" if prog.lock else ""), flush=True)
    run = run_backend(sc, backend, progress=progress)
    ident = run.ident
    if ident is None or not ident.done:
        raise CommissionError(_stopped(prog, ident, run, sc, cs))
    res = reduce(prog, ident, sc, cs, run.windows["theta_hat"])
    bias = 0.0 if cs.magnets else cs.current * SCAN_BIAS_SHARE
    tr = truth(sc, bias)
    rows = {}
    for name in ("R_s", "L_d", "L_q", "psi_f", "J", "B", "T_c"):
        if name not in res.values:
            continue
        ref = tr["R_path"] if name == "R_s" else tr[name]
        rows[name] = {"measured": res.values[name], "truth": ref,
                      "rel_error": (res.values[name] - ref) / ref if ref else None}
    rows["R_s"]["truth_motor_only"] = tr["R_s"]
    for name in ("L_d", "L_q"):
        rows[name]["at_current"] = bias
    th_true = (run.windows["theta_e"][0] / 2**32 * 2 * math.pi)
    period = 2 * math.pi if cs.magnets else math.pi
    err = (res.theta_r - th_true + period / 2) % period - period / 2
    mag = sc.plant["mag"]
    map_rows = []
    for i_d, i_q, L in res.map:
        Lt = incremental_inductance(mag, *psi_from_current(mag, i_d, i_q))
        map_rows.append({"i_d": i_d, "i_q": i_q, "L_dd": float(L[0, 0]), "L_qq": float(L[1, 1]),
                         "L_dq": float(L[0, 1]), "truth_dd": float(Lt[0, 0]), "truth_qq": float(Lt[1, 1]),
                         "truth_dq": float(Lt[0, 1]),
                         "rel_error_dd": float(L[0, 0] / Lt[0, 0] - 1), "rel_error_qq": float(L[1, 1] / Lt[1, 1] - 1)})
    tune = tuning(sc, res)
    summary = {"scenario": str(path), "duration_s": prog.duration, "steps": prog.params.n_steps,
               "wall_s": run.wall_s, "values": rows, "angle_error_deg": math.degrees(err),
               "snr_scan": res.snr, "map": map_rows,
               # where L_d, L_q come from: the low-frequency steps (their up and down transitions [H]), the HF scan, or
               # (a reluctance machine whose steps disagree) L_d from the pair on the d axis and L_q from the scan
               # ("axis"; "fit_L_d", "axis_L_d": the scan's and the pair's L_d, kept for a reluctance machine)
               "inductance_from": "lf" if res.lf.get("used") else "axis" if "fit_L_d" in res.scan else "scan",
               **{k: res.scan[k] for k in ("fit_L_d", "axis_L_d") if k in res.scan},
               "lf": {axis: list(res.lf[axis]) for axis in ("d", "q") if axis in res.lf},
               "map_max_rel_error": max(max(abs(r["rel_error_dd"]), abs(r["rel_error_qq"])) for r in map_rows),
               # a reluctance machine: the algebraic saturation model fitted to the map and the chords
               # (golden.commission saturation_data), its RMS relative residual, and its flux linkages against the
               # plant's at test points
               **({"saturation": {"model": res.saturation, "rms": res.saturation_rms,
                                  "flux_check": saturation_check(sc, res.saturation)}}
                  if res.saturation is not None else {}),
               # a magnet machine's program ends with its coast: the gates off, the rotor turning (r/min)
               "coasting_at_end_rpm": (res.spin["w_coast"] / sc.plant["mech"]["pole_pairs"] * 30 / math.pi
                                       if "w_coast" in res.spin else None),
               "tuning": tune}
    (out / "commission.json").write_text(json.dumps(summary, indent=1, default=float))
    _figures(out, prog, res, run, sc, map_rows, tr)
    if progress:
        _print(summary)
    method = load_scenario(path).estimator.low                     # the application's own method
    if not tune["hf_possible"] and METHODS[method].injection != INJ_NONE:
        raise CommissionError(f"{sc.name}: the HF method {method!r} is refused: the saliency signal at the largest HF "
                              f"amplitude ({tune['snr_at_V_h']:.2f} per window at V_h {tune['V_h']:.0f} V) is below "
                              f"{SNR_MIN_SALIENCY} times the measured noise (commission.json written, no "
                              "commissioned.toml): choose a model-based method or a larger commission.hf_voltage_max")
    (out / "commissioned.toml").write_text(tomli_w.dumps(commissioned_scenario(path, res, tune)))
    return summary



class CommissionError(RuntimeError):
    """The identification program stopped before its end; the message says where and why."""


def _stopped(prog, ident, run, sc, cs) -> str:
    """Where the program (the executor ``ident`` at the end of ``run``) stopped, with what the scan saw when it got
    that far."""
    from golden.firmware.protection import FAULT_NAMES
    if ident is None:
        return f"{sc.name}: the {run.backend} backend returned no identification state"
    k = ident.k
    stage = prog.steps[k].stage if k < len(prog.steps) else "end"
    msg = (f"{sc.name}: the identification program stopped in stage {stage!r} (step {k} of {prog.params.n_steps}), "
           f"fault {FAULT_NAMES[int(run.windows['fault'][-1])]}")
    last_scan = max(i for i, s in enumerate(prog.steps) if s.stage == "scan")
    if k > last_scan:
        res = reduce(prog, ident, sc, cs, scan_only=True)
        sal = (res.values["L_q"] - res.values["L_d"]) / (res.values["L_q"] + res.values["L_d"])
        msg += (f"; the scan saw L_d {res.values['L_d']:.4g} H, L_q {res.values['L_q']:.4g} H "
                f"(saliency {100 * sal:.2f} %, SNR {res.snr:.1f} per window)")
        if not cs.magnets and abs(sal) < 0.02:
            msg += (": too little saliency to find the rotor angle, so the map and the spin ran in a wrong frame (a "
                    "reluctance machine whose saliency appears only with current needs the biased scan)")
        else:
            msg += (": the current gains come from the scan's inductances; an HF amplitude small beside the dead "
                    f"time's voltage ({sc.pwm.dead_time * sc.pwm.f_sw * sc.plant['inv']['V_dc']:.3g} V here) makes "
                    "them wrong: raise commission.hf_voltage_max or commission.probe_voltage (docs/commissioning.md)")
    return msg


def _print(s: dict) -> None:
    print(f"{'quantity':8s} {'measured':>12s} {'truth':>12s} {'error':>8s}")
    for name, r in s["values"].items():
        e = "" if r["rel_error"] is None else f"{100 * r['rel_error']:+7.2f}%"
        print(f"{name:8s} {r['measured']:12.5g} {r['truth']:12.5g} {e:>8s}")
    print(f"rotor angle error at standstill {s['angle_error_deg']:+.2f} deg; scan SNR {s['snr_scan']:.1f}; "
          f"map: largest error {100 * s['map_max_rel_error']:.1f}% over {len(s['map'])} points")
    if "saturation" in s:
        sat = s["saturation"]
        exps = ", ".join(f"{k} {sat['model'][k]}" for k in EXPONENT_NAMES)
        worst = max(c["rel_error"] for c in sat["flux_check"])
        print(f"saturation model fitted ({exps}; RMS residual {100 * sat['rms']:.1f} %): flux linkages within "
              f"{100 * worst:.1f} % of the plant's at {len(sat['flux_check'])} points; [model.saturation] written")
    if s["coasting_at_end_rpm"] is not None:
        print(f"the program ended with the gates off and the rotor coasting at {s['coasting_at_end_rpm']:.0f} r/min "
              "(it stops by its friction; a drive started before then needs the flying start, [protection] catch_time)")
    t = s["tuning"]
    print(f"tuning: V_h {t['V_h']:.1f} V (SNR {t['snr_at_V_h']:.1f})"
          + (f", hand-over {t['handover_up'] * 30 / math.pi:.0f}/{t['handover_down'] * 30 / math.pi:.0f} r/min"
             if "handover_up" in t else "") + ("" if t["hf_possible"] else "; HF methods REFUSED: saliency too small"))


def _lf_figure(out: Path, prog, res, run, sc, plt, tr: dict) -> None:
    """commission_lf.png: the current and the voltage written along each axis of the stage lf (holds, the up
    and the down transition shaded), with the inductances found and the plant's (``tr``: hfi.commission.truth)."""
    sc_ = scales(sc)
    starts = np.concatenate([[0], np.cumsum(prog.params.s_n)])
    axes = [a for a in ("d", "q") if a in res.lf]
    fig, axs = plt.subplots(2, len(axes), figsize=(5 * len(axes), 5), sharex="col", squeeze=False)
    for col, axis in enumerate(axes):
        truth_l = tr["L_" + axis]
        ks = [k for k, s in enumerate(prog.steps) if s.stage.startswith("lf") and s.axis == axis]
        j0, j1 = starts[ks[0]], starts[ks[-1] + 1]
        t_ms = np.arange(j1 - j0) / sc_.f_sw * 1e3
        axs[0, col].plot(t_ms, run.windows["i_d"][j0:j1] * sc_.i_lsb, lw=1)
        axs[1, col].plot(t_ms, run.windows["v_d"][j0:j1] * sc_.v_lsb, lw=1)
        for k in ks:
            if prog.steps[k].stage in ("lf_up", "lf_down"):
                for ax in axs[:, col]:
                    ax.axvspan((starts[k] - j0) / sc_.f_sw * 1e3, (starts[k + 1] - j0) / sc_.f_sw * 1e3,
                               color="C1", alpha=0.2)
        up, down = res.lf[axis]
        axs[0, col].set_title(f"along {axis}: L {1e3 * up:.2f} / {1e3 * down:.2f} mH (up / down), plant "
                              f"{1e3 * truth_l:.2f} mH", fontsize=8)
        axs[0, col].set_ylabel(f"i_{axis} window mean [A]")
        axs[1, col].set_ylabel(f"v_{axis} written [V]")
        axs[1, col].set_xlabel("time in the stage [ms] (shaded: the summed transitions)")
    verdict = "used" if res.lf["used"] else "not used: up and down disagree, the HF scan is taken"
    fig.suptitle(f"{sc.name}: low-frequency inductance steps ({verdict})", fontsize=9)
    fig.tight_layout()
    fig.savefig(out / "commission_lf.png", dpi=110)
    plt.close(fig)


def _saturation_figure(out: Path, res, sc, plt, map_rows) -> None:
    """``commission_saturation.png``: the fitted saturation model's flux linkages along each axis at three currents
    on the other (lines) against the plant's (dotted), and its incremental inductances against the map's."""
    mag, fit = sc.plant["mag"], res.saturation
    i_max = max(abs(r["i_d"]) for r in map_rows)
    grid = np.linspace(-i_max, i_max, 161)
    fig, axs = plt.subplots(1, 3, figsize=(13, 4))
    for n, (ax, name) in enumerate(zip(axs[:2], ("d", "q"))):
        for other in (0.0, 0.5 * i_max, i_max):
            cur = (grid, np.full_like(grid, other)) if n == 0 else (np.full_like(grid, other), grid)
            line, = ax.plot(grid, fluxes(fit, *cur)[n], lw=1.2, label=f"fitted, i_{'qd'[n]} = {other:g} A")
            truth = [psi_from_current(mag, a, b)[n] for a, b in zip(*cur)]
            ax.plot(grid, truth, "k:", lw=1)
        ax.set_xlabel(f"i_{name} [A]")
        ax.set_ylabel(f"psi_{name} [V*s] (lines fitted, dotted plant)")
        ax.legend(fontsize=7)
    ax = axs[2]
    for key in ("dd", "qq"):
        rows = [r for r in map_rows if (r["i_d"] if key == "dd" else r["i_q"])]      # own-axis current
        g = [np.linalg.inv(np.array([[a, b], [b, c]])) for a, b, c in
             (jacobian(fit, *fluxes(fit, r["i_d"], r["i_q"])) for r in rows)]
        model = [1e3 * (L[0, 0] if key == "dd" else L[1, 1]) for L in g]
        ax.plot([1e3 * r["L_" + key] for r in rows], model, "o", label=f"L_{key}")
    lim = ax.get_xlim()
    ax.plot(lim, lim, "k-", lw=0.6)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("measured (map) [mH]")
    ax.set_ylabel("fitted model [mH]")
    ax.legend(fontsize=7)
    e = ", ".join(f"{k} {v:g}" for k, v in fit.items() if k in EXPONENT_NAMES)
    fig.suptitle(f"{sc.name}: fitted saturation model ({e}; RMS residual {100 * res.saturation_rms:.1f} %)",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(out / "commission_saturation.png", dpi=110)
    plt.close(fig)


def _figures(out: Path, prog, res, run, sc, map_rows, tr: dict) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from golden.plant.fluxmap import incremental_inductance as l_inc
    mag = sc.plant["mag"]
    # scan
    fig, ax = plt.subplots(figsize=(7, 4))
    ph = np.degrees(res.scan["phi"])
    ax.plot(ph, res.scan["gamma"].real, "o", label="along the injection (measured)")
    ax.plot(ph, -res.scan["gamma"].imag, "s", label="across (measured)")
    th = run.windows["theta_e"][0] / 2**32 * 2 * math.pi
    L0 = l_inc(mag, *psi_from_current(mag, 0, 0))
    G = np.linalg.inv(L0)
    fine = np.linspace(0, math.pi, 181)
    rel = fine - th
    along = [np.array([math.cos(a), math.sin(a)]) @ G @ np.array([math.cos(a), math.sin(a)]) for a in rel]
    across = [np.array([-math.sin(a), math.cos(a)]) @ G @ np.array([math.cos(a), math.sin(a)]) for a in rel]
    ax.plot(np.degrees(fine), along, "-", lw=1, label="plant: along")
    ax.plot(np.degrees(fine), across, "--", lw=1, label="plant: across")
    ax.set_xlabel("injection angle in the stator [deg el]")
    ax.set_ylabel("inverse incremental inductance [1/H]")
    ax.set_title(f"{sc.name}: HF scan at standstill (rotor at {math.degrees(th) % 360:.1f} deg, "
                 f"found {math.degrees(res.theta_r) % 360:.1f} deg)", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "commission_scan.png", dpi=110)
    plt.close(fig)
    # map
    fig, axs = plt.subplots(1, 2, figsize=(10, 4))
    for key, ax, name in (("dd", axs[0], "L_dd"), ("qq", axs[1], "L_qq")):
        for iq in sorted({r["i_q"] for r in map_rows}):
            rr = [r for r in map_rows if r["i_q"] == iq]
            x = [r["i_d"] for r in rr]
            line, = ax.plot(x, [1e3 * r["truth_" + key] for r in rr], "-", lw=1)
            ax.plot(x, [1e3 * r["L_" + key] for r in rr], "o", color=line.get_color(), label=f"i_q = {iq:.2f} A")
        ax.set_xlabel("i_d [A]")
        ax.set_ylabel(f"{name} [mH] (markers measured, lines plant)")
        ax.legend(fontsize=7)
    fig.suptitle(f"{sc.name}: incremental inductance map", fontsize=9)
    fig.tight_layout()
    fig.savefig(out / "commission_map.png", dpi=110)
    plt.close(fig)
    if res.lf:
        _lf_figure(out, prog, res, run, sc, plt, tr)
    if res.saturation is not None:
        _saturation_figure(out, res, sc, plt, map_rows)
    # spin
    fig, ax = plt.subplots(figsize=(8, 4))
    t = run.t
    pp = sc.plant["mech"]["pole_pairs"]

    ax.plot(t, run.windows["omega_m"] * 30 / math.pi, lw=1, label="rotor speed (plant)")
    w_frame = frame_speed(run.windows["theta_hat"], scales(sc).w_lsb) / pp * 30 / math.pi
    ax.plot(t, w_frame, "--", lw=1, label="frame speed (program)")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("speed [r/min]")
    ax.set_title(f"{sc.name}: spin test (I/f); J {res.values['J']:.4g} kg*m^2", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "commission_spin.png", dpi=110)
    plt.close(fig)
