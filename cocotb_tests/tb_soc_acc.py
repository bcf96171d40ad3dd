"""cocotb testbench of the SoC's accelerators rtl/hfi_soc_acc.v (with hfi_cordic and hfi_flux_lut) on its
native bus (run by cocotb_tests/test_soc_acc.py, not by pytest).

References, independent of the Verilog: ``golden.fpga.cordic.sincos_q15`` (32 bits, 16 iterations: the
firmware's sine/cosine), ``golden.firmware.flux_lut.lut_point`` on the LUT of the 003 scenario
(``golden.control_config.firmware_params`` of scenarios/varatharajan2020_torquestep.toml), the register
addresses and fields of ``golden.accmap`` (rtl/regs/hfi_acc.rdl). What is tested here is the bus side:
the words, the waiting (a result read straight after its start returns the new result), the table
loading with the auto-incrementing index, the read-back of the configuration and unmapped addresses.
The units' arithmetic over its whole range is cocotb_tests/test_cordic.py and test_flux_lut.py.

Bus (hfi_soc_ctl's contract): the master holds ``sel`` (with addr, wstrb, wdata) until it sees ``ready``
at a rising edge; the access happens at the edge where ``sel`` is high, ``ready`` low and the unit free;
``ready`` and ``rdata`` follow one clock later.
"""

from __future__ import annotations

import os

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, RisingEdge, ReadOnly

from golden.accmap import REGISTERS
from golden.control_config import firmware_params
from golden.firmware.flux_lut import lut_point
from golden.fpga.cordic import sincos_q15
from golden.scenario import load_scenario
from hdl_runner import ROOT

ADDR = {name: reg["addr"] for name, reg in REGISTERS.items()}
WORD = 0xFFFFFFFF
WIDE = ("LAM_D", "LAM_Q", "DL_D", "DL_Q", "DL_DQ")
NARROW = ("L_D", "L_Q", "L_DQ")
TABLES = ("t_d", "t_q", "t_ld", "t_lq", "t_ldq")


def _field(reg: str, name: str, value: int) -> int:
    lsb, width = REGISTERS[reg]["fields"][name][:2]
    assert 0 <= value < 1 << width, (reg, name, value)
    return value << lsb


class Bus:
    def __init__(self, dut):
        self.dut = dut
        self.waits = 0            # clocks an access waited beyond the one-clock answer

    async def access(self, addr: int, wdata: int = 0, write: bool = False) -> int:
        dut = self.dut
        await FallingEdge(dut.clk)
        dut.sel.value = 1
        dut.addr.value = addr
        dut.wstrb.value = 0xF if write else 0
        dut.wdata.value = wdata & WORD
        n = 0
        while True:
            await RisingEdge(dut.clk)
            await ReadOnly()
            if dut.ready.value == 1:
                break
            n += 1
        self.waits += max(n - 1, 0)
        value = int(dut.rdata.value)
        await FallingEdge(dut.clk)
        dut.sel.value = 0
        dut.wstrb.value = 0
        return value

    async def write(self, name: str, value: int) -> None:
        await self.access(ADDR[name], value, True)

    async def read(self, name: str) -> int:
        return await self.access(ADDR[name])


async def start(dut) -> Bus:
    cocotb.start_soon(Clock(dut.clk, 20, unit="ns").start())
    dut.sel.value = 0
    dut.addr.value = 0
    dut.wstrb.value = 0
    dut.wdata.value = 0
    dut.rst.value = 1
    for _ in range(3):
        await RisingEdge(dut.clk)
    await FallingEdge(dut.clk)
    dut.rst.value = 0
    return Bus(dut)


def _rng() -> np.random.Generator:
    return np.random.default_rng(int(os.environ["HFI_SEED"]))


def _count() -> int:
    return int(os.environ["HFI_RANDOM_N"])


def _s32(v: int) -> int:
    return v - (1 << 32) if v >> 31 else v


def _s16(v: int) -> int:
    return v - (1 << 16) if v >> 15 else v


@cocotb.test()
async def sincos_random(dut):
    """SIN_ANGLE then SINCOS = golden sincos_q15 (the firmware's); the read waits for the CORDIC."""
    bus = await start(dut)
    rng = _rng()
    angles = [0, 1 << 30, 1 << 31, 3 << 30, WORD] + rng.integers(0, 1 << 32, size=_count(), dtype=np.uint64).tolist()
    for a in angles:
        await bus.write("SIN_ANGLE", int(a))
        v = await bus.read("SINCOS")
        assert (_s16(v & 0xFFFF), _s16(v >> 16)) == sincos_q15(int(a)), hex(a)
    assert bus.waits >= 10 * len(angles), bus.waits   # the CORDIC's 18 clocks were waited for


async def _load(bus: Bus, lut) -> None:
    await bus.write("LUT_CFG", _field("LUT_CFG", "N_D", lut.n_d) | _field("LUT_CFG", "N_Q", lut.n_q)
                    | _field("LUT_CFG", "SHIFT", lut.shift) | _field("LUT_CFG", "COARSE", lut.coarse)
                    | _field("LUT_CFG", "F_SHIFT", lut.f_shift))
    await bus.write("LUT_KNEE", lut.knee)
    for j, name in enumerate(TABLES):
        await bus.write("LUT_TW_ADDR", _field("LUT_TW_ADDR", "TABLE", j))
        for v in getattr(lut, name):
            await bus.write("LUT_TW_DATA", v & WORD)


@cocotb.test()
async def flux_lut_through_the_bus(dut):
    """The 003 scenario's LUT loaded with the auto-incrementing index, then look-ups at random currents (and
    the corners): every result word = golden lut_point, read straight after LUT_IQ (the reads wait)."""
    bus = await start(dut)
    lut = firmware_params(load_scenario(ROOT / "scenarios" / "varatharajan2020_torquestep.toml")).hfo.lut
    await _load(bus, lut)
    rng = _rng()
    n = max(_count() // 10, 50)
    cur = [(0, 0), (-1, 0), (0, -1), (1 << 18, -(1 << 18)), (-(1 << 18), 1 << 18)]
    cur += [tuple(int(x) for x in rng.integers(-(1 << 16), 1 << 16, size=2)) for _ in range(n)]
    for i_d, i_q in cur:
        await bus.write("LUT_ID", i_d & WORD)
        await bus.write("LUT_IQ", i_q & WORD)
        want = lut_point(lut, i_d, i_q)
        for name in WIDE:
            lo, hi = await bus.read(f"{name}_LO"), await bus.read(f"{name}_HI")
            got = (hi << 32 | lo) - ((1 << 64) if hi >> 31 else 0)
            assert got == getattr(want, name.lower()), (name, i_d, i_q, got, want)
        for name in NARROW:
            assert _s32(await bus.read(name)) == getattr(want, name.lower()), (name, i_d, i_q, want)


@cocotb.test()
async def registers_read_back(dut):
    """The configuration registers read back what was written (their fields only; the table index
    advances by one per LUT_TW_DATA write, TABLE stays); unmapped words and write-only ones read 0."""
    bus = await start(dut)
    rng = _rng()
    for _ in range(200):
        v = int(rng.integers(0, 1 << 32))
        for name in ("LUT_CFG", "LUT_KNEE", "LUT_ID", "LUT_TW_ADDR"):
            await bus.write(name, v)
            mask = sum(((1 << w) - 1) << lsb for lsb, w, *_ in REGISTERS[name]["fields"].values())
            assert await bus.read(name) == v & mask, (name, hex(v))
        await bus.write("LUT_TW_DATA", 0)
        idx_lsb, idx_w = REGISTERS["LUT_TW_ADDR"]["fields"]["INDEX"][:2]
        mask = sum(((1 << w) - 1) << lsb for lsb, w, *_ in REGISTERS["LUT_TW_ADDR"]["fields"].values())
        want = (v & mask & ~(((1 << idx_w) - 1) << idx_lsb)) | ((((v >> idx_lsb) + 1) & ((1 << idx_w) - 1)) << idx_lsb)
        assert await bus.read("LUT_TW_ADDR") == want
    for a in [a for a in range(0, 256, 4) if a not in ADDR.values()] + [ADDR["SIN_ANGLE"], ADDR["LUT_TW_DATA"]]:
        assert await bus.access(a) == 0, hex(a)
