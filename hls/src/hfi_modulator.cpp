// Modulator, docs/spec.md 3.5 (golden/fpga/modulator.py compares). Widths: the worst cases over every
// register value stated in the golden module's docstring (SIN/COS not required on the unit circle).
#include "hfi_modulator.h"

// round(2^15 * sqrt(3) / 2), the inverse Clarke coefficient (golden.fpga.modulator.SQRT3_HALF_Q15).
static const ap_uint<15> HFI_SQRT3_HALF_Q15 = 28378;

typedef ap_int<18> s18;

// Phase voltage of leg x in its compare: clamp(H/2 + round_shr(v'*H, 15), 0, H) (spec 3.5 step 5).
static u16 compare_of(s18 v_shifted, u16 half) {
#pragma HLS INLINE
    const ap_int<34> prod = v_shifted * half;                         // s18 x u16 -> s34
    const ap_int<35> term = hfi_round_shr<15>(prod);                  // |term| < 2^18
    const ap_int<20> raw = ap_int<20>(half >> 1) + ap_int<20>(term);  // |v'| <= 87916: |raw| < 2^19
    return raw < 0 ? u16(0) : (raw > half ? half : u16(raw));
}

// golden.fpga.modulator.compares with sign = +1 at the top, -1 at the bottom; rot: its rot = (inj_cos, inj_sin).
void hfi_modulator(s16 v_d, s16 v_q, s16 v_h, bool rot, s16 inj_sin, s16 inj_cos, s16 sin_q15, s16 cos_q15,
                   u16 half, bool top, u16 cmp[3]) {
#pragma HLS INLINE off
#pragma HLS ARRAY_PARTITION variable = cmp complete
    // Square wave (rot = 0): the injection on the estimated d-axis, eq. (14), vd = V_D + sgn*V_H (s17),
    // no rotating term (C = S = 0). Rotating (rot = 1, Tap et al. 2023, eq. (9)): vd = V_D and the
    // third product V_H*(C, S) below. One datapath: the spec 3.5 sums with C = S = 0 for the square wave.
    const ap_int<17> vd = rot ? ap_int<17>(v_d) : (top ? ap_int<17>(v_d + v_h) : ap_int<17>(v_d - v_h));
    const s16 c_r = rot ? inj_cos : s16(0);
    const s16 s_r = rot ? inj_sin : s16(0);
    // Inverse Park plus the rotating vector: |vd| <= 65535, so each product fits s32 (V_H*C, V_H*S:
    // u15 x s16); the sums s33 (square wave: two products of |.| <= 65535*32768; rotating: |vd| <= 32768,
    // three products of |.| <= 2^30, within 3*2^30), the results s18.
    const ap_int<32> vd_c = vd * cos_q15;
    const ap_int<32> vd_s = vd * sin_q15;
    const ap_int<32> vq_s = v_q * sin_q15;
    const ap_int<32> vq_c = v_q * cos_q15;
    const ap_int<32> vh_c = v_h * c_r;
    const ap_int<32> vh_s = v_h * s_r;
    const s18 v_al = hfi_round_shr<15>(ap_int<33>(ap_int<33>(vd_c) - vq_s + vh_c));   // within +-98303
    const s18 v_be = hfi_round_shr<15>(ap_int<33>(ap_int<33>(vd_s) + vq_c + vh_s));   // within +-98303
    // Inverse Clarke: v_b/c = -v_alpha/2 +- sqrt(3)/2 v_beta; the sums s33, results within +-101517.
    const ap_int<32> a_part = -(ap_int<32>(v_al) << 14);
    const ap_int<33> b_part = v_be * HFI_SQRT3_HALF_Q15;                // s18 x u15 -> s33
    s18 v[3];
#pragma HLS ARRAY_PARTITION variable = v complete
    v[0] = v_al;
    v[1] = hfi_round_shr<15>(ap_int<33>(a_part + b_part));
    v[2] = hfi_round_shr<15>(ap_int<33>(a_part - b_part));
    // Min-max zero sequence: off = shr(max + min, 1).
    s18 hi = v[0];
    s18 lo = v[0];
    for (int x = 1; x < 3; x++) {
#pragma HLS UNROLL
        hi = v[x] > hi ? v[x] : hi;
        lo = v[x] < lo ? v[x] : lo;
    }
    const s18 off = hfi_shr<1>(ap_int<19>(ap_int<19>(hi) + lo));
    for (int x = 0; x < 3; x++) {
#pragma HLS UNROLL
        cmp[x] = compare_of(s18(v[x] - off), half);                    // |v_x - off| <= 87916
    }
}
