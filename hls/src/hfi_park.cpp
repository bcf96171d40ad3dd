// Clarke and Park transforms: docs/spec.md 3.2, golden.fpga.park.clarke / golden.fpga.park.park.
#include "hfi_park.h"

// round(2^15 / sqrt(3)), the Clarke coefficient (u15): golden.fpga.park.INV_SQRT3_Q15.
static const ap_uint<15> HFI_INV_SQRT3_Q15 = 18919;

// i_alpha = i_a; i_beta = sat(round_shr((i_a + 2*i_b) * 18919, 15), 16): s18 x u15 -> s33
// (golden.fpga.park.clarke).
void hfi_clarke(s16 i_a, s16 i_b, s16 &i_alpha, s16 &i_beta) {
#pragma HLS INLINE
    const ap_int<18> s = ap_int<18>(i_a) + i_b + i_b;
    const ap_int<33> prod = hfi_mul(s, HFI_INV_SQRT3_Q15);
    i_alpha = i_a;
    i_beta = hfi_sat<16>(hfi_round_shr<15>(prod));
}

// sat(round_shr(sum, 15), 16) of a sum or difference of two s16 x s16 products. Each product is s32
// (it reaches +2^30 at (-2^15)^2); the sum reaches 2^31, so it is formed in s33 (spec 3.2).
static s16 hfi_park_round(const ap_int<33> &sum) {
#pragma HLS INLINE
    return hfi_sat<16>(hfi_round_shr<15>(sum));
}

// i_d = sat(round_shr(i_alpha*COS + i_beta*SIN, 15), 16), i_q = sat(round_shr(i_beta*COS - i_alpha*SIN, 15), 16)
// (golden.fpga.park.park).
void hfi_park(s16 i_alpha, s16 i_beta, s16 sin_q15, s16 cos_q15, s16 &i_d, s16 &i_q) {
#pragma HLS INLINE
    const ap_int<32> ac = hfi_mul(i_alpha, cos_q15), bs = hfi_mul(i_beta, sin_q15);
    const ap_int<32> bc = hfi_mul(i_beta, cos_q15), as = hfi_mul(i_alpha, sin_q15);
    i_d = hfi_park_round(ap_int<33>(ac) + bs);
    i_q = hfi_park_round(ap_int<33>(bc) - as);
}
