#!/usr/bin/env python3
"""Benchmark of the three closed-loop backends side by side: simulated seconds per wall second, one core.

Runs one scenario (default ``scenarios/fullload_start.toml``) for ``--duration`` simulated seconds
(default 0.4 s) on the ``golden`` (Python bit-true model), ``rtl`` (firmware on the Verilated hfi_soc)
and ``hls`` (HLS C++ kernels + host firmware + C plant, native) backends, after building everything
(not timed). The hls backend runs ``--repeat`` times (best wall time kept; it is the fastest and the
most sensitive to the other core's load). Prints one line per backend (wall time, real-time factor,
speed-up over golden), the hls backend's split between the plant and the kernels + firmware, and ends
with ``realtime_factor: X`` (the hls backend; the project's target is >= 10).

    python scripts/bench_hls.py [--duration 0.4] [--scenario FILE] [--repeat 3] [--no-rtl]
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import numpy as np  # noqa: E402

from golden.closedloop import ClosedLoop  # noqa: E402
from golden.scenario import ScenarioError, load_scenario  # noqa: E402
from hfi.argtypes import positive_finite, positive_int  # noqa: E402
from hfi.hls_backend import HlsBackendError, HlsClosedLoop  # noqa: E402
from hfi.hls_build import HlsBuildError, build  # noqa: E402
from hfi.rtl_backend import RtlBackendError, RtlClosedLoop  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenario", default=os.path.join(HERE, "..", "scenarios", "fullload_start.toml"))
    ap.add_argument("--duration", type=positive_finite, default=0.4, help="simulated seconds (default 0.4)")
    ap.add_argument("--repeat", type=positive_int, default=3, help="runs of the hls backend, best kept (default 3)")
    ap.add_argument("--no-rtl", action="store_true", help="skip the (slow) rtl backend")
    args = ap.parse_args(argv)
    try:
        sc = dataclasses.replace(load_scenario(args.scenario), duration=args.duration)
        build("loop")
        runs = {"golden": ClosedLoop(sc).run(progress=False)}
        if not args.no_rtl:
            runs["rtl"] = RtlClosedLoop(sc).run(progress=False)
        runs["hls"] = min((HlsClosedLoop(sc).run(progress=False) for _ in range(args.repeat)), key=lambda r: r.wall_s)
    except (ScenarioError, RtlBackendError, HlsBackendError, HlsBuildError, ValueError, OSError) as exc:
        print(f"bench_hls: {exc}", file=sys.stderr)
        return 1
    sim_s = float(runs["golden"].t[-1])
    for name, res in runs.items():
        same = all(np.array_equal(res.windows[k], runs["golden"].windows[k]) for k in ("gamma", "theta_hat", "theta_e"))
        print(f"{name:>6}: {sim_s:.3f} s simulated in {res.wall_s:8.3f} s wall: realtime factor "
              f"{sim_s / res.wall_s:8.4f}, {runs['golden'].wall_s / res.wall_s:7.2f}x golden"
              f"{'' if same else '  (TRACE DIFFERS FROM GOLDEN)'}")
    hls = runs["hls"]
    n_win = len(hls.t)
    print(f"hls per window ({n_win} windows): {1e6 * hls.wall_s / n_win:.1f} us, of which plant "
          f"{1e6 * hls.plant_wall_s / n_win:.1f} us, kernels + firmware + records "
          f"{1e6 * (hls.wall_s - hls.plant_wall_s) / n_win:.1f} us; plant-only bound "
          f"{sim_s / hls.plant_wall_s:.2f}x real time")
    print(f"hfi_window_dsp alone (C simulation, 200-sample windows): {window_dsp_ns_per_sample():.1f} ns per sample")
    print(f"realtime_factor: {sim_s / hls.wall_s:.3f}")
    return 0


def window_dsp_ns_per_sample(n: int = 200, repeat: int = 20_000) -> float:
    """The ``hfi_window_dsp`` kernel's time per sample in the C-simulation library (``csim_window_dsp_time``), on
    random 12-bit codes around mid-scale with 90 % of the samples kept."""
    from hfi import hls_build
    ffi, lib = hls_build.csim()
    rng = np.random.default_rng(1)
    a = np.ascontiguousarray(rng.integers(1900, 2200, n), dtype=np.uint16)
    b = np.ascontiguousarray(rng.integers(1900, 2200, n), dtype=np.uint16)
    w = np.ascontiguousarray(rng.integers(-32768, 32768, n), dtype=np.int16)
    keep = np.ascontiguousarray(rng.random(n) < 0.9, dtype=np.uint8)
    ns = lib.csim_window_dsp_time(repeat, n, ffi.from_buffer("uint16_t[]", a), ffi.from_buffer("uint16_t[]", b),
                                  ffi.from_buffer("int16_t[]", w), ffi.from_buffer("uint8_t[]", keep),
                                  12, 10, -10, 16400, 16300, 12000, 30000)
    return ns / (repeat * n)


if __name__ == "__main__":
    sys.exit(main())
