"""Register fuzzing of hfi_dsp (issue 19 item 5, docs/fuzz.md): random reads and writes over the whole
8-bit AXI4-Lite address space (reserved, unmapped and unaligned addresses, illegal field values, random
WSTRB, random gaps and READY back-pressure, writes while the outputs switch, FAULT_CLEAR), the STO and
DESAT pins toggled at random instants and ADC codes that trip the overcurrent limit; every clock is
checked by the Verilog checker of cocotb_tests/hdl/tb_reg_fuzz.v (no shoot-through, no gate on while
a fault is latched or 3 clocks after STO/DESAT, drive_allowed, every request answered within
BUS_BOUND cycles, AXI response rules) and every response against golden/regmap.py
(cocotb_tests/tb_reg_fuzz.py). The checker's self-test injects one violation of each gate invariant.

``make test`` runs a short fuzz (FUZZ_TRANSACTIONS_SHORT); ``make fuzz`` runs 10^6 transactions.
FUZZ_SEED (else HFI_SEED, else a fresh seed, printed) and FUZZ_TRANSACTIONS override.
"""

from __future__ import annotations

import os
import random

from hdl_runner import TB_DIR, core_rtl_files, fuzz_seed, rtl_sources, run_cocotb

FUZZ_TRANSACTIONS_SHORT = 20_000
"""Transactions of the short run in make test (well under a minute)."""
BUS_BOUND = 32
"""Clocks a request may wait for its response before the checker counts a bus violation."""
ADC_BITS = 12
N_CODES = 1 << 20
"""ADC conversions in codes.hex (adc_model's MAX_CODES); later conversions read mid-scale."""


def adc_codes(rng: random.Random) -> list[int]:
    """Code pairs ("aaaabbbb") per conversion: mostly small currents around mid-scale, some anywhere in
    the range and some at full scale, which exceed any OC_LIMIT below 2047 * 16 LSB."""
    mid, top = 1 << (ADC_BITS - 1), (1 << ADC_BITS) - 1

    def code() -> int:
        u = rng.random()
        if u < 0.9:
            return mid + rng.randint(-200, 200)
        return rng.randint(0, top) if u < 0.99 else rng.choice((0, top))

    return [(code() << 16) | code() for _ in range(N_CODES)]


def test_reg_fuzz(tmp_path):
    seed = fuzz_seed()
    total = int(os.environ.get("FUZZ_TRANSACTIONS", FUZZ_TRANSACTIONS_SHORT))
    print(f"reg fuzz: FUZZ_SEED={seed} FUZZ_TRANSACTIONS={total}")
    build = tmp_path / "build"
    build.mkdir(parents=True)
    (build / "codes.hex").write_text("".join(f"{c:08x}\n" for c in adc_codes(random.Random(seed))))
    run_cocotb(sim="verilator", toplevel="tb_reg_fuzz",
               sources=[*rtl_sources(*core_rtl_files()), TB_DIR / "hdl" / "adc_model.v",
                        TB_DIR / "hdl" / "tb_reg_fuzz.v"],
               tb_module="tb_reg_fuzz", build_dir=build,
               parameters={"ADC_BITS": ADC_BITS, "BUS_BOUND": BUS_BOUND},
               env={"FUZZ_SEED": seed, "FUZZ_TRANSACTIONS": total, "FUZZ_BUS_BOUND": BUS_BOUND},
               build_args=["--timing"], expect_tests=2)
