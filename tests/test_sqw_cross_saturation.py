"""The square-wave estimator on a reluctance machine (golden/firmware/sqw_bangbang.py, golden/control_config.py
``cross_saturation_table``; docs/methods.md, "A reluctance machine under the square wave"): its magnetizing
current and its cross-saturation table.

The table is checked against an independent computation: the plant's own magnetic model (the C plant's
``mag_eval`` through golden.plant.fluxmap, not golden.saturation_fit's Python) at the operating point the drive
asks for, which for a magnet-free machine's MTPA is ``i_d = -|i_q|`` in closed form; the estimator's use of it by
hand-computed cases; C against golden by tests/test_fw_c.py (random tables) and tests/test_hls_identity.py.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import hfi.sweep as sw  # noqa: E402
from golden.control_config import cross_saturation_table, hardware_config, scales, sqw_params  # noqa: E402
from golden.firmware.sqw_bangbang import SqwParams, cross_saturation_gamma  # noqa: E402
from golden.hf_gain import hf_response, sensor_bandwidth  # noqa: E402
from golden.plant.binding import mag_eval  # noqa: E402
from golden.plant.fluxmap import psi_from_current  # noqa: E402
from golden.scenario import ScenarioError, load_scenario, parse_scenario  # noqa: E402

SPEC = ROOT / "sweeps" / "cross_002_on_003.toml"


def _syrm(**settings):
    """The first point of the SyRM pair's sweep with the table on and ``settings`` (dotted keys) set."""
    job = sw.jobs(sw.load_spec(SPEC), "test")[0]
    sw._set(job.tree, "estimator.sqw_bangbang.cross_saturation", "on")
    for key, value in settings.items():
        sw._set(job.tree, key, value)
    return parse_scenario(job.tree, SPEC.name)


def test_table_is_the_plants_cross_term_times_the_hf_gain():
    sc = _syrm()
    shift, table = cross_saturation_table(sc)
    sc_ = scales(sc)
    i_max = sc_.current(sc.control.i_max)
    assert len(table) - 2 < (i_max + (1 << shift) - 1) >> shift <= len(table) - 1    # covers 0..i_max, no more
    gain = hf_response(hardware_config(sc), sc_, sc.pwm.tick_hz, sc_.voltage(sc.injection.V_h), 0, 32767,
                       sensor_bw=sensor_bandwidth(sc))[0]
    i_d_min = sc.estimator.params["sqw_bangbang"]["i_d_min"]
    expected = []
    for k in range(len(table)):
        q = (k << shift) * sc_.i_lsb
        i_d = min(-q, -i_d_min)                    # MTPA of a linear magnet-free model: i_d = -i_q
        psi = psi_from_current(sc.plant["mag"], i_d, q)
        g_dq = mag_eval(sc.plant["mag"], psi[0], psi[1])[3]      # d i_d / d psi_q
        expected.append(round(gain * g_dq))
    assert table[0] == 0 and list(table) == expected
    assert min(table) < -1000                     # worth correcting: a window's GAMMA noise is about 300


def test_without_mtpa_the_table_holds_the_magnetizing_current():
    sc = _syrm(**{"control.mtpa": "off"})
    shift, table = cross_saturation_table(sc)
    sc_ = scales(sc)
    gain = hf_response(hardware_config(sc), sc_, sc.pwm.tick_hz, sc_.voltage(sc.injection.V_h), 0, 32767,
                       sensor_bw=sensor_bandwidth(sc))[0]
    q = (3 << shift) * sc_.i_lsb
    psi = psi_from_current(sc.plant["mag"], -0.3, q)
    assert table[3] == round(gain * mag_eval(sc.plant["mag"], psi[0], psi[1])[3])


def test_a_linear_model_is_refused_with_the_key():
    sc = load_scenario(ROOT / "scenarios" / "fullload_start.toml")
    sc.estimator.params["sqw_bangbang"]["cross_saturation"] = "on"
    with pytest.raises(ValueError, match="estimator.sqw_bangbang.cross_saturation"):
        sqw_params(sc)


def test_a_bad_choice_is_refused():
    job = sw.jobs(sw.load_spec(SPEC), "test")[0]
    sw._set(job.tree, "estimator.sqw_bangbang.cross_saturation", "yes")
    with pytest.raises(ScenarioError, match="estimator.sqw_bangbang.cross_saturation"):
        parse_scenario(job.tree, SPEC.name)


@pytest.mark.parametrize("i_q, expected", [
    (0, 10), (4, 10 + (30 - 10) * 4 // 8), (8, 30), (12, 30 + (-20 - 30) * 4 // 8), (16, -20), (1000, -20),
    (-4, -20), (-12, -5), (-(1 << 31), 20),
], ids=["zero", "between", "point", "falling", "end", "beyond", "negative", "negative_between", "s32_min"])
def test_the_estimator_reads_the_table_odd_in_i_q(i_q, expected):
    """``sign(i_q) g0(|i_q|)`` with the MTPA table's interpolation (floor shifts): grid 8 LSB, table (10, 30, -20)."""
    p = SqwParams(k_bb=1, pll_kp=0, pll_ki=0, xs_shift=3, xs_gamma=(10, 30, -20))
    assert cross_saturation_gamma(p, i_q) == expected


def test_no_table_reads_zero_and_bad_tables_are_refused():
    assert cross_saturation_gamma(SqwParams(1, 0, 0), 12345) == 0
    for kw in ({"xs_shift": 21, "xs_gamma": (0, 1)}, {"xs_gamma": (5,)}, {"xs_gamma": (0, 1 << 15)},
               {"xs_gamma": tuple(range(34))}):
        with pytest.raises(ValueError, match="cross-saturation table"):
            SqwParams(1, 0, 0, **kw)
    assert np.array_equal(SqwParams(1, 0, 0, xs_gamma=(1, 2, 3)).xs_len, 3)
