"""The facts of the hfi_soc platform that more than one language needs, written once (docs/soc.md).

``scripts/gen_regs.py`` (``make regs``; its platform part is ``scripts/gen_platform.py``) generates
from this module:

* ``firmware/include/hfi_soc_platform.h``: the memory map, the RAM size and the window interrupt of the
  firmware (C);
* ``firmware/src/fw_trace.h``: the firmware trace record (``TRACE``) as the macro ``FW_TRACE_RECORD``
  and its length ``FW_TRACE_WORDS``;
* ``firmware/hfi_soc_memory.ld`` (the linker script's ``MEMORY``) and ``firmware/hfi_soc_platform.mk``
  (``RAM_BYTES`` of the RAM image);
* ``rtl/hfi_soc_platform.vh``: the address decode and the parameter defaults of ``rtl/hfi_soc.v``;
* ``hls/backend/hls_window.h``: ``struct hls_window``, the integer columns of
  :data:`golden.closedloop.WINDOW_FIELDS` (that tuple is the source of the per-window record).

Python (``hfi/rtl_backend.py``) imports the constants. The dead-time floor and the shortest sampling
interval are facts of the golden model (``golden.fpga``): they are re-exported here, not restated.
"""

from __future__ import annotations

from dataclasses import dataclass

from golden.fpga.adc_trigger import OS_MIN_DEFAULT
from golden.fpga.gate_generator import DEAD_MIN_DEFAULT

# ---------------------------------------------------------------- memory map (hfi_soc address decode)
PAGE_BITS = 4
"""The SoC decodes the top PAGE_BITS address bits (31:28): one page of 256 MiB per target."""
RAM_BASE = 0x0000_0000
"""RAM: code, data, stack (the stack grows down from the end)."""
DSP_BASE = 0x8000_0000
"""hfi_dsp registers (docs/registers.md). Peripherals sit in the upper half of the address space: the
core's data cache treats addresses with bit 31 set as I/O (never cached)."""
CTL_BASE = 0x9000_0000
"""SoC control block hfi_soc_ctl (docs/soc_registers.md)."""
ACC_BASE = 0xA000_0000
"""The arithmetic accelerators hfi_soc_acc in the CPU clock (docs/acc_registers.md)."""
IO_BIT = 31
"""Address bit that makes an access I/O (uncached) for the VexRiscv data cache (CPU_VARIANT)."""
RAM_BYTES = 65536
"""On-chip RAM of hfi_soc (parameter RAM_BYTES), the firmware's link region and its RAM image."""
IDENT_RAM_BYTES = 131072
"""RAM of the commissioning build (hfi_soc RAM_BYTES, the image ``make -C firmware IDENT=1``): the control firmware
with the identification executor and its program and sums (struct fw_ident, about 16 KiB) do not fit RAM_BYTES.
128 KiB take 64 DP16KD: the ULX3S's LFE5U-85F has 208, the LFE5U-25F 56 (docs/commissioning.md)."""

# ---------------------------------------------------------------- hfi_dsp parameters of the SoC
ADC_BITS = 12
"""Resolution of the serial ADC the SoC's hfi_dsp reads (a scenario's sens.adc_bits must equal it)."""
IRQ_LATENCY = 400
"""Window interrupt, clocks after the window boundary; the commit deadline is P - IRQ_LATENCY."""
PIN_LATENCY = 3
"""hfi_dsp's pins show tick t in clock t + PIN_LATENCY, clocks counted from 0 at the first clock with
rst = 0 and run = 1: the gate mask of tick t and the CONVST rise of a sample taken at tick t (the
registered timing reset, the gate generator's register and the output register; docs/rtl.md)."""
DEAD_MIN = DEAD_MIN_DEFAULT
"""Dead-time floor [clocks] (docs/spec.md 2.4)."""
OS_MIN = OS_MIN_DEFAULT
"""Shortest oversampling interval [clocks] (docs/spec.md 2.3)."""
IRQ_WINDOW = 3
"""Line of the core's external interrupt array (VexRiscv externalInterruptArray) that carries the hfi_dsp
window interrupt."""

# ---------------------------------------------------------------- CPU and clocks
CPU_PACKAGE = "pythondata_cpu_vexriscv"
"""PyPI package (pythondata-cpu-vexriscv) that holds the core's Verilog; never copied here."""
CPU_VARIANT = "VexRiscv.v"
"""The package's Verilog file of the configuration the SoC runs (the LiteX "standard" VexRiscv): RV32IM,
4 KiB instruction and data caches, single-cycle multiplier, iterative divider, machine-mode interrupts and
exceptions (docs/soc.md, "Why VexRiscv"). The SoC's core is generated from the package's generator
sources with this configuration and a larger instruction cache (hfi/vexriscv_gen.py); its ports are
checked against this file."""
CPU_ICACHE_BYTES = 16384
"""Instruction cache of the generated core (``GenCoreDefault --iCacheSize``): each method's control step
fits it (the 4 KiB of the package's files made refills 30-45 % of every step); 32 KiB measured faster for
the 000 and 003 steps but does not fit the LFE5U-25F's 56 block RAMs beside the 64 KiB RAM (docs/soc.md,
"The instruction cache"). A board may build another size (scripts/bitstream.py, ``Board.icache``)."""
CPU_PREDICTION = "dynamic_target"
"""Branch prediction of the generated core (``GenCoreDefault --prediction``: ``none``, ``static`` as the
package's files, ``dynamic``, ``dynamic_target``): ``dynamic_target`` (a branch target buffer in the fetch
stage) takes 5-12 % fewer clocks per control step on average than ``static`` (3-7 % in the worst step;
the firmware's saturations and mode tests are branches a static rule mispredicts) for 236 LUT4, 243 FF and
3 DP16KD more, with the core's Fmax unchanged (docs/soc.md, "Branch prediction"); both boards build it (a
board may build another: ``Board.prediction`` in scripts/bitstream.py)."""
CPU_CFU = True
"""The core has LiteX's CFU port (``GenCoreDefault --cfu true``, as the package's ``VexRiscv_FullCfu.v``): the
custom-0 instructions of the fixed-point unit rtl/hfi_cfu.v (docs/soc.md, "The fixed-point instructions")."""
CFU_OPCODE = 0x0B
"""Major opcode of the fixed-point instructions: RISC-V custom-0, R-type, as LiteX's CFU port decodes it
(``function_id = {funct7, funct3}``)."""
CFU_OPS = {"MUL": 0, "MAC": 1, "MSU": 2, "ADD": 3, "RND": 4, "FLR": 5, "SET": 6, "DIV": 7}
"""funct3 of each fixed-point instruction (hfi/cfu.py gives each one's arithmetic; funct7 holds the shift
``k``, 0..63, or DIV's width)."""
CPU_DCACHE_BYTES = 4096
"""Data cache of the core (the package's configuration, which the generator keeps): direct-mapped, so data
this far apart shares a line (scripts/fw_profile.py reports its refills per object)."""
CPU_CLOCK_DIVIDER = 2
"""The CPU clock is the tick clock divided by this (50 MHz at the 100 MHz tick): the board PLL makes
both; the co-simulation (sim/soc_sim.cpp) toggles cpu_clk with every CPU_CLOCK_DIVIDER-th tick clock."""


# ---------------------------------------------------------------- firmware trace record
@dataclass(frozen=True)
class TraceWord:
    """One 32-bit word of the firmware trace record.

    ``expr``: its C expression in ``FW_TRACE_RECORD(put, st, window, cycles)`` (``st`` the firmware's
    ``struct fw_state``); ``signed``: the word is an int32 (else uint32). A word whose name is a column
    of golden.closedloop.WINDOW_FIELDS fills that column in the rtl backend.
    """

    name: str
    expr: str
    signed: bool


TRACE = (
    TraceWord("window", "window", False),                  # window index k (WINDOW_COUNT - 2)
    TraceWord("theta_hat", "st.theta_hat", False),
    TraceWord("omega_f", "fw_lowpass_out(st.speed_f)", True),
    TraceWord("i_d", "st.i_d", True),
    TraceWord("i_q", "st.i_q", True),
    TraceWord("i_d_ref", "st.i_d_ref", True),
    TraceWord("i_q_ref", "st.i_q_ref", True),
    TraceWord("mode", "st.mode", True),
    TraceWord("fault", "st.fault", True),                  # fault code (golden.firmware.protection)
    TraceWord("flipped", "st.flipped", True),
    TraceWord("est", "st.active", True),                   # estimator slot in charge
    TraceWord("theta_lo", "st.est_theta[0]", False),
    TraceWord("theta_hi", "st.est_theta[1]", False),
    TraceWord("omega_lo", "st.est_omega[0]", True),
    TraceWord("omega_hi", "st.est_omega[1]", True),
    TraceWord("cycles", "cycles", False),                  # rdcycle count of the control step
)
"""The firmware trace record (one per window, on the SoC trace port), in order."""

TRACE_FIELDS = tuple(w.name for w in TRACE)
"""Names of the trace words, in order."""
