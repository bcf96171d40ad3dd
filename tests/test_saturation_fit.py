"""The algebraic saturation model (golden.saturation_fit) against the plant's C model, its inversion, and its fit
recovering a known machine from its own inductances (docs/commissioning.md, "The saturation model of a reluctance
machine"); the scenario's [model.saturation] table."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

from golden import saturation_fit as sf
from golden.control_config import controller_motor
from golden.motors import preset
from golden.plant.binding import MAG_KINDS, mag_eval
from golden.scenario import ScenarioError, parse_scenario

SYRM = dict(preset("varatharajan2020_syrm")["mag"])


def test_model_is_the_plants():
    """Currents and Jacobian equal the plant's MAG_ALGEBRAIC (C) at random fluxes of both signs."""
    rng = np.random.default_rng(3)
    for psi_d, psi_q in rng.uniform(-0.4, 0.4, (200, 2)) * (1.0, 3.0):
        ref = mag_eval(SYRM, psi_d, psi_q)
        i_d, i_q = sf.currents(SYRM, psi_d, psi_q)
        g_dd, g_dq, g_qq = sf.jacobian(SYRM, psi_d, psi_q)
        np.testing.assert_allclose([i_d, i_q, g_dd, g_dq, g_dq, g_qq], ref, rtol=1e-12, atol=1e-12)


def test_fluxes_invert_the_currents():
    """From the unsaturated start and from a warm start elsewhere: the currents of the fluxes found are the ones
    asked for."""
    i_d, i_q = np.meshgrid(np.linspace(-8, 8, 9), np.linspace(-8, 8, 9))
    for start in (None, (np.full(i_d.shape, 0.05), np.full(i_d.shape, -0.5))):
        psi_d, psi_q = sf.fluxes(SYRM, i_d, i_q, start=start)
        back = sf.currents(SYRM, psi_d, psi_q)
        np.testing.assert_allclose(back[0], i_d, atol=1e-11)
        np.testing.assert_allclose(back[1], i_q, atol=1e-11)


def synthetic(c: dict) -> sf.InductanceData:
    """The commissioning's data (golden.commission.saturation_data: a 5 x 3 map, the chords of stage lf at the scan's
    bias 0.5 A) computed exactly from the model ``c``."""
    rows = []
    for i_q in (0.0, 4.0, 8.0):
        for i_d in (-8.0, -4.0, 0.0, 4.0, 8.0):
            g = sf.jacobian(c, *sf.fluxes(c, i_d, i_q))
            L = np.linalg.inv(np.array([[g[0], g[1]], [g[1], g[2]]], dtype=float))
            rows.append((i_d, i_q, L[0, 0], L[0, 1], L[1, 1], 1.0 if i_d else 0.1, float(i_d != 0 and i_q != 0),
                         1.0 if i_q else 0.1))
    chords = []
    for axis, lo, hi in ((0, 0.4, 0.6), (1, 0.45, 0.55)):
        ends = [sf.fluxes(c, *((i, 0.0) if axis == 0 else (0.0, i)))[axis] for i in (lo, hi)]
        chords.append((axis, lo, hi, float(ends[1] - ends[0]) / (hi - lo), 2.0))
    return sf.InductanceData(np.array(rows), np.array(chords))


def test_fit_recovers_a_known_machine():
    """The 003 SyRM's own inductances: the descent from Hinkkanen et al.'s exponents (1, 5, 0, 1) finds the preset's
    (2, 7, 0, 1) and the coefficients within 0.1 %, the residual near zero."""
    model, rms = sf.fit_inductances(synthetic(SYRM))
    assert {k: model[k] for k in sf.EXPONENT_NAMES} == {k: SYRM[k] for k in sf.EXPONENT_NAMES}
    for k in sf.COEF_NAMES:
        assert model[k] == pytest.approx(SYRM[k], rel=1e-3), k
    assert rms < 1e-5


MODEL = {"R_s": "4.6 ohm", "L_d": "0.053 H", "L_q": "0.93 H", "psi_f": "0 Wb", "J": "0.04 kg*m^2"}


def with_model(model: dict) -> dict:
    """The 003 scenario's tree with ``[model]`` = ``model``."""
    with open("scenarios/varatharajan2020_speedrange.toml", "rb") as f:
        return {**tomllib.load(f), "model": model}


def test_model_saturation_table():
    """[model.saturation] gives the controller the algebraic model; a missing coefficient is refused by name, and so
    is a model without a flux solution within control.i_max."""
    sat = {k: SYRM[k] for k in sf.COEF_NAMES + sf.EXPONENT_NAMES}
    mag = controller_motor(parse_scenario(with_model({**MODEL, "saturation": sat}), "t")).mag
    assert mag["kind"] == MAG_KINDS["algebraic"] and all(mag[k] == sat[k] for k in sat)
    assert controller_motor(parse_scenario(with_model(MODEL), "t")).mag["kind"] == MAG_KINDS["linear"]
    with pytest.raises(ScenarioError, match=r"model\.saturation\.a_dq: missing"):
        parse_scenario(with_model({**MODEL, "saturation": {k: v for k, v in sat.items() if k != "a_dq"}}), "t")
    # a model that carries no current within i_max (its unsaturated inductance 10^12 H, the saturation beyond any
    # float) is refused with the first current it fails at, not left to the flux tables' inversion
    with pytest.raises(ScenarioError, match=r"model\.saturation: the model has no flux linkage for the currents"):
        parse_scenario(with_model({**MODEL, "saturation": {**sat, "a_d0": 1e-12, "S": 60}}), "t")
