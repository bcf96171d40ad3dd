// Dead-time gate generator, docs/spec.md 2.4 (golden/fpga/gate_generator.py; the per-tick state
// machine of rtl/hfi_gate_gen.v, whose registered gate output is this kernel's mask one clock later).
#include "hfi_gate_gen.h"

static const int HFI_LEGS = 3;
static const ap_uint<16> HFI_EL_MAX = 0xFFFF;   // saturation of the per-leg tick counter

// golden.fpga.gate_generator.effective_dead_ticks: max(DEAD_TICKS, DEAD_MIN).
u16 hfi_effective_dead(u16 dead_ticks_register, u16 dead_min) {
#pragma HLS INLINE
    return dead_ticks_register < dead_min ? dead_min : dead_ticks_register;
}

// Ideal switch signal (spec 2.4, GateGenerator.add_half): s = 1 iff phi < cmp on the rising half,
// 2H - phi <= cmp on the falling half.
bool hfi_ideal_switch(ap_uint<17> phase, u16 half, u16 cmp_rise, u16 cmp_fall) {
#pragma HLS INLINE
    const ap_uint<17> period = ap_uint<17>(half) << 1;
    return phase < half ? phase < cmp_rise : ap_uint<17>(period - phase) <= cmp_fall;
}

// Reset (the RTL's rst): s = 0 and en = 0 before tick 0, so an enable in tick 0 is a rise.
void hfi_gate_reset(hfi_gate_state &st) {
    st.s_q = 0;
    st.en_q = false;
    for (int x = 0; x < HFI_LEGS; x++) {
#pragma HLS UNROLL
        st.el[x] = 0;
    }
}

// el of the next tick if it does not restart: el + 1, saturating.
static ap_uint<16> el_step(ap_uint<16> el) {
#pragma HLS INLINE
    return el == HFI_EL_MAX ? el : ap_uint<16>(el + 1);
}

// Mask bits of leg x: bit 2x = high switch (s = 1), bit 2x + 1 = low switch (s = 0).
static ap_uint<6> leg_bits(int x, bool s, bool on) {
#pragma HLS INLINE
    return ap_uint<6>(on ? (s ? 1 : 2) : 0) << (2 * x);
}

// One tick (spec 2.4): a leg restarts when its s changes or en rises; el = 0 at a restart, else the
// stored count; the selected switch is on iff en & !restart & el >= D. st.el holds el of the next
// tick (el + 1, saturating: the RTL's el_q).
ap_uint<6> hfi_gate_tick(hfi_gate_state &st, ap_uint<3> s, bool en, u16 dead) {
#pragma HLS INLINE off
#pragma HLS ARRAY_PARTITION variable = st.el complete
    const bool en_rise = en && !st.en_q;
    ap_uint<6> mask = 0;
    for (int x = 0; x < HFI_LEGS; x++) {
#pragma HLS UNROLL
        const bool restart = (s[x] != st.s_q[x]) || en_rise;
        const ap_uint<16> el = restart ? ap_uint<16>(0) : st.el[x];
        const bool on = en && !restart && el >= dead;
        mask |= leg_bits(x, s[x], on);
        st.el[x] = el_step(el);
    }
    st.s_q = s;
    st.en_q = en;
    return mask;
}

// n ticks with s and en constant, in closed form. Only the first tick can restart a leg (s and en do
// not change afterwards), so el(k) = min(el(0) + k, 65535) for k = 0..n-1, non-decreasing: the leg
// turns on at the first k with en & (k > 0 | !restart) & el(k) >= D, and stays on.
ap_uint<6> hfi_gate_advance(hfi_gate_state &st, ap_uint<3> s, bool en, u16 dead, ap_uint<32> n,
                            ap_uint<32> on_at[3]) {
#pragma HLS INLINE off
#pragma HLS ARRAY_PARTITION variable = st.el complete
#pragma HLS ARRAY_PARTITION variable = on_at complete
    const bool en_rise = en && !st.en_q;
    ap_uint<6> mask = 0;
    for (int x = 0; x < HFI_LEGS; x++) {
#pragma HLS UNROLL
        const bool restart = (s[x] != st.s_q[x]) || en_rise;
        const ap_uint<16> el0 = restart ? ap_uint<16>(0) : st.el[x];
        const bool on0 = en && !restart && el0 >= dead;
        // first k >= 1 with el0 + k >= D (D <= 65535, so the saturation never hides it)
        const ap_uint<17> k_on = el0 + 1 >= dead ? ap_uint<17>(1) : ap_uint<17>(dead - el0);
        on_at[x] = !en ? n : (on0 ? ap_uint<32>(0) : (k_on < n ? ap_uint<32>(k_on) : n));
        mask |= leg_bits(x, s[x], on0);
        const ap_uint<33> el_end = ap_uint<33>(el0) + n;                 // el of the tick after the n
        st.el[x] = el_end > HFI_EL_MAX ? HFI_EL_MAX : ap_uint<16>(el_end);
    }
    st.s_q = s;
    st.en_q = en;
    return mask;
}
