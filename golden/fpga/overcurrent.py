"""The hardware overcurrent comparator and its fault latch, bit-true, per window (docs/spec.md 3.7).

Every processed sample (every conversion, blanked or not: ``hfi_overcurrent`` sees each ``hfi_adc_scale``
result) is compared: ``|i_a| > OC_LIMIT``, ``|i_b| > OC_LIMIT`` or ``|i_a + i_b| > OC_LIMIT`` (``i_c = -i_a -
i_b``, exact in 18 bits; ``OC_LIMIT`` u16) trips. The first trip latches ``STATUS.FAULT_OC`` and turns every gate
off; nothing clears it in a closed-loop run (the firmware never writes ``CTRL.FAULT_CLEAR``). Timing, from
the sampling instant ``t_s`` of the tripping sample, in ticks (spec 2.1): the plant sees all gates off from
``t_s + gate_off_delay(adc_bits)``, and ``WIN_FAULT.OC`` of window ``k`` (the fault latches at the window
boundary, spec 2.2) is 1 from the first window whose boundary ``(k+1) P + H/2`` is at or after
``t_s + fault_delay(adc_bits)``. Both delays were measured on the RTL (cocotb_tests/tb_dsp_safety.py asserts
them) and follow from the sample pipeline: the serial ADC's conversion and read-out (``hfi_adc_if``), the
scaling (``hfi_adc_scale``), the comparator's register, the fault latch and the gate output register.
"""

from __future__ import annotations

import numpy as np

from golden.fpga.adc_scale import adc_to_current_kernel
from golden.regmap import WIN_FAULT_OC_MASK

CONV_TICKS = 12
"""hfi_adc_if's conversion time at hfi_dsp's default [ticks]."""
SCLK_HALF = 1
"""hfi_adc_if's serial clock half period at hfi_dsp's default [ticks]."""


def adc_latency(adc_bits: int) -> int:
    """hfi_adc_if's LATENCY [ticks]: from its start to its codes, ``CONV_TICKS + 2 ADC_BITS SCLK_HALF + 2``."""
    return CONV_TICKS + 2 * adc_bits * SCLK_HALF + 2


def gate_off_delay(adc_bits: int) -> int:
    """Ticks from the tripping sample's sampling instant to the first tick the plant sees every gate off:
    ``adc_latency + 6`` (the sample strobe 1, the conversion and read-out, the scaling 4, the comparator's
    register 1; the kill clears the gate output register directly, one clock before the fault latch reads 1)."""
    return adc_latency(adc_bits) + 6


def fault_delay(adc_bits: int) -> int:
    """Ticks from the tripping sample's sampling instant to the first window boundary whose ``WIN_FAULT`` shows
    it (the boundary at or after ``t_s + fault_delay``): ``adc_latency + 7``, the tick ``STATUS.FAULT_OC`` first
    reads 1 (``WIN_FAULT`` takes the latches as they read in the boundary tick)."""
    return adc_latency(adc_bits) + 7


def over_limit(i_a: np.ndarray, i_b: np.ndarray, limit: int) -> np.ndarray:
    """Per sample, whether ``|i_a|``, ``|i_b|`` or ``|i_a + i_b|`` exceeds ``limit`` (int64 arrays of s16 currents,
    ``limit`` u16): the comparator of hfi_overcurrent."""
    return (np.abs(i_a) > limit) | (np.abs(i_b) > limit) | (np.abs(i_a + i_b) > limit)


class OvercurrentLatch:
    """The comparator and ``FAULT.OC`` of one run: :meth:`first_trip` looks at a window's samples (cheaply
    while no current can reach the limit); once tripped, :attr:`trip_tick` holds the sampling instant."""

    def __init__(self, adc_bits: int, offsets: tuple[int, int], gains: tuple[int, int], limit: int):
        self.bits, self.offsets, self.gains, self.limit = adc_bits, offsets, gains, limit
        self.gate_delay, self.fault_delay = gate_off_delay(adc_bits), fault_delay(adc_bits)
        self.trip_tick: int | None = None
        # the codes whose current is within half the limit on both channels (an interval: the scalings are
        # monotonic): a window whose codes all lie in it cannot trip, not even through i_c
        codes = np.arange(1 << adc_bits)
        ok = np.ones(len(codes), dtype=bool)
        for ch in (0, 1):
            ok &= np.abs(adc_to_current_kernel(codes, adc_bits, offsets[ch], gains[ch])) <= limit // 2
        ok = np.flatnonzero(ok)
        self._safe = (int(ok[0]), int(ok[-1])) if len(ok) else (1, 0)   # both channels' (the intersection)

    def first_trip(self, ticks: np.ndarray, codes: np.ndarray) -> int | None:
        """The sampling instant of the first sample of a window (``ticks`` in order, ``codes`` (n, >= 2): the codes
        of the channels a and b in its first two columns, other current channels after them) beyond the limit, or
        None. Does not latch (the caller does, :meth:`latch`)."""
        if not len(ticks) or self._safe[0] <= codes.min() and codes.max() <= self._safe[1]:
            return None                                   # every code in the safe interval (the quick test)
        i_a = adc_to_current_kernel(codes[:, 0], self.bits, self.offsets[0], self.gains[0])
        i_b = adc_to_current_kernel(codes[:, 1], self.bits, self.offsets[1], self.gains[1])
        over = np.flatnonzero(over_limit(i_a, i_b, self.limit))
        return int(ticks[over[0]]) if len(over) else None

    def latch(self, t_s: int) -> None:
        """The trip of the sample at ``t_s`` (the first: later ones change nothing)."""
        if self.trip_tick is None:
            self.trip_tick = t_s

    @property
    def kill_tick(self) -> int | None:
        """The first tick with every gate off (None: not tripped)."""
        return None if self.trip_tick is None else self.trip_tick + self.gate_delay

    def status(self, boundary: int) -> int:
        """``WIN_FAULT`` of the window ending at the boundary tick ``boundary``: its ``OC`` bit once the latch reads 1
        there."""
        return WIN_FAULT_OC_MASK if self.trip_tick is not None and self.trip_tick + self.fault_delay <= boundary else 0


def cut_edges(ticks: np.ndarray, masks: np.ndarray, kill: int | None, mask_before: int, end: int
              ) -> tuple[np.ndarray, np.ndarray]:
    """A window's gate edges (``ticks``, ``masks``, every tick before ``end``) as the plant sees them once the
    comparator kills the gates at tick ``kill``: those before it, then all off at ``kill`` (unless they already
    are), none after. ``mask_before``: the mask in effect before the window's first edge. Unchanged when
    ``kill`` is None or not before ``end`` (a kill in the next window)."""
    if kill is None or kill >= end:
        return ticks, masks
    keep = ticks < kill
    t, m = ticks[keep], masks[keep]
    if (int(m[-1]) if len(m) else mask_before) != 0:
        t, m = np.append(t, kill), np.append(m, 0)
    return t.astype(ticks.dtype, copy=False), m.astype(masks.dtype, copy=False)
