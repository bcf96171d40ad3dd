"""Packaging of the RTL for users: the FuseSoC core lists exactly the IP's sources, and the whole IP
passes Verilator's strictest lint (-Wall) with no waiver outside the source files themselves."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CORE = ROOT / "hfi_dsp.core"


def core_files() -> list[str]:
    return re.findall(r"^\s+- (rtl/\S+?)(?::|$)", CORE.read_text(), flags=re.M)


def test_core_lists_every_rtl_source():
    listed = set(core_files())
    sources = {p.relative_to(ROOT).as_posix() for p in (ROOT / "rtl").glob("hfi_*.v")}
    includes = {p.relative_to(ROOT).as_posix() for p in (ROOT / "rtl").rglob("*.vh")}
    assert sources | includes == listed, (f"not in hfi_dsp.core: {sorted(sources | includes - listed)}; "
                                          f"listed but missing: {sorted(listed - sources - includes)}")


def test_core_parameters_match_the_top():
    top = (ROOT / "rtl" / "hfi_dsp.v").read_text()
    params = dict(re.findall(r"parameter (\w+) = (\d+)", top.split(") (", 1)[0]))
    core = dict(re.findall(r"^  (\w+): \{datatype: int, default: (\d+)", CORE.read_text(), flags=re.M))
    assert params == core, f"hfi_dsp parameters {params} != hfi_dsp.core {core}"


def test_verilator_lint_wall_whole_ip():
    verilator = Path(sys.executable).parent / "verilator"
    files = [p.relative_to(ROOT).as_posix() for p in sorted((ROOT / "rtl").glob("hfi_*.v"))]
    proc = subprocess.run([str(verilator), "--lint-only", "-Wall", "-Irtl", "--top-module", "hfi_dsp", *files],
                          cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
