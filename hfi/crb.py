"""The angle noise of an estimator against the Cramér-Rao bound of the samples the hardware takes.

At standstill the rotor angle is a constant, and every current sample the ADC converts carries some
information about it: the currents' response to the voltage applied (the injection, the PWM, the switching
states) depends on the angle through the saliency. The **Fisher information** of a stretch of a run is

    J = sum over samples s and the two measured phases k of (d i_k(s) / d theta)^2 / sigma^2,

with ``sigma^2`` the sensor noise plus the ADC's quantisation (``LSB^2 / 12``) and the derivative taken on the
plant itself: the gate signals the drive applied in the stretch are replayed twice on a locked rotor, at
``theta -+ DELTA``, without noise (hfi.crb.sample_information). ``1 / J`` bounds the variance of any unbiased
estimate of the angle from those samples (the bound given the applied voltages, which the drive knows).
Per control window, ``sigma_w^2 = N_windows / J``.

An estimator is a tracker: its error is correlated over some time. Over a long stretch ``T`` the mean of its
output has the variance ``sigma^2 tau_c / T`` (``sigma^2`` the variance of its error, ``tau_c`` the
integrated correlation time, by batch means); the samples of that stretch allow
``sigma_w^2 T_w / T`` at best. Their ratio is the **efficiency** ``eta = sigma_w^2 T_w / (sigma^2 tau_c)``: 1
means the estimator uses all the information in the samples it is given, 0.01 that it needs a hundred times
the data an efficient one would. The bias (the error's mean) is reported apart; the bound is about noise.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass

import numpy as np

from golden.plant import Plant

DELTA = 1e-4
"""Half the angle step of the central difference [rad el]."""
SETTLE_S = 0.02
"""The replay starts this long before the stretch, so that its currents converge to the run's (L/R is a few ms
on the four motors)."""
PHASES = (0, 1)
"""The measured phases (the hardware has two current sensors, a and b)."""


def noise_variance(plant: dict) -> float:
    """Variance of one current sample [A^2]: sensor noise plus the ADC's quantisation."""
    sens = plant["sens"]
    lsb = 2 * sens["adc_range"] / 2 ** sens["adc_bits"]
    return sens["noise_rms"] ** 2 + lsb * lsb / 12


def _replay(plant: dict, theta_e: float, edges: tuple[np.ndarray, np.ndarray], start: int, ticks: np.ndarray) -> np.ndarray:
    """The analog sensor values (no noise) at ``ticks`` of the gate signals ``edges`` applied from tick
    ``start`` on, with the rotor locked at electrical angle ``theta_e``."""
    p = copy.deepcopy(plant)
    p["sens"]["noise_rms"] = 0.0
    p["mech"]["imposed_speed"] = 1
    p["speed"] = {"t": [0.0], "v": [0.0], "puls_freq": 0.0, "puls_depth": 0.0}
    p["omega_m0"] = 0.0
    p["theta_m0"] = theta_e / p["mech"]["pole_pairs"]
    p["faults"] = []
    e_tick, e_mask = edges
    before = np.searchsorted(e_tick, start, side="right") - 1
    mask0 = int(e_mask[before]) if before >= 0 else 0
    keep = e_tick > start
    edge_ticks = np.concatenate(([0], e_tick[keep] - start))
    masks = np.concatenate(([mask0], e_mask[keep])).astype(np.int32)
    return Plant(p).run(edge_ticks, ticks - start, gates=masks, analog=True)["analog"]


def sample_information(plant: dict, tick_hz: float, edges: tuple[np.ndarray, np.ndarray], sample_ticks: np.ndarray,
                       theta_e: float, t0: float, t1: float) -> float:
    """Fisher information about the electrical angle [1/rad^2] in the samples of ``[t0, t1)`` (module docstring)."""
    ticks = sample_ticks[(sample_ticks >= t0 * tick_hz) & (sample_ticks < t1 * tick_hz)]
    if ticks.size == 0:
        raise ValueError(f"no ADC sample in [{t0:g}, {t1:g}) s")
    start = int(ticks[0] - SETTLE_S * tick_hz)
    if start < 0:
        raise ValueError(f"the stretch must start at least {SETTLE_S:g} s into the run")
    plus = _replay(plant, theta_e + DELTA, edges, start, ticks)
    minus = _replay(plant, theta_e - DELTA, edges, start, ticks)
    slope = (plus[:, PHASES] - minus[:, PHASES]) / (2 * DELTA)
    return float(np.sum(slope * slope)) / noise_variance(plant)


BLOCKS = 20
"""Batch means: the stretch is cut into this many blocks (the correlation time's estimate has a relative
standard deviation of about ``sqrt(2 / (BLOCKS - 1))``, 32 %)."""


def correlation_time(x: np.ndarray, blocks: int = BLOCKS) -> float:
    """Integrated correlation time of ``x`` in samples, ``sum over all lags of rho(k)`` (1 for white noise,
    below 1 for an alternating error such as a bang-bang limit cycle), by batch means: ``B var(block
    means) / var(x)`` over ``blocks`` blocks of ``B`` samples."""
    x = np.asarray(x, dtype=float)
    size = x.size // blocks
    if size < 1:
        raise ValueError(f"{x.size} samples cannot make {blocks} blocks")
    var = float(np.var(x[:size * blocks]))
    if var == 0.0:
        return 1.0
    means = x[:size * blocks].reshape(blocks, size).mean(axis=1)
    return size * float(np.var(means, ddof=1)) / var


@dataclass(frozen=True)
class Bound:
    """The angle noise of one run's stretch against its bound [deg el, ms]."""

    crb_window_deg: float
    """The Cramér-Rao standard deviation of one control window's samples."""
    err_std_deg: float
    """The standard deviation of the estimator's angle error (its mean, the bias, is not part of the bound)."""
    tau_c_ms: float
    """The estimator error's integrated correlation time."""
    efficiency: float
    """``crb_window^2 * window / (err_std^2 * tau_c)``; nan where the error does not vary."""


def bound(plant: dict, tick_hz: float, res, err_deg: np.ndarray, t0: float, t1: float) -> Bound:
    """The :class:`Bound` of run ``res`` (its gate edges, ADC samples, true angle and the angle error
    ``err_deg`` of each window) over ``[t0, t1)``, at the rotor's mean angle there."""
    sel = (res.t >= t0) & (res.t < t1)
    if sel.sum() < 2:
        raise ValueError(f"fewer than two control windows in [{t0:g}, {t1:g}) s")
    theta = res.windows["theta_e"][sel].astype(float) * (2 * math.pi / 2 ** 32)
    theta_e = float(np.angle(np.mean(np.exp(1j * theta))))
    info = sample_information(plant, tick_hz, (res.edges["tick"], res.edges["mask"]), res.samples["tick"],
                              theta_e, t0, t1)
    n_win = int(sel.sum())
    window_s = float(np.median(np.diff(res.t[sel])))
    crb = math.degrees(math.sqrt(n_win / info)) if info > 0 else math.inf     # no information: gates off
    e = err_deg[sel]
    std = float(np.std(e))
    tau = correlation_time(e) * window_s
    return Bound(crb, std, 1e3 * tau, efficiency(crb, window_s, std, tau))


def efficiency(crb_deg: float, window_s: float, std_deg: float, tau_s: float) -> float:
    """``crb^2 T_w / (std^2 tau_c)`` (module docstring); nan for an error that does not vary (a run whose gates
    went off) or whose block means all agree, and for samples without information (``crb_deg`` infinite)."""
    spread = std_deg * std_deg * tau_s
    return crb_deg * crb_deg * window_s / spread if spread > 0 and math.isfinite(crb_deg) else math.nan
