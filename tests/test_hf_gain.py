"""The hardware's HF gain (golden.hf_gain): the ideal inverter's against the square-wave limit and the sensors' lag in
closed form, and the real inverter's node voltages against the dead time's and the node capacitance's closed forms
(docs/commissioning.md)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from golden.control_config import hardware_config, scales
from golden.fpga.adc_trigger import sample_phases
from golden.fpga.carrier import counter
from golden.fpga.cordic import demod_weight
from golden.hf_gain import InverterModel, OperatingPoint, hf_response, node_voltages
from golden.scenario import load_scenario

DEFAULT = "scenarios/fullload_start.toml"
TICK_HZ = 100e6


@pytest.fixture(scope="module")
def drive():
    sc = load_scenario(DEFAULT)
    return sc, hardware_config(sc), scales(sc)


def test_hf_response_square_wave_limit(drive):
    """A small V_H comes as short pulses in the middle of each half period: the current of 1 H is a square wave
    of amplitude V / (4 f_sw), high around the carrier bottom; its weighted sum (independent of the modulator
    here) matches the hardware model within 1 %."""
    sc, hw, scl = drive
    v_h = 300                                         # 5 V on 560 V
    g_d, g_q = hf_response(hw, scl, sc.pwm.tick_hz, v_h, 0, 32767)
    H, P = hw.pwm_half, 2 * hw.pwm_half
    phase = (np.sort((sample_phases(hw.adc_mode, H, hw.os_ticks) - H // 2) % P) + H // 2) % P
    w = np.asarray(demod_weight(counter(phase, H), H, hw.cw_angle_step), dtype=float)
    amp = v_h * scl.v_lsb / (4 * scl.f_sw) / scl.i_lsb
    square = np.where((phase < H // 2) | (phase >= P - H // 2), amp, -amp)
    assert g_d == pytest.approx(float(square @ w) / 2**15, rel=0.01)
    assert abs(g_q) < 0.01 * abs(g_d)


@pytest.mark.parametrize("bw", [20e3, 5e3])
def test_hf_response_through_the_sensors_lag(bw, drive):
    """The sensors' first-order lag in the HF gain: in the square-wave limit, the response through the lag over the
    response without it equals that ratio for the square wave through a first-order lag in its periodic steady state
    (closed form: within a half period ``y = A - (A + Y) exp(-t / tau)``, ``Y = A tanh(T_half / (2 tau))``) within
    0.1 % (0.94 at 20 kHz, 0.50 at 5 kHz on the default 5 kHz carrier); no bandwidth is no lag."""
    sc, hw, scl = drive
    v_h = 300
    H, P = hw.pwm_half, 2 * hw.pwm_half
    phase = (np.sort((sample_phases(hw.adc_mode, H, hw.os_ticks) - H // 2) % P) + H // 2) % P
    w = np.asarray(demod_weight(counter(phase, H), H, hw.cw_angle_step), dtype=float)
    amp = v_h * scl.v_lsb / (4 * scl.f_sw) / scl.i_lsb
    tau = sc.pwm.tick_hz / (2 * math.pi * bw)                  # ticks
    y_end = amp * math.tanh(H / (2 * tau))
    u = (phase + H // 2) % P                                   # ticks since the square wave's rising edge
    lagged = np.where(u < H, amp - (amp + y_end) * np.exp(-u / tau), -amp + (amp + y_end) * np.exp(-(u - H) / tau))
    square = np.where(u < H, amp, -amp)
    plain = hf_response(hw, scl, sc.pwm.tick_hz, v_h, 0, 32767)
    assert hf_response(hw, scl, sc.pwm.tick_hz, v_h, 0, 32767, sensor_bw=0.0) == plain
    ratio = hf_response(hw, scl, sc.pwm.tick_hz, v_h, 0, 32767, sensor_bw=bw)[0] / plain[0]
    assert ratio == pytest.approx(float(lagged @ w) / float(square @ w), rel=1e-3)


def test_dc_voltage_drives_no_hf(drive):
    """The periodic steady state: a dc voltage (the resistance's drop at a dc current) without injection gives no
    response, and the response to an injection does not depend on the sign of a dc voltage beside it (on the 003
    SyRM's map at +-8 A, 45 V, the gain was 199 and 223 for the same 1 H before the mean voltage was taken out). The
    dc voltage still moves the HF pulses within the halves: 1 % of the gain between +-43 V here."""
    sc, hw, scl = drive
    plus = hf_response(hw, scl, sc.pwm.tick_hz, 3000, 0, 32767, v_d=2500)
    minus = hf_response(hw, scl, sc.pwm.tick_hz, 3000, 0, 32767, v_d=-2500)
    g = hf_response(hw, scl, sc.pwm.tick_hz, 0, 0, 32767, v_d=2500, v_q=-900)
    assert max(abs(x) for x in g) < 1e-4 * plus[0]          # the demodulator's weights: not exactly antisymmetric
    assert plus[0] == pytest.approx(minus[0], rel=0.015)


def test_ideal_inverter_model_is_the_ideal_gain(drive):
    """An inverter without dead time, drops or node capacitance at the modulator's own full scale gives the ideal
    gain, whatever the operating point; an inverter model without an operating point is refused."""
    sc, hw, scl = drive
    ideal = InverterModel(dead=0, v_dc=scl.v_lsb * 2**15)
    point = OperatingPoint(np.array([[180.0, 12.0], [12.0, 160.0]]), (0.05, -0.02))
    for s, c in ((0, 32767), (23170, 23170), (-12540, -30274)):
        a = hf_response(hw, scl, sc.pwm.tick_hz, 3600, s, c, 150, -80)
        b = hf_response(hw, scl, sc.pwm.tick_hz, 3600, s, c, 150, -80, inverter=ideal, point=point)
        assert b == pytest.approx(a, rel=1e-9, abs=1e-9)
    with pytest.raises(ValueError, match="go together"):
        hf_response(hw, scl, sc.pwm.tick_hz, 3600, 0, 32767, inverter=ideal)


def pattern(P: int, cmp: int) -> np.ndarray:
    """The ideal switch signal of one leg over a period: high before ``cmp`` in the rising half and from ``P - cmp``
    in the falling one (spec 2.4), as a (P, 3) array of three equal legs."""
    phi = np.arange(P)
    on = (phi < cmp) | (phi >= P - cmp)
    return np.repeat(on[:, None], 3, axis=1)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_dead_time_moves_one_edge(sign):
    """C_node = 0: a current out of the leg (> 0) holds the node low through the lower diode for the dead time after
    ``s`` rises (the rise D ticks late), and the fall is on time; a current into the leg the other way round. The
    diode's and the switch's drops sit on the rail the current picks."""
    P, cmp, D = 2000, 400, 50
    inv = InverterModel(dead=D, v_dc=500.0, v_sw=1.0, r_sw=0.5, v_diode=2.0, r_diode=0.25)
    on = pattern(P, cmp)
    i = np.full((P, 3), 2.0 * sign)
    v = node_voltages(on, [(cmp, P - cmp)] * 3, i, inv, TICK_HZ)
    high = 500.0 - 1.0 - 0.5 * 2.0 if sign > 0 else 500.0 + 2.0 + 0.25 * 2.0
    low = -2.0 - 0.25 * 2.0 if sign > 0 else 1.0 + 0.5 * 2.0
    phi = np.arange(P)
    if sign > 0:
        want = np.where((phi < cmp) | (phi >= P - cmp + D), high, low)
    else:
        want = np.where((phi < cmp + D) | (phi >= P - cmp), high, low)
    np.testing.assert_allclose(v[:, 0], want)
    np.testing.assert_allclose(v[:, 1], want)


def test_node_capacitance_ramp():
    """C_node > 0: after ``s`` falls with a current out of the leg, the current discharges the node at
    ``i / C`` per second from the high rail until the lower diode clamps it; a small current does not get there
    within the dead time and the low switch takes the node at its end."""
    P, cmp, D = 2000, 400, 300
    c_node, v_dc = 1e-9, 500.0
    inv = InverterModel(dead=D, v_dc=v_dc, c_node=c_node)
    on = pattern(P, cmp)
    big, small = 2.0, 0.05                             # 20 V per tick: 25 ticks to the rail; 0.5 V: 1000 (> D)
    i = np.tile(np.array([big, small, -big]), (P, 1))
    v = node_voltages(on, [(cmp, P - cmp)] * 3, i, inv, TICK_HZ)
    k = np.arange(D)
    np.testing.assert_allclose(v[cmp + k, 0], np.maximum(v_dc - big * k / (c_node * TICK_HZ), 0.0), atol=1e-9)
    np.testing.assert_allclose(v[cmp + k, 1], v_dc - small * k / (c_node * TICK_HZ), atol=1e-9)
    assert v[cmp + D, 1] == 0.0                       # the low switch on at the end of the dead time
    # a current into the leg charges the node after s rises: leg c from 0 V up to the rail
    np.testing.assert_allclose(v[P - cmp + k, 2], np.minimum(big * k / (c_node * TICK_HZ), v_dc), atol=1e-9)
