"""The hardware's HF gain: what the demodulator reads for a known inductance, with and without the inverter's error.

Host-side models for the reduction of the commissioning program (:mod:`golden.commission`, docs/commissioning.md):
one PWM period in its periodic steady state, from the modulator's own compares (spec 3.5) to the demodulator's
weights (spec 3.3, 3.4). :func:`hf_response` is the ideal inverter's: a response is the machine's inverse
incremental inductance times it. With :class:`InverterModel` it takes the inverter's error as well (the dead time
after each edge of the ideal switch signals, the node capacitances, the devices' drops, and the dead-time
compensation's shift of the compares), which depends on the sign of each phase current at each edge, and so on the
operating point: the dc currents and the machine's admittance (:class:`OperatingPoint`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from golden.fpga.adc_trigger import sample_phases
from golden.fpga.carrier import counter
from golden.fpga.cordic import demod_weight
from golden.fpga.deadtime_comp import compensate
from golden.fpga.gate_generator import effective_dead_ticks
from golden.fpga.modulator import compares

SIGN_ITERATIONS = 4
"""Passes of the fixed point currents -> edge signs -> node voltages -> currents (the first from the ideal
voltages); the Table I map's responses change by less than 1e-4 after the third (measured 2026-11-29)."""


def sensor_bandwidth(sc) -> float:
    """The current sensors' bandwidth [Hz] (0: ideal) that :func:`hf_response` takes into account: the sensors'
    data sheet value, ``sensors.bandwidth`` of the scenario (decision: the drive's designer knows the sensors
    fitted, as the dead time; a different sensor is a different scenario)."""
    return float(sc.plant["sens"]["bandwidth_hz"])


@dataclass(frozen=True)
class InverterModel:
    """What the drive knows of its inverter: the dead time it applies (the ``DEAD_TICKS`` register, at least the
    hardware's ``DEAD_MIN``), its dead-time compensation (``DTC_GAIN``, ``HF_AMP``, ``RECIP_H``) and, from the
    power devices' data sheet like the sensors' bandwidth, the link voltage, the node capacitance and the drops
    (decision, docs/commissioning.md). Voltages [V], resistances [ohm], capacitance [F]."""

    dead: int
    v_dc: float
    c_node: float = 0.0
    v_sw: float = 0.0
    r_sw: float = 0.0
    v_diode: float = 0.0
    r_diode: float = 0.0
    dtc_gain: int = 0
    hf_amp: int = 0
    recip_h: int = 0


def inverter_model(sc, hw) -> InverterModel:
    """The :class:`InverterModel` of scenario ``sc`` with its hardware configuration ``hw``."""
    inv = sc.plant["inv"]
    return InverterModel(dead=effective_dead_ticks(hw.dead_ticks), v_dc=float(inv["V_dc"]), c_node=float(inv["C_node"]),
                         v_sw=float(inv["v_sw"]), r_sw=float(inv["r_sw"]), v_diode=float(inv["v_diode"]),
                         r_diode=float(inv["r_diode"]), dtc_gain=hw.dtc_gain, hf_amp=hw.hf_amp, recip_h=hw.recip_h)


@dataclass(frozen=True)
class OperatingPoint:
    """The machine at the step: ``y`` its incremental admittance (inverse inductance, 2x2 [1/H]) and ``i_dc`` its
    currents [A], both in the step's frame; ``i_ref`` the current references the dead-time compensation is
    given [current LSB] (d, q of the frame)."""

    y: np.ndarray
    i_dc: tuple[float, float]
    i_ref: tuple[int, int] = (0, 0)


def hf_response(hw, scl, tick_hz: float, v_h: int, s: int, c: int, v_d: int = 0, v_q: int = 0,
                sensor_bw: float = 0.0, inverter: InverterModel | None = None,
                point: OperatingPoint | None = None) -> tuple[float, float]:
    """``(GAMMA_D, GAMMA)`` of one window for an ideal inductance of 1 H: the hardware's HF gain.

    The modulator's compares (spec 3.5) for the registers ``V_D = v_d``, ``V_Q = v_q``, ``V_H = v_h`` and the
    frame ``SIN = s``, ``COS = c`` in both halves, the ideal switch signals (spec 2.4, no dead time), the phase
    voltages without their common mode at every tick of a period, the current of a 1 H inductance (their
    integral, without its mean: the steady state of a lossless load), through the current sensors' first-order
    lag of bandwidth ``sensor_bw`` [Hz] (0: none; in the periodic steady state, by the period's spectrum), Park
    into the frame, sampled at the window's instants and weighted as the demodulator does (spec 3.3, 3.4). The
    lag matters: 0.8 us at 200 kHz shifts the HF current against the demodulator's weights and takes about 1.5 %
    of the response at 10 kHz (measured on the 000 motor's map, docs/commissioning.md). For a small ``V_H`` the HF
    voltage comes as short pulses around the middle of each half period and the current is nearly a square
    wave of amplitude ``V_H / (4 f_sw L)``, whose fundamental is ``4/pi`` of that (not the triangle of
    Benevieri et al. 2023, eq. (17), ``8/pi^2``, which holds only when the pulses fill the halves). A machine's
    response is this times its inverse incremental inductance in the injection direction (``GAMMA_D``) and
    across it (``GAMMA``).

    With ``inverter`` and ``point``: the compares after the dead-time compensation, and the node voltages of the
    real inverter (:func:`node_voltages`) for the phase currents of ``point`` (its dc currents plus the ripple its
    admittance draws from these voltages, a fixed point of :data:`SIGN_ITERATIONS` passes); the result is still the
    volt-seconds' response of 1 H (the machine's response is ``point.y`` times it), now with the inverter's error
    at this operating point in it, across the frame as well as along it."""
    if (inverter is None) != (point is None):
        raise ValueError("hf_response: the inverter model and the operating point go together")
    H, P = hw.pwm_half, 2 * hw.pwm_half
    rise, fall = (compares(v_d, v_q, v_h, s, c, H, sign) for sign in (-1, 1))
    if inverter is not None and inverter.dtc_gain:
        rise, fall = (compensate(cm, sign, H, inverter.dead, inverter.dtc_gain, point.i_ref[0], point.i_ref[1],
                                 inverter.hf_amp, s, c, inverter.recip_h) for cm, sign in ((rise, -1), (fall, 1)))
    rise, fall = np.array(rise), np.array(fall)
    phi = np.arange(P)
    on = np.where(phi[:, None] < H, phi[:, None] < rise[None, :], (P - phi[:, None]) <= fall[None, :])
    v_full = scl.v_lsb * 2**15
    cf, sf = c / 32768, s / 32768

    def volt_seconds(v: np.ndarray) -> np.ndarray:
        """The frame's volt-seconds over the period (without their mean) of the leg voltages ``v`` [V], less the
        period's mean voltage (the resistance's drop in the steady state: it drives no current ripple)."""
        v = v - v.mean(axis=1, keepdims=True)
        v_al, v_be = v[:, 0], (v[:, 1] - v[:, 2]) / math.sqrt(3)
        v_f = np.stack([v_al * cf + v_be * sf, v_be * cf - v_al * sf])
        lam = np.cumsum(v_f - v_f.mean(axis=1, keepdims=True), axis=1) / tick_hz
        return lam - lam.mean(axis=1, keepdims=True)

    lam = volt_seconds(on.astype(float) * v_full)                  # current of 1 H [A]
    if inverter is not None:
        edges = [(rise[x], P - fall[x]) for x in range(3)]         # s falls (rising half), s rises (falling half)
        i_dc = np.asarray(point.i_dc, dtype=float)
        for _ in range(SIGN_ITERATIONS):
            i_f = i_dc[:, None] + np.asarray(point.y, dtype=float) @ lam               # frame currents [A]
            i_abc = _phases(i_f[0] * cf - i_f[1] * sf, i_f[0] * sf + i_f[1] * cf)
            lam = volt_seconds(node_voltages(on, edges, i_abc, inverter, tick_hz))
    if sensor_bw > 0.0:                                              # the sensors' lag, periodic steady state
        f = np.fft.rfftfreq(P, d=1.0 / tick_hz)
        lam = np.fft.irfft(np.fft.rfft(lam, axis=1) / (1.0 + 1j * f / sensor_bw), n=P, axis=1)
    rel = np.sort((sample_phases(hw.adc_mode, H, hw.os_ticks) - H // 2) % P)
    phase = (rel + H // 2) % P
    w = np.asarray(demod_weight(counter(phase, H), H, hw.cw_angle_step), dtype=float)
    i = lam[:, phase] / scl.i_lsb
    return float(i[0] @ w / 2**15), float(i[1] @ w / 2**15)


def _phases(i_al: np.ndarray, i_be: np.ndarray) -> np.ndarray:
    """Phase currents (ticks x 3) from alpha, beta (amplitude-invariant Clarke)."""
    h = math.sqrt(3) / 2
    return np.stack([i_al, -0.5 * i_al + h * i_be, -0.5 * i_al - h * i_be], axis=1)


def node_voltages(on: np.ndarray, edges, i_abc: np.ndarray, inv: InverterModel, tick_hz: float) -> np.ndarray:
    """The leg voltages (ticks x 3) [V] of the ideal switch signals ``on`` through the real inverter, for the phase
    currents ``i_abc`` (ticks x 3, positive out of the leg), as the plant's inverter (docs/plant.md): a conducting
    leg sits on its rail less the switch's drop or beyond it by the diode's, whichever the current's sign picks;
    for the dead time after each edge of ``s`` (``edges``: per leg, the ticks where ``s`` falls and rises) both
    switches are off and the current drives the node: through a diode at once (``C_node = 0``), or charging the node
    capacitance until a diode clamps it or the other switch turns on."""
    ai = np.abs(i_abc)
    high = np.where(i_abc >= 0.0, inv.v_dc - inv.v_sw - inv.r_sw * ai, inv.v_dc + inv.v_diode + inv.r_diode * ai)
    low = np.where(i_abc <= 0.0, inv.v_sw + inv.r_sw * ai, -inv.v_diode - inv.r_diode * ai)
    v = np.where(on, high, low)
    P, D = on.shape[0], inv.dead
    lo_clamp, hi_clamp = -inv.v_diode, inv.v_dc + inv.v_diode
    for x in range(3):
        for t0 in edges[x]:
            idx = (int(t0) + np.arange(D)) % P
            i = i_abc[idx, x]
            if inv.c_node > 0.0:
                node, step = v[(int(t0) - 1) % P, x], 1.0 / (inv.c_node * tick_hz)   # where the switch left it
                for j, i_j in enumerate(i):
                    if i_j > 0.0 and node <= lo_clamp:
                        v[idx[j], x] = -inv.v_diode - inv.r_diode * i_j
                    elif i_j < 0.0 and node >= hi_clamp:
                        v[idx[j], x] = inv.v_dc + inv.v_diode - inv.r_diode * i_j
                    else:
                        v[idx[j], x] = node
                        node = min(max(node - i_j * step, lo_clamp), hi_clamp)
            else:
                v[idx, x] = np.where(i > 0.0, -inv.v_diode - inv.r_diode * np.abs(i),
                                     np.where(i < 0.0, inv.v_dc + inv.v_diode + inv.r_diode * np.abs(i), v[idx, x]))
    return v
