// Template definitions of hls/include/hfi_cordic.h: the rotation CORDIC of docs/spec.md 3.3
// (golden.fpga.cordic.cordic_sincos, golden.fpga.cordic.to_q15). Included at the end of hfi_cordic.h.
#ifndef HFI_CORDIC_IMPL_H
#define HFI_CORDIC_IMPL_H

// Half a turn of the u32 binary angle (2^31).
const ap_uint<32> HFI_HALF_TURN = ap_uint<32>(1) << 31;

// The folded angle of spec 3.3: a - 2^31 if the top two bits are 01 or 10 (90 deg ... 270 deg), else
// a read as s32; in [-2^30, 2^30) either way. The subtraction wraps modulo 2^32 (binary angle).
inline s32 hfi_cordic_fold(const u32 &angle, bool &negate) {
#pragma HLS INLINE
    const ap_uint<2> quadrant = angle(31, 30);
    negate = quadrant == 1 || quadrant == 2;
    return negate ? s32(u32(angle - HFI_HALF_TURN)) : s32(angle);
}

// golden.fpga.cordic.cordic_sincos: x0 = round(K_N * 2^(WIDTH-2)) (generated table), y0 = 0; iteration
// i: d = +1 if z >= 0 else -1, x' = x - d*shr(y, i), y' = y + d*shr(x, i), z' = z - d*ATAN[i].
// |x|, |y| stay near 2^(WIDTH-2) (K_N * the CORDIC gain = 1, plus truncation errors) and |z| <= 2^30,
// so the sWIDTH / s32 registers never overflow (golden module docstring, "Widths").
template <int WIDTH, int ITERATIONS>
void hfi_cordic_sincos(u32 angle, ap_int<WIDTH> &sin_raw, ap_int<WIDTH> &cos_raw) {
#pragma HLS INLINE off
    static_assert(WIDTH >= HFI_CORDIC_WIDTH_MIN && WIDTH <= HFI_CORDIC_WIDTH_MAX, "WIDTH must be 17..32");
    static_assert(ITERATIONS >= 1 && ITERATIONS <= WIDTH, "ITERATIONS must be 1..WIDTH");
    bool negate;
    s32 z = hfi_cordic_fold(angle, negate);
    ap_int<WIDTH> x = HFI_CORDIC_X0[WIDTH - HFI_CORDIC_WIDTH_MIN][ITERATIONS - 1];
    ap_int<WIDTH> y = 0;
    for (int i = 0; i < ITERATIONS; i++) {
#pragma HLS UNROLL
        const ap_int<WIDTH> xs = x >> i, ys = y >> i;     // shr(x, i), shr(y, i): arithmetic shifts
        const s32 atan_i = HFI_CORDIC_ATAN[i];
        if (z >= 0) {
            x = x - ys;
            y = y + xs;
            z = z - atan_i;
        } else {
            x = x + ys;
            y = y - xs;
            z = z + atan_i;
        }
    }
    sin_raw = negate ? ap_int<WIDTH>(-y) : y;
    cos_raw = negate ? ap_int<WIDTH>(-x) : x;
}

// golden.fpga.cordic.to_q15: sat(round_shr(v, WIDTH - 17), 16), Q2.(WIDTH-2) -> Q1.15.
template <int WIDTH>
s16 hfi_to_q15(const ap_int<WIDTH> &v) {
#pragma HLS INLINE
    static_assert(WIDTH >= HFI_CORDIC_WIDTH_MIN && WIDTH <= HFI_CORDIC_WIDTH_MAX, "WIDTH must be 17..32");
    return hfi_sat<16>(hfi_round_shr<WIDTH - 17>(v));
}

#endif
