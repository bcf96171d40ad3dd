"""Tests of the motor presets (golden/motors.py) against the paper tables and docs/motors.md.

Only numpy and math: the magnetic models are re-implemented here from the formulas in
golden/plant/src/plant_api.h, independently of the C plant (whose binding may not be built).
"""

from __future__ import annotations

import math
import re
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from golden import motors  # noqa: E402

SQRT_3_2 = math.sqrt(1.5)  # peak phase -> line-to-line rms


# ---- independent models (plant_api.h formulas) ------------------------------------------------------
def dsat_h(m: dict, x: float) -> float:
    """h(x) = x/L_d0 (1 + a|x/psi_f|^S) with L_d0 chosen so that the incremental L at i = 0 is L_d."""
    L_d0 = m["L_d"] * (1.0 + m["dsat_a"] * (m["dsat_S"] + 1))
    return x / L_d0 * (1.0 + m["dsat_a"] * abs(x / m["psi_f"]) ** m["dsat_S"])


def dsat_dh(m: dict, x: float) -> float:
    L_d0 = m["L_d"] * (1.0 + m["dsat_a"] * (m["dsat_S"] + 1))
    return (1.0 + m["dsat_a"] * (m["dsat_S"] + 1) * abs(x / m["psi_f"]) ** m["dsat_S"]) / L_d0


def dsat_psi_d(m: dict, i_d: float) -> float:
    """Invert i_d = h(psi_d) - h(psi_f) by Newton's method."""
    x = m["psi_f"] + m["L_d"] * i_d
    for _ in range(100):
        dx = (dsat_h(m, x) - dsat_h(m, m["psi_f"]) - i_d) / dsat_dh(m, x)
        x -= dx
        if abs(dx) < 1e-15:
            break
    return x


def alg_currents(m: dict, psi_d, psi_q):
    x, y = np.asarray(psi_d, float) - m["psi_f"], np.asarray(psi_q, float)
    ax, ay = np.abs(x), np.abs(y)
    S, T, U, V = m["S"], m["T"], m["U"], m["V"]
    i_d = (m["a_d0"] + m["a_dd"] * ax**S + m["a_dq"] / (V + 2) * ax**U * ay ** (V + 2)) * x
    i_q = (m["a_q0"] + m["a_qq"] * ay**T + m["a_dq"] / (U + 2) * ax ** (U + 2) * ay**V) * y
    return i_d, i_q


def fd_jacobian(m: dict, psi_d: float, psi_q: float, h: float = 1e-4):
    """Central differences with one Richardson step: [[di_d/dpsi_d, di_d/dpsi_q], [di_q/dpsi_d, di_q/dpsi_q]]."""

    def central(step):
        jac = np.empty((2, 2))
        for k, (ed, eq) in enumerate(((step, 0.0), (0.0, step))):
            p = np.array(alg_currents(m, psi_d + ed, psi_q + eq))
            n = np.array(alg_currents(m, psi_d - ed, psi_q - eq))
            jac[:, k] = (p - n) / (2.0 * step)
        return jac

    return (4.0 * central(h / 2.0) - central(h)) / 3.0


def alg_fluxes(m: dict, i_d: float, i_q: float):
    """Invert the algebraic model with damped Newton steps on the finite-difference Jacobian."""
    psi = np.array([m["psi_f"] + i_d / m["a_d0"], i_q / m["a_q0"]])
    target = np.array([i_d, i_q])
    for _ in range(200):
        r = np.array(alg_currents(m, *psi)) - target
        if np.hypot(*r) < 1e-12:
            return float(psi[0]), float(psi[1])
        step = np.linalg.solve(fd_jacobian(m, *psi), r)
        lam = 1.0
        while lam > 1e-6 and np.hypot(*(np.array(alg_currents(m, *(psi - lam * step))) - target)) >= np.hypot(*r):
            lam *= 0.5
        psi = psi - lam * step
    raise AssertionError("flux inversion did not converge")


def fluxes(m: dict, i_d: float, i_q: float):
    if m["kind"] == motors.MAG_LINEAR:
        return m["psi_f"] + m["L_d"] * i_d, m["L_q"] * i_q
    if m["kind"] == motors.MAG_DSAT:
        return dsat_psi_d(m, i_d), m["L_q"] * i_q
    return alg_fluxes(m, i_d, i_q)


def torque(p: dict, i_d: float, i_q: float) -> float:
    psi_d, psi_q = fluxes(p["mag"], i_d, i_q)
    return 1.5 * p["mech"]["pole_pairs"] * (psi_d * i_q - psi_q * i_d)


def omega_e(p: dict) -> float:
    return p["rated"]["speed_rpm"] * 2.0 * math.pi / 60.0 * p["mech"]["pole_pairs"]


def header_fields(struct: str) -> set[str]:
    """Field names of a struct in golden/plant/src/plant_api.h."""
    text = (ROOT / "golden" / "plant" / "src" / "plant_api.h").read_text()
    body = re.search(r"struct " + struct + r" \{(.*?)\};", text, re.DOTALL).group(1)
    body = re.sub(r"/\*.*?\*/", "", body, flags=re.DOTALL)
    names = set()
    for decl in body.split(";"):
        decl = decl.strip()
        if decl:
            for part in decl.split(",")[1:] + [decl.split(",")[0]]:
                names.add(re.findall(r"\w+", part.split("[")[0])[-1])
    return names


ALL = motors.names()


# ---- structure ----------------------------------------------------------------------------------------
def test_preset_names():
    assert ALL == ["benevieri2023_table1", "benevieri2023_table3", "tap2023_pmasynrm", "xue2022_pmsm",
                   "varatharajan2020_syrm"]


@pytest.mark.parametrize("name", ALL)
def test_required_fields_positive(name):
    p = motors.preset(name)
    assert set(p) == {"R_s", "mag", "mech", "rated"}
    assert p["R_s"] > 0.0
    m = p["mag"]
    if m["kind"] in (motors.MAG_LINEAR, motors.MAG_DSAT):
        assert m["psi_f"] > 0.0 and m["L_d"] > 0.0 and m["L_q"] > 0.0
        assert m["L_d"] < m["L_q"], "plant convention: d = magnet axis, L_d < L_q for these machines"
        if m["kind"] == motors.MAG_DSAT:
            assert m["dsat_a"] > 0.0
            assert isinstance(m["dsat_S"], int) and m["dsat_S"] >= 2 and m["dsat_S"] % 2 == 0
    else:
        assert m["kind"] == motors.MAG_ALGEBRAIC
        assert m["psi_f"] == 0.0
        for k in ("a_d0", "a_dd", "a_q0", "a_qq", "a_dq"):
            assert m[k] > 0.0, k
        for k in ("S", "T", "U", "V"):
            assert isinstance(m[k], int) and 0 <= m[k] <= 16, k
    me = p["mech"]
    assert set(me) == {"pole_pairs", "J", "B", "T_c", "w_stick"}
    assert isinstance(me["pole_pairs"], int) and me["pole_pairs"] >= 1
    for k in ("J", "B", "T_c", "w_stick"):
        assert me[k] > 0.0, k
    r = p["rated"]
    assert set(r) == {"torque", "speed_rpm", "current_peak", "voltage", "power", "V_dc", "i_d", "i_q"}
    for k in ("torque", "speed_rpm", "current_peak", "voltage", "power", "V_dc", "i_q"):
        assert r[k] > 0.0, k
    assert r["i_d"] <= 0.0
    assert math.hypot(r["i_d"], r["i_q"]) == pytest.approx(r["current_peak"], abs=1e-3)
    # the rated values agree with each other: power = torque * speed within 2 % (the tables round the
    # power: 7.1 N*m at 1500 r/min is 1115 W for "1.1 kW")
    assert r["torque"] * r["speed_rpm"] * math.pi / 30.0 == pytest.approx(r["power"], rel=0.02)


@pytest.mark.parametrize("name", ALL)
def test_plant_fields_match_header(name):
    fields = motors.plant_fields(name)
    assert set(fields) == {"R_s", "mag", "mech"}
    assert set(fields["mag"]) <= header_fields("mag_params")
    assert set(fields["mech"]) <= header_fields("mech_params")
    assert motors.plant_fields(motors.preset(name)) == fields


def test_preset_is_a_deep_copy():
    p = motors.preset("benevieri2023_table1")
    p["mag"]["L_d"] = 1.0
    p["rated"]["torque"] = 0.0
    assert motors.PRESETS["benevieri2023_table1"]["mag"]["L_d"] == 5.59e-3
    assert motors.preset("benevieri2023_table1")["rated"]["torque"] == 2.0


def test_unknown_preset_lists_names():
    with pytest.raises(KeyError) as err:
        motors.preset("no_such_motor")
    for name in ALL:
        assert name in str(err.value)


# ---- paper literals -------------------------------------------------------------------------------------
@pytest.mark.parametrize("name, psi_f, L_d, L_q, rated", [
    # Benevieri et al. 2023, Table I (2.2 A read as peak)
    ("benevieri2023_table1", 0.147, 5.59e-3, 6.26e-3, (2.0, 5000.0, 1040.0, 376.0, 2.2)),
    # Table III (3.6 A read as rms)
    ("benevieri2023_table3", 0.34, 4.9e-3, 5.3e-3, (10.0, 1995.0, 2090.0, 376.0, 3.6 * math.sqrt(2.0))),
])
def test_benevieri_table_literals(name, psi_f, L_d, L_q, rated):
    p = motors.preset(name)
    assert (p["mag"]["psi_f"], p["mag"]["L_d"], p["mag"]["L_q"], p["mech"]["pole_pairs"]) == (psi_f, L_d, L_q, 4)
    r = p["rated"]
    assert (r["torque"], r["speed_rpm"], r["power"], r["voltage"], r["current_peak"]) == rated


def test_xue_and_syrm_literals():
    x = motors.preset("xue2022_pmsm")
    assert (x["R_s"], x["mag"]["L_d"], x["mag"]["L_q"], x["mech"]["pole_pairs"]) == (0.19, 3.53e-3, 7.48e-3, 4)
    assert (x["rated"]["V_dc"], x["rated"]["speed_rpm"], x["rated"]["power"]) == (540.0, 1200.0, 3000.0)
    s = motors.preset("varatharajan2020_syrm")
    assert (s["R_s"], s["mech"]["J"], s["mech"]["pole_pairs"]) == (4.5, 0.04, 2)
    r = s["rated"]
    assert (r["torque"], r["speed_rpm"], r["power"], r["voltage"]) == (7.1, 1500.0, 1100.0, 340.0)
    assert r["current_peak"] == 2.3 * math.sqrt(2.0)


# ---- 000: conversion of the paper's frame (d = high inductance, magnet on -q) ---------------------------------
def test_tap_conversion_literals():
    p = motors.preset("tap2023_pmasynrm")
    assert p["mag"]["kind"] == motors.MAG_DSAT
    assert (p["mag"]["L_d"], p["mag"]["L_q"], p["mag"]["psi_f"]) == (0.067, 0.182, 0.096)
    assert (p["mag"]["dsat_a"], p["mag"]["dsat_S"]) == (0.00033, 4)
    assert (p["R_s"], p["mech"]["pole_pairs"]) == (5.9, 2)
    assert p["rated"]["current_peak"] == 1.62 * math.sqrt(2.0)


def test_tap_conversion_same_machine():
    """Paper frame (L_d,p = 182 mH, L_q,p = 67 mH, psi_q,p = L_q,p i_q,p - lambda) at angle theta_p and
    plant frame at theta = theta_p - 90 deg describe the same stator flux and torque (the preset's data
    without its assumed saturation, which the paper does not have)."""
    m = dict(motors.preset("tap2023_pmasynrm")["mag"], kind=motors.MAG_LINEAR)
    p = 2
    rng = np.random.default_rng(0)
    for _ in range(20):
        th_p = rng.uniform(-math.pi, math.pi)
        i_ab = rng.uniform(-3.0, 3.0, 2)

        def park(th, v):
            return np.array([math.cos(th) * v[0] + math.sin(th) * v[1], -math.sin(th) * v[0] + math.cos(th) * v[1]])

        def inv_park(th, v):
            return np.array([math.cos(th) * v[0] - math.sin(th) * v[1], math.sin(th) * v[0] + math.cos(th) * v[1]])

        idp, iqp = park(th_p, i_ab)
        psi_p = np.array([0.182 * idp, 0.067 * iqp - 0.096])
        t_paper = 1.5 * p * (psi_p[0] * iqp - psi_p[1] * idp)
        th = th_p - math.pi / 2.0
        i_d, i_q = park(th, i_ab)
        assert (i_d, i_q) == pytest.approx((-iqp, idp), abs=1e-12)
        psi = np.array(fluxes(m, i_d, i_q))
        assert inv_park(th, psi) == pytest.approx(inv_park(th_p, psi_p), abs=1e-12)
        assert 1.5 * p * (psi[0] * i_q - psi[1] * i_d) == pytest.approx(t_paper, abs=1e-12)


def test_tap_reluctance_torque_adds_with_negative_i_d():
    p = motors.preset("tap2023_pmasynrm")
    p["mag"] = m = dict(p["mag"], kind=motors.MAG_LINEAR)      # the paper's (linear) machine
    # T = 1.5 p (psi_f i_q + (L_d - L_q) i_d i_q): (L_d - L_q) < 0, so i_d < 0 adds reluctance torque
    assert torque(p, -1.0, 1.0) > torque(p, 0.0, 1.0) > torque(p, 1.0, 1.0)
    assert torque(p, -1.0, 1.0) - torque(p, 0.0, 1.0) == pytest.approx(1.5 * 2 * (m["L_q"] - m["L_d"]), rel=1e-12)


# ---- computed checks of docs/motors.md --------------------------------------------------------------------
def test_table1_torque_constant_and_back_emf():
    p = motors.preset("benevieri2023_table1")
    k_t = 1.5 * p["mech"]["pole_pairs"] * p["mag"]["psi_f"]
    assert abs(k_t - 0.882) < 1e-12
    assert k_t * p["rated"]["current_peak"] == pytest.approx(1.9404, abs=1e-12)  # "1.94 N*m"
    e = p["mag"]["psi_f"] * omega_e(p)
    assert e == pytest.approx(307.88, abs=0.01)            # V peak phase
    assert e * SQRT_3_2 == pytest.approx(377.07, abs=0.01)  # V line rms, vs 376 V rated
    assert e * SQRT_3_2 == pytest.approx(p["rated"]["voltage"], rel=0.005)


def test_table3_torque_and_back_emf():
    p = motors.preset("benevieri2023_table3")
    k_t = 1.5 * p["mech"]["pole_pairs"] * p["mag"]["psi_f"]
    assert k_t == pytest.approx(2.04, abs=1e-12)
    assert k_t * 3.6 == pytest.approx(7.344, abs=1e-12)  # 3.6 A as a peak value: far below 10 N*m
    assert torque(p, p["rated"]["i_d"], p["rated"]["i_q"]) == pytest.approx(10.386, abs=1e-3)
    assert p["mag"]["psi_f"] * omega_e(p) * SQRT_3_2 == pytest.approx(347.98, abs=0.01)


@pytest.mark.parametrize("name, band, expected, current", [
    ("benevieri2023_table1", (0.05, 0.08), 0.0641, 2.2),
    ("benevieri2023_table3", (0.05, 0.08), 0.0630, 3.6 * math.sqrt(2.0)),
    ("tap2023_pmasynrm", (0.05, 0.08), 0.0665, 1.62 * math.sqrt(2.0)),
])
def test_dsat_asymmetry(name, band, expected, current):
    m = motors.preset(name)["mag"]
    assert m["kind"] == motors.MAG_DSAT
    assert 1.0 / dsat_dh(m, m["psi_f"]) == pytest.approx(m["L_d"], rel=1e-12)  # L_d = incremental at i = 0
    l_pos = 1.0 / dsat_dh(m, dsat_psi_d(m, +current))
    l_neg = 1.0 / dsat_dh(m, dsat_psi_d(m, -current))
    assert dsat_h(m, dsat_psi_d(m, current)) - dsat_h(m, m["psi_f"]) == pytest.approx(current, rel=1e-12)
    asym = 1.0 - l_pos / l_neg
    assert band[0] <= asym <= band[1]
    assert asym == pytest.approx(expected, abs=5e-5)


def test_dsat_incremental_inductances_table1():
    m = motors.preset("benevieri2023_table1")["mag"]
    assert 1.0 / dsat_dh(m, dsat_psi_d(m, 2.2)) == pytest.approx(5.391e-3, abs=1e-6)
    assert 1.0 / dsat_dh(m, dsat_psi_d(m, -2.2)) == pytest.approx(5.761e-3, abs=1e-6)


@pytest.mark.parametrize("name, t_doc", [
    ("benevieri2023_table1", 1.9406),
    ("benevieri2023_table3", 10.386),
    ("tap2023_pmasynrm", 1.3987),
    ("xue2022_pmsm", 23.874),
    ("varatharajan2020_syrm", 7.056),
])
def test_rated_point_torque_and_mtpa(name, t_doc):
    """Torque at the documented rated point (docs/motors.md, to 1 %), and that the point is the MTPA:
    moving the current angle by +-1 deg on the same circle lowers the torque."""
    p = motors.preset(name)
    r = p["rated"]
    t = torque(p, r["i_d"], r["i_q"])
    assert t == pytest.approx(t_doc, rel=0.01)
    amp, ang = math.hypot(r["i_d"], r["i_q"]), math.atan2(r["i_q"], r["i_d"])
    for d in (-1.0, 1.0):
        a = ang + math.radians(d)
        assert torque(p, amp * math.cos(a), amp * math.sin(a)) < t


def test_xue_assumed_flux():
    p = motors.preset("xue2022_pmsm")
    e_ll = p["mag"]["psi_f"] * omega_e(p) * SQRT_3_2
    assert e_ll == pytest.approx(307.81, abs=0.01)
    assert e_ll / (p["rated"]["V_dc"] / math.sqrt(2.0)) == pytest.approx(0.806, abs=1e-3)
    assert p["rated"]["torque"] == pytest.approx(23.873, abs=1e-3)
    assert torque(p, p["rated"]["i_d"], p["rated"]["i_q"]) == pytest.approx(p["rated"]["torque"], rel=1e-4)


# ---- 003: algebraic SyRM model ------------------------------------------------------------------------------
SYRM = motors.preset("varatharajan2020_syrm")
PSI_POINTS = [(0.05, 0.3), (-0.08, 0.9), (0.12, -1.1), (-0.15, -0.5), (0.2, 1.2), (-0.01, 0.02), (0.1, 0.7)]


@pytest.mark.parametrize("psi_d, psi_q", PSI_POINTS)
def test_syrm_reciprocity(psi_d, psi_q):
    jac = fd_jacobian(SYRM["mag"], psi_d, psi_q)
    assert jac[0, 1] == pytest.approx(jac[1, 0], rel=1e-9)
    assert jac[0, 1] != 0.0


def test_syrm_jacobian_positive_definite():
    m = SYRM["mag"]
    for psi_d in np.linspace(-0.25, 0.25, 11):
        for psi_q in np.linspace(-1.3, 1.3, 11):
            jac = fd_jacobian(m, psi_d + 1e-3, psi_q + 1e-3)
            assert jac[0, 0] > 0.0 and jac[1, 1] > 0.0
            assert np.linalg.det(jac) > 0.5 * jac[0, 0] * jac[1, 1]


def test_syrm_flux_map_shape():
    """The features documented in docs/motors.md: no saliency at i = 0, ribs, saturation, cross-saturation."""
    m = SYRM["mag"]
    assert m["a_q0"] / m["a_d0"] == pytest.approx(1.0, abs=0.02)  # l_q/l_d at i = 0: 0.99
    assert fluxes(m, 0.0, 1.0)[1] == pytest.approx(0.802, abs=1e-3)
    assert fluxes(m, 0.0, 3.0)[1] == pytest.approx(1.058, abs=1e-3)
    assert fluxes(m, -3.0, 0.0)[0] == pytest.approx(-0.136, abs=1e-3)
    drop = 1.0 - fluxes(m, -3.0, 1.25)[1] / fluxes(m, 0.0, 1.25)[1]
    assert drop == pytest.approx(0.065, abs=1e-3)
    psi = fluxes(m, SYRM["rated"]["i_d"], SYRM["rated"]["i_q"])
    l_mat = np.linalg.inv(fd_jacobian(m, *psi))
    assert l_mat[1, 1] / l_mat[0, 0] == pytest.approx(9.43, abs=0.01)  # d = the low-inductance axis


def test_syrm_rated_voltage():
    p = SYRM
    r = p["rated"]
    psi_d, psi_q = fluxes(p["mag"], r["i_d"], r["i_q"])
    w = omega_e(p)
    assert w * math.hypot(psi_d, psi_q) * SQRT_3_2 == pytest.approx(342.7, abs=0.1)
    v = math.hypot(p["R_s"] * r["i_d"] - w * psi_q, p["R_s"] * r["i_q"] + w * psi_d)
    assert v * SQRT_3_2 == pytest.approx(357.4, abs=0.1)
    assert v * SQRT_3_2 / r["voltage"] == pytest.approx(1.051, abs=1e-3)
