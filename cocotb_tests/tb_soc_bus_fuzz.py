"""cocotb side of the SoC peripheral-bus fuzzer (test_soc_bus_fuzz.py, docs/fuzz.md, "SoC bus").

The two native-bus slaves of hfi_soc's CPU, hfi_soc_ctl (page 0x000) and hfi_soc_acc with the RAM on its
data port (page 0x100), behind the wrapper cocotb_tests/hdl/tb_soc_bus_fuzz.v. The bus master is Verilog
(the wrapper's, driven by one command per access: address, strobes, data, idle gap, reset): Python only
hands over the next command and reads the previous response, once per access, so accesses follow back to
back and the 59-clock look-ups cost no Python per clock. The per-cycle invariants (ready only for a
pending sel, every access answered within its bound, the accelerator's RAM port only while the bus holds
a LUT_IQ write and exactly 20 clocks per look-up, the trace port) are checked in Verilog; this module
checks every response against a model built from the generated register maps (golden/socmap.py,
golden/accmap.py) and the RTL's documented behaviour:

- rw registers read back what was last written, masked to their fields (LUT_BASE_*: the RAM's byte
  address bits, docs/acc_registers.md); reset values after a reset; a write stores the whole word
  whatever its non-zero strobes (both modules: "writes store the whole word"); wstrb = 0 is a read;
- the dsp_run output follows CTRL.DSP_RUN (checked after every access);
- ID reads 0x48464953; CYCLE_LO reads the cycle count of the clock the read was presented in (the
  wrapper counts it independently), CYCLE_HI the high word latched by the last CYCLE_LO read;
  UART_STATUS reads 0 or 1;
- SINCOS reads golden.fpga.cordic.sincos_q15 of the last SIN_ANGLE write (0 after reset), also when read
  while the CORDIC computes; VEC_ANGLE and VEC_MAG read golden.firmware.vector.vector_angle of the last
  VEC_X write and the last VEC_Y write (each saturated to +-2^28; 0 after reset), likewise; the look-up result registers read 0 after a reset and, after a look-up, one
  value each until the next look-up (the look-up itself is checked against golden in test_soc_acc.py;
  here the tables are random RAM words and the grid random, outside the unit's exact range);
- write-only registers, unmapped words and unaligned byte addresses read 0 (the slaves' default read
  branch; hfi_soc.v: an unmapped page reads 0 likewise; test_soc_acc.py's contract);
- waits (clocks with sel and no ready): 1 on the ctl page ("answered one clock later"); on the acc page 1,
  except a LUT_IQ write (LUT_WAIT = 60: the look-up's 59 clocks, then ready), a SIN_ANGLE write or
  SINCOS read while the CORDIC runs and an access to VEC_* while the vectoring CORDIC runs (at most
  SIN_WAIT_MAX: both have a LATENCY of 18).

Reproducible: ``random.Random(FUZZ_SEED)``; FUZZ_TRANSACTIONS accesses (resets not counted).
"""

from __future__ import annotations

import os
import random
from dataclasses import dataclass

import cocotb
from cocotb.triggers import ClockCycles, FallingEdge, ValueChange

from golden import accmap as am
from golden import socmap as sm
from golden.firmware.vector import INPUT_LIMIT, vector_angle
from golden.fpga.cordic import sincos_q15

ACC = 0x100
"""Address bit 8 selects the accelerator page in the wrapper."""
WORD = 0xFFFFFFFF
RAM_AW = 12
"""Word-address width of the wrapper's RAM (16 KiB of random words)."""
LUT_WAIT = 60
"""Clocks a LUT_IQ write waits: hfi_flux_lut's LATENCY 59 (start cycle to done), ready in the clock after."""
SIN_WAIT_MAX = 18
"""Longest wait of a SIN_ANGLE write or SINCOS read behind a running CORDIC: done 18 clocks after the
SIN_ANGLE write's clock s (hfi_cordic LATENCY, docs/acc_registers.md), so an access presented at s + 2
(straight after the write's ready) is taken at s + 19 and waits s + 2 .. s + 19."""
CTL_BOUND, ACC_BOUND = 1, LUT_WAIT + 4
"""The checker's bounds (clocks with sel and no ready): ctl exactly its documented 1; acc the look-up's 60
plus a margin of 4."""
PROGRESS = 100_000
VIOLATIONS = ("viol_ready", "viol_bound", "viol_mem", "viol_trace")
COVERAGE = ("cov_lut", "cov_lut_abort", "cov_b2b", "cov_trace", "cov_mem")
PY_COVERAGE = ("sin_waited", "vec_waited", "resets", "unaligned_writes", "lut_learned")
COVERAGE_CAP = 3
"""The run goes on past FUZZ_TRANSACTIONS until every coverage counter is non-zero, up to this many times."""


def field_mask(reg: dict) -> int:
    return sum(((1 << w) - 1) << lsb for lsb, w, *_ in reg["fields"].values())


CTL_RW = {r["addr"]: field_mask(r) for r in sm.REGISTERS.values()
          if all(f[3] == "rw" for f in r["fields"].values())}
CTL_RESET = {a: sm.REGISTERS[n]["reset"] for n, r in sm.REGISTERS.items() for a in [r["addr"]] if a in CTL_RW}
BASES = {am.REGISTERS[n]["addr"] for n in am.REGISTERS if n.startswith("LUT_BASE_")}
ACC_RW = {r["addr"]: ((4 << RAM_AW) - 1 if r["addr"] in BASES else field_mask(r))
          for r in am.REGISTERS.values() if all(f[3] == "rw" for f in r["fields"].values())}
ACC_RESET = {r["addr"]: r["reset"] for r in am.REGISTERS.values() if r["addr"] in ACC_RW}
RESULTS = tuple(r["addr"] for n, r in am.REGISTERS.items() if am.LAM_D_LO_ADDR <= r["addr"] <= am.DL_DQ_HI_ADDR)
SIN_ADDRS = (am.SIN_ANGLE_ADDR, am.SINCOS_ADDR)
VEC_ADDRS = (am.VEC_X_ADDR, am.VEC_Y_ADDR, am.VEC_ANGLE_ADDR, am.VEC_MAG_ADDR)
CTL_MAPPED = sorted(r["addr"] for r in sm.REGISTERS.values())
ACC_MAPPED = sorted(r["addr"] for r in am.REGISTERS.values())


@dataclass
class Cmd:
    addr: int = 0            # 9 bits: page (bit 8) and byte address
    wstrb: int = 0           # 0: read
    wdata: int = 0
    gap: int = 0             # idle clocks before the access (or the reset)
    rst: bool = False        # a reset of rst_len clocks instead of an access
    rst_len: int = 1
    abort: int = 0           # > 0: withdraw the access by a reset after this many unanswered clocks


@dataclass
class Rsp:
    rdata: int
    wait: int
    aborted: bool
    cycle: int


class Master:
    """Hands commands to the wrapper's bus master (module docstring): ``step(cmd)`` presents ``cmd`` and
    returns when the master took it, with the command it completed in that edge and its response."""

    def __init__(self, dut):
        self.dut, self.seq, self.current = dut, 0, None

    def _drive(self, c: Cmd) -> None:
        d = self.dut
        d.cmd_addr.value = c.addr
        d.cmd_wstrb.value = c.wstrb
        d.cmd_wdata.value = c.wdata
        d.cmd_gap.value = c.gap
        d.cmd_rst.value = int(c.rst)
        d.cmd_rst_len.value = c.rst_len
        d.cmd_abort.value = c.abort
        self.seq ^= 1
        d.cmd_seq.value = self.seq

    def _rsp(self) -> Rsp:
        d = self.dut
        return Rsp(int(d.rsp_rdata.value), int(d.rsp_wait.value), bool(int(d.rsp_aborted.value)),
                   int(d.rsp_cycle.value))

    async def step(self, c: Cmd):
        self._drive(c)
        await ValueChange(self.dut.take_toggle)
        done, self.current = self.current, c
        return (done, self._rsp()) if done is not None else (None, None)

    async def flush(self):
        """Wait for the command in progress; returns it and its response."""
        done, self.current = self.current, None
        if done is None:
            return None, None
        await ValueChange(self.dut.rsp_toggle)
        return done, self._rsp()

    async def access(self, addr: int, wstrb: int = 0, wdata: int = 0) -> Rsp:
        await self.step(Cmd(addr, wstrb, wdata))
        return (await self.flush())[1]


def counters(dut) -> dict:
    return {n: int(getattr(dut, n).value) for n in ("cycles", "bus_max_ctl", "bus_max_acc", *VIOLATIONS, *COVERAGE)}


async def start(dut) -> Master:
    for name in ("cmd_seq", "cmd_addr", "cmd_wstrb", "cmd_wdata", "cmd_gap", "cmd_rst", "cmd_rst_len",
                 "cmd_abort", "inject_ready", "inject_mem", "clear"):
        getattr(dut, name).value = 0
    dut.rst_ext.value = 1
    await ClockCycles(dut.clk, 10)
    await FallingEdge(dut.clk)
    dut.rst_ext.value = 0
    await pulse(dut, "clear")
    return Master(dut)


async def pulse(dut, name: str) -> None:
    """Hold input ``name`` at 1 for exactly one clock (set and cleared at falling edges)."""
    await FallingEdge(dut.clk)
    getattr(dut, name).value = 1
    await FallingEdge(dut.clk)
    getattr(dut, name).value = 0


def _sat28(v: int) -> int:
    """The s32 word v saturated to +-2^28, as hfi_vector saturates its inputs."""
    v = v - (1 << 32) if v >> 31 else v
    return max(-INPUT_LIMIT, min(INPUT_LIMIT, v))


class Model:
    """The registers as the maps and the RTL say (module docstring)."""

    def __init__(self):
        self.reset()

    def reset(self) -> None:
        self.ctl = dict(CTL_RESET)
        self.acc = dict(ACC_RESET)
        self.cycle_hi = 0
        self.sincos = 0
        self.vec_x = 0
        self.vec = {am.VEC_ANGLE_ADDR: 0, am.VEC_MAG_ADDR: 0}
        self.results = {a: 0 for a in RESULTS}   # None: a look-up ran, value not read yet

    def write(self, addr: int, data: int) -> None:
        a = addr & 0xFF
        if addr & ACC:
            if a == am.SIN_ANGLE_ADDR:
                s, c = sincos_q15(data)
                self.sincos = ((int(c) & 0xFFFF) << 16) | (int(s) & 0xFFFF)
            elif a == am.VEC_X_ADDR:
                self.vec_x = data
            elif a == am.VEC_Y_ADDR:
                angle, mag = vector_angle(_sat28(self.vec_x), _sat28(data))
                self.vec = {am.VEC_ANGLE_ADDR: angle, am.VEC_MAG_ADDR: mag & WORD}
            elif a in ACC_RW:
                self.acc[a] = data & ACC_RW[a]
            if a == am.LUT_IQ_ADDR:
                self.results = dict.fromkeys(RESULTS)
        elif a in CTL_RW:
            self.ctl[a] = data & CTL_RW[a]

    def read(self, addr: int, rsp: Rsp) -> tuple[int | None, None]:
        """Expected read data (None: any value is right), and None."""
        a = addr & 0xFF
        if addr & ACC:
            if a == am.SINCOS_ADDR:
                return self.sincos, None
            if a in self.vec:
                return self.vec[a], None
            if a == am.CAPS_ADDR:                 # the default build: every option
                return am.REGISTERS["CAPS"]["reset"], None
            if a in ACC_RW:
                return self.acc[a], None
            if a in self.results:
                if self.results[a] is None:
                    self.results[a] = rsp.rdata
                    return None, None
                return self.results[a], None
            return 0, None
        if a == sm.ID_ADDR:
            return sm.ID_VALUE_RESET, None
        if a == sm.CYCLE_LO_ADDR:
            self.cycle_hi = (rsp.cycle >> 32) & WORD
            return rsp.cycle & WORD, None
        if a == sm.CYCLE_HI_ADDR:
            return self.cycle_hi, None
        if a == sm.UART_STATUS_ADDR:
            return None, None                     # TX_BUSY: checked to be 0 or 1 below
        return self.ctl.get(a, 0), None


def expected_wait(c: Cmd) -> tuple[int, int]:
    """Range of the clocks the access may wait with sel and no ready."""
    a = c.addr & 0xFF
    if not c.addr & ACC:
        return 1, 1
    if a == am.LUT_IQ_ADDR and c.wstrb:
        return LUT_WAIT, LUT_WAIT
    if a in SIN_ADDRS or a in VEC_ADDRS:
        return 1, SIN_WAIT_MAX
    return 1, 1


class Fuzzer:
    def __init__(self, dut, master: Master, seed: int, total: int):
        self.dut, self.m, self.total = dut, master, total
        self.rng = random.Random(seed)
        self.model = Model()
        self.done = 0
        self.mismatches = 0
        self.cov = dict.fromkeys(PY_COVERAGE, 0)
        self.max_sin_wait = 0

    def mismatch(self, what: str) -> None:
        self.mismatches += 1
        if self.mismatches <= 10:
            cocotb.log.error(f"response mismatch after {self.done} accesses: {what}")

    def data(self) -> int:
        rng = self.rng
        return rng.choice((0, WORD, rng.getrandbits(32), rng.getrandbits(16), rng.randint(0, 4095),
                           rng.randint(0, 127), 1 << rng.randint(0, 31)))

    def command(self) -> Cmd:
        rng = self.rng
        u = rng.random()
        gap = 0 if u < 0.6 else rng.randint(1, 8) if u < 0.9 else rng.randint(10, 200)
        if rng.random() < 0.002:
            return Cmd(gap=gap, rst=True, rst_len=rng.randint(1, 20))
        wstrb = 0xF if rng.random() < 0.7 else rng.getrandbits(4)
        if rng.random() < 0.5:                                  # ctl page
            u = rng.random()
            if u < 0.35:
                return Cmd(rng.choice(CTL_MAPPED), 0, self.data(), gap)
            if u < 0.75:
                return Cmd(rng.choice(CTL_MAPPED), wstrb, self.data(), gap)
            return Cmd(rng.getrandbits(8), rng.choice((0, wstrb)), self.data(), gap)
        u = rng.random()                                        # acc page
        if u < 0.08:                                            # a look-up, sometimes cut by a reset
            abort = rng.randint(1, LUT_WAIT - 1) if rng.random() < 0.05 else 0
            return Cmd(ACC | am.LUT_IQ_ADDR, 0xF if rng.random() < 0.8 else rng.randint(1, 15), self.data(),
                       gap, rst_len=rng.randint(1, 20), abort=abort)
        if u < 0.16:
            return Cmd(ACC | am.SIN_ANGLE_ADDR, wstrb if wstrb else 0xF, self.data(), gap)
        if u < 0.26:                                            # often straight after its start: waits;
            abort = rng.randint(1, SIN_WAIT_MAX) if rng.random() < 0.03 else 0   # sometimes cut by a reset
            return Cmd(ACC | am.SINCOS_ADDR, 0, self.data(), rng.choice((0, 0, 0, rng.randint(1, 20))),
                       rst_len=rng.randint(1, 20), abort=abort)
        if u < 0.34:                                            # a vector, its results often straight after
            if rng.random() < 0.5:
                return Cmd(ACC | rng.choice((am.VEC_X_ADDR, am.VEC_Y_ADDR)), wstrb if wstrb else 0xF, self.data(), gap)
            return Cmd(ACC | rng.choice((am.VEC_ANGLE_ADDR, am.VEC_MAG_ADDR)), 0, self.data(),
                       rng.choice((0, 0, 0, rng.randint(1, 20))))
        if u < 0.50:
            return Cmd(ACC | rng.choice(ACC_MAPPED), 0, self.data(), gap)
        if u < 0.80:
            a = rng.choice(ACC_MAPPED)
            d = self.data()
            if a in BASES and rng.random() < 0.5:               # a table anywhere in the RAM
                d = rng.getrandbits(4 + 12 + 2) & ~1
            return Cmd(ACC | a, wstrb, d, gap)
        return Cmd(ACC | rng.getrandbits(8), rng.choice((0, wstrb)), self.data(), gap)

    def check(self, c: Cmd, r: Rsp) -> None:
        self.done += not c.rst
        where = f"{'acc' if c.addr & ACC else 'ctl'} 0x{c.addr & 0xFF:02X}"
        if c.rst or r.aborted:
            self.cov["resets"] += 1
            self.model.reset()
        elif c.wstrb:
            if c.addr & 3:
                self.cov["unaligned_writes"] += 1
            self.model.write(c.addr, c.wdata)
        else:
            want, _ = self.model.read(c.addr, r)
            if want is None and c.addr & ACC:
                self.cov["lut_learned"] += 1
            if (c.addr & 0x1FF) == sm.UART_STATUS_ADDR and r.rdata not in (0, 1):
                self.mismatch(f"read {where}: 0x{r.rdata:08X}, expected 0 or 1")
            if want is not None and r.rdata != want:
                self.mismatch(f"read {where}: 0x{r.rdata:08X}, expected 0x{want:08X}")
        if not c.rst and not r.aborted:
            lo, hi = expected_wait(c)
            if not lo <= r.wait <= hi:
                self.mismatch(f"{'write' if c.wstrb else 'read'} {where}: waited {r.wait} clocks, expected "
                              f"{lo}..{hi}")
            if c.addr & ACC and (c.addr & 0xFF) in SIN_ADDRS:
                self.max_sin_wait = max(self.max_sin_wait, r.wait)
                self.cov["sin_waited"] += r.wait > 1
            if c.addr & ACC and (c.addr & 0xFF) in VEC_ADDRS:
                self.cov["vec_waited"] += r.wait > 1
        if int(self.dut.dsp_run.value) != self.model.ctl[sm.CTRL_ADDR]:
            self.mismatch(f"dsp_run {self.dut.dsp_run.value} after {where}, CTRL.DSP_RUN written "
                          f"{self.model.ctl[sm.CTRL_ADDR]}")
        if self.done % PROGRESS == 0 and not c.rst:
            k = counters(self.dut)
            cocotb.log.info(f"soc bus fuzz progress: {self.done} accesses, {k['cycles']} cycles checked, "
                            f"{sum(k[v] for v in VIOLATIONS)} checker violations, {self.mismatches} "
                            f"response mismatches")

    def covered(self) -> bool:
        k = counters(self.dut)
        return all(k[n] for n in COVERAGE) and all(self.cov.values())

    async def run(self) -> None:
        while self.done < self.total or (self.done < COVERAGE_CAP * self.total and not self.covered()):
            done, rsp = await self.m.step(self.command())
            if done is not None:
                self.check(done, rsp)
        done, rsp = await self.m.flush()
        if done is not None:
            self.check(done, rsp)


@cocotb.test()
async def checker_self_test(dut):
    """The checker counts what it should: one injected ready with no sel pending and one injected mem_en
    with no LUT_IQ write held are one violation each; a real access and a look-up add none."""
    m = await start(dut)
    await ClockCycles(dut.clk, 5)
    await pulse(dut, "inject_ready")
    await ClockCycles(dut.clk, 3)
    c = counters(dut)
    assert c["viol_ready"] == 1 and sum(c[v] for v in VIOLATIONS) == 1, c
    await pulse(dut, "inject_mem")
    await ClockCycles(dut.clk, 3)
    c = counters(dut)
    assert c["viol_mem"] == 1 and sum(c[v] for v in VIOLATIONS) == 2, c
    assert (await m.access(sm.ID_ADDR)).rdata == sm.ID_VALUE_RESET
    r = await m.access(ACC | am.LUT_IQ_ADDR, 0xF, 5)
    assert r.wait == LUT_WAIT, r
    c = counters(dut)
    assert sum(c[v] for v in VIOLATIONS) == 2 and c["cov_lut"] == 1 and c["cov_mem"] == 20, c
    assert c["bus_max_ctl"] == 1 and c["bus_max_acc"] == LUT_WAIT, c


@cocotb.test()
async def fuzz(dut):
    """FUZZ_TRANSACTIONS random accesses with seed FUZZ_SEED: no checker violation, every response as the
    model says, the corners of COVERAGE reached, and afterwards the bus still works."""
    seed, total = int(os.environ["FUZZ_SEED"]), int(os.environ["FUZZ_TRANSACTIONS"])
    cocotb.log.info(f"soc bus fuzz: seed {seed}, {total} accesses, bounds ctl {CTL_BOUND} acc {ACC_BOUND}")
    m = await start(dut)
    f = Fuzzer(dut, m, seed, total)
    await f.run()

    # no lock-up: a clean write and read-back of rw registers on both pages, ID
    probe = random.Random(seed).getrandbits(32)
    assert (await m.access(sm.UART_DIV_ADDR, 0xF, probe)).wait == 1
    assert (await m.access(sm.UART_DIV_ADDR)).rdata == probe & 0xFFFF
    await m.access(ACC | am.LUT_KNEE_ADDR, 0xF, probe)
    assert (await m.access(ACC | am.LUT_KNEE_ADDR)).rdata == probe
    assert (await m.access(ACC | am.LUT_IQ_ADDR, 0xF, 0)).wait == LUT_WAIT
    assert (await m.access(sm.ID_ADDR)).rdata == sm.ID_VALUE_RESET

    c = counters(dut)
    violations = sum(c[v] for v in VIOLATIONS)
    cocotb.log.info("soc bus fuzz counters: " + ", ".join(f"{k} {v}" for k, v in c.items())
                    + ", " + ", ".join(f"{k} {v}" for k, v in f.cov.items()) + f", max_sin_wait {f.max_sin_wait}")
    cocotb.log.info(f"fuzz: {f.done} transactions, {c['cycles']} cycles checked, {violations + f.mismatches} "
                    f"violations, seed {seed}")
    assert f.done >= total
    assert violations == 0 and f.mismatches == 0, f"seed {seed}: {c}, {f.mismatches} response mismatches"
    assert c["bus_max_ctl"] == CTL_BOUND and c["bus_max_acc"] == LUT_WAIT, c
    for name in COVERAGE:
        assert c[name] > 0, f"seed {seed}: the fuzzer never reached {name}: {c}"
    for name, n in f.cov.items():
        assert n > 0, f"seed {seed}: the fuzzer never reached {name}: {f.cov}"
