"""Dead-time gate generator of docs/spec.md section 2.4 (golden/fpga/gate_generator.py).

Expected edges are derived by hand in the comments from the spec's rules, never from the function under
test:

* ideal switch signal of leg x: ``s = 1`` iff ``phi < cmp`` on the rising half, iff ``P - phi <= cmp`` on
  the falling half; for a half starting at ``start`` that is ``s = 1`` on ``[start, start + cmp)``
  (rising) and on ``[start + H - cmp, start + H)`` (falling); the reset level is ``s = 0``;
* the switch selected by ``s`` (high for 1, low for 0) turns on ``D`` ticks after the latest of the last
  change of ``s`` and the enabling, and turns off at the tick ``s`` leaves it (a pulse of ``s`` of at most
  ``D`` ticks never turns on);
* gate mask bit ``2x`` = high switch of leg x, ``2x + 1`` = low switch: a_hi 1, a_lo 2, b_hi 4, b_lo 8,
  c_hi 16, c_lo 32.

The random safety test rebuilds the gate waveform tick by tick from an independent implementation of
these rules and compares it with the generator's edges.
"""

from __future__ import annotations

import random

import numpy as np
import pytest

from golden.fpga.gate_generator import DEAD_MIN_DEFAULT, GateGenerator, effective_dead_ticks

A_HI, A_LO, B_HI, B_LO, C_HI, C_LO = 1, 2, 4, 8, 16, 32
H = 100
D = 10


def gen(dead: int = D) -> GateGenerator:
    return GateGenerator(dead, dead_min=1)


def edges(g: GateGenerator, until: int):
    t, m = g.take_edges(until)
    assert t.dtype == np.int64 and m.dtype == np.int32
    return t.tolist(), m.tolist()


# ---- effective dead time -----------------------------------------------------------------------------
def test_dead_min_default():
    assert DEAD_MIN_DEFAULT == 50


@pytest.mark.parametrize("register, dead_min, expected", [
    (0, 50, 50), (1, 50, 50), (49, 50, 50), (50, 50, 50), (51, 50, 51), (400, 50, 400),
    (0xFFFF, 50, 0xFFFF), (0, 1, 1), (7, 1, 7), (100, 0xFFFF, 0xFFFF),
])
def test_effective_dead_ticks_clamps_to_dead_min(register, dead_min, expected):
    assert effective_dead_ticks(register, dead_min) == expected


def test_effective_dead_ticks_default_dead_min():
    assert effective_dead_ticks(0) == DEAD_MIN_DEFAULT
    assert effective_dead_ticks(400) == 400          # 4 us at 100 MHz, the paper's dead time


@pytest.mark.parametrize("register", [-1, 0x10000, 1 << 20, -(1 << 16)])
def test_effective_dead_ticks_rejects_non_u16(register):
    with pytest.raises(ValueError):
        effective_dead_ticks(register)


@pytest.mark.parametrize("dead_min", [0, -1, 0x10000])
def test_effective_dead_ticks_rejects_bad_dead_min(dead_min):
    with pytest.raises(ValueError):
        effective_dead_ticks(100, dead_min)


def test_generator_applies_the_clamp():
    assert GateGenerator(10).dead == DEAD_MIN_DEFAULT   # register below DEAD_MIN_DEFAULT
    assert GateGenerator(10, dead_min=1).dead == 10
    assert GateGenerator(400).dead == 400
    with pytest.raises(ValueError):
        GateGenerator(0x10000)
    with pytest.raises(ValueError):
        GateGenerator(-1)


# ---- one PWM period by hand --------------------------------------------------------------------------
def test_one_period_compare_40_by_hand():
    # H = 100 (P = 200), D = 10, enabled at tick 0; leg a: compare 40 on both halves; legs b, c: 0.
    # leg a ideal signal: rising [0, 100): s = 1 iff phi < 40 -> 1 on [0, 40), 0 on [40, 100);
    #   falling [100, 200): s = 1 iff 200 - phi <= 40 iff phi >= 160 -> 0 on [100, 160), 1 on [160, 200).
    #   changes: 0 (0 -> 1 from the reset level), 40 (-> 0), 160 (-> 1).
    #   high: on at max(0, 0) + 10 = 10, off at 40;  low: on at 40 + 10 = 50, off at 160;
    #   high: on at 160 + 10 = 170 (still on at the end).
    #   (the low switch of the reset level would turn on at 0 + 10 = 10 but s leaves 0 at tick 0.)
    # legs b, c: s = 0 throughout (phi < 0 never; 200 - phi <= 0 never): low on at 0 + 10 = 10.
    # masks: 10: A_HI|B_LO|C_LO = 1+8+32 = 41; 40: 40; 50: 40|A_LO = 42; 160: 40; 170: 41.
    g = gen()
    g.set_enabled(0, True)
    g.add_half(0, H, True, [40, 0, 0])
    g.add_half(100, H, False, [40, 0, 0])
    assert edges(g, 200) == ([10, 40, 50, 160, 170], [41, 40, 42, 40, 41])
    assert g.mask == 41
    assert g.take_switch_ticks(200).tolist() == [0, 40, 160]


def test_one_period_streamed_in_pieces():
    # The same period taken out in pieces gives the same edges: after the rising half (horizon 100),
    # edges before 45 are 10 (41) and 40 (40); the turn-on of a_lo at 50 is known once the falling half
    # is added (its next change, 160, is later); then 50, 160, 170.
    g = gen()
    g.set_enabled(0, True)
    g.add_half(0, H, True, [40, 0, 0])
    assert edges(g, 45) == ([10, 40], [41, 40])
    assert edges(g, 45) == ([], [])
    assert edges(g, 100) == ([50], [42])
    g.add_half(100, H, False, [40, 0, 0])
    assert edges(g, 165) == ([160], [40])
    assert edges(g, 200) == ([170], [41])
    assert g.take_switch_ticks(100).tolist() == [0, 40]
    assert g.take_switch_ticks(200).tolist() == [160]
    assert g.take_switch_ticks(200).tolist() == []


# ---- short pulses ------------------------------------------------------------------------------------
@pytest.mark.parametrize("cmp, expected", [
    # leg a, rising half with compare c: s = 1 on [0, c), a pulse of c ticks.
    # c = 5 (< D): a_hi would turn on at 0 + 10 = 10 >= 5: never; a_lo on at 5 + 10 = 15.
    (5, ([10, 15], [40, 42])),
    # c = 10 (= D): a_hi would turn on at 10 = the tick s falls: never; a_lo on at 20.
    (10, ([10, 20], [40, 42])),
    # c = 11 (= D + 1): a_hi on at 10, off at 11 (one tick); a_lo on at 21.
    (11, ([10, 11, 21], [41, 40, 42])),
])
def test_short_high_pulse_within_rising_half(cmp, expected):
    # legs b, c compare 0: low on at 10 (B_LO|C_LO = 40).
    g = gen()
    g.set_enabled(0, True)
    g.add_half(0, H, True, [cmp, 0, 0])
    assert edges(g, 100) == expected


@pytest.mark.parametrize("f, r, expected", [
    # leg a: falling half [100, 200) compare f -> s = 1 on [200 - f, 200); rising half [200, 300)
    # compare r -> s = 1 on [200, 200 + r): one high pulse [200 - f, 200 + r) of f + r ticks across the
    # period boundary. Before it: rising [0, 100) compare 0 -> s = 0, a_lo on at 10.
    # (5, 5): pulse [195, 205), 10 ticks = D: a_lo off at 195, a_hi would turn on at 205 = its end:
    #   never; a_lo on again at 205 + 10 = 215.
    (5, 5, ([10, 195, 215], [42, 40, 42])),
    # (6, 5): pulse [194, 205), 11 ticks: a_lo off 194, a_hi on 204, off 205, a_lo on 215.
    (6, 5, ([10, 194, 204, 205, 215], [42, 40, 41, 40, 42])),
    # (2, 1): pulse [198, 201), 3 ticks: a_lo off 198, on again at 201 + 10 = 211.
    (2, 1, ([10, 198, 211], [42, 40, 42])),
])
def test_short_high_pulse_across_period_boundary(f, r, expected):
    # legs b, c compare 0 throughout: low on at 10. Masks: 42 = A_LO|B_LO|C_LO, 40 = B_LO|C_LO,
    # 41 = A_HI|B_LO|C_LO.
    g = gen()
    g.set_enabled(0, True)
    g.add_half(0, H, True, [0, 0, 0])
    g.add_half(100, H, False, [f, 0, 0])
    g.add_half(200, H, True, [r, 0, 0])
    assert edges(g, 300) == expected


@pytest.mark.parametrize("p, expected", [
    # leg a: rising [0, 100) compare 100 -> s = 1 throughout, a_hi on at 10.
    # falling [100, 200) compare 100 - p -> s = 1 iff 200 - phi <= 100 - p iff phi >= 100 + p:
    # a low pulse s = 0 on [100, 100 + p).
    # p = 10 (= D): a_hi off at 100; a_lo would turn on at 110 = its end: never; a_hi on at 120.
    (10, ([10, 100, 120], [41, 40, 41])),
    # p = 11: a_hi off 100, a_lo on 110, off 111, a_hi on 121.
    (11, ([10, 100, 110, 111, 121], [41, 40, 42, 40, 41])),
    # p = 3: a_hi off 100, on again 113.
    (3, ([10, 100, 113], [41, 40, 41])),
])
def test_short_low_pulse(p, expected):
    g = gen()
    g.set_enabled(0, True)
    g.add_half(0, H, True, [100, 0, 0])
    g.add_half(100, H, False, [100 - p, 0, 0])
    assert edges(g, 200) == expected


# ---- compare 0 and compare H, half boundaries ------------------------------------------------------
def test_compare_0_and_h_hold_through_halves():
    # leg a compares per half: rising H, falling H, rising 0, falling 0, rising H.
    #   [0, 100) s = 1 (phi < 100 always); [100, 200) s = 1 (200 - phi <= 100 always there);
    #   [200, 300) s = 0; [300, 400) s = 0 (200 - phi <= 0 never); [400, 500) s = 1.
    #   changes 0, 200, 400 only (none at 100 or 300: the switch is held through the boundary).
    #   a_hi on 10, off 200; a_lo on 210, off 400; a_hi on 410.
    # leg b compares: 0, H, H, 0, 0 -> s = 0 [0, 100), 1 [100, 300), 0 [300, 500):
    #   b_lo on 10, off 100; b_hi on 110, off 300; b_lo on 310.
    # leg c compare 0 throughout: c_lo on 10.
    # masks: 10: A_HI|B_LO|C_LO = 41; 100: 33; 110: 33|B_HI = 37; 200: 36; 210: 38; 300: 34;
    #        310: 34|B_LO = 42; 400: 40; 410: 41.
    g = gen()
    g.set_enabled(0, True)
    seq = [(True, [H, 0, 0]), (False, [H, H, 0]), (True, [0, H, 0]), (False, [0, 0, 0]), (True, [H, 0, 0])]
    for k, (rising, cmps) in enumerate(seq):
        g.add_half(100 * k, H, rising, cmps)
    assert edges(g, 500) == ([10, 100, 110, 200, 210, 300, 310, 400, 410],
                             [41, 33, 37, 36, 38, 34, 42, 40, 41])
    # ideal changes: a at 0, 200, 400; b at 100, 300; c never
    assert g.take_switch_ticks(500).tolist() == [0, 100, 200, 300, 400]


def test_falling_compare_h_minus_one_and_rising_one():
    # falling half compare H - 1 = 99: s = 1 iff 200 - phi <= 99 iff phi >= 101: a 1-tick low pulse
    # [100, 101) after a rising compare H (s = 1 on [0, 100)); then rising compare 1: s = 1 on
    # [200, 201), 0 on [201, 300). Leg a: a_hi on 10, off 100, on 101 + 10 = 111, off 201;
    # a_lo on 211. Legs b, c compare 0: low on 10.
    g = gen()
    g.set_enabled(0, True)
    g.add_half(0, H, True, [H, 0, 0])
    g.add_half(100, H, False, [H - 1, 0, 0])
    g.add_half(200, H, True, [1, 0, 0])
    assert edges(g, 300) == ([10, 100, 111, 201, 211], [41, 40, 41, 40, 42])
    # leg a changes at 0 (reset level 0 -> 1), 100, 101, 201 (not at 200: s = 1 on both sides)
    assert g.take_switch_ticks(300).tolist() == [0, 100, 101, 201]


# ---- enable and disable ------------------------------------------------------------------------------
def _first_period(g: GateGenerator) -> None:
    # leg a compare 40 (s = 1 [0, 40), 0 [40, 160), 1 [160, 200)); leg b 0 (s = 0, never changes);
    # leg c H (s = 1 from tick 0 on).
    g.add_half(0, H, True, [40, 0, H])
    g.add_half(100, H, False, [40, 0, H])


def test_disabled_generator_never_turns_on():
    rng = random.Random(1)
    g = gen()
    for k in range(40):
        g.add_half(k * H, H, k % 2 == 0, [rng.randint(0, H) for _ in range(3)])
        if k % 7 == 3:
            assert edges(g, k * H + 50) == ([], [])
    assert edges(g, 40 * H) == ([], [])
    assert g.mask == 0


def test_enable_at_period_start_by_hand():
    # Disabled during [0, 200); enabled at 200 (set before the rising half at 200 is added, as the
    # hardware does at the carrier bottom). Third half, rising [200, 300), compares 40, 0, H.
    # leg a: last change 160 (s = 1), s stays 1 until 240: a_hi on at max(160, 200) + 10 = 210, off 240;
    #        a_lo on at 250.
    # leg b: s = 0 since the reset (last change "0"): b_lo on at max(0, 200) + 10 = 210.
    # leg c: s = 1 since tick 0: c_hi on at 210.
    # masks: 210: A_HI|B_LO|C_HI = 1+8+16 = 25; 240: 24; 250: 26.
    g = gen()
    _first_period(g)
    assert edges(g, 200) == ([], [])
    g.set_enabled(200, True)
    g.add_half(200, H, True, [40, 0, H])
    assert edges(g, 300) == ([210, 240, 250], [25, 24, 26])


def test_enable_where_a_leg_changes_at_the_enable_tick():
    # As above but the rising half at 200 has leg a compare 0: s(a) falls 1 -> 0 at 200 = the enable
    # tick: a_lo on at max(200, 200) + 10 = 210. Legs b, c as above. Mask at 210: A_LO|B_LO|C_HI = 26.
    g = gen()
    _first_period(g)
    g.set_enabled(200, True)
    g.add_half(200, H, True, [0, 0, H])
    assert edges(g, 300) == ([210], [26])


def test_enable_at_falling_half_start():
    # Enabled at 100 (the top), before the falling half. Last changes: a 40 (s = 0), b none, c 0 (s = 1).
    # a_lo, b_lo, c_hi on at 110 (= max(40, 100) + 10 etc.): mask 2+8+16 = 26;
    # a: s rises at 160 -> a_lo off 160 (mask 24), a_hi on 170 (mask 25).
    g = gen()
    g.add_half(0, H, True, [40, 0, H])
    g.set_enabled(100, True)
    g.add_half(100, H, False, [40, 0, H])
    assert edges(g, 200) == ([110, 160, 170], [26, 24, 25])


def test_disable_turns_everything_off_at_that_tick():
    # Enabled at 0, first period as in _first_period: a_hi 10..40, a_lo 50..160, a_hi from 170;
    # b_lo from 10; c_hi from 10. Masks: 10: 1+8+16 = 25; 40: 24; 50: 26; 160: 24; 170: 25.
    # Disabled at 200: all off at 200 (mask 0); the next halves change a again but nothing turns on.
    g = gen()
    g.set_enabled(0, True)
    _first_period(g)
    g.set_enabled(200, False)
    g.add_half(200, H, True, [40, 0, H])
    g.add_half(300, H, False, [40, 0, H])
    assert edges(g, 400) == ([10, 40, 50, 160, 170, 200], [25, 24, 26, 24, 25, 0])


@pytest.mark.parametrize("f, expected", [
    # leg a: rising compare 0 (a_lo from 10), falling compare f: s rises at 200 - f and a_hi would
    # turn on at 210 - f. Disabled at 200: all off at 200.
    # f = 10: a_lo off 190, a_hi would turn on at 200 = the disable tick: never (zero length).
    (10, ([10, 190, 200], [42, 40, 0])),
    # f = 5: a_hi would turn on at 205, after the disable: never.
    (5, ([10, 195, 200], [42, 40, 0])),
    # f = 11: a_hi on at 199 for one tick, off at 200 with the rest.
    (11, ([10, 189, 199, 200], [42, 40, 41, 0])),
])
def test_disable_cancels_a_pending_turn_on(f, expected):
    g = gen()
    g.set_enabled(0, True)
    g.add_half(0, H, True, [0, 0, 0])
    g.add_half(100, H, False, [f, 0, 0])
    g.set_enabled(200, False)
    g.add_half(200, H, True, [0, 0, 0])
    assert edges(g, 300) == expected


def test_reenable_after_disable():
    # Enabled at 0 with compares 0 everywhere: all lows on at 10 (mask 42). Disabled at 100 (mask 0),
    # enabled again at 200: lows on at 210 (s = 0 since the reset: max(0, 200) + 10).
    g = gen()
    g.set_enabled(0, True)
    g.add_half(0, H, True, [0, 0, 0])
    g.set_enabled(100, False)
    g.add_half(100, H, False, [0, 0, 0])
    g.set_enabled(200, True)
    g.add_half(200, H, True, [0, 0, 0])
    assert edges(g, 300) == ([10, 100, 210], [42, 0, 42])


def test_set_enabled_same_value_is_a_no_op():
    # Enabling again at 100 must not restart the dead time: a_lo etc. stay on from 10.
    g = gen()
    g.set_enabled(0, True)
    g.add_half(0, H, True, [0, 0, 0])
    g.set_enabled(100, True)
    g.add_half(100, H, False, [0, 0, 0])
    assert edges(g, 200) == ([10], [42])


@pytest.mark.parametrize("enabled", [True, False])
def test_enable_change_only_at_the_end_of_the_added_halves(enabled):
    """The outputs are enabled/disabled at a carrier bottom or top, i.e. where the added half periods
    end (spec 2.4); a change inside already-added halves is refused, not silently mis-modelled."""
    g = GateGenerator(10, dead_min=1)
    if not enabled:
        g.set_enabled(0, True)
    g.add_half(0, 100, True, [40, 0, 0])
    with pytest.raises(ValueError, match="end of the added half periods"):
        g.set_enabled(5, enabled)
    g.set_enabled(100, enabled)


def test_take_edges_beyond_horizon_raises():
    g = gen()
    with pytest.raises(ValueError):
        g.take_edges(1)
    g.add_half(0, H, True, [40, 0, 0])
    g.take_edges(100)                              # exactly the horizon is fine
    with pytest.raises(ValueError):
        g.take_edges(101)


def test_add_half_out_of_order_raises():
    g = gen()
    with pytest.raises(ValueError):
        g.add_half(100, H, True, [0, 0, 0])       # must start at 0
    g.add_half(0, H, True, [0, 0, 0])
    for start in (0, 50, 99, 101, 200):           # only 100 = the horizon is accepted
        with pytest.raises(ValueError):
            g.add_half(start, H, False, [0, 0, 0])
    g.add_half(100, H, False, [0, 0, 0])
    assert g.horizon == 200


def test_add_half_bad_half_or_compare_raises():
    g = gen()
    with pytest.raises(ValueError):
        g.add_half(0, 1, True, [0, 0, 0])
    with pytest.raises(ValueError):
        g.add_half(0, H, True, [0, H + 1, 0])
    with pytest.raises(ValueError):
        g.add_half(0, H, True, [0, 0, -1])


def test_set_enabled_beyond_horizon_raises():
    g = gen()
    with pytest.raises(ValueError):
        g.set_enabled(1, True)
    g.add_half(0, H, True, [0, 0, 0])
    with pytest.raises(ValueError):
        g.set_enabled(101, True)


# ---- random safety property --------------------------------------------------------------------------
def _ideal(H_: int, halves) -> np.ndarray:
    """s[leg, t] from the spec's definition, tick by tick (halves alternate rising/falling from 0)."""
    P = 2 * H_
    T = H_ * len(halves)
    t = np.arange(T)
    phi = t % P
    s = np.zeros((3, T), dtype=np.int64)
    for leg in range(3):
        cmp = np.array([halves[k][leg] for k in range(len(halves))])[t // H_]
        s[leg] = np.where(phi < H_, phi < cmp, P - phi <= cmp)
    return s


def _last_change(x: np.ndarray) -> np.ndarray:
    """Latest tick tau <= t with x[tau] != x[tau - 1] (x[-1] = 0), 0 if none."""
    prev = np.concatenate([[0], x[:-1]])
    idx = np.where(x != prev, np.arange(len(x)), 0)
    return np.maximum.accumulate(idx)


def _reference_mask(s: np.ndarray, en: np.ndarray, dead: int) -> np.ndarray:
    """Per-tick gate mask from the spec's rules (independent of the generator's event logic)."""
    T = s.shape[1]
    t = np.arange(T)
    en_prev = np.concatenate([[0], en[:-1]])
    en_since = np.maximum.accumulate(np.where((en == 1) & (en_prev == 0), t, 0))
    mask = np.zeros(T, dtype=np.int64)
    for leg in range(3):
        on = (en == 1) & (t >= np.maximum(_last_change(s[leg]), en_since) + dead)
        bit = np.where(s[leg] == 1, 1 << (2 * leg), 1 << (2 * leg + 1))
        mask |= np.where(on, bit, 0)
    return mask


def _mask_from_edges(ticks, masks, T: int) -> np.ndarray:
    out = np.zeros(T, dtype=np.int64)
    for tk, m in zip(ticks, masks):
        out[tk:] = m
    return out


def _random_case(seed: int):
    rng = random.Random(seed)
    H_ = rng.choice([4, 6, 8, 10, 16, 20, 30, 40])
    dead = rng.randint(1, H_)
    n = rng.randint(1, 14)
    special = [0, H_, dead, dead - 1, dead + 1, H_ - dead, H_ - dead - 1, H_ - dead + 1, 1, H_ - 1]
    halves, enables = [], []
    for _ in range(n):
        halves.append([min(H_, max(0, rng.choice(special))) if rng.random() < 0.35 else rng.randint(0, H_)
                       for _ in range(3)])
        enables.append(rng.random() < 0.5 if rng.random() < 0.4 else None)   # None: no call
    return H_, dead, halves, enables


@pytest.mark.parametrize("block", range(4))
def test_random_safety_property(block):
    for seed in range(block * 500, block * 500 + 500):          # 2000 sequences in all
        H_, dead, halves, enables = _random_case(seed)
        rng = random.Random(10**6 + seed)
        g = GateGenerator(dead, dead_min=1)
        g0 = GateGenerator(dead, dead_min=1, switch_ticks=False)    # the same gates without the switch record
        n = len(halves)
        T = H_ * n
        en = np.zeros(T, dtype=np.int64)
        state = 0
        ticks, masks, sw = [], [], []
        taken = 0
        for k in range(n):
            start = k * H_
            if enables[k] is not None:
                g.set_enabled(start, enables[k])
                g0.set_enabled(start, enables[k])
                state = int(enables[k])
            en[start:start + H_] = state
            g.add_half(start, H_, k % 2 == 0, halves[k])
            g0.add_half(start, H_, k % 2 == 0, halves[k])
            if rng.random() < 0.5:                           # stream the edges out in random pieces
                until = rng.randint(taken, g.horizon)
                t_, m_ = g.take_edges(until)
                t0, m0 = g0.take_edges(until)
                assert t0.tolist() == t_.tolist() and m0.tolist() == m_.tolist(), f"seed {seed}"
                assert all(taken <= x < until for x in t_.tolist()), f"seed {seed}"
                ticks += t_.tolist()
                masks += m_.tolist()
                sw += g.take_switch_ticks(until).tolist()
                taken = until
        t_, m_ = g.take_edges(T)
        t0, m0 = g0.take_edges(T)
        assert t0.tolist() == t_.tolist() and m0.tolist() == m_.tolist(), f"seed {seed}"
        ticks += t_.tolist()
        masks += m_.tolist()
        sw += g.take_switch_ticks(T).tolist()
        msg = f"seed {seed}: H {H_} dead {dead} halves {halves} enables {enables}"

        # edges: strictly increasing ticks, every edge changes the mask
        assert ticks == sorted(set(ticks)), msg
        assert all(a != b for a, b in zip([0] + masks, masks)), msg

        s = _ideal(H_, halves)
        got = _mask_from_edges(ticks, masks, T)
        # the two switches of a leg are never on together
        for leg in range(3):
            both = (3 << (2 * leg))
            assert not np.any((got & both) == both), msg
        # every on-interval starts >= dead after the last change of the leg's ideal signal (and after
        # the enabling), and the switch that conducts is the one s selects
        prev = np.concatenate([[0], got[:-1]])
        for leg in range(3):
            lc = _last_change(s[leg])
            for bit, level in ((1 << (2 * leg), 1), (1 << (2 * leg + 1), 0)):
                on = (got & bit) != 0
                starts = np.flatnonzero(on & ((prev & bit) == 0))
                assert np.all(starts >= lc[starts] + dead), msg
                assert np.all(s[leg][on] == level), msg
                assert np.all(en[on] == 1), msg
        # the whole waveform equals the tick-by-tick reference
        ref = _reference_mask(s, en, dead)
        bad = np.flatnonzero(ref != got)
        assert bad.size == 0, f"{msg}: first mismatch at tick {bad[0] if bad.size else None}"
        # switch ticks: the ticks where some leg's ideal signal changes (reset level 0)
        s_prev = np.concatenate([np.zeros((3, 1), dtype=np.int64), s[:, :-1]], axis=1)
        expected_sw = np.flatnonzero(np.any(s != s_prev, axis=0)).tolist()
        assert sw == sorted(sw), msg
        assert sorted(set(sw)) == expected_sw, msg


def test_switch_ticks_not_recorded_when_not_asked():
    g = GateGenerator(D, dead_min=1, switch_ticks=False)
    g.add_half(0, H, True, [40, 40, 0])
    assert g._switch_ticks == []
    with pytest.raises(ValueError, match="switch_ticks=False"):
        g.take_switch_ticks(100)


def test_switch_ticks_one_entry_per_leg_change():
    # Legs a and b both compare 40 on a rising half: both rise at 0 and fall at 40. The generator lists
    # a tick once per leg that changes there (the blanking only needs the set of ticks).
    g = gen()
    g.add_half(0, H, True, [40, 40, 0])
    assert g.take_switch_ticks(100).tolist() == [0, 0, 40, 40]
