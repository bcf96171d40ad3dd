"""Open-loop injection run: the foundation's main job until the closed loop exists.

Drives the plant with :mod:`golden.openloop` gate edges (square-wave injection on a fixed estimated
d-axis plus optional fundamental voltages), samples the sensors every 1 us, and reduces the samples
per carrier period to what the estimator will see: the HF peak-to-peak currents in the estimated
frame and the eq. (19) demodulation of i_q_hat (Benevieri et al. 2023).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from golden.openloop import PwmConfig, final_levels, gate_edges, injection_compares
from golden.plant import Plant
from golden.scenario import Scenario

SAMPLE_TICKS = 100
"""Oversampling interval [ticks]: 1 us at 100 MHz."""


@dataclass
class OpenLoopResult:
    """Samples and per-period reductions of an open-loop run (arrays, SI units)."""

    t: np.ndarray              # sample times [s]
    i_meas: np.ndarray         # (n, 3) measured phase currents from the ADC codes [A]
    adc: np.ndarray            # (n, 3) raw ADC codes
    truth: np.ndarray          # (n,) plant_state records
    i_hat: np.ndarray          # (n, 2) measured currents in the estimated frame [A]
    cw: np.ndarray             # (n,) carrier in [-1, 1] at each sample
    period_t: np.ndarray       # (m,) period start times [s]
    pp_hat: np.ndarray         # (m, 2) peak-to-peak of i_d_hat, i_q_hat per period [A]
    env_hat: np.ndarray        # (m, 2) HF envelopes: amplitudes of i_d_hat, i_q_hat on -cw per period [A]
    demod: np.ndarray          # (m,) mean of i_q_hat * sin(-cw pi/2) per period [A]
    wall_s: float


def adc_to_current(adc: np.ndarray, bits: int, rng: float) -> np.ndarray:
    """Inverse of the plant's ADC transfer: mid-scale code = 0 A, LSB = 2 rng / 2^bits."""
    return (adc.astype(float) - 2 ** (bits - 1)) * (2.0 * rng / 2 ** bits)


def estimated_frame(i_abc: np.ndarray, theta_hat: float) -> np.ndarray:
    """Clarke (amplitude-invariant) then Park with the estimated angle: columns i_d_hat, i_q_hat."""
    i_al = (2 * i_abc[:, 0] - i_abc[:, 1] - i_abc[:, 2]) / 3
    i_be = (i_abc[:, 1] - i_abc[:, 2]) / math.sqrt(3)
    c, s = math.cos(theta_hat), math.sin(theta_hat)
    return np.stack([c * i_al + s * i_be, -s * i_al + c * i_be], axis=1)


def carrier(ticks: np.ndarray, half: int) -> np.ndarray:
    """Triangular carrier cw in [-1, 1]: -1 at the period start (bottom), +1 at mid-period (top)."""
    phase = ticks % (2 * half)
    return np.where(phase < half, 2 * phase / half - 1, 3 - 2 * phase / half)


def simulate(scn: Scenario, progress: bool = True, chunk_periods: int = 50) -> OpenLoopResult:
    """Run the scenario's injection open loop for its duration."""
    cfg = PwmConfig(scn.pwm.f_sw, scn.pwm.dead_time, scn.pwm.tick_hz)
    inj = scn.injection
    period = 2 * cfg.half
    n_periods = max(1, int(round(scn.duration * scn.pwm.f_sw)))
    plant = Plant(scn.plant)
    adc, truth, levels = [], [], None
    bar = _progress(n_periods, progress, scn.name)
    t_start = time.perf_counter()
    for first in range(0, n_periods, chunk_periods):
        n = min(chunk_periods, n_periods - first)
        cmp = injection_compares(cfg, n, scn.plant["inv"]["V_dc"], inj.V_h, inj.theta_hat, inj.v_d, inj.v_q)
        ticks, masks = gate_edges(cfg, cmp, start_tick=first * period, initial_levels=levels)
        levels = final_levels(cfg, cmp)
        samples = np.arange(first * period, (first + n) * period, SAMPLE_TICKS)
        out = plant.run(ticks, samples, gates=masks, truth=True)
        adc.append(out["adc"])
        truth.append(out["truth"])
        bar(n)
    wall = time.perf_counter() - t_start
    adc = np.concatenate(adc)
    truth = np.concatenate(truth)
    sens = scn.plant["sens"]
    i_meas = adc_to_current(adc, sens["adc_bits"], sens["adc_range"])
    i_hat = estimated_frame(i_meas, inj.theta_hat)
    ticks = truth["tick"]
    cw = carrier(ticks, cfg.half)
    per = period // SAMPLE_TICKS
    m = len(ticks) // per
    blocks = i_hat[: m * per].reshape(m, per, 2)
    weights = np.sin(-cw[:per] * math.pi / 2)  # Benevieri et al. 2023, eq. (19)
    demod = (blocks[:, :, 1] * weights).mean(axis=1)
    return OpenLoopResult(t=truth["t"], i_meas=i_meas, adc=adc, truth=truth, i_hat=i_hat, cw=cw,
                          period_t=ticks[: m * per: per] / scn.pwm.tick_hz, pp_hat=np.ptp(blocks, axis=1),
                          env_hat=envelopes(blocks, cw[:per]), demod=demod, wall_s=wall)


def envelopes(blocks: np.ndarray, cw: np.ndarray) -> np.ndarray:
    """Least-squares amplitude a of each period's samples on the injection waveform: y ~ a (-cw) + b.

    For a linear machine under ideal square-wave voltage, a is the bracket of eq. (18) (q) and of its
    d counterpart (Benevieri et al. 2023); PWM ripple, being orthogonal to -cw on average, drops out.
    """
    x = -cw - np.mean(-cw)
    y = blocks - blocks.mean(axis=1, keepdims=True)
    return np.einsum("p,mpk->mk", x, y) / np.dot(x, x)


def theory_envelopes(scn: Scenario, err: float) -> tuple[float, float]:
    """HF envelopes (amplitudes on -cw) on the estimated axes for a linear machine with the scenario's
    L_d, L_q under ideal square-wave voltage: Benevieri et al. 2023, eq. (18),
    a_q = V_h/(8 f_sw) (L_q - L_d)/(L_d L_q) sin(2 err), and its d counterpart
    a_d = V_h/(4 f_sw) (cos^2(err)/L_d + sin^2(err)/L_q); the peak-to-peak values are twice these."""
    L_d, L_q = scn.plant["mag"]["L_d"], scn.plant["mag"]["L_q"]
    V_h, f = scn.injection.V_h, scn.pwm.f_sw
    a_d = V_h / (4 * f) * (math.cos(err) ** 2 / L_d + math.sin(err) ** 2 / L_q)
    a_q = V_h / (8 * f) * (L_q - L_d) / (L_d * L_q) * math.sin(2 * err)
    return a_d, a_q


def _progress(total: int, enabled: bool, label: str):
    """A callable advancing a progress bar by n periods (tqdm on a terminal or in a log)."""
    if not enabled:
        return lambda n: None
    from tqdm import tqdm
    bar = tqdm(total=total, unit="period", desc=label, mininterval=1.0)

    def step(n):
        bar.update(n)
        if bar.n >= total:
            bar.close()
    return step
