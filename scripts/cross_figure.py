#!/usr/bin/env python3
"""The methods on each other's motors (docs/compare.md): angle error against load from the cross-pair sweeps'
results, one panel per pair, one line per speed (median RMS of the kept runs, a bar to the worst peak, a cross with
the share of runs lost or tripped). Where a sweep varies ``protection.hf_response``, the runs with the check out of
the way (1.0) are drawn: the check's own trips are in the text.

    hfi sweep sweeps/cross_<pair>.toml       # each pair first (out/sweep/<name>/results.parquet)
    python scripts/cross_figure.py [--out docs/figures/compare_cross_pairs.png]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
from pathlib import Path

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from hfi.compare import kept  # noqa: E402
from hfi.report import save_figure  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
PAIRS = (("cross_001_on_002", {}, "001 method on the Table I SPMSM (5 kHz)"),
         ("cross_001_on_000", {}, "001 method on the 000 PMaSynRM (10 kHz), SNR rule"),
         ("cross_000_on_002", {"injection.V_h": "21 V", "pwm.dead_time": "4 us"},
          "000 method on the Table I SPMSM (5 kHz), 21 V, 4 us dead time"),
         ("cross_000_on_002", {"injection.V_h": "21 V", "pwm.dead_time": "0.5 us"},
          "000 method on the Table I SPMSM, 21 V, 0.5 us dead time"),
         ("cross_002_on_001", {"estimator.sqw_bangbang.K_bb": "40 rad/s"},
          "002 method on the 001 IPMSM (1 kHz), step rule"),
         ("cross_002_on_001", {"estimator.sqw_bangbang.K_bb": "68.6 rad/s"},
          "002 method on the 001 IPMSM (1 kHz), slew rule"),
         ("cross_002_on_000", {}, "002 method on the 000 PMaSynRM (10 kHz), SNR + slew rules"),
         ("cross_002_on_003", {"control.current_bw": "150 Hz", "estimator.sqw_bangbang.cross_saturation": "off"},
          "002 method on the 003 SyRM (10 kHz), PIs 150 Hz"),
         ("cross_002_on_003", {"control.current_bw": "40 Hz", "estimator.sqw_bangbang.cross_saturation": "off"},
          "002 method on the 003 SyRM, PIs 40 Hz"),
         ("cross_002_on_003", {"control.current_bw": "40 Hz", "estimator.sqw_bangbang.cross_saturation": "on"},
          "002 on the 003 SyRM, PIs 40 Hz + cross-saturation table"),
         ("cross_001_on_003", {"estimator.sqw_cic.cross_saturation": "off"},
          "001 method on the 003 SyRM (10 kHz), PIs 40 Hz, 0.3 A on d"),
         ("cross_001_on_003", {"estimator.sqw_cic.cross_saturation": "on"},
          "001 on the 003 SyRM, + cross-saturation table"),
         ("cross_000_on_003", {"estimator.rot_bpf.cross_saturation": "off"},
          "000 method on the 003 SyRM (10 kHz), PIs 40 Hz, 0.3 A on d"),
         ("cross_000_on_003", {"estimator.rot_bpf.cross_saturation": "on"},
          "000 on the 003 SyRM, + cross-saturation table"))
"""(sweep name, the values of its other axes a panel draws, panel title), in the order of docs/compare.md."""
CHECK_OFF = 1.0
"""``protection.hf_response`` of the runs drawn where the sweep varies it."""


def rows_of(name: str, axes: dict) -> list[dict]:
    """The result rows of sweep ``name`` (out/sweep/<name>/results.parquet) with the check out of the way and the
    values ``axes`` of its other axes."""
    import pyarrow.parquet as pq
    path = ROOT / "out" / "sweep" / name / "results.parquet"
    if not path.is_file():
        raise FileNotFoundError(f"{path}: run `hfi sweep sweeps/{name}.toml` first")
    rows = pq.read_table(path).to_pylist()
    want = {"protection.hf_response": CHECK_OFF, **axes}
    return [r for r in rows if all(r.get(k, v) == v for k, v in want.items())]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "figures" / "compare_cross_pairs.png")
    args = ap.parse_args(argv)
    try:
        data = [(title, rows_of(name, axes)) for name, axes, title in PAIRS]
        if not all(rows for _, rows in data):
            raise FileNotFoundError("a panel has no rows: run its sweep again (sweeps/cross_*.toml)")
    except (FileNotFoundError, OSError) as exc:
        print(f"cross_figure: {exc}", file=sys.stderr)
        return 1
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ncols = 3
    nrows = -(-len(data) // ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(4.0 * ncols, 4.2 * nrows), sharey=True, squeeze=False)
    for ax in axes.flat[len(data):]:
        ax.set_visible(False)
    for ax, (title, rows) in zip(axes.flat, data):
        speeds = sorted({r["reference.speed.scale"] for r in rows})
        for k, speed in enumerate(speeds):
            loads = sorted({r["load.torque.scale"] for r in rows if r["reference.speed.scale"] == speed})
            x, med, peak, lost = [], [], [], []
            for load in loads:
                g = [r for r in rows if r["reference.speed.scale"] == speed and r["load.torque.scale"] == load]
                ok = [r for r in g if kept(r)]
                x.append(load + (k - (len(speeds) - 1) / 2) * 0.04)
                med.append(statistics.median(r["win0.err_rms_deg"] for r in ok) if ok else float("nan"))
                peak.append(max(r["win0.err_peak_deg"] for r in ok) if ok else float("nan"))
                lost.append((len(g) - len(ok)) / len(g))
            line, = ax.plot(x, med, "o-", color=f"C{k}", label=f"{100 * speed:.0f} % of rated speed")
            ax.vlines(x, med, peak, color=line.get_color(), alpha=0.5)
            for xi, share in zip(x, lost):
                if share:
                    ax.plot(xi, 0.3, "x", color=line.get_color(), markersize=9)
                    ax.annotate(f"{100 * share:.0f}%", (xi, 0.3), textcoords="offset points", xytext=(0, 6 + 9 * k),
                                ha="center", fontsize=7, color=line.get_color())
        ax.set_title(title, fontsize=8)
        ax.set_xlabel("load [p.u. of rated torque]")
        ax.set_yscale("log")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
    for row in axes:
        row[0].set_ylabel("angle error [deg el]: median RMS (dot), worst peak (bar)\n"
                          "x: share of seeds that lost lock or tripped")
    fig.suptitle("The methods on each other's motors (HF response check out of the way or off; 10 seeds a point, "
                 "5 for the 000 method and on the SyRM)",
                 fontsize=10)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    print(f"wrote {save_figure(fig, str(args.out.parent), args.out.name, top=1 - 0.35 / fig.get_figheight())}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
