#!/usr/bin/env python3
"""Why a run of ``sweeps/startup_2000.toml`` is lost (docs/sweep.md "Measured"): one run of the sweep (its point and
seed) on the hls backend, as the sweep ran it and with ``--set`` values (by default a shorter dead time), from just
before the rated-load step at standstill (0.3 s) until 0.4 s: the rotor's true and estimated speed, the angle error,
the demodulated error signal's sign against the true error's (the bang-bang estimator steps by the sign of ``GAMMA``),
and the q current with its reference.

    python scripts/startup_loss_figure.py [--point 62 --seed 1009] [--set KEY=VALUE]... [--out docs/figures/startup_loss.png]
"""

from __future__ import annotations

import argparse
import copy
import os
import sys
from pathlib import Path

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "sweeps" / "startup_2000.toml"
SPAN_S = (0.29, 0.40)
RPM = 2 * np.pi / 60
OTHER = "pwm.dead_time=3 us"


def run(point: int, seed: int, overrides: dict):
    """The sweep's run ``point``/``seed`` with ``overrides`` set: (scenario, result)."""
    import hfi.sweep as sw
    from golden.scenario import parse_scenario
    from hfi.backends import get

    # the random design's draws do not depend on [set]: the point and seed are the same drive with the overrides
    job = next((j for j in sw.jobs(sw.load_spec(SPEC, overrides), "figure")
                if j.point == point and j.tree["scenario"]["seed"] == seed), None)
    if job is None:
        raise SystemExit(f"startup_loss_figure: {SPEC.name} has no run at point {point}, seed {seed}")
    sc = parse_scenario(copy.deepcopy(job.tree), SPEC.name)
    return sc, get("hls").run(sc, progress=False)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--point", type=int, default=62)
    ap.add_argument("--seed", type=int, default=1009)
    ap.add_argument("--set", action="append", metavar="KEY=VALUE", help=f"the second column's values (default: {OTHER})")
    ap.add_argument("--out", default=str(ROOT / "docs" / "figures" / "startup_loss.png"))
    args = ap.parse_args(argv)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from hfi.report import metrics_of, save_figure
    from hfi.sweep import parse_set

    other = parse_set(args.set or [OTHER])
    cases = [("as the sweep ran it", {}), (", ".join(f"{k} = {v}" for k, v in other.items()), other)]
    fig, axes = plt.subplots(4, 2, figsize=(13, 9), sharex=True, sharey="row")
    for col, (name, overrides) in enumerate(cases):
        sc, res = run(args.point, args.seed, overrides)
        m = metrics_of(sc, res)
        w, t = res.windows, res.t
        sel = (t >= SPAN_S[0]) & (t < SPAN_S[1])
        err = res.angle_error_deg()
        ax = axes[0, col]
        ax.plot(t[sel], w["omega_m"][sel] / RPM, label="true")
        ax.plot(t[sel], w["omega_f"][sel] / res.scales.speed_mech(RPM), lw=0.8, label="estimated (PLL, filtered)")
        ax.set_ylabel("speed [r/min]")
        ax.set_title(f"{name}: {'lost, ' + m['faults']['code'] if not (m['locked'] and m['final_mode'] == 'RUN') else 'kept'}"
                     f" (peak error after start {m['angle_error_after_start']['peak_deg']:.0f}°)", fontsize=9)
        axes[1, col].plot(t[sel], err[sel], lw=0.8)
        axes[1, col].set_ylabel("θ − θ̂ [deg el]")
        # the estimator moves its angle towards the rotor when GAMMA's sign is the true error's
        agree = np.sign(w["gamma"][sel]) == np.sign(err[sel])
        k = np.flatnonzero(sel)
        axes[2, col].plot(t[k], np.convolve(agree, np.ones(10) / 10, mode="same"), lw=0.8)
        axes[2, col].axhline(0.5, color="k", lw=0.5, ls=":")
        axes[2, col].set_ylabel("share of windows\nwith sign(γ) = sign(err)\n(10-window mean)")
        axes[2, col].set_ylim(0, 1.05)
        axes[3, col].plot(t[sel], w["i_q_true"][sel], label="i_q (true)")
        axes[3, col].plot(t[sel], w["i_q_ref"][sel] * res.scales.i_lsb, lw=0.8, label="i_q reference")
        axes[3, col].plot(t[sel], w["load_torque"][sel], lw=0.8, label="load [N·m]")
        axes[3, col].set_ylabel("[A], [N·m]")
        axes[3, col].set_xlabel("t [s]")
    for ax in axes.flat:
        ax.grid(alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7, loc="lower left")
    fig.suptitle(f"{SPEC.name}, point {args.point}, seed {args.seed}: the rated-load step at standstill (0.3 s)")
    print(save_figure(fig, os.path.dirname(args.out), os.path.basename(args.out), top=0.95))
    return 0


if __name__ == "__main__":
    sys.exit(main())
