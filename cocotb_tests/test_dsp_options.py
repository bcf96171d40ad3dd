"""hfi_dsp's build options (docs/rtl.md "Build options"): with ROT_INJ, DIFF_CIC, FCS_MPC all 1 (the default) and
all 0, CAPS reads them, and each mode of a missing block does what the register map documents: the rotating
injection adds no voltage (every compare H/2 with V = 0), the CIC results read 0, the direct mode applies the
zero vector 000 (every compare 0, VECTOR.NEXT 0). With the blocks in, the same writes give a rotating voltage,
CIC results and an active vector, so each check can fail."""

from __future__ import annotations

import random

import pytest

from hdl_runner import TB_DIR, core_rtl_files, rtl_sources, run_cocotb


@pytest.mark.parametrize("on", [1, 0], ids=["options_in", "options_out"])
def test_dsp_options(tmp_path, on):
    bits = 12
    mid = 1 << (bits - 1)
    rng = random.Random(5)
    codes = [((mid + rng.randint(-200, 200)) << 16) | (mid + rng.randint(-200, 200)) for _ in range(20000)]
    build = tmp_path / "build"
    build.mkdir(parents=True)
    (build / "codes.hex").write_text("".join(f"{c:08x}\n" for c in codes))
    run_cocotb(sim="verilator", toplevel="tb_hfi_dsp",
               sources=[*rtl_sources(*core_rtl_files()), TB_DIR / "hdl" / "adc_model.v",
                        TB_DIR / "hdl" / "tb_hfi_dsp.v"],
               tb_module="tb_dsp_options", build_dir=build,
               parameters={"ADC_BITS": bits, "ROT_INJ": on, "DIFF_CIC": on, "FCS_MPC": on},
               env={"HFI_OPTIONS_ON": on}, build_args=["--timing"], expect_tests=3,
               public_all=True)    # tb_dsp_options reads hfi_dsp's compares (dut.dut.cmp_*)
