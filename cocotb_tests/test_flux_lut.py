"""rtl/hfi_flux_lut.v (the flux-map LUT accelerator, golden/firmware/flux_lut.py ``lut_point``): cocotb on
Verilator and Icarus, lint, and the elaboration-time parameter check.

The cocotb coroutines are in tb_flux_lut.py (directed, random_lookups, extreme_tables, reset_mid_operation,
start_while_busy); HFI_RANDOM_N look-ups (default hdl_runner.RANDOM_N on Verilator, RANDOM_N_ICARUS on
Icarus) against golden ``lut_point`` on the real motor table and random tables.
"""

from __future__ import annotations

import os
import shutil
import subprocess

import pytest

import hdl_runner

TOP = "hfi_flux_lut"
SRC = "hfi_flux_lut.v"
N_COCOTB_TESTS = 5


@pytest.mark.parametrize("sim", hdl_runner.SIMULATORS)
def test_flux_lut(sim, tmp_path):
    hdl_runner.run_cocotb(sim=sim, toplevel=TOP, sources=hdl_runner.rtl_sources(SRC), tb_module="tb_flux_lut",
                          build_dir=tmp_path / "build", expect_tests=N_COCOTB_TESTS)


def _tool(name: str) -> str:
    path = shutil.which(name, path=f"{hdl_runner.VENV_BIN}{os.pathsep}{os.environ.get('PATH', '')}")
    assert path, f"{name} not found (run scripts/setup.sh)"
    return path


def _verilator_lint(max_points: int) -> subprocess.CompletedProcess:
    return subprocess.run([_tool("verilator"), "--lint-only", "-Wall", f"-I{hdl_runner.RTL}",
                           f"-GMAX_POINTS={max_points}", str(hdl_runner.RTL / SRC)], capture_output=True, text=True)


def _iverilog(max_points: int, tmp_path) -> subprocess.CompletedProcess:
    return subprocess.run([_tool("iverilog"), "-g2005", "-Wall", "-I", str(hdl_runner.RTL),
                           "-P", f"{TOP}.MAX_POINTS={max_points}", "-o", str(tmp_path / "flux_lut.vvp"),
                           str(hdl_runner.RTL / SRC)], capture_output=True, text=True)


@pytest.mark.parametrize("max_points", [1024])
def test_lint_clean(max_points, tmp_path):
    """verilator --lint-only -Wall and iverilog -g2005 -Wall: no message at all."""
    proc = _verilator_lint(max_points)
    assert proc.returncode == 0 and "%Warning" not in proc.stderr, proc.stderr
    proc = _iverilog(max_points, tmp_path)
    assert proc.returncode == 0 and not proc.stderr.strip() and not proc.stdout.strip(), proc.stdout + proc.stderr


BAD_MODULE = "hfi_flux_lut_bad_parameter_MAX_POINTS_4_to_1024"


@pytest.mark.parametrize("max_points", [3, 1025])
def test_bad_parameters_are_build_errors(max_points, tmp_path):
    """MAX_POINTS outside 4..1024: both simulators refuse to build, naming the check's module."""
    proc = _verilator_lint(max_points)
    assert proc.returncode != 0 and BAD_MODULE in proc.stderr, proc.stderr
    proc = _iverilog(max_points, tmp_path)
    assert proc.returncode != 0 and BAD_MODULE in proc.stdout + proc.stderr, proc.stdout + proc.stderr
