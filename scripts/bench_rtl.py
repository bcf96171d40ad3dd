#!/usr/bin/env python3
"""Benchmark of the ``rtl`` closed-loop backend: simulated clock cycles per wall second on one core.

Runs the default scenario (``scenarios/fullload_start.toml``) on the Verilated hfi_soc with the C plant
for ``--duration`` simulated seconds (default 0.2 s), twice: on the FPGA build with every optional block in (the
baseline) and on the scenario's system (only the blocks its methods need, the build the rtl backend runs; docs/rtl.md
"Build options"). The builds are not timed (a result's wall time is its co-simulation's). Prints the
simulated clocks, the wall time of each co-simulation, the firmware's cycles per control period, the ratio,
and ends with ``mcycles_per_s: X`` (million simulated clocks per wall second of the scenario's system; the
project's target is >= 5).

    python scripts/bench_rtl.py [--duration 0.2] [--scenario FILE]
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from golden.scenario import ScenarioError, load_scenario  # noqa: E402
from hfi.argtypes import positive_finite  # noqa: E402
from hfi.rtl_backend import EVERY_BLOCK, RtlBackendError, RtlClosedLoop  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenario", default=os.path.join(HERE, "..", "scenarios", "fullload_start.toml"))
    ap.add_argument("--duration", type=positive_finite, default=0.2, help="simulated seconds (default 0.2)")
    args = ap.parse_args(argv)
    try:
        sc = dataclasses.replace(load_scenario(args.scenario), duration=args.duration)
        # the builds are not timed: a run's wall_s is its co-simulation's
        runs = {"every block": RtlClosedLoop(sc).run(progress=False, options=EVERY_BLOCK),
                "the scenario's system": RtlClosedLoop(sc).run(progress=False)}
    except (ScenarioError, RtlBackendError, ValueError, OSError) as exc:
        print(f"bench_rtl: {exc}", file=sys.stderr)
        return 1
    for name, res in runs.items():
        soc = res.soc
        left = ", ".join(soc["left_out"]) or "none"
        print(f"scenario {sc.name} on {name} (left out: {left}): {float(res.t[-1]):.3f} s simulated, "
              f"{soc['sim_cycles']} clocks, {soc['wall_s']:.2f} s wall (co-simulation only), "
              f"{soc['mcycles_per_s']} M clocks/s")
    res = runs["the scenario's system"]
    soc = res.soc
    print(f"the scenario's system against every block: "
          f"{soc['mcycles_per_s'] / runs['every block'].soc['mcycles_per_s']:.2f}x")
    print(f"realtime factor {float(res.t[-1]) / soc['wall_s']:.4f}; firmware cycles per period: max "
          f"{soc['fw_cycles_max']} (target {soc['fw_cycles_target']}), mean {soc['fw_cycles_mean']}; "
          f"interrupt to COMMIT max {soc['irq_to_commit_cycles_max']} (deadline {soc['deadline_cycles']}); "
          f"late commits {soc['late_commits']}")
    print(f"mcycles_per_s: {soc['mcycles_per_s']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
