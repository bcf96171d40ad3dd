"""Copper loss and audible torque of a run, from the plant's running integrals (docs/compare.md).

The trace holds, at every window end, the plant's integrals since t = 0 of the copper loss (``e_cu``), of
i_d and i_q (``q_d``, ``q_q``), of the torque (``t_int``) and of its square (``t2_int``) (golden.closedloop
``truth_columns``). Their differences over a window are exact window means, whatever the injection or
the PWM do inside the window, where a sample at the window end is not: the 002 square wave puts a
triangle extreme of its HF current on every window end.

* **Copper loss** over a stretch of windows: ``(E_cu(end) - E_cu(start)) / T``. Its **ripple part** is
  what is left after the loss of the stretch's mean rotor-frame current, ``1.5 R_s |mean i_dq|^2``: the
  injection, the PWM or switching-state ripple, and the control loops' oscillations. In steady state the
  fundamental current is constant in the rotor frame, so the ripple part holds everything else.
* **Audible torque**, the acoustic proxy: the A-weighted RMS of the torque's variation. Below the window
  rate it is the spectrum of the window means (a Hann-windowed periodogram, each bin weighted by A(f),
  IEC 61672-1, from 20 Hz); inside the windows it is the torque's variance within each window, weighted
  by A at the window rate (the lowest frequency a variation inside a window can have, and the 002
  injection's frequency). A proxy, not a sound level: the motors' structures are not modelled.
"""

from __future__ import annotations

import math

import numpy as np

AUDIBLE_FROM_HZ = 20.0
"""Lower edge of the audible band [Hz]."""


def a_weighting(f: np.ndarray) -> np.ndarray:
    """IEC 61672-1 A-weighting as a linear amplitude factor (1 at 1 kHz)."""
    f2 = np.asarray(f, dtype=float) ** 2
    ra = 12194.0 ** 2 * f2 ** 2 / ((f2 + 20.6 ** 2) * np.sqrt((f2 + 107.7 ** 2) * (f2 + 737.9 ** 2)) * (f2 + 12194.0 ** 2))
    return ra * 10 ** (2.0 / 20)


def _stretch(windows: dict, t: np.ndarray, sel: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Boundary indices (the window before the first selected one, then every selected one) and the
    windows' durations [s]."""
    idx = np.flatnonzero(sel)
    if idx.size and idx[0] == 0:
        idx = idx[1:]
    if idx.size == 0:
        raise ValueError("the stretch holds no window after the first one of the run")
    bounds = np.concatenate(([idx[0] - 1], idx))
    return bounds, np.diff(t[bounds])


def copper_loss(windows: dict, t: np.ndarray, sel: np.ndarray, R_s: float) -> tuple[float, float]:
    """(total, ripple part) of the copper loss [W] over the selected windows (module docstring)."""
    b, dt = _stretch(windows, t, sel)
    span = float(np.sum(dt))
    total = (windows["e_cu"][b[-1]] - windows["e_cu"][b[0]]) / span
    i_d = (windows["q_d"][b[-1]] - windows["q_d"][b[0]]) / span
    i_q = (windows["q_q"][b[-1]] - windows["q_q"][b[0]]) / span
    return float(total), float(total - 1.5 * R_s * (i_d * i_d + i_q * i_q))


def audible_torque(windows: dict, t: np.ndarray, sel: np.ndarray) -> float:
    """A-weighted RMS of the torque's variation over the selected windows [N*m] (module docstring)."""
    b, dt = _stretch(windows, t, sel)
    mean = np.diff(windows["t_int"][b]) / dt
    within = np.maximum(np.diff(windows["t2_int"][b]) / dt - mean * mean, 0.0)
    step = float(np.median(dt))
    power = float(np.mean(within)) * float(a_weighting(1.0 / step)) ** 2
    n = mean.size
    if n >= 2:
        hann = np.hanning(n)
        spec = np.abs(np.fft.rfft((mean - np.mean(mean)) * hann)) ** 2 / (n * n * np.mean(hann ** 2))
        spec[1:(n + 1) // 2] *= 2.0          # one-sided: every bin but dc and (n even) Nyquist twice
        f = np.fft.rfftfreq(n, step)
        band = f >= AUDIBLE_FROM_HZ
        power += float(np.sum(spec[band] * a_weighting(f[band]) ** 2))
    return math.sqrt(power)
