"""rtl/hfi_vector.v against golden/firmware/vector.py (spec 5.3): cocotb on Verilator and Icarus, and lint.

The cocotb coroutines are in tb_vector.py. Random pairs: hdl_runner's default counts (under Verilator 100 000 in
``make deep``, the project rule for a bit-true block, and 20 000 in ``make test``; 10 000 and 2 000 under Icarus);
``HFI_RANDOM_N`` overrides both. The include file rtl/hfi_cordic_tables.vh is found through hdl_runner's include path
(``rtl/``), as for hfi_cordic.v.
"""

from __future__ import annotations

import os
import shutil
import subprocess

import pytest

import hdl_runner

TOP = "hfi_vector"
N_COCOTB_TESTS = 5  # directed, random_pairs, back_to_back, start_while_busy, reset_mid_operation


@pytest.mark.parametrize("sim", hdl_runner.SIMULATORS)
def test_vector(sim, tmp_path):
    hdl_runner.run_cocotb(
        sim=sim, toplevel=TOP, sources=hdl_runner.rtl_sources("hfi_vector.v"), tb_module="tb_vector",
        build_dir=tmp_path / "build", expect_tests=N_COCOTB_TESTS)


def _tool(name: str) -> str:
    path = shutil.which(name, path=f"{hdl_runner.VENV_BIN}{os.pathsep}{os.environ.get('PATH', '')}")
    assert path, f"{name} not found (run scripts/setup.sh)"
    return path


def test_lint_clean(tmp_path):
    """verilator --lint-only -Wall and iverilog -Wall: no message at all."""
    src = str(hdl_runner.rtl_sources("hfi_vector.v")[0])
    proc = subprocess.run([_tool("verilator"), "--lint-only", "-Wall", f"-I{hdl_runner.RTL}", src],
                          capture_output=True, text=True)
    assert proc.returncode == 0 and "%Warning" not in proc.stderr, proc.stderr
    proc = subprocess.run([_tool("iverilog"), "-g2012", "-Wall", "-I", str(hdl_runner.RTL),
                           "-o", str(tmp_path / "vector.vvp"), src], capture_output=True, text=True)
    assert proc.returncode == 0 and not proc.stderr.strip() and not proc.stdout.strip(), proc.stdout + proc.stderr
