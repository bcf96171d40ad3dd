"""Packaging of the RTL for users: the FuseSoC core lists exactly the IP's sources, and the whole IP
passes Verilator's strictest lint (-Wall) with no waiver outside the source files themselves."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CORE = ROOT / "hfi_dsp.core"


SOC_FILES = {"rtl/hfi_soc.v", "rtl/hfi_soc_ctl.v", "rtl/hfi_ram.v", "rtl/hfi_uart_tx.v", "rtl/regs/hfi_soc_map.vh",
             "rtl/hfi_soc_platform.vh", "rtl/hfi_cdc_bus.v", "rtl/hfi_soc_acc.v", "rtl/hfi_flux_lut.v", "rtl/hfi_vector.v",
             "rtl/regs/hfi_acc_map.vh", "rtl/hfi_cfu.v", "rtl/hfi_win_copy.v"}
"""The SoC around the IP (docs/soc.md): not part of hfi_dsp.core."""


def ip_sources() -> list[str]:
    return [p.relative_to(ROOT).as_posix() for p in sorted((ROOT / "rtl").glob("hfi_*.v"))
            if p.relative_to(ROOT).as_posix() not in SOC_FILES]


def core_files() -> list[str]:
    return re.findall(r"^\s+- (rtl/\S+?)(?::|$)", CORE.read_text(), flags=re.M)


def test_core_lists_every_rtl_source():
    listed = set(core_files())
    sources = set(ip_sources())
    includes = {p.relative_to(ROOT).as_posix() for p in (ROOT / "rtl").rglob("*.vh")} - SOC_FILES
    assert sources | includes == listed, (f"not in hfi_dsp.core: {sorted(sources | includes - listed)}; "
                                          f"listed but missing: {sorted(listed - sources - includes)}")


def test_core_parameters_match_the_top():
    top = (ROOT / "rtl" / "hfi_dsp.v").read_text()
    params = dict(re.findall(r"parameter (\w+) = (\d+)", top.split(") (", 1)[0]))
    core = dict(re.findall(r"^  (\w+): \{datatype: int, default: (\d+)", CORE.read_text(), flags=re.M))
    assert params == core, f"hfi_dsp parameters {params} != hfi_dsp.core {core}"


OPTIONS_OFF = ["-GROT_INJ=0", "-GDIFF_CIC=0", "-GFCS_MPC=0"]
"""hfi_dsp's build options (docs/rtl.md "Build options"), all left out."""


@pytest.mark.parametrize("options", [[], OPTIONS_OFF], ids=["default", "options_off"])
def test_verilator_lint_wall_whole_ip(options):
    verilator = Path(sys.executable).parent / "verilator"
    proc = subprocess.run([str(verilator), "--lint-only", "-Wall", "-Irtl", "--top-module", "hfi_dsp",
                           *options, *ip_sources()], cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr


@pytest.mark.parametrize("acc,options", [(1, []), (0, []), (1, OPTIONS_OFF + ["-GFLUX_LUT=0"]), (0, ["-GCFU=0"])],
                         ids=["acc", "no_acc", "acc_options_off", "no_acc_no_cfu"])
def test_verilator_lint_wall_soc(tmp_path, acc, options):
    """The SoC (our files) passes -Wall too, with and without its accelerators (parameter ACC), without its
    fixed-point unit (CFU = 0, the Tang Nano 20K's build) and with every
    build option left out; the core and the AXI4-Lite adapter's file (dependencies, not our source) are waived."""
    from hfi.rtl_backend import cpu_source, picorv32_source

    verilator = Path(sys.executable).parent / "verilator"
    waiver = tmp_path / "waive_dependencies.vlt"
    waiver.write_text(f'`verilator_config\nlint_off -file "*/picorv32.v"\nlint_off -file "*/{cpu_source().name}"\n')
    files = sorted({p.relative_to(ROOT).as_posix() for p in (ROOT / "rtl").glob("hfi_*.v")})
    proc = subprocess.run([str(verilator), "--lint-only", "-Wall", "-Irtl", "--top-module", "hfi_soc", f"-GACC={acc}", *options,
                           "--timescale", "1ns/1ps", str(waiver),
                           *files, str(cpu_source()), str(picorv32_source())], cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_core_falls_back_to_the_package_file(monkeypatch, tmp_path, capsys):
    """Without the generated core (a machine where hfi/vexriscv_gen.py cannot run) the SoC takes the package's
    VexRiscv_FullCfu.v, says so once, and the generated core, when there, has exactly that file's ports: the
    package's VexRiscv.v (the configuration it is generated from) and the CFU port."""
    from hfi import rtl_backend, soc_platform, vexriscv_gen

    generated = vexriscv_gen.core_path()
    package = rtl_backend._package_file(soc_platform.CPU_PACKAGE, soc_platform.CPU_VARIANT)
    with_cfu = rtl_backend._package_file(soc_platform.CPU_PACKAGE, vexriscv_gen.CFU_VARIANT)
    assert vexriscv_gen._ports(with_cfu, False) == vexriscv_gen._ports(package)
    assert len(vexriscv_gen._ports(with_cfu, True)) == 8
    if generated.is_file():
        assert rtl_backend.cpu_source() == generated
        assert vexriscv_gen._ports(generated) == vexriscv_gen._ports(with_cfu)
    monkeypatch.setattr(vexriscv_gen, "core_path", lambda icache_bytes=0, prediction="": tmp_path / "missing.v")
    monkeypatch.setattr(rtl_backend, "_warned_fallback", False)
    assert rtl_backend.cpu_source().name == vexriscv_gen.CFU_VARIANT
    assert rtl_backend.cpu_source().name == vexriscv_gen.CFU_VARIANT
    err = capsys.readouterr().err
    assert err.count("4 KiB instruction cache") == 1, err


def test_core_name_says_cache_and_prediction_and_bad_options_are_refused():
    """The generated core's file names its instruction cache and (unless static, as the package's files) its
    branch prediction; a cache that is no power of two and an unknown predictor stop before any tool runs."""
    from hfi import soc_platform, vexriscv_gen

    assert vexriscv_gen.core_name(16384, "static") == "VexRiscv_I16K"
    assert vexriscv_gen.core_name(4096, "dynamic_target") == "VexRiscv_I4K_dynamic_target"
    assert vexriscv_gen.core_name(4096, "static", cfu=True) == "VexRiscv_I4K_cfu"
    assert vexriscv_gen.core_path().name == f"VexRiscv_I16K_{soc_platform.CPU_PREDICTION}_cfu.v"
    assert soc_platform.CPU_PREDICTION in vexriscv_gen.PREDICTIONS
    with pytest.raises(vexriscv_gen.CoreGenError, match="power of two"):
        vexriscv_gen.generate(3000, "static")
    with pytest.raises(vexriscv_gen.CoreGenError, match="branch prediction 'bimodal'"):
        vexriscv_gen.generate(16384, "bimodal")
