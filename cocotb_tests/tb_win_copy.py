"""cocotb testbench of rtl/hfi_win_copy.v (the CPU-clock copy of hfi_dsp's window-result registers), through
the wrapper cocotb_tests/hdl/tb_win_copy.v (run by cocotb_tests/test_win_copy.py, not by pytest).

The copy (clock ``s_clk``, the CPU's) takes, all words at once, the words of ``src`` that the mask
HFI_WINDOW_COPY_WORDS marks, in the clock after the two-flop-synchronized ``src_tog`` changed. The reference
for which words are copied is ``golden.regmap.WINDOW_COPY`` (the register names; their byte addresses from
``golden.regmap.REGISTERS``), not the Verilog's mask.

Source (clock ``m_clk``, hfi_dsp's place; :meth:`Bench.source`): windows as hfi_dsp makes them. Every copied
word takes a new random value (nonzero, different from the previous window's) in one m clock and src_tog flips
in the next (the flip edge ``t_f``); the words then hold for a random number of m clocks, at least
:data:`HOLD_MIN_S` s clocks; then, in about half the windows, the next window boundary is emulated before its
toggle: 1..4 changes of random subsets of the copied words to junk values (spread over up to ~12 s clocks),
which never get a toggle. The words that are not copied take new junk at every change of ``src``. After each
reset the source waits for both sides to leave reset and keeps changing junk values, without a toggle, for a
while (:data:`FIRST_DELAY_S` s clocks, longer after a reset in the middle) before its first window.
src_tog is forced to 0 by the m-side reset (as hfi_dsp's window_tog); the words are not reset. A monitor
checks that src_tog changes exactly at the logged flips (or to 0 in reset).

Reads (s side; :meth:`Bench.read`): the master presents ``sel`` and a random copied address at a falling edge
of ``s_clk`` and holds them until the rising edge where it sees ``ready``; the next read follows right there
(back-to-back) or after random idle clocks (``sel`` low, junk address). Checked for every read, with R the
rising edge that samples it (half a clock after it is presented):

* ``hit`` = 1 and ``ready`` rises at R (exactly one s clock after sel was presented), falls at R + Ts
  (high exactly one clock: a monitor counts its rises, one per read and none without a read);
* ``rdata`` is exactly the word the copy holds before edge R (RTL: ``rdata <= word`` at R). The copy of a
  flip at ``t_f``: the first synchronizer flop takes the new src_tog at the first s edge S > t_f (or at S = t_f
  when both edges fall at the same instant: simulator order), the second at S + Ts, ``take`` is high in the
  following clock, so the copy takes the words at S + 2Ts and the read register returns them from
  R = S + 3Ts on: 2 synchronizer flops + the take clock + the read's register. As R - 3Ts is an s edge,
  this is exact in the read's own terms:

      R - t_f > 3 Ts: rdata = the window of the flip (or a later one);
      R - t_f < 3 Ts: rdata = the previous window (0 after a reset);
      R - t_f = 3 Ts (an s edge at t_f itself): either of the two.

  In terms of the instant the read is presented (P = R - Ts/2, the falling edge before R): every read
  presented more than 2.5 s clocks after the flip (2.5 s clocks + 1 m clock after the words changed; so
  certainly every read presented more than 4 s clocks + 2 m clocks after the flip) returns the new window,
  none presented less than 2.5 s clocks after it does. So a read returns only the current window or the
  one before, and never a value the source held without a toggle (junk, the next window's words before its
  flip, the words held during and after a reset). (Both simulators return the window before at
  R - t_f = 3 Ts: the s edge at t_f samples src_tog's old value; the statistics count it.)

* After every reset (both sides, one asynchronous ``rst`` through a synchronizer per side, as hfi_soc),
  every copied word reads 0 until the first toggle after it, whatever the source holds.

Clocks are cocotb GPI clocks with even periods in ps (50 % duty), changed only between traffic (the source
stopped, the copy settled: flips before the clock change count as copied); every time above is exact in ps.

Seeds: ``HFI_SEED`` (printed); each test draws from its own streams of
``numpy.random.SeedSequence([HFI_SEED, test number])``, so a failure replays with ``HFI_SEED=<seed>``.
``HFI_RANDOM_N`` is the number of reads per clock pair; ``HFI_WINCOPY_PAIRS`` the number of random clock
pairs besides the three fixed ones (default :data:`N_PAIRS`).
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass

import cocotb
import numpy as np
from cocotb.triggers import FallingEdge, Timer, ValueChange

from golden import regmap as rm
from two_clocks import RESET_SLOW_CLOCKS, TwoClockBench, clock_pairs, now

COPY_ADDRS = tuple(rm.REGISTERS[name]["addr"] for name in rm.WINDOW_COPY)
"""Byte addresses of the copied registers (golden.regmap.WINDOW_COPY)."""
NAME = {rm.REGISTERS[name]["addr"]: name for name in rm.WINDOW_COPY}
N_PAIRS = 8
"""Random clock pairs of random_clock_ratios, besides equal clocks in phase, 30:1 and 1:30."""
SYNC_CLOCKS = 3
"""A read sampled at the s edge R returns the words of a flip at t_f iff R - t_f > SYNC_CLOCKS * Ts
(either at equality): see the module docstring."""
HOLD_MIN_S = 20
"""The copied words hold for at least this many s clocks after the flip (the brief's floor; hfi_dsp holds
them for a PWM period minus the interrupt latency)."""
FIRST_DELAY_S = 8
"""After a reset or a change of clocks the source changes only junk, without a toggle, for at least this
many s clocks before its first window."""
WORD = 0xFFFFFFFF


class _SourceReset(Exception):
    """The m side went into reset while the source waited."""


@dataclass
class Flip:
    index: int
    t: int                      # the m edge at which src_tog took its new value (ps)
    words: dict[int, int]       # copied byte address -> value, held since the m edge before t


class Bench(TwoClockBench):
    """Clocks, reset, the m-side source, the s-side reader and the monitors of the wrapper tb_win_copy."""

    def __init__(self, dut, name: str, test_id: int):
        super().__init__(dut, name, test_id, "HFI_WINCOPY_PAIRS", N_PAIRS)
        self.rng_src = self.rng_aux
        self.current = ""
        # source state
        self.cur = dict.fromkeys(COPY_ADDRS, 0)   # the copied words of src_next (src from the next m edge)
        self.tog = 0                              # src_tog as the source has set it
        self.flips: list[Flip] = []
        self.flip_t: list[int] = []
        self.junk_values: set[int] = set()        # values the source gave copied words without a toggle
        self.src_log: list[tuple[int, dict[int, int]]] = []   # (m edge, the copied words src takes there)
        self.m_resets = 0                         # rises of m_rst seen by the monitor
        self.first_delay_s = FIRST_DELAY_S         # junk only before the first window after a (re)start
        self.first_hold_s = HOLD_MIN_S            # the hold of that first window
        # reader state
        self.epoch = 0                            # flips[epoch:] came after the last s-side reset
        self.settled_t = 0                        # flips before this time are copied (clocks changed after)
        self.reads = 0
        self.ready_rises = 0
        self.pending = False
        self.confirmed = 0                        # logged flips the src_tog monitor saw happen
        self.either_new = None                    # expected(): the flip's word when R - t_f = 3Ts

    # ------------------------------------------------------------------ start, clocks, reset
    async def start(self) -> None:
        d = self.dut
        for sig in (d.s_clk, d.m_clk, d.sel):
            sig.value = 0
        v = d.src_tog.value                         # as a test before left it (x at time 0): it changes in reset only
        d.tog_next.value = int(v) if v.is_resolvable else 0
        d.rst.value = 1
        d.addr.value = 0
        for a in COPY_ADDRS:                        # junk from the start (taken at the first m edge)
            self.cur[a] = self.fresh({0})
            self.junk_values.add(self.cur[a])
        self.write_src(0)
        await Timer(1, unit="ns")
        cocotb.start_soon(self.ready_monitor())
        cocotb.start_soon(self.m_rst_monitor())
        cocotb.start_soon(self.s_rst_monitor())
        cocotb.start_soon(self.tog_monitor())

    async def set_clocks(self, ts: int, tm: int, off_s: int, off_m: int) -> None:
        """Restart the clocks with periods ts, tm (even ps): first rising edges off_s, off_m ps from now. Every
        flip logged so far has been copied (the caller settled the copy before)."""
        await self.stop_clocks()
        self.settled_t = now()
        await self.start_clocks(ts, tm, off_s, off_m)

    async def reset(self) -> None:
        """rst high at a random instant for >= 20 clocks of the slower clock, then low at a random instant;
        returns at the first falling edge of s_clk with s_rst low (the reader may present a read there).
        Checks that both sides are in reset and ready low at the end of the pulse."""
        d = self.dut
        slow = max(self.ts, self.tm)
        await Timer(int(self.rng.integers(1, slow)), unit="ps")
        d.sel.value = 0
        d.rst.value = 1
        await Timer(RESET_SLOW_CLOCKS * slow + int(self.rng.integers(0, 4 * slow)), unit="ps")
        got = {n: int(getattr(d, n).value) for n in ("s_rst", "m_rst", "ready", "src_tog")}
        assert got == dict(s_rst=1, m_rst=1, ready=0, src_tog=0), self.fail(f"in reset: {got}")
        d.rst.value = 0
        self.stats["resets"] += 1
        await self.wait_s_active()

    async def wait_s_active(self) -> None:
        d = self.dut
        await FallingEdge(d.s_clk)
        while int(d.s_rst.value):
            self.junk_s()
            await FallingEdge(d.s_clk)

    # ------------------------------------------------------------------ monitors
    async def m_rst_monitor(self) -> None:
        """m_rst rising: src_tog goes to 0 at the next m edge and must stay there after the reset."""
        d = self.dut
        while True:
            await ValueChange(d.m_rst)
            if int(d.m_rst.value):
                self.m_resets += 1
                self.tog = 0
                d.tog_next.value = 0

    async def s_rst_monitor(self) -> None:
        """s_rst falling: the copy reads 0 until the flips logged from here on."""
        d = self.dut
        while True:
            await ValueChange(d.s_rst)
            if not int(d.s_rst.value):
                self.epoch = len(self.flips)

    async def tog_monitor(self) -> None:
        """src_tog changes exactly at the logged flips, or to 0 with m_rst high (the bench's own check)."""
        d = self.dut
        while True:
            await ValueChange(d.src_tog)
            v, t = int(d.src_tog.value), now()
            logged = self.confirmed < len(self.flips) and self.flip_t[self.confirmed] == t
            if int(d.m_rst.value) and v == 0 and not logged:
                continue
            if logged:
                self.confirmed += 1
            else:
                nxt = self.flip_t[self.confirmed] if self.confirmed < len(self.flips) else None
                self.error(f"src_tog -> {v} at {t} ps, the next logged flip is at {nxt} ps")

    async def ready_monitor(self) -> None:
        """ready may rise only while a read is pending, once per read."""
        while True:
            await ValueChange(self.dut.ready)
            if not int(self.dut.ready.value):
                continue
            self.ready_rises += 1
            if not self.pending:
                self.error(f"ready rose with no read pending ({self.reads} reads done)")
            elif self.ready_rises != self.reads + 1:
                self.error(f"ready rose a second time for read {self.reads}")

    # ------------------------------------------------------------------ source (m side)
    def write_src(self, t_edge: int | None = None) -> None:
        """src_next: the copied words of self.cur, junk in every other word (taken at the next m edge, at
        t_edge: by default half an m clock from now, the source writing at falling edges)."""
        junk = self.rng_src.integers(0, 1 << 32, size=64, dtype=np.uint64)
        for a, v in self.cur.items():
            junk[a // 4] = v
        self.dut.src_next.value = int.from_bytes(junk.astype("<u4").tobytes(), "little")
        self.src_log.append((now() + self.tm // 2 if t_edge is None else t_edge, dict(self.cur)))

    def fresh(self, avoid: set[int]) -> int:
        while True:
            v = int(self.rng_src.integers(1, 1 << 32))
            if v not in avoid:
                return v

    def check_source_reset(self, seen: int) -> None:
        if self.m_resets != seen:
            raise _SourceReset

    async def source(self) -> None:
        """The m-side source: windows until cancelled; after every m-side reset, wait for both sides to leave
        reset and start again with the junk-only delay. Runs from any time (syncs to a falling edge of m_clk)."""
        d = self.dut
        while True:
            try:
                await FallingEdge(d.m_clk)
                while int(d.m_rst.value) or int(d.s_rst.value):
                    if int(d.m_rst.value):
                        await FallingEdge(d.m_rst)
                    if int(d.s_rst.value):
                        await FallingEdge(d.s_rst)
                    await FallingEdge(d.m_clk)
                seen = self.m_resets           # m_rst is low: a reset from here on counts
                await self.junk_phase(seen, self.first_delay_s, steps=int(self.rng_src.integers(1, 5)), all_first=True)
                await self.window(seen, self.first_hold_s)
                while True:
                    await self.window(seen, HOLD_MIN_S)
            except _SourceReset:
                self.stats["source windows cut by a reset"] += 1

    async def m_wait(self, clocks: int, seen: int) -> None:
        """From a falling edge of m_clk to the one `clocks` (>= 0) later."""
        if clocks:
            await Timer(clocks * self.tm, unit="ps")
        self.check_source_reset(seen)

    async def junk_phase(self, seen: int, span_s: int, steps: int, all_first: bool = False) -> None:
        """`steps` changes of random subsets of the copied words to junk values, no toggle, at random m clocks
        (one m clock apart at least) of a span of at least span_s s clocks; ends at the falling edge of m_clk
        at the end of the span. all_first: the first change, at the m edge right after the call, gives every
        copied word a junk value."""
        span_m = max(steps, math.ceil(span_s * self.ts / self.tm))
        at = np.sort(self.rng_src.choice(np.arange(0, span_m), size=steps, replace=False))
        if all_first:
            at[0] = 0
        gaps = np.diff(at, prepend=0)
        for n, g in enumerate(gaps):
            await self.m_wait(int(g), seen)
            k = len(COPY_ADDRS) if all_first and n == 0 else int(self.rng_src.integers(1, len(COPY_ADDRS) + 1))
            for a in self.rng_src.choice(COPY_ADDRS, size=k, replace=False):
                v = self.fresh({self.cur[int(a)]})
                self.cur[int(a)] = v
                self.junk_values.add(v)
            self.write_src()
        await self.m_wait(span_m - int(at[-1]), seen)

    async def window(self, seen: int, hold_s: int) -> None:
        """From a falling edge of m_clk: new words at the next m edge, the flip at the one after, the hold (at
        least hold_s s clocks), and maybe the next boundary's junk. Ends at a falling edge of m_clk."""
        d = self.dut
        last = self.flips[-1].words if self.flips else {}
        for a in COPY_ADDRS:
            self.cur[a] = self.fresh({self.cur[a], last.get(a, 0)})
        self.write_src()
        await self.m_wait(1, seen)
        assert not int(d.m_rst.value)      # else the monitor counted a reset (m_wait raised)
        self.tog ^= 1
        d.tog_next.value = self.tog
        t_f = now() + self.tm // 2
        self.flips.append(Flip(len(self.flips), t_f, dict(self.cur)))
        self.flip_t.append(t_f)
        self.stats["windows"] += 1
        base = max(2, math.ceil(hold_s * self.ts / self.tm))
        r = self.rng_src.random()
        hold = base if r < 0.1 else base + int(self.rng_src.integers(0, base + 1)) if r < 0.85 \
            else base + int(self.rng_src.integers(0, 5 * base))
        await self.m_wait(hold, seen)          # the words change at the edge hold m clocks after the flip
        if self.rng_src.random() < 0.5:
            self.stats["windows with junk before the next"] += 1
            await self.junk_phase(seen, 12, steps=int(self.rng_src.integers(1, 5)))

    def run_source(self):
        return cocotb.start_soon(self.source())

    async def settle(self, task) -> None:
        """Stop the source and idle until every logged flip is copied (> 3 s clocks + 1 m clock)."""
        task.cancel()
        self.junk_s()
        await Timer(6 * self.ts + 2 * self.tm, unit="ps")
        self.check_errors()
        assert self.confirmed == len(self.flips), self.fail(
            f"{len(self.flips)} flips logged, src_tog changed at {self.confirmed} of them")
        assert self.ready_rises == self.reads, self.fail(f"{self.ready_rises} ready pulses for {self.reads} reads")

    # ------------------------------------------------------------------ reader (s side)
    def junk_s(self) -> None:
        self.dut.sel.value = 0
        self.dut.addr.value = int(self.rng.integers(0, 256))

    def expected(self, r: int, addr: int) -> tuple[set[int], str]:
        """The values a read sampled at the s edge r may return (one, or two with an s edge at a flip), and
        the read's class for the statistics."""
        ts = self.ts
        cut = r - SYNC_CLOCKS * ts
        lo = self.epoch
        if cut <= self.settled_t:
            i = bisect.bisect_left(self.flip_t, self.settled_t, lo)
            eq = None
        else:
            i = bisect.bisect_left(self.flip_t, cut, lo)
            eq = i if i < len(self.flip_t) and self.flip_t[i] == cut else None
        prev = self.flips[i - 1].words[addr] if i > lo else 0
        allowed = {prev}
        if eq is not None:
            allowed.add(self.flips[eq].words[addr])
            self.either_new = self.flips[eq].words[addr]
        # class: the latest flip before r (after the last reset)
        j = bisect.bisect_left(self.flip_t, r, lo) - 1
        if j < lo:
            kind = "no flip since the reset"
        elif self.flip_t[j] < self.settled_t:
            kind = "latest flip before the clock change"
        else:
            dt = r - self.flip_t[j]
            if dt < ts:
                kind = "flip in flight, R - t_f < Ts"
            elif dt < 2 * ts:
                kind = "flip in flight, Ts <= R - t_f < 2Ts"
            elif dt < 3 * ts:
                kind = "flip in flight, 2Ts <= R - t_f < 3Ts"
            elif dt == 3 * ts:
                kind = "R - t_f = 3Ts (either)"
            elif dt <= 4 * ts:
                kind = "new, 3Ts < R - t_f <= 4Ts"
            else:
                kind = "new, R - t_f > 4Ts"
        return allowed, kind

    def src_at(self, t: int, addr: int) -> int:
        """The copied word at addr that src held at time t (from the source's log; an m edge at t counted)."""
        k = bisect.bisect_right(self.src_log, t, key=lambda e: e[0]) - 1
        return self.src_log[k][1][addr]

    async def read(self, addr: int) -> int:
        """At a falling edge of s_clk, ready low: present a read of addr; returns rdata at the falling edge
        two clocks later (the master saw ready at the rising edge before; sel still high: the caller presents
        the next read or idles)."""
        d = self.dut
        ts = self.ts
        self.current = f"read {self.reads} of {NAME.get(addr, '?')} (0x{addr:02X})"
        assert int(d.ready.value) == 0, self.fail("ready high before the read was presented")
        d.sel.value = 1
        d.addr.value = addr
        self.pending = True
        r = now() + ts // 2
        await Timer(ts, unit="ps")
        got = (int(d.hit.value), int(d.ready.value))
        assert got == (1, 1), self.fail(f"(hit, ready) = {got} half an s clock after the edge that sampled the "
                                        f"read, expected (1, 1)")
        rdata = int(d.rdata.value)
        self.either_new = None
        allowed, kind = self.expected(r, addr)
        self.stats[kind] += 1
        if self.either_new is not None:
            got = "the flip's window" if rdata == self.either_new else "the window before"
            self.stats[f"R - t_f = 3Ts: {got}"] += 1
        src = self.src_at(r, addr)
        if src not in allowed:
            self.stats["source held another value at R"] += 1
            if src in self.junk_values:
                self.stats["source held junk at R"] += 1
        if rdata not in allowed:
            why = ""
            if rdata in self.junk_values:
                why = " (a value the source held without a toggle)"
            elif any(rdata == f.words[addr] for f in self.flips):
                k = next(f.index for f in reversed(self.flips) if rdata == f.words[addr])
                why = f" (the words of flip {k} at {self.flip_t[k]} ps)"
            near = [t for t in self.flip_t[max(self.epoch, len(self.flip_t) - 3):] if t < r + 4 * ts]
            assert False, self.fail(
                f"rdata 0x{rdata:08X}{why} at the edge R={r} ps, expected {sorted(f'0x{v:08X}' for v in allowed)} "
                f"({kind}; the latest flips at {near} ps, R - 3Ts = {r - SYNC_CLOCKS * ts} ps)")
        await Timer(ts, unit="ps")
        assert int(d.ready.value) == 0, self.fail("ready high for more than one s clock")
        self.pending = False
        self.reads += 1
        self.stats["reads"] += 1
        self.check_errors()
        self.current = ""
        return rdata

    def random_gap(self) -> int:
        r = self.rng.random()
        if r < 0.45:
            return 0
        if r < 0.8:
            return int(self.rng.integers(1, 4))
        if r < 0.95:
            return int(self.rng.integers(4, 12))
        return int(self.rng.integers(12, 41))

    async def traffic(self, n: int) -> None:
        """n reads of random copied addresses with random idle gaps, from a falling edge of s_clk."""
        for i in range(n):
            gap = self.random_gap()
            if gap:
                self.junk_s()
                await Timer(gap * self.ts, unit="ps")
            elif i:
                self.stats["back-to-back"] += 1
            await self.read(int(self.rng.choice(COPY_ADDRS)))
        self.junk_s()

    async def read_all(self) -> dict[int, int]:
        """Every copied word once, back-to-back, in random order."""
        order = [int(a) for a in self.rng.permutation(COPY_ADDRS)]
        got = {a: await self.read(a) for a in order}
        self.junk_s()
        return got

    def summary(self) -> str:
        return f"{self.name}: {dict(sorted(self.stats.items()))}"


FIXED_PAIRS = ((10_000, 10_000, 0, 0), (3_000, 90_000, None, None), (90_000, 3_000, None, None))
"""Equal clocks in phase (every flip on an s edge: the either-case of the bound), s 30 times faster, m 30
times faster (None: a random phase)."""


def fixed_pairs(rng) -> list[tuple[int, int, int, int]]:
    return [(ts, tm, int(rng.integers(0, ts)) if a is None else a, int(rng.integers(0, tm)) if b is None else b)
            for ts, tm, a, b in FIXED_PAIRS]


# ---------------------------------------------------------------------- tests
@cocotb.test()
async def hit_decode(dut):
    """hit = 1 exactly at the byte addresses of golden.regmap.WINDOW_COPY: all 256 addresses, with sel low
    (combinational) and high; a read of each answers ready exactly one clock after it is presented, of any
    other address never."""
    b = Bench(dut, "hit_decode", 1)
    await b.start()
    await b.set_clocks(10_000, 10_000, 0, 2_000)
    await b.reset()
    d = dut
    copy = set(COPY_ADDRS)
    assert len(copy) == len(rm.WINDOW_COPY) and all(a % 4 == 0 for a in copy), COPY_ADDRS
    for addr in range(256):                       # sel low: hit only decodes the address
        d.addr.value = addr
        await Timer(1, unit="ns")
        assert int(d.hit.value) == (addr in copy), b.fail(f"sel low, addr 0x{addr:02X}: hit = {int(d.hit.value)}")
    await FallingEdge(d.s_clk)
    for addr in range(256):
        b.current = f"addr 0x{addr:02X}"
        want = int(addr in copy)
        if want:
            await b.read(addr)
            b.junk_s()
            await FallingEdge(d.s_clk)
            continue
        d.sel.value = 1
        d.addr.value = addr
        for k in range(3):                         # sel held 3 clocks: never a ready
            await FallingEdge(d.s_clk)
            got = (int(d.hit.value), int(d.ready.value))
            assert got == (0, 0), b.fail(f"sel high {k + 1} clocks at a word not copied: (hit, ready) = {got}")
        b.junk_s()
        await FallingEdge(d.s_clk)
    b.check_errors()
    assert b.ready_rises == b.reads == len(copy)


READS_AFTER_RESET_S = 2 * 2 * len(COPY_ADDRS) + 20
"""The source's junk-only delay and first hold after a reset in reads_after_reset: two back-to-back reads of
every word (2 s clocks each) and margin."""


def long_first_window(b: Bench, on: bool) -> None:
    b.first_delay_s = READS_AFTER_RESET_S if on else FIRST_DELAY_S
    b.first_hold_s = READS_AFTER_RESET_S if on else HOLD_MIN_S


async def reads_after_reset(b: Bench) -> None:
    """Right after a reset (long_first_window on): every copied word reads 0, twice, back-to-back, while the
    source changes junk without a toggle; then, once the first window's flip is copied, every word reads that
    window (within its hold)."""
    assert b.epoch == len(b.flips), b.fail("a flip before the first reads after the reset")
    t0 = now()
    got = await b.read_all()
    got2 = await b.read_all()
    assert all(b.src_at(t, a) != 0 for a in COPY_ADDRS for t in (t0, now())), b.fail("the source held zeros")
    assert len(b.flips) == b.epoch, b.fail(f"the source flipped before the reads after the reset ended "
                                           f"(first delay {b.first_delay_s} s clocks too short)")
    bad = {NAME[a]: f"0x{v:08X}" for a, v in {**got, **got2}.items() if v != 0}
    assert not bad, b.fail(f"after reset, before the first toggle: {bad}")
    b.stats["words read 0 after a reset"] += 2 * len(got)
    while len(b.flips) == b.epoch:
        await Timer(b.ts, unit="ps")
    first = b.flips[b.epoch]
    if first.t + SYNC_CLOCKS * b.ts > now():
        await Timer(first.t + SYNC_CLOCKS * b.ts - now(), unit="ps")
    await FallingEdge(b.dut.s_clk)            # every read from here: R - t_f > 3Ts
    got = await b.read_all()
    assert len(b.flips) == b.epoch + 1 or b.flip_t[b.epoch + 1] > now() - b.ts, b.fail("first hold too short")
    assert got == first.words, b.fail("after the first toggle after the reset: "
                                      f"{ {NAME[a]: (hex(got[a]), hex(first.words[a])) for a in got} }")
    b.stats["first windows after a reset read whole"] += 1
    long_first_window(b, False)


def reset_setups(b: Bench) -> list[tuple[int, int, int, int]]:
    """The clock pairs of the reset tests: the fixed ones and two random pairs."""
    return [*fixed_pairs(b.rng_clk), *clock_pairs(b.rng_clk, 4)[-2:]]


async def start_after_reset(b: Bench, k: int, setup: tuple[int, int, int, int], long_first: bool):
    """Setup ``k`` of the reset tests: its clocks, the first window's timing (``long_first_window``), a reset,
    then the source running (its task)."""
    ts, tm, off_s, off_m = setup
    b.where = f"setup {k}"
    await b.set_clocks(ts, tm, off_s, off_m)
    long_first_window(b, long_first)
    await b.reset()
    return b.run_source()


@cocotb.test()
async def reads_zero_after_reset(dut):
    """After reset every copied word reads 0 until the first toggle, whatever the source's words hold (junk
    changing without a toggle, nonzero): equal clocks in phase, 30:1, 1:30 and two random pairs, from the
    reset at start-up and after traffic."""
    b = Bench(dut, "reads_zero_after_reset", 2)
    await b.start()
    setups = reset_setups(b)
    for k, setup in enumerate(setups):
        task = await start_after_reset(b, k, setup, True)
        await reads_after_reset(b)
        await b.traffic(max(20, b.n_random // 10))
        await b.settle(task)
    cocotb.log.info(b.summary())
    assert b.stats["words read 0 after a reset"] == 2 * len(COPY_ADDRS) * len(setups)
    assert b.stats["first windows after a reset read whole"] == len(setups)


@cocotb.test()
async def random_clock_ratios(dut):
    """Windows from the source against back-to-back reads with random gaps on equal clocks in phase, 30:1, 1:30
    and HFI_WINCOPY_PAIRS random pairs (3..97 ns, ratios 1:30..30:1, random phases), HFI_RANDOM_N reads each;
    a reset before every other pair. Every read exact (module docstring)."""
    b = Bench(dut, "random_clock_ratios", 3)
    await b.start()
    pairs = [*fixed_pairs(b.rng_clk), *clock_pairs(b.rng_clk, b.n_pairs)]
    for k, (ts, tm, off_s, off_m) in enumerate(pairs):
        b.where = f"pair {k}"
        await b.set_clocks(ts, tm, off_s, off_m)
        cocotb.log.info(f"pair {k}: Ts={ts} ps Tm={tm} ps (Ts/Tm={ts / tm:.3f}), first edges "
                        f"s@{b.phase[0]} m@{b.phase[1]} ps")
        long_first_window(b, False)
        if k % 2 == 0:
            await b.reset()
        else:
            await FallingEdge(dut.s_clk)
        task = b.run_source()
        await b.traffic(b.n_random)
        await b.settle(task)
    cocotb.log.info(b.summary())
    ratios = [ts / tm for ts, tm, _, _ in pairs]
    cocotb.log.info(f"Ts/Tm from {min(ratios):.4f} to {max(ratios):.2f}")
    s = b.stats
    assert b.reads == len(pairs) * b.n_random
    assert min(ratios) < 1 / 20 and max(ratios) > 20, ratios
    assert s["back-to-back"] > 0 and s["windows"] > len(pairs)
    if b.n_random >= 200:      # the reads that tell the bound from a copy a clock early or late
        for kind in ("flip in flight, Ts <= R - t_f < 2Ts", "flip in flight, 2Ts <= R - t_f < 3Ts",
                     "new, 3Ts < R - t_f <= 4Ts", "R - t_f = 3Ts (either)", "source held junk at R",
                     "source held another value at R"):
            assert s[kind] > 0, f"no read of the kind '{kind}': {dict(s)}"


@cocotb.test()
async def reset_in_the_middle(dut):
    """Resets at random instants while windows and reads run (the copy holding a window, a flip possibly in
    flight): every copied word reads 0 after each, until the first toggle after it; then windows again.
    Three resets on each of equal clocks in phase, 30:1, 1:30 and two random pairs."""
    b = Bench(dut, "reset_in_the_middle", 4)
    await b.start()
    setups = reset_setups(b)
    n = max(20, b.n_random // 10)
    for k, setup in enumerate(setups):
        ts = setup[0]
        task = await start_after_reset(b, k, setup, False)
        await b.traffic(n)
        for _ in range(3):
            before = b.stats["reads"]
            # the copy holds a window (nonzero words) when the reset comes
            while len(b.flips) <= b.epoch:
                await b.traffic(1)
            long_first_window(b, True)        # for the source's restart after the reset
            await Timer(int(b.rng.integers(0, 30 * ts)), unit="ps")   # anywhere in the window
            await b.reset()
            await reads_after_reset(b)
            await b.traffic(n)
            assert b.stats["reads"] > before
        await b.settle(task)
    cocotb.log.info(b.summary())
    assert b.stats["words read 0 after a reset"] == 2 * len(COPY_ADDRS) * 3 * len(setups)
    assert b.stats["resets"] == 4 * len(setups)
