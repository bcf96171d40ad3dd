"""cocotb testbench of rtl/hfi_adc_if.v (run by cocotb_tests/test_adc_if.py, not by pytest).

Two top levels (``HFI_ADC_TOP``):

* ``single``: ``hfi_adc_if`` itself (the default parameters);
* ``sweep``: a generated wrapper ``adc_if_sweep`` with one instance per parameter point, ports
  ``p<i>_<port>``, plus spare inputs ``x_*`` for the BFM self-check. All instances run at once,
  each with its own stimulus, reset, BFM and checks (one simulator build for the whole sweep).

``HFI_ADC_POINTS`` lists the parameter points ``bits,conv_ticks,sclk_half;...`` in instance order.

Reference: there is no golden Python model of the interface (it passes the plant's codes through); the
reference is the documented timing of the RTL header, evaluated by :class:`LaneModel`:
``LATENCY = CYCLE = C + 2*B*H + 2``; CONVST high in cycles ``a+1 .. a+C`` of a start accepted in cycle
``a``, CS_N low in ``a+C+1 .. a+LATENCY-1``, SCLK high in the odd half periods of that window,
``done`` in ``a+LATENCY``; a start is accepted iff ``rst = 0`` and no conversion is running
(``busy = 0``); a reset in cycle ``r`` kills everything from cycle ``r+1`` on. The codes are the ones
the BFM (cocotb_tests/adc_bfm.py) converted at the CONVST edge, which also checks the ADC protocol:
three independent codes per conversion (lanes A, B and the dc-link lane C, each with 0 and full scale
among them), so ``code_c`` is checked wherever ``code_a`` and ``code_b`` are, and a swapped or stuck lane
shows.
"""

from __future__ import annotations

import bisect
import os

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.handle import Immediate
from cocotb.triggers import RisingEdge, Timer

from adc_bfm import _LEVEL, AdcBfm, now_steps

PERIOD_NS = 10
TOP = os.environ.get("HFI_ADC_TOP", "single")
POINTS = [tuple(int(v) for v in p.split(",")) for p in os.environ.get("HFI_ADC_POINTS", "12,12,1").split(";")]

CODE_PORTS = ("code_a", "code_b", "code_c")           # the held codes of lanes A, B, C
OUT_PORTS = ("busy", "adc_convst", "adc_cs_n", "adc_sclk", "done", *CODE_PORTS)
START_PORTS = ("busy", *CODE_PORTS)                   # sampled in every start cycle
DONE_PORTS = ("done", "busy", "adc_cs_n", *CODE_PORTS)   # sampled in every done cycle
PORTS = ("rst", "start", "adc_convst", "adc_cs_n", "adc_sclk", "adc_sdo_a", "adc_sdo_b", "adc_sdo_c", "busy",
         "done", *CODE_PORTS)


# ----------------------------------------------------------------------------------------- reference
class LaneModel:
    """Expected outputs of one instance for a given stimulus (start runs and reset intervals)."""

    def __init__(self, bits: int, conv: int, half: int):
        self.bits, self.conv, self.half = bits, conv, half
        self.latency = conv + 2 * bits * half + 2
        self.cycle = self.latency
        self.starts: set[int] = set()       # cycles with start = 1
        self.resets: list[int] = [-1]       # cycles with rst = 1 (sorted; the initial reset ends at -1)
        self.codes: dict[int, tuple[int, int, int]] = {}   # CONVST cycle -> codes (A, B, C) of that conversion
        # results of solve()
        self.accepted: list[int] = []
        self.dones: list[int] = []
        self.done_codes: list[tuple[int, int, int]] = []

    def next_reset(self, c: int) -> int | None:
        """First reset cycle >= c."""
        i = bisect.bisect_left(self.resets, c)
        return self.resets[i] if i < len(self.resets) else None

    def in_reset(self, c: int) -> bool:
        i = bisect.bisect_left(self.resets, c)
        return i < len(self.resets) and self.resets[i] == c

    def busy_at(self, c: int) -> bool:
        """busy in cycle c, from the conversions accepted so far (before c)."""
        i = bisect.bisect_left(self.accepted, c) - 1
        if i < 0:
            return False
        a = self.accepted[i]
        r = self.next_reset(a + 1)
        if r is not None and r < c:
            return False
        return 1 <= c - a <= self.latency - 1

    def solve(self) -> None:
        """Which starts are taken, where done comes, from the stimulus."""
        self.accepted, self.dones, self.done_codes = [], [], []
        for s in sorted(self.starts):
            if self.in_reset(s) or self.busy_at(s):
                continue
            self.accepted.append(s)
            r = self.next_reset(s + 1)
            d = s + self.latency
            if r is None or r >= d:          # a reset in the done cycle itself comes too late
                self.dones.append(d)
                self.done_codes.append(self.codes[s + 1])

    def outputs(self, c: int) -> dict[str, int]:
        """Expected busy, adc_convst, adc_cs_n, adc_sclk, done, code_a, code_b, code_c in cycle c."""
        out = dict(busy=0, adc_convst=0, adc_cs_n=1, adc_sclk=0, done=0, code_a=0, code_b=0, code_c=0)
        i = bisect.bisect_left(self.accepted, c) - 1
        if i >= 0:
            a = self.accepted[i]
            r = self.next_reset(a + 1)
            if r is None or r >= c:                # conversion a still alive in cycle c
                o = c - a
                if 1 <= o <= self.latency - 1:
                    out["busy"] = 1
                if 1 <= o <= self.conv:
                    out["adc_convst"] = 1
                if self.conv + 1 <= o <= self.latency - 1:
                    out["adc_cs_n"] = 0
                    p = o - self.conv - 1
                    out["adc_sclk"] = int(p < 2 * self.bits * self.half and (p // self.half) % 2 == 1)
                if o == self.latency:
                    out["done"] = 1
        j = bisect.bisect_right(self.dones, c) - 1
        if j >= 0:
            d = self.dones[j]
            r = self.next_reset(d)
            if r is None or r >= c:
                out["code_a"], out["code_b"], out["code_c"] = self.done_codes[j]
        return out


# ----------------------------------------------------------------------------------------- lanes
class Lane:
    """One DUT instance: its handles, parameters, model, BFM and event list."""

    def __init__(self, dut, prefix: str, point: tuple[int, int, int], index: int, seed: int):
        self.h = {p: getattr(dut, prefix + p) for p in PORTS}
        self.bits, self.conv, self.half = point
        self.name = f"lane{index}(B={self.bits},C={self.conv},H={self.half})"
        for port in CODE_PORTS:
            width = len(self.h[port])
            assert width == self.bits, f"{self.name}: {port} has {width} bits, the test expects {self.bits}"
        self.rng = np.random.default_rng([seed, index])
        self.model = LaneModel(*point)
        self.events: list[tuple] = [(0, 0, "rst", 0)]   # (cycle, order, kind, arg); rst ends at 0
        self.finished = False
        self.planned: list[int] = []        # starts the random test means to be accepted
        self.planned_resets = 0
        self.done_cycles: list[int] = []
        self.bfm = AdcBfm(self.h["adc_convst"], self.h["adc_cs_n"], self.h["adc_sclk"], self.h["adc_sdo_a"],
                          self.h["adc_sdo_b"], self.h["adc_sdo_c"], bits=self.bits, conv_ticks=self.conv,
                          sclk_half=self.half, clk_period_ns=PERIOD_NS, codes_at=self.codes_at,
                          seed=int(self.rng.integers(1 << 31)), name=self.name)

    def codes_at(self, cycle: int) -> tuple[int, int, int]:
        try:
            return self.model.codes[cycle]
        except KeyError:
            raise AssertionError(f"{self.name}: CONVST rose in cycle {cycle}, where the model has no "
                                 f"accepted start in cycle {cycle - 1}") from None

    def random_code(self) -> int:
        top = (1 << self.bits) - 1
        u = self.rng.random()
        if u < 0.1:
            return 0
        if u < 0.2:
            return top
        if u < 0.25:
            return 0x5555 & top
        if u < 0.3:
            return 0xAAAA & top
        if u < 0.35:
            return 1 << int(self.rng.integers(self.bits))
        return int(self.rng.integers(top + 1))

    # --- stimulus building (cycles are absolute: cycle 0 = first cycle after the initial reset)
    def start_run(self, first: int, last: int) -> None:
        """start = 1 in cycles first..last; samples busy and the held codes in the first cycle."""
        self.model.starts.update(range(first, last + 1))
        for c in range(first, last + 2):      # a code for every cycle in which CONVST might rise
            if c not in self.model.codes:   # three independent codes (lanes A, B, C)
                self.model.codes[c] = (self.random_code(), self.random_code(), self.random_code())
        self.sample(first, START_PORTS)

    def reset(self, first: int, length: int) -> None:
        """rst = 1 in cycles first..first+length-1; samples the outputs after it."""
        self.model.resets.extend(range(first, first + length))
        self.events.append((first, 1, "rst", 1))
        self.events.append((first + length, 0, "rst", 0))
        self.sample(first + length)

    def sample(self, c: int, ports: tuple[str, ...] = OUT_PORTS) -> None:
        """Compare the outputs ``ports`` with the model in cycle c."""
        self.events.append((c, 2, "sample", ports))

    def finish(self) -> None:
        """Solve the model, add the start edges (runs of the union of start cycles) and done samples."""
        prev = None
        for c in sorted(self.model.starts):
            if c - 1 != prev:
                if prev is not None:
                    self.events.append((prev + 1, 0, "start", 0))
                self.events.append((c, 1, "start", 1))
            prev = c
        if prev is not None:
            self.events.append((prev + 1, 0, "start", 0))
        self.model.resets.sort()
        self.model.solve()
        for d in self.model.dones:
            self.sample(d, DONE_PORTS)
        self.events.sort(key=lambda e: (e[0], e[1]))
        self.finished = True

    # --- running
    def check_outputs(self, c: int, ports: tuple[str, ...]) -> None:
        exp = self.model.outputs(c)
        for port in ports:
            want = exp[port]
            got = int(self.h[port].value)
            if got != want:
                raise AssertionError(f"{self.name} cycle {c}: {port} RTL={got} expected={want} "
                                     f"(last accepted start {self._last_start(c)})")

    def _last_start(self, c: int):
        i = bisect.bisect_left(self.model.accepted, c) - 1
        return self.model.accepted[i] if i >= 0 else None

    async def drive(self, origin: int, period: int) -> None:
        half = period // 2
        for c, _, kind, arg in self.events:
            dt = origin + c * period + half - now_steps()
            if dt > 0:
                await Timer(dt, unit="step")
            if kind == "sample":
                self.check_outputs(c, arg)
            elif kind == "start":
                self.h["start"].set(Immediate(_LEVEL[arg]))   # mid-cycle: no edge to race with
            else:
                self.h["rst"].set(Immediate(_LEVEL[arg]))
                # an early CS rising edge is allowed while the host is reset (aborted read)
                self.bfm.abort_allowed = bool(arg)

    async def watch_done(self, origin: int, period: int) -> None:
        edge = RisingEdge(self.h["done"])
        while True:
            await edge
            self.done_cycles.append((now_steps() - origin) // period)

    def final_checks(self) -> None:
        m = self.model
        exp_convst = [a + 1 for a in m.accepted]
        if self.bfm.convst_cycles != exp_convst:
            raise AssertionError(f"{self.name}: CONVST cycles differ, first: "
                                 f"{_first_diff(self.bfm.convst_cycles, exp_convst)}")
        if self.done_cycles != m.dones:
            raise AssertionError(f"{self.name}: done cycles differ, first: {_first_diff(self.done_cycles, m.dones)}")
        # the BFM converted the model's codes (all three lanes) at every accepted start
        exp_conv = [(a + 1, *m.codes[a + 1]) for a in m.accepted]
        if self.bfm.converted != exp_conv:
            raise AssertionError(f"{self.name}: the BFM's conversions (cycle, A, B, C) differ from the model's, "
                                 f"first: {_first_diff(self.bfm.converted, exp_conv)}")
        # complete reads: no reset before the last SCLK falling edge (a reset sampled at that edge,
        # rst = 1 in cycle a + LATENCY - 2, makes CS rise with it: complete or aborted, in either order)
        lo = sum(1 for a in m.accepted if _none_or_ge(m.next_reset(a + 1), a + m.latency - 1))
        hi = sum(1 for a in m.accepted if _none_or_ge(m.next_reset(a + 1), a + m.latency - 2))
        if not lo <= self.bfm.reads <= hi:
            raise AssertionError(f"{self.name}: the ADC saw {self.bfm.reads} complete reads, expected "
                                 f"{lo}..{hi}")
        self.bfm.check_clean()


def _none_or_ge(r, limit) -> bool:
    return r is None or r >= limit


def _first_diff(got: list, exp: list) -> str:
    for i, (g, e) in enumerate(zip(got, exp)):
        if g != e:
            return f"#{i}: RTL {g}, expected {e}"
    return f"lengths RTL {len(got)}, expected {len(exp)}"


def make_lanes(dut, seed: int) -> list[Lane]:
    if TOP == "single":
        return [Lane(dut, "", POINTS[0], 0, seed)]
    return [Lane(dut, f"p{i}_", p, i, seed) for i, p in enumerate(POINTS)]


async def run_lanes(dut, lanes: list[Lane], last_cycle: int) -> None:
    """Reset all lanes, run their event lists (cycle 0 = first cycle after reset), check at the end."""
    clock = Clock(dut.clk, PERIOD_NS, unit="ns", impl="gpi")
    for lane in lanes:
        lane.h["rst"].value = 1
        lane.h["start"].value = 0
    clock.start()
    edge = RisingEdge(dut.clk)
    for _ in range(3):
        await edge
    origin = now_steps()                # rising edge that begins cycle 0 (rst = 1 was sampled here)
    period = lanes[0].bfm.period
    tasks = []
    for lane in lanes:
        if not lane.finished:
            lane.finish()
        lane.bfm.set_cycle_origin(origin)
        lane.bfm.start()
        tasks.append(cocotb.start_soon(lane.watch_done(origin, period)))
    drivers = [cocotb.start_soon(lane.drive(origin, period)) for lane in lanes]
    for d in drivers:
        await d
    end = max(last_cycle, max(lane.events[-1][0] for lane in lanes)) + 2
    dt = origin + end * period - now_steps()
    if dt > 0:
        await Timer(dt, unit="step")
    for t in tasks:
        t.cancel()
    for lane in lanes:
        lane.bfm.stop()
        lane.final_checks()
    clock.stop()


# ----------------------------------------------------------------------------------------- tests
def _seed_and_count() -> tuple[int, int]:
    seed = int(os.environ["HFI_SEED"])
    count = int(os.environ["HFI_RANDOM_N"])
    cocotb.log.info(f"tb_adc_if: HFI_SEED={seed} HFI_RANDOM_N={count} top={TOP} points={POINTS}")
    return seed, count


@cocotb.test()
async def random_conversions(dut):
    """HFI_RANDOM_N accepted conversions per instance: random codes (0 and full scale included), random
    start spacing >= CYCLE (a third exactly CYCLE: back to back), starts while busy (ignored), rare
    resets at random points of a conversion (then the next start as soon as the reset and t_CONV
    allow). Checked against LaneModel: busy and the held codes in every start cycle, done/busy/CS/codes
    in every done cycle, all outputs in a random cycle of every other conversion, the cycle of every
    CONVST rising edge and every done pulse, the number of complete reads; the BFM checks the ADC
    protocol and the sampling instant of every bit."""
    seed, count = _seed_and_count()
    lanes = make_lanes(dut, seed)
    last = 0
    for lane in lanes:
        rng, cyc, lat = lane.rng, lane.model.cycle, lane.model.latency
        c = int(rng.integers(0, 3))
        for _ in range(count):
            lane.planned.append(c)
            lane.start_run(c, c)
            a = c
            if rng.random() < 0.5:        # all outputs at a random point of the conversion
                lane.sample(a + int(rng.integers(1, lat + 1)))
            r0 = a + int(rng.integers(1, lat + 2)) if rng.random() < 0.004 else None
            if rng.random() < 0.25:       # a start while busy: ignored (before a reset, if any)
                b = a + int(rng.choice([1, cyc - 1, int(rng.integers(1, cyc))]))
                if r0 is None or b < r0:
                    lane.start_run(b, b)
            if r0 is not None:            # reset at a random point of this conversion (or just after)
                lane.planned_resets += 1
                length = int(rng.integers(1, 5))
                lane.reset(r0, length)
                # the next CONVST must not come before the ADC's conversion is over (t_CONV)
                c = max(r0 + length, a + lane.conv) + int(rng.integers(0, 3))
                continue
            u = rng.random()
            if u < 0.35:
                c = a + cyc               # back to back
            elif u < 0.93:
                c = a + cyc + int(rng.integers(1, 9))
            else:
                c = a + cyc + int(rng.integers(9, 2 * cyc))
        last = max(last, c + lat)
    await run_lanes(dut, lanes, last)
    for lane in lanes:
        n = len(lane.model.dones)
        cocotb.log.info(f"{lane.name}: {len(lane.model.accepted)} conversions accepted, {n} completed, "
                        f"{len(lane.model.starts) - len(lane.model.accepted)} starts ignored, "
                        f"{lane.bfm.aborts} reads aborted by reset")
        assert lane.model.accepted == lane.planned, \
            f"{lane.name}: testbench error, the model does not accept the planned starts " \
            f"({_first_diff(lane.model.accepted, lane.planned)})"
        assert n >= len(lane.planned) - lane.planned_resets, f"{lane.name}: only {n} conversions completed"


def pattern_codes(bits: int) -> list[tuple[int, int, int]]:
    """Directed code triples (A, B, C): zero, full scale, every mix of 0 and full scale over the three
    lanes, alternating bits, walking ones and walking zeros (C's one/zero at yet another position than
    A's and B's, so no two lanes carry the same word unless bits <= 2)."""
    top = (1 << bits) - 1
    h5, ha = 0x5555 & top, 0xAAAA & top
    triples = [(0, 0, 0), (top, top, top), (0, top, 0), (top, 0, top), (0, 0, top), (top, top, 0),
               (0, top, top), (top, 0, 0), (h5, ha, h5), (ha, h5, ha), (h5, h5, ha), (ha, ha, h5)]
    walk = [(k, bits - 1 - k, (k + bits // 2) % bits) for k in range(bits)]
    triples += [(1 << ka, 1 << kb, 1 << kc) for ka, kb, kc in walk]
    triples += [(top ^ (1 << ka), top ^ (1 << kb), top ^ (1 << kc)) for ka, kb, kc in walk]
    return triples


def reset_offsets(lane: Lane) -> list[int]:
    """Offsets (from an accepted start) of the directed resets: all of 0 .. LATENCY+1 for the short
    cycles (the default one included); for long cycles the phase boundaries and 24 random offsets."""
    lat, conv, half = lane.model.latency, lane.conv, lane.half
    if lat <= 60:
        return list(range(lat + 2))
    c0 = conv + 1                                         # first cycle with CS low
    picks = {0, 1, 2, conv - 1, conv, c0, c0 + 1, c0 + half, c0 + half + 1, lat - 3, lat - 2, lat - 1, lat, lat + 1}
    picks |= {int(v) for v in lane.rng.integers(0, lat + 2, 24)}
    return sorted(p for p in picks if 0 <= p <= lat + 1)


@cocotb.test()
async def directed(dut):
    """Per instance: pattern codes back to back at exactly CYCLE (codes from the BFM's queue); a start
    one cycle early (ignored) then at CYCLE; start held high for 4 CYCLEs (a conversion every CYCLE);
    a reset in every cycle of a conversion (offset 0 .. LATENCY+1, start held high through the reset
    so the first cycle after it starts the next conversion), with all outputs sampled around it."""
    seed, _ = _seed_and_count()
    lanes = make_lanes(dut, seed)
    last = 0
    for lane in lanes:
        cyc, lat, conv = lane.model.cycle, lane.model.latency, lane.conv
        triples = pattern_codes(lane.bits)
        c = 2
        for triple in triples:                              # back to back, exactly CYCLE apart
            lane.start_run(c, c)
            lane.model.codes[c + 1] = triple
            lane.sample(c + 1 + int(lane.rng.integers(0, lat)))
            c += cyc
        lane.start_run(c + cyc - 1, c + cyc - 1)            # busy in its last cycle: ignored
        lane.sample(c + cyc - 1)
        c += cyc
        lane.start_run(c, c)                                # accepted
        c += cyc + 3
        lane.start_run(c, c + 4 * cyc)                      # held high: a conversion every CYCLE
        for k in range(4 * cyc + 1):
            if k % 7 == 0 or k % cyc in (0, 1, cyc - 1):
                lane.sample(c + k)
        c += 5 * cyc + 2
        for o in reset_offsets(lane):                       # reset at (every) offset of a conversion
            a = c
            lane.start_run(a, a)
            length = max(1, conv - o) + int(lane.rng.integers(0, 2))
            r0, r1 = a + o, a + o + length                  # r1 >= a + conv: t_CONV is over
            lane.reset(r0, length)
            for k in (r0 - 1, r0, r0 + 1):
                lane.sample(k)
            lane.start_run(r0, r1)                          # start during the reset, and just after it
            lane.sample(r1 + 1)
            c = r1 + cyc + int(lane.rng.integers(0, 3))
        lane.reset(c, 2)                                    # reset while idle
        c += 2
        lane.start_run(c, c)
        c += cyc + 2
        last = max(last, c)
        lane.finish()
        # codes from the queue, in the order of the accepted starts (the queue mode of the BFM)
        lane.bfm.codes_at = None
        for a in lane.model.accepted:
            lane.bfm.push(*lane.model.codes[a + 1])
    await run_lanes(dut, lanes, last)
    for lane in lanes:
        assert not lane.bfm.queue, f"{lane.name}: {len(lane.bfm.queue)} queued codes were not converted"
        cocotb.log.info(f"{lane.name}: {len(lane.model.accepted)} conversions, {len(lane.model.dones)} "
                        f"completed, {lane.bfm.aborts} reads aborted by a reset")


# ----------------------------------------------------------------------------------------- BFM self-check
class _FrameWriter:
    """Drives the spare pins x_convst/x_cs_n/x_sclk of the sweep wrapper (the BFM under test watches
    them) from a list of (cycle, pin, level) writes, and reads the BFM's lanes x_sdo_a/b/c at given
    cycles before the writes of that cycle (the value just before an edge)."""

    def __init__(self, dut, origin: int, period: int):
        self.dut, self.origin, self.period = dut, origin, period
        self.writes: list[tuple[int, str, int]] = []
        self.reads: list[tuple[int, tuple[int, int, int], str]] = []

    def frame(self, t0: int, codes: tuple[int, int, int], *, bits=4, conv=3, cs_at=None, high=2, low=2,
              pulses=None, convst_len=None) -> int:
        """A conversion at t0 and a read (CS falls at t0 + cs_at); returns the cycle after CS rose."""
        cs_at = conv if cs_at is None else cs_at
        pulses = bits if pulses is None else pulses
        convst_len = cs_at if convst_len is None else convst_len
        self.writes += [(t0, "x_convst", 1), (t0 + convst_len, "x_convst", 0), (t0 + cs_at, "x_cs_n", 0)]
        t = t0 + cs_at
        for k in range(pulses):
            t += low
            self.writes.append((t, "x_sclk", 1))
            t += high
            if k < bits:   # bit k of every lane's code is on the lanes just before this falling edge
                self.reads.append((t, tuple((code >> (bits - 1 - k)) & 1 for code in codes), f"bit {k}"))
            self.writes.append((t, "x_sclk", 0))
        self.writes.append((t + 1, "x_cs_n", 1))
        return t + 2

    async def play(self) -> None:
        events = sorted([(c, 0, pin, v) for c, pin, v in self.writes] +
                        [(c, -1, what, exp) for c, exp, what in self.reads], key=lambda e: (e[0], e[1]))
        for c, kind, name, arg in events:
            dt = self.origin + c * self.period + self.period // 2 - now_steps()
            if dt > 0:
                await Timer(dt, unit="step")
            if kind < 0:
                got = (int(self.dut.x_sdo_a.value), int(self.dut.x_sdo_b.value), int(self.dut.x_sdo_c.value))
                assert got == arg, f"BFM self-check cycle {c}: {name} on the lanes (A, B, C) {got}, expected {arg}"
            else:
                getattr(self.dut, name).value = arg
        self.writes, self.reads = [], []
        await Timer(self.period, unit="step")       # let the BFM see the last edge


if TOP == "sweep":
    @cocotb.test()
    async def bfm_self_check(dut):
        """The BFM's protocol checks fire (each violation once, with its message), a correct frame
        gives the queued codes bit by bit on all three lanes and no error, an allowed abort is counted,
        not an error; codes that are not three in-range integers are refused."""
        from adc_bfm import AdcProtocolError
        seed, _ = _seed_and_count()
        clock = Clock(dut.clk, PERIOD_NS, unit="ns", impl="gpi")
        clock.start()
        dut.x_convst.value, dut.x_cs_n.value, dut.x_sclk.value = 0, 1, 0
        await RisingEdge(dut.clk)
        await RisingEdge(dut.clk)
        bfm = AdcBfm(dut.x_convst, dut.x_cs_n, dut.x_sclk, dut.x_sdo_a, dut.x_sdo_b, dut.x_sdo_c, bits=4,
                     conv_ticks=3, sclk_half=2, clk_period_ns=PERIOD_NS, quiet_ticks=2, raise_on_error=False,
                     seed=seed, name="selfcheck")
        bfm.set_cycle_origin()
        bfm.start()
        fw = _FrameWriter(dut, bfm.origin, bfm.period)
        rng = np.random.default_rng(seed)

        async def case(title: str, expected: list[str], build) -> None:
            n0 = len(bfm.errors)
            build()
            await fw.play()
            new = bfm.errors[n0:]
            missing = [e for e in expected if not any(e in m for m in new)]
            assert not missing and len(new) == len(expected), \
                f"BFM self-check '{title}': expected errors {expected}, got {new}"
            cocotb.log.info(f"BFM self-check '{title}': {new if new else 'no error'}")

        t = 2

        def codes(fixed: tuple[int, int, int] | None = None) -> tuple[int, int, int]:
            triple = tuple(int(v) for v in rng.integers(16, size=3)) if fixed is None else fixed
            bfm.push(*triple)
            return triple

        def good(fixed=None):
            nonlocal t
            t = fw.frame(t, codes(fixed)) + 2

        reads0, conv0 = bfm.reads, len(bfm.converted)
        await case("correct frame", [], good)
        await case("correct frames back to back", [], lambda: [good() for _ in range(4)])
        corners = [(0, 15, 0), (15, 0, 15), (0, 0, 15), (15, 15, 0), (0x5, 0xA, 0x9)]
        await case("corner codes, lane C apart from A and B", [], lambda: [good(c) for c in corners])
        assert bfm.reads == reads0 + 10, f"BFM self-check: {bfm.reads - reads0} complete reads, expected 10"
        assert [c[1:] for c in bfm.converted[conv0 + 5:]] == corners, \
            f"BFM self-check: converted {bfm.converted[conv0 + 5:]}, queued {corners}"
        for bad_codes in ((16, 0, 0), (0, 16, 0), (0, 0, 16), (0, 0, -1)):   # out of range, any lane
            try:
                bfm.push(*bad_codes)
            except ValueError:
                pass
            else:
                raise AssertionError(f"BFM self-check: codes {bad_codes} accepted")
        assert not bfm.queue, f"BFM self-check: refused codes left in the queue {list(bfm.queue)}"

        def cs_early():
            nonlocal t
            t = fw.frame(t, codes(), cs_at=2) + 2
        await case("CS before t_CONV", ["before the conversion finished"], cs_early)

        def fast_high():
            nonlocal t
            t = fw.frame(t, codes(), high=1) + 2
        await case("SCLK high too short", ["SCLK high time"] * 4, fast_high)

        def fast_low():
            nonlocal t
            t = fw.frame(t, codes(), low=1) + 2
        await case("SCLK low too short", ["CS falling to the first SCLK rising edge"] + ["SCLK low time"] * 3,
                   fast_low)

        def short_read():
            nonlocal t
            t = fw.frame(t, codes(), pulses=3) + 2
        await case("CS rises after 3 of 4 bits", ["CS rose after 3 of 4 bits"], short_read)

        def long_read():
            nonlocal t
            t = fw.frame(t, codes(), pulses=5) + 2
        await case("five SCLK pulses", ["SCLK pulse 5 in a frame of 4 bits"], long_read)

        def convst_converting():
            nonlocal t
            codes()
            fw.writes += [(t, "x_convst", 1), (t + 1, "x_convst", 0)]
            t = fw.frame(t + 2, codes()) + 2
        await case("CONVST while converting", ["CONVST rose while converting"], convst_converting)

        def convst_reading():
            nonlocal t
            end = fw.frame(t, codes())
            codes()
            fw.writes += [(t + 5, "x_convst", 1), (t + 6, "x_convst", 0)]
            t = end + 4
            t = fw.frame(t, codes()) + 2
        await case("CONVST while CS low", ["CONVST rose while CS is low"], convst_reading)

        def convst_quiet():
            nonlocal t
            end = fw.frame(t, codes())          # CS rises at end - 1; t_QUIET is 2 clocks here
            t = fw.frame(end, codes()) + 2
        await case("CONVST within t_QUIET", ["after CS rose (t_QUIET"], convst_quiet)

        def sclk_idle():
            nonlocal t
            fw.writes += [(t, "x_sclk", 1), (t + 2, "x_sclk", 0)]
            t += 4
        await case("SCLK while CS high", ["SCLK rose while CS is high", "SCLK fell while CS is high"], sclk_idle)

        def cs_alone():
            nonlocal t
            fw.writes += [(t, "x_cs_n", 0), (t + 2, "x_cs_n", 1)]
            t += 4
        await case("CS without a conversion", ["CS fell without a conversion", "CS rose after 0 of 4 bits"],
                   cs_alone)

        def no_codes():
            nonlocal t
            fw.writes += [(t, "x_convst", 1), (t + 3, "x_convst", 0)]
            t += 6
        await case("CONVST with an empty queue", ["CONVST with no codes queued"], no_codes)

        def abort():
            nonlocal t
            bfm.abort_allowed = True
            t = fw.frame(t, codes(), pulses=2) + 2
        aborts0 = bfm.aborts
        await case("allowed abort (host reset)", [], abort)
        bfm.abort_allowed = False
        assert bfm.aborts == aborts0 + 1, "BFM self-check: the allowed abort was not counted"
        await case("correct frame after the errors", [], good)
        bfm.stop()
        clock.stop()

        # the raising mode and the summary check
        strict = AdcBfm(dut.x_convst, dut.x_cs_n, dut.x_sclk, dut.x_sdo_a, dut.x_sdo_b, dut.x_sdo_c, bits=4,
                        conv_ticks=3, sclk_half=2, name="strict")
        try:
            strict._error("test violation")
        except AdcProtocolError as e:
            assert "strict ADC protocol error" in str(e) and "test violation" in str(e), str(e)
        else:
            raise AssertionError("raise_on_error=True did not raise")
        try:
            bfm.check_clean()
        except AdcProtocolError as e:
            assert "protocol errors" in str(e)
        else:
            raise AssertionError("check_clean() did not raise with recorded errors")
        for bad in (dict(bits=0, conv_ticks=1, sclk_half=1), dict(bits=17, conv_ticks=1, sclk_half=1),
                    dict(bits=4, conv_ticks=0, sclk_half=1), dict(bits=4, conv_ticks=1, sclk_half=0),
                    dict(bits=4, conv_ticks=1, sclk_half=1, codes=[(1, 2)]),          # a pair: no lane C
                    dict(bits=4, conv_ticks=1, sclk_half=1, codes=[(1, 2, 3, 4)]),
                    dict(bits=4, conv_ticks=1, sclk_half=1, codes=[(1, 2, 16)])):
            try:
                AdcBfm(dut.x_convst, dut.x_cs_n, dut.x_sclk, dut.x_sdo_a, dut.x_sdo_b, dut.x_sdo_c, **bad)
            except ValueError:
                pass
            else:
                raise AssertionError(f"AdcBfm accepted {bad}")
