"""Safety logic of docs/spec.md section 3.8 (golden/fpga/safety.py, SafetyLogic).

The expected values are derived by hand from the rules of the module docstring, never by re-running
the model:

* ``sto_s(t) = sto(t - 2)`` (0 in clocks 0 and 1), the same for ``desat``;
* ``kill(t) = fault_oc | fault_wdt | fault_sto | fault_desat | sto_s | desat_s`` (latches at the start
  of clock t);
* ``gate`` of clock t is the register value loaded at the end of t: 0 if ``rst(t)`` or ``kill(t)``,
  else ``gate_in(t)``; the gate *pin* shows it in clock t + 1, so an STO pin raised in clock T shows
  ``sto_s`` in T + 2 and all gate pins 0 from clock T + 3 on;
* a latch is set in the clock after its input (``oc_trip``, ``wdt_expired``, ``sto_s``, ``desat_s``),
  ``fault_clear`` clears all four in the next clock, a set in the same clock wins; ``rst`` clears them;
* ``en_applied`` takes ``ctrl_enable`` at ``at_bottom`` and drops in the clock after a kill;
  ``enable = (at_bottom ? ctrl_enable : en_applied) & ~kill``; ``outputs_on = en_applied & ~fault``;
* ``drive_allowed = ~(fault_sto | fault_desat | sto_s | desat_s)``.

The random test checks the model against an independent implementation of these rules written from the
input history (no state machine shared with the model).
"""

from __future__ import annotations

import random

import pytest

from golden.fpga.safety import SYNC_STAGES, SafetyInputs, SafetyLogic, SafetyOutputs

BITS = ("rst", "sto", "desat", "oc_trip", "wdt_expired", "fault_clear", "ctrl_enable", "at_bottom")


def run(inputs: list[SafetyInputs]) -> list[SafetyOutputs]:
    m = SafetyLogic()
    return [m.step(x) for x in inputs]


def seq(n: int, **at) -> list[SafetyInputs]:
    """``n`` clocks of default inputs; ``at[name] = {clock: value}`` or a constant for every clock."""
    out = []
    for t in range(n):
        kw = {}
        for name, v in at.items():
            if isinstance(v, dict):
                if t in v:
                    kw[name] = v[t]
            elif callable(v):
                kw[name] = v(t)
            else:
                kw[name] = v
        out.append(SafetyInputs(**kw))
    return out


def pins(outs: list[SafetyOutputs]) -> list[int]:
    """Gate pins per clock: the register value loaded at the end of the clock before (0 in clock 0)."""
    return [0] + [o.gate for o in outs[:-1]]


def test_sync_stages_is_two():
    assert SYNC_STAGES == 2


def test_idle_outputs():
    for o in run(seq(5)):
        assert o == SafetyOutputs(sto_s=0, desat_s=0, fault_oc=0, fault_wdt=0, fault_sto=0, fault_desat=0,
                                  kill=0, enable=0, outputs_on=0, drive_allowed=1, gate=0)


def test_gate_register_passes_gate_in_without_kill():
    # no fault: gate(t) = gate_in(t), whatever enable is (the gate generator honours enable)
    g = [0x15, 0x2A, 0x3F, 0x00, 0x09, 0x24]
    outs = run(seq(6, gate_in=lambda t: g[t]))
    assert [o.gate for o in outs] == g
    assert pins(outs) == [0] + g[:-1]


@pytest.mark.parametrize("pin", ["sto", "desat"])
@pytest.mark.parametrize("T", [0, 1, 2, 7])
def test_pin_removes_gates_three_clocks_later(pin, T):
    n = T + 10
    outs = run(seq(n, gate_in=0x15, **{pin: lambda t: int(t >= T)}))
    p = pins(outs)
    # the pin shows gate_in until clock T + 2 (inclusive; clock 0 shows the reset value 0)
    assert p[1:T + 3] == [0x15] * (T + 2)
    assert p[T + 3:] == [0] * (n - T - 3)
    sync = [getattr(o, f"{pin}_s") for o in outs]
    assert sync == [0] * (T + 2) + [1] * (n - T - 2)
    assert [o.kill for o in outs] == [0] * (T + 2) + [1] * (n - T - 2)
    assert [o.drive_allowed for o in outs] == [1] * (T + 2) + [0] * (n - T - 2)
    latch = [getattr(o, f"fault_{pin}") for o in outs]
    assert latch == [0] * (T + 3) + [1] * (n - T - 3)
    other = "desat" if pin == "sto" else "sto"
    assert all(getattr(o, f"fault_{other}") == 0 and getattr(o, f"{other}_s") == 0 for o in outs)
    assert all(o.fault_oc == 0 and o.fault_wdt == 0 for o in outs)


@pytest.mark.parametrize("pin", ["sto", "desat"])
def test_one_clock_pulse_is_latched(pin):
    # pulse in clock 3: synchronized in clock 5 only, latched from clock 6 until the clear in clock 20
    outs = run(seq(30, gate_in=0x3F, fault_clear={20: 1}, **{pin: {3: 1}}))
    assert [getattr(o, f"{pin}_s") for o in outs] == [int(t == 5) for t in range(30)]
    assert [getattr(o, f"fault_{pin}") for o in outs] == [int(6 <= t <= 20) for t in range(30)]
    assert [o.kill for o in outs] == [int(5 <= t <= 20) for t in range(30)]
    assert [o.drive_allowed for o in outs] == [int(not 5 <= t <= 20) for t in range(30)]
    assert pins(outs) == [0] + [0 if 6 <= t <= 21 else 0x3F for t in range(1, 30)]


@pytest.mark.parametrize("pin", ["sto", "desat"])
def test_clear_while_pin_held_is_ignored(pin):
    # held from clock 0 to 19 (sto_s 2..21), clears in clocks 5, 10, 21 (the last clock of sto_s = 1)
    # and 22 (the first with sto_s = 0: clears the latch, 0 from clock 23)
    outs = run(seq(30, **{pin: lambda t: int(t < 20)}, fault_clear={5: 1, 10: 1, 21: 1, 22: 1}))
    latch = [getattr(o, f"fault_{pin}") for o in outs]
    assert latch == [int(3 <= t <= 22) for t in range(30)]
    assert [o.kill for o in outs] == [int(2 <= t <= 22) for t in range(30)]
    assert [o.drive_allowed for o in outs] == [int(not 2 <= t <= 22) for t in range(30)]


def test_released_pin_stays_latched_until_clear():
    outs = run(seq(40, sto=lambda t: int(t < 5), fault_clear={30: 1}))
    # sto_s in clocks 2..6; latched 3..30 (the clear of clock 30 acts at its end)
    assert [o.sto_s for o in outs] == [int(2 <= t <= 6) for t in range(40)]
    assert [o.fault_sto for o in outs] == [int(3 <= t <= 30) for t in range(40)]
    assert [o.drive_allowed for o in outs] == [int(not 2 <= t <= 30) for t in range(40)]


@pytest.mark.parametrize("field,inp", [("fault_oc", "oc_trip"), ("fault_wdt", "wdt_expired")])
def test_set_wins_over_clear(field, inp):
    # set in clock 2 (latched 3..), set and clear together in clock 6 (stays 1), clear alone in clock 9
    outs = run(seq(12, **{inp: {2: 1, 6: 1}}, fault_clear={6: 1, 9: 1}))
    assert [getattr(o, field) for o in outs] == [int(3 <= t <= 9) for t in range(12)]
    # set and clear in the same clock from 0: set
    outs = run(seq(4, **{inp: {1: 1}}, fault_clear={1: 1}))
    assert [getattr(o, field) for o in outs] == [0, 0, 1, 1]
    # an oc/wdt fault kills the gates but leaves the driver enabled
    outs = run(seq(12, gate_in=0x21, **{inp: {2: 1}}, fault_clear={9: 1}))
    assert [o.kill for o in outs] == [int(3 <= t <= 9) for t in range(12)]
    assert all(o.drive_allowed == 1 for o in outs)
    assert pins(outs) == [0, 0x21, 0x21, 0x21] + [0] * 7 + [0x21]


def test_clear_clears_all_four_latches():
    x = seq(20, oc_trip={1: 1}, wdt_expired={1: 1}, sto={0: 1}, desat={0: 1}, fault_clear={10: 1})
    outs = run(x)
    for f in ("fault_oc", "fault_wdt", "fault_sto", "fault_desat"):
        exp = [int((3 if f in ("fault_sto", "fault_desat") else 2) <= t <= 10) for t in range(20)]
        assert [getattr(o, f) for o in outs] == exp, f


def test_enable_applies_at_bottoms_and_drops_after_kill():
    # ctrl_enable from clock 2; bottoms at 0, 10, 20, 30, 40; oc trip in clock 15 (latched 16..25),
    # clear in clock 25 (kill 0 from 26): enable back only at the bottom 30
    bottoms = {0, 10, 20, 30, 40}
    x = seq(45, ctrl_enable=lambda t: int(t >= 2), at_bottom=lambda t: int(t in bottoms),
            oc_trip={15: 1}, fault_clear={25: 1})
    outs = run(x)
    en = [o.enable for o in outs]
    assert en == [int(10 <= t <= 15 or t >= 30) for t in range(45)]
    # outputs_on = en_applied & ~fault: en_applied 1 in clocks 11..16 (dropped in the clock after the
    # first kill clock 16), masked by the fault in 16; then from 31 on
    assert [o.outputs_on for o in outs] == [int(11 <= t <= 15 or t >= 31) for t in range(45)]
    assert [o.kill for o in outs] == [int(16 <= t <= 25) for t in range(45)]


def test_enable_off_at_bottom_and_bottom_during_kill():
    # enabled at bottom 0; ctrl_enable falls in clock 5: enable stays 1 until bottom 10 (0 there)
    outs = run(seq(15, ctrl_enable=lambda t: int(t < 5), at_bottom=lambda t: int(t in (0, 10))))
    assert [o.enable for o in outs] == [int(t < 10) for t in range(15)]
    # a bottom in a kill clock does not enable: sto held 0..6 -> sto_s 2..8; bottoms 5 and 12;
    # latch 3..; clear in 9 -> kill 0 from 10; enable only at the bottom 12
    outs = run(seq(20, ctrl_enable=1, sto=lambda t: int(t <= 6), fault_clear={9: 1},
                   at_bottom=lambda t: int(t in (5, 12))))
    assert [o.enable for o in outs] == [int(t >= 12) for t in range(20)]
    assert [o.kill for o in outs] == [int(2 <= t <= 9) for t in range(20)]


def test_reset_clears_latches_enable_and_gate_but_not_synchronizers():
    x = seq(14, ctrl_enable=1, at_bottom={0: 1}, gate_in=0x0C, oc_trip={1: 1}, rst={4: 1, 10: 1},
            sto={9: 1})
    outs = run(x)
    assert [o.fault_oc for o in outs] == [int(2 <= t <= 4) for t in range(14)]
    assert [o.outputs_on for o in outs] == [int(t == 1) for t in range(14)]
    # the STO pulse of clock 9 crosses the synchronizer while rst is high in clock 10: sto_s in 11,
    # latched in 12 (rst only in clock 10)
    assert [o.sto_s for o in outs] == [int(t == 11) for t in range(14)]
    assert [o.fault_sto for o in outs] == [int(t >= 12) for t in range(14)]
    gates = [o.gate for o in outs]
    assert gates == [0x0C, 0x0C, 0, 0, 0, 0x0C, 0x0C, 0x0C, 0x0C, 0x0C, 0, 0, 0, 0]


@pytest.mark.parametrize("name", BITS)
@pytest.mark.parametrize("bad", [2, -1])
def test_non_bit_inputs_raise(name, bad):
    with pytest.raises(ValueError, match=name):
        SafetyLogic().step(SafetyInputs(**{name: bad}))


@pytest.mark.parametrize("bad", [64, -1, 0x100])
def test_gate_in_out_of_six_bits_raises(bad):
    with pytest.raises(ValueError, match="gate_in"):
        SafetyLogic().step(SafetyInputs(gate_in=bad))
    SafetyLogic().step(SafetyInputs(gate_in=0x3F))  # the widest legal mask


def reference(xs: list[SafetyInputs]) -> list[tuple]:
    """Independent implementation of the docstring rules from the input history."""
    out = []
    latch = dict(oc=0, wdt=0, sto=0, desat=0)
    en_applied = 0
    for t, x in enumerate(xs):
        sto_s = xs[t - 2].sto if t >= 2 else 0
        desat_s = xs[t - 2].desat if t >= 2 else 0
        fault = any(latch.values())
        kill = int(fault or sto_s or desat_s)
        en_now = (x.ctrl_enable and not kill) if x.at_bottom else en_applied
        out.append((sto_s, desat_s, latch["oc"], latch["wdt"], latch["sto"], latch["desat"], kill,
                    int(bool(en_now) and not kill), int(bool(en_applied) and not fault),
                    int(not (latch["sto"] or latch["desat"] or sto_s or desat_s)),
                    0 if (x.rst or kill) else x.gate_in))
        if x.rst:
            latch = dict(oc=0, wdt=0, sto=0, desat=0)
            en_applied = 0
            continue
        sets = dict(oc=x.oc_trip, wdt=x.wdt_expired, sto=sto_s, desat=desat_s)
        latch = {k: int(bool(sets[k]) or (bool(latch[k]) and not x.fault_clear)) for k in latch}
        if kill:
            en_applied = 0
        elif x.at_bottom:
            en_applied = x.ctrl_enable
    return out


def test_random_sequences_against_independent_rules(seed):
    rng = random.Random(seed)
    for _ in range(20):
        n = 2000
        p = {k: rng.choice([0.01, 0.05, 0.3]) for k in BITS}
        p["rst"] = 0.005
        xs, level = [], {k: 0 for k in BITS}
        for _t in range(n):
            for k in ("sto", "desat", "ctrl_enable", "wdt_expired"):
                if rng.random() < p[k]:
                    level[k] ^= 1
            xs.append(SafetyInputs(
                rst=int(rng.random() < p["rst"]), sto=level["sto"], desat=level["desat"],
                oc_trip=int(rng.random() < p["oc_trip"]), wdt_expired=level["wdt_expired"],
                fault_clear=int(rng.random() < p["fault_clear"]), ctrl_enable=level["ctrl_enable"],
                at_bottom=int(rng.random() < p["at_bottom"]), gate_in=rng.randrange(64)))
        got = [tuple(o.__dict__.values()) for o in run(xs)]
        assert tuple(SafetyOutputs.__dataclass_fields__) == ("sto_s", "desat_s", "fault_oc", "fault_wdt",
                                                             "fault_sto", "fault_desat", "kill", "enable",
                                                             "outputs_on", "drive_allowed", "gate")
        exp = reference(xs)
        for t, (g, e) in enumerate(zip(got, exp)):
            assert g == e, f"clock {t}: model {g}, rules {e} (inputs {xs[max(0, t - 3):t + 1]})"
