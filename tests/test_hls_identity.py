"""Identity of the ``hls`` backend with the ``golden`` backend (issue: HLS-style C++ of the DSP path).

The ``hls`` backend (:mod:`hfi.hls_backend`) runs the HLS kernels of ``hls/`` (native C simulation),
the host build of the firmware and the C plant; the ``golden`` backend runs the Python bit-true model
with the same plant library. The default scenario (``scenarios/fullload_start.toml``, start-up from
standstill under 2 N·m through both speed steps), full length and same seed, must give identical
per-window columns (window results, estimator and controller state, compares, plant truth), register
writes, ADC samples and gate edges. Shorter runs cover the configurations the default scenario does not
use: OS_BLANK sampling, DS sampling, a host-side switch to DS during the run, no dead-time compensation,
the rotating injection (CTRL.INJ_ROT); the hand-over scenario (scenarios/handover_short.toml) runs both
estimator methods in charge in turn; the 001 drive (scenarios/xue2022_noload.toml, full length) runs the
period square wave (CTRL.INJ_PER) with the differencing and CIC block (hfi_diff_cic) and its estimator;
the 003 drive (scenarios/varatharajan2020_torquestep.toml, 1 s) runs the direct-vector mode (CTRL.DIRECT:
the FCS-MPC state at the carrier top, VECTOR and TOP_I).

Every column compared is one the hls backend *produces*, none is copied from the scenario into the
result: ``speed_ref`` is the value the native loop passed to ``fw_step`` for that window, ``adc_mode``
the mode its sampling used (so the host-side switch to DS is checked), the firmware state columns are
read from the host firmware's state (``FW_TRACE_COLUMNS``, the same table as the rtl trace).
"""

from __future__ import annotations

import dataclasses
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from golden.closedloop import OUTPUT_FIELDS, WINDOW_FIELDS, ClosedLoop
from golden.fpga.rot_injection import inj_step
from golden.scenario import load_scenario
from hfi.hls_backend import HlsBackendError, HlsClosedLoop

ROOT = Path(__file__).resolve().parents[1]


def _default():
    return load_scenario(ROOT / "scenarios" / "fullload_start.toml")


def _first_difference(a: np.ndarray, b: np.ndarray) -> str:
    if a.shape != b.shape:
        return f"shapes {a.shape} vs {b.shape}"
    i = int(np.flatnonzero(a != b)[0])
    return f"index {i}: golden {a[i]!r}, hls {b[i]!r}"


def _assert_identical(gold, hls) -> None:
    bad = {k: _first_difference(gold.windows[k], hls.windows[k]) for k in WINDOW_FIELDS
           if not np.array_equal(gold.windows[k], hls.windows[k])}
    assert not bad, f"per-window columns differ: {bad}"
    bad = {k: _first_difference(gold.writes[k], hls.writes[k]) for k in OUTPUT_FIELDS
           if not np.array_equal(gold.writes[k], hls.writes[k])}
    assert not bad, f"firmware register writes differ: {bad}"
    for group in ("samples", "edges"):
        g, h = getattr(gold, group), getattr(hls, group)
        assert set(g) == set(h)
        for k in g:
            assert np.array_equal(g[k], h[k]), f"{group}.{k}: {_first_difference(g[k], h[k])}"
    assert hls.flipped == gold.flipped


@pytest.fixture(scope="module")
def default_runs():
    sc = _default()
    return sc, ClosedLoop(sc).run(progress=False), HlsClosedLoop(sc).run(progress=False)


@pytest.mark.xdist_group("hls_default_runs")
def test_default_scenario_identical(default_runs):
    sc, gold, hls = default_runs
    assert len(hls.t) == int((round(sc.duration * sc.pwm.tick_hz) - 5000) // 20000) == 11999
    _assert_identical(gold, hls)
    assert hls.backend == "hls"


@pytest.mark.xdist_group("hls_default_runs")
def test_default_scenario_covers_start_up_and_speed_control(default_runs):
    """The compared run visits CONVERGE, both polarity pulses, RELAX and RUN, and has millions of samples."""
    _, _, hls = default_runs
    assert {0, 1, 2, 3, 4} <= set(np.unique(hls.windows["mode"]).tolist())
    assert len(hls.samples["tick"]) == 200 * len(hls.t) and len(hls.edges["tick"]) > 100_000


@pytest.mark.parametrize("change", [
    {"adc_mode": "OS_BLANK"},
    {"adc_mode": "OS_BLANK", "dead_time_comp": "off"},
    {"adc_mode": "DS"},
    {"switch_to_ds_at": 0.1},
], ids=["os_blank", "os_blank_no_dtc", "ds", "switch_to_ds"])
def test_other_configurations_identical(change):
    sc = _default()
    sc = dataclasses.replace(sc, duration=0.2, control=dataclasses.replace(sc.control, **change))
    gold, hls = ClosedLoop(sc).run(progress=False), HlsClosedLoop(sc).run(progress=False)
    _assert_identical(gold, hls)
    if change.get("adc_mode") == "OS_BLANK":     # the blanking acted
        assert hls.windows["n_samples"].min() < 200


def test_hand_over_scenario_identical():
    """scenarios/handover_short.toml, full length: both estimator methods in charge in turn, identical."""
    sc = load_scenario(ROOT / "scenarios" / "handover_short.toml")
    gold, hls = ClosedLoop(sc).run(progress=False), HlsClosedLoop(sc).run(progress=False)
    _assert_identical(gold, hls)
    assert np.diff(hls.windows["est"]).tolist().count(1) == 1 and np.diff(hls.windows["est"]).tolist().count(-1) == 1


def test_flying_start_identical():
    """scenarios/flying_start.toml, full length: switched on with the motor coasting at 800 r/min, CATCH on the rotor
    flux observer, RUN on it, the hand-back to the HF estimator; identical."""
    sc = load_scenario(ROOT / "scenarios" / "flying_start.toml")
    gold, hls = ClosedLoop(sc).run(progress=False), HlsClosedLoop(sc).run(progress=False)
    _assert_identical(gold, hls)
    assert hls.windows["est"][0] == 1 and np.diff(hls.windows["est"]).tolist().count(-1) == 1


def test_a_slip_check_trip_is_identical():
    """The fault matrix's 30 % gain error at 250 r/min without load (hfi.faults), until 0.82 s: the HF estimator
    slips away from the rotor flux observer beside it and the slip check trips (lock_loss) 4.65 ms after the onset;
    the C hand_over and fw_slip_check on the hls backend, identical in every window to the golden model."""
    from golden.firmware.protection import FAULT_LOCK_LOSS
    from hfi import faults

    sc = faults.scenario(faults.FAULTS["sensor gain x0.7 (a)"], 250.0, False, 0.82)
    gold, hls = ClosedLoop(sc).run(progress=False), HlsClosedLoop(sc).run(progress=False)
    _assert_identical(gold, hls)
    fault = hls.windows["fault"]
    assert fault[-1] == FAULT_LOCK_LOSS and hls.t[np.flatnonzero(fault)[0]] == pytest.approx(faults.ONSET_S + 4.65e-3)


def test_tap2023_flying_start_identical():
    """The 000 drive switched on at 800 r/min (scenarios/tap2023_flying.toml), its first 0.2 s: CATCH and braking
    on the rotor flux observer with the active flux's magnitude, the hand-back to the rotating injection."""
    sc = dataclasses.replace(load_scenario(ROOT / "scenarios" / "tap2023_flying.toml"), duration=0.2)
    _assert_identical(ClosedLoop(sc).run(progress=False), HlsClosedLoop(sc).run(progress=False))


def test_tap2023_identical():
    """The 000 drive (scenarios/tap2023_fullload.toml) at its 10 kHz for 0.3 s: pilot polarity, the
    rotating injection, the notch, MTPA and the EEMF observer in parallel, identical to golden."""
    sc = dataclasses.replace(load_scenario(ROOT / "scenarios" / "tap2023_fullload.toml"), duration=0.3)
    gold, hls = ClosedLoop(sc).run(progress=False), HlsClosedLoop(sc).run(progress=False)
    assert {0, 1, 2, 3, 4} <= set(np.unique(hls.windows["mode"]).tolist())
    for k in gold.windows:
        assert np.array_equal(gold.windows[k], hls.windows[k]), k


def test_rotating_injection_identical():
    """CTRL.INJ_ROT = 1 (docs/spec.md 3.5): the phase accumulator, its sin/cos (hfi_cordic_sincos<32, 16>)
    and the modulator's rotating term of the hls backend give the golden loop's compares, gate edges,
    samples and firmware state; the step wraps the u32 accumulator every few periods."""
    sc = dataclasses.replace(_default(), duration=0.1)
    gold_loop, hls_loop = ClosedLoop(sc), HlsClosedLoop(sc)
    f_sw = sc.pwm.tick_hz / (2 * gold_loop.hw.pwm_half)
    hw = dataclasses.replace(gold_loop.hw, inj_rot=1, inj_step=inj_step(-0.37 * f_sw, f_sw))
    assert hw.inj_step > 1 << 31 and hw.inj_step & 0xFFFF          # backwards, not a round number
    gold_loop.hw = hls_loop.hw = hw
    gold, hls = gold_loop.run(progress=False), hls_loop.run(progress=False)
    _assert_identical(gold, hls)
    assert gold.writes["v_h"].max() > 0                                # the rotating term acted


def test_xue2022_identical():
    """The 001 drive (scenarios/xue2022_noload.toml, 1 kHz) full length (3 s: converge, pilot polarity,
    100 then 300 r/min): the period square wave's sign in the compares, the carrier-bottom sample through
    hfi_adc_scale, hfi_clarke and hfi_diff_cic (CIC_QA/QB to the firmware, ENV_A/B recorded), the sqw_cic
    observer of the host firmware: every column identical to golden."""
    sc = load_scenario(ROOT / "scenarios" / "xue2022_noload.toml")
    gold, hls = ClosedLoop(sc).run(progress=False), HlsClosedLoop(sc).run(progress=False)
    _assert_identical(gold, hls)
    assert hls.hw.inj_per == 1 and {0, 1, 2, 3, 4} <= set(np.unique(hls.windows["mode"]).tolist())
    for k in ("cic_qa", "cic_qb", "env_a", "env_b"):
        assert np.count_nonzero(hls.windows[k]) > len(hls.t) // 2 and len(np.unique(hls.windows[k])) > 100, k


def test_period_square_wave_other_comb_delays_identical():
    """CIC_M other than the scenario's 2: 1, 5, the largest 16 and 200 (used as 16), and 0 (used as 1),
    on the default scenario's 5 kHz loop for 0.1 s with the period square wave forced on."""
    for m in (0, 1, 5, 16, 200):
        sc = dataclasses.replace(_default(), duration=0.1)
        gold_loop, hls_loop = ClosedLoop(sc), HlsClosedLoop(sc)
        gold_loop.hw = hls_loop.hw = dataclasses.replace(gold_loop.hw, inj_per=1, cic_m=m)
        gold, hls = gold_loop.run(progress=False), hls_loop.run(progress=False)
        _assert_identical(gold, hls)
        assert np.count_nonzero(hls.windows["cic_qa"]) > 0, m


def test_varatharajan2020_direct_vector_identical():
    """The 003 drive (scenarios/varatharajan2020_torquestep.toml: 10 kHz FCS-MPC, CTRL.DIRECT = 1, the
    hfo_proj estimator, DS sampling) for 1 s, through the 0 -> 2 p.u. load step at 0.8 s: the state
    chosen at each carrier top (hfi_modulator_direct on the active V_D, V_Q, SIN, COS, FCS_A, FCS_CTRL and
    the state applied), its compares 0/H at the top and the bottom without dead-time compensation, VECTOR
    and TOP_I (the carrier-top sample's Clarke currents, spec 3.11) to the host firmware: every column,
    write, sample and edge identical to golden."""
    from hfi.backends import get

    sc = dataclasses.replace(load_scenario(ROOT / "scenarios" / "varatharajan2020_torquestep.toml"), duration=1.0)
    gold = ClosedLoop(sc).run(progress=False)
    hls = get("hls").run(sc, progress=False)
    assert hls.hw.direct == 1 and hls.backend == "hls"
    _assert_identical(gold, hls)
    w = hls.windows
    assert set(np.unique(w["vector"]).tolist()) == set(range(8))              # every state, both zeros
    assert np.count_nonzero(w["top_ia"]) > len(hls.t) // 2 and np.count_nonzero(w["top_ib"]) > len(hls.t) // 2
    high = [w[f"cmp_top_{x}"] == hls.hw.pwm_half for x in "abc"]          # compares 0 or H, bottom = top
    for x, hi in zip("abc", high):
        assert np.all((w[f"cmp_top_{x}"] == 0) | hi) and np.array_equal(w[f"cmp_top_{x}"], w[f"cmp_bot_{x}"]), x
    state = sum(hi.astype(np.int64) << i for i, hi in enumerate(high))
    assert np.array_equal(state, w["vector"])                                  # VECTOR = the state applied
    assert {0, 3, 4} <= set(np.unique(w["mode"]).tolist())
    assert w["load_torque"][-1] > 14.0                                          # the load step is in the run


def test_square_wave_on_the_syrm_identical():
    """The 002 method on the 003 SyRM (sweeps/cross_002_on_003.toml at standstill, the rated-load point with the
    cross-saturation table, 1.8 s: the load ramp to 1.7 s): no polarity test, the HF estimator's magnetizing
    current (``estimator.sqw_bangbang.i_d_min``) asked from CONVERGE on, MTPA in RUN, the table read at the q
    currents of the load: identical to golden; the d-current reference in CONVERGE and RELAX is the estimator's,
    -0.3 A in LSB, and the q current reaches the table's third point."""
    import hfi.sweep as sw
    from golden.control_config import scales, sqw_params
    from golden.firmware.supervisor import MODE_CONVERGE, MODE_RELAX, MODE_RUN
    from golden.scenario import parse_scenario

    job = next(j for j in sw.jobs(sw.load_spec(ROOT / "sweeps" / "cross_002_on_003.toml"), "test")
               if j.settings == {"reference.speed": ("scale", 0), "load.torque": ("scale", 1.0),
                                 "control.current_bw": ("value", "40 Hz"),
                                 "estimator.sqw_bangbang.cross_saturation": ("value", "on")})
    sc = dataclasses.replace(parse_scenario(job.tree, "cross_002_on_003"), duration=1.8)
    gold, hls = ClosedLoop(sc).run(progress=False), HlsClosedLoop(sc).run(progress=False)
    _assert_identical(gold, hls)
    mode, i_d_ref = hls.windows["mode"], hls.windows["i_d_ref"]
    assert {MODE_CONVERGE, MODE_RELAX, MODE_RUN} <= set(np.unique(mode).tolist())
    start = (mode == MODE_CONVERGE) | (mode == MODE_RELAX)
    assert set(np.unique(i_d_ref[start][1:]).tolist()) == {-scales(sc).current(0.3)}
    assert np.max(np.abs(hls.windows["i_q"])) > 2 << sqw_params(sc).xs_shift


@pytest.mark.parametrize("pair, key", [("cross_000_on_003", "estimator.rot_bpf.cross_saturation"),
                                       ("cross_001_on_003", "estimator.sqw_cic.cross_saturation")])
def test_the_other_hf_methods_on_the_syrm_identical(pair, key):
    """The 000 and 001 methods on the 003 SyRM with their cross-saturation tables (the sweeps' standstill, rated-load
    point, 1.8 s: the load ramp to 1.7 s): the magnetizing current from CONVERGE on, MTPA in RUN, the table read at
    the q currents of the load (C's odd_lookup on int16_t tables): identical to golden, and the q current reaches
    the table's third point."""
    import hfi.sweep as sw
    from golden.control_config import rot_bpf_params, sqw_cic_params
    from golden.scenario import parse_scenario

    job = next(j for j in sw.jobs(sw.load_spec(ROOT / "sweeps" / f"{pair}.toml"), "test")
               if j.settings == {"reference.speed": ("scale", 0), "load.torque": ("scale", 1.0), key: ("value", "on")})
    sc = dataclasses.replace(parse_scenario(job.tree, pair), duration=1.8)
    gold, hls = ClosedLoop(sc).run(progress=False), HlsClosedLoop(sc).run(progress=False)
    _assert_identical(gold, hls)
    p = rot_bpf_params(sc) if "rot_bpf" in key else sqw_cic_params(sc)
    assert p.xs_len > 2 and np.max(np.abs(hls.windows["i_q"])) > 2 << p.xs_shift


def test_rotating_injection_on_the_spmsm_identical():
    """The 000 method on the 002 system's Table I SPMSM (sweeps/cross_000_on_002.toml at standstill, rated load,
    21 V, the 0.5 us stage, the dead-time compensation's zone 0.2 A; 1.8 s: the load ramp to 1.7 s): the rotating
    injection at 500 Hz on a 5 kHz carrier (a 10-step staircase), N = 10, the notch at 500 Hz in the current loops,
    the 002 drive's saturation polarity test: identical to golden; the injection's phase steps a tenth of a turn
    per period, and the low slot holds the rotor within 10 deg at the end."""
    import hfi.sweep as sw
    from golden.firmware.supervisor import MODE_CONVERGE, MODE_RUN
    from golden.scenario import parse_scenario

    job = next(j for j in sw.jobs(sw.load_spec(ROOT / "sweeps" / "cross_000_on_002.toml"), "test")
               if j.settings == {"reference.speed": ("scale", 0), "load.torque": ("scale", 1.0),
                                 "injection.V_h": ("value", "21 V"), "pwm.dead_time": ("value", "0.5 us")})
    sc = dataclasses.replace(parse_scenario(job.tree, "cross_000_on_002"), duration=1.8)
    gold, hls = ClosedLoop(sc).run(progress=False), HlsClosedLoop(sc).run(progress=False)
    _assert_identical(gold, hls)
    assert hls.hw.inj_rot == 1 and hls.hw.inj_step == inj_step(500.0, 5000.0)
    assert set(np.diff(hls.windows["inj_phase"].astype(np.int64)) % (1 << 32)) == {hls.hw.inj_step}
    assert {MODE_CONVERGE, MODE_RUN} <= set(np.unique(hls.windows["mode"]).tolist())
    assert abs(hls.angle_error_deg()[-1]) < 10.0


@pytest.mark.parametrize("change, message", [
    ({"inj_rot": 2}, "inj_rot = 2 must be 0 or 1"),
    ({"inj_rot": 1, "inj_step": 1 << 32}, "inj_step = 4294967296 is not a u32 INJ_STEP register value"),
    ({"inj_rot": 1, "inj_step": -1}, "inj_step = -1 is not a u32"),
    ({"inj_per": 2}, "inj_per = 2 must be 0 or 1"),
    ({"cic_m": 256}, "cic_m = 256 is not a u8 CIC_M register value"),
    ({"direct": 2}, "direct = 2 must be 0 or 1"),
], ids=["inj_rot", "inj_step_high", "inj_step_negative", "inj_per", "cic_m", "direct"])
def test_bad_rotating_injection_setup_is_refused(change, message):
    loop = HlsClosedLoop(dataclasses.replace(_default(), duration=0.01))
    loop.hw = dataclasses.replace(loop.hw, **change)
    with pytest.raises(HlsBackendError, match=message):
        loop.run(progress=False)


def test_bad_setup_is_refused_with_a_message():
    """A register value the native loop cannot take (here an ADC resolution of 17 bits) is an error
    with a message, not a crash."""
    sc = dataclasses.replace(_default(), duration=0.01)
    loop = HlsClosedLoop(sc)
    loop.hw = dataclasses.replace(loop.hw, adc_bits=17)
    with pytest.raises(HlsBackendError, match="adc_bits must be 1..16"):
        loop.run(progress=False)


def test_a_diverged_plant_stops_both_loops_with_the_plant_message():
    """A dc-link resistance of 1e30 ohm makes the plant diverge: golden raises PlantError and the hls loop (its C++
    event loop, sim/plant_loop.cpp) refuses the window, both with ``plant_status_text(PLANT_NOT_FINITE)``, the one
    wording of plant_api.h."""
    from golden.plant.binding import PlantError, library, status_error
    sc = dataclasses.replace(_default(), duration=1e-3)
    sc.plant = dict(sc.plant, inv=dict(sc.plant["inv"], R_dc=1e30))
    text = str(status_error(library().PLANT_NOT_FINITE))
    assert text.startswith("the plant's state is no longer finite (NaN or infinite)")
    with pytest.raises(PlantError) as gold:
        ClosedLoop(sc).run(progress=False)
    assert str(gold.value) == text
    with pytest.raises(HlsBackendError) as hls:
        HlsClosedLoop(sc).run(progress=False)
    assert f"(status {library().PLANT_NOT_FINITE}: {text})" in str(hls.value)


def test_run_script_hls_backend(tmp_path):
    """scripts/run.py --backend hls writes the same outputs as the other backends."""
    scen = tmp_path / "short.toml"
    text = (ROOT / "scenarios" / "fullload_start.toml").read_text()
    assert 'duration = "2.4 s"' in text
    scen.write_text(text.replace('duration = "2.4 s"', 'duration = "20 ms"'))
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, str(ROOT / "scripts" / "run.py"), str(scen), "--out", str(out),
                           "--quiet", "--backend", "hls"], capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    m = json.loads((out / "metrics.json").read_text())
    assert m["backend"] == "hls" and 0 < m["plant_wall_s"] < m["wall_s"] + 0.01
    assert (out / "trace.npz").is_file() and (out / "closed_loop.png").is_file()
