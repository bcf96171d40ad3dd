"""Hardware safety logic of hfi_dsp, clock by clock: STO, driver fault (DESAT), fault latches, output
enable and the last gate register (docs/spec.md, section 3.8; rtl/hfi_safety.v).

This is the specification of ``rtl/hfi_safety.v``: one call of :meth:`SafetyLogic.step` is one clock.
The inputs are the values present during the clock, the outputs are the combinational values of that
clock and, for ``gate``, the register that the clock edge at its end loads (visible from the next
clock on).

Rules (spec 3.8)
- ``sto`` and ``desat`` are asynchronous pins (active high after the board's polarity): each goes
  through a two-flop synchronizer, ``sto_s(t) = sto(t - 2)`` (0 in the first two clocks).
- ``kill = fault_oc | fault_wdt | fault_sto | fault_desat | sto_s | desat_s``.
- ``gate(t + 1) = 0`` if ``rst(t)`` or ``kill(t)``, else ``gate_in(t)``: STO, synchronized, removes
  every gate in the next clock, whatever the registers and the firmware do.
- The latches: a fault sets its flag in the next clock (``oc_trip``, ``wdt_expired``, ``sto_s``,
  ``desat_s``); ``fault_clear`` (CTRL.FAULT_CLEAR) clears all four, but a set in the same clock wins,
  so a fault whose input is still active (STO held, DESAT held) cannot be cleared: the gates stay off
  until STO is released *and* the firmware re-arms by writing FAULT_CLEAR.
- Output enable: ``en_applied`` follows CTRL.ENABLE at carrier bottoms and drops in the clock after
  any ``kill``; the gate generator sees ``enable = en_now & ~kill`` with
  ``en_now = at_bottom ? ctrl_enable : en_applied`` and ``kill`` (so after a re-arm the gates
  return at a carrier bottom, after a full dead time).
- ``drive_allowed = ~(fault_sto | fault_desat | sto_s | desat_s)``: the gate driver's enable pin.
"""

from __future__ import annotations

from dataclasses import dataclass

SYNC_STAGES = 2
"""Flip-flops of the STO and DESAT synchronizers (rtl/hfi_cdc_sync.v, STAGES)."""


@dataclass(frozen=True)
class SafetyInputs:
    """The inputs of one clock (all 0/1 except ``gate_in``, the 6-bit gate generator output)."""

    rst: int = 0
    sto: int = 0
    desat: int = 0
    oc_trip: int = 0
    wdt_expired: int = 0
    fault_clear: int = 0
    ctrl_enable: int = 0
    at_bottom: int = 0
    gate_in: int = 0


@dataclass(frozen=True)
class SafetyOutputs:
    """The outputs of one clock: combinational values, the registered state at the clock's start, and
    ``gate`` (the output register, as loaded at the end of the clock)."""

    sto_s: int
    desat_s: int
    fault_oc: int
    fault_wdt: int
    fault_sto: int
    fault_desat: int
    kill: int
    enable: int
    outputs_on: int
    drive_allowed: int
    gate: int


class SafetyLogic:
    """Bit-true clock-by-clock model of rtl/hfi_safety.v (module docstring)."""

    def __init__(self) -> None:
        self.sto_chain = [0] * SYNC_STAGES      # the synchronizers start at their configuration value 0
        self.desat_chain = [0] * SYNC_STAGES
        self.fault_oc = self.fault_wdt = self.fault_sto = self.fault_desat = 0
        self.en_applied = 0
        self.gate = 0

    def step(self, x: SafetyInputs) -> SafetyOutputs:
        for name in ("rst", "sto", "desat", "oc_trip", "wdt_expired", "fault_clear", "ctrl_enable", "at_bottom"):
            if getattr(x, name) not in (0, 1):
                raise ValueError(f"{name} = {getattr(x, name)!r} is not a bit")
        if not 0 <= x.gate_in <= 0x3F:
            raise ValueError(f"gate_in = {x.gate_in!r} is not a 6-bit gate mask")
        sto_s, desat_s = self.sto_chain[-1], self.desat_chain[-1]
        fault = self.fault_oc | self.fault_wdt | self.fault_sto | self.fault_desat
        kill = fault | sto_s | desat_s
        en_now = x.ctrl_enable if x.at_bottom else self.en_applied
        out_now = SafetyOutputs(
            sto_s=sto_s, desat_s=desat_s, fault_oc=self.fault_oc, fault_wdt=self.fault_wdt,
            fault_sto=self.fault_sto, fault_desat=self.fault_desat, kill=kill, enable=en_now & (1 - kill),
            outputs_on=self.en_applied & (1 - fault),
            drive_allowed=1 - (self.fault_sto | self.fault_desat | sto_s | desat_s),
            gate=0 if (x.rst or kill) else x.gate_in)
        # the clock edge
        self.sto_chain = [x.sto] + self.sto_chain[:-1]
        self.desat_chain = [x.desat] + self.desat_chain[:-1]
        self.gate = out_now.gate
        if x.rst:
            self.fault_oc = self.fault_wdt = self.fault_sto = self.fault_desat = 0
            self.en_applied = 0
            return out_now
        keep = 1 - x.fault_clear
        self.fault_oc = (self.fault_oc & keep) | x.oc_trip
        self.fault_wdt = (self.fault_wdt & keep) | x.wdt_expired
        self.fault_sto = (self.fault_sto & keep) | sto_s
        self.fault_desat = (self.fault_desat & keep) | desat_s
        self.en_applied = 0 if kill else (x.ctrl_enable if x.at_bottom else self.en_applied)
        return out_now
