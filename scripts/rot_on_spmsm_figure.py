#!/usr/bin/env python3
"""The 000 method on the 002 system's Table I SPMSM (docs/compare.md, "The 000 method on the Table I SPMSM"): one
point of ``sweeps/cross_000_on_002.toml`` (standstill, the load ramped to rated from 1.4 to 1.7 s, 21 V, its first
seed) on the paper's 4 us power stage and on a 0.5 us one, on the hls backend. The angle error in RUN, the q current,
and what the phase currents themselves say about the rotor, demodulated offline from the ADC samples without the
estimator: the negative-sequence current at -f_inj over 10 ms blocks (five injection periods), its magnitude against
the saliency's share (Tap et al. 2023, eq. (11) with R neglected: ``V_h |L_d - L_q| / (2 w_h L_d L_q)``) and the
angle it carries (``(arg - 2 theta_true) / 2``, taken from its mean in the unloaded second before the ramp): the
error the estimator could not avoid, however it filters.

    python scripts/rot_on_spmsm_figure.py [--out docs/figures/compare_rotating_on_spmsm.png]
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "sweeps" / "cross_000_on_002.toml"
POINT = {"reference.speed": ("scale", 0), "load.torque": ("scale", 1.0), "injection.V_h": ("value", "21 V")}
DEAD_TIMES = (("4 us", "4 us dead time (the paper's stage)"), ("0.5 us", "0.5 us dead time (SiC-class stage)"))
BLOCK_S = 0.01
"""Offline demodulation block: five periods of the 500 Hz injection."""
REFERENCE_S = (0.4, 1.4)
"""The unloaded stretch in RUN, before the load ramp, whose mean angle is the demodulation's zero."""


def run(dead_time: str):
    """The point's first seed with ``pwm.dead_time``: (scenario, result)."""
    import hfi.sweep as sw
    from golden.scenario import parse_scenario
    from hfi.backends import get

    want = {**POINT, "pwm.dead_time": ("value", dead_time)}
    job = next((j for j in sw.jobs(sw.load_spec(SPEC), "figure") if j.settings == want), None)
    if job is None:
        raise SystemExit(f"{SPEC.name} has no point {want}")
    sc = parse_scenario(job.tree, SPEC.name)
    return sc, get("hls").run(sc, progress=False)


def negative_sequence(sc, res, f_inj: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Block centres [s], the negative-sequence phasor of the sampled stator current at ``-f_inj`` per block [A]
    and twice the true electrical angle per block [rad]."""
    bits = res.hw.adc_bits
    lsb = 2 * sc.plant["sens"]["adc_range"] / 2 ** bits
    i_a = (res.samples["adc_a"].astype(float) - 2 ** (bits - 1)) * lsb
    i_b = (res.samples["adc_b"].astype(float) - 2 ** (bits - 1)) * lsb
    ts = res.samples["tick"] / res.tick_hz
    i_ab = i_a + 1j * (i_a + 2 * i_b) / np.sqrt(3)                       # Clarke, two sensors
    prod = i_ab * np.exp(2j * np.pi * f_inj * ts)
    theta = res.windows["theta_e"].astype(float) / 2**32 * 2 * np.pi
    blocks = np.floor(ts / BLOCK_S).astype(np.int64)
    wblocks = np.floor(res.t / BLOCK_S).astype(np.int64)
    n = int(blocks.max()) + 1
    count = np.bincount(blocks, minlength=n)
    phasor = np.bincount(blocks, prod.real, n) / np.maximum(count, 1) + 1j * np.bincount(blocks, prod.imag, n) / \
        np.maximum(count, 1)
    two_theta = np.angle(np.bincount(wblocks, np.cos(2 * theta), n) + 1j * np.bincount(wblocks, np.sin(2 * theta), n))
    keep = count > 0
    return ((np.arange(n) + 0.5) * BLOCK_S)[keep], phasor[keep], two_theta[keep]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "figures" / "compare_rotating_on_spmsm.png")
    args = ap.parse_args(argv)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from golden.firmware.supervisor import MODE_FAULT, MODE_RUN
    from hfi.report import save_figure

    fig, axes = plt.subplots(2, 2, figsize=(12, 8), sharex=True)
    for k, (dead_time, label) in enumerate(DEAD_TIMES):
        print(f"running {SPEC.name} {POINT} with {dead_time} dead time ...", flush=True)
        sc, res = run(dead_time)
        w, t = res.windows, res.t
        on = w["mode"] == MODE_RUN
        err = (res.angle_error_deg() + 90) % 180 - 90
        axes[0][0].plot(t[on], err[on], color=f"C{k}", lw=0.5, label=label)
        axes[0][1].plot(t, np.where(w["mode"] == MODE_FAULT, np.nan, w["i_q_true"]), color=f"C{k}", lw=0.6,
                        label=label)
        mag = sc.plant["mag"]
        f_inj = sc.estimator.params["rot_bpf"]["f_inj"]
        tb, ph, two_theta = negative_sequence(sc, res, f_inj)
        live = np.array([bool(np.all(w["mode"][(t >= c - BLOCK_S / 2) & (t < c + BLOCK_S / 2)] == MODE_RUN))
                         for c in tb])
        carried = np.angle(ph * np.exp(-1j * two_theta))
        ref = (tb >= REFERENCE_S[0]) & (tb < REFERENCE_S[1]) & live
        zero = np.angle(np.mean(np.exp(1j * carried[ref])))
        dev = np.degrees(np.angle(np.exp(1j * (carried - zero)))) / 2
        axes[1][0].plot(tb[live], dev[live], ".-", color=f"C{k}", ms=3, lw=0.6, label=label)
        axes[1][1].plot(tb[live], 1e3 * np.abs(ph[live]), ".-", color=f"C{k}", ms=3, lw=0.6, label=label)
        if k == 0:
            v_h = sc.injection.V_h
            w_h = 2 * np.pi * f_inj
            sal = v_h * abs(mag["L_d"] - mag["L_q"]) / (2 * w_h * mag["L_d"] * mag["L_q"])
            axes[1][1].axhline(1e3 * sal, color="k", ls="--", lw=0.8,
                               label=f"saliency alone, eq. (11): {1e3 * sal:.0f} mA")
    axes[0][0].set_title("angle error in RUN [deg el, mod 180] (the load ramps to rated from 1.4 to 1.7 s)",
                         fontsize=9)
    axes[0][0].set_ylim(-90, 90)
    axes[0][1].set_title("q current (plant) [A]; gaps: the drive tripped", fontsize=9)
    axes[1][0].set_title("angle the sampled currents carry, offline [deg el]: (arg I(-f_inj) - 2 theta) / 2, "
                         "zero = its mean 0.4-1.4 s", fontsize=9)
    axes[1][1].set_title("negative-sequence current |I(-f_inj)| over 10 ms [mA]", fontsize=9)
    for ax in axes.flat:
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    for ax in axes[1]:
        ax.set_xlabel("t [s]")
    fig.suptitle("The 000 method (rotating injection 21 V at 500 Hz) on the Table I SPMSM at standstill: "
                 "the dead time, not the estimator", fontsize=10)
    print("wrote", save_figure(fig, str(args.out.parent), args.out.name))
    return 0


if __name__ == "__main__":
    sys.exit(main())
