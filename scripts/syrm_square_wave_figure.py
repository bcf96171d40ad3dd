#!/usr/bin/env python3
"""The 002 method on the 003 SyRM at speed (docs/compare.md, "The 002 method on the 003 SyRM"): one point of
``sweeps/cross_002_on_003.toml`` (0.5 p.u. of speed, no load, its first seed) with the 002 drive's current PIs
(150 Hz) and at 40 Hz, on the hls backend: rotor and estimated speed, angle error (mod 180 deg), and a zoom into
the d current and its voltage when the d-axis PI starts to limit-cycle; beside them the HF estimator's offset
from cross-saturation, from the plant's model (the angle at which the HF response's quadrature part vanishes).

    python scripts/syrm_square_wave_figure.py [--out docs/figures/compare_syrm_square_wave.png]
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "sweeps" / "cross_002_on_003.toml"
POINT = {"reference.speed": ("scale", 0.5), "load.torque": ("scale", 0.0)}
DURATION = 0.9
"""Seconds simulated: the speed ramp starts at 0.5 s; both runs are lost or stable before 0.9 s."""


def run(current_bw: str):
    """The point's first seed with ``control.current_bw`` = ``current_bw``, ``DURATION`` s: (t, windows, scenario)."""
    import dataclasses

    import hfi.sweep as sw
    from golden.scenario import parse_scenario
    from hfi.backends import get

    for job in sw.jobs(sw.load_spec(SPEC), "figure"):
        s = job.settings
        if all(s[k] == v for k, v in POINT.items()) and s["control.current_bw"] == ("value", current_bw):
            break
    else:
        raise SystemExit(f"{SPEC.name} has no point {POINT} at {current_bw}")
    sc = dataclasses.replace(parse_scenario(job.tree, SPEC.name), duration=DURATION)
    res = get("hls").run(sc, progress=False)
    return res.t, res.windows, sc


def cross_saturation_offset(i_s: np.ndarray) -> np.ndarray:
    """The HF estimator's equilibrium offset [deg] from the q axis's normal on the SyRM preset's model, along the
    controller's MTPA (i_d = -i_q, at least 0.3 A on d): 90 deg minus half the angle of the incremental inductance
    matrix's principal axis, ``0.5 atan2(2 L_dq, L_d - L_q)``."""
    from golden.motors import preset
    from golden.saturation_fit import fluxes, jacobian

    mag = preset("varatharajan2020_syrm")["mag"]
    out = []
    for i in i_s:
        i_d, i_q = min(-0.3, -i / np.sqrt(2)), i / np.sqrt(2)
        psi_d, psi_q = fluxes(mag, np.array(i_d), np.array(i_q))
        g_dd, g_dq, g_qq = (float(x) for x in jacobian(mag, psi_d, psi_q))
        lmat = np.linalg.inv(np.array([[g_dd, g_dq], [g_dq, g_qq]]))
        out.append(90.0 - abs(0.5 * np.degrees(np.arctan2(2 * lmat[0, 1], lmat[0, 0] - lmat[1, 1]))))
    return np.array(out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "figures" / "compare_syrm_square_wave.png")
    args = ap.parse_args(argv)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from golden.control_config import scales
    from golden.firmware.supervisor import MODE_RUN
    from hfi.paper import RPM

    fig, axes = plt.subplots(3, 3, figsize=(14, 9))
    for col, bw in enumerate(("150 Hz", "40 Hz")):
        print(f"running {SPEC.name} {POINT} at current_bw {bw} ...", flush=True)
        t, w, sc = run(bw)
        sc_ = scales(sc)
        err = ((w["theta_hat"].astype(np.int64) - w["theta_e"].astype(np.int64)) / 2**32 * 360 + 90) % 180 - 90
        run_ = w["mode"] == MODE_RUN
        ax = axes[0][col]
        ax.plot(t, w["omega_m"] * 60 / (2 * np.pi), label="rotor")
        ax.plot(t, w["omega_f"] / sc_.speed_mech(RPM), label="estimated (filtered)", alpha=0.8)
        ax.plot(t, w["speed_ref"] / sc_.speed_mech(RPM), "k--", lw=0.8, label="reference")
        ax.set_title(f"current PIs at {bw}: speed [r/min]", fontsize=9)
        ax.legend(fontsize=7)
        ax.set_xlim(0.45, DURATION)
        ax = axes[1][col]
        ax.plot(t[run_], err[run_], lw=0.5)
        ax.set_title("angle error [deg el, mod 180]", fontsize=9)
        ax.set_xlim(0.45, DURATION)
        ax.set_ylim(-90, 90)
        ax = axes[2][col]
        zoom = (t > 0.555) & (t < 0.565)
        ax.plot(t[zoom] * 1e3, w["i_d"][zoom] * sc_.i_lsb, label="i_d measured [A]")
        ax.plot(t[zoom] * 1e3, w["i_d_ref"][zoom] * sc_.i_lsb, label="i_d reference [A]")
        ax2 = ax.twinx()
        ax2.plot(t[zoom] * 1e3, w["v_d"][zoom] * sc_.v_lsb, "C3", lw=0.8, label="v_d [V]")
        ax2.set_ylabel("v_d [V]", color="C3")
        ax.set_xlabel("t [ms]")
        ax.set_title("zoom 555-565 ms: the d loop", fontsize=9)
        ax.legend(fontsize=7, loc="lower left")
    i_s = np.linspace(0.0, 6.0, 61)
    ax = axes[0][2]
    ax.plot(i_s, cross_saturation_offset(i_s))
    ax.set_xlabel("current magnitude on the MTPA line [A] (rated 3.25 A)")
    ax.set_title("HF estimator's offset by cross-saturation [deg el]", fontsize=9)
    ax.grid(True, alpha=0.3)
    axes[1][2].set_visible(False)
    axes[2][2].set_visible(False)
    fig.suptitle("The 002 method (square wave at 10 kHz, bang-bang + PLL) on the 003 SyRM at 0.5 p.u. of speed, "
                 "no load", fontsize=10)
    fig.tight_layout()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out, dpi=100)
    plt.close(fig)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
