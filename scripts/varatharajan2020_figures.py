#!/usr/bin/env python3
"""Figures of the 003 method's scenarios like the paper's (Varatharajan et al. 2020, Figs. 8-13).

Each scenario runs on the golden backend. Per scenario (docs/figures/varatharajan2020_<name>.png): speed
(reference, rotor, estimate), the electrical position error modulo 180 deg (the angle the state was chosen
with against the true angle in the middle of the applied period, ``angle_error_at_bottom``), the torque
(electromagnetic, load) and the fusion weight ``f`` of eq. (38b), computed from the filtered speed estimate
(the supervisor's, 25 Hz) with the scenario's ``g`` and ``w_g`` (the estimator uses its PLL integrator's
speed, which the trace does not hold; both are smooth, the PLL's output is not).

Usage: scripts/varatharajan2020_figures.py [NAME ...] [--out docs/figures]   (names: torquestep speedrange
tracking maperror; default all). Prints the metrics that docs/methods.md quotes.
"""

from __future__ import annotations

import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from golden.closedloop import ClosedLoop  # noqa: E402
from golden.scenario import load_scenario  # noqa: E402
from hfi.report import metrics_of  # noqa: E402

NAMES = ("torquestep", "speedrange", "tracking", "maperror")
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
RPM = 30 / math.pi


def fusion_weight(sc, omega_e: np.ndarray) -> np.ndarray:
    """Eq. (38b) on the electrical speed [rad/s]."""
    t = sc.estimator.params["hfo_proj"]
    g, wg = 2 * math.pi * t["g"], 2 * math.pi * t["w_g"]
    return np.clip((g + wg - np.abs(omega_e)) / (2 * wg), 0.0, 1.0)


def figure(name: str, out_dir: str) -> dict:
    sc = load_scenario(os.path.join(ROOT, "scenarios", f"varatharajan2020_{name}.toml"))
    print(f"{sc.name}: {sc.duration:g} s on the golden backend ...", flush=True)
    res = ClosedLoop(sc).run(progress=False)
    m = metrics_of(sc, res)
    w, t = res.windows, res.t
    scale = res.scales.speed_mech(1.0)
    est = w["omega_f"] / scale
    fig, ax = plt.subplots(4, 1, figsize=(9, 9), sharex=True)
    ax[0].plot(t, w["speed_ref"] / scale * RPM, lw=1.0, label="reference")
    ax[0].plot(t, w["omega_m"] * RPM, lw=0.8, label="rotor")
    ax[0].plot(t, est * RPM, lw=0.6, alpha=0.8, label="estimated (filtered)")
    ax[0].set_ylabel("speed [r/min]")
    ax[0].legend(loc="best", fontsize=8)
    ax[1].plot(t, res.angle_error_deg(quarters=3), lw=0.5)
    ax[1].set_ylabel("θ − θ̂ [deg el.]\n(mod 180)")
    ax[2].plot(t, w["torque"], lw=0.4, label="electromagnetic")
    ax[2].plot(t, w["load_torque"], lw=1.0, label="load")
    ax[2].set_ylabel("torque [N·m]")
    ax[2].legend(loc="best", fontsize=8)
    ax[3].plot(t, fusion_weight(sc, est * res.scales.pole_pairs), lw=0.8)
    ax[3].set_ylabel("fusion weight f")
    ax[3].set_ylim(-0.05, 1.05)
    ax[3].set_xlabel("t [s]")
    for a in ax:
        a.grid(alpha=0.3)
    fig.suptitle(f"{sc.name}: {sc.description}", fontsize=9)
    fig.tight_layout()
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, f"varatharajan2020_{name}.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    a = m["angle_error_at_bottom"]
    print(f"  wrote {path}; locked {m['locked']}, angle error after start: RMS {a['rms_deg']} deg, "
          f"peak {a['peak_deg']} deg")
    for s in m["segments"]:
        print(f"  plateau {s['plateau']}: speed {s['speed_mean_rpm']} r/min (ref {s['speed_ref_rpm']}), "
              f"error RMS {s['err_rms_deg']} deg, peak {s['err_peak_bottom_deg']} deg")
    return m


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", metavar="NAME", help=f"any of {', '.join(NAMES)}")
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "figures"))
    args = ap.parse_args()
    bad = [n for n in args.names if n not in NAMES]
    if bad:
        ap.error(f"unknown scenario name(s) {', '.join(bad)}; choose from {', '.join(NAMES)}")
    for name in args.names or NAMES:
        figure(name, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
