"""The start of a test on tb_hfi_dsp (hfi_dsp with the ADC model and recorders), shared by its benches."""

from __future__ import annotations

from cocotb.triggers import ClockCycles

from axil_driver import AxiLiteMaster


async def start(dut) -> AxiLiteMaster:
    """Safety pins low, recorders running, 20 clocks of reset; returns the AXI4-Lite master on ``s_axil``."""
    axi = AxiLiteMaster(dut, "s_axil", dut.clk)
    dut.flush.value = 0
    dut.sto.value = 0
    dut.desat.value = 0
    dut.rst.value = 1
    await ClockCycles(dut.clk, 20)
    dut.rst.value = 0
    return axi
