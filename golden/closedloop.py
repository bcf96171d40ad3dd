"""The golden closed loop: plant + bit-true FPGA blocks + bit-true firmware, event-exact.

One iteration per integration window ``k`` = ticks ``[k·P + H/2, (k+1)·P + H/2)`` (docs/spec.md, 2):

1. at the window boundary the pending commit (firmware output of window ``k−2``) becomes active;
2. the compare values of the top of period ``k`` and the bottom of period ``k+1`` are latched from the
   active registers (modulator) and fed to the dead-time gate generator; the enable written by the
   firmware after window ``k−1`` takes effect at that bottom;
3. the plant runs through the window with the gate edges and the ADC sampling instants (one C call);
4. ADC scale -> Clarke/Park with the active sin/cos -> CORDIC weights -> demodulator: the window result;
5. the firmware task runs on it; its register writes are committed at the boundary after next.

Everything between the ADC codes and the gate edges is integer arithmetic of ``golden.fpga`` and
``golden.firmware``; the plant is the C library. The RTL co-simulation makes the same plant calls in
the same order, so the traces are identical.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from golden.control_config import HardwareConfig, Scales, firmware_params, hardware_config, scales
from golden.firmware.supervisor import MODE_NAMES, RESET_OUTPUTS, Firmware, Outputs
from golden.fpga.adc_frozen import frozen_lanes
from golden.fpga.adc_scale import adc_to_current
from golden.fpga.adc_trigger import MODE_DS, MODE_OS_BLANK, blank_mask, sample_phases
from golden.fpga.carrier import counter
from golden.fpga.cordic import demod_weight
from golden.fpga.deadtime_comp import compensate
from golden.fpga.demodulator import WindowResult
from golden.fpga.diff_cic import DiffCic
from golden.fpga.gate_generator import GateGenerator
from golden.fpga.overcurrent import OvercurrentLatch, cut_edges
from golden.fpga.modulator import compares, direct_compares, direct_state
from golden.fpga.park import clarke
from golden.fpga.rot_injection import RotatingInjection
from golden.fpga.window_dsp import window_dsp
from golden.plant import STATE_DTYPE, Plant
from golden.scenario import Scenario

WINDOW_FIELDS = (
    "tick", "gamma", "gamma_d", "n_samples", "sum_id", "sum_iq", "wsum", "i_d", "i_q", "i_d_ref", "i_q_ref",
    "v_d", "v_q", "sin", "cos", "theta_hat", "omega_f", "speed_ref", "mode", "fault",
    "adc_mode", "cmp_top_a", "cmp_top_b", "cmp_top_c", "cmp_bot_a", "cmp_bot_b", "cmp_bot_c",
    "est", "theta_lo", "theta_hi", "omega_lo", "omega_hi", "inj_phase", "cic_qa", "cic_qb", "env_a", "env_b",
    "vector", "vector_next", "top_ia", "top_ib", "vdc", "win_fault", "win_adc", "theta_e", "omega_m", "torque",
    "load_torque", "i_d_true", "i_q_true",
    "e_cu", "q_d", "q_q", "t_int", "t2_int")
"""Per-window trace columns (integers of the spec, and the plant's truth at the window end; ``e_cu``, ``q_d``,
``q_q``, ``t_int``, ``t2_int`` are the plant's running integrals of the copper loss, i_d, i_q, the torque and
its square since t = 0, whose differences give exact window means: hfi.ripple). ``est`` is
the estimator slot in charge (0 low-speed, 1 high-speed), ``theta_lo/hi`` and ``omega_lo/hi`` each slot's
outputs (docs/methods.md), ``inj_phase`` the rotating injection's phase in the window (``INJ_PHASE``),
``cic_qa/qb`` and ``env_a/b`` the differencing and CIC block's outputs (``golden.fpga.diff_cic``), ``win_fault`` and
``win_adc`` the registers ``WIN_FAULT`` and ``WIN_ADC`` as the firmware read them (spec 2.2, 3.7, 3.13)."""


OUTPUT_FIELDS = ("v_d", "v_q", "v_h", "sin", "cos", "enable", "i_d_ref", "i_q_ref")
"""Per-window register writes of the firmware (golden.firmware.supervisor.Outputs): written after window
``k``, committed at the boundary of window ``k + 2``; ``enable`` applies at the bottom of period ``k + 2``."""


def profile_at(points: list[tuple[float, float]], t: np.ndarray) -> np.ndarray:
    """Piecewise-linear profile, held outside its points; at equal times the later point wins."""
    if not points:
        return np.zeros_like(t)
    ts = np.array([p[0] for p in points])
    vs = np.array([p[1] for p in points])
    idx = np.searchsorted(ts, t, side="right") - 1
    out = np.empty_like(t)
    before = idx < 0
    out[before] = vs[0]
    last = idx >= len(ts) - 1
    out[last & ~before] = vs[-1]
    mid = ~before & ~last
    i = idx[mid]
    span = ts[i + 1] - ts[i]
    frac = np.where(span > 0, (t[mid] - ts[i]) / np.where(span > 0, span, 1.0), 1.0)
    out[mid] = vs[i] + frac * (vs[i + 1] - vs[i])
    return out


@dataclass
class ClosedLoopResult:
    """Traces of a closed-loop run."""

    windows: dict            # WINDOW_FIELDS -> array (one entry per window)
    samples: dict            # "tick", "adc_a", "adc_b", "adc_vdc" (every ADC sample, as converted)
    edges: dict              # "tick", "mask": every gate-mask change (mask after the tick)
    writes: dict             # OUTPUT_FIELDS -> array: the firmware's register values after each window
    hw: HardwareConfig
    scales: Scales
    tick_hz: float
    flipped: int
    wall_s: float
    soc: dict | None = None  # rtl backend only: firmware cycles, late commits, co-simulation speed, UART log
    backend: str = "golden"  # golden, rtl or hls
    plant_wall_s: float | None = None  # hls backend: wall seconds inside the plant calls (of wall_s)
    ident: object = None     # control.mode = "commission" (golden, hls): the identification executor at the end
                             # (golden.firmware.ident.Ident: its sums for golden.commission.reduce); None otherwise

    @property
    def t(self) -> np.ndarray:
        """Window end times [s]."""
        return self.windows["tick"] / self.tick_hz

    def angle_error_deg(self, column: str = "theta_hat", quarters: int = 2) -> np.ndarray:
        """Electrical angle error per window [deg], wrapped to +-180: the true angle in the middle of
        window ``k`` minus the angle the hardware used during window ``k`` (``column`` written after
        window ``k - 2``, committed at the boundary of ``k``; the reset angle 0 before). ``column``:
        ``theta_hat`` (the angle in use) or one estimator slot's output, ``theta_lo`` / ``theta_hi``.
        The middle is halfway between the window-end angles of ``k - 1`` and ``k`` (``k = 0``: its end);
        ``quarters = 3`` takes the true angle three quarters into the window instead: at the carrier
        bottom, the sampling instant of the 001 method (golden.fpga.diff_cic), and the middle of the state
        the direct-vector mode applies (003). A reluctance machine's errors are wrapped to +-90 instead
        (``scales.angle_period_deg``: its d axis and the opposite one look alike)."""
        th = self.windows["theta_e"].astype(np.int64)
        prev = np.concatenate([th[:1], th[:-1]])
        mid = prev + (((th - prev + 2**31) % 2**32 - 2**31) * quarters // 4)
        used = np.concatenate([np.zeros(2, dtype=np.int64), self.windows[column][:-2].astype(np.int64)])[:len(th)]
        period = round(2**32 * self.scales.angle_period_deg / 360.0)     # a reluctance machine: +-90 deg
        err = (mid - used + period // 2) % period - period // 2
        return err * (360.0 / 2**32)


def speed_references(sc: Scenario, hw: HardwareConfig, sc_: Scales) -> np.ndarray:
    """The firmware's speed reference of every window of the run (int32, one per window; its length is
    the number of windows): the scenario's reference profile at each window end, in speed LSB.
    Every backend runs exactly these windows. ValueError if the run is shorter than one window."""
    H, P, tick_hz = hw.pwm_half, 2 * hw.pwm_half, sc.pwm.tick_hz
    n_win = int((round(sc.duration * tick_hz) - H // 2) // P)
    if n_win < 1:
        raise ValueError(f"duration {sc.duration} s is shorter than one PWM period")
    win_end = (np.arange(n_win, dtype=np.int64) + 1) * P + H // 2
    return np.array([sc_.speed_mech(v) for v in profile_at(sc.reference_speed, win_end / tick_hz)], dtype=np.int32)


class ClosedLoop:
    """Closed-loop simulation of one scenario (``control.mode`` closed or fixed_angle)."""

    def __init__(self, sc: Scenario):
        if sc.control is None:
            raise ValueError(f"scenario {sc.name} has no [control] settings")
        self.sc = sc
        self.hw = hardware_config(sc)
        self.scales = scales(sc)
        self.fw = Firmware(firmware_params(sc))
        self.plant = Plant(sc.plant)
        self.half = self.hw.pwm_half
        # the switching instants only for the blanking (OS_BLANK is fixed for a run; the DS switch leaves it)
        self.gen = GateGenerator(self.hw.dead_ticks, switch_ticks=self.hw.adc_mode == MODE_OS_BLANK)
        self.rot_inj = RotatingInjection()
        self.diff_cic = DiffCic()
        self._pattern = {}

    def _window_pattern(self, mode: int):
        """Sample offsets from the window start, their CORDIC weights, and the index of the carrier-bottom sample
        (``P - H/2`` after the window start, in every mode; identical every window)."""
        if mode not in self._pattern:
            H, P = self.half, 2 * self.half
            phases = sample_phases(mode, H, self.hw.os_ticks)
            rel = np.sort((phases - H // 2) % P).astype(np.int64)
            c = counter((rel + H // 2) % P, H)
            w = demod_weight(c, H, self.hw.cw_angle_step)
            self._pattern[mode] = (rel, np.asarray(w, dtype=np.int16),   # s16 (spec 3.4): window_dsp takes it as is
                                   int(np.searchsorted(rel, P - H // 2)))
        return self._pattern[mode]

    def _compares(self, o: Outputs, sign: int, rot: tuple[int, int] | None = None, inj_sign: int | None = None):
        """The compares of one half (``sign``: -1 rising, +1 falling); ``inj_sign``: the period square
        wave's sign (``CTRL.INJ_PER``), else the half's own (spec 3.5)."""
        cmps = compares(o.v_d, o.v_q, o.v_h, o.sin, o.cos, self.half, sign if inj_sign is None else inj_sign, rot)
        hw = self.hw
        if hw.dtc_gain:
            cmps = compensate(cmps, sign, self.half, self.gen.dead, hw.dtc_gain, o.i_d_ref, o.i_q_ref,
                              hw.hf_amp, o.sin, o.cos, hw.recip_h)
        return cmps

    def _top_sample(self, rel: np.ndarray, adc: np.ndarray, keep, top: tuple[int, int]) -> tuple[int, int]:
        """``TOP_I`` (spec 3.11): the Clarke currents of the window's sample at the carrier top (``H/2``
        after the window start), or ``top`` (the previous value) when the window has none."""
        hw, H = self.hw, self.half
        j = int(np.searchsorted(rel, H // 2))
        if j >= len(rel) or rel[j] != H // 2 or (keep is not None and not keep[j]):
            return top
        i_al, i_be = clarke(adc_to_current(int(adc[j, 0]), hw.adc_bits, hw.adc_offset[0], hw.adc_gain[0]),
                            adc_to_current(int(adc[j, 1]), hw.adc_bits, hw.adc_offset[1], hw.adc_gain[1]))
        return int(i_al), int(i_be)

    def run(self, progress: bool = True) -> ClosedLoopResult:
        sc, hw, H = self.sc, self.hw, self.half
        P = 2 * H
        tick_hz = sc.pwm.tick_hz
        speed_ref = speed_references(sc, hw, self.scales).tolist()
        n_win = len(speed_ref)
        ds_from = (math.inf if sc.control.switch_to_ds_at is None else sc.control.switch_to_ds_at) * tick_hz
        rec = {name: np.zeros(n_win, dtype=np.int64) for name in WINDOW_FIELDS}
        truths = []
        s_ticks, s_a, s_b, s_vdc = [], [], [], []
        edge_ticks, edge_masks = [], []

        active = RESET_OUTPUTS
        outs: list[Outputs] = []
        gen, plant, fw = self.gen, self.plant, self.fw
        # CTRL.INJ_PER (spec 3.5): the sign S toggles at every carrier bottom, from +1 after reset; the
        # square wave of period k is S_k. inj_sign is None while the mode is off.
        per = bool(hw.inj_per) and not hw.inj_rot
        inj_sign = -1 if per else None
        # CTRL.DIRECT (spec 3.10): the state applied, 0 after reset; the first half (before the first
        # boundary) has the reset compares in either mode
        direct = bool(hw.direct)
        state = 0
        nxt = _direct_next(active, state) if direct else 0  # the state from the next top (VECTOR.NEXT)
        top = (0, 0)                                      # TOP_I after reset
        gen.add_half(0, H, True, self._compares(active, -1, None, inj_sign))
        prev_switch = np.zeros(0, dtype=np.int64)
        # the hardware overcurrent comparator (spec 3.7): a trip turns the gates off mid-window, so a window
        # with a tripping sample runs again from its start with the edges cut (the plant's checkpoint)
        oc = OvercurrentLatch(hw.adc_bits, hw.adc_offset, hw.adc_gain, hw.oc_limit)
        mask_now = 0                                      # the gate mask the plant holds (the last edge applied)
        t0 = time.perf_counter()
        bar = _Progress(n_win, sc.name) if progress else None
        for k in range(n_win):
            zc = k * P + H // 2
            if k >= 2:
                active = outs[k - 2]                      # commit at the window boundary
            enable = outs[k - 1].enable if k >= 1 else 0
            adc_mode = MODE_DS if zc >= ds_from else hw.adc_mode
            # CTRL.INJ_EN is 1 in every closed-loop run (the supervisor stops an injection with V_H = 0),
            # so the rotating injection is on exactly when INJ_ROT is
            inj_phase, rot = self.rot_inj.boundary(bool(hw.inj_rot), hw.inj_step)
            if direct:                                    # CTRL.DIRECT (spec 3.10): one state top to top
                state = nxt
                cmp_top = direct_compares(state, H)
            else:
                cmp_top = self._compares(active, +1, rot, inj_sign)
            gen.add_half(k * P + H, H, False, cmp_top)
            gen.set_enabled((k + 1) * P, bool(enable))
            plus = inj_sign == 1                          # period k, which ends at the bottom sample below
            if per:
                inj_sign = -inj_sign
            cmp_bot = cmp_top if direct else self._compares(active, -1, rot, inj_sign)
            gen.add_half((k + 1) * P, H, True, cmp_bot)
            e_ticks, e_masks = cut_edges(*gen.take_edges(zc + P), oc.kill_tick, mask_now, zc + P)
            rel, w, j_bot = self._window_pattern(adc_mode)
            ticks = rel + zc
            armed = oc.trip_tick is None
            if armed:
                plant.checkpoint()
            out = plant.run(e_ticks, ticks, gates=e_masks)
            if armed and (t_s := oc.first_trip(ticks, out["adc"])) is not None:
                oc.latch(t_s)
                if oc.kill_tick < zc + P:                 # the gates go off in this window: run it again
                    plant.rollback()
                    e_ticks, e_masks = cut_edges(e_ticks, e_masks, oc.kill_tick, mask_now, zc + P)
                    out = plant.run(e_ticks, ticks, gates=e_masks)
            if len(e_masks):
                mask_now = int(e_masks[-1])
            edge_ticks.append(e_ticks)
            edge_masks.append(e_masks)
            plant.advance(zc + P)
            truth = plant.state()
            adc = out["adc"]
            adc_a, adc_b = adc[:, 0], adc[:, 1]
            keep = None
            if adc_mode == MODE_OS_BLANK:
                sw = gen.take_switch_ticks(zc + P)
                keep = ~blank_mask(ticks, np.concatenate([prev_switch, sw]), hw.blank_ticks)
                prev_switch = sw[sw >= zc + P - hw.blank_ticks]
            win, _, _ = window_dsp(adc_a, adc_b, hw.adc_bits, hw.adc_offset[0], hw.adc_offset[1],
                                   hw.adc_gain[0], hw.adc_gain[1], active.sin, active.cos, w, keep)
            # the carrier-bottom sample (phase 0, in every ADC mode) through the differencing and CIC block;
            # the mode is fixed for a run, and without it plus is never 1, so the block's outputs stay 0
            # (the hardware steps it anyway; skipping it here changes no output)
            q_a = q_b = e_a = e_b = 0
            if per:
                j = j_bot
                i_al, i_be = clarke(
                    adc_to_current(int(adc_a[j]), hw.adc_bits, hw.adc_offset[0], hw.adc_gain[0]),
                    adc_to_current(int(adc_b[j]), hw.adc_bits, hw.adc_offset[1], hw.adc_gain[1]))
                q_a, q_b, e_a, e_b = self.diff_cic.step(int(i_al), int(i_be), plus, hw.cic_m)
            # VDC (spec 3.12): the dc-link channel's code of the same bottom sample, in every mode; WIN_FAULT
            # (spec 3.7): the overcurrent latch at the boundary that ends the window; WIN_ADC (spec 3.13)
            latched = {"vdc": int(out["vdc"][j_bot]), "status": oc.status(zc + P),
                       "frozen": frozen_lanes(adc_a, adc_b)}
            if inj_phase or per:
                latched.update(inj_phase=inj_phase, cic_qa=q_a, cic_qb=q_b, env_a=e_a, env_b=e_b)
            if direct:                                    # VECTOR and TOP_I (spec 3.10, 3.11)
                top = self._top_sample(rel, adc, keep, top)
                # the next boundary commits outs[k - 1] (the reset set before k = 1): the next top's state
                nxt = _direct_next(outs[k - 1] if k >= 1 else active, state)
                latched.update(vector=state, vector_next=nxt, top_ia=top[0], top_ib=top[1])
            win = WindowResult(**{**win.__dict__, **latched})   # dataclasses.replace, without its field walk
            o = fw.step(win, speed_ref[k])
            outs.append(o)
            s_ticks.append(ticks)
            s_a.append(adc_a)
            s_b.append(adc_b)
            s_vdc.append(out["vdc"])
            r = rec
            r["tick"][k] = zc + P
            r["gamma"][k], r["gamma_d"][k], r["n_samples"][k] = win.gamma, win.gamma_d, win.n_samples
            r["sum_id"][k], r["sum_iq"][k], r["wsum"][k] = win.sum_id, win.sum_iq, win.wsum
            r["i_d"][k], r["i_q"][k], r["i_d_ref"][k], r["i_q_ref"][k] = fw.i_d, fw.i_q, fw.i_d_ref, fw.i_q_ref
            r["v_d"][k], r["v_q"][k], r["sin"][k], r["cos"][k] = o.v_d, o.v_q, o.sin, o.cos
            r["theta_hat"][k], r["omega_f"][k], r["speed_ref"][k] = fw.theta_hat, fw.omega_f, speed_ref[k]
            r["mode"][k], r["fault"][k], r["adc_mode"][k] = fw.mode, fw.fault, adc_mode
            r["est"][k], r["theta_lo"][k], r["theta_hi"][k] = fw.active, fw.est_theta[0], fw.est_theta[1]
            r["omega_lo"][k], r["omega_hi"][k] = fw.est_omega[0], fw.est_omega[1]
            r["inj_phase"][k] = inj_phase
            r["cic_qa"][k], r["cic_qb"][k], r["env_a"][k], r["env_b"][k] = q_a, q_b, e_a, e_b
            r["vector"][k], r["vector_next"][k] = win.vector, win.vector_next
            r["top_ia"][k], r["top_ib"][k] = win.top_ia, win.top_ib
            r["vdc"][k] = win.vdc
            r["win_fault"][k], r["win_adc"][k] = win.status, win.frozen
            r["cmp_top_a"][k], r["cmp_top_b"][k], r["cmp_top_c"][k] = cmp_top
            r["cmp_bot_a"][k], r["cmp_bot_b"][k], r["cmp_bot_c"][k] = cmp_bot
            truths.append(truth)
            if bar is not None:
                bar.update(k + 1, fw)
        if bar is not None:
            bar.close()
        rec.update(truth_columns(np.array(truths, dtype=STATE_DTYPE), self.scales.pole_pairs))
        samples = {"tick": np.concatenate(s_ticks), "adc_a": np.concatenate(s_a).astype(np.uint16),
                   "adc_b": np.concatenate(s_b).astype(np.uint16), "adc_vdc": np.concatenate(s_vdc).astype(np.uint16)}
        edges = {"tick": np.concatenate(edge_ticks), "mask": np.concatenate(edge_masks)}
        writes = {f: np.array([getattr(o, f) for o in outs], dtype=np.int64) for f in OUTPUT_FIELDS}
        return ClosedLoopResult(rec, samples, edges, writes, hw, self.scales, tick_hz, fw.flipped,
                                time.perf_counter() - t0, ident=fw.ident)


def _direct_next(regs: Outputs, state: int) -> int:
    """The direct-vector mode's choice (spec 3.10) from the committed register set ``regs`` and the state
    applied now."""
    return direct_state(regs.v_d, regs.v_q, regs.sin, regs.cos, regs.fcs_a1, regs.fcs_a2, regs.fcs_phi_min,
                        bool(regs.fcs_constrain), state)


def truth_columns(truth: np.ndarray, pole_pairs: int) -> dict:
    """Per-window plant-truth columns of the trace from ``struct plant_state`` records (one per window
    end): ``theta_e`` as a u32 binary angle (as the golden loop records it), ``omega_m``, ``torque``,
    ``load_torque``, ``i_d_true``, ``i_q_true`` and the running integrals ``e_cu`` [J], ``q_d``, ``q_q`` [A*s],
    ``t_int`` [N*m*s], ``t2_int`` [N^2*m^2*s] (``struct plant_state``)."""
    return {
        "theta_e": np.array([int(th * pole_pairs / (2 * math.pi) * 2**32) % 2**32 for th in truth["theta_m"].tolist()],
                            dtype=np.int64),
        "omega_m": truth["omega_m"].astype(float), "torque": truth["torque"].astype(float),
        "load_torque": truth["load_torque"].astype(float),
        "i_d_true": truth["i_d"].astype(float), "i_q_true": truth["i_q"].astype(float),
        "e_cu": truth["E_cu"].astype(float), "q_d": truth["Q_d"].astype(float), "q_q": truth["Q_q"].astype(float),
        "t_int": truth["T_int"].astype(float), "t2_int": truth["T2_int"].astype(float),
    }


class _Progress:
    """Progress line on stderr: windows done, simulated time, mode, speed (every ~0.5 s wall)."""

    def __init__(self, total: int, name: str):
        from tqdm import tqdm
        self.bar = tqdm(total=total, desc=name, unit="win", mininterval=0.5, leave=True)
        self.done = 0

    def update(self, k: int, fw: Firmware) -> None:
        if k - self.done >= 250:
            self.bar.update(k - self.done)
            self.bar.set_postfix_str(MODE_NAMES[fw.mode], refresh=False)
            self.done = k

    def close(self) -> None:
        self.bar.close()
