"""cocotb testbench of the fixed-point instructions rtl/hfi_cfu.v (run by cocotb_tests/test_cfu.py, not by pytest).

Reference, independent of the Verilog: :class:`hfi.cfu.CfuModel` (whose arithmetic is golden.fixed's). The bench
plays the CPU's side of LiteX's CFU port: it presents one instruction at a time (``cmd_valid`` with the
function id ``{funct7, funct3}`` and rs1, rs2) and takes the answers with a random ``rsp_ready`` (the core's
memory stage can be stuck), and checks, for every instruction:

- the answer against the model (accumulating instructions answer 0, RND/FLR/DIV the model's value), in order,
  one answer per command;
- the timing the firmware's cycle counts rest on: with ``rsp_ready`` high, MUL/MAC/MSU/ADD/SET are answered in
  the clock after their command and taken back to back (a command every clock), RND/FLR three clocks after, DIV
  five clocks after when its quotient saturates, else 5 + w (:func:`div_latency`);
- no command is taken while an answer waits for the CPU or an RND/FLR/DIV is in flight.

Random programs: HFI_RANDOM_N instructions (default 100 000 under Verilator) drawn as the firmware's idioms
(a MUL or SET then MAC/MSU/ADD then RND/FLR, or SET then DIV as the firmware's saturated quotients) and as any
sequence, with operands of every size and the corners (INT32_MIN, INT32_MAX, 0, +-1, powers of two), shifts
0..63 and widths 0..63, divisors of every size and sign (0 and the quotients just below and at the limit too);
directed: each instruction's corners (the 64-bit wrap of the sums and of the rounding, k = 0 and 63, widths 0,
1, 32, 33; DIV: INT64_MIN by -1, a zero divisor, widths 0, 1, 2, 32, 63).
"""

from __future__ import annotations

import os

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.triggers import ReadOnly, RisingEdge

from golden.fixed import wrap
from hfi.cfu import CfuModel, div_width
from hfi.soc_platform import CFU_OPS

PERIOD_NS = 20
INT32_MIN, INT32_MAX = -(1 << 31), (1 << 31) - 1
SPECIAL = (0, 1, -1, 2, -2, INT32_MIN, INT32_MAX, INT32_MIN + 1, 1 << 30, -(1 << 30), 32767, -32768, 1 << 15)
OPS = CFU_OPS
READS = (OPS["RND"], OPS["FLR"], OPS["DIV"])
READ_LATENCY = 3
"""Clocks from an RND/FLR command to its answer (rtl/hfi_cfu.v: the read skips the product stage)."""


def div_latency(n: int, d: int, k: int) -> int:
    """Clocks from a DIV command to its answer: 5 when the quotient saturates (the compare of floor(|n| /
    2^(w-1)) with |d|), else 5 + w (w - 1 quotient bits, one per clock, and the sign)."""
    w = div_width(k)
    return 5 if (abs(n) >> (w - 1)) >= abs(d) else 5 + w


def divisor(rng: np.random.Generator, n: int) -> tuple[int, int]:
    """(rs1, rs2) of a DIV: a 64-bit divisor of every size and sign; often one that puts the quotient of ``n``
    just below, at or above a width's limit, sometimes 0."""
    u = rng.random()
    if u < 0.05:
        d = 0
    elif u < 0.4 and n != 0:
        w = int(rng.choice([16, 18, 21, 22, 32, 2]))
        d = max(abs(n) >> (w - 1), 1) + int(rng.integers(-2, 3))
        d = (d if d != 0 else 1) * (1 if rng.random() < 0.5 else -1)
    else:
        b = int(rng.integers(0, 63))
        d = int(rng.integers(-(1 << b), (1 << b) + 1)) << int(rng.integers(0, 2))
    d = max(min(d, (1 << 63) - 1), -(1 << 63))
    return d >> 32, d & 0xFFFF_FFFF


def operand(rng: np.random.Generator) -> int:
    kind = rng.integers(0, 4)
    if kind == 0:
        return int(rng.integers(INT32_MIN, INT32_MAX + 1))
    if kind == 1:
        b = int(rng.integers(0, 31))
        return int(rng.integers(-(1 << b), (1 << b) + 1))
    if kind == 2:
        return SPECIAL[int(rng.integers(0, len(SPECIAL)))]
    return int(rng.integers(-(1 << 16), 1 << 16))


def width(rng: np.random.Generator) -> int:
    """rs1 of an RND/FLR: mostly a real width (16, 21, 26, 29, 32: the firmware's), else any 6-bit field, with
    random upper bits (the unit reads bits 5:0 only)."""
    w = int(rng.choice([16, 21, 26, 29, 32, 1, 0, 33])) if rng.random() < 0.7 else int(rng.integers(0, 64))
    return w | (int(rng.integers(0, 1 << 26)) << 6 if rng.random() < 0.2 else 0)


def program(rng: np.random.Generator, n: int) -> list[tuple[int, int, int, int]]:
    """``n`` instructions (op, k, rs1, rs2): the firmware's idioms and free sequences."""
    out: list[tuple[int, int, int, int]] = []
    while len(out) < n:
        if rng.random() < 0.6:                       # an idiom: start, accumulate, read
            k = int(rng.choice([0, 0, 8, 16, 24, 28, 32])) if rng.random() < 0.7 else int(rng.integers(0, 64))
            out.append((OPS["MUL"] if rng.random() < 0.8 else OPS["SET"], k, operand(rng), operand(rng)))
            for _ in range(int(rng.integers(0, 5))):
                op = int(rng.choice([OPS["MAC"], OPS["MSU"], OPS["ADD"]]))
                out.append((op, k if rng.random() < 0.8 else int(rng.integers(0, 64)), operand(rng), operand(rng)))
            rk = int(rng.choice([0, 8, 15, 16, 28])) if rng.random() < 0.7 else int(rng.integers(0, 64))
            out.append((int(rng.choice(READS[:2])), rk, width(rng), operand(rng)))
        elif rng.random() < 0.5:                     # a saturated quotient: SET the dividend, DIV
            hi, lo = operand(rng), operand(rng)
            if rng.random() < 0.5:                   # a dividend of any size
                b = int(rng.integers(0, 63))
                v = int(rng.integers(-(1 << b), (1 << b) + 1))
                hi, lo = v >> 32, v & 0xFFFF_FFFF
            out.append((OPS["SET"], 0, hi, lo))
            w = int(rng.choice([16, 18, 21, 22])) if rng.random() < 0.7 else int(rng.integers(0, 64))
            out.append((OPS["DIV"], w, *divisor(rng, (hi << 32) + (lo & 0xFFFF_FFFF))))
        else:
            op = int(rng.integers(0, 8))
            a = width(rng) if op in READS[:2] else operand(rng)
            out.append((op, int(rng.integers(0, 64)), a, operand(rng)))
    return out[:n]


def directed() -> list[tuple[int, int, int, int]]:
    """Each instruction's corners."""
    M, X = INT32_MIN, INT32_MAX
    p = [(OPS["MUL"], 0, M, M), (OPS["FLR"], 32, 0, 0), (OPS["FLR"], 0, 0, 0), (OPS["RND"], 0, 32, 0),
         (OPS["MAC"], 0, M, M), (OPS["FLR"], 32, 0, 0),                  # 2^63: wraps to INT64_MIN
         (OPS["MSU"], 63, M, X), (OPS["FLR"], 63, 0, 0), (OPS["FLR"], 62, 33, 0),
         (OPS["SET"], 0, X, -1), (OPS["RND"], 1, 0, 0), (OPS["RND"], 63, 32, 0),   # rounding carry wraps
         (OPS["SET"], 0, -1, -1), (OPS["RND"], 1, 1, 0), (OPS["RND"], 1, 32, 0), (OPS["FLR"], 1, 32, 0),
         (OPS["SET"], 0, 0, 1 << 14), (OPS["RND"], 15, 16, 0), (OPS["SET"], 0, -1, -(1 << 14)),
         (OPS["RND"], 15, 16, 0), (OPS["FLR"], 15, 16, 0),                # exactly one half: rounds up
         (OPS["ADD"], 63, 1, 0), (OPS["FLR"], 32, 0, 0), (OPS["ADD"], 0, M, X), (OPS["FLR"], 0, 0, 0),
         (OPS["MUL"], 0, 1 << 20, 1 << 20), (OPS["RND"], 0, 32, 0), (OPS["RND"], 0, 1, 0), (OPS["RND"], 0, 2, 0),
         (OPS["RND"], 8, 21, 0), (OPS["FLR"], 40, 32, 0), (OPS["RND"], 40, 32, 0),
         (OPS["SET"], 0, M, 0), (OPS["DIV"], 32, -1, -1), (OPS["DIV"], 63, -1, -1),    # INT64_MIN / -1
         (OPS["DIV"], 0, 0, 0), (OPS["DIV"], 1, 0, 1), (OPS["DIV"], 2, 0, 1),       # / 0, widths 0, 1, 2
         (OPS["FLR"], 32, 0, 0),                                                # DIV keeps acc
         (OPS["SET"], 0, 0, 0), (OPS["DIV"], 16, 0, 0), (OPS["DIV"], 16, 0, 7),    # 0 / 0, 0 / 7
         (OPS["SET"], 0, 0, 32767 * 5), (OPS["DIV"], 16, 0, 5), (OPS["DIV"], 16, 0, 4),  # at, above the limit
         (OPS["SET"], 0, -1, -32768 * 5), (OPS["DIV"], 16, 0, 5), (OPS["DIV"], 16, -1, -5),
         (OPS["SET"], 0, X, -1), (OPS["DIV"], 32, M, 0), (OPS["DIV"], 32, X, -1),   # INT64_MAX / INT64_MIN, / itself
         (OPS["SET"], 0, 1 << 20, 12345), (OPS["DIV"], 22, 0, 1 << 31), (OPS["DIV"], 22, 0, 3)]
    return p


class Cpu:
    """The CPU's side of the port, with a random ``rsp_ready``."""

    def __init__(self, dut, rng, p_ready: float, model: CfuModel | None = None):
        self.dut, self.rng, self.p_ready = dut, rng, p_ready
        self.model = model or CfuModel()
        self.clock = 0

    async def run(self, prog: list[tuple[int, int, int, int]]) -> int:
        dut = self.dut
        pending: list[tuple[int, int, int, int]] = []     # (expected answer, op, clock of its command, latency)
        i = 0
        checked = 0
        while i < len(prog) or pending:
            # drive this clock's inputs
            if i < len(prog):
                op, k, a, b = prog[i]
                dut.cmd_valid.value = 1
                dut.cmd_function_id.value = (k << 3) | op
                dut.cmd_inputs_0.value = a & 0xFFFFFFFF
                dut.cmd_inputs_1.value = b & 0xFFFFFFFF
            else:
                dut.cmd_valid.value = 0
            ready = 1 if self.p_ready >= 1.0 else int(self.rng.random() < self.p_ready)
            dut.rsp_ready.value = ready
            await ReadOnly()
            fire = i < len(prog) and int(dut.cmd_ready.value) == 1
            take = int(dut.rsp_valid.value) == 1 and ready
            if int(dut.rsp_valid.value) == 1 and not pending:
                raise AssertionError(f"clock {self.clock}: an answer without a command")
            if fire and (pending and (pending[-1][1] in READS or int(dut.rsp_valid.value) and not ready)):
                raise AssertionError(f"clock {self.clock}: a command taken while an answer is due")
            if take:
                want, op, at, want_lat = pending.pop(0)
                got = int(dut.rsp_outputs_0.value.to_signed())
                assert got == want, (f"instruction {checked} (op {op}, command at clock {at}): answer {got}, "
                                     f"model {want}")
                if self.p_ready >= 1.0:
                    lat = self.clock - at
                    assert lat == want_lat, f"op {op}: answered {lat} clocks after its command, {want_lat} expected"
                checked += 1
            if fire:
                op, k, a, b = prog[i]
                lat = 1 if op not in READS else READ_LATENCY if op != OPS["DIV"] else \
                    div_latency(self.model.acc, (wrap(a, 32) << 32) + (b & 0xFFFF_FFFF), k)
                pending.append((self.model.step(op, k, a, b), op, self.clock, lat))
                i += 1
            await RisingEdge(dut.clk)
            self.clock += 1
        return checked


async def reset(dut):
    cocotb.start_soon(Clock(dut.clk, PERIOD_NS, unit="ns").start())
    dut.rst.value = 1
    dut.cmd_valid.value = 0
    dut.rsp_ready.value = 0
    for _ in range(3):
        await RisingEdge(dut.clk)
    dut.rst.value = 0
    await RisingEdge(dut.clk)


@cocotb.test()
async def directed_corners(dut):
    """Each instruction's corners, the CPU always ready: answers and latencies."""
    await reset(dut)
    prog = directed()
    checked = await Cpu(dut, np.random.default_rng(0), 1.0).run(prog)
    assert checked == len(prog)


@cocotb.test()
async def back_to_back(dut):
    """With rsp_ready high, accumulating instructions issue one per clock."""
    await reset(dut)
    prog = [(OPS["MUL"], 0, 3, 5)] + [(OPS["MAC"], 0, 7, 11)] * 20 + [(OPS["FLR"], 0, 32, 0)]
    cpu = Cpu(dut, np.random.default_rng(0), 1.0)
    checked = await cpu.run(prog)
    assert checked == len(prog)
    assert cpu.model.acc == 15 + 20 * 77
    assert cpu.clock == 21 + READ_LATENCY + 1, f"{cpu.clock} clocks for 21 accumulations and a read"


@cocotb.test()
async def random_programs(dut):
    """HFI_RANDOM_N random instructions: half with the CPU always ready (latencies checked), half with a
    random rsp_ready."""
    seed = int(os.environ.get("HFI_SEED", "1"))
    n = int(os.environ.get("HFI_RANDOM_N", "2000"))
    rng = np.random.default_rng(seed)
    await reset(dut)
    model = CfuModel()
    first = program(rng, n // 2)
    assert await Cpu(dut, rng, 1.0, model).run(first) == len(first)
    second = program(rng, n - n // 2)
    assert await Cpu(dut, rng, 0.6, model).run(second) == len(second)
