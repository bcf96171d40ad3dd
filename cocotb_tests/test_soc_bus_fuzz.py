"""Fuzzing of the SoC's peripheral bus (docs/fuzz.md, "SoC bus"): hfi_soc_ctl and hfi_soc_acc (with the RAM
the flux-map unit reads) on the CPU's native bus, random reads and writes over every byte address of both
256-byte pages (unmapped, reserved and unaligned ones, random data, random strobes with 0 = read), back to
back and with gaps, CORDIC results read while it computes, look-ups with their tables anywhere in RAM,
random resets (also in the middle of a look-up). Every clock is checked by the Verilog checker of
cocotb_tests/hdl/tb_soc_bus_fuzz.v (ready only for a pending sel, answered within the bound, the RAM port
only during a look-up), every response against golden/socmap.py and golden/accmap.py
(cocotb_tests/tb_soc_bus_fuzz.py); a checker self-test injects one fault of each kind.

``make test`` runs a short fuzz (FUZZ_TRANSACTIONS_SHORT); ``make fuzz`` runs 10^6 accesses.
FUZZ_SEED (else HFI_SEED, else a fresh seed, printed) and FUZZ_TRANSACTIONS override.
"""

from __future__ import annotations

import os
import random

from hdl_runner import TB_DIR, fuzz_seed, rtl_sources, run_cocotb
from tb_soc_bus_fuzz import ACC_BOUND, CTL_BOUND, RAM_AW

FUZZ_TRANSACTIONS_SHORT = 30_000
"""Accesses of the short run in make test."""
RTL_FILES = ("hfi_soc_ctl.v", "hfi_uart_tx.v", "hfi_soc_acc.v", "hfi_cordic.v", "hfi_vector.v", "hfi_flux_lut.v", "hfi_ram.v")


def test_soc_bus_fuzz(tmp_path):
    seed = fuzz_seed()
    total = int(os.environ.get("FUZZ_TRANSACTIONS", FUZZ_TRANSACTIONS_SHORT))
    print(f"soc bus fuzz: FUZZ_SEED={seed} FUZZ_TRANSACTIONS={total}")
    build = tmp_path / "build"
    build.mkdir(parents=True)
    image = build / "ram_init.hex"                   # the look-ups' "tables": random RAM words
    rng = random.Random(seed ^ 0x5EED)
    image.write_text("".join(f"{rng.getrandbits(32):08x}\n" for _ in range(1 << RAM_AW)))
    run_cocotb(sim="verilator", toplevel="tb_soc_bus_fuzz",
               sources=[*rtl_sources(*RTL_FILES), TB_DIR / "hdl" / "tb_soc_bus_fuzz.v"],
               tb_module="tb_soc_bus_fuzz", build_dir=build,
               parameters={"RAM_AW": RAM_AW, "RAM_INIT": f'"{image}"', "CTL_BOUND": CTL_BOUND,
                           "ACC_BOUND": ACC_BOUND},
               env={"FUZZ_SEED": seed, "FUZZ_TRANSACTIONS": total},
               build_args=["--timing"], expect_tests=2)
