"""The random depth of the cocotb runs (cocotb_tests/hdl_runner.py): the suite's in ``make test``, the full one in
``make deep`` (``HFI_DEEP=1``), ``HFI_RANDOM_N`` over both (README, Tests)."""

from __future__ import annotations

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
