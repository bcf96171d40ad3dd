"""cocotb side of the golden closed-loop replay through hfi_dsp (see test_dsp_replay.py).

The ADC model of tb_hfi_dsp.v returns the golden ADC codes (codes.hex, written by the pytest side);
this coroutine plays the firmware: after every window interrupt it reads the window results over
AXI4-Lite (with INJ_PHASE, the differencing/CIC block's CIC_QA, CIC_QB, ENV_A, ENV_B, the dc-link code VDC,
the window's fault latches WIN_FAULT, its frozen lanes WIN_ADC and the carrier-top sample TOP_I), compares them
with the golden window (VDC, WIN_FAULT, WIN_ADC, the whole 32-bit words, with the golden columns ``vdc``,
``win_fault``, ``win_adc``; TOP_I with the trace's top_exp_* columns, computed by
test_dsp_replay.top_i_expected from the golden ADC codes), writes the golden firmware's registers and
commits. VDC must read 0 after reset until the first window boundary, and after window -1 the dc-link code
of its carrier-bottom sample (the trace's ``vdc_pre``, test_dsp_replay.adc_words). The gate edges and
sampling instants recorded by the Verilog are compared at the end; then ``replay_summary.json`` in the test
directory gives the counts compared.

The registers the SoC's CPU reads from its copy (``golden.regmap.WINDOW_COPY``, rtl/hfi_win_copy.v) must hold
from hfi_dsp's window_tog flip on: tb_hfi_dsp's check (``win_copy_mask``, driven here) counts every change of
one of them in the clock of a flip or in the WIN_HOLD (64) clocks after it, which must be none, and the flips,
which must be one per window interrupt (checked after every interrupt: interrupt j follows the flip of window
j - 1 by one clock), and the fewest clocks from a flip to the next change of a copied register (win_hold_min;
at least one seen by the end) must reach the next window boundary: the period minus IRQ_LATENCY + 1.

Start-up: by default the carrier runs from reset (its registers must equal the reset values) and the
configuration is written before the first window boundary. A trace with ``cfg_start_held`` = 1 (a
carrier other than the reset one, or the period square wave, whose sign at tick 0's bottom follows
CTRL.INJ_PER) holds the timing (tb_hfi_dsp's ``hold``, hfi_dsp's ``run`` = 0), writes every register,
waits for the carrier's H*STEP product and releases it: tick 0 comes after the configuration, as in
the SoC.
"""

from __future__ import annotations

import json
import os

import cocotb
import numpy as np
from cocotb.triggers import ClockCycles, RisingEdge, with_timeout

from axil_driver import AxiLiteMaster
from golden import regmap as rm

from hfi.soc_platform import PIN_LATENCY

GATE_LATENCY = CONVST_LATENCY = PIN_LATENCY
"""hfi_dsp's gate pins show the golden gate mask of tick t in cycle t + GATE_LATENCY, the ADC's CONVST
of the sample taken at tick t rises in cycle t + CONVST_LATENCY (hfi/soc_platform.py, docs/rtl.md)."""

RESULTS = (("GAMMA", "gamma", True), ("GAMMA_D", "gamma_d", True), ("SUM_ID", "sum_id", True),
           ("SUM_IQ", "sum_iq", True), ("WSUM", "wsum", True), ("N_SAMPLES", "n_samples", False),
           ("INJ_PHASE", "inj_phase", False), ("CIC_QA", "cic_qa", True), ("CIC_QB", "cic_qb", True),
           ("ENV_A", "env_a", True), ("ENV_B", "env_b", True), ("VDC", "vdc", False),
           ("WIN_FAULT", "win_fault", False), ("WIN_ADC", "win_adc", False))


SUMMARY = "replay_summary.json"
"""Written into the test directory once every window, gate edge and sampling instant compared equal: the counts of
each (``windows``, ``top_i_windows``, ``gate_edges``, ``samples``)."""


WINDOW_COPY_MASK = sum(1 << rm.REGISTERS[name]["addr"] // 4 for name in rm.WINDOW_COPY)
"""tb_hfi_dsp's win_copy_mask: bit i for the window-copy register at byte address 4*i."""
WIN_HOLD = 64
"""tb_hfi_dsp's WIN_HOLD (its default): no copied word may change in the flip's clock or the 64 after it."""
NONE_SEEN = 0xFFFFFFFF
"""win_hold_min before any change of a copied word after a flip."""
DSP_IRQ_LATENCY = 400
"""hfi_dsp's default IRQ_LATENCY (tb_hfi_dsp keeps it; tb_dsp_safety.IRQ_LATENCY): window_tog flips IRQ_LATENCY + 1
clocks after the window boundary, so the copied registers hold for a period minus IRQ_LATENCY + 1 clocks."""


def window_copy_check(dut, flips: int | None = None, where: str = "", hold: int = WIN_HOLD + 1) -> tuple[int, int]:
    """tb_hfi_dsp's window-copy check (win_copy_mask driven since the reset): no copied register changed
    within WIN_HOLD clocks of a window_tog flip (none earlier than ``hold`` clocks after one), and ``flips``
    flips (None: at least one). Returns (flips, win_hold_min)."""
    n, errors, hold_min = (int(getattr(dut, k).value) for k in ("win_tog_flips", "win_copy_errors", "win_hold_min"))
    assert errors == 0, (f"{where}{errors} changes of window-copy registers in the clock of a window_tog flip or the "
                         f"{WIN_HOLD} clocks after it (the first printed by tb_hfi_dsp); fewest clocks {hold_min}")
    assert hold_min >= hold, (f"{where}a window-copy register changed {hold_min} clocks after a window_tog flip, "
                              f"expected none before {hold} clocks")
    assert (n > 0) if flips is None else (n == flips), f"{where}window_tog flipped {n} times, expected {flips or '> 0'}"
    return n, hold_min


def s32(v: int) -> int:
    return v - (1 << 32) if v & (1 << 31) else v


@cocotb.test()
async def replay_golden_closed_loop(dut):
    tr = dict(np.load(os.environ["HFI_REPLAY_TRACE"]))
    n_win = len(tr["win_gamma"])
    cocotb.log.info(f"replaying {n_win} golden windows")
    axi = AxiLiteMaster(dut, "s_axil", dut.clk)
    cfg = {k: int(tr[f"cfg_{k}"]) for k in ("pwm_half", "dead_ticks", "os_ticks", "blank_ticks",
                                            "cw_angle_step", "adc_mode", "dtc_gain", "hf_amp", "recip_h",
                                            "adc_offset_a", "adc_offset_b", "adc_gain_a", "adc_gain_b",
                                            "inj_rot", "inj_step", "inj_per", "cic_m", "start_held")}
    held = bool(cfg["start_held"])
    dut.flush.value = 0
    dut.hold.value = int(held)
    dut.win_copy_mask.value = WINDOW_COPY_MASK
    dut.rst.value = 1
    await ClockCycles(dut.clk, 20)
    dut.rst.value = 0

    # Start-up configuration: while the timing is held, or (the carrier already running from the reset
    # values, checked equal) before the first boundary.
    if not held:
        assert cfg["pwm_half"] == rm.PWM_HALF_VALUE_RESET and cfg["cw_angle_step"] == rm.CW_ANGLE_STEP_VALUE_RESET, \
            "the replay assumes the scenario's carrier equals the register reset values (or a held start)"
    ctrl_bits = dict(INJ_EN=1, INJ_ROT=cfg["inj_rot"], INJ_PER=cfg["inj_per"], ADC_MODE=cfg["adc_mode"])
    writes = [("PWM_HALF", rm.pack("PWM_HALF", VALUE=cfg["pwm_half"])),
              ("CW_ANGLE_STEP", rm.pack("CW_ANGLE_STEP", VALUE=cfg["cw_angle_step"])),
              ("DEAD_TICKS", rm.pack("DEAD_TICKS", VALUE=cfg["dead_ticks"])),
              ("OS_TICKS", rm.pack("OS_TICKS", VALUE=cfg["os_ticks"])),
              ("BLANK_TICKS", rm.pack("BLANK_TICKS", VALUE=cfg["blank_ticks"])),
              ("ADC_OFFSET", rm.pack("ADC_OFFSET", A=cfg["adc_offset_a"], B=cfg["adc_offset_b"])),
              ("ADC_GAIN", rm.pack("ADC_GAIN", A=cfg["adc_gain_a"], B=cfg["adc_gain_b"])),
              ("DTC_GAIN", rm.pack("DTC_GAIN", VALUE=cfg["dtc_gain"])),
              ("HF_AMP", rm.pack("HF_AMP", VALUE=cfg["hf_amp"])),
              ("RECIP_H", rm.pack("RECIP_H", VALUE=cfg["recip_h"])),
              ("INJ_STEP", rm.pack("INJ_STEP", VALUE=cfg["inj_step"])),
              ("CIC_M", rm.pack("CIC_M", VALUE=cfg["cic_m"])),
              ("IRQ_ENABLE", rm.pack("IRQ_ENABLE", WINDOW=1)),
              ("CTRL", rm.pack("CTRL", **ctrl_bits))]
    for name, value in writes:
        await axi.write(rm.REGISTERS[name]["addr"], value)
    # VDC after reset: 0 (held: the timing is in reset; else tick 0's bottom sample is converted or being
    # converted, but VDC only takes it at the first window boundary, checked below to be still ahead)
    value, resp = await axi.read(rm.VDC_ADDR)
    assert (value, resp) == (rm.REGISTERS["VDC"]["reset"], 0), \
        f"VDC before the first window boundary: 0x{value:08X} (resp {resp}), expected the reset 0"
    if held:
        await ClockCycles(dut.clk, 20)      # the carrier's H*STEP product (docs/rtl.md: reset >= 20 clocks)
        assert int(dut.tick.value) == 0, "the timing ran while held"
        dut.hold.value = 0
    else:
        assert int(dut.tick.value) < cfg["pwm_half"] // 2, "configuration not done before the first boundary"

    w = {k[len("write_"):]: tr[k] for k in tr if k.startswith("write_")}
    top_exp = np.stack([tr["top_exp_ia"], tr["top_exp_ib"]], axis=1)
    top_chk = tr["top_exp_chk"]
    mismatches = []
    for j in range(n_win + 1):          # interrupt j reports window j - 1 (window -1: before tick H/2)
        await with_timeout(RisingEdge(dut.irq), 4 * cfg["pwm_half"] * 10, "ns")
        got = {}
        for reg, _, signed in RESULTS:
            value, resp = await axi.read(rm.REGISTERS[reg]["addr"])
            assert resp == 0, f"read of {reg} answered {resp}"
            got[reg] = s32(value) if signed else value
        value, resp = await axi.read(rm.TOP_I_ADDR)
        assert resp == 0, f"read of TOP_I answered {resp}"
        top = rm.unpack("TOP_I", value)
        got_top = (top["I_ALPHA"], top["I_BETA"])
        if j == 0:
            assert got_top == (0, 0), f"TOP_I after window -1 (no top sample) is {got_top}, expected the reset 0"
            assert got["VDC"] == int(tr["vdc_pre"]), \
                f"VDC after window -1 is {got['VDC']}, expected {int(tr['vdc_pre'])} (its bottom sample's dc-link code)"
        window_copy_check(dut, j + 1, f"interrupt {j}: ", 2 * cfg["pwm_half"] - DSP_IRQ_LATENCY - 1)
        if j >= 1:
            k = j - 1
            for reg, col, _ in RESULTS:
                if got[reg] != int(tr[f"win_{col}"][k]):
                    mismatches.append(f"window {k}: {reg} RTL {got[reg]} golden {int(tr[f'win_{col}'][k])}")
            exp_top = (int(top_exp[k, 0]), int(top_exp[k, 1]))
            if top_chk[k] and got_top != exp_top:
                mismatches.append(f"window {k}: TOP_I (I_ALPHA, I_BETA) RTL {got_top} golden {exp_top}")
            if mismatches:
                break
            o = {f: int(w[f][k]) for f in w}
            await axi.write(rm.V_DQ_ADDR, rm.pack("V_DQ", V_D=o["v_d"], V_Q=o["v_q"]))
            await axi.write(rm.V_H_ADDR, rm.pack("V_H", VALUE=o["v_h"]))
            await axi.write(rm.SINCOS_ADDR, rm.pack("SINCOS", SIN=o["sin"], COS=o["cos"]))
            await axi.write(rm.I_REF_ADDR, rm.pack("I_REF", I_D=o["i_d_ref"], I_Q=o["i_q_ref"]))
            await axi.write(rm.CTRL_ADDR, rm.pack("CTRL", ENABLE=o["enable"], **ctrl_bits))
            await axi.write(rm.COMMIT_ADDR, rm.pack("COMMIT", GO=1))
        await axi.write(rm.IRQ_STATUS_ADDR, rm.pack("IRQ_STATUS", WINDOW=1))
    assert not mismatches, "window results differ from the golden model:\n" + "\n".join(mismatches[:20])

    status, _ = await axi.read(rm.STATUS_ADDR)
    late, _ = await axi.read(rm.LATE_COUNT_ADDR)
    assert rm.unpack("STATUS", status)["FAULT_OC"] == 0 and rm.unpack("STATUS", status)["FAULT_WDT"] == 0, \
        f"a fault was latched: STATUS = 0x{status:X}"
    # Windows -1 and 0 have no commit (the golden firmware's first output is committed at window 2).
    assert late == 2, f"LATE_COUNT = {late}, expected 2"

    flips, hold_min = window_copy_check(dut, n_win + 1, hold=2 * cfg["pwm_half"] - DSP_IRQ_LATENCY - 1)
    assert hold_min != NONE_SEEN, "no change of a window-copy register after a window_tog flip was checked"
    cocotb.log.info(f"window copy: {flips} window_tog flips, no copied register changed within {WIN_HOLD} clocks of "
                    f"one; the fewest clocks from a flip to the next change: {hold_min}")

    dut.flush.value = 1
    await ClockCycles(dut.clk, 2)
    end = int(tr["end_tick"])
    rtl_edges = np.loadtxt("gates.txt", dtype=np.int64, ndmin=2)
    rtl_edges = rtl_edges[rtl_edges[:, 0] - GATE_LATENCY < end]
    gold_ticks, gold_masks = tr["edge_tick"], tr["edge_mask"]
    n = min(len(rtl_edges), len(gold_ticks))
    bad = np.flatnonzero((rtl_edges[:n, 0] - GATE_LATENCY != gold_ticks[:n]) | (rtl_edges[:n, 1] != gold_masks[:n]))
    assert len(rtl_edges) == len(gold_ticks) and bad.size == 0, (
        f"gate edges differ: RTL {len(rtl_edges)} edges, golden {len(gold_ticks)}; first difference at "
        f"edge {bad[0] if bad.size else n}: RTL {rtl_edges[bad[0]] if bad.size else '-'} (tick + GATE_LATENCY, mask), "
        f"golden {(gold_ticks[bad[0]], gold_masks[bad[0]]) if bad.size else '-'}")
    convst = np.loadtxt("convst.txt", dtype=np.int64, ndmin=1) - CONVST_LATENCY
    convst = convst[(convst >= int(tr["first_window_tick"])) & (convst < end)]
    assert np.array_equal(convst, tr["sample_tick"]), (
        f"sampling instants differ: RTL {len(convst)}, golden {len(tr['sample_tick'])} samples")
    with open(SUMMARY, "w") as f:       # what was compared, for the caller (scripts/gatelevel.py)
        json.dump({"windows": n_win, "top_i_windows": int(np.count_nonzero(top_chk)),
                   "gate_edges": int(len(gold_ticks)), "samples": int(len(convst))}, f)
    cocotb.log.info(f"replay equal: {n_win} windows ({', '.join(r for r, _, _ in RESULTS)}, TOP_I in "
                    f"{int(np.count_nonzero(top_chk))}), {len(gold_ticks)} gate edges, "
                    f"{len(convst)} sampling instants")
