// Fixed-width integer types and the arithmetic helpers of docs/spec.md section 1 (golden/fixed.py),
// on the Xilinx arbitrary-precision types (ap_int.h, carried by the PyPI package hls4ml).
//
// Every helper is a plain function template on ap_int: it synthesizes to a compare/select or an
// adder and a wire shift. All widths are at most 64 bits, so C simulation uses ap_int's single-word
// fast path.
#ifndef HFI_FIXED_H
#define HFI_FIXED_H

#include <ap_int.h>

typedef ap_int<16> s16;
typedef ap_uint<16> u16;
typedef ap_int<32> s32;
typedef ap_uint<32> u32;

// sat(x, N): clamp to [-2^(N-1), 2^(N-1) - 1] (golden.fixed.sat).
template <int N, int M>
inline ap_int<N> hfi_sat(const ap_int<M> &x) {
    const int W = (M > N ? M : N) + 1;
    const ap_int<W> hi = (ap_int<W>(1) << (N - 1)) - 1;
    const ap_int<W> lo = -hi - 1;
    const ap_int<W> v = x;
    return v > hi ? ap_int<N>(hi) : (v < lo ? ap_int<N>(lo) : ap_int<N>(v));
}

// usat(x, N): clamp to [0, 2^N - 1] (golden.fixed.usat).
template <int N, int M>
inline ap_uint<N> hfi_usat(const ap_int<M> &x) {
    const int W = (M > N ? M : N) + 2;
    const ap_int<W> hi = (ap_int<W>(1) << N) - 1;
    const ap_int<W> v = x;
    return v > hi ? ap_uint<N>(hi) : (v < 0 ? ap_uint<N>(0) : ap_uint<N>(v));
}

// shr(x, n): floor(x / 2^n), an arithmetic right shift (golden.fixed.shr).
template <int S, int M>
inline ap_int<M> hfi_shr(const ap_int<M> &x) {
    return x >> S;
}

// round_shr(x, n): floor((x + 2^(n-1)) / 2^n), round half up (golden.fixed.round_shr); the sum is
// formed one bit wider, so it never overflows.
template <int S, int M>
inline ap_int<M + 1> hfi_round_shr(const ap_int<M> &x) {
    const ap_int<M + 1> v = x;
    return (v + (ap_int<M + 1>(1) << (S - 1))) >> S;
}

#endif
