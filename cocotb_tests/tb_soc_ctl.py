"""cocotb testbench of the SoC control block rtl/hfi_soc_ctl.v (with its UART rtl/hfi_uart_tx.v) and of
the RAM rtl/hfi_ram.v, through the wrapper cocotb_tests/hdl/tb_soc_ctl_ram.v (run by
cocotb_tests/test_soc_ctl.py, not by pytest).

References, independent of the Verilog:
* :class:`SocCtlModel`, built from ``golden.socmap.REGISTERS`` (addresses, fields, access types, resets)
  and the written contract of rtl/regs/hfi_soc.rdl: the native PicoRV32 bus (an access is sampled at
  the rising edge where ``sel`` is high and ``ready`` low; ``ready`` is high for the one clock after it
  and ``rdata`` is valid then; reads see the state before that edge; writes (any non-zero ``wstrb``)
  store the whole word, as the header of hfi_soc_ctl.v states); the UART as 8N1 frames (start bit, 8
  data bits LSB first, stop bit, each bit ``max(UART_DIV, 16)`` clocks, the line low from the clock
  after the accepted write); TX_BUSY high for exactly those 10 bit periods; a UART_DATA write is
  ignored when a read at the same edge would show TX_BUSY = 1. The model is stepped once per rising
  edge and every output is compared in every clock.
* The testbench's own clock count since reset release (rising edges with ``rst`` low before the edge
  that samples the read) for CYCLE_LO, and a decoder of the recorded ``uart_tx`` line
  (:func:`decode_uart`) for the bytes on the wire.
* For the RAM: the $readmemh image parsed in Python, and a word array with byte-lane writes.

Clock numbering: ``Bench.n`` counts rising edges; outputs are sampled at the falling edge after edge
``n`` and inputs driven there for edge ``n + 1``.

The CYCLE_HI snapshot across a 2^32 (and 2^64) boundary cannot be reached by counting in a short
simulation: test ``cycle_hi_snapshot`` deposits a value into the counter register ``u_ctl.cycles``
(Verilator --public-flat-rw, Icarus VPI) and counts on from there (``reset_mid_operation`` too, to see a
reset clear a loaded CYCLE_HI); the other tests leave the counter alone, so CYCLE_HI reads 0 there.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge

from golden.socmap import REGISTERS

ID_ASCII = b"HFIS"
"""The ID register's documented value, ASCII "HFIS" (rtl/regs/hfi_soc.rdl)."""
UART_MIN_DIV = 16
"""UART_DIV values below this act as this (rtl/regs/hfi_soc.rdl, UART_DIV)."""
UART_FRAME_BITS = 10
"""8N1: start bit, 8 data bits, stop bit."""
WORD = 0xFFFFFFFF
COVERAGE_MIN_N = 500
"""Below this HFI_RANDOM_N (a quick run by hand) the random tests skip their coverage assertions."""

ADDR = {name: reg["addr"] for name, reg in REGISTERS.items()}
UNMAPPED = [a for a in range(0, 256, 4) if a not in ADDR.values()]
"""Word addresses of the 8-bit window that hold no register (PicoRV32 addresses are word aligned)."""

# How the model shows each field: rw fields (with the output port carrying the stored value, or
# None), write-only fields with a side effect, read-only hardware values (no reset of their own).
RW_PORTS = {("CTRL", "DSP_RUN"): "dsp_run", ("UART_DIV", "VALUE"): None, ("FW_STATUS", "MODE"): None,
            ("FW_STATUS", "FAULT"): None}
WO_EFFECTS = {("UART_DATA", "DATA"): "uart", ("TRACE", "VALUE"): "trace"}
HW_VALUES = {("CYCLE_LO", "VALUE"): "cycle_lo", ("CYCLE_HI", "VALUE"): "cycle_hi",
             ("UART_STATUS", "TX_BUSY"): "tx_busy"}


def uart_period(div: int) -> int:
    """Clocks per bit for a UART_DIV value (values below 16 act as 16)."""
    return max(div, UART_MIN_DIV)


def uart_levels(byte: int) -> list[int]:
    """Line levels of one 8N1 frame, bit by bit: start 0, data LSB first, stop 1."""
    return [0] + [(byte >> i) & 1 for i in range(8)] + [1]


@dataclass
class Frame:
    """One UART byte on the line: the start bit is on the line from clock ``start``."""
    start: int
    byte: int
    period: int

    @property
    def end(self) -> int:
        """First clock after the stop bit."""
        return self.start + UART_FRAME_BITS * self.period

    def level(self, n: int) -> int:
        return uart_levels(self.byte)[(n - self.start) // self.period]


def decode_uart(line: list, first: int, periods: list[int]) -> list[tuple[int, int]]:
    """Decode the recorded line (``line[n]`` = uart_tx after edge n) from clock ``first`` on.

    ``periods`` are the expected bit periods of the successive frames. Every bit of a frame must hold
    its level for exactly its period (the start bit low, the stop bit high), the line is high between
    frames. Returns ``[(clock of the start bit's first clock, byte), ...]``.
    """
    frames, n, periods = [], first, list(periods)
    while n < len(line):
        if line[n] == 1:
            n += 1
            continue
        assert periods, f"uart_tx: start bit at clock {n} but no further frame was expected"
        p = periods.pop(0)
        assert n + UART_FRAME_BITS * p <= len(line), f"uart_tx: frame at clock {n} not recorded to its end"
        bits = []
        for k in range(UART_FRAME_BITS):
            cell = line[n + k * p:n + (k + 1) * p]
            assert len(set(cell)) == 1, (f"uart_tx: bit {k} of the frame at clock {n} is not constant for "
                                         f"{p} clocks: {cell}")
            bits.append(cell[0])
        assert bits[0] == 0 and bits[-1] == 1, f"uart_tx: frame at clock {n}: start/stop bits {bits}"
        frames.append((n, sum(bit << i for i, bit in enumerate(bits[1:9]))))
        n += UART_FRAME_BITS * p
    assert not periods, f"uart_tx: {len(periods)} expected frames missing"
    return frames


def _field_mask(width: int) -> int:
    return (1 << width) - 1


class SocCtlModel:
    """hfi_soc_ctl from golden.socmap.REGISTERS and the RDL's text, stepped once per rising edge."""

    def __init__(self):
        self.by_addr = {reg["addr"]: name for name, reg in REGISTERS.items()}
        for name, reg in REGISTERS.items():
            for field, (_lsb, _width, reset, access) in reg["fields"].items():
                key = (name, field)
                table = {"rw": RW_PORTS, "wo": WO_EFFECTS, "ro": HW_VALUES if reset is None else {key: 0}}
                assert key in table.get(access, {}), f"{name}.{field} ({access}) not modelled by tb_soc_ctl"
        self.frames: list[Frame] = []   # every accepted byte (for the line decoder)
        self.ignored = 0                # UART_DATA writes ignored while busy
        self.reset()

    def reset(self) -> None:
        self.store = {key: REGISTERS[key[0]]["fields"][key[1]][2] for key in RW_PORTS}
        self.cycles = 0
        self.cycle_hi = 0
        self.ready = 0
        self.rdata = 0
        self.trace = None
        self.frame: Frame | None = None

    # ------------------------------------------------------------------ state seen by the bus
    def busy(self, n: int) -> int:
        """TX_BUSY after edge n."""
        return int(self.frame is not None and self.frame.start <= n < self.frame.end)

    def hw_value(self, what: str, n: int) -> int:
        """A read-only hardware field as read at edge n (the state before that edge)."""
        return {"cycle_lo": self.cycles & WORD, "cycle_hi": self.cycle_hi, "tx_busy": self.busy(n - 1)}[what]

    def read(self, addr: int, n: int) -> int:
        name = self.by_addr.get(addr)
        if name is None:
            return 0
        value = 0
        for field, (lsb, _width, reset, access) in REGISTERS[name]["fields"].items():
            key = (name, field)
            if access == "rw":
                v = self.store[key]
            elif access == "wo":
                v = 0
            else:
                v = reset if reset is not None else self.hw_value(HW_VALUES[key], n)
            value |= v << lsb
        if name == "CYCLE_LO":
            self.cycle_hi = self.cycles >> 32
        return value

    def write(self, addr: int, data: int, n: int) -> None:
        name = self.by_addr.get(addr)
        if name is None:
            return
        for field, (lsb, width, _reset, access) in REGISTERS[name]["fields"].items():
            key, v = (name, field), (data >> lsb) & _field_mask(width)
            if access == "rw":
                self.store[key] = v
            elif WO_EFFECTS.get(key) == "uart":
                self.uart_write(v, n)
            elif WO_EFFECTS.get(key) == "trace":
                self.trace = v

    def uart_write(self, byte: int, n: int) -> None:
        if self.busy(n - 1):
            self.ignored += 1
            return
        self.frame = Frame(n, byte, uart_period(self.store[("UART_DIV", "VALUE")]))
        self.frames.append(self.frame)

    # ------------------------------------------------------------------ one clock
    def edge(self, n: int, rst: int, sel: int, addr: int, wstrb: int, wdata: int) -> None:
        """State after rising edge n with these inputs."""
        if rst:
            self.reset()
            return
        access = sel and not self.ready  # the edge where the master sees ready is not a new access
        self.ready = int(bool(access))
        self.trace = None
        if access and wstrb == 0:
            self.rdata = self.read(addr, n)
        elif access:
            self.write(addr, wdata, n)
        self.cycles = (self.cycles + 1) & ((1 << 64) - 1)

    def outputs(self, n: int) -> dict[str, int]:
        """Expected output ports after edge n (rdata and trace_data are checked separately)."""
        out = {"ready": self.ready, "trace_valid": int(self.trace is not None),
               "uart_tx": self.frame.level(n) if self.busy(n) else 1}
        out.update({port: self.store[key] for key, port in RW_PORTS.items() if port is not None})
        return out


class Bench:
    """Clock-by-clock driver of the wrapper: bus master, RAM ports, per-clock output checks."""

    def __init__(self, dut, name: str):
        self.dut = dut
        self.name = name
        self.seed = int(os.environ["HFI_SEED"])
        self.n_random = int(os.environ["HFI_RANDOM_N"])
        self.rng = np.random.default_rng(self.seed)
        cocotb.log.info(f"{name}: HFI_SEED={self.seed} HFI_RANDOM_N={self.n_random}")
        self.model = SocCtlModel()
        self.fall = FallingEdge(dut.clk)
        self.n = 0                  # rising edges so far (this test)
        self.released = None        # clocks since the last reset release (rising edges with rst low)
        self.line: list = []        # line[n] = uart_tx after edge n (None before the first reset)
        self.trace_log: list[tuple[int, int]] = []
        self.checking = False
        self.inputs = dict(rst=1, sel=0, addr=0, wstrb=0, wdata=0)
        self.ram_inputs = dict(ram_wstrb=0, ram_waddr=0, ram_wdata=0, ram_ren=0, ram_raddr=0)
        self.applied: dict[str, int] = {}

    def fail(self, text: str) -> str:
        return f"{self.name}, clock {self.n} (HFI_SEED={self.seed}): {text}"

    async def start(self) -> None:
        """Start the clock and reset the control block for 3 clocks."""
        Clock(self.dut.clk, 10, unit="ns", impl="gpi").start()
        self.apply()
        await self.fall
        self.line.append(None)
        await self.reset(3)

    def apply(self) -> None:
        """Write the inputs that changed since the last clock."""
        for port, value in {**self.inputs, **self.ram_inputs}.items():
            if self.applied.get(port) != value:
                getattr(self.dut, port).value = value
                self.applied[port] = value

    async def tick(self) -> None:
        """One clock: the inputs of ``self.inputs`` are sampled at the next rising edge; then the
        model steps and every output is checked at the falling edge."""
        self.apply()
        await self.fall
        self.n += 1
        i = self.inputs
        self.model.edge(self.n, **i)
        self.released = 0 if i["rst"] else (None if self.released is None else self.released + 1)
        self.checking = self.checking or bool(i["rst"])
        if not self.checking:
            self.line.append(None)
            return
        self.check_outputs()

    def check_outputs(self) -> None:
        d, m = self.dut, self.model
        for port, want in m.outputs(self.n).items():
            got = int(getattr(d, port).value)
            assert got == want, self.fail(f"{port} = {got}, model {want}")
        if m.ready:
            got = int(d.rdata.value)
            assert got == m.rdata, self.fail(f"rdata = 0x{got:08X}, model 0x{m.rdata:08X}")
        if m.trace is not None:
            got = int(d.trace_data.value)
            assert got == m.trace, self.fail(f"trace_data = 0x{got:08X}, model 0x{m.trace:08X}")
            self.trace_log.append((self.n, got))
        self.line.append(int(d.uart_tx.value))

    async def idle(self, clocks: int) -> None:
        self.inputs.update(sel=0, wstrb=0)
        for _ in range(clocks):
            await self.tick()

    async def reset(self, clocks: int) -> None:
        self.inputs.update(rst=1, sel=0, wstrb=0)
        for _ in range(clocks):
            await self.tick()
        self.inputs["rst"] = 0

    # ------------------------------------------------------------------ bus master
    async def access(self, addr: int, wdata: int | None = None, wstrb: int = 0xF, gap: int = 0,
                     at: int | None = None, hold: bool = True) -> tuple[int, int, int | None]:
        """One PicoRV32-style access (a read if ``wdata`` is None: wstrb 0, random wdata).

        After ``gap`` idle clocks (or idle until the access is sampled at edge ``at``), ``sel`` is held
        until the edge where the master sees ``ready`` (``hold``; else dropped after the sampling
        edge). Returns (sampling edge, rdata after it, clocks since reset release before it).
        """
        if at is not None:
            gap = at - self.n - 1
            assert gap >= 0, self.fail(f"access at edge {at} requested too late")
        await self.idle(gap)
        read = wdata is None
        self.inputs.update(sel=1, addr=addr, wstrb=0 if read else wstrb,
                           wdata=int(self.rng.integers(0, 1 << 32)) if read else wdata)
        count = self.released
        await self.tick()
        edge = self.n
        assert int(self.dut.ready.value) == 1, self.fail(f"no ready after the access to 0x{addr:02X}")
        rdata = int(self.dut.rdata.value)
        if not hold:
            self.inputs.update(sel=0, wstrb=0)
        await self.tick()
        assert int(self.dut.ready.value) == 0, self.fail("ready longer than one clock")
        self.inputs.update(sel=0, wstrb=0)
        return edge, rdata, count

    async def read(self, name_or_addr, **kw) -> int:
        addr = ADDR.get(name_or_addr, name_or_addr)
        return (await self.access(addr, **kw))[1]

    async def write(self, name_or_addr, data: int, wstrb: int = 0xF, **kw) -> int:
        """Returns the edge that sampled the write."""
        addr = ADDR.get(name_or_addr, name_or_addr)
        return (await self.access(addr, data, wstrb, **kw))[0]

    def random_word(self) -> int:
        return int(self.rng.integers(0, 1 << 32))

    def random_strb(self) -> int:
        """A non-zero byte strobe (wstrb 0 is a read)."""
        return int(self.rng.integers(1, 16))

    def random_gap(self) -> int:
        return int(self.rng.choice([0, 0, 0, 1, 2, 3]))

    async def uart_drain(self) -> None:
        """Idle until the line has finished its current frame."""
        m = self.model
        await self.idle(max(0, (m.frame.end if m.frame else 0) - self.n))


def _random_div(rng) -> int:
    """A UART_DIV value: below 16 (acts as 16) half of the time, else 16..48."""
    return int(rng.integers(0, 16)) if rng.random() < 0.5 else int(rng.integers(16, 49))


# ---------------------------------------------------------------------- control block tests
@cocotb.test()
async def reset_values(dut):
    """Every register's reset value (golden.socmap), ID = ASCII "HFIS", outputs after reset."""
    b = Bench(dut, "reset_values")
    await b.start()
    assert REGISTERS["ID"]["reset"] == int.from_bytes(ID_ASCII, "big")
    assert (int(dut.dsp_run.value), int(dut.uart_tx.value), int(dut.trace_valid.value),
            int(dut.ready.value)) == (0, 1, 0, 0)
    for name, reg in REGISTERS.items():
        _, data, count = await b.access(reg["addr"])
        expected = {"CYCLE_LO": count, "CYCLE_HI": 0, "UART_STATUS": 0}.get(name, reg["reset"])
        assert data == expected, b.fail(f"{name} after reset: 0x{data:08X}, expected 0x{expected:08X}")
    assert await b.read("UART_DIV") == 434


@cocotb.test()
async def dsp_run_control(dut):
    """CTRL.DSP_RUN: random words and strobes, read back (bits 31:1 read 0), dsp_run from the clock
    after the write edge."""
    b = Bench(dut, "dsp_run_control")
    await b.start()
    values = [1, 0, 0xFFFFFFFF, 0xFFFFFFFE, 1, 1, 0] + [b.random_word() for _ in range(40)]
    for v in values:
        edge = await b.write("CTRL", v, b.random_strb(), gap=b.random_gap())
        assert b.n == edge + 1 and int(dut.dsp_run.value) == v & 1, b.fail(f"dsp_run after CTRL <= 0x{v:08X}")
        assert await b.read("CTRL", gap=b.random_gap()) == v & 1


@cocotb.test()
async def cycle_counter(dut):
    """CYCLE_LO = clocks since reset release (counted here); CYCLE_HI = 0 (the high word cannot move
    in a short simulation, see cycle_hi_snapshot); a reset restarts the count."""
    b = Bench(dut, "cycle_counter")
    await b.start()
    for i in range(60):
        if i in (20, 40):
            await b.reset(1 + i // 20)
        gap = 1000 if i == 59 else int(b.rng.integers(0, 40))
        _, lo, count = await b.access(ADDR["CYCLE_LO"], gap=gap)
        assert lo == count, b.fail(f"CYCLE_LO = {lo}, {count} clocks since reset release")
        assert await b.read("CYCLE_HI", gap=b.random_gap()) == 0
    assert count > 1000


@cocotb.test()
async def cycle_hi_snapshot(dut):
    """CYCLE_LO read copies the high word into CYCLE_HI: across 2^32 and 2^64 boundaries (counter
    deposited), CYCLE_HI alone or other reads do not update it, random 64-bit values are consistent."""
    b = Bench(dut, "cycle_hi_snapshot")
    await b.start()
    counter = dut.u_ctl.cycles

    def deposit(value: int) -> int:
        """Counter value before the next edge; returns that edge."""
        counter.value = value
        b.model.cycles = value
        return b.n + 1

    async def read64(gap: int) -> tuple[int, int, int]:
        lo_edge, lo, _ = await b.access(ADDR["CYCLE_LO"], gap=gap)
        hi = await b.read("CYCLE_HI", gap=b.random_gap())
        return lo_edge, lo, hi

    hi0 = 0x12345678
    first = deposit(hi0 << 32 | (WORD - 1))  # CYCLE_LO read at `first`: 0xFFFFFFFE, wraps 2 clocks later
    edge, lo, hi = await read64(0)
    assert (edge, lo, hi) == (first, WORD - 1, hi0), b.fail(f"before the carry: {lo:#x} {hi:#x}")
    assert b.n > edge + 2                                  # the live high word is hi0 + 1 by now
    assert await b.read("CYCLE_HI") == hi0, b.fail("CYCLE_HI followed the live counter")
    for name in ("ID", "CTRL", "CYCLE_HI", "UART_STATUS", "TRACE", "UART_DIV"):
        await b.read(name)
        assert await b.read("CYCLE_HI") == hi0, b.fail(f"CYCLE_HI changed by a read of {name}")
    edge, lo, hi = await read64(0)
    assert hi == hi0 + 1 and lo == edge - first - 2, b.fail(f"after the carry: {lo:#x} {hi:#x}")
    first = deposit((1 << 64) - 2)
    edge, lo, hi = await read64(0)
    assert (lo, hi) == (WORD - 1, WORD)
    edge, lo, hi = await read64(1)
    assert (lo, hi) == (edge - first - 2, 0), b.fail(f"after 2^64: {lo:#x} {hi:#x}")
    for _ in range(30):
        value = int(b.rng.integers(0, 1 << 63)) * 2 + int(b.rng.integers(0, 2))
        first = deposit(value)
        edge, lo, hi = await read64(int(b.rng.integers(0, 6)))
        expected = (value + edge - first) & ((1 << 64) - 1)
        assert hi << 32 | lo == expected, b.fail(f"deposit {value:#x}: read {hi:#x}:{lo:08x}, "
                                                 f"expected {expected:#x}")


@cocotb.test()
async def uart_frames(dut):
    """Random bytes at random UART_DIV (below 16 act as 16): the decoded line equals the accepted
    bytes, the start bit in the clock after the write edge; TX_BUSY for exactly 10 bit periods
    (probed at the last busy and the first idle edge); writes while busy ignored; a UART_DIV write
    during a frame only affects the next one."""
    b = Bench(dut, "uart_frames")
    await b.start()
    n_bytes = max(8, b.n_random // 50)
    modes = ("poll", "ignored_while_busy", "status_last_busy", "status_first_idle", "write_at_end",
             "back_to_back", "div_mid_frame")
    first = b.n + 1
    sent = []                 # (write edge, byte, period) of the bytes this test expects on the line
    ignored = 0
    div = REGISTERS["UART_DIV"]["reset"]   # the first byte at the reset value 434
    for i in range(n_bytes):
        if i:
            div = [0, 1, 15, 16, 17][i - 1] if i <= 5 else _random_div(b.rng)
            await b.write("UART_DIV", div | b.random_word() & 0xFFFF0000, b.random_strb())
            assert await b.read("UART_DIV") == div
        byte = int(b.rng.integers(0, 256))
        edge = await b.write("UART_DATA", byte | b.random_word() & 0xFFFFFF00, b.random_strb(),
                             gap=b.random_gap())
        p = uart_period(div)
        sent.append((edge, byte, p))
        end = edge + UART_FRAME_BITS * p      # first edge that sees the transmitter idle is end + 1
        assert b.line[edge] == 0, b.fail(f"no start bit in the clock after the write edge {edge}")
        assert await b.read("UART_STATUS") == 1, b.fail("TX_BUSY not set 2 clocks after the write")
        mode = modes[i % len(modes)]
        if mode == "ignored_while_busy":
            await b.write("UART_DATA", byte ^ 0xFF, at=int(b.rng.integers(b.n + 1, end + 1)))
            ignored += 1
        elif mode == "status_last_busy":
            assert await b.read("UART_STATUS", at=end) == 1, b.fail("TX_BUSY ended early")
        elif mode == "status_first_idle":
            assert await b.read("UART_STATUS", at=end + 1) == 0, b.fail("TX_BUSY too long")
        elif mode == "write_at_end":
            await b.write("UART_DATA", byte ^ 0x5A, at=end)
            ignored += 1
        elif mode == "back_to_back":
            byte2 = int(b.rng.integers(0, 256))
            sent.append((await b.write("UART_DATA", byte2, at=end + 1), byte2, p))
        elif mode == "div_mid_frame":
            await b.write("UART_DIV", 16 + int(b.rng.integers(1, 30)), at=int(b.rng.integers(b.n + 1, end)))
        while await b.read("UART_STATUS", gap=b.random_gap()):
            pass
    await b.uart_drain()
    await b.idle(3)
    decoded = decode_uart(b.line, first, [p for _, _, p in sent])
    assert decoded == [(edge, byte) for edge, byte, _ in sent], b.fail(f"line {decoded}, written {sent}")
    assert [(f.start, f.byte, f.period) for f in b.model.frames] == sent
    assert b.model.ignored == ignored
    cocotb.log.info(f"uart_frames: {len(sent)} bytes, {ignored} ignored writes, {b.n} clocks")


@cocotb.test()
async def trace_port(dut):
    """TRACE: each write (any strobes, back to back or spaced) gives one trace_valid pulse with the
    word in the clock after the write edge; TRACE reads 0 and a read gives no pulse."""
    b = Bench(dut, "trace_port")
    await b.start()
    written = []
    for i in range(60):
        if i % 7 == 3:
            assert await b.read("TRACE", gap=b.random_gap()) == 0
        data = [0, WORD][i] if i < 2 else b.random_word()
        written.append((await b.write("TRACE", data, b.random_strb(), gap=b.random_gap(),
                                      hold=bool(i % 2)), data))
    await b.idle(2)
    assert b.trace_log == written, b.fail(f"trace pulses {b.trace_log[:4]}..., writes {written[:4]}...")


@cocotb.test()
async def unmapped_and_write_only(dut):
    """Every unmapped word address reads 0 and ignores writes (of all ones and all zeros: no register,
    pulse or byte changes); the write-only UART_DATA and TRACE read 0."""
    b = Bench(dut, "unmapped_and_write_only")
    await b.start()
    await b.write("CTRL", 1)
    await b.write("UART_DIV", 0x1234)
    for addr in UNMAPPED:
        assert await b.read(addr, gap=b.random_gap()) == 0, b.fail(f"read of unmapped 0x{addr:02X}")
        for data in (WORD, 0):
            await b.write(addr, data, b.random_strb(), gap=b.random_gap())
    assert b.trace_log == [] and b.model.frames == [] and set(b.line[3:]) == {1}
    assert await b.read("CTRL") == 1 and await b.read("UART_DIV") == 0x1234
    for name in ("UART_DATA", "TRACE"):
        await b.write(name, WORD)
        assert await b.read(name) == 0, b.fail(f"write-only {name} does not read 0")
    for name in REGISTERS:
        await b.read(name)


@cocotb.test()
async def reset_mid_operation(dut):
    """A reset during a UART frame, with DSP_RUN set, UART_DIV changed and CYCLE_HI loaded: the line
    goes idle at the reset edge and every register is back at its reset value."""
    b = Bench(dut, "reset_mid_operation")
    await b.start()
    for clocks in (1, 3):
        await b.write("CTRL", 1)
        await b.write("UART_DIV", 20)
        b.model.cycles = 7 << 32
        dut.u_ctl.cycles.value = 7 << 32
        assert await b.read("CYCLE_LO") == 0
        assert await b.read("CYCLE_HI") == 7
        edge = await b.write("UART_DATA", 0x00)
        await b.write("TRACE", 0xCAFE)
        await b.idle(int(b.rng.integers(0, 150)))
        assert b.model.busy(b.n)
        await b.reset(clocks)
        assert b.line[b.n - clocks + 1:] == [1] * clocks and b.line[edge] == 0
        for name, reg in REGISTERS.items():
            _, data, count = await b.access(reg["addr"])
            expected = {"CYCLE_LO": count, "CYCLE_HI": 0, "UART_STATUS": 0}.get(name, reg["reset"])
            assert data == expected, b.fail(f"{name} after a reset: 0x{data:08X}, expected 0x{expected:08X}")


@cocotb.test()
async def random_accesses(dut):
    """HFI_RANDOM_N random reads and writes (mapped and unmapped addresses, random strobes, gaps of
    0-3 clocks, sel held or dropped after ready, rare resets) against the model in every clock."""
    b = Bench(dut, "random_accesses")
    await b.start()
    names = list(REGISTERS)
    kinds = {"read": 0, "write": 0, "reset": 0}
    for i in range(b.n_random):
        r = b.rng.random()
        addr = ADDR[names[int(b.rng.integers(0, len(names)))]] if r < 0.85 else int(b.rng.choice(UNMAPPED))
        if b.rng.random() < 0.005 or i == b.n_random // 2:
            kinds["reset"] += 1
            await b.reset(int(b.rng.integers(1, 3)))
            continue
        kw = dict(gap=b.random_gap(), hold=bool(b.rng.random() < 0.7))
        if b.rng.random() < 0.5:
            kinds["read"] += 1
            await b.access(addr, **kw)
            continue
        data = b.random_word()
        if addr == ADDR["UART_DIV"]:
            data = data & 0xFFFF0000 | _random_div(b.rng)
        kinds["write"] += 1
        await b.access(addr, data, b.random_strb(), **kw)
    await b.uart_drain()
    cocotb.log.info(f"random_accesses: {kinds}, {len(b.model.frames)} UART bytes, {b.model.ignored} "
                    f"ignored, {len(b.trace_log)} trace pulses, {b.n} clocks")
    if b.n_random >= COVERAGE_MIN_N:
        assert len(b.model.frames) > 0 and len(b.trace_log) > 0 and b.model.ignored > 0


# ---------------------------------------------------------------------- RAM tests
def read_hex_image(path: str) -> list[int]:
    """The $readmemh image: one 32-bit hex word per line, word 0 first."""
    with open(path) as f:
        return [int(line, 16) for line in f if line.strip()]


class RamModel:
    """Word array with byte-lane writes; a read returns the word as before the edge's write, except a read
    of the word written at the same edge: its value is undefined in the hardware (hfi_ram's header:
    `no_rw_check`, the SoC never uses it), so the model returns None (not checked)."""

    def __init__(self, words: list[int]):
        self.mem = list(words)

    def edge(self, wstrb: int, waddr: int, wdata: int, ren: int, raddr: int) -> int | None:
        rdata = self.mem[raddr] if ren and not (wstrb and raddr == waddr) else None
        lanes = sum(0xFF << 8 * k for k in range(4) if wstrb >> k & 1)
        self.mem[waddr] = self.mem[waddr] & ~lanes | wdata & lanes
        return rdata


async def ram_clock(b: Bench, ram: RamModel, **ports) -> None:
    """One RAM clock with these port values (ram_ prefix omitted); checks rdata if read."""
    b.ram_inputs.update({f"ram_{k}": v for k, v in ports.items()})
    await b.tick()
    exp = ram.edge(**ports)
    if exp is not None:
        got = int(b.dut.ram_rdata.value)
        assert got == exp, b.fail(f"ram_rdata = 0x{got:08X}, model 0x{exp:08X} (ports {ports})")


@cocotb.test()
async def ram_init_file(dut):
    """hfi_ram loads INIT_FILE with $readmemh: every word reads back, one per clock, in random order."""
    b = Bench(dut, "ram_init_file")
    await b.start()
    words = read_hex_image(os.environ["HFI_RAM_INIT"])
    assert len(words) == 1 << len(dut.ram_raddr), f"image of {len(words)} words"
    ram = RamModel(words)
    for a in b.rng.permutation(len(words)):
        await ram_clock(b, ram, wstrb=0, waddr=0, wdata=0, ren=1, raddr=int(a))


@cocotb.test()
async def ram_strobes_and_collisions(dut):
    """Random writes with every byte strobe pattern and reads, one clock latency; reads of the word written
    in the same clock happen often (not checked: undefined), and every later read of it sees the write
    (HFI_RANDOM_N clocks; a few hot addresses)."""
    b = Bench(dut, "ram_strobes_and_collisions")
    await b.start()
    ram = RamModel(read_hex_image(os.environ["HFI_RAM_INIT"]))
    n_words = len(ram.mem)
    hot = b.rng.choice(n_words, size=4, replace=False)
    seen_strb, same = set(), 0

    def address() -> int:
        return int(b.rng.choice(hot)) if b.rng.random() < 0.6 else int(b.rng.integers(0, n_words))

    for _ in range(b.n_random):
        wstrb, waddr, ren = int(b.rng.integers(0, 16)), address(), int(b.rng.random() < 0.8)
        raddr = waddr if b.rng.random() < 0.3 else address()
        seen_strb.add(wstrb)
        same += bool(ren and wstrb and raddr == waddr)
        await ram_clock(b, ram, wstrb=wstrb, waddr=waddr, wdata=b.random_word(), ren=ren, raddr=raddr)
    for a in range(n_words):  # the final contents
        await ram_clock(b, ram, wstrb=0, waddr=0, wdata=0, ren=1, raddr=a)
    cocotb.log.info(f"ram: {b.n_random} clocks, {same} reads of the word written in the same clock")
    if b.n_random >= COVERAGE_MIN_N:
        assert seen_strb == set(range(16)) and same > b.n_random // 10
