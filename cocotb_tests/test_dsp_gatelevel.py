"""Gate-level replay, short (issue 15 item 4: what is built is what was verified).

The ECP5 netlist of hfi_dsp (synth_ecp5 at the default parameters, the netlist make synth places and
routes) with the cell models Yosys ships replays the first SHORT_S of the RTL replay's golden closed loop
(cocotb_tests/test_dsp_replay.py: same scenario, same inputs, same testbench tb_hfi_dsp.v +
tb_dsp_replay.py): every window result (GAMMA, GAMMA_D, SUM_ID, SUM_IQ, WSUM, N_SAMPLES), every gate
edge and every sampling instant must equal the golden trace. The flow, its caches (netlist keyed by
rtl/, Verilated simulator keyed by the netlist) and the long replay (make gatelevel, 1004 windows) are
in scripts/gatelevel.py; docs/rtl.md "Gate-level replay" has the times. The replay runs in ``make deep``, not in
``make test``: from a clean clone it synthesizes and builds the netlist's simulator first (4.5 min of a core on the
reference machine, a third of the suite's budget; README "Tests").
"""

from __future__ import annotations

import sys

import pytest

from hdl_runner import ROOT, RTL

sys.path.insert(0, str(ROOT / "scripts"))
import gatelevel  # noqa: E402

SHORT_S = 0.02
"""Simulated time of the short replay [s]: 99 windows, 2 M clock cycles (about 30 s of Verilator once the
netlist and the simulator are cached; docs/rtl.md)."""
SHORT_WINDOWS = 99


def test_gatelevel_sources_are_the_netlist():
    """The simulation reads the netlist and the cell models, no RTL source."""
    files = gatelevel.sources()
    assert not [f for f in files if f.resolve().parent == RTL], "an rtl/ source in the gate-level build"
    assert ROOT / gatelevel.NETLIST in files and ROOT / gatelevel.SHIM in files
    assert gatelevel.cell_models_dir() / "cells_sim.v" in files and gatelevel.MULT_MODEL in files


@pytest.mark.deep
@pytest.mark.long
def test_gatelevel_replay_short(tmp_path):
    r = gatelevel.replay(SHORT_S, tmp_path / "run")
    print(f"compared equal: {r['windows']} windows, {r['gate_edges']} gate edges, {r['samples']} sampling instants")
    assert r["windows"] == r["golden_windows"] == SHORT_WINDOWS      # every window of the golden trace compared
    assert r["gate_edges"] > 6 * SHORT_WINDOWS and r["samples"] > 100 * SHORT_WINDOWS   # 1 us oversampling
