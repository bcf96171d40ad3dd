"""Outputs of an open-loop injection run (:mod:`hfi.openloop_run`): ``trace.npz``, ``metrics.json``, plots.

- ``trace.npz``: per-sample ADC codes, measured and true currents, estimated-frame currents, carrier;
  per-period HF envelopes, peak-to-peak currents and eq. (19) demodulation;
- ``metrics.json``: HF envelopes vs eq. (18), demodulated signal, sensor error, speed of the run;
- ``phase_currents.png``, ``dq_estimated.png``, ``hf_envelopes.png``.
"""

from __future__ import annotations

import json
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from golden.scenario import Scenario  # noqa: E402
from hfi.openloop_run import OpenLoopResult, estimated_frame, theory_envelopes  # noqa: E402
from hfi.report import save_figure  # noqa: E402


def metrics_of(scn: Scenario, res: OpenLoopResult) -> dict:
    """Numbers of the run: HF envelopes (measured, theory), peak-to-peak, demodulation, noise, speed."""
    theta_e = float(res.truth["theta_e"][0])
    err = theta_e - scn.injection.theta_hat
    a_d, a_q = theory_envelopes(scn, err)
    half = len(res.pp_hat) // 2  # second half of the run: start-up transient gone
    noise = res.i_meas - res.truth["i_abc"]
    return {
        "scenario": scn.name,
        "duration_s": float(len(res.pp_hat) / scn.pwm.f_sw),
        "samples": int(len(res.t)),
        "angle_error_deg": math.degrees(err),
        "hf_envelope_d_hat_A": {"measured": float(np.median(res.env_hat[half:, 0])), "eq18_linear": a_d},
        "hf_envelope_q_hat_A": {"measured": float(np.median(res.env_hat[half:, 1])), "eq18_linear": a_q},
        "peak_to_peak_A": {"d_hat": float(np.median(res.pp_hat[half:, 0])),
                           "q_hat": float(np.median(res.pp_hat[half:, 1]))},
        "demod_eq19_A": {"mean": float(np.mean(res.demod[len(res.demod) // 2:])),
                         "std_per_period": float(np.std(res.demod[len(res.demod) // 2:]))},
        "measurement_error_rms_A": [float(x) for x in np.sqrt(np.mean(noise ** 2, axis=0))],
        "rotor_speed_end_rpm": float(res.truth["omega_m"][-1] * 60 / (2 * math.pi)),
        "wall_s": res.wall_s,
        "realtime_factor": float(len(res.pp_hat) / scn.pwm.f_sw / res.wall_s),
    }


def plot(scn: Scenario, res: OpenLoopResult, out_dir: str) -> list[str]:
    """The three figures of the run; returns their paths."""
    per = len(res.cw) // len(res.pp_hat)
    last = slice(len(res.t) - 2 * per, len(res.t))
    t_ms = res.t[last] * 1e3
    files = []

    fig, ax = plt.subplots(figsize=(10, 4.5))
    for k, name in enumerate("abc"):
        ax.plot(t_ms, res.i_meas[last, k], ".", ms=2, label=f"i_{name} measured (ADC)")
        ax.plot(t_ms, res.truth["i_abc"][last, k], "-", lw=1, label=f"i_{name} true")
    ax.set(xlabel="t [ms]", ylabel="current [A]", title=f"{scn.name}: phase currents, last two PWM periods")
    ax.legend(ncol=3, fontsize=8)
    ax.grid(alpha=0.3)
    files.append(save_figure(fig, out_dir, "phase_currents.png"))

    true_hat = estimated_frame(res.truth["i_abc"], scn.injection.theta_hat)
    fig, axes = plt.subplots(3, 1, figsize=(10, 7), sharex=True)
    axes[0].plot(t_ms, res.cw[last], "k-", lw=1)
    axes[0].set(ylabel="carrier cw")
    for k, name in enumerate(("i_d_hat", "i_q_hat")):
        axes[k + 1].plot(t_ms, res.i_hat[last, k], ".", ms=2, label=f"{name} measured")
        axes[k + 1].plot(t_ms, true_hat[last, k], "-", lw=1, label=f"{name} true")
        axes[k + 1].set(ylabel=f"{name} [A]")
        axes[k + 1].legend(fontsize=8)
        axes[k + 1].grid(alpha=0.3)
    axes[2].set(xlabel="t [ms]")
    fig.suptitle(f"{scn.name}: currents in the estimated frame (theta_hat = "
                 f"{math.degrees(scn.injection.theta_hat):.1f} deg)")
    files.append(save_figure(fig, out_dir, "dq_estimated.png"))

    err = float(res.truth["theta_e"][0]) - scn.injection.theta_hat
    a_d, a_q = theory_envelopes(scn, err)
    fig, axes = plt.subplots(3, 1, figsize=(10, 7), sharex=True)
    tp = res.period_t * 1e3
    axes[0].plot(tp, res.env_hat[:, 0], label="measured: amplitude of i_d_hat on -cw")
    axes[0].axhline(a_d, color="k", ls="--", label="eq. (18) d counterpart, ideal square wave, linear L_d/L_q")
    axes[0].set(ylabel="d envelope [A]")
    axes[1].plot(tp, res.env_hat[:, 1], label="measured: amplitude of i_q_hat on -cw")
    axes[1].axhline(a_q, color="k", ls="--", label="eq. (18), ideal square wave, linear L_d/L_q")
    axes[1].set(ylabel="q envelope [A]")
    axes[2].plot(tp, res.demod, label="mean of i_q_hat sin(-cw pi/2) (eq. 19)")
    axes[2].set(ylabel="demodulated [A]", xlabel="t [ms]")
    for ax in axes:
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    fig.suptitle(f"{scn.name}: HF envelopes per PWM period (angle error {math.degrees(err):.1f} deg)")
    files.append(save_figure(fig, out_dir, "hf_envelopes.png"))
    return files


def write_all(scn: Scenario, res: OpenLoopResult, out_dir: str) -> tuple[dict, list[str]]:
    """Write trace, metrics and plots into ``out_dir``; return the metrics and the files written."""
    os.makedirs(out_dir, exist_ok=True)
    trace = os.path.join(out_dir, "trace.npz")
    np.savez_compressed(trace, t=res.t, adc=res.adc, i_meas=res.i_meas, i_true=res.truth["i_abc"],
                        i_hat=res.i_hat, cw=res.cw, theta_e=res.truth["theta_e"], omega_m=res.truth["omega_m"],
                        period_t=res.period_t, pp_hat=res.pp_hat, env_hat=res.env_hat, demod=res.demod)
    metrics = metrics_of(scn, res)
    mpath = os.path.join(out_dir, "metrics.json")
    with open(mpath, "w") as fh:
        json.dump(metrics, fh, indent=2)
    return metrics, [trace, mpath] + plot(scn, res, out_dir)
