/* control.c - the firmware's control algorithms (docs/spec.md, section 5), freestanding C11.
 *
 * Every function is the bit-exact twin of the golden model named in its comment and performs the
 * integer operations its docstring prescribes for C, in the same order: int32_t/uint32_t/int64_t only,
 * arithmetic right shifts of signed values (GCC), wrapping unsigned adds for binary angles, casts to
 * int32_t for angle differences (golden.fixed.wrap), `/` for golden.fixed.c_div. No floating point,
 * no libc, no global mutable state (the only static data is the generated CORDIC table).
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

#include "fw_cordic_table.h"
#include "fw_methods.h"

#define HALF_TURN 0x80000000u /* golden.firmware.supervisor.HALF_TURN: half an electrical turn */

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

/* min(max(x, -lim), lim) for lim >= 0 (the clamps of golden.firmware.pi.pi_step) */
static int64_t clamp_sym(int64_t x, int64_t lim)
{
    return x > lim ? lim : x < -lim ? -lim : x;
}

/* ---- blocks ------------------------------------------------------------------------------------ */

/* golden.firmware.means.window_means: c_div of the window sums by N (u16, so n32 >= 0 and
 * INT32_MIN / -1 cannot occur); 0 if N == 0. */
void fw_window_means(int32_t sum_id, int32_t sum_iq, uint32_t n, int32_t *i_d, int32_t *i_q)
{
    int32_t n32 = (int32_t)n;

    *i_d = n32 ? sum_id / n32 : 0;
    *i_q = n32 ? sum_iq / n32 : 0;
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
    s->omega = sat32((((int64_t)kp * e) >> 16) + (integ >> 24));
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
 * Always inlined: fw_step runs it three times, and the call costs about 10 % of its cycles. */
static inline __attribute__((always_inline)) int32_t pi_step(int64_t *integ, int32_t ref, int32_t meas,
                                                             const struct fw_pi_params *p)
{
    int32_t e, si = p->si, limit = p->limit;

    if (__builtin_sub_overflow(ref, meas, &e))                           /* 1 */
        e = ref < 0 ? INT32_MIN : INT32_MAX;
    e = opaque_s32(e);
    int64_t prop = shr64((int64_t)p->kp * e, p->sp);                     /* 2 */
    int64_t lim_i = (int64_t)((uint64_t)(uint32_t)limit << si);          /* limit << si, limit >= 1 */
    int64_t cand = clamp_sym(*integ + (int64_t)p->ki * e, lim_i);        /* 3 */
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

/* golden.fixed.sat(x, bits) for 1 <= bits <= 32 of an int64 */
static int64_t sat_bits(int64_t x, int bits)
{
    int64_t hi = ((int64_t)1 << (bits - 1)) - 1;

    return x > hi ? hi : x < -hi - 1 ? -hi - 1 : x;
}

/* golden.fixed.round_shr(x, n) of an int64, n >= 1 */
static int64_t round_shr64(int64_t x, int n)
{
    return (x + ((int64_t)1 << (n - 1))) >> n;
}

/* golden.firmware.estimator.inv_park */
static void inv_park(int32_t d, int32_t q, int32_t s, int32_t c, int32_t *al, int32_t *be)
{
    *al = (int32_t)sat_bits(round_shr64((int64_t)d * c - (int64_t)q * s, 15), 32);
    *be = (int32_t)sat_bits(round_shr64((int64_t)d * s + (int64_t)q * c, 15), 32);
}

/* golden.firmware.estimator.window_voltage */
void fw_window_voltage(const struct fw_outputs *now, const struct fw_outputs *before, int32_t *v_al, int32_t *v_be)
{
    int32_t a1, b1, a0, b0;

    inv_park(now->v_d, now->v_q, now->sin, now->cos, &a1, &b1);
    inv_park(before->v_d, before->v_q, before->sin, before->cos, &a0, &b0);
    *v_al = (int32_t)round_shr64(3 * (int64_t)a1 + a0, 2);
    *v_be = (int32_t)round_shr64(3 * (int64_t)b1 + b0, 2);
}

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

/* ---- estimator sqw_bangbang (golden.firmware.sqw_bangbang) ------------------------------------------ */

void fw_sqw_step(struct fw_state *st, const struct fw_params *p, const struct fw_meas *m, uint32_t *theta,
                 int32_t *omega)
{
    struct fw_sqw_state *e = &st->sqw;

    if (e->hold > 0) {
        e->hold--;
        e->theta += (uint32_t)e->pll.omega;
    } else {
        /* Benevieri et al. 2023, Fig. 1: bang-bang on gamma, integrated to theta_hat; PLL -> speed */
        e->theta = fw_bangbang_step(e->theta, m->win->gamma, p->sqw.k_bb);
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
    (void)p;
    return 0;
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
    /* Ortega et al. 2011: correction along eta towards |eta| = psi_f (normalised gradient) */
    int64_t g = ((int64_t)rp->k_c * fw_rfo_correction(rp->psi_f, mag)) >> 16;
    e->x_al = (int32_t)sat_bits(e->x_al + dx_al + (((int64_t)eta_al * g) >> 16), 32);
    e->x_be = (int32_t)sat_bits(e->x_be + dx_be + (((int64_t)eta_be * g) >> 16), 32);
    fw_pll_step(&e->pll, ang, rp->pll_kp, rp->pll_ki);
    e->omega = e->pll.omega;
    e->theta = ang + 2u * (uint32_t)e->omega;
    *theta = e->theta;
    *omega = e->omega;
}

void fw_rfo_turn(struct fw_state *st, uint32_t delta)
{
    struct fw_rfo_state *e = &st->rfo;
    int32_t s, c;

    fw_sincos_q15(delta, &s, &c);
    int32_t x_al = (int32_t)sat_bits(round_shr64((int64_t)e->x_al * c - (int64_t)e->x_be * s, 15), 32);
    int32_t x_be = (int32_t)sat_bits(round_shr64((int64_t)e->x_al * s + (int64_t)e->x_be * c, 15), 32);
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
    e->x_al = (int32_t)sat_bits(round_shr64((int64_t)p->rfo.psi_f * c, 15) + (((int64_t)p->rfo.l_s * e->i_al) >> 16), 32);
    e->x_be = (int32_t)sat_bits(round_shr64((int64_t)p->rfo.psi_f * s, 15) + (((int64_t)p->rfo.l_s * e->i_be) >> 16), 32);
    e->pll.theta = mid + (uint32_t)omega;
    e->pll.integ = (int64_t)omega * 16777216;
    e->pll.omega = omega;
    e->theta = theta;
    e->omega = omega;
}

int32_t fw_rfo_i_d(const struct fw_params *p)
{
    return p->rfo.i_d;
}

/* golden.firmware.methods.CLASSES: the members of the plug-in interface, by method id. */
static const struct fw_est_ops fw_methods[FW_METHODS] = {
    [FW_METHOD_SQW_BANGBANG] = {fw_sqw_step, fw_sqw_turn, fw_sqw_sync, fw_sqw_i_d},
    [FW_METHOD_RFO] = {fw_rfo_step, fw_rfo_turn, fw_rfo_sync, fw_rfo_i_d},
};

/* Whether a method's injection is on while it is in charge, by method id (generated, fw_methods.h). */
static const uint8_t fw_method_injects[FW_METHODS] = FW_METHOD_INJECTS;

/* The method id of a slot (0: none). */
static int32_t slot_method(const struct fw_params *p, int32_t slot)
{
    return slot == FW_SLOT_LOW ? p->low : p->high;
}

/* ---- supervisor (golden.firmware.supervisor.Firmware) ------------------------------------------- */

static const struct fw_outputs reset_outputs = {0, 0, 0, 0, 32767, 0, 0, 0}; /* RESET_OUTPUTS */

/* Firmware.__init__ / __post_init__: everything 0, CONVERGE; FIXED at fixed_angle if enabled. */
void fw_init(struct fw_state *st, const struct fw_params *p)
{
    static const struct fw_state zero;

    *st = zero;
    st->mode = p->fixed_enable ? FW_FIXED : FW_CONVERGE;
    st->theta_hat = p->fixed_enable ? p->fixed_angle : 0u;
    st->act[0] = st->act[1] = st->prev = reset_outputs;
}

/* Firmware._next */
static void next_mode(struct fw_state *st, int32_t mode)
{
    st->mode = mode;
    st->n = 0;
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

/* Firmware._hand_over (Benevieri et al. 2023, Sec. IV-F) */
static void hand_over(struct fw_state *st, const struct fw_params *p)
{
    if (p->high == FW_METHOD_NONE)
        return;
    int32_t w = fw_lowpass_out(st->speed_f);
    uint32_t mag = w < 0 ? 0u - (uint32_t)w : (uint32_t)w;   /* abs(omega_f) for every s32 */

    if (st->active == FW_SLOT_LOW && mag > (uint32_t)p->w_up) {
        st->active = FW_SLOT_HIGH;
        st->offset = (int32_t)(st->est_theta[FW_SLOT_LOW] - st->est_theta[FW_SLOT_HIGH]);
    } else if (st->active == FW_SLOT_HIGH && mag < (uint32_t)p->w_down) {
        uint32_t theta = angle_in_use(st);

        st->active = FW_SLOT_LOW;
        fw_methods[p->low].sync(st, p, theta, st->est_omega[FW_SLOT_HIGH]);
        st->est_theta[FW_SLOT_LOW] = theta;
        st->est_omega[FW_SLOT_LOW] = st->est_omega[FW_SLOT_HIGH];
    }
}

/* Firmware._supervise: the start-up state machine; returns i_d* (its i_q* is always 0). */
static int32_t supervise(struct fw_state *st, const struct fw_params *p, const struct fw_window *win)
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
            if (st->pol_neg > st->pol_pos) { /* the -d direction saturates: theta_hat is off by pi */
                fw_methods[p->low].turn(st, HALF_TURN);
                st->est_theta[FW_SLOT_LOW] += HALF_TURN;
                st->flipped = 1;
            }
            next_mode(st, FW_RELAX);
            return 0;
        }
        return -p->i_pulse;
    case FW_RELAX:
        if (st->n >= p->n_settle) {
            next_mode(st, FW_RUN);
            if (p->high != FW_METHOD_NONE) {
                fw_methods[p->high].sync(st, p, st->est_theta[FW_SLOT_LOW], st->est_omega[FW_SLOT_LOW]);
                st->est_theta[FW_SLOT_HIGH] = st->est_theta[FW_SLOT_LOW];
                st->est_omega[FW_SLOT_HIGH] = st->est_omega[FW_SLOT_LOW];
            }
        }
        return 0;
    default:
        return 0;
    }
}

/* golden.firmware.supervisor.Firmware.step: one window interrupt, same state updates in the same order. */
void fw_step(struct fw_state *st, const struct fw_params *p, const struct fw_window *win, int32_t speed_ref,
             struct fw_outputs *out)
{
    int32_t i_d, i_q, i_d_ref = 0, i_q_ref = 0;

    fw_window_means(win->sum_id, win->sum_iq, win->n_samples, &i_d, &i_q);
    st->i_d = i_d;
    st->i_q = i_q;
    count_window(st);
    if (st->mode != FW_FAULT && (over_trip(i_d, p->i_trip) || over_trip(i_q, p->i_trip)))
        next_mode(st, FW_FAULT);
    if (st->mode != FW_FIXED && st->mode != FW_FAULT) {
        struct fw_meas m;

        m.win = win;
        m.i_d = i_d;
        m.i_q = i_q;
        m.sin = st->act[0].sin;
        m.cos = st->act[0].cos;
        fw_window_voltage(&st->act[0], &st->prev, &m.v_al, &m.v_be);
        estimate(st, p, &m);
        if (st->active == FW_SLOT_HIGH)
            st->offset -= (int32_t)(((int64_t)st->offset * p->merge) >> 16);
        st->speed_f = fw_lowpass_step(st->speed_f, st->est_omega[st->active], p->speed_lp);
        i_d_ref = supervise(st, p, win);
        if (st->mode == FW_RUN) {
            hand_over(st, p);
            i_d_ref = fw_methods[slot_method(p, st->active)].i_d(p);
            i_q_ref = pi_step(&st->speed_int, speed_ref, fw_lowpass_out(st->speed_f), &p->speed_pi);
        }
        st->theta_hat = angle_in_use(st);
    }
    st->i_d_ref = i_d_ref;
    st->i_q_ref = i_q_ref;
    if (st->mode == FW_FAULT) {
        st->id_int = 0;
        st->iq_int = 0;
        *out = reset_outputs; /* FAULT: the reset values, gates off */
    } else {
        out->v_d = pi_step(&st->id_int, i_d_ref, i_d, &p->id_pi);
        out->v_q = pi_step(&st->iq_int, i_q_ref, i_q, &p->iq_pi);
        int32_t method = slot_method(p, st->active);
        out->v_h = st->mode == FW_FIXED || fw_method_injects[method] ? p->v_h : 0;
        fw_sincos_q15(st->theta_hat, &out->sin, &out->cos);
        out->enable = 1;
        out->i_d_ref = i_d_ref;
        out->i_q_ref = i_q_ref;
    }
    st->prev = st->act[0];
    st->act[0] = st->act[1];
    st->act[1] = *out;
}
