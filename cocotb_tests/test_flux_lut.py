"""rtl/hfi_flux_lut.v (the flux-map LUT accelerator, golden/firmware/flux_lut.py ``lut_point``): cocotb on
Verilator and Icarus through the wrapper cocotb_tests/hdl/tb_flux_lut_ram.v (the unit reading its tables
from rtl/hfi_ram.v's port b, wired as in hfi_soc), and lint.

The cocotb coroutines are in tb_flux_lut.py (directed, random_lookups, extreme_tables, reset_mid_operation,
start_while_busy); HFI_RANDOM_N look-ups (default ``hdl_runner.random_count``: the suite's or ``make deep``'s depth
per simulator) against golden ``lut_point`` on the real motor table and random tables, each load at new random
byte bases in the RAM.
"""

from __future__ import annotations

import os
import shutil
import subprocess

import pytest

import hdl_runner

TOP = "tb_flux_lut_ram"
SRC = "hfi_flux_lut.v"
WRAPPER = hdl_runner.TB_DIR / "hdl" / "tb_flux_lut_ram.v"
RAM_AW = 14             # the unit's default: 64 KiB
N_COCOTB_TESTS = 5


@pytest.mark.long
@pytest.mark.parametrize("sim", hdl_runner.SIMULATORS)
def test_flux_lut(sim, tmp_path):
    hdl_runner.run_cocotb(sim=sim, toplevel=TOP, sources=[*hdl_runner.rtl_sources("hfi_ram.v", SRC), WRAPPER],
                          tb_module="tb_flux_lut", build_dir=tmp_path / "build", parameters={"RAM_AW": RAM_AW},
                          expect_tests=N_COCOTB_TESTS)


def _tool(name: str) -> str:
    path = shutil.which(name, path=f"{hdl_runner.VENV_BIN}{os.pathsep}{os.environ.get('PATH', '')}")
    assert path, f"{name} not found (run scripts/setup.sh)"
    return path


@pytest.mark.parametrize("ram_aw", [14, 13, 8])
def test_lint_clean(ram_aw, tmp_path):
    """verilator --lint-only -Wall and iverilog -g2005 -Wall of the unit (RAM_AW: the default, the SoC's
    32 KiB, a small RAM narrower than a table offset): no message at all."""
    proc = subprocess.run([_tool("verilator"), "--lint-only", "-Wall", f"-I{hdl_runner.RTL}", f"-GRAM_AW={ram_aw}",
                           str(hdl_runner.RTL / SRC)], capture_output=True, text=True)
    assert proc.returncode == 0 and "%Warning" not in proc.stderr, proc.stderr
    proc = subprocess.run([_tool("iverilog"), "-g2005", "-Wall", "-I", str(hdl_runner.RTL),
                           "-P", f"hfi_flux_lut.RAM_AW={ram_aw}", "-o", str(tmp_path / "flux_lut.vvp"),
                           str(hdl_runner.RTL / SRC)], capture_output=True, text=True)
    assert proc.returncode == 0 and not proc.stderr.strip() and not proc.stdout.strip(), proc.stdout + proc.stderr
