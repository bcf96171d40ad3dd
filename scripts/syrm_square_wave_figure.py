#!/usr/bin/env python3
"""The 002 method on the 003 SyRM (docs/compare.md, "The 002 method on the 003 SyRM"): one point of
``sweeps/cross_002_on_003.toml`` (10 % of rated speed, rated load, its first seed) in its three configurations, on
the hls backend: the 002 drive's current PIs (150 Hz), the PIs at 40 Hz, and 40 Hz with the cross-saturation table.
Speed, angle error (mod 180 deg), the d loop where the 150 Hz PI first hits its voltage limit, and the HF
estimator's offset from cross-saturation on the plant's model (the angle of the principal axis of the incremental
inductance matrix along the drive's current references: 0.3 A on d at least, MTPA i_d = -i_q above).

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
POINT = {"reference.speed": ("scale", 0.1), "load.torque": ("scale", 1.0)}
ARMS = (("150 Hz", "off", "current PIs 150 Hz (the 002 drive's)"),
        ("40 Hz", "off", "current PIs 40 Hz"),
        ("40 Hz", "on", "40 Hz + cross-saturation table"))
"""(control.current_bw, estimator.sqw_bangbang.cross_saturation, label) of each run."""


def run(current_bw: str, cross: str):
    """The point's first seed in one configuration: (t, windows, scenario)."""
    import hfi.sweep as sw
    from golden.scenario import parse_scenario
    from hfi.backends import get

    want = {**POINT, "control.current_bw": ("value", current_bw),
            "estimator.sqw_bangbang.cross_saturation": ("value", cross)}
    job = next((j for j in sw.jobs(sw.load_spec(SPEC), "figure") if j.settings == want), None)
    if job is None:
        raise SystemExit(f"{SPEC.name} has no point {want}")
    sc = parse_scenario(job.tree, SPEC.name)
    res = get("hls").run(sc, progress=False)
    return res.t, res.windows, sc


def cross_saturation_offset(i_s: np.ndarray) -> np.ndarray:
    """The angle [deg] between the d-axis and the principal axis of the SyRM preset's incremental inductance matrix
    (the plant's model, golden.plant.fluxmap) at ``i_d = min(-0.3, -i/sqrt 2)``, ``i_q = i/sqrt 2`` for each
    magnitude ``i`` [A]."""
    from golden.motors import preset
    from golden.plant.fluxmap import incremental_inductance, psi_from_current

    mag = preset("varatharajan2020_syrm")["mag"]
    out = []
    for i in i_s:
        psi = psi_from_current(mag, min(-0.3, -i / np.sqrt(2)), i / np.sqrt(2))
        lmat = incremental_inductance(mag, psi[0], psi[1])
        out.append(90.0 - abs(0.5 * np.degrees(np.arctan2(2 * lmat[0, 1], lmat[0, 0] - lmat[1, 1]))))
    return np.array(out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "figures" / "compare_syrm_square_wave.png")
    args = ap.parse_args(argv)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from golden.control_config import firmware_params, scales
    from golden.firmware.supervisor import MODE_RUN
    from hfi.paper import RPM
    from hfi.report import save_figure

    fig, axes = plt.subplots(2, 3, figsize=(15, 8.5))
    runs = []
    for k, (bw, cross, label) in enumerate(ARMS):
        print(f"running {SPEC.name} {POINT}: {label} ...", flush=True)
        t, w, sc = run(bw, cross)
        runs.append((t, w, sc))
        sc_ = scales(sc)
        err = ((w["theta_hat"].astype(np.int64) - w["theta_e"].astype(np.int64)) / 2**32 * 360 + 90) % 180 - 90
        on = w["mode"] == MODE_RUN
        axes[0][0].plot(t, w["omega_m"] * 60 / (2 * np.pi), color=f"C{k}", lw=0.9, label=f"{label}: rotor")
        axes[0][1].plot(t[on], np.where(on, err, np.nan)[on], color=f"C{k}", lw=0.4, alpha=0.8, label=label)
        if k == 0:
            axes[0][0].plot(t, w["speed_ref"] / sc_.speed_mech(RPM), "k--", lw=0.8, label="reference")
    axes[0][0].set_title("rotor speed [r/min] (the load ramps to rated from 1.4 to 1.7 s)", fontsize=9)
    axes[0][0].legend(fontsize=7)
    axes[0][1].set_title("angle error [deg el, mod 180] in RUN", fontsize=9)
    axes[0][1].set_ylim(-90, 90)
    axes[0][1].legend(fontsize=7)
    for ax in axes[0][:2]:
        ax.set_xlabel("t [s]")
        ax.grid(True, alpha=0.3)
    i_s = np.linspace(0.0, 6.0, 61)
    ax = axes[0][2]
    ax.plot(i_s, cross_saturation_offset(i_s))
    ax.set_xlabel("current magnitude [A] (rated 3.25 A), i_d = min(-0.3 A, -i_q)")
    ax.set_title("HF axis off d by cross-saturation, plant model [deg el]", fontsize=9)
    ax.grid(True, alpha=0.3)
    t, w, sc = runs[0]
    v_lim = firmware_params(sc).id_pi.limit
    hit = np.flatnonzero((w["mode"] == MODE_RUN) & (np.abs(w["v_d"]) >= v_lim))
    t0 = t[hit[0]] - 0.002 if len(hit) else t[len(t) // 2]
    for col, (t, w, sc) in enumerate(runs[:2]):
        sc_ = scales(sc)
        ax = axes[1][col]
        zoom = (t > t0) & (t < t0 + 0.01)
        ax.plot(t[zoom] * 1e3, w["i_d"][zoom] * sc_.i_lsb, label="i_d measured [A]")
        ax.plot(t[zoom] * 1e3, w["i_d_ref"][zoom] * sc_.i_lsb, label="i_d reference [A]")
        ax2 = ax.twinx()
        ax2.plot(t[zoom] * 1e3, w["v_d"][zoom] * sc_.v_lsb, "C3", lw=0.8)
        ax2.set_ylabel("v_d (current PI output) [V]", color="C3")
        ax.set_xlabel("t [ms]")
        ax.set_title(f"{ARMS[col][2]}: the d loop, 10 ms", fontsize=9)
        ax.legend(fontsize=7, loc="lower left")
    axes[1][2].set_visible(False)
    fig.suptitle("The 002 method (square wave at 10 kHz, bang-bang + PLL, 0.3 A on d) on the 003 SyRM: "
                 "10 % of rated speed, rated load", fontsize=10)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    print(f"wrote {save_figure(fig, str(args.out.parent), args.out.name)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
