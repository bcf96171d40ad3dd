"""cocotb testbench of the clock-domain crossing rtl/hfi_cdc_bus.v and its synchronizer rtl/hfi_cdc_sync.v,
through the wrapper cocotb_tests/hdl/tb_cdc_bus.v (run by cocotb_tests/test_cdc_bus.py, not by pytest).

The bus (s side: CPU clock ``s_clk``; m side: DSP clock ``m_clk``) is driven by
* a master on the s side (:meth:`Bench.access`): it drives ``s_valid`` with address, data and strobe at a
  falling edge of ``s_clk`` and holds them until the rising edge where it sees ``s_ready`` (``s_ready``
  is registered, so that is the edge after the one that raised it: "the master drops valid the clock
  after ready"); the next access may follow right there (back-to-back) or after idle clocks, during
  which address, data and strobe carry random junk with ``s_valid`` low;
* a model slave on the m side (:meth:`Bench.slave`) with a register file of 256 32-bit words (one per
  8-bit address, byte-lane writes): it answers each access after 0..5 m clocks of waiting (``m_ready``
  high for one clock, ``m_rdata`` the word for a read, random junk in every other clock).

The reference is independent of both: :class:`RefRegs` replays the master's own issued accesses in
order (the same initial contents as the slave), so it predicts every read value. Checked, access by
access (first error fails the test, with seed, clock periods and phases, access number):
* the slave sees every access exactly once, in issue order, with its address, data and strobe; it never
  sees ``m_valid`` rise without an access pending on the s side;
* ``m_valid`` stays high with unchanged address, data and strobe in every m clock until the clock
  ``m_ready`` is sampled, and is low in the next one;
* ``s_ready`` rises only while an access is pending and after the slave answered it, is high for
  exactly one s clock; a read returns the reference value;
* latency: with the accept edge ``a`` (the first s edge that sees ``s_valid``) and ``d`` the slave's
  waiting clocks, ``s_ready`` rises at ``a + L`` with (3+d)·Tm + 2·Ts <= L <= (4+d)·Tm + 3·Ts
  (two-flop synchronizer each way, one clock to raise ``m_valid``, one to raise ``s_ready``; the
  bounds include the "sampled or not" case of edges of both clocks at the same instant); with equal
  clocks in phase exactly L = (7+d)·T. Accesses that wait for the m side to leave reset are checked
  for completion only.

Resets: one asynchronous ``rst`` through an hfi_cdc_sync per side (RESET_VALUE 1), as hfi_soc does,
held for >= 20 clocks of the slower clock, asserted and released at random instants.

Clocks are cocotb GPI clocks with even periods in ps (50 % duty); they are changed only while the bus is
idle (stopped at a falling edge, restarted with a rising edge after a random offset per clock).

hfi_cdc_sync (three instances on their own clock ``y_clk``: STAGES 2 with RESET_VALUE 0 and 1, STAGES 3)
is checked against the times of its input changes: q takes each new level at the STAGES-th rising
edge at or after the change (STAGES or STAGES + 1 if the change falls on an edge, "2..3 clocks"
for STAGES 2), exactly once per change (every value change of q recorded, and q sampled every clock).

Seeds: ``HFI_SEED`` (printed); each test draws from its own streams of
``numpy.random.SeedSequence([HFI_SEED, test number])``, so a failure replays with ``HFI_SEED=<seed>``.
``HFI_RANDOM_N`` is the number of accesses per clock pair; ``HFI_CDC_PAIRS`` the number of random clock
pairs (default :data:`N_PAIRS`).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, First, RisingEdge, Timer, ValueChange

from two_clocks import PERIOD_MAX_PS, PERIOD_MIN_PS, RESET_SLOW_CLOCKS, TwoClockBench, clock_pairs, now

N_PAIRS = 32
"""Random clock pairs of test random_clock_ratios (2 of them equal and nearly equal periods)."""
DELAY_MAX = 5
"""The slave waits 0..DELAY_MAX m clocks with m_ready low before the clock with m_ready high."""
WORDS = 256
"""8-bit addresses (AW = 8, as in hfi_soc): the slave's register file has one word per address."""
HOT_ADDRS = 6
"""Accesses go to a few hot addresses most of the time, so reads see earlier writes."""
WORD = 0xFFFFFFFF


def lane_mask(wstrb: int) -> int:
    return sum(0xFF << 8 * k for k in range(4) if wstrb >> k & 1)


class RefRegs:
    """Reference register file: 32-bit words, a write replaces the bytes its strobe selects."""

    def __init__(self, init: list[int]):
        self.word = list(init)

    def read(self, addr: int) -> int:
        return self.word[addr]

    def write(self, addr: int, data: int, wstrb: int) -> None:
        m = lane_mask(wstrb)
        self.word[addr] = self.word[addr] & ~m & WORD | data & m


class SlaveRegs:
    """The m-side slave's own storage: four bytes per address (written lane by lane)."""

    def __init__(self, init: list[int]):
        self.lanes = [[w >> 8 * k & 0xFF for k in range(4)] for w in init]

    def read(self, addr: int) -> int:
        return int.from_bytes(bytes(self.lanes[addr]), "little")

    def write(self, addr: int, data: int, wstrb: int) -> None:
        for k in range(4):
            if wstrb >> k & 1:
                self.lanes[addr][k] = data >> 8 * k & 0xFF


@dataclass
class Access:
    index: int
    addr: int
    wdata: int
    wstrb: int
    expect: int | None = None     # a read: the reference value when it was issued
    accept_t: int = 0             # the s edge that samples it (ps)
    delay: int | None = None      # the slave's waiting clocks

    def __str__(self) -> str:
        kind = "read" if self.wstrb == 0 else f"write 0x{self.wdata:08X} strobe 0x{self.wstrb:X}"
        return f"access {self.index} ({kind} at 0x{self.addr:02X})"


class Bench(TwoClockBench):
    """Clocks, reset, s-side master, m-side slave and monitors of the wrapper tb_cdc_bus."""

    def __init__(self, dut, name: str, test_id: int):
        super().__init__(dut, name, test_id, "HFI_CDC_PAIRS", N_PAIRS)
        self.rng_slave = self.rng_aux
        init = [int(x) for x in self.rng.integers(0, 1 << 32, size=WORDS)]
        self.ref = RefRegs(init)
        self.slave_regs = SlaveRegs(init)
        self.hot = [int(x) for x in self.rng.choice(WORDS, size=HOT_ADDRS, replace=False)]
        self.issued: list[Access] = []
        self.answered = 0             # accesses the slave has answered (m_ready given)
        self.done = 0                 # accesses completed on the s side (s_ready seen, valid dropped)
        self.pending = False          # the master holds an access (from valid to the edge it sees ready)
        self.ready_rises = 0          # s_ready rising edges seen by the monitor
        self.slave_busy = False
        self.current: Access | None = None   # the master's latest access, for messages
        self.m_active_t = None        # from this time on the m side is out of reset (None: in reset)
        self.exact_period = None      # equal clocks in phase: the exact latency check uses this period
        self.latency = []             # (L - lower bound) / (upper - lower) of checked accesses

    # ------------------------------------------------------------------ start, clocks, reset
    async def start(self) -> None:
        d = self.dut
        for sig in (d.s_clk, d.m_clk, d.y_clk, d.s_valid, d.m_ready, d.y_d):
            sig.value = 0
        d.rst.value = 1
        self.junk_s()
        d.m_rdata.value = self.junk()
        await Timer(1, unit="ns")
        cocotb.start_soon(self.slave())
        cocotb.start_soon(self.ready_monitor())
        cocotb.start_soon(self.m_rst_monitor())

    async def set_clocks(self, ts: int, tm: int, off_s: int, off_m: int) -> None:
        """Restart the clocks with periods ts, tm (even ps): first rising edges off_s, off_m ps from now; the bus
        must be idle."""
        self.current = None
        await self.start_clocks(ts, tm, off_s, off_m)

    async def reset(self) -> None:
        """rst high at a random instant for >= 20 clocks of the slower clock, then low at a random
        instant. Checks that both sides are in reset and quiet at the end of the pulse."""
        d = self.dut
        slow = max(self.ts, self.tm)
        await Timer(int(self.rng.integers(1, slow)), unit="ps")
        d.rst.value = 1
        await Timer(RESET_SLOW_CLOCKS * slow + int(self.rng.integers(0, 4 * slow)), unit="ps")
        got = {n: int(getattr(d, n).value) for n in ("s_rst", "m_rst", "s_ready", "m_valid")}
        assert got == dict(s_rst=1, m_rst=1, s_ready=0, m_valid=0), self.fail(f"in reset: {got}")
        d.rst.value = 0
        self.stats["resets"] += 1

    # ------------------------------------------------------------------ monitors and slave
    async def m_rst_monitor(self) -> None:
        d = self.dut
        while True:
            await ValueChange(d.m_rst)
            # the m logic still samples reset at the edge where m_rst falls; it runs from the next one
            self.m_active_t = None if int(d.m_rst.value) else now() + self.tm

    async def ready_monitor(self) -> None:
        """s_ready may rise only while an access is pending, once per access."""
        while True:
            await RisingEdge(self.dut.s_ready)
            self.ready_rises += 1
            if not self.pending:
                self.error(f"s_ready rose with no access pending ({self.done} accesses done)")
            elif self.ready_rises != self.done + 1:
                self.error(f"s_ready rose a second time for access {self.done}")

    async def slave(self) -> None:
        """Model slave on the m side; checks m_valid and the bundled address/data/strobe."""
        d = self.dut
        while True:
            await RisingEdge(d.m_valid)
            await FallingEdge(d.m_clk)
            self.slave_busy = True
            try:
                if not int(d.m_valid.value):
                    self.error("m_valid high for less than one m clock")
                    continue
                if self.answered >= len(self.issued) or not self.pending:
                    self.error(f"m_valid rose with no access pending on the s side ({self.answered} "
                               f"answered, {len(self.issued)} issued, pending={self.pending})")
                    continue
                acc = self.issued[self.answered]
                seen = (int(d.m_addr.value), int(d.m_wdata.value), int(d.m_wstrb.value))
                if seen != (acc.addr, acc.wdata, acc.wstrb):
                    self.error(f"m side got addr 0x{seen[0]:02X} wdata 0x{seen[1]:08X} wstrb 0x{seen[2]:X}, "
                               f"expected {acc} (wdata 0x{acc.wdata:08X})")
                    continue
                delay = int(self.rng_slave.integers(0, DELAY_MAX + 1))
                for k in range(delay):
                    d.m_rdata.value = self.junk()
                    await FallingEdge(d.m_clk)
                    now_seen = (int(d.m_valid.value), int(d.m_addr.value), int(d.m_wdata.value),
                                int(d.m_wstrb.value))
                    if now_seen != (1, *seen):
                        self.error(f"{acc}: m_valid/addr/wdata/wstrb = {now_seen} in wait clock {k + 1} of "
                                   f"{delay}, expected held (1, {seen})")
                d.m_ready.value = 1
                if acc.wstrb == 0:
                    d.m_rdata.value = self.slave_regs.read(acc.addr)
                else:
                    d.m_rdata.value = self.junk()
                    self.slave_regs.write(acc.addr, acc.wdata, acc.wstrb)
                acc.delay = delay
                self.answered += 1
                await FallingEdge(d.m_clk)
                d.m_ready.value = 0
                d.m_rdata.value = self.junk()
                if int(d.m_valid.value):
                    self.error(f"{acc}: m_valid still high in the m clock after m_ready")
            finally:
                self.slave_busy = False

    # ------------------------------------------------------------------ master
    def junk(self) -> int:
        return int(self.rng_clk.integers(0, 1 << 32))

    def junk_s(self) -> None:
        """s_valid low, random address/data/strobe."""
        d = self.dut
        d.s_valid.value = 0
        d.s_addr.value = int(self.rng_clk.integers(0, WORDS))
        d.s_wdata.value = self.junk()
        d.s_wstrb.value = int(self.rng_clk.integers(0, 16))

    def random_access(self) -> tuple[int, int | None, int]:
        """(addr, wdata or None for a read, wstrb)."""
        r = self.rng
        addr = int(r.choice(self.hot)) if r.random() < 0.6 else int(r.integers(0, WORDS))
        if r.random() < 0.5:
            return addr, None, 0
        wstrb = 0xF if r.random() < 0.3 else int(r.integers(1, 16))
        return addr, int(r.integers(0, 1 << 32)), wstrb

    def random_gap(self) -> int:
        r = self.rng.random()
        if r < 0.35:
            return 0
        if r < 0.7:
            return int(self.rng.integers(1, 4))
        if r < 0.9:
            return int(self.rng.integers(4, 16))
        return int(self.rng.integers(16, 61))

    async def idle(self, clocks: int) -> None:
        for _ in range(clocks):
            self.junk_s()
            await FallingEdge(self.dut.s_clk)

    async def access(self, addr: int, wdata: int | None, wstrb: int) -> int:
        """One access, starting at a falling edge of s_clk (the bus idle) and ending at the falling edge
        after the edge where the master sees s_ready (valid still high up to there). Returns s_rdata."""
        d = self.dut
        while int(d.s_rst.value):
            self.junk_s()
            self.stats["waits for s reset"] += 1
            await FallingEdge(d.s_clk)
        read = wdata is None
        if read:
            wdata = self.junk()
        acc = Access(len(self.issued), addr, wdata, wstrb)
        self.current = acc
        if read:
            acc.expect = self.ref.read(addr)
        assert int(d.s_ready.value) == 0, self.fail(f"s_ready high before {acc} was presented")
        self.issued.append(acc)
        self.pending = True
        d.s_valid.value = 1
        d.s_addr.value = addr
        d.s_wdata.value = wdata
        d.s_wstrb.value = wstrb
        acc.accept_t = now() + self.ts // 2          # the next rising edge samples it
        m_active = self.m_active_t is not None and self.m_active_t <= acc.accept_t
        if not m_active:
            self.stats["accesses waiting for the m reset"] += 1
        limit = 40 * (self.ts + self.tm)
        timeout = Timer(limit, unit="ps")
        fired = await First(RisingEdge(d.s_ready), timeout)
        self.check_errors()
        assert fired is not timeout, self.fail(f"no s_ready within {limit} ps of {acc} "
                                               f"(the slave answered {self.answered} accesses)")
        latency = now() - acc.accept_t
        await FallingEdge(d.s_clk)                    # after the edge that raised s_ready
        self.check_errors()
        assert int(d.s_ready.value) == 1, self.fail(f"{acc}: s_ready shorter than one s clock")
        assert self.answered == acc.index + 1, self.fail(f"{acc}: s_ready before the slave answered it")
        rdata = int(d.s_rdata.value)
        if read:
            assert rdata == acc.expect, self.fail(f"{acc}: s_rdata 0x{rdata:08X}, "
                                                  f"reference 0x{acc.expect:08X}")
            self.stats["reads"] += 1
        else:
            self.ref.write(addr, wdata, wstrb)
            self.stats["writes"] += 1
        if m_active:
            self.check_latency(acc, latency)
        await FallingEdge(d.s_clk)                    # the master saw ready at this edge; valid drops now
        assert int(d.s_ready.value) == 0, self.fail(f"{acc}: s_ready high for more than one s clock")
        self.pending = False
        self.done += 1
        self.stats["accesses"] += 1
        self.stats[f"slave delay {acc.delay}"] += 1
        return rdata

    def check_latency(self, acc: Access, latency: int) -> None:
        ts, tm, dl = self.ts, self.tm, acc.delay
        lo, hi = (3 + dl) * tm + 2 * ts, (4 + dl) * tm + 3 * ts
        assert lo <= latency <= hi, self.fail(
            f"{acc}: s_ready {latency} ps after the accept edge, expected {lo}..{hi} ps "
            f"(slave delay {dl})")
        if self.exact_period is not None:
            exp = (7 + dl) * self.exact_period
            assert latency == exp, self.fail(f"{acc}: equal clocks in phase: latency {latency} ps, "
                                             f"expected exactly {exp} ps ((7 + {dl}) clocks)")
        self.stats["latency checked"] += 1
        self.latency.append((latency - lo) / (hi - lo) if hi > lo else 0.0)

    async def traffic(self, n: int, gaps: str = "random", pattern: str = "random") -> None:
        """n accesses from a falling edge of s_clk; gaps "random" or "zero" (all back-to-back);
        pattern "random" or "write_read" (each write read back at once)."""
        for i in range(n):
            gap = self.random_gap() if gaps == "random" else 0
            if gap == 0 and i > 0:
                self.stats["back-to-back"] += 1
            await self.idle(gap)
            if pattern == "write_read" and i % 2 == 1:
                prev = self.issued[-1]
                addr, wdata, wstrb = prev.addr, None, 0
            else:
                addr, wdata, wstrb = self.random_access()
                if pattern == "write_read" and wdata is None:
                    wdata, wstrb = int(self.rng.integers(0, 1 << 32)), int(self.rng.integers(1, 16))
            await self.access(addr, wdata, wstrb)
        self.junk_s()

    async def settle(self) -> None:
        """Idle for 8 clocks of the slower clock; then every access issued must be done, once."""
        await Timer(8 * max(self.ts, self.tm), unit="ps")
        await FallingEdge(self.dut.s_clk)
        while self.slave_busy:
            await FallingEdge(self.dut.m_clk)
        self.check_errors()
        n = len(self.issued)
        assert self.answered == n and self.done == n and self.ready_rises == n, self.fail(
            f"after idling: {n} issued, {self.answered} answered by the slave, {self.done} done, "
            f"{self.ready_rises} s_ready pulses")

    def summary(self) -> str:
        lat = (f", latency within its bounds at {min(self.latency):.2f}..{max(self.latency):.2f}"
               if self.latency else "")
        return f"{self.name}: {dict(sorted(self.stats.items()))}{lat}"


# ---------------------------------------------------------------------- bus tests
@cocotb.test()
async def random_clock_ratios(dut):
    """HFI_CDC_PAIRS random clock pairs (3..97 ns, ratios 1:30..30:1, random phases), HFI_RANDOM_N random
    accesses each (random addresses, data, strobes, reads and writes, gaps 0..60 clocks); a reset before
    every other pair, the others keep the handshake state across the change of clocks."""
    b = Bench(dut, "random_clock_ratios", 1)
    await b.start()
    pairs = clock_pairs(b.rng, b.n_pairs)
    for k, (ts, tm, off_s, off_m) in enumerate(pairs):
        b.where = f"pair {k}"
        await b.set_clocks(ts, tm, off_s, off_m)
        cocotb.log.info(f"pair {k}: Ts={ts} ps Tm={tm} ps (Ts/Tm={ts / tm:.3f}), first edges "
                        f"s@{b.phase[0]} m@{b.phase[1]} ps")
        if k % 2 == 0:
            await b.reset()
        await FallingEdge(dut.s_clk)
        await b.traffic(b.n_random)
        await b.settle()
    cocotb.log.info(b.summary())
    ratios = [ts / tm for ts, tm, _, _ in pairs]
    cocotb.log.info(f"Ts/Tm from {min(ratios):.4f} to {max(ratios):.2f}")
    assert b.done == len(pairs) * b.n_random == b.stats["accesses"], b.fail("access count")
    assert b.stats["reads"] > 0 and b.stats["writes"] > 0 and b.stats["back-to-back"] > 0
    assert b.stats["latency checked"] > b.done // 2
    if b.n_pairs >= N_PAIRS:
        assert min(ratios) < 1 / 20 and max(ratios) > 20, ratios
    if b.done >= 1000:
        assert all(b.stats[f"slave delay {k}"] > 0 for k in range(DELAY_MAX + 1)), b.stats


async def directed(dut, name: str, test_id: int, ts: int, tm: int, in_phase: bool = False,
                   gaps: str = "random", pattern: str = "random") -> Bench:
    b = Bench(dut, name, test_id)
    await b.start()
    b.where = name
    off_s, off_m = (0, 0) if in_phase else (int(b.rng.integers(0, ts)), int(b.rng.integers(0, tm)))
    await b.set_clocks(ts, tm, off_s, off_m)
    await b.reset()
    if in_phase:
        b.exact_period = ts
    await FallingEdge(dut.s_clk)
    await b.traffic(b.n_random, gaps, pattern)
    await b.settle()
    cocotb.log.info(b.summary())
    assert b.done == b.n_random, b.fail("access count")
    return b


@cocotb.test()
async def equal_clocks_in_phase(dut):
    """Ts = Tm = 10 ns, rising edges together: every latency exactly (7 + slave delay) clocks."""
    b = await directed(dut, "equal_clocks_in_phase", 2, 10_000, 10_000, in_phase=True)
    assert b.stats["latency checked"] >= b.done - 1


@cocotb.test()
async def s_fast_30_to_1(dut):
    """s_clk 30 times faster than m_clk (3 ns and 90 ns), random phases."""
    await directed(dut, "s_fast_30_to_1", 3, 3_000, 90_000)


@cocotb.test()
async def m_fast_1_to_30(dut):
    """m_clk 30 times faster than s_clk (90 ns and 3 ns), random phases."""
    await directed(dut, "m_fast_1_to_30", 4, 90_000, 3_000)


@cocotb.test()
async def back_to_back(dut):
    """Every access presented the clock after the previous s_ready (the master keeps valid high through
    the edge where it sees ready and presents the next access right after it), each write read back at
    once: with equal clocks in phase (exact latency: the access is taken at that first edge), 30:1,
    1:30 and a random pair."""
    b = Bench(dut, "back_to_back", 5)
    await b.start()
    rnd = clock_pairs(b.rng_clk, 4)[-1]
    for k, (ts, tm, off_s, off_m) in enumerate([(10_000, 10_000, 0, 0),
                                                 (3_000, 90_000, int(b.rng.integers(0, 3_000)), 0),
                                                 (90_000, 3_000, 0, int(b.rng.integers(0, 3_000))), rnd]):
        b.where = f"setup {k}"
        await b.set_clocks(ts, tm, off_s, off_m)
        await b.reset()
        b.exact_period = ts if (ts, tm, off_s, off_m) == (10_000, 10_000, 0, 0) else None
        await FallingEdge(dut.s_clk)
        before = b.stats["latency checked"]
        await b.traffic(b.n_random, gaps="zero", pattern="write_read")
        await b.settle()
        assert b.stats["latency checked"] - before >= b.n_random - 1, b.fail("latency checks")
    cocotb.log.info(b.summary())
    assert b.done == 4 * b.n_random and b.stats["back-to-back"] == 4 * (b.n_random - 1)


@cocotb.test()
async def reset_idle_then_traffic(dut):
    """Reset of both sides while idle (one rst through the two synchronizers, as in hfi_soc; the
    handshake left in either toggle state), then traffic again; twice per clock setup, for equal
    clocks, 30:1, 1:30 and two random pairs. Nothing may move on either bus during or after the reset
    until the master's next access; the first access after the reset may have to wait for the m side."""
    b = Bench(dut, "reset_idle_then_traffic", 6)
    await b.start()
    setups = [(10_000, 10_000, 0, 0), (3_000, 90_000, 0, 0), (90_000, 3_000, 0, 0),
              *clock_pairs(b.rng_clk, 6)[-2:]]
    n = max(5, b.n_random // 10)
    for k, (ts, tm, off_s, off_m) in enumerate(setups):
        b.where = f"setup {k}"
        await b.set_clocks(ts, tm, off_s, off_m)
        await b.reset()
        for rnd in range(3):
            await FallingEdge(dut.s_clk)
            await b.traffic(n + (rnd + k) % 2)       # odd and even counts: req/ack left at 0 and at 1
            await b.settle()
            await Timer(int(b.rng.integers(0, 10 * max(ts, tm))), unit="ps")
            await b.reset()
            await b.settle()                         # no access may appear from the reset alone
    await FallingEdge(dut.s_clk)
    await b.traffic(n)
    await b.settle()
    cocotb.log.info(b.summary())
    assert b.stats["resets"] == 4 * len(setups)
    assert b.stats["accesses waiting for the m reset"] > 0, b.stats


# ---------------------------------------------------------------------- hfi_cdc_sync
SYNCS = (("y_q2", 2, 0), ("y_q2r", 2, 1), ("y_q3", 3, 0))
"""(wrapper output, STAGES, RESET_VALUE) of the synchronizers on y_clk."""


@cocotb.test()
async def sync_levels(dut):
    """hfi_cdc_sync: levels of y_d held for 3..11 clocks of y_clk, changed at random instants (a quarter
    exactly on a rising edge, a quarter on a falling edge), on three random y_clk periods. Each change
    must appear at q at the STAGES-th rising edge after it (STAGES or STAGES + 1 edges counted from an
    edge the change falls on), exactly once: q changes once per change of y_d (recorded value
    changes), and q sampled at every falling edge of y_clk shows one change per change of y_d."""
    b = Bench(dut, "sync_levels", 7)
    rng = b.rng
    d = dut
    d.y_clk.value = 0
    d.y_d.value = 0
    await Timer(1, unit="ns")
    for name, _, rv in SYNCS:
        got = int(getattr(d, name).value)
        assert got == rv, b.fail(f"{name} = {got} before the first clock, expected RESET_VALUE {rv}")
    events = [(now(), 0, 0)]                 # (time, new y_d, segment)
    changes = {name: [] for name, _, _ in SYNCS}
    samples = {name: [] for name, _, _ in SYNCS}

    async def watch(name: str) -> None:
        sig = getattr(d, name)
        while True:
            await ValueChange(sig)
            changes[name].append((now(), int(sig.value)))

    async def sample() -> None:
        while True:
            await FallingEdge(d.y_clk)
            t = now()
            for name, _, _ in SYNCS:
                samples[name].append((t, int(getattr(d, name).value)))

    for name, _, _ in SYNCS:
        cocotb.start_soon(watch(name))
    cocotb.start_soon(sample())

    segments = []                            # (first rising edge, period)
    per_segment = max(50, b.n_random // 2)
    clock = None
    kinds = Counter()
    level = 0
    for seg in range(3):
        ty = 2 * int(rng.integers(PERIOD_MIN_PS // 2, PERIOD_MAX_PS // 2 + 1))
        if seg == 0:
            ty = 2 * int(rng.integers(PERIOD_MIN_PS // 2, 10_000 // 2))     # one fast clock
        if clock is not None:
            await FallingEdge(d.y_clk)
            clock.stop()
        await Timer(int(rng.integers(1, ty)), unit="ps")
        clock = Clock(d.y_clk, ty, unit="ps", impl="gpi")
        t0 = now()
        clock.start(start_high=True)
        segments.append((t0, ty))
        t_prev = t0
        for _ in range(per_segment):
            base = t_prev + 3 * ty + int(rng.integers(0, 7 * ty))
            kind = int(rng.integers(0, 4))
            if kind == 0:                    # on a rising edge
                t = t0 + -(-(base - t0) // ty) * ty
            elif kind == 1:                  # on a falling edge
                t = t0 + ty // 2 + -(-(base - t0 - ty // 2) // ty) * ty
            else:
                t = base
            kinds[("rising edge", "falling edge", "between", "between")[kind]] += 1
            await Timer(t - now(), unit="ps")
            level ^= 1
            d.y_d.value = level
            events.append((t, level, seg))
            t_prev = t
        await Timer(12 * ty, unit="ps")      # the last change through every instance
    checked = 0
    for name, stages, rv in SYNCS:
        prev = rv
        expected = []
        for t, v, seg in events:
            if v != prev:
                expected.append((t, v, seg))
                prev = v
        got = changes[name]
        assert len(got) == len(expected), b.fail(
            f"{name}: {len(got)} value changes of q for {len(expected)} changes of y_d")
        for (t, v, seg), (tq, vq) in zip(expected, got):
            t0, ty = segments[seg]
            where = f"{name}: y_d -> {v} at {t} ps (y_clk {ty} ps from {t0} ps)"
            assert vq == v, b.fail(f"{where}: q -> {vq} at {tq} ps")
            assert tq >= t0 and (tq - t0) % ty == 0, b.fail(f"{where}: q changed at {tq} ps, "
                                                            "not on a rising edge")
            first = max(0, -(-(t - t0) // ty))          # index of the first rising edge at or after t
            edges = (tq - t0) // ty - first + 1         # rising edges in [t, tq]
            on_edge = t >= t0 and (t - t0) % ty == 0
            allowed = {stages, stages + 1} if on_edge else {stages}
            assert edges in allowed, b.fail(f"{where}: q changed at the {edges}th rising edge, expected "
                                            f"{sorted(allowed)}")
            checked += 1
        seq = samples[name]
        flips = [(t, q) for (t, q), (_, p) in zip(seq[1:], seq[:-1]) if q != p]
        # the first sample is at the first falling edge; a change of q before it is not a sampled flip
        first_sample_t = seq[0][0]
        sampled_expected = [(tq, vq) for tq, vq in got if tq > first_sample_t]
        assert len(flips) == len(sampled_expected), b.fail(
            f"{name}: sampled every clock, q changed {len(flips)} times, expected {len(sampled_expected)}")
        for (ts_, q), (tq, vq) in zip(flips, sampled_expected):
            t0, ty = next((s for s in reversed(segments) if s[0] <= tq))
            assert q == vq and ts_ == tq + ty // 2, b.fail(
                f"{name}: sampled change to {q} at {ts_} ps, q changed to {vq} at {tq} ps")
    cocotb.log.info(f"sync_levels: {len(events) - 1} changes of y_d ({dict(kinds)}), {checked} q changes "
                    f"checked on {len(SYNCS)} synchronizers, y_clk periods {[s[1] for s in segments]} ps")
    assert checked >= len(SYNCS) * 3 * 50
