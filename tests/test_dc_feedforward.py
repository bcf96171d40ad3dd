"""The dc-link voltage feed-forward (``control.dc_feedforward``, golden/firmware/dc_feedforward.py) in the closed
loop: the default drive (scenarios/fullload_start.toml) with the link 10 % low from 0.6 s. Without the
feed-forward the square-wave injection's HF response falls with the link and the HF response check trips; with it
the drive rides through, and every V_H written is the nominal amplitude times nominal over measured link, from
that window's own VDC sample. The hls backend (the C firmware) is identical to golden with it."""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import numpy as np
import pytest

from golden.closedloop import ClosedLoop
from golden.control_config import firmware_params
from golden.firmware.dc_feedforward import ff_gain
from golden.firmware.protection import FAULT_HF_RESPONSE
from golden.firmware.supervisor import MODE_FAULT, MODE_RUN
from golden.fixed import round_shr
from golden.scenario import ScenarioError, parse_scenario

pytestmark = pytest.mark.xdist_group("dc_feedforward")
"""The module's tests share a module fixture: one worker runs them all (make test: --dist loadgroup)."""

ROOT = Path(__file__).resolve().parents[1]
BASE = tomllib.loads((ROOT / "scenarios" / "fullload_start.toml").read_text())
SAG_AT = 0.6


def sag(ff: str, duration: float = 0.8, factor: float = 0.9):
    data = copy.deepcopy(BASE)
    data["scenario"]["duration"] = f"{duration} s"
    data.setdefault("control", {})["dc_feedforward"] = ff
    data["faults"] = [{"kind": "dc_link", "factor": factor, "at": f"{SAG_AT} s"}]
    return parse_scenario(data, "fullload_start.toml with a sag")


@pytest.fixture(scope="module")
def runs():
    return {ff: ClosedLoop(sag(ff)).run(progress=False) for ff in ("off", "on")}


def test_without_it_a_10_percent_sag_trips_the_hf_check(runs):
    w, t = runs["off"].windows, runs["off"].t
    trip = np.flatnonzero(w["mode"] == MODE_FAULT)
    assert len(trip) and SAG_AT < t[trip[0]] < SAG_AT + 0.02 and w["fault"][trip[0]] == FAULT_HF_RESPONSE


def test_with_it_the_drive_rides_through(runs):
    w, t = runs["on"].windows, runs["on"].t
    assert not (w["mode"] == MODE_FAULT).any() and (w["mode"][t > SAG_AT] == MODE_RUN).all()
    assert (w["vdc"][t > SAG_AT + 0.001] < 0.92 * w["vdc"][t < SAG_AT].mean()).all()      # the link did sag


def test_each_v_h_written_is_scaled_by_its_window(runs):
    """V_H = round_shr(V_H_nom k, 14), k from the same window's VDC (the feed-forward's own integers), where the
    injection is on; before the sag k is within 1 % of 1, after it 1/0.9."""
    res, p = runs["on"], firmware_params(sag("on"))
    on = res.writes["v_h"] != 0
    k = np.array([ff_gain(int(v), p.ff_nom, p.ff_lo, p.ff_hi) for v in res.windows["vdc"]])
    want = np.minimum(round_shr(p.v_h * k, 14), 0x7FFF)
    assert on.sum() > 0.9 * len(on) and np.array_equal(res.writes["v_h"][on], want[on])
    after = res.t > SAG_AT + 0.001
    assert abs(np.median(k[~after]) / 2**14 - 1) < 0.01 and abs(np.median(k[after]) / 2**14 - 1 / 0.9) < 0.01


def test_hls_is_identical_with_it():
    from hfi.hls_backend import HlsClosedLoop

    sc = sag("on", duration=0.7)
    gold, hls = ClosedLoop(sc).run(progress=False), HlsClosedLoop(sc).run(progress=False)
    for k in gold.windows:
        assert np.array_equal(gold.windows[k], hls.windows[k]), k
    for k in gold.writes:
        assert np.array_equal(gold.writes[k], hls.writes[k]), k


def test_it_needs_the_measurement():
    data = copy.deepcopy(BASE)
    data.setdefault("control", {})["dc_feedforward"] = "on"
    data.setdefault("sensors", {})["vdc_range"] = "0 V"
    with pytest.raises(ScenarioError, match=r"control.dc_feedforward.*needs the dc-link measurement"):
        parse_scenario(data, "no channel")
