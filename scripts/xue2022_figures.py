#!/usr/bin/env python3
"""Figures of the 001 method's scenarios like the paper's (Xue et al. 2022, Figs. 11-18), and its stability
margin.

Each scenario runs on the golden backend. Per scenario (docs/figures/xue2022_<name>.png): speed
(reference, rotor, estimate), the electrical angle error (the window's applied angle against the true
angle in its middle, and against the one at the carrier bottom, the sampling instant: docs/metrics.md),
and the position quadrature signal before (the held envelope ``ENV_A/B``) and after the CIC interpolation
(``CIC_QA/QB``) over 50 ms of the last plateau. ``spectrum`` (docs/figures/xue2022_spectrum.png) is the
paper's Figs. 11-12: the alpha component of both signals at 300 r/min no load and their spectra, where the
CIC's attenuation of the hold's images (around multiples of 500 Hz) shows. ``margin`` ramps the speed
reference of ``xue2022_noload`` from 300 r/min upwards at 100 r/min/s and prints the speed at which the
angle error first leaves 60 deg (docs/figures/xue2022_margin.png).

Usage: scripts/xue2022_figures.py [NAME ...] [--out docs/figures]   (names: noload loadstep loadedstart
spectrum margin; default all). Prints the plateau statistics and the largest speed-estimation error.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from golden.closedloop import ClosedLoop  # noqa: E402
from golden.firmware.supervisor import MODE_RUN  # noqa: E402
from golden.scenario import load_scenario  # noqa: E402
from hfi.report import LOCK_DEG, metrics_of  # noqa: E402

SCENARIOS = ("noload", "loadstep", "loadedstart")
NAMES = SCENARIOS + ("spectrum", "margin")
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
RPM = 30 / math.pi
MARGIN_RATE = 100.0
"""Speed-reference ramp of the margin run [r/min per s]."""


def scenario(name: str):
    return load_scenario(os.path.join(ROOT, "scenarios", f"xue2022_{name}.toml"))


def speeds(res) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rotor, estimated (the estimator's own speed) and reference speeds [r/min] per window."""
    w, scale = res.windows, res.scales.speed_mech(1.0)
    return w["omega_m"] * RPM, w["omega_lo"] / scale * RPM, w["speed_ref"] / scale * RPM


def figure(name: str, out_dir: str) -> dict:
    sc = scenario(name)
    res = ClosedLoop(sc).run(progress=False)
    m = metrics_of(sc, res)
    w, t = res.windows, res.t
    rotor, est, ref = speeds(res)
    run = w["mode"] == MODE_RUN
    fig, ax = plt.subplots(3, 1, figsize=(9, 8), sharex=False)
    ax[0].plot(t, ref, "k--", lw=1, label="reference")
    ax[0].plot(t, rotor, lw=1, label="rotor")
    ax[0].plot(t, est, lw=0.8, alpha=0.8, label="estimate (Luenberger observer)")
    ax[0].set_ylabel("speed [r/min]")
    ax[0].legend(loc="best", fontsize=8)
    ax[1].plot(t, np.radians(res.angle_error_deg()), lw=0.6, label="applied angle vs window middle")
    ax[1].plot(t, np.radians(res.angle_error_deg(quarters=3)), lw=0.6, alpha=0.7, label="vs carrier bottom (sampling)")
    ax[1].set_ylabel("angle error [rad el]")
    ax[1].set_ylim(-0.3, 0.3)
    ax[1].set_xlabel("time [s]")
    ax[1].legend(loc="best", fontsize=8)
    k1 = len(t)
    k0 = max(k1 - round(0.05 * sc.pwm.f_sw), 0)
    lsb = res.scales.i_lsb
    ax[2].step(t[k0:k1], w["env_a"][k0:k1] * lsb, where="post", lw=0.8, label="envelope alpha (held, 500 Hz)")
    ax[2].step(t[k0:k1], w["env_b"][k0:k1] * lsb, where="post", lw=0.8, label="envelope beta")
    m_cic = sc.estimator.params["sqw_cic"]["cic_m"]
    ax[2].plot(t[k0:k1], w["cic_qa"][k0:k1] * lsb / m_cic, ".-", lw=0.8, ms=3, label="CIC output alpha / M")
    ax[2].plot(t[k0:k1], w["cic_qb"][k0:k1] * lsb / m_cic, ".-", lw=0.8, ms=3, label="CIC output beta / M")
    ax[2].set_ylabel("quadrature signal [A]")
    ax[2].set_xlabel("time [s] (last 50 ms)")
    ax[2].legend(loc="best", fontsize=7)
    seg = "; ".join(f"{s['speed_ref_rpm']:g} r/min: peak {math.radians(s['err_peak_deg']):.3f} rad"
                    for s in m["segments"])
    fig.suptitle(f"xue2022_{name}: {sc.description}\n{seg}", fontsize=9)
    fig.tight_layout()
    path = os.path.join(out_dir, f"xue2022_{name}.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return {"figure": path, "metrics": m, "est_err_max": float(np.max(np.abs(est - rotor)[run])) if run.any() else None,
            "ref_err_max": float(np.max(np.abs(rotor - ref)[run])) if run.any() else None}


def spectrum(out_dir: str) -> str:
    """Figs. 11-12: the held envelope and the CIC output at 300 r/min, no load, and their spectra."""
    sc = scenario("noload")
    res = ClosedLoop(sc).run(progress=False)
    w, t, f_sw = res.windows, res.t, sc.pwm.f_sw
    sel = t >= t[-1] - 1.0                        # the last second of the 300 r/min plateau
    m_cic = sc.estimator.params["sqw_cic"]["cic_m"]
    env = w["env_a"][sel] * res.scales.i_lsb
    cic = w["cic_qa"][sel] * res.scales.i_lsb / m_cic
    fig, ax = plt.subplots(2, 1, figsize=(9, 6))
    ts = t[sel][:100]
    ax[0].step(ts, env[:100], where="post", lw=1, label="envelope (held, Fig. 11a)")
    ax[0].plot(ts, cic[:100], ".-", lw=1, ms=3, label="after the CIC (Fig. 12a)")
    ax[0].set(xlabel="time [s]", ylabel="alpha component [A]")
    ax[0].legend(fontsize=8)
    for x, label in ((env, "envelope (held)"), (cic, "after the CIC")):
        spec = np.abs(np.fft.rfft((x - x.mean()) * np.hanning(len(x)))) * 2 / (0.5 * len(x))
        ax[1].semilogy(np.fft.rfftfreq(len(x), 1 / f_sw), np.maximum(spec, 1e-6), lw=0.8, label=label)
    ax[1].set(xlabel="frequency [Hz] (signals at the PWM rate)", ylabel="amplitude [A]", ylim=(1e-5, 10))
    ax[1].legend(fontsize=8)
    fig.suptitle("xue2022_noload, 300 r/min: the position quadrature signal before and after the CIC", fontsize=9)
    fig.tight_layout()
    path = os.path.join(out_dir, "xue2022_spectrum.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def margin(out_dir: str) -> tuple[float | None, str]:
    """The highest speed with lock: ``xue2022_noload`` whose reference ramps on from 300 r/min."""
    base = scenario("noload")
    t_ramp = 3.2
    top = 300.0 + MARGIN_RATE * 10.0
    ref = [(0.0, 0.0), (0.3, 0.0), (0.6, 100 / RPM), (1.5, 100 / RPM), (1.9, 300 / RPM), (t_ramp, 300 / RPM),
           (t_ramp + 10.0, top / RPM)]
    sc = dataclasses.replace(base, reference_speed=ref, duration=t_ramp + 10.0)
    res = ClosedLoop(sc).run(progress=False)
    rotor, est, r = speeds(res)
    err = res.angle_error_deg()
    mode = res.windows["mode"]
    run = np.arange(len(mode)) >= np.argmax(mode == MODE_RUN)      # from the start of RUN on (FAULT included)
    lost = np.flatnonzero(run & (np.abs(err) >= LOCK_DEG))
    speed = float(rotor[lost[0]]) if len(lost) else None
    fig, ax = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
    ax[0].plot(res.t, r, "k--", lw=1, label="reference")
    ax[0].plot(res.t, rotor, lw=1, label="rotor")
    ax[0].set_ylabel("speed [r/min]")
    ax[0].legend(fontsize=8)
    ax[1].plot(res.t, err, lw=0.6)
    ax[1].axhline(LOCK_DEG, color="r", lw=0.6)
    ax[1].axhline(-LOCK_DEG, color="r", lw=0.6)
    ax[1].set(xlabel="time [s]", ylabel="angle error [deg el]", ylim=(-180, 180))
    fig.suptitle(f"xue2022_noload, reference ramped at {MARGIN_RATE:g} r/min/s from 300 r/min: lock "
                 + (f"lost at {speed:.0f} r/min" if speed is not None else f"held up to {top:.0f} r/min"), fontsize=9)
    fig.tight_layout()
    path = os.path.join(out_dir, "xue2022_margin.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return speed, path


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", metavar="NAME", help=f"({', '.join(NAMES)}; default all)")
    ap.add_argument("--out", default=os.path.normpath(os.path.join(ROOT, "docs", "figures")))
    args = ap.parse_args()
    bad = [n for n in args.names if n not in NAMES]
    if bad:
        ap.error(f"unknown name {', '.join(bad)}: choose from {', '.join(NAMES)}")
    os.makedirs(args.out, exist_ok=True)
    for name in args.names or NAMES:
        if name == "spectrum":
            print(f"spectrum: wrote {spectrum(args.out)}")
            continue
        if name == "margin":
            speed, path = margin(args.out)
            print(f"margin: lock {'lost at %.0f r/min' % speed if speed is not None else 'held over the ramp'}; "
                  f"wrote {path}")
            continue
        r = figure(name, args.out)
        m = r["metrics"]
        err = m["angle_error_after_start"]
        print(f"xue2022_{name}: locked {m['locked']}, polarity flipped {m['polarity_flipped']}, after the start "
              f"peak {math.radians(err['peak_deg']):.3f} rad ({err['peak_deg']} deg), at the carrier bottom "
              f"{math.radians(m['angle_error_at_bottom']['peak_deg']):.3f} rad; speed estimate error max "
              f"{r['est_err_max']:.1f} r/min, speed vs reference max {r['ref_err_max']:.1f} r/min; wrote {r['figure']}")
        for s in m["segments"]:
            print(f"  {s['speed_ref_rpm']:7.1f} r/min: mean {s['speed_mean_rpm']:7.2f}, angle error "
                  f"{math.radians(s['err_rms_deg']):.4f} rad RMS, {math.radians(s['err_peak_deg']):.4f} rad peak "
                  f"({math.radians(s['err_peak_bottom_deg']):.4f} at the carrier bottom)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
