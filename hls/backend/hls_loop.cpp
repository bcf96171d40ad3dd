// Closed loop of the `hls` backend (hls_loop.h): the golden loop of golden/closedloop.py with every
// FPGA block replaced by its HLS kernel, the firmware by its host build and the plant by the same C
// library and calls. This file is the test bench around the kernels, not synthesizable code.
//
// Window k covers the ticks [k*P + H/2, (k+1)*P + H/2) (docs/spec.md 2.1). Per window:
//   1. the commit of the firmware's outputs of window k-2 becomes active at the boundary; the enable
//      written after window k-1 takes effect at the bottom (k+1)*P (spec 2.2);
//   2. the rotating injection's phase accumulator steps (golden/fpga/rot_injection.py: while INJ_ROT,
//      phi = P, P += INJ_STEP, (S, C) = hfi_sincos_q15(phi); else P = 0, no rotating term);
//      hfi_modulator (+ hfi_deadtime_comp) latch the compares of the top of period k and the bottom of
//      period k+1 from the active registers and (C, S) (spec 3.5, 3.6); with the period square wave
//      (CTRL.INJ_PER, not INJ_ROT) the injection's sign is S_k at the top and S_{k+1} = -S_k at the
//      bottom (golden inj_sign; the dead-time compensation keeps the half's sign), and plus = (S_k = +1);
//      with CTRL.DIRECT (spec 3.10) hfi_modulator_direct chooses instead, at the top, the state from the
//      active registers (V_D, V_Q, SIN, COS, FCS_A, FCS_CTRL) and the state applied so far, with the
//      compares 0/H; the bottom reuses them; no dead-time compensation;
//   3. the gate generator runs through the window: the ideal switch signals (hfi_ideal_switch) change
//      at most once per leg and half period, so hfi_gate_advance covers each stretch between changes
//      in one step, and its turn-on offsets give the gate edges (spec 2.4);
//   4. the plant applies the edges and converts at the sampling instants (hfi_adc_trigger over one
//      period, cached per ADC mode), then runs to the window end (PlantLoop::run_window,
//      sim/plant_loop.h, which records the edges, samples and truth as the rtl backend's harness does);
//   5. hfi_window_dsp (ADC scale, Clarke, Park, demodulator) with the CORDIC weights
//      (hfi_demod_weight) and, in OS_BLANK, the blanking decision (hfi_blanked) gives the window
//      result (with INJ_PHASE = phi of step 2); the carrier-bottom sample of the window (phase 0, at
//      (k+1)*P, in every ADC mode) through hfi_adc_scale and hfi_clarke steps hfi_diff_cic with plus and
//      CIC_M (spec 3.9): CIC_QA/QB and ENV_A/B of the window; in the direct-vector mode the carrier-top
//      sample (phase H) through hfi_adc_scale and hfi_clarke gives TOP_I (spec 3.11, held over a window
//      without one), VECTOR.STATE is the state of step 2 and VECTOR.NEXT the one the next boundary's
//      commit chooses (the modulator holds it before the firmware reads); fw_step computes the next register values; the
//      firmware-state columns of the window record are those of the firmware's trace record
//      (FW_TRACE_COLUMNS, fw_trace.h, generated).
#include "hls_loop.h"

#include <algorithm>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "../../sim/plant_loop.h"

extern "C" {
#pragma GCC visibility push(default)   // imported from libhfifw.so
#include "control.h"
#pragma GCC visibility pop
#include "fw_trace.h"
#include "../../firmware/include/hfi_regs.h"
}

#include "hfi_adc_frozen.h"
#include "hfi_adc_scale.h"
#include "hfi_adc_trigger.h"
#include "hfi_carrier.h"
#include "hfi_cordic.h"
#include "hfi_deadtime_comp.h"
#include "hfi_diff_cic.h"
#include "hfi_fcs_mpc.h"
#include "hfi_gate_gen.h"
#include "hfi_modulator.h"
#include "hfi_overcurrent.h"
#include "hfi_park.h"
#include "hfi_window_dsp.h"

namespace {

// The register reset values (hfi_regs.h, generated from rtl/regs/hfi_regs.rdl), in fw_outputs order.
const fw_outputs RESET_OUTPUTS = {
    HFI_REGS__V_DQ__V_D_reset, HFI_REGS__V_DQ__V_Q_reset, HFI_REGS__V_H__VALUE_reset, HFI_REGS__SINCOS__SIN_reset,
    HFI_REGS__SINCOS__COS_reset, HFI_REGS__CTRL__ENABLE_reset, HFI_REGS__I_REF__I_D_reset, HFI_REGS__I_REF__I_Q_reset,
    HFI_REGS__FCS_A__A1_reset, HFI_REGS__FCS_A__A2_reset, HFI_REGS__FCS_CTRL__PHI_MIN_reset,
    HFI_REGS__FCS_CTRL__CONSTRAIN_reset};

struct Pattern {                       // sampling instants of one window, identical in every window
    std::vector<int64_t> rel;          // offsets from the window start, sorted
    std::vector<s16> w;                // their demodulation weights
};

// Sorts the n (<= 4) ticks of a[] in place (insertion sort; std::sort trips GCC's array-bounds check here).
void sort_small(int64_t *a, int n) {
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && a[j - 1] > a[j]; j--) std::swap(a[j - 1], a[j]);
}

}  // namespace

struct hls_loop {
    hls_loop(const hls_setup &setup, plant *pl, int32_t half)
        : s(setup), loop(pl, half, setup.n_windows, setup.speed_ref, setup.adc_bits) {
        // hfi_adc_scale of every code of lanes A and B for the overcurrent comparator's check of every sample (the
        // run's offsets and gains are fixed): a look-up instead of two kernel calls per sample, the same values
        for (int code = 0; code < (1 << setup.adc_bits); code++) {
            scaled_a.push_back(hfi_adc_scale(ap_uint<16>(code), setup.adc_bits, setup.adc_offset_a, setup.adc_gain_a));
            scaled_b.push_back(hfi_adc_scale(ap_uint<16>(code), setup.adc_bits, setup.adc_offset_b, setup.adc_gain_b));
        }
        // the codes whose current is within half the limit on both lanes (an interval: the scalings are monotonic):
        // a sample with both codes in it cannot trip (|i_a|, |i_b| <= L/2, so |i_a + i_b| <= L), the comparator
        // kernel runs only on the others (golden.fpga.overcurrent.OvercurrentLatch's quick test, per sample)
        const int half_limit = int(setup.oc_limit) / 2;
        for (int code = 0; code < int(scaled_a.size()); code++) {
            if (std::abs(scaled_a[size_t(code)].to_int()) > half_limit || std::abs(scaled_b[size_t(code)].to_int()) > half_limit)
                continue;
            if (safe_lo > safe_hi) safe_lo = code;
            safe_hi = code;
        }
    }
    hls_setup s;                       // half, os_ticks: effective values
    PlantLoop loop;                    // the plant calls and their records
    int32_t dead = 0;                  // effective dead time
    fw_params fwp{};
    fw_state fw{};
    std::string error;

    fw_outputs active = RESET_OUTPUTS, prev1 = RESET_OUTPUTS, prev2 = RESET_OUTPUTS;
    hfi_gate_state gate;
    u16 cmp_rise[3];                   // compares of the current rising half (latched at its bottom)
    u16 cmp_fall[3];                   // compares of the current falling half (latched at its top)
    int64_t cursor = 0;                // the gate generator has run up to here
    ap_uint<3> s_prev = 0;             // ideal switch signals of the tick before the cursor
    bool en = false;                   // enable in effect
    int64_t mask = 0;                  // gate mask after the last edge
    int64_t plant_mask = 0;            // the gate mask the plant holds (0 from the overcurrent kill on)
    int64_t oc_trip = -1;              // sampling instant of the sample that tripped the comparator (-1: none)
    int64_t last_switch = -1;          // latest switching instant (-1: none yet)
    u32 inj_acc = 0;                   // rotating injection's phase accumulator P (0 after reset)
    bool per = false;                  // the period square wave is on (CTRL.INJ_PER and not INJ_ROT)
    int inj_sign = 1;                  // its sign S of the current period (golden inj_sign)
    hfi_diff_cic_state cic;            // the differencing and CIC block
    ap_uint<3> vec_state = 0;          // CTRL.DIRECT: the state applied (0 after reset and while the mode is off)
    int32_t top_ia = 0, top_ib = 0;    // TOP_I (spec 3.11): 0 after reset, held over a window without a top sample
    Pattern pattern[4];
    bool have_pattern[4] = {false, false, false, false};
    std::vector<s16> scaled_a, scaled_b;                // hfi_adc_scale by code (the constructor)
    int safe_lo = 1, safe_hi = 0;                       // the codes that cannot trip the comparator (empty: none)
    // hfi_adc_scale of `code` from the table, or from the kernel for a code outside it (which the plant never gives
    // and PlantLoop then refuses with its message)
    s16 scaled(const std::vector<s16> &table, int code, s16 offset, u16 gain) const {
        return code >= 0 && size_t(code) < table.size() ? table[size_t(code)]
                                                         : hfi_adc_scale(ap_uint<16>(code), s.adc_bits, offset, gain);
    }

    std::vector<hls_window> windows;
    std::vector<fw_outputs> outputs;

    // per-window scratch
    std::vector<long long> e_ticks, s_ticks;            // plant_run takes long long ticks
    std::vector<int64_t> sw_ticks;
    std::vector<int> e_masks, adc;
    ap_uint<16> adc_a[HFI_WINDOW_MAX], adc_b[HFI_WINDOW_MAX];
    s16 w[HFI_WINDOW_MAX], i_d[HFI_WINDOW_MAX], i_q[HFI_WINDOW_MAX];
    bool keep[HFI_WINDOW_MAX];

    const Pattern &window_pattern(int mode);
    bool cut_edges(int64_t end);
    void compares(const fw_outputs &o, bool top, bool rot, s16 inj_sin, s16 inj_cos, u16 cmp[3],
                  bool inj_top) const;
    void gate_range(int64_t a, int64_t b, int64_t half_start, bool rising);
    void gate_segment(int64_t a, int64_t b);
    bool step();
};

// Sampling offsets of a window in ADC mode `mode`: the phases at which hfi_adc_trigger fires over one
// period, moved to the window start (golden ClosedLoop._window_pattern), and their CORDIC weights.
const Pattern &hls_loop::window_pattern(int mode) {
    if (!have_pattern[mode]) {
        const int64_t H = s.half, P = 2 * H;
        Pattern &p = pattern[mode];
        for (int64_t phase = 0; phase < P; phase++)
            if (hfi_adc_trigger(ap_uint<17>(phase), ap_uint<2>(mode), u16(H), u16(s.os_ticks), u16(s.os_min)))
                p.rel.push_back(((phase - H / 2) % P + P) % P);
        std::sort(p.rel.begin(), p.rel.end());
        for (int64_t r : p.rel) {
            const u16 c = hfi_carrier_counter(ap_uint<17>((r + H / 2) % P), u16(H));
            p.w.push_back(hfi_demod_weight(c, u16(H), u32(s.cw_angle_step)));
        }
        have_pattern[mode] = true;
    }
    return pattern[mode];
}

// Compares of one latch from the register values o (golden ClosedLoop._compares); rot: the rotating
// injection with (C, S) = (inj_cos, inj_sin), else the square wave with the sign +1 if inj_top, -1 else
// (the half's own sign, top, unless the period square wave gives S; the compensation uses top).
void hls_loop::compares(const fw_outputs &o, bool top, bool rot, s16 inj_sin, s16 inj_cos, u16 cmp[3],
                        bool inj_top) const {
    u16 raw[3];
    hfi_modulator(s16(o.v_d), s16(o.v_q), s16(o.v_h), rot, inj_sin, inj_cos, s16(o.sin), s16(o.cos), u16(s.half),
                  inj_top, raw);
    if (s.dtc_gain)
        hfi_deadtime_comp(raw, top, u16(s.half), u16(dead), u16(s.dtc_gain), s16(o.i_d_ref), s16(o.i_q_ref),
                          ap_uint<15>(s.hf_amp), s16(o.sin), s16(o.cos), u32(s.recip_h), cmp);
    else
        for (int x = 0; x < 3; x++) cmp[x] = raw[x];
}

// The gate generator over ticks [a, b) of the half period starting at half_start, cut where an
// ideal switch signal changes (rising half: at half_start + cmp, falling: at half_start + H - cmp).
void hls_loop::gate_range(int64_t a, int64_t b, int64_t half_start, bool rising) {
    int64_t cut[4];
    int n = 0;
    cut[n++] = a;
    for (int x = 0; x < 3; x++) {
        const int64_t c = rising ? int64_t(cmp_rise[x]) : int64_t(cmp_fall[x]);
        const int64_t t = rising ? half_start + c : half_start + s.half - c;
        if (t > a && t < b) cut[n++] = t;
    }
    sort_small(cut, n);
    for (int i = 0; i < n; i++) {
        if (i + 1 < n && cut[i + 1] == cut[i]) continue;
        gate_segment(cut[i], i + 1 < n ? cut[i + 1] : b);
    }
}

// Ticks [a, b) with constant ideal switch signals and enable: one hfi_gate_advance.
void hls_loop::gate_segment(int64_t a, int64_t b) {
    const int64_t P = 2 * int64_t(s.half);
    const ap_uint<17> phase = ap_uint<17>(a % P);
    ap_uint<3> sw = 0;
    for (int x = 0; x < 3; x++)
        sw[x] = hfi_ideal_switch(phase, u16(s.half), cmp_rise[x], cmp_fall[x]) ? 1 : 0;
    if (sw != s_prev) {
        sw_ticks.push_back(a);
        last_switch = a;
    }
    s_prev = sw;
    ap_uint<32> on_at[3];
    const int64_t first = int64_t(hfi_gate_advance(gate, sw, en, u16(dead), ap_uint<32>(b - a), on_at));
    if (first != mask) {
        mask = first;
        e_ticks.push_back(a);
        e_masks.push_back(int(mask));
    }
    // turn-ons later in the segment, in tick order (nothing turns off inside a segment)
    int64_t off[3];
    int m = 0;
    for (int x = 0; x < 3; x++) {
        const int64_t o = int64_t(on_at[x]);
        if (o > 0 && o < b - a) off[m++] = o;
    }
    sort_small(off, m);
    for (int i = 0; i < m; i++) {
        if (i > 0 && off[i] == off[i - 1]) continue;
        int64_t add = 0;
        for (int x = 0; x < 3; x++)
            if (int64_t(on_at[x]) == off[i]) add |= int64_t(1) << (2 * x + (sw[x] ? 0 : 1));
        const int64_t next = mask | add;
        if (next != mask) {
            mask = next;
            e_ticks.push_back(a + off[i]);
            e_masks.push_back(int(mask));
        }
    }
}

// The overcurrent kill (spec 3.7; golden.fpga.overcurrent.cut_edges): once tripped, the window's edges before
// the kill tick stay, then all gates off at it (unless they already are), none after; nothing when not tripped
// or the kill tick is not before `end` (a kill in the next window). true: the edges changed.
bool hls_loop::cut_edges(int64_t end) {
    if (oc_trip < 0 || oc_trip + s.oc_gate_delay >= end) return false;
    const long long kill = oc_trip + s.oc_gate_delay;
    size_t n = 0;
    while (n < e_ticks.size() && e_ticks[n] < kill) n++;
    const int before = n ? e_masks[n - 1] : int(plant_mask);
    const bool changed = n < e_ticks.size() || before != 0;
    e_ticks.resize(n);
    e_masks.resize(n);
    if (before != 0) {
        e_ticks.push_back(kill);
        e_masks.push_back(0);
    }
    return changed;
}

// One window (golden ClosedLoop.run, loop body).
bool hls_loop::step() {
    const int64_t H = s.half, P = 2 * H;
    const int32_t k = int32_t(loop.windows_ended());
    const int64_t zc = loop.window_start(k), end = loop.window_end(k);
    if (k >= 2) active = prev2;                           // commit at the window boundary
    const bool enable = k >= 1 && prev1.enable;
    const int adc_mode = zc >= s.ds_from_tick ? HFI_MODE_DS : s.adc_mode;
    // Rotating injection (golden RotatingInjection.boundary): on, this window's sets use phi = P and
    // P advances by INJ_STEP (mod 2^32); off, P = 0 and no rotating term (phi reads 0).
    const bool rot = s.inj_rot != 0;
    u32 inj_phase = 0;
    s16 inj_sin = 0, inj_cos = 0;
    if (rot) {
        inj_phase = inj_acc;
        inj_acc = inj_acc + u32(uint32_t(s.inj_step));
        hfi_sincos_q15(inj_phase, inj_sin, inj_cos);      // hfi_cordic_sincos<32, 16>, Q1.15
    } else {
        inj_acc = 0;
    }
    u16 cmp_top[3], cmp_bot[3];
    const bool direct = s.direct != 0;
    if (direct)                                           // CTRL.DIRECT (spec 3.10): one state from top to top
        vec_state = hfi_modulator_direct(s16(active.v_d), s16(active.v_q), s16(active.sin), s16(active.cos),
                                         s16(active.fcs_a1), s16(active.fcs_a2), u16(active.fcs_phi_min),
                                         active.fcs_constrain != 0, vec_state, u16(H), cmp_top);
    else
        compares(active, true, rot, inj_sin, inj_cos, cmp_top, per ? inj_sign > 0 : true);
    const bool plus = per && inj_sign > 0;               // period k, which ends at this window's bottom
    if (per) inj_sign = -inj_sign;                        // S flips at the bottom (k+1)*P
    if (direct)                                           // the bottom reuses the top's state, no compensation
        for (int x = 0; x < 3; x++) cmp_bot[x] = cmp_top[x];
    else
        compares(active, false, rot, inj_sin, inj_cos, cmp_bot, per ? inj_sign > 0 : false);

    e_ticks.clear();
    e_masks.clear();
    sw_ticks.clear();
    int64_t latest = last_switch;                         // latest switching instant before the window
    const int64_t top = int64_t(k) * P + H, bottom = (int64_t(k) + 1) * P;
    gate_range(cursor, top, int64_t(k) * P, true);        // rest of the rising half of period k
    for (int x = 0; x < 3; x++) cmp_fall[x] = cmp_top[x];
    gate_range(top, bottom, top, false);
    for (int x = 0; x < 3; x++) cmp_rise[x] = cmp_bot[x];
    en = enable;
    gate_range(bottom, end, bottom, true);
    cursor = end;

    const Pattern &pat = window_pattern(adc_mode);
    const int n = int(pat.rel.size());
    s_ticks.resize(n);
    for (int i = 0; i < n; i++) s_ticks[i] = zc + pat.rel[i];
    hfi_adc_cfg cfg;
    cfg.bits = s.adc_bits;
    cfg.offset_a = s.adc_offset_a;
    cfg.offset_b = s.adc_offset_b;
    cfg.gain_a = s.adc_gain_a;
    cfg.gain_b = s.adc_gain_b;
    // the hardware overcurrent comparator (spec 3.7): a kill pending from the last window cuts these edges; while
    // not tripped, every sample is compared, and a trip whose kill lies in this window runs it again, cut
    cut_edges(end);
    bool ran;
    if (oc_trip < 0) {
        ran = loop.run_window_checked(e_ticks, e_masks, s_ticks, adc, [&](const std::vector<int> &codes) {
            for (int i = 0; i < n && oc_trip < 0; i++) {
                const int a = codes[PLANT_ADC_CHANNELS * i], b = codes[PLANT_ADC_CHANNELS * i + 1];
                if (a >= safe_lo && a <= safe_hi && b >= safe_lo && b <= safe_hi)
                    continue;
                if (hfi_overcurrent(scaled(scaled_a, a, cfg.offset_a, cfg.gain_a),
                                    scaled(scaled_b, b, cfg.offset_b, cfg.gain_b), u16(s.oc_limit)))
                    oc_trip = s_ticks[i];
            }
            return cut_edges(end);
        });
    } else {
        ran = loop.run_window(e_ticks, e_masks, s_ticks, adc);
    }
    if (!ran) {
        error = loop.error();
        return false;
    }
    if (!e_masks.empty()) plant_mask = e_masks.back();

    size_t sw_i = 0;
    for (int i = 0; i < n; i++) {
        adc_a[i] = adc[PLANT_ADC_CHANNELS * i];
        adc_b[i] = adc[PLANT_ADC_CHANNELS * i + 1];
        w[i] = pat.w[i];
        keep[i] = true;
        if (adc_mode == HFI_MODE_OS_BLANK) {
            // spec 2.3: dropped if the latest switching instant t_s <= t lies less than BLANK_TICKS before it
            while (sw_i < sw_ticks.size() && sw_ticks[sw_i] <= s_ticks[i]) latest = sw_ticks[sw_i++];
            keep[i] = latest < 0 || !hfi_blanked(ap_uint<64>(s_ticks[i] - latest), u16(s.blank_ticks));
        }
    }
    hfi_window_result res;
    hfi_window_dsp(adc_a, adc_b, w, keep, ap_uint<12>(n), cfg, s16(active.sin), s16(active.cos), i_d, i_q, res);
    // the carrier-bottom sample (phase 0: offset P - H/2 from the window start, in every ADC mode)
    const int j = int(std::lower_bound(pat.rel.begin(), pat.rel.end(), P - H / 2) - pat.rel.begin());
    s16 i_alpha, i_beta;
    hfi_clarke(hfi_adc_scale(adc_a[j], cfg.bits, cfg.offset_a, cfg.gain_a),
               hfi_adc_scale(adc_b[j], cfg.bits, cfg.offset_b, cfg.gain_b), i_alpha, i_beta);
    s21 cic_qa, cic_qb;
    s17 env_a, env_b;
    hfi_diff_cic_step(cic, i_alpha, i_beta, plus, ap_uint<8>(s.cic_m), cic_qa, cic_qb, env_a, env_b);
    if (direct) {
        // TOP_I (spec 3.11, golden ClosedLoop._top_sample): the sample at the carrier top (phase H: offset
        // H/2 from the window start, H even) through hfi_adc_scale and hfi_clarke, unless the window has
        // none (OS grid) or it was blanked; then the previous value stays
        const int t = int(std::lower_bound(pat.rel.begin(), pat.rel.end(), H / 2) - pat.rel.begin());
        if (t < n && pat.rel[t] == H / 2 && keep[t]) {
            s16 t_al, t_be;
            hfi_clarke(hfi_adc_scale(adc_a[t], cfg.bits, cfg.offset_a, cfg.gain_a),
                       hfi_adc_scale(adc_b[t], cfg.bits, cfg.offset_b, cfg.gain_b), t_al, t_be);
            top_ia = int32_t(t_al);
            top_ib = int32_t(t_be);
        }
    }

    fw_window win{};                                      // VECTOR, TOP_I read 0 while the mode is off
    win.gamma = int32_t(res.gamma);
    win.gamma_d = int32_t(res.gamma_d);
    win.sum_id = int32_t(res.sum_id);
    win.sum_iq = int32_t(res.sum_iq);
    win.n_samples = uint32_t(res.n_samples);
    win.inj_phase = inj_phase.to_uint();                  // INJ_PHASE, latched with the window results
    win.cic_qa = int32_t(cic_qa);                         // CIC_QA, CIC_QB (latched with them too)
    win.cic_qb = int32_t(cic_qb);
    win.vdc = uint32_t(adc[PLANT_ADC_CHANNELS * j + PLANT_ADC_VDC]);  // VDC (spec 3.12): the dc-link code of the bottom sample
    // WIN_FAULT (spec 2.2, 3.7): the overcurrent latch at the boundary that ends the window
    win.status = oc_trip >= 0 && oc_trip + s.oc_fault_delay <= end ? uint32_t(HFI_REGS__WIN_FAULT__OC_bm) : 0u;
    win.frozen = uint32_t(hfi_adc_frozen(adc_a, adc_b, n));    // WIN_ADC (spec 3.13): every conversion, blanked too
    if (direct) {                                         // VECTOR, TOP_I (latched with the window results)
        // VECTOR.NEXT: the modulator's choice from the set the next boundary commits (the outputs of the
        // previous step; the reset set before k = 1) and the state applied now, held until that top
        const fw_outputs &nx = k >= 1 ? prev1 : active;
        u16 unused[3];
        win.vector = int32_t(vec_state.to_uint());
        win.vector_next = int32_t(hfi_modulator_direct(s16(nx.v_d), s16(nx.v_q), s16(nx.sin), s16(nx.cos),
                                                       s16(nx.fcs_a1), s16(nx.fcs_a2), u16(nx.fcs_phi_min),
                                                       nx.fcs_constrain != 0, vec_state, u16(H), unused).to_uint());
        win.top_ia = top_ia;
        win.top_ib = top_ib;
    }
    fw_outputs o;
    const int32_t speed_ref = loop.speed_ref(k);
    fw_step(&fw, &fwp, &win, speed_ref, &o);

    hls_window r{};                        // a column nothing fills stays 0
    r.tick = end;
    r.gamma = win.gamma;
    r.gamma_d = win.gamma_d;
    r.n_samples = win.n_samples;
    r.sum_id = win.sum_id;
    r.sum_iq = win.sum_iq;
    r.wsum = int32_t(res.wsum);            // WSUM (the firmware does not use it)
    r.inj_phase = win.inj_phase;           // what the firmware was given as INJ_PHASE
    r.cic_qa = win.cic_qa;                 // ... as CIC_QA, CIC_QB
    r.cic_qb = win.cic_qb;
    r.env_a = int32_t(env_a);              // ENV_A, ENV_B (the firmware does not use them)
    r.env_b = int32_t(env_b);
    r.vector = win.vector;                 // what the firmware was given as VECTOR, TOP_I
    r.vector_next = win.vector_next;
    r.top_ia = win.top_ia;
    r.top_ib = win.top_ib;
    r.vdc = win.vdc;
    r.win_fault = win.status;              // what the firmware was given as WIN_FAULT, WIN_ADC
    r.win_adc = win.frozen;
#define HLS_WINDOW_COLUMN(column, value) r.column = int64_t(value)
    FW_TRACE_COLUMNS(HLS_WINDOW_COLUMN, fw);
#undef HLS_WINDOW_COLUMN
    r.v_d = o.v_d;
    r.v_q = o.v_q;
    r.sin = o.sin;
    r.cos = o.cos;
    r.speed_ref = speed_ref;               // what the firmware was given
    r.adc_mode = adc_mode;                 // what the sampling used
    r.cmp_top_a = cmp_top[0];
    r.cmp_top_b = cmp_top[1];
    r.cmp_top_c = cmp_top[2];
    r.cmp_bot_a = cmp_bot[0];
    r.cmp_bot_b = cmp_bot[1];
    r.cmp_bot_c = cmp_bot[2];
    windows.push_back(r);
    outputs.push_back(o);
    prev2 = prev1;
    prev1 = o;
    return true;
}

static bool setup_error(char *err, int err_len, const std::string &msg) {
    set_message(err, err_len, msg);
    return false;
}

static bool check_setup(const hls_setup *s, char *err, int err_len) {
    char msg[200];
    if (s->half < 0 || s->half > 0xFFFF) {
        std::snprintf(msg, sizeof msg, "half = %d is not a u16 PWM_HALF register value", s->half);
        return setup_error(err, err_len, msg);
    }
    if (s->dead_ticks < 0 || s->dead_ticks > 0xFFFF || s->dead_min < 1 || s->dead_min > 0xFFFF)
        return setup_error(err, err_len, "dead_ticks must be u16 and dead_min 1..65535");
    if (s->os_min < 1 || s->os_min > 0xFFFF || s->os_ticks < 0 || s->os_ticks > 0xFFFF)
        return setup_error(err, err_len, "os_ticks must be u16 and os_min 1..65535");
    if (s->blank_ticks < 0 || s->blank_ticks > 0xFFFF) return setup_error(err, err_len, "blank_ticks must be u16");
    if (s->adc_mode < 0 || s->adc_mode > 3) return setup_error(err, err_len, "adc_mode must be 0..3");
    if (s->adc_offset_a < -32768 || s->adc_offset_a > 32767 || s->adc_offset_b < -32768 || s->adc_offset_b > 32767)
        return setup_error(err, err_len, "adc offsets must be s16");
    if (s->adc_gain_a < 0 || s->adc_gain_a > 0xFFFF || s->adc_gain_b < 0 || s->adc_gain_b > 0xFFFF)
        return setup_error(err, err_len, "adc gains must be u16");
    if (s->dtc_gain < 0 || s->dtc_gain > 0xFFFF || s->hf_amp < 0 || s->hf_amp > 0x7FFF)
        return setup_error(err, err_len, "dtc_gain must be u16 and hf_amp u15");
    if (s->inj_rot != 0 && s->inj_rot != 1) {
        std::snprintf(msg, sizeof msg, "inj_rot = %d must be 0 or 1 (CTRL.INJ_ROT)", s->inj_rot);
        return setup_error(err, err_len, msg);
    }
    if (s->inj_per != 0 && s->inj_per != 1) {
        std::snprintf(msg, sizeof msg, "inj_per = %d must be 0 or 1 (CTRL.INJ_PER)", s->inj_per);
        return setup_error(err, err_len, msg);
    }
    if (s->direct != 0 && s->direct != 1) {
        std::snprintf(msg, sizeof msg, "direct = %d must be 0 or 1 (CTRL.DIRECT)", s->direct);
        return setup_error(err, err_len, msg);
    }
    if (s->cic_m < 0 || s->cic_m > 0xFF) {
        std::snprintf(msg, sizeof msg, "cic_m = %d is not a u8 CIC_M register value", s->cic_m);
        return setup_error(err, err_len, msg);
    }
    if (s->oc_limit < 0 || s->oc_limit > 0xFFFF || s->oc_gate_delay < 1 || s->oc_fault_delay < 1) {
        std::snprintf(msg, sizeof msg, "oc_limit = %d is not a u16 OC_LIMIT register value, or a trip delay "
                      "(%d, %d) is below 1 tick", s->oc_limit, s->oc_gate_delay, s->oc_fault_delay);
        return setup_error(err, err_len, msg);
    }
    if (s->inj_step < 0 || s->inj_step > int64_t(0xFFFFFFFF)) {
        std::snprintf(msg, sizeof msg, "inj_step = %lld is not a u32 INJ_STEP register value",
                      static_cast<long long>(s->inj_step));
        return setup_error(err, err_len, msg);
    }
    const std::string bad = PlantLoop::check(int32_t(hfi_effective_half(u16(s->half))), s->n_windows, s->speed_ref,
                                             s->adc_bits);
    return bad.empty() || setup_error(err, err_len, bad);
}

// The library's only exports (it is built with -fvisibility=hidden, see hls/Makefile).
#pragma GCC visibility push(default)
extern "C" {

hls_loop *hls_loop_create(const hls_setup *setup, const fw_params *fw, plant *pl, char *err, int err_len) {
    if (setup == nullptr || fw == nullptr || pl == nullptr) {
        setup_error(err, err_len, "setup, firmware parameters and plant must not be NULL");
        return nullptr;
    }
    if (!check_setup(setup, err, err_len)) return nullptr;
    const int32_t half = int32_t(hfi_effective_half(u16(setup->half)));
    hls_loop *h = new hls_loop(*setup, pl, half);
    h->s.half = half;
    h->s.os_ticks = int32_t(hfi_effective_os_ticks(u16(setup->os_ticks), u16(setup->os_min)));
    h->dead = int32_t(hfi_effective_dead(u16(setup->dead_ticks), u16(setup->dead_min)));
    h->s.speed_ref = nullptr;              // copied by the plant loop
    h->fwp = *fw;
    fw_init(&h->fw, &h->fwp);
    hfi_gate_reset(h->gate);
    hfi_diff_cic_reset(h->cic);
    // the period square wave (golden: per = inj_per and not inj_rot): S = +1 after reset flips at the
    // first bottom (tick 0), so period 0 runs S = -1
    h->per = setup->inj_per != 0 && setup->inj_rot == 0;
    h->inj_sign = h->per ? -1 : 1;
    for (int mode = 0; mode < 4; mode++) {
        if (h->window_pattern(mode).rel.size() > size_t(HFI_WINDOW_MAX)) {
            setup_error(err, err_len, "more samples per window than HFI_WINDOW_MAX");
            delete h;
            return nullptr;
        }
    }
    // the first bottom latches the reset registers, before the first boundary: no rotating term
    h->compares(RESET_OUTPUTS, false, false, s16(0), s16(0), h->cmp_rise, false);   // S_0 = -1 or the half's sign
    for (int x = 0; x < 3; x++) h->cmp_fall[x] = 0;
    const size_t n = size_t(setup->n_windows);
    h->windows.reserve(n);
    h->outputs.reserve(n);
    h->loop.truth.reserve(n);
    h->loop.samples.reserve(n * h->pattern[setup->adc_mode].rel.size());
    h->loop.edges.reserve(n * 13);
    return h;
}

int32_t hls_loop_set_ident(hls_loop *h, fw_ident *ident) {
    if (ident == nullptr || h->loop.windows_ended() != 0) return -1;
    h->fw.ident = ident;
    fw_init(&h->fw, &h->fwp);              // keeps the pointer and starts the program (FW_IDENT)
    return 0;
}

int32_t hls_loop_run(hls_loop *h, int32_t n_windows) {
    if (!h->error.empty()) return -1;
    for (int32_t i = 0; i < n_windows && h->loop.windows_ended() < h->loop.n_windows(); i++)
        if (!h->step()) return -1;
    return int32_t(h->loop.windows_ended());
}

const char *hls_loop_error(const hls_loop *h) { return h->error.c_str(); }

int64_t hls_loop_count(const hls_loop *h, int32_t kind) {
    switch (kind) {
        case HLS_WINDOWS: return int64_t(h->windows.size());
        case HLS_OUTPUTS: return int64_t(h->outputs.size());
        case HLS_TRUTH: return int64_t(h->loop.truth.size());
        case HLS_SAMPLES: return int64_t(h->loop.samples.size());
        case HLS_EDGES: return int64_t(h->loop.edges.size());
        default: return -1;
    }
}

void hls_loop_copy(const hls_loop *h, int32_t kind, void *dst) {
    switch (kind) {
        case HLS_WINDOWS: copy_records(h->windows, 0, int64_t(h->windows.size()), dst); break;
        case HLS_OUTPUTS: copy_records(h->outputs, 0, int64_t(h->outputs.size()), dst); break;
        case HLS_TRUTH: copy_records(h->loop.truth, 0, int64_t(h->loop.truth.size()), dst); break;
        case HLS_SAMPLES: copy_records(h->loop.samples, 0, int64_t(h->loop.samples.size()), dst); break;
        case HLS_EDGES: copy_records(h->loop.edges, 0, int64_t(h->loop.edges.size()), dst); break;
        default: break;
    }
}

int32_t hls_loop_flipped(const hls_loop *h) { return h->fw.flipped; }

double hls_loop_plant_seconds(const hls_loop *h) { return h->loop.plant_seconds(); }

void hls_loop_free(hls_loop *h) { delete h; }

}  // extern "C"
#pragma GCC visibility pop
