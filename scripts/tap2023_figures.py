#!/usr/bin/env python3
"""Figures of the 000 method's scenarios like the paper's (Tap et al. 2023, Figs. 14, 18-24): speed
(reference, rotor, estimate), electrical angle error, and the demodulated error signal of the HF
estimator (eq. (17), normalised: the PLL's input ``err`` of golden/firmware/rot_bpf.py).

Each scenario runs on the golden backend; the error signal is obtained by stepping a second
``RotatingBpf`` with the same integers on the recorded window results (window-mean currents, the sin/cos
active in each window, INJ_PHASE) from the start of RUN, which the run's own estimator also starts
from (it is ``sync``ed there after the pilot pulses), so the replay follows it bit for bit while the HF
estimator is in charge.

``wayback`` runs ``tap2023_highspeed`` twice more, the EEMF observer tuned as the paper leaves it (PLL
100 1/s, 2500 1/s^2, no d-current floor) and with the defaults, and plots both (docs/methods.md).

Usage: scripts/tap2023_figures.py [NAME ...] [--out docs/figures]   (names: fullload step reversal
pulsating highspeed wayback; default all). Prints the plateau statistics of each run.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from golden.closedloop import ClosedLoop  # noqa: E402
from golden.control_config import firmware_params  # noqa: E402
from golden.firmware.estimator import Measurement  # noqa: E402
from golden.firmware.rot_bpf import RotatingBpf  # noqa: E402
from golden.firmware.supervisor import MODE_RUN  # noqa: E402
from golden.fixed import wrap  # noqa: E402
from golden.fpga.cordic import sincos_q15  # noqa: E402
from golden.fpga.demodulator import WindowResult  # noqa: E402
from golden.scenario import load_scenario  # noqa: E402
from hfi.report import metrics_of  # noqa: E402

NAMES = ("fullload", "step", "reversal", "pulsating", "highspeed", "wayback")
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def replay_error(sc, res) -> np.ndarray:
    """The HF estimator's normalised error [deg] per window from the start of RUN (NaN before)."""
    w = res.windows
    est = RotatingBpf(firmware_params(sc).rot)
    run = np.flatnonzero(w["mode"] == MODE_RUN)
    out = np.full(len(res.t), np.nan)
    if not len(run):
        return out
    k0 = int(run[0])
    est.sync(int(w["theta_lo"][k0 - 1]), 0)
    for k in range(k0, len(res.t)):
        s_a, c_a = (int(w["sin"][k - 2]), int(w["cos"][k - 2])) if k >= 2 else (0, 32767)
        s_i, c_i = sincos_q15(int(w["inj_phase"][k]))
        win = WindowResult(0, 0, 0, 0, 0, 1, int(w["inj_phase"][k]))
        est.step(Measurement(win, int(w["i_d"][k]), int(w["i_q"][k]), s_a, c_a, 0, 0, s_i, c_i))
        if w["est"][k] == 0:
            out[k] = wrap(est.err, 32) * 360 / 2**32
    return out


def figure(name: str, out_dir: str) -> dict:
    sc = load_scenario(os.path.join(ROOT, "scenarios", f"tap2023_{name}.toml"))
    res = ClosedLoop(sc).run(progress=False)
    m = metrics_of(sc, res)
    w, t = res.windows, res.t
    rpm = 30 / np.pi
    scale = res.scales.speed_mech(1.0)
    fig, ax = plt.subplots(3, 1, figsize=(9, 8), sharex=True)
    ax[0].plot(t, w["speed_ref"] / scale * rpm, "k--", lw=1, label="reference")
    ax[0].plot(t, w["omega_m"] * rpm, lw=1, label="rotor")
    ax[0].plot(t, w["omega_f"] / scale * rpm, lw=0.8, alpha=0.8, label="estimate (filtered)")
    ax[0].set_ylabel("speed [r/min]")
    ax[0].legend(loc="best", fontsize=8)
    ax[1].plot(t, res.angle_error_deg(), lw=0.6)
    hi = w["est"] == 1
    if hi.any():
        ax[1].plot(t[hi], res.angle_error_deg()[hi], ".", ms=1, label="EEMF observer in charge")
        ax[1].legend(loc="best", fontsize=8)
    ax[1].set_ylabel("angle error [deg el]")
    ax[1].set_ylim(-10, 10)
    ax[2].plot(t, replay_error(sc, res), lw=0.6)
    ax[2].set_ylabel("HF error signal [deg]")
    ax[2].set_ylim(-10, 10)
    ax[2].set_xlabel("time [s]")
    seg = "; ".join(f"{s['speed_ref_rpm']:g} r/min: {s['err_rms_deg']} deg RMS" for s in m["segments"])
    fig.suptitle(f"tap2023_{name}: {sc.description}\n{seg}", fontsize=9)
    fig.tight_layout()
    path = os.path.join(out_dir, f"tap2023_{name}.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return {"figure": path, "locked": m["locked"], "segments": m["segments"],
            "switches": m["estimator_switches"], "flipped": m["polarity_flipped"]}


PAPER_SMO = {"pll_kp": 100.0, "pll_ki": 2500.0, "i_d_min": 0.0}
"""The EEMF observer's tuning before the way back was measured: the rot_bpf PLL's gains, no d-current floor."""


def wayback_figure(out_dir: str) -> dict:
    """tap2023_highspeed with PAPER_SMO and with the defaults: speed and angle error of each."""
    base = load_scenario(os.path.join(ROOT, "scenarios", "tap2023_highspeed.toml"))
    est = base.estimator
    paper = dataclasses.replace(base, estimator=dataclasses.replace(
        est, params=dict(est.params, eemf_smo=dict(est.params["eemf_smo"], **PAPER_SMO))))
    fig, ax = plt.subplots(3, 1, figsize=(9, 8), sharex=True)
    rpm = 30 / np.pi
    out = {}
    for label, sc in (("PLL 100 1/s, 2500 1/s^2, i_d floor 0 A", paper),
                      ("defaults: PLL 400 1/s, 40000 1/s^2, i_d floor 1 A", base)):
        res = ClosedLoop(sc).run(progress=False)
        m = metrics_of(sc, res)
        out[label] = m
        err = res.angle_error_deg()
        ax[0].plot(res.t, res.windows["omega_m"] * rpm, lw=1, label=f"rotor, {label}")
        ax[1].plot(res.t, err, lw=0.6, label=f"{label}: {'locked' if m['locked'] else 'LOCK LOST'}")
        ax[2].plot(res.t, res.windows["i_d"] * res.scales.i_lsb, lw=0.6, label=label)
    scale = res.scales.speed_mech(1.0)
    ax[0].plot(res.t, res.windows["speed_ref"] / scale * rpm, "k--", lw=1, label="reference")
    ax[0].set_ylabel("speed [r/min]")
    ax[0].legend(loc="best", fontsize=7)
    ax[1].set_ylabel("angle error [deg el]")
    ax[1].set_ylim(-40, 40)
    ax[1].legend(loc="best", fontsize=7)
    ax[2].set_ylabel("i_d (window mean) [A]")
    ax[2].set_xlabel("time [s]")
    fig.suptitle("tap2023_highspeed, the way back through the hand-back: EEMF observer tuning", fontsize=9)
    fig.tight_layout()
    path = os.path.join(out_dir, "tap2023_wayback.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return {"figure": path, "runs": out}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", metavar="NAME", help=f"scenarios ({', '.join(NAMES)}; default all)")
    ap.add_argument("--out", default=os.path.normpath(os.path.join(ROOT, "docs", "figures")))
    args = ap.parse_args()
    bad = [n for n in args.names if n not in NAMES]
    if bad:
        ap.error(f"unknown scenario {', '.join(bad)}: choose from {', '.join(NAMES)}")
    args.names = args.names or list(NAMES)
    os.makedirs(args.out, exist_ok=True)
    for name in args.names:
        if name == "wayback":
            r = wayback_figure(args.out)
            for label, m in r["runs"].items():
                err = m["angle_error_after_start"]
                print(f"wayback, {label}: locked {m['locked']}, angle error after start {err['rms_deg']} deg RMS, "
                      f"{err['peak_deg']} deg peak")
            print(f"wrote {r['figure']}")
            continue
        r = figure(name, args.out)
        print(f"tap2023_{name}: locked {r['locked']}, switches {r['switches']}, wrote {r['figure']}")
        for s in r["segments"]:
            print(f"  {s['speed_ref_rpm']:8.2f} r/min: mean {s['speed_mean_rpm']:8.2f}, ripple {s['speed_ripple_rpm']:6.2f} "
                  f"r/min, angle error {s['err_rms_deg']} deg RMS, {s['err_peak_deg']} deg peak ({', '.join(s['estimators'])})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
