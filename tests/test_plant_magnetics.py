"""Magnetic models of the plant: inversion, incremental inductances, reciprocity, co-energy torque,
flux-map tables (docs/plant.md, "Magnetic models")."""

from __future__ import annotations

import math

import numpy as np
import pytest

from golden.plant import Plant, default_params, mag_eval, merge
from golden.plant.fluxmap import (incremental_inductance, psi_from_current, table_from_flux_map,
                                  table_from_model)

LINEAR = {"kind": 0, "psi_f": 0.147, "L_d": 5.59e-3, "L_q": 6.26e-3}
DSAT = {"kind": 1, "psi_f": 0.147, "L_d": 5.59e-3, "L_q": 6.26e-3, "dsat_a": 0.05, "dsat_S": 4}
# algebraic model with cross-saturation (coefficient magnitudes of a 1 kW-class SyRM, our axes:
# d = low inductance); with and without a magnet
ALGEBRAIC = {"kind": 2, "psi_f": 0.0, "a_d0": 8.0, "a_dd": 300.0, "S": 2, "a_q0": 1.2, "a_qq": 2.5, "T": 5,
             "a_dq": 40.0, "U": 1, "V": 0}
ALGEBRAIC_PM = dict(ALGEBRAIC, psi_f=0.05)
MODELS = {"linear": LINEAR, "dsat": DSAT, "algebraic": ALGEBRAIC, "algebraic_pm": ALGEBRAIC_PM}
CURRENTS = [(0.0, 0.0), (2.0, 0.5), (-2.0, 1.5), (1.0, -3.0), (-0.5, -0.7)]


@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize("i_d, i_q", CURRENTS)
def test_flux_and_current_maps_invert_each_other(name, i_d, i_q):
    mag = MODELS[name]
    psi = psi_from_current(mag, i_d, i_q)
    back = mag_eval(mag, *psi)[:2]
    np.testing.assert_allclose(back, [i_d, i_q], rtol=0, atol=1e-12)


@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize("i_d, i_q", CURRENTS)
def test_jacobian_matches_finite_differences(name, i_d, i_q):
    mag = MODELS[name]
    psi = psi_from_current(mag, i_d, i_q)
    jac = mag_eval(mag, *psi)[2:].reshape(2, 2)
    h = 1e-6
    fd = np.empty((2, 2))
    for col in range(2):
        dp = np.zeros(2)
        dp[col] = h
        fd[:, col] = (mag_eval(mag, *(psi + dp))[:2] - mag_eval(mag, *(psi - dp))[:2]) / (2 * h)
    np.testing.assert_allclose(jac, fd, rtol=1e-6, atol=1e-6 * np.max(np.abs(fd)))
    # reciprocity: the models derive from an energy function, so the Jacobian is symmetric
    assert jac[0, 1] == pytest.approx(jac[1, 0], rel=1e-12, abs=1e-15)


def test_linear_incremental_inductances_are_the_parameters():
    np.testing.assert_allclose(incremental_inductance(LINEAR, 0.2, 0.01), np.diag([5.59e-3, 6.26e-3]), rtol=1e-14)


def test_dsat_incremental_inductance_at_zero_current_is_L_d_and_asymmetric():
    """MAG_DSAT: l_d(i_d = 0) = L_d; at +I it is lower than at -I (what polarity detection uses):
    l_d = 1 / h'(psi_d), h'(x) = (1 + a (S+1) |x/psi_f|^S) / L_d0, L_d0 = L_d (1 + a (S+1))."""
    a, S, pf, L_d = DSAT["dsat_a"], DSAT["dsat_S"], DSAT["psi_f"], DSAT["L_d"]
    L0 = L_d * (1 + a * (S + 1))
    assert incremental_inductance(DSAT, pf, 0.0)[0, 0] == pytest.approx(L_d, rel=1e-14)
    for current in (2.2, -2.2):
        psi_d = psi_from_current(DSAT, current, 0.0)[0]
        expected = L0 / (1 + a * (S + 1) * abs(psi_d / pf) ** S)
        assert incremental_inductance(DSAT, psi_d, 0.0)[0, 0] == pytest.approx(expected, rel=1e-12)
    l_pos = incremental_inductance(DSAT, psi_from_current(DSAT, 2.2, 0.0)[0], 0.0)[0, 0]
    l_neg = incremental_inductance(DSAT, psi_from_current(DSAT, -2.2, 0.0)[0], 0.0)[0, 0]
    assert l_pos < L_d < l_neg


def coenergy(mag: dict, i_d: float, i_q: float, n: int = 24) -> float:
    """Co-energy per unit of the amplitude-invariant frame: integral of psi . di along the straight
    path from 0 to i (Gauss-Legendre), using the inverted model."""
    x, w = np.polynomial.legendre.leggauss(n)
    s = 0.5 * (x + 1)
    total = 0.0
    for sk, wk in zip(s, w):
        psi = psi_from_current(mag, sk * i_d, sk * i_q)
        total += 0.5 * wk * (psi[0] * i_d + psi[1] * i_q)
    return total


@pytest.mark.parametrize("name", ["linear", "dsat", "algebraic_pm"])
def test_torque_from_coenergy_matches_dq_formula(name):
    """T = p dW'/dtheta at constant stator (alpha-beta) currents, with W' = 1.5 * co-energy of
    the rotor-frame currents, equals 1.5 p (psi_d i_q - psi_q i_d)."""
    mag, p = MODELS[name], 2
    i_ab = np.array([1.3, -0.9])
    theta, h = 0.35, 1e-4

    def w_of(th):
        c, s = math.cos(th), math.sin(th)
        return 1.5 * coenergy(mag, c * i_ab[0] + s * i_ab[1], -s * i_ab[0] + c * i_ab[1])

    torque_coenergy = p * (w_of(theta + h) - w_of(theta - h)) / (2 * h)
    c, s = math.cos(theta), math.sin(theta)
    i_d, i_q = c * i_ab[0] + s * i_ab[1], -s * i_ab[0] + c * i_ab[1]
    psi = psi_from_current(mag, i_d, i_q)
    torque_dq = 1.5 * p * (psi[0] * i_q - psi[1] * i_d)
    assert abs(torque_dq) > 1e-3
    assert torque_coenergy == pytest.approx(torque_dq, rel=1e-6)


def test_table_from_model_is_exact_on_nodes_and_close_between():
    grid_d, grid_q = np.linspace(-0.3, 0.3, 61), np.linspace(-0.6, 0.6, 121)
    tab = table_from_model(ALGEBRAIC, grid_d, grid_q)
    for pd, pq in [(grid_d[7], grid_q[90]), (grid_d[40], grid_q[3])]:
        # a node reproduces the sampled value up to the rounding of its grid coordinate
        np.testing.assert_allclose(mag_eval(tab, pd, pq)[:2], mag_eval(ALGEBRAIC, pd, pq)[:2], rtol=1e-12)
    # between nodes: bilinear interpolation error, bounded by h^2/8 * max|f''| (about 0.5 % here)
    for pd, pq in [(0.105, 0.205), (-0.2175, 0.4525), (0.0025, -0.0975)]:
        exact = mag_eval(ALGEBRAIC, pd, pq)[:2]
        np.testing.assert_allclose(mag_eval(tab, pd, pq)[:2], exact, rtol=1e-2, atol=2e-3)


def test_table_from_measured_flux_map_inverts_it():
    """A 'measured' flux map psi(i) (here made from the algebraic model) becomes a current table i(psi)
    that reproduces the model to the interpolation error."""
    id_grid, iq_grid = np.linspace(-4, 4, 41), np.linspace(-4, 4, 41)
    psi_d = np.empty((41, 41))
    psi_q = np.empty((41, 41))
    for r, iq in enumerate(iq_grid):
        for c, i_d in enumerate(id_grid):
            psi_d[r, c], psi_q[r, c] = psi_from_current(ALGEBRAIC, i_d, iq)
    tab = table_from_flux_map(id_grid, iq_grid, psi_d, psi_q, np.linspace(-0.2, 0.2, 21), np.linspace(-0.6, 0.6, 31))
    assert tab["psi_f"] == pytest.approx(0.0, abs=1e-12)
    for pd, pq in [(0.05, 0.3), (-0.1, -0.2), (0.12, 0.01)]:
        np.testing.assert_allclose(mag_eval(tab, pd, pq)[:2], mag_eval(ALGEBRAIC, pd, pq)[:2], rtol=3e-2, atol=3e-2)


def test_plant_with_table_follows_the_model_it_samples():
    """Locked-rotor voltage step: the table plant tracks the algebraic plant."""
    tab = table_from_model(ALGEBRAIC, np.linspace(-0.3, 0.3, 121), np.linspace(-0.8, 0.8, 161))
    currents = []
    for mag in (ALGEBRAIC, tab):
        p = merge(default_params(), {"mag": mag, "R_s": 4.5, "mech": {"imposed_speed": 1}, "theta_m0": 0.2})
        v = [40.0, -10.0, -30.0]
        out = Plant(p).run([0], np.arange(0, 2_000_001, 50_000), volts=[v], truth=True)  # 20 ms
        currents.append(np.stack([out["truth"]["i_d"], out["truth"]["i_q"]], axis=1))
    scale = np.max(np.abs(currents[0]))
    assert scale > 1.0
    assert np.max(np.abs(currents[1] - currents[0])) < 5e-3 * scale


def test_psi_from_current_falls_back_to_backtracking():
    """A stiff model (the 003 SyRM's with its cross-saturation coefficient 10^12, as a mistyped controller model
    may have it) cycles under the damped Newton steps alone; the second, backtracking attempt finds the fluxes
    whose currents are the ones asked for."""
    from golden.motors import preset
    from golden.plant.binding import mag_eval
    from golden.plant.fluxmap import psi_from_current
    mag = dict(preset("varatharajan2020_syrm")["mag"], a_dq=1e12)
    for i in ((-3.959897740716342, 0.5649866220271175), (-5.932041233300841, 4.058453283754617)):
        psi = psi_from_current(mag, *i)
        np.testing.assert_allclose(mag_eval(mag, *psi)[:2], i, rtol=1e-12)
