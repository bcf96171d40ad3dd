"""metrics.json of a closed-loop run (hfi/report.py, docs/metrics.md) on a synthetic trace whose
numbers are worked out by hand below."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from golden.closedloop import WINDOW_FIELDS, ClosedLoopResult
from golden.control_config import Scales
from golden.firmware.supervisor import MODE_NAMES
from hfi import report

RPM = 2 * math.pi / 60
TURN = 2**32
MODE = {name: k for k, name in enumerate(MODE_NAMES)}
LOAD = [(0.0, 0.0), (1.0, 0.0), (1.0, 2.0), (1.2, 2.0), (1.4, 1.0)]
"""Load torque: a step at 1.0 s, a ramp 1.2 -> 1.4 s: changes end at 1.0 s and 1.4 s."""


def synthetic() -> tuple[SimpleNamespace, ClosedLoopResult]:
    """2000 windows of 1 ms (t = 1 ms .. 2 s); one speed LSB = 1 r/min (w_lsb = 2 pi/60, one pole pair).

    mode: RUN from 0.1 s; reference: 0 r/min to 0.5 s, 50 to 0.6 s, 100 to 2 s;
    true angle: 10 deg to 0.449 s, -30 deg to 1.849 s, 20 deg to 2 s; theta_hat 0: the angle error
    (golden.closedloop, the true angle in the middle of the window) is that, and the midpoints -10 deg
    at 0.450 s and -5 deg at 1.850 s;
    measured speed: 5 r/min before 0.45 s, -5 to 0.6 s, 100 to 1.9 s, 104 to 2 s;
    est: 1 (high-speed slot) from 1.2 s to 1.8 s (windows ending 1.200 .. 1.799).
    """
    ms = np.arange(1, 2001)
    w = {name: np.zeros(len(ms), dtype=np.int64) for name in WINDOW_FIELDS}
    w["tick"] = ms * 100_000
    w["mode"][:] = np.where(ms >= 100, MODE["RUN"], MODE["CONVERGE"])
    w["speed_ref"][:] = np.select([ms <= 500, ms <= 600], [0, 50], 100)
    w["omega_f"][:] = np.where(ms <= 600, 0, 98)
    err_deg = np.select([ms < 450, ms < 1850], [10.0, -30.0], 20.0)
    w["theta_e"][:] = np.round(err_deg / 360 * TURN).astype(np.int64) % TURN
    w["est"][:] = (ms >= 1200) & (ms < 1800)
    windows = {k: v.astype(float) if k in ("omega_m", "load_torque", "torque", "i_d_true", "i_q_true") else v
               for k, v in w.items()}
    windows["omega_m"] = np.select([ms < 450, ms <= 600, ms < 1900], [5.0, -5.0, 100.0], 104.0) * RPM
    res = ClosedLoopResult(windows=windows, samples={"tick": np.arange(10)}, edges={}, writes={}, hw=None,
                           scales=Scales(i_lsb=1.0, v_lsb=1.0, w_lsb=RPM, f_sw=1000.0, pole_pairs=1),
                           tick_hz=100e6, flipped=0, wall_s=4.0)
    w["vdc"][:] = np.where(ms < 1000, 2048, 1536)                   # 560 V, then 420 V (1120 V over 12 bits)
    windows["vdc"] = w["vdc"]
    sc = SimpleNamespace(name="synthetic", faults=(), plant={"mech": {"imposed_speed": 0},
                                                             "sens": {"vdc_range": 1120.0, "adc_bits": 12},
                                                  "load": {"t": [p[0] for p in LOAD], "v": [p[1] for p in LOAD]}})
    return sc, res


def test_profile_changes_are_the_ends_of_steps_and_ramps():
    assert report.profile_changes([p[0] for p in LOAD], [p[1] for p in LOAD]) == [1.0, 1.4]
    assert report.profile_changes([], []) == []
    assert report.profile_changes([0.0, 0.3, 0.3], [0.0, 0.0, 0.0]) == []


def test_segments_follow_the_settling_rule():
    sc, res = synthetic()
    m = report.metrics_of(sc, res)
    assert m["run_from_s"] == 0.1
    # plateau 0 r/min, windows 1..500 ms: settled from max(0.001, RUN 0.1) + 0.3 = 0.4 s to 0.5 s;
    # 50 windows (400..449 ms) at +10 deg / 5 r/min, 51 (450..500 ms) at -5 r/min, -10 deg then -30 deg
    # plateau 50 r/min (501..600 ms): settled part would start at 0.801 s, after its end: no segment
    # plateau 100 r/min (601..2000 ms): load changes at 1.0 and 1.4 s -> settled from 1.7 s to 2.0 s;
    # 150 windows (1700..1849) at -30 deg, 1850 at -5 deg, 150 (1851..2000) at +20 deg;
    # 200 at 100 r/min, 101 at 104; three quarters into the window (the carrier bottom) the transition
    # windows read -20 deg (450 ms) and +7.5 deg (1850 ms): the peaks stay 30 deg
    bottom = res.angle_error_deg(quarters=3)
    assert (bottom[449], bottom[1849]) == (pytest.approx(-20.0, abs=1e-6), pytest.approx(7.5, abs=1e-6))
    assert m["angle_error_at_bottom"]["peak_deg"] == 30.0
    assert m["segments"] == [
        {"plateau": [0.001, 0.5], "t": [0.4, 0.5], "speed_ref_rpm": 0.0,
         "speed_mean_rpm": round((50 * 5 - 51 * 5) / 101, 2), "speed_ripple_rpm": 5.0,
         "err_rms_deg": round(math.sqrt((50 * 100 + 100 + 50 * 900) / 101), 2), "err_peak_deg": 30.0,
         "err_peak_bottom_deg": 30.0, "estimators": ["low"]},
        {"plateau": [0.601, 2.0], "t": [1.7, 2.0], "speed_ref_rpm": 100.0,
         "speed_mean_rpm": round((200 * 100 + 101 * 104) / 301, 2), "speed_ripple_rpm": 2.0,
         "err_rms_deg": round(math.sqrt((150 * 900 + 25 + 150 * 400) / 301), 2), "err_peak_deg": 30.0,
         "err_peak_bottom_deg": 30.0, "estimators": ["low", "high"]},
    ]


def test_estimator_switches():
    sc, res = synthetic()
    m = report.metrics_of(sc, res)
    assert m["estimator_switches"] == 2
    assert m["estimator_switch_events"] == [
        {"t_s": 1.2, "to": "high", "speed_rpm": 100.0, "speed_est_rpm": 98.0},
        {"t_s": 1.8, "to": "low", "speed_rpm": 100.0, "speed_est_rpm": 98.0}]
    assert report.est_spans(res) == [(pytest.approx(1.199), 1.799)]


def test_locked_and_angle_error_after_start():
    sc, res = synthetic()
    m = report.metrics_of(sc, res)
    assert m["locked"] is True                                      # 30 deg < 60 deg
    assert m["angle_error_after_start"]["peak_deg"] == 30.0
    assert m["realtime_factor"] == 0.5 and m["backend"] == "golden"
    res.windows["theta_e"][1500:1502] = round(61 / 360 * TURN)        # window 1501: 61 deg
    assert report.metrics_of(sc, res)["locked"] is False


def test_angle_deg_wraps():
    a = np.array([0, TURN - 2**30, 2**31, TURN + 2**30], dtype=np.int64)
    assert report.angle_deg(a).tolist() == [0.0, 270.0, 180.0, 90.0]


def test_dc_link_as_measured():
    """VDC codes in volts of the channel (1120 V / 2^12 per code): 999 windows at 560 V, 1001 at 420 V."""
    sc, res = synthetic()
    assert report.metrics_of(sc, res)["dc_link"] == {"min_v": 420.0, "mean_v": round((999 * 560 + 1001 * 420) / 2000, 2),
                                                     "max_v": 560.0}
    sc.plant["sens"]["vdc_range"] = 0.0
    assert report.metrics_of(sc, res)["dc_link"] is None
