"""Self-commissioning: the firmware's identification executor (golden.firmware.ident) against closed forms,
the hardware's HF gain against the square-wave limit, and the whole sequence on the default scenario's plant
against the plant's truth (docs/commissioning.md)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from golden.firmware.ident import (F_FIT, F_LEVEL, F_NEG, F_OPEN, F_POL, F_SCAN, F_SET, F_SNAP, SIXTH, Ident,
                                   IdentParams)
from golden.firmware.supervisor import RESET_OUTPUTS
from golden.fixed import c_div, wrap

DEFAULT = "scenarios/fullload_start.toml"


def program(steps, **kw) -> IdentParams:
    """IdentParams from (n, m, i_d, i_q, v_h, phi, dw, flags) rows."""
    cols = list(zip(*steps))
    base = dict(c_kp=1 << 40, c_ki=1000, v_lim=20000, c_lvl=1 << 30, lvl_max=1 << 24, vh_max=32767, i_slew=1 << 20)
    base.update(kw)
    return IdentParams(*[tuple(c) for c in cols], **base)


class _St:
    id_int = iq_int = 0


def run(idn: Ident, windows) -> None:
    """Feed ``(gamma_d, gamma_q)`` per window; the executor's outputs drive nothing here."""
    st = _St()
    for g_d, g_q in windows:
        idn.measure(0, 0, g_d, g_q, RESET_OUTPUTS, RESET_OUTPUTS)
        if idn.done:
            return
        idn.refs(0, 0, st)


@pytest.mark.parametrize("theta_deg", [0.0, 17.0, 63.5, 101.0, 179.0])
def test_scan_fit_angle_gain_and_level(theta_deg):
    """Responses g_d - j g_q = Y0 + Y2 exp(j 2 (phi - theta_r)) at 8 angles, in pairs (v, 2v): the angle
    within the CORDIC's precision (mod 180 deg), kp = c_kp (v_h(2v) - v_h(v)) / sum of the differences, and
    the level c_lvl / G of the probe."""
    K, y0, y2 = 8, 20000.0, 3000.0
    th = math.radians(theta_deg)
    steps = [(2, 1, 0, 0, 100, 0, 0, F_SET | F_OPEN | F_LEVEL)]
    windows = [(0, 0), (5000, 0)]                       # the probe: G = 5000
    for k in range(K):
        phi = (k << 31) // K
        a = 2 * (phi / 2**32 * 2 * math.pi - th)
        for twice in (0, 1):
            steps.append((2, 1, 0, 0, 100 << twice, phi, 0,
                          F_SET | F_OPEN | F_SCAN | (0 if twice else F_NEG) | (F_FIT if k == K - 1 and twice else 0)))
            scale = 1 + twice
            windows += [(0, 0), (round(scale * (y0 + y2 * math.cos(a))), round(scale * -y2 * math.sin(a)))]
    p = program(steps)
    idn = Ident(p)
    run(idn, windows)
    assert idn.lvl == c_div(p.c_lvl, 5000)
    found = idn.theta_r / 2**32 * 360.0
    err = (found - theta_deg + 90.0) % 180.0 - 90.0
    assert abs(err) < 0.05
    sum_diff = sum(windows[2 + 4 * k + 3][0] - windows[2 + 4 * k + 1][0] for k in range(K))
    v = lambda s: min((s * idn.lvl) >> 16, p.vh_max)    # noqa: E731
    assert idn.fit_y0 == sum_diff
    assert idn.kp == min(c_div(p.c_kp * (v(200) - v(100)), sum_diff), (1 << 31) - 1)
    assert idn.ki == (idn.kp * p.c_ki) >> 16


@pytest.mark.parametrize("first, second, flipped", [(900, 1000, True), (1000, 900, False)])
def test_polarity(first, second, flipped):
    """F_POL turns the angle by half a turn when the -I_p response is the larger."""
    p = program([(2, 1, 100, 0, 50, 0, 0, F_SET), (2, 1, -100, 0, 50, 0, 0, F_SET | F_POL)])
    idn = Ident(p)
    run(idn, [(0, 0), (first, 0), (0, 0), (second, 0)])
    assert idn.theta_r == (1 << 31 if flipped else 0)


def test_level_without_response_fails():
    p = program([(2, 1, 0, 0, 100, 0, 0, F_SET | F_OPEN | F_LEVEL)])
    idn = Ident(p)
    run(idn, [(0, 0), (0, 0)])
    assert idn.failed == 1


def test_frame_speed_ramp():
    """Without F_SET the frame speed grows by dw each period and the angle by the speed: after n calls
    w = n dw, theta = dw n (n + 1) / 2 (mod 2^32)."""
    dw, n = 123457, 50
    p = program([(1, 0, 0, 0, 0, 0, 0, F_SET), (n + 1, 0, 0, 0, 0, 0, dw, 0)])
    idn = Ident(p)
    st = _St()
    idn.refs(0, 0, st)                 # step 0: the F_SET call
    for _ in range(n):
        idn.measure(0, 0, 0, 0, RESET_OUTPUTS, RESET_OUTPUTS)
        idn.refs(0, 0, st)
    assert idn.w == n * dw
    assert idn.theta == (dw * n * (n + 1) // 2) % 2**32


@pytest.mark.parametrize("theta_r", [0, 100_000_000, SIXTH // 2 + 5, 3_000_000_000, 2**32 - 7])
def test_snap_ends_on_a_phase_axis(theta_r):
    """F_SNAP: the frame reaches the nearest multiple of 60 deg at the end of the step, within the division's
    rounding (n LSB), and stops there."""
    n = 37
    p = program([(n, 0, 0, 0, 0, 0, 0, F_SET | F_SNAP), (3, 0, 0, 0, 0, 0, 0, 0)])
    idn = Ident(p)
    idn.theta_r = theta_r
    idn._start()
    st = _St()
    for _ in range(n + 2):
        idn.refs(0, 0, st)
        idn.measure(0, 0, 0, 0, RESET_OUTPUTS, RESET_OUTPUTS)
    nearest = min(((k << 32) // 6 for k in range(7)), key=lambda a: abs(wrap(a - theta_r, 32)))
    assert abs(wrap(idn.theta - nearest, 32)) <= n
    assert idn.w == 0


def test_bad_program_refused():
    with pytest.raises(ValueError, match="n 0 must be >= 1"):
        program([(0, 0, 0, 0, 0, 0, 0, 0)])
    with pytest.raises(ValueError, match="v_h 40000"):
        program([(2, 1, 0, 0, 40000, 0, 0, 0)])


@pytest.mark.parametrize("path, theta_m", [(DEFAULT, 7.0), (DEFAULT, 61.0), (DEFAULT, 152.0),
                                           ("scenarios/xue2022_noload.toml", 33.0),
                                           ("scenarios/xue2022_noload.toml", 171.0)])
def test_standstill_angle_and_polarity(path, theta_m):
    """The rotor angle found at standstill (probe, scan, polarity) within 10 deg of the plant's, the polarity right
    (scripts/commission_polarity.py runs 20 random angles per motor)."""
    from hfi.commission import standstill_angle
    found, true = standstill_angle(path, theta_m)
    assert abs((found - true + 180.0) % 360.0 - 180.0) < 10.0


FAST = "hls"
"""The backend of the tests of accuracy and of the error paths: the hls loop, bit-identical to the golden backend over
the default motor's whole program (test_commission_hls_identical_to_golden_whole_program) and 5-7 times faster."""


@pytest.fixture(scope="module")
def default_commission(tmp_path_factory):
    from hfi.commission import commission
    out = tmp_path_factory.mktemp("commission")
    return commission(DEFAULT, out, progress=False), out


@pytest.mark.xdist_group("default_commission")
def test_commission_default_motor(default_commission):
    """The whole sequence on the Table I motor with the scenario's sensors, offsets and 4 us dead time: R (the
    current path: motor plus the inverter's conduction slope), L_d, L_q at zero current and psi_f within 3 %,
    J within 10 % of the plant's, the rotor angle at standstill within 10 deg, the saturation map within 5 % at each
    of its 15 points (1.8 % measured; 7.2 % before the map's inverter model, docs/commissioning.md)."""
    s = default_commission[0]
    v = s["values"]
    for name in ("R_s", "L_d", "L_q", "psi_f"):
        assert abs(v[name]["rel_error"]) < 0.03, (name, v[name])
    assert abs(v["J"]["rel_error"]) < 0.10
    assert abs(s["angle_error_deg"]) < 10.0
    assert s["tuning"]["hf_possible"]
    assert_map_within(s, 0.05)


def assert_map_within(s: dict, tol: float, own_current_only: bool = False) -> None:
    """Every entry of the measured saturation map within ``tol`` of the plant's incremental inductance (15 points);
    ``own_current_only``: the entries whose own axis carries current (L_dd where i_d != 0, L_qq where i_q != 0)."""
    assert len(s["map"]) == 15
    for r in s["map"]:
        for axis, i in (("dd", r["i_d"]), ("qq", r["i_q"])):
            if i or not own_current_only:
                assert abs(r["rel_error_" + axis]) < tol, (axis, r)


@pytest.mark.parametrize("path, drive", [("scenarios/bench2_loadsteps.toml", False),
                                         ("scenarios/xue2022_noload.toml", True)])
def test_commission_other_pm_motors(path, drive, tmp_path):
    """The 002 Table III motor and the 001 IPMSM, each with its scenario's sensors, offsets and dead time: R, L_d,
    L_q, psi_f within 3 % and J within 10 % of the plant's, the standstill angle within 10 deg, the map within 5 %
    (0.3 % and 0.8 % measured) (the 000 motor: the test below; the 003 SyRM, its inductances at the scan's bias:
    test_commission_reluctance_motor). ``drive``: the drive tuned from it (commissioned.toml) runs the scenario
    without a fault, its angle error RMS on each plateau within 1.5 times the hand-tuned drive's (the 001 drive:
    1.11 and 1.54 deg against 1.03 and 1.36; with V_h from the signal-to-noise rule alone, 5.4 V, it tripped;
    the Table III scenario's rated-load steps are issue 14's)."""
    from hfi.commission import commission
    s = commission(path, tmp_path, progress=False, backend=FAST)
    for name in ("R_s", "L_d", "L_q", "psi_f"):
        assert abs(s["values"][name]["rel_error"]) < 0.03, (name, s["values"][name])
    assert abs(s["values"]["J"]["rel_error"]) < 0.10
    assert abs(s["angle_error_deg"]) < 10.0
    assert_map_within(s, 0.05)
    if drive:
        assert_tuned_drive(tmp_path, path, 1.5)


def assert_tuned_drive(out, path: str, factor: float) -> None:
    """The drive tuned by the commissioning in ``out`` (commissioned.toml) runs the scenario ``path`` on FAST without
    a fault, the angle error RMS of each speed plateau below ``factor`` times the hand-tuned drive's."""
    from hfi.run import run_file
    tuned = run_file(str(out / "commissioned.toml"), FAST, str(out / "tuned"), progress=False)
    hand = run_file(path, FAST, str(out / "hand"), progress=False)
    assert tuned.metrics["faults"]["code"] == "none", tuned.metrics["faults"]
    assert len(tuned.metrics["segments"]) == len(hand.metrics["segments"]) > 0
    for a, b in zip(tuned.metrics["segments"], hand.metrics["segments"]):
        assert a["speed_ref_rpm"] == b["speed_ref_rpm"]
        assert a["err_rms_deg"] < factor * b["err_rms_deg"], (a, b)


def test_commission_reluctance_motor(tmp_path):
    """The 003 SyRM (no magnets: a biased scan under current control, no polarity test, no coast): R within 3 % and
    J within 10 %; its inductances at the scan's bias from the current steps of stage lf (on q with the gains set
    for q), the up and the down transition agreeing: L_d and L_q within 3 %, L_d nearer the plant's incremental
    inductance there than the pair on the fitted axis (stage axis) and than the scan's first-harmonic fit
    (docs/commissioning.md: -0.3 % and -1.3 % measured; the targets at zero current are out of reach of the
    injection); the map within 5 % wherever the injected axis carries current (1.7 % measured; the entries at zero
    current on their own axis, 1 H, draw a few mA of HF current: 9-16 %). The algebraic saturation model fitted to
    them (golden.saturation_fit) gives the flux linkages within 3 % of the plant's at the check points (1.7 %
    measured), and the drive tuned from it (commissioned.toml, its [model.saturation]) runs the scenario's speed
    range without a fault, its angle error RMS on each plateau within 1.5 times the hand-tuned drive's (1.26 and
    1.15 deg against 1.07 and 0.91 measured; with the linear model of before it tripped on overcurrent at 0.52 s)."""
    from hfi.commission import commission
    s = commission("scenarios/varatharajan2020_speedrange.toml", tmp_path, progress=False, backend=FAST)
    v = s["values"]
    assert "psi_f" not in v and s["inductance_from"] == "lf" and set(s["lf"]) == {"d", "q"}
    assert abs(v["R_s"]["rel_error"]) < 0.03 and abs(v["J"]["rel_error"]) < 0.10
    truth = v["L_d"]["truth"]
    assert abs(v["L_d"]["measured"] - truth) < abs(s["axis_L_d"] - truth) < abs(s["fit_L_d"] - truth)
    assert abs(v["L_d"]["rel_error"]) < 0.03, v["L_d"]
    assert abs(v["L_q"]["rel_error"]) < 0.03, v["L_q"]
    for axis in ("d", "q"):
        up, down = s["lf"][axis]
        assert v["L_" + axis]["measured"] == pytest.approx(0.5 * (up + down), rel=1e-12)
    assert_map_within(s, 0.05, own_current_only=True)
    assert all(c["rel_error"] < 0.03 for c in s["saturation"]["flux_check"]), s["saturation"]["flux_check"]
    assert_tuned_drive(tmp_path, "scenarios/varatharajan2020_speedrange.toml", 1.5)


@pytest.mark.xdist_group("default_commission")
def test_commission_hls_identical_to_golden_whole_program(default_commission, tmp_path):
    """The default motor's whole program (every stage, the coast last) on the hls backend: every measured value, the
    map, the standstill angle, the scan's SNR and the tuning equal to the golden backend's (default_commission) to the
    last bit."""
    from hfi.commission import commission
    s = commission(DEFAULT, tmp_path, progress=False, backend="hls")
    gold = default_commission[0]
    for key in ("values", "map", "angle_error_deg", "snr_scan", "tuning", "lf", "inductance_from", "steps"):
        assert s[key] == gold[key], key


@pytest.mark.xdist_group("default_commission")
def test_self_tuned_drive_no_worse_than_hand_tuned(default_commission, tmp_path):
    """The default scenario with the commissioned [model], V_h and hand-over speeds (commissioned.toml) on the
    hls loop (FAST): no fault, and the angle error RMS of every speed plateau no worse than the hand-tuned run's."""
    from hfi.run import run_file
    tuned = run_file(str(default_commission[1] / "commissioned.toml"), FAST, str(tmp_path / "tuned"), progress=False)
    hand = run_file(DEFAULT, FAST, str(tmp_path / "hand"), progress=False)
    assert tuned.metrics["faults"]["code"] == "none"
    assert len(tuned.metrics["segments"]) == len(hand.metrics["segments"]) > 0     # every plateau compared
    for a, b in zip(tuned.metrics["segments"], hand.metrics["segments"]):
        assert a["speed_ref_rpm"] == b["speed_ref_rpm"]
        assert a["err_rms_deg"] <= b["err_rms_deg"], (a, b)


def test_commission_hls_identical_to_golden():
    """The commissioning run (cut to 3 s: the probe, the scan, the polarity test, the first steps of the map with
    the shaft held) on
    the hls backend (native loop, host build of the C firmware with its identification block) gives the golden
    backend's trace and the identification executor's state (every sum of every step) bit for bit."""
    import dataclasses

    from golden.scenario import parse_scenario
    from hfi.backends import run
    from hfi.commission import run_scenario_dict
    path = "scenarios/xue2022_noload.toml"
    d = run_scenario_dict(path)
    d["scenario"]["duration"] = "3 s"
    sc = parse_scenario(d, path)
    gold = run(sc, "golden", progress=False)
    hls = run(sc, "hls", progress=False)
    for name in ("mode", "i_d", "i_q", "v_d", "v_q", "gamma", "gamma_d", "theta_hat", "fault"):
        np.testing.assert_array_equal(hls.windows[name], gold.windows[name], err_msg=name)
    assert isinstance(hls.ident, Ident) and isinstance(gold.ident, Ident)
    assert gold.ident.k > 0 and any(gold.ident.r_gd)        # it got into the program and summed something
    for f in dataclasses.fields(Ident):
        assert getattr(hls.ident, f.name) == getattr(gold.ident, f.name), f.name


@pytest.mark.long
def test_commission_rtl_identical_to_golden(tmp_path):
    """The commissioning image on the soft core (rtl backend: make -C firmware IDENT=1, the SoC with
    soc_platform.IDENT_RAM_BYTES of RAM; the program patched into the RAM image at fw_ident and the executor's state
    read back from the RAM at the end), cut to 0.4 s of the default motor's run (the probe and the first scan
    steps): every window column and every field of the executor's state as on the golden backend, no late commit."""
    import dataclasses

    from golden.closedloop import WINDOW_FIELDS
    from golden.scenario import parse_scenario
    from hfi.backends import run
    from hfi.commission import run_scenario_dict
    from hfi.rtl_backend import RtlClosedLoop
    path = "scenarios/fullload_start.toml"
    d = run_scenario_dict(path)
    d["scenario"]["duration"] = "0.4 s"
    d.pop("faults")                                          # the shaft lock, from 1.5 s: after the cut
    sc = parse_scenario(d, path)
    gold = run(sc, "golden", progress=False)
    rtl = RtlClosedLoop(sc).run(progress=False, workdir=tmp_path)
    for name in WINDOW_FIELDS:
        np.testing.assert_array_equal(rtl.windows[name], gold.windows[name], err_msg=name)
    assert gold.ident.k >= 3 and any(gold.ident.r_gd)       # past the probe, into the scan
    for f in dataclasses.fields(Ident):
        assert getattr(rtl.ident, f.name) == getattr(gold.ident, f.name), f.name
    assert rtl.soc["late_commits"] == 0


def _weak_scenario(tmp_path, v_max: str):
    import tomllib

    import tomli_w
    with open("scenarios/xue2022_noload.toml", "rb") as f:
        d = tomllib.load(f)
    d["commission"] = {"hf_voltage_max": v_max}
    path = tmp_path / "weak.toml"
    path.write_text(tomli_w.dumps(d))
    return path


def test_too_small_hf_amplitude_stops_with_its_reason(tmp_path):
    """The 001 drive with the HF amplitude capped at 0.3 V (the dead time's voltage is 2.2 V): the scan's
    inductances are wrong, the current gains from them too, and in the polarity test the current reaches the ADC's
    full scale, where the hardware comparator (OC_LIMIT at its reset value) turns the gates off; the error
    names the stage, the fault, what the scan saw and what to raise."""
    from hfi.commission import CommissionError, commission
    with pytest.raises(CommissionError, match=r"stage 'polarity'.*fault hardware.*scan saw L_d.*hf_voltage_max"):
        commission(_weak_scenario(tmp_path, "0.3 V"), tmp_path / "out", progress=False, backend=FAST)


@pytest.mark.parametrize("table, words", [
    ({"hf_voltage_max": "0.01 V"}, r"commission.probe_voltage: 0.005 V is below one voltage LSB \(0\.0\d+ V\) "
                                   r"\(derived: half of hf_voltage_max at most\)"),
    ({"hf_voltage_max": "1 mV", "probe_voltage": "10 V"}, r"commission.hf_voltage_max: 0.001 V is below one voltage LSB"),
    ({"speed": "1e30 rpm"}, r"commission.speed: 1e\+30 r/min turns the spin's frame by .* of an electrical turn per "
                            r"PWM period \(a quarter at most\)"),
])
def test_settings_the_program_cannot_hold_are_refused(tmp_path, table, words):
    """Found by probing the command (2026-11-30): an HF amplitude below one voltage LSB divided by zero in the
    probe's expected response, and a spin speed of 1e30 r/min wrapped the frame speed silently (the run "succeeded"
    with J < 0). Refused, naming the key, before anything runs."""
    from golden.commission import build_program, settings
    from golden.scenario import load_scenario
    path = _weak_scenario(tmp_path, "100 V")
    text = path.read_text().replace('hf_voltage_max = "100 V"', "\n".join(f'{k} = "{v}"' for k, v in table.items()))
    path.write_text(text)
    sc = load_scenario(path)
    with pytest.raises(ValueError, match=words):
        build_program(sc, settings(sc))


def test_hf_method_refused_writes_no_configuration(tmp_path, monkeypatch):
    """When the tuning finds the saliency signal below SNR_MIN_SALIENCY times the noise (forced here), the
    application's HF method (sqw_cic) is refused with the numbers: commission.json written, no commissioned.toml."""
    import hfi.commission as hc
    real = hc.tuning
    monkeypatch.setattr(hc, "tuning", lambda sc, res: {**real(sc, res), "hf_possible": False})
    with pytest.raises(hc.CommissionError, match="'sqw_cic' is refused"):
        hc.commission("scenarios/xue2022_noload.toml", tmp_path / "out", progress=False, backend=FAST)
    assert (tmp_path / "out" / "commission.json").is_file()
    assert not (tmp_path / "out" / "commissioned.toml").exists()


def test_lf_inductance_closed_form():
    """golden.commission._lf_inductance on sums made from a known inductance: the transition's voltage sum is
    L (I2 - I1) / T plus f(i) summed over its windows, f(i) = R i + V0 (the line through the holds); it returns L
    for the up and the down transition."""
    from types import SimpleNamespace

    from golden.commission import Program, StepInfo, _lf_inductance
    L, R, V0, T, n = 0.067, 5.9, 3.2, 1e-4, 200
    i1, i2, i_lsb, v_lsb = 0.27, 0.53, 1e-3, 1e-2
    f = lambda i: R * i + V0                                         # noqa: E731
    sum_i = {"lf_up": 0.5 * n * i2, "lf_down": 0.4 * n * i1 + 0.6 * n * i2}   # any transient: f is linear
    stages = ["lf_lo", "lf_up", "lf_hi", "lf_down", "lf_lo2"]
    r_id, r_vd, means = [], [], []
    for s in stages:
        if s in sum_i:
            d_i = (i2 - i1) if s == "lf_up" else (i1 - i2)
            r_id.append(sum_i[s] / i_lsb)
            r_vd.append((L * d_i / T + R * sum_i[s] + n * V0) / v_lsb)
            means.append(None)
        else:
            i = i1 if s != "lf_hi" else i2
            r_id.append(0)
            r_vd.append(0)
            means.append({"id": i / i_lsb, "vd": f(i) / v_lsb})
    params = SimpleNamespace(s_m=[n] * len(stages))
    prog = Program(params, tuple(StepInfo(s, axis="d") for s in stages), None, 1.0)
    up, down = _lf_inductance(prog, SimpleNamespace(r_id=r_id, r_vd=r_vd), means, "d", i_lsb, v_lsb, T)
    assert up == pytest.approx(L, rel=1e-12) and down == pytest.approx(L, rel=1e-12)


def test_commission_000_motor_low_frequency_inductances(tmp_path):
    """The 000 motor (67 / 182 mH, 10 kHz): the HF scan's current is 10-40 mA, where the node capacitances decide
    the dead time's share (its L_d 6.9 % high); the low-frequency steps (stage lf) agree up and down and give L_d,
    L_q within 3 % of the plant's; R and psi_f within 3 %, J within 10 % (psi_f was 3.8 % high while the coast's two
    halves were half turns each: the sensors' offsets leave a dead-time error fixed in the stationary frame); the map
    within 5 % (3.4 % measured; 7.4 % before the map's single step and inverter model)."""
    from hfi.commission import commission
    s = commission("scenarios/tap2023_step.toml", tmp_path, progress=False, backend=FAST)
    assert s["inductance_from"] == "lf" and (tmp_path / "commission_lf.png").is_file()
    for name in ("R_s", "L_d", "L_q", "psi_f"):
        assert abs(s["values"][name]["rel_error"]) < 0.03, (name, s["values"][name])
    assert abs(s["values"]["J"]["rel_error"]) < 0.10
    assert_map_within(s, 0.05)
