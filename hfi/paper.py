"""The paper's experiments (Benevieri et al. 2023, Sec. IV) on the golden closed loop, and their metrics.

Each experiment is the default scenario (``scenarios/fullload_start.toml``: Table I motor, the assumed
002 inverter and sensors, Table II control parameters) with a few keys changed, so every figure group
runs on the same hardware model. :func:`experiment` builds the scenario, :func:`evaluate_*` reduce the
traces to the numbers printed next to the paper's in ``out/paper/metrics.json``.

Angle error convention (docs/spec.md 5.2): err = θ − θ̂ (electrical); γ = +K·sin(2·err).
"""

from __future__ import annotations

import copy
import math
import tomllib
from pathlib import Path

import numpy as np

from golden.closedloop import ClosedLoop, ClosedLoopResult
from golden.scenario import Scenario, parse_scenario

ROOT = Path(__file__).resolve().parents[1]
BASE = ROOT / "scenarios" / "fullload_start.toml"
RPM = 2 * math.pi / 60


def base_data() -> dict:
    """The default scenario as a TOML tree."""
    with open(BASE, "rb") as fh:
        return tomllib.load(fh)


def _merge(tree: dict, changes: dict) -> dict:
    """Merge ``changes`` into ``tree``; a value of None removes the key."""
    for key, value in changes.items():
        if value is None:
            tree.pop(key, None)
        elif isinstance(value, dict) and isinstance(tree.get(key), dict):
            _merge(tree[key], value)
        else:
            tree[key] = value
    return tree


def experiment(name: str, changes: dict) -> Scenario:
    """The default scenario with ``changes`` merged in (nested dicts), named ``name``."""
    data = _merge(copy.deepcopy(base_data()), changes)
    data["scenario"]["name"] = name
    data.setdefault("output", {})["dir"] = f"out/paper/{name}"
    return parse_scenario(data, source=f"paper:{name}")


def run(sc: Scenario, progress: bool = False) -> ClosedLoopResult:
    return ClosedLoop(sc).run(progress=progress)


# ---- scenario builders --------------------------------------------------------------------------
def gamma_sweep(adc_mode: str, duration: float = 1.0, speed_rpm: float = 30.0, seed: int = 1) -> Scenario:
    """Figs. 6-9: fixed estimated angle θ̂ = 0, rotor turned by the load machine at ``speed_rpm``;
    current controllers running with zero references (they keep the back-EMF of the turning rotor from
    driving current)."""
    return experiment(f"gamma_{adc_mode.lower()}", {
        "scenario": {"duration": duration, "seed": seed},
        "control": {"mode": "fixed_angle", "theta_hat": 0.0, "adc_mode": adc_mode},
        "load": {"mode": "speed", "speed": [[0.0, f"{speed_rpm} rpm"]], "torque": None},
        "reference": {"speed": []},
    })


def speed_steps(name: str, load_nm: float, t_load: float = 0.3, t50: float = 0.8, t250: float = 1.6,
                duration: float = 2.4, **extra) -> Scenario:
    """Figs. 12-17: start-up, optional load step at standstill, 0 -> 50 -> 250 r/min (0.1 s ramps)."""
    changes = {
        "scenario": {"duration": duration},
        "load": {"torque": [[0.0, 0.0], [t_load, 0.0], [t_load, load_nm]]},
        "reference": {"speed": [[0.0, "0 rpm"], [t50, "0 rpm"], [t50 + 0.1, "50 rpm"], [t250, "50 rpm"],
                                [t250 + 0.1, "250 rpm"]]},
    }
    return experiment(name, _merge(changes, extra))


def load_steps(speed_rpm: float, load_nm: float = 2.0, duration: float = 2.0, t_on: float = 0.8,
               t_off: float = 1.4, rise: float = 0.0, **extra) -> Scenario:
    """Figs. 18-23 (and 33-36): at ``speed_rpm`` apply full load at ``t_on`` and release it at ``t_off``,
    each within ``rise`` seconds (0: a step)."""
    return experiment(f"load_steps_{int(speed_rpm)}rpm", _merge({
        "scenario": {"duration": duration},
        "load": {"torque": [[0.0, 0.0], [t_on, 0.0], [t_on + rise, load_nm], [t_off, load_nm],
                            [t_off + rise, 0.0]]},
        "reference": {"speed": [[0.0, "0 rpm"], [0.2, "0 rpm"], [0.4, f"{speed_rpm} rpm"]]},
    }, extra))


def ds_switch(t_switch: float = 1.0, duration: float = 1.5, **extra) -> Scenario:
    """Fig. 11: no-load start to 250 r/min with OS, then the ADC switched to DS at ``t_switch``."""
    return experiment("ds_switch", _merge({
        "scenario": {"duration": duration},
        "load": {"torque": []},
        "reference": {"speed": [[0.0, "0 rpm"], [0.2, "0 rpm"], [0.5, "250 rpm"]]},
        "control": {"switch_to_ds_at": t_switch},
    }, extra))


def sine_reference(load_nm: float, freq: float = 5.0, mean_rpm: float = 100.0, amp_rpm: float = 50.0,
                   t_start: float = 0.6, duration: float = 2.0) -> Scenario:
    """Figs. 24-25: sinusoidal speed reference (``freq``) around ``mean_rpm``, with or without load."""
    t = np.arange(t_start, duration + 1e-9, 1.0 / (freq * 40))
    points = [[0.0, "0 rpm"], [0.2, "0 rpm"], [0.4, f"{mean_rpm} rpm"]]
    points += [[float(x), f"{mean_rpm + amp_rpm * math.sin(2 * math.pi * freq * (x - t_start)):.6f} rpm"] for x in t]
    torque = [[0.0, 0.0], [0.1, 0.0], [0.1, load_nm]] if load_nm else []
    return experiment(f"sine_{int(load_nm)}nm", {
        "scenario": {"duration": duration},
        "load": {"torque": torque},
        "reference": {"speed": points},
    })


def random_start(theta_m_deg: float, seed: int, load_nm: float = 2.0, duration: float = 0.6) -> Scenario:
    """Start from a given rotor angle: polarity detection, full load once the speed loop holds the
    rotor (0.2 s; the load machine cannot be allowed to spin a rotor nobody holds), then 50 r/min."""
    return experiment(f"start_{theta_m_deg:.0f}deg", {
        "scenario": {"duration": duration, "seed": seed},
        "load": {"torque": [[0.0, 0.0], [0.2, 0.0], [0.2, load_nm]],
                 "initial": {"theta_m": f"{theta_m_deg} deg", "omega_m": "0 rpm"}},
        "reference": {"speed": [[0.0, "0 rpm"], [0.25, "0 rpm"], [0.35, "50 rpm"]]},
    })


# ---- metrics ------------------------------------------------------------------------------------
def gamma_fit(res: ClosedLoopResult, skip: float = 0.02) -> dict:
    """Fit γ = K·sin(2·(err − δ)) by least squares over the windows after ``skip`` seconds.

    Returns K, δ [deg], R², and the zero-crossing spread: RMS distance [deg] of the sign changes of γ
    from the nearest ideal zero (multiples of 90°).
    """
    sel = res.t >= skip
    err = np.radians(res.angle_error_deg()[sel])
    g = res.windows["gamma"][sel].astype(float)
    a = np.stack([np.sin(2 * err), np.cos(2 * err)], axis=1)
    (c_s, c_c), *_ = np.linalg.lstsq(a, g, rcond=None)
    k = math.hypot(c_s, c_c)
    delta = -0.5 * math.atan2(c_c, c_s)          # K sin(2 err - 2 delta) = K cos(2δ) sin(2err) - K sin(2δ) cos(2err)
    fit = a @ np.array([c_s, c_c])
    r2 = 1.0 - float(np.sum((g - fit) ** 2) / np.sum((g - g.mean()) ** 2))
    flips = np.nonzero(np.sign(g[1:]) != np.sign(g[:-1]))[0]
    e_deg = np.degrees(0.5 * (err[flips] + err[flips + 1]))
    dist = (e_deg + 45.0) % 90.0 - 45.0
    spread = float(np.sqrt(np.mean(dist ** 2))) if len(dist) else 0.0
    return {"K": round(k, 1), "delta_deg": round(math.degrees(delta), 2), "r2": round(r2, 4),
            "zero_cross_spread_deg": round(spread, 2), "windows": int(sel.sum())}


def segment_stats(res: ClosedLoopResult, t0: float, t1: float) -> dict:
    """Angle error RMS / peak [deg el.] and measured speed mean / ripple [r/min] over [t0, t1)."""
    sel = (res.t >= t0) & (res.t < t1)
    err = res.angle_error_deg()[sel]
    rpm = res.windows["omega_m"][sel] / RPM
    return {"t": [t0, t1], "err_rms_deg": round(float(np.sqrt(np.mean(err ** 2))), 2),
            "err_peak_deg": round(float(np.max(np.abs(err))), 2),
            "speed_mean_rpm": round(float(np.mean(rpm)), 2),
            "speed_ripple_rpm": round(float(0.5 * (np.max(rpm) - np.min(rpm))), 2)}


def locked(res: ClosedLoopResult, t0: float, limit_deg: float = 60.0) -> bool:
    """Never more than ``limit_deg`` of angle error after ``t0`` (the estimator stays on its axis)."""
    return bool(np.all(np.abs(res.angle_error_deg()[res.t >= t0]) < limit_deg))


def sine_gain(res: ClosedLoopResult, freq: float, t0: float) -> dict:
    """Amplitude ratio and phase of the measured speed to the reference at ``freq`` (LS sine fit)."""
    sel = res.t >= t0
    t = res.t[sel]
    basis = np.stack([np.sin(2 * math.pi * freq * t), np.cos(2 * math.pi * freq * t), np.ones_like(t)], axis=1)
    ref = res.windows["speed_ref"][sel] / res.scales.speed_mech(RPM)
    meas = res.windows["omega_m"][sel] / RPM
    (rs, rc, _), *_ = np.linalg.lstsq(basis, ref, rcond=None)
    (ms, mc, _), *_ = np.linalg.lstsq(basis, meas, rcond=None)
    gain = math.hypot(ms, mc) / math.hypot(rs, rc)
    phase = math.degrees(math.atan2(mc, ms) - math.atan2(rc, rs))
    return {"freq_hz": freq, "gain": round(gain, 3), "gain_db": round(20 * math.log10(gain), 2),
            "phase_deg": round((phase + 180) % 360 - 180, 1)}
