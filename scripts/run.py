#!/usr/bin/env python3
"""Main job (``make run``): simulate a scenario and write its trace, metrics and plots.

A scenario with a ``[control]`` table runs a closed loop (the default, ``scenarios/fullload_start.toml``)
on one of three backends (``--backend``, default ``$BACKEND`` or ``rtl``):

- ``rtl``: the firmware (firmware/, C) on the PicoRV32 of the Verilated ``hfi_soc`` drives the C plant
  through the RTL (:mod:`hfi.rtl_backend`; ``--fst`` writes waveforms);
- ``golden``: the bit-true Python model of the same system (:mod:`golden.closedloop`), ~30x faster;
- ``hls``: the HLS-style C++ kernels of hls/ (native C simulation) with the host build of the firmware
  and the C plant (:mod:`hfi.hls_backend`), the fastest.

All give identical traces (tests/test_rtl_identity.py, tests/test_hls_identity.py) and write
``trace.npz`` (per-window registers, firmware state and plant truth; every ADC sample), ``metrics.json`` (angle error and speed per reference plateau),
``closed_loop.png`` and ``phase_current.png`` (:mod:`hfi.report`).

A scenario without one is the open-loop injection study of :mod:`hfi.openloop_run`:
square-wave injection on a fixed estimated d-axis into the realistic plant. Outputs, in the
scenario's output directory (default ``out/<scenario name>/``):

- ``trace.npz``: per-sample ADC codes, measured and true currents, estimated-frame currents,
  carrier; per-period HF envelopes, peak-to-peak currents and eq. (19) demodulation;
- ``metrics.json``: HF envelopes vs eq. (18), demodulated signal, sensor error, speed of the run;
- ``phase_currents.png``, ``dq_estimated.png``, ``hf_envelopes.png``.

Usage: scripts/run.py [SCENARIO.toml] [--out DIR] [--quiet] [--backend rtl|golden|hls]
                     [--fst FILE [--fst-window T0 T1]]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from golden.plant import PlantError  # noqa: E402
from golden.scenario import ScenarioError, load_scenario  # noqa: E402
from hfi import backends  # noqa: E402
from hfi.openloop_run import simulate, theory_envelopes  # noqa: E402
from hfi.report import write_all  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_SCENARIO = os.path.join(HERE, "..", "scenarios", "fullload_start.toml")
BACKENDS = backends.NAMES


def metrics_of(scn, res) -> dict:
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


def _true_hat(res, theta_hat):
    i = res.truth["i_abc"]
    i_al = (2 * i[:, 0] - i[:, 1] - i[:, 2]) / 3
    i_be = (i[:, 1] - i[:, 2]) / math.sqrt(3)
    c, s = math.cos(theta_hat), math.sin(theta_hat)
    return np.stack([c * i_al + s * i_be, -s * i_al + c * i_be], axis=1)


def plot(scn, res, out_dir: str) -> list[str]:
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
    files.append(_save(fig, out_dir, "phase_currents.png"))

    true_hat = _true_hat(res, scn.injection.theta_hat)
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
    files.append(_save(fig, out_dir, "dq_estimated.png"))

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
    files.append(_save(fig, out_dir, "hf_envelopes.png"))
    return files


def _save(fig, out_dir, name) -> str:
    path = os.path.join(out_dir, name)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scenario", nargs="?", default=DEFAULT_SCENARIO)
    ap.add_argument("--out", help="output directory (default: the scenario's output.dir)")
    ap.add_argument("--quiet", action="store_true", help="no progress bar")
    ap.add_argument("--backend", choices=BACKENDS, default=os.environ.get("BACKEND") or "rtl",
                    help="closed-loop backend (default: $BACKEND or rtl)")
    ap.add_argument("--fst", help="rtl backend: write an FST waveform of the SoC to this file")
    ap.add_argument("--fst-window", nargs=2, type=float, metavar=("T0", "T1"), default=(0.0, 0.002),
                    help="time span of the waveform [s] (default 0 0.002)")
    args = ap.parse_args()
    if args.backend not in BACKENDS:
        print(f"run: unknown backend {args.backend!r} ({', '.join(BACKENDS)})", file=sys.stderr)
        return 1
    try:
        scn = load_scenario(args.scenario)
        out_dir = args.out or scn.output.dir
        os.makedirs(out_dir, exist_ok=True)
        if scn.control is not None:
            options = {"fst": args.fst, "fst_window": tuple(args.fst_window)} if args.backend == "rtl" else {}
            res = backends.run(scn, args.backend, progress=not args.quiet, **options)
            if res.soc is not None:
                sys.stderr.write("".join(f"[fw] {line}\n" for line in res.soc["uart_log"].splitlines()))
            metrics, files = write_all(scn, res, out_dir)
            print(json.dumps(metrics, indent=2))
            print("wrote", ", ".join(files))
            return 0
        res = simulate(scn, progress=not args.quiet)
    except (ScenarioError, PlantError, OSError, ValueError, backends.BackendError) as exc:
        print(f"run: {exc}", file=sys.stderr)
        return 1
    np.savez_compressed(os.path.join(out_dir, "trace.npz"), t=res.t, adc=res.adc, i_meas=res.i_meas,
                        i_true=res.truth["i_abc"], i_hat=res.i_hat, cw=res.cw, theta_e=res.truth["theta_e"],
                        omega_m=res.truth["omega_m"], period_t=res.period_t, pp_hat=res.pp_hat,
                        env_hat=res.env_hat, demod=res.demod)
    metrics = metrics_of(scn, res)
    with open(os.path.join(out_dir, "metrics.json"), "w") as fh:
        json.dump(metrics, fh, indent=2)
    files = plot(scn, res, out_dir)
    print(json.dumps(metrics, indent=2))
    print("wrote", ", ".join([os.path.join(out_dir, f) for f in ("trace.npz", "metrics.json")] + files))
    return 0


if __name__ == "__main__":
    sys.exit(main())
