"""Replay of a golden closed loop through the whole IP (hfi_dsp), issue 4 item 3.

The default scenario (scenarios/fullload_start.toml: start-up at standstill under full load) runs on
the golden closed loop for REPLAY_S seconds; its ADC codes feed the ADC model of tb_hfi_dsp.v at the
same sampling ticks and its firmware's register writes are replayed after every window interrupt.
Every window result (GAMMA, GAMMA_D, SUM_ID, SUM_IQ, WSUM, N_SAMPLES, INJ_PHASE, and the differencing/CIC
block's CIC_QA, CIC_QB, ENV_A, ENV_B), every gate edge tick and mask and every sampling instant must
equal the golden trace; VDC (the ADC's third lane, the dc-link code of the window's carrier-bottom sample,
docs/spec.md 3.12) must equal the golden column ``vdc`` in every window of every replay, read 0 after
reset and, after window -1, the dc-link code fed to its samples (write_inputs). Verilator only (20 M
clock cycles). Two shorter replays cover the rotating
injection (CTRL.INJ_ROT) and the 001 method's period square wave with its differencing and CIC
(CTRL.INJ_PER, CIC_M; scenarios/xue2022_noload.toml). TOP_I (the carrier-top sample, docs/spec.md
3.11) is checked in every window against the Clarke currents of the golden ADC codes of the sample at
phase H (top_i_expected: computed here, since the golden loop fills its top_ia/top_ib columns only in
the direct-vector mode); a short replay in the DS mode covers it (and the other results) with two
samples per window.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from golden import regmap as rm
from golden.closedloop import ClosedLoop
from golden.fpga.adc_scale import adc_to_current
from golden.fpga.adc_trigger import MODE_OS_BLANK, sample_phases
from golden.fpga.park import clarke
from golden.fpga.rot_injection import inj_step
from golden.scenario import load_scenario
from hfi import paper
from hdl_runner import TB_DIR, core_rtl_files, rtl_sources, run_cocotb

ROOT = TB_DIR.parent

REPLAY_S = 0.201
"""Simulated time of the replay [s] (>= 0.2 s: 1004 windows at 5 kHz)."""
ROT_REPLAY_S = 0.03
"""Simulated time of the rotating-injection replay [s] (150 windows, 15 turns of a 500 Hz injection)."""
PER_REPLAY_S = 0.1
"""Simulated time of the period-square-wave replay [s] (99 windows at 1 kHz, 10 M clock cycles)."""
DS_REPLAY_S = 0.03
"""Simulated time of the DS-mode replay [s] (150 windows at 5 kHz)."""
RTL_FILES = core_rtl_files()
"""The Verilog sources of hfi_dsp, as listed in hfi_dsp.core."""


def top_i_expected(res) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """TOP_I (docs/spec.md 3.11) of every window from the golden samples, independently of the golden
    loop: the Clarke currents (golden.fpga.park.clarke of adc_to_current) of window k's sample at the
    carrier top (tick k*P + H), or the previous value (0 after reset) when the window has none.
    Returns (I_ALPHA, I_BETA, checked); an OS_BLANK window with a top sample may have blanked it (the
    trace does not carry the keep flags), so TOP_I is unchecked from there to the next window with an
    OS or DS top sample."""
    hw, H = res.hw, res.hw.pwm_half
    tick, code_a, code_b = res.samples["tick"], res.samples["adc_a"], res.samples["adc_b"]
    modes = res.windows["adc_mode"]
    n = len(res.windows["gamma"])
    ia, ib, chk = np.zeros(n, dtype=np.int64), np.zeros(n, dtype=np.int64), np.ones(n, dtype=bool)
    cur, known = (0, 0), True
    for k in range(n):
        t = k * 2 * H + H
        j = int(np.searchsorted(tick, t))
        if j < len(tick) and tick[j] == t:
            if modes[k] == MODE_OS_BLANK:
                known = False
            else:
                i_al, i_be = clarke(adc_to_current(int(code_a[j]), hw.adc_bits, hw.adc_offset[0], hw.adc_gain[0]),
                                    adc_to_current(int(code_b[j]), hw.adc_bits, hw.adc_offset[1], hw.adc_gain[1]))
                cur, known = (int(i_al), int(i_be)), True
        ia[k], ib[k], chk[k] = cur[0], cur[1], known
    return ia, ib, chk


def adc_words(res) -> tuple[np.ndarray, int]:
    """The ADC model's codes.hex words (cocotb_tests/hdl/adc_model.v: "ccccaaaabbbb", C = the dc-link lane),
    one per conversion in order, and the dc-link code of window -1. Window -1 (the samples before tick
    H/2, which the golden loop does not run) converts mid-scale (0 A) currents and the dc-link code of the
    golden loop's first sample (the dc link is charged before tick 0); then every golden sample's codes."""
    hw, H = res.hw, res.hw.pwm_half
    pre = int(np.count_nonzero(sample_phases(hw.adc_mode, H, hw.os_ticks) < H // 2))  # window -1
    mid = 1 << (hw.adc_bits - 1)
    a, b, c = (res.samples[k].astype(np.int64) for k in ("adc_a", "adc_b", "adc_vdc"))
    assert len(a) == len(b) == len(c), "golden samples: adc_a, adc_b, adc_vdc differ in length"
    top = (1 << hw.adc_bits) - 1
    assert ((0 <= c) & (c <= top)).all(), f"golden adc_vdc outside 0..{top}"
    vdc_pre = int(c[0])
    words = np.concatenate([np.full(pre, (vdc_pre << 32) | (mid << 16) | mid, dtype=np.int64),
                            (c << 32) | (a << 16) | b])
    return words, vdc_pre


def write_inputs(res, build_dir) -> None:
    """codes.hex for the ADC model and trace.npz for the cocotb side."""
    hw, H = res.hw, res.hw.pwm_half
    first = H // 2
    words, vdc_pre = adc_words(res)
    build_dir.mkdir(parents=True, exist_ok=True)
    (build_dir / "codes.hex").write_text("".join(f"{v:012x}\n" for v in words))
    cfg = {"pwm_half": hw.pwm_half, "dead_ticks": hw.dead_ticks, "os_ticks": hw.os_ticks,
           "blank_ticks": hw.blank_ticks, "cw_angle_step": hw.cw_angle_step, "adc_mode": hw.adc_mode,
           "dtc_gain": hw.dtc_gain, "hf_amp": hw.hf_amp, "recip_h": hw.recip_h,
           "adc_offset_a": hw.adc_offset[0], "adc_offset_b": hw.adc_offset[1],
           "adc_gain_a": hw.adc_gain[0], "adc_gain_b": hw.adc_gain[1], "inj_rot": hw.inj_rot,
           "inj_step": hw.inj_step, "inj_per": hw.inj_per, "cic_m": hw.cic_m,
           # configure before tick 0 (tb_dsp_replay.py) when the carrier is not the reset one, with the
           # period square wave (its sign at tick 0's bottom follows CTRL.INJ_PER), or with an ADC mode other
           # than the reset one (window -1's sampling instants follow CTRL.ADC_MODE while held)
           "start_held": int(hw.pwm_half != rm.PWM_HALF_VALUE_RESET or hw.cw_angle_step != rm.CW_ANGLE_STEP_VALUE_RESET
                             or bool(hw.inj_per) or hw.adc_mode != rm.CTRL_ADC_MODE_RESET)}
    n_win = len(res.windows["gamma"])
    top_ia, top_ib, top_chk = top_i_expected(res)
    np.savez(build_dir / "trace.npz", top_exp_ia=top_ia, top_exp_ib=top_ib, top_exp_chk=top_chk,
             vdc_pre=np.int64(vdc_pre),
             **{f"win_{k}": v for k, v in res.windows.items() if v.dtype.kind == "i"},
             **{f"write_{k}": v for k, v in res.writes.items()},
             edge_tick=res.edges["tick"], edge_mask=res.edges["mask"], sample_tick=res.samples["tick"],
             end_tick=np.int64(n_win * 2 * H + first), first_window_tick=np.int64(first),
             **{f"cfg_{k}": np.int64(v) for k, v in cfg.items()})


def replay(res, tmp_path) -> None:
    """Replay a golden closed-loop result through hfi_dsp (tb_dsp_replay.py compares)."""
    build = tmp_path / "build"
    write_inputs(res, build)
    run_cocotb(sim="verilator", toplevel="tb_hfi_dsp",
               sources=[*rtl_sources(*RTL_FILES), TB_DIR / "hdl" / "adc_model.v", TB_DIR / "hdl" / "tb_hfi_dsp.v"],
               tb_module="tb_dsp_replay", build_dir=build, parameters={"ADC_BITS": res.hw.adc_bits},
               env={"HFI_REPLAY_TRACE": build / "trace.npz"}, build_args=["--timing"], expect_tests=1)


@pytest.mark.long
def test_replay_default_scenario(tmp_path):
    sc = paper.experiment("replay", {"scenario": {"duration": REPLAY_S}})
    res = ClosedLoop(sc).run(progress=False)
    assert len(res.windows["gamma"]) >= 1000
    assert res.windows["mode"].max() > 0, "the golden run never left the first supervisor state"
    top_ia, top_ib, top_chk = top_i_expected(res)
    assert top_chk.all() and len(np.unique(top_ia)) > 10 and len(np.unique(top_ib)) > 10
    replay(res, tmp_path)


def test_replay_ds_mode(tmp_path):
    """The default closed loop in the DS mode (CTRL.ADC_MODE = 1: the carrier bottom and top samples
    only; a held start, since window -1 already samples in that mode): every window result, TOP_I from
    the top sample of every window, gate edges and sampling instants."""
    sc = paper.experiment("replay", {"scenario": {"duration": DS_REPLAY_S}, "control": {"adc_mode": "DS"}})
    res = ClosedLoop(sc).run(progress=False)
    assert res.hw.adc_mode == 1 and (res.windows["n_samples"] == 2).all()
    top_ia, top_ib, top_chk = top_i_expected(res)
    assert top_chk.all() and len(np.unique(top_ia)) > 10 and len(np.unique(top_ib)) > 10
    replay(res, tmp_path)


def test_replay_rotating_injection(tmp_path):
    """The same closed loop with the rotating injection (CTRL.INJ_ROT, INJ_STEP for 500 Hz, amplitude
    V_H as the firmware writes it): gate edges and INJ_PHASE through the phase accumulator, the
    injection CORDIC and the modulator's rotating products, against golden/fpga/rot_injection.py."""
    sc = paper.experiment("replay", {"scenario": {"duration": ROT_REPLAY_S}})
    loop = ClosedLoop(sc)
    loop.hw = dataclasses.replace(loop.hw, inj_rot=1, inj_step=inj_step(500.0, sc.pwm.f_sw))
    res = loop.run(progress=False)
    assert res.windows["inj_phase"][-1] != 0 and (res.writes["v_h"] > 0).any()
    replay(res, tmp_path)


@pytest.mark.long
def test_replay_period_square_wave(tmp_path):
    """The 001 drive (scenarios/xue2022_noload.toml, 1 kHz, PWM_HALF 50000: a held start) for 0.1 s: the
    period square wave (CTRL.INJ_PER: the sign S flips at every carrier bottom, the modulator's compares
    with V_D + S*V_H) and the differencing and CIC block of the carrier-bottom samples (CIC_M = 2):
    every CIC_QA, CIC_QB, ENV_A, ENV_B, window result and gate edge equal golden/closedloop.py."""
    sc = load_scenario(ROOT / "scenarios" / "xue2022_noload.toml")
    res = ClosedLoop(dataclasses.replace(sc, duration=PER_REPLAY_S)).run(progress=False)
    w = res.windows
    assert res.hw.inj_per == 1 and res.hw.cic_m == 2 and (res.writes["v_h"] > 0).any()
    # the envelope took both signs' periods apart: nonzero and changing CIC outputs
    assert np.count_nonzero(w["cic_qa"]) > len(w["cic_qa"]) // 2 and len(np.unique(w["env_b"])) > 10
    replay(res, tmp_path)
