// Fixed-width integer types and the arithmetic helpers of docs/spec.md section 1 (golden/fixed.py),
// on the Xilinx arbitrary-precision types (ap_int.h, carried by the PyPI package hls4ml).
//
// Every helper is a plain function template on ap_int: it synthesizes to a compare/select or an
// adder and a wire shift. All widths are at most 64 bits, so C simulation uses ap_int's single-word
// fast path.
#ifndef HFI_FIXED_H
#define HFI_FIXED_H

#include <ap_int.h>
#include <type_traits>

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

// round_shr(x, n): floor((x + 2^(n-1)) / 2^n), round half up (golden.fixed.round_shr); n = 0 is the
// identity. The sum is formed one bit wider, so it never overflows: on the native value up to 62 bits
// (fast in C simulation), in ap_int arithmetic beyond.
template <int S, int M>
inline ap_int<M + 1> hfi_round_shr_(const ap_int<M> &x, std::true_type /* M <= 62 */) {
    const long long half = S > 0 ? 1LL << (S > 0 ? S - 1 : 0) : 0;
    return ap_int<M + 1>((x.to_int64() + half) >> S);
}
template <int S, int M>
inline ap_int<M + 1> hfi_round_shr_(const ap_int<M> &x, std::false_type /* M > 62 */) {
    ap_int<M + 1> half = 0;
    if (S > 0) half[S > 0 ? S - 1 : 0] = 1;
    const ap_int<M + 1> v = ap_int<M + 1>(x) + half;
    return v >> S;
}
template <int S, int M>
inline ap_int<M + 1> hfi_round_shr(const ap_int<M> &x) {
    static_assert(S >= 0 && S < M, "hfi_round_shr: 0 <= S < M");
    return hfi_round_shr_<S>(x, std::integral_constant<bool, (M <= 62)>());
}

// Full-width product a * b (golden: the exact product; spec 1 "Products are formed at full width").
// Formed as the native 64-bit product, exact since M1 + M2 <= 63: in C simulation ap_int's operator*
// takes its multi-word path (with a heap allocation) whenever the product is wider than 32 bits;
// synthesizes to an M1 x M2 multiplier.
template <int M1, bool S1, int M2, bool S2>
inline ap_int<M1 + M2 + ((S1 || S2) ? 0 : 1)> hfi_mul(const ap_int_base<M1, S1> &a, const ap_int_base<M2, S2> &b) {
    static_assert(M1 + M2 <= 63, "hfi_mul: the product must fit the native 64-bit product");
    return ap_int<M1 + M2 + ((S1 || S2) ? 0 : 1)>(a.to_int64() * b.to_int64());
}

#endif
