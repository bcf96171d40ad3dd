/* fw_fx.h - sums of 32 x 32-bit products with a shift, a rounding and a saturation: golden's fixed-point idioms
 * (golden.fixed: round_shr, shr, sat) as the fixed-point instructions of the SoC (hfi/cfu.py, rtl/hfi_cfu.v,
 * docs/soc.md "The fixed-point instructions"; -DFW_CFU: the SoC build) or as the same int64 C (the host build).
 *
 *   FX_ACC(acc);                    declare an accumulator (int64 on the host; the unit's on the SoC)
 *   FX_MUL(acc, a, b, k)            acc  = (a * b) >> k      (a, b int32; k a constant 0, 8, .., 56; >> floors)
 *   FX_MAC(acc, a, b, k)            acc += (a * b) >> k
 *   FX_MSU(acc, a, b, k)            acc -= (a * b) >> k
 *   FX_ADD(acc, a, k, b)            acc += (a << k) + b      (k 0, 8, .., 56: the unit shifts products by bytes)
 *   FX_SET(acc, hi, lo)             acc = (hi << 32) + (uint32_t)lo    (an int64 value, from its two words)
 *   FX_RND(acc, k, bits)            sat(round_shr(acc, k), bits)   as int32 (k 0..63; bits 1..32; 0: the low word)
 *   FX_FLR(acc, k, bits)            sat(acc >> k, bits)
 *   FX_DIV(acc, d, bits)            sat(c_div(acc, d), bits)       (d int64 != 0; bits a constant 2..22; acc kept)
 *
 * and, on their own accumulator, the two-product idioms (values, each a single expression):
 *   FX_DOT(a, b, c, d, k, bits)     sat(round_shr(a * b + c * d, k), bits)
 *   FX_CROSS(a, b, c, d, k, bits)   sat(round_shr(a * b - c * d, k), bits)
 *   FX_PROD(a, b, k, bits)          sat(round_shr(a * b, k), bits)
 *   FX_SHR(a, b, k, bits)           sat(shr(a * b, k), bits)           (floor: the C's (a * b) >> k)
 *   FX_SUM(a, b, bits)              sat(a + b, bits)                   (in int64: no wrap)
 *
 * One accumulator: on the SoC there is one, so the operands of these macros are plain values (never an FX_*
 * expression, which would run its own accumulation in the middle of this one), an accumulation is started
 * (FX_MUL, FX_SET) and read (FX_RND/FX_FLR) before another starts, and only the control step (the window interrupt, which is not nested) uses it. The
 * operands are int32 values (the unit's registers): a caller whose C had an int64 operand there cannot use
 * these. The sums are the C's int64 sums (the callers' documented ranges keep them from overflowing).
 */
#ifndef FW_FX_H
#define FW_FX_H

#include <stdint.h>

#include "hfi_soc_platform.h"

#ifdef FW_CFU

#define FX_ACC(acc) const int acc = 0
#define FX_INSN_(f3, k, a, b)                                                                                          \
    _Static_assert((k) % 8 == 0 && (k) >= 0 && (k) < 64, "FX_MUL/MAC/MSU/ADD: the unit shifts by whole bytes");     \
    __asm__ volatile(".insn r %0, %1, %2, x0, %3, %4" ::"i"(HFI_CFU_OPCODE), "i"(f3), "i"(k), "r"((int32_t)(a)),     \
                     "r"((int32_t)(b)))
#define FX_READ_(f3, k, bits)                                                                                          \
    __extension__({                                                                                                    \
        int32_t fx_r_;                                                                                                 \
        __asm__ volatile(".insn r %1, %2, %3, %0, %4, x0"                                                            \
                         : "=r"(fx_r_)                                                                                 \
                         : "i"(HFI_CFU_OPCODE), "i"(f3), "i"(k), "r"((int32_t)(bits)));                               \
        fx_r_;                                                                                                         \
    })
#define FX_MUL(acc, a, b, k) do { (void)(acc); FX_INSN_(HFI_CFU_MUL, k, a, b); } while (0)
#define FX_MAC(acc, a, b, k) do { (void)(acc); FX_INSN_(HFI_CFU_MAC, k, a, b); } while (0)
#define FX_MSU(acc, a, b, k) do { (void)(acc); FX_INSN_(HFI_CFU_MSU, k, a, b); } while (0)
#define FX_ADD(acc, a, k, b) do { (void)(acc); FX_INSN_(HFI_CFU_ADD, k, a, b); } while (0)
#define FX_SET(acc, hi, lo) do { (void)(acc); FX_INSN_(HFI_CFU_SET, 0, hi, lo); } while (0)
#define FX_RND(acc, k, bits) ((void)(acc), FX_READ_(HFI_CFU_RND, k, bits))
#define FX_FLR(acc, k, bits) ((void)(acc), FX_READ_(HFI_CFU_FLR, k, bits))
/* the divisor's words in rs1 (high) and rs2 (low), the width in funct7 */
#define FX_DIV(acc, d, bits)                                                                                           \
    __extension__({                                                                                                    \
        _Static_assert((bits) >= 2 && (bits) <= 22, "FX_DIV: 2..22 bits (fw_sat_div64 where the unit is not)");      \
        const int64_t fx_dv_ = (d);                                                                                    \
        int32_t fx_q_;                                                                                                 \
        (void)(acc);                                                                                                   \
        __asm__ volatile(".insn r %1, %2, %3, %0, %4, %5"                                                            \
                         : "=r"(fx_q_)                                                                                 \
                         : "i"(HFI_CFU_OPCODE), "i"(HFI_CFU_DIV), "i"(bits), "r"((int32_t)(fx_dv_ >> 32)),             \
                           "r"((int32_t)fx_dv_));                                                                      \
        fx_q_;                                                                                                         \
    })

#else

#define FX_ACC(acc) int64_t acc
/* the unit's byte shifts (k & 56; the SoC build refuses any other k at compile time) */
#define FX_MUL(acc, a, b, k) ((acc) = ((int64_t)(int32_t)(a) * (int32_t)(b)) >> ((k) & 56))
#define FX_MAC(acc, a, b, k) ((acc) += ((int64_t)(int32_t)(a) * (int32_t)(b)) >> ((k) & 56))
#define FX_MSU(acc, a, b, k) ((acc) -= ((int64_t)(int32_t)(a) * (int32_t)(b)) >> ((k) & 56))
#define FX_ADD(acc, a, k, b) ((acc) += (int64_t)((uint64_t)(int64_t)(int32_t)(a) << ((k) & 56)) + (int32_t)(b))
#define FX_SET(acc, hi, lo) ((acc) = (int64_t)(((uint64_t)(uint32_t)(hi) << 32) | (uint32_t)(lo)))
#define FX_RND(acc, k, bits) fx_result_((acc), (k), (bits), 1)
#define FX_FLR(acc, k, bits) fx_result_((acc), (k), (bits), 0)
/* the SoC build without the unit: control.c's software (no libgcc 64-bit division; d != 0, bits <= 22) */
#ifdef __riscv
int32_t fw_sat_div64(int64_t n, int64_t d, int32_t bits);
#define FX_DIV(acc, d, bits) fw_sat_div64((acc), (d), (bits))
#else
#define FX_DIV(acc, d, bits) fx_quotient_((acc), (d), (bits))
#endif

/* RND / FLR of hfi/cfu.py: the rounding's add wraps as the unit's 64-bit adder does */
static inline int32_t fx_result_(int64_t acc, int k, int32_t bits, int rounding)
{
    int64_t v = rounding && k ? (int64_t)((uint64_t)acc + ((uint64_t)1 << (k - 1))) >> k : acc >> k;
    int w = bits & 63;

    if (w < 1 || w > 32)
        return (int32_t)(uint32_t)(uint64_t)v;
    int64_t hi = ((int64_t)1 << (w - 1)) - 1;
    return (int32_t)(v > hi ? hi : v < -hi - 1 ? -hi - 1 : v);
}

/* DIV of hfi/cfu.py: the width k clamped to 2..32; a zero divisor gives the limit of the dividend's sign (the host's
 * FX_DIV, which tests/test_fw_fx.py checks against the model) */
static inline int32_t fx_quotient_(int64_t n, int64_t d, int k)
{
    int w = k < 2 ? 2 : k > 32 ? 32 : k;
    uint64_t a = n < 0 ? 0u - (uint64_t)n : (uint64_t)n, b = d < 0 ? 0u - (uint64_t)d : (uint64_t)d;
    int neg = (n < 0) != (d < 0);

    if ((a >> (w - 1)) >= b) /* |c_div(n, d)| >= 2^(w-1), or d = 0 */
        return neg ? (int32_t)(0u - ((uint32_t)1 << (w - 1))) : (int32_t)(((uint32_t)1 << (w - 1)) - 1u);
    uint32_t q = (uint32_t)(a / b);
    return neg ? (int32_t)(0u - q) : (int32_t)q;
}

#endif

/* FX_USUAL: 1 where a caller's usual-case path on the unit (operands known to fit its int32 registers, beside a general
 * int64 path: control.c's park64, inv_park64, hfo_euler, eq. (29)'s strength) is compiled: the SoC build with the unit
 * and the host build, whose tests check both paths against golden (tests/test_fw_c.py); 0 in the SoC build without
 * the unit, where the two paths are the same int64 C and only the general one is kept (that image must fit the RAM
 * with the software sin/cos and flux-map look-up beside it). */
#if defined(FW_CFU) || !defined(__riscv)
#define FX_USUAL 1
#else
#define FX_USUAL 0
#endif

#define FX_DOT(a, b, c, d, k, bits)                                                                                    \
    __extension__({ FX_ACC(fx_d_); FX_MUL(fx_d_, a, b, 0); FX_MAC(fx_d_, c, d, 0); FX_RND(fx_d_, k, bits); })
#define FX_CROSS(a, b, c, d, k, bits)                                                                                  \
    __extension__({ FX_ACC(fx_d_); FX_MUL(fx_d_, a, b, 0); FX_MSU(fx_d_, c, d, 0); FX_RND(fx_d_, k, bits); })
#define FX_PROD(a, b, k, bits) __extension__({ FX_ACC(fx_d_); FX_MUL(fx_d_, a, b, 0); FX_RND(fx_d_, k, bits); })
#define FX_SUM(a, b, bits) __extension__({ FX_ACC(fx_d_); FX_MUL(fx_d_, a, 1, 0); FX_ADD(fx_d_, b, 0, 0); FX_FLR(fx_d_, 0, bits); })
#define FX_SHR(a, b, k, bits) __extension__({ FX_ACC(fx_d_); FX_MUL(fx_d_, a, b, 0); FX_FLR(fx_d_, k, bits); })

#endif
