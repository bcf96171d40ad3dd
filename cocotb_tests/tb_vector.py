"""cocotb testbench of rtl/hfi_vector.v against golden/firmware/vector.py (run by test_vector.py, not by pytest).

Reference: ``golden.firmware.vector.vector_angle(x, y)`` (docs/spec.md 5.3) of the inputs saturated to
``[-INPUT_LIMIT, INPUT_LIMIT]`` (2^28, the golden precondition; the RTL saturates, see its header).
Every result (``angle`` u32, ``mag`` s32) is compared exactly. As a check of the reference itself (so
that the bench cannot agree with a golden called the wrong way), the directed vectors of magnitude
>= 2^20 also compare the golden result with ``math.atan2`` / ``math.hypot`` within loose bounds.

Environment (set by test_vector.py through hdl_runner.run_cocotb): ``HFI_SEED`` (numpy generator seed),
``HFI_RANDOM_N`` (number of random (x, y) pairs of the ``random_pairs`` test).

Timing of the bench: inputs are written and outputs read 1 ns after each falling clock edge ("sample
point" of a cycle), never at an edge, so the C clock (``impl="gpi"``) and plain ``Timer`` waits are
race-free and the simulator runs the cycles between two checks without Python. A start written at the
sample point of cycle ``t`` is taken by the rising edge that ends cycle ``t``; ``busy`` must be 1 at the
sample points of ``t + 1 .. t + 17``, ``done`` 1 at ``t + LATENCY`` (18) only. The streams check that
with :class:`pulse_monitor.HighMonitor` on ``done`` and on ``busy`` (value changes, no per-cycle Python):
the sets of cycles in which each is high must be exactly the expected ones (no spurious, lost, early,
late or stretched pulses). :meth:`Bench.one_checked` checks every cycle at its sample point instead.
"""

from __future__ import annotations

import math

import cocotb
import numpy as np
from cocotb.utils import get_sim_time

from golden.firmware.vector import INPUT_LIMIT, vector_angle
from pulse_monitor import HighMonitor
from unit_bench import UnitBench

PERIOD_NS = 10
LATENCY = 18            # rtl/hfi_vector.v localparam LATENCY = ITERATIONS + 2: start cycle -> done cycle
LIMIT = INPUT_LIMIT     # 2^28
INT32_MIN, INT32_MAX = -(1 << 31), (1 << 31) - 1
MASK32 = (1 << 32) - 1
SPECIAL = (0, 1, -1, 2, -2, LIMIT, -LIMIT, LIMIT - 1, -LIMIT + 1, LIMIT + 1, -LIMIT - 1,
           1 << 30, -(1 << 30), INT32_MIN, INT32_MAX, INT32_MIN + 1)
"""Component values of the random mix's "special" kind: zero, +-1, the limit and its neighbours, far beyond."""


# ---- reference --------------------------------------------------------------------------------------
def sat28(v: int) -> int:
    """Saturate to [-INPUT_LIMIT, INPUT_LIMIT] (what the RTL does to x and y before the CORDIC)."""
    return LIMIT if v > LIMIT else -LIMIT if v < -LIMIT else v


def golden(x: int, y: int) -> tuple[int, int]:
    """(angle, mag) of the golden model for s32 inputs x, y (saturated to its precondition first)."""
    return vector_angle(sat28(x), sat28(y))


def check_golden_plausible(x: int, y: int, want: tuple[int, int]) -> None:
    """The golden result against floating point for vectors of magnitude >= 2^20 (after saturation):
    angle within 2^16 binary-angle units (0.0055 deg; observed <= 23 000), magnitude within 1e-4
    (observed < 4e-6). Guards the bench, not the RTL."""
    xs, ys = sat28(x), sat28(y)
    r = math.hypot(xs, ys)
    if r < (1 << 20):
        return
    ref = math.atan2(ys, xs) / (2 * math.pi) * 2 ** 32
    d = (want[0] - ref + 2 ** 31) % 2 ** 32 - 2 ** 31
    assert abs(d) < (1 << 16), f"golden angle of ({x}, {y}) = {want[0]}, atan2 {ref:.0f}: reference misused?"
    assert abs(want[1] / r - 1) < 1e-4, f"golden mag of ({x}, {y}) = {want[1]}, hypot {r:.0f}: reference misused?"


def directed_pairs() -> list[tuple[int, int]]:
    """Corners: zero, the axes, the +-2^28 diagonals, the fold (x < 0, y = 0), unit vectors around the
    origin, near-axis vectors on both sides of the fold, and inputs beyond the limit."""
    L = LIMIT
    out = [(0, 0), (L, 0), (-L, 0), (0, L), (0, -L)]
    out += [(sx * L, sy * L) for sx in (1, -1) for sy in (1, -1)]
    out += [(-12345, 0), (-(L - 1), 0), (-1, 0), (-1, -1), (1, -1), (1, 1), (-1, 1), (1, 0), (0, 1), (0, -1),
            (-2, 0), (-2, 1), (-2, -1)]
    out += [(L, 1), (L, -1), (-L, 1), (-L, -1), (1, L), (-1, L), (1, -L), (-1, -L),
            (L - 1, -(L - 1)), (-(L - 1), L - 1), (12345, -54321), (-54321, -12345)]
    beyond = [INT32_MIN, INT32_MAX, INT32_MIN + 1, L + 1, -(L + 1), 1 << 30, -(1 << 30)]
    out += [(v, 0) for v in beyond] + [(0, v) for v in beyond]
    out += [(a, b) for a in (INT32_MIN, INT32_MAX) for b in (INT32_MIN, INT32_MAX)]
    out += [(sx * (L + 1), sy * (L + 1)) for sx in (1, -1) for sy in (1, -1)]
    out += [(sx << 30, sy << 30) for sx in (1, -1) for sy in (1, -1)]
    out += [(L + 1, 5), (-(L + 1), -7), (INT32_MIN, 1), (INT32_MIN, -1), (INT32_MAX, -3), (3, INT32_MIN),
            (-(1 << 30), 1000), (1000, 1 << 30), (L + 1, L), (-L, -(L + 1))]
    return list(dict.fromkeys(out))


def random_components(rng: np.random.Generator, n: int) -> list[int]:
    """``n`` s32 values, a mix: 40 % uniform in [-2^28, 2^28], 30 % small (uniform in [-2^k, 2^k], k
    uniform in 0..27, a fifth of them exactly +-2^k), 20 % uniform over all of s32 (mostly beyond the
    limit), 10 % special values (:data:`SPECIAL`)."""
    kind = rng.choice(4, size=n, p=[0.4, 0.3, 0.2, 0.1])
    uni = rng.integers(-LIMIT, LIMIT + 1, size=n, dtype=np.int64)
    k = rng.integers(0, 28, size=n)
    small = np.floor(rng.uniform(-1.0, 1.0, size=n) * (2.0 ** k + 1)).astype(np.int64)
    small = np.clip(small, -(1 << k), 1 << k)
    pow2 = rng.random(n) < 0.2
    small[pow2] = np.where(rng.random(int(pow2.sum())) < 0.5, 1, -1) << k[pow2]
    full = rng.integers(INT32_MIN, INT32_MAX + 1, size=n, dtype=np.int64)
    special = np.asarray(SPECIAL, dtype=np.int64)[rng.integers(0, len(SPECIAL), size=n)]
    return np.choose(kind, [uni, small, full, special]).tolist()


# ---- bench -------------------------------------------------------------------------------------------
class Bench(UnitBench):
    """Clock, reset and the start/done protocol of hfi_vector."""

    def __init__(self, dut):
        super().__init__(dut, PERIOD_NS, info=f"LATENCY={LATENCY}")

    def drive(self, start: int, x: int, y: int) -> None:
        self.dut.start.value = start
        self.dut.x.value = x & MASK32
        self.dut.y.value = y & MASK32

    async def setup(self) -> None:
        dut = self.dut
        assert len(dut.x) == 32 and len(dut.y) == 32 and len(dut.angle) == 32 and len(dut.mag) == 32
        await self.power_up(lambda: self.drive(0, 0, 0))
        self.expect_outputs((0, 0), "after reset (reset value of angle, mag)")

    # ---- observations --------------------------------------------------------------------------------
    def outputs(self) -> tuple[int, int]:
        return self.dut.angle.value.to_unsigned(), self.dut.mag.value.to_signed()

    def expect_outputs(self, want: tuple[int, int], what: str) -> None:
        got = self.outputs()
        assert got == want, f"cycle {self.cycle}, {what}: (angle, mag) = RTL {got}, expected {want}"

    # ---- one computation with a full cycle-by-cycle protocol check -----------------------------------
    async def one_checked(self, x: int, y: int, label: str) -> tuple[int, int]:
        """Start (x, y) now (start was low, the unit idle), check busy/done/held outputs in every cycle
        (other x, y driven from the cycle after the start); returns at the cycle after done with the
        result."""
        prev = self.outputs()
        self.expect_idle(f"{label}: start cycle")
        self.drive(1, x, y)
        await self.cycles(1)
        self.drive(0, ~x, y ^ 0x5A5A5A5A)  # x, y are sampled in the start cycle only
        for k in range(1, LATENCY):
            self.expect_flags(1, 0, f"{label}: {k} cycles after start")
            self.expect_outputs(prev, f"{label}: outputs held while busy, {k} cycles after start")
            await self.cycles(1)
        self.expect_flags(0, 1, f"{label}: done cycle = start + LATENCY ({LATENCY})")
        result = self.outputs()
        await self.cycles(1)
        self.expect_idle(f"{label}: cycle after done (done is a one-cycle pulse)")
        self.expect_outputs(result, f"{label}: outputs held after done")
        return result

    # ---- a stream of computations, timing checked by monitors ----------------------------------------
    async def stream(self, pairs, label: str, gaps=None, hold=None, garbage=None) -> None:
        """Run every (x, y) of ``pairs``, compare each result with :func:`golden`.

        Vector k starts at cycle s_k; s_{k+1} = s_k + LATENCY + gaps[k] (gap 0: the start is in the done
        cycle of vector k). In the cycle after each start, x, y change to garbage[k] and start stays
        high if hold[k] (a start while busy: ignored) and drops to 0 in the done cycle if a gap follows.
        Defaults: random gaps (mostly 0), hold half of the time, random s32 garbage. Checks each result in
        its done cycle, the previous result held in the cycle after the start, and (monitors) that done
        is high exactly in the cycles s_k + LATENCY and busy exactly in s_k + 1 .. s_k + LATENCY - 1.
        """
        n = len(pairs)
        rng = self.rng
        if gaps is None:
            gaps = rng.choice(np.array([0, 0, 0, 0, 0, 0, 1, 2, 5]), size=n).tolist()
        if hold is None:
            hold = (rng.random(n) < 0.5).tolist()
        if garbage is None:
            garbage = rng.integers(INT32_MIN, INT32_MAX + 1, size=(n, 2), dtype=np.int64).tolist()
        want = [golden(x, y) for x, y in pairs]
        start_h, x_h, y_h, angle_h, mag_h = self.dut.start, self.dut.x, self.dut.y, self.dut.angle, self.dut.mag
        t0 = get_sim_time(unit="ns")
        c0 = self.cycle
        mon_done = HighMonitor(self.dut, t0, "done")
        mon_busy = HighMonitor(self.dut, t0, "busy")
        exp_done: set[int] = set()
        exp_busy: set[int] = set()
        prev = self.outputs()
        s = 0  # start cycle of the vector, relative to c0
        self.drive(1, *pairs[0])
        for k in range(n):
            exp_busy.update(range(s + 1, s + LATENCY))
            exp_done.add(s + LATENCY)
            await self.cycles(1)
            got = (angle_h.value.to_unsigned(), mag_h.value.to_signed())
            if got != prev:
                assert False, (f"{label} vector {k} {pairs[k]}: outputs changed before done, cycle after "
                               f"the start: {got}, previous result {prev}")
            gx, gy = garbage[k]
            start_h.value = int(hold[k])
            x_h.value = gx & MASK32
            y_h.value = gy & MASK32
            await self.cycles(LATENCY - 1)
            got = (angle_h.value.to_unsigned(), mag_h.value.to_signed())
            if got != want[k]:
                x, y = pairs[k]
                assert False, (f"{label} vector {k}: (x, y) = ({x}, {y}) (saturated ({sat28(x)}, {sat28(y)})): "
                               f"(angle, mag) RTL {got}, golden {want[k]} (HFI_SEED={self.seed})")
            prev = got
            s += LATENCY
            if k + 1 < n:
                if gaps[k]:
                    start_h.value = 0
                    await self.cycles(gaps[k])
                    s += gaps[k]
                x, y = pairs[k + 1]
                start_h.value = 1
                x_h.value = x & MASK32
                y_h.value = y & MASK32
        start_h.value = 0
        await self.cycles(LATENCY + 2)
        high_done, high_busy = mon_done.stop(), mon_busy.stop()
        assert high_done == exp_done, (
            f"{label}: done high in unexpected cycles {sorted(high_done - exp_done)[:10]}, missing in "
            f"{sorted(exp_done - high_done)[:10]} (cycles from the stream start, cycle {c0})")
        assert high_busy == exp_busy, (
            f"{label}: busy high in unexpected cycles {sorted(high_busy - exp_busy)[:10]}, missing in "
            f"{sorted(exp_busy - high_busy)[:10]} (cycles from the stream start, cycle {c0})")
        self.expect_idle(f"{label}: after the last vector")
        self.expect_outputs(want[-1], f"{label}: last result held")


# ---- tests --------------------------------------------------------------------------------------------
@cocotb.test()
async def directed(dut):
    """Directed corners (zero, axes, +-2^28 diagonals, the fold, unit vectors, beyond the limit), each
    with a cycle-by-cycle protocol check, then all again as a random-protocol stream."""
    tb = Bench(dut)
    await tb.setup()
    pairs = directed_pairs()
    for x, y in pairs:
        want = golden(x, y)
        check_golden_plausible(x, y, want)
        got = await tb.one_checked(x, y, f"directed ({x}, {y})")
        assert got == want, (f"directed (x, y) = ({x}, {y}) (saturated ({sat28(x)}, {sat28(y)})): "
                             f"(angle, mag) RTL {got}, golden {want}")
        if (x, y) != (sat28(x), sat28(y)):  # beyond the limit: the RTL gives its own result of the saturated vector
            sat = await tb.one_checked(sat28(x), sat28(y), f"directed ({x}, {y}) saturated")
            assert got == sat, f"(x, y) = ({x}, {y}): RTL {got}, the RTL's saturated vector {sat}"
    assert golden(-LIMIT, 0)[0] != 0 and golden(0, 0)[1] == 0
    await tb.stream(pairs, "directed stream")


@cocotb.test()
async def random_pairs(dut):
    """HFI_RANDOM_N random (x, y): each component from a mix of uniform in +-2^28, small magnitudes
    (+-2^k ranges and exact powers), full-range s32 beyond the limit and special values; random protocol
    (mostly back to back, some gaps, start held with garbage while busy); exact results, done exactly
    LATENCY cycles after each start (monitors)."""
    tb = Bench(dut)
    await tb.setup()
    n = tb.random_n
    xs = random_components(tb.rng, n)
    ys = random_components(tb.rng, n)
    pairs = list(zip(xs, ys))
    n_sat = sum((x, y) != (sat28(x), sat28(y)) for x, y in pairs)
    n_fold = sum(sat28(x) < 0 for x in xs)
    n_small = sum(max(abs(x), abs(y)) < (1 << 16) for x, y in pairs)
    cocotb.log.info(f"{n} random pairs: {n_sat} beyond the limit, {n_fold} folded (x < 0), "
                    f"{n_small} with |x|, |y| < 2^16")
    await tb.stream(pairs, "random")


@cocotb.test()
async def back_to_back(dut):
    """start held high for 12 vectors, x and y changed only in the done cycles (otherwise garbage): each
    new start in the done cycle is accepted, one result per LATENCY clocks, checked cycle by cycle; then a
    start in the cycle after done (one idle cycle) works too."""
    tb = Bench(dut)
    await tb.setup()
    m = 12
    pairs = [tuple(p) for p in tb.rng.integers(-LIMIT, LIMIT + 1, size=(m, 2), dtype=np.int64).tolist()]
    pairs[0] = (-LIMIT, 0)  # the fold, nonzero result
    first = tb.cycle
    tb.expect_idle("before the first start")
    tb.drive(1, *pairs[0])
    for k in range(m):
        await tb.cycles(1)
        for j in range(1, LATENCY):  # start stays 1 with garbage inputs: ignored while busy
            tb.expect_flags(1, 0, f"vector {k}: {j} cycles after the start (start held)")
            tb.drive(1, ~pairs[k][0], pairs[k][1] ^ 0x13579BDF)
            if j < LATENCY - 1:
                await tb.cycles(1)
        await tb.cycles(1)
        tb.expect_flags(0, 1, f"vector {k}: done cycle = start + LATENCY")
        tb.expect_outputs(golden(*pairs[k]), f"vector {k} {pairs[k]}")
        if k + 1 < m:
            tb.drive(1, *pairs[k + 1])  # the next start in the done cycle
        else:
            tb.drive(0, 0, 0)
    assert tb.cycle - first == m * LATENCY, f"{m} results took {tb.cycle - first} cycles, not {m * LATENCY}"
    await tb.cycles(1)
    tb.expect_idle("after the last back-to-back vector")
    tb.expect_outputs(golden(*pairs[-1]), "last back-to-back result held")
    for j in range(LATENCY + 2):  # the start dropped in the last done cycle: nothing more runs
        await tb.cycles(1)
        tb.expect_idle(f"{j + 2} cycles after the last done")
    # a start one cycle after done (idle in between), each checked per cycle
    a, b = golden(LIMIT, -LIMIT), golden(-5, 7)
    got = await tb.one_checked(LIMIT, -LIMIT, "start after idle")
    assert got == a, f"(2^28, -2^28): RTL {got}, golden {a}"
    got = await tb.one_checked(-5, 7, "start in the cycle after done")
    assert got == b, f"(-5, 7): RTL {got}, golden {b}"
    # the same back-to-back stream with the monitors (garbage while busy, start held)
    await tb.stream(pairs, "back-to-back stream", gaps=[0] * m, hold=[True] * m)


@cocotb.test()
async def start_while_busy(dut):
    """A start while busy is ignored: held high with other inputs in every busy cycle, or a single pulse
    in one random busy cycle: one done at start + LATENCY with the first inputs' result, no extra done."""
    tb = Bench(dut)
    await tb.setup()
    for trial in range(6):
        x, y = tb.rng.integers(-LIMIT, LIMIT + 1, size=2, dtype=np.int64).tolist()
        others = tb.rng.integers(INT32_MIN, INT32_MAX + 1, size=(LATENCY, 2), dtype=np.int64).tolist()
        pulse_at = int(tb.rng.integers(1, LATENCY)) if trial % 2 else None  # None: held in every cycle
        want = golden(x, y)
        tb.drive(1, x, y)
        await tb.cycles(1)
        for k in range(1, LATENCY):
            tb.expect_flags(1, 0, f"trial {trial}: {k} cycles after the start")
            start = 1 if pulse_at is None or pulse_at == k else 0
            tb.drive(start, *others[k])
            await tb.cycles(1)
        tb.drive(0, 0, 0)
        tb.expect_flags(0, 1, f"trial {trial}: done cycle")
        tb.expect_outputs(want, f"trial {trial}: (x, y) = ({x}, {y}), start while busy "
                                f"{'held' if pulse_at is None else f'pulsed {pulse_at} cycles after the start'}")
        for j in range(LATENCY + 2):
            await tb.cycles(1)
            tb.expect_idle(f"trial {trial}: {j + 1} cycles after done (ignored starts must not run)")
            tb.expect_outputs(want, f"trial {trial}: outputs held")


@cocotb.test()
async def reset_mid_operation(dut):
    """A reset k cycles after the start (k = 0: in the start cycle, .. k = LATENCY - 1: the cycle before
    done) aborts the computation: busy and done drop, no done follows, angle = mag = 0; the next start
    works. Also a start during reset is ignored."""
    tb = Bench(dut)
    await tb.setup()
    vecs = [tuple(p) for p in tb.rng.integers(-LIMIT, LIMIT + 1, size=(LATENCY, 2), dtype=np.int64).tolist()]
    for k in range(LATENCY):
        got = await tb.one_checked(LIMIT, LIMIT, f"reset k={k}: before")  # a nonzero previous result
        assert got == golden(LIMIT, LIMIT) and got[1] != 0
        x, y = vecs[k]
        await tb.start_then_reset(k, lambda: tb.drive(1, x, y), lambda: tb.drive(0, 0, 0),
                                  f"reset {k} cycles after the start")
        tb.expect_outputs((0, 0), f"reset {k} cycles after the start: reset outputs")
        for j in range(LATENCY + 2):
            await tb.cycles(1)
            tb.expect_idle(f"reset {k} cycles after the start: {j + 1} cycles after the reset "
                           "(the aborted computation must not finish)")
            tb.expect_outputs((0, 0), f"reset {k} cycles after the start: outputs stay 0")
        want = golden(x, y)
        got = await tb.one_checked(x, y, f"after reset k={k}")
        assert got == want, f"after reset k={k}: ({x}, {y}): RTL {got}, golden {want}"
    # a start held during a multi-cycle reset is ignored; one after the release works
    tb.dut.rst.value = 1
    tb.drive(1, LIMIT, LIMIT)
    await tb.cycles(3)
    tb.dut.rst.value = 0
    tb.drive(0, 0, 0)
    for j in range(LATENCY + 2):
        tb.expect_idle(f"{j} cycles after a start during reset")
        tb.expect_outputs((0, 0), "after a start during reset")
        await tb.cycles(1)
    await tb.stream(vecs[:3], "after reset stream")
