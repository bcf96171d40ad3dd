// CORDIC users of docs/spec.md 3.3: the firmware's Q1.15 sin/cos and the demodulation weight
// (golden.fpga.cordic.sincos_q15, golden.fpga.cordic.demod_weight).
#include "hfi_cordic.h"

// golden.fpga.cordic.sincos_q15 with its defaults (WIDTH, ITERATIONS) = (32, 16), spec 5.2.
void hfi_sincos_q15(u32 angle, s16 &sin_q15, s16 &cos_q15) {
    ap_int<32> s, c;
    hfi_cordic_sincos<32, 16>(angle, s, c);
    sin_q15 = hfi_to_q15<32>(s);
    cos_q15 = hfi_to_q15<32>(c);
}

// golden.fpga.cordic.demod_weight: a = uwrap((H - 2c) * CW_ANGLE_STEP, 32) (s17 x u32 -> s49, then the
// binary-angle wrap: its low 32 bits), w = to_q15(sin(a)) with (WIDTH, ITERATIONS) = (32, 32).
s16 hfi_demod_weight(u16 counter, u16 half, u32 step) {
    const ap_int<17> span = ap_int<17>(half) - counter - counter;
    const ap_int<49> prod = hfi_mul(span, step);
    const u32 angle = prod(31, 0);
    ap_int<32> s, c;
    hfi_cordic_sincos<32, 32>(angle, s, c);
    return hfi_to_q15<32>(s);
}
