"""The platform facts of hfi_soc (hfi/soc_platform.py) and the files generated from them and from
golden.closedloop.WINDOW_FIELDS (scripts/gen_platform.py): up to date, and what each language reads is
the source's value (the C preprocessor, Verilator's elaboration of hfi_soc, the linker script)."""

from __future__ import annotations

import importlib.util
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from golden.closedloop import WINDOW_FIELDS
from hfi import soc_platform as sp

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "scripts" / "gen_platform.py"


def _load_gen():
    spec = importlib.util.spec_from_file_location("gen_platform", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


gen = _load_gen()


def test_generated_platform_files_up_to_date():
    problems = gen.check()
    assert problems == [], "run `make regs` (python scripts/gen_regs.py):\n" + "\n".join(problems)


def test_check_mode_reports_missing_and_changed_files(tmp_path):
    proc = subprocess.run([sys.executable, str(SCRIPT), "--check"], capture_output=True, text=True, cwd=tmp_path)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert gen.check(tmp_path) == [f"{rel}: missing" for rel in gen.RENDERERS]
    gen.write(tmp_path)
    assert gen.check(tmp_path) == []
    (tmp_path / gen.VERILOG).write_text(gen.render_verilog().replace(str(sp.RAM_BYTES), str(2 * sp.RAM_BYTES)))
    assert gen.check(tmp_path) == [f"{gen.VERILOG}: differs"]


def _c_value(expr: str, includes: str) -> int:
    """The value of a C expression as the host compiler evaluates it with the firmware's headers."""
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        pytest.skip("no C compiler")
    proc = subprocess.run([cc, "-E", "-P", "-I", str(ROOT / "firmware/include"), "-I", str(ROOT / "firmware/src"),
                           "-"], input=f"{includes}\nHFI_VALUE = {expr};\n", capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    line = [x for x in proc.stdout.splitlines() if x.startswith("HFI_VALUE")][0]
    return eval(line.split("=", 1)[1].strip(" ;").replace("u", ""))  # noqa: S307 (literal arithmetic)


def test_c_header_carries_the_source_values():
    inc = '#include "hfi_soc_platform.h"'
    assert _c_value("HFI_SOC_DSP_BASE", inc) == sp.DSP_BASE == 0x8000_0000
    assert _c_value("HFI_SOC_CTL_BASE", inc) == sp.CTL_BASE == 0x9000_0000
    assert _c_value("HFI_SOC_ACC_BASE", inc) == sp.ACC_BASE == 0xA000_0000
    assert _c_value("HFI_SOC_RAM_BYTES", inc) == sp.RAM_BYTES
    assert _c_value("HFI_SOC_IRQ_WINDOW", inc) == sp.IRQ_WINDOW
    assert _c_value("FW_TRACE_WORDS", '#include "fw_trace.h"') == len(sp.TRACE)


def test_trace_record_macro_writes_every_word_in_order():
    text = gen.render_trace()
    record = text[text.index("#define FW_TRACE_RECORD"):text.index("#define FW_TRACE_COLUMNS")]
    assert re.findall(r"put\(\(uint32_t\)\((.+?)\)\); /\* (\w+),", record) == [(w.expr, w.name) for w in sp.TRACE]
    columns = text[text.index("#define FW_TRACE_COLUMNS"):]
    assert [c for c, _ in re.findall(r"X\((\w+), (.+?)\);", columns)] == [
        w.name for w in sp.TRACE if w.name in WINDOW_FIELDS]


def test_trace_carries_the_estimator_slots():
    """The five slot columns of the golden trace come from the firmware's own state."""
    exprs = {w.name: w.expr for w in sp.TRACE}
    assert {k: exprs[k] for k in ("est", "theta_lo", "theta_hi", "omega_lo", "omega_hi")} == {
        "est": "st.active", "theta_lo": "st.est_theta[0]", "theta_hi": "st.est_theta[1]",
        "omega_lo": "st.est_omega[0]", "omega_hi": "st.est_omega[1]"}


def test_hls_window_record_is_the_integer_columns_of_window_fields():
    fields = re.findall(r"int64_t (\w+);", (ROOT / gen.HLS_WINDOW).read_text())
    assert fields == list(gen.window_record_fields())
    assert fields == [f for f in WINDOW_FIELDS if f not in
                      ("theta_e", "omega_m", "torque", "load_torque", "i_d_true", "i_q_true",
                       "e_cu", "q_d", "q_q", "t_int", "t2_int")]


def test_linker_and_make_fragments():
    # the commissioning image links for IDENT_RAM_BYTES: firmware/Makefile's IDENT=1 defines hfi_ram_bytes
    assert f"LENGTH = DEFINED(hfi_ram_bytes) ? hfi_ram_bytes : {sp.RAM_BYTES} }}" in (ROOT / gen.LINKER).read_text()
    assert f"RAM_BYTES := {sp.RAM_BYTES}\nIDENT_RAM_BYTES := {sp.IDENT_RAM_BYTES}\n" in (ROOT / gen.MAKE).read_text()
    assert "--defsym=hfi_ram_bytes=$(IDENT_RAM_BYTES)" in (ROOT / "firmware/Makefile").read_text()
    assert "INCLUDE hfi_soc_memory.ld" in (ROOT / "firmware/link.ld").read_text()


def test_dsp_defaults_equal_the_soc_values():
    """hfi_dsp's own parameter defaults (rtl/hfi_dsp.v, the IP) are the SoC's values of the source."""
    top = (ROOT / "rtl" / "hfi_dsp.v").read_text().split(") (", 1)[0]
    params = {k: int(v) for k, v in re.findall(r"parameter (\w+) = (\d+)", top)}
    assert {k: params[k] for k in ("ADC_BITS", "DEAD_MIN", "IRQ_LATENCY", "OS_MIN")} == {
        "ADC_BITS": sp.ADC_BITS, "DEAD_MIN": sp.DEAD_MIN, "IRQ_LATENCY": sp.IRQ_LATENCY, "OS_MIN": sp.OS_MIN}


def test_bad_source_values_are_refused(monkeypatch):
    monkeypatch.setattr(sp, "DSP_BASE", 0x1000_0100)
    with pytest.raises(gen.PlatformError, match="DSP_BASE = 0x10000100 is not a multiple of 2"):
        gen.render_header()
    monkeypatch.setattr(sp, "DSP_BASE", sp.CTL_BASE)
    with pytest.raises(gen.PlatformError, match="share a page"):
        gen.render_verilog()


def test_firmware_budget_by_period():
    """The step's budget (docs/soc.md, "Firmware budget"): 25 % of a 5 kHz period (issue 15), 70 % of the
    10 kHz methods' 100 us (issue 18: 30 % to spare); the 200 us boundary belongs to the long periods."""
    from hfi.rtl_backend import fw_budget_share
    assert fw_budget_share(1 / 5e3) == fw_budget_share(200e-6) == fw_budget_share(1e-3) == 0.25
    assert fw_budget_share(1 / 10e3) == fw_budget_share(199e-6) == 0.70
