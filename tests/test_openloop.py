"""Open-loop PWM stimulus (golden/openloop.py) and the scenario -> plant -> main-job chain."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from golden.openloop import PwmConfig, final_levels, gate_edges, injection_compares
from golden.scenario import load_scenario
from hfi.openloop_run import carrier, envelopes, simulate

ROOT = Path(__file__).resolve().parents[1]


def mask_at(ticks, masks, grid):
    """The gate mask in force at each tick of grid (0 before the first edge)."""
    idx = np.searchsorted(ticks, grid, side="right") - 1
    return np.where(idx >= 0, masks[np.maximum(idx, 0)], 0)


def test_injection_sign_follows_eq14():
    """v_dh = -V_h while the carrier rises (half periods 0, 2, ...), +V_h while it falls: on the
    estimated d-axis at theta_hat = 0 that is leg a below / above the others."""
    cfg = PwmConfig()
    cmp = injection_compares(cfg, 2, 560.0, 100.0, 0.0)
    assert all(cmp[k, 0] < cmp[k, 1] for k in (0, 2))
    assert all(cmp[k, 0] > cmp[k, 1] for k in (1, 3))
    # min-max zero sequence: duties centred on 0.5; line-to-line volts = V_dc * (d_a - d_b)
    v_ab = (cmp[1, 0] - cmp[1, 1]) / cfg.half * 560.0
    assert v_ab == pytest.approx(1.5 * 100.0, abs=560.0 / cfg.half)
    assert cmp[1].max() + cmp[1].min() == pytest.approx(cfg.half, abs=1)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_gate_edges_respect_dead_time_and_duty(seed):
    """Never both switches of a leg on; each turn-on follows the other switch's turn-off by exactly
    the dead time; high time per half period = compare - dead time (pulse shortening)."""
    rng = np.random.default_rng(seed)
    cfg = PwmConfig()
    cmp = rng.integers(600, cfg.half - 600, size=(20, 3))
    ticks, masks = gate_edges(cfg, cmp)
    grid = np.arange(0, 10 * 2 * cfg.half)
    m = mask_at(ticks, masks, grid)
    for leg in range(3):
        hi, lo = (m >> (2 * leg)) & 1, (m >> (2 * leg + 1)) & 1
        assert not np.any(hi & lo)
        on_hi = np.flatnonzero(np.diff(hi) == 1) + 1
        off_lo = np.flatnonzero(np.diff(lo) == -1) + 1
        # every high turn-on after the first (from all switches off) comes one dead time after a low turn-off
        assert len(on_hi) >= 9
        assert set(on_hi[1:] - cfg.dead_ticks) <= set(off_lo)
        # the high switch conducts compare - dead time in every half period with a turn-on inside it
        for k in range(1, 19):
            seg = hi[k * cfg.half:(k + 1) * cfg.half]
            if k % 2 == 0:  # rising half: on from the half start (its turn-on was in the previous half)
                assert seg.sum() == cmp[k, leg]
            else:  # falling half: turns on at half - compare + dead time
                assert seg.sum() == cmp[k, leg] - cfg.dead_ticks


def test_chunked_edges_equal_one_piece():
    cfg = PwmConfig()
    cmp = injection_compares(cfg, 8, 560.0, 100.0, 0.7, v_d=10.0, v_q=40.0)
    t_all, m_all = gate_edges(cfg, cmp)
    t1, m1 = gate_edges(cfg, cmp[:6])
    t2, m2 = gate_edges(cfg, cmp[6:], start_tick=3 * 2 * cfg.half, initial_levels=final_levels(cfg, cmp[:6]))
    grid = np.arange(0, 8 * 2 * cfg.half, 3)
    np.testing.assert_array_equal(mask_at(t_all, m_all, grid),
                                  mask_at(np.concatenate([t1, t2]), np.concatenate([m1, m2]), grid))


def test_short_pulses_are_swallowed():
    """A compare closer to the carrier extremes than the dead time gives no high pulse at all."""
    cfg = PwmConfig()
    cmp = np.tile([100, 5000, 9900], (6, 1))
    ticks, masks = gate_edges(cfg, cmp)
    m = mask_at(ticks, masks, np.arange(2 * cfg.half, 6 * cfg.half))
    assert not np.any(m & 0b00_0001)     # leg a: 2 us high windows < 4 us dead time: never turns on
    assert not np.any(m & 0b10_0000)     # leg c: 2 us low windows: its low switch never turns on
    # leg c high except the 2 us low window and the dead time before its next turn-on: 600 of 20000 ticks
    assert np.mean((m & 0b01_0000) > 0) == pytest.approx(1 - 600 / 20000)


def test_carrier_and_envelope_helpers():
    half = 10000
    ticks = np.array([0, 5000, 10000, 15000, 20000])
    np.testing.assert_allclose(carrier(ticks, half), [-1, 0, 1, 0, -1])
    cw = carrier(np.arange(0, 2 * half, 100), half)
    blocks = np.stack([0.3 * -cw + 0.1, -0.05 * -cw], axis=1)[None]
    np.testing.assert_allclose(envelopes(blocks, cw), [[0.3, -0.05]], atol=1e-12)


def test_scenario_runs_through_the_plant_and_matches_eq18_shape():
    """The default scenario for 10 ms: the q envelope has the sign of sin(2 err) (err = -30 deg) and the
    measured currents follow the true ones to the sensor error."""
    scn = load_scenario(ROOT / "scenarios" / "openloop_injection.toml")
    scn.duration = 0.01
    res = simulate(scn, progress=False)
    assert len(res.pp_hat) == 50
    err = res.truth["theta_e"][0] - scn.injection.theta_hat
    assert math.sin(2 * err) < 0 and np.all(res.env_hat[5:, 1] < 0)
    assert np.all(res.env_hat[5:, 0] > 0.5)
    rms = np.sqrt(np.mean((res.i_meas - res.truth["i_abc"]) ** 2, axis=0))
    assert np.all(rms < 0.06) and np.all(rms > 0.015)


def test_main_job_writes_outputs(tmp_path):
    scn_text = (ROOT / "scenarios" / "openloop_injection.toml").read_text().replace('duration = "50 ms"',
                                                                                     'duration = "4 ms"')
    scn_file = tmp_path / "short.toml"
    scn_file.write_text(scn_text)
    proc = subprocess.run([sys.executable, str(ROOT / "scripts" / "run.py"), str(scn_file), "--out",
                           str(tmp_path / "out"), "--quiet"], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    metrics = json.loads((tmp_path / "out" / "metrics.json").read_text())
    assert metrics["samples"] == 4000
    for name in ("trace.npz", "phase_currents.png", "dq_estimated.png", "hf_envelopes.png"):
        assert (tmp_path / "out" / name).stat().st_size > 1000


def test_main_job_reports_bad_scenario_without_traceback(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[scenario]\nname = "x"\nduration = "1 ms"\n[pwm]\ndead_time = "150 us"\n')
    proc = subprocess.run([sys.executable, str(ROOT / "scripts" / "run.py"), str(bad), "--quiet"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 1
    assert "Traceback" not in proc.stderr and "dead_time" in proc.stderr
