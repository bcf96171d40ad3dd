"""Minimal cocotb AXI4-Lite master (our own code), shared by the hfi_regs and hfi_dsp testbenches.

``AxiLiteMaster(dut, prefix="s_axil", clk=dut.clk)`` drives ``<prefix>_aw*/w*/b*/ar*/r*``:

* ``await write(addr, data, strb=0xF) -> bresp`` and ``await read(addr) -> (rdata, rresp)``.
* Timing: inputs change right after a rising edge; ``ReadOnly`` of the same time step samples the
  slave's (possibly combinational) READY/VALID, so a handshake is recognised for the edge that follows.
  AWVALID and WVALID are presented together (unless ``aw_delay``/``w_delay`` skew them) and each is
  held until its own handshake; BREADY/RREADY rise in the clock after the request handshake (the
  earliest a response can come) or ``bready_delay``/``rready_delay`` clocks later, and fall after the
  response handshake (one transaction outstanding per direction). A call returns just after the edge of its
  last handshake, so calls issued back to back give back-to-back transactions. Call from a writable
  phase (after an edge or a Timer; from ``ReadOnly`` it first waits for the next rising edge).
* Reads and writes have separate locks, so one read and one write may run concurrently.
* ``aw_time``/``ar_time``: simulation time (steps) of the rising edge of the last AW/W and AR
  handshakes (the edge at which the slave took the request).
* Checks: a slave that does not answer within ``timeout`` cycles raises ``AxiLiteTimeout``; BVALID or
  RVALID before the request was accepted, and a response that drops or changes while the master
  stalls READY, raise ``AxiLiteProtocolError``.
"""

from __future__ import annotations

from cocotb.simtime import get_sim_time
from cocotb.triggers import Lock, ReadOnly, RisingEdge, current_gpi_trigger


class AxiLiteTimeout(AssertionError):
    """The slave did not complete a handshake within the timeout."""


class AxiLiteProtocolError(AssertionError):
    """The slave violated the AXI4-Lite handshake rules."""


class AxiLiteMaster:
    def __init__(self, dut, prefix: str = "s_axil", clk=None, timeout: int = 1000):
        s = {n: getattr(dut, f"{prefix}_{n}") for n in (
            "awaddr", "awvalid", "awready", "wdata", "wstrb", "wvalid", "wready", "bresp", "bvalid",
            "bready", "araddr", "arvalid", "arready", "rdata", "rresp", "rvalid", "rready")}
        self.__dict__.update(s)
        self.clk = clk if clk is not None else dut.clk
        self.prefix, self.timeout = prefix, timeout
        self._edge, self._ro = RisingEdge(self.clk), ReadOnly()
        self._wlock, self._rlock = Lock(f"{prefix}_wr"), Lock(f"{prefix}_rd")
        self.aw_time = self.ar_time = None
        self.idle()

    def idle(self) -> None:
        """Drive the master's outputs idle (VALIDs and READYs low), e.g. after a reset."""
        for sig in (self.awvalid, self.wvalid, self.bready, self.arvalid, self.rready):
            sig.value = 0

    async def _writable(self) -> None:
        if isinstance(current_gpi_trigger(), ReadOnly):
            await self._edge

    def _fail(self, what: str, addr: int, cycles: int) -> None:
        self.idle()
        raise AxiLiteTimeout(f"{self.prefix}: no {what} for address 0x{addr:X} within {cycles} cycles")

    async def write(self, addr: int, data: int, strb: int = 0xF, *, aw_delay: int = 0, w_delay: int = 0,
                    bready_delay: int = 0) -> int:
        """Write ``data`` (byte lanes ``strb``) at ``addr``; returns BRESP (0 OKAY, 2 SLVERR)."""
        async with self._wlock:
            await self._writable()
            self.awaddr.value, self.wdata.value, self.wstrb.value = addr, data, strb
            aw_wait, w_wait = aw_delay, w_delay     # cycles before presenting; -1: handshake done
            b_wait = None                           # cycles before BREADY, counted from the handshakes
            held = None                             # (bresp) seen while BREADY is low
            self.awvalid.value, self.wvalid.value, self.bready.value = int(aw_wait == 0), int(w_wait == 0), 0
            for _ in range(self.timeout):
                if b_wait == 0:
                    self.bready.value = 1
                await self._ro
                aw_hs = aw_wait == 0 and self.awready.value == 1
                w_hs = w_wait == 0 and self.wready.value == 1
                bvalid = self.bvalid.value == 1
                if bvalid and b_wait is None:
                    raise AxiLiteProtocolError(f"{self.prefix}: BVALID before AW/W accepted (0x{addr:X})")
                if held is not None and not bvalid:
                    raise AxiLiteProtocolError(f"{self.prefix}: BVALID dropped before BREADY (0x{addr:X})")
                if bvalid:
                    resp = int(self.bresp.value)
                    if held is not None and resp != held:
                        raise AxiLiteProtocolError(f"{self.prefix}: BRESP changed while BVALID waited")
                    held = resp
                await self._edge
                if bvalid and b_wait == 0:
                    self.bready.value = 0
                    return resp
                if b_wait is not None and b_wait > 0:
                    b_wait -= 1
                if aw_hs:
                    self.awvalid.value, aw_wait, self.aw_time = 0, -1, get_sim_time()
                elif aw_wait > 0:
                    aw_wait -= 1
                    self.awvalid.value = int(aw_wait == 0)
                if w_hs:
                    self.wvalid.value, w_wait = 0, -1
                elif w_wait > 0:
                    w_wait -= 1
                    self.wvalid.value = int(w_wait == 0)
                if b_wait is None and aw_wait < 0 and w_wait < 0:
                    b_wait = bready_delay
            self._fail("write response" if b_wait is not None else "AWREADY/WREADY", addr, self.timeout)

    async def read(self, addr: int, *, rready_delay: int = 0) -> tuple[int, int]:
        """Read ``addr``; returns ``(RDATA, RRESP)``."""
        async with self._rlock:
            await self._writable()
            self.araddr.value, self.arvalid.value, self.rready.value = addr, 1, 0
            r_wait = None
            held = None
            for _ in range(self.timeout):
                if r_wait == 0:
                    self.rready.value = 1
                await self._ro
                ar_hs = r_wait is None and self.arready.value == 1
                rvalid = self.rvalid.value == 1
                if rvalid and r_wait is None:
                    raise AxiLiteProtocolError(f"{self.prefix}: RVALID before AR accepted (0x{addr:X})")
                if held is not None and not rvalid:
                    raise AxiLiteProtocolError(f"{self.prefix}: RVALID dropped before RREADY (0x{addr:X})")
                if rvalid:
                    resp = (int(self.rdata.value), int(self.rresp.value))
                    if held is not None and resp != held:
                        raise AxiLiteProtocolError(f"{self.prefix}: RDATA/RRESP changed while RVALID waited")
                    held = resp
                await self._edge
                if rvalid and r_wait == 0:
                    self.rready.value = 0
                    return resp
                if r_wait is not None and r_wait > 0:
                    r_wait -= 1
                if ar_hs:
                    self.arvalid.value, r_wait, self.ar_time = 0, rready_delay, get_sim_time()
            self._fail("read data" if r_wait is not None else "ARREADY", addr, self.timeout)
