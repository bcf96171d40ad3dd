"""Default plant parameters, as a nested dict whose keys are the field names of ``struct plant_params``
in ``golden/plant/src/plant_api.h`` (the single source of the layout).

Motor presets (:mod:`golden.motors`) replace ``R_s``, ``mag`` and ``mech``; scenarios override any
field. Every number here is an assumption documented in ``docs/plant.md``.
"""

from __future__ import annotations

import copy

TICK_HZ = 100e6
"""FPGA clock: every plant time is an integer number of these ticks."""

VDC_RANGE_DEFAULT = 2.0
"""The dc-link channel's full scale (``sens.vdc_range``) as a multiple of ``inv.V_dc``, here and for a scenario
without ``sensors.vdc_range``: the nominal link at mid-scale, room for the overvoltage trip and for a
regenerating link (docs/scenario.md)."""

_DEFAULTS: dict = {
    "tick_hz": TICK_HZ,
    "max_substep_ticks": 100,  # RK4 step <= 1 us (accuracy study: docs/plant.md, scripts/bench_plant.py)
    "max_substep_commutation_ticks": 25,  # <= 0.25 us while a node capacitance is charged in dead time
    "seed": 1,
    "R_s": 3.0,
    "mag": {
        "kind": 0,
        "psi_f": 0.147,
        "L_d": 5.59e-3,
        "L_q": 6.26e-3,
        "dsat_a": 0.0,
        "dsat_S": 4,
        "a_d0": 0.0, "a_dd": 0.0, "a_q0": 0.0, "a_qq": 0.0, "a_dq": 0.0,
        "S": 0, "T": 0, "U": 0, "V": 0,
        "tab_nd": 0, "tab_nq": 0,
        "tab_psid0": 0.0, "tab_dpsid": 0.0, "tab_psiq0": 0.0, "tab_dpsiq": 0.0,
        "tab_id": None, "tab_iq": None,
    },
    "mech": {
        "pole_pairs": 4,
        "J": 4.0e-3,
        "B": 1.0e-4,
        "T_c": 0.02,
        "w_stick": 0.01,
        "imposed_speed": 0,
    },
    "inv": {
        "V_dc": 560.0,
        "R_dc": 0.0,
        "ripple_amp": 0.0,
        "ripple_freq": 300.0,
        "v_sw": 0.0, "r_sw": 0.0,
        "v_diode": 0.0, "r_diode": 0.0,
        "C_node": 0.0,
    },
    "sens": {
        "gain": [1.0, 1.0, 1.0],
        "offset": [0.0, 0.0, 0.0],
        "noise_rms": 0.0,
        "bandwidth_hz": 0.0,
        "ring_amp": 0.0,
        "ring_freq": 1.0e6,
        "ring_tau": 1.0e-6,
        "ring_cross": 0.0,
        "adc_bits": 16,
        "adc_range": 10.0,
        "vdc_range": VDC_RANGE_DEFAULT * 560.0,   # the inverter's V_dc above; 0 = no dc-link channel
        "vdc_gain": 1.0,
        "vdc_noise_rms": 0.0,
    },
    "load": {"t": [], "v": [], "puls_freq": 0.0, "puls_depth": 0.0},
    "speed": {"t": [], "v": [], "puls_freq": 0.0, "puls_depth": 0.0},
    "theta_m0": 0.0,
    "omega_m0": 0.0,
    "faults": [],  # struct fault entries (kind, channel, tick, value, rate), in tick order: docs/faults.md
}


def default_params() -> dict:
    """A fresh, fully populated parameter tree (ideal sensors, no load, linear Table I motor)."""
    return copy.deepcopy(_DEFAULTS)


def merge(base: dict, override: dict) -> dict:
    """Recursively copy ``override`` into a deep copy of ``base``; unknown keys raise ``KeyError``."""
    out = copy.deepcopy(base)
    for key, value in override.items():
        if key not in out:
            raise KeyError(key)
        if isinstance(out[key], dict) and isinstance(value, dict):
            out[key] = merge(out[key], value)
        else:
            out[key] = copy.deepcopy(value)
    return out
