#!/usr/bin/env python3
"""The flying start's figures (docs/faults.md), on the golden backend: speed (true, estimated, reference), angle
error, current amplitude and the supervisor's mode.

* scenarios/flying_start.toml (the drive switched on while the Table I motor coasts at ``--rpm``) with its
  ``catch_time`` and its short-circuit probe (``catch_probe``), with the catch but without the probe, and without
  either (the standstill start);
* ``--high A,B``: a scenario (``--scenario``) with each of these high-speed estimators (``estimator.high``), e.g.
  the 000 drive's flying start with the paper's EEMF observer and with the rotor flux observer.

    python scripts/flying_start_figure.py [--rpm 800] [--out docs/figures/flying_start.png]
    python scripts/flying_start_figure.py --rpm 2500 --out docs/figures/flying_start_probe.png
    python scripts/flying_start_figure.py --scenario scenarios/tap2023_flying.toml --high eemf_smo,rfo \\
        --out docs/figures/flying_start_000.png
"""

from __future__ import annotations

import argparse
import os
import sys
import tomllib

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from golden.closedloop import ClosedLoop  # noqa: E402
from golden.firmware.protection import FAULT_NAMES  # noqa: E402
from golden.firmware.supervisor import MODE_FAULT, MODE_NAMES  # noqa: E402
from golden.scenario import ScenarioError, parse_scenario  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SCENARIO = os.path.join(HERE, "..", "scenarios", "flying_start.toml")
RPM = np.pi / 30


def run(catch: bool, rpm: float, probe: bool = True, scenario: str = SCENARIO, high: str | None = None):
    """``scenario`` at ``rpm`` initial speed, with its catch_time (and its short-circuit probe, or without it) or
    with the flying start off; ``high``: with this high-speed estimator instead of the scenario's."""
    with open(scenario, "rb") as f:
        data = tomllib.load(f)
    data["load"]["initial"]["omega_m"] = f"{rpm} rpm"
    if not catch:
        data["protection"]["catch_time"] = "0 s"
    if not catch or not probe:
        data["protection"]["catch_probe"] = "0 A"
    if high is not None:
        data["estimator"]["high"] = high
    return ClosedLoop(parse_scenario(data, f"{scenario} at {rpm} rpm")).run(progress=False)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rpm", type=float, default=800.0, help="the coasting motor's speed at switch-on [r/min]")
    ap.add_argument("--out", default=os.path.join(HERE, "..", "docs", "figures", "flying_start.png"))
    ap.add_argument("--scenario", default=SCENARIO, help="scenario file (default scenarios/flying_start.toml)")
    ap.add_argument("--high", help="comma-separated high-speed estimators to compare (estimator.high)")
    args = ap.parse_args(argv)
    if not -5000 <= args.rpm <= 5000:
        print("flying_start_figure: --rpm must be within +-5000", file=sys.stderr)
        return 1
    try:
        if args.high:
            runs = {f"estimator.high = {h}": run(True, args.rpm, scenario=args.scenario, high=h)
                    for h in args.high.split(",")}
        else:
            runs = {"flying start (catch_time 40 ms, probe)": run(True, args.rpm),
                    "flying start without the probe": run(True, args.rpm, probe=False),
                    "standstill start": run(False, args.rpm)}
    except (OSError, ScenarioError) as exc:
        print(f"flying_start_figure: {exc}", file=sys.stderr)
        return 1
    fig, ax = plt.subplots(4, 1, figsize=(8, 9), sharex=True)
    for k, (label, res) in enumerate(runs.items()):
        w, t = res.windows, res.t
        line = ax[0].plot(t, w["omega_m"] / RPM, lw=1.0, label=f"{label}: true")[0]
        ax[0].plot(t, w["omega_f"] / res.scales.speed_mech(RPM), lw=0.6, ls="--", color=line.get_color(),
                   label=f"{label}: estimated")
        ax[1].plot(t, res.angle_error_deg(), lw=0.6, color=line.get_color())
        ax[2].plot(t, np.hypot(w["i_d_true"], w["i_q_true"]), lw=0.6, color=line.get_color())
        ax[3].step(t, w["mode"] + 0.1 * k, where="post", lw=1.0, color=line.get_color())
        trip = np.flatnonzero(w["mode"] == MODE_FAULT)
        if len(trip):
            ax[0].annotate(f"trip: {FAULT_NAMES[w['fault'][trip[0]]]}", (t[trip[0]], w["omega_m"][trip[0]] / RPM),
                           fontsize=8, color=line.get_color())
    first = next(iter(runs.values()))
    ax[0].plot(first.t, first.windows["speed_ref"] / first.scales.speed_mech(RPM), color="k", lw=0.8, label="reference")
    ax[0].set_ylabel("speed [r/min]")
    ax[0].legend(fontsize=7)
    ax[1].set(ylabel="angle error [deg el.]", ylim=(-180, 180))
    ax[2].set_ylabel("|i| [A]")
    used = sorted({int(m) for res in runs.values() for m in np.unique(res.windows["mode"])})
    ax[3].set(yticks=used, yticklabels=[MODE_NAMES[m] for m in used], xlabel="t [s]")
    for a in ax:
        a.grid(alpha=0.3)
    fig.suptitle(f"switched on with the motor coasting at {args.rpm:g} r/min ({os.path.basename(args.scenario)})")
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    fig.savefig(args.out, dpi=110)
    for label, res in runs.items():
        w, t = res.windows, res.t
        end = t >= t[-1] - 0.1
        err = res.angle_error_deg()[end]
        peak = np.hypot(w["i_d_true"], w["i_q_true"]).max()
        print(f"{label}: end speed {np.mean(w['omega_m'][end]) / RPM:.1f} r/min, angle error RMS "
              f"{np.sqrt(np.mean(err ** 2)):.2f} deg, peak current {peak:.2f} A, "
              f"modes {' '.join(MODE_NAMES[m] for m in np.unique(w['mode']))}")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
