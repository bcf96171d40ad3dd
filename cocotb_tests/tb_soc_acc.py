"""cocotb testbench of the SoC's accelerators rtl/hfi_soc_acc.v (with hfi_cordic and hfi_flux_lut) on its
native bus, with the RAM on its data port (wrapper cocotb_tests/hdl/tb_soc_acc_ram.v; run by
cocotb_tests/test_soc_acc.py, not by pytest).

References, independent of the Verilog: ``golden.fpga.cordic.sincos_q15`` (32 bits, 16 iterations: the
firmware's sine/cosine), ``golden.firmware.flux_lut.lut_point`` on the LUT of the 003 scenario
(``golden.control_config.firmware_params`` of scenarios/varatharajan2020_torquestep.toml), the register
addresses and fields of ``golden.accmap`` (rtl/regs/hfi_acc.rdl). What is tested here is the bus side:
the words, the waiting (a SINCOS read straight after its start returns the new result; the LUT_IQ write
is answered when the look-up is done), the tables read from the RAM at their LUT_BASE_* addresses (the
int16 tables at byte addresses 2 mod 4, the tables next to each other), the RAM port used only while the
bus waits on LUT_IQ, the read-back of the configuration and unmapped addresses.
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
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge
from cocotb.utils import get_sim_time

from golden.accmap import REGISTERS
from golden.control_config import firmware_params
from golden.firmware.flux_lut import lut_point
from golden.fpga.cordic import sincos_q15
from golden.scenario import load_scenario
from hdl_runner import ROOT

ADDR = {name: reg["addr"] for name, reg in REGISTERS.items()}
RAM_AW = 12
"""Word-address width of the test RAM (16 KiB: the 003 tables take 14 KB)."""
BASE_REGS = ("LUT_BASE_D", "LUT_BASE_Q", "LUT_BASE_LD", "LUT_BASE_LQ", "LUT_BASE_LDQ")
WORD = 0xFFFFFFFF
def scenario_lut():
    return firmware_params(load_scenario(ROOT / "scenarios" / "varatharajan2020_torquestep.toml")).hfo.lut


def table_bases(lut) -> list[int]:
    """Byte addresses of the five tables in the test RAM: back to back from byte 2 (so the int16 tables
    start at 2 mod 4, the int32 ones 4-aligned after them)."""
    n, bases, at = lut.n_d * lut.n_q, [], 2
    for size in (2, 2, 4, 4, 4):
        at = at if size == 2 else (at + 3) & ~3
        bases.append(at)
        at += size * n
    assert at <= 4 << RAM_AW
    return bases


def ram_image() -> list[int]:
    """The test RAM's words: the scenario's tables at :func:`table_bases`, little endian, 0 elsewhere."""
    lut = scenario_lut()
    mem = bytearray(4 << RAM_AW)
    for base, name, size in zip(table_bases(lut), TABLES, (2, 2, 4, 4, 4)):
        for i, v in enumerate(getattr(lut, name)):
            mem[base + size * i:base + size * (i + 1)] = (v & ((1 << (8 * size)) - 1)).to_bytes(size, "little")
    return [int.from_bytes(mem[4 * k:4 * k + 4], "little") for k in range(1 << RAM_AW)]


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


async def _watch_mem_en(dut, bad: list) -> None:
    """mem_en high only while the bus holds a LUT_IQ write (sel high, not yet answered)."""
    while True:
        await RisingEdge(dut.clk)
        await ReadOnly()
        if dut.mem_en.value == 1 and not (dut.sel.value == 1 and int(dut.addr.value) == ADDR["LUT_IQ"]
                                          and int(dut.wstrb.value) != 0):
            bad.append(get_sim_time("ns"))


@cocotb.test()
async def flux_lut_through_the_bus(dut):
    """The 003 scenario's tables in the RAM at their LUT_BASE_* addresses, then look-ups at random currents
    (and the corners): every result word = golden lut_point; the LUT_IQ write waits for the look-up; the
    RAM port only meanwhile."""
    bus = await start(dut)
    bad: list = []
    cocotb.start_soon(_watch_mem_en(dut, bad))
    lut = scenario_lut()
    await bus.write("LUT_CFG", _field("LUT_CFG", "N_D", lut.n_d) | _field("LUT_CFG", "N_Q", lut.n_q)
                    | _field("LUT_CFG", "SHIFT", lut.shift) | _field("LUT_CFG", "COARSE", lut.coarse)
                    | _field("LUT_CFG", "F_SHIFT", lut.f_shift))
    await bus.write("LUT_KNEE", lut.knee)
    for name, base in zip(BASE_REGS, table_bases(lut)):
        await bus.write(name, base)
    rng = _rng()
    n = max(_count() // 10, 50)
    cur = [(0, 0), (-1, 0), (0, -1), (1 << 18, -(1 << 18)), (-(1 << 18), 1 << 18)]
    cur += [tuple(int(x) for x in rng.integers(-(1 << 16), 1 << 16, size=2)) for _ in range(n)]
    for i_d, i_q in cur:
        await bus.write("LUT_ID", i_d & WORD)
        before = bus.waits
        await bus.write("LUT_IQ", i_q & WORD)
        assert bus.waits - before >= 40, bus.waits - before          # answered when the look-up is done
        want = lut_point(lut, i_d, i_q)
        for name in WIDE:
            lo, hi = await bus.read(f"{name}_LO"), await bus.read(f"{name}_HI")
            got = (hi << 32 | lo) - ((1 << 64) if hi >> 31 else 0)
            assert got == getattr(want, name.lower()), (name, i_d, i_q, got, want)
        for name in NARROW:
            assert _s32(await bus.read(name)) == getattr(want, name.lower()), (name, i_d, i_q, want)
    assert not bad, f"mem_en high outside a LUT_IQ write at {bad[:5]} ns"


@cocotb.test()
async def registers_read_back(dut):
    """The configuration registers read back what was written (their fields only; the table addresses
    their RAM_AW + 2 low bits, the byte address inside the RAM); unmapped and write-only words read 0."""
    bus = await start(dut)
    rng = _rng()
    for _ in range(200):
        v = int(rng.integers(0, 1 << 32))
        for name in ("LUT_CFG", "LUT_KNEE", "LUT_ID") + BASE_REGS:
            await bus.write(name, v)
            mask = sum(((1 << w) - 1) << lsb for lsb, w, *_ in REGISTERS[name]["fields"].values())
            if name in BASE_REGS:
                mask = (4 << RAM_AW) - 1
            assert await bus.read(name) == v & mask, (name, hex(v))
    for a in [a for a in range(0, 256, 4) if a not in ADDR.values()] + [ADDR["SIN_ANGLE"]]:
        assert await bus.access(a) == 0, hex(a)
