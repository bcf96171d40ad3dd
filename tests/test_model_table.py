"""The scenario table ``[model]``: the motor data the controller is tuned from (golden.scenario ModelSettings,
golden.control_config.controller_motor), instead of the plant's own nominal data."""

from __future__ import annotations

import copy
import math
import re

import pytest

from golden.control_config import controller_motor, firmware_params, hardware_config, scales
from golden.firmware.pi import pi_gains
from golden.motors import PRESETS
from golden.scenario import ScenarioError, parse_scenario

PRESET = "benevieri2023_table1"     # d-saturating model: its nominal data are its own L_d, L_q, psi_f
BASE = {"scenario": {"name": "model_table", "duration": "10 ms"},
        "motor": {"preset": PRESET}, "control": {}}
"""A closed-loop scenario on the defaults (sqw_bangbang estimator, no flux maps)."""


def own_model(preset: str = PRESET) -> dict:
    """A ``[model]`` table with the preset's own nominal data (SI numbers)."""
    p = PRESETS[preset]
    return {"R_s": p["R_s"], "L_d": p["mag"]["L_d"], "L_q": p["mag"]["L_q"], "psi_f": p["mag"]["psi_f"],
            "J": p["mech"]["J"]}


def scenario(model: dict | None = None, base: dict = BASE):
    data = copy.deepcopy(base)
    if model is not None:
        data["model"] = model
    return parse_scenario(data)


def current_gains(sc, r_s: float) -> tuple[int, int]:
    """The current PI's (kp, ki), computed here from the technical optimum on the scenario's own L."""
    sc_, ctl, mag = scales(sc), sc.control, PRESETS[PRESET]["mag"]
    w_c = 2 * math.pi * ctl.current_bw
    return pi_gains(0.5 * (mag["L_d"] + mag["L_q"]) * w_c, r_s * w_c, sc_.i_lsb / sc_.v_lsb, sc.pwm.f_sw, 16, 16)


def speed_gains(sc, j: float) -> tuple[int, int]:
    """The speed PI's (kp, ki): ``k_p = J w_s / (K_t p)``, ``k_i = k_p w_s / 4``, ``K_t = 1.5 p psi_f``."""
    sc_, ctl = scales(sc), sc.control
    p = PRESETS[PRESET]["mech"]["pole_pairs"]
    w_s = 2 * math.pi * ctl.speed_bw
    kp_w = j * w_s / (1.5 * p * PRESETS[PRESET]["mag"]["psi_f"] * p)
    return pi_gains(kp_w, kp_w * w_s / 4, sc_.w_lsb / sc_.i_lsb, sc.pwm.f_sw, sp=24, si=31)


def test_absent_model_is_none_and_the_plant_data():
    sc = scenario()
    assert sc.model is None
    cm = controller_motor(sc)
    assert cm.R_s == sc.plant["R_s"] and cm.J == sc.plant["mech"]["J"] and cm.mag is sc.plant["mag"]
    assert cm.pole_pairs == sc.plant["mech"]["pole_pairs"]


def test_model_settings_read_with_units_and_defaults():
    sc = scenario({"R_s": "3.1 ohm", "L_d": "5.6 mH", "L_q": "6.3 mH", "psi_f": "0.147 Wb",
                   "J": "4.1e-3 kg*m^2", "T_c": "0.02 N*m"})
    m = sc.model
    assert (m.R_s, m.L_d, m.L_q, m.psi_f, m.J, m.B, m.T_c) == pytest.approx(
        (3.1, 5.6e-3, 6.3e-3, 0.147, 4.1e-3, 0.0, 0.02))
    cm = controller_motor(sc)
    assert cm.mag["kind"] == 0 and (cm.mag["L_d"], cm.mag["L_q"], cm.mag["psi_f"]) == (m.L_d, m.L_q, m.psi_f)
    assert cm.pole_pairs == PRESETS[PRESET]["mech"]["pole_pairs"]
    assert sc.plant["R_s"] == PRESETS[PRESET]["R_s"]          # the plant keeps the true machine


def test_own_data_gives_the_same_gains():
    """(a) [model] = the preset's own nominal data: the same current PI (and everything else here)."""
    plain, modelled = scenario(), scenario(own_model())
    fp, fm = firmware_params(plain), firmware_params(modelled)
    assert fm.id_pi == fp.id_pi and fm.iq_pi == fp.iq_pi
    assert (fm.id_pi.kp, fm.id_pi.ki) == current_gains(plain, PRESETS[PRESET]["R_s"])
    assert fm.speed_pi == fp.speed_pi and fm.prot == fp.prot
    assert fm == fp
    assert hardware_config(modelled) == hardware_config(plain)


def test_double_resistance_doubles_the_current_integral_gain():
    """(b) R_s doubled in [model]: the current PI's k_i doubles (k_i = R w_c), k_p stays."""
    r_s = PRESETS[PRESET]["R_s"]
    plain = firmware_params(scenario())
    sc = scenario(own_model() | {"R_s": 2 * r_s})
    fm = firmware_params(sc)
    kp, ki = current_gains(sc, 2 * r_s)
    assert (fm.id_pi.kp, fm.id_pi.ki) == (kp, ki) and fm.iq_pi == fm.id_pi
    assert fm.id_pi.kp == plain.id_pi.kp
    assert abs(fm.id_pi.ki - 2 * plain.id_pi.ki) <= 1
    assert fm.prot.r != plain.prot.r                          # the fault checks' model follows too


def test_double_inertia_doubles_the_speed_kp():
    """(c) J doubled in [model]: the speed PI's k_p (and k_i) double, within rounding."""
    j = PRESETS[PRESET]["mech"]["J"]
    plain = firmware_params(scenario())
    sc = scenario(own_model() | {"J": 2 * j})
    fm = firmware_params(sc)
    assert (fm.speed_pi.kp, fm.speed_pi.ki) == speed_gains(sc, 2 * j)
    assert (plain.speed_pi.kp, plain.speed_pi.ki) == speed_gains(sc, j)
    assert abs(fm.speed_pi.kp - 2 * plain.speed_pi.kp) <= 1
    assert fm.id_pi == plain.id_pi


@pytest.mark.parametrize("key", ["R_s", "L_d", "L_q", "psi_f", "J"])
def test_missing_required_key(key):
    """(d) each of R_s, L_d, L_q, psi_f, J is required when [model] is given."""
    model = own_model()
    del model[key]
    with pytest.raises(ScenarioError) as info:
        scenario(model)
    assert info.value.problems == [f"model.{key}: missing (required when [model] is given)"]


def test_empty_model_table_lists_every_missing_key():
    with pytest.raises(ScenarioError) as info:
        scenario({})
    assert sorted(info.value.problems) == sorted(f"model.{k}: missing (required when [model] is given)"
                                                 for k in ("R_s", "L_d", "L_q", "psi_f", "J"))


@pytest.mark.parametrize("key, value, reason", [
    ("R_s", "-3 ohm", "must be > 0"), ("R_s", 0, "must be > 0"), ("L_d", "-1 mH", "must be > 0"),
    ("J", 0, "must be > 0"), ("psi_f", "-0.1 Wb", "must be >= 0"), ("B", -1e-4, "must be >= 0"),
    ("T_c", "-0.02 N*m", "must be >= 0")])
def test_negative_values_refused(key, value, reason):
    """(e) negative R_s (and the other non-physical values) refused, with the path."""
    with pytest.raises(ScenarioError) as info:
        scenario(own_model() | {key: value})
    assert len(info.value.problems) == 1
    assert info.value.problems[0].startswith(f"model.{key}: {reason}")


def test_unknown_key_and_wrong_unit():
    with pytest.raises(ScenarioError) as info:
        scenario(own_model() | {"L_s": "5 mH", "J": "4 mH"})
    text = "\n".join(info.value.problems)
    assert "model.L_s: unknown key" in text and "model.J:" in text


def test_misplaced_motor_key_still_points_to_the_plant():
    """[model] repeats motor keys: a misplaced one still suggests the plant's table."""
    with pytest.raises(ScenarioError) as info:
        parse_scenario({"scenario": {"name": "x", "duration": 1}, "motor": {"L_d": "5 mH"}})
    assert info.value.problems == ["motor.L_d: unknown key (did you mean 'motor.magnetic.L_d'?)"]


def test_reluctance_model_uses_the_mtpa_torque():
    """psi_f = 0: the speed PI's torque per ampere from the linear model's MTPA point (L_q > L_d)."""
    sc = scenario({"R_s": 3.0, "L_d": 5e-3, "L_q": 15e-3, "psi_f": 0.0, "J": 4e-3})
    i_nom = 0.5 * sc.control.i_max
    p = PRESETS[PRESET]["mech"]["pole_pairs"]
    k_t = 1.5 * p * (15e-3 - 5e-3) * 0.5 * i_nom            # at 45 deg: 1.5 p (L_q - L_d) i^2 / 2, per i
    sc_, w_s = scales(sc), 2 * math.pi * sc.control.speed_bw
    kp_w = 4e-3 * w_s / (k_t * p)
    expected = pi_gains(kp_w, kp_w * w_s / 4, sc_.w_lsb / sc_.i_lsb, sc.pwm.f_sw, sp=24, si=31)
    got = firmware_params(sc).speed_pi
    assert abs(got.kp - expected[0]) <= 1 and abs(got.ki - expected[1]) <= 1
    with pytest.raises(ValueError, match="L_q > L_d"):
        firmware_params(scenario({"R_s": 3.0, "L_d": 15e-3, "L_q": 5e-3, "psi_f": 0.0, "J": 4e-3}))


def with_error(error: dict | None, model: dict | None = None):
    data = copy.deepcopy(BASE)
    if model is not None:
        data["model"] = model
    if error is not None:
        data["model_error"] = error
    return parse_scenario(data)


def test_model_error_scales_the_controllers_data_and_only_them():
    plain, off = with_error(None), with_error({"R_s": 1.2, "L_d": 0.8, "L_q": 1.1, "psi_f": 0.9, "J": 2.0})
    a, b = controller_motor(plain), controller_motor(off)
    assert (b.R_s, b.J) == (a.R_s * 1.2, a.J * 2.0)
    assert (b.mag["L_d"], b.mag["L_q"], b.mag["psi_f"]) == (a.mag["L_d"] * 0.8, a.mag["L_q"] * 1.1, a.mag["psi_f"] * 0.9)
    assert {k: v for k, v in b.mag.items() if k not in ("L_d", "L_q", "psi_f")} == \
           {k: v for k, v in a.mag.items() if k not in ("L_d", "L_q", "psi_f")}
    assert off.plant == plain.plant                                   # the machine is the same
    assert firmware_params(with_error({"R_s": 2.0})).id_pi.ki == current_gains(plain, 2 * a.R_s)[1]
    # on a [model] table too
    c = controller_motor(with_error({"L_q": 1.5}, own_model()))
    assert c.mag["L_q"] == own_model()["L_q"] * 1.5


def test_model_error_of_ones_is_bit_exact_and_bad_factors_are_refused():
    assert firmware_params(with_error({})) == firmware_params(with_error(None))
    assert hardware_config(with_error({"R_s": 1, "L_d": 1.0})) == hardware_config(with_error(None))
    with pytest.raises(ScenarioError) as exc:
        with_error({"L_x": 1.2, "psi_f": 0, "J": "x"})
    text = str(exc.value)
    # L_d and L_q are equally close to L_x: either suggestion is right
    assert re.search(r"model_error\.L_x: unknown key \(did you mean 'L_[dq]'\?\)", text), text
    assert "model_error.psi_f: must be between 0.01 and 100 (a factor on the controller's motor data), got 0" in text
    assert "model_error.J" in text


def test_predicted_hf_current_of_a_model_without_an_inductance_parameter():
    """HF_AMP (the dead-time compensation's HF current, V_h / (4 f_sw L_d)) of an algebraic model (the 003 SyRM under
    a square-wave method) takes the nominal motor's L_d at half i_max, as the current PIs (it took the parameter
    dict's default 5.59 mH, whatever the machine: 733 LSB here instead of 122)."""
    import tomllib

    from golden.flux_tables import nominal_motor
    with open("scenarios/varatharajan2020_speedrange.toml", "rb") as f:
        d = tomllib.load(f)
    d["control"].update(law="foc_pwm", polarity="none")
    d["estimator"], d["injection"] = {"low": "sqw_bangbang", "high": "none"}, {"V_h": "100 V"}
    sc = parse_scenario(d, "syrm_sqw")
    L_d = nominal_motor(sc.plant["mag"], 2, 0.5 * sc.control.i_max)["L_d"]
    assert hardware_config(sc).hf_amp == scales(sc).current(100.0 / (4 * sc.pwm.f_sw * L_d)) == 122
