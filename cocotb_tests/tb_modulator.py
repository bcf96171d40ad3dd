"""cocotb testbench of rtl/hfi_modulator.v (run by cocotb_tests/test_modulator.py, not by pytest).

Every result is compared with the golden chain of ``golden/closedloop.py`` ``ClosedLoop._compares``:
``compares(...)`` of golden/fpga/modulator.py for sign +1 (top) and -1 (bottom), each followed by
``compensate(...)`` of golden/fpga/deadtime_comp.py when ``DTC_GAIN != 0``.

Random vectors: ``numpy.random.default_rng(HFI_SEED)``, ``HFI_RANDOM_N`` of them (set by hdl_runner),
from golden/testvectors/modulator.py (shared with tests/test_hls_modulator.py): the register draws
(``draw_registers``) cover the full ranges with their extremes, typical small values, unit-circle
SIN/COS, powers of two for SIN/COS and H (exact half-LSB ties of the rounding shifts), DTC_GAIN = 0 for
half the vectors, RECIP_H = round(2^32/H) mostly and any u32 sometimes, and about 3 % vectors built to
tie in the min-max (v_a = v_b, v_a = v_c, v_b = v_c, all three); ``corner_vectors`` the extremes. The random
run drives the module as fast as it allows (a start in the done cycle), changes the registers right
after every start (the module must have sampled them), sometimes pulses start while busy (ignored) or
leaves idle cycles, and checks in the cycle before done that the outputs still hold the previous
results, in the done cycle all six outputs against the golden chain. :class:`Coverage` counts the
corner cases reached (over-modulation, ties, rounding ties, compensation clamps, i_x beyond the RTL's
saturation bound, non-nominal RECIP_H) and fails the run if one was never reached.

``inj_neg`` (the period square wave of CTRL.INJ_PER with S = -1, spec 3.5: the injection's signs of
the two sets swapped, the dead-time compensation keeping the half's sign) is not one of the shared
register draws: :func:`with_inj_neg` sets it in a third of the vectors from its own generator (so the
shared vectors stay those of tests/test_hls_modulator.py); the golden chain is then ``_compares`` with
``inj_sign = -sign`` (golden/closedloop.py).

Direct-vector mode (CTRL.DIRECT, spec 3.10): the inputs ``direct, fcs_a1, fcs_a2, fcs_phi_min,
fcs_constrain`` (0 in the vectors above) and the output ``state``. With ``direct`` both sets are
``direct_compares(s, H)`` of golden/fpga/modulator.py, ``s = direct_state(...)`` (choose_vector on the
inverse Park without injection) with the state the module applied after its previous run (0 after reset
and after a run without the mode); ``state`` is s (0 without the mode). The Driver carries that state
from vector to vector. :func:`with_direct` draws the mode's registers (its own generator);
``direct_random`` runs >= HFI_RANDOM_N of them mixed with a tenth of ordinary vectors, ``direct_cases``
the directed ones (every sector, the zero vector 000/111 by the state now, the constraint on, off and
dropped, extreme v_alpha/v_beta and A1/A2).

All driving happens at falling-edge instants; waits of several cycles are single timers (a Python
wake-up per clock edge would dominate the run time).
"""

from __future__ import annotations

import os

import numpy as np

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, FallingEdge, Timer

from golden.fixed import round_shr, shr
from golden.fpga.deadtime_comp import compensate, phase_current, recip_half
from golden.fpga.fcs_mpc import VX, VY, choose_vector
from golden.fpga.modulator import compares, direct_alpha_beta, direct_compares, direct_state
from golden.testvectors.modulator import REGS, as_dicts, corner_vectors, draw_registers, rot_arg, v_abc

LATENCY = 105
"""hfi_modulator: start in cycle 0, done and the new outputs in cycle LATENCY (its header)."""

OUTS = ("cmp_top_a", "cmp_top_b", "cmp_top_c", "cmp_bot_a", "cmp_bot_b", "cmp_bot_c")
COVERAGE_N = 20000
"""Corner-case counts are measured on the first COVERAGE_N random vectors (pure-Python replicas)."""


# ---------------------------------------------------------------------------------------------- golden
def golden_set(r: dict, sign: int) -> tuple[int, int, int]:
    """One compare set exactly as ClosedLoop._compares (compensation only when DTC_GAIN != 0), with
    ``inj_sign = -sign`` when the vector has ``inj_neg`` (the compensation keeps ``sign``)."""
    inj_sign = -sign if r.get("inj_neg", 0) else sign
    cmps = compares(r["v_d"], r["v_q"], r["v_h"], r["sin_q15"], r["cos_q15"], r["half"], inj_sign, rot_arg(r))
    if r["dtc_gain"]:
        cmps = compensate(cmps, sign, r["half"], r["dead"], r["dtc_gain"], r["i_d_ref"], r["i_q_ref"],
                          r["hf_amp"], r["sin_q15"], r["cos_q15"], r["recip_h"])
    return tuple(int(c) for c in cmps)


def golden_chain(r: dict) -> tuple[int, ...]:
    """The six outputs (top a, b, c, bottom a, b, c) without the direct-vector mode."""
    return golden_set(r, +1) + golden_set(r, -1)


DIRECT_REGS = ("direct", "fcs_a1", "fcs_a2", "fcs_phi_min", "fcs_constrain")


def golden_step(r: dict, state: int) -> tuple[tuple[int, ...], int]:
    """``(six outputs, state output)`` of one run with the state ``state`` applied before it."""
    if not r.get("direct", 0):
        return golden_chain(r), 0
    s = direct_state(r["v_d"], r["v_q"], r["sin_q15"], r["cos_q15"], r["fcs_a1"], r["fcs_a2"],
                     r["fcs_phi_min"], bool(r["fcs_constrain"]), state)
    return direct_compares(s, r["half"]) * 2, s


def with_direct(vecs: list[dict], seed: int, p_direct: float = 0.9) -> list[dict]:
    """The vectors with the direct-vector mode in a fraction ``p_direct`` of them and its registers
    drawn (own generator): A1, A2 full s16 or typical Q12 (|A| <= 2^13) or extremes, PHI_MIN over its
    range, near typical strengths, 0 or 65535, CONSTRAIN half of the time."""
    g = np.random.default_rng([seed, 17])
    n = len(vecs)
    def s16(k):
        kind = g.integers(0, 4, k)
        full = g.integers(-32768, 32768, k)
        small = g.integers(-8192, 8193, k)
        ext = g.choice(np.array([-32768, 32767, 0, 4096, -4096]), k)
        return np.where(kind == 0, full, np.where(kind == 3, ext, small))
    a1, a2 = s16(n), s16(n)
    kind = g.integers(0, 5, n)
    phi = np.where(kind == 0, g.integers(0, 65536, n),
                   np.where(kind == 1, g.integers(0, 4096, n),
                            np.where(kind == 2, g.integers(0, 30000, n),
                                     np.where(kind == 3, 0, 65535))))
    on = g.random(n) < p_direct
    con = g.random(n) < 0.5
    return [r | {"direct": int(o), "fcs_a1": int(x), "fcs_a2": int(y), "fcs_phi_min": int(p),
                 "fcs_constrain": int(c)} for r, o, x, y, p, c in zip(vecs, on, a1, a2, phi, con)]


# ---------------------------------------------------------------------------------------------- coverage
class Coverage:
    """Counts of the corner cases a run exercised (from replicas of the golden steps)."""

    NAMES = ("clip_low", "clip_high", "tie_ab", "tie_ac", "tie_bc", "tie_abc", "round_half_park",
             "rot", "round_half_rot", "round_half_cmp", "dtc_on", "c_linear", "c_clamped_D", "cmp_comp_clamped", "ix_beyond_s25",
             "recip_nonnominal")

    def __init__(self):
        self.n = dict.fromkeys(self.NAMES, 0)

    def add(self, r: dict):
        n = self.n
        H = r["half"]
        for sign in (1, -1):
            a, b, c = v_abc(r["v_d"], r["v_q"], r["v_h"], r["sin_q15"], r["cos_q15"], sign, r["rot"],
                            r["inj_sin"], r["inj_cos"])
            n["tie_ab"] += a == b
            n["tie_ac"] += a == c
            n["tie_bc"] += b == c
            n["tie_abc"] += a == b == c
            vd = r["v_d"] + sign * r["v_h"] * (1 - r["rot"])
            vr = r["v_h"] * r["rot"]
            park = (vd * r["cos_q15"] - r["v_q"] * r["sin_q15"] + vr * r["inj_cos"],
                    vd * r["sin_q15"] + r["v_q"] * r["cos_q15"] + vr * r["inj_sin"])
            n["rot"] += r["rot"]
            n["round_half_rot"] += r["rot"] and any((x + 16384) % 32768 == 0 for x in park)
            n["round_half_park"] += any((x + 16384) % 32768 == 0 for x in park)   # exactly x.5 LSB
            off = shr(max(a, b, c) + min(a, b, c), 1)
            n["round_half_cmp"] += any(((v - off) * H + 16384) % 32768 == 0 for v in (a, b, c))
            raw = [(H >> 1) + round_shr((v - off) * H, 15) for v in (a, b, c)]
            n["clip_low"] += any(x < 0 for x in raw)
            n["clip_high"] += any(x > H for x in raw)
            if r["dtc_gain"]:
                n["dtc_on"] += 1
                n["recip_nonnominal"] += r["recip_h"] != recip_half(H)
                cmps = compares(r["v_d"], r["v_q"], r["v_h"], r["sin_q15"], r["cos_q15"], H, sign, rot_arg(r))
                for leg, cmp in enumerate(cmps):
                    hf = round_shr(r["hf_amp"] * (2 * cmp - H) * r["recip_h"], 32)
                    ix = phase_current(leg, r["i_d_ref"] - hf, r["i_q_ref"], r["sin_q15"], r["cos_q15"])
                    n["ix_beyond_s25"] += not -(1 << 24) <= ix < (1 << 24)
                    cr = shr(ix * r["dtc_gain"], 8)
                    if abs(cr) > r["dead"]:
                        n["c_clamped_D"] += 1
                    elif cr:
                        n["c_linear"] += 1
                    cc = max(-r["dead"], min(r["dead"], cr))
                    adj = min(cc, 0) if sign < 0 else max(cc, 0)
                    n["cmp_comp_clamped"] += not 0 <= cmp + adj <= H

    def report(self, log, label):
        log.info(f"{label} coverage: " + ", ".join(f"{k}={v}" for k, v in self.n.items()))

    def require(self, names):
        missing = [k for k in names if self.n[k] == 0]
        assert not missing, f"corner cases never exercised: {missing} ({self.n})"


# ---------------------------------------------------------------------------------------------- driving
CLOCK_NS = 10


async def cycles(n: int):
    """Wait n clock periods in one simulator callback (ClockCycles wakes Python at every edge).

    All driving happens at falling-edge instants (reached once with FallingEdge after the clock
    starts): registered outputs are stable there, and inputs written there are sampled by the next
    rising edge, whichever order the simulator gives the timer and the clock toggle."""
    if n > 0:
        await Timer(n * CLOCK_NS, unit="ns")


def seed_and_count():
    seed = int(os.environ["HFI_SEED"])
    count = int(os.environ["HFI_RANDOM_N"])
    cocotb.log.info(f"HFI_SEED={seed} HFI_RANDOM_N={count}")
    return seed, count


_HANDLES: dict[tuple[int, tuple[str, ...]], list] = {}


def handles(dut, names: tuple[str, ...]) -> list:
    """The signal handles of ``names``, looked up once per DUT (a lookup per access cost a fifth of the random
    test's Python time)."""
    key = (id(dut), names)
    if key not in _HANDLES:
        _HANDLES[key] = [getattr(dut, k) for k in names]
    return _HANDLES[key]


def apply(dut, r: dict):
    for k, h in zip(REGS, handles(dut, REGS)):
        h.value = r[k]
    dut.inj_neg.value = r.get("inj_neg", 0)
    for k, h in zip(DIRECT_REGS, handles(dut, DIRECT_REGS)):
        h.value = r.get(k, 0)


def with_inj_neg(vecs: list[dict], seed: int) -> list[dict]:
    """The vectors with ``inj_neg`` = 1 in about a third of them (its own generator: the shared
    register draws are unchanged)."""
    neg = np.random.default_rng([seed, 5]).random(len(vecs)) < 1 / 3
    return [r | {"inj_neg": int(n)} for r, n in zip(vecs, neg)]


def read_outs(dut) -> tuple[int, ...]:
    return tuple(h.value.to_unsigned() for h in handles(dut, OUTS))


def fmt(r: dict) -> str:
    return "{" + ", ".join(f"{k}={r[k]}" for k in REGS + ("inj_neg",) + DIRECT_REGS if k in r) + "}"


def check_outs(dut, expected, what: str, r: dict | None = None):
    got = read_outs(dut)
    if got != tuple(expected):
        diff = ", ".join(f"{k}: RTL {g} golden {e}" for k, g, e in zip(OUTS, got, expected) if g != e)
        raise AssertionError(f"{what}: {diff}" + (f"; registers {fmt(r)}" if r is not None else ""))


async def start_clock_and_reset(dut, half=10000, n_cycles=3):
    Clock(dut.clk, CLOCK_NS, unit="ns").start()
    dut.start.value = 0
    apply(dut, {k: 0 for k in REGS} | {"half": half, "dead": 1})
    dut.rst.value = 1
    await ClockCycles(dut.clk, n_cycles, rising=False)        # aligned to a falling edge
    dut.rst.value = 0
    return (half >> 1,) * 6


class Driver:
    """Drives the module from falling edges; `t` counts falling edges since the current start."""

    def __init__(self, dut, rng=None, p_busy_start=0.0, p_gap=0.0):
        self.state = 0                                  # the direct-vector state applied (0 after reset)
        self.dut = dut
        self.rng = rng
        self.p_busy_start = p_busy_start
        self.p_gap = p_gap
        self.busy_starts = 0
        self.gaps = 0

    async def run(self, vecs, prev, label="vector"):
        """Run `vecs` (dicts) back to back; `prev` are the outputs before the first start. Returns the
        last outputs. The caller leaves the DUT idle at a falling edge with start low."""
        dut, rng = self.dut, self.rng
        expected, states = [], []
        for r in vecs:
            out, self.state = golden_step(r, self.state)
            expected.append(out)
            states.append(self.state)
        apply(dut, vecs[0])
        dut.start.value = 1
        for i, r in enumerate(vecs):
            await cycles(1)                             # cycle 1: registers already sampled
            t = 1
            dut.start.value = 0
            if i + 1 < len(vecs):
                apply(dut, vecs[i + 1])                 # register changes in mid-operation
            if rng is not None and rng.random() < self.p_busy_start:
                k = int(rng.integers(1, LATENCY - 1))   # start in cycle k (busy): ignored
                if k > t:
                    await cycles(k - t)
                dut.start.value = 1
                await cycles(1)
                dut.start.value = 0
                t = k + 1
                self.busy_starts += 1
            if LATENCY - 1 > t:
                await cycles(LATENCY - 1 - t)
            if int(dut.done.value) != 0 or int(dut.busy.value) != 1:
                raise AssertionError(f"{label} {i}: cycle {LATENCY - 1}: done={dut.done.value} "
                                     f"busy={dut.busy.value}, expected 0 and 1")
            check_outs(dut, prev, f"{label} {i}: outputs changed before done (cycle {LATENCY - 1})")
            await cycles(1)                             # cycle LATENCY
            if int(dut.done.value) != 1 or int(dut.busy.value) != 0:
                raise AssertionError(f"{label} {i}: cycle {LATENCY}: done={dut.done.value} "
                                     f"busy={dut.busy.value}, expected 1 and 0")
            check_outs(dut, expected[i], f"{label} {i} (state before: {states[i - 1] if i else '?'})", r)
            if int(dut.state.value) != states[i]:
                raise AssertionError(f"{label} {i}: state RTL {int(dut.state.value)} golden {states[i]}; "
                                     f"registers {fmt(r)} {[r.get(k, 0) for k in DIRECT_REGS]}")
            prev = expected[i]
            if rng is not None and rng.random() < self.p_gap:
                gap = int(rng.integers(1, 4))
                await cycles(gap)
                if int(dut.done.value) != 0 or int(dut.busy.value) != 0:
                    raise AssertionError(f"{label} {i}: idle after done: done={dut.done.value} "
                                         f"busy={dut.busy.value}")
                check_outs(dut, prev, f"{label} {i}: outputs changed while idle")
                self.gaps += 1
            if i + 1 < len(vecs):
                dut.start.value = 1
        return prev


# ---------------------------------------------------------------------------------------------- tests
@cocotb.test()
async def random_vectors(dut):
    """HFI_RANDOM_N random start vectors, back to back, against the golden chain."""
    seed, count = seed_and_count()
    rng = np.random.default_rng(seed)
    vecs = with_inj_neg(as_dicts(draw_registers(rng, count)), seed)
    prev = await start_clock_and_reset(dut)
    drv = Driver(dut, rng, p_busy_start=0.05, p_gap=0.05)
    await drv.run(vecs, prev, "random vector")
    cov = Coverage()
    for r in vecs[:COVERAGE_N]:
        cov.add(r)
    cov.report(cocotb.log, f"random (first {min(count, COVERAGE_N)} vectors)")
    n_neg = sum(r["inj_neg"] and not r["rot"] and r["v_h"] > 0 for r in vecs)
    cocotb.log.info(f"{n_neg} vectors with the period square wave's S = -1 (inj_neg, V_H > 0)")
    if count >= 2000:
        assert n_neg > count // 10, "too few inj_neg vectors"

    cocotb.log.info(f"{count} vectors, {drv.busy_starts} starts while busy, {drv.gaps} idle gaps")
    if count >= 2000:           # an exact half-LSB tie of the injection's rotation: about one in 1500 vectors
        cov.require(Coverage.NAMES if count >= COVERAGE_N else [k for k in Coverage.NAMES if k != "round_half_rot"])


@cocotb.test()
async def corner_cases(dut):
    """Register extremes, over-modulation, min-max ties, DTC extremes; each checked in full."""
    base = corner_vectors()
    vecs = base + [r | {"inj_neg": 1} for r in base]        # each corner also with the signs swapped
    prev = await start_clock_and_reset(dut)
    await Driver(dut).run(vecs, prev, "corner vector")
    cov = Coverage()
    for r in vecs:
        cov.add(r)
    cov.report(cocotb.log, "corner")
    cov.require(("clip_low", "clip_high", "tie_bc", "tie_abc", "rot", "c_clamped_D", "cmp_comp_clamped",
                 "ix_beyond_s25", "recip_nonnominal"))


@cocotb.test()
async def reset_values(dut):
    """In reset the six outputs follow half >> 1 of the half input; they hold it after reset."""
    Clock(dut.clk, 10, unit="ns").start()
    dut.start.value = 0
    apply(dut, {k: 0 for k in REGS} | {"half": 512, "dead": 1})
    dut.rst.value = 1
    await ClockCycles(dut.clk, 2, rising=False)              # a rising edge in reset, at a falling edge
    for half in (512, 65534, 10000, 1234, 65535, 0, 2):
        dut.half.value = half
        await FallingEdge(dut.clk)
        check_outs(dut, (half >> 1,) * 6, f"reset with half={half}")
        assert int(dut.busy.value) == 0 and int(dut.done.value) == 0, "busy/done in reset"
    dut.rst.value = 0
    dut.half.value = 30000
    for cyc in range(5):
        await FallingEdge(dut.clk)
        check_outs(dut, (1,) * 6, f"cycle {cyc} after reset (half changed to 30000)")
        assert int(dut.busy.value) == 0 and int(dut.done.value) == 0, "busy/done after reset without start"


@cocotb.test()
async def reset_mid_operation(dut):
    """A reset in any phase (modulator steps, top and bottom compensation, the last cycle) abandons
    the computation: outputs half >> 1, no done; the next start computes correctly."""
    rng = np.random.default_rng(int(os.environ["HFI_SEED"]) + 1)
    prev = await start_clock_and_reset(dut)
    vecs = as_dicts(draw_registers(rng, 60))
    for j, k in enumerate((1, 2, 5, 14, 22, 25, 26, 27, 44, 64, 65, 66, 80, 103, LATENCY - 1)):
        r = vecs[j] | {"dtc_gain": 1 + j * 4000}
        apply(dut, r)
        dut.start.value = 1
        await cycles(1)
        dut.start.value = 0
        if k > 1:
            await cycles(k - 1)  # cycle k
        assert int(dut.busy.value) == 1, f"not busy in cycle {k}"
        dut.rst.value = 1
        dut.half.value = 2000 + 2 * j
        await cycles(1)
        dut.rst.value = 0
        prev = ((2000 + 2 * j) >> 1,) * 6
        check_outs(dut, prev, f"reset in cycle {k}")
        for cyc in range(LATENCY + 3):                       # nothing completes after the reset
            assert int(dut.done.value) == 0 and int(dut.busy.value) == 0, f"done/busy {cyc} cycles after reset"
            check_outs(dut, prev, f"{cyc} cycles after the reset in cycle {k}")
            await cycles(1)
        prev = await Driver(dut).run([vecs[30 + j]], prev, f"vector after reset in cycle {k}")


@cocotb.test()
async def start_held_high(dut):
    """start held high for several periods: accepted only when idle (cycles 0, LATENCY, 2*LATENCY..)
    with the registers of that cycle; done exactly once per period; outputs change only at done."""
    rng = np.random.default_rng(int(os.environ["HFI_SEED"]) + 2)
    prev = await start_clock_and_reset(dut)
    vecs = with_inj_neg(as_dicts(draw_registers(rng, 6 * LATENCY)), int(os.environ["HFI_SEED"]) + 2)
    dut.start.value = 1
    accepted = []
    for cyc in range(5 * LATENCY + 1):
        apply(dut, vecs[cyc])                                # new registers in every cycle
        if cyc % LATENCY == 0:
            accepted.append(vecs[cyc])
        await cycles(1)
        c = cyc + 1                                          # cycles since the first start
        want_done = c % LATENCY == 0
        assert int(dut.done.value) == want_done, f"cycle {c}: done={dut.done.value}"
        assert int(dut.busy.value) == (not want_done), f"cycle {c}: busy={dut.busy.value}"
        if want_done:
            k = c // LATENCY - 1
            check_outs(dut, golden_chain(accepted[k]), f"held start, result {k}", accepted[k])
            prev = read_outs(dut)
        else:
            check_outs(dut, prev, f"held start: outputs changed in cycle {c} (not a done cycle)")
    dut.start.value = 0


# ---------------------------------------------------------------------------------------------- direct mode
class DirectCoverage:
    """Counts of the direct-vector mode's cases (from the golden choice)."""

    NAMES = ("state_000", "state_111", "active_1", "active_2", "active_3", "active_4", "active_5", "active_6",
             "constrained_differs", "constraint_dropped", "zero_excluded", "mode_off")

    def __init__(self):
        self.n = dict.fromkeys(self.NAMES, 0)

    def add(self, vecs: list[dict]):
        n, state = self.n, 0
        order = (0b001, 0b011, 0b010, 0b110, 0b100, 0b101)
        for r in vecs:
            if not r.get("direct", 0):
                n["mode_off"] += 1
                state = 0
                continue
            v_al, v_be = direct_alpha_beta(r["v_d"], r["v_q"], r["sin_q15"], r["cos_q15"])
            args = (v_al, v_be, r["sin_q15"], r["cos_q15"], r["fcs_a1"], r["fcs_a2"], r["fcs_phi_min"])
            s, _ = choose_vector(*args, bool(r["fcs_constrain"]), state)
            free, _ = choose_vector(*args, False, state)
            if r["fcs_constrain"]:
                c_, s_ = r["cos_q15"], r["sin_q15"]
                p = [round_shr(r["fcs_a1"] * round_shr(y * c_ - x * s_, 15)
                               - r["fcs_a2"] * round_shr(x * c_ + y * s_, 15), 12) for x, y in zip(VX, VY)]
                n["constrained_differs"] += s != free
                n["constraint_dropped"] += not any(abs(pj) > r["fcs_phi_min"] for pj in p)
                n["zero_excluded"] += free in (0, 7) and s not in (0, 7)
            n["state_000"] += s == 0
            n["state_111"] += s == 7
            if s not in (0, 7):
                n[f"active_{order.index(s) + 1}"] += 1
            state = s

    def report(self, log, label):
        log.info(f"{label} direct coverage: " + ", ".join(f"{k}={v}" for k, v in self.n.items()))

    def require(self, names):
        missing = [k for k in names if self.n[k] == 0]
        assert not missing, f"direct-mode cases never exercised: {missing} ({self.n})"


@cocotb.test()
async def direct_random(dut):
    """HFI_RANDOM_N random vectors of the direct-vector mode (a tenth with the mode off), back to back,
    starts while busy and idle gaps, against golden direct_state/direct_compares with the state carried."""
    seed, count = seed_and_count()
    rng = np.random.default_rng([seed, 23])
    vecs = with_direct(with_inj_neg(as_dicts(draw_registers(rng, count)), seed + 7), seed)
    prev = await start_clock_and_reset(dut)
    drv = Driver(dut, rng, p_busy_start=0.05, p_gap=0.05)
    await drv.run(vecs, prev, "direct vector")
    cov = DirectCoverage()
    cov.add(vecs)
    cov.report(cocotb.log, f"random ({count} vectors)")
    if count >= 2000:
        cov.require(DirectCoverage.NAMES)


def _direct_case(v_d, v_q, s, c, a1=0, a2=0, phi=0, con=0, half=10000):
    return {k: 0 for k in REGS} | {"v_d": v_d, "v_q": v_q, "sin_q15": s, "cos_q15": c, "half": half,
                                    "dead": 1, "recip_h": recip_half(half), "direct": 1, "fcs_a1": a1,
                                    "fcs_a2": a2, "fcs_phi_min": phi, "fcs_constrain": con}


def direct_cases() -> list[dict]:
    """Directed vectors of the direct-vector mode (run in this order: the state carries)."""
    import math
    vecs = []
    # every sector: a large voltage at angles 0..355 deg (unit circle SIN/COS, and V_D/V_Q rotated)
    for deg in range(0, 360, 5):
        s, c = round(32767 * math.sin(math.radians(deg))), round(32767 * math.cos(math.radians(deg)))
        vecs.append(_direct_case(20000, 0, s, c))
        vecs.append(_direct_case(14000, 14000, 0, 32767) | {"v_d": round(20000 * math.cos(math.radians(deg))),
                                                           "v_q": round(20000 * math.sin(math.radians(deg)))})
    # the zero vector by the state now: from a two-high state (011 at 60 deg) -> 111, then from 111 -> 111,
    # from a one-high state (001 at 0 deg) -> 000, from 000 -> 000
    s60, c60 = round(32767 * math.sin(math.pi / 3)), round(32767 * math.cos(math.pi / 3))
    vecs += [_direct_case(25000, 0, s60, c60), _direct_case(0, 0, 0, 32767), _direct_case(100, -50, 0, 32767),
             _direct_case(25000, 0, 0, 32767), _direct_case(0, 0, 0, 32767), _direct_case(-30, 70, 0, 32767),
             _direct_case(25000, 0, 0, -32768), _direct_case(0, 0, 0, 32767)]        # 110 (two high) -> 111
    # the constraint on and off with the same voltage; dropped when nothing is eligible
    for a1, a2 in ((4096, 0), (0, 4096), (3000, -2000), (32767, -32768), (-32768, 32767), (0, 0)):
        for phi in (0, 1, 5000, 10000, 20000, 65535):
            for con in (0, 1):
                vecs.append(_direct_case(3000, 2000, 12000, 30000, a1, a2, phi, con))
                vecs.append(_direct_case(0, 0, -20000, 25000, a1, a2, phi, con))
    # extreme v_alpha / v_beta (SIN/COS not on the unit circle)
    for vd in (-32768, 32767):
        for vq in (-32768, 32767):
            for s in (-32768, 32767):
                for c in (-32768, 32767):
                    vecs.append(_direct_case(vd, vq, s, c, -32768, 32767, 65535, 1, half=65534))
                    vecs.append(_direct_case(vd, vq, s, c, 32767, 32767, 0, 1, half=512))
    # exact ties, with COS = -2^15, SIN = 0 (then v_alpha = -V_D, v_beta = -V_Q exactly): d_1 = d_0 = 0
    # (v = (14921, 3998): the zero vector wins), d_1 = d_2 (v_alpha = 0: 011 wins), d_3 = d_4 (v_beta = 0
    # side), one LSB either way; then fine angle sweeps across the sector borders at magnitudes near
    # the switching to the zero vector (the K_j differ between even and odd j)
    for vd, vq in ((-14921, -3998), (-14922, -3998), (-14920, -3998), (-14921, -3999), (0, -20000),
                   (1, -20000), (-1, -20000), (0, 20000), (21845, 0), (10923, 0), (10922, 0),
                   (-11022, -6364), (-21746, -12555), (11022, 6364), (21746, 12555)):   # d_1 - d_0 = +1, -1
        vecs.append(_direct_case(vd, vq, 0, -32768))
    for mag in (10900, 10923, 10950, 12000, 30000):
        for tenth in range(0, 3600, 75):
            a = math.radians(tenth / 10 + 0.05)
            vecs.append(_direct_case(-round(mag * math.cos(a)), -round(mag * math.sin(a)), 0, -32768))
    # the mode off in between (state back to 0), then on again from 0
    vecs += [{k: 0 for k in REGS} | {"half": 2000, "dead": 1, "recip_h": recip_half(2000), "cos_q15": 32767},
             _direct_case(0, 0, 0, 32767)]
    return vecs


@cocotb.test()
async def direct_directed(dut):
    """Directed vectors of the direct-vector mode, in sequence (the state now carries), each checked."""
    vecs = direct_cases()
    prev = await start_clock_and_reset(dut)
    await Driver(dut).run(vecs, prev, "direct case")
    cov = DirectCoverage()
    cov.add(vecs)
    cov.report(cocotb.log, "directed")
    cov.require(DirectCoverage.NAMES)
