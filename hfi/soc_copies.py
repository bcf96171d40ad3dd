"""Scenarios adapted to the soft core's speed: copies of a drive whose firmware step overruns its own period on the
VexRiscv at 50 MHz, slowed down so that the rtl backend can run them (tests/test_rtl_identity.py compares them with
golden; scripts/fw_layout.py profiles the 003 step on one)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

from golden.scenario import Scenario, load_scenario

ROOT = Path(__file__).resolve().parents[1]
SLOWDOWN_003 = 5.0
"""Factor of :func:`varatharajan2020_2khz`: 10 kHz / 5 = 2 kHz."""


def varatharajan2020_2khz() -> Scenario:
    """The 003 drive (scenarios/varatharajan2020_torquestep.toml: law fcs_mpc, CTRL.DIRECT, the estimator
    hfo_proj) at 2 kHz: its firmware step takes about 8100 CPU clocks mean in RUN, 8400 worst (with the accelerators
    of hfi_soc_acc and the 16 KiB instruction cache, docs/methods.md) on the soft core, more than the 5000 of
    the scenario's 10 kHz period, and the first step's CTRL.ENABLE must land within
    three quarters of a period (18 750 clocks at 2 kHz). So the rtl backend runs it at f_sw / 5 with V_dc / 5
    (the same flux per vector and period, so the same current ripple per period: 3 A on l_d, not 15 A
    through the trip limit), the voltage thresholds phi_min and phi_knee / 5 with it, and the 2 p.u. load
    step at 0.4 s (in RUN) instead of 0.8 s."""
    sc = load_scenario(ROOT / "scenarios" / "varatharajan2020_torquestep.toml")
    k = SLOWDOWN_003
    hp = sc.estimator.params["hfo_proj"]
    params = dict(sc.estimator.params, hfo_proj=dict(hp, phi_min=hp["phi_min"] / k, phi_knee=hp["phi_knee"] / k))
    plant = dict(sc.plant, inv=dict(sc.plant["inv"], V_dc=sc.plant["inv"]["V_dc"] / k),
                 load=dict(sc.plant["load"], t=[0.0, 0.4, 0.4]))
    return dataclasses.replace(sc, pwm=dataclasses.replace(sc.pwm, f_sw=sc.pwm.f_sw / k), plant=plant,
                               estimator=dataclasses.replace(sc.estimator, params=params))
