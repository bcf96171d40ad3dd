"""Open-loop PWM with square-wave injection: gate edges in integer clock ticks for the plant.

This is the stimulus of the foundation's main job and benchmark (before the closed loop exists):
an up/down carrier with double update (compare values reloaded at carrier top and bottom), the
square-wave injection on a fixed estimated d-axis, min-max zero-sequence modulation and dead time.
The bit-true modulator of the FPGA (golden model issue) replaces the float duty computation here.

Carrier convention (docs/plant.md): the counter c runs 0 -> half -> 0 over one PWM period
(``half = tick_hz / (2 f_sw)``); cw = 2 c / half - 1, so the carrier bottom (cw = -1) is at the
period start. A leg's ideal switch signal is 1 while ``c < compare``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class PwmConfig:
    """PWM timing.

    Attributes
    ----------
    f_sw : float
        Switching (carrier) frequency [Hz].
    dead_time : float
        Dead time inserted before every turn-on [s].
    tick_hz : float
        Clock [Hz]; the carrier half period must be an integer number of ticks.
    """

    f_sw: float = 5e3
    dead_time: float = 4e-6
    tick_hz: float = 100e6

    @property
    def half(self) -> int:
        """Carrier half period [ticks]."""
        half = self.tick_hz / (2.0 * self.f_sw)
        if half != round(half) or half < 2:
            raise ValueError(f"tick_hz / (2 f_sw) = {half} must be an integer >= 2")
        return int(half)

    @property
    def dead_ticks(self) -> int:
        """Dead time [ticks], rounded to the clock."""
        return int(round(self.dead_time * self.tick_hz))


def injection_compares(cfg: PwmConfig, n_periods: int, v_dc: float, v_h: float, theta_hat: float,
                       v_d: float = 0.0, v_q: float = 0.0) -> np.ndarray:
    """Compare values for every half period: shape (2 * n_periods, 3), integers in [0, half].

    Half period 2k is carrier rising (bottom -> top), 2k+1 falling. The d-axis injection is
    v_dh = V_h * -sign(d cw/dt) (Benevieri et al. 2023, eq. (14)): -V_h while rising, +V_h while falling.
    """
    half = cfg.half
    sign = np.where(np.arange(2 * n_periods) % 2 == 0, -1.0, 1.0)
    vd = v_d + v_h * sign
    c, s = math.cos(theta_hat), math.sin(theta_hat)
    v_al = c * vd - s * v_q
    v_be = s * vd + c * v_q
    v_abc = np.stack([v_al, -0.5 * v_al + math.sqrt(3) / 2 * v_be, -0.5 * v_al - math.sqrt(3) / 2 * v_be], axis=1)
    v_abc -= 0.5 * (v_abc.max(axis=1, keepdims=True) + v_abc.min(axis=1, keepdims=True))  # min-max offset
    duty = np.clip(0.5 + v_abc / v_dc, 0.0, 1.0)
    return np.rint(duty * half).astype(np.int64)


def gate_edges(cfg: PwmConfig, compares: np.ndarray, start_tick: int = 0, initial_levels=None):
    """Gate edges (tick, mask) for the given compare values, with dead time.

    ``initial_levels`` continues a previous call: the ideal switch level of each leg before
    ``start_tick`` (see :func:`final_levels`), its gates settled. ``None``: all switches off before.

    Returns
    -------
    ticks : ndarray of int64, non-decreasing
    masks : ndarray of int32, the full 6-bit gate mask from that tick on (bit 2k high, 2k+1 low switch)
    """
    half, td = cfg.half, cfg.dead_ticks
    n_half = compares.shape[0]
    base = start_tick + np.arange(n_half, dtype=np.int64) * half
    rising = (np.arange(n_half) % 2) == 0
    ev_ticks, ev_bits, ev_vals = [], [], []
    for leg in range(3):
        cmp = compares[:, leg]
        # ideal switch signal: high on [b, b+cmp) in a rising half, on [b+half-cmp, b+half) in a falling
        # half. Two candidate transitions per half: the level at its start and the change inside it.
        start_level = np.where(rising, cmp > 0, cmp == half).astype(np.int64)
        mid = np.where(rising, base + cmp, base + half - cmp)
        mid_level = np.where(rising, 0, 1)
        t_tr = np.stack([base, mid], axis=1).ravel()
        v_tr = np.stack([start_level, mid_level], axis=1).ravel()
        order = np.argsort(t_tr, kind="stable")
        t_tr, v_tr = t_tr[order], v_tr[order]
        last = np.concatenate([t_tr[1:] != t_tr[:-1], [True]])  # at equal ticks the later one wins
        t_tr, v_tr = t_tr[last], v_tr[last]
        before = 0 if initial_levels is None else int(initial_levels[leg])
        changes = v_tr != np.concatenate([[before], v_tr[:-1]])
        t_tr, v_tr = t_tr[changes], v_tr[changes]
        t_next = np.concatenate([t_tr[1:], [np.iinfo(np.int64).max]])
        hi, lo = 2 * leg, 2 * leg + 1
        for val in (0, 1):
            sel = v_tr == val
            off_bit, on_bit = (hi, lo) if val == 0 else (lo, hi)
            ev_ticks.append(t_tr[sel]); ev_bits.append(np.full(sel.sum(), off_bit)); ev_vals.append(np.zeros(sel.sum(), int))
            on_ok = sel & (t_tr + td < t_next)  # a pulse shorter than the dead time never turns on
            ev_ticks.append(t_tr[on_ok] + td); ev_bits.append(np.full(on_ok.sum(), on_bit)); ev_vals.append(np.ones(on_ok.sum(), int))
    ticks = np.concatenate(ev_ticks)
    bits = np.concatenate(ev_bits)
    vals = np.concatenate(ev_vals)
    order = np.lexsort((vals, ticks))  # at equal ticks, turn-offs before turn-ons
    ticks, bits, vals = ticks[order], bits[order], vals[order]
    if initial_levels is None:
        init = np.zeros(6, dtype=np.int32)
    else:
        lv = np.asarray(initial_levels, dtype=np.int32)
        init = np.stack([lv, 1 - lv], axis=1).ravel()  # high switch = level, low switch = not level
    state = np.zeros((len(ticks), 6), dtype=np.int32)
    for b in range(6):
        idx = np.where(bits == b, np.arange(len(ticks)), -1)
        last = np.maximum.accumulate(idx)
        state[:, b] = np.where(last >= 0, vals[np.maximum(last, 0)], init[b])
    masks = (state << np.arange(6)).sum(axis=1).astype(np.int32)
    # one edge per distinct tick: keep the last mask at each tick
    last_at_tick = np.concatenate([ticks[1:] != ticks[:-1], [True]])
    return ticks[last_at_tick], masks[last_at_tick]


def final_levels(cfg: PwmConfig, compares: np.ndarray) -> np.ndarray:
    """Ideal switch level of each leg at the end of the last half period of ``compares``."""
    last = compares[-1]
    rising = (compares.shape[0] - 1) % 2 == 0
    return (last == cfg.half).astype(np.int32) if rising else (last > 0).astype(np.int32)
