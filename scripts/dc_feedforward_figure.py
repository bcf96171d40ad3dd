#!/usr/bin/env python3
"""The dc-link voltage feed-forward's figure (docs/faults.md): the default drive (scenarios/fullload_start.toml)
with the link 10 % low from 0.6 s, without and with ``control.dc_feedforward``, on the golden backend: the
measured link, the HF response (GAMMA_D) against the level the check learned, the angle error and the speed.

    python scripts/dc_feedforward_figure.py [--factor 0.9] [--out docs/figures/dc_sag_feedforward.png]
"""

from __future__ import annotations

import argparse
import copy
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
from golden.firmware.supervisor import MODE_FAULT  # noqa: E402
from golden.scenario import ScenarioError, parse_scenario  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SAG_AT = 0.6


def run(ff: str, factor: float):
    path = os.path.join(HERE, "..", "scenarios", "fullload_start.toml")
    with open(path, "rb") as f:
        data = tomllib.load(f)
    data = copy.deepcopy(data)
    data["scenario"]["duration"] = "0.9 s"
    data.setdefault("control", {})["dc_feedforward"] = ff
    data["faults"] = [{"kind": "dc_link", "factor": factor, "at": f"{SAG_AT} s"}]
    return ClosedLoop(parse_scenario(data, f"{path} with a sag")).run(progress=False)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--factor", type=float, default=0.9, help="the link during the sag, of nominal (default 0.9)")
    ap.add_argument("--out", default=os.path.join(HERE, "..", "docs", "figures", "dc_sag_feedforward.png"))
    args = ap.parse_args(argv)
    if not 0 < args.factor <= 2:
        print("dc_feedforward_figure: --factor must be in (0, 2]", file=sys.stderr)
        return 1
    try:
        runs = {ff: run(ff, args.factor) for ff in ("off", "on")}
    except ScenarioError as exc:
        print(f"dc_feedforward_figure: {exc}", file=sys.stderr)
        return 1
    fig, ax = plt.subplots(4, 1, figsize=(8, 9), sharex=True)
    for ff, res in runs.items():
        w, t = res.windows, res.t * 1e3
        label = f"feed-forward {ff}"
        trip = np.flatnonzero(w["mode"] == MODE_FAULT)
        if len(trip):
            label += f" (trips {FAULT_NAMES[w['fault'][trip[0]]]} at {t[trip[0]] - SAG_AT * 1e3:.1f} ms)"
        ax[0].plot(t, w["vdc"], label=label)
        ax[1].plot(t, w["gamma_d"], label=label)
        ax[2].plot(t, res.angle_error_deg(), label=label)
        ax[3].plot(t, w["omega_m"] * 30 / np.pi, label=label)
        print(f"{label}; angle error after the sag {np.sqrt(np.mean(res.angle_error_deg()[res.t > SAG_AT + 0.05] ** 2)):.2f}"
              " deg RMS" if not len(trip) else label)
    for a, name in zip(ax, ("VDC [code]", "HF response GAMMA_D", "angle error [deg el]", "speed [r/min]")):
        a.set_ylabel(name)
        a.axvline(SAG_AT * 1e3, color="k", lw=0.5)
        a.grid(True, lw=0.3)
    ax[0].legend(fontsize=8)
    ax[-1].set_xlabel("time [ms]")
    ax[0].set_title(f"Default drive, dc link at {100 * args.factor:.0f} % from {SAG_AT * 1e3:.0f} ms")
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
