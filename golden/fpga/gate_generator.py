"""Dead-time gate generator: ideal switch signals -> six gate signals, as edges in clock ticks.

docs/spec.md, section 2.4. Per leg x the ideal switch signal ``s`` is 1 while ``phi < cmp_x`` on the
rising half and while ``P - phi <= cmp_x`` on the falling half. The switch selected by ``s`` (high for
1, low for 0) turns on ``D`` ticks after the latest of the last change of ``s`` and the enabling of the
outputs, and turns off at the tick ``s`` leaves it; a pulse of ``s`` of at most ``D`` ticks never turns
on. Both switches of a leg are therefore never on together.

The model is streaming, like the hardware: compare values are added one half period at a time (in
order), and the gate edges before a tick are taken out once everything that could still cancel them
is known (the caller must have added the half periods up to that tick).
"""

from __future__ import annotations

import numpy as np

DEAD_MIN_DEFAULT = 50
"""Synthesis parameter: smallest dead time [ticks] the hardware will use, whatever the register says."""


def effective_dead_ticks(register: int, dead_min: int = DEAD_MIN_DEFAULT) -> int:
    """The dead time the hardware applies: ``max(DEAD_TICKS, DEAD_MIN)`` (spec 2.4)."""
    if not 0 <= register <= 0xFFFF:
        raise ValueError(f"DEAD_TICKS = {register} is not a u16 register value")
    if not 1 <= dead_min <= 0xFFFF:
        raise ValueError(f"DEAD_MIN = {dead_min} must be in 1..65535")
    return max(register, dead_min)


class GateGenerator:
    """Streaming dead-time gate generator for three legs.

    Parameters
    ----------
    dead_ticks : int
        ``DEAD_TICKS`` register value (clamped to ``dead_min``).
    dead_min : int
        ``DEAD_MIN`` synthesis parameter.
    switch_ticks : bool
        Record the instants of the ideal switch signals' changes for :meth:`take_switch_ticks` (the
        blanking of ``OS_BLANK`` reads them); False skips that bookkeeping.
    """

    def __init__(self, dead_ticks: int, dead_min: int = DEAD_MIN_DEFAULT, switch_ticks: bool = True):
        self.dead = effective_dead_ticks(dead_ticks, dead_min)
        self.track_switches = switch_ticks
        self.level = [0, 0, 0]              # ideal switch signal s of each leg
        self.since = [0, 0, 0]              # tick from which s (and the enable) has been stable
        self.pending: list[tuple[int, int] | None] = [None, None, None]  # (turn-on tick, gate bit)
        self.enabled = False
        self.horizon = 0                    # everything before this tick has been added
        self._events: list[tuple[int, int, int]] = []   # final (tick, value, bit), unordered
        self._switch_ticks: list[int] = []  # ticks at which some ideal switch signal changed
        self.mask = 0                       # gate mask after the last edge taken out

    # ---- inputs --------------------------------------------------------------------------------
    def _change(self, leg: int, tick: int, level: int) -> None:
        """The ideal switch signal of ``leg`` becomes ``level`` at ``tick``."""
        pend = self.pending[leg]
        if pend is not None and pend[0] >= tick:
            self.pending[leg] = None          # the pulse was too short: never turned on
        elif pend is not None:
            self._events.append((pend[0], 1, pend[1]))
            self.pending[leg] = None
        on_bit = 2 * leg + (0 if self.level[leg] else 1)
        self._events.append((tick, 0, on_bit))  # turn-off (a no-op if it never turned on)
        self.level[leg] = level
        self.since[leg] = tick
        if self.enabled:
            self.pending[leg] = (tick + self.dead, 2 * leg + (0 if level else 1))

    def add_half(self, start: int, half: int, rising: bool, compares) -> None:
        """Add one carrier half period starting at ``start`` with the compare values latched there."""
        if start != self.horizon:
            raise ValueError(f"half period starts at {start}, expected {self.horizon}")
        if half < 2:
            raise ValueError(f"half period {half} must be >= 2 ticks")
        for leg in range(3):
            cmp = int(compares[leg])
            if not 0 <= cmp <= half:
                raise ValueError(f"compare {cmp} of leg {leg} is outside 0..{half}")
            if rising:   # s = 1 on [start, start + cmp)
                first, mid, mid_level = (1 if cmp > 0 else 0), start + cmp, 0
            else:        # s = 1 on [start + half - cmp, start + half)
                first, mid, mid_level = (1 if cmp == half else 0), start + half - cmp, 1
            if first != self.level[leg]:
                self._change(leg, start, first)
                if self.track_switches:
                    self._switch_ticks.append(start)
            if 0 < cmp < half and mid_level != self.level[leg]:
                self._change(leg, mid, mid_level)
                if self.track_switches:
                    self._switch_ticks.append(mid)
        self.horizon = start + half

    def set_enabled(self, tick: int, enabled: bool) -> None:
        """Enable (gates follow s after the dead time) or disable (all off at once) at ``tick``, which must
        be the end of the half periods added so far (a carrier bottom or top, spec 2.4)."""
        if tick != self.horizon:
            raise ValueError(f"enable change at {tick}: only at the end of the added half periods ({self.horizon})")
        if enabled == self.enabled:
            return
        self.enabled = enabled
        for leg in range(3):
            pend = self.pending[leg]
            if enabled:
                start = max(self.since[leg], tick)
                self.pending[leg] = (start + self.dead, 2 * leg + (0 if self.level[leg] else 1))
                self.since[leg] = start
            else:
                if pend is not None and pend[0] < tick:
                    self._events.append((pend[0], 1, pend[1]))
                self.pending[leg] = None
                self._events.append((tick, 0, 2 * leg))
                self._events.append((tick, 0, 2 * leg + 1))

    # ---- outputs -------------------------------------------------------------------------------
    def take_edges(self, until: int) -> tuple[np.ndarray, np.ndarray]:
        """Gate edges before ``until``: (ticks int64, masks int32), one per tick where the mask changes.

        ``until`` must not exceed the end of the added half periods (a later change could still
        cancel a pending turn-on).
        """
        if until > self.horizon:
            raise ValueError(f"edges up to {until} requested, half periods added only up to {self.horizon}")
        for leg in range(3):
            pend = self.pending[leg]
            if pend is not None and pend[0] < until:
                self._events.append((pend[0], 1, pend[1]))
                self.pending[leg] = None
        now = [e for e in self._events if e[0] < until]
        self._events = [e for e in self._events if e[0] >= until]
        # at one tick, turn-offs (value 0) before turn-ons; the mask after the tick is what the plant sees (the
        # order of the bits within one tick and value changes no mask)
        now.sort()
        ticks, masks = [], []
        mask = self.mask
        for tick, value, bit in now:
            new = (mask | (1 << bit)) if value else (mask & ~(1 << bit))
            if new == mask:
                continue
            mask = new
            if ticks and ticks[-1] == tick:
                masks[-1] = mask
            else:
                ticks.append(tick)
                masks.append(mask)
        self.mask = mask
        return np.array(ticks, dtype=np.int64), np.array(masks, dtype=np.int32)

    def take_switch_ticks(self, until: int) -> np.ndarray:
        """Ticks (sorted) before ``until`` at which some leg's ideal switch signal changed."""
        if not self.track_switches:
            raise ValueError("switch ticks asked of a gate generator made with switch_ticks=False")
        now = sorted(t for t in self._switch_ticks if t < until)
        self._switch_ticks = [t for t in self._switch_ticks if t >= until]
        return np.array(now, dtype=np.int64)
