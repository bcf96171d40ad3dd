"""Scenario files: a TOML description of one simulation run, with units, defaults and validation.

A scenario names a motor preset and overrides any plant parameter (motor, mechanics, inverter,
current sensors, load), and sets what is not part of the plant: the PWM, the high-frequency
injection, the reference speed and where results go. :func:`load_scenario` reads a file,
:func:`parse_scenario` an already parsed dict; both return a :class:`Scenario` whose ``plant`` is a
complete parameter tree for the plant binding (``golden/plant/defaults.py`` layout), or raise
:class:`ScenarioError` listing every problem found, each with its dotted path
(``motor.magnetic.L_d: ...``). The format is documented in ``docs/scenario.md``; the accepted keys
are :data:`SCHEMA`.

Command line::

    python -m golden.scenario check FILE...
"""

from __future__ import annotations

import argparse
import difflib
import math
import re
import sys
import tomllib
from dataclasses import dataclass, fields as dataclass_fields
from pathlib import Path
from typing import Callable

import numpy as np

from golden import motors
from golden.firmware.estimator import METHODS, SLOT_HIGH, SLOT_LOW
from golden.limits import check_limits
from golden.plant import defaults as _plant_defaults
from golden.plant.binding import GATE_BITS, ffi as _plant_ffi
from golden.saturation_fit import fluxes
from golden.units import UnitError, finite_float, format_quantity, parse_quantity, type_name


MAG_MODELS: dict[str, int] = {"linear": 0, "dsat": 1, "algebraic": 2, "table": 3}
"""``motor.magnetic.model`` name -> ``mag.kind`` (``enum mag_kind`` in plant_api.h)."""

LOAD_MODES: dict[str, int] = {"torque": 0, "speed": 1}
"""``load.mode`` name -> ``mech.imposed_speed``."""

CONTROL_MODES: dict[str, int] = {"closed": 0, "fixed_angle": 1, "commission": 2}
"""``control.mode``: sensorless speed control, or the open-loop test with a fixed estimated angle."""

ADC_MODES: dict[str, int] = {"OS": 0, "DS": 1, "OS_BLANK": 2}
"""``control.adc_mode`` name -> ``CTRL.ADC_MODE`` (docs/spec.md, 2.3)."""

LOW_ESTIMATORS: dict[str, int] = {m.name: m.method for m in METHODS.values() if SLOT_LOW in m.slots}
"""``estimator.low`` name -> method id (golden.firmware.estimator.METHODS)."""

HIGH_ESTIMATORS: dict[str, int] = {"none": 0} | {m.name: m.method for m in METHODS.values()
                                                  if SLOT_HIGH in m.slots}
"""``estimator.high`` name -> method id (0: no hand-over)."""

SEED_LIMIT = 2**64
"""Seeds are ``unsigned long long``: 0 <= seed < 2**64."""

MAX_TICKS = 2**31 - 1
"""Tick counts such as ``max_substep_ticks`` are C ``int``."""

Check = Callable[[object], "str | None"]
"""A value check: returns the reason a (converted) value is invalid, or None."""


# ---- value checks ---------------------------------------------------------------------------------
def _positive(x: float) -> str | None:
    return None if x > 0 else "must be > 0"


def _non_negative(x: float) -> str | None:
    return None if x >= 0 else "must be >= 0"


def _between(low: int, high: int) -> Check:
    """A check for an integer in ``[low, high]``."""
    return lambda x: None if low <= x <= high else f"must be between {low} and {high}"


def _model_factor(x: float) -> str | None:
    """A ``[model_error]`` factor: a wrong controller, not a different motor (0.01..100; the comparison's errors are
    +-20 %). Found by tests/test_scenario_fuzz.py (2026-12-01): 5e-324 divided by zero in the HF current's scale."""
    return None if 0.01 <= x <= 100.0 else "must be between 0.01 and 100 (a factor on the controller's motor data)"


def _below_half_turn(x: float) -> str | None:
    """An angle limit the firmware holds as a binary angle (int32: below half a turn)."""
    return None if 0 < x < math.pi else "must be > 0 and below 180 deg (the firmware's int32 binary angle)"


def _off_or_below_half_turn(x: float) -> str | None:
    """An angle threshold the firmware holds as a binary angle, 0 meaning off."""
    return None if 0 <= x < math.pi else "must be >= 0 (0: off) and below 180 deg (the firmware's int32 binary angle)"


def _hold_time(x: float) -> str | None:
    return None if 0 <= x <= 10 else "must be between 0 and 10 s"


def _even_2_to_16(x: int) -> str | None:
    return None if 2 <= x <= 16 and x % 2 == 0 else "must be an even integer in 2..16 (the plant's range)"


def _file_name(x: str) -> str | None:
    """Names are used as directory names: letters, digits, '_', '-' and '.'."""
    ok = re.fullmatch(r"[A-Za-z0-9_.-]+", x) is not None
    return None if ok else "must be a non-empty name of letters, digits, '_', '-' and '.'"


def _non_empty(x: str) -> str | None:
    return None if x else "must not be empty"


# ---- schema ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Field:
    """One key of a scenario table.

    Attributes
    ----------
    kind : str
        ``"quantity"`` (number or ``"<number> <unit>"`` of ``dimension``), ``"number"`` (bare SI
        number), ``"integer"``, ``"text"``, ``"choice"`` (a key of ``choices``), ``"vector"`` (three
        quantities, one per phase, or one for all), ``"profile"`` (``[time, value]`` pairs, value of
        ``dimension``) or ``"table"`` (a sub-table, whose keys are ``SCHEMA[dotted path]``).
    dimension : str
        A dimension of :mod:`golden.units`, for quantities, vectors and profile values.
    check : Check or None
        Extra condition on the converted value.
    plant : tuple of str
        Where the value goes in the plant parameter tree (empty: not a plant parameter).
    choices : dict or None
        For ``"choice"``: accepted names -> value stored in the plant tree.
    default : object
        Value used when the key is absent (plant parameters default to the preset/plant defaults).
    required : bool
        The key must be present.
    """

    kind: str
    dimension: str = "dimensionless"
    check: Check | None = None
    plant: tuple[str, ...] = ()
    choices: dict[str, int] | None = None
    default: object = None
    required: bool = False


def _q(dimension: str, check: Check | None = None, plant: tuple[str, ...] = (),
       default: float | None = None) -> Field:
    """A quantity field."""
    return Field("quantity", dimension, check, plant, default=default)


def _int(check: Check, plant: tuple[str, ...] = ()) -> Field:
    """An integer field."""
    return Field("integer", check=check, plant=plant)


def _num(check: Check, plant: tuple[str, ...]) -> Field:
    """A bare-number field (SI coefficient without a unit of its own)."""
    return Field("number", check=check, plant=plant)


_TABLE = Field("table")

SCHEMA: dict[str, dict[str, Field]] = {
    "": {**{name: _TABLE for name in ("scenario", "motor", "mechanics", "inverter", "pwm", "sensors",
                                      "injection", "load", "reference", "control", "estimator",
                                      "simulation", "output", "protection", "model", "model_error", "commission")},
         "faults": Field("faults")},
    "scenario": {
        "name": Field("text", check=_file_name, required=True),
        "description": Field("text", default=""),
        "duration": Field("quantity", "time", _positive, required=True),
        "seed": _int(_between(0, SEED_LIMIT - 1), ("seed",)),
    },
    "motor": {
        "preset": Field("text"),
        "R_s": _q("resistance", _positive, ("R_s",)),
        "pole_pairs": _int(_between(1, 1000), ("mech", "pole_pairs")),
        "magnetic": _TABLE,
    },
    "motor.magnetic": {
        "model": Field("choice", plant=("mag", "kind"), choices=MAG_MODELS),
        "psi_f": _q("flux", _non_negative, ("mag", "psi_f")),
        "L_d": _q("inductance", _positive, ("mag", "L_d")),
        "L_q": _q("inductance", _positive, ("mag", "L_q")),
        "dsat_a": _num(_non_negative, ("mag", "dsat_a")),
        "dsat_S": _int(_even_2_to_16, ("mag", "dsat_S")),
        "a_d0": _num(_positive, ("mag", "a_d0")),
        "a_dd": _num(_non_negative, ("mag", "a_dd")),
        "a_q0": _num(_positive, ("mag", "a_q0")),
        "a_qq": _num(_non_negative, ("mag", "a_qq")),
        "a_dq": _num(_non_negative, ("mag", "a_dq")),
        **{exp: _int(_between(0, 64), ("mag", exp)) for exp in ("S", "T", "U", "V")},
    },
    "mechanics": {
        "J": _q("inertia", _positive, ("mech", "J")),
        "B": _q("viscous_friction", _non_negative, ("mech", "B")),
        "T_c": _q("torque", _non_negative, ("mech", "T_c")),
        "w_stick": _q("speed", _positive, ("mech", "w_stick")),
    },
    "inverter": {
        "V_dc": _q("voltage", _positive, ("inv", "V_dc")),
        "R_dc": _q("resistance", _non_negative, ("inv", "R_dc")),
        "ripple_amp": _q("voltage", _non_negative, ("inv", "ripple_amp")),
        "ripple_freq": _q("frequency", _non_negative, ("inv", "ripple_freq")),
        "v_sw": _q("voltage", _non_negative, ("inv", "v_sw")),
        "r_sw": _q("resistance", _non_negative, ("inv", "r_sw")),
        "v_diode": _q("voltage", _non_negative, ("inv", "v_diode")),
        "r_diode": _q("resistance", _non_negative, ("inv", "r_diode")),
        "C_node": _q("capacitance", _non_negative, ("inv", "C_node")),
    },
    "pwm": {
        "f_sw": _q("frequency", _positive, default=5e3),
        "dead_time": _q("time", _non_negative, default=4e-6),
        "tick_hz": _q("frequency", _positive, ("tick_hz",)),
    },
    "sensors": {
        "gain": Field("vector", "dimensionless", _positive, ("sens", "gain")),
        "offset": Field("vector", "current", None, ("sens", "offset")),
        "noise_rms": _q("current", _non_negative, ("sens", "noise_rms")),
        "bandwidth": _q("frequency", _non_negative, ("sens", "bandwidth_hz")),
        "ring_amp": _q("current", _non_negative, ("sens", "ring_amp")),
        "ring_freq": _q("frequency", _positive, ("sens", "ring_freq")),
        "ring_tau": _q("time", _positive, ("sens", "ring_tau")),
        "ring_cross": _q("dimensionless", _non_negative, ("sens", "ring_cross")),
        "adc_bits": _int(_between(1, 24), ("sens", "adc_bits")),
        "adc_range": _q("current", _positive, ("sens", "adc_range")),
        # the dc-link channel (docs/scenario.md): absent vdc_range is 2 x inverter.V_dc; 0 V: no channel
        "vdc_range": _q("voltage", _non_negative, ("sens", "vdc_range")),
        "vdc_gain": _q("dimensionless", _positive, ("sens", "vdc_gain")),
        "vdc_noise": _q("voltage", _non_negative, ("sens", "vdc_noise_rms")),
    },
    "injection": {
        "V_h": _q("voltage", _non_negative, default=100.0),
        "theta_hat": _q("angle", default=0.0),
        "v_d": _q("voltage", default=0.0),
        "v_q": _q("voltage", default=0.0),
    },
    "load": {
        "mode": Field("choice", choices=LOAD_MODES, default="torque"),
        "torque": Field("profile", "torque", default=[]),
        "speed": Field("profile", "speed", default=[]),
        "pulsation": _TABLE,
        "initial": _TABLE,
    },
    "load.pulsation": {
        "freq": _q("frequency", _non_negative, default=0.0),
        "depth": _q("dimensionless", _non_negative, default=0.0),
    },
    "load.initial": {
        "theta_m": _q("angle", None, ("theta_m0",)),
        "omega_m": _q("speed", None, ("omega_m0",)),
    },
    "reference": {
        "speed": Field("profile", "speed", default=[]),
    },
    "control": {
        "mode": Field("choice", choices=CONTROL_MODES, default="closed"),
        "adc_mode": Field("choice", choices=ADC_MODES, default="OS"),
        "switch_to_ds_at": _q("time", _non_negative),
        "sample_interval": _q("time", _positive, default=1e-6),
        "blank": _q("time", _non_negative, default=10e-6),
        "speed_filter": _q("frequency", _positive, default=30.0),
        "speed_bw": _q("frequency", _positive, default=8.0),
        "current_bw": _q("frequency", _positive, default=150.0),
        "i_max": _q("current", _positive, default=3.0),
        "v_max": _q("voltage", _positive, default=150.0),
        "i_trip": _q("current", _positive, default=6.0),
        "oc_limit": _q("current", _positive),
        "theta_hat": _q("angle", default=0.0),
        "converge": _q("time", _positive, default=0.06),
        "pulse": _q("time", _positive, default=0.03),
        "settle": _q("time", _positive, default=0.01),
        "i_pulse": _q("current", _positive, default=2.2),
        "dead_time_comp": Field("choice", choices={"off": 0, "on": 1}, default="off"),
        "dtc_zone": _q("current", _positive, default=0.1),
        "polarity": Field("choice", choices={"current": 0, "pilot": 1, "none": 2}, default="current"),
        "v_pilot": _q("voltage", _positive, default=100.0),
        "mtpa": Field("choice", choices={"off": 0, "on": 1}, default="off"),
        "notch_freq": _q("frequency", _non_negative, default=0.0),
        "notch_width": _q("frequency", _positive, default=400.0),
        "speed_rate": _q("frequency", _non_negative, default=0.0),
        "current_slew": _q("current_rate", _non_negative, default=0.0),
        "load_observer": _q("frequency", _non_negative, default=0.0),
        "law": Field("choice", choices={"foc_pwm": 0, "fcs_mpc": 1}, default="foc_pwm"),
        "flux_min": _q("flux", _non_negative, default=0.06),
        "inv_v_drop": _q("voltage", _non_negative, default=0.0),
        "inv_r_drop": _q("resistance", _non_negative, default=0.0),
        "dc_feedforward": Field("choice", choices={"off": 0, "on": 1}, default="off"),
    },
    "estimator": {
        "low": Field("choice", choices=LOW_ESTIMATORS, default="sqw_bangbang"),
        "high": Field("choice", choices=HIGH_ESTIMATORS, default="none"),
        "handover_up": _q("speed", _non_negative, default=350 * math.pi / 30),
        "handover_down": _q("speed", _non_negative, default=300 * math.pi / 30),
        "merge_time": _q("time", _positive, default=0.02),
        "watchdog_angle": _q("angle", _off_or_below_half_turn, default=0.0),
        "watchdog_speed": _q("speed", _non_negative, default=100 * math.pi / 30),
        "watchdog_hold": _q("time", _hold_time, default=0.05),
        "sqw_bangbang": _TABLE,
        "rfo": _TABLE,
        "rot_bpf": _TABLE,
        "eemf_smo": _TABLE,
        "sqw_cic": _TABLE,
        "hfo_proj": _TABLE,
    },
    # One table per method (docs/methods.md): its own parameters, used when a slot names it.
    "estimator.sqw_bangbang": {
        "K_bb": _q("speed", _positive, default=200.0),
        "pll_kp": Field("number", check=_positive, default=200.0),
        "pll_ki": Field("number", check=_positive, default=10000.0),
        "i_d_min": _q("current", _non_negative, default=0.0),
        "cross_saturation": Field("choice", choices=("off", "on"), default="off"),
    },
    "estimator.rfo": {
        "flux_bw": _q("frequency", _positive, default=70.0),
        "flux_bw_min": _q("frequency", _positive, default=5.0),
        "flux_ratio": Field("number", check=_positive, default=0.5),
        "pll_kp": Field("number", check=_positive, default=1000.0),
        "pll_ki": Field("number", check=_positive, default=250000.0),
        "i_d_min": _q("current", _non_negative, default=1.0),
    },
    "estimator.rot_bpf": {
        "f_inj": _q("frequency", _positive, default=500.0),
        "bpf_width": _q("frequency", _positive, default=164.0),
        "n_avg": Field("integer", check=_between(1, 32), default=20),
        "pll_kp": Field("number", check=_positive, default=100.0),
        "pll_ki": Field("number", check=_positive, default=2500.0),
        "hold": _q("time", _non_negative, default=0.008),
        "tracking": Field("choice", choices={"pll": 0, "observer": 1}, default="pll"),
        "observer_bw": _q("frequency", _positive, default=8.0),
        "i_d_min": _q("current", _non_negative, default=0.0),
        "cross_saturation": Field("choice", choices=("off", "on"), default="off"),
    },
    "estimator.eemf_smo": {
        "model": Field("choice", choices={"Lq": 0, "Ld": 1}, default="Lq"),
        "z_max": _q("voltage", _positive, default=200.0),
        "obs_pole": Field("number", check=_between(0.0, 0.95), default=0.5),
        "lpf_ratio": Field("number", check=_positive, default=2.0),
        "lpf_min": _q("frequency", _positive, default=5.0),
        "lpf_max": _q("frequency", _positive, default=1000.0),
        "e_min": _q("voltage", _non_negative, default=2.0),
        "dir_speed": _q("speed", _non_negative, default=50 * math.pi / 30),
        "pll_kp": Field("number", check=_positive, default=400.0),
        "pll_ki": Field("number", check=_positive, default=40000.0),
        "i_d_min": _q("current", _non_negative, default=1.0),
    },
    "estimator.sqw_cic": {
        "observer_bw": _q("frequency", _positive, default=15.0),
        "cic_m": Field("integer", check=_between(1, 16), default=2),
        "torque_ff": Field("choice", choices={"off": 0, "on": 1}, default="on"),
        "q_min": _q("current", _non_negative, default=0.1),
        "hold": _q("time", _non_negative, default=0.004),
        "i_d_min": _q("current", _non_negative, default=0.0),
        "cross_saturation": Field("choice", choices=("off", "on"), default="off"),
    },
    "estimator.hfo_proj": {
        "g": _q("frequency", _positive, default=10.0),
        "w_g": _q("frequency", _positive, default=2.0),
        "pll_bw": _q("frequency", _positive, default=25.0),
        "phi_min": _q("voltage", _non_negative, default=60.0),
        "phi_knee": _q("voltage", _positive, default=200.0),
        "n_max": Field("integer", check=_between(0, 1000), default=5),
        "lut_step": _q("current", _positive, default=0.125),
        "lut_knee": _q("current", _non_negative, default=2.0),
        "lut_coarse": Field("integer", check=_between(0, 4), default=1),
        "lut_max_d": _q("current", _positive, default=10.0),
        "lut_max_q": _q("current", _positive, default=4.5),
        "eps_max": _q("angle", _below_half_turn, default=math.pi / 18),
        "i_lag": _q("time", _non_negative, default=0.0),
        "hold": Field("choice", choices={"off": 0, "on": 1}, default="on"),
        "map_scale_d": Field("number", check=_between(0.5, 2.0), default=1.0),
        "map_scale_q": Field("number", check=_between(0.5, 2.0), default=1.0),
    },
    # Fault checks of the firmware (golden.firmware.protection, docs/faults.md); 0 turns a check off, an
    # absent key takes the default that golden.control_config.protection_params derives from the scenario.
    "protection": {
        "checks": Field("choice", choices={"on": 1, "off": 0}, default="on"),
        "lock_emf": _q("voltage", _non_negative),
        "lock_emf_rel": Field("number", check=_non_negative, default=0.25),
        "lock_time": _q("time", _positive, default=5e-3),
        "track_current": _q("current", _non_negative),
        "track_time": _q("time", _positive, default=20e-3),
        "overload_time": _q("time", _non_negative, default=0.5),
        "overload_speed": _q("speed", _non_negative, default=100 * math.pi / 30),
        "overload_speed_time": _q("time", _non_negative, default=0.02),
        "speed_max": _q("speed", _non_negative),
        "asc_speed": _q("speed", _non_negative),
        "restarts": Field("integer", check=_between(0, 1000), default=0),
        "restart_delay": _q("time", _positive, default=0.5),
        "catch_time": _q("time", _non_negative, default=0.0),
        "catch_probe": _q("current", _non_negative, default=0.0),
        "hf_response": Field("number", check=_between(0, 1), default=0.09),
        "hf_time": _q("time", _positive, default=3.2e-3),
        "undervoltage": Field("number", check=lambda x: None if 0 < x < 1 else "must be between 0 and 1",
                              default=0.75),
        "overvoltage": Field("number", check=lambda x: None if x > 1 else "must be > 1", default=1.25),
        "dc_link_time": _q("time", _positive, default=0.6e-3),
        "frozen_time": _q("time", _non_negative, default=0.8e-3),
        "frozen_samples": Field("integer", check=_between(2, 65535), default=16),
        "slip_speed": _q("speed", _non_negative),
        "slip_time": _q("time", _positive, default=5e-3),
        "load_max": Field("number", check=_non_negative, default=1.4),
        "load_time": _q("time", _positive, default=20e-3),
    },
    # Self-commissioning (`hfi commission`, golden.commission): absent keys are derived from the scenario
    "commission": {
        "current": _q("current", _positive),
        "hf_current": _q("current", _positive),
        "probe_voltage": _q("voltage", _positive),
        "hf_voltage_max": _q("voltage", _positive),
        "speed": _q("speed", _positive),
        "spin_time": _q("time", _positive, default=1.0),
        "lock": Field("choice", choices={"on": 1, "off": 0}, default="on"),
        "scan_points": Field("integer", check=_between(4, 24), default=12),
        "snr": Field("number", check=_positive, default=8.0),
    },
    # The controller's motor model (measured by `hfi commission`): what golden.control_config tunes the firmware
    # from instead of the plant's own data; R_s, L_d, L_q, psi_f and J are required when the table is given
    # (_check_model), absent: the plant's nominal data.
    "model": {
        "R_s": _q("resistance", _positive),
        "L_d": _q("inductance", _positive),
        "L_q": _q("inductance", _positive),
        "psi_f": _q("flux", _non_negative),
        "J": _q("inertia", _positive),
        "B": _q("viscous_friction", _non_negative, default=0.0),
        "T_c": _q("torque", _non_negative, default=0.0),
        "saturation": _TABLE,
    },
    # The controller's saturation model (a reluctance machine's, fitted by `hfi commission`): the algebraic model of
    # motor.magnetic (golden.saturation_fit), every key required when the table is given (_check_model)
    "model.saturation": {
        "a_d0": Field("number", check=_positive), "a_q0": Field("number", check=_positive),
        **{name: Field("number", check=_non_negative) for name in ("a_dd", "a_qq", "a_dq")},
        **{exp: Field("integer", check=_between(0, 64)) for exp in ("S", "T", "U", "V")},
    },
    "model_error": {name: Field("number", check=_model_factor, default=1.0)
                    for name in ("R_s", "L_d", "L_q", "psi_f", "J")},
    "simulation": {
        "max_substep": _q("time", _positive),
        "max_substep_commutation": _q("time", _positive),
    },
    "output": {
        "dir": Field("text", check=_non_empty),
    },
}
"""Dotted table path (``""`` is the top level) -> key -> :class:`Field`."""

_PHASE = Field("choice", choices={"a": 0, "b": 1, "c": 2}, required=True)
_ADC_CHANNEL = Field("choice", choices={"a": 0, "b": 1, "c": 2, "dc": 3}, required=True)
"""An ADC fault's channel: the current of phase a, b, c, or the dc link (``dc``: plant channel 3, lane C)."""
FAULTS: dict[str, tuple[str, dict[str, Field]]] = {
    "sensor_offset": ("FAULT_SENSOR_OFFSET", {"phase": _PHASE, "offset": _q("current", None, default=0.0),
                                              "drift": _q("current_rate", None, default=0.0)}),
    "sensor_gain": ("FAULT_SENSOR_GAIN", {"phase": _PHASE,
                                          "gain": Field("number", check=_non_negative, required=True)}),
    "adc_stuck": ("FAULT_ADC_STUCK", {"phase": _ADC_CHANNEL, "code": Field("integer", check=_non_negative,
                                                                           required=True)}),
    "adc_lane_dead": ("FAULT_ADC_STUCK", {"phase": _ADC_CHANNEL}),
    "phase_open": ("FAULT_PHASE_OPEN", {"phase": _PHASE}),
    "switch_open": ("FAULT_SWITCH_OPEN", {"switch": Field("choice", choices=GATE_BITS, required=True)}),
    "dc_link": ("FAULT_DC_LINK", {"factor": Field("number", check=_between(0.0, 2.0), required=True),
                                  "tau": _q("time", _non_negative, default=0.0)}),
    "load_step": ("FAULT_LOAD_STEP", {"torque": Field("quantity", "torque", required=True)}),
    "rotor_blocked": ("FAULT_ROTOR_BLOCKED", {}),
}
"""``[[faults]]`` kind -> (``enum fault_kind`` name in plant_api.h, its keys besides ``kind`` and ``at``);
docs/faults.md. ``adc_lane_dead``: the serial data line of the channel stuck low, which reads code 0."""

FAULT_KIND_IDS: dict[str, int] = _plant_ffi.typeof("enum fault_kind").relements
"""``enum fault_kind`` name -> value, read from plant_api.h."""


def _join(section: str, key: str) -> str:
    return f"{section}.{key}" if section else key


def _field(path: str) -> Field:
    """The :class:`Field` of a dotted path such as ``"motor.magnetic.L_d"``."""
    section, _, key = path.rpartition(".")
    return SCHEMA[section][key]


# ---- results --------------------------------------------------------------------------------------
class ScenarioError(ValueError):
    """An invalid scenario; ``problems`` lists every problem found, each starting with its path.

    Parameters
    ----------
    source : str
        The file name (or a description of where the data came from).
    problems : list of str
        One message per problem.
    """

    def __init__(self, source: str, problems: list[str]):
        self.source = source
        self.problems = list(problems)
        count = f"{len(problems)} problem{'s' if len(problems) != 1 else ''}"
        super().__init__(f"{source}: {count}:\n  " + "\n  ".join(self.problems))


@dataclass(frozen=True)
class PwmSettings:
    """FPGA PWM: switching frequency [Hz], dead time [s] and FPGA clock [Hz]."""

    f_sw: float
    dead_time: float
    tick_hz: float


@dataclass(frozen=True)
class InjectionSettings:
    """Square-wave injection of amplitude ``V_h`` [V] on the fixed estimated d-axis ``theta_hat``
    [rad, electrical], on top of the fundamental voltage references ``v_d``, ``v_q`` [V]."""

    V_h: float
    theta_hat: float
    v_d: float
    v_q: float


@dataclass(frozen=True)
class ControlSettings:
    """The controller: ``control.*`` of docs/scenario.md, SI units (angles in rad, speeds in rad/s;
    ``switch_to_ds_at`` is None when the ADC mode never changes."""

    mode: str
    adc_mode: str
    switch_to_ds_at: float | None
    sample_interval: float
    blank: float
    speed_filter: float
    speed_bw: float
    current_bw: float
    i_max: float
    v_max: float
    i_trip: float
    oc_limit: float | None
    theta_hat: float
    converge: float
    pulse: float
    settle: float
    i_pulse: float
    dead_time_comp: str
    dtc_zone: float
    polarity: str
    v_pilot: float
    mtpa: str
    notch_freq: float
    notch_width: float
    speed_rate: float
    current_slew: float
    load_observer: float
    law: str
    flux_min: float
    inv_v_drop: float
    inv_r_drop: float
    dc_feedforward: str


@dataclass(frozen=True)
class EstimatorSettings:
    """The estimator slots (``estimator.*``, docs/methods.md): ``low`` and ``high`` method names
    (``high`` may be ``"none"``), the hand-over speeds [rad/s mechanical] and the merge time constant [s];
    ``params``: method name -> that method's own table (SI values, defaults filled in); the hand-over's watchdog
    (docs/methods.md): the angle between the two slots beyond which it acts [rad electrical, 0: off], the speed
    above which it acts [rad/s mechanical] and how long its hand-over holds [s]."""

    low: str
    high: str
    handover_up: float
    handover_down: float
    merge_time: float
    params: dict
    watchdog_angle: float = 0.0
    watchdog_speed: float = 0.0
    watchdog_hold: float = 0.0


@dataclass(frozen=True)
class ProtectionSettings:
    """The ``[protection]`` table (docs/faults.md): SI values, None where the key is absent (the default is
    derived from the scenario by golden.control_config.protection_params)."""

    checks: str
    lock_emf: float | None
    lock_emf_rel: float
    lock_time: float
    track_current: float | None
    track_time: float
    overload_time: float
    overload_speed: float
    overload_speed_time: float
    speed_max: float | None
    asc_speed: float | None
    restarts: int
    restart_delay: float
    catch_time: float
    catch_probe: float
    hf_response: float
    hf_time: float
    undervoltage: float
    overvoltage: float
    dc_link_time: float
    frozen_time: float
    frozen_samples: int
    slip_speed: float | None
    slip_time: float
    load_max: float
    load_time: float


@dataclass(frozen=True)
class CommissionTable:
    """The ``[commission]`` table (docs/commissioning.md): SI values, None where a key is absent (its default is
    derived from the scenario by golden.commission.settings)."""

    current: float | None
    hf_current: float | None
    probe_voltage: float | None
    hf_voltage_max: float | None
    speed: float | None
    spin_time: float
    lock: str
    scan_points: int
    snr: float


@dataclass(frozen=True)
class ModelSettings:
    """The ``[model]`` table (docs/scenario.md): the motor data the controller uses, SI units. ``R_s`` [ohm]
    (motor and inverter), ``L_d``, ``L_q`` [H] (incremental, at zero current), ``psi_f`` [V*s] (0: a reluctance
    machine), ``J`` [kg*m^2], ``B`` [N*m*s/rad], ``T_c`` [N*m]; ``saturation``: the ``[model.saturation]`` table
    (the algebraic model's coefficients and exponents, SI) or None: with it the controller's magnetic model is that
    model (and ``L_d``, ``L_q`` are the measured values, for the record), without it a linear one of ``L_d``,
    ``L_q``, ``psi_f``."""

    R_s: float
    L_d: float
    L_q: float
    psi_f: float
    J: float
    B: float
    T_c: float
    saturation: dict | None = None


@dataclass(frozen=True)
class ModelError:
    """The ``[model_error]`` table (docs/scenario.md): factors on the controller's motor data, for robustness
    studies (1: exact). The plant is unchanged."""

    R_s: float
    L_d: float
    L_q: float
    psi_f: float
    J: float


MODEL_REQUIRED = ("R_s", "L_d", "L_q", "psi_f", "J")
"""The ``[model]`` keys required when the table is given."""


@dataclass(frozen=True)
class OutputSettings:
    """Where the run writes its results (a directory, relative to the working directory)."""

    dir: str


@dataclass
class Scenario:
    """A validated scenario.

    Attributes
    ----------
    name, description : str
    duration : float
        Simulated time [s].
    seed : int
        Random seed (also ``plant["seed"]``).
    plant : dict
        Complete plant parameter tree (keys of ``struct plant_params``), SI units.
    pwm : PwmSettings
    injection : InjectionSettings
    reference_speed : list of (float, float)
        Piecewise-linear reference speed points (time [s], mechanical speed [rad/s]).
    output : OutputSettings
    preset : str or None
        The motor preset the plant parameters start from (None: plant defaults).
    source : str
        Where the scenario was read from.
    faults : tuple of FaultSpec
        The ``[[faults]]`` entries in onset order (also ``plant["faults"]``).
    protection : ProtectionSettings
        The fault checks' settings (``[protection]``, defaults filled in where fixed).
    model : ModelSettings or None
        The controller's motor model (``[model]``); None when the table is absent (the controller then
        takes the plant's nominal data: golden.control_config.controller_motor).
    model_error : ModelError or None
        Factors on that model (``[model_error]``); None when the table is absent.
    """

    name: str
    description: str
    duration: float
    seed: int
    plant: dict
    pwm: PwmSettings
    injection: InjectionSettings
    reference_speed: list[tuple[float, float]]
    output: OutputSettings
    control: ControlSettings | None = None
    estimator: EstimatorSettings | None = None
    preset: str | None = None
    source: str = "<dict>"
    faults: tuple = ()
    protection: ProtectionSettings | None = None
    model: ModelSettings | None = None
    commission: CommissionTable | None = None
    model_error: ModelError | None = None

    def summary(self) -> str:
        """One line: name, duration, motor, load, PWM and injection."""
        model = {kind: name for name, kind in MAG_MODELS.items()}[self.plant["mag"]["kind"]]
        mode = "speed" if self.plant["mech"]["imposed_speed"] else "torque"
        points = len(self.plant[{"speed": "speed", "torque": "load"}[mode]]["t"])
        return (f"{self.name}: {format_quantity(self.duration, 's')}, "
                f"motor {self.preset or 'default'} ({model}), {mode} load ({points} points), "
                f"f_sw {format_quantity(self.pwm.f_sw, 'Hz')}, "
                f"dead time {format_quantity(self.pwm.dead_time, 's')}, "
                f"V_h {format_quantity(self.injection.V_h, 'V')}")


# ---- conversion of one value ----------------------------------------------------------------------
class _Problems(ValueError):
    """Problems with one field (a vector or a profile may have several)."""

    def __init__(self, *messages: str):
        super().__init__("; ".join(messages))
        self.messages = list(messages)


def _checked(spec: Field, value: object, raw: object, path: str) -> object:
    """Apply ``spec.check`` to a converted value."""
    reason = spec.check(value) if spec.check else None
    if reason:
        raise _Problems(f"{path}: {reason}, got {raw!r}")
    return value


def _to_quantity(spec: Field, raw: object, path: str) -> float:
    try:
        value = parse_quantity(raw, spec.dimension, path)
    except UnitError as exc:
        raise _Problems(str(exc)) from None
    return _checked(spec, value, raw, path)


def _to_number(spec: Field, raw: object, path: str) -> float:
    if isinstance(raw, bool) or not isinstance(raw, (int, float)):
        raise _Problems(f"{path}: expected a bare number in SI units, got {type_name(raw)} "
                        f"({raw!r})")
    try:
        value = finite_float(raw, path)
    except UnitError as exc:
        raise _Problems(str(exc)) from None
    return _checked(spec, value, raw, path)


def _to_integer(spec: Field, raw: object, path: str) -> int:
    if isinstance(raw, bool) or not isinstance(raw, int):
        raise _Problems(f"{path}: expected an integer, got {type_name(raw)} ({raw!r})")
    return _checked(spec, raw, raw, path)


def _to_text(spec: Field, raw: object, path: str) -> str:
    if not isinstance(raw, str):
        raise _Problems(f"{path}: expected a string, got {type_name(raw)}")
    return _checked(spec, raw, raw, path)


def _to_choice(spec: Field, raw: object, path: str) -> str:
    names = list(spec.choices)
    if raw not in names:
        close = difflib.get_close_matches(str(raw), names, n=1)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise _Problems(f"{path}: {raw!r} is not one of {', '.join(map(repr, names))}{hint}")
    return raw


def _to_vector(spec: Field, raw: object, path: str) -> list[float]:
    """Three per-phase quantities, or one quantity for all three phases."""
    element = Field("quantity", spec.dimension, spec.check)
    if not isinstance(raw, list):
        return [_to_quantity(element, raw, path)] * 3
    if len(raw) != 3:
        raise _Problems(f"{path}: expected 3 values (phases a, b, c) or a single value, "
                        f"got {len(raw)}")
    return _collect([(_to_quantity, element, item, f"{path}[{i}]") for i, item in enumerate(raw)])


def _collect(jobs: list[tuple]) -> list:
    """Run ``converter(spec, raw, path)`` for each job; raise all their problems together."""
    results, messages = [], []
    for converter, spec, raw, path in jobs:
        try:
            results.append(converter(spec, raw, path))
        except _Problems as exc:
            messages += exc.messages
    if messages:
        raise _Problems(*messages)
    return results


def _to_point(spec: Field, raw: object, path: str) -> tuple[float, float]:
    """One ``[time, value]`` profile point."""
    if not isinstance(raw, list) or len(raw) != 2:
        got = f"an array of length {len(raw)}" if isinstance(raw, list) else type_name(raw)
        raise _Problems(f"{path}: expected a [time, value] pair, got {got}")
    time, value = _collect([(_to_quantity, Field("quantity", "time"), raw[0], f"{path}[0]"),
                            (_to_quantity, Field("quantity", spec.dimension), raw[1], f"{path}[1]")])
    return time, value


def _to_profile(spec: Field, raw: object, path: str) -> list[tuple[float, float]]:
    """Piecewise-linear ``[[time, value], ...]`` points with non-decreasing times."""
    if not isinstance(raw, list):
        raise _Problems(f"{path}: expected an array of [time, value] pairs, got {type_name(raw)}")
    points = _collect([(_to_point, spec, item, f"{path}[{i}]") for i, item in enumerate(raw)])
    backwards = [f"{path}[{i}]: time {raw[i][0]!r} is before the previous point's time "
                 f"{raw[i - 1][0]!r} (times must be non-decreasing)"
                 for i in range(1, len(points)) if points[i][0] < points[i - 1][0]]
    if backwards:
        raise _Problems(*backwards)
    return points


@dataclass(frozen=True)
class FaultSpec:
    """One ``[[faults]]`` entry: its kind (a key of :data:`FAULTS`), onset ``at`` [s], its end ``until`` [s]
    (None: the end of the run) and its own keys (SI values, defaults filled in)."""

    kind: str
    at: float
    values: dict
    until: float | None = None


def _to_fault(raw: object, path: str) -> FaultSpec:
    """One ``[[faults]]`` table: ``kind``, ``at`` and the kind's keys."""
    if not isinstance(raw, dict):
        raise _Problems(f"{path}: expected a table ([[faults]]), got {type_name(raw)}")
    if "kind" not in raw:
        raise _Problems(f"{path}.kind: missing (one of {', '.join(map(repr, FAULTS))})")
    kind = _to_choice(Field("choice", choices=dict.fromkeys(FAULTS, 0)), raw["kind"], f"{path}.kind")
    fields = {"at": _q("time", _non_negative), "until": _q("time", _positive)} | FAULTS[kind][1]
    messages = [f"{path}.{key}: not a key of fault kind {kind!r} (valid: kind, {', '.join(fields)})"
                for key in raw if key != "kind" and key not in fields]
    jobs = [(key, spec) for key, spec in fields.items() if key in raw]
    messages += [f"{path}.{key}: missing (required for fault kind {kind!r})"
                 for key, spec in fields.items() if key not in raw and (spec.required or key == "at")]
    values = {key: spec.default for key, spec in fields.items()}
    try:
        converted = _collect([(_CONVERTERS[spec.kind], spec, raw[key], f"{path}.{key}") for key, spec in jobs])
        values.update(zip((key for key, _ in jobs), converted))
    except _Problems as exc:
        messages += exc.messages
    if messages:
        raise _Problems(*messages)
    at, until = values.pop("at"), values.pop("until")
    if until is not None and until <= at:
        raise _Problems(f"{path}.until: {format_quantity(until, 's')} is not after at = {format_quantity(at, 's')}")
    return FaultSpec(kind, at, values, until)


def _to_faults(spec: Field, raw: object, path: str) -> list[FaultSpec]:
    """The ``[[faults]]`` array of tables."""
    if not isinstance(raw, list):
        raise _Problems(f"{path}: expected an array of tables ([[faults]]), got {type_name(raw)}")
    return _collect([(lambda _spec, item, where: _to_fault(item, where), spec, item, f"{path}[{i}]")
                     for i, item in enumerate(raw)])


_CONVERTERS = {"quantity": _to_quantity, "number": _to_number, "integer": _to_integer,
               "text": _to_text, "choice": _to_choice, "vector": _to_vector,
               "profile": _to_profile, "faults": _to_faults}


# ---- reading the tree -----------------------------------------------------------------------------
def _suggestion(key: str, section: str) -> str:
    """A hint for an unknown key: the same key in another table, or the closest valid key."""
    elsewhere = [_join(other, key) for other, fields in SCHEMA.items()
                 if other != section and key in fields]
    # [model] and [model_error] repeat motor keys for the controller: a misplaced motor key more likely means
    # the plant's
    elsewhere = [path for path in elsewhere if not path.startswith(("model.", "model_error."))] or elsewhere
    if elsewhere:
        return f" (did you mean {' or '.join(map(repr, elsewhere))}?)"
    valid = {name.lower(): name for name in SCHEMA[section]}
    close = difflib.get_close_matches(key.lower(), valid, n=1)
    if close:
        return f" (did you mean {valid[close[0]]!r}?)"
    return f" (valid: {', '.join(SCHEMA[section])})"


class _Reader:
    """Converts a parsed TOML tree against :data:`SCHEMA`, collecting every problem.

    Attributes
    ----------
    values : dict
        Dotted path -> converted value, for the keys present and valid.
    invalid : set of str
        Dotted paths of the keys present but invalid (consistency checks skip them).
    problems : list of str
    tables : set of str
        Dotted paths of the tables present.
    """

    def __init__(self) -> None:
        self.values: dict[str, object] = {}
        self.invalid: set[str] = set()
        self.problems: list[str] = []
        self.tables: set[str] = set()

    def read(self, table: dict, section: str = "") -> None:
        """Convert every key of ``table`` (the table at dotted path ``section``)."""
        for key, raw in table.items():
            path = _join(section, key)
            spec = SCHEMA[section].get(key)
            if spec is None:
                what = "key" if section else "section" if isinstance(raw, dict) else "top-level key"
                self.problems.append(f"{path}: unknown {what}{_suggestion(key, section)}")
            elif spec.kind == "table" and isinstance(raw, dict):
                self.tables.add(path)
                self.read(raw, path)
            elif spec.kind == "table":
                self.problems.append(f"{path}: expected a table, got {type_name(raw)}")
            else:
                self._convert(spec, raw, path)

    def _convert(self, spec: Field, raw: object, path: str) -> None:
        try:
            self.values[path] = _CONVERTERS[spec.kind](spec, raw, path)
        except _Problems as exc:
            self.problems += exc.messages
            self.invalid.add(path)

    def require(self) -> None:
        """Report the required keys that are absent."""
        for section, fields in SCHEMA.items():
            for key, spec in fields.items():
                path = _join(section, key)
                if spec.required and path not in self.values and path not in self.invalid:
                    self.problems.append(f"{path}: missing (required)")

    def has_table(self, section: str) -> bool:
        """Whether the scenario has the table ``section`` (possibly empty)."""
        return section in self.tables or any(p.startswith(section + ".") for p in self.values)

    def get(self, path: str) -> object:
        """The value of a non-plant key: as given, else its default (None if it was invalid)."""
        if path in self.invalid:
            return None
        return self.values.get(path, _field(path).default)

    def error(self, path: str, message: str) -> None:
        """Record a problem found by a consistency check."""
        self.problems.append(f"{path}: {message}")
        self.invalid.add(path)


# ---- building the plant tree ----------------------------------------------------------------------
def _preset_params(reader: _Reader, presets: dict | None) -> dict:
    """The partial plant tree of the preset named by ``motor.preset`` ({} when none)."""
    name = reader.values.get("motor.preset")
    if name is None:
        return {}
    if presets is None:
        presets = motors.PRESETS
    if name not in presets:
        close = difflib.get_close_matches(name, list(presets), n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        reader.error("motor.preset", f"unknown preset {name!r} ({hint}valid presets: "
                                     f"{', '.join(sorted(presets))})")
        return {}
    return {key: value for key, value in presets[name].items() if key in motors.PLANT_KEYS}


def _set(tree: dict, keys: tuple[str, ...], value: object) -> None:
    for key in keys[:-1]:
        tree = tree[key]
    tree[keys[-1]] = value


def _plant_profile(points: list[tuple[float, float]], reader: _Reader) -> dict:
    """A ``struct profile`` dict from points and the ``load.pulsation`` settings."""
    return {"t": [t for t, _ in points], "v": [v for _, v in points],
            "puls_freq": reader.get("load.pulsation.freq") or 0.0,
            "puls_depth": reader.get("load.pulsation.depth") or 0.0}


_TICK_FIELDS = {"simulation.max_substep": "max_substep_ticks",
                "simulation.max_substep_commutation": "max_substep_commutation_ticks"}
"""Durations given in seconds that the plant takes in whole ticks: path -> plant key."""


def _to_ticks(reader: _Reader, path: str, tick_hz: float) -> int | None:
    """The duration at ``path`` in whole ticks (rounded down), None when absent or invalid."""
    seconds = reader.values.get(path)
    if seconds is None or "pwm.tick_hz" in reader.invalid:
        return None
    scaled = seconds * tick_hz * (1 + 1e-9)
    ticks = math.floor(scaled) if math.isfinite(scaled) else math.inf      # inf: beyond a float, refused below
    text = format_quantity(seconds, "s")
    clock = f"pwm.tick_hz = {format_quantity(tick_hz, 'Hz')}"
    if ticks < 1:
        reader.error(path, f"{text} is shorter than one tick ({format_quantity(1 / tick_hz, 's')} "
                           f"at {clock})")
    elif ticks > MAX_TICKS:
        reader.error(path, f"{text} is more than {MAX_TICKS} ticks at {clock}")
    else:
        return ticks
    return None


def _build_plant(reader: _Reader, presets: dict | None) -> dict:
    """Defaults, then the preset, then every plant key of the scenario."""
    plant = _plant_defaults.merge(_plant_defaults.default_params(), _preset_params(reader, presets))
    for path, value in reader.values.items():
        spec = _field(path)
        if spec.plant:
            _set(plant, spec.plant, spec.choices[value] if spec.choices else value)
    mode = reader.get("load.mode")
    if mode is not None:
        plant["mech"]["imposed_speed"] = LOAD_MODES[mode]
        profile_key = {"torque": "load", "speed": "speed"}[mode]
        plant[profile_key] = _plant_profile(reader.get(f"load.{mode}") or [], reader)
    for path, plant_key in _TICK_FIELDS.items():
        ticks = _to_ticks(reader, path, plant["tick_hz"])
        if ticks is not None:
            plant[plant_key] = ticks
    if "sensors.vdc_range" not in reader.values:
        plant["sens"]["vdc_range"] = _plant_defaults.VDC_RANGE_DEFAULT * plant["inv"]["V_dc"]
    plant["faults"] = [_plant_fault(f, plant["tick_hz"]) for f in sorted(reader.get("faults") or [],
                                                                          key=lambda f: f.at)]
    return plant


def _plant_fault(f: FaultSpec, tick_hz: float) -> dict:
    """A ``struct fault`` of the plant (plant_api.h) from a scenario fault."""
    v = f.values
    channel = (FAULTS[f.kind][1]["phase"].choices[v["phase"]] if "phase" in v
               else GATE_BITS[v["switch"]] if "switch" in v else 0)
    value, rate = {
        "sensor_offset": (v.get("offset"), v.get("drift")), "sensor_gain": (v.get("gain"), 0.0),
        "adc_stuck": (v.get("code"), 0.0), "dc_link": (v.get("factor"), v.get("tau")),
        "load_step": (v.get("torque"), 0.0)}.get(f.kind, (0.0, 0.0))
    return {"kind": FAULT_KIND_IDS[FAULTS[f.kind][0]], "channel": channel,
            "tick": round(f.at * tick_hz), "until": 0 if f.until is None else round(f.until * tick_hz),
            "value": float(value), "rate": float(rate)}


# ---- consistency checks ---------------------------------------------------------------------------
def _check_dead_time(reader: _Reader) -> None:
    f_sw, dead_time = reader.get("pwm.f_sw"), reader.get("pwm.dead_time")
    if f_sw is None or dead_time is None or dead_time < 0.5 / f_sw:
        return
    reader.error("pwm.dead_time",
                 f"{format_quantity(dead_time, 's')} must be shorter than half the PWM period "
                 f"({format_quantity(0.5 / f_sw, 's')} at pwm.f_sw = {format_quantity(f_sw, 'Hz')})")


MAX_WINDOWS = 2_000_000
"""The most PWM periods a run may have: a run keeps every window's record and every sample in memory (about 3 KB per
window with 1 us oversampling), so 2 million is about 6 GB (400 s at 5 kHz)."""


def _check_duration(reader: _Reader) -> None:
    duration, f_sw = reader.get("scenario.duration"), reader.get("pwm.f_sw")
    if duration is None or f_sw is None or duration * f_sw <= MAX_WINDOWS:
        return
    reader.error("scenario.duration", f"{duration:.6g} s is {duration * f_sw:.3g} PWM periods at "
                 f"pwm.f_sw = {format_quantity(f_sw, 'Hz')}, more than {MAX_WINDOWS} (golden.scenario.MAX_WINDOWS: "
                 "a run keeps every window in memory); split it")


def _check_load_profiles(reader: _Reader) -> None:
    """The profile of the load mode is required; the other one would be silently ignored."""
    mode = reader.get("load.mode")
    if mode is None:
        return
    other = {"torque": "speed", "speed": "torque"}[mode]
    if f"load.{other}" in reader.values:
        reader.error(f"load.{other}", f"not used when load.mode = {mode!r}")
    if mode == "speed" and "load.speed" not in reader.values and "load.speed" not in reader.invalid:
        reader.error("load.speed", "missing (required when load.mode = 'speed')")


def _check_magnetics(reader: _Reader, mag: dict) -> None:
    """Parameters the chosen magnetic model needs, whether from the scenario or the preset."""
    if reader.values.get("motor.magnetic.model") == "table":
        reader.error("motor.magnetic.model", "'table' is not supported in scenario files yet "
                                             "(use a preset that provides the tables)")
    needs = {MAG_MODELS["dsat"]: ("psi_f",), MAG_MODELS["algebraic"]: ("a_d0", "a_q0")}
    model = {kind: name for name, kind in MAG_MODELS.items()}[mag["kind"]]
    for key in needs.get(mag["kind"], ()):
        path = f"motor.magnetic.{key}"
        if mag[key] <= 0 and path not in reader.invalid:
            reader.error(path, f"must be > 0 for model {model!r}, got {mag[key]!r}")


def _check_injection(reader: _Reader, plant: dict) -> None:
    """The injection plus the fundamental must stay within the linear modulation range."""
    inj = [reader.get(f"injection.{key}") for key in ("V_h", "v_d", "v_q")]
    if None in inj or "inverter.V_dc" in reader.invalid:
        return
    V_h, v_d, v_q = inj
    peak = math.hypot(abs(v_d) + V_h, v_q)
    limit = plant["inv"]["V_dc"] / math.sqrt(3)
    if peak > limit:
        reader.error("injection.V_h",
                     f"injection plus fundamental reach {format_quantity(peak, 'V')} "
                     f"(hypot(|v_d| + V_h, v_q)), above the linear modulation limit "
                     f"V_dc/sqrt(3) = {format_quantity(limit, 'V')} "
                     f"(inverter.V_dc = {format_quantity(plant['inv']['V_dc'], 'V')})")


def _check_estimator(reader: _Reader) -> None:
    """Hand-over speeds in order; the estimator table only with a closed-loop ``[control]``."""
    if reader.has_table("estimator") and not reader.has_table("control"):
        reader.error("estimator", "needs a [control] table (the estimators run in the closed loop only)")
    law, low, high = reader.get("control.law"), reader.get("estimator.low"), reader.get("estimator.high")
    flux = METHODS[low].flux if low in METHODS else False
    if law == "fcs_mpc" and not (flux and high == "none"):
        reader.error("control.law", f"fcs_mpc needs an estimator that observes the stator flux as "
                     f"estimator.low ({', '.join(m.name for m in METHODS.values() if m.flux)}) and "
                     f"estimator.high = \"none\" (got {low!r} and {high!r})")
    if law == "fcs_mpc" and reader.get("control.adc_mode") == "OS_BLANK":
        reader.error("control.adc_mode", "fcs_mpc needs the carrier-top samples (TOP_I), which OS_BLANK drops "
                     "whenever the inverter state changes there: use DS or OS")
    if law == "fcs_mpc" and reader.get("control.polarity") != "none":
        reader.error("control.polarity", "fcs_mpc runs without a polarity test (its law ignores the test's "
                     "current and voltage pulses): set control.polarity = \"none\"")
    if law != "fcs_mpc" and flux:
        reader.error("estimator.low", f"{low} runs with the direct-vector control law: set control.law = \"fcs_mpc\"")
    lo, hi = reader.get("estimator.rfo.flux_bw_min"), reader.get("estimator.rfo.flux_bw")
    if lo is not None and hi is not None and lo > hi:
        reader.error("estimator.rfo.flux_bw_min", f"{lo:g} Hz is above estimator.rfo.flux_bw ({hi:g} Hz): "
                     "the correction rate's floor must not exceed its ceiling")
    if reader.get("protection.catch_time"):
        if high == "none":
            reader.error("protection.catch_time", "the flying start needs a high-speed estimator (estimator.high) "
                         "to find a spinning rotor's angle and speed")
        if law != "foc_pwm":
            reader.error("protection.catch_time", "the flying start holds the currents at zero with the current "
                         "PIs: it needs control.law = \"foc_pwm\"")
    if reader.get("protection.catch_probe") and not reader.get("protection.catch_time"):
        reader.error("protection.catch_probe", "the short-circuit probe is the flying start's first step: it needs "
                     "protection.catch_time > 0")
    if reader.get("estimator.watchdog_angle") and reader.get("estimator.high") in (None, "none"):
        reader.error("estimator.watchdog_angle", "the hand-over's watchdog compares the two slots' angles: it needs "
                     "a high-speed estimator (estimator.high)")
    up, down = reader.get("estimator.handover_up"), reader.get("estimator.handover_down")
    if up is not None and down is not None and down > up:
        reader.error("estimator.handover_down",
                     f"{down * 30 / math.pi:g} rpm is above estimator.handover_up "
                     f"({up * 30 / math.pi:g} rpm): the hysteresis needs down <= up")


def _check_model(reader: _Reader) -> None:
    """A ``[model]`` table gives the whole model the controller needs (B and T_c default to 0)."""
    if not reader.has_table("model"):
        return
    for key in MODEL_REQUIRED:
        path = f"model.{key}"
        if path not in reader.values and path not in reader.invalid:
            reader.error(path, "missing (required when [model] is given)")
    if reader.has_table("model.saturation"):
        keys = [f"model.saturation.{key}" for key in SCHEMA["model.saturation"]]
        for path in keys:
            if path not in reader.values and path not in reader.invalid:
                reader.error(path, "missing (every coefficient and exponent is required when [model.saturation] "
                                   "is given)")
        if all(path in reader.values for path in keys):
            _check_saturation_model(reader, {path.rsplit(".", 1)[1]: reader.values[path] for path in keys})


def _check_saturation_model(reader: _Reader, model: dict) -> None:
    """The controller's saturation model must carry every current up to ``control.i_max`` (the controller's flux
    tables invert it there): a model without a flux solution in that range is refused with the current."""
    i_max = reader.values.get("control.i_max", SCHEMA["control"]["i_max"].default)

    def solvable(i_d, i_q) -> bool:
        try:
            with np.errstate(all="ignore"):
                return bool(np.all(np.isfinite(fluxes(model, i_d, i_q))))
        except RuntimeError:
            return False

    i_d, i_q = np.meshgrid(*(np.linspace(-i_max, i_max, 9),) * 2)
    if solvable(i_d, i_q):
        return
    bad = next((a, b) for a, b in zip(i_d.ravel(), i_q.ravel()) if not solvable(a, b))
    reader.error("model.saturation", f"the model has no flux linkage for the currents ({bad[0]:g}, {bad[1]:g}) A, "
                                     "within control.i_max: its coefficients or exponents are out of reach "
                                     "(docs/scenario.md)")


def _check_faults(reader: _Reader, plant: dict) -> None:
    """Onsets inside the run, one open phase, codes the ADC has, load steps only on a torque load."""
    faults, duration = reader.get("faults") or [], reader.get("scenario.duration")
    bits = plant["sens"]["adc_bits"]
    for i, f in enumerate(faults):
        path = f"faults[{i}]"
        if duration is not None and f.at >= duration:
            reader.error(f"{path}.at", f"{format_quantity(f.at, 's')} is not before the end of the run "
                                      f"(scenario.duration = {format_quantity(duration, 's')})")
        if f.kind == "adc_stuck" and f.values["code"] >= 2 ** bits:
            reader.error(f"{path}.code", f"{f.values['code']} is not a code of a {bits}-bit ADC "
                                        f"(0..{2 ** bits - 1}, sensors.adc_bits)")
        if f.kind == "load_step" and plant["mech"]["imposed_speed"]:
            reader.error(f"{path}.kind", "a load step needs load.mode = \"torque\" (the load machine imposes "
                                        "the speed)")
    if sum(f.kind == "phase_open" for f in faults) > 1:   # (the plant allows one, whatever their times)
        reader.error("faults", "at most one phase can be open (two open phases carry no current at all)")


# ---- public API -----------------------------------------------------------------------------------
def parse_scenario(data: dict, source: str = "<dict>", presets: dict | None = None) -> Scenario:
    """Validate a parsed scenario tree and build the :class:`Scenario`.

    Parameters
    ----------
    data : dict
        The scenario as parsed from TOML (tables are dicts, arrays are lists).
    source : str
        Named in error messages (the file name).
    presets : dict or None
        Motor presets, name -> partial plant tree (keys ``R_s``, ``mag``, ``mech``); None uses
        ``golden.motors.PRESETS``.

    Returns
    -------
    Scenario

    Raises
    ------
    ScenarioError
        Listing every problem found, each prefixed by its dotted path.
    """
    reader = _Reader()
    reader.read(data)
    reader.require()
    plant = _build_plant(reader, presets)
    _check_dead_time(reader)
    _check_duration(reader)
    _check_load_profiles(reader)
    _check_magnetics(reader, plant["mag"])
    _check_injection(reader, plant)
    _check_estimator(reader)
    _check_model(reader)
    check_limits(reader, plant)
    _check_faults(reader, plant)
    if reader.problems:
        raise ScenarioError(source, reader.problems)
    return _make_scenario(reader, plant, source)


def _make_scenario(reader: _Reader, plant: dict, source: str) -> Scenario:
    get = reader.get
    name = get("scenario.name")
    return Scenario(
        name=name,
        description=get("scenario.description"),
        duration=get("scenario.duration"),
        seed=plant["seed"],
        plant=plant,
        pwm=PwmSettings(get("pwm.f_sw"), get("pwm.dead_time"), plant["tick_hz"]),
        injection=InjectionSettings(*(get(f"injection.{key}")
                                      for key in ("V_h", "theta_hat", "v_d", "v_q"))),
        reference_speed=list(get("reference.speed")),
        output=OutputSettings(reader.values.get("output.dir", f"out/{name}")),
        control=(ControlSettings(*(get(f"control.{f.name}") for f in dataclass_fields(ControlSettings)))
                 if reader.has_table("control") else None),
        estimator=EstimatorSettings(
            get("estimator.low"), get("estimator.high"), get("estimator.handover_up"),
            get("estimator.handover_down"), get("estimator.merge_time"),
            {name: {key: get(f"estimator.{name}.{key}") for key in SCHEMA[f"estimator.{name}"]}
             for name in METHODS},
            get("estimator.watchdog_angle"), get("estimator.watchdog_speed"), get("estimator.watchdog_hold")),
        preset=reader.values.get("motor.preset"),
        source=source,
        faults=tuple(sorted(get("faults") or [], key=lambda f: f.at)),
        protection=ProtectionSettings(*(get(f"protection.{f.name}") for f in dataclass_fields(ProtectionSettings))),
        commission=CommissionTable(*(get(f"commission.{f.name}") for f in dataclass_fields(CommissionTable))),
        model=(ModelSettings(*(get(f"model.{f.name}") for f in dataclass_fields(ModelSettings)
                                 if f.name != "saturation"),
                               saturation=({key: get(f"model.saturation.{key}") for key in SCHEMA["model.saturation"]}
                                           if reader.has_table("model.saturation") else None))
               if reader.has_table("model") else None),
        model_error=(ModelError(*(get(f"model_error.{f.name}") for f in dataclass_fields(ModelError)))
                     if reader.has_table("model_error") else None),
    )


def load_scenario(path: str | Path, presets: dict | None = None) -> Scenario:
    """Read and validate a scenario file.

    Parameters
    ----------
    path : str or Path
        A TOML file (UTF-8).
    presets : dict or None
        See :func:`parse_scenario`.

    Returns
    -------
    Scenario

    Raises
    ------
    ScenarioError
        For TOML syntax errors (with the line) and every invalid field.
    OSError
        If the file cannot be read.
    """
    return parse_scenario(read_toml(path), source=str(path), presets=presets)


def read_toml(path: str | Path) -> dict:
    """The TOML tree of the scenario file ``path``; ScenarioError naming the file for a syntax error or text not in
    UTF-8, OSError if it cannot be read."""
    with open(path, "rb") as file:
        try:
            return tomllib.load(file)
        except tomllib.TOMLDecodeError as exc:
            raise ScenarioError(str(path), [f"TOML syntax error: {exc}"]) from None
        except UnicodeDecodeError as exc:
            raise ScenarioError(str(path), [f"not UTF-8 text: {exc}"]) from None


def main(argv: list[str] | None = None) -> int:
    """``check FILE...``: validate scenario files; returns 1 if any is invalid or unreadable."""
    parser = argparse.ArgumentParser(prog="python -m golden.scenario",
                                     description="Scenario file tools (format: docs/scenario.md).")
    commands = parser.add_subparsers(dest="command", required=True)
    check = commands.add_parser("check", help="validate scenario files and print a summary")
    check.add_argument("files", nargs="+", metavar="FILE")
    args = parser.parse_args(argv)
    status = 0
    for name in args.files:
        try:
            scenario = load_scenario(name)
        except ScenarioError as exc:
            print(exc)
            status = 1
        except OSError as exc:
            print(f"{name}: cannot read: {exc.strerror or exc}")
            status = 1
        else:
            print(f"{name}: ok ({scenario.summary()})")
    return status


if __name__ == "__main__":
    sys.exit(main())
