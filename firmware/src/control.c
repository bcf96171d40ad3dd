/* control.c - the firmware's control algorithms (docs/spec.md, section 5), freestanding C11.
 *
 * Every function is the bit-exact twin of the golden model named in its comment and performs the
 * integer operations its docstring prescribes for C, in the same order: int32_t/uint32_t/int64_t only,
 * arithmetic right shifts of signed values (GCC), wrapping unsigned adds for binary angles, casts to
 * int32_t for angle differences (golden.fixed.wrap), `/` for golden.fixed.c_div. No floating point,
 * no libc but memset and memcpy (firmware/src/mem.c on the core), no global mutable state (the only static data is the
 * generated CORDIC table).
 * For the cycle budget on PicoRV32 a few steps take a cheaper form with the same value for every legal
 * input (each says so where it is): the PI error as an overflow-checked 32-bit subtraction, 64-bit
 * shifts by 0..31 from 32-bit halves, the speed filter's r a in uint32_t, the CORDIC unrolled, the PI
 * inlined into fw_step.
 * tests/test_fw_c.py checks every function against the golden model (host build, firmware/Makefile).
 *
 * Ranges the C relies on (the golden docstrings): N_SAMPLES is u16; PI gains, limits and PLL gains as
 * golden.firmware.pi.PiParams and pll.pll_gains; 0 <= speed_lp <= 65536; i_pulse != INT32_MIN (the
 * golden -i_pulse would not fit the s32 current reference).
 */
#include "control.h"

#include <stddef.h>

#include "fw_cordic_table.h"
#include "fw_fx.h"
#include "fw_methods.h"
#include "hfi_regs.h"

void *memset(void *dst, int c, size_t n); /* firmware/src/mem.c (the host build: the C library's) */
void *memcpy(void *dst, const void *src, size_t n);

#define HALF_TURN 0x80000000u /* golden.firmware.supervisor.HALF_TURN: half an electrical turn */

/* The constant tables the control step reads, placed right after the state (firmware/link.ld, .state): in
 * .rodata their offset in the 4 KiB direct-mapped data cache moved with the code's size, and one change put
 * fw_methods on the stack's lines (docs/soc.md, "The data cache"). */
#define STEP_TABLE __attribute__((section(".state_tables")))

/* The body of a small block that fw_step runs once per period, inlined there; the block's public function (the host
 * tests', the other callers') calls the same body: the call's register moves were about a third of its clocks. */
#define STEP_INLINE __attribute__((always_inline)) static inline

/* ---- fixed-point helpers (golden/fixed.py) ------------------------------------------------------ */

/* golden.fixed.sat(x, 32) */
static int32_t sat32(int64_t x)
{
    return x > INT32_MAX ? INT32_MAX : x < INT32_MIN ? INT32_MIN : (int32_t)x;
}

/* golden.fixed.sat(x, 16) */
static int32_t sat16(int32_t x)
{
    return x > INT16_MAX ? INT16_MAX : x < INT16_MIN ? INT16_MIN : x;
}

/* golden.fixed.shr(x, n) of an int64 for 0 <= n <= 31 (the PI shift counts sp, si), formed from the
 * 32-bit halves: GCC's generic 64-bit shift on RV32 also handles n >= 32 and costs a branch more. */
static int64_t shr64(int64_t x, int32_t n)
{
    uint32_t lo = (uint32_t)x;
    int32_t hi = (int32_t)(x >> 32);
    uint32_t new_lo = (lo >> n) | (((uint32_t)hi << 1) << (31 - n));

    return (int64_t)(((uint64_t)(uint32_t)(hi >> n) << 32) | new_lo);
}

/* x itself, hidden from the optimiser (speed only, no value change): GCC then forms (int64_t)k * x as one
 * widening mul/mulh pair on RV32 instead of a full 64 x 64 product of sign-extended operands, which it
 * otherwise does when x comes out of a saturation. */
static int32_t opaque_s32(int32_t x)
{
    __asm__("" : "+r"(x));
    return x;
}

/* min(max(x, -lim), lim) for 0 <= lim < 2^62 (the clamps of golden.firmware.pi.pi_step): x + lim in uint64 lies in
 * [0, 2 lim] exactly when x is inside (no wrap for any int64 x: x + lim < 2^64), so the common case is one unsigned
 * 64-bit compare instead of two signed ones */
static int64_t clamp_sym(int64_t x, int64_t lim)
{
    if ((uint64_t)x + (uint64_t)lim <= 2u * (uint64_t)lim)
        return x;
    return x < 0 ? -lim : lim;
}

/* ---- blocks ------------------------------------------------------------------------------------ */

/* the bit length of x (Python int.bit_length) by halving, without libgcc's __clzsi2 and its table (a data-cache
 * line of its own) */
static int32_t bit_length32(uint32_t x)
{
    int32_t n = 0;

    if (x >> 16) { n += 16; x >>= 16; }
    if (x >> 8) { n += 8; x >>= 8; }
    if (x >> 4) { n += 4; x >>= 4; }
    if (x >> 2) { n += 2; x >>= 2; }
    if (x >> 1) { n += 1; x >>= 1; }
    return n + (int32_t)x;
}

/* c_div(x, d) for 3 <= d < 2^16 by a multiply with the divisor's magic number (div, from div_magic), when
 * |x| < 2^30; the core's divide (about 35 clocks) otherwise. With l = ceil(log2 d), s = 30 + l = 32 + t and
 * M = floor(2^s / d) + 1 (so M d = 2^s + e, 0 < e <= d): x M / 2^s = x / d + x e / (d 2^s), and |x| e < 2^s
 * keeps the second term below 1/d, so floor(x M / 2^s) is floor(x / d) for x >= 0 and one below trunc(x / d)
 * for x < 0 (the term is > 0 and x / d lies on or below the integer it truncates to). Granlund & Montgomery,
 * "Division by invariant integers using multiplication", PLDI 1994, Sec. 5; M < 2^31 fits a signed mulh.
 * d = 1, 2 (the 003 drive's windows: one or two samples) without a divide: x, and trunc(x / 2) as
 * (x + 1) >> 1 for x < 0. tests/test_fw_c.py checks it against golden for every d at the edges of the fast range. */
static int32_t div_by(const struct fw_divisor *div, int32_t x)
{
    if (div->n < 3u)
        return div->n == 1u ? x : (x + (int32_t)((uint32_t)x >> 31)) >> 1;
    if ((uint32_t)x + (1u << 30) >= (1u << 31))               /* |x| >= 2^30: the divide */
        return x / (int32_t)div->n;
    int32_t hi = (int32_t)(((int64_t)x * div->m) >> 32);     /* one mulh */

    return (hi >> div->t) + (int32_t)((uint32_t)x >> 31);
}

/* div's magic number for d (1 <= d < 2^16): M = floor(2^(30+l) / d) + 1 from 32-bit divides, as
 * 2^(l-1) floor(2^31 / d) + floor(2^(l-1) (2^31 mod d) / d) + 1 (each term < 2^31 for l <= 16). */
static void div_magic(struct fw_divisor *div, uint32_t d)
{
    div->n = d;
    if (d < 3u)
        return;
    const int32_t l = bit_length32(d - 1u);
    const uint32_t q = 0x80000000u / d, r = 0x80000000u - q * d;

    div->m = (int32_t)((q << (l - 1)) + (r << (l - 1)) / d + 1u);
    div->t = l - 2;
}

/* golden.firmware.means.window_means: c_div of the window sums by N (u16, so INT32_MIN / -1 cannot occur); 0 if
 * N == 0. The divisions go by div's magic number for N (kept while N stays; about 16 clocks for both instead of
 * 70 on the core). */
void fw_window_means(struct fw_divisor *div, int32_t sum_id, int32_t sum_iq, uint32_t n, int32_t *i_d,
                     int32_t *i_q)
{
    if (n == 0u) {
        *i_d = *i_q = 0;
        return;
    }
    if (n != div->n)
        div_magic(div, n);
    *i_d = div_by(div, sum_id);
    *i_q = div_by(div, sum_iq);
}

/* golden.firmware.bangbang.bangbang_step (Benevieri et al. 2023, Sec. II-B, Fig. 1) */
uint32_t fw_bangbang_step(uint32_t theta_hat, int32_t gamma, uint32_t k_bb)
{
    if (gamma > 0)
        return theta_hat + k_bb;
    if (gamma < 0)
        return theta_hat - k_bb;
    return theta_hat;
}

/* golden.firmware.pll.pll_step: e = wrap(theta_hat - theta, 32); integ = sat(integ + ki e, 64);
 * omega = sat(shr(kp e, 16) + shr(integ, 24), 32); theta = uwrap(theta + omega, 32). */
void fw_pll_step(struct fw_pll *s, uint32_t theta_hat, int32_t kp, int32_t ki)
{
    int32_t e = (int32_t)(theta_hat - s->theta);
    int64_t p = (int64_t)ki * e; /* |p| < 2^62 */
    int64_t integ;

    if (__builtin_add_overflow(s->integ, p, &integ))
        integ = p < 0 ? INT64_MIN : INT64_MAX;
    s->integ = integ;
    FX_ACC(acc);                                 /* shr(kp e, 16) + shr(integ, 24), the latter from integ's words */
    FX_MUL(acc, kp, e, 16);
    FX_ADD(acc, (int32_t)(integ >> 32), 8, (int32_t)((uint32_t)integ >> 24));
    s->omega = FX_FLR(acc, 0, 32);
    s->theta += (uint32_t)s->omega;
}

/* golden.firmware.lowpass.lowpass_step: F + shr(((x << 16) - F) * a, 16) with the product split so that
 * it cannot overflow int64 (|d| < 2^48, a <= 2^16): floor(d a / 2^16) = q a + floor(r a / 2^16). */
int64_t fw_lowpass_step(int64_t f, int32_t x, int32_t a)
{
    int64_t d = (int64_t)x * 65536 - f;
    int64_t q = d >> 16;                       /* |q| <= 2^32 */
    uint32_t r = (uint32_t)(d & 0xFFFF);       /* 0 <= r < 2^16 */
    uint32_t ua = (uint32_t)a;                 /* 0 <= a <= 2^16: r a < 2^32, exact in uint32_t */

    return f + q * (int64_t)ua + (int64_t)((r * ua) >> 16);
}

/* golden.firmware.lowpass.lowpass_out: shr(F, 16) */
int32_t fw_lowpass_out(int64_t f)
{
    return (int32_t)(f >> 16);
}

/* golden.firmware.pi.pi_step: conditional-integration anti-windup, steps 1..6 of its docstring. Step 1
 * as a 32-bit subtraction with overflow check (the same value as the int64 difference clamped to s32);
 * step 6 reuses the u of step 4 when the integrator takes cand (then both sums are equal).
 * Not inlined: one copy for fw_step's three calls. Inlined three times, the 002 step in RUN took 2357 CPU
 * clocks mean instead of 2117 (fullload_start, 16 KiB instruction cache; 3913 instead of 3707 with 4 KiB). */
static __attribute__((noinline)) int32_t pi_step(int64_t *integ, int32_t ref, int32_t meas,
                                                             const struct fw_pi_params *p)
{
    int32_t e, si = p->si, limit = p->limit;

    if (__builtin_sub_overflow(ref, meas, &e))                           /* 1 */
        e = ref < 0 ? INT32_MIN : INT32_MAX;
    e = opaque_s32(e);
    int64_t prop = shr64((int64_t)p->kp * e, p->sp);                     /* 2 */
    int64_t cand = clamp_sym(*integ + (int64_t)p->ki * e, p->lim_i);     /* 3 */

    /* the usual case in 32-bit words: |prop| < 2^30 and limit < 2^30; |cand|, |integ| <= lim_i (the integrator's
     * range, golden's precondition), so their shifts by si lie in [-limit, limit]: the low word of shr64, and
     * every sum below within int32 */
    if ((uint64_t)prop + (1u << 30) < (1u << 31) && limit < (1 << 30)) {
        const int32_t p32 = (int32_t)prop;
        int32_t v = p32 + (int32_t)shr64(cand, si);                      /* 4 */

        if (e > 0 ? v > limit : e < 0 && v < -limit)                     /* 5: frozen */
            v = p32 + (int32_t)shr64(*integ, si);                        /* 6, integ_new = integ */
        else
            *integ = cand;                                               /* 6, integ_new = cand */
        return v > limit ? limit : v < -limit ? -limit : v;
    }
    int64_t u = prop + shr64(cand, si);                                  /* 4 */

    if (e > 0 ? u > limit : e < 0 && u < -(int64_t)limit)                /* 5: frozen */
        u = prop + shr64(*integ, si);                                    /* 6, integ_new = integ */
    else
        *integ = cand;                                                   /* 6, integ_new = cand */
    return (int32_t)clamp_sym(u, limit);
}

/* golden.firmware.pi.pi_step: returns u, updates *integ */
int32_t fw_pi_step(int64_t *integ, int32_t ref, int32_t meas, const struct fw_pi_params *p)
{
    return pi_step(integ, ref, meas, p);
}

#ifndef FW_ACC /* the SoC build takes sin/cos, the vector angle and the flux-map look-up from hfi_soc_acc (fw_acc.c): same results */
/* Q2.30 CORDIC output -> Q1.15: golden.fpga.cordic.to_q15(v, 32) = sat(round_shr(v, 15), 16).
 * |v| < 2^31 - 2^14, so the rounding add cannot overflow. */
static int32_t cordic_to_q15(int32_t v)
{
    return sat16((v + (1 << 14)) >> 15);
}

/* golden.fpga.cordic.sincos_q15(angle, 32, 16): fold to [-2^30, 2^30), rotate FW_CORDIC_ITERATIONS
 * times from (x0, 0) (each step uses the old x and y), negate if folded. z, x, y stay inside s32. */
void fw_sincos_q15(uint32_t angle, int32_t *sin_q15, int32_t *cos_q15)
{
    uint32_t quadrant = angle >> 30;
    int fold = quadrant == 1u || quadrant == 2u;
    int32_t z = (int32_t)(fold ? angle - HALF_TURN : angle);
    int32_t x = FW_CORDIC_X0, y = 0;

#pragma GCC unroll 4 /* 4, not 16: the fully unrolled loop (1.1 KiB) costs more in cache refills than it saves */
    for (int i = 0; i < FW_CORDIC_ITERATIONS; i++) {
        int32_t xs = x >> i, ys = y >> i;

        if (z >= 0) {
            x -= ys;
            y += xs;
            z -= fw_cordic_atan[i];
        } else {
            x += ys;
            y -= xs;
            z += fw_cordic_atan[i];
        }
    }
    if (fold) {
        x = -x;
        y = -y;
    }
    *sin_q15 = cordic_to_q15(y);
    *cos_q15 = cordic_to_q15(x);
}

static uint32_t sincos_angle; /* fw_sincos_start's angle */

void fw_sincos_start(uint32_t angle)
{
    sincos_angle = angle;
}

void fw_sincos_take(int32_t *sin_q15, int32_t *cos_q15)
{
    fw_sincos_q15(sincos_angle, sin_q15, cos_q15);
}
#endif

/* golden.fixed.sat(x, bits) for 1 <= bits <= 32 of an int64 */
static int64_t sat_bits(int64_t x, int bits)
{
    int64_t hi = ((int64_t)1 << (bits - 1)) - 1;

    return x > hi ? hi : x < -hi - 1 ? -hi - 1 : x;
}

/* sat_bits(c_div(n, d), bits) for d != 0, |n| and |d| < 2^63, 2 <= bits <= 22, without a 64-bit division
 * (libgcc's __divdi3: about 170 clocks on the soft core, and its count-leading-zeros table on the data cache).
 * With a = |n|, b = |d| and L = 2^(bits-1): the truncated quotient's magnitude is floor(a / b), which is >= L
 * exactly when floor(a / L) >= b (one compare: the result saturates). Below that, a < L b: the divisor shifted
 * right by s keeps 32 - bits significant bits, rounded up (bh 2^s >= b), so a >> s < 2^31 and each 32-bit
 * division's digit floor((a >> s) / bh) is at most the true quotient of the remainder; the remainder shrinks
 * by about 2^(31 - bits) per digit (a digit of 0 counts as 1 while the remainder is >= b). tests/test_fw_c.py
 * checks it against golden's expression over random and edge operands. */
int32_t fw_sat_div64(int64_t n, int64_t d, int32_t bits)
{
    const uint64_t lim = (uint64_t)1 << (bits - 1);
    uint64_t a = n < 0 ? 0u - (uint64_t)n : (uint64_t)n, b = d < 0 ? 0u - (uint64_t)d : (uint64_t)d;
    const int neg = (n < 0) != (d < 0);

    if ((a >> (bits - 1)) >= b)                         /* floor(a / lim) */
        return neg ? -(int32_t)lim : (int32_t)(lim - 1u);
    int32_t s = ((b >> 32) ? 32 + bit_length32((uint32_t)(b >> 32)) : bit_length32((uint32_t)b)) - (32 - bits);
    s = s > 0 ? s : 0;
    const uint32_t bh = (uint32_t)(b >> s) + (s > 0 && (b & (((uint64_t)1 << s) - 1u)) ? 1u : 0u);
    uint32_t q = 0;
    while (a >= b) {
        uint32_t digit = (uint32_t)(a >> s) / bh;
        digit = digit ? digit : 1u;
        q += digit;
        a -= (uint64_t)digit * b;
    }
    return neg ? -(int32_t)q : (int32_t)q;
}

/* sat_bits(c_div(n, d), bits) where the 003 observer needs it (d != 0, a constant bits <= 22): the fixed-point unit's
 * DIV on the SoC (rtl/hfi_cfu.v, hfi/cfu.py, in 5 + bits clocks), fw_sat_div64 above in the SoC build without the unit,
 * the unit's model in the host build (fw_fx.h FX_DIV) */
#define SAT_DIV64(n, d, bits)                                                                                          \
    __extension__({                                                                                                    \
        const int64_t sd_n_ = (n), sd_d_ = (d);                                                                        \
        FX_ACC(sd_acc_);                                                                                               \
        FX_SET(sd_acc_, (int32_t)(sd_n_ >> 32), (int32_t)sd_n_);                                                       \
        FX_DIV(sd_acc_, sd_d_, bits);                                                                                  \
    })

/* golden.fixed.round_shr(x, n) of an int64, n >= 1 */
static int64_t round_shr64(int64_t x, int n)
{
    return (x + ((int64_t)1 << (n - 1))) >> n;
}

/* golden.firmware.estimator.inv_park */
static void inv_park(int32_t d, int32_t q, int32_t s, int32_t c, int32_t *al, int32_t *be)
{
    *al = FX_CROSS(d, c, q, s, 15, 32);
    *be = FX_DOT(d, s, q, c, 15, 32);
}

/* golden.firmware.estimator.window_voltage */
STEP_INLINE void window_voltage(const struct fw_outputs *now, const struct fw_outputs *before, int32_t *v_al,
                                int32_t *v_be)
{
    int32_t a1, b1, a0, b0;

    inv_park(now->v_d, now->v_q, now->sin, now->cos, &a1, &b1);
    inv_park(before->v_d, before->v_q, before->sin, before->cos, &a0, &b0);
    *v_al = FX_DOT(3, a1, 1, a0, 2, 0);
    *v_be = FX_DOT(3, b1, 1, b0, 2, 0);
}

void fw_window_voltage(const struct fw_outputs *now, const struct fw_outputs *before, int32_t *v_al, int32_t *v_be)
{
    window_voltage(now, before, v_al, v_be);
}

/* dc_feedforward.dc_feedforward: the voltages times ff_nom / vdc (Q14, vdc clamped to [ff_lo, ff_hi], ff_lo >= 1,
 * ff_nom < 2^16: the quotient's operands below 2^31, k <= 2^30; the products in int64) */
void fw_dc_feedforward(struct fw_outputs *out, uint32_t vdc, int32_t ff_nom, int32_t ff_lo, int32_t ff_hi)
{
    int32_t v = (int64_t)vdc < ff_lo ? ff_lo : (int64_t)vdc > ff_hi ? ff_hi : (int32_t)vdc;
    int64_t k = (int64_t)((((uint32_t)ff_nom << 14) + (uint32_t)(v / 2)) / (uint32_t)v);
    int64_t v_h = (out->v_h * k + (1 << 13)) >> 14;

    out->v_d = (int32_t)sat_bits((out->v_d * k + (1 << 13)) >> 14, 16);
    out->v_q = (int32_t)sat_bits((out->v_q * k + (1 << 13)) >> 14, 16);
    out->v_h = (int32_t)(v_h < 0 ? 0 : v_h < 0x7FFF ? v_h : 0x7FFF); /* V_H: 15 unsigned bits */
}

#ifndef FW_ACC /* the SoC build takes it from hfi_soc_acc (fw_acc.c): same results */
/* golden.firmware.vector.vector_angle: the vectoring CORDIC with the table of fw_sincos_q15. */
void fw_vector_angle(int32_t x, int32_t y, uint32_t *angle, int32_t *mag)
{
    uint32_t z = 0u;

    if (x < 0) {
        x = -x;
        y = -y;
        z = HALF_TURN;
    }
    for (int i = 0; i < FW_CORDIC_ITERATIONS; i++) {
        int32_t xs = x >> i, ys = y >> i;

        if (y > 0) {
            x += ys;
            y -= xs;
            z += (uint32_t)fw_cordic_atan[i];
        } else {
            x -= ys;
            y += xs;
            z -= (uint32_t)fw_cordic_atan[i];
        }
    }
    *angle = z;
    *mag = (int32_t)(((int64_t)x * FW_CORDIC_X0) >> 30);
}

#endif

#ifndef FW_NO_PROBE /* the image without the accelerators has no room for the probe (firmware/Makefile) */
/* golden.fixed.sat(x, 29) */
static int32_t sat_29(int32_t x)
{
    return x < -(1 << 28) ? -(1 << 28) : x > (1 << 28) - 1 ? (1 << 28) - 1 : x;
}

/* golden.firmware.catch_probe.probe_estimate: the rotor's angle at pulse 2's centroid and the back-EMF's advance
 * between the pulses, from the two pulses' offset-free window means */
__attribute__((cold)) int32_t fw_probe_estimate(int32_t d1x, int32_t d1y, int32_t d2x, int32_t d2y, int32_t i_min,
                                                uint32_t *theta, int32_t *delta)
{
    uint32_t a1, a2;
    int32_t m1, m2;

    fw_vector_angle(sat_29(d1x), sat_29(d1y), &a1, &m1); /* the vector angle's range, +-2^28 */
    fw_vector_angle(sat_29(d2x), sat_29(d2y), &a2, &m2);
    int32_t d = (int32_t)(a2 - a1);

    *theta = 0;
    *delta = 0;
    if (m1 < i_min || m2 < i_min || d == 0)
        return 0;
    *theta = a2 + 0x80000000u - (d > 0 ? 0x40000000u : 0xC0000000u); /* HALF_TURN - (+-QUARTER_TURN) */
    *delta = d;
    return 1;
}

/* golden.firmware.catch_probe.probe_angles: delta / G, theta + 5 delta / (3 G), theta + 8 delta / (3 G) (c_div) */
__attribute__((noinline, cold)) void fw_probe_angles(uint32_t theta, int32_t delta, int32_t *omega, uint32_t *theta_a,
                                                     uint32_t *theta_b)
{
    *omega = delta / FW_PROBE_GAP;
    *theta_a = theta + (uint32_t)(int32_t)((int64_t)5 * delta / (3 * FW_PROBE_GAP));
    *theta_b = theta + (uint32_t)(int32_t)((int64_t)8 * delta / (3 * FW_PROBE_GAP));
}
#endif

/* golden.fixed.sat(x, bits) of an int32 for 1 <= bits <= 31 */
static int32_t sat_s32(int32_t x, int bits)
{
    int32_t hi = (int32_t)((1u << (bits - 1)) - 1u);

    return x > hi ? hi : x < -hi - 1 ? -hi - 1 : x;
}

/* golden.firmware.biquad.biquad_step: direct form I, Q28 coefficients, inputs x << Y_FRAC as products
 * (|x| < 2^20, |y| < 2^31: every product below 2^61, the sum of five within int64). */
void fw_biquad_step(struct fw_biquad *s, int32_t x, const struct fw_biquad_coef *c)
{
    const int32_t f = 1 << FW_BIQUAD_Y_FRAC; /* |x| < 2^20: x * f fits int32, every product is 32 x 32 */
    FX_ACC(acc);

    FX_MUL(acc, c->b0, x * f, 0);
    FX_MAC(acc, c->b1, s->x1 * f, 0);
    FX_MAC(acc, c->b2, s->x2 * f, 0);
    FX_MSU(acc, c->a1, s->y1, 0);
    FX_MSU(acc, c->a2, s->y2, 0);
    int32_t y = FX_RND(acc, FW_BIQUAD_COEF_FRAC, 32);

    s->x2 = s->x1;
    s->x1 = x;
    s->y2 = s->y1;
    s->y1 = y;
}

/* golden.firmware.mtpa.mtpa_lookup: i_s clamped to the table's end, then linear interpolation
 * (2 <= len <= FW_MTPA_LEN, s16 values, 0 <= shift <= 20: the product is below 2^37 and its shift fits int32). */
STEP_INLINE void mtpa_lookup(uint32_t i_s, int32_t shift, int32_t len, const int32_t *t_d, const int32_t *t_q,
                             int32_t *i_d, int32_t *i_q)
{
    uint32_t end = (uint32_t)(len - 1) << shift;
    uint32_t x = i_s < end ? i_s : end;
    int32_t k = (int32_t)(x >> shift);

    if (k > len - 2)
        k = len - 2;
    int32_t f = (int32_t)(x - ((uint32_t)k << shift));  /* 0 <= f <= 2^(shift + 1): x <= end < 2^26 */
    *i_d = t_d[k] + (int32_t)shr64((int64_t)(t_d[k + 1] - t_d[k]) * f, shift);
    *i_q = t_q[k] + (int32_t)shr64((int64_t)(t_q[k + 1] - t_q[k]) * f, shift);
}

/* Whether a method's cross-saturation table is filled (main.c refuses it in the image without them, FW_NO_XS). */
int fw_uses_xs_tables(const struct fw_params *p)
{
    return p->sqw.xs_len || p->rot.xs_len || p->cic.xs_len;
}

#ifndef FW_NO_XS /* the image without the accelerators has no room for them (firmware/Makefile) */
/* golden.firmware.mtpa.odd_lookup: sign(i_q) t(|i_q|) of a table over |i_q|, mtpa_lookup's clamp and interpolation
 * (2 <= len <= FW_MTPA_LEN, 0 <= shift <= 20; the table in int16_t for the RAM image's size: the result's magnitude
 * is below 2^15). Out of line: the cross-saturation tables of the sqw_bangbang, rot_bpf and sqw_cic steps, which
 * only a reluctance machine's drive fills. */
static __attribute__((noinline)) int32_t odd_lookup(int32_t i_q, int32_t shift, int32_t len, const int16_t *t)
{
    uint32_t a = i_q < 0 ? 0u - (uint32_t)i_q : (uint32_t)i_q;
    uint32_t end = (uint32_t)(len - 1) << shift;
    uint32_t x = a < end ? a : end;
    int32_t k = (int32_t)(x >> shift);

    if (k > len - 2)
        k = len - 2;
    int32_t f = (int32_t)(x - ((uint32_t)k << shift)); /* as mtpa_lookup */
    int32_t v = t[k] + (int32_t)shr64((int64_t)(t[k + 1] - t[k]) * f, shift);
    return i_q < 0 ? -v : v;
}
#endif

void fw_mtpa_lookup(uint32_t i_s, int32_t shift, int32_t len, const int32_t *t_d, const int32_t *t_q, int32_t *i_d,
                    int32_t *i_q)
{
    mtpa_lookup(i_s, shift, len, t_d, t_q, i_d, i_q);
}

/* golden.firmware.estimator.injection_voltage (v in 0..2^15, Q15 sin/cos: products below 2^32) */
void fw_injection_voltage(int32_t v_now, int32_t v_before, int32_t s, int32_t c, int32_t cd, int32_t sd, int32_t *v_al,
                          int32_t *v_be)
{
    int32_t c_b = FX_DOT(c, cd, s, sd, 15, 0);
    int32_t s_b = FX_CROSS(s, cd, c, sd, 15, 0);

    *v_al = FX_DOT(3 * v_now, c, v_before, c_b, 17, 0);
    *v_be = FX_DOT(3 * v_now, s, v_before, s_b, 17, 0);
}

/* ---- estimator sqw_bangbang (golden.firmware.sqw_bangbang) ------------------------------------------ */

void fw_sqw_step(struct fw_state *st, const struct fw_params *p, const struct fw_meas *m, uint32_t *theta,
                 int32_t *omega)
{
    struct fw_sqw_state *e = &st->sqw;

    if (e->hold > 0) {
        e->hold--;
        e->theta += (uint32_t)e->pll.omega;
    } else {
        /* Benevieri et al. 2023, Fig. 1: bang-bang on gamma, integrated to theta_hat; PLL -> speed; gamma less the
         * response the machine's cross-saturation gives on the d-axis (golden cross_saturation_gamma) */
        int32_t gamma = m->win->gamma;
#ifndef FW_NO_XS
        if (p->sqw.xs_len)
            gamma = sat32((int64_t)gamma - odd_lookup(m->i_q, p->sqw.xs_shift, p->sqw.xs_len, p->sqw.xs_gamma));
#endif
        e->theta = fw_bangbang_step(e->theta, gamma, p->sqw.k_bb);
    }
    fw_pll_step(&e->pll, e->theta, p->sqw.pll_kp, p->sqw.pll_ki);
    e->omega = e->pll.omega;
    *theta = e->theta;
    *omega = e->omega;
}

void fw_sqw_turn(struct fw_state *st, uint32_t delta)
{
    st->sqw.theta += delta;
    st->sqw.pll.theta += delta;
}

void fw_sqw_sync(struct fw_state *st, const struct fw_params *p, uint32_t theta, int32_t omega)
{
    struct fw_sqw_state *e = &st->sqw;

    (void)p;
    e->theta = theta;
    e->pll.theta = theta + (uint32_t)omega;
    e->pll.integ = (int64_t)omega * 16777216; /* omega << 24 */
    e->pll.omega = omega;
    e->omega = omega;
    e->hold = FW_SQW_SYNC_HOLD;
}

int32_t fw_sqw_i_d(const struct fw_params *p)
{
    return p->sqw.i_d;
}

/* ---- estimator rfo (golden.firmware.rfo) ------------------------------------------------------------ */

/* golden.firmware.rfo step 5: clamp(c_div((psi_f - mag) << 16, max(mag, 1)), -Q_LIMIT, Q_LIMIT), bit for
 * bit, without a 64-bit division (libgcc's __divdi3 was a tenth of the control step on the soft core and
 * a kilobyte of its instruction cache). With a = |psi_f - mag| and den = max(mag, 1), the truncated
 * quotient's magnitude is floor(a 2^16 / den) = (a / den) 2^16 + floor((a % den) 2^16 / den): the integer
 * part by the 32-bit divider (beyond Q_LIMIT >> 16 the result is clamped anyway), the 16 fraction bits by
 * restoring division (remainder < den < 2^31, so its double fits 32 bits). psi_f >= 0 (rfo_params) and
 * mag >= 0 (a magnitude) keep psi_f - mag in int32; a negative mag takes the 64-bit path. */
int32_t fw_rfo_correction(int32_t psi_f, int32_t mag)
{
    const uint32_t limit = (uint32_t)FW_RFO_Q_LIMIT;
    if (mag < 0 || psi_f < 0) {
        int64_t q = ((int64_t)psi_f - mag) * 65536 / (mag > 0 ? mag : 1);
        return (int32_t)(q > FW_RFO_Q_LIMIT ? FW_RFO_Q_LIMIT : q < -FW_RFO_Q_LIMIT ? -FW_RFO_Q_LIMIT : q);
    }
    int32_t d = psi_f - mag;
    uint32_t a = d < 0 ? 0u - (uint32_t)d : (uint32_t)d;
    uint32_t den = mag > 0 ? (uint32_t)mag : 1u;
    uint32_t hi = a / den;
    uint32_t q;
    if (hi > (limit >> 16)) {
        q = limit;
    } else {
        uint32_t r = a - hi * den, frac = 0;
        for (int i = 0; i < 16; i++) {
            r <<= 1;
            frac <<= 1;
            if (r >= den) {
                r -= den;
                frac |= 1u;
            }
        }
        q = (hi << 16) | frac;
        q = q > limit ? limit : q;
    }
    return d < 0 ? -(int32_t)q : (int32_t)q;
}

/* golden.firmware.rfo.active_flux: psi_f + (L_d - L_q) i_d [flux LSB] within 1..2^27 */
static inline int32_t rfo_active_flux(const struct fw_rfo_params *rp, int32_t i_d)
{
    int64_t a = rp->psi_f + (((int64_t)rp->l_dq * i_d) >> 16);
    return a < 1 ? 1 : a > FW_RFO_A_MAX ? FW_RFO_A_MAX : (int32_t)a;
}

void fw_rfo_step(struct fw_state *st, const struct fw_params *p, const struct fw_meas *m, uint32_t *theta,
                 int32_t *omega)
{
    struct fw_rfo_state *e = &st->rfo;
    const struct fw_rfo_params *rp = &p->rfo;
    int32_t i_al, i_be;
    uint32_t ang;
    int32_t mag;

    inv_park(m->i_d, m->i_q, m->sin, m->cos, &i_al, &i_be);
    e->i_al = i_al;
    e->i_be = i_be;
    int64_t dx_al = (int64_t)m->v_al * (1 << FW_RFO_FLUX_FRAC) - (((int64_t)rp->r_s * i_al) >> (16 - FW_RFO_FLUX_FRAC));
    int64_t dx_be = (int64_t)m->v_be * (1 << FW_RFO_FLUX_FRAC) - (((int64_t)rp->r_s * i_be) >> (16 - FW_RFO_FLUX_FRAC));
    int32_t eta_al = (int32_t)sat_bits(e->x_al + (dx_al >> 1) - (((int64_t)rp->l_s * i_al) >> 16), 29);
    int32_t eta_be = (int32_t)sat_bits(e->x_be + (dx_be >> 1) - (((int64_t)rp->l_s * i_be) >> 16), 29);
    fw_vector_angle(eta_al, eta_be, &ang, &mag);
    e->mag = mag;
    /* Ortega et al. 2011: correction along eta towards |eta| = A (normalised gradient), A the active flux */
    /* the correction rate follows the speed: k_r |w_i| >> 32 within [k_min, k_c] (w_i: the PLL integrator's
       speed of the previous period) */
    int64_t w_i = sat32(e->pll.integ >> 24);
    int64_t k = ((w_i < 0 ? -w_i : w_i) * rp->k_r) >> 32;
    k = k < rp->k_min ? rp->k_min : k;
    k = k > rp->k_c ? rp->k_c : k;                      /* the ceiling wins (golden: min(max(k, k_min), k_c)) */
    if (!e->synced)                                     /* acquiring: the fastest correction */
        k = rp->k_c;
    e->a_mag = rfo_active_flux(rp, m->i_d);
    int64_t g = (k * fw_rfo_correction(e->a_mag, mag)) >> 16;
    e->x_al = (int32_t)sat_bits(e->x_al + dx_al + (((int64_t)eta_al * g) >> 16), 32);
    e->x_be = (int32_t)sat_bits(e->x_be + dx_be + (((int64_t)eta_be * g) >> 16), 32);
    fw_pll_step(&e->pll, ang, rp->pll_kp, rp->pll_ki);
    e->omega = e->pll.omega;
    e->theta = ang + 2u * (uint32_t)sat32(e->pll.integ >> 24);   /* advanced by the integrator's speed */
    *theta = e->theta;
    *omega = e->omega;
}

void fw_rfo_turn(struct fw_state *st, uint32_t delta)
{
    struct fw_rfo_state *e = &st->rfo;
    int32_t s, c;

    fw_sincos_q15(delta, &s, &c);
    int32_t x_al = FX_CROSS(e->x_al, c, e->x_be, s, 15, 32);
    int32_t x_be = FX_DOT(e->x_al, s, e->x_be, c, 15, 32);
    e->x_al = x_al;
    e->x_be = x_be;
    e->pll.theta += delta;
    e->theta += delta;
}

void fw_rfo_sync(struct fw_state *st, const struct fw_params *p, uint32_t theta, int32_t omega)
{
    struct fw_rfo_state *e = &st->rfo;
    uint32_t mid = theta - 2u * (uint32_t)omega;
    int32_t s, c;

    fw_sincos_q15(mid, &s, &c);
    e->x_al = (int32_t)sat_bits(round_shr64((int64_t)e->a_mag * c, 15) + (((int64_t)p->rfo.l_s * e->i_al) >> 16), 32);
    e->x_be = (int32_t)sat_bits(round_shr64((int64_t)e->a_mag * s, 15) + (((int64_t)p->rfo.l_s * e->i_be) >> 16), 32);
    e->pll.theta = mid + (uint32_t)omega;
    e->pll.integ = (int64_t)omega * 16777216;
    e->pll.omega = omega;
    e->theta = theta;
    e->omega = omega;
    e->synced = 1;
}

int32_t fw_rfo_i_d(const struct fw_params *p)
{
    return p->rfo.i_d;
}

/* ---- the motion observer (golden.firmware.motion), shared by rot_bpf and sqw_cic ------------------------- */

/* golden.fixed.sat(a + b, 64) of int64 a, b: on overflow both have the sign of b. */
static int64_t sat_add64(int64_t a, int64_t b)
{
    int64_t s;

    if (__builtin_add_overflow(a, b, &s))
        s = b < 0 ? INT64_MIN : INT64_MAX;
    return s;
}

/* golden.fixed.sat(a + b + c, 64) of the exact sum of int64 a, b, c (|a + b + c| < 3 2^63): each of the
 * two wrapping adds is off by +-2^64 when it overflows (the sign of its second operand); with k such
 * wraps in all the wrapped result t is the exact sum - k 2^64, so k > 0 means above INT64_MAX, k < 0
 * below INT64_MIN, k = 0 that t is the exact sum. */
static int64_t sat_add3_64(int64_t a, int64_t b, int64_t c)
{
    int64_t s, t;
    int k = 0;

    if (__builtin_add_overflow(a, b, &s))
        k += b < 0 ? -1 : 1;
    if (__builtin_add_overflow(s, c, &t))
        k += c < 0 ? -1 : 1;
    return k > 0 ? INT64_MAX : k < 0 ? INT64_MIN : t;
}

/* golden.firmware.motion.motion_step: the motion observer (Xue et al. 2022, eqs. (9)-(12); poles at -a) with
 * the torque feed-forward, shared by sqw_cic and rot_bpf; the same operations in the same order. Ranges:
 * struct fw_cic_params (control.h): |c_t i_q| <= 2^61, |c_r i_d i_q| <= 2^62 after the s16 saturation, so
 * |c2 e + ff| < 2^63. */
static void fw_motion_step(uint32_t *theta_o, int64_t *w, int64_t *z, int32_t *omega, int32_t err, int32_t i_d_mean,
                           int32_t i_q_mean, int32_t c1, int32_t c2, int32_t c3, int64_t c_t, int64_t c_r)
{
    err = opaque_s32(err); /* opaque_s32: the products below as 32 x 32 (speed, no value change) */
    int32_t i_d = opaque_s32(sat16(i_d_mean)), i_q = opaque_s32(sat16(i_q_mean));
    int64_t ff = c_t * i_q + ((c_r * (i_d * i_q)) >> 16); /* n_p T_e / J: the torque feed-forward */
    *z = sat_add64(*z, (int64_t)c1 * err);
    *w = sat_add3_64(*w, *z, (int64_t)c2 * err + ff);
    *omega = sat32(*w >> FW_MOTION_Q_W);
    *theta_o += (uint32_t)*omega + (uint32_t)(((int64_t)c3 * err) >> 16);
}

/* ---- estimator rot_bpf (golden.firmware.rot_bpf; Tap et al. 2023, Sec. II-B..E) ------------------------ */

void fw_rot_step(struct fw_state *st, const struct fw_params *p, const struct fw_meas *m, uint32_t *theta,
                 int32_t *omega)
{
    struct fw_rot_state *e = &st->rot;
    const struct fw_rot_params *rp = &p->rot;
    int32_t i_al, i_be;
    uint32_t psi;

    inv_park(m->i_d, m->i_q, m->sin, m->cos, &i_al, &i_be);
    int32_t c = FX_CROSS(m->inj_cos, rp->q_cos, m->inj_sin, rp->q_sin, 15, 0); /* INJ_PHASE - INJ_STEP/4 */
    int32_t s = FX_DOT(m->inj_sin, rp->q_cos, m->inj_cos, rp->q_sin, 15, 0);
    int32_t x_d = FX_DOT(i_al, c, i_be, s, 15, FW_ROT_X_BITS); /* eq. (12) */
    int32_t x_q = FX_CROSS(i_be, c, i_al, s, 15, FW_ROT_X_BITS);
    fw_biquad_step(&e->bd, x_d, &rp->bpf); /* eq. (13) */
    fw_biquad_step(&e->bq, x_q, &rp->bpf);
    int32_t y_d = e->bd.y1, y_q = e->bq.y1;
    int32_t s2 = FX_PROD(2 * s, c, 15, 0), c2 = FX_CROSS(c, c, s, s, 15, 0); /* |s|, |c| <= 2^15 */
    int32_t z_d = FX_CROSS(y_d, c2, y_q, s2, 15, FW_ROT_Z_BITS); /* eq. (15) */
    int32_t z_q = FX_DOT(y_d, s2, y_q, c2, 15, FW_ROT_Z_BITS);
    int32_t k = e->idx; /* eq. (16): moving sum */
    e->sum_d += z_d - e->buf_d[k];
    e->sum_q += z_q - e->buf_q[k];
    e->buf_d[k] = z_d;
    e->buf_q[k] = z_q;
    e->idx = k + 1 < rp->n_avg ? k + 1 : 0;
    fw_vector_angle((int32_t)sat_bits(e->sum_d, 29), (int32_t)sat_bits(e->sum_q, 29), &psi, &e->mag);
    int observer = rp->tracking == FW_ROT_TRACK_OBSERVER;
    uint32_t tracked = observer ? e->theta_o : e->pll.theta;
    if (e->hold > 0) {
        e->hold--;
        e->err = 0;
    } else { /* eq. (17), normalised; psi less the cross-saturation's turn (golden cross_saturation_turn) */
#ifndef FW_NO_XS
        uint32_t xs = rp->xs_len ? (uint32_t)odd_lookup(m->i_q, rp->xs_shift, rp->xs_len, rp->xs_angle) << 16 : 0u;
#else
        const uint32_t xs = 0u;
#endif
        e->err = (int32_t)(psi - rp->offset - xs - 2u * tracked) >> 1;
    }
    if (observer) {
        fw_motion_step(&e->theta_o, &e->w, &e->z, &e->omega, e->err, m->i_d, m->i_q, rp->c1, rp->c2, rp->c3, rp->c_t,
                       rp->c_r);
        tracked = e->theta_o;
    } else {
        fw_pll_step(&e->pll, e->pll.theta + (uint32_t)e->err, rp->pll_kp, rp->pll_ki);
        e->omega = e->pll.omega;
        tracked = e->pll.theta;
    }
    e->theta = tracked + (uint32_t)FX_SHR(e->omega, rp->k_delay, 16, 0); /* eqs. (18)-(19) */
    *theta = e->theta;
    *omega = e->omega;
}

void fw_rot_turn(struct fw_state *st, uint32_t delta)
{
    st->rot.pll.theta += delta;
    st->rot.theta_o += delta;
    st->rot.theta += delta;
}

void fw_rot_sync(struct fw_state *st, const struct fw_params *p, uint32_t theta, int32_t omega)
{
    struct fw_rot_state *e = &st->rot;

    memset(e, 0, sizeof *e); /* in place: a static zero copy lands wherever the code's size puts it in the data cache */
    e->pll.theta = theta - (uint32_t)(((int64_t)omega * p->rot.k_delay) >> 16);
    e->pll.integ = (int64_t)omega * 16777216;
    e->pll.omega = omega;
    e->theta_o = e->pll.theta; /* golden.firmware.motion.motion_sync */
    e->w = (int64_t)omega * 16777216;
    e->theta = theta;
    e->omega = omega;
    e->hold = p->rot.n_hold;
}

/* golden.firmware.rot_bpf.RotatingBpf.i_d: estimator.rot_bpf.i_d_min (0, Tap et al. 2023's, on a magnet motor) */
int32_t fw_rot_i_d(const struct fw_params *p)
{
    return p->rot.i_d;
}

/* ---- estimator eemf_smo (golden.firmware.eemf_smo; Tap et al. 2023, Sec. II-F) ---------------------------- */

/* min(max(x, -lim), lim), lim >= 0 (golden.firmware.eemf_smo._clamp) */
static int32_t clamp_z(int32_t x, int32_t lim)
{
    return x > lim ? lim : x < -lim ? -lim : x;
}

void fw_smo_step(struct fw_state *st, const struct fw_params *p, const struct fw_meas *m, uint32_t *theta,
                 int32_t *omega)
{
    struct fw_smo_state *e = &st->smo;
    const struct fw_smo_params *sp = &p->smo;
    int32_t i_al, i_be;
    uint32_t ang;

    inv_park(m->i_d, m->i_q, m->sin, m->cos, &i_al, &i_be);
    FX_ACC(acc);
    FX_MUL(acc, e->ih_al, 1, 0);
    FX_MSU(acc, i_al, 1 << FW_SMO_I_FRAC, 0);
    int32_t eps_al = FX_FLR(acc, 0, 32);
    FX_MUL(acc, e->ih_be, 1, 0);
    FX_MSU(acc, i_be, 1 << FW_SMO_I_FRAC, 0);
    int32_t eps_be = FX_FLR(acc, 0, 32);
    /* clamp_z of the int64 product shifted: the same on its int32 saturation (z_max < 2^31) */
    int32_t z_al = clamp_z(FX_SHR(eps_al, sp->k_lin, 16, 32), sp->z_max);
    int32_t z_be = clamp_z(FX_SHR(eps_be, sp->k_lin, 16, 32), sp->z_max);
    int32_t g = FX_SHR(e->pll.omega, sp->c_x, 32, 0); /* |g| < 2^23 */
    FX_MUL(acc, m->v_al, 1, 0);
    FX_MSU(acc, z_al, 1, 0);
    int32_t u_al = FX_FLR(acc, 0, 32);
    FX_MUL(acc, m->v_be, 1, 0);
    FX_MSU(acc, z_be, 1, 0);
    int32_t u_be = FX_FLR(acc, 0, 32);
    /* Tap et al. 2023, eq. (20) in the plant's frame with L_o, driven by the sliding-mode term z; with the old
     * i_hat: ih + shr(c_v u, 8) - shr(c_r ih, 16) -+ shr(g ih_other, 16), saturated to s32 */
    FX_MUL(acc, sp->c_v, u_al, 16 - FW_SMO_I_FRAC);
    FX_MSU(acc, sp->c_r, e->ih_al, 16);
    FX_MSU(acc, g, e->ih_be, 16);
    FX_ADD(acc, e->ih_al, 0, 0);
    int32_t ih_al = FX_FLR(acc, 0, 32);
    FX_MUL(acc, sp->c_v, u_be, 16 - FW_SMO_I_FRAC);
    FX_MSU(acc, sp->c_r, e->ih_be, 16);
    FX_MAC(acc, g, e->ih_al, 16);
    FX_ADD(acc, e->ih_be, 0, 0);
    e->ih_be = FX_FLR(acc, 0, 32);
    e->ih_al = ih_al;
    int64_t w_i = e->pll.integ >> 24;
    int64_t a = ((w_i < 0 ? -w_i : w_i) * sp->c_a) >> 24;
    a = a < sp->a_min ? sp->a_min : a;
    a = a > sp->a_max ? sp->a_max : a;
    /* |z << 8| < 2^23 and e_f stays between its old value and z << 8: the difference fits int32 */
    e->ef_al += FX_SHR((int32_t)a, z_al * (1 << FW_SMO_I_FRAC) - e->ef_al, 16, 0);
    e->ef_be += FX_SHR((int32_t)a, z_be * (1 << FW_SMO_I_FRAC) - e->ef_be, 16, 0);
    fw_vector_angle((int32_t)sat_bits(e->ef_al, 29), (int32_t)sat_bits(e->ef_be, 29), &ang, &e->mag); /* eq. (22) */
    if (e->mag < sp->e_min)
        ang = e->pll.theta;
    fw_pll_step(&e->pll, ang, sp->pll_kp, sp->pll_ki);
    e->omega = e->pll.omega;
    if (w_i > sp->w_dir)
        e->dir = 1;
    else if (w_i < -(int64_t)sp->w_dir)
        e->dir = -1;
    uint32_t lead = e->dir > 0 ? sp->lag0 - FW_SMO_QUARTER : FW_SMO_QUARTER - sp->lag0;
    e->theta = e->pll.theta + lead + (uint32_t)FX_SHR(e->omega, sp->k_delay, 16, 0);
    *theta = e->theta;
    *omega = e->omega;
}

void fw_smo_turn(struct fw_state *st, uint32_t delta)
{
    st->smo.pll.theta += delta;
    st->smo.theta += delta;
}

void fw_smo_sync(struct fw_state *st, const struct fw_params *p, uint32_t theta, int32_t omega)
{
    struct fw_smo_state *e = &st->smo;

    e->dir = omega < 0 ? -1 : 1;
    uint32_t lead = e->dir > 0 ? p->smo.lag0 - FW_SMO_QUARTER : FW_SMO_QUARTER - p->smo.lag0;
    e->pll.theta = theta - lead - (uint32_t)(((int64_t)omega * p->smo.k_delay) >> 16);
    e->pll.integ = (int64_t)omega * 16777216;
    e->pll.omega = omega;
    e->theta = theta;
    e->omega = omega;
}

int32_t fw_smo_i_d(const struct fw_params *p)
{
    return p->smo.i_d;
}

/* ---- estimator sqw_cic (golden.firmware.sqw_cic; Xue et al. 2022, Sec. 3, Figs. 2 and 10) -------------- */

/* golden.firmware.sqw_cic.SquareWaveCic.step (Xue et al. 2022): the angle of the CIC-interpolated
 * quadrature signal (eq. (6)), the quadrature PLL's error scaled to slope 1 (Fig. 10), the Luenberger
 * observer with the torque feed-forward (eqs. (9)-(12)), the delay compensation; the same operations in
 * the same order. Ranges: struct fw_cic_params (control.h); |i_d i_q| <= 2^30 after the s16 saturation. */
void fw_cic_step(struct fw_state *st, const struct fw_params *p, const struct fw_meas *m, uint32_t *theta,
                 int32_t *omega)
{
    struct fw_cic_state *e = &st->cic;
    const struct fw_cic_params *cp = &p->cic;
    uint32_t psi;
    int32_t err;

    fw_vector_angle(sat_s32(m->win->cic_qa, 29), sat_s32(m->win->cic_qb, 29), &psi, &e->mag);
    if (e->hold > 0) {
        e->hold--;
        err = 0;
    } else if (e->mag < cp->q_min) {
        err = 0;
    } else { /* Fig. 10, scaled to slope 1; psi less the cross-saturation's angle (golden mtpa.odd_lookup) */
#ifndef FW_NO_XS
        uint32_t xs = cp->xs_len ? (uint32_t)odd_lookup(m->i_q, cp->xs_shift, cp->xs_len, cp->xs_angle) << 16 : 0u;
#else
        const uint32_t xs = 0u;
#endif
        err = sat32(((int64_t)cp->g * (int32_t)(psi - xs - e->theta_o)) >> 16);
    }
    e->err = err;
    fw_motion_step(&e->theta_o, &e->w, &e->z, &e->omega, err, m->i_d, m->i_q, cp->c1, cp->c2, cp->c3, cp->c_t,
                   cp->c_r); /* eqs. (9)-(12): poles at -a, torque feed-forward */
    e->theta = e->theta_o + (uint32_t)(((int64_t)e->omega * cp->k_delay) >> 16);
    *theta = e->theta;
    *omega = e->omega;
}

/* golden.firmware.sqw_cic.SquareWaveCic.turn (Xue et al. 2022): both angles turned by delta. */
void fw_cic_turn(struct fw_state *st, uint32_t delta)
{
    st->cic.theta_o += delta;
    st->cic.theta += delta;
}

/* golden.firmware.sqw_cic.SquareWaveCic.sync (Xue et al. 2022): the observer continues from theta at omega
 * (z = 0) and ignores the error for n_hold periods. */
void fw_cic_sync(struct fw_state *st, const struct fw_params *p, uint32_t theta, int32_t omega)
{
    struct fw_cic_state *e = &st->cic;

    e->theta_o = theta - (uint32_t)(((int64_t)omega * p->cic.k_delay) >> 16);
    e->w = (int64_t)omega * 16777216; /* omega << 24 */
    e->z = 0;
    e->hold = p->cic.n_hold;
    e->theta = theta;
    e->omega = omega;
}

/* golden.firmware.sqw_cic.SquareWaveCic.i_d: estimator.sqw_cic.i_d_min (0, Xue et al. 2022's, on a magnet motor) */
int32_t fw_cic_i_d(const struct fw_params *p)
{
    return p->cic.i_d;
}

/* ---- the 003 method: state voltages, flux LUT, applied flux, hfo_proj, fcs_mpc ---------------------- */

/* -2^n <= x < 2^n (1 <= n <= 31): x fits the fixed-point unit's int32 operands with room (its usual case) */
static inline int fits_bits64(int64_t x, int n)
{
    const int32_t lo = (int32_t)x, hi = (int32_t)((uint64_t)x >> 32);

    return hi == lo >> 31 && (uint32_t)lo + (1u << n) < (2u << n); /* the high word only the low word's sign */
}

/* golden.firmware.hfo_proj.projection_coefficients (eqs. (28)-(30), corrected): the normalised inductances
 * below 2^20 in magnitude (the table's l_shift brings the inductance tables below 2^15), so they are int32 values
 * and every product and the numerators shifted by 12 are below 2^57. */
static int64_t shr_any64(int64_t x, int32_t n);
void fw_projection_coefficients(const struct fw_lut_point *pt, int32_t l_shift, int32_t *a1, int32_t *a2)
{
    const int32_t ld = (int32_t)shr_any64(pt->l_d, l_shift), lq = (int32_t)shr_any64(pt->l_q, l_shift);
    const int32_t ldq = (int32_t)shr_any64(pt->l_dq, l_shift), dld = (int32_t)shr_any64(pt->dl_d, l_shift);
    const int32_t dldq = (int32_t)shr_any64(pt->dl_dq, l_shift);
    const int64_t det = (int64_t)ld * lq - (int64_t)ldq * ldq;

    if (det <= 0) {
        *a1 = *a2 = 0;
        return;
    }
    /* on the unit: each product of two of the values (below 2^20, above) times 4096 as the product of both shifted
     * by 6 (each factor below 2^27), the numerator in the accumulator divided there */
    const int32_t d6 = ld * 64, q6 = lq * 64, x6 = ldq * 64, dd6 = dld * 64, dx6 = dldq * 64;
    FX_ACC(acc);

    FX_MUL(acc, d6, d6 - q6, 0);
    FX_MAC(acc, 2 * x6, x6, 0);
    FX_MAC(acc, dd6, x6, 0);
    FX_MSU(acc, dx6, d6, 0);
    *a1 = FX_DIV(acc, det, 16);
    FX_MUL(acc, x6, d6 + q6, 0);
    FX_MAC(acc, dd6, q6, 0);
    FX_MSU(acc, dx6, x6, 0);
    *a2 = FX_DIV(acc, det, 16);
}

/* golden.fixed.shr(x, n) of an int64 for any n >= 0 (n >= 63: the sign) */
static int64_t shr_any64(int64_t x, int32_t n)
{
    return n >= 63 ? (x < 0 ? -1 : 0) : x >> n;
}

/* golden.firmware.estimator.park of int64 components (|a|, |b| < 2^46: the products below 2^62), in int64 */
static __attribute__((noinline)) void park64_wide(int64_t a, int64_t b, int32_t s, int32_t c, int64_t *d, int64_t *q)
{
    *d = round_shr64(a * c + b * s, 15);
    *q = round_shr64(b * c - a * s, 15);
}

/* park64_wide, inlined for the usual case -2^29 <= a, b < 2^29 on the fixed-point unit: |a c| + |b s| <= 2^45
 * (|s|, |c| <= 2^15), so the rounded sums are within 2^30 and its 32-bit saturation never acts */
STEP_INLINE void park64(int64_t a, int64_t b, int32_t s, int32_t c, int64_t *d, int64_t *q)
{
    if (FX_USUAL && fits_bits64(a, 29) && fits_bits64(b, 29)) {
        *d = FX_DOT((int32_t)a, c, (int32_t)b, s, 15, 32);
        *q = FX_CROSS((int32_t)b, c, (int32_t)a, s, 15, 32);
    } else {
        park64_wide(a, b, s, c, d, q);
    }
}

/* golden.firmware.estimator.inv_park of int64 components (saturated to s32 as golden), in int64 */
static __attribute__((noinline)) void inv_park64_wide(int64_t d, int64_t q, int32_t s, int32_t c, int32_t *al,
                                                      int32_t *be)
{
    *al = sat32(round_shr64(d * c - q * s, 15));
    *be = sat32(round_shr64(d * s + q * c, 15));
}

/* inv_park64_wide, inlined: inv_park (the fixed-point unit's) when both components fit in int32 */
STEP_INLINE void inv_park64(int64_t d, int64_t q, int32_t s, int32_t c, int32_t *al, int32_t *be)
{
    if (FX_USUAL && (int32_t)d == d && (int32_t)q == q)
        inv_park((int32_t)d, (int32_t)q, s, c, al, be);
    else
        inv_park64_wide(d, q, s, c, al, be);
}

static int64_t abs64(int64_t x)
{
    return x < 0 ? -x : x;
}

/* golden.fpga.fcs_mpc.state_voltage by state 0..7 (bit 0 = phase a): VX, VY of the active states 001, 011,
 * 010, 110, 100, 101 ((2/3) 2^15 (cos, sin)(60 deg j), j = 0..5), 0 for 000 and 111 */
static const int32_t state_vx[8] STEP_TABLE = {0, 21845, -10923, 10923, -10923, 10923, -21845, 0};
static const int32_t state_vy[8] STEP_TABLE = {0, 0, 18919, 18919, -18919, -18919, 0, 0};

void fw_state_voltage(int32_t state, int32_t *v_al, int32_t *v_be)
{
    *v_al = state_vx[state & 7];
    *v_be = state_vy[state & 7];
}

/* golden.firmware.flux_lut.warp (x >= 0) */
int32_t fw_warp(int32_t x, int32_t knee, int32_t coarse)
{
    return x < knee ? x : knee + ((x - knee) >> coarse);
}

#ifndef FW_ACC
/* golden.firmware.flux_lut._cell: the first corner's index and the fractions */
static void lut_cell(const struct fw_flux_lut *lut, int32_t i_d, int32_t i_q, int32_t *k, int64_t *fx, int64_t *fy)
{
    int32_t s = lut->shift;
    int32_t x = fw_warp(i_d < 0 ? -i_d : i_d, lut->knee, lut->coarse);
    int32_t y = fw_warp(i_q < 0 ? -i_q : i_q, lut->knee, lut->coarse);
    int32_t c = x >> s, r = y >> s;

    if (c > lut->n_d - 2)
        c = lut->n_d - 2;
    if (r > lut->n_q - 2)
        r = lut->n_q - 2;
    *k = r * lut->n_d + c;
    *fx = (int64_t)x - ((int64_t)c << s);
    *fy = (int64_t)y - ((int64_t)r << s);
}

/* golden.firmware.flux_lut._bilinear of the corners t00, t01, t10, t11 */
static int64_t bilinear64(int64_t t00, int64_t t01, int64_t t10, int64_t t11, int64_t fx, int64_t fy, int32_t s)
{
    int64_t a = t00 + (((t01 - t00) * fx) >> s);
    int64_t b = t10 + (((t11 - t10) * fx) >> s);

    return a + (((b - a) * fy) >> s);
}

/* golden.firmware.flux_lut._bilinear of an inductance table t (s32) at the cell k */
static int64_t lut_bilinear(const int32_t *t, int32_t k, int32_t n, int64_t fx, int64_t fy, int32_t s)
{
    return bilinear64(t[k], t[k + 1], t[k + n], t[k + n + 1], fx, fy, s);
}

/* a flux table t (s16, units of 2^f_shift flux units) at the cell k, in flux units: the interpolation
 * shifted left by f_shift (golden's << of a negative int: a product) */
static int64_t lut_bilinear_flux(const int16_t *t, int32_t k, int32_t n, int64_t fx, int64_t fy, int32_t s,
                                 int32_t f_shift)
{
    return bilinear64(t[k], t[k + 1], t[k + n], t[k + n + 1], fx, fy, s) * ((int64_t)1 << f_shift);
}

_Static_assert(sizeof(((struct fw_flux_lut *)0)->t_d) / sizeof(int16_t) == FW_LUT_MAX_POINTS,
               "control.h's flux tables hold golden.firmware.flux_lut.LUT_MAX_POINTS entries");
_Static_assert(sizeof(((struct fw_flux_lut *)0)->t_ld) / sizeof(int32_t) == FW_LUT_MAX_POINTS,
               "control.h's inductance tables hold golden.firmware.flux_lut.LUT_MAX_POINTS entries");

/* golden.firmware.flux_lut.lut_flux */
void fw_lut_flux(const struct fw_flux_lut *lut, int32_t i_d, int32_t i_q, int64_t *lam_d, int64_t *lam_q)
{
    int32_t k;
    int64_t fx, fy;

    lut_cell(lut, i_d, i_q, &k, &fx, &fy);
    int64_t d = lut_bilinear_flux(lut->t_d, k, lut->n_d, fx, fy, lut->shift, lut->f_shift);
    int64_t q = lut_bilinear_flux(lut->t_q, k, lut->n_d, fx, fy, lut->shift, lut->f_shift);
    *lam_d = i_d < 0 ? -d : d;
    *lam_q = i_q < 0 ? -q : q;
}

/* golden.firmware.flux_lut.lut_point */
void fw_lut_point(const struct fw_flux_lut *lut, int32_t i_d, int32_t i_q, struct fw_lut_point *pt)
{
    int32_t k, n = lut->n_d, s = lut->shift;
    int64_t fx, fy, one = (int64_t)1 << s;

    lut_cell(lut, i_d, i_q, &k, &fx, &fy);
    int64_t lam_d = lut_bilinear_flux(lut->t_d, k, n, fx, fy, s, lut->f_shift);
    int64_t lam_q = lut_bilinear_flux(lut->t_q, k, n, fx, fy, s, lut->f_shift);
    fx = fx < one ? fx : one;
    fy = fy < one ? fy : one;
    int64_t l_d = lut_bilinear(lut->t_ld, k, n, fx, fy, s);
    int64_t l_q = lut_bilinear(lut->t_lq, k, n, fx, fy, s);
    int64_t l_dq = lut_bilinear(lut->t_ldq, k, n, fx, fy, s);
    int64_t w = (int64_t)1 << lut->coarse;
    int64_t wx = (i_d < 0 ? -(int64_t)i_d : i_d) < lut->knee ? w : 1;
    int64_t wy = (i_q < 0 ? -(int64_t)i_q : i_q) < lut->knee ? w : 1;
    int64_t sd = i_d < 0 ? -1 : 1, sq = i_q < 0 ? -1 : 1;
    const int32_t *tabs[3] = {lut->t_ld, lut->t_lq, lut->t_ldq};
    int64_t gx[3], gy[3];
    for (int j = 0; j < 3; j++) {
        const int32_t *t = tabs[j];
        int64_t t00 = t[k], t01 = t[k + 1], t10 = t[k + n], t11 = t[k + n + 1];

        gx[j] = ((t01 - t00) * (one - fy) + (t11 - t10) * fy) * wx;
        gy[j] = ((t10 - t00) * (one - fx) + (t11 - t01) * fx) * wy;
    }
    int64_t id = i_d, iq = i_q, aid = i_d < 0 ? -id : id, aiq = i_q < 0 ? -iq : iq;
    pt->dl_d = (-iq * sd * gx[0] + id * sq * gy[0]) >> (2 * s + lut->coarse);
    pt->dl_q = (-iq * sd * gx[1] + id * sq * gy[1]) >> (2 * s + lut->coarse);
    pt->dl_dq = (-aiq * gx[2] + aid * gy[2]) >> (2 * s + lut->coarse);
    pt->lam_d = sd * lam_d;
    pt->lam_q = sq * lam_q;
    pt->l_d = l_d;
    pt->l_q = l_q;
    pt->l_dq = sd * sq * l_dq;
}
#endif

/* golden.firmware.applied_flux.applied_flux, split in what depends on the currents (once per instant) and on the
 * states. A phase's e_x = (-ds dt_f if ds sg_x > 0) - sg_x vth_f (ds its switch's change, sg_x its current's sign)
 * is -sg_x (vth_f + bit_x dt_f), bit_x = 1 when it switched in the current's direction (turned on for sg_x > 0, off
 * for sg_x < 0). The flux sums c . e (c = 10923 (2, -1, -1) for alpha, 18919 (0, 1, -1) for beta) are therefore
 * a vth_f + b dt_f, a = sum c_x (-sg_x) from the signs alone, b = the sum of w_x = c_x (-sg_x) over the phases that
 * switched in their current's direction: no multiply and no branch on the data per state pair. */
struct phase_flux {
    int32_t a_al, a_be;       /* |a| <= 4 10923: a vth_f, b dt_f below 2^44 */
    int32_t w_al[3], w_be[3]; /* w_be[0] = 0 */
    int32_t pos, neg;         /* the phases whose current is positive, negative (bit x = phase x) */
};

/* the phases' current signs, of i_a, of 56756 i_be - 32768 i_al (i_b) and of -32768 i_al - 56756 i_be (i_c) (the
 * exact products' signs from their int32 saturation, which keeps the sign), and the weights above */
STEP_INLINE void phase_flux_of(int32_t i_al, int32_t i_be, struct phase_flux *pf)
{
    const int32_t sb = FX_CROSS(56756, i_be, 32768, i_al, 0, 32), sc = FX_DOT(32768, i_al, 56756, i_be, 0, 32);
    const int32_t s0 = (i_al > 0) - (i_al < 0), s1 = (sb > 0) - (sb < 0), s2 = (sc < 0) - (sc > 0);

    pf->w_al[0] = -2 * 10923 * s0;
    pf->w_al[1] = 10923 * s1;
    pf->w_al[2] = 10923 * s2;
    pf->w_be[0] = 0;
    pf->w_be[1] = -18919 * s1;
    pf->w_be[2] = 18919 * s2;
    pf->a_al = pf->w_al[0] + pf->w_al[1] + pf->w_al[2];
    pf->a_be = pf->w_be[1] + pf->w_be[2];
    pf->pos = (s0 > 0) | (s1 > 0) << 1 | (s2 > 0) << 2;
    pf->neg = (s0 < 0) | (s1 < 0) << 1 | (s2 < 0) << 2;
}

/* applied_flux from the currents' phase_flux (0 <= dt_f, vth_f <= 2^28): (v << FLUX_FRAC) + round_shr(a vth_f + b dt_f,
 * 15) as round_shr(a vth_f + b dt_f + v 2^(15 + FLUX_FRAC), 15), the added term a multiple of 2^15 */
static __attribute__((noinline)) void applied_flux_of(int32_t old, int32_t new_state, const struct phase_flux *pf,
                                                      int32_t dt_f, int32_t vth_f, int32_t *f_al, int32_t *f_be)
{
    const int32_t sel = (new_state & ~old & pf->pos) | (old & ~new_state & pf->neg);
    const int32_t m0 = -(sel & 1), m1 = -(sel >> 1 & 1), m2 = -(sel >> 2 & 1);
    const int32_t b_al = (pf->w_al[0] & m0) + (pf->w_al[1] & m1) + (pf->w_al[2] & m2);
    const int32_t b_be = (pf->w_be[1] & m1) + (pf->w_be[2] & m2);
    FX_ACC(acc);

    FX_MUL(acc, pf->a_al, vth_f, 0);
    FX_MAC(acc, b_al, dt_f, 0);
    FX_MAC(acc, state_vx[new_state & 7], 1 << (15 + FW_FLUX_FRAC), 0);
    *f_al = FX_RND(acc, 15, 0);
    FX_MUL(acc, pf->a_be, vth_f, 0);
    FX_MAC(acc, b_be, dt_f, 0);
    FX_MAC(acc, state_vy[new_state & 7], 1 << (15 + FW_FLUX_FRAC), 0);
    *f_be = FX_RND(acc, 15, 0);
}

/* golden.firmware.applied_flux.applied_flux (0 <= dt_f, vth_f <= 2^28, s16 currents) */
void fw_applied_flux(int32_t old, int32_t new_state, int32_t i_al, int32_t i_be, int32_t dt_f, int32_t vth_f,
                     int32_t *f_al, int32_t *f_be)
{
    struct phase_flux pf;

    phase_flux_of(i_al, i_be, &pf);
    applied_flux_of(old, new_state, &pf, dt_f, vth_f, f_al, f_be);
}

/* HybridFluxProjection._limit: min(max(e, -eps_max), eps_max) */
static int32_t hfo_limit(int32_t e, int32_t eps_max)
{
    e = e > -eps_max ? e : -eps_max;
    return e < eps_max ? e : eps_max;
}

/* _limit(_to_bin(x)) of golden.firmware.hfo_proj: radians (Q16, int32) to binary angle (shr(x RAD_BIN, 16)), limited
 * to eps_max; the product on the fixed-point unit, saturated to s32 there (the limit of a saturated value is that
 * of the value: [-eps_max, eps_max] lies within s32) */
static int32_t hfo_angle(int32_t x_q16, int32_t eps_max)
{
    return hfo_limit(FX_SHR(x_q16, 683565276, 16, 32), eps_max); /* RAD_BIN */
}

/* the bit length of x >= 0 (Python int.bit_length) */
static int32_t bit_length64(int64_t x)
{
    return (uint64_t)x >> 32 ? 32 + bit_length32((uint32_t)((uint64_t)x >> 32)) : bit_length32((uint32_t)x);
}

/* HybridFluxProjection.step's step 5 (APP), its operands normalised to 15 bits: nb = max(bit_length(max(|a_d|,
 * |a_q|)) - 15, 0), then a >> nb and sat(x >> nb, 16); in 32-bit words when all four fit int32 (the usual case) */
STEP_INLINE void app_normalise(int64_t a_d, int64_t a_q, int64_t x_d, int64_t x_q, int32_t *ad, int32_t *aq,
                               int32_t *xd, int32_t *xq)
{
    if (FX_USUAL && (int32_t)a_d == a_d && (int32_t)a_q == a_q && (int32_t)x_d == x_d && (int32_t)x_q == x_q) {
        const int32_t d = (int32_t)a_d, q = (int32_t)a_q;
        const uint32_t md = d < 0 ? 0u - (uint32_t)d : (uint32_t)d, mq = q < 0 ? 0u - (uint32_t)q : (uint32_t)q;
        int32_t nb = bit_length32(md > mq ? md : mq) - 15;
        nb = nb > 0 ? nb : 0;
        const int32_t vd = (int32_t)x_d >> nb, vq = (int32_t)x_q >> nb;
        *ad = d >> nb;
        *aq = q >> nb;
        *xd = vd > 32767 ? 32767 : vd < -32768 ? -32768 : vd;
        *xq = vq > 32767 ? 32767 : vq < -32768 ? -32768 : vq;
        return;
    }
    const int64_t md = abs64(a_d), mq = abs64(a_q);
    int32_t nb = bit_length64(md > mq ? md : mq) - 15;
    nb = nb > 0 ? nb : 0;
    *ad = (int32_t)(a_d >> nb);
    *aq = (int32_t)(a_q >> nb);
    *xd = (int32_t)sat_bits(x_d >> nb, 16);
    *xq = (int32_t)sat_bits(x_q >> nb, 16);
}

/* HybridFluxProjection.step's eq. (5), one component: sat(psi + a - shr(r_f i, 16) + shr(c_g (lam - psi), 16), 32);
 * on the fixed-point unit when lam - psi fits its int32 operand (the usual case: both are far from the limits) */
static int32_t hfo_euler(int32_t psi, int32_t a, int32_t i, int32_t lam, const struct fw_hfo_params *hp)
{
    int32_t diff;

    if (!FX_USUAL || __builtin_sub_overflow(lam, psi, &diff))
        return sat32((int64_t)psi + a - (((int64_t)hp->r_f * i) >> 16)
                     + (((int64_t)hp->c_g * ((int64_t)lam - psi)) >> 16));
    FX_ACC(acc);
    FX_MUL(acc, hp->c_g, diff, 16);
    FX_MSU(acc, hp->r_f, i, 16);
    FX_ADD(acc, psi, 0, a);
    return FX_FLR(acc, 0, 32);
}

/* HybridFluxProjection.step's step 0, one component: (int32_t)(r + shr(c_lag (r - r_prev), 16)) on the fixed-point
 * unit (r, r_prev s16: TOP_I; the difference fits its operand) */
static int32_t hfo_lag(int32_t r, int32_t r_prev, int32_t c_lag)
{
    FX_ACC(acc);

    FX_MUL(acc, c_lag, r - r_prev, 16);
    FX_ADD(acc, r, 0, 0);
    return FX_FLR(acc, 0, 0);
}

/* golden.firmware.hfo_proj.HybridFluxProjection.step (Varatharajan et al. 2020, Secs. II-B, III-C, IV): the
 * hybrid flux observer, the current model from the LUT, the projection's coefficients, the low-speed error,
 * APP, fusion and PLL; the same operations in the same order (in int64_t, on the fixed-point unit where the
 * operands fit its int32 registers). On the method's own state and parameters and the window's TOP_I and
 * VECTOR, so that fw_hfo_idle can run it on a copy. */
static __attribute__((noinline)) void hfo_step(struct fw_hfo_state *e, const struct fw_hfo_params *hp,
                                               const struct fw_window *win, uint32_t *theta, int32_t *omega)
{
    const struct fw_flux_lut *lut = &hp->lut;
    int64_t w_i = e->integ >> 24;
    int32_t r_al = win->top_ia, r_be = win->top_ib;       /* TOP_I, as sampled */
    fw_sincos_start(e->th);                                /* taken in step 2: the CORDIC runs meanwhile */
    /* 0. the current at the top, corrected for the sensors' lag */
    int32_t i_al = hfo_lag(r_al, e->r_al, hp->c_lag), i_be = hfo_lag(r_be, e->r_be, hp->c_lag);
    int32_t a_al, a_be;

    fw_applied_flux(e->vec_old, e->vec, e->i_al, e->i_be, hp->dt_f, hp->vth_f, &a_al, &a_be);
    /* 1. eq. (5) */
    int32_t psi_al = hfo_euler(e->psi_al, a_al, e->i_al, e->lam_al, hp);
    int32_t psi_be = hfo_euler(e->psi_be, a_be, e->i_be, e->lam_be, hp);
    /* 2. the current model */
    int32_t s, c;
    int64_t i_d, i_q;
    struct fw_lut_point pt;
    int32_t lam_al, lam_be;
    fw_sincos_take(&s, &c);
    fw_sincos_start(e->th - (uint32_t)w_i);                /* step 4's previous instant (unused when f = 0) */
    park64(i_al, i_be, s, c, &i_d, &i_q);
    fw_lut_point(lut, (int32_t)i_d, (int32_t)i_q, &pt);
    inv_park64(pt.lam_d, pt.lam_q, s, c, &lam_al, &lam_be);
    /* 3. eq. (30)'s coefficients */
    int32_t a1, a2;
    fw_projection_coefficients(&pt, lut->l_shift, &a1, &a2);
    /* 6. fusion weight */
    /* golden's clamp of c_div(n 2^16, 2 wg_b) (wg_b >= 1): 0 for n <= 0, 2^16 for n >= 2 wg_b, and in between the
     * quotient itself (0..2^16): the divide only inside the band */
    const int64_t f_n = (int64_t)hp->g_b + hp->wg_b - abs64(w_i);
    const int64_t f_d = 2 * (int64_t)hp->wg_b;
    const int32_t f = f_n <= 0 ? 0 : f_n >= f_d ? 65536 : SAT_DIV64(f_n * 65536, f_d, 18);
    /* fw_hfo_idle: warm it from 7/8 of the band's lower edge on, and stop at 31/32 */
    fw_idle_work = f == 65536 && 8 * (f_n - f_d) < (int64_t)hp->g_b - hp->wg_b &&
                   32 * (f_n - f_d) >= (int64_t)hp->g_b - hp->wg_b;
    /* 4. low speed */
    int64_t eps_h = 0;
    int valid = 0;
    e->e_d = e->s_h = 0;
    if (f > 0) {
        int32_t sp, cp, sm, cm, lp_al, lp_be;
        int64_t pd, pq, lpd, lpq, dpd, dpq, dlam_d, dlam_q;

        fw_sincos_take(&sp, &cp);                          /* e->th - w_i */
        fw_sincos_start(e->th - (uint32_t)(w_i >> 1));
        park64(e->i_al, e->i_be, sp, cp, &pd, &pq);
        fw_lut_flux(lut, (int32_t)pd, (int32_t)pq, &lpd, &lpq);
        inv_park64(lpd, lpq, sp, cp, &lp_al, &lp_be);
        fw_sincos_take(&sm, &cm);                          /* e->th - w_i / 2 */
        park64((int64_t)psi_al - e->psi_al, (int64_t)psi_be - e->psi_be, sm, cm, &dpd, &dpq);
        park64((int64_t)lam_al - lp_al, (int64_t)lam_be - lp_be, sm, cm, &dlam_d, &dlam_q);
        int64_t e_d = dpd - dlam_d;
        /* eq. (29); on the unit for |dpd|, |dpq| <= 2^27: |a1 dpq| + |a2 dpd| <= 2^43 (|a1|, |a2| <= 2^15) */
        int64_t strength = FX_USUAL && fits_bits64(dpd, 27) && fits_bits64(dpq, 27)
                               ? FX_CROSS(a1, (int32_t)dpq, a2, (int32_t)dpd, 12, 32)
                               : round_shr64(a1 * dpq - a2 * dpd, 12);
        valid = abs64(strength) > ((int64_t)hp->phi_min << FW_FLUX_FRAC);
        if (valid) {
            /* sat32(q) as sat_bits(q, 21): |q| >= 2^20 gives |_to_bin| > 10^10 > eps_max either way, so
             * the limit's result is the same (_to_bin is monotonic) */
            int32_t q;

            if (abs64(strength) >= hp->s_knee)
                q = SAT_DIV64(e_d * 65536, strength, 21);
            else
                q = SAT_DIV64(sat_bits(e_d, 24) * strength * 65536, (int64_t)hp->s_knee * hp->s_knee, 21);
            eps_h = hfo_angle(q, hp->eps_max);
            e->th_meas = e->th + (uint32_t)eps_h;
        } else if (hp->hold && e->since < hp->n_max) {
            eps_h = hfo_limit((int32_t)(e->th_meas - e->th), hp->eps_max);
        }
        e->e_d = e_d;
        e->s_h = strength;
    }
    e->n_rej = valid ? 0 : (e->n_rej + 1 < 65536 ? e->n_rej + 1 : 65536);
    e->since = valid ? 0 : (e->since + 1 < 65536 ? e->since + 1 : 65536);
    e->th_meas += (uint32_t)w_i;
    /* 5. high speed: APP */
    int64_t eps_t = 0;
    if (f < 65536 && w_i != 0) {
        int64_t pd, pq;

        park64(psi_al, psi_be, s, c, &pd, &pq);
        int64_t x_d = pd - pt.lam_d, x_q = pq - pt.lam_q;
        /* l_* fit s32 (interpolations of the s28 tables with fractions in 0..1), |i_d|, |i_q| <= 2^18 (control.h):
         * each product one mul and one mulh */
        const int32_t ld = (int32_t)pt.l_d, lq = (int32_t)pt.l_q, ldq = (int32_t)pt.l_dq;
        const int32_t id = (int32_t)i_d, iq = (int32_t)i_q;
        int64_t a_d = -pt.lam_q + (((int64_t)ld * iq - (int64_t)ldq * id) >> lut->shift);
        int64_t a_q = pt.lam_d + (((int64_t)ldq * iq - (int64_t)lq * id) >> lut->shift);
        int32_t ad, aq, xd, xq;
        app_normalise(a_d, a_q, x_d, x_q, &ad, &aq, &xd, &xq);
        /* |a_d|, |a_q| <= 2^15 now, x_d, x_q s16: the sums of products below 2^47 on the fixed-point unit, the
         * dividends' factor 65536 in the operand (x << 16 fits int32) */
        const int64_t sq = (int64_t)(ad * ad) + (int64_t)(aq * aq);   /* each square <= 2^30, the sum up to 2^31 */
        if (sq > 0) {
            FX_ACC(acc);

            FX_MUL(acc, ad, xd * 65536, 0);
            FX_MAC(acc, aq, xq * 65536, 0);
            const int32_t q1 = FX_DIV(acc, sq, 21);
            FX_MUL(acc, aq, xd * 65536, 0);
            FX_MSU(acc, ad, xq * 65536, 0);
            const int32_t q2 = FX_DIV(acc, sq, 21);
            /* c_div(q2 g_b, w_i) as sat_bits(., 22): beyond it |q1 - .| >= 2^20 on the same side (|q1| < 2^20),
             * where the limit's result is the same (above) */
            FX_MUL(acc, q2, hp->g_b, 0);
            eps_t = hfo_angle(sat32((int64_t)q1 - FX_DIV(acc, w_i, 22)), hp->eps_max);
        }
    }
    /* the fusion on the unit: 0 <= f <= 2^16, |eps_h|, |eps_t| <= eps_max (int32) */
    FX_ACC(acc);
    FX_MUL(acc, f, (int32_t)eps_h, 0);
    FX_MAC(acc, 65536 - f, (int32_t)eps_t, 0);
    int32_t eps = FX_FLR(acc, 16, 32);
    /* 7. PLL: w = sat32(shr(kp eps, 16) + shr(integ, 24)), shr(integ, 24) = (hi << 8) + (lo >> 24) of its words */
    e->integ = sat_add64(e->integ, (int64_t)hp->ki * eps);
    FX_MUL(acc, hp->kp, eps, 16);
    FX_ADD(acc, (int32_t)((uint64_t)e->integ >> 32), 8, (int32_t)((uint32_t)e->integ >> 24));
    int32_t w = FX_FLR(acc, 0, 32);
    e->th += (uint32_t)w;
    /* 8. state and outputs */
    e->psi_al = psi_al;
    e->psi_be = psi_be;
    e->lam_al = lam_al;
    e->lam_be = lam_be;
    e->i_al = i_al;
    e->i_be = i_be;
    e->vec_old = e->vec;
    e->vec = win->vector;
    e->r_al = r_al;
    e->r_be = r_be;
    e->eps_h = (int32_t)eps_h;
    e->eps_t = (int32_t)eps_t;
    e->f = f;
    e->fcs_a1 = a1;
    e->fcs_a2 = a2;
    e->constrain = f > 0 && e->n_rej > hp->n_max && e->cons_wait == 0;
    e->cons_wait = e->constrain ? 2 : (e->cons_wait - 1 > 0 ? e->cons_wait - 1 : 0);
    e->omega = w;
    e->theta = e->th + (uint32_t)FX_SHR(w, hp->k_delay, 16, 0);
    *theta = e->theta;
    *omega = e->omega;
}

/* a tail call: the step's frames lie where they did before hfo_step was apart (the 4 KiB data cache) */
void fw_hfo_step(struct fw_state *st, const struct fw_params *p, const struct fw_meas *m, uint32_t *theta,
                 int32_t *omega)
{
    hfo_step(&st->hfo, &p->hfo, m->win, theta, omega);
}

/* The idle loop's part (fw_idle), beside golden (which has no caches): the step's code in the instruction cache
 * before the fusion band. The step runs APP from the band's lower edge |w_i| > g_b - wg_b on; until then that code
 * has not run, its cache lines belong to others, and the band's first step refilled them (4081 CPU clocks, 82 % of
 * the 10 kHz period, where the band's other steps take up to 3594: docs/soc.md). From 7/8 to 31/32 of that speed
 * (the step sets fw_idle_work), the idle loop runs the step once per period on a copy of the state with the PLL's
 * speed inside the band (both estimators and the fusion run; the copy's step clears fw_idle_work), the window's currents the last
 * ones: nothing is written but the copy, and the accelerators' and the fixed-point unit's results are its own (an
 * interrupted sequence only spoils the copy's: the step starts each of its own). The next step pays for it (the
 * copy's APP evicts lines of the low-speed code: about 180 CPU clocks), so the zone is narrow: from half the edge on,
 * the 2 p.u. torque step's speed transient put 15 steps above 3500. It ends below the edge: the steps of the last
 * 1/32 run without it and restore their own lines (APP's stay, the step's code does not evict them), so the band's
 * first step no longer pays for the last copy (3556 -> 3391 CPU clocks). Empty where FW_IDLE_WARM is 0. */
void fw_hfo_idle(const struct fw_state *st, const struct fw_params *p)
{
#if FW_IDLE_WARM
    const struct fw_hfo_params *hp = &p->hfo;
    struct fw_hfo_state copy = st->hfo;
    struct fw_window win = {0};

    win.top_ia = copy.r_al;
    win.top_ib = copy.r_be;
    win.vector = copy.vec;
    uint32_t theta;
    int32_t omega;

    copy.integ = (int64_t)hp->g_b << 24;
    hfo_step(&copy, hp, &win, &theta, &omega);
#else
    (void)st;
    (void)p;
#endif
}

/* golden.firmware.hfo_proj.HybridFluxProjection.turn */
void fw_hfo_turn(struct fw_state *st, uint32_t delta)
{
    st->hfo.th += delta;
    st->hfo.theta += delta;
}

/* golden.firmware.hfo_proj.HybridFluxProjection.sync */
void fw_hfo_sync(struct fw_state *st, const struct fw_params *p, uint32_t theta, int32_t omega)
{
    struct fw_hfo_state *e = &st->hfo;

    e->th = theta - (uint32_t)(((int64_t)omega * p->hfo.k_delay) >> 16);
    e->integ = (int64_t)omega * 16777216; /* omega << 24 */
    e->theta = theta;
    e->omega = omega;
}

/* Estimator.i_d: 0 */
int32_t fw_hfo_i_d(const struct fw_params *p)
{
    (void)p;
    return 0;
}

/* the flux outputs (Estimator.psi_al, psi_be, fcs_a1, fcs_a2, constrain) */
void fw_hfo_flux(const struct fw_state *st, struct fw_est_flux *f)
{
    f->psi_al = st->hfo.psi_al;
    f->psi_be = st->hfo.psi_be;
    f->fcs_a1 = st->hfo.fcs_a1;
    f->fcs_a2 = st->hfo.fcs_a2;
    f->constrain = st->hfo.constrain;
}

/* golden.firmware.fcs_law.flux_reference (i_s s32; |i_s| as uint32_t) */
void fw_flux_reference(const struct fw_fcs_params *p, int32_t i_s, int32_t *d, int32_t *q)
{
    uint32_t mag = i_s < 0 ? 0u - (uint32_t)i_s : (uint32_t)i_s;
    int32_t qq;

    fw_mtpa_lookup(mag, p->shift, p->len, p->t_d, p->t_q, d, &qq);
    *q = i_s < 0 ? -qq : qq;
}

/* deadbeat_voltage's eq. (14), one component: sat(round_shr(ref - p2, FLUX_FRAC) + shr(r_v i, 16), 32) with
 * p2 = psi + a1 + a2 - 2 shr(r_f i, 16) (eq. (13), two periods ahead), on the fixed-point unit. The second term
 * m = shr(r_v i, 16) is an integer, so it joins the rounded one as m 2^FLUX_FRAC inside the rounding; |m| < 2^31
 * (int32 r_v, s16 top currents: the TOP_I field). */
static int32_t deadbeat_component(const struct fw_fcs_params *p, int32_t ref, int32_t psi, int32_t a1, int32_t a2,
                                  int32_t i)
{
    _Static_assert(FW_FLUX_FRAC == 8, "the unit adds m << FW_FLUX_FRAC: a whole byte");
    const int32_t m = FX_SHR(p->r_v, i, 16, 0);
    FX_ACC(acc);

    FX_MUL(acc, p->r_f, i, 16);
    FX_MAC(acc, p->r_f, i, 16);
    FX_ADD(acc, m, 8, ref);
    FX_MSU(acc, psi, 1, 0);
    FX_MSU(acc, a1, 1, 0);
    FX_MSU(acc, a2, 1, 0);
    return FX_RND(acc, FW_FLUX_FRAC, 32);
}

/* golden.firmware.fcs_law.deadbeat_voltage (Varatharajan et al. 2020, eqs. (13)-(14)) */
void fw_deadbeat_voltage(const struct fw_fcs_params *p, int32_t psi_al, int32_t psi_be, int32_t i_al, int32_t i_be,
                         int32_t before, int32_t vector, int32_t nxt, uint32_t theta, int32_t omega,
                         int32_t i_s, int32_t *v_d, int32_t *v_q, int32_t *sin_q15, int32_t *cos_q15)
{
    int32_t a1a, a1b, a2a, a2b, d_ref, q_ref, s, c, ref_a, ref_b;
    struct phase_flux pf;

    fw_sincos_start(theta + (uint32_t)(omega >> 1));  /* the CORDIC runs while the applied flux is summed */
    phase_flux_of(i_al, i_be, &pf);                  /* the same currents at both switching instants */
    applied_flux_of(before, vector, &pf, p->dt_f, p->vth_f, &a1a, &a1b);
    applied_flux_of(vector, nxt, &pf, p->dt_f, p->vth_f, &a2a, &a2b);
    fw_flux_reference(p, i_s, &d_ref, &q_ref);
    fw_sincos_take(&s, &c);
    fw_sincos_start(theta);
    inv_park(d_ref, q_ref, s, c, &ref_a, &ref_b);
    int32_t v_a = deadbeat_component(p, ref_a, psi_al, a1a, a2a, i_al);
    int32_t v_b = deadbeat_component(p, ref_b, psi_be, a1b, a2b, i_be);
    int64_t d, q;
    fw_sincos_take(&s, &c);
    *sin_q15 = s;
    *cos_q15 = c;
    park64(v_a, v_b, s, c, &d, &q);
    while (abs64(d) > p->v_lim || abs64(q) > p->v_lim) {
        d >>= 1;
        q >>= 1;
    }
    *v_d = (int32_t)d;
    *v_q = (int32_t)q;
}

/* golden.firmware.methods.CLASSES: the members of the plug-in interface, by method id. */
static const struct fw_est_ops fw_methods[FW_METHODS] STEP_TABLE = {
    [FW_METHOD_SQW_BANGBANG] = {fw_sqw_step, fw_sqw_turn, fw_sqw_sync, fw_sqw_i_d, 0, 0},
    [FW_METHOD_RFO] = {fw_rfo_step, fw_rfo_turn, fw_rfo_sync, fw_rfo_i_d, 0, 0},
    [FW_METHOD_ROT_BPF] = {fw_rot_step, fw_rot_turn, fw_rot_sync, fw_rot_i_d, 0, 0},
    [FW_METHOD_EEMF_SMO] = {fw_smo_step, fw_smo_turn, fw_smo_sync, fw_smo_i_d, 0, 0},
    [FW_METHOD_SQW_CIC] = {fw_cic_step, fw_cic_turn, fw_cic_sync, fw_cic_i_d, 0, 0},
    [FW_METHOD_HFO_PROJ] = {fw_hfo_step, fw_hfo_turn, fw_hfo_sync, fw_hfo_i_d, fw_hfo_flux, fw_hfo_idle},
};

/* Whether a method's injection is on while it is in charge, by method id (generated, fw_methods.h). */
static const uint8_t fw_method_injects[FW_METHODS] STEP_TABLE = FW_METHOD_INJECTS;

/* The method id of a slot (0: none). */
static int32_t slot_method(const struct fw_params *p, int32_t slot)
{
    return slot == FW_SLOT_LOW ? p->low : p->high;
}

volatile int32_t fw_idle_work __attribute__((section(".state_vars"))); /* beside main.c's HANDLER_VAR */

#if FW_IDLE_WARM
void fw_idle(const struct fw_state *st, const struct fw_params *p)
{
    fw_idle_work = 0;
    for (int32_t slot = FW_SLOT_LOW; slot <= FW_SLOT_HIGH; slot++) {
        const int32_t method = slot_method(p, slot);

        if (method > 0 && method < FW_METHODS && fw_methods[method].idle)
            fw_methods[method].idle(st, p);
    }
}
#endif

/* ---- self-commissioning: the identification program's executor (golden.firmware.ident.Ident) ----- */

_Static_assert(sizeof(((struct fw_ident_params *)0)->s_n) / sizeof(int32_t) == FW_IDENT_MAX,
               "struct fw_ident_params: the step arrays must have FW_IDENT_MAX entries");
_Static_assert(sizeof(((struct fw_ident_state *)0)->r_id) / sizeof(int32_t) == FW_IDENT_MAX &&
               sizeof(((struct fw_ident_state *)0)->r_gd) / sizeof(int64_t) == FW_IDENT_MAX,
               "struct fw_ident_state: the sum arrays must have FW_IDENT_MAX entries");

/* FW_NO_IDENT (the RISC-V image by default, firmware/Makefile): the executor is compiled out; fw_init does not
 * read fw_state.ident and the state never enters FW_IDENT. The host build (cffi, tests/test_fw_c.py) has it. */
#ifndef FW_NO_IDENT

enum { F_SET = 1, F_SCAN = 2, F_FIT = 4, F_POL = 8, F_OPEN = 16, F_LEVEL = 32, F_NEG = 128,
       F_SNAP = 256, F_GAIN = 512 }; /* ident.F_* */
#define IDENT_KP_MAX INT32_MAX         /* ident.KP_MAX */
#define IDENT_SIXTH 715827882          /* ident.SIXTH = 2^32 // 6 */
#define VECTOR_INPUT_LIMIT (1 << 28)   /* golden.firmware.vector.INPUT_LIMIT */
#define IDENT_G2_SHIFT 8               /* ident.G2_SHIFT */
#define IDENT_G2_BITS 24               /* ident.G2_BITS */

/* Ident._start: enter step k; F_SET puts the frame at theta_r + phi, at rest, and keeps its
 * turn (jump); F_SNAP then sets the speed that takes it to the nearest phase axis over the step's other
 * windows: w = c_div(wrap(axis - theta, 32), max(n - 1, 1)) with axis = ((floor((theta + SIXTH / 2) / SIXTH)
 * mod 6) 2^32) // 6 (in int64: theta + SIXTH / 2 exceeds u32). */
static void ident_start(struct fw_ident_state *id, const struct fw_ident_params *p)
{
    int32_t f = p->s_flags[id->k];

    if (f & F_SET) {
        uint32_t theta = id->theta_r + p->s_phi[id->k];

        id->jump = theta - id->theta;
        id->theta = theta;
        id->w = 0;
        if (f & F_SNAP) {
            int64_t sector = (((int64_t)theta + (IDENT_SIXTH >> 1)) / IDENT_SIXTH) % 6;
            uint32_t axis = (uint32_t)((sector << 32) / 6);
            int32_t n1 = p->s_n[id->k] - 1;

            id->w = (int32_t)(axis - theta) / (n1 > 1 ? n1 : 1);   /* c_div, the divisor >= 1 (n >= 2) */
        }
    }
}

/* Ident.__init__ / __post_init__: everything 0 (cleared in place) but the level factor (1.0, Q16), then step 0
 * starts. */
static void ident_init(struct fw_ident_state *id, const struct fw_ident_params *p)
{
    memset(id, 0, sizeof *id);
    id->lvl = 1 << 16;
    ident_start(id, p);
}

/* Ident.v_h: min(shr(s_vh[k] lvl, 16), vh_max) (s_vh <= 2^15, lvl <= 2^24: the product below 2^39) */
static int32_t ident_v_h(const struct fw_ident_state *id, const struct fw_ident_params *p, int32_t k)
{
    int64_t v = ((int64_t)p->s_vh[k] * id->lvl) >> 16;

    return v < p->vh_max ? (int32_t)v : p->vh_max;
}

/* Ident._finish: the decisions at the end of step k (F_GAIN, F_LEVEL, F_SCAN, F_FIT, F_SNAP, F_POL, in this
 * order). */
static void ident_finish(struct fw_ident_state *id, const struct fw_ident_params *p, int32_t k)
{
    int32_t f = p->s_flags[k];

    if (f & F_GAIN) {                                  /* at the amplitude the step ran with: before F_LEVEL */
        if (id->r_gd[k] <= 0) {
            id->failed = 1;
        } else {
            int64_t kp = p->c_gain * ident_v_h(id, p, k) / id->r_gd[k];   /* c_div: 0 <= c_gain v_h < 2^61 */

            id->kp = kp < IDENT_KP_MAX ? (int32_t)kp : IDENT_KP_MAX;
            id->ki = (int32_t)(((int64_t)id->kp * p->c_ki) >> 16);
        }
    }
    if (f & F_LEVEL) {
        if (id->r_gd[k] <= 0) {
            id->failed = 1;
        } else {
            int64_t lvl = p->c_lvl / id->r_gd[k];      /* c_div, both >= 0 */
            id->lvl = lvl < p->lvl_max ? (int32_t)lvl : p->lvl_max;
        }
    }
    if (f & F_SCAN) {
        int32_t s2, c2;
        int64_t g_d = id->r_gd[k], g_q = id->r_gq[k];

        fw_sincos_q15(2u * p->s_phi[k], &s2, &c2);
        if (f & F_NEG) {
            g_d = -g_d;
            g_q = -g_q;
        }
        id->fit_x += g_d * c2 - g_q * s2;
        id->fit_y += g_d * s2 + g_q * c2;
        id->fit_y0 += g_d;
    }
    if (f & F_FIT) {
        int64_t x = id->fit_x, y = id->fit_y;
        uint32_t a;
        int32_t mag;

        while (abs64(x) > VECTOR_INPUT_LIMIT || abs64(y) > VECTOR_INPUT_LIMIT) { /* max(|x|, |y|) > limit */
            x >>= 1;
            y >>= 1;
        }
        fw_vector_angle((int32_t)x, (int32_t)y, &a, &mag);
        id->theta_r = a >> 1;
        if (id->fit_y0 <= 0) {
            id->failed = 1;
        } else if (p->c_kp) {
            int64_t dv = (int64_t)ident_v_h(id, p, k) - ident_v_h(id, p, k - 1);   /* k >= 1 (IdentParams) */
            int64_t kp = p->c_kp * dv / id->fit_y0;     /* c_div: 0 <= c_kp dv < 2^61 */

            id->kp = kp < IDENT_KP_MAX ? (int32_t)kp : IDENT_KP_MAX;   /* >= 0: s_vh[k] > s_vh[k - 1] */
            id->ki = (int32_t)(((int64_t)id->kp * p->c_ki) >> 16);
        }
    }
    if (f & F_SNAP)
        id->w = 0;
    if ((f & F_POL) && id->r_gd[k] > id->r_gd[k - 1])   /* k >= 1 (IdentParams) */
        id->theta_r += HALF_TURN;
}

/* Ident.measure: one window; summed when it is one of the step's last m; at the step's end, its action. */
static void ident_measure(struct fw_ident_state *id, const struct fw_ident_params *p, int32_t i_d, int32_t i_q,
                          int32_t gamma_d, int32_t gamma_q, const struct fw_outputs *now,
                          const struct fw_outputs *before)
{
    int32_t k = id->k;

    id->n++;
    if ((int64_t)id->n > (int64_t)p->s_n[k] - p->s_m[k]) {
        int32_t a, b;
        int64_t v_d, v_q;

        fw_window_voltage(now, before, &a, &b);
        park64(a, b, now->sin, now->cos, &v_d, &v_q);
        id->r_id[k] += i_d;                     /* s16-range means, m <= 32767: within int32 (control.h) */
        id->r_iq[k] += i_q;
        id->r_vd[k] += (int32_t)v_d;
        id->r_vq[k] += (int32_t)v_q;
        id->r_gd[k] += gamma_d;
        id->r_gq[k] += gamma_q;
        if (p->s_flags[k] & F_SCAN) {
            int64_t g_d = sat_bits(gamma_d, IDENT_G2_BITS), g_q = sat_bits(gamma_q, IDENT_G2_BITS);

            id->g2 += (g_d * g_d + g_q * g_q) >> IDENT_G2_SHIFT;   /* shr: the sum >= 0 */
        }
    }
    if (id->n < p->s_n[k])
        return;
    ident_finish(id, p, k);
    id->k = k + 1;
    id->n = 0;
    if (id->k == p->n_steps)
        id->done = 1;
    else
        ident_start(id, p);
}

/* Ident.refs: in an F_SET step's first call the references in use and the PI integrators turn with the
 * frame's jump (park, int64), else the frame advances (w += dw saturated, theta += w); the references approach
 * the step's by at most i_slew; the window means of an F_SET step's first two calls (run in the frame before
 * its jump) turn by the jump (park in int64), all others are used as measured (the PI's error is
 * sat(ref - mean, 32) as golden's pi_step, formed here and handed to fw_pi_step as ref - 0); the current PIs
 * (kp, ki Q16, the integrators id_int, iq_int of fw_state) or zero voltage (F_OPEN); out->v_h the step's
 * amplitude. */
static void ident_refs(struct fw_state *st, const struct fw_ident_params *p, int32_t i_d, int32_t i_q,
                       struct fw_outputs *out)
{
    struct fw_ident_state *id = &st->ident->s;
    int32_t k = id->k, f = p->s_flags[k], s, c;
    int64_t d, q;

    if ((f & F_SET) && id->n == 0) {
        fw_sincos_q15(id->jump, &s, &c);
        park64(id->ref_d, id->ref_q, s, c, &d, &q);
        id->ref_d = sat16(sat32(d));            /* sat(x, 16); |d|, |q| < 2^17 (s16 references) */
        id->ref_q = sat16(sat32(q));
        park64(st->id_int, st->iq_int, s, c, &d, &q);
        st->id_int = d;
        st->iq_int = q;
    } else {
        id->w = sat32((int64_t)id->w + p->s_dw[k]);
        id->theta += (uint32_t)id->w;
    }
    d = (int64_t)id->ref_d - p->i_slew;
    q = (int64_t)id->ref_d + p->i_slew;
    id->ref_d = (int32_t)(p->s_id[k] < d ? d : p->s_id[k] > q ? q : p->s_id[k]);
    d = (int64_t)id->ref_q - p->i_slew;
    q = (int64_t)id->ref_q + p->i_slew;
    id->ref_q = (int32_t)(p->s_iq[k] < d ? d : p->s_iq[k] > q ? q : p->s_iq[k]);
    d = i_d;
    q = i_q;
    if ((f & F_SET) && id->n < 2) {   /* the means of the step's first two calls: in the frame before its jump */
        fw_sincos_q15(id->jump, &s, &c);
        park64(i_d, i_q, s, c, &d, &q);
    }
    if (f & F_OPEN) {
        out->v_d = out->v_q = 0;
        st->id_int = st->iq_int = 0;
    } else {
        const struct fw_pi_params pi = {id->kp, 16, id->ki, 16, p->v_lim, (int64_t)p->v_lim << 16};

        out->v_d = fw_pi_step(&st->id_int, sat32((int64_t)id->ref_d - d), 0, &pi);
        out->v_q = fw_pi_step(&st->iq_int, sat32((int64_t)id->ref_q - q), 0, &pi);
    }
    out->v_h = ident_v_h(id, p, k);
}
#endif /* FW_NO_IDENT */

/* ---- supervisor (golden.firmware.supervisor.Firmware) ------------------------------------------- */

static const struct fw_outputs reset_outputs = {0, 0, 0, 0, 32767, 0, 0, 0, 0, 0, 0, 0}; /* RESET_OUTPUTS */

/* ---- the output history (struct fw_state hist, hist_at) --------------------------------------- */

/* golden Firmware.act[0]: the outputs active in this window */
static const struct fw_outputs *act0(const struct fw_state *st)
{
    return &st->hist[st->hist_at];
}

#ifndef FW_NO_PROBE
/* golden Firmware.act[1]: the outputs of the last step (read by the flying-start probe only) */
static const struct fw_outputs *act1(const struct fw_state *st)
{
    return &st->hist[st->hist_at == 2 ? 0 : st->hist_at + 1];
}
#endif

/* golden Firmware.prev: the outputs active in the window before */
static const struct fw_outputs *prev_out(const struct fw_state *st)
{
    return &st->hist[st->hist_at == 0 ? 2 : st->hist_at - 1];
}

/* prev, act[0], act[1] = act[0], act[1], out (Firmware.step's last lines): out goes into prev's slot, which
 * becomes act[1], and the index moves on one slot */
static void push_outputs(struct fw_state *st, const struct fw_outputs *out)
{
    const int32_t at = st->hist_at;

    st->hist[at == 0 ? 2 : at - 1] = *out;
    st->hist_at = at == 2 ? 0 : at + 1;
}

/* Firmware.__init__ / __post_init__: everything 0 (the EEMF observer's direction forwards), CONVERGE; FIXED at
 * fixed_angle if enabled; else CATCH with the high slot in charge if the flying start is on; IDENT with the
 * executor at its step 0 if st->ident is set (before FIXED). */
void fw_init(struct fw_state *st, const struct fw_params *p)
{
#ifndef FW_NO_IDENT
    struct fw_ident *ident = st->ident; /* the caller's (control.h): kept */
#endif

    /* cleared in place (a static zero copy would take its size again in the RAM image) */
    memset(st, 0, sizeof *st);
    st->mode = p->fixed_enable ? FW_FIXED : FW_CONVERGE;
    st->theta_hat = p->fixed_enable ? p->fixed_angle : 0u;
    if (!p->fixed_enable && p->prot.catch_n > 0 && p->high != FW_METHOD_NONE) {
        st->mode = FW_CATCH;
        st->active = FW_SLOT_HIGH;
    }
    st->hist[0] = st->hist[1] = st->hist[2] = reset_outputs; /* hist_at 0 */
    st->smo.dir = 1; /* EemfSmo.__init__: forwards */
#ifndef FW_NO_IDENT
    st->ident = ident;
    if (ident) { /* the identification program instead of the start-up (and of FIXED, CATCH) */
        st->mode = FW_IDENT;
        st->active = FW_SLOT_LOW;
        st->theta_hat = 0u;
        ident_init(&ident->s, &ident->p);
    }
#endif
}

/* Firmware._next */
static void next_mode(struct fw_state *st, int32_t mode)
{
    st->mode = mode;
    st->n = 0;
}

/* ---- fault checks (golden.firmware.protection) -------------------------------------------------- */

/* protection.emf_residual: the two components, each saturated to s32 */
void fw_emf_residual(const struct fw_prot_params *p, int32_t v_d, int32_t v_q, int32_t i_d, int32_t i_q,
                     int32_t omega, int32_t *e_d, int32_t *e_q)
{
    FX_ACC(acc);
    FX_MUL(acc, p->ld, i_d, 16);
    FX_ADD(acc, p->psi_f, 0, 0);
    int32_t psi_d = FX_FLR(acc, 0, 32);
    int32_t psi_q = FX_SHR(p->lq, i_q, 16, 32);

    FX_MUL(acc, omega, psi_q, 32);
    FX_MSU(acc, p->r, i_d, 16);
    FX_ADD(acc, v_d, 0, 0);
    *e_d = FX_FLR(acc, 0, 32);
    FX_MUL(acc, v_q, 1, 0);
    FX_MSU(acc, p->r, i_q, 16);
    FX_MSU(acc, omega, psi_d, 32);
    *e_q = FX_FLR(acc, 0, 32);
}

#define OVL_CAP (1 << 30) /* protection.OVL_CAP */
#define SLIP_AGREE (1u << 29) /* protection.SLIP_AGREE: 45 deg */
#define SLIP_TRIP (1u << 30)  /* protection.SLIP_TRIP: 90 deg */

/* n + 1 while cond, up to OVL_CAP; 0 otherwise */
/* golden shr(a - b, k) for 0 <= k <= 30 without the 33-bit difference: shr(a, k) - shr(b, k), less one when a's low
 * k bits are below b's (the borrow); for k = 0 the int32 wrap of a - b, as the int32 cast of the exact value */
static int32_t shr_diff(int32_t a, int32_t b, int32_t k)
{
    const uint32_t m = (1u << k) - 1u;

    return (int32_t)((uint32_t)(a >> k) - (uint32_t)(b >> k) - (((uint32_t)a & m) < ((uint32_t)b & m)));
}

static int32_t count_while(int32_t n, int cond)
{
    return cond ? (n < OVL_CAP ? n + 1 : OVL_CAP) : 0;
}

/* protection.protect_step */
int32_t fw_protect_step(struct fw_state *st, const struct fw_prot_params *p, int32_t v_d, int32_t v_q, int32_t i_d,
                        int32_t i_q, int32_t i_d_ref, int32_t i_q_ref, int32_t omega_f, int32_t speed_ref,
                        int32_t at_limit, int32_t hf_on, int32_t hf)
{
    int32_t err = sat32(abs64((int64_t)speed_ref - omega_f));
    uint32_t w_abs = omega_f < 0 ? 0u - (uint32_t)omega_f : (uint32_t)omega_f; /* |omega_f| for every s32 */

    if (p->emf_tol) { /* a check that is off costs nothing; the signed components filtered (33-bit differences) */
        int32_t e_d, e_q;

        fw_emf_residual(p, v_d, v_q, i_d, i_q, omega_f, &e_d, &e_q);
        st->emf_d += shr_diff(e_d, st->emf_d, p->emf_k);
        st->emf_q += shr_diff(e_q, st->emf_q, p->emf_k);
    }
    if (p->track_tol)
        st->track_f += (sat32(abs64((int64_t)i_d_ref - i_d) + abs64((int64_t)i_q_ref - i_q)) - st->track_f) >> p->track_k;
    st->ovl_n = count_while(st->ovl_n, at_limit);
    if (st->ovl_n == 1 || (at_limit && p->ovl_w && st->e0 - err > p->ovl_w)) { /* at the limit, or progress (e0, err >= 0) */
        st->ovl_n = 1;
        st->e0 = err;
    }
    st->ovl_e = count_while(st->ovl_e, at_limit && (int64_t)err - st->e0 > p->ovl_w);
    if (p->ld_max) { /* the load's acceleration: n_p T_e / J less the speed's change (|products| < 2^62) */
        if (!st->ld_n) {
            st->ld_w = omega_f;
            st->ld_n = 1;
        }
        const int64_t id16 = sat16(i_d), iq16 = sat16(i_q);
        const int64_t torque = (p->ld_ct * iq16 + ((p->ld_cr * (id16 * iq16)) >> 16)) >> 24;
        int32_t load = sat32(torque - ((int64_t)omega_f - st->ld_w));

        /* sat32(ld_f + shr(load - ld_f, k)) lies between ld_f and load, so within s32 (no saturation needed); its
         * step as shr_diff's 32-bit floor (a variable 64-bit shift took 70 instructions, 26 CPU clocks a period) */
        st->ld_f = (int32_t)((uint32_t)st->ld_f + (uint32_t)shr_diff(load, st->ld_f, p->ld_k));
        st->ld_w = omega_f;
    }
    if (p->hf_tol) {
        if (!hf_on || st->hf_ref <= 0)
            st->hf_f = 0;
        else
            st->hf_f = sat32(st->hf_f + ((sat32(abs64((int64_t)hf - st->hf_ref)) - (int64_t)st->hf_f) >> p->hf_k));
    }
    if (p->w_max && w_abs > (uint32_t)p->w_max + (uint32_t)st->w_catch) /* both below 2^31 */
        return FW_FAULT_OVERSPEED;
    if (p->emf_tol && sat32(abs64(st->emf_d) + abs64(st->emf_q)) > p->emf_tol + (((int64_t)w_abs * p->psi_rel) >> 32))
        return FW_FAULT_LOCK_LOSS;
    if (p->track_tol && st->track_f > p->track_tol)
        return FW_FAULT_TRACKING;
    if ((p->ovl_n && st->ovl_n >= p->ovl_n) || (p->ovl_m && st->ovl_e >= p->ovl_m)
        || (p->ld_max && abs64(st->ld_f) > p->ld_max))
        return FW_FAULT_OVERLOAD;
    if (p->hf_tol && st->hf_f > (((int64_t)st->hf_ref * p->hf_tol) >> 16))
        return FW_FAULT_HF_RESPONSE;
    return FW_FAULT_NONE;
}

/* protection.dc_link_check: one period of the dc-link check (every mode but FAULT) */
int32_t fw_dc_link_check(struct fw_state *st, const struct fw_prot_params *p, uint32_t vdc)
{
    if (!p->vdc_n)
        return FW_FAULT_NONE;
    st->vdc_lo_n = count_while(st->vdc_lo_n, (int64_t)vdc < p->vdc_lo);
    st->vdc_hi_n = count_while(st->vdc_hi_n, (int64_t)vdc > p->vdc_hi);
    if (st->vdc_lo_n >= p->vdc_n)
        return FW_FAULT_UNDERVOLTAGE;
    if (st->vdc_hi_n >= p->vdc_n)
        return FW_FAULT_OVERVOLTAGE;
    return FW_FAULT_NONE;
}

/* protection.frozen_check: one RUN period of the sensor check (lane A / B frozen in a window of at least frz_min
 * samples, frz_n periods in a row) */
STEP_INLINE int32_t frozen_check(struct fw_state *st, const struct fw_prot_params *p, uint32_t frozen,
                                 uint32_t n_samples)
{
    const int32_t n = p->frz_n;
    int32_t a, b;

    if (!n)
        return FW_FAULT_NONE;
    if ((int64_t)n_samples < p->frz_min) /* too few samples: the window does not count */
        frozen = 0;
    /* count_while written out (0 <= counts <= OVL_CAP): this form is 128 bytes, one 32-byte line less in the ACC=0
     * image than with the calls, whose RAM is short of stack (firmware/link.ld) */
    a = (frozen & HFI_REGS__WIN_ADC__FROZEN_A_bm) ? st->frz_a + (st->frz_a < OVL_CAP) : 0;
    b = (frozen & HFI_REGS__WIN_ADC__FROZEN_B_bm) ? st->frz_b + (st->frz_b < OVL_CAP) : 0;
    st->frz_a = a;
    st->frz_b = b;
    return a >= n || b >= n ? FW_FAULT_SENSOR : FW_FAULT_NONE;
}

int32_t fw_frozen_check(struct fw_state *st, const struct fw_prot_params *p, uint32_t frozen, uint32_t n_samples)
{
    return frozen_check(st, p, frozen, n_samples);
}

/* protection.hf_learn: one CONVERGE period of the HF response check's reference. Not inlined: start-up code,
 * outside the steps' working set in the instruction cache (firmware/link.ld). */
__attribute__((noinline)) void fw_hf_learn(struct fw_state *st, const struct fw_prot_params *p, int32_t gamma_d)
{
    if (p->hf_tol)
        st->hf_ref = sat32(st->hf_ref + (((int64_t)gamma_d - st->hf_ref) >> p->hf_k));
}

/* Firmware._applied_dq: under the fcs_mpc law, the window's applied voltage in the frame active in it: VECTOR for
 * three quarters, the state before for the first (state voltages below 2^15: the sums and products are small).
 * Not inlined, like fcs_outputs: the 003 method's code lies with its own (firmware/link.ld). */
static __attribute__((noinline)) void applied_dq(const struct fw_state *st, const struct fw_window *win, const struct fw_outputs *now,
                       int32_t *v_d, int32_t *v_q)
{
    int32_t a0, b0, a1, b1;
    int64_t d, q;

    fw_state_voltage(st->vec_before, &a0, &b0);
    fw_state_voltage(win->vector, &a1, &b1);
    park64((a0 + 3 * a1) >> 2, (b0 + 3 * b1) >> 2, now->sin, now->cos, &d, &q);
    *v_d = (int32_t)d;
    *v_q = (int32_t)q;
}

/* protection.FAULT_NAMES */
const char *fw_fault_name(int32_t code)
{
    static const char *const names[FW_FAULTS] = {"none", "overcurrent", "overspeed", "lock_loss", "current_tracking",
                                                 "overload", "hardware", "ident", "hf_response",
                                                 "undervoltage", "overvoltage", "sensor"};

    return code >= 0 && code < FW_FAULTS ? names[code] : "?";
}

/* Firmware._restart: fw_init but the fault code, the restart count and the output history. Not inlined: it runs
 * only after a fault, and fw_step's code stays within the instruction cache's working set (firmware/link.ld). */
static __attribute__((noinline)) void restart(struct fw_state *st, const struct fw_params *p)
{
    int32_t fault = st->fault, restarts = st->restarts + 1, at = st->hist_at;
    struct fw_outputs history[3]; /* the ring: one copy each way (the smaller code) */

    memcpy(history, st->hist, sizeof history);
    fw_init(st, p);
    memcpy(st->hist, history, sizeof history);
    st->hist_at = at;
    st->fault = fault;
    st->restarts = restarts;
}

/* Firmware._trip: FAULT with the code; the active short circuit above w_asc under the FOC law. It runs once, at a
 * fault: out of line in the accelerated build, where its four call sites in fw_step would each carry a copy on the
 * 000 step's cache lines (tests/test_fw_layout.py: 8 bytes to spare); inlined in the ACC=0 build, whose limit is
 * the RAM left for the stack, not the cache (the copies cost 32 bytes less than a function of its own there). */
#ifdef FW_ACC
static __attribute__((noinline)) void trip(struct fw_state *st, const struct fw_params *p, int32_t code)
#else
static void trip(struct fw_state *st, const struct fw_params *p, int32_t code)
#endif
{
    st->fault = code;
    st->asc = p->prot.w_asc > 0 && abs64(fw_lowpass_out(st->speed_f)) > p->prot.w_asc && p->law == FW_LAW_FOC_PWM;
    next_mode(st, FW_FAULT);
}

/* Firmware.step: self.n += 1. n saturates at INT32_MAX where the golden int keeps counting: only in
 * RUN, FIXED and FAULT (the start-up states leave at n <= their s32 window count), after 2^31 - 1
 * windows, and n is a diagnostic there. */
static void count_window(struct fw_state *st)
{
    if (st->n < INT32_MAX)
        st->n++;
}

/* abs(i) > i_trip of Firmware.step, for every s32 pair: |i| as uint32_t (abs(INT32_MIN) = 2^31 does not
 * fit int32); a negative i_trip is exceeded by every |i|. */
static int over_trip(int32_t i, int32_t i_trip)
{
    uint32_t mag = i < 0 ? 0u - (uint32_t)i : (uint32_t)i;

    return i_trip < 0 || mag > (uint32_t)i_trip;
}

/* Firmware._estimate: the low slot while it is in charge, the high slot always. */
static void estimate(struct fw_state *st, const struct fw_params *p, const struct fw_meas *m)
{
    for (int32_t slot = FW_SLOT_LOW; slot <= FW_SLOT_HIGH; slot++) {
        int32_t method = slot_method(p, slot);

        if (method != FW_METHOD_NONE && (slot == FW_SLOT_HIGH || st->active == FW_SLOT_LOW))
            fw_methods[method].step(st, p, m, &st->est_theta[slot], &st->est_omega[slot]);
    }
}

/* Firmware._angle */
static uint32_t angle_in_use(const struct fw_state *st)
{
    if (st->active == FW_SLOT_LOW)
        return st->est_theta[FW_SLOT_LOW];
    return st->est_theta[FW_SLOT_HIGH] + (uint32_t)st->offset;
}

/* Firmware._sync: sync a slot's estimator and take its outputs. */
static void sync_slot(struct fw_state *st, const struct fw_params *p, int32_t slot, uint32_t theta, int32_t omega)
{
    fw_methods[slot_method(p, slot)].sync(st, p, theta, omega);
    st->est_theta[slot] = theta;
    st->est_omega[slot] = omega;
}

/* magnitude of an s32 as u32 (abs for every s32, INT32_MIN included) */
static inline uint32_t mag32(int32_t x)
{
    return x < 0 ? 0u - (uint32_t)x : (uint32_t)x;
}

/* protection.slip_check: one RUN period of the slip check with a high slot (gap: the low slot's angle less the high
 * slot's); the last agreement (within 45 deg, speeds of one sign both above slip_w) arms it for slip_n periods. Not
 * inlined: hand_over with the call still fits its 512 bytes (-falign-functions=64), so that no code after it moves
 * (the 003 group's cache layout, firmware/link.ld); it lies at the end of .text, with the code not named there. */
__attribute__((noinline)) int32_t fw_slip_check(struct fw_state *st, const struct fw_prot_params *p,
                                                int32_t low_in_charge, int32_t gap, int32_t omega_f, int32_t omega_hi)
{
    if (!p->slip_w)
        return FW_FAULT_NONE;
    if (!low_in_charge) {
        st->slip_left = 0;
        return FW_FAULT_NONE;
    }
    if (mag32(gap) < SLIP_AGREE && (omega_f > 0) == (omega_hi > 0) && mag32(omega_f) > (uint32_t)p->slip_w &&
        mag32(omega_hi) > (uint32_t)p->slip_w)
        st->slip_left = p->slip_n;
    else if (st->slip_left > 0)
        st->slip_left--;
    return mag32(gap) > SLIP_TRIP && st->slip_left > 0 ? FW_FAULT_LOCK_LOSS : FW_FAULT_NONE;
}

/* Firmware._hand_over (Benevieri et al. 2023, Sec. IV-F), with the watchdog (wd_delta != 0); the caller tests
 * p->high. Not inlined: a section of its own at the end of link.ld's shared group, so that fw_step's size (and with
 * it every address after it, the 003 group's cache layout) does not depend on its size. */
static __attribute__((noinline)) int32_t hand_over(struct fw_state *st, const struct fw_params *p)
{
    const int32_t omega_f = fw_lowpass_out(st->speed_f);
    const int32_t gap = (int32_t)(st->est_theta[FW_SLOT_LOW] - st->est_theta[FW_SLOT_HIGH]);
    const int32_t slip = fw_slip_check(st, &p->prot, st->active == FW_SLOT_LOW, gap, omega_f,
                                       st->est_omega[FW_SLOT_HIGH]);
    uint32_t mag = mag32(omega_f);

    if (p->wd_delta) {
        if (st->wd_n > 0) {
            st->wd_n--;
            return slip;
        }
        uint32_t hi = mag32(st->est_omega[FW_SLOT_HIGH]);
        mag = hi > mag ? hi : mag;
    }
    if (st->active == FW_SLOT_LOW) {
        int wrong = p->wd_delta && mag32(gap) > p->wd_delta;

        if (mag > (uint32_t)p->w_up) {
            st->active = FW_SLOT_HIGH;
            st->offset = wrong ? 0 : gap;
        } else if (wrong && mag > (uint32_t)p->wd_speed) {
            st->active = FW_SLOT_HIGH;
            st->offset = 0;
            st->wd_n = p->wd_hold;
        }
    } else if (mag < (uint32_t)p->w_down) {
        uint32_t theta = angle_in_use(st);

        st->active = FW_SLOT_LOW;
        st->w_catch = 0; /* a flying start's raised speed limit ends here */
        sync_slot(st, p, FW_SLOT_LOW, theta, st->est_omega[FW_SLOT_HIGH]);
    }
    return slip;
}

/* Firmware._decide_polarity; once per start (not inlined, like fw_hf_learn) */
static __attribute__((noinline)) void decide_polarity(struct fw_state *st, const struct fw_params *p)
{
    if (st->pol_neg > st->pol_pos) { /* the -d direction saturates: theta_hat is off by pi */
        fw_methods[p->low].turn(st, HALF_TURN);
        st->est_theta[FW_SLOT_LOW] += HALF_TURN;
        st->flipped = 1;
    }
}

/* Firmware._relax */
static void relax(struct fw_state *st, const struct fw_params *p)
{
    if (st->mode == FW_RELAX && st->n >= p->n_settle) {
        next_mode(st, FW_RUN);
        if (p->pol_mode == FW_POL_PILOT)
            sync_slot(st, p, FW_SLOT_LOW, st->est_theta[FW_SLOT_LOW], 0);
        if (p->high != FW_METHOD_NONE)
            sync_slot(st, p, FW_SLOT_HIGH, st->est_theta[FW_SLOT_LOW], st->est_omega[FW_SLOT_LOW]);
    }
}

/* Firmware._supervise_pilot (Tap et al. 2023, Sec. II-D): returns i_d* (always 0 here); *pilot = 1 and
 * *v_pilot the voltage while a pilot pulse is written. */
static int32_t supervise_pilot(struct fw_state *st, const struct fw_params *p, int32_t *pilot, int32_t *v_pilot)
{
    switch (st->mode) {
    case FW_CONVERGE:
        if (st->n >= p->n_converge)
            next_mode(st, FW_POL_POS);
        return 0;
    case FW_POL_POS:
    case FW_POL_NEG:
        if (st->n == 1 && st->mode == FW_POL_NEG)
            st->pol_pos = st->i_d;
        if (st->n >= p->n_settle + p->n_pulse) {
            next_mode(st, st->mode == FW_POL_POS ? FW_POL_NEG : FW_RELAX);
            return 0;
        }
        if (st->n >= p->n_settle) {
            *pilot = 1;
            *v_pilot = st->mode == FW_POL_POS ? p->v_pilot : -p->v_pilot;
        }
        return 0;
    default:
        if (st->mode == FW_RELAX && st->n == 1) {
            st->pol_neg = -(int64_t)st->i_d;
            decide_polarity(st, p);
        }
        relax(st, p);
        return 0;
    }
}

/* Firmware._supervise with current-pulse polarity detection (pol_mode current, the 002 method's start-up). Not
 * inlined: its code lies with the 002 method's (firmware/link.ld), outside the other methods' steps. */
static __attribute__((noinline)) int32_t supervise_pulses(struct fw_state *st, const struct fw_params *p,
                                                          const struct fw_window *win)
{
    switch (st->mode) {
    case FW_CONVERGE:
        if (st->n >= p->n_converge) {
            next_mode(st, FW_POL_POS);
            return p->i_pulse;
        }
        return 0;
    case FW_POL_POS:
        if (st->n > p->n_settle)
            st->pol_pos += win->gamma_d;
        if (st->n >= p->n_pulse) {
            next_mode(st, FW_POL_NEG);
            return -p->i_pulse;
        }
        return p->i_pulse;
    case FW_POL_NEG:
        if (st->n > p->n_settle)
            st->pol_neg += win->gamma_d;
        if (st->n >= p->n_pulse) {
            decide_polarity(st, p);
            next_mode(st, FW_RELAX);
            return 0;
        }
        return -p->i_pulse;
    default:
        relax(st, p);
        return 0;
    }
}

#ifndef FW_NO_PROBE
/* Firmware._back_emf: the q voltage that cancels the back-EMF at omega, within the current PI's limit */
static int32_t back_emf(const struct fw_params *p, int32_t omega)
{
    int64_t v = ((int64_t)omega * p->prot.psi_f) >> 32;
    int64_t lim = p->iq_pi.limit;

    return (int32_t)(v < -lim ? -lim : v > lim ? lim : v);
}

/* Firmware._probe, with the condition of its call in step (CATCH, a probe on and not done, n < PROBE_END): steps 1
 * .. PROBE_END - 1 of the flying start's probe (golden.firmware.catch_probe). Returns 1 with *out filled, 0 when
 * fw_step goes on as without a probe (off, done, or the gates were on in window 0). Out of line and placed with
 * the start-up code: fw_step's own code stays as it was (the 000 step's span, firmware/link.ld). */
static __attribute__((noinline, cold)) int probe_step(struct fw_state *st, const struct fw_params *p, int32_t i_d, int32_t i_q,
                                                      struct fw_outputs *out)
{
    const int32_t n = st->n;

    if (!p->prot.probe_min || st->probe < 0 || n >= FW_PROBE_END)
        return 0;
    if (n == 1 && (act0(st)->enable | act1(st)->enable)) { /* the gates were on (an active short circuit) */
        st->probe = -1;
        return 0;
    }
    const int32_t dx = sat32((int64_t)i_d - st->pr_x0), dy = sat32((int64_t)i_q - st->pr_y0);

    *out = reset_outputs;
    out->enable = n == 1 || n == FW_PROBE_GAP + 1; /* catch_probe.probe_enable */
    if (n == 1) {
        st->pr_x0 = i_d;
        st->pr_y0 = i_q;
    } else if (n == 2) {
        st->pr_x1 = dx;
        st->pr_y1 = dy;
    } else if (n == FW_PROBE_GAP + 2) { /* the estimate; found: the back-EMF's voltage in the frame of window G + 3 */
        st->probe = fw_probe_estimate(st->pr_x1, st->pr_y1, dx, dy, p->prot.probe_min, &st->pr_theta,
                                      &st->pr_delta) ? 1 : -1;
        if (st->probe > 0) {
            uint32_t theta_a, theta_b;
            int32_t omega;

            fw_probe_angles(st->pr_theta, st->pr_delta, &omega, &theta_a, &theta_b);
            out->v_q = back_emf(p, omega);
            st->theta_hat = theta_a; /* the angle whose sin/cos this step writes */
            fw_sincos_q15(theta_a, &out->sin, &out->cos);
        }
    }
    return 1;
}

#endif

/* Firmware._catch: after catch_n windows of CATCH, RUN on the high slot, or the standstill start; at PROBE_END a
 * probe that found the rotor starts the current-control catch from it. */
static __attribute__((noinline, cold)) void catch_end(struct fw_state *st, const struct fw_params *p)
{
#ifndef FW_NO_PROBE
    if (st->probe == 1 && st->n == FW_PROBE_END) {
        uint32_t theta_a, theta_b;
        int32_t omega;

        fw_probe_angles(st->pr_theta, st->pr_delta, &omega, &theta_a, &theta_b);
        st->probe = -1;
        st->speed_f = (int64_t)omega * 65536;                            /* omega << 16 */
        sync_slot(st, p, FW_SLOT_HIGH, theta_b, omega);
        st->id_int = 0;
        st->iq_int = (int64_t)back_emf(p, omega) * ((int64_t)1 << p->iq_pi.si);   /* << si */
    }
#endif
    if (st->n < p->prot.catch_n)
        return;
    int64_t w = abs64(fw_lowpass_out(st->speed_f));

    if (w >= p->w_down) {
        st->w_catch = (int32_t)(w < INT32_MAX ? w : INT32_MAX);
        next_mode(st, FW_RUN);
        sync_slot(st, p, FW_SLOT_HIGH, st->est_theta[FW_SLOT_HIGH], st->est_omega[FW_SLOT_HIGH]);
    } else {
        st->active = FW_SLOT_LOW;
        st->speed_f = 0;
        next_mode(st, FW_CONVERGE);
    }
}

/* Firmware._supervise: the start-up state machine; returns i_d* (its i_q* is always 0). */
static int32_t supervise(struct fw_state *st, const struct fw_params *p, const struct fw_window *win, int32_t *pilot,
                         int32_t *v_pilot)
{
    if (st->mode == FW_CATCH) { /* i_d* 0; in the second half, spinning, the estimator's (golden: after _catch) */
        catch_end(st, p);
        return 2 * (int64_t)st->n > p->prot.catch_n && abs64(fw_lowpass_out(st->speed_f)) >= p->w_down
                   ? fw_methods[slot_method(p, st->active)].i_d(p) : 0;
    }
    if (p->pol_mode == FW_POL_PILOT)
        return supervise_pilot(st, p, pilot, v_pilot);
    if (p->pol_mode == FW_POL_NONE) { /* a reluctance machine: CONVERGE goes straight to RELAX */
        if (st->mode == FW_CONVERGE && st->n >= p->n_converge)
            next_mode(st, FW_RELAX);
        relax(st, p);
        /* magnetized as the estimator asks; in RUN run_refs sets i_d*, so no indirect call there (golden: the value
         * returned in RUN is unused) */
        return st->mode == FW_RUN ? 0 : fw_methods[slot_method(p, st->active)].i_d(p);
    }
    return supervise_pulses(st, p, win);
}

/* Firmware._frozen: pilot polarity detection steps no estimator in POL_POS, POL_NEG and RELAX. */
static int frozen(const struct fw_state *st, const struct fw_params *p)
{
    return p->pol_mode == FW_POL_PILOT && (st->mode == FW_POL_POS || st->mode == FW_POL_NEG || st->mode == FW_RELAX);
}

/* Firmware._injecting: whether the outputs of this step carry the injection. */
static int injecting(const struct fw_state *st, const struct fw_params *p)
{
    if (st->mode == FW_FIXED)
        return 1;
    if (p->pol_mode == FW_POL_PILOT && (st->mode == FW_POL_POS || st->mode == FW_POL_NEG))
        return 0;
    return fw_method_injects[slot_method(p, st->active)] != FW_INJ_NONE;
}

/* Whether fw_step can read win->gamma or win->gamma_d with these parameters (main.c reads GAMMA and GAMMA_D only
 * then, two register reads across the clock crossing, about 22 CPU clocks per period): only the square-wave
 * response does, in the estimator that injects it (sqw_bangbang), the HF response check and its learning (both
 * while that injection is on), the current-pulse polarity detection and the identification program. */
int fw_reads_gamma(const struct fw_state *st, const struct fw_params *p)
{
    int uses = fw_method_injects[slot_method(p, FW_SLOT_LOW)] == FW_INJ_SQW_D ||
               fw_method_injects[slot_method(p, FW_SLOT_HIGH)] == FW_INJ_SQW_D || p->pol_mode == FW_POL_CURRENT;
#ifndef FW_NO_IDENT
    uses = uses || st->ident != 0;
#else
    (void)st;
#endif
    return uses;
}

/* Firmware._square_wave_on: the square wave on d_hat was on for the whole window (the estimator in charge injects
 * it, the register sets active in the window and in the one before both with V_H != 0). */
static int square_wave_on(const struct fw_state *st, const struct fw_params *p)
{
    return fw_method_injects[slot_method(p, st->active)] == FW_INJ_SQW_D && act0(st)->v_h != 0 && prev_out(st)->v_h != 0;
}

/* Firmware._feedback: the window means through the notch (input saturated to FW_NOTCH_BITS), if on. */
static void feedback(struct fw_state *st, const struct fw_params *p, int32_t *i_d, int32_t *i_q)
{
    if (!p->notch_on)
        return;
    fw_biquad_step(&st->nd, sat_s32(*i_d, FW_NOTCH_BITS), &p->notch);
    fw_biquad_step(&st->nq, sat_s32(*i_q, FW_NOTCH_BITS), &p->notch);
    *i_d = (int32_t)round_shr64(st->nd.y1, FW_BIQUAD_Y_FRAC);
    *i_q = (int32_t)round_shr64(st->nq.y1, FW_BIQUAD_Y_FRAC);
}

/* golden.firmware.load_observer.load_obs_step: the speed loop's load-torque observer, the same operations in
 * the same order. |g sat(.)| < 2^62 and |shr(l1 e, 8)| < 2^55: their sum is exact in int64; the sums with w and
 * i_l saturate (sat_add64), and i_l is then clamped to +-(limit << 32) <= 2^63 - 2^32 as golden's exact sum. Not
 * inlined: only the 003 scenarios turn it on, and its code lies with the 003 method's (firmware/link.ld). */
static __attribute__((noinline)) void fw_lobs_step(struct fw_state *st, const struct fw_lobs_params *lp, int32_t omega, int32_t limit)
{
    int32_t e = sat32((int64_t)omega - (st->lobs_w >> FW_LOBS_W_FRAC));
    int32_t di = sat32((int64_t)st->i_s_cmd - (st->lobs_i >> FW_LOBS_I_FRAC));
    st->lobs_w = sat_add64(st->lobs_w, (int64_t)lp->g * di + (((int64_t)lp->l1 * e) >> 8));
    int64_t lim = (int64_t)limit << FW_LOBS_I_FRAC;
    int64_t i_l = sat_add64(st->lobs_i, -(((int64_t)lp->l2g * e) >> 8));
    st->lobs_i = i_l < -lim ? -lim : i_l > lim ? lim : i_l;
}

/* Firmware._run_refs: the speed PI every speed_div periods (plus the load observer's current, if on), the slew
 * limit, then MTPA (if a table is given). */
static void run_refs(struct fw_state *st, const struct fw_params *p, int32_t speed_ref, int32_t *i_d_ref,
                     int32_t *i_q_ref)
{
    if (st->speed_cnt == 0) {
        int32_t omega = fw_lowpass_out(st->speed_f);
        int32_t u = pi_step(&st->speed_int, speed_ref, omega, &p->speed_pi);
        if (p->lobs.g != 0) {
            int32_t lim = p->speed_pi.limit;
            fw_lobs_step(st, &p->lobs, omega, lim);
            int64_t v = (int64_t)u + (st->lobs_i >> FW_LOBS_I_FRAC);
            u = (int32_t)(v < -lim ? -lim : v > lim ? lim : v);
        }
        st->i_s_ref = u;
    }
    st->speed_cnt = st->speed_cnt + 1 < p->speed_div ? st->speed_cnt + 1 : 0;
    if (p->i_slew > 0) { /* |i_s_cmd| <= 2^31, i_slew <= 2^30: the bounds in int64 */
        int64_t lo = (int64_t)st->i_s_cmd - p->i_slew, hi = (int64_t)st->i_s_cmd + p->i_slew;
        st->i_s_cmd = (int32_t)(st->i_s_ref < lo ? lo : st->i_s_ref > hi ? hi : st->i_s_ref);
    } else {
        st->i_s_cmd = st->i_s_ref;
    }
    int32_t i_d_est = fw_methods[slot_method(p, st->active)].i_d(p);
    if (p->mtpa_len == 0) {
        *i_d_ref = i_d_est;
        *i_q_ref = st->i_s_cmd;
        return;
    }
    int32_t i_d, i_q;
    uint32_t mag = st->i_s_cmd < 0 ? 0u - (uint32_t)st->i_s_cmd : (uint32_t)st->i_s_cmd;
    mtpa_lookup(mag, p->mtpa_shift, p->mtpa_len, p->mtpa_id, p->mtpa_iq, &i_d, &i_q);
    *i_d_ref = i_d < i_d_est ? i_d : i_d_est;
    *i_q_ref = st->i_s_cmd < 0 ? -i_q : i_q;
}

/* Firmware._dtc_refs: the currents written to I_D_REF / I_Q_REF (read by the dead-time compensation only),
 * plus the rotating injection's predicted HF current in the window of use (hf_dtc <= 2^15: products < 2^31). */
static void dtc_refs(const struct fw_params *p, int32_t i_d_ref, int32_t i_q_ref, int32_t v_h, int32_t s_i, int32_t c_i,
                     struct fw_outputs *out)
{
    if (!p->inj_rot || v_h == 0) {
        out->i_d_ref = i_d_ref;
        out->i_q_ref = i_q_ref;
        return;
    }
    int32_t s_n = FX_DOT(s_i, p->inj_c2, c_i, p->inj_s2, 15, 0);
    int32_t c_n = FX_CROSS(c_i, p->inj_c2, s_i, p->inj_s2, 15, 0);
    int32_t h_al = FX_PROD(p->hf_dtc, s_n, 15, 0), h_be = -FX_PROD(p->hf_dtc, c_n, 15, 0);
    int32_t r_d = FX_DOT(h_al, out->cos, h_be, out->sin, 15, 0);
    int32_t r_q = FX_CROSS(h_be, out->cos, h_al, out->sin, 15, 0);
    out->i_d_ref = FX_SUM(i_d_ref, r_d, 32);
    out->i_q_ref = FX_SUM(i_q_ref, r_q, 32);
}

/* Firmware._fcs_outputs: the fcs_mpc law (golden.firmware.fcs_law): the deadbeat voltage for the angle in use
 * from the flux of the estimator in charge, its constraint coefficients; i_s the current command. Not
 * inlined: the 003 method's code lies with its own, outside the other methods' steps (firmware/link.ld). */
static __attribute__((noinline)) void fcs_outputs(struct fw_state *st, const struct fw_params *p, const struct fw_window *win, int32_t i_s,
                        struct fw_outputs *out)
{
    struct fw_est_flux f = {0, 0, 0, 0, 0};
    const struct fw_est_ops *ops = &fw_methods[slot_method(p, st->active)];
    int32_t v_d, v_q;

    if (ops->flux)
        ops->flux(st, &f);
    fw_deadbeat_voltage(&p->fcs, f.psi_al, f.psi_be, win->top_ia, win->top_ib, st->vec_before, win->vector,
                        win->vector_next, st->theta_hat, st->est_omega[st->active], i_s, &v_d, &v_q, &out->sin,
                        &out->cos);
    st->vec_before = win->vector;
    out->v_d = v_d;
    out->v_q = v_q;
    out->v_h = 0;
    out->enable = 1;
    out->i_d_ref = 0;
    out->i_q_ref = 0;
    out->fcs_a1 = f.fcs_a1;
    out->fcs_a2 = f.fcs_a2;
    out->fcs_phi_min = p->fcs.phi_min;
    out->fcs_constrain = f.constrain;
}

#ifndef FW_NO_IDENT
/* Firmware._ident_outputs: one window of the identification program (st->ident); gates off (the reset values)
 * when the program has ended (DONE) or failed (FAULT, FW_FAULT_IDENT). Not inlined: fw_step's own code (the
 * instruction cache's working set in operation) stays as without the executor. */
static __attribute__((noinline)) void ident_outputs(struct fw_state *st, const struct fw_params *p,
                                                    const struct fw_window *win, int32_t i_d, int32_t i_q,
                                                    struct fw_outputs *out)
{
    struct fw_ident_state *id = &st->ident->s;

    *out = reset_outputs;
    ident_measure(id, &st->ident->p, i_d, i_q, win->gamma_d, win->gamma, act0(st), prev_out(st));
    if (id->failed) {
        trip(st, p, FW_FAULT_IDENT);
        return;
    }
    if (id->done) {
        next_mode(st, FW_DONE);
        return;
    }
    ident_refs(st, &st->ident->p, i_d, i_q, out);
    st->theta_hat = id->theta;
    st->i_d_ref = id->ref_d;
    st->i_q_ref = id->ref_q;
    fw_sincos_q15(st->theta_hat, &out->sin, &out->cos);
    out->enable = 1;
    out->i_d_ref = st->i_d_ref;
    out->i_q_ref = st->i_q_ref;
}
#endif /* FW_NO_IDENT */

/* golden.firmware.supervisor.Firmware.step: one window interrupt, same state updates in the same order. */
void fw_step(struct fw_state *st, const struct fw_params *p, const struct fw_window *win, int32_t speed_ref,
             struct fw_outputs *out)
{
    int32_t i_d, i_q, i_d_ref = 0, i_q_ref = 0, pilot = 0, v_pilot = 0, s_inj = 0, c_inj = 32767, i_d_prev, i_q_prev;

    if (st->mode == FW_FAULT && st->restarts < p->prot.restarts && st->n >= p->prot.restart_n &&
        st->fault != FW_FAULT_HARDWARE) /* a hardware trip is not retried: its latch holds the gates off */
        restart(st, p);
    i_d_prev = st->i_d_ref; /* the references of the last period */
    i_q_prev = st->i_q_ref;

    if (p->inj_rot)
        fw_sincos_q15(win->inj_phase, &s_inj, &c_inj);
    fw_window_means(&st->mean_div, win->sum_id, win->sum_iq, win->n_samples, &i_d, &i_q);
    st->i_d = i_d;
    st->i_q = i_q;
    count_window(st);
    if (st->mode != FW_FAULT && win->status != 0)
        trip(st, p, FW_FAULT_HARDWARE);
    else if (st->mode != FW_FAULT && (over_trip(i_d, p->i_trip) || over_trip(i_q, p->i_trip)))
        trip(st, p, FW_FAULT_OVERCURRENT);
    if (st->mode != FW_FAULT) {
        int32_t dc = fw_dc_link_check(st, &p->prot, win->vdc);

        if (dc != FW_FAULT_NONE)
            trip(st, p, dc);
    }
#ifndef FW_NO_IDENT
    if (st->mode == FW_IDENT || st->mode == FW_DONE) { /* self-commissioning, before everything else */
        if (st->mode == FW_IDENT)
            ident_outputs(st, p, win, i_d, i_q, out);
        else
            *out = reset_outputs;
        push_outputs(st, out);
        return;
    }
#endif
#ifndef FW_NO_PROBE
    if (st->mode == FW_CATCH && probe_step(st, p, i_d, i_q, out))
        goto emit;
#endif
    if (st->mode != FW_FIXED && st->mode != FW_FAULT) {
        struct fw_meas m;
        int hf_on;

        m.win = win;
        m.i_d = i_d;
        m.i_q = i_q;
        m.sin = act0(st)->sin;
        m.cos = act0(st)->cos;
        window_voltage(act0(st), prev_out(st), &m.v_al, &m.v_be);
        m.inj_sin = s_inj;
        m.inj_cos = c_inj;
        if (p->inj_rot) {
            int32_t a, b;

            fw_injection_voltage(act0(st)->v_h, prev_out(st)->v_h, m.inj_sin, m.inj_cos, p->inj_cd, p->inj_sd, &a, &b);
            m.v_al = FX_SUM(m.v_al, a, 32);
            m.v_be = FX_SUM(m.v_be, b, 32);
        }
        hf_on = square_wave_on(st, p);
        if (st->mode == FW_CONVERGE && hf_on)
            fw_hf_learn(st, &p->prot, win->gamma_d);
        if (!frozen(st, p))
            estimate(st, p, &m);
        if (st->active == FW_SLOT_HIGH)
            st->offset -= (int32_t)(((int64_t)st->offset * p->merge) >> 16);
        st->speed_f = fw_lowpass_step(st->speed_f, st->est_omega[st->active], p->speed_lp);
        i_d_ref = supervise(st, p, win, &pilot, &v_pilot);
        if (st->mode == FW_RUN) {
            int32_t code, slip = FW_FAULT_NONE;

            if (p->high != FW_METHOD_NONE)
                slip = hand_over(st, p);
            run_refs(st, p, speed_ref, &i_d_ref, &i_q_ref);
            int32_t v_d = act0(st)->v_d, v_q = act0(st)->v_q;

            if (p->law == FW_LAW_FCS_MPC && p->prot.emf_tol != 0) /* only the lock check reads it */
                applied_dq(st, win, act0(st), &v_d, &v_q);
            const int32_t frozen = frozen_check(st, &p->prot, win->frozen, win->n_samples);   /* the cause first */

            code = fw_protect_step(st, &p->prot, v_d, v_q, i_d, i_q, i_d_prev, i_q_prev,
                                   fw_lowpass_out(st->speed_f), speed_ref, abs64(st->i_s_ref) >= p->speed_pi.limit,
                                   hf_on, win->gamma_d);
            if (code == FW_FAULT_NONE)
                code = slip;
            if (frozen != FW_FAULT_NONE || code != FW_FAULT_NONE)
                trip(st, p, frozen != FW_FAULT_NONE ? frozen : code);
        }
        st->theta_hat = angle_in_use(st);
    }
    st->i_d_ref = i_d_ref;
    st->i_q_ref = i_q_ref;
    feedback(st, p, &i_d, &i_q);
    if (st->mode == FW_FAULT) {
        st->id_int = 0;
        st->iq_int = 0;
        *out = reset_outputs; /* FAULT: the reset values, gates off */
        if (st->asc) { /* the active short circuit: zero voltage, outputs on */
            fw_sincos_q15(st->theta_hat, &out->sin, &out->cos);
            out->enable = 1;
        }
    } else if (p->law == FW_LAW_FCS_MPC) {
        fcs_outputs(st, p, win, i_q_ref, out);
    } else {
        if (pilot) { /* pilot voltage: current control off */
            out->v_d = v_pilot;
            out->v_q = 0;
            st->id_int = 0;
            st->iq_int = 0;
        } else {
            out->v_d = pi_step(&st->id_int, i_d_ref, i_d, &p->id_pi);
            out->v_q = pi_step(&st->iq_int, i_q_ref, i_q, &p->iq_pi);
        }
        out->v_h = injecting(st, p) ? p->v_h : 0;
        fw_sincos_q15(st->theta_hat, &out->sin, &out->cos);
        out->enable = 1;
        out->fcs_a1 = out->fcs_a2 = out->fcs_phi_min = out->fcs_constrain = 0;
        dtc_refs(p, i_d_ref, i_q_ref, out->v_h, s_inj, c_inj, out);
    }
#ifndef FW_NO_PROBE
emit:
#endif
    push_outputs(st, out); /* the voltages applied: the estimators' and checks' */
    if (p->ff_nom && p->law == FW_LAW_FOC_PWM)
        fw_dc_feedforward(out, win->vdc, p->ff_nom, p->ff_lo, p->ff_hi);
}
