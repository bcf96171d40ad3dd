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

// sat(x, N): clamp to [-2^(N-1), 2^(N-1) - 1] (golden.fixed.sat). N <= 63, M <= 64: the compares
// are made on the native value (the same two comparators in hardware; in C simulation this avoids
// ap_int's multi-word path, which a compare against a 64-bit constant would take).
template <int N, int M>
inline ap_int<N> hfi_sat(const ap_int<M> &x) {
    const long long hi = (1LL << (N - 1)) - 1;
    const long long lo = -hi - 1;
    const long long v = x.to_int64();
    return ap_int<N>(v > hi ? hi : (v < lo ? lo : v));
}

// usat(x, N): clamp to [0, 2^N - 1] (golden.fixed.usat). N <= 62, M <= 64.
template <int N, int M>
inline ap_uint<N> hfi_usat(const ap_int<M> &x) {
    const long long hi = (1LL << N) - 1;
    const long long v = x.to_int64();
    return ap_uint<N>(v > hi ? hi : (v < 0 ? 0 : v));
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
    const ap_int<M + 1> v = x + ap_int<M + 1>(1LL << (S - 1));
    return v >> S;
}

#endif
