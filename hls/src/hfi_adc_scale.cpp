// ADC offset and scale: docs/spec.md 3.1, golden.fpga.adc_scale.adc_to_current.
#include "hfi_adc_scale.h"

// x = (code - 2^(B-1)) * 2^(16-B), the left-aligned code (s16). code < 2^B, so code << (16-B) < 2^16 and
// x lies in [-2^15, 2^15 - 2^(16-B)]: the narrowing to s16 cannot overflow.
// Formed on the native value (a barrel shifter and a subtractor in hardware either way): in C simulation an
// ap_uint shift by a variable amount takes ap_int's general path, and this runs once per ADC sample.
static s16 hfi_adc_left_align(ap_uint<16> code, ap_uint<5> bits) {
#pragma HLS INLINE
    const int left = int((code.to_uint() << (16 - bits.to_int())) & 0xFFFFu);
    return s16(left - (1 << 15));
}

// i = sat(round_shr((x - ADC_OFFSET) * ADC_GAIN, 14), 16): s17 x u16 -> s33 (golden adc_to_current).
s16 hfi_adc_scale(ap_uint<16> code, ap_uint<5> bits, s16 offset, u16 gain) {
#pragma HLS INLINE
    const ap_int<17> diff = ap_int<17>(hfi_adc_left_align(code, bits)) - offset;
    const ap_int<33> prod = hfi_mul(diff, gain);
    return hfi_sat<16>(hfi_round_shr<14>(prod));
}
