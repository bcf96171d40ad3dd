"""pytest entry of the hfi_adc_scale cocotb tests (rtl/hfi_adc_scale.v, spec 3.1).

ADC_BITS sweep {1, 8, 12, 14, 16}: the default 12 bits with the full vector count, the other points
with 2000 random conversions each (the directed cases run at every point).
"""

from __future__ import annotations

import pytest

import hdl_runner

DEFAULT_BITS = 12
SWEEP_N = 2000


@pytest.mark.parametrize("bits", [1, 8, 12, 14, 16])
@pytest.mark.parametrize("sim", hdl_runner.SIMULATORS)
def test_adc_scale(sim, bits, tmp_path):
    hdl_runner.run_cocotb(sim=sim, toplevel="hfi_adc_scale",
                          sources=hdl_runner.rtl_sources("hfi_mul18.v", "hfi_adc_scale.v"),
                          tb_module="tb_adc_scale", build_dir=tmp_path / "build",
                          parameters={"ADC_BITS": bits}, env={"HFI_ADC_BITS": bits}, expect_tests=2,
                          random_n=None if bits == DEFAULT_BITS else SWEEP_N)
