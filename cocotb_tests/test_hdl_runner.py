"""cocotb_tests/hdl_runner.py: the random depth of the cocotb runs (the suite's in ``make test``, the full one in
``make deep`` (``HFI_DEEP=1``), ``HFI_RANDOM_N`` over both: README, Tests) and what a Verilator build makes public."""

from __future__ import annotations

from pathlib import Path

import pytest

import hdl_runner


@pytest.mark.parametrize("deep, sim, expected", [(None, "verilator", 20_000), ("0", "verilator", 20_000),
                                                 ("1", "verilator", 100_000), (None, "icarus", 2_000),
                                                 ("1", "icarus", 10_000)])
def test_random_count_follows_the_depth(monkeypatch, deep, sim, expected):
    monkeypatch.delenv("HFI_RANDOM_N", raising=False)
    if deep is None:
        monkeypatch.delenv("HFI_DEEP", raising=False)
    else:
        monkeypatch.setenv("HFI_DEEP", deep)
    assert hdl_runner.random_count(sim) == expected


def test_random_n_overrides_the_depth(monkeypatch):
    monkeypatch.setenv("HFI_DEEP", "1")
    monkeypatch.setenv("HFI_RANDOM_N", "123")
    assert hdl_runner.random_count("verilator") == 123


class _Runner:
    """cocotb's runner as run_cocotb calls it: records the build's arguments, runs nothing."""

    def __init__(self):
        self.builds = []

    def build(self, build_dir, **kw):
        Path(build_dir).mkdir(parents=True, exist_ok=True)
        self.builds.append(kw)

    def test(self, **kw):
        return kw["results_xml"]


@pytest.mark.parametrize("sim, public_all, hidden", [("verilator", False, True), ("verilator", True, False),
                                                     ("icarus", False, False)])
def test_only_the_top_is_public_under_verilator(monkeypatch, tmp_path, sim, public_all, hidden):
    """Verilator builds get ``--no-public-flat-rw`` after cocotb's ``--public-flat-rw`` and, first among the sources,
    a control file making the top module's signals public (docs/rtl.md, Verification); ``public_all`` keeps cocotb's
    visibility; Icarus is untouched."""
    runner = _Runner()
    monkeypatch.setattr(hdl_runner, "get_runner", lambda sim: runner)
    monkeypatch.setattr(hdl_runner, "get_results", lambda xml: (1, 0))
    monkeypatch.setattr(hdl_runner, "BUILD_CACHE", tmp_path / "cache")
    src = tmp_path / "top.v"
    src.write_text("module top; endmodule\n")
    hdl_runner.run_cocotb(sim=sim, toplevel="top", sources=[src], tb_module="tb_top", build_dir=tmp_path / "b",
                          public_all=public_all)
    (build,) = runner.builds
    assert ("--no-public-flat-rw" in build["build_args"]) == hidden
    if hidden:
        vlt = Path(build["sources"][0])
        assert vlt.read_text() == '`verilator_config\npublic_flat_rw -module "top" -var "*"\n'
        assert build["sources"][1:] == [str(src)]
    else:
        assert build["sources"] == [str(src)]
