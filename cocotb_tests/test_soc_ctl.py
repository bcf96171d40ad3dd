"""pytest side of the SoC control block and RAM tests: cocotb_tests/tb_soc_ctl.py on both simulators,
through the wrapper cocotb_tests/hdl/tb_soc_ctl_ram.v (hfi_soc_ctl with hfi_uart_tx, and hfi_ram with
a $readmemh image written here into the build directory and passed as its INIT_FILE).

Random counts: HFI_RANDOM_N bus accesses and RAM clocks, HFI_RANDOM_N / 50 UART bytes (5000 under
Verilator, 1000 under Icarus; ``HFI_RANDOM_N`` overrides both).
"""

from __future__ import annotations

import pytest

import hdl_runner

N_TESTS = 11  # cocotb tests in tb_soc_ctl.py
RANDOM_N = {"verilator": 5000, "icarus": 1000}
RAM_WORDS = 256
RTL_FILES = ("hfi_uart_tx.v", "hfi_soc_ctl.v", "hfi_ram.v")


def ram_image_word(i: int) -> int:
    """Word i of the RAM image: every byte differs between neighbouring words (a multiplicative hash)."""
    return (i * 0x9E3779B1 + 0x01234567) & 0xFFFFFFFF


def write_ram_image(path) -> None:
    """A $readmemh file of RAM_WORDS words (one hex word per line, word 0 first)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("".join(f"{ram_image_word(i):08x}\n" for i in range(RAM_WORDS)))


@pytest.mark.parametrize("sim", hdl_runner.SIMULATORS)
def test_soc_ctl(sim, tmp_path):
    build = tmp_path / "build"
    image = build / "ram_init.hex"
    write_ram_image(image)
    hdl_runner.run_cocotb(
        sim=sim, toplevel="tb_soc_ctl_ram",
        sources=[*hdl_runner.rtl_sources(*RTL_FILES), hdl_runner.TB_DIR / "hdl" / "tb_soc_ctl_ram.v"],
        tb_module="tb_soc_ctl", build_dir=build,
        parameters={"RAM_WORDS": RAM_WORDS, "RAM_INIT": f'"{image}"'},
        env={"HFI_RAM_INIT": image}, expect_tests=N_TESTS, random_n=RANDOM_N[sim],
        public_all=True)    # tb_soc_ctl deposits into the cycle counter, dut.u_ctl.cycles
