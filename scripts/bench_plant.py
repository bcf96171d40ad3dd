#!/usr/bin/env python3
"""Plant speed and step-size accuracy for the 002 defaults.

Simulated seconds per wall second on one core for the default open-loop scenario (Table I motor,
5 kHz PWM with 4 us dead time at 100 MHz ticks, 200 current samples per period, realistic sensors),
through the batch API (one C call per chunk of periods; and one call per PWM period, as the golden
closed loop calls it: microseconds per 200 us window) and through the per-event API (one Python
call per gate edge and per sample). Then the integration-step study behind the default step length:
the same run with shorter steps, and the largest current difference.

Usage: scripts/bench_plant.py [--scenario FILE] [--seconds S] [--event-seconds S]
The last line printed is ``realtime_factor: X`` (batch API).
"""

from __future__ import annotations

import argparse
import os
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # one core: no BLAS threads spinning beside the plant
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import numpy as np  # noqa: E402

from golden.openloop import PwmConfig, gate_edges, injection_compares  # noqa: E402
from golden.plant import Plant, merge  # noqa: E402
from golden.scenario import ScenarioError, load_scenario  # noqa: E402
from hfi.argtypes import positive_finite  # noqa: E402

SAMPLE_TICKS = 100  # 1 us oversampling: 200 samples per 5 kHz period


def stimulus(scn, n_periods: int):
    """Gate edges and sample ticks of ``n_periods`` PWM periods of the scenario's injection."""
    cfg = PwmConfig(scn.pwm.f_sw, scn.pwm.dead_time, scn.pwm.tick_hz)
    inj = scn.injection
    cmp = injection_compares(cfg, n_periods, scn.plant["inv"]["V_dc"], inj.V_h, inj.theta_hat, inj.v_d, inj.v_q)
    ticks, masks = gate_edges(cfg, cmp)
    samples = np.arange(0, n_periods * 2 * cfg.half, SAMPLE_TICKS)
    return ticks, masks, samples


def bench_batch(scn, seconds: float, chunk: int = 50) -> float:
    """Simulated seconds per wall second, batch API, one call per ``chunk`` periods (``chunk = 1``: as
    the golden closed loop calls it, once per PWM window)."""
    period_ticks = int(round(scn.pwm.tick_hz / scn.pwm.f_sw))
    n_total = int(round(seconds * scn.pwm.f_sw))
    ticks, masks, samples = stimulus(scn, n_total)
    bounds = np.arange(0, n_total + chunk, chunk) * period_ticks
    e_idx, s_idx = np.searchsorted(ticks, bounds), np.searchsorted(samples, bounds)
    plant = Plant(scn.plant)
    t0 = time.perf_counter()
    for k in range(len(bounds) - 1):
        plant.run(ticks[e_idx[k]:e_idx[k + 1]], samples[s_idx[k]:s_idx[k + 1]], gates=masks[e_idx[k]:e_idx[k + 1]])
    return n_total / scn.pwm.f_sw / (time.perf_counter() - t0)


def bench_events(scn, seconds: float) -> float:
    """Simulated seconds per wall second through the per-event API (one Python call per event)."""
    period = 1.0 / scn.pwm.f_sw
    n = max(1, int(round(seconds / period)))
    ticks, masks, samples = stimulus(scn, n)
    events = sorted([(int(t), 0, int(m)) for t, m in zip(ticks, masks)] + [(int(t), 1, 0) for t in samples])
    plant = Plant(scn.plant)
    t0 = time.perf_counter()
    for tick, kind, mask in events:
        plant.advance(tick)
        if kind == 0:
            plant.set_gates(mask)
        else:
            plant.sample()
    return n * period / (time.perf_counter() - t0)


STEPS = [(100, 25), (25, 25), (100, 5), (25, 5)]
"""(max_substep_ticks, max_substep_commutation_ticks) pairs compared with the reference (2, 1)."""


def step_study(scn, seconds: float = 0.02) -> list[tuple[tuple[int, int], float, float]]:
    """Largest phase-current difference vs 20 ns / 10 ns reference steps, noise off."""
    n = int(round(seconds * scn.pwm.f_sw))
    ticks, masks, samples = stimulus(scn, n)
    quiet = merge(scn.plant, {"sens": {"noise_rms": 0.0}})

    def currents(step, commutation):
        p = merge(quiet, {"max_substep_ticks": step, "max_substep_commutation_ticks": commutation})
        return Plant(p).run(ticks, samples, gates=masks, truth=True)["truth"]["i_abc"]

    ref = currents(2, 1)
    scale = np.max(np.abs(ref))
    out = []
    for steps in STEPS:
        diff = float(np.max(np.abs(currents(*steps) - ref)))
        out.append((steps, diff, diff / scale))
    return out


def main() -> int:
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default=os.path.join(here, "..", "scenarios", "openloop_injection.toml"))
    ap.add_argument("--seconds", type=positive_finite, default=2.0, help="simulated time for the batch benchmark")
    ap.add_argument("--event-seconds", type=positive_finite, default=0.05, help="simulated time, per-event benchmark")
    args = ap.parse_args()
    try:
        scn = load_scenario(args.scenario)
    except (ScenarioError, OSError) as exc:
        print(f"bench_plant: {exc}", file=sys.stderr)
        return 1
    if min(args.seconds, args.event_seconds) < 1 / scn.pwm.f_sw:
        print(f"bench_plant: --seconds and --event-seconds must be at least one PWM period ({1 / scn.pwm.f_sw:g} s)",
              file=sys.stderr)
        return 1
    print(f"scenario: {scn.name}; f_sw {scn.pwm.f_sw:g} Hz, dead time {scn.pwm.dead_time * 1e6:g} us, "
          f"{int(scn.pwm.tick_hz / scn.pwm.f_sw / SAMPLE_TICKS)} samples/period, "
          f"max step {scn.plant['max_substep_ticks']} ticks")
    print("step-size study (20 ms, max |i - i_ref|, reference steps 20 ns / 10 ns while commutating):")
    for (step, comm), diff, rel in step_study(scn):
        print(f"  step {step / scn.pwm.tick_hz * 1e6:5.2f} us, commutating {comm / scn.pwm.tick_hz * 1e6:5.2f} us: "
              f"{diff:.3e} A ({rel:.1e} of peak)")
    print(f"per-event API ({args.event_seconds:g} s simulated) ...", flush=True)
    ev = bench_events(scn, args.event_seconds)
    print(f"  per-event API: {ev:8.3f} x real time")
    print(f"batch API ({args.seconds:g} s simulated) ...", flush=True)
    per_window = max(bench_batch(scn, args.seconds, chunk=1) for _ in range(2))
    print(f"  one call per PWM period: {per_window:8.3f} x real time, "
          f"{1e6 / scn.pwm.f_sw / per_window:6.1f} us per {1e6 / scn.pwm.f_sw:g} us window (best of 2)")
    rtf = max(bench_batch(scn, args.seconds) for _ in range(2))
    print(f"  batch API:     {rtf:8.3f} x real time (best of 2)")
    print(f"realtime_factor: {rtf:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
