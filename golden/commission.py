"""Self-commissioning, host side: the identification program and the reduction of its sums (docs/commissioning.md).

:func:`build_program` turns the scenario's ``[commission]`` settings and the drive's formats into the
program the firmware runs (:mod:`golden.firmware.ident`); :func:`reduce` turns the per-step sums the
firmware leaves into the motor's data; :func:`tuning` into the controller's settings. The stages:

1. ``probe``: one HF step at ``probe_voltage``; the firmware lowers the HF level (``F_LEVEL``) when the HF
   current would exceed ``hf_current`` (a motor of small inductance), never raises it.
2. ``scan``: the HF square wave on a frame at ``K`` angles over half a turn, each at ``v`` and ``2 v`` (the
   difference removes the dead time's share), no current control; the firmware fits the rotor angle and sets
   the current PIs (``F_FIT``). Host: ``L_d``, ``L_q`` at zero current from the mean and the second harmonic of
   the responses. A reluctance machine, whose saliency appears only with current: a bias along the injection,
   current control with gains from the probe (``F_GAIN``), the shaft held; then ``axis``: a pair on the fitted d
   axis with the bias along it, whose response replaces the fit's ``L_d`` (the fit's first harmonic misses the
   sharp maximum of the biased admittance); then the current steps of stage ``lf`` (4b) around the bias on d and
   on q (current gains set for q's inductance by an ``F_GAIN`` step on q, the probe's set back after), whose
   ``L_d``, ``L_q`` replace those when their transitions agree.
3. ``polarity`` (magnets only): ``+I_p`` then ``-I_p`` on d with the injection; the firmware turns the
   angle by half a turn when the second response is the larger (``F_POL``). The shaft is held from here.
4. ``map``: the incremental inductance matrix on a grid of (i_d, i_q): at each point the injection on d,
   then on q (the frame turned by a quarter turn, the current references turned with it), one step each at
   ``2 v``; the host takes the inverter's error at the point out with its model (:mod:`golden.hf_gain`). Points
   with ``i_q != 0`` make torque: the map needs the shaft held (``lock = "on"``, as a brake or a locking pin on
   a bench does); without it only the ``i_q = 0`` line is measured.
4b. ``lf`` (magnets only): along d, then q, the current stepped up from ``hf_current / 2`` to ``hf_current`` and
   back under current control, every window of the transitions summed: ``L = (T sum(v) - T sum(f(i))) / (I2 -
   I1)``, ``f`` (resistance and the inverter's error) the line through the holds before and after. Its ``L_d``,
   ``L_q`` replace the scan's when the up and the down transition agree (:data:`LF_AGREE`): a large inductance,
   whose HF current at ``f_sw`` is too small for the scan (the 000 motor's).
5. ``resistance``: the current turned from the rotor's axis to the nearest phase axis (``F_SNAP``), three
   levels; ``V = R i + V0 + b / i`` removes the drops that do not depend on the current level (the dead
   time's residual, the switches' knee voltages) and the node capacitances' share at small currents.
6. ``spin``: the shaft released, the current vector (half the test current) turns at a prescribed speed
   profile (I/f), the rotor follows it: up to ``speed / 2``, hold, accelerate to ``speed``, hold, decelerate
   to ``speed / 2``, hold; then down to 0, or with magnets up to ``speed`` again and the coast, which ends the
   program with the rotor coasting. Flux in the frame from the voltage model at constant frame speed,
   ``psi = (v - V0 - R i) / (j w)``; torque ``1.5 p (psi x i)``; ``psi_f = abs(v) / w_r`` in the coast with the
   current held at zero, over whole turns (``w_r`` the frame's speed plus the turn of the back-EMF in the frame
   from the first turn to the second); ``J``
   from the torques accelerating and decelerating through the same speeds, ``(T_acc - T_dec) / (2 a)``
   (friction and every constant bias cancel); the friction ``B``, ``T_c`` from the holds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from golden.control_config import hardware_config, scales
from golden.firmware.ident import (F_FIT, F_GAIN, F_LEVEL, F_NEG, F_OPEN, F_POL, F_SCAN, F_SET, F_SNAP, G2_SHIFT,
                                   IdentParams)
from golden.fixed import to_fixed
from golden.fpga.cordic import sincos_q15
from golden.hf_gain import OperatingPoint, hf_response, inverter_model, sensor_bandwidth
from golden.saturation_fit import InductanceData, fit_inductances

QUARTER = 1 << 30
PROBE_DEAD_TIMES = 8.0
"""The probe's HF amplitude is this many times the dead time's voltage (the scan's pair: once and twice it; the
map's steps twice it), unless ``hf_current`` caps it; the tuned ``V_h`` is at least this many (hfi.commission
``tuning``). Measured (golden, the map then a pair at half and once the probe): on the 002 Table I motor (11.2 V of
dead time) a scan pair of 2.2 and 4.4 times put the angle 20 deg off and L_q 36 % high, 4 and 8 times gave
0.4 % but a map pair of 2 and 4 times errors up to 20 %, 4.3 and 8.6 times (map 2.1 and 4.3) 0.3 % and a map
within 9 %; on the 001 motor (2.2 V) 4 and 8 times: L_d 3.9 % low, 8.8 and 17.6 times: within 1.1 % and the map
within 4.2 %."""
HF_CURRENT_SHARE = 1 / 6
"""Default ``hf_current`` (the cap of the HF current amplitude) as a share of ``current``: a larger HF excursion
saturates the motor (the 001 motor at a quarter of its 12 A: L_q 3.4 % low)."""
SCAN_BIAS_SHARE = 1 / 16
"""A reluctance machine's scan: the bias current along the injection, as a share of ``current`` (the 003 SyRM's
saliency at zero current is 0.7 %; with 0.5 A along d its d inductance is 19 times below q's)."""
SATURATION_RATIO = 50.0
"""A reluctance machine's current gains are set for this many times less inductance than the probe saw at zero
current (the 003 SyRM: 1.03 H at zero, 0.02 H at 2 A, 0.01 H at 6 A along d): slow at small currents, stable at
the largest."""
SPIN_SPEED_MIN = 500 * math.pi / 30
"""The default spin speed is half the largest reference speed, at least this [rad/s mechanical]."""
LF_LEVELS = (0.5, 1.0)
"""The low-frequency inductance steps (stage ``lf``): the two current levels, shares of ``hf_current``."""
LF_SETTLE = 30.0
"""A transition step of stage ``lf`` lasts this many times 1 / (2 pi current_bw): the current loop's step,
its slow integral tail included, is over within it. Measured on the 000 motor (golden): 12 left the tail in the
hold after it (L_q 4 % high), 30 gave L_d, L_q within 0.3 % and 0.6 %, 60 within 0.3 % and 1.1 % (more windows
summed, more noise)."""
LF_AGREE = 0.05
"""The low-frequency inductances replace the scan's when the up and the down transition agree within this share on
both axes: the signal ``L (I2 - I1)`` must stand out of the inverter's error over the transition, which a small
inductance does not (the 002 motors' 5.6-13 mH: the two differ by a factor of 3 and more; the 001 motor's: by 20 %),
and a large one does, where the HF scan's current is smallest (the 000 motor: 1.3 % and 3 %)."""
LF_D_LEVELS = (0.8, 1.2)
"""A reluctance machine's stage lf on d (2c): the two levels, shares of the scan's bias. The step's size is the
signal against the noise of the transition's sum: between 0.95 and 1.05 of the bias L_d scattered from -5.7 to
+6.2 % over five noise seeds (the up and the down transition 13 % apart in one: the fallback), between 0.8 and 1.2
from -0.3 to +1.3 %. The chord's own error on the 003 SyRM's map (d's inductance falls from 0.062 H at 0.4 A to
0.047 H at 0.6 A): +0.8 % (+0.05 % between 0.95 and 1.05, +1.9 % between 0.7 and 1.3); measured 2026-11-29."""
LF_Q_LEVELS = (0.9, 1.1)
"""A reluctance machine's stage lf on q (2c): the two levels, shares of the scan's bias. q's inductance is large,
so the step's signal is large and the chord's error rules: -1.3 % between 0.8 and 1.2 (L_q -2.1 to -2.4 % over five
seeds), -0.3 % between 0.9 and 1.1 (L_q -0.9 to -1.4 %); measured 2026-11-29."""
CHORD_WEIGHT = 2.0
"""Weight of stage lf's chords beside the map's entries in the saturation model's fit (:func:`saturation_data`)."""
ZERO_CURRENT_WEIGHT = 0.1
"""Weight of the map's entries at zero current on their own axis in that fit (9-16 % off on the 003 SyRM). With 0 the
unsaturated inductance is left to the chords alone and the fit drifted to a_d0 = 5e-10 (an infinite L_d at zero
current); 0.1 gave a_d0 0.87 (the plant's 0.97), 0.25 and 0.5 pulled q's coefficients 1-9 % off (2026-11-29)."""
MAP_ITERATIONS = 3
"""Passes of the map's correction for the inverter's error (:func:`reduce`)."""
R_LEVELS = (0.5, 0.75, 1.0)
"""Current levels of the resistance steps (shares of ``current``)."""
SPIN_MEASURED = ("hold_low", "accel", "hold_high", "coast_a", "coast_b", "decel", "hold_low2")
"""The spin's measured stages."""


@dataclass(frozen=True)
class CommissionSettings:
    """``[commission]`` of the scenario (SI units; docs/scenario.md).

    current : test current of the resistance, polarity and map steps and of the spin [A]
    hf_current : target amplitude of the HF current [A]
    probe_voltage : amplitude of the probe step [V]
    hf_voltage_max : largest HF amplitude [V]
    speed : top speed of the spin [rad/s mechanical]
    spin_time : duration of the acceleration between half and full speed [s]
    lock : the shaft is held during the map
    scan_points : angles of the scan over half a turn
    magnets : the machine has magnets (polarity test, psi_f)
    settle, measure : windows before the measured ones and measured windows of a standstill step [s]
    """

    current: float
    hf_current: float
    probe_voltage: float
    hf_voltage_max: float
    speed: float
    spin_time: float = 1.0
    lock: bool = True
    scan_points: int = 12
    magnets: bool = True
    settle: float = 0.02
    measure: float = 0.04


def settings(sc) -> CommissionSettings:
    """The scenario's ``[commission]`` table with its derived defaults: ``current`` = ``control.i_max``,
    ``hf_current`` HF_CURRENT_SHARE of it, ``probe_voltage`` PROBE_DEAD_TIMES times the dead time's voltage ``t_d f_sw
    V_dc`` (at least 2 % of V_dc, at most half of ``hf_voltage_max``), ``hf_voltage_max`` 50 % of V_dc, ``speed`` the
    largest reference speed (at least SPIN_SPEED_MIN). ``magnets``: the machine type, which the user knows (a
    reluctance machine is the one whose angle is pi-periodic, ``Scales.angle_period_deg``)."""
    t, ctl, v_dc = sc.commission, sc.control, sc.plant["inv"]["V_dc"]
    current = t.current or ctl.i_max
    v_dt = sc.pwm.dead_time * sc.pwm.f_sw * v_dc                     # the dead time's voltage
    v_max = t.hf_voltage_max or 0.5 * v_dc
    return CommissionSettings(
        current=current, hf_current=t.hf_current or HF_CURRENT_SHARE * current,
        probe_voltage=t.probe_voltage or min(max(PROBE_DEAD_TIMES * v_dt, 0.02 * v_dc), 0.5 * v_max),
        hf_voltage_max=v_max, speed=t.speed or spin_speed(sc.reference_speed),
        spin_time=t.spin_time, lock=t.lock == "on", scan_points=t.scan_points,
        magnets=scales(sc).angle_period_deg == 360.0)


def spin_speed(reference: list) -> float:
    """The default spin speed [rad/s mechanical]: half the largest speed of a reference profile, at least
    SPIN_SPEED_MIN (the 003 SyRM lost its I/f synchronism braking from its full 1500 r/min at half its test
    current: J came out 38 % low; from 750 r/min within 1 %)."""
    return max(0.5 * max((abs(v) for _, v in reference), default=0.0), SPIN_SPEED_MIN)


@dataclass(frozen=True)
class StepInfo:
    """What the host knows of a step: its stage, its currents in the frame [A], its frame angle relative to the
    rotor (phi, rad) and the HF axis ("d" injection on the rotor d axis, "q" on q)."""

    stage: str
    i_d: float = 0.0
    i_q: float = 0.0
    phi: float = 0.0
    axis: str = ""


@dataclass(frozen=True)
class Program:
    """The firmware's program, each step's meaning and the time span in which the shaft must be held (None:
    never)."""

    params: IdentParams
    steps: tuple
    lock: tuple | None
    duration: float


def build_program(sc, cs: CommissionSettings) -> Program:
    """The identification program of scenario ``sc`` with the settings ``cs`` (module docstring)."""
    sc_, hw = scales(sc), hardware_config(sc)
    f_sw = sc_.f_sw
    win = lambda t: max(round(t * f_sw), 1)                        # noqa: E731
    n_set, n_meas = win(cs.settle) + 2, win(cs.measure)
    cur = sc_.current
    rows, infos = [], []

    def add(info: StepInfo, n: int, m: int, flags: int, i_d: float = 0.0, i_q: float = 0.0, vh: int = 0,
            phi: int = 0, dw: int = 0) -> None:
        rows.append((n, m, cur(i_d), cur(i_q), vh, phi % 2**32, dw, flags))
        infos.append(info)

    w_frame = cs.speed * sc_.pole_pairs / f_sw                      # the spin frame's top advance [rad per period]
    if not w_frame < 0.5 * math.pi:
        raise ValueError(f"commission.speed: {cs.speed * 30 / math.pi:.6g} r/min turns the spin's frame by "
                         f"{w_frame / (2 * math.pi):.3g} of an electrical turn per PWM period (a quarter at most)")
    for key, volts in (("hf_voltage_max", cs.hf_voltage_max), ("probe_voltage", cs.probe_voltage)):
        if sc_.voltage(volts) < 1:
            derived = key == "probe_voltage" and sc.commission.probe_voltage is None
            raise ValueError(f"commission.{key}: {volts:.6g} V is below one voltage LSB ({sc_.v_lsb:.6g} V)"
                             + (" (derived: half of hf_voltage_max at most)" if derived else ""))
    v_probe = min(sc_.voltage(cs.probe_voltage), 32767)
    g_unit = hf_response(hw, sc_, sc.pwm.tick_hz, v_probe, 0, 32767,
                         sensor_bw=sensor_bandwidth(sc))[0] / (v_probe * sc_.v_lsb)   # per V and 1/H
    # 1. probe
    # a reluctance machine's scan needs a bias current (its saliency appears only with current), so current
    # control from the probe on: gains from the probe's response for SATURATION_RATIO times less inductance
    add(StepInfo("probe", axis="d"), n_set + n_meas, n_meas,
        F_SET | F_OPEN | F_LEVEL | (0 if cs.magnets else F_GAIN), vh=v_probe)
    bias = 0.0 if cs.magnets else cs.current * SCAN_BIAS_SHARE
    lock_from = len(rows) + 1 if not cs.magnets else None      # the biased scan makes torque: the shaft held
    # 2. scan
    K = cs.scan_points
    for k in range(K):
        phi = (k << 31) // K
        for twice in (0, 1):
            add(StepInfo("scan", phi=phi * 2 * math.pi / 2**32, axis="frame"), n_set + n_meas, n_meas,
                F_SET | (F_OPEN if cs.magnets else 0) | F_SCAN | (F_FIT if k == K - 1 and twice else 0)
                | (0 if twice else F_NEG), i_d=bias, vh=v_probe << twice, phi=phi)
    # 2b. axis (a reluctance machine): the scan's fit is a first harmonic, and the biased admittance over the angle
    # is not one (a sharp maximum on d, a broad minimum around q: on the 003 SyRM the fit put L_d 18 % high), so L_d
    # comes from a pair on the fitted d axis, the bias along it as in the scan (7 % high). The same on q was not
    # kept: its 1 H draws a response 18 times smaller, and its bias settles through a current loop 47 times
    # slower than designed (SATURATION_RATIO): -1 % to +20 % with the settle times tried; q: 2c below
    n_tr = win(LF_SETTLE / (2 * math.pi * sc.control.current_bw))

    def lf(axis: str, phi: int, lo: float, hi: float) -> None:
        """Stage lf along ``axis`` (the frame at ``theta_r + phi``): holds at ``lo`` and ``hi``, the up and the
        down transition between them summed window by window (4b below)."""
        add(StepInfo("lf_lo", lo, 0.0, phi * 2 * math.pi / 2**32, axis), n_set + n_meas, n_meas, F_SET, i_d=lo, phi=phi)
        for stage, i, n in (("lf_up", hi, n_tr), ("lf_hi", hi, n_meas), ("lf_down", lo, n_tr), ("lf_lo2", lo, n_meas)):
            add(StepInfo(stage, i, 0.0, phi * 2 * math.pi / 2**32, axis), n, n, 0, i_d=i)

    if not cs.magnets:
        for twice in (0, 1):
            add(StepInfo("axis", bias, 0.0, 0.0, "d"), n_set + n_meas, n_meas, F_SET, i_d=bias, vh=v_probe << twice)
        # 2c. lf (a reluctance machine, decision 2026-11-29): q's HF current at the bias is a few mA, where the
        # inverter's error at small currents reads its admittance 13 % low (the scan's samples near q; with an
        # ideal inverter within 6 %), so L_q, and L_d with it, come from current steps around the bias, as a magnet
        # machine's (4b); d first, with the probe's gains. On q they need the current loop designed for q's
        # inductance, not SATURATION_RATIO times less: an F_GAIN step on q summed over SATURATION_RATIO times fewer
        # windows sets kp that many times higher (kp = c_gain v_h / sum G); after the steps, the current back to
        # zero, a step as the probe (open, at rest) sets the probe's gains back for the map
        lf("d", 0, *(f * bias for f in LF_D_LEVELS))
        lo_q, hi_q = (f * bias for f in LF_Q_LEVELS)
        m_g = max(round(n_meas / SATURATION_RATIO), 1)
        add(StepInfo("gain_q", lo_q, 0.0, math.pi / 2, "q"), n_set + m_g, m_g, F_SET | F_GAIN, i_d=lo_q, vh=v_probe,
            phi=QUARTER)
        lf("q", QUARTER, lo_q, hi_q)
        add(StepInfo("q_zero", axis="q"), n_set, 0, 0)
        add(StepInfo("gain_back", axis="d"), n_set + n_meas, n_meas, F_SET | F_OPEN | F_GAIN, vh=v_probe)
    # 3. polarity: twice the standstill time (the current loop settles first); the shaft is held from here
    lock_from = len(rows) if lock_from is None else lock_from
    if cs.magnets:
        for sign in (1, -1):
            add(StepInfo("polarity", i_d=sign * cs.current, axis="d"), 2 * n_set + n_meas, n_meas,
                F_SET | (F_POL if sign < 0 else 0), i_d=sign * cs.current, vh=v_probe)
    # 4. map: one step per axis at the scan's larger amplitude; the host takes the inverter's error at each point
    # out with its model (reduce): a pair of amplitudes does not cancel it where a phase current crosses zero with
    # the HF at one amplitude and not at the other (docs/commissioning.md)
    grid_q = (0.0, 0.5, 1.0) if cs.lock else (0.0,)
    for fq in grid_q:
        for fd in (-1.0, -0.5, 0.0, 0.5, 1.0):
            i_d, i_q = fd * cs.current, fq * cs.current
            add(StepInfo("map", i_d, i_q, 0.0, "d"), n_set + n_meas, n_meas, F_SET, i_d=i_d, i_q=i_q, vh=v_probe << 1)
            add(StepInfo("map", i_d, i_q, math.pi / 2, "q"), n_set + n_meas, n_meas, F_SET, i_d=i_q, i_q=-i_d,
                vh=v_probe << 1, phi=QUARTER)
    # 4b. lf (magnets only; a reluctance machine's inductance at the two levels is not the scan's, at its bias):
    # the inductance along d and q from a current step between two levels of the same sign (no zero crossing: the
    # inverter's error is a smooth function of the current, taken from the two holds), every window of the
    # transition summed: T sum(v) = L (I2 - I1) + T sum(f(i)), f through the holds' means
    lo, hi = (f * cs.hf_current for f in LF_LEVELS)
    for axis, phi in ((("d", 0), ("q", QUARTER)) if cs.magnets else ()):
        lf(axis, phi, lo, hi)
    # 5. resistance: the current on the nearest phase axis (the other phases carry half of it, outside the
    # dead-time compensation's zone when current / 4 > dtc_zone): it starts on the rotor's own axis (d with
    # magnets, q without: a free rotor is pulled into alignment, not away) and turns there in 1 s (F_SNAP);
    # with the lock the shaft is still held (a free rotor of a machine whose reluctance torque outweighs the
    # magnet's at this current, the 000 motor's, would swing between the levels)
    add(StepInfo("align", cs.current), win(1.0), 0, F_SET | F_SNAP, i_d=cs.current,
        phi=0 if cs.magnets else QUARTER)
    for level in R_LEVELS:
        add(StepInfo("resistance", level * cs.current), win(0.1) + n_meas * 2, n_meas * 2, 0, i_d=level * cs.current)
    # the spin's current: half the test current (the I/f needs only the friction's and the ramps' torque; a
    # smaller current snaps the rotor less when it comes back after a coast)
    i_spin = 0.5 * cs.current
    # the current down, the shaft released, then up again in steps over 0.6 s: the rotor moves to its
    # equilibrium with the current slowly instead of swinging there
    add(StepInfo("release"), win(0.1), 0, 0)
    lock_to = len(rows)
    for j in range(6):
        add(StepInfo("spin_in", (j + 1) / 6 * i_spin), win(0.1), 0, 0, i_d=(j + 1) / 6 * i_spin)
    # 6. spin
    w_top = cs.speed * sc_.pole_pairs                                # rad/s electrical
    a = 0.5 * w_top / cs.spin_time                                   # rad/s^2 electrical
    to_dw = lambda acc: round(acc / f_sw / sc_.w_lsb)                 # noqa: E731  speed LSB per period
    n_j, t_j = 4, min(0.25 * cs.spin_time, 0.3)

    def ramp(stage: str, sign: int, t_const: float, measure: bool) -> None:
        """Acceleration ``sign * a`` entered and left through ``n_j`` sub-steps each (jerk limited)."""
        for j in range(n_j):
            add(StepInfo(stage + "_in", i_spin), win(t_j / n_j), 0, 0, i_d=i_spin,
                dw=to_dw(sign * a * (j + 0.5) / n_j))
        n = win(t_const)
        add(StepInfo(stage, i_spin), n, (n * 3) // 4 if measure else 0, 0, i_d=i_spin, dw=to_dw(sign * a))
        for j in range(n_j):
            add(StepInfo(stage + "_out", i_spin), win(t_j / n_j), 0, 0, i_d=i_spin,
                dw=to_dw(sign * a * (n_j - j - 0.5) / n_j))

    # speed gained by a ramp: a t_j (jerk phases) + a t_const; the half speed takes t_const = w/2a - t_j
    t_half = max(0.5 * w_top / a - t_j, 0.05)
    hold = win(max(0.5, 0.5 * cs.spin_time))
    ramp("spin_up", 1, t_half, False)
    add(StepInfo("hold_low", i_spin), hold, hold // 2, 0, i_d=i_spin)
    ramp("accel", 1, t_half, True)
    add(StepInfo("hold_high", i_spin), hold, hold // 2, 0, i_d=i_spin)
    ramp("decel", -1, t_half, True)
    add(StepInfo("hold_low2", i_spin), hold, hold // 2, 0, i_d=i_spin)
    if cs.magnets:
        # back to the top speed, then the coast, last (decision 2026-11-29, docs/commissioning.md): the current
        # held at zero for a turn (the current loop's tail), then two measured halves of a whole electrical turn
        # each. At zero current the voltage is the back-EMF plus the inverter's error: with the PWM ripple
        # crossing zero it repeats every sixth, and the sensors' offsets leave a dc current in the phases whose
        # dead-time error is a fixed vector in the stator (volts on the 000 motor), turning once per turn in
        # this frame: a whole turn's mean removes it, a half turn's kept it (psi_f 3.8 % high). The rotor, slowed
        # by its friction, has slipped from the frame by the end: the program ends there, the gates off, the
        # rotor coasting down (a current brought back catches it with a swing, which spoiled J when the decel
        # came after it)
        ramp("spin_up2", 1, t_half, False)
        add(StepInfo("hold_top", i_spin), win(0.2), 0, 0, i_d=i_spin)
        m_c = max(round(2 * math.pi / w_top * f_sw), 1)
        add(StepInfo("coast"), max(n_set, m_c), 0, 0)
        add(StepInfo("coast_a"), m_c, m_c, 0)
        add(StepInfo("coast_b"), m_c, m_c, 0)
    else:
        ramp("spin_down", -1, t_half, False)
        add(StepInfo("stop", i_spin), win(0.2), 0, 0, i_d=i_spin)

    cols = list(zip(*rows))
    vh_max = min(sc_.voltage(cs.hf_voltage_max), 32767)
    c_kp = round(2 * math.pi * sc.control.current_bw * sc_.i_lsb * 2**16 * K * n_meas * g_unit) if cs.magnets else 0
    c_gain = 0 if cs.magnets else round(2 * math.pi * sc.control.current_bw * sc_.i_lsb * 2**16 * n_meas * g_unit
                                        / SATURATION_RATIO)
    params = IdentParams(*[tuple(int(x) for x in c) for c in cols],
                         c_kp=c_kp, c_ki=to_fixed(2 * math.pi * sc.control.current_bw / 4 / f_sw, 16),
                         v_lim=min(sc_.voltage(sc.control.v_max), 32767),
                         c_lvl=round(2**16 * g_unit * 4 * f_sw * cs.hf_current * n_meas),
                         i_slew=max(cur(cs.current) // max(n_set // 4, 1), 1),
                         c_gain=c_gain, lvl_max=1 << 16, vh_max=vh_max)
    starts = np.cumsum((0,) + params.s_n)
    period = 1.0 / f_sw
    lock = (float(starts[lock_from] * period), float(starts[lock_to] * period)) if cs.lock else None
    return Program(params, tuple(infos), lock, float((starts[-1] + 4) * period))


@dataclass
class Results:
    """The measured motor data (SI) and the intermediate values the report draws."""

    values: dict = field(default_factory=dict)     # name -> measured value
    theta_r: float = 0.0                           # rotor angle found [rad electrical]
    scan: dict = field(default_factory=dict)
    map: list = field(default_factory=list)         # (i_d, i_q, L 2x2) per grid point
    spin: dict = field(default_factory=dict)
    snr: float = 0.0
    lf: dict = field(default_factory=dict)          # "d", "q": (up, down) [H]; "used": they replaced the scan's
    saturation: dict | None = None                  # a reluctance machine's fitted algebraic model (coefficients,
    saturation_rms: float = 0.0                     # exponents) and its RMS relative residual (saturation_data)


def _lf_inductance(prog: Program, st, means: list, axis: str, i_lsb: float, v_lsb: float,
                   period: float) -> tuple[float, float]:
    """The inductance along ``axis`` [H] from the up and the down transition of stage ``lf``: ``T sum(v) - T
    sum(f(i))`` over ``I2 - I1``, ``f`` the line through the two holds' means (voltage and current; the
    resistance and the inverter's error, static functions of the current)."""
    ks = {s.stage: k for k, s in enumerate(prog.steps) if s.stage.startswith("lf") and s.axis == axis}
    out = []
    for tr, a, b in (("lf_up", "lf_lo", "lf_hi"), ("lf_down", "lf_hi", "lf_lo2")):
        i1, v1 = means[ks[a]]["id"] * i_lsb, means[ks[a]]["vd"] * v_lsb
        i2, v2 = means[ks[b]]["id"] * i_lsb, means[ks[b]]["vd"] * v_lsb
        k, n = ks[tr], prog.params.s_m[ks[tr]]
        sum_f = n * v1 + (v2 - v1) / (i2 - i1) * (st.r_id[k] * i_lsb - n * i1)
        out.append(period * (st.r_vd[k] * v_lsb - sum_f) / (i2 - i1))
    return out[0], out[1]


def saturation_data(prog: Program, res: Results) -> InductanceData:
    """What the saturation model is fitted to: the map's entries (L_dq where both currents are not zero; L_dd, L_qq
    at zero current on their own axis with the weight :data:`ZERO_CURRENT_WEIGHT`: their HF current is a few mA on a
    reluctance machine), and the chords of stage lf along d and q (weight :data:`CHORD_WEIGHT`: the only points at
    small currents, where the inductance changes fastest)."""
    own = lambda i: 1.0 if i else ZERO_CURRENT_WEIGHT                                    # noqa: E731
    points = [(i_d, i_q, L[0, 0], L[0, 1], L[1, 1], own(i_d), float(i_d != 0 and i_q != 0), own(i_q))
              for i_d, i_q, L in res.map]
    chords = []
    for n, axis in enumerate(("d", "q")):
        levels = {s.stage: s.i_d for s in prog.steps if s.stage in ("lf_lo", "lf_hi") and s.axis == axis}
        if axis in res.lf and len(levels) == 2:
            chords.append((n, levels["lf_lo"], levels["lf_hi"], float(np.mean(res.lf[axis])), CHORD_WEIGHT))
    return InductanceData(np.array(points), np.array(chords).reshape(-1, 5))


def _step_means(st, k: int, m: int) -> dict:
    """The means over the measured windows of step ``k`` [LSB]."""
    return {name: getattr(st, "r_" + name)[k] / m for name in ("id", "iq", "vd", "vq", "gd", "gq")}


def frame_speed(theta: np.ndarray, w_lsb: float) -> np.ndarray:
    """The frame speed [rad/s electrical] the firmware wrote at each call, from the angles it wrote (the trace's
    ``theta_hat``: ``theta_k = theta_(k-1) + w_k``); 0 at the first."""
    d = np.diff(np.asarray(theta, dtype=np.int64), prepend=int(theta[0]))
    return ((d + 2**31) % 2**32 - 2**31) * w_lsb


def reduce(prog: Program, st, sc, cs: CommissionSettings, theta: np.ndarray | None = None,
           scan_only: bool = False, map_iterations: int = MAP_ITERATIONS) -> Results:
    """The motor data from the firmware's sums ``st`` (an :class:`~golden.firmware.ident.Ident`) and the frame
    angles it wrote each window (``theta``, the trace's ``theta_hat``; the spin's speeds); ``scan_only``: the
    inductances, the angle and the noise of the scan alone (a program that stopped after it); ``map_iterations``:
    the passes of the map's correction for the inverter's error (0: the ideal inverter's gains)."""
    sc_, hw = scales(sc), hardware_config(sc)
    f_sw, i_lsb, v_lsb = sc_.f_sw, sc_.i_lsb, sc_.v_lsb
    p = prog.params
    res = Results(theta_r=st.theta_r * 2 * math.pi / 2**32)
    means = [(_step_means(st, k, p.s_m[k]) if p.s_m[k] else None) for k in range(p.n_steps)]
    vh = [min((p.s_vh[k] * st.lvl) >> 16, p.vh_max) for k in range(p.n_steps)]
    gains = {}

    def gain(k: int) -> float:
        """The hardware's HF gain of step ``k`` (:func:`hf_response`) at its amplitude, its frame in the stator
        (the scan before the angle was known: phi; later theta_r + phi) and its voltages."""
        if k not in gains:
            th = prog.steps[k].phi if prog.steps[k].stage in ("probe", "scan") else res.theta_r + prog.steps[k].phi
            s, c = sincos_q15(round(th / (2 * math.pi) * 2**32) % 2**32)
            gains[k] = hf_response(hw, sc_, sc.pwm.tick_hz, vh[k], s, c, round(means[k]["vd"]),
                                   round(means[k]["vq"]), sensor_bw=sensor_bandwidth(sc))[0]
        return gains[k]

    def pair(k: int) -> complex:
        """``Gamma_along - j Gamma_across`` [1/H] from the pair of steps ``k - 1`` (``v_h``) and ``k`` (``2 v_h``):
        the difference of their responses over the difference of the hardware's gains."""
        a, b = means[k - 1], means[k]
        if gain(k) == gain(k - 1):
            raise ValueError(f"step {k} ({prog.steps[k].stage}): the HF amplitude pair is one amplitude "
                             f"({vh[k]} LSB: commission.hf_voltage_max reached by both); raise hf_voltage_max or "
                             "lower hf_current")
        return ((b["gd"] - a["gd"]) - 1j * (b["gq"] - a["gq"])) / (gain(k) - gain(k - 1))

    # scan: g_d - j g_q = Y0 + Y2 exp(j 2 (phi - theta_r))
    scan = [k for k, s in enumerate(prog.steps) if s.stage == "scan"][1::2]
    phi = np.array([prog.steps[k].phi for k in scan])
    z = np.array([pair(k) for k in scan])
    y0 = float(np.mean(z.real))
    c2 = np.mean(z * np.exp(-2j * phi))
    y2 = float(abs(c2))
    res.values["L_d"], res.values["L_q"] = 1.0 / (y0 + y2), 1.0 / (y0 - y2)
    res.scan = {"phi": phi, "gamma": z, "theta_r": float(-np.angle(c2) / 2) % math.pi}
    # noise of one window's GAMMA_D, GAMMA (around each step's means), per axis, from the firmware's sum of
    # squares over every scan step
    every = [k for k, s in enumerate(prog.steps) if s.stage == "scan"]
    n_win = sum(p.s_m[k] for k in every)
    var = (st.g2 * 2**G2_SHIFT - sum(p.s_m[k] * (means[k]["gd"] ** 2 + means[k]["gq"] ** 2) for k in every)) / n_win
    sigma = math.sqrt(max(var, 0.0) / 2)
    g_sal = y2 * (gain(scan[0]) - gain(scan[0] - 1))                  # the saliency part of GAMMA [LSB] per v_h
    res.snr = g_sal / sigma if sigma > 0 else math.inf
    res.scan.update(sigma=sigma, g_sal=g_sal, v_hf=(vh[scan[0]] - vh[scan[0] - 1]) * v_lsb)
    if scan_only:
        return res
    # axis (a reluctance machine): the admittance along d at the bias replaces the fit's
    ax = [k for k, s in enumerate(prog.steps) if s.stage == "axis"][1::2]
    if ax:
        res.scan["fit_L_d"] = res.values["L_d"]
        res.values["L_d"] = res.scan["axis_L_d"] = 1.0 / pair(ax[0]).real
    # map: the inverse incremental inductance from the d and the q step of each point, with the inverter's error
    # at the point (golden.hf_gain): each step's responses are G times its HF gains, which depend on G (the phase
    # currents' signs at the switching edges); from the ideal inverter's G, map_iterations passes
    inv = inverter_model(sc, hw)

    def turn(phi: float) -> np.ndarray:
        """Coordinates in a frame ``phi`` ahead of the map's (the rotor's found) frame."""
        return np.array([[math.cos(phi), math.sin(phi)], [-math.sin(phi), math.cos(phi)]])

    def map_gains(k: int, y_map: np.ndarray | None) -> np.ndarray:
        """Step ``k``'s HF gains (GAMMA_D, GAMMA per 1 H): the ideal inverter's (``y_map`` None), else with the
        inverter's error for the admittance ``y_map`` (the map's frame) at the step's currents."""
        r, m = turn(prog.steps[k].phi), means[k]
        s, c = sincos_q15(round((res.theta_r + prog.steps[k].phi) / (2 * math.pi) * 2**32) % 2**32)
        point = None if y_map is None else OperatingPoint(r @ y_map @ r.T, (m["id"] * i_lsb, m["iq"] * i_lsb),
                                                          (p.s_id[k], p.s_iq[k]))
        return np.array(hf_response(hw, sc_, sc.pwm.tick_hz, vh[k], s, c, round(m["vd"]), round(m["vq"]),
                                    sensor_bw=sensor_bandwidth(sc), inverter=None if point is None else inv,
                                    point=point))

    mp = [k for k, s in enumerate(prog.steps) if s.stage == "map"]
    for kd, kq in zip(mp[::2], mp[1::2]):
        G = None
        for _ in range(map_iterations + 1):
            # G [u_d u_q] = [g_d g_q]: the responses and gains of both steps in the map's frame
            g, u = zip(*((turn(prog.steps[k].phi).T @ np.stack([[means[k]["gd"], means[k]["gq"]], map_gains(k, G)],
                                                                axis=1)).T for k in (kd, kq)))
            G = np.stack(g, axis=1) @ np.linalg.inv(np.stack(u, axis=1))
            G = 0.5 * (G + G.T)
        res.map.append((prog.steps[kd].i_d, prog.steps[kd].i_q, np.linalg.inv(G)))
    # lf: per axis, the up and the down transition; their mean replaces the scan's inductance when they agree
    axes = sorted({s.axis for s in prog.steps if s.stage == "lf_up"})
    if axes:
        res.lf = {axis: _lf_inductance(prog, st, means, axis, i_lsb, v_lsb, 1.0 / f_sw) for axis in axes}
        res.lf["used"] = all(abs(a - b) <= LF_AGREE * 0.5 * (a + b) for a, b in (res.lf[axis] for axis in axes))
        if res.lf["used"]:
            for axis in axes:
                res.values["L_" + axis] = float(np.mean(res.lf[axis]))
    # a reluctance machine: the algebraic saturation model fitted to the map and the chords of stage lf (its
    # controller's flux maps come from it; the points are too few and too far apart to interpolate)
    if not cs.magnets and res.lf.get("used"):
        res.saturation, res.saturation_rms = fit_inductances(saturation_data(prog, res))
    # resistance: V = R i + V0 + b / i through the three levels (b: the dead time's share that the node
    # capacitances take back at small currents, their charge time ~ C V_dc / i)
    rk = [k for k, s in enumerate(prog.steps) if s.stage == "resistance"]
    i_r = np.array([means[k]["id"] * i_lsb for k in rk])
    v_r = np.array([means[k]["vd"] * v_lsb for k in rk])
    R, v0, b = np.linalg.solve(np.stack([i_r, np.ones_like(i_r), 1 / i_r], axis=1), v_r)
    res.values["R_s"] = float(R)
    v0 = float(v0 + b / i_r[-1])                                     # the drops at the spin's current
    res.spin.update(v0=v0, i_r=i_r, v_r=v_r, r2=float((v_r[-1] - v_r[0]) / (i_r[-1] - i_r[0])))
    # spin: flux and torque of every measured step
    starts = np.concatenate([[0], np.cumsum(p.s_n)])
    w_frame = frame_speed(theta, sc_.w_lsb)
    pp = sc_.pole_pairs
    L_q = res.values["L_q"]
    spin = {}
    for k, s in enumerate(prog.steps):
        if s.stage not in SPIN_MEASURED or means[k] is None:
            continue
        j1 = starts[k + 1]
        # the frame speed active in the measured windows (written two calls before)
        w = float(np.mean(w_frame[j1 - p.s_m[k] - 2:j1 - 2]))
        mk = means[k]
        i = np.array([mk["id"], mk["iq"]]) * i_lsb
        v = np.array([mk["vd"], mk["vq"]]) * v_lsb
        i_n = i / max(np.hypot(*i), 1e-9)
        e = v - R * i - v0 * i_n                                    # drops along the current removed
        psi = np.array([e[1], -e[0]]) / w
        torque = 1.5 * pp * (psi[0] * i[1] - psi[1] * i[0])
        act = psi - L_q * i
        delta = math.atan2(act[1], act[0]) - math.atan2(i[1], i[0])
        spin[s.stage] = {"w": w, "torque": torque, "delta": delta, "v": v}
    a = abs(p.s_dw[[k for k, s in enumerate(prog.steps) if s.stage == "accel"][0]]) * sc_.w_lsb * f_sw  # rad/s^2 el
    res.spin.update(spin)
    if cs.magnets:
        # the coast: |v| = w_r psi_f, the rotor's speed w_r = the frame's plus the turn of the back-EMF in the
        # frame from the first half to the second (the rotor keeps the speed its I/f swing had)
        ca, cb = spin["coast_a"], spin["coast_b"]
        turn = math.remainder(math.atan2(cb["v"][1], cb["v"][0]) - math.atan2(ca["v"][1], ca["v"][0]), 2 * math.pi)
        w_r = 0.5 * (ca["w"] + cb["w"]) + turn * f_sw / p.s_m[[k for k, s in enumerate(prog.steps)
                                                              if s.stage == "coast_a"][0]]
        res.values["psi_f"] = 0.5 * (np.hypot(*ca["v"]) + np.hypot(*cb["v"])) / w_r
        res.spin["w_coast"] = w_r
    t_acc, t_dec = spin["accel"]["torque"], spin["decel"]["torque"]
    res.values["J"] = (t_acc - t_dec) / (2 * a / pp)
    w1, w2 = 0.5 * (spin["hold_low"]["w"] + spin["hold_low2"]["w"]) / pp, spin["hold_high"]["w"] / pp
    t1, t2 = 0.5 * (spin["hold_low"]["torque"] + spin["hold_low2"]["torque"]), spin["hold_high"]["torque"]
    res.values["B"] = (t2 - t1) / (w2 - w1)
    res.values["T_c"] = t1 - res.values["B"] * w1
    return res
