"""cocotb testbench of rtl/hfi_flux_lut.v against golden/firmware/flux_lut.py ``lut_point`` (run by
test_flux_lut.py, not by pytest), through the wrapper cocotb_tests/hdl/tb_flux_lut_ram.v: the unit reads
its tables from hfi_ram's port b, wired as in hfi_soc.

Environment (set by test_flux_lut.py through hdl_runner.run_cocotb): ``HFI_SEED``, ``HFI_RANDOM_N``.

Tables: (a) the real motor map of scenarios/varatharajan2020_torquestep.toml, built as the firmware's
configuration does (golden.control_config.hfo_proj_params -> golden.flux_tables.flux_lut); (b) random
tables with random n_d, n_q (2..64, n_d n_q <= 1024), shift 0..12, knee 0..2^18+1, coarse 0..4,
f_shift 0..16, flux tables s16, inductance tables |t| < 2^28 (one set also with full-range s32 inductance
tables, which the RTL claims exact too). Every load places the five tables in the RAM at new random byte
bases (``layout``: random order, int16 tables at bases 0 or 2 mod 4, int32 at multiples of 4, each table
adjacent to the one before it or after a random gap, the block at RAM address 0, at the top of the RAM or
anywhere between; the words of the block not holding table entries, including the other halves of
words shared with int16 entries, are random junk) and writes the block word by word through the RAM's
write port.

RAM port checks: mem_en must never be high while busy is low (the wrapper's sticky ``bad_en``, checked
after every stream and at the end of each test; cycle by cycle in ``one_checked``, where mem_en must be
high exactly in cycles 7..26 after the start); every completed look-up makes exactly 20 reads (the
wrapper's ``reads`` counter); the wrapper feeds the unit junk on mem_rdata except in the cycle after a
read.

Golden values are compared modulo 2^64 (the outputs are s64; golden's Python integers are unbounded:
only the flux far beyond the grid with shift < 3 leaves int64).

Timing of the bench: inputs are written and outputs read 1 ns after each falling clock edge (sample
point), never at an edge; a start written at the sample point of cycle t is taken by the rising edge that
ends cycle t; ``done`` must be 1 at the sample point of cycle t + LATENCY, busy 1 from t + 1 to
t + LATENCY - 1. Per look-up the bench awaits one or two Timers (no per-clock Python), so 100 000 look-ups
run in seconds under Verilator.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import cocotb
import numpy as np
from cocotb.triggers import Timer

from golden.firmware.flux_lut import LUT_MAX_AXIS, LUT_MAX_POINTS, FluxLut, lut_flux, lut_point, unwarp, warp
from unit_bench import UnitBench

PERIOD_NS = 10
LATENCY = 59            # rtl/hfi_flux_lut.v localparam LATENCY
N_READS = 20            # RAM reads per look-up (4 corners x 5 tables)
READ_CYCLES = range(7, 27)  # cycles after the start cycle with mem_en high
I_MAX = 1 << 18         # |i_d|, |i_q| range of the block (control.h)
L_MAX = 1 << 28         # |t_l*| range of the inductance tables (control.h)
OUTPUTS = ("lam_d", "lam_q", "l_d", "l_q", "l_dq", "dl_d", "dl_q", "dl_dq")
BASES = ("base_d", "base_q", "base_ld", "base_lq", "base_ldq")
SCENARIO = Path(__file__).resolve().parents[1] / "scenarios" / "varatharajan2020_torquestep.toml"


def wrap64(v: int) -> int:
    return ((v + (1 << 63)) & ((1 << 64) - 1)) - (1 << 63)


def golden(lut: FluxLut, i_d: int, i_q: int) -> tuple[int, ...]:
    p = lut_point(lut, i_d, i_q)
    return tuple(wrap64(getattr(p, f)) for f in OUTPUTS)


@lru_cache(maxsize=1)
def real_lut() -> FluxLut:
    """The firmware's table of the 003 scenario (as golden.control_config builds it)."""
    from golden.control_config import hfo_proj_params
    from golden.scenario import load_scenario

    return hfo_proj_params(load_scenario(SCENARIO)).lut


def random_lut(rng: np.random.Generator, n_d: int | None = None, n_q: int | None = None, shift: int | None = None,
               knee: int | None = None, coarse: int | None = None, f_shift: int | None = None,
               l_max: int = L_MAX, extreme: bool = False) -> FluxLut:
    """A random table within the block's ranges (``extreme``: values only at the ends of their range)."""
    if n_d is None:
        n_d = int(rng.integers(2, LUT_MAX_AXIS + 1))
    if n_q is None:
        n_q = int(rng.integers(2, min(LUT_MAX_AXIS, LUT_MAX_POINTS // n_d) + 1))
    assert 2 <= n_d <= LUT_MAX_AXIS and 2 <= n_q <= LUT_MAX_AXIS and n_d * n_q <= LUT_MAX_POINTS
    shift = int(rng.integers(0, 13)) if shift is None else shift
    coarse = int(rng.integers(0, 5)) if coarse is None else coarse
    f_shift = int(rng.integers(0, 17)) if f_shift is None else f_shift
    if knee is None:
        kind = int(rng.integers(0, 4))
        if kind == 0:
            knee = 0
        elif kind == 1:   # a grid point (the project's tables)
            knee = int(rng.integers(0, max(n_d, n_q))) << shift
        elif kind == 2:
            knee = int(rng.integers(0, I_MAX + 2))
        else:
            knee = int(rng.integers(0, 4 << shift))
    n = n_d * n_q

    def tab(lo: int, hi: int) -> tuple[int, ...]:
        if extreme:
            return tuple(int(v) for v in rng.choice(np.array([lo, hi, lo + 1, hi - 1, 0], dtype=np.int64), size=n))
        return tuple(int(v) for v in rng.integers(lo, hi + 1, size=n, dtype=np.int64))

    t_d, t_q = tab(-32768, 32767), tab(-32768, 32767)
    t_ld, t_lq, t_ldq = (tab(-(l_max - 1), l_max - 1) for _ in range(3))
    return FluxLut(n_d, n_q, shift, knee, coarse, f_shift, 0, t_d, t_q, t_ld, t_lq, t_ldq)


def layout(rng: np.random.Generator, n: int, ram_bytes: int) -> tuple[int, ...]:
    """Random byte bases of (t_d, t_q, t_ld, t_lq, t_ldq) for ``n`` entries each in a RAM of ``ram_bytes``:
    a random order; int16 tables at even bases (0 or 2 mod 4), int32 at multiples of 4; each table directly
    after the previous one (half of the cases; the next 4-aligned address for an int32 table) or after a
    random gap; the block at address 0, ending at the top of the RAM, or at a random place."""
    sizes = (2 * n, 2 * n, 4 * n, 4 * n, 4 * n)
    rel = [0] * 5
    p = int(rng.integers(0, 2)) * 2          # the block starts at 0 or 2 mod 4
    for j in rng.permutation(5).tolist():
        if rng.random() >= 0.5:
            p += 2 * int(rng.integers(1, 40)) if rng.random() < 0.8 else 2 * int(rng.integers(1, 2000))
        if j >= 2:
            p = (p + 3) & ~3
        rel[j] = p
        p += sizes[j]
    span = (p + 3) & ~3
    assert span <= ram_bytes
    kind = int(rng.integers(0, 4))
    if kind == 0:
        start = 0
    elif kind == 1:
        start = ram_bytes - span
    else:
        start = int(rng.integers(0, (ram_bytes - span) // 4 + 1)) * 4
    return tuple(start + r for r in rel)


def describe(lut: FluxLut) -> str:
    return (f"n_d={lut.n_d} n_q={lut.n_q} shift={lut.shift} knee={lut.knee} coarse={lut.coarse} "
            f"f_shift={lut.f_shift}")


def currents(rng: np.random.Generator, lut: FluxLut, n: int) -> list[tuple[int, int]]:
    """``n`` (i_d, i_q) pairs in |i| <= 2^18: uniform, inside the grid, at and next to grid points, at the
    knee, small, and the range ends; random signs (all four quadrants)."""
    s = lut.shift
    span_d = unwarp((lut.n_d - 1) << s, lut.knee, lut.coarse)
    span_q = unwarp((lut.n_q - 1) << s, lut.knee, lut.coarse)

    def axis(count: int, span: int, n_axis: int) -> np.ndarray:
        kind = rng.integers(0, 7, size=count)
        v = rng.integers(0, I_MAX + 1, size=count, dtype=np.int64)                     # uniform
        inside = rng.integers(0, min(I_MAX, span + span // 4 + 2) + 1, size=count, dtype=np.int64)
        v = np.where(kind == 1, inside, v)
        gp = np.array([unwarp(c << s, lut.knee, lut.coarse) for c in range(n_axis)], dtype=np.int64)
        grid = gp[rng.integers(0, n_axis, size=count)] + rng.integers(-1, 2, size=count)
        v = np.where(kind == 2, grid, v)
        knee = lut.knee + rng.integers(-2, 3, size=count)
        v = np.where(kind == 3, knee, v)
        small = rng.integers(0, (2 << s) + 1, size=count, dtype=np.int64)
        v = np.where(kind == 4, small, v)
        ends = np.array([0, 1, I_MAX, I_MAX - 1, span, span + 1], dtype=np.int64)[rng.integers(0, 6, size=count)]
        v = np.where(kind == 5, ends, v)
        v = np.clip(v, 0, I_MAX)
        sign = np.where(rng.random(count) < 0.5, -1, 1)
        return v * sign

    i_d = axis(n, span_d, lut.n_d)
    i_q = axis(n, span_q, lut.n_q)
    return list(zip(i_d.tolist(), i_q.tolist()))


class Bench(UnitBench):
    """Clock, reset, table loading and the start/done protocol of hfi_flux_lut."""

    def __init__(self, dut):
        super().__init__(dut, PERIOD_NS, info=f"LATENCY={LATENCY}")
        self.lut: FluxLut | None = None
        self.ram_aw = len(dut.ram_addr)
        self.ram_bytes = 4 << self.ram_aw
        self.bases: tuple[int, ...] = ()
        self.outs = [getattr(dut, f) for f in OUTPUTS]

    async def setup(self) -> None:
        dut = self.dut
        assert all(len(o) == 64 for o in self.outs)

        def idle():
            dut.start.value = 0
            dut.i_d.value = 0
            dut.i_q.value = 0
            dut.ram_wstrb.value = 0
            dut.ram_addr.value = 0
            dut.ram_wdata.value = 0
            for name in BASES:
                getattr(dut, name).value = 0
            for name in ("n_d", "n_q", "shift", "knee", "coarse", "f_shift"):
                getattr(dut, name).value = 2 if name in ("n_d", "n_q") else 0

        await self.power_up(idle)
        self.expect_outputs((0,) * 8, "after reset")

    async def load(self, lut: FluxLut) -> None:
        """Place the five tables at a new random ``layout`` in the RAM: write the words of the block (junk
        where no entry is) through the RAM's write port, one word per cycle; set the bases and the
        configuration."""
        dut = self.dut
        rng = self.rng
        tabs = (lut.t_d, lut.t_q, lut.t_ld, lut.t_lq, lut.t_ldq)
        n = lut.n_d * lut.n_q
        bases = layout(rng, n, self.ram_bytes)
        lo = min(bases) & ~3
        hi = max(b + (2 if j < 2 else 4) * n for j, b in enumerate(bases))
        words = rng.integers(0, 1 << 32, size=(hi - lo + 3) // 4, dtype=np.int64).tolist()
        owner = {}                           # byte address of an entry -> table (overlap check)
        for j, (t, b) in enumerate(zip(tabs, bases)):
            size = 2 if j < 2 else 4
            assert b % size == 0
            for i, v in enumerate(t):
                a = b + size * i
                assert a not in owner and a + size <= self.ram_bytes
                owner[a] = j
                w = (a - lo) >> 2
                if size == 4:
                    words[w] = v & 0xFFFFFFFF
                elif a & 2:
                    words[w] = (words[w] & 0x0000FFFF) | ((v & 0xFFFF) << 16)
                else:
                    words[w] = (words[w] & 0xFFFF0000) | (v & 0xFFFF)
        dut.ram_wstrb.value = 0xF
        for w, v in enumerate(words):
            dut.ram_addr.value = (lo >> 2) + w
            dut.ram_wdata.value = v
            await self.cycles(1)
        dut.ram_wstrb.value = 0
        dut.ram_addr.value = int(rng.integers(0, 1 << self.ram_aw))
        for name, b in zip(BASES, bases):
            getattr(dut, name).value = b
        self.bases = bases
        dut.n_d.value = lut.n_d
        dut.n_q.value = lut.n_q
        dut.shift.value = lut.shift
        dut.knee.value = lut.knee
        dut.coarse.value = lut.coarse
        dut.f_shift.value = lut.f_shift
        self.lut = lut
        await self.cycles(1)
        cocotb.log.info(f"loaded {describe(lut)} at byte bases {bases} ({len(words)} words)")

    # ---- observations --------------------------------------------------------------------------------
    def outputs(self) -> tuple[int, ...]:
        return tuple(o.value.to_signed() for o in self.outs)

    def expect_idle(self, what: str) -> None:
        super().expect_idle(what)
        assert int(self.dut.mem_en.value) == 0, f"cycle {self.cycle}, {what}: mem_en high while idle"

    def reads(self) -> int:
        return int(self.dut.reads.value)

    def expect_no_bad_en(self, what: str) -> None:
        assert int(self.dut.bad_en.value) == 0, f"{what}: mem_en was high in a cycle with busy low"

    def expect_outputs(self, want, what: str) -> None:
        got = self.outputs()
        if got != tuple(want):
            diff = {f: (g, w) for f, g, w in zip(OUTPUTS, got, want) if g != w}
            assert False, f"cycle {self.cycle}, {what}: RTL != golden (RTL, golden): {diff}"

    def check(self, i_d: int, i_q: int, label: str) -> None:
        want = golden(self.lut, i_d, i_q)
        self.expect_outputs(want, f"{label}: (i_d, i_q) = ({i_d}, {i_q}), {describe(self.lut)}")
        assert want[:2] == tuple(wrap64(v) for v in lut_flux(self.lut, i_d, i_q))

    # ---- one look-up with a cycle-by-cycle protocol check --------------------------------------------
    async def one_checked(self, i_d: int, i_q: int, label: str) -> tuple[int, ...]:
        dut = self.dut
        prev = self.outputs()
        dut.i_d.value = i_d
        dut.i_q.value = i_q
        dut.start.value = 1
        self.expect_flags(0, 0, f"{label}: start cycle")
        assert int(dut.mem_en.value) == 0, f"{label}: mem_en high in the start cycle"
        reads0 = self.reads()
        await self.cycles(1)
        dut.start.value = 0
        dut.i_d.value = -i_d - 1   # sampled in the start cycle only
        dut.i_q.value = -i_q - 1
        for k in range(1, LATENCY):
            self.expect_flags(1, 0, f"{label}: {k} cycles after start")
            en = int(dut.mem_en.value)
            assert en == (k in READ_CYCLES), f"{label}: mem_en = {en} {k} cycles after start"
            if k in (1, LATENCY - 1):
                self.expect_outputs(prev, f"{label}: outputs held while busy, {k} cycles after start")
            await self.cycles(1)
        self.expect_flags(0, 1, f"{label}: done cycle = start + LATENCY ({LATENCY})")
        assert int(dut.mem_en.value) == 0, f"{label}: mem_en high in the done cycle"
        assert self.reads() - reads0 == N_READS, f"{label}: {self.reads() - reads0} RAM reads, expected {N_READS}"
        self.check(i_d, i_q, label)
        result = self.outputs()
        await self.cycles(1)
        self.expect_idle(f"{label}: cycle after done (one-cycle pulse)")
        self.expect_outputs(result, f"{label}: outputs held after done")
        return result

    # ---- a stream of look-ups -----------------------------------------------------------------------
    async def stream(self, pairs, label: str) -> None:
        """Look up every (i_d, i_q) of ``pairs`` on the loaded table, compare with golden ``lut_point``.

        Per look-up at random: (0) start held high with the same inputs through the look-up (one Timer;
        the next start in the done cycle, back to back), (1) 0..3 idle cycles first, start dropped after
        one cycle with other inputs, busy/done and held outputs checked the cycle before done, (2) start
        held high with other currents while busy (ignored)."""
        dut = self.dut
        lut = self.lut
        n = len(pairs)
        want = [golden(lut, a, b) for a, b in pairs]
        mode = self.rng.choice(np.array([0, 0, 1, 2]), size=n).tolist()
        gaps = self.rng.choice(np.array([0, 0, 1, 3]), size=n).tolist()
        garbage = self.rng.integers(-I_MAX, I_MAX + 1, size=(n, 2), dtype=np.int64).tolist()
        start, i_d_h, i_q_h, busy, done = dut.start, dut.i_d, dut.i_q, dut.busy, dut.done
        outs = self.outs
        prev = self.outputs()
        reads0 = self.reads()
        t_lat, t_lat1, t_lat2, t_one = (Timer(m * PERIOD_NS, unit="ns") for m in (LATENCY, LATENCY - 1,
                                                                                 LATENCY - 2, 1))
        for k in range(n):
            a, b = pairs[k]
            m = mode[k]
            if m == 1 and gaps[k]:
                start.value = 0
                await self.cycles(gaps[k])
                if int(busy.value) or int(done.value):
                    self.expect_idle(f"{label} {k}: idle gap before the start")
            i_d_h.value = a
            i_q_h.value = b
            start.value = 1
            if m == 0:
                await t_lat
            else:
                await t_one
                g = garbage[k]
                i_d_h.value = g[0]
                i_q_h.value = g[1]
                if m == 1:
                    start.value = 0
                    await t_lat2
                    if not int(busy.value) or int(done.value):
                        self.expect_flags(1, 0, f"{label} {k}: the cycle before done")
                    got = tuple(o.value.to_signed() for o in outs)
                    assert got == prev, f"{label} {k}: outputs not held until done: {got}, previous {prev}"
                    await t_one
                else:
                    await t_lat1
            self.cycle += LATENCY
            if int(busy.value) or not int(done.value):
                self.expect_flags(0, 1, f"{label} {k} (i_d, i_q) = ({a}, {b}): done cycle = start + LATENCY")
            got = tuple(o.value.to_signed() for o in outs)
            if got != want[k]:
                diff = {f: (g, w) for f, g, w in zip(OUTPUTS, got, want[k]) if g != w}
                assert False, (f"{label} {k}: (i_d, i_q) = ({a}, {b}), {describe(lut)}: RTL != golden "
                               f"(RTL, golden): {diff}")
            prev = got
        start.value = 0
        await self.cycles(1)
        self.expect_idle(f"{label}: after the last look-up")
        got_reads = (self.reads() - reads0) & 0xFFFFFFFF
        assert got_reads == N_READS * n, f"{label}: {got_reads} RAM reads for {n} look-ups, expected {N_READS * n}"
        self.expect_no_bad_en(label)


def directed_currents(lut: FluxLut) -> list[tuple[int, int]]:
    """Zero, grid points (in all four quadrants), the knee boundary, beyond the grid, the range ends."""
    s, kn, co = lut.shift, lut.knee, lut.coarse
    pts = [(0, 0), (1, 0), (0, 1), (-1, 0), (0, -1), (-1, -1)]
    gd = [unwarp(c << s, kn, co) for c in range(lut.n_d)]
    gq = [unwarp(r << s, kn, co) for r in range(lut.n_q)]
    for c in (0, 1, lut.n_d // 2, lut.n_d - 2, lut.n_d - 1):
        for r in (0, 1, lut.n_q // 2, lut.n_q - 2, lut.n_q - 1):
            for sd, sq in ((1, 1), (-1, 1), (1, -1), (-1, -1)):
                pts.append((sd * min(gd[c], I_MAX), sq * min(gq[r], I_MAX)))
    for dk in (-2, -1, 0, 1, 2, 1 << s, (1 << s) + 1):
        v = min(max(kn + dk, 0), I_MAX)
        pts += [(v, gq[1]), (-v, -gq[1]), (gq[1], v), (-v, v), (v, -v)]
    for f in (1, 2, 4, 16, 64):             # beyond the grid: extrapolated flux, clamped inductances
        vd, vq = min(gd[-1] + f * (1 << s), I_MAX), min(gq[-1] + f * (1 << s), I_MAX)
        pts += [(vd, 0), (0, vq), (vd, vq), (-vd, vq), (vd, -vq), (-vd, -vq)]
    pts += [(I_MAX, I_MAX), (-I_MAX, I_MAX), (I_MAX, -I_MAX), (-I_MAX, -I_MAX), (I_MAX - 1, -(I_MAX - 1))]
    pts += [(gd[1] // 2, -gq[min(2, lut.n_q - 1)] // 3 - 1), (-(gd[-1] - 1), gq[-1] - 1)]
    return [(max(min(a, I_MAX), -I_MAX), max(min(b, I_MAX), -I_MAX)) for a, b in pts]


# ---- tests --------------------------------------------------------------------------------------------
@cocotb.test()
async def directed(dut):
    """The real table: zero, grid points in all quadrants, the knee, beyond the grid (cycle-by-cycle
    protocol check for a few, then all as a stream)."""
    tb = Bench(dut)
    await tb.setup()
    lut = real_lut()
    assert lut.knee > 0 and lut.coarse > 0, "the real table should have a knee"
    await tb.load(lut)
    pts = directed_currents(lut)
    # the directed points do reach beyond the grid and both sides of the knee
    xs = [warp(abs(a), lut.knee, lut.coarse) for a, _ in pts]
    assert max(xs) > (lut.n_d - 1) << lut.shift and min(abs(a) for a, _ in pts) < lut.knee
    for k, (a, b) in enumerate(pts[:12]):
        await tb.one_checked(a, b, f"directed {k}")
    await tb.stream(pts, "directed stream")


@cocotb.test()
async def random_lookups(dut):
    """HFI_RANDOM_N look-ups: half on the real table (at four layouts), half over five random tables (random
    protocol)."""
    tb = Bench(dut)
    await tb.setup()
    n = tb.random_n
    n_real = n - 5 * (n // 10)
    for j in range(4):                      # the real table at four layouts
        await tb.load(real_lut())
        await tb.stream(currents(tb.rng, real_lut(), n_real // 4 + (n_real % 4 if j == 3 else 0)),
                        f"random, real table, layout {j}")
    for j in range(5):
        lut = random_lut(tb.rng)
        await tb.load(lut)
        await tb.stream(currents(tb.rng, lut, n // 10), f"random, table {j}")


@cocotb.test()
async def extreme_tables(dut):
    """Tables at the ends of the ranges: s16 / s32 extremes, shift 0 and 12, coarse 0 and 4, f_shift 0 and
    16, n_d or n_q = 2, 64 x 16, 16 x 64, 32 x 32, knee 0 / 2^18 + 1 / inside the grid."""
    tb = Bench(dut)
    await tb.setup()
    rng = tb.rng
    count = max(200, tb.random_n // 50)
    cases = [dict(n_d=2, n_q=2, shift=0, knee=0, coarse=0, f_shift=16, extreme=True),
             dict(n_d=64, n_q=16, shift=12, knee=1 << 14, coarse=4, f_shift=16, extreme=True),
             dict(n_d=16, n_q=64, shift=0, knee=3, coarse=4, f_shift=0, extreme=True),
             dict(n_d=32, n_q=32, shift=8, knee=(1 << 18) + 1, coarse=4, f_shift=13),
             dict(n_d=2, n_q=64, shift=12, knee=0, coarse=4, f_shift=16, l_max=1 << 31, extreme=True),
             dict(n_d=64, n_q=2, shift=1, knee=100, coarse=3, f_shift=7, l_max=1 << 31)]
    for j, kw in enumerate(cases):
        lut = random_lut(rng, **kw)
        await tb.load(lut)
        pts = directed_currents(lut) + currents(rng, lut, count)
        await tb.one_checked(*pts[-1], f"extreme table {j}")
        await tb.stream(pts, f"extreme table {j}")


@cocotb.test()
async def reset_mid_operation(dut):
    """A reset in every cycle of a look-up (from the start cycle on) aborts it: busy and done drop, no
    done follows, outputs go to 0, mem_en is low from the reset on; the next start works."""
    tb = Bench(dut)
    await tb.setup()
    lut = real_lut()
    await tb.load(lut)
    pts = currents(tb.rng, lut, LATENCY + 1)
    pts[0] = (lut.knee + 5, -(lut.knee // 2))
    await tb.stream(pts[:1], "before reset")
    assert any(tb.outputs()), "outputs zero before the reset test"
    for k in range(LATENCY):
        dut.i_d.value, dut.i_q.value = pts[k + 1]
        dut.start.value = 1
        if k == 0:
            dut.rst.value = 1
        await tb.cycles(1)
        dut.start.value = 0
        if k:
            if k > 1:
                await tb.cycles(k - 1)
            tb.expect_flags(1, 0, f"reset test k={k}: busy before the reset")
            dut.rst.value = 1
            await tb.cycles(1)
        dut.rst.value = 0
        reads0 = tb.reads()
        tb.expect_idle(f"reset {k} cycles after the start: right after the reset")
        tb.expect_outputs((0,) * 8, f"reset {k} cycles after the start: reset outputs")
        await tb.cycles(LATENCY + 2)
        tb.expect_idle(f"reset {k} cycles after the start: the aborted look-up must not finish")
        tb.expect_outputs((0,) * 8, f"reset {k} cycles after the start: outputs stay 0")
        assert tb.reads() == reads0, f"reset {k} cycles after the start: RAM reads after the reset"
        await tb.stream([pts[k + 1]], f"after reset k={k}")
    tb.expect_no_bad_en("reset test")


@cocotb.test()
async def start_while_busy(dut):
    """Starts with other currents in every busy cycle are ignored: one done, the first look-up's result;
    then starts in the done cycle and in the cycle after it."""
    tb = Bench(dut)
    await tb.setup()
    lut = real_lut()
    await tb.load(lut)
    for trial in range(4):
        (a, b), *others = currents(tb.rng, lut, LATENCY)
        dut.i_d.value, dut.i_q.value = a, b
        dut.start.value = 1
        await tb.cycles(1)
        for k in range(1, LATENCY):
            tb.expect_flags(1, 0, f"trial {trial}: {k} cycles after start, start held with other currents")
            dut.i_d.value, dut.i_q.value = others[k - 1]
            await tb.cycles(1)
        dut.start.value = 0
        tb.expect_flags(0, 1, f"trial {trial}: done cycle")
        tb.check(a, b, f"trial {trial}")
        want = tb.outputs()
        for j in range(LATENCY + 2):
            await tb.cycles(1)
            tb.expect_idle(f"trial {trial}: {j + 1} cycles after done (ignored starts must not run)")
        tb.expect_outputs(want, f"trial {trial}: outputs held")
    p, q = currents(tb.rng, lut, 2)
    await tb.one_checked(*p, "start after idle")          # returns one cycle after done
    await tb.one_checked(*q, "start in the cycle after done")
    await tb.stream(currents(tb.rng, lut, 20), "back to back")
    tb.expect_no_bad_en("start while busy")
