// FCS-MPC vector choice, docs/spec.md 3.10 (golden/fpga/fcs_mpc.py choose_vector). Widths: |vd_j|,
// |vq_j| <= 29842 (s16; the sums within 2^30); the p_j sum within 2*2^15*29842 < 2^31 (s32), p_j s20;
// d_j = K_j - 2 (v_al VX_j + v_be VY_j) within +-8.4e9 (s35) for s18 v_al, v_be.
#include "hfi_fcs_mpc.h"

typedef ap_int<18> s18;

// The six active states in angle order 0, 60, ..., 300 deg and their voltages (golden ACTIVE_STATES,
// VX, VY, K).
static const ap_uint<3> FCS_STATE[6] = {1, 3, 2, 6, 4, 5};
static const ap_int<16> FCS_VX[6] = {21845, 10923, -10923, -21845, -10923, 10923};
static const ap_int<16> FCS_VY[6] = {0, 18919, 18919, 0, -18919, -18919};
static const ap_uint<29> FCS_K[6] = {477204025, 477240490, 477240490, 477204025, 477240490, 477240490};

ap_uint<3> hfi_fcs_choose(s18 v_al, s18 v_be, s16 sin_q15, s16 cos_q15, s16 a1, s16 a2, u16 phi_min,
                          bool constrain, ap_uint<3> state_now) {
#pragma HLS INLINE off
    // Two candidates side by side: the constrained one (eligible active vectors only) and the
    // unconstrained one (the zero vector first, d_0 = 0, then every active vector); the first of
    // equal d wins in both.
    bool ca_ok = false;
    ap_uint<3> ca_s = 0, cb_s = 0;
    ap_int<36> ca_d = 0, cb_d = 0;
    for (int j = 0; j < 6; j++) {
#pragma HLS PIPELINE II = 1
        const ap_int<16> x = FCS_VX[j], y = FCS_VY[j];
        const ap_int<31> sd = ap_int<31>(x * cos_q15) + ap_int<31>(y * sin_q15);
        const ap_int<31> sq = ap_int<31>(y * cos_q15) - ap_int<31>(x * sin_q15);
        const s16 vd = hfi_round_shr<15>(sd);                                   // |.| <= 29842
        const s16 vq = hfi_round_shr<15>(sq);
        const ap_int<33> ps = ap_int<33>(a1 * vq) - ap_int<33>(a2 * vd);          // |.| < 2^31
        const ap_int<21> p = hfi_round_shr<12>(ps);                              // s20
        const ap_int<21> pa = p < 0 ? ap_int<21>(-p) : p;
        const bool elig = pa > ap_int<21>(phi_min);
        const ap_int<36> dot = ap_int<36>(v_al * x) + ap_int<36>(v_be * y);      // |.| < 2^33
        const ap_int<36> d = ap_int<36>(FCS_K[j]) - (dot << 1);
        if (elig && (!ca_ok || d < ca_d)) {
            ca_ok = true;
            ca_s = FCS_STATE[j];
            ca_d = d;
        }
        if (d < cb_d) {
            cb_s = FCS_STATE[j];
            cb_d = d;
        }
    }
    const ap_uint<3> pick = (constrain && ca_ok) ? ca_s : cb_s;
    if (pick != 0) {
        return pick;
    }
    const int high = int(state_now[0]) + int(state_now[1]) + int(state_now[2]);
    return high >= 2 ? ap_uint<3>(7) : ap_uint<3>(0);                         // fewer legs to switch
}

ap_uint<3> hfi_modulator_direct(s16 v_d, s16 v_q, s16 sin_q15, s16 cos_q15, s16 a1, s16 a2, u16 phi_min,
                                bool constrain, ap_uint<3> state_now, u16 half, u16 cmp[3]) {
#pragma HLS INLINE off
#pragma HLS ARRAY_PARTITION variable = cmp complete
    // Inverse Park without injection (spec 3.5 step 2 with V_H = 0): products s32, sums s33.
    const s18 v_al = hfi_round_shr<15>(ap_int<33>(ap_int<33>(v_d * cos_q15) - ap_int<32>(v_q * sin_q15)));
    const s18 v_be = hfi_round_shr<15>(ap_int<33>(ap_int<33>(v_d * sin_q15) + ap_int<32>(v_q * cos_q15)));
    const ap_uint<3> s = hfi_fcs_choose(v_al, v_be, sin_q15, cos_q15, a1, a2, phi_min, constrain, state_now);
    for (int x = 0; x < 3; x++) {
#pragma HLS UNROLL
        cmp[x] = s[x] ? half : u16(0);
    }
    return s;
}
