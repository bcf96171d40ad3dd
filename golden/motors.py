"""Motor presets: the machines of the reference papers, as partial plant parameter trees.

Each entry of :data:`PRESETS` holds the plant fields ``R_s``, ``mag`` (a partial ``struct mag_params``,
always with ``kind``) and ``mech`` (``pole_pairs, J, B, T_c, w_stick``), keyed by the C field names of
``golden/plant/src/plant_api.h``, plus a ``rated`` dict of informational values that the project uses
for tests and plots. ``rated`` is not a plant field: :func:`plant_fields` returns the preset without it,
ready for ``golden.plant.defaults.merge(default_params(), plant_fields(name))``.

Conventions of the plant (and of every number here): rotor frame d = magnet axis, or on a machine
without magnet the axis of LOWER inductance; amplitude-invariant Clarke transform, so currents, fluxes
and voltages in the dq frame are phase PEAK values; torque T = 1.5 p (psi_d i_q - psi_q i_d); psi_f is
the peak phase flux linkage of the magnet.

Keys of ``rated`` (all in SI units, all > 0 except ``i_d``):

``torque`` [N*m], ``speed_rpm`` [r/min], ``power`` [W]
    Rated values of the paper (``torque`` of ``xue2022_pmsm`` is derived as power / speed).
``current_peak`` [A]
    Rated current as the peak phase current = |i| in the dq frame (the papers' rms values times
    sqrt(2) where the paper's value is rms; see ``docs/motors.md`` for each decision).
``voltage`` [V]
    Rated line-to-line rms voltage; where the paper gives only the dc link, the largest line rms voltage
    of linear space-vector modulation, V_dc / sqrt(2).
``V_dc`` [V]
    DC-link voltage of the paper's drive, or an assumption documented in ``docs/motors.md``.
``i_d``, ``i_q`` [A]
    Maximum-torque-per-ampere split of ``current_peak`` in the plant's frame (motoring, i_q > 0),
    rounded to 1 mA.

Every value and assumption is documented, with its source and reasoning, in ``docs/motors.md``.
"""

from __future__ import annotations

import copy
import math

MAG_LINEAR = 0
MAG_DSAT = 1
MAG_ALGEBRAIC = 2
MAG_TABLE = 3

PLANT_KEYS = ("R_s", "mag", "mech")
"""Top-level keys of a preset that are plant fields (``rated`` is not)."""

_SQRT2 = math.sqrt(2.0)

PRESETS: dict[str, dict] = {
    # ---- 002 paper (Benevieri et al. 2023), Table I: 2 N*m, 5000 r/min, 1.04 kW, 376 V, 2.2 A ---------
    "benevieri2023_table1": {
        "R_s": 3.0,  # assumed: 1 kW-class servo, copper loss 1.5*R*I^2 = 21.8 W = 2.1 % at 2.2 A
        "mag": {
            "kind": MAG_DSAT,
            "psi_f": 0.147,   # Table I [Wb]: peak phase flux (back-EMF 377 V line rms at 5000 r/min)
            "L_d": 5.59e-3,   # Table I, measured at 5 kHz: incremental at i = 0
            "L_q": 6.26e-3,   # Table I
            "dsat_a": 0.022,  # assumed: l_d(+2.2 A) is 6.41 % below l_d(-2.2 A) (docs/motors.md)
            "dsat_S": 4,      # assumed
        },
        "mech": {
            "pole_pairs": 4,  # Table I
            "J": 4.0e-3,      # assumed: motor 2e-4 + coupled 25.7 N*m load machine 3.8e-3 kg*m^2
            "B": 1.0e-4,      # assumed: 0.052 N*m (2.6 % of rated) at 5000 r/min
            "T_c": 0.02,      # assumed: 1 % of rated torque
            "w_stick": 0.01,  # numerical regularisation of the Coulomb friction [rad/s]
        },
        "rated": {
            "torque": 2.0, "speed_rpm": 5000.0, "power": 1040.0, "voltage": 376.0,
            "current_peak": 2.2,  # Table I, a peak value: 0.882 N*m/A * 2.2 A = 1.94 N*m
            "V_dc": 560.0,        # assumed (project default): 400 V grid, rectified
            "i_d": -0.022, "i_q": 2.2,
        },
    },
    # ---- 002 paper, Table III: 10 N*m, 1995 r/min, 2.09 kW, 376 V, 3.6 A --------------------------------
    "benevieri2023_table3": {
        "R_s": 1.5,  # assumed: 2 kW-class servo, copper loss 58 W = 2.8 % at 5.09 A peak
        "mag": {
            "kind": MAG_DSAT,
            "psi_f": 0.34,    # Table III [Wb] (back-EMF 348 V line rms at 1995 r/min)
            "L_d": 4.9e-3,    # Table III: incremental at i = 0
            "L_q": 5.3e-3,    # Table III
            "dsat_a": 0.025,  # assumed: l_d(+5.09 A) is 6.30 % below l_d(-5.09 A)
            "dsat_S": 4,      # assumed
        },
        "mech": {
            "pole_pairs": 4,  # Table III
            "J": 5.5e-3,      # assumed: motor 1.2e-3 + coupled 29 N*m, 3000 r/min load machine 4.3e-3
            "B": 5.0e-4,      # assumed: 0.104 N*m (1 % of rated) at 1995 r/min
            "T_c": 0.1,       # assumed: 1 % of rated torque
            "w_stick": 0.01,
        },
        "rated": {
            "torque": 10.0, "speed_rpm": 1995.0, "power": 2090.0, "voltage": 376.0,
            "current_peak": 3.6 * _SQRT2,  # Table III's 3.6 A is rms: as a peak it would give 7.34 N*m
            "V_dc": 560.0,
            "i_d": -0.030, "i_q": 5.091,
        },
    },
    # ---- 000 paper (Tap et al. 2023), Table 1: washing-machine PMaSynRM, 375 W, 1.2 N*m -----------------
    # The paper puts d on the HIGH-inductance axis with the magnet on -q. Plant frame: d = the paper's
    # -q axis (magnet), q = the paper's d axis, theta = theta_paper - 90 deg; so L_d = L_q,paper and
    # L_q = L_d,paper (docs/motors.md derives the mapping of the voltage and torque equations).
    "tap2023_pmasynrm": {
        "R_s": 5.9,  # Table 1
        "mag": {
            "kind": MAG_DSAT,    # the paper gives no saturation data, but its polarity test needs some
            "psi_f": 0.096,      # Table 1: lambda_PM = 96 mWb
            "L_d": 0.067,        # Table 1: L_q,paper = 67 mH
            "L_q": 0.182,        # Table 1: L_d,paper = 182 mH
            "dsat_a": 0.00033,   # assumed: l_d(+2.29 A) is 6.65 % below l_d(-2.29 A) (docs/motors.md)
            "dsat_S": 4,         # assumed
        },
        "mech": {
            "pole_pairs": 2,  # Table 1
            "J": 2.7e-3,      # assumed: rotor 3e-4 + drum with wet laundry 0.35 kg*m^2 through a 1:12 belt
            "B": 2.0e-4,      # assumed: 0.063 N*m (5 % of rated) at 3000 r/min
            "T_c": 0.06,      # assumed: belt, drum bearings and seal, 5 % of rated torque
            "w_stick": 0.01,
        },
        "rated": {
            "torque": 1.2, "power": 375.0,
            "speed_rpm": 3000.0,            # base frequency 100 Hz with 2 pole pairs
            "current_peak": 1.62 * _SQRT2,  # Table 1: 1.62 A rms phase current
            "V_dc": 350.0,                  # Table 1
            "voltage": 350.0 / _SQRT2,      # no rated voltage in the paper: V_dc/sqrt(2)
            "i_d": -1.425, "i_q": 1.794,
        },
    },
    # ---- 001 paper (Xue et al. 2022), Table 1: IPMSM 3 kW, 540 V dc, 1200 r/min ------------------------
    "xue2022_pmsm": {
        "R_s": 0.19,  # Table 1
        "mag": {
            "kind": MAG_DSAT,    # the paper gives no saturation data; magnet polarity detection needs some
            "psi_f": 0.5,      # assumed: back-EMF 308 V line rms at 1200 r/min = 81 % of V_dc/sqrt(2)
            "L_d": 3.53e-3,    # Table 1
            "L_q": 7.48e-3,    # Table 1
            "dsat_a": 0.04,    # assumed: l_d(+5.7 A) about 5 % below l_d(-5.7 A) (docs/motors.md)
            "dsat_S": 4,       # assumed
        },
        "mech": {
            "pole_pairs": 4,  # Table 1
            "J": 0.02,        # assumed: motor 8e-3 + coupled load machine 1.2e-2 kg*m^2
            "B": 1.9e-3,      # assumed: 0.24 N*m (1 % of rated) at 1200 r/min
            "T_c": 0.24,      # assumed: 1 % of rated torque
            "w_stick": 0.01,
        },
        "rated": {
            "torque": 3000.0 / (1200.0 * 2.0 * math.pi / 60.0),  # 23.87 N*m = power / speed
            "speed_rpm": 1200.0, "power": 3000.0,
            "current_peak": 7.942,     # derived: MTPA current for 23.87 N*m with psi_f = 0.5 Wb
            "V_dc": 540.0,             # Table 1
            "voltage": 540.0 / _SQRT2,  # no rated voltage in the paper: V_dc/sqrt(2)
            "i_d": -0.494, "i_q": 7.927,
        },
    },
    # ---- 003 paper (Varatharajan et al. 2020), Table I: SyRM 1.1 kW, 1500 r/min, 7.1 N*m ----------
    # Plant frame: d = the LOW-inductance axis (the paper's q axis, with the ribs), q = the paper's d axis.
    # MAG_ALGEBRAIC coefficients fitted by scripts/fit_syrm_preset.py (run it to reproduce them and the
    # checks; docs/motors.md and docs/img/syrm_fluxmaps.png).
    "varatharajan2020_syrm": {
        "R_s": 4.5,  # Table I
        "mag": {
            "kind": MAG_ALGEBRAIC,
            "psi_f": 0.0,     # no magnet
            "a_d0": 0.9727, "a_dd": 1150.0, "a_q0": 0.9799, "a_qq": 1.248, "a_dq": 48.47,
            "S": 2, "T": 7, "U": 0, "V": 1,
        },
        "mech": {
            "pole_pairs": 2,  # Table I
            "J": 0.04,        # Table I
            "B": 4.5e-4,      # assumed: 0.071 N*m (1 % of rated) at 1500 r/min
            "T_c": 0.07,      # assumed: 1 % of rated torque
            "w_stick": 0.01,
        },
        "rated": {
            "torque": 7.1, "speed_rpm": 1500.0, "power": 1100.0, "voltage": 340.0,
            "current_peak": 2.3 * _SQRT2,  # Table I: 2.3 A rms
            "V_dc": 540.0,                 # assumed: 400 V grid, rectified
            "i_d": -2.855, "i_q": 1.559,   # MTPA of the fitted model: 7.056 N*m
        },
    },
}


def names() -> list[str]:
    """Names of the presets, in the order of :data:`PRESETS`."""
    return list(PRESETS)


def preset(name: str) -> dict:
    """A deep copy of one preset, including its informational ``rated`` dict.

    Parameters
    ----------
    name : str
        A key of :data:`PRESETS`.

    Returns
    -------
    dict
        ``{"R_s": ..., "mag": {...}, "mech": {...}, "rated": {...}}``; modifying it leaves
        :data:`PRESETS` unchanged.

    Raises
    ------
    KeyError
        If ``name`` is not a preset; the message lists the valid names.
    """
    try:
        return copy.deepcopy(PRESETS[name])
    except (KeyError, TypeError):
        raise KeyError(f"unknown motor preset {name!r}; valid presets: {', '.join(PRESETS)}") from None


def plant_fields(preset_or_name: str | dict) -> dict:
    """Only the plant fields (``R_s``, ``mag``, ``mech``) of a preset, as a deep copy.

    Parameters
    ----------
    preset_or_name : str or dict
        A preset name, or a preset dict as returned by :func:`preset`.

    Returns
    -------
    dict
        A partial parameter tree without ``rated``, to merge into ``golden.plant.defaults``.
    """
    p = preset(preset_or_name) if isinstance(preset_or_name, str) else preset_or_name
    return {k: copy.deepcopy(p[k]) for k in PLANT_KEYS}
