// Dead-time compensation, docs/spec.md 3.6 (golden/fpga/deadtime_comp.py compensate).
#include "hfi_deadtime_comp.h"

// round(2^15 * sqrt(3) / 2), the inverse Clarke coefficient (golden.fpga.modulator.SQRT3_HALF_Q15).
static const ap_uint<15> HFI_DTC_SQRT3_HALF_Q15 = 28378;

typedef ap_int<25> s25;
typedef ap_int<33> s33;

// Phase currents of the three legs from i_d, i_q: inverse Park, inverse Clarke with round_shr(., 15)
// (golden.fpga.deadtime_comp.phase_current). |i_d| < 2^31 + 2^15 (s33), |i_q| <= 2^15.
static void phase_currents(s33 i_d, s16 i_q, s16 sin_q15, s16 cos_q15, ap_int<37> i_x[3]) {
#pragma HLS INLINE
    const ap_int<49> d_c = i_d * cos_q15;                             // s33 x s16 -> s49
    const ap_int<49> d_s = i_d * sin_q15;
    const ap_int<32> q_s = i_q * sin_q15;                             // s16 x s16 -> s32
    const ap_int<32> q_c = i_q * cos_q15;
    const ap_int<35> i_al = hfi_round_shr<15>(ap_int<50>(ap_int<50>(d_c) - q_s));   // < 2^34
    const ap_int<35> i_be = hfi_round_shr<15>(ap_int<50>(ap_int<50>(d_s) + q_c));
    const ap_int<50> a_part = -(ap_int<50>(i_al) << 14);              // |.| < 2^48
    const ap_int<50> b_part = i_be * HFI_DTC_SQRT3_HALF_Q15;          // s35 x u15 -> s50
    i_x[0] = i_al;
    i_x[1] = hfi_round_shr<15>(ap_int<51>(ap_int<51>(a_part) + b_part));             // < 2^36
    i_x[2] = hfi_round_shr<15>(ap_int<51>(ap_int<51>(a_part) - b_part));
}

// Edge shift c = clamp(shr(i_x * DTC_GAIN, 8), -D, D). i_x is first saturated to s25 (as the RTL):
// for |i_x| >= 2^24 and DTC_GAIN >= 1, |shr(i_x * gain, 8)| >= 2^16 > D either way, and DTC_GAIN = 0
// gives 0 either way, so the result is exact with an s25 x u16 -> s41 product.
static ap_int<17> edge_shift(ap_int<37> i_x, u16 gain, u16 dead) {
#pragma HLS INLINE
    const ap_int<41> prod = hfi_sat<25>(i_x) * gain;
    const ap_int<41> c = hfi_shr<8>(prod);
    const ap_int<17> d = dead;
    return c > d ? d : (c < -d ? ap_int<17>(-d) : ap_int<17>(c));
}

// golden.fpga.deadtime_comp.compensate: per leg, the HF d-current at the edge
// hf = round_shr(HF_AMP * (2 cmp - H) * RECIP_H, 32), i_d = I_D_REF - hf, the phase current i_x, the
// shift c; rising half (top = false) cmp += min(c, 0), falling half cmp += max(c, 0); clamped 0..H.
void hfi_deadtime_comp(const u16 cmp_in[3], bool top, u16 half, u16 dead, u16 gain, s16 i_d_ref,
                       s16 i_q_ref, ap_uint<15> hf_amp, s16 sin_q15, s16 cos_q15, u32 recip_h,
                       u16 cmp_out[3]) {
#pragma HLS INLINE off
#pragma HLS ARRAY_PARTITION variable = cmp_in complete
#pragma HLS ARRAY_PARTITION variable = cmp_out complete
    for (int x = 0; x < 3; x++) {
#pragma HLS UNROLL
        const ap_int<18> slope = ap_int<18>(cmp_in[x]) * 2 - half;      // 2 cmp - H, |.| <= 65534
        const ap_int<33> amp = hf_amp * slope;                            // u15 x s18 -> s33
        // s33 x u32: |amp| <= 32767 * 65534 < 2^31, so the product fits s64 (< 2^63) and |hf| < 2^31
        const ap_int<64> hf_full = amp * recip_h;
        const ap_int<32> hf = hfi_round_shr<32>(hf_full);
        const s33 i_d = s33(i_d_ref) - hf;
        ap_int<37> i_x[3];
#pragma HLS ARRAY_PARTITION variable = i_x complete
        phase_currents(i_d, i_q_ref, sin_q15, cos_q15, i_x);
        const ap_int<17> c = edge_shift(i_x[x], gain, dead);
        const ap_int<17> adj = top ? (c > 0 ? c : ap_int<17>(0)) : (c < 0 ? c : ap_int<17>(0));
        const ap_int<18> moved = ap_int<18>(cmp_in[x]) + adj;
        cmp_out[x] = moved < 0 ? u16(0) : (moved > half ? half : u16(moved));
    }
}
