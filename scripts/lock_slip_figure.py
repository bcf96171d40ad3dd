#!/usr/bin/env python3
"""The fault matrix's slow lock losses (docs/faults.md): the three cells whose lost lock was tripped later than
20 ms after it was lost before the slip check (0.5 A offset on sensor a at 0 and 50 r/min, 30 % gain error on sensor
a at 250 r/min, all without load), on the golden backend, the gain error's cell twice: with the slip check off (as
before it) and on. Angle error of the angle in use and of the rotor flux observer beside it, with the 60 and 90 deg
marks; true and estimated speed.

    python scripts/lock_slip_figure.py [--out docs/figures/fault_slow_lock_loss.png] [--jobs 2]

Prints for each cell when the angle error first passed 60 and 90 deg, how long it stayed beyond 60 deg in its
longest stretch, and the trip.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys
from concurrent.futures import ProcessPoolExecutor

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from golden.closedloop import ClosedLoop  # noqa: E402
from golden.firmware.protection import FAULT_NAMES  # noqa: E402
from golden.firmware.supervisor import MODE_FAULT  # noqa: E402
from hfi.faults import DURATION_S, FAULTS, ONSET_S, scenario  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
RPM = np.pi / 30
CELLS = (("sensor offset 0.5 A (a)", 0.0, True), ("sensor offset 0.5 A (a)", 50.0, True),
         ("sensor gain x0.7 (a)", 250.0, False), ("sensor gain x0.7 (a)", 250.0, True))
"""The matrix cells (fault, speed, slip check on; no load) whose lost lock was tripped 66-248 ms after it was lost
before the slip check."""
LOCK_DEG = 60.0


def run(cell: tuple[str, float, bool]) -> dict:
    """One cell on the golden closed loop; the columns the figure and the summary need."""
    name, rpm, slip = cell
    sc = scenario(FAULTS[name], rpm, False, DURATION_S)
    if not slip:
        sc = dataclasses.replace(sc, protection=dataclasses.replace(sc.protection, slip_speed=0.0))
    res = ClosedLoop(sc).run(progress=False)
    w = res.windows
    return {"t": res.t, "err": res.angle_error_deg(), "err_hi": res.angle_error_deg("theta_hi"),
            "true": w["omega_m"] / RPM,
            "est": w["omega_f"] / res.scales.speed_mech(RPM), "mode": w["mode"], "fault": w["fault"]}


def longest(flags: np.ndarray) -> int:
    """The longest run of True in ``flags`` [windows]."""
    best = cur = 0
    for f in flags:
        cur = cur + 1 if f else 0
        best = max(best, cur)
    return best


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=os.path.join(HERE, "..", "docs", "figures", "fault_slow_lock_loss.png"))
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args(argv)
    if args.jobs < 1:
        print("lock_slip_figure: --jobs must be >= 1", file=sys.stderr)
        return 1
    with ProcessPoolExecutor(args.jobs) as ex:
        runs = list(ex.map(run, CELLS))
    fig, ax = plt.subplots(2, len(CELLS), figsize=(17, 6.5), sharex="col")
    for k, ((name, rpm, slip), r) in enumerate(zip(CELLS, runs)):
        t, err = r["t"], r["err"]
        on = (t >= ONSET_S) & (r["mode"] != MODE_FAULT)
        trip = np.flatnonzero(r["mode"] == MODE_FAULT)
        t_trip = float(t[trip[0]]) if len(trip) else None
        first = {lim: (float(t[np.flatnonzero(on & (np.abs(err) > lim))[0]]) if (on & (np.abs(err) > lim)).any()
                       else None) for lim in (LOCK_DEG, 90.0)}
        stretch = longest(on & (np.abs(err) > LOCK_DEG)) * float(t[1] - t[0]) * 1e3
        code = FAULT_NAMES[int(r["fault"][trip[0]])] if len(trip) else "none"
        shown = (t >= ONSET_S - 0.05) & (t <= (t_trip + 0.05 if t_trip else t[-1]))
        ax[0, k].plot(t[shown], err[shown], lw=0.6, label="angle in use (HF)")
        ax[0, k].plot(t[shown], r["err_hi"][shown], lw=0.6, color="tab:green", alpha=0.7, label="rotor flux observer")
        for lim in (LOCK_DEG, 90.0):
            ax[0, k].axhline(lim, color="r" if lim == LOCK_DEG else "k", lw=0.7, ls="--")
            ax[0, k].axhline(-lim, color="r" if lim == LOCK_DEG else "k", lw=0.7, ls="--")
        ax[1, k].plot(t[shown], r["true"][shown], lw=1.0, label="true")
        ax[1, k].plot(t[shown], r["est"][shown], lw=0.6, label="estimated (filtered)")
        for a in ax[:, k]:
            a.axvline(ONSET_S, color="r", lw=0.8)
            if t_trip is not None:
                a.axvline(t_trip, color="k", lw=0.8, ls=":")
            a.grid(alpha=0.3)
        ax[0, k].set(title=f"{name}, {rpm:g} r/min, no load\nslip check {'on' if slip else 'off'}: {code}",
                     ylim=(-185, 185))
        ax[1, k].set(xlabel="t [s] (red: onset, dotted: trip)")
        print(f"{name} at {rpm:g} r/min, slip check {'on' if slip else 'off'}: error beyond 60 deg first at {first[LOCK_DEG]} s, beyond 90 deg first at "
              f"{first[90.0]} s, longest stretch beyond 60 deg {stretch:.1f} ms; trip {code} at {t_trip} s")
    ax[0, 0].set_ylabel("angle error [deg el.] (dashed: 60, 90)")
    ax[1, 0].set_ylabel("speed [r/min]")
    ax[1, 0].legend(fontsize=8)
    ax[0, 0].legend(fontsize=8, loc="lower left")
    fig.suptitle("the fault matrix's slow lock losses: a sawtooth, and polarity slips towards 180 deg; the gain "
                 "error's slip without and with the slip check (the observer stays with the rotor)")
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    fig.savefig(args.out, dpi=100)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
