// The hardware overcurrent comparator: docs/spec.md 3.7, golden.fpga.overcurrent.over_limit.
#include "hfi_overcurrent.h"

// |x| > L as x > L or x < -L, in 19 bits (s18 magnitudes up to 65536 against the zero-extended u16 limit).
static bool hfi_beyond(const ap_int<19> &x, const ap_int<19> &lim) {
#pragma HLS INLINE
    return x > lim || x < -lim;
}

bool hfi_overcurrent(s16 i_a, s16 i_b, u16 limit) {
#pragma HLS INLINE
    const ap_int<19> lim = limit;
    const ap_int<19> sum = ap_int<19>(i_a) + i_b;
    return hfi_beyond(i_a, lim) || hfi_beyond(i_b, lim) || hfi_beyond(sum, lim);
}
