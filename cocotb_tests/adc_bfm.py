"""Bus-functional model of a serial, three-channel, simultaneous-sampling SAR ADC (cocotb).

The ADC class of ``rtl/hfi_adc_if.v`` (AD7380-4/AD7381-4 class): a CONVST rising edge samples the three
channels (phase currents A and B, the dc-link voltage C) and starts the conversion (``t_CONV``); then,
while CS is low, the three results are shifted out MSB first on three data lanes (SDOA, SDOB, SDOC) with
one common SCLK that idles low. The ADC drives a new bit after every SCLK falling edge, on every lane at
once: the lanes differ only in their data.

Data timing (worst case of the part class, the same on every lane): bit ``k`` (``k = 0`` is the MSB) is
driven *valid* only from SCLK rising edge ``k`` until just after SCLK falling edge ``k``; at every other
time (CS high, between CS falling and the first rising edge, in each SCLK low phase) each lane carries
its own random garbage (independent bits per lane). A host that samples a lane anywhere but in the SCLK
high phase or at the falling edge itself reads garbage, so the BFM checks the sampling instant of the
interface, not only its bit order.

Protocol checks (each one is an error; with ``raise_on_error`` the BFM raises :class:`AdcProtocolError`
from its monitor task, which fails the running cocotb test with the message):

* CONVST rising while the ADC is busy: converting (less than ``conv_ticks`` clocks since the last
  CONVST rising edge), reading (CS low) or within ``quiet_ticks`` clocks after CS rose (``t_QUIET``);
* CS falling without a conversion, or before the conversion finished (``t_CONV``), or with SCLK high;
* SCLK faster than allowed: a high or low phase (including CS falling to the first rising edge)
  shorter than ``sclk_half`` clocks;
* SCLK toggling while CS is high, more than ``bits`` SCLK pulses in one frame;
* CS rising before all ``bits`` bits were clocked out (an aborted read), unless :attr:`abort_allowed`
  is set: the test sets it while it resets the host (see the RTL header), and then an SCLK falling
  edge in the same time step as the CS rising edge is accepted too;
* a conversion without a code to convert (empty queue).

A conversion's codes are a triple ``(code_a, code_b, code_c)``, one unsigned ``bits``-bit code per lane
(A, B: the phase currents, offset binary; C: the dc-link voltage, unipolar; the BFM does not interpret
them). They come from a queue (``codes=[(a, b, c), ...]``, :meth:`push`) or from a callback
``codes_at(convst_cycle) -> (code_a, code_b, code_c)`` called at each CONVST rising edge (the replay test
of the whole IP returns the golden ADC codes of the sampling tick ``convst_cycle - 1``, docs/rtl.md).
Anything but three integers in ``0 .. 2**bits - 1`` raises ``ValueError`` (from :meth:`push` or the
constructor for the queue, from the monitor task for ``codes_at``): a test error, not a protocol error. Cycle
numbers are counted in clock periods from :attr:`origin` (simulation steps, set by
:meth:`set_cycle_origin` at the rising clock edge that starts cycle 0, i.e. tick 0); every CONVST rising
edge is recorded in :attr:`convst_cycles`, every conversion with its codes in :attr:`converted`.

The BFM only reacts to edges of CONVST, CS and SCLK (no per-clock wake-ups): about ``2*bits + 3``
Python wake-ups per conversion. Start it (:meth:`start`) once the host's outputs are out of reset.
The lanes are written as immediate deposits right after the host clock edge that moved SCLK or CS, so
the host's input registers sample them at the next edge.

Example (the whole-IP replay test)::

    bfm = AdcBfm(dut.adc_convst, dut.adc_cs_n, dut.adc_sclk, dut.adc_sdo_a, dut.adc_sdo_b, dut.adc_sdo_c,
                 bits=12, conv_ticks=12, sclk_half=1, codes_at=lambda cyc: golden_codes[cyc - 1])
    bfm.set_cycle_origin()      # at the rising clock edge that begins tick 0
    bfm.start()
"""

from __future__ import annotations

import random
from collections import deque
from typing import Callable, Iterable

import cocotb
from cocotb.handle import Immediate
from cocotb.triggers import FallingEdge, RisingEdge, ValueChange
from cocotb.types import Logic
from cocotb.utils import get_sim_steps

_now = cocotb.simulator.get_sim_time
_LEVEL = (Logic(0), Logic(1))
LANES = ("a", "b", "c")
"""The data lanes, in the order of a conversion's code triple (SDOA, SDOB, SDOC)."""

Codes = tuple[int, int, int]
"""One conversion: ``(code_a, code_b, code_c)``."""


def now_steps() -> int:
    """Current simulation time in simulator steps (an int)."""
    high, low = _now()
    return high << 32 | low


class AdcProtocolError(Exception):
    """A protocol or timing violation seen by :class:`AdcBfm`."""


class AdcBfm:
    """Serial three-lane simultaneous-sampling SAR ADC.

    Parameters
    ----------
    convst, cs_n, sclk :
        Handles of the host's outputs (watched).
    sdo_a, sdo_b, sdo_c :
        Handles of the host's data inputs (driven): lanes A, B (phase currents) and C (dc link).
    bits, conv_ticks, sclk_half :
        Resolution, minimum conversion time and minimum SCLK half period, the latter two in periods
        of the host clock (``clk_period_ns``).
    codes, codes_at :
        A queue of ``(code_a, code_b, code_c)`` triples, or a callback from the CONVST cycle to the
        triple (at most one of them; the queue can also be filled later with :meth:`push`).
    quiet_ticks :
        Minimum time from CS rising to the next CONVST rising edge (``t_QUIET``), in clocks.
    raise_on_error :
        Raise :class:`AdcProtocolError` at the first violation (default); else only record it in
        :attr:`errors`.
    seed :
        Seed of the garbage on the data lanes.
    """

    def __init__(self, convst, cs_n, sclk, sdo_a, sdo_b, sdo_c, *, bits: int, conv_ticks: int, sclk_half: int,
                 codes: Iterable[Codes] | None = None,
                 codes_at: Callable[[int], Codes] | None = None,
                 clk_period_ns: float = 10, quiet_ticks: int = 1, raise_on_error: bool = True,
                 seed: int = 0, name: str = "adc"):
        if not 1 <= bits <= 16 or conv_ticks < 1 or sclk_half < 1 or quiet_ticks < 0:
            raise ValueError(f"bad ADC parameters bits={bits} conv_ticks={conv_ticks} "
                             f"sclk_half={sclk_half} quiet_ticks={quiet_ticks}")
        if codes is not None and codes_at is not None:
            raise ValueError("give a code queue or a codes_at callback, not both")
        self.convst, self.cs_n, self.sclk = convst, cs_n, sclk
        self.sdo_a, self.sdo_b, self.sdo_c = sdo_a, sdo_b, sdo_c
        self._lanes = (sdo_a, sdo_b, sdo_c)
        self.bits, self.conv_ticks, self.sclk_half = bits, conv_ticks, sclk_half
        self.name = name
        self.raise_on_error = raise_on_error
        self.codes_at = codes_at
        self.queue: deque[Codes] = deque(self._checked(c, "queued") for c in (codes or ()))
        self.period = get_sim_steps(clk_period_ns, "ns")
        self.t_conv = conv_ticks * self.period
        self.t_half = sclk_half * self.period
        self.t_quiet = quiet_ticks * self.period
        self.origin = 0
        self.abort_allowed = False
        self._rng = random.Random(seed)
        # records
        self.convst_cycles: list[int] = []     # cycle of every CONVST rising edge
        self.converted: list[tuple[int, int, int, int]] = []   # (cycle, code_a, code_b, code_c) per conversion
        self.reads = 0                         # complete reads (all bits clocked out, CS rose)
        self.aborts = 0                        # reads ended early by CS (allowed)
        self.errors: list[str] = []
        # state
        self._conv_start: int | None = None    # time of the last CONVST rising edge
        self._result: Codes | None = None      # converted, not yet read
        self._frame = False                    # CS low
        self._cs_rise = None                   # time CS last rose
        self._last_edge = 0                    # time of the last SCLK edge or CS falling edge
        self._rises = 0                        # SCLK rising edges in this frame
        self._falls = 0                        # SCLK falling edges in this frame
        self._words: Codes = (0, 0, 0)         # the codes being read out (A, B, C)
        self._sdo = (-1, -1, -1)               # levels driven on the lanes (A, B, C)
        self._tasks = []

    # ---------------------------------------------------------------- control
    def start(self) -> "AdcBfm":
        """Start the monitors (and drive garbage on the data lanes)."""
        self._sdo = (-1, -1, -1)
        self._garbage()
        self._tasks = [cocotb.start_soon(self._convst_monitor()), cocotb.start_soon(self._cs_monitor()),
                       cocotb.start_soon(self._sclk_monitor())]
        return self

    def stop(self) -> None:
        for task in self._tasks:
            task.cancel()
        self._tasks = []

    def set_cycle_origin(self, steps: int | None = None) -> None:
        """Cycle 0 starts now (call at the rising clock edge that begins tick 0) or at ``steps``."""
        self.origin = now_steps() if steps is None else steps

    def cycle(self, steps: int | None = None) -> int:
        """Clock cycle (from :attr:`origin`) of the time ``steps`` (default: now)."""
        t = now_steps() if steps is None else steps
        return (t - self.origin) // self.period

    def push(self, code_a: int, code_b: int, code_c: int) -> None:
        """Queue the codes of one future conversion (lanes A, B, C)."""
        self.queue.append(self._checked((code_a, code_b, code_c), "pushed"))

    def check_clean(self) -> None:
        """Raise :class:`AdcProtocolError` listing the recorded errors, if any."""
        if self.errors:
            raise AdcProtocolError(f"{self.name}: {len(self.errors)} protocol errors, first: "
                                   + "; ".join(self.errors[:5]))

    # ---------------------------------------------------------------- internals
    def _error(self, msg: str) -> None:
        text = f"{self.name} ADC protocol error at cycle {self.cycle()}: {msg}"
        self.errors.append(text)
        if self.raise_on_error:
            raise AdcProtocolError(text)

    def _checked(self, codes, what: str, cycle: int | None = None) -> Codes:
        """``codes`` as a triple of ints in 0 .. 2**bits - 1, else ValueError."""
        where = "" if cycle is None else f" for CONVST cycle {cycle}"
        try:
            triple = tuple(int(v) for v in codes)
        except (TypeError, ValueError):
            raise ValueError(f"{self.name}: {what} codes {codes!r}{where} are not integers") from None
        if len(triple) != len(LANES):
            raise ValueError(f"{self.name}: {what} codes {triple}{where}: expected {len(LANES)} "
                             f"(code_a, code_b, code_c)")
        top = (1 << self.bits) - 1
        if not all(0 <= v <= top for v in triple):
            raise ValueError(f"{self.name}: {what} codes {triple}{where} outside 0..{top}")
        return triple

    def _drive(self, levels: tuple[int, int, int]) -> None:
        """Drive the data lanes (A, B, C): only what changes, as immediate deposits (no ReadWrite
        phase per edge). Safe: the BFM writes right after a host clock edge, whose flip-flops have sampled."""
        for lane, new, old in zip(self._lanes, levels, self._sdo):
            if new != old:
                lane.set(Immediate(_LEVEL[new]))
        self._sdo = levels

    def _garbage(self) -> None:
        """Random levels on every lane, independent per lane (the bits are not valid now)."""
        bits = self._rng.getrandbits(len(LANES))
        self._drive(tuple((bits >> i) & 1 for i in range(len(LANES))))

    async def _convst_monitor(self) -> None:
        edge = RisingEdge(self.convst)
        while True:
            await edge
            now = now_steps()
            cyc = self.cycle(now)
            if self._conv_start is not None and now - self._conv_start < self.t_conv:
                self._error(f"CONVST rose while converting ({now - self._conv_start} of "
                            f"{self.t_conv} steps of t_CONV since the last CONVST)")
            if self._frame:
                self._error("CONVST rose while CS is low (read in progress)")
            if self._cs_rise is not None and now - self._cs_rise < self.t_quiet:
                self._error(f"CONVST rose {now - self._cs_rise} steps after CS rose (t_QUIET "
                            f"{self.t_quiet} steps)")
            if self.codes_at is not None:
                codes = self._checked(self.codes_at(cyc), "codes_at", cyc)
            elif self.queue:
                codes = self.queue.popleft()
            else:
                codes = None
                self._error("CONVST with no codes queued")
            self.convst_cycles.append(cyc)
            self._conv_start = now
            self._result = codes
            if codes is not None:
                self.converted.append((cyc, *codes))

    async def _cs_monitor(self) -> None:
        edge = ValueChange(self.cs_n)
        while True:
            await edge
            now = now_steps()
            if not self.cs_n.value:                       # CS falling: start of a read frame
                if self._result is None:
                    self._error("CS fell without a conversion to read")
                elif now - self._conv_start < self.t_conv:
                    self._error(f"CS fell {now - self._conv_start} steps after CONVST, before the "
                                f"conversion finished (t_CONV {self.t_conv} steps)")
                if self.sclk.value:
                    self._error("CS fell with SCLK high (SCLK must idle low)")
                self._frame = True
                self._rises = self._falls = 0
                self._last_edge = now
                self._words = self._result if self._result is not None else (0, 0, 0)
                self._result = None
                self._garbage()
            else:                                         # CS rising: end of the frame
                if self._frame:
                    if self._falls < self.bits or self._rises != self._falls:
                        if self.abort_allowed:
                            self.aborts += 1
                        else:
                            self._error(f"CS rose after {self._falls} of {self.bits} bits "
                                        f"(SCLK rising edges {self._rises}): incomplete read")
                    else:
                        self.reads += 1
                self._frame = False
                self._cs_rise = now
                self._garbage()

    async def _sclk_monitor(self) -> None:
        rise, fall = RisingEdge(self.sclk), FallingEdge(self.sclk)
        top = self.bits - 1
        try:
            high = bool(self.sclk.value)
        except ValueError:                     # X before the host's reset: treat as idle (low)
            high = False
        while True:
            await (fall if high else rise)     # a 0/1 signal: rising and falling edges alternate
            high = not high
            now = now_steps()
            if not self._frame:
                if not high and now == self._cs_rise and self.abort_allowed:
                    continue              # a host reset ends the frame: CS rises as SCLK falls
                if not self.cs_n.value:   # CS fell in this very time step and its monitor runs later
                    self._error("SCLK edge at the CS falling edge")
                else:
                    self._error(f"SCLK {'rose' if high else 'fell'} while CS is high")
                continue
            dt = now - self._last_edge
            if dt < self.t_half:
                what = ("CS falling to the first SCLK rising edge" if high and self._rises == 0
                        else "SCLK low time" if high else "SCLK high time")
                self._error(f"{what} {dt} steps < {self.t_half} steps (SCLK faster than allowed)")
            self._last_edge = now
            if high:
                k = self._rises
                self._rises += 1
                if k > top:
                    self._error(f"SCLK pulse {k + 1} in a frame of {self.bits} bits")
                    continue
                # bit k valid from this rising edge until just after the next falling edge (every lane)
                self._drive(tuple((w >> (top - k)) & 1 for w in self._words))
            else:
                self._falls += 1
                self._garbage()
