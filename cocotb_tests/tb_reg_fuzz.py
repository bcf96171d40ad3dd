"""cocotb side of the hfi_dsp register fuzzer (issue 19 item 5; test_reg_fuzz.py, docs/fuzz.md).

Bus master: cocotbext-axi's AXI4-Lite channel drivers (AxiLiteAWSource, AxiLiteWSource, AxiLiteBSink,
AxiLiteARSource, AxiLiteRSink) wired to ``s_axil_*``. cocotbext-axi's ``AxiLiteMaster`` builds WSTRB
from a contiguous byte range (``write(addr, bytes)``), so it cannot present WSTRB = 0 or a
non-contiguous mask (0b0101, 0b1001, ...); driving its channels directly presents any address
(unaligned and unmapped included), any data and any strobe, and the drivers' pause generators skew
AWVALID against WVALID and hold BREADY/RREADY low (back-pressure). One write and one read are in
flight at a time, issued by two concurrent coroutines.

The per-cycle invariants (no shoot-through, no gate on while a fault is latched or 3 clocks after the
STO/DESAT pin, drive_allowed, every request answered within BUS_BOUND cycles, AXI response rules) are
checked in Verilog (cocotb_tests/hdl/tb_reg_fuzz.v); this module checks every response against the
register map (golden/regmap.py) through tb_regs.RegModel, the transaction-level register file of the register
bench: BRESP/RRESP = OKAY exactly for word-aligned mapped addresses (and for writes, not a register held by
SAFETY_LOCK while it is set), RDATA = 0 for an unmapped read, and RDATA of every register the bus alone sets
(rw, w1s and w1p fields, constants: all but STATUS, IRQ_STATUS and the hardware's results) equal to a value the
model held while the read was in flight (the writes run concurrently: a write to the same register between the
read's issue and its data makes either value right).

Reproducible: the stimulus comes from ``random.Random(FUZZ_SEED)`` (the simulation is deterministic),
FUZZ_TRANSACTIONS transactions (reads + writes) in epochs that end with a reset of the DUT.
"""

from __future__ import annotations

import logging
import os
import random

import cocotb
from cocotb.triggers import ClockCycles, FallingEdge, Timer
from cocotbext.axi import AxiLiteBus
from cocotbext.axi.axil_channels import (AxiLiteARSource, AxiLiteARTransaction, AxiLiteAWSource,
                                         AxiLiteAWTransaction, AxiLiteBSink, AxiLiteRSink,
                                         AxiLiteWSource, AxiLiteWTransaction)

from golden import regmap as rm
from tb_regs import RegModel

CLK_NS = 10
OKAY, SLVERR = 0, 2
REG_WAIT = 2
"""hfi_regs: a request (AWVALID & WVALID, or ARVALID) waits 2 cycles for its response (READY in the
clock after VALID is seen, BVALID/RVALID in the next): the longest wait the checker must measure."""
PRELUDE_WRITES = 4
"""Writes of Fuzzer.prelude at the start of an epoch."""
PROGRESS = 100_000
"""Transactions between progress lines."""
MAPPED = sorted(r["addr"] for r in rm.REGISTERS.values())
LOCK_ADDR = rm.SAFETY_LOCK_ADDR
CONSTANTS = {rm.REGISTERS[name]["addr"]: rm.REGISTERS[name]["reset"] for name in ("ID", "VERSION", "CAPS")}
PREDICTABLE = sorted(r["addr"] for r in rm.REGISTERS.values()
                     if all(access in ("rw", "w1s", "w1p") or (access == "ro" and reset is not None)
                            for _, _, reset, access in r["fields"].values()))
"""Registers whose read value follows from the writes alone (RegModel predicts it)."""
VIOLATIONS = ("viol_shoot", "viol_kill", "viol_drive", "viol_bus", "viol_proto")
COVERAGE = ("cov_gates_on", "cov_kill", "cov_wr_on", "cov_oc", "cov_wdt", "cov_sto", "cov_desat")
COVERAGE_CAP = 3
"""A run goes on past FUZZ_TRANSACTIONS, epoch by epoch, until every COVERAGE counter is non-zero, up to this
many times FUZZ_TRANSACTIONS (a short run's seed may otherwise miss a corner: seed 9 at 12 000)."""


class FuzzBus:
    """AXI4-Lite master from cocotbext-axi's channel drivers (module docstring)."""

    def __init__(self, dut):
        logging.getLogger(f"cocotb.{dut._name}.m_axil").setLevel(logging.WARNING)   # one line per reset
        bus = AxiLiteBus.from_prefix(dut, "m_axil")
        self.aw = AxiLiteAWSource(bus.write.aw, dut.clk_m, dut.rst)
        self.w = AxiLiteWSource(bus.write.w, dut.clk_m, dut.rst)
        self.b = AxiLiteBSink(bus.write.b, dut.clk_m, dut.rst)
        self.ar = AxiLiteARSource(bus.read.ar, dut.clk_m, dut.rst)
        self.r = AxiLiteRSink(bus.read.r, dut.clk_m, dut.rst)

    @staticmethod
    def _hold(channel, cycles: int) -> None:
        """Pause a channel driver for ``cycles`` clocks (VALID of a source, READY of a sink)."""
        if cycles:
            channel.set_pause_generator(iter([True] * cycles + [False]))

    async def write(self, addr: int, data: int, strb: int = 0xF, aw_hold: int = 0, w_hold: int = 0,
                    b_hold: int = 0) -> int:
        """One write; returns BRESP."""
        self._hold(self.aw, aw_hold)
        self._hold(self.w, w_hold)
        self._hold(self.b, b_hold)
        await self.aw.send(AxiLiteAWTransaction(awaddr=addr))
        await self.w.send(AxiLiteWTransaction(wdata=data, wstrb=strb))
        return int((await self.b.recv()).bresp)

    async def read(self, addr: int, ar_hold: int = 0, r_hold: int = 0) -> tuple[int, int]:
        """One read; returns (RDATA, RRESP)."""
        self._hold(self.ar, ar_hold)
        self._hold(self.r, r_hold)
        await self.ar.send(AxiLiteARTransaction(araddr=addr))
        r = await self.r.recv()
        return int(r.rdata), int(r.rresp)


def counters(dut) -> dict:
    """The checker's counters (tb_reg_fuzz.v)."""
    return {name: int(getattr(dut, name).value) for name in ("cycles", "bus_max", *VIOLATIONS, *COVERAGE)}


async def reset(dut, cycles: int = 10) -> None:
    await FallingEdge(dut.clk)
    dut.rst.value = 1
    await ClockCycles(dut.clk, cycles)
    await FallingEdge(dut.clk)
    dut.rst.value = 0


async def start(dut) -> FuzzBus:
    for name in ("sto", "desat", "inject_shoot", "inject_gate", "clear"):
        getattr(dut, name).value = 0
    dut.rst.value = 0
    bus = FuzzBus(dut)
    await reset(dut, 20)
    await FallingEdge(dut.clk)
    dut.clear.value = 1
    await FallingEdge(dut.clk)
    dut.clear.value = 0
    return bus


async def inject(dut, name: str) -> int:
    """Hold inject input ``name`` at 1 for exactly one cycle (set and cleared at falling edges); returns 1 if
    the checker required all gates off in that cycle (its ``cov_kill`` counted it: a fault latched, or
    STO/DESAT past their latency), else 0."""
    await FallingEdge(dut.clk)
    before = counters(dut)["cov_kill"]
    getattr(dut, name).value = 1
    await FallingEdge(dut.clk)
    getattr(dut, name).value = 0
    return counters(dut)["cov_kill"] - before


@cocotb.test()
async def checker_self_test(dut):
    """The checker counts what it should: one injected shoot-through cycle is one violation (and a kill
    violation too exactly when the gates had to be off then: the seed's random ADC codes may latch an
    overcurrent trip early); a gate seen on in the cycle 2 after the STO pin rises is allowed if no fault
    is latched, in the cycle 3 after it is one violation (the documented latency, docs/spec.md 3.8); the
    real DUT adds none."""
    await start(dut)
    await ClockCycles(dut.clk, 50)
    k1 = await inject(dut, "inject_shoot")
    await ClockCycles(dut.clk, 5)
    c = counters(dut)
    assert c["viol_shoot"] == 1 and c["viol_kill"] == k1 and sum(c[v] for v in VIOLATIONS) == 1 + k1, (k1, c)
    await FallingEdge(dut.clk)
    pre = counters(dut)["cov_kill"]
    await FallingEdge(dut.clk)                      # cycle k: the pin rises
    fault_free = counters(dut)["cov_kill"] == pre   # no fault latched in the cycle before
    dut.sto.value = 1
    await FallingEdge(dut.clk)                      # cycle k + 1
    k2 = await inject(dut, "inject_gate")           # cycle k + 2: not yet required off by STO
    k3 = await inject(dut, "inject_gate")           # cycle k + 3: required off
    await ClockCycles(dut.clk, 5)
    c = counters(dut)
    assert k3 == 1, f"STO did not require the gates off in cycle k + 3: {c}"
    if fault_free:
        assert k2 == 0, f"gate in cycle k + 2 after STO required off: {c}"
    assert c["viol_kill"] == k1 + k2 + k3 and c["viol_shoot"] == 1, (k1, k2, k3, c)
    assert sum(c[v] for v in VIOLATIONS) == 1 + k1 + k2 + k3, (k1, k2, k3, c)
    assert c["cov_sto"] == 1 and c["cycles"] > 60, c
    dut.sto.value = 0


class Fuzzer:
    """The random stimulus of one run and its response checks (module docstring)."""

    def __init__(self, dut, bus: FuzzBus, seed: int, total: int):
        self.dut, self.bus, self.total = dut, bus, total
        rng = random.Random(seed)
        self.rng_w, self.rng_r, self.rng_pin, self.rng_epoch = (random.Random(rng.getrandbits(64))
                                                                for _ in range(4))
        self.done = 0               # transactions completed
        self.mismatches = 0         # responses that differ from the register map
        self.model = RegModel()     # the register file as the writes so far set it (SAFETY_LOCK included)
        self.history: dict[int, list[int]] = {}   # per PREDICTABLE address: its values since the reset, in order
        self.pending = None         # the address of the write in flight (issued, BRESP not yet received)
        self.readbacks = 0          # reads whose RDATA the model predicted and checked
        self.stop_pins = False
        self.reset_model()

    def reset_model(self) -> None:
        """After a reset of the DUT: every register at its reset value."""
        self.model.reset()
        self.history = {a: [self.model.read(a)[0]] for a in PREDICTABLE}

    def count(self) -> None:
        self.done += 1
        if self.done % PROGRESS == 0:
            c = counters(self.dut)
            cocotb.log.info(f"fuzz progress: {self.done} transactions, {c['cycles']} cycles checked, "
                            f"{sum(c[v] for v in VIOLATIONS)} checker violations, {self.mismatches} "
                            f"response mismatches")

    def mismatch(self, what: str) -> None:
        self.mismatches += 1
        if self.mismatches <= 10:
            cocotb.log.error(f"response mismatch after {self.done} transactions: {what}")

    @staticmethod
    async def gap(rng: random.Random) -> None:
        u = rng.random()
        if u < 0.6:
            return
        cycles = rng.randint(1, 8) if u < 0.9 else rng.randint(10, 2000)
        await Timer(cycles * CLK_NS, "ns")

    @staticmethod
    def data(rng: random.Random) -> int:
        return rng.choice((0, 0xFFFFFFFF, rng.getrandbits(32), rng.getrandbits(16), rng.randint(0, 4095),
                           rng.randint(0, 63), 1 << rng.randint(0, 31)))

    def ctrl(self, rng: random.Random) -> int:
        """A CTRL word: mostly ENABLE, often FAULT_CLEAR, every other field (ADC_MODE 3 included) random,
        sometimes reserved bits set."""
        v = rm.pack("CTRL", ENABLE=int(rng.random() < 0.85), INJ_EN=rng.getrandbits(1),
                    ADC_MODE=rng.getrandbits(2), INJ_ROT=rng.getrandbits(1), INJ_PER=rng.getrandbits(1),
                    DIRECT=int(rng.random() < 0.2), FAULT_CLEAR=rng.getrandbits(1))
        return v | (rng.getrandbits(32) if rng.random() < 0.1 else 0)

    async def write(self, addr: int, data: int, strb: int = 0xF, holds: tuple = ()) -> None:
        """One write, its BRESP checked against the register model, which applies it (SAFETY_LOCK included)."""
        locked = self.model.store[("SAFETY_LOCK", "LOCK")]
        expect, _ = self.model.write(addr, data, strb)
        if addr in self.history:
            self.history[addr].append(self.model.read(addr)[0])
        self.pending = addr
        resp = await self.bus.write(addr, data, strb, *holds)
        self.pending = None
        if resp != expect:
            self.mismatch(f"write 0x{addr:02X} <= 0x{data:08X} strb 0x{strb:X}: BRESP {resp}, expected "
                          f"{expect} (lock {int(locked)})")
        self.count()

    async def prelude(self) -> None:
        """The start of an epoch: a short carrier period, a watchdog, a random overcurrent limit and
        the outputs enabled, so that the gates switch, the watchdog can fire and the ADC codes trip."""
        rng = self.rng_epoch
        for addr, data in ((rm.PWM_HALF_ADDR, rng.randint(1000, 3000)), (rm.WDT_PERIODS_ADDR, rng.randint(1, 3)),
                           (rm.OC_LIMIT_ADDR, rng.choice((rng.randint(0, 32767), 32767))),
                           (rm.CTRL_ADDR, rm.pack("CTRL", ENABLE=1, INJ_EN=1, FAULT_CLEAR=1))):
            await self.write(addr, data)

    async def writer(self, n: int, commits: bool) -> None:
        """``n`` random writes; without ``commits`` none sets COMMIT.GO and WDT_PERIODS stays 1 to 3, so
        the watchdog fires."""
        rng = self.rng_w
        for _ in range(n):
            u = rng.random()
            strb = 0xF if rng.random() < 0.7 else rng.getrandbits(4)
            if u < 0.2:
                addr, data = rm.CTRL_ADDR, self.ctrl(rng)
            elif u < 0.25:
                addr, data = rm.COMMIT_ADDR, self.data(rng) | rng.getrandbits(1)
            elif u < 0.75:
                addr, data = rng.choice(MAPPED), self.data(rng)
                if addr == LOCK_ADDR and rng.random() > 0.02:
                    data &= ~1                      # lock rarely, so the locked registers get fuzzed
            else:
                addr, data = rng.getrandbits(8), self.data(rng)
            if addr == rm.COMMIT_ADDR and not commits:
                data &= ~rm.COMMIT_GO_MASK
            if addr == rm.WDT_PERIODS_ADDR and not commits:
                data = rng.randint(1, 3)            # keep the watchdog armed
            holds = (rng.choice((0, 0, 0, 1, 2, 5)), rng.choice((0, 0, 0, 1, 3)), rng.choice((0, 0, 1, 4, 40)))
            await self.write(addr, data, strb, holds)
            await self.gap(rng)

    async def reader(self, n: int) -> None:
        rng = self.rng_r
        for _ in range(n):
            u = rng.random()
            if u < 0.3:
                addr = rm.STATUS_ADDR
            elif u < 0.8:
                addr = rng.choice(MAPPED)
            else:
                addr = rng.getrandbits(8)
            values = self.history.get(addr)
            # the value in effect at the issue: the one before a write to this address still in flight
            first = len(values) - 1 - (self.pending == addr) if values else 0
            data, resp = await self.bus.read(addr, rng.choice((0, 0, 1, 3)), rng.choice((0, 0, 1, 4, 40)))
            if addr not in MAPPED and (resp, data) != (SLVERR, 0):
                self.mismatch(f"read 0x{addr:02X}: RRESP {resp} RDATA 0x{data:08X}, expected SLVERR, 0")
            if addr in MAPPED and resp != OKAY:
                self.mismatch(f"read 0x{addr:02X}: RRESP {resp}")
            self.readbacks += bool(values)
            if values and data not in values[first:]:
                self.mismatch(f"read 0x{addr:02X}: RDATA 0x{data:08X}, the model held "
                              f"{', '.join(f'0x{v:08X}' for v in values[first:])} while the read was in flight")
            self.count()
            await self.gap(rng)

    async def pins(self) -> None:
        """Toggle STO and DESAT at random instants: one-cycle glitches, short and long pulses."""
        rng, dut = self.rng_pin, self.dut
        while not self.stop_pins:
            await Timer(rng.choice((rng.randint(1, 3000), rng.randint(3000, 60000))) * CLK_NS, "ns")
            await FallingEdge(dut.clk)
            which = rng.choice(("sto", "desat", "both"))
            for name in ("sto", "desat"):
                if which in (name, "both"):
                    getattr(dut, name).value = 1
            await Timer(rng.choice((1, 2, 3, rng.randint(4, 200), rng.randint(200, 20000))) * CLK_NS, "ns")
            dut.sto.value = 0
            dut.desat.value = 0

    async def run(self) -> None:
        """Epochs of concurrent writes, reads and pin toggles, each ended by a reset; every other
        epoch commits nothing. At least ``total`` transactions, more (COVERAGE_CAP) until every corner of
        COVERAGE was reached."""
        dut, epoch = self.dut, 0
        while self.done < self.total or (self.done < COVERAGE_CAP * self.total
                                         and not all(counters(dut)[name] for name in COVERAGE)):
            n = self.rng_epoch.randint(2000, 12000)
            if self.done < self.total:
                n = min(n, self.total - self.done)
            if n > PRELUDE_WRITES:
                await self.prelude()
                n -= PRELUDE_WRITES
            n_w = n // 2 + self.rng_epoch.randint(0, n % 2)
            self.stop_pins = False
            pins = cocotb.start_soon(self.pins())
            w = cocotb.start_soon(self.writer(n_w, commits=epoch % 2 == 0))
            r = cocotb.start_soon(self.reader(n - n_w))
            await w
            await r
            self.stop_pins = True
            await pins
            await reset(dut, self.rng_epoch.randint(1, 20))
            self.reset_model()
            epoch += 1


@cocotb.test()
async def fuzz(dut):
    """FUZZ_TRANSACTIONS random transactions with seed FUZZ_SEED; zero violations, every response as
    the register map says, the fuzzer reached faults, STO/DESAT and switching gates, and afterwards
    the bus still works (FAULT_CLEAR, write and read back)."""
    seed, total = int(os.environ["FUZZ_SEED"]), int(os.environ["FUZZ_TRANSACTIONS"])
    bus_bound = int(os.environ["FUZZ_BUS_BOUND"])
    cocotb.log.info(f"fuzz: seed {seed}, {total} transactions, bus bound {bus_bound} cycles")
    bus = await start(dut)
    f = Fuzzer(dut, bus, seed, total)
    await f.run()

    # no lock-up: clear the faults, write and read back
    await ClockCycles(dut.clk, 10)
    assert await bus.write(rm.CTRL_ADDR, rm.pack("CTRL", FAULT_CLEAR=1)) == OKAY
    st, resp = await bus.read(rm.STATUS_ADDR)
    st = rm.unpack("STATUS", st)
    assert resp == OKAY and st["FAULT_STO"] == st["FAULT_DESAT"] == st["STO_ACTIVE"] == st["DESAT_ACTIVE"] == 0, st
    probe = random.Random(seed).getrandbits(32)
    assert await bus.write(rm.SPEED_REF_ADDR, probe) == OKAY
    assert await bus.read(rm.SPEED_REF_ADDR) == (probe, OKAY)
    assert await bus.read(rm.ID_ADDR) == (CONSTANTS[rm.ID_ADDR], OKAY)

    c = counters(dut)
    violations = sum(c[v] for v in VIOLATIONS)
    cocotb.log.info("fuzz counters: " + ", ".join(f"{k} {v}" for k, v in c.items()))
    cocotb.log.info(f"fuzz: {f.done} transactions ({f.readbacks} reads with their RDATA predicted), {c['cycles']} "
                    f"cycles checked, {violations + f.mismatches} violations, seed {seed}")
    assert f.done >= total and f.readbacks > total // 10
    assert violations == 0 and f.mismatches == 0, f"seed {seed}: {c}, {f.mismatches} response mismatches"
    assert c["bus_max"] == REG_WAIT, f"longest bus wait {c['bus_max']} cycles, hfi_regs answers in {REG_WAIT}"
    for name in COVERAGE:
        assert c[name] > 0, f"seed {seed}: the fuzzer never reached {name}: {c}"
