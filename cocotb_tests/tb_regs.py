"""cocotb testbench of rtl/hfi_regs.v (run by cocotb_tests/test_regs.py, not by pytest).

The reference is a transaction-level Python model built from ``golden.regmap.REGISTERS`` (addresses,
fields, resets, access types), not from the Verilog; the only testbench knowledge is the table below
mapping each field to its port of hfi_regs (checked to cover every field of the map).

Timing contract checked exactly (times of the AXI handshakes recorded by the driver):
* a write takes effect at the edge of its AW/W handshake; a read returns the registers and hardware
  inputs as they were just before the edge of its AR handshake (a read and a write accepted at the
  same edge: the read sees the old value);
* w1p fields (CTRL.FAULT_CLEAR, COMMIT.GO): a one-clock pulse starting at the handshake edge of a
  write that has the bit set (and its byte strobe on), none otherwise;
* IRQ_STATUS.WINDOW set at the edge that samples ``irq_window_set`` = 1, cleared by a write of 1 at
  its handshake edge, set wins over a simultaneous clear; ``irq`` = status & enable one clock later;
* w1s fields (SAFETY_LOCK.LOCK): a write of 1 (byte strobe on) sets the field at its handshake edge,
  0 has no effect, only rst clears it;
* locks (``golden.regmap.LOCKED_BY``): while the lock field is 1 (as before the write's edge), a
  write to a register with a locked field changes nothing in that register (whatever WDATA and WSTRB,
  also no w1p pulse) and answers SLVERR.
"""

from __future__ import annotations

import os

import cocotb
import numpy as np
from cocotb.clock import Clock
from cocotb.simtime import get_sim_time
from cocotb.triggers import ClockCycles, ReadOnly, RisingEdge, ValueChange

from axil_driver import AxiLiteMaster
from golden.regmap import LOCKED_BY, REGISTERS

OKAY, SLVERR = 0, 2
ACCEPT_CLOCKS = 1
"""rtl/hfi_regs.v registers AW/W (and AR) before it accepts them: the handshake is one edge after the
edge that first sees the valids (the only timing of the slave the testbench knows besides the table)."""

# Field -> port of hfi_regs. rw fields: the output carrying the stored value (None: no hardware
# port, e.g. the SPEED_REF mailbox; IRQ_ENABLE is seen through `irq`); ro fields without a reset: the
# hardware input shown in the field; w1p fields: the pulse output; w1c fields: the hardware set input.
RW_PORTS = {
    ("CTRL", "ENABLE"): "ctrl_enable", ("CTRL", "INJ_EN"): "ctrl_inj_en",
    ("CTRL", "ADC_MODE"): "ctrl_adc_mode", ("CTRL", "INJ_ROT"): "ctrl_inj_rot", ("CTRL", "INJ_PER"): "ctrl_inj_per",
    ("CTRL", "DIRECT"): "ctrl_direct",
    ("IRQ_ENABLE", "WINDOW"): None,
    ("PWM_HALF", "VALUE"): "pwm_half", ("DEAD_TICKS", "VALUE"): "dead_ticks",
    ("OS_TICKS", "VALUE"): "os_ticks", ("BLANK_TICKS", "VALUE"): "blank_ticks",
    ("CW_ANGLE_STEP", "VALUE"): "cw_angle_step",
    ("ADC_OFFSET", "A"): "adc_offset_a", ("ADC_OFFSET", "B"): "adc_offset_b",
    ("ADC_GAIN", "A"): "adc_gain_a", ("ADC_GAIN", "B"): "adc_gain_b",
    ("OC_LIMIT", "VALUE"): "oc_limit", ("WDT_PERIODS", "VALUE"): "wdt_periods",
    ("V_DQ", "V_D"): "v_d", ("V_DQ", "V_Q"): "v_q", ("V_H", "VALUE"): "v_h",
    ("SINCOS", "SIN"): "sin_q15", ("SINCOS", "COS"): "cos_q15",
    ("SPEED_REF", "VALUE"): None,
    ("DTC_GAIN", "VALUE"): "dtc_gain", ("HF_AMP", "VALUE"): "hf_amp", ("RECIP_H", "VALUE"): "recip_h",
    ("I_REF", "I_D"): "i_d_ref", ("I_REF", "I_Q"): "i_q_ref", ("INJ_STEP", "VALUE"): "inj_step",
    ("CIC_M", "VALUE"): "cic_m",
    ("FCS_A", "A1"): "fcs_a1", ("FCS_A", "A2"): "fcs_a2",
    ("FCS_CTRL", "PHI_MIN"): "fcs_phi_min", ("FCS_CTRL", "CONSTRAIN"): "fcs_constrain",
}
HW_PORTS = {
    ("STATUS", "FAULT_OC"): "status_fault_oc", ("STATUS", "FAULT_WDT"): "status_fault_wdt",
    ("STATUS", "OUTPUTS_ON"): "status_outputs_on", ("STATUS", "COMMIT_PENDING"): "status_commit_pending",
    ("STATUS", "FAULT_STO"): "status_fault_sto", ("STATUS", "FAULT_DESAT"): "status_fault_desat",
    ("STATUS", "STO_ACTIVE"): "status_sto_active", ("STATUS", "DESAT_ACTIVE"): "status_desat_active",
    ("GAMMA", "VALUE"): "gamma", ("GAMMA_D", "VALUE"): "gamma_d", ("SUM_ID", "VALUE"): "sum_id",
    ("SUM_IQ", "VALUE"): "sum_iq", ("WSUM", "VALUE"): "wsum", ("N_SAMPLES", "VALUE"): "n_samples",
    ("WINDOW_COUNT", "VALUE"): "window_count", ("LATE_COUNT", "VALUE"): "late_count",
    ("INJ_PHASE", "VALUE"): "inj_phase", ("CIC_QA", "VALUE"): "cic_qa", ("CIC_QB", "VALUE"): "cic_qb",
    ("ENV_A", "VALUE"): "env_a", ("ENV_B", "VALUE"): "env_b",
    ("VECTOR", "STATE"): "vector_state", ("VECTOR", "NEXT"): "vector_next",
    ("TOP_I", "I_ALPHA"): "top_i_alpha", ("TOP_I", "I_BETA"): "top_i_beta",
    ("VDC", "CODE"): "vdc_code",
    ("WIN_FAULT", "OC"): "win_fault_oc", ("WIN_FAULT", "WDT"): "win_fault_wdt",
    ("WIN_FAULT", "STO"): "win_fault_sto", ("WIN_FAULT", "DESAT"): "win_fault_desat",
    ("WIN_ADC", "FROZEN_A"): "win_adc_frozen_a", ("WIN_ADC", "FROZEN_B"): "win_adc_frozen_b",
}
PULSE_PORTS = {("CTRL", "FAULT_CLEAR"): "fault_clear", ("COMMIT", "GO"): "commit_go"}
SET_PORTS = {("IRQ_STATUS", "WINDOW"): "irq_window_set"}
W1S_PORTS = {("SAFETY_LOCK", "LOCK"): None}   # w1s fields: no hardware port (the lock acts inside hfi_regs)
IRQ_PAIR = ("IRQ_STATUS", "IRQ_ENABLE")  # irq = |(IRQ_STATUS & IRQ_ENABLE) over same-named fields


def _mask(width: int, lsb: int = 0) -> int:
    return ((1 << width) - 1) << lsb


def _byte_mask(strb: int) -> int:
    return sum(0xFF << (8 * i) for i in range(4) if strb >> i & 1)


class RegModel:
    """Register file of golden.regmap.REGISTERS at transaction level."""

    def __init__(self):
        self.by_addr = {r["addr"]: name for name, r in REGISTERS.items()}
        for name, reg in REGISTERS.items():
            for field, (lsb, width, reset, access) in reg["fields"].items():
                key = (name, field)
                known = {"rw": RW_PORTS, "w1p": PULSE_PORTS, "w1c": SET_PORTS, "w1s": W1S_PORTS}.get(access)
                if access == "ro":
                    known = HW_PORTS if reset is None else {key: None}
                assert known is not None, f"{name}.{field}: access {access!r} not modelled by tb_regs"
                assert key in known, f"{name}.{field} ({access}) has no port in tb_regs' field->port table"
        for key, lock in LOCKED_BY.items():
            assert key[1] in REGISTERS[key[0]]["fields"], f"LOCKED_BY: unknown field {key}"
            lsb, width, reset, access = REGISTERS[lock[0]]["fields"][lock[1]]
            assert width == 1 and access == "w1s", f"LOCKED_BY: lock {lock} is not a 1-bit w1s field"
        # register -> its lock fields (a register is locked as a whole: any locked field freezes it)
        self.locks = {}
        for (reg, _field), lock in LOCKED_BY.items():
            self.locks.setdefault(reg, set()).add(lock)
        self.hw = {key: 0 for key in HW_PORTS}
        self.reset()

    def reset(self) -> None:
        self.store = {(name, f): reset for name, r in REGISTERS.items()
                      for f, (_, _, reset, access) in r["fields"].items() if access in ("rw", "w1c", "w1s")}

    def locked(self, name: str) -> bool:
        """Whether writes to register ``name`` are refused now (one of its lock fields is 1)."""
        return any(self.store[lock] for lock in self.locks.get(name, ()))

    def known(self, addr: int) -> bool:
        return addr in self.by_addr

    def read(self, addr: int) -> tuple[int, int]:
        name = self.by_addr.get(addr)
        if name is None:
            return 0, SLVERR
        value = 0
        for field, (lsb, width, reset, access) in REGISTERS[name]["fields"].items():
            if access in ("rw", "w1c", "w1s"):
                v = self.store[(name, field)]
            elif access == "ro":
                v = reset if reset is not None else self.hw[(name, field)]
            else:  # w1p reads 0
                v = 0
            value |= v << lsb
        return value, OKAY

    def write(self, addr: int, data: int, strb: int, set_also: bool = False) -> tuple[int, list]:
        """Apply a write; returns (BRESP, [w1p (reg, field) pulsed]). ``set_also``: the hardware set
        of the w1c fields at the same edge."""
        name = self.by_addr.get(addr)
        pulses = []
        locked = name is not None and self.locked(name)
        if name is not None and not locked:
            bmask = _byte_mask(strb)
            for field, (lsb, width, reset, access) in REGISTERS[name]["fields"].items():
                m = _mask(width, lsb) & bmask
                key = (name, field)
                if access == "rw":
                    self.store[key] = ((self.store[key] << lsb & ~m | data & m) >> lsb) & _mask(width)
                elif access == "w1c":
                    self.store[key] &= ~((data & m) >> lsb)
                elif access == "w1s":
                    self.store[key] |= (data & m) >> lsb
                elif access == "w1p" and data & m:
                    pulses.append(key)
        if set_also:
            self.hw_set()
        return (OKAY if name is not None and not locked else SLVERR), pulses

    def hw_set(self) -> None:
        for key in SET_PORTS:
            self.store[key] = 1

    def irq(self) -> int:
        st, en = IRQ_PAIR
        return int(any(self.store[(st, f)] & self.store.get((en, f), 0) for (r, f) in SET_PORTS if r == st))


class TransitionLog:
    """Records (time, value) of every change of a 1-bit signal."""

    def __init__(self, sig):
        self.sig, self.events = sig, []
        self.task = cocotb.start_soon(self._run())

    async def _run(self):
        change = ValueChange(self.sig)
        while True:
            await change
            self.events.append((get_sim_time(), int(self.sig.value)))


class Bench:
    def __init__(self, dut, name: str):
        self.dut = dut
        self.seed = int(os.environ["HFI_SEED"])
        self.n = int(os.environ["HFI_RANDOM_N"])
        self.rng = np.random.default_rng(self.seed)
        self.addr_bits = len(dut.s_axil_awaddr)
        cocotb.log.info(f"{name}: HFI_SEED={self.seed} HFI_RANDOM_N={self.n} ADDR_BITS={self.addr_bits}")
        self.model = RegModel()
        self.edge = RisingEdge(dut.clk)
        self.ro = ReadOnly()
        for (reg, field), port in {**RW_PORTS, **HW_PORTS, **PULSE_PORTS, **SET_PORTS}.items():
            if port is not None:
                width = REGISTERS[reg]["fields"][field][1]
                assert len(getattr(dut, port)) == width, \
                    f"port {port}: {len(getattr(dut, port))} bits, field {reg}.{field} has {width}"
        self.rw_ports = [(key, getattr(dut, p)) for key, p in RW_PORTS.items() if p is not None]
        self.hw_ports = [(key, getattr(dut, p), REGISTERS[key[0]]["fields"][key[1]][1])
                         for key, p in HW_PORTS.items()]
        self.expected_pulses = {key: [] for key in PULSE_PORTS}

    async def start(self):
        dut = self.dut
        Clock(dut.clk, 10, unit="ns", impl="gpi").start()
        dut.rst.value = 1
        dut.irq_window_set.value = 0
        self.axi = AxiLiteMaster(dut, "s_axil", dut.clk)
        self.randomize_hw()
        await ClockCycles(dut.clk, 3)
        dut.rst.value = 0
        t0 = get_sim_time()
        await self.edge
        self.period = get_sim_time() - t0
        self.pulse_logs = {key: TransitionLog(getattr(dut, p)) for key, p in PULSE_PORTS.items()}
        self.irq_log = TransitionLog(dut.irq)

    def randomize_hw(self, special: int | None = None):
        for key, sig, width in self.hw_ports:
            if special is None:
                v = int(self.rng.integers(0, 1 << width))
            else:
                v = special & _mask(width)
            sig.value = v
            self.model.hw[key] = v

    def random_addr(self) -> int:
        r = self.rng.random()
        if r < 0.8:
            return int(self.rng.choice(list(self.model.by_addr)))
        if r < 0.9:
            unmapped = [a for a in range(0, 256, 4) if a not in self.model.by_addr]
            return int(self.rng.choice(unmapped))
        if r < 0.95 or self.addr_bits <= 8:
            return int(self.rng.choice(list(self.model.by_addr))) | int(self.rng.integers(1, 4))
        return int(self.rng.integers(1, 1 << (self.addr_bits - 8))) << 8 | int(
            self.rng.choice(list(self.model.by_addr)))

    def random_data(self) -> int:
        r = self.rng.random()
        if r < 0.1:
            return 0
        if r < 0.2:
            return 0xFFFFFFFF
        if r < 0.3:
            return int(self.rng.choice([0x80008000, 0x7FFF7FFF, 0x00000001, 0x00000100, 0xFFFF0000]))
        return int(self.rng.integers(0, 1 << 32))

    def random_strb(self) -> int:
        return 0xF if self.rng.random() < 0.5 else int(self.rng.integers(0, 16))

    # ------------------------------------------------------------------ checked transactions
    async def write(self, addr, data, strb=0xF, what="", set_also=False, **delays):
        resp = await self.axi.write(addr, data, strb, **delays)
        exp, pulses = self.model.write(addr, data, strb, set_also)
        assert resp == exp, (f"{what} write 0x{addr:X} <= 0x{data:08X} strb {strb:X}: BRESP {resp}, "
                             f"expected {exp}")
        for key in pulses:
            self.expected_pulses[key] += [(self.axi.aw_time, 1), (self.axi.aw_time + self.period, 0)]
        return resp

    async def read(self, addr, what="", **delays):
        data, resp = await self.axi.read(addr, **delays)
        exp = self.model.read(addr)
        reg = self.model.by_addr.get(addr, "unmapped")
        assert (data, resp) == exp, (f"{what} read 0x{addr:X} ({reg}): RTL (0x{data:08X}, resp {resp}), "
                                     f"model (0x{exp[0]:08X}, resp {exp[1]})")
        return data

    async def pulse_set_at_accept(self) -> int:
        """The hardware set at the edge that accepts a write started now (hfi_regs accepts AW/W
        ACCEPT_CLOCKS edges after it first sees them); returns the time of that edge."""
        for _ in range(ACCEPT_CLOCKS):
            await self.edge
        return await self.pulse_set()

    async def pulse_set(self, cycles: int = 1) -> int:
        """Drive irq_window_set high for ``cycles`` clocks; returns the time of the first sampling edge."""
        self.dut.irq_window_set.value = 1
        await self.edge
        t = get_sim_time()
        self.model.hw_set()
        for _ in range(cycles - 1):
            await self.edge
        self.dut.irq_window_set.value = 0
        return t

    async def checkpoint(self, what: str):
        """In ReadOnly of the current step: every field output, irq and the w1p pulse history against
        the model; then on to the next rising edge."""
        await self.ro
        for key, sig in self.rw_ports:
            got, exp = int(sig.value), self.model.store[key]
            assert got == exp, f"{what}: port of {key[0]}.{key[1]} = 0x{got:X}, model 0x{exp:X}"
        got = int(self.dut.irq.value)  # callers leave >= 1 clock after the last status/enable change
        assert got == self.model.irq(), f"{what}: irq = {got}, model {self.model.irq()}"
        for key, log in self.pulse_logs.items():
            assert log.events == self.expected_pulses[key], (
                f"{what}: {PULSE_PORTS[key]} transitions (time, value) {log.events[-6:]}, "
                f"expected {self.expected_pulses[key][-6:]}")
        await self.edge

    async def reset(self, cycles: int = 1):
        self.axi.idle()
        self.dut.rst.value = 1
        await ClockCycles(self.dut.clk, cycles)
        self.dut.rst.value = 0
        self.model.reset()
        await self.edge

    async def read_all(self, what: str):
        for name, reg in REGISTERS.items():
            await self.read(reg["addr"], f"{what} {name}")


# ---------------------------------------------------------------------- tests
@cocotb.test()
async def reset_values(dut):
    """Every register's reset value; hardware fields show random inputs; ID/VERSION constants."""
    b = Bench(dut, "reset_values")
    await b.start()
    await b.checkpoint("after reset")  # field outputs = resets, irq 0, no pulse
    for name, reg in REGISTERS.items():
        data = await b.read(reg["addr"], f"reset {name}")
        hw_mask = sum(_mask(w, lsb) for f, (lsb, w, rst, acc) in reg["fields"].items() if rst is None)
        assert data & ~hw_mask == reg["reset"], \
            f"{name}: reset 0x{data & ~hw_mask:08X}, REGISTERS reset 0x{reg['reset']:08X}"
    assert await b.read(REGISTERS["ID"]["addr"]) == 0x48464931  # 'HFI1'
    for i in range(20):
        b.randomize_hw(special={0: 0, 1: 0xFFFFFFFF, 2: 0x80000000, 3: 0x7FFFFFFF}.get(i))
        for name in dict.fromkeys(k[0] for k in HW_PORTS):
            await b.read(REGISTERS[name]["addr"], f"hw pattern {i} {name}")
    await b.checkpoint("end")


@cocotb.test()
async def rw_fields_with_strobes(dut):
    """rw fields: random data and byte strobes, read back (bits outside fields read 0), field ports."""
    b = Bench(dut, "rw_fields_with_strobes")
    await b.start()
    for name, reg in REGISTERS.items():
        for i, (data, strb) in enumerate([(0xFFFFFFFF, 0xF), (0, 0xF), (0xFFFFFFFF, 0x1), (0xFFFFFFFF, 0x0)]
                                         + [(b.random_data(), b.random_strb()) for _ in range(12)]):
            if name in ("IRQ_STATUS",) and i % 3 == 0:
                await b.pulse_set()
            await b.write(reg["addr"], data, strb, f"{name} #{i}")
            await b.read(reg["addr"], f"{name} #{i}")
            if i % 4 == 0:
                await b.checkpoint(f"{name} #{i}")
    await b.checkpoint("end")
    await b.read_all("end")


@cocotb.test()
async def w1p_pulses(dut):
    """CTRL.FAULT_CLEAR and COMMIT.GO: a one-clock pulse at the handshake edge of each write of 1."""
    b = Bench(dut, "w1p_pulses")
    await b.start()
    for (reg, field), port in PULSE_PORTS.items():
        addr = REGISTERS[reg]["addr"]
        lsb = REGISTERS[reg]["fields"][field][0]
        bit, strb_on, strb_off = 1 << lsb, 1 << (lsb // 8), 0xF & ~(1 << (lsb // 8))
        cases = [(bit, 0xF), (0, 0xF), (bit, strb_off), (bit, strb_on), (0xFFFFFFFF, 0xF),
                 (~bit & 0xFFFFFFFF, 0xF),
                 (bit | 0x0D, 0xF), (bit, 0xF), (bit, 0xF), (0xFFFFFFFF, 0x0)]
        for i, (data, strb) in enumerate(cases):
            n_before = len(b.expected_pulses[(reg, field)])
            await b.write(addr, data, strb, f"{port} case {i}")
            assert (len(b.expected_pulses[(reg, field)]) > n_before) == bool(data & bit and strb & strb_on)
            if i != 7:  # case 7 -> 8: two writes of 1 back to back
                await b.read(addr, f"{port} case {i}")  # the w1p bit reads 0
                await b.checkpoint(f"{port} case {i}")
        await b.checkpoint(f"{port} end")
        assert len(b.pulse_logs[(reg, field)].events) == 2 * 6, "expected 6 pulses"
    # exact cycles by sampling every clock around one write
    samples = []

    async def sampler(n):
        for _ in range(n):
            await b.ro
            samples.append((get_sim_time(), int(dut.commit_go.value), int(dut.fault_clear.value)))
            await b.edge
    task = cocotb.start_soon(sampler(8))
    await b.write(REGISTERS["COMMIT"]["addr"], 1)
    t = b.axi.aw_time
    await task
    high = [(ts, cg) for ts, cg, fc in samples if cg or fc]
    assert high == [(t, 1)], f"commit_go samples {samples}, handshake edge at {t}"
    await b.checkpoint("end")


@cocotb.test()
async def irq_status_and_line(dut):
    """IRQ_STATUS.WINDOW: hardware set, write-1 clear, write 0 no effect, set wins; irq registered."""
    b = Bench(dut, "irq_status_and_line")
    await b.start()
    P = b.period
    st, en = REGISTERS["IRQ_STATUS"]["addr"], REGISTERS["IRQ_ENABLE"]["addr"]
    irq = b.irq_log.events

    async def settle(what):
        await ClockCycles(dut.clk, 2)
        await b.checkpoint(what)
        await b.read(st, what)

    t = await b.pulse_set()                                   # set, disabled: status 1, irq 0
    await settle("set while disabled")
    assert irq == [] and b.model.store[("IRQ_STATUS", "WINDOW")] == 1
    await b.write(en, 1, 0xF, "enable")                       # irq rises one clock after the enable
    await settle("enabled")
    assert irq == [(b.axi.aw_time + P, 1)], f"irq {irq}, enable written at {b.axi.aw_time}"
    await b.write(st, 0, 0xF, "write 0")                      # no effect
    await b.write(st, 0xFFFFFFFE, 0xF, "write ~1")
    await b.write(st, 1, 0xE, "write 1, byte 0 off")
    await settle("no clear")
    assert len(irq) == 1
    await b.write(st, 1, 0x1, "clear")                        # cleared at the handshake, irq one later
    await settle("cleared")
    assert irq[1:] == [(b.axi.aw_time + P, 0)], f"irq {irq}"
    t = await b.pulse_set()                                   # set while enabled
    await settle("set while enabled")
    assert irq[2:] == [(t + P, 1)], f"irq {irq}, set sampled at {t}"
    # set and clear at the same edge, status 1 before: set wins, irq stays 1
    task = cocotb.start_soon(b.pulse_set_at_accept())
    await b.write(st, 1, 0xF, "set+clear (status 1)", set_also=True)
    assert await task == b.axi.aw_time, "the clear was not accepted at the edge of the set"
    await settle("set wins (1)")
    assert len(irq) == 3
    await b.write(st, 1, 0xF, "clear")
    await settle("cleared again")
    assert irq[3:] == [(b.axi.aw_time + P, 0)]
    # set and clear at the same edge, status 0 before: ends 1, irq rises
    task = cocotb.start_soon(b.pulse_set_at_accept())
    await b.write(st, 1, 0xF, "set+clear (status 0)", set_also=True)
    t = await task
    assert t == b.axi.aw_time
    await settle("set wins (0)")
    assert irq[4:] == [(t + P, 1)]
    # a clear one clock after the set, and one during a 3-clock set
    await b.write(en, 0, 0xF, "disable")
    await settle("disabled")
    assert irq[5:] == [(b.axi.aw_time + P, 0)]
    await b.write(en, 1, 0xF, "enable again")
    task = cocotb.start_soon(b.pulse_set(3))
    await b.write(st, 1, 0xF, "clear during a 3-clock set", set_also=True)
    await task
    await settle("3-clock set")
    assert b.model.store[("IRQ_STATUS", "WINDOW")] == 1
    await b.write(st, 1, 0xF, "clear")
    await settle("final clear")
    assert irq[-1][1] == 0 and len(irq) == 8, f"irq {irq}"
    # back-to-back: set pulses every other clock with enable toggling, irq follows status & enable
    for i in range(40):
        if b.rng.random() < 0.5:
            await b.pulse_set(int(b.rng.integers(1, 3)))
        await b.write(int(b.rng.choice([st, en])), b.random_data(), b.random_strb(), f"mix {i}")
        await b.checkpoint(f"mix {i}")


@cocotb.test()
async def unmapped_addresses(dut):
    """Unmapped, unaligned and (ADDR_BITS > 8) out-of-window addresses: SLVERR, data 0, no effect."""
    b = Bench(dut, "unmapped_addresses")
    await b.start()
    await b.write(REGISTERS["IRQ_ENABLE"]["addr"], 1)
    await b.pulse_set()  # status 1: a write aliasing IRQ_STATUS would clear it
    mapped = sorted(b.model.by_addr)
    addrs = [a for a in range(0, 256, 4) if a not in b.model.by_addr]
    assert {0x3C, 0xC4, 0xFC} <= set(addrs)   # 0xC4: the first word after the last register (WIN_ADC @ 0xC0)
    addrs += [a | off for a in mapped for off in (1, 2, 3)]
    if b.addr_bits > 8:
        addrs += [(1 << k) | a for k in range(8, b.addr_bits) for a in mapped]
        addrs += [((1 << b.addr_bits) - 1) & ~0xFF | a for a in mapped]
    for a in addrs:
        assert not b.model.known(a)
        await b.read(a, "unmapped")
        for data, strb in ((0xFFFFFFFF, 0xF), (b.random_data(), b.random_strb())):
            await b.write(a, data, strb, "unmapped")
        if a % 7 == 0:
            await b.checkpoint(f"unmapped 0x{a:X}")
    await b.checkpoint("unmapped end")
    await b.read_all("after unmapped accesses")
    assert all(not log.events for log in b.pulse_logs.values())


@cocotb.test()
async def reset_mid_operation(dut):
    """Reset while a write response / read data waits for READY, and between transactions."""
    b = Bench(dut, "reset_mid_operation")
    await b.start()

    async def scramble(what):
        for name, reg in REGISTERS.items():
            await b.write(reg["addr"], b.random_data(), 0xF, f"{what} {name}")
        await b.write(REGISTERS["IRQ_ENABLE"]["addr"], 1)
        await b.pulse_set()
        await b.edge  # irq one clock after the set
        await b.checkpoint(what)
        assert int(dut.irq.value) == 1

    for case in ("bvalid", "rvalid", "idle", "long"):
        await scramble(f"before reset ({case})")
        if case in ("bvalid", "rvalid"):
            if case == "bvalid":
                task = cocotb.start_soon(b.axi.write(REGISTERS["PWM_HALF"]["addr"], 0x1234, bready_delay=50))
                sig = dut.s_axil_bvalid
            else:
                task = cocotb.start_soon(b.axi.read(REGISTERS["GAMMA"]["addr"], rready_delay=50))
                sig = dut.s_axil_rvalid
            for _ in range(5):
                await b.edge
            await b.ro
            assert int(sig.value) == 1, f"{case}: response not pending before the reset"
            await b.edge
            task.cancel()
            b.axi = AxiLiteMaster(dut, "s_axil", dut.clk)  # fresh master: the cancelled one is abandoned
        await b.reset(5 if case == "long" else 1)
        await b.ro
        assert int(dut.s_axil_bvalid.value) == 0 and int(dut.s_axil_rvalid.value) == 0, \
            f"{case}: BVALID/RVALID after reset"
        assert int(dut.irq.value) == 0, f"{case}: irq after reset"
        await b.edge
        await b.checkpoint(f"after reset ({case})")
        await b.read_all(f"after reset ({case})")


@cocotb.test()
async def random_sequence(dut):
    """HFI_RANDOM_N random transactions (back to back, delayed READY/VALID, concurrent read+write,
    hardware inputs, interrupt sets, resets) against the model."""
    b = Bench(dut, "random_sequence")
    await b.start()
    rng = b.rng
    counts = {}
    for i in range(b.n):
        r = rng.random()
        what = f"txn {i}"
        if r < 0.33:
            kind = "write"
            delays = {}
            if rng.random() < 0.3:
                delays = dict(aw_delay=int(rng.integers(0, 4)), w_delay=int(rng.integers(0, 4)),
                              bready_delay=int(rng.integers(0, 5)))
            await b.write(b.random_addr(), b.random_data(), b.random_strb(), what, **delays)
        elif r < 0.66:
            kind = "read"
            delays = {"rready_delay": int(rng.integers(1, 5))} if rng.random() < 0.3 else {}
            await b.read(b.random_addr(), what, **delays)
        elif r < 0.76:
            kind = "read+write"
            waddr, raddr = b.random_addr(), (b.random_addr() if rng.random() < 0.5 else None)
            data, strb = b.random_data(), b.random_strb()
            raddr = waddr if raddr is None else raddr
            wd = dict(aw_delay=int(rng.integers(0, 3)), w_delay=int(rng.integers(0, 3)),
                      bready_delay=int(rng.integers(0, 3)))
            rd = dict(rready_delay=int(rng.integers(0, 3)))
            if rng.random() < 0.5:
                wd, rd = {}, {}
            old = b.model.read(raddr)
            wtask = cocotb.start_soon(b.axi.write(waddr, data, strb, **wd))
            rtask = cocotb.start_soon(b.axi.read(raddr, **rd))
            # the read is started one scheduling step later but in the same time step
            resp = await wtask
            got = await rtask
            exp_b, pulses = b.model.write(waddr, data, strb)
            for key in pulses:
                b.expected_pulses[key] += [(b.axi.aw_time, 1), (b.axi.aw_time + b.period, 0)]
            new = b.model.read(raddr)
            exp = new if b.axi.aw_time < b.axi.ar_time else old
            assert resp == exp_b, f"{what}: concurrent write 0x{waddr:X} BRESP {resp}, expected {exp_b}"
            assert got == exp, (f"{what}: concurrent read 0x{raddr:X} (write 0x{waddr:X} <= 0x{data:08X} "
                                f"strb {strb:X} at {b.axi.aw_time}, read at {b.axi.ar_time}): RTL "
                                f"(0x{got[0]:08X}, {got[1]}), model (0x{exp[0]:08X}, {exp[1]})")
        elif r < 0.84:
            kind = "hw inputs"
            b.randomize_hw()
        elif r < 0.90:
            kind = "irq set"
            await b.pulse_set(int(rng.integers(1, 3)))
            await b.edge  # irq follows one clock later
        elif r < 0.93:
            kind = "irq set+clear"
            task = cocotb.start_soon(b.pulse_set_at_accept())
            await b.write(REGISTERS["IRQ_STATUS"]["addr"], b.random_data(), b.random_strb(), what,
                          set_also=True)
            assert await task == b.axi.aw_time
        elif r < 0.932:
            kind = "reset"
            await b.reset(int(rng.integers(1, 4)))
        else:
            kind = "idle"
            await ClockCycles(dut.clk, int(rng.integers(1, 4)))
        counts[kind] = counts.get(kind, 0) + 1
        if rng.random() < 0.15:
            await b.checkpoint(f"{what} ({kind})")
    await b.checkpoint("end")
    await b.read_all("end")
    cocotb.log.info(f"random_sequence: {b.n} transactions {counts}; pulses "
                    f"{ {PULSE_PORTS[k]: len(v) // 2 for k, v in b.expected_pulses.items()} }")


@cocotb.test()
async def raw_random_handshakes(dut):
    """Cycle-level: random VALID/READY on all five channels driven directly (AR issued while R is
    pending, AW and W presented independently, READY toggling freely), random irq_window_set; every
    handshake, response, pulse and irq checked each clock against the model."""
    b = Bench(dut, "raw_random_handshakes")
    await b.start()
    rng, m = b.rng, b.model
    s = {n: getattr(dut, f"s_axil_{n}") for n in (
        "awaddr", "awvalid", "awready", "wdata", "wstrb", "wvalid", "wready", "bresp", "bvalid", "bready",
        "araddr", "arvalid", "arready", "rdata", "rresp", "rvalid", "rready")}
    drv = dict(awvalid=0, wvalid=0, arvalid=0, bready=0, rready=0, set=0,
               awaddr=0, araddr=0, wdata=0, wstrb=0)
    ar_q, aw_q, w_q, b_q = [], [], [], []
    exp_pulse = {key: 0 for key in PULSE_PORTS}
    exp_irq = 0
    held_b = held_r = None  # response seen with READY low: must stay until taken
    n_cycles = max(500, b.n // 4)
    stats = dict(reads=0, writes=0)
    for cyc in range(n_cycles):
        await b.ro
        what = f"cycle {cyc}"
        for key, port in PULSE_PORTS.items():
            got = int(getattr(dut, port).value)
            assert got == exp_pulse[key], f"{what}: {port} = {got}, expected {exp_pulse[key]}"
        assert int(dut.irq.value) == exp_irq, f"{what}: irq = {int(dut.irq.value)}, expected {exp_irq}"
        if cyc % 16 == 0:
            for key, sig in b.rw_ports:
                assert int(sig.value) == m.store[key], f"{what}: port of {key} = {int(sig.value):#x}"
        v = {n: int(h.value) for n, h in s.items() if n not in ("awaddr", "wdata", "wstrb", "araddr")}
        for held, ch, payload in ((held_b, "b", ("bresp",)), (held_r, "r", ("rdata", "rresp"))):
            if held is not None:
                now = tuple(v[p] for p in payload)
                assert v[f"{ch}valid"] and now == held, \
                    f"{what}: {ch.upper()} response dropped/changed while READY was low ({held} -> {now})"
        held_b = (v["bresp"],) if v["bvalid"] and not drv["bready"] else None
        held_r = (v["rdata"], v["rresp"]) if v["rvalid"] and not drv["rready"] else None
        await b.edge
        # ---- what happened at this edge (in RTL order: reads see the old state, writes, then set)
        exp_irq = m.irq()
        if v["rvalid"] and drv["rready"]:
            assert ar_q, f"{what}: R beat without an accepted AR"
            exp = ar_q.pop(0)
            got = (v["rdata"], v["rresp"])
            assert got == exp, f"{what}: R beat (0x{got[0]:08X}, {got[1]}), model (0x{exp[0]:08X}, {exp[1]})"
            stats["reads"] += 1
        if v["bvalid"] and drv["bready"]:
            assert b_q, f"{what}: B beat without an accepted write"
            exp = b_q.pop(0)
            assert v["bresp"] == exp, f"{what}: BRESP {v['bresp']}, model {exp}"
            stats["writes"] += 1
        ar_hs = drv["arvalid"] and v["arready"]
        aw_hs = drv["awvalid"] and v["awready"]
        w_hs = drv["wvalid"] and v["wready"]
        if ar_hs:
            ar_q.append(m.read(drv["araddr"]))
        if aw_hs:
            aw_q.append(drv["awaddr"])
        if w_hs:
            w_q.append((drv["wdata"], drv["wstrb"]))
        exp_pulse = {key: 0 for key in PULSE_PORTS}
        while aw_q and w_q:
            resp, pulses = m.write(aw_q.pop(0), *w_q.pop(0))
            b_q.append(resp)
            for key in pulses:
                exp_pulse[key] = 1
        if drv["set"]:
            m.hw_set()
        # ---- drive the next cycle (a VALID without handshake holds its payload)
        if not drv["awvalid"] or aw_hs:
            drv["awvalid"] = int(rng.random() < 0.6)
            drv["awaddr"] = b.random_addr()
        if not drv["wvalid"] or w_hs:
            drv["wvalid"] = int(rng.random() < 0.6)
            drv["wdata"], drv["wstrb"] = b.random_data(), b.random_strb()
        if not drv["arvalid"] or ar_hs:
            drv["arvalid"] = int(rng.random() < 0.6)
            drv["araddr"] = b.random_addr()
        drv["bready"], drv["rready"] = int(rng.random() < 0.6), int(rng.random() < 0.6)
        drv["set"] = int(rng.random() < 0.1)
        if rng.random() < 0.03:
            b.randomize_hw()
        for n in ("awvalid", "awaddr", "wvalid", "wdata", "wstrb", "arvalid", "araddr", "bready", "rready"):
            s[n].value = drv[n]
        dut.irq_window_set.value = drv["set"]
    cocotb.log.info(f"raw_random_handshakes: {n_cycles} cycles, {stats}")
    assert stats["reads"] > n_cycles // 8 and stats["writes"] > n_cycles // 8, stats


def _locked_regs() -> list[str]:
    """Registers with a field in golden.regmap.LOCKED_BY (locked by SAFETY_LOCK.LOCK)."""
    return list(dict.fromkeys(reg for reg, _field in LOCKED_BY))


def _lock_addr() -> tuple[int, int]:
    """(address, bit) of the lock field of LOCKED_BY (a single lock in this map)."""
    locks = set(LOCKED_BY.values())
    assert len(locks) == 1, f"tb_regs expects one lock field, LOCKED_BY has {locks}"
    reg, field = locks.pop()
    return REGISTERS[reg]["addr"], REGISTERS[reg]["fields"][field][0]


@cocotb.test()
async def safety_lock(dut):
    """SAFETY_LOCK.LOCK (w1s): 0 and strobed-off 1 do nothing, 1 sets, only rst clears; while set,
    writes to the LOCKED_BY registers (any data, any WSTRB, also none) answer SLVERR and change
    nothing; every other register stays writable."""
    b = Bench(dut, "safety_lock")
    await b.start()
    locked = _locked_regs()
    assert locked, "LOCKED_BY is empty"
    lock_addr, lock_bit = _lock_addr()
    bit, strb_on = 1 << lock_bit, 1 << (lock_bit // 8)
    others = [n for n, r in REGISTERS.items() if n not in locked]

    async def writable(what):
        for name in locked:
            for data, strb in ((0xFFFFFFFF, 0xF), (b.random_data(), 0xF), (b.random_data(), 0x1)):
                assert await b.write(REGISTERS[name]["addr"], data, strb, f"{what} {name}") == OKAY
                await b.read(REGISTERS[name]["addr"], f"{what} {name}")
        await b.checkpoint(what)

    await writable("unlocked")
    # writes that must not set the lock
    for i, (data, strb) in enumerate([(0, 0xF), (~bit & 0xFFFFFFFF, 0xF), (bit, 0xF & ~strb_on),
                                      (0xFFFFFFFF, 0x0)]):
        assert await b.write(lock_addr, data, strb, f"no-lock write {i}") == OKAY
        assert await b.read(lock_addr, f"no-lock write {i}") == 0
    await writable("still unlocked")
    # lock
    assert await b.write(lock_addr, bit, strb_on, "lock") == OKAY
    assert await b.read(lock_addr, "locked") == bit
    for name in locked:
        before = await b.read(REGISTERS[name]["addr"], f"locked {name}")
        for data, strb in [(0xFFFFFFFF, 0xF), (0, 0xF), (0xFFFFFFFF, 0x1), (0xFFFFFFFF, 0x2), (0x5A5A, 0x0),
                           (~before & 0xFFFFFFFF, 0xF)] + [(b.random_data(), b.random_strb()) for _ in range(8)]:
            assert await b.write(REGISTERS[name]["addr"], data, strb, f"locked {name}") == SLVERR
            assert await b.read(REGISTERS[name]["addr"], f"locked {name}") == before
        await b.checkpoint(f"locked {name}")
    # the lock cannot be cleared by software
    for data, strb in ((0, 0xF), (0, strb_on), (0xFFFFFFFE, 0xF), (0xFFFFFFFF, 0xF)):
        assert await b.write(lock_addr, data, strb, "unlock attempt") == OKAY
        assert await b.read(lock_addr, "unlock attempt") == bit
    # every other register still writable (and the w1p pulses still fire)
    for name in others:
        for data, strb in ((b.random_data(), 0xF), (b.random_data(), b.random_strb())):
            if name == "IRQ_STATUS":
                await b.pulse_set()
            await b.write(REGISTERS[name]["addr"], data, strb, f"locked, other {name}")
            await b.read(REGISTERS[name]["addr"], f"locked, other {name}")
        await b.checkpoint(f"locked, other {name}")
    assert await b.read(lock_addr, "still locked") == bit
    # back to back: lock write followed directly by a write to a locked register (locked already)
    await b.reset()
    assert await b.read(lock_addr, "after reset") == 0
    await writable("after reset")
    name = locked[0]
    await b.write(lock_addr, 0xFFFFFFFF, 0xF, "lock again")
    assert await b.write(REGISTERS[name]["addr"], 0x1234, 0xF, f"right after the lock {name}") == SLVERR
    await b.checkpoint("end")
    await b.read_all("end")


@cocotb.test()
async def lock_at_random_point(dut):
    """Random writes (strobes, delays, concurrent reads) biased to the locked registers and the lock
    register; the lock is set at a random transaction of each round, a reset ends each round."""
    b = Bench(dut, "lock_at_random_point")
    await b.start()
    rng = b.rng
    locked_addrs = [REGISTERS[n]["addr"] for n in _locked_regs()]
    lock_addr, lock_bit = _lock_addr()
    n_rounds = 4
    m = max(40, b.n // (5 * n_rounds))
    counts = dict(locked_slverr=0, locked_okay=0)
    for rnd in range(n_rounds):
        lock_at = int(rng.integers(0, m))
        for i in range(m):
            what = f"round {rnd} txn {i} (lock at {lock_at})"
            r = rng.random()
            if i == lock_at:
                data = b.random_data() | 1 << lock_bit
                strb = b.random_strb() | 1 << (lock_bit // 8)
                assert await b.write(lock_addr, data, strb, f"{what}: lock") == OKAY
                assert b.model.store[("SAFETY_LOCK", "LOCK")] == 1
                continue
            if r < 0.45:
                addr = int(rng.choice(locked_addrs))
            elif r < 0.55:
                addr = lock_addr
            else:
                addr = b.random_addr()
            if r < 0.8:
                data, strb = b.random_data(), b.random_strb()
                if i < lock_at and addr == lock_addr:
                    data &= ~(1 << lock_bit)     # the lock only at lock_at
                delays = {}
                if rng.random() < 0.3:
                    delays = dict(aw_delay=int(rng.integers(0, 3)), w_delay=int(rng.integers(0, 3)),
                                  bready_delay=int(rng.integers(0, 3)))
                resp = await b.write(addr, data, strb, what, **delays)
                if addr in locked_addrs:
                    counts["locked_slverr" if resp == SLVERR else "locked_okay"] += 1
                    assert (resp == SLVERR) == (i > lock_at), f"{what}: BRESP {resp}"
            else:
                await b.read(addr if rng.random() < 0.7 else b.random_addr(), what)
            if rng.random() < 0.1:
                await b.checkpoint(what)
        await b.checkpoint(f"round {rnd} end")
        await b.read_all(f"round {rnd} end")
        await b.reset(int(rng.integers(1, 3)))
    cocotb.log.info(f"lock_at_random_point: {n_rounds} rounds of {m} transactions, {counts}")
    assert counts["locked_slverr"] and counts["locked_okay"], counts


@cocotb.test()
async def driver_timeout(dut):
    """The AXI master's timeout: a slave held in reset never answers; clear errors, not a hang."""
    from axil_driver import AxiLiteTimeout
    b = Bench(dut, "driver_timeout")
    await b.start()
    dut.rst.value = 1
    axi = AxiLiteMaster(dut, "s_axil", dut.clk, timeout=20)
    # AWREADY/WREADY and ARREADY follow the registered valids, which rst holds off
    for op, args, text in ((axi.write, (0x18, 1), "no AWREADY/WREADY for address 0x18 within 20 cycles"),
                           (axi.read, (0x18,), "no ARREADY for address 0x18 within 20 cycles")):
        try:
            await op(*args)
        except AxiLiteTimeout as e:
            assert text in str(e), f"timeout message {str(e)!r}"
        else:
            raise AssertionError(f"{op.__name__} did not time out")
    dut.rst.value = 0
