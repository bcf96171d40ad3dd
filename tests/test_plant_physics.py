"""Physics of the C plant against analytical results (docs/plant.md, "Verification").

Every expected value is computed here from a formula, independently of the plant's code.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from golden.openloop import PwmConfig, gate_edges
from golden.plant import Plant, default_params, merge

TICK = 100e6
V_H, F_SW = 100.0, 5e3
L_D, L_Q, R_S, PSI_F = 5.59e-3, 6.26e-3, 3.0, 0.147
POLE_PAIRS = 4


def params(**over) -> dict:
    """Table I machine, linear magnetics, ideal sensors; nested overrides by keyword."""
    return merge(default_params(), over)


def locked(theta_e: float, **over) -> dict:
    """Rotor held at electrical angle theta_e by the load machine (imposed zero speed)."""
    base = {"mech": {"imposed_speed": 1}, "theta_m0": theta_e / 4}
    return merge(params(**base), over)


def alpha_beta(i_abc: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    i_a, i_b, i_c = i_abc[:, 0], i_abc[:, 1], i_abc[:, 2]
    return (2 * i_a - i_b - i_c) / 3, (i_b - i_c) / math.sqrt(3)


def square_wave_on_estimated_d(theta_hat: float, n_periods: int):
    """Ideal +-V_H square wave on the estimated d-axis at F_SW (Benevieri et al. 2023, eq. (14)).

    -V_H while the carrier rises, +V_H while it falls; the first segment lasts a quarter period so
    that the triangular HF current is centred on zero.
    """
    half = int(TICK / F_SW / 2)
    ticks = [0] + [half // 2 + k * half for k in range(2 * n_periods)]
    signs = [-1.0] + [1.0 if k % 2 == 0 else -1.0 for k in range(2 * n_periods)]
    c, s = math.cos(theta_hat), math.sin(theta_hat)
    volts = []
    for sg in signs:
        v_al, v_be = sg * V_H * c, sg * V_H * s
        volts.append([v_al, -0.5 * v_al + math.sqrt(3) / 2 * v_be, -0.5 * v_al - math.sqrt(3) / 2 * v_be])
    return np.array(ticks), np.array(volts)


@pytest.mark.parametrize("err_deg", [0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 90.0])
def test_locked_rotor_hf_currents_follow_eq18(err_deg):
    """Peak-to-peak HF currents in the estimated frame vs Benevieri et al. 2023, eq. (18) and its d twin.

    eq. (18): i_qh = V_h/(8 f_sw) * (L_q - L_d)/(L_d L_q) * (-cw) * sin(2 err), cw in [-1, 1]
    d-axis:   i_dh = V_h/(4 f_sw) * (cos^2(err)/L_d + sin^2(err)/L_q) * (-cw)
    """
    theta = 0.4
    err = math.radians(err_deg)
    theta_hat = theta - err
    ticks, volts = square_wave_on_estimated_d(theta_hat, n_periods=6)
    plant = Plant(locked(theta))
    period = int(TICK / F_SW)
    samples = np.arange(4 * period, 6 * period + 1, 100)  # last two periods, every 1 us
    out = plant.run(ticks, samples, volts=volts, truth=True)
    i_al, i_be = alpha_beta(out["truth"]["i_abc"])
    i_dh = math.cos(theta_hat) * i_al + math.sin(theta_hat) * i_be
    i_qh = -math.sin(theta_hat) * i_al + math.cos(theta_hat) * i_be

    pp_d = V_H / (2 * F_SW) * (math.cos(err) ** 2 / L_D + math.sin(err) ** 2 / L_Q)
    pp_q = V_H / (4 * F_SW) * (L_Q - L_D) / (L_D * L_Q) * abs(math.sin(2 * err))
    assert np.ptp(i_dh) == pytest.approx(pp_d, rel=5e-3)
    pp_q_45 = V_H / (4 * F_SW) * (L_Q - L_D) / (L_D * L_Q)
    if abs(math.sin(2 * err)) > 0.2:
        assert np.ptp(i_qh) == pytest.approx(pp_q, rel=5e-3)
    else:
        assert abs(np.ptp(i_qh) - pp_q) < 5e-3 * pp_q_45
    # sign convention: the q response is the d response times (L_q - L_d) sin(2 err) / (2 L_d L_q (...))
    slope = np.polyfit(i_dh - i_dh.mean(), i_qh - i_qh.mean(), 1)[0]
    expected = 0.5 * (L_Q - L_D) / (L_D * L_Q) * math.sin(2 * err) / (
        math.cos(err) ** 2 / L_D + math.sin(err) ** 2 / L_Q)
    assert slope == pytest.approx(expected, rel=2e-2, abs=2e-4)


@pytest.mark.parametrize("theta_e, axis", [(0.0, "d"), (0.7, "d"), (0.7, "q")])
def test_current_step_response_is_exponential(theta_e, axis):
    """Locked rotor, voltage step on one rotor axis: i = V/R (1 - exp(-t R/L))."""
    v = 30.0
    ang = theta_e if axis == "d" else theta_e + math.pi / 2
    inductance = L_D if axis == "d" else L_Q
    v_al, v_be = v * math.cos(ang), v * math.sin(ang)
    v_abc = [v_al, -0.5 * v_al + math.sqrt(3) / 2 * v_be, -0.5 * v_al - math.sqrt(3) / 2 * v_be]
    plant = Plant(locked(theta_e))
    samples = np.arange(0, 500_001, 1000)  # 5 ms = 2.7 time constants
    out = plant.run([0], samples, volts=[v_abc], truth=True)
    t = samples / TICK
    expected = v / R_S * (1 - np.exp(-t * R_S / inductance))
    got = out["truth"]["i_d" if axis == "d" else "i_q"]
    other = out["truth"]["i_q" if axis == "d" else "i_d"]
    assert np.max(np.abs(got - expected)) < 1e-9 * v / R_S
    assert np.max(np.abs(other)) < 1e-9 * v / R_S
    # the running integrals (struct plant_state Q_d, Q_q, E_cu, T_int, T2_int; hfi.ripple), in closed form:
    # int i dt = I (t - tau (1 - e)), int i^2 dt = I^2 (t - 2 tau (1 - e) + tau/2 (1 - e^2)), e = exp(-t/tau)
    i_ss, tau = v / R_S, inductance / R_S
    e = np.exp(-t / tau)
    charge = i_ss * (t - tau * (1 - e))
    square = i_ss ** 2 * (t - 2 * tau * (1 - e) + tau / 2 * (1 - e ** 2))
    truth = out["truth"]
    assert np.max(np.abs(truth["Q_d" if axis == "d" else "Q_q"] - charge)) < 1e-9 * i_ss * t[-1]
    assert np.max(np.abs(truth["Q_q" if axis == "d" else "Q_d"])) < 1e-9 * i_ss * t[-1]
    assert np.max(np.abs(truth["E_cu"] - 1.5 * R_S * square)) < 1e-9 * 1.5 * v * i_ss * t[-1]
    # torque 1.5 p (psi_d i_q - psi_q i_d): 0 for a d step, 1.5 p psi_f i_q for a q step
    torque = 1.5 * POLE_PAIRS * PSI_F * charge if axis == "q" else 0 * t
    assert np.max(np.abs(truth["T_int"] - torque)) < 1e-9 * 1.5 * POLE_PAIRS * PSI_F * i_ss * t[-1]
    k_t = 1.5 * POLE_PAIRS * PSI_F if axis == "q" else 0.0
    assert np.max(np.abs(truth["T2_int"] - k_t ** 2 * square)) < 1e-9 * (1.5 * POLE_PAIRS * PSI_F * i_ss) ** 2 * t[-1]


def test_load_torque_decelerates_at_TL_over_J():
    """No electromagnetic torque (psi_f = 0, round rotor, no voltage): omega = w0 - T_L t / J,
    theta = th0 + w0 t - T_L t^2 / (2 J)."""
    J, T_L, w0 = 4e-3, 0.5, 20.0
    p = params(mag={"psi_f": 0.0, "L_d": L_Q}, mech={"J": J, "B": 0.0, "T_c": 0.0},
               load={"t": [0.0], "v": [T_L]}, omega_m0=w0)
    plant = Plant(p)
    samples = np.arange(0, 2_000_001, 100_000)
    out = plant.run([0], samples, volts=[[0.0, 0.0, 0.0]], truth=True)
    t = samples / TICK
    assert np.max(np.abs(out["truth"]["torque"])) == 0.0
    np.testing.assert_allclose(out["truth"]["omega_m"], w0 - T_L / J * t, rtol=0, atol=1e-10)
    theta = np.unwrap(out["truth"]["theta_m"])
    np.testing.assert_allclose(theta, w0 * t - T_L / (2 * J) * t ** 2, rtol=0, atol=1e-9)


def test_acceleration_equals_net_torque_over_J():
    """Rotating-voltage start under load: d(omega)/dt == (T_e - T_L - B omega)/J at every sample
    (central differences of the sampled speed)."""
    J, B, T_L = 4e-3, 2e-4, 0.3
    p = params(mech={"J": J, "B": B, "T_c": 0.0}, load={"t": [0.0], "v": [T_L]})
    plant = Plant(p)
    # slow open-loop V/f: 60 V at 10 Hz electrical, updated every 10 us
    ticks = np.arange(0, 3_000_000, 1000)
    th = 2 * math.pi * 10 * ticks / TICK
    v = 60.0
    volts = np.stack([v * np.cos(th), v * np.cos(th - 2 * math.pi / 3), v * np.cos(th + 2 * math.pi / 3)], axis=1)
    samples = np.arange(1_000_000, 3_000_000, 50)
    tr = plant.run(ticks, samples, volts=volts, truth=True)["truth"]
    h = 50 / TICK
    dw = (tr["omega_m"][2:] - tr["omega_m"][:-2]) / (2 * h)
    rhs = (tr["torque"][1:-1] - tr["load_torque"][1:-1] - B * tr["omega_m"][1:-1]) / J
    # skip samples next to a voltage update (the torque has a kink there)
    smooth = (samples[1:-1] % 1000 != 0) & (samples[1:-1] % 1000 != 50) & (samples[1:-1] % 1000 != 950)
    scale = np.max(np.abs(rhs))
    assert scale > 10.0  # the test really accelerates the rotor
    assert np.max(np.abs(dw - rhs)[smooth]) < 1e-5 * scale


def magnetic_energy(mag: dict, psi_d: np.ndarray, psi_q: np.ndarray) -> np.ndarray:
    """Stored magnetic energy [J] (amplitude-invariant frame: 1.5 * integral of i . dpsi), from the
    closed forms of the models' energy functions (docs/plant.md)."""
    x = psi_d - mag["psi_f"]
    if mag["kind"] == 0:
        return 1.5 * (x ** 2 / (2 * mag["L_d"]) + psi_q ** 2 / (2 * mag["L_q"]))
    if mag["kind"] == 1:
        a, S, pf = mag["dsat_a"], mag["dsat_S"], mag["psi_f"]
        L0 = mag["L_d"] * (1 + a * (S + 1))
        h_pf = pf / L0 * (1 + a)

        def prim(z):  # integral of h(z) - h(psi_f)
            return z ** 2 / (2 * L0) + a * np.abs(z) ** (S + 2) / ((S + 2) * L0 * pf ** S) - h_pf * z
        return 1.5 * (prim(psi_d) - prim(pf) + psi_q ** 2 / (2 * mag["L_q"]))
    raise AssertionError("no closed form")


@pytest.mark.parametrize("mag_over", [{"kind": 0}, {"kind": 1, "dsat_a": 0.08, "dsat_S": 4}])
def test_energy_balance_through_pwm(mag_over):
    """Gate-level PWM with dead time, V/f start under load and friction:
    E_in = E_cu + E_mech + (W_mag(end) - W_mag(start)) within 0.1 % of E_in."""
    p = params(mag=mag_over, mech={"J": 2e-3, "B": 1e-4, "T_c": 0.02}, load={"t": [0.0], "v": [0.4]})
    plant = Plant(p)
    cfg = PwmConfig()
    n = 200  # periods = 40 ms
    k = np.arange(2 * n)
    th = 2 * math.pi * 8 * k * cfg.half / TICK + 0.3
    v = 40.0
    v_abc = np.stack([v * np.cos(th), v * np.cos(th - 2 * math.pi / 3), v * np.cos(th + 2 * math.pi / 3)], axis=1)
    cmp = np.rint((0.5 + v_abc / 560.0) * cfg.half).astype(np.int64)
    ticks, masks = gate_edges(cfg, cmp)
    tr = plant.run(ticks, [0, 2 * n * cfg.half], gates=masks, truth=True)["truth"]
    end = tr[-1]
    w = magnetic_energy(p["mag"], tr["psi_d"], tr["psi_q"])
    assert end["E_in"] > 0.5  # real work was done
    assert abs(end["omega_m"]) > 1.0
    balance = end["E_cu"] + end["E_mech"] + (w[-1] - w[0])
    assert balance == pytest.approx(end["E_in"], rel=1e-3)


def pwm_node_mean(p: dict, cmp_abc, settle_periods=50):
    """Hold constant compare values; sample one period at every tick after settling.

    Returns (mean node voltages, mean currents, (min, max) of the phase-a current over the dead time
    after its high switch turns off).
    """
    cfg = PwmConfig()
    plant = Plant(p)
    n = settle_periods + 1
    cmp = np.tile(np.asarray(cmp_abc, dtype=np.int64), (2 * n, 1))
    ticks, masks = gate_edges(cfg, cmp)
    start = settle_periods * 2 * cfg.half
    samples = np.arange(start, start + 2 * cfg.half)
    tr = plant.run(ticks, samples, gates=masks, truth=True)["truth"]
    window = tr["i_abc"][cmp_abc[0]:cmp_abc[0] + cfg.dead_ticks + 1, 0]  # signal falls at start + compare
    return tr["v_node"].mean(axis=0), tr["i_abc"].mean(axis=0), (window.min(), window.max())


def test_dead_time_voltage_error_is_sign_i_vdc_td_fsw():
    """Ideal diodes: mean phase-node voltage = duty * V_dc - sign(i) * V_dc * t_d * f_sw, exactly."""
    cfg = PwmConfig()
    cmp = [6000, 4500, 4500]  # v_a > 0 -> i_a > 0, i_b, i_c < 0
    mean_v, i, _ = pwm_node_mean(locked(0.0), cmp)
    ideal = np.array(cmp) / cfg.half * 560.0
    assert i[0] > 0.5 and i[1] < -0.2 and i[2] < -0.2
    expected = ideal - np.sign(i) * 560.0 * cfg.dead_time * cfg.f_sw
    np.testing.assert_allclose(mean_v, expected, rtol=0, atol=1e-9)


def capacitive_loss_fraction(i: float, c_node: float, t_d: float, v_dc: float = 560.0) -> float:
    """Dead-time volt-second loss with a node capacitance, as a fraction of the ideal-diode loss
    V_dc t_d, for a constant current i: the node falls as V_dc - i t / C; the ramp t_r = V_dc C / i.
    1 - t_r / (2 t_d) if the ramp ends inside the dead time, else i t_d / (2 C V_dc)."""
    t_r = v_dc * c_node / i
    return 1 - t_r / (2 * t_d) if t_r <= t_d else i * t_d / (2 * c_node * v_dc)


@pytest.mark.parametrize("c_node, cmp_a", [(1e-9, 6000), (2e-9, 5300), (1e-9, 5120), (2e-9, 5060)])
def test_node_capacitance_softens_dead_time_error(c_node, cmp_a):
    """The loss fraction grows with the current, so with the phase current between i_min and i_max
    over the dead time it lies between the constant-current values at i_min and i_max."""
    cfg = PwmConfig()
    cmp_bc = cfg.half - (cmp_a - cfg.half // 2) // 2 - cfg.half // 2
    mean_v, _, (i_min, i_max) = pwm_node_mean(locked(0.0, inv={"C_node": c_node}), [cmp_a, cmp_bc, cmp_bc])
    frac = (cmp_a / cfg.half * 560.0 - mean_v[0]) / (560.0 * cfg.dead_time * cfg.f_sw)
    assert i_min > 0.05
    lo = capacitive_loss_fraction(i_min, c_node, cfg.dead_time)
    hi = capacitive_loss_fraction(i_max, c_node, cfg.dead_time)
    tick_res = 1.5 / TICK / cfg.dead_time  # a ramp sampled at every tick: +-1.5 ticks of the window
    assert lo - tick_res <= frac <= hi + tick_res
    assert hi - lo < 0.35  # the bracket is informative


def test_node_capacitance_large_current_ramp():
    """At 13.7 A the ramp (41 ns) is short: loss = 1 - t_r / (2 t_d), to the resolution of a ramp
    sampled at every 10 ns tick (1.5 ticks of the 4 us window)."""
    cfg = PwmConfig()
    mean_v, _, (i_min, i_max) = pwm_node_mean(locked(0.0, inv={"C_node": 1e-9}), [6000, 4500, 4500])
    frac = (6000 / cfg.half * 560.0 - mean_v[0]) / (560.0 * cfg.dead_time * cfg.f_sw)
    assert i_max - i_min < 0.05 * i_min
    tick_res = 1.5 / TICK / cfg.dead_time
    assert frac == pytest.approx(capacitive_loss_fraction(i_min, 1e-9, cfg.dead_time), abs=tick_res)
