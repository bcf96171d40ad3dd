/* hfi-sensorless plant: PMSM / SyRM machine, 2-level inverter with dead time, current sensors, ADC.
 *
 * One library shared by every backend (golden closed loop, Verilator co-simulation). The model and
 * its assumptions are documented in docs/plant.md; the API and every parameter in plant_api.h.
 *
 * Integration: classic RK4 on the state vector below, with steps of at most max_substep_ticks,
 * split at every gate edge, voltage step and sample instant (so no step straddles an input change).
 * The rotor angle inside a step is handled with a small-angle rotation of the step's sin/cos, so
 * one sincos() per step suffices.
 *
 * Speed (docs/plant.md, "Performance"): deriv() is inlined and so specialised for the common step in
 * which every leg conducts; one-entry memos keyed by exact arguments spare recomputing the sin/cos,
 * currents, bus voltage and load of a state several functions look at. No change of this kind alters a
 * floating-point operation: the results are the bits of the plain code.
 *
 * Build with -ffp-contract=off and without -ffast-math: results must be reproducible bit for bit.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "plant_api.h"

#define TWO_PI 6.283185307179586476925
#define SQRT3_2 0.866025403784438646764
#define INV_SQRT3 0.577350269189625764509
#define GAUSS_BLOCK 64
#define RING_CACHE 8 /* phasor rotations kept: the sample spacing and the odd intervals around edges */
#define COMMUTATION_OVERSHOOT 0.01 /* ticks past the predicted rail crossing */
#define OPEN_PHASE_TAU 10e-6       /* an open phase's current decays to 0 with this time constant [s] */

/* state vector indices */
enum { X_PSID, X_PSIQ, X_OMM, X_THM, X_VNA, X_VNB, X_VNC, X_EIN, X_ECU, X_EMECH, X_QD, X_QQ, X_TQ, X_TQ2, NX };

/* leg switch states */
enum { LEG_OFF = 0, LEG_HIGH = 1, LEG_LOW = 2, LEG_SHORT = 3 };

/* A magnetic model with its derived constants. */
struct mag_model {
    struct mag_params m;
    double inv_L_d, inv_L_q; /* MAG_LINEAR; MAG_DSAT: inv_L_q only */
    double inv_L_d0;         /* MAG_DSAT: 1/unsaturated slope of h() */
    double inv_psi_f;        /* MAG_DSAT */
    double h_psif;           /* MAG_DSAT: h(psi_f), so that i_d = 0 at psi_d = psi_f */
};


struct plant {
    const struct plant *self; /* the plant itself: a snapshot's owner (plant_restore) */
    struct plant_params p;
    double *owned;            /* copies of profile and table arrays */
    struct fault *faults_owned; /* copy of the fault list */
    struct mag_model mag;
    long long tick;
    double sub;               /* ticks of the step sequence inside advance() (0 outside) */
    double v_bus_step;        /* dc-link voltage (with ripple, without sag) during the present step */
    double x[NX];
    int gates;
    int legs[3];
    int voltage_mode;
    double v_ideal[3];
    double v_hold[3];         /* last node voltage per leg (ideal commutation at zero current) */
    uint64_t rng[4];
    uint64_t rng_vdc[4];      /* the dc-link channel's noise: a stream of its own (sens.vdc_noise_rms) */
    double gauss_buf[GAUSS_BLOCK];
    int gauss_next;
    double gauss_vdc_buf[GAUSS_BLOCK];
    int gauss_vdc_next;
    double i_end[3];          /* phase currents of the present state: the last integration step's end */
    double ring_re[3], ring_im[3]; /* ringing phasor per leg: sum of sign*exp(lambda*(t - t_edge)) */
    long long ring_tick;           /* time of the phasors */
    long long ring_dt[RING_CACHE]; /* phasor rotation over ring_dt[slot] ticks (-1: empty), */
    double ring_rot_re[RING_CACHE], ring_rot_im[RING_CACHE]; /* slot = ring_dt % RING_CACHE */
    long long shoot_through_ticks;
    int cursor_load, cursor_speed;
    double y[3];              /* sensor outputs (first-order filter of the phase currents) */
    double inv_J;             /* 1/J */
    double adc_full, adc_inv_lsb; /* 2^adc_bits, codes per ampere */
    double vdc_codes;         /* dc-link channel: codes per volt (0: no channel) */
    double filt_h, filt_decay; /* sensor filter: last step length [s] and exp(-h/tau) */
    double filt_tau;          /* sensor filter time constant [s] */
    /* One-entry memos of pure functions, keyed by their exact arguments (NaN = empty): a hit returns
     * the same bits as the computation, so results never depend on the call history. */
    double trig_th, trig_c, trig_s;            /* cos, sin of the electrical angle trig_th */
    double bus_t, bus_v;                       /* bus_voltage() at bus_t */
    double cur_psid, cur_psiq, cur_id, cur_iq; /* mag_currents() at (cur_psid, cur_psiq) */
    double load_t, load_v;                     /* load profile at load_t */
    double load_lo, load_hi, load_hold;        /* the load profile is load_hold on [load_lo, load_hi) */
    /* faults (docs/faults.md): the last onset or end applied, and the effects of the active faults */
    long long fault_tick;     /* the last fault onset or end applied (-1: none yet) */
    int sens_fault;           /* 1 once a sensor or ADC fault acts: sample() takes the slow path */
    double f_gain[3];         /* sensor gain factors */
    double f_off[3], f_rate[3]; /* sensor offset added: f_off + f_rate * t [A] */
    int f_stuck[PLANT_ADC_CHANNELS]; /* ADC code forced (-1: none) */
    int open_phase;           /* phase disconnected (-1: none) */
    int dead_switches;        /* gate bits whose switch never turns on */
    int dc_fault;             /* dc link: V * (dc_value + (1 - dc_value) exp(-(t - dc_t0)/dc_tau)) */
    double dc_value, dc_tau, dc_t0;
    double load_add;          /* load torque added [N*m] */
    int blocked;              /* rotor held: speed 0 */
};

/* quantities computed along with the derivative, for outputs */
struct aux {
    double i_d, i_q, i_abc[3], v_node[3], v_d, v_q, v_dc, torque, load_torque, omega_m;
};

/* ------------------------------------------------------------------------------------------------ */
/* random numbers: xoshiro256** seeded by splitmix64; Gaussian by Box-Muller                         */

static uint64_t splitmix64(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

static uint64_t xoshiro_next(uint64_t s[4])
{
    uint64_t result = rotl(s[1] * 5, 7) * 9;
    uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

static double uniform_open(uint64_t s[4]) /* in (0, 1) */
{
    return ((double)(xoshiro_next(s) >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

/* Standard normal numbers by Marsaglia's polar method, generated GAUSS_BLOCK at a time: first the
 * accepted points of the unit disc (a rejected candidate is overwritten, so there is no unpredictable
 * branch), then the independent log/sqrt computations, which overlap. The sequence is that of drawing
 * pairs one by one, and does not depend on when blocks are made. */
static void gauss_refill(uint64_t rng[4], double buf[GAUSS_BLOCK])
{
    double u[GAUSS_BLOCK / 2], v[GAUSS_BLOCK / 2], r2[GAUSS_BLOCK / 2];
    int n = 0;
    while (n < GAUSS_BLOCK / 2) {
        u[n] = 2.0 * uniform_open(rng) - 1.0;
        v[n] = 2.0 * uniform_open(rng) - 1.0;
        r2[n] = u[n] * u[n] + v[n] * v[n];
        n += r2[n] < 1.0 && r2[n] != 0.0; /* in the disc, 0 excluded */
    }
    for (int k = 0; k < GAUSS_BLOCK / 2; k++) {
        double m = sqrt(-2.0 * log(r2[k]) / r2[k]);
        buf[2 * k] = u[k] * m;
        buf[2 * k + 1] = v[k] * m;
    }
}

/* The current channels' stream and the dc-link channel's, each with its own generator and block. */
static inline double gauss(struct plant *p)
{
    if (p->gauss_next == GAUSS_BLOCK) {
        gauss_refill(p->rng, p->gauss_buf);
        p->gauss_next = 0;
    }
    return p->gauss_buf[p->gauss_next++];
}

static inline double gauss_vdc(struct plant *p)
{
    if (p->gauss_vdc_next == GAUSS_BLOCK) {
        gauss_refill(p->rng_vdc, p->gauss_vdc_buf);
        p->gauss_vdc_next = 0;
    }
    return p->gauss_vdc_buf[p->gauss_vdc_next++];
}

/* ------------------------------------------------------------------------------------------------ */
/* magnetic models                                                                                  */

/* x^n, n >= 0, by squaring: the product of the powers x^(2^k) of the set bits k of n, lowest first
 * (the first factor is not multiplied by 1.0, which would not change it) */
static inline double ipow(double x, int n)
{
    if (n == 0)
        return 1.0;
    while (!(n & 1)) {
        x *= x;
        n >>= 1;
    }
    double r = x;
    while (n >>= 1) {
        x *= x;
        if (n & 1)
            r *= x;
    }
    return r;
}

static void mag_init(struct mag_model *mm, const struct mag_params *m)
{
    memset(mm, 0, sizeof *mm);
    mm->m = *m;
    if (m->kind == MAG_LINEAR || m->kind == MAG_DSAT) {
        mm->inv_L_d = 1.0 / m->L_d;
        mm->inv_L_q = 1.0 / m->L_q;
    }
    if (m->kind == MAG_DSAT) {
        /* h'(psi_f) = (1 + a(S+1))/L_d0 = 1/L_d */
        mm->inv_L_d0 = 1.0 / (m->L_d * (1.0 + m->dsat_a * (m->dsat_S + 1)));
        mm->inv_psi_f = 1.0 / m->psi_f;
        mm->h_psif = m->psi_f * mm->inv_L_d0 * (1.0 + m->dsat_a);
    }
}

/* Currents from flux linkages; jac (may be NULL): di_d/dpsi_d, di_d/dpsi_q, di_q/dpsi_d, di_q/dpsi_q. */
static inline __attribute__((always_inline)) void mag_currents(const struct mag_model *mm, double psi_d,
                                                               double psi_q, double *i_d, double *i_q, double *jac)
{
    const struct mag_params *m = &mm->m;
    switch (m->kind) {
    case MAG_LINEAR:
        *i_d = (psi_d - m->psi_f) * mm->inv_L_d;
        *i_q = psi_q * mm->inv_L_q;
        if (jac) {
            jac[0] = mm->inv_L_d;
            jac[1] = jac[2] = 0.0;
            jac[3] = mm->inv_L_q;
        }
        return;
    case MAG_DSAT: {
        double rs = ipow(fabs(psi_d * mm->inv_psi_f), m->dsat_S);
        *i_d = psi_d * mm->inv_L_d0 * (1.0 + m->dsat_a * rs) - mm->h_psif;
        *i_q = psi_q * mm->inv_L_q;
        if (jac) {
            jac[0] = (1.0 + m->dsat_a * (m->dsat_S + 1) * rs) * mm->inv_L_d0;
            jac[1] = jac[2] = 0.0;
            jac[3] = mm->inv_L_q;
        }
        return;
    }
    case MAG_ALGEBRAIC: {
        double x = psi_d - m->psi_f, y = psi_q, ax = fabs(x), ay = fabs(y);
        double xS = ipow(ax, m->S), yT = ipow(ay, m->T), xU = ipow(ax, m->U), yV = ipow(ay, m->V);
        double xU2 = xU * ax * ax, yV2 = yV * ay * ay;
        double kd = m->a_dq / (m->V + 2), kq = m->a_dq / (m->U + 2);
        *i_d = (m->a_d0 + m->a_dd * xS + kd * xU * yV2) * x;
        *i_q = (m->a_q0 + m->a_qq * yT + kq * xU2 * yV) * y;
        if (jac) {
            jac[0] = m->a_d0 + m->a_dd * (m->S + 1) * xS + kd * (m->U + 1) * xU * yV2;
            jac[3] = m->a_q0 + m->a_qq * (m->T + 1) * yT + kq * (m->V + 1) * xU2 * yV;
            /* mixed second derivative of the energy a_dq/((U+2)(V+2)) |x|^(U+2) |y|^(V+2) */
            jac[1] = jac[2] = m->a_dq * xU * x * yV * y;
        }
        return;
    }
    case MAG_TABLE: {
        double fd = (psi_d - m->tab_psid0) / m->tab_dpsid, fq = (psi_q - m->tab_psiq0) / m->tab_dpsiq;
        int kd = (int)floor(fd), kq = (int)floor(fq);
        kd = kd < 0 ? 0 : (kd > m->tab_nd - 2 ? m->tab_nd - 2 : kd);
        kq = kq < 0 ? 0 : (kq > m->tab_nq - 2 ? m->tab_nq - 2 : kq);
        double u = fd - kd, w = fq - kq; /* outside the grid: linear extrapolation of the edge cell */
        for (int k = 0; k < 2; k++) {
            const double *tab = k == 0 ? m->tab_id : m->tab_iq;
            double f00 = tab[kq * m->tab_nd + kd], f10 = tab[kq * m->tab_nd + kd + 1];
            double f01 = tab[(kq + 1) * m->tab_nd + kd], f11 = tab[(kq + 1) * m->tab_nd + kd + 1];
            double val = f00 * (1 - u) * (1 - w) + f10 * u * (1 - w) + f01 * (1 - u) * w + f11 * u * w;
            *(k == 0 ? i_d : i_q) = val;
            if (jac) {
                jac[2 * k] = ((f10 - f00) * (1 - w) + (f11 - f01) * w) / m->tab_dpsid;
                jac[2 * k + 1] = ((f01 - f00) * (1 - u) + (f11 - f10) * u) / m->tab_dpsiq;
            }
        }
        return;
    }
    default: /* refused by plant_create */
        *i_d = *i_q = 0.0;
        if (jac)
            jac[0] = jac[1] = jac[2] = jac[3] = 0.0;
        return;
    }
}

void plant_mag_eval(const struct mag_params *m, double psi_d, double psi_q, double out[6])
{
    struct mag_model mm;
    mag_init(&mm, m);
    mag_currents(&mm, psi_d, psi_q, &out[0], &out[1], &out[2]);
}

/* ------------------------------------------------------------------------------------------------ */
/* profiles                                                                                         */

static inline double profile_eval(const struct profile *pr, int *cursor, double t)
{
    if (pr->n <= 0)
        return 0.0;
    int k = *cursor;
    while (k > 0 && pr->t[k] > t)
        k--;
    while (k + 1 < pr->n && pr->t[k + 1] <= t)
        k++;
    *cursor = k;
    double v;
    if (t < pr->t[0])
        v = pr->v[0];
    else if (k + 1 >= pr->n)
        v = pr->v[pr->n - 1];
    else
        v = pr->v[k] + (pr->v[k + 1] - pr->v[k]) * (t - pr->t[k]) / (pr->t[k + 1] - pr->t[k]);
    if (pr->puls_depth != 0.0)
        v *= 1.0 + pr->puls_depth * sin(TWO_PI * pr->puls_freq * t);
    return v;
}

static inline int same_bits(double a, double b)
{
    uint64_t ua, ub;
    memcpy(&ua, &a, sizeof ua);
    memcpy(&ub, &b, sizeof ub);
    return ua == ub;
}

static double tick_time(const struct plant *p, long long tick) { return (double)tick / p->p.tick_hz; }

/* dc-link voltage without the load-dependent sag: the diode clamps of an idle phase node. The ripple
 * (hundreds of Hz) is evaluated once per integration step. */
static double bus_voltage(struct plant *p, double t)
{
    const struct inverter_params *inv = &p->p.inv;
    double v = inv->V_dc;
    if (inv->ripple_amp != 0.0) {
        if (!same_bits(t, p->bus_t)) {
            p->bus_t = t;
            p->bus_v = inv->V_dc + inv->ripple_amp * sin(TWO_PI * inv->ripple_freq * t);
        }
        v = p->bus_v;
    }
    if (p->dc_fault) /* FAULT_DC_LINK: the source falls to dc_value of itself */
        v *= p->dc_tau > 0.0 ? p->dc_value + (1.0 - p->dc_value) * exp(-(t - p->dc_t0) / p->dc_tau) : p->dc_value;
    return v;
}

/* The stretch [lo, hi) around t (in segment k, the cursor profile_eval() left) on which profile_eval()
 * returns one value, and that value; lo = hi = NaN when the profile is not constant around t. */
static void profile_stretch(const struct profile *pr, int k, double t, double *lo, double *hi, double *value)
{
    *lo = *hi = NAN;
    if (pr->n <= 0 || pr->puls_depth != 0.0)
        return;
    if (t < pr->t[0]) {
        *lo = -INFINITY, *hi = pr->t[0], *value = pr->v[0];
    } else if (k + 1 >= pr->n) {
        *lo = pr->t[pr->n - 1], *hi = INFINITY, *value = pr->v[pr->n - 1];
    } else if (pr->v[k + 1] == pr->v[k]) { /* the interpolation adds (v[k+1] - v[k]) * ... = +0 */
        *lo = pr->t[k], *hi = pr->t[k + 1], *value = pr->v[k] + 0.0;
    }
}

/* load torque profile at t: constant stretches are kept (a step's stages mostly fall in one), and a
 * memo of the last time (the two middle RK4 stages share theirs) */
static inline double load_torque(struct plant *p, double t)
{
    if (!p->p.load.n)
        return 0.0;
    if (t >= p->load_lo && t < p->load_hi)
        return p->load_hold;
    if (!same_bits(t, p->load_t)) {
        p->load_t = t;
        p->load_v = profile_eval(&p->p.load, &p->cursor_load, t);
        profile_stretch(&p->p.load, p->cursor_load, t, &p->load_lo, &p->load_hi, &p->load_hold);
    }
    return p->load_v;
}

/* cos, sin of the electrical angle th */
static void trig(struct plant *p, double th, double *c, double *s)
{
    if (!same_bits(th, p->trig_th)) {
        p->trig_th = th;
        p->trig_c = cos(th);
        p->trig_s = sin(th);
    }
    *c = p->trig_c;
    *s = p->trig_s;
}

/* currents of the flux linkages of state x (memo: the state at the end of a step is the one the
 * next step and the commutation check start from) */
static inline void state_currents(struct plant *p, const double *x, double *i_d, double *i_q)
{
    if (!same_bits(x[X_PSID], p->cur_psid) || !same_bits(x[X_PSIQ], p->cur_psiq)) {
        p->cur_psid = x[X_PSID];
        p->cur_psiq = x[X_PSIQ];
        mag_currents(&p->mag, x[X_PSID], x[X_PSIQ], &p->cur_id, &p->cur_iq, NULL);
    }
    *i_d = p->cur_id;
    *i_q = p->cur_iq;
}

/* ------------------------------------------------------------------------------------------------ */
/* dynamics                                                                                         */

static inline __attribute__((always_inline)) double leg_voltage(const struct plant *p, int leg, double i, double v_dc,
                                                                double v_bus, double v_node_state, double *dv_node)
{
    const struct inverter_params *inv = &p->p.inv;
    double ai = fabs(i);
    *dv_node = 0.0;
    switch (p->legs[leg]) {
    case LEG_HIGH: /* i > 0 through the upper switch, i < 0 through the upper diode */
        return i >= 0.0 ? v_dc - inv->v_sw - inv->r_sw * ai : v_dc + inv->v_diode + inv->r_diode * ai;
    case LEG_LOW:
        return i <= 0.0 ? inv->v_sw + inv->r_sw * ai : -inv->v_diode - inv->r_diode * ai;
    case LEG_OFF:
        if (inv->C_node > 0.0) {
            /* the phase current charges the node capacitance until a diode clamps it */
            if (i > 0.0 && v_node_state <= -inv->v_diode)
                return -inv->v_diode - inv->r_diode * ai;
            if (i < 0.0 && v_node_state >= v_bus + inv->v_diode)
                return v_bus + inv->v_diode + inv->r_diode * ai;
            *dv_node = -i / inv->C_node;
            return v_node_state;
        }
        if (i > 0.0)
            return -inv->v_diode - inv->r_diode * ai;
        if (i < 0.0)
            return v_dc + inv->v_diode + inv->r_diode * ai;
        return p->v_hold[leg];
    default: /* shoot-through: a hardware fault, flagged; the node is taken at mid-bus */
        return 0.5 * v_dc;
    }
}

/* FAULT_PHASE_OPEN: the voltage of the motor terminal of phase k (disconnected from its leg) that keeps
 * its current on d i_k/dt = -i_k/OPEN_PHASE_TAU (so i_k stays 0 once it has decayed). With the other
 * node voltages v (v[k] ignored) the flux derivative is base + u w, w = (2/3) g in the rotor frame, where
 * i_k = g . i_dq, g = (c e_a + s e_b, -s e_a + c e_b) for the phase axis e of phase k; di/dt = Jac dpsi/dt,
 * dg/dt = omega_e (g_q, -g_d). Jac (the incremental inverse inductance) is positive definite, so the
 * denominator g . Jac w > 0. */
static double open_terminal_voltage(struct plant *p, const double *x, double i_d, double i_q, double c,
                                    double s, double omega_e, const double *v, int k)
{
    static const double axis[3][2] = {{1.0, 0.0}, {-0.5, SQRT3_2}, {-0.5, -SQRT3_2}};
    double vo[3] = {v[0], v[1], v[2]}, jac[4], id, iq;
    vo[k] = 0.0;
    double v_al = (2.0 / 3.0) * (vo[0] - 0.5 * (vo[1] + vo[2])), v_be = (vo[1] - vo[2]) * INV_SQRT3;
    double b_d = c * v_al + s * v_be - p->p.R_s * i_d + omega_e * x[X_PSIQ];
    double b_q = -s * v_al + c * v_be - p->p.R_s * i_q - omega_e * x[X_PSID];
    double g_d = c * axis[k][0] + s * axis[k][1], g_q = -s * axis[k][0] + c * axis[k][1];
    mag_currents(&p->mag, x[X_PSID], x[X_PSIQ], &id, &iq, jac);
    double jg_d = jac[0] * g_d + jac[1] * g_q, jg_q = jac[2] * g_d + jac[3] * g_q; /* Jac^T g (Jac symmetric) */
    double i_k = g_d * i_d + g_q * i_q;
    double num = -i_k / OPEN_PHASE_TAU - omega_e * (g_q * i_d - g_d * i_q) - (jg_d * b_d + jg_q * b_q);
    return num / ((2.0 / 3.0) * (jg_d * g_d + jg_q * g_q));
}

/* Current drawn from the dc link: the phases whose node sits on the positive rail (switch or diode). */
static inline double dc_current(const struct plant *p, const double i_abc[3])
{
    double i_dc = 0.0;
    for (int k = 0; k < 3; k++)
        if (p->legs[k] == LEG_HIGH || (p->legs[k] == LEG_OFF && i_abc[k] < 0.0 && p->p.inv.C_node == 0.0))
            i_dc += i_abc[k];
    return i_dc;
}

/* Derivative of the state at time t (s). i_d, i_q: the currents of its flux linkages (mag_currents);
 * c, s: cos/sin of the electrical angle of this state. v_ab: the machine's alpha-beta voltage when it
 * is known not to depend on the state (NULL if not). Inlined, so that each call site is specialised
 * for its constant arguments (v_ab, a). */
static inline __attribute__((always_inline)) void deriv(struct plant *p, double t, const double *x, double i_d,
                                                         double i_q, double c, double s, const double *v_ab,
                                                         double *dx, struct aux *a)
{
    const struct plant_params *pp = &p->p;
    double i_abc[3] = {0.0, 0.0, 0.0};
    if (!v_ab || a) {
        double i_al = c * i_d - s * i_q, i_be = s * i_d + c * i_q;
        i_abc[0] = i_al;
        i_abc[1] = -0.5 * i_al + SQRT3_2 * i_be;
        i_abc[2] = -0.5 * i_al - SQRT3_2 * i_be;
    }

    double omega_m = p->blocked ? 0.0
                     : (pp->mech.imposed_speed ? profile_eval(&pp->speed, &p->cursor_speed, t) : x[X_OMM]);

    double v[3] = {0.0, 0.0, 0.0}, dvn[3] = {0.0, 0.0, 0.0}, v_dc = pp->inv.V_dc, v_al, v_be;
    if (v_ab) {
        v_al = v_ab[0];
        v_be = v_ab[1];
    } else if (p->voltage_mode) {
        for (int k = 0; k < 3; k++)
            v[k] = p->v_ideal[k];
    } else {
        v_dc = p->v_bus_step;
        double v_bus = v_dc;
        if (pp->inv.R_dc != 0.0)
            v_dc -= pp->inv.R_dc * dc_current(p, i_abc);
        for (int k = 0; k < 3; k++)
            v[k] = leg_voltage(p, k, i_abc[k], v_dc, v_bus, x[X_VNA + k], &dvn[k]);
    }
    if (!v_ab && p->open_phase >= 0) {
        int k = p->open_phase;
        v[k] = open_terminal_voltage(p, x, i_d, i_q, c, s, pp->mech.pole_pairs * omega_m, v, k);
        dvn[k] = 0.0;
    }
    if (!v_ab) {
        v_al = (2.0 / 3.0) * (v[0] - 0.5 * (v[1] + v[2]));
        v_be = (v[1] - v[2]) * INV_SQRT3;
    }
    double v_d = c * v_al + s * v_be, v_q = -s * v_al + c * v_be;

    int pz = pp->mech.pole_pairs;
    double omega_e = pz * omega_m;
    double torque = 1.5 * pz * (x[X_PSID] * i_q - x[X_PSIQ] * i_d);

    dx[X_PSID] = v_d - pp->R_s * i_d + omega_e * x[X_PSIQ];
    dx[X_PSIQ] = v_q - pp->R_s * i_q - omega_e * x[X_PSID];
    double load = 0.0;
    if (pp->mech.imposed_speed || p->blocked) {
        dx[X_OMM] = 0.0;
    } else {
        load = load_torque(p, t) + p->load_add;
        double fric = pp->mech.B * omega_m;
        if (pp->mech.T_c != 0.0) {
            double r = omega_m / pp->mech.w_stick;
            fric += pp->mech.T_c * (r > 1.0 ? 1.0 : (r < -1.0 ? -1.0 : r));
        }
        dx[X_OMM] = (torque - load - fric) * p->inv_J;
    }
    dx[X_THM] = omega_m;
    for (int k = 0; k < 3; k++)
        dx[X_VNA + k] = dvn[k];
    dx[X_EIN] = 1.5 * (v_d * i_d + v_q * i_q);
    dx[X_ECU] = 1.5 * pp->R_s * (i_d * i_d + i_q * i_q);
    dx[X_EMECH] = torque * omega_m;
    dx[X_QD] = i_d;
    dx[X_QQ] = i_q;
    dx[X_TQ] = torque;
    dx[X_TQ2] = torque * torque;

    if (a) {
        a->i_d = i_d;
        a->i_q = i_q;
        for (int k = 0; k < 3; k++) {
            a->i_abc[k] = i_abc[k];
            a->v_node[k] = v[k];
        }
        a->v_d = v_d;
        a->v_q = v_q;
        a->v_dc = v_dc;
        a->torque = torque;
        a->load_torque = load;
        a->omega_m = omega_m;
    }
}

/* cos/sin of th0 + delta from c0 = cos(th0), s0 = sin(th0) */
static void rotate(double c0, double s0, double th0, double delta, double *c, double *s)
{
    if (fabs(delta) < 1e-2) { /* Taylor series; truncation below 2e-17 */
        double d2 = delta * delta;
        double cd = 1.0 - d2 * (0.5 - d2 * (1.0 / 24.0 - d2 * (1.0 / 720.0)));
        double sd = delta * (1.0 - d2 * (1.0 / 6.0 - d2 * (1.0 / 120.0 - d2 * (1.0 / 5040.0))));
        *c = c0 * cd - s0 * sd;
        *s = s0 * cd + c0 * sd;
    } else {
        *c = cos(th0 + delta);
        *s = sin(th0 + delta);
    }
}


static void state_trig(struct plant *p, double *c, double *s, double *th)
{
    *th = p->p.mech.pole_pairs * p->x[X_THM];
    trig(p, *th, c, s);
}

/* After an input change: make the algebraic states consistent with the state (imposed speed, node
 * voltages of conducting legs, held voltage of idle legs, sensor output without filter). */
static void settle(struct plant *p)
{
    double c, s, th, i_d, i_q;
    struct aux a;
    double dx[NX];
    state_trig(p, &c, &s, &th);
    state_currents(p, p->x, &i_d, &i_q);
    p->v_bus_step = bus_voltage(p, tick_time(p, p->tick));
    deriv(p, tick_time(p, p->tick), p->x, i_d, i_q, c, s, NULL, dx, &a);
    if (p->p.mech.imposed_speed)
        p->x[X_OMM] = a.omega_m;
    for (int k = 0; k < 3; k++) {
        if (p->p.sens.bandwidth_hz <= 0.0)
            p->y[k] = a.i_abc[k];
        p->x[X_VNA + k] = a.v_node[k];
        if (!p->voltage_mode && p->legs[k] != LEG_OFF)
            p->v_hold[k] = a.v_node[k];
    }
}

/* phase currents of the plant's state x at electrical angle (c, s) */
static void phase_currents(struct plant *p, const double *x, double c, double s, double i_abc[3])
{
    double i_d, i_q;
    state_currents(p, x, &i_d, &i_q);
    double i_al = c * i_d - s * i_q, i_be = s * i_d + c * i_q;
    i_abc[0] = i_al;
    i_abc[1] = -0.5 * i_al + SQRT3_2 * i_be;
    i_abc[2] = -0.5 * i_al - SQRT3_2 * i_be;
}

/* First-order sensor over one step, exact for a phase current that is linear over the step:
 * y(h) = i1 - k*tau + (y0 - i0 + k*tau)*exp(-h/tau), k = (i1 - i0)/h. */
static void sensor_step(struct plant *p, double h, const double i0[3], const double i1[3])
{
    if (p->p.sens.bandwidth_hz <= 0.0) {
        for (int k = 0; k < 3; k++)
            p->y[k] = i1[k];
        return;
    }
    double tau = p->filt_tau;
    if (h != p->filt_h) {
        p->filt_h = h;
        p->filt_decay = exp(-h / tau);
    }
    for (int k = 0; k < 3; k++) {
        double ktau = (i1[k] - i0[k]) / h * tau;
        p->y[k] = i1[k] - ktau + (p->y[k] - i0[k] + ktau) * p->filt_decay;
    }
}

/* Stages 2 to 4 of an RK4 step from x0 with first stage k1, then the new state x (see rk4_step).
 * Inlined into two call sites: with v_ab fixed (every leg conducts, so only the machine and mechanical
 * states move: nstage = 4, a constant) and NULL, so that deriv() is specialised for each. */
static inline __attribute__((always_inline)) void rk4_stages(struct plant *p, double t, double h, int nstage,
                                                             const double *x0, const double *k1, double *x,
                                                             double ch, double sh, double c1, double s1,
                                                             const double *v_ab)
{
    double k2[NX], k3[NX], k4[NX], xs[NX], i_d, i_q;
    memcpy(xs, x0, sizeof xs);
    for (int k = 0; k < nstage; k++)
        xs[k] = x0[k] + 0.5 * h * k1[k];
    mag_currents(&p->mag, xs[X_PSID], xs[X_PSIQ], &i_d, &i_q, NULL);
    deriv(p, t + 0.5 * h, xs, i_d, i_q, ch, sh, v_ab, k2, NULL);
    for (int k = 0; k < nstage; k++)
        xs[k] = x0[k] + 0.5 * h * k2[k];
    mag_currents(&p->mag, xs[X_PSID], xs[X_PSIQ], &i_d, &i_q, NULL);
    deriv(p, t + 0.5 * h, xs, i_d, i_q, ch, sh, v_ab, k3, NULL);
    for (int k = 0; k < nstage; k++)
        xs[k] = x0[k] + h * k3[k];
    mag_currents(&p->mag, xs[X_PSID], xs[X_PSIQ], &i_d, &i_q, NULL);
    deriv(p, t + h, xs, i_d, i_q, c1, s1, v_ab, k4, NULL);
    for (int k = 0; k < NX; k++)
        x[k] = x0[k] + h / 6.0 * (k1[k] + 2.0 * k2[k] + 2.0 * k3[k] + k4[k]);
}

/* One RK4 step of nticks. Inside the step the electrical angle follows th0 + omega_e0*t (the speed
 * changes by far less than 1e-3 rad/s within a microsecond step), so the stage angles come from one
 * small rotation. The intermediate stages update the machine and mechanical states, and the node
 * voltages only while a node capacitance commutates; the energies are quadratures of the stages. */
static void rk4_step(struct plant *p, double nticks)
{
    double h = nticks / p->p.tick_hz, t = ((double)p->tick + p->sub) / p->p.tick_hz;
    double k1[NX], i1[3];
    double *x = p->x;
    int pz = p->p.mech.pole_pairs;
    int nstage = X_THM + 1;
    if (p->p.inv.C_node > 0.0 && !p->voltage_mode)
        for (int k = 0; k < 3; k++)
            if (p->legs[k] == LEG_OFF)
                nstage = X_VNC + 1;
    double th0 = pz * x[X_THM], c0, s0, ch, sh, c1, s1, i_d, i_q;
    trig(p, th0, &c0, &s0);
    p->v_bus_step = bus_voltage(p, t);
    rotate(c0, s0, th0, 0.5 * h * pz * x[X_OMM], &ch, &sh);
    rotate(ch, sh, th0 + 0.5 * h * pz * x[X_OMM], 0.5 * h * pz * x[X_OMM], &c1, &s1);
    struct aux a0;

    state_currents(p, x, &i_d, &i_q);
    deriv(p, t, x, i_d, i_q, c0, s0, NULL, k1, &a0);
    /* While every leg conducts (a switch or its diode on), the node voltages depend on the state only
     * through the device drops and the dc-link sag, which change negligibly within a step (<= 1 us):
     * they are taken at the start of the step and held. Legs in dead time are evaluated at every stage. */
    double v_ab_fixed[2];
    int fixed = 1;
    if (!p->voltage_mode)
        for (int k = 0; k < 3; k++)
            if (p->legs[k] != LEG_HIGH && p->legs[k] != LEG_LOW)
                fixed = 0;
    if (p->open_phase >= 0) /* the open terminal's voltage depends on the state at every stage */
        fixed = 0;
    if (fixed) {
        v_ab_fixed[0] = (2.0 / 3.0) * (a0.v_node[0] - 0.5 * (a0.v_node[1] + a0.v_node[2]));
        v_ab_fixed[1] = (a0.v_node[1] - a0.v_node[2]) * INV_SQRT3;
    }
    double x0[NX];
    memcpy(x0, x, sizeof x0);
    if (fixed) { /* every leg conducts (or ideal voltages): no node voltage moves, nstage = X_THM + 1 */
        rk4_stages(p, t, h, X_THM + 1, x0, k1, x, ch, sh, c1, s1, v_ab_fixed);
        phase_currents(p, x, c1, s1, i1);
        /* a conducting leg whose current changed sign switched between switch and diode drop inside
         * the step: redo the step with the leg voltages evaluated at every stage */
        if (!p->voltage_mode && (p->p.inv.v_sw != 0.0 || p->p.inv.v_diode != 0.0)) {
            int flip = 0;
            for (int k = 0; k < 3; k++)
                flip |= (a0.i_abc[k] > 0.0) != (i1[k] > 0.0);
            fixed = !flip;
        }
    }
    if (!fixed) {
        rk4_stages(p, t, h, nstage, x0, k1, x, ch, sh, c1, s1, NULL);
        phase_currents(p, x, c1, s1, i1);
    }
    p->sub += nticks;

    sensor_step(p, h, a0.i_abc, i1);
    memcpy(p->i_end, i1, sizeof p->i_end);

    if (nstage > X_THM + 1) {
        const struct inverter_params *inv = &p->p.inv;
        double hi = bus_voltage(p, t + h) + inv->v_diode; /* the next step's bus */
        for (int leg = 0; leg < 3; leg++) {
            double *vn = &x[X_VNA + leg];
            *vn = *vn < -inv->v_diode ? -inv->v_diode : (*vn > hi ? hi : *vn);
        }
    }
    if (x[X_THM] >= TWO_PI || x[X_THM] < 0.0)
        x[X_THM] -= TWO_PI * floor(x[X_THM] / TWO_PI);
    if (p->blocked)
        x[X_OMM] = 0.0;
    else if (p->p.mech.imposed_speed)
        x[X_OMM] = profile_eval(&p->p.speed, &p->cursor_speed, t + h);
}

/* While the phase current charges the node capacitance of an idle leg, the step ends just past the
 * instant the node is predicted to reach its rail (diode clamp), at most max_substep_commutation_ticks,
 * so that the kink of the node voltage falls on a step boundary; 0 when no node is commutating. */
static double commutation_step(struct plant *p)
{
    const struct inverter_params *inv = &p->p.inv;
    if (inv->C_node <= 0.0 || p->voltage_mode)
        return 0.0;
    int any_off = 0;
    for (int k = 0; k < 3; k++)
        any_off |= p->legs[k] == LEG_OFF;
    if (!any_off)
        return 0.0;
    double c, s, th, i_abc[3];
    state_trig(p, &c, &s, &th);
    phase_currents(p, p->x, c, s, i_abc);
    double step = 0.0, cap = p->p.max_substep_commutation_ticks;
    for (int k = 0; k < 3; k++) {
        if (p->legs[k] != LEG_OFF)
            continue;
        double v = p->x[X_VNA + k], i = i_abc[k], lo = -inv->v_diode;
        double hi = bus_voltage(p, ((double)p->tick + p->sub) / p->p.tick_hz) + inv->v_diode;
        double t_rail = i > 0.0 ? (v - lo) * inv->C_node / i : (hi - v) * inv->C_node / -i;
        if (i == 0.0 || t_rail * p->p.tick_hz <= COMMUTATION_OVERSHOOT)
            continue; /* clamped by a diode (or about to be), or no current to move the node */
        double n = t_rail * p->p.tick_hz + COMMUTATION_OVERSHOOT;
        n = n > cap ? cap : n;
        if (step == 0.0 || n < step)
            step = n;
    }
    return step;
}

static int advance_to(struct plant *p, long long tick)
{
    double total = (double)(tick - p->tick);
    p->sub = 0.0;
    while (p->sub < total) {
        double rem = total - p->sub, step = commutation_step(p);
        if (step == 0.0) { /* equal steps of at most max_substep_ticks over the rest of the interval */
            double n = ceil(rem / p->p.max_substep_ticks);
            step = rem / n;
        }
        if (step >= rem)
            step = rem;
        rk4_step(p, step);
        if (step == rem) /* exactly at the target, whatever the rounding of the sum */
            p->sub = total;
    }
    p->tick = tick;
    p->sub = 0.0;
    if (!p->voltage_mode)
        for (int k = 0; k < 3; k++)
            if (p->legs[k] == LEG_SHORT)
                p->shoot_through_ticks += (long long)total;
    return 0;
}

/* ------------------------------------------------------------------------------------------------ */
/* inputs and outputs                                                                               */

/* Ringing after every switch turn-on: amp*sign*exp(-dt/tau)*sin(2*pi*f*dt) on the switched phase
 * (ring_cross times that on the others), summed over edges as one phasor per leg:
 * z <- z*exp(lambda*dt) between events, z += sign at an edge, ringing = Im(z). */
static inline void ring_advance(struct plant *p)
{
    const struct sensor_params *sp = &p->p.sens;
    long long dt = p->tick - p->ring_tick;
    p->ring_tick = p->tick;
    if (dt == 0)
        return;
    int slot = (int)(dt % RING_CACHE);
    if (dt != p->ring_dt[slot]) {
        double d = tick_time(p, dt), mag = exp(-d / sp->ring_tau);
        p->ring_dt[slot] = dt;
        p->ring_rot_re[slot] = mag * cos(TWO_PI * sp->ring_freq * d);
        p->ring_rot_im[slot] = mag * sin(TWO_PI * sp->ring_freq * d);
    }
    double rot_re = p->ring_rot_re[slot], rot_im = p->ring_rot_im[slot];
    for (int k = 0; k < 3; k++) {
        double re = p->ring_re[k], im = p->ring_im[k];
        p->ring_re[k] = re * rot_re - im * rot_im;
        p->ring_im[k] = re * rot_im + im * rot_re;
        if (fabs(p->ring_re[k]) + fabs(p->ring_im[k]) < 1e-12) /* decayed: stop denormals */
            p->ring_re[k] = p->ring_im[k] = 0.0;
    }
}

/* the state of leg k under the gate mask gates */
static int leg_of(int gates, int k)
{
    int hi = (gates >> (2 * k)) & 1, lo = (gates >> (2 * k + 1)) & 1;
    return hi && lo ? LEG_SHORT : (hi ? LEG_HIGH : (lo ? LEG_LOW : LEG_OFF));
}

/* the leg states of the commanded mask without the switches that never turn on (FAULT_SWITCH_OPEN) */
static void dead_switch_legs(struct plant *p)
{
    for (int k = 0; k < 3; k++)
        p->legs[k] = leg_of(p->gates & ~p->dead_switches, k);
}

static int set_gates(struct plant *p, int gates)
{
    int status = 0;
    for (int k = 0; k < 3; k++) {
        int leg = leg_of(gates & ~p->dead_switches, k); /* a switch that never turns on stays off */
        int was = p->voltage_mode ? LEG_OFF : p->legs[k];
        if ((leg == LEG_HIGH || leg == LEG_LOW) && leg != was && p->p.sens.ring_amp > 0.0) {
            ring_advance(p);
            p->ring_re[k] += leg == LEG_HIGH ? 1.0 : -1.0;
        }
        if (leg_of(gates, k) == LEG_SHORT) /* what was commanded */
            status = PLANT_SHOOT_THROUGH;
        p->legs[k] = leg;
    }
    p->gates = gates & 63;
    p->voltage_mode = 0;
    settle(p);
    return status;
}

/* The effects of the faults active at the present tick (docs/faults.md), from neutral: recomputed at every
 * onset and end, like an input change (no step straddles one). A drift runs from its own onset. */
static void fault_effects(struct plant *p)
{
    int was_blocked = p->blocked;
    for (int k = 0; k < 3; k++) {
        p->f_gain[k] = 1.0;
        p->f_off[k] = p->f_rate[k] = 0.0;
    }
    for (int k = 0; k < PLANT_ADC_CHANNELS; k++)
        p->f_stuck[k] = -1;
    p->sens_fault = p->dc_fault = p->blocked = p->dead_switches = 0;
    p->open_phase = -1;
    p->load_add = 0.0;
    for (int i = 0; i < p->p.n_faults; i++) {
        const struct fault *f = &p->p.faults[i];
        if (f->tick > p->tick || (f->until > 0 && p->tick >= f->until))
            continue;
        int ch = f->channel;
        double t = tick_time(p, f->tick);
        switch (f->kind) {
        case FAULT_SENSOR_OFFSET:
            p->f_off[ch] += f->value - f->rate * t;
            p->f_rate[ch] += f->rate;
            p->sens_fault = 1;
            break;
        case FAULT_SENSOR_GAIN:
            p->f_gain[ch] *= f->value;
            p->sens_fault = 1;
            break;
        case FAULT_ADC_STUCK:
            p->f_stuck[ch] = (int)f->value;
            p->sens_fault = 1;
            break;
        case FAULT_PHASE_OPEN:
            p->open_phase = ch;
            break;
        case FAULT_SWITCH_OPEN:
            p->dead_switches |= 1 << ch;
            break;
        case FAULT_DC_LINK:
            p->dc_fault = 1;
            p->dc_value = f->value;
            p->dc_tau = f->rate;
            p->dc_t0 = t;
            break;
        case FAULT_LOAD_STEP:
            p->load_add += f->value;
            break;
        case FAULT_ROTOR_BLOCKED:
            p->blocked = 1;
            break;
        default: /* refused by plant_create */
            break;
        }
    }
    if (p->blocked && !was_blocked)
        p->x[X_OMM] = 0.0;
    if (!p->voltage_mode)
        dead_switch_legs(p);
    settle(p);
}

/* The next fault onset or end after the last one applied (fault_tick) and not after tick; -1 if none. */
static long long next_fault_event(const struct plant *p, long long tick)
{
    long long next = -1;
    for (int i = 0; i < p->p.n_faults; i++) {
        const struct fault *f = &p->p.faults[i];
        long long ev[2] = {f->tick, f->until};
        for (int k = 0; k < 2; k++)
            if ((k == 0 || ev[k] > 0) && ev[k] > p->fault_tick && ev[k] <= tick && (next < 0 || ev[k] < next))
                next = ev[k];
    }
    return next;
}

/* Integrate to tick, applying every fault onset and end on the way. */
static int advance(struct plant *p, long long tick)
{
    if (tick < p->tick)
        return PLANT_BAD_ORDER;
    for (long long ev; (ev = next_fault_event(p, tick)) >= 0;) {
        if (ev > p->tick)
            advance_to(p, ev);
        p->fault_tick = ev;
        fault_effects(p);
    }
    return advance_to(p, tick);
}

static int set_voltage(struct plant *p, const double v_abc[3])
{
    for (int k = 0; k < 3; k++)
        p->v_ideal[k] = v_abc[k];
    p->voltage_mode = 1;
    settle(p);
    return 0;
}

static double ringing(const struct plant *p, int ch)
{
    const struct sensor_params *sp = &p->p.sens;
    double others = p->ring_im[0] + p->ring_im[1] + p->ring_im[2] - p->ring_im[ch];
    return sp->ring_amp * (p->ring_im[ch] + sp->ring_cross * others);
}

/* The dc-link voltage at the present tick, as its sensor sees it: the source (ripple, FAULT_DC_LINK)
 * less the drop R_dc * i_dc of the current the legs on the positive rail draw now. */
static double link_voltage(struct plant *p)
{
    double v = bus_voltage(p, tick_time(p, p->tick));
    if (p->p.inv.R_dc != 0.0 && !p->voltage_mode)
        v -= p->p.inv.R_dc * dc_current(p, p->i_end);
    return v;
}

static int sample(struct plant *p, int adc[PLANT_ADC_CHANNELS], double analog[PLANT_ADC_CHANNELS])
{
    const struct sensor_params *sp = &p->p.sens;
    double full = p->adc_full, inv_lsb = p->adc_inv_lsb;
    if (sp->ring_amp > 0.0)
        ring_advance(p);
    double t = tick_time(p, p->tick);
    for (int k = 0; k < 3; k++) {
        double y = p->sens_fault ? sp->gain[k] * p->f_gain[k] * p->y[k] + sp->offset[k] + (p->f_off[k] + p->f_rate[k] * t)
                                 : sp->gain[k] * p->y[k] + sp->offset[k];
        y += ringing(p, k);
        if (sp->noise_rms > 0.0)
            y += sp->noise_rms * gauss(p);
        /* clip(floor(z), 0, full - 1); for 0 <= z < full, floor is the truncation of the conversion */
        double z = y * inv_lsb + 0.5 * full + 0.5;
        if (!isfinite(z))
            return PLANT_NOT_FINITE; /* a diverged state has no code (and NaN has no int conversion) */
        adc[k] = z < 0.0 ? 0 : (z >= full ? (int)(full - 1.0) : (int)z);
        if (p->sens_fault && p->f_stuck[k] >= 0)
            adc[k] = p->f_stuck[k];
        if (analog)
            analog[k] = y;
    }
    /* the dc-link channel: unipolar, code = clip(floor(v * codes_per_volt + 1/2), 0, full - 1) */
    if (p->vdc_codes > 0.0) {
        double v = sp->vdc_gain * link_voltage(p);
        if (sp->vdc_noise_rms > 0.0)
            v += sp->vdc_noise_rms * gauss_vdc(p);
        double z = v * p->vdc_codes + 0.5;
        if (!isfinite(z))
            return PLANT_NOT_FINITE;
        adc[PLANT_ADC_VDC] = z < 0.0 ? 0 : (z >= full ? (int)(full - 1.0) : (int)z);
        if (analog)
            analog[PLANT_ADC_VDC] = v;
    } else {
        adc[PLANT_ADC_VDC] = 0;
        if (analog)
            analog[PLANT_ADC_VDC] = 0.0;
    }
    if (p->sens_fault && p->f_stuck[PLANT_ADC_VDC] >= 0)
        adc[PLANT_ADC_VDC] = p->f_stuck[PLANT_ADC_VDC];
    return 0;
}

static void get_state(const struct plant *p, struct plant_state *o)
{
    struct plant *q = (struct plant *)p; /* deriv() moves the profile cursors, memos and bus cache only */
    double c, s, th, i_d, i_q, dx[NX];
    struct aux a;
    state_trig(q, &c, &s, &th);
    state_currents(q, p->x, &i_d, &i_q);
    q->v_bus_step = bus_voltage(q, tick_time(p, p->tick));
    deriv(q, tick_time(p, p->tick), p->x, i_d, i_q, c, s, NULL, dx, &a);
    memset(o, 0, sizeof *o);
    o->tick = p->tick;
    o->t = tick_time(p, p->tick);
    o->theta_e = th - TWO_PI * floor(th / TWO_PI);
    o->omega_m = a.omega_m;
    o->omega_e = p->p.mech.pole_pairs * a.omega_m;
    o->theta_m = p->x[X_THM];
    o->psi_d = p->x[X_PSID];
    o->psi_q = p->x[X_PSIQ];
    o->i_d = a.i_d;
    o->i_q = a.i_q;
    for (int k = 0; k < 3; k++) {
        o->i_abc[k] = a.i_abc[k];
        o->v_node[k] = a.v_node[k];
        o->sensor_y[k] = p->y[k];
    }
    o->v_d = a.v_d;
    o->v_q = a.v_q;
    o->v_dc = a.v_dc;
    o->torque = a.torque;
    o->load_torque = a.load_torque;
    o->E_in = p->x[X_EIN];
    o->E_cu = p->x[X_ECU];
    o->E_mech = p->x[X_EMECH];
    o->Q_d = p->x[X_QD];
    o->Q_q = p->x[X_QQ];
    o->T_int = p->x[X_TQ];
    o->T2_int = p->x[X_TQ2];
    o->gates = p->gates;
    o->voltage_mode = p->voltage_mode;
    o->shoot_through_ticks = p->shoot_through_ticks;
}

/* the per-event API (the batch API below calls the same internal functions) */
int plant_advance(struct plant *p, long long tick) { return advance(p, tick); }
const char *plant_status_text(int status)
{
    switch (status) {
    case 0: return "ok";
    case PLANT_BAD_ORDER: return "edge and sample ticks must be non-decreasing and not before the plant's time";
    case PLANT_SHOOT_THROUGH: return "a gate mask turned on both switches of a leg";
    case PLANT_BAD_MASK: return "gates must hold one 6-bit mask (0..63) per edge";
    case PLANT_NOT_FINITE:
        return "the plant's state is no longer finite (NaN or infinite): the simulation diverged, check the motor, "
               "mechanics and inverter values of the scenario";
    default: return "unknown plant status";
    }
}

int plant_set_gates(struct plant *p, int gates) { return set_gates(p, gates); }
int plant_set_voltage(struct plant *p, const double v_abc[3]) { return set_voltage(p, v_abc); }
int plant_sample(struct plant *p, int adc[PLANT_ADC_CHANNELS], double analog[PLANT_ADC_CHANNELS])
{
    return sample(p, adc, analog);
}
void plant_get_state(const struct plant *p, struct plant_state *out) { get_state(p, out); }

int plant_run(struct plant *p, int n_edges, const long long *edge_ticks, const int *gates, const double *volts,
              int n_samples, const long long *sample_ticks, int *adc_out, double *analog_out,
              struct plant_state *truth_out)
{
    int i = 0, j = 0, status = 0;
    if (!volts)
        for (int k = 0; k < n_edges; k++)
            if (gates[k] < 0 || gates[k] > 63)
                return PLANT_BAD_MASK; /* checked before anything is applied */
    while (i < n_edges || j < n_samples) {
        if (i < n_edges && (j >= n_samples || edge_ticks[i] <= sample_ticks[j])) {
            if (advance(p, edge_ticks[i]) != 0)
                return PLANT_BAD_ORDER;
            int st = volts ? set_voltage(p, volts + 3 * i) : set_gates(p, gates[i]);
            if (st != 0)
                status = st;
            i++;
        } else {
            if (advance(p, sample_ticks[j]) != 0)
                return PLANT_BAD_ORDER;
            if (sample(p, adc_out + PLANT_ADC_CHANNELS * j, analog_out ? analog_out + PLANT_ADC_CHANNELS * j : NULL) != 0)
                return PLANT_NOT_FINITE;
            if (truth_out)
                get_state(p, truth_out + j);
            j++;
        }
    }
    return status;
}

/* ------------------------------------------------------------------------------------------------ */
/* creation and parameter checks                                                                    */

#define REQUIRE(cond, ...)                                                                              \
    do {                                                                                                \
        if (!(cond)) {                                                                                  \
            if (err && err_len > 0)                                                                     \
                snprintf(err, (size_t)err_len, __VA_ARGS__);                                            \
            return 0;                                                                                   \
        }                                                                                               \
    } while (0)

static int profile_ok(const struct profile *pr, const char *name, char *err, int err_len)
{
    REQUIRE(pr->n >= 0, "%s: negative point count", name);
    REQUIRE(pr->n == 0 || (pr->t && pr->v), "%s: missing arrays", name);
    for (int k = 0; k < pr->n; k++) {
        REQUIRE(isfinite(pr->t[k]) && isfinite(pr->v[k]), "%s: point %d is not finite", name, k);
        REQUIRE(k == 0 || pr->t[k] >= pr->t[k - 1], "%s: times must not decrease (point %d)", name, k);
    }
    REQUIRE(isfinite(pr->puls_freq) && pr->puls_freq >= 0.0, "%s: puls_freq must be >= 0", name);
    REQUIRE(isfinite(pr->puls_depth), "%s: puls_depth must be finite", name);
    return 1;
}

static int params_ok(const struct plant_params *pp, char *err, int err_len)
{
    const struct mag_params *m = &pp->mag;
    REQUIRE(pp->tick_hz > 0.0 && isfinite(pp->tick_hz), "tick_hz must be > 0");
    REQUIRE(pp->max_substep_ticks >= 1, "max_substep_ticks must be >= 1");
    REQUIRE(pp->max_substep_commutation_ticks >= 1, "max_substep_commutation_ticks must be >= 1");
    REQUIRE(pp->R_s >= 0.0 && isfinite(pp->R_s), "R_s must be >= 0");
    REQUIRE(m->kind >= MAG_LINEAR && m->kind <= MAG_TABLE, "mag.kind %d is not a magnetic model", m->kind);
    REQUIRE(m->psi_f >= 0.0 && isfinite(m->psi_f), "mag.psi_f must be >= 0");
    if (m->kind == MAG_LINEAR || m->kind == MAG_DSAT) {
        REQUIRE(m->L_d > 0.0 && isfinite(m->L_d), "mag.L_d must be > 0");
        REQUIRE(m->L_q > 0.0 && isfinite(m->L_q), "mag.L_q must be > 0");
    }
    if (m->kind == MAG_DSAT) {
        REQUIRE(m->psi_f > 0.0, "mag.psi_f must be > 0 for the d-saturation model");
        REQUIRE(m->dsat_a >= 0.0 && isfinite(m->dsat_a), "mag.dsat_a must be >= 0");
        REQUIRE(m->dsat_S >= 1 && m->dsat_S <= 16, "mag.dsat_S must be in 1..16");
    }
    if (m->kind == MAG_ALGEBRAIC) {
        REQUIRE(m->a_d0 > 0.0 && m->a_q0 > 0.0, "mag.a_d0 and mag.a_q0 must be > 0");
        REQUIRE(m->a_dd >= 0.0 && m->a_qq >= 0.0 && m->a_dq >= 0.0, "mag.a_dd, a_qq, a_dq must be >= 0");
        REQUIRE(m->S >= 0 && m->T >= 0 && m->U >= 0 && m->V >= 0 && m->S <= 16 && m->T <= 16 && m->U <= 16 &&
                    m->V <= 16,
                "mag exponents S, T, U, V must be in 0..16");
    }
    if (m->kind == MAG_TABLE) {
        REQUIRE(m->tab_nd >= 2 && m->tab_nq >= 2, "mag table needs at least 2x2 points");
        REQUIRE(m->tab_dpsid > 0.0 && m->tab_dpsiq > 0.0, "mag table spacing must be > 0");
        REQUIRE(m->tab_id && m->tab_iq, "mag table arrays missing");
    }
    const struct mech_params *me = &pp->mech;
    REQUIRE(me->pole_pairs >= 1 && me->pole_pairs <= 64, "mech.pole_pairs must be in 1..64");
    REQUIRE(me->imposed_speed || (me->J > 0.0 && isfinite(me->J)), "mech.J must be > 0");
    REQUIRE(me->B >= 0.0 && me->T_c >= 0.0, "mech.B and mech.T_c must be >= 0");
    REQUIRE(me->T_c == 0.0 || me->w_stick > 0.0, "mech.w_stick must be > 0 when T_c > 0");
    const struct inverter_params *inv = &pp->inv;
    REQUIRE(inv->V_dc > 0.0 && isfinite(inv->V_dc), "inv.V_dc must be > 0");
    REQUIRE(inv->R_dc >= 0.0 && inv->C_node >= 0.0, "inv.R_dc and inv.C_node must be >= 0");
    REQUIRE(inv->v_sw >= 0.0 && inv->r_sw >= 0.0 && inv->v_diode >= 0.0 && inv->r_diode >= 0.0,
            "inverter device drops must be >= 0");
    REQUIRE(inv->ripple_amp >= 0.0 && inv->ripple_freq >= 0.0, "inv ripple must be >= 0");
    const struct sensor_params *sp = &pp->sens;
    for (int k = 0; k < 3; k++) {
        REQUIRE(sp->gain[k] > 0.0 && isfinite(sp->gain[k]), "sens.gain[%d] must be > 0", k);
        REQUIRE(isfinite(sp->offset[k]), "sens.offset[%d] must be finite", k);
    }
    REQUIRE(sp->noise_rms >= 0.0 && sp->bandwidth_hz >= 0.0, "sens.noise_rms and bandwidth_hz must be >= 0");
    REQUIRE(sp->ring_amp >= 0.0 && sp->ring_cross >= 0.0 && sp->ring_freq >= 0.0, "sens ringing must be >= 0");
    REQUIRE(sp->ring_amp == 0.0 || sp->ring_tau > 0.0, "sens.ring_tau must be > 0 when ring_amp > 0");
    REQUIRE(sp->adc_bits >= 1 && sp->adc_bits <= 24, "sens.adc_bits must be in 1..24");
    REQUIRE(sp->adc_range > 0.0 && isfinite(sp->adc_range), "sens.adc_range must be > 0");
    REQUIRE(sp->vdc_range >= 0.0 && isfinite(sp->vdc_range), "sens.vdc_range must be >= 0 (0: no dc-link channel)");
    REQUIRE(sp->vdc_gain > 0.0 && isfinite(sp->vdc_gain), "sens.vdc_gain must be > 0");
    REQUIRE(sp->vdc_noise_rms >= 0.0 && isfinite(sp->vdc_noise_rms), "sens.vdc_noise_rms must be >= 0");
    if (!profile_ok(&pp->load, "load", err, err_len) || !profile_ok(&pp->speed, "speed", err, err_len))
        return 0;
    REQUIRE(pp->n_faults >= 0 && (pp->n_faults == 0 || pp->faults), "faults: missing array");
    int open = 0;
    for (int k = 0; k < pp->n_faults; k++) {
        const struct fault *f = &pp->faults[k];
        REQUIRE(f->kind >= FAULT_SENSOR_OFFSET && f->kind <= FAULT_ROTOR_BLOCKED, "faults[%d]: kind %d is not a fault",
                k, f->kind);
        REQUIRE(f->tick >= 0 && (k == 0 || f->tick >= pp->faults[k - 1].tick),
                "faults[%d]: tick must be >= 0 and not before the previous fault's", k);
        REQUIRE(f->until == 0 || f->until > f->tick, "faults[%d]: until must be 0 (never) or after tick", k);
        REQUIRE(isfinite(f->value) && isfinite(f->rate), "faults[%d]: value and rate must be finite", k);
        int nch = f->kind == FAULT_SWITCH_OPEN ? 6 : (f->kind == FAULT_ADC_STUCK ? PLANT_ADC_CHANNELS : 3);
        REQUIRE(f->channel >= 0 && f->channel < nch, "faults[%d]: channel must be in 0..%d", k, nch - 1);
        REQUIRE(f->kind != FAULT_SENSOR_GAIN || f->value >= 0.0, "faults[%d]: a gain factor must be >= 0", k);
        REQUIRE(f->kind != FAULT_ADC_STUCK || (f->value >= 0.0 && f->value < ldexp(1.0, sp->adc_bits) &&
                                               f->value == floor(f->value)),
                "faults[%d]: a stuck code must be an integer in 0..2^adc_bits-1", k);
        REQUIRE(f->kind != FAULT_DC_LINK || (f->value >= 0.0 && f->value <= 2.0 && f->rate >= 0.0),
                "faults[%d]: a dc-link factor must be in 0..2 and its time constant >= 0", k);
        REQUIRE(f->kind != FAULT_PHASE_OPEN || !open++, "faults[%d]: at most one phase can be open", k);
    }
    return 1;
}

static double *copy_array(double **cursor, const double *src, int n)
{
    double *dst = *cursor;
    if (n > 0)
        memcpy(dst, src, (size_t)n * sizeof(double));
    *cursor += n;
    return dst;
}

struct plant *plant_create(const struct plant_params *params, char *err, int err_len)
{
    if (!params_ok(params, err, err_len))
        return NULL;
    struct plant *p = calloc(1, sizeof *p);
    if (!p)
        return NULL;
    p->self = p;
    p->p = *params;
    int ntab = params->mag.kind == MAG_TABLE ? params->mag.tab_nd * params->mag.tab_nq : 0;
    size_t total = 2 * (size_t)params->load.n + 2 * (size_t)params->speed.n + 2 * (size_t)ntab;
    p->owned = malloc((total ? total : 1) * sizeof(double));
    p->faults_owned = malloc((params->n_faults ? (size_t)params->n_faults : 1) * sizeof(struct fault));
    if (!p->owned || !p->faults_owned) {
        free(p->owned);
        free(p->faults_owned);
        free(p);
        return NULL;
    }
    if (params->n_faults)
        memcpy(p->faults_owned, params->faults, (size_t)params->n_faults * sizeof(struct fault));
    p->p.faults = p->faults_owned;
    double *cur = p->owned;
    p->p.load.t = copy_array(&cur, params->load.t, params->load.n);
    p->p.load.v = copy_array(&cur, params->load.v, params->load.n);
    p->p.speed.t = copy_array(&cur, params->speed.t, params->speed.n);
    p->p.speed.v = copy_array(&cur, params->speed.v, params->speed.n);
    if (ntab) {
        p->p.mag.tab_id = copy_array(&cur, params->mag.tab_id, ntab);
        p->p.mag.tab_iq = copy_array(&cur, params->mag.tab_iq, ntab);
    }
    mag_init(&p->mag, &p->p.mag);
    p->inv_J = params->mech.J > 0.0 ? 1.0 / params->mech.J : 0.0;

    uint64_t s = params->seed;
    for (int k = 0; k < 4; k++)
        p->rng[k] = splitmix64(&s);
    for (int k = 0; k < 4; k++) /* after the current channels' words: their stream is unchanged */
        p->rng_vdc[k] = splitmix64(&s);

    for (int k = 0; k < RING_CACHE; k++)
        p->ring_dt[k] = -1;
    p->filt_tau = params->sens.bandwidth_hz > 0.0 ? 1.0 / (TWO_PI * params->sens.bandwidth_hz) : 0.0;
    p->trig_th = p->bus_t = p->cur_psid = p->cur_psiq = p->load_t = p->load_lo = p->load_hi = NAN;
    p->gauss_next = p->gauss_vdc_next = GAUSS_BLOCK;
    p->adc_full = ldexp(1.0, params->sens.adc_bits);
    p->adc_inv_lsb = p->adc_full / (2.0 * params->sens.adc_range);
    p->vdc_codes = params->sens.vdc_range > 0.0 ? p->adc_full / params->sens.vdc_range : 0.0;
    p->x[X_PSID] = params->mag.psi_f; /* i = 0 */
    p->x[X_PSIQ] = 0.0;
    p->x[X_THM] = params->theta_m0;
    p->x[X_OMM] = params->omega_m0;
    double cos_th, sin_th, th;
    state_trig(p, &cos_th, &sin_th, &th);
    phase_currents(p, p->x, cos_th, sin_th, p->i_end); /* the steps keep it from here on */
    p->fault_tick = -1;
    fault_effects(p); /* neutral */
    advance(p, 0);    /* faults at tick 0 */
    return p;
}

/* The whole struct is the snapshot: the arrays it points to (owned, faults_owned, the parameters' profiles and
 * tables) are written once by plant_create and never change, so the copy and the plant share them. */
size_t plant_snapshot_size(void) { return sizeof(struct plant); }

void plant_save(const struct plant *p, void *buf) { memcpy(buf, p, sizeof *p); }

int plant_restore(struct plant *p, const void *buf)
{
    const struct plant *s = buf;

    if (s->self != p)
        return -1;
    memcpy(p, s, sizeof *p);
    return 0;
}

void plant_free(struct plant *p)
{
    if (p) {
        free(p->owned);
        free(p->faults_owned);
        free(p);
    }
}
