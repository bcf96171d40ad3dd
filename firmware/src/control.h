/* control.h - the firmware's control algorithms, portable C (RV32IM and the host build alike).
 *
 * Every function is the C twin of a golden model in golden/firmware/ and performs the same integer
 * operations in the same order (docs/spec.md, section 5). Nothing here touches hardware: main.c reads
 * the window results from the hfi_dsp registers, calls fw_step() and writes the outputs back.
 * The host build (firmware/Makefile, target host) compiles this file into a shared library that
 * tests/test_fw_c.py checks against the golden model on random and corner-case inputs.
 *
 * This header is also parsed by cffi (hfi/fw_c.py, hfi/rtl_backend.py, tests): keep it to plain struct
 * definitions, stdint types and function prototypes; the preprocessor lines are stripped.
 */
#ifndef HFI_CONTROL_H
#define HFI_CONTROL_H

#include <stdint.h>

/* Supervisor states (golden.firmware.supervisor.MODE_*). */
enum fw_mode { FW_CONVERGE = 0, FW_POL_POS = 1, FW_POL_NEG = 2, FW_RELAX = 3, FW_RUN = 4, FW_FIXED = 5, FW_FAULT = 6,
               FW_IDENT = 7, FW_DONE = 8, FW_CATCH = 9 };

/* PI parameters (golden.firmware.pi.PiParams): kp in Q(sp), ki in Q(si), |u| <= limit. */
struct fw_pi_params {
    int32_t kp;
    int32_t sp;
    int32_t ki;
    int32_t si;
    int32_t limit;
    int64_t lim_i;          /* limit << si (golden PiParams.lim_i, derived there; the host writes it) */
};

/* Estimator methods (golden.firmware.estimator.METHOD_*): the ids a slot of fw_params names. */
enum fw_method { FW_METHOD_NONE = 0, FW_METHOD_SQW_BANGBANG = 1, FW_METHOD_RFO = 2, FW_METHOD_ROT_BPF = 3,
                 FW_METHOD_EEMF_SMO = 4, FW_METHOD_SQW_CIC = 5, FW_METHOD_HFO_PROJ = 6, FW_METHODS = 7 };

/* Polarity detection (golden.firmware.supervisor.POL_*). */
enum fw_pol_mode { FW_POL_CURRENT = 0, FW_POL_PILOT = 1, FW_POL_NONE = 2 };

/* Fault codes (golden.firmware.protection.FAULT_*; names in fw_fault_name). */
enum fw_fault { FW_FAULT_NONE = 0, FW_FAULT_OVERCURRENT = 1, FW_FAULT_OVERSPEED = 2, FW_FAULT_LOCK_LOSS = 3,
                FW_FAULT_TRACKING = 4, FW_FAULT_OVERLOAD = 5, FW_FAULT_HARDWARE = 6, FW_FAULT_IDENT = 7, FW_FAULT_HF_RESPONSE = 8,
                FW_FAULT_UNDERVOLTAGE = 9, FW_FAULT_OVERVOLTAGE = 10, FW_FAULT_SENSOR = 11, FW_FAULTS = 12 };

/* Limits of the fault checks (golden.firmware.protection.ProtParams; 0 turns a check off). */
struct fw_prot_params {
    int32_t r;               /* R_s, voltage LSB per current LSB, Q16 */
    int32_t ld;              /* L_d, L_q: flux LSB per current LSB, Q16 */
    int32_t lq;
    int32_t psi_f;           /* flux LSB */
    int32_t emf_k;           /* residual filter: time constant 2^emf_k periods */
    int32_t emf_tol;         /* voltage LSB, at standstill */
    int32_t psi_rel;         /* the limit's growth with speed, flux LSB */
    int32_t track_k;         /* tracking-error filter: 2^track_k periods */
    int32_t track_tol;       /* current LSB */
    int32_t ovl_n;           /* periods at the speed PI's limit */
    int32_t ovl_w;           /* growth of the speed error at the limit, speed LSB, */
    int32_t ovl_m;           /* for this many periods */
    int32_t w_max;           /* speed LSB */
    int32_t w_asc;           /* speed LSB */
    int32_t restarts;        /* automatic restarts at most (0: none) */
    int32_t restart_n;       /* periods in FAULT before each */
    int32_t catch_n;         /* the flying start: periods in CATCH at every start (0: off) */
    int32_t hf_k;            /* HF response check: filter time constant 2^hf_k periods */
    int32_t hf_tol;          /* HF response check: limit, share of the learned GAMMA_D, Q16 (0: off) */
    int32_t vdc_lo;          /* dc-link check: under- and overvoltage limits, VDC codes */
    int32_t vdc_hi;
    int32_t vdc_n;           /* periods in a row beyond a limit before the trip (0: off) */
    int32_t frz_n;           /* sensor check: periods in a row with a frozen current lane before the trip (0: off) */
    int32_t frz_min;         /* the fewest samples a window needs to count */
    int32_t probe_min;       /* the flying start's short-circuit probe: the least pulse current that finds the rotor
                              * (0: no probe; golden.firmware.catch_probe) */
    int32_t slip_w;          /* slip check: the speed above which the slots' agreement arms it, speed LSB (0: off) */
    int32_t slip_n;          /* the periods an agreement keeps it armed */
    int64_t ld_ct;           /* overload check's load part: n_p T_e / J per current LSB, Q24, and per LSB^2, Q40 */
    int64_t ld_cr;
    int32_t ld_k;            /* its filter: time constant 2^ld_k periods */
    int32_t ld_max;          /* its limit on the load's acceleration, speed LSB per period (0: off) */
};

/* Current-loop laws (golden.firmware.fcs_law.LAW_*). */
enum fw_law { FW_LAW_FOC_PWM = 0, FW_LAW_FCS_MPC = 1 };

/* Estimator slots of the supervisor (golden.firmware.estimator.SLOT_*). */
enum fw_slot { FW_SLOT_LOW = 0, FW_SLOT_HIGH = 1 };

/* PLL state (golden.firmware.pll.PllState). */
struct fw_pll {
    uint32_t theta;
    int32_t omega;
    int64_t integ;
};

/* Second-order section (golden.firmware.biquad): Q28 coefficients, and the last two inputs and outputs. */
struct fw_biquad_coef {
    int32_t b0;
    int32_t b1;
    int32_t b2;
    int32_t a1;
    int32_t a2;
};

struct fw_biquad {
    int32_t x1;
    int32_t x2;
    int32_t y1;
    int32_t y2;
};

/* ---- method sqw_bangbang (golden.firmware.sqw_bangbang) ---- */
struct fw_sqw_params {
    uint32_t k_bb;
    int32_t pll_kp;
    int32_t pll_ki;
    int32_t i_d;             /* current LSB, <= 0: the magnetizing current of a reluctance machine (0 on magnets) */
    int32_t xs_shift;        /* the cross-saturation table (golden SqwParams): grid step 2^xs_shift current LSB, */
    int16_t xs_gamma[33];    /* GAMMA LSB (s16) at |i_q| = k << xs_shift, */
    int32_t xs_len;          /* its points: 0 (off) or 2..33 */
};

struct fw_sqw_state {
    uint32_t theta;
    int32_t omega;
    struct fw_pll pll;
    int32_t hold;
};

/* ---- method rfo (golden.firmware.rfo) ---- */
struct fw_rfo_params {
    int32_t r_s;
    int32_t l_s;
    int32_t psi_f;
    int32_t k_c;
    int32_t k_min;
    int32_t k_r;
    int32_t pll_kp;
    int32_t pll_ki;
    int32_t i_d;
    int32_t l_dq;
};

struct fw_rfo_state {
    uint32_t theta;
    int32_t omega;
    struct fw_pll pll;
    int32_t x_al;
    int32_t x_be;
    int32_t i_al;
    int32_t i_be;
    int32_t a_mag;           /* the active flux's magnitude the last step aimed at (0 before the first) */
    int32_t mag;
    int32_t synced;          /* 0 from fw_init to the first sync: the flux is unknown, the correction at k_c */
};

/* ---- the speed loop's load-torque observer (golden.firmware.load_observer; g = 0: off) ----
 * 0 < g, l1, l2g < 2^31 when on (golden.control_config.load_observer_params checks them). */
struct fw_lobs_params {
    int32_t g;               /* Q16 speed per current LSB per speed-loop step */
    int32_t l1;              /* Q24 */
    int32_t l2g;             /* Q40 */
};

/* ---- method rot_bpf (golden.firmware.rot_bpf) ---- */
struct fw_rot_params {
    int32_t q_cos;
    int32_t q_sin;
    struct fw_biquad_coef bpf;
    int32_t n_avg;
    uint32_t offset;
    int32_t pll_kp;
    int32_t pll_ki;
    int32_t k_delay;
    int32_t n_hold;
    int32_t tracking;        /* golden.firmware.rot_bpf.TRACK_PLL 0, TRACK_OBSERVER 1 */
    int32_t c1;              /* the motion observer's gains (golden.firmware.motion; ranges: struct fw_cic_params) */
    int32_t c2;
    int32_t c3;
    int64_t c_t;
    int64_t c_r;
    int32_t i_d;             /* the d-current it asks for while in charge (<= 0) */
    int32_t xs_shift;        /* the cross-saturation table (golden RotParams): grid step 2^xs_shift current LSB, */
    int16_t xs_angle[33];    /* the negative sequence's turn in 2^16 binary angle at |i_q| = k << xs_shift (s16), */
    int32_t xs_len;          /* its points: 0 (off) or 2..33 (golden.firmware.mtpa.MTPA_LEN) */
};

struct fw_rot_state {
    uint32_t theta;
    int32_t omega;
    struct fw_pll pll;
    uint32_t theta_o;        /* the motion observer (TRACK_OBSERVER): angle, speed and load acceleration, Q24 */
    int64_t w;
    int64_t z;
    struct fw_biquad bd;
    struct fw_biquad bq;
    int32_t buf_d[32];       /* golden.firmware.rot_bpf.N_MAX */
    int32_t buf_q[32];
    int32_t idx;
    int32_t sum_d;
    int32_t sum_q;
    int32_t mag;
    int32_t err;
    int32_t hold;
};

/* ---- method eemf_smo (golden.firmware.eemf_smo) ---- */
struct fw_smo_params {
    int32_t c_v;
    int32_t c_r;
    int32_t c_x;
    int32_t k_lin;
    int32_t z_max;
    int32_t c_a;
    int32_t a_min;
    int32_t a_max;
    uint32_t lag0;
    int32_t pll_kp;
    int32_t pll_ki;
    int32_t k_delay;
    int32_t e_min;
    int32_t w_dir;
    int32_t i_d;
};

struct fw_smo_state {
    uint32_t theta;
    int32_t omega;
    struct fw_pll pll;
    int32_t ih_al;
    int32_t ih_be;
    int32_t ef_al;
    int32_t ef_be;
    int32_t mag;
    int32_t dir;
};

/* ---- method sqw_cic (golden.firmware.sqw_cic; Xue et al. 2022) ----
 * Ranges the C relies on (tests/test_fw_c.py draws over them; the host's values in brackets: xue2022_noload):
 *   g, c1, c2, c3, k_delay, q_min, n_hold: any int32_t            [124104, 4162, 198701, 12353, 147456, 328, 4]
 *       (g * wrap(psi - theta_o), c1 e, c2 e, c3 e, omega k_delay: 32 x 32 products, |.| <= 2^62)
 *   c_t: |c_t| <= 2^46 (int64_t: beyond 2^31 on real motors)    [4199825053]
 *       (c_t i_q with |i_q| <= 2^15: |.| <= 2^61)
 *   c_r: |c_r| <= 2^32 (int64_t)                                 [-1327144717]
 *       (c_r (i_d i_q) with |i_d i_q| <= 2^30: |.| <= 2^62, shifted by 16: <= 2^46)
 * so c2 e + ff is below 2^62 + 2^61 + 2^46 < 2^63 in magnitude, exact in int64; the sums with w and z
 * saturate as golden's sat(., 64) (overflow-checked adds). The int64_t members leave 4 bytes of padding in
 * each block, the same on RV32 (ilp32) and the host (x86-64): both align int64_t to 8. */
struct fw_cic_params {
    int32_t g;
    int32_t c1;
    int32_t c2;
    int32_t c3;
    int64_t c_t;
    int64_t c_r;
    int32_t k_delay;
    int32_t q_min;
    int32_t n_hold;
    int32_t i_d;             /* the d-current it asks for while in charge (<= 0; in the struct's former padding) */
    int32_t xs_shift;        /* the cross-saturation table (golden CicParams): grid step 2^xs_shift current LSB, */
    int16_t xs_angle[33];    /* the envelope's angle off d in 2^16 binary angle at |i_q| = k << xs_shift (s16), */
    int32_t xs_len;          /* its points: 0 (off) or 2..33 (golden.firmware.mtpa.MTPA_LEN) */
};

struct fw_cic_state {
    uint32_t theta_o;        /* the observer's angle (u32 binary angle) */
    int64_t w;               /* speed, Q24 binary angle per period */
    int64_t z;               /* acceleration integrator, Q24 binary angle per period^2 */
    int32_t hold;            /* periods left without error after a sync */
    int32_t err;             /* the last error e */
    int32_t mag;             /* vector_angle magnitude of the quadrature signal */
    uint32_t theta;
    int32_t omega;
};

/* ---- the flux-map look-up table (golden.firmware.flux_lut; Varatharajan et al. 2020, eqs. (8), (12)) ----
 * n_d x n_q points (2 <= n_d, n_q; n_d n_q <= 1024 = golden.firmware.flux_lut.LUT_MAX_POINTS = FW_LUT_MAX_POINTS
 * entries reserved per table), step 2^shift current LSB below knee, 2^coarse times that above. The flux tables
 * t_d, t_q are s16 in units of 2^f_shift flux units (0 <= f_shift <= 16 [13]; the look-up shifts the
 * interpolated value left by f_shift), the inductance tables s32; l_shift (0 <= l_shift <= 16 [10]) is the
 * projection's normalisation (golden.firmware.hfo_proj). The ranges the C relies on (tests/test_fw_c.py: the
 * host's tables of varatharajan2020_syrm, |t_l*| < 2^28, and currents up to 2^18):
 *   |i_d|, |i_q| <= 2^18, |t| < 2^28, shift <= 12, 0 <= coarse <= 4, f_shift <= 16: the interpolation's
 *   products below 2^62 (int64_t), the flux beyond the grid and the derivatives dl_* beyond s32 (so struct fw_lut_point is int64_t). */
struct fw_flux_lut {
    int32_t n_d;
    int32_t n_q;
    int32_t shift;
    int32_t knee;
    int32_t coarse;
    int32_t f_shift;
    int32_t l_shift;
    int16_t t_d[1024];       /* golden.firmware.flux_lut.LUT_MAX_POINTS (FW_LUT_MAX_POINTS, checked in control.c) */
    int16_t t_q[1024];
    int32_t t_ld[1024];
    int32_t t_lq[1024];
    int32_t t_ldq[1024];
};

/* golden.firmware.flux_lut.LutPoint */
struct fw_lut_point {
    int64_t lam_d;
    int64_t lam_q;
    int64_t l_d;
    int64_t l_q;
    int64_t l_dq;
    int64_t dl_d;
    int64_t dl_q;
    int64_t dl_dq;
};

/* ---- method hfo_proj (golden.firmware.hfo_proj; Varatharajan et al. 2020) ----
 * Ranges the C relies on (the host's values in brackets: varatharajan2020_torquestep): TOP_I s16;
 * 0 <= c_lag <= 2^16 (so the lag-corrected currents stay within 3 2^15 and their Park within the LUT's 2^18);
 * r_f, c_g, kp, ki, k_delay, g_b: int32_t; wg_b >= 1; eps_max >= 0; 0 <= dt_f, vth_f <= 2^28 [83886, 17088];
 * phi_min u16 [3641]; 1 <= s_knee <= 2^23 [2097152]; the LUT's ranges above.
 * Every intermediate is int64_t (the golden ints are unbounded; with these ranges none leaves int64). */
struct fw_hfo_params {
    struct fw_flux_lut lut;
    int32_t c_lag;
    int32_t r_f;
    int32_t dt_f;
    int32_t vth_f;
    int32_t c_g;
    int32_t phi_min;
    int32_t s_knee;
    int32_t n_max;
    int32_t g_b;
    int32_t wg_b;
    int32_t kp;
    int32_t ki;
    int32_t k_delay;
    int32_t eps_max;
    int32_t hold;
};

struct fw_hfo_state {
    uint32_t th;             /* angle predicted for the next carrier top */
    int64_t integ;           /* PLL integrator (Q24) */
    int32_t psi_al;          /* observed stator flux at the last top (stationary frame, flux units) */
    int32_t psi_be;
    int32_t lam_al;          /* the current model's flux at the last top */
    int32_t lam_be;
    int32_t i_al;            /* the last top currents (lag-corrected) */
    int32_t i_be;
    int32_t r_al;            /* and as sampled (TOP_I) */
    int32_t r_be;
    int32_t vec;             /* the state applied since the last top */
    int32_t vec_old;         /* the state before it */
    int32_t n_rej;
    int32_t since;
    uint32_t th_meas;
    int32_t eps_h;           /* diagnostics: the errors, the fusion weight (Q16) */
    int32_t eps_t;
    int32_t f;
    int64_t e_d;             /* diagnostics: the last low-speed error and strength [flux units] */
    int64_t s_h;
    uint32_t theta;
    int32_t omega;
    int32_t fcs_a1;          /* outputs for the fcs_mpc law (Estimator.fcs_a1, fcs_a2, constrain) */
    int32_t fcs_a2;
    int32_t constrain;
    int32_t cons_wait;
};

/* ---- control law fcs_mpc (golden.firmware.fcs_law.FcsParams) ----
 * t_d, t_q: the flux reference table (golden.firmware.mtpa.mtpa_lookup's grid, 2..33 points, len of them;
 * |t| < 2^30 so that the differences fit int32_t); r_f, r_v int32_t; 0 <= dt_f, vth_f <= 2^28; phi_min u16;
 * 1 <= v_lim <= 32767. len is C only (params_to_c: len(t_d)). */
struct fw_fcs_params {
    int32_t r_f;
    int32_t r_v;
    int32_t dt_f;
    int32_t vth_f;
    int32_t shift;
    int32_t t_d[33];         /* golden.firmware.mtpa.MTPA_LEN */
    int32_t t_q[33];
    int32_t phi_min;
    int32_t v_lim;
    int32_t len;
};

/* ---- self-commissioning: the identification program (golden.firmware.ident.IdentParams; docs/commissioning.md) ----
 * One array entry per step (n_steps <= FW_IDENT_MAX entries used; the arrays are written with the literal 160
 * because cffi parses this header without its preprocessor lines: control.c checks it against FW_IDENT_MAX).
 * IdentParams checks the ranges the C relies on: s_n >= 1, 0 <= s_m <= min(s_n, 32767) (M_MAX), |s_id|, |s_iq|
 * within s16, 0 <= s_vh <= 32767, F_FIT and F_POL not on step 0, F_FIT with s_vh[k] > s_vh[k - 1] (kp >= 0),
 * F_SNAP with s_n >= 2, 0 <= c_kp < 2^46, 0 <= c_ki <= 2^16, 1 <= v_lim <= 32767, 0 <= c_lvl, c_gain < 2^46,
 * 0 <= lvl_max <= 2^24, 1 <= i_slew <= 2^20, 0 <= vh_max <= 32767. n_steps: IdentParams.n_steps (a derived
 * field, init=False: hfi/fw_c.py ident_to_c writes it).
 * Neither block is part of struct fw_params / struct fw_state (nor of the config block, fw_config.h): together
 * they take about 10 KB, more than the RISC-V image has to spare in its 64 KiB of RAM. They sit in a
 * struct fw_ident that the state points to (fw_state.ident; NULL: no identification, the default image,
 * firmware/Makefile).
 * The sums (struct fw_ident_state): r_id, r_iq, r_vd, r_vq add s16-range means (the window current means of
 * s16 samples; the voltages within the PI limit turned by park: |v| < 46341) over at most M_MAX windows, so
 * int32; r_gd, r_gq add the s32 responses (int64); g2 saturates the responses to 24 bits (< 2^39 a window,
 * < 2^62 over 160 steps of M_MAX windows). One range golden does not check: the scan sums fit_x, fit_y add
 * r_g * 2^15 per F_SCAN step, within int64 while the sum over the scan steps of m (|GAMMA_D| + |GAMMA|) stays
 * below 2^47 (e.g. 2^31 responses over 2^15 summed scan windows). */
#define FW_IDENT_MAX 160 /* golden.firmware.ident.IDENT_MAX */

struct fw_ident_params {
    int32_t s_n[160];        /* windows of each step (FW_IDENT_MAX) */
    int32_t s_m[160];        /* how many of its last windows are summed */
    int32_t s_id[160];       /* current references in the step's frame */
    int32_t s_iq[160];
    int32_t s_vh[160];       /* HF amplitude before the level factor */
    uint32_t s_phi[160];     /* frame angle (u32 binary angle) */
    int32_t s_dw[160];       /* frame speed change per period */
    int32_t s_flags[160];    /* golden.firmware.ident.F_* */
    int64_t c_kp;
    int32_t c_ki;
    int32_t v_lim;
    int64_t c_lvl;
    int64_t c_gain;          /* F_GAIN: kp = c_gain v_h / G, 0..2^46 */
    int32_t lvl_max;         /* 0..2^24 */
    int32_t i_slew;          /* current LSB per period, 1..2^20 */
    int32_t vh_max;
    int32_t n_steps;
};

/* The executor's state (golden.firmware.ident.Ident): the step, the frame, the fitted angle and gains, the sums. */
struct fw_ident_state {
    int32_t k;               /* step index */
    int32_t n;               /* windows into the step */
    uint32_t theta;          /* frame angle */
    int32_t w;               /* frame speed, binary angle per period */
    uint32_t theta_r;        /* rotor angle found */
    int32_t kp;              /* current-PI gains (Q16), set at F_FIT */
    int32_t ki;
    int32_t lvl;             /* HF level factor (Q16), set at F_LEVEL */
    int32_t ref_d;           /* current references in use (slew-limited towards the step's) */
    int32_t ref_q;
    uint32_t jump;           /* the frame's turn at the last F_SET */
    int64_t fit_x;           /* scan sums */
    int64_t fit_y;
    int64_t fit_y0;
    int32_t failed;
    int32_t done;
    int32_t r_id[160];       /* per-step sums over the last m windows (FW_IDENT_MAX): the s16 means */
    int32_t r_iq[160];
    int32_t r_vd[160];
    int32_t r_vq[160];
    int64_t r_gd[160];       /* the responses */
    int64_t r_gq[160];
    int64_t g2;              /* the scan steps' noise sum: shr(sat(GAMMA_D, 24)^2 + sat(GAMMA, 24)^2, 8) */
};

/* The identification program and its executor (golden: FirmwareParams.ident and Firmware.ident), reached through
 * fw_state.ident. */
struct fw_ident {
    struct fw_ident_params p;
    struct fw_ident_state s;
};

/* Firmware parameters (golden.firmware.supervisor.FirmwareParams), computed on the host by
 * golden/control_config.py: the method of each slot, one parameter block per method (zero when no slot
 * uses it), the shared loops. fixed_enable = 1 selects the open-loop test at fixed_angle (FIXED);
 * mtpa_len = 0 (no table) and notch_on = 0 turn those blocks off. The identification program (golden's
 * FirmwareParams.ident) is not here: it comes with fw_state.ident. */
struct fw_params {
    int32_t low;
    int32_t high;
    struct fw_sqw_params sqw;
    struct fw_rfo_params rfo;
    struct fw_rot_params rot;
    struct fw_smo_params smo;
    struct fw_cic_params cic;
    struct fw_hfo_params hfo;
    int32_t speed_lp;
    struct fw_pi_params speed_pi;
    struct fw_pi_params id_pi;
    struct fw_pi_params iq_pi;
    int32_t v_h;
    int32_t i_pulse;
    int32_t n_converge;
    int32_t n_pulse;
    int32_t n_settle;
    int32_t i_trip;
    int32_t w_up;
    int32_t w_down;
    int32_t merge;
    int32_t fixed_enable;
    uint32_t fixed_angle;
    int32_t inj_rot;
    int32_t inj_cd;
    int32_t inj_sd;
    int32_t inj_c2;
    int32_t inj_s2;
    int32_t hf_dtc;
    int32_t pol_mode;
    int32_t v_pilot;
    int32_t mtpa_shift;
    int32_t mtpa_len;
    int32_t mtpa_id[33];     /* golden.firmware.mtpa.MTPA_LEN */
    int32_t mtpa_iq[33];
    int32_t notch_on;
    struct fw_biquad_coef notch;
    int32_t speed_div;
    int32_t i_slew;
    int32_t law;             /* enum fw_law */
    struct fw_fcs_params fcs;
    struct fw_prot_params prot;
    struct fw_lobs_params lobs;
    int32_t ff_nom;          /* dc-link voltage feed-forward (golden.firmware.dc_feedforward): 0 = off */
    int32_t ff_lo;
    int32_t ff_hi;
    uint32_t wd_delta;       /* the hand-over's watchdog (docs/methods.md): the slots' angle gap beyond which it acts
                              * (0 = off, below 2^31), the speed above which it acts and the periods its hand-over holds */
    int32_t wd_speed;
    int32_t wd_hold;
};

/* A divisor and its magic number for fw_window_means (control.c, div_magic): m and t are valid for n >= 3 and
 * are recomputed when the window's sample count differs from n (0: none yet). Not part of golden's state. */
struct fw_divisor {
    uint32_t n;
    int32_t m;
    int32_t t;
};

/* Register values written by one control step (golden.firmware.supervisor.Outputs). */
struct fw_outputs {
    int32_t v_d;
    int32_t v_q;
    int32_t v_h;
    int32_t sin;
    int32_t cos;
    int32_t enable;
    int32_t i_d_ref;
    int32_t i_q_ref;
    int32_t fcs_a1;          /* FCS_A.A1, A2: s16 Q12 (direct-vector mode, spec 3.10) */
    int32_t fcs_a2;
    int32_t fcs_phi_min;     /* FCS_CTRL.PHI_MIN, u16 */
    int32_t fcs_constrain;   /* FCS_CTRL.CONSTRAIN */
};

/* State of the control task (golden.firmware.supervisor.Firmware). */
struct fw_state {
    int32_t mode;
    int32_t n;
    uint32_t theta_hat;
    int32_t flipped;
    int64_t speed_f;
    int64_t speed_int;
    int64_t id_int;
    int64_t iq_int;
    int64_t pol_pos;
    int64_t pol_neg;
    int32_t i_d;
    int32_t i_q;
    int32_t i_d_ref;
    int32_t i_q_ref;
    int32_t active;          /* estimator slot in charge: 0 low-speed, 1 high-speed (docs/methods.md) */
    uint32_t est_theta[2];   /* each slot's angle output of the last step (u32 binary angle) */
    int32_t est_omega[2];    /* each slot's speed output of the last step (binary angle per period) */
    int32_t offset;          /* hand-over angle offset: angle in use - high slot's angle */
    struct fw_outputs hist[3];  /* the output history (golden Firmware.act[0], act[1], prev) as a ring: act[0]
                                 * (outputs of step k-2, active in this window) in hist[hist_at], act[1] (step k-1)
                                 * in the next slot, prev (step k-3, active in the window before) in the one after;
                                 * a step writes one slot and moves the index instead of copying two records */
    int32_t hist_at;            /* 0..2 */
    struct fw_divisor mean_div; /* the window means' divisor (fw_window_means) */
    int32_t speed_cnt;          /* periods since the last speed-PI step */
    int32_t i_s_ref;            /* speed-PI output, held between its steps */
    int32_t i_s_cmd;            /* the current command: i_s_ref through the slew limit */
    int64_t lobs_w;             /* load observer: speed, Q16 */
    int64_t lobs_i;             /* load observer: load current, Q32 (|.| <= speed_pi.limit << 32) */
    int32_t vec_before;         /* fcs_mpc: VECTOR of the previous step */
    int32_t fault;              /* enum fw_fault, set with FW_FAULT */
    int32_t asc;                /* 1: the safe state is the active short circuit */
    int32_t emf_d;              /* protection filters (the lock check's residual components) and overload counts */
    int32_t emf_q;
    int32_t track_f;
    int32_t ovl_n;
    int32_t ovl_e;
    int32_t e0;                 /* |speed error| when the speed PI reached its limit */
    int32_t ld_w;               /* overload check's load part: the last filtered speed, whether it holds one (0 at */
    int32_t ld_n;               /* every start) and the filtered load acceleration */
    int32_t ld_f;
    int32_t w_catch;            /* the speed a flying start caught, 0..2^31-1 (overspeed counts from it until the
                                 * hand-over down) */
    int32_t hf_ref;             /* HF response check: GAMMA_D learned in CONVERGE, the filtered deviation from it */
    int32_t hf_f;
    int32_t vdc_lo_n;           /* dc-link check: periods in a row below / above its limits */
    int32_t vdc_hi_n;
    int32_t frz_a;              /* sensor check: periods in a row with lane A / B frozen */
    int32_t frz_b;
    int32_t probe;              /* flying-start probe (golden.firmware.catch_probe): 0 on, 1 found, -1 off this start */
    int32_t pr_x0;              /* its gates-off window means (the sensors' offsets), pulse 1's mean less them, the */
    int32_t pr_y0;              /* angle found and the advance between the pulses */
    int32_t pr_x1;
    int32_t pr_y1;
    uint32_t pr_theta;
    int32_t pr_delta;
    int32_t restarts;           /* automatic restarts done */
    struct fw_biquad nd;        /* feedback notch states */
    struct fw_biquad nq;
    struct fw_sqw_state sqw;    /* one state block per method */
    struct fw_rfo_state rfo;
    struct fw_rot_state rot;
    struct fw_smo_state smo;
    struct fw_cic_state cic;
    struct fw_hfo_state hfo;
    int32_t wd_n;                  /* the hand-over's watchdog: periods its hand-over still holds (after the blocks:
                                    * the members before keep their offsets, the cache layout of the state) */
    int32_t slip_left;             /* the slip check (protection.slip_check): periods the last agreement still arms it */
    struct fw_ident *ident;        /* the identification program and its executor's state (golden:
                                    * FirmwareParams.ident, Firmware.ident); NULL: none. Set by the caller before
                                    * fw_init, which keeps it (the only member it does not clear; with FW_NO_IDENT
                                    * it clears it too). fw_state (8-byte aligned) has no 4-byte hole on RV32:
                                    * wherever it goes it grows the struct by 8 (960 -> 968, 4 of them padding). */
};

/* Window results of the demodulator (registers GAMMA ... N_SAMPLES; not WSUM, which nothing here uses). */
struct fw_window {
    int32_t gamma;          /* GAMMA, GAMMA_D: read by main.c only when the square-wave response is used (0 else) */
    int32_t gamma_d;
    int32_t sum_id;
    int32_t sum_iq;
    uint32_t n_samples;
    uint32_t inj_phase;     /* INJ_PHASE (golden WindowResult.inj_phase) */
    int32_t cic_qa;         /* CIC_QA, CIC_QB: s21 (golden WindowResult.cic_qa, cic_qb; the estimator sqw_cic) */
    int32_t cic_qb;
    int32_t vector;         /* VECTOR.STATE, u3 (golden WindowResult.vector; the direct-vector mode) */
    int32_t vector_next;    /* VECTOR.NEXT, u3 (golden WindowResult.vector_next) */
    int32_t top_ia;         /* TOP_I: s16 each, the Clarke currents of the carrier-top sample */
    int32_t top_ib;
    uint32_t vdc;           /* VDC.CODE, uB: the dc-link channel's code of the carrier-bottom sample (spec 3.12) */
    uint32_t status;        /* WIN_FAULT: STATUS's fault latches (FAULT_OC, WDT, STO, DESAT, at their STATUS bit
                             * positions) at the window boundary (docs/spec.md 2.2), other bits 0 */
    uint32_t frozen;        /* WIN_ADC: FROZEN_A, FROZEN_B, the current lanes that returned one code for every
                             * conversion of the window (docs/spec.md 3.13), other bits 0 */
};

/* What every estimator gets once per period (golden.firmware.estimator.Measurement). */
struct fw_meas {
    const struct fw_window *win;
    int32_t i_d;
    int32_t i_q;
    int32_t sin;
    int32_t cos;
    int32_t v_al;
    int32_t v_be;
    int32_t inj_sin;
    int32_t inj_cos;
};

/* golden.firmware.means.window_means */
void fw_window_means(struct fw_divisor *div, int32_t sum_id, int32_t sum_iq, uint32_t n, int32_t *i_d,
                     int32_t *i_q);
/* golden.firmware.bangbang.bangbang_step */
uint32_t fw_bangbang_step(uint32_t theta_hat, int32_t gamma, uint32_t k_bb);
/* golden.firmware.pll.pll_step (updates *s in place) */
void fw_pll_step(struct fw_pll *s, uint32_t theta_hat, int32_t kp, int32_t ki);
/* golden.firmware.lowpass.lowpass_step / lowpass_out */
int64_t fw_lowpass_step(int64_t f, int32_t x, int32_t a);
int32_t fw_lowpass_out(int64_t f);
/* golden.firmware.pi.pi_step: returns u, updates *integ */
int32_t fw_pi_step(int64_t *integ, int32_t ref, int32_t meas, const struct fw_pi_params *p);
/* golden.fpga.cordic.sincos_q15(angle, 32, 16): the firmware's sin/cos of theta_hat, Q1.15 */
void fw_sincos_q15(uint32_t angle, int32_t *sin_q15, int32_t *cos_q15);
/* the same in two halves, so that the SoC's CORDIC (18 clocks) runs while the CPU does other work: fw_sincos_start(angle),
 * then fw_sincos_take gives fw_sincos_q15(angle); no other sin/cos in between */
void fw_sincos_start(uint32_t angle);
void fw_sincos_take(int32_t *sin_q15, int32_t *cos_q15);
/* the accelerators' CAPS register (the SoC build with them only: fw_acc.c) */
uint32_t fw_acc_caps(void);
/* golden.firmware.vector.vector_angle: |x|, |y| <= 2^28 */
void fw_vector_angle(int32_t x, int32_t y, uint32_t *angle, int32_t *mag);
/* golden.firmware.catch_probe.probe_estimate: returns found (0/1), *theta and *delta (0 when not found) */
int32_t fw_probe_estimate(int32_t d1x, int32_t d1y, int32_t d2x, int32_t d2y, int32_t i_min, uint32_t *theta,
                          int32_t *delta);
/* golden.firmware.catch_probe.probe_angles */
void fw_probe_angles(uint32_t theta, int32_t delta, int32_t *omega, uint32_t *theta_a, uint32_t *theta_b);
/* golden.firmware.biquad.biquad_step (updates *s; the output is s->y1) */
void fw_biquad_step(struct fw_biquad *s, int32_t x, const struct fw_biquad_coef *c);
/* golden.firmware.mtpa.mtpa_lookup */
void fw_mtpa_lookup(uint32_t i_s, int32_t shift, int32_t len, const int32_t *t_d, const int32_t *t_q, int32_t *i_d,
                    int32_t *i_q);
/* golden.firmware.estimator.injection_voltage */
void fw_injection_voltage(int32_t v_now, int32_t v_before, int32_t s, int32_t c, int32_t cd, int32_t sd, int32_t *v_al,
                          int32_t *v_be);
/* golden.firmware.estimator.window_voltage */
void fw_window_voltage(const struct fw_outputs *now, const struct fw_outputs *before, int32_t *v_al, int32_t *v_be);

/* The flux outputs of an estimator (golden.firmware.estimator.Estimator.psi_al ... constrain). */
struct fw_est_flux {
    int32_t psi_al;
    int32_t psi_be;
    int32_t fcs_a1;
    int32_t fcs_a2;
    int32_t constrain;
};

/* golden.fpga.fcs_mpc.state_voltage */
void fw_state_voltage(int32_t state, int32_t *v_al, int32_t *v_be);
/* golden.firmware.flux_lut.warp / lut_flux / lut_point */
int32_t fw_warp(int32_t x, int32_t knee, int32_t coarse);
void fw_lut_flux(const struct fw_flux_lut *lut, int32_t i_d, int32_t i_q, int64_t *lam_d, int64_t *lam_q);
void fw_lut_point(const struct fw_flux_lut *lut, int32_t i_d, int32_t i_q, struct fw_lut_point *pt);
/* golden.firmware.hfo_proj.projection_coefficients */
void fw_projection_coefficients(const struct fw_lut_point *pt, int32_t l_shift, int32_t *a1, int32_t *a2);
/* golden.firmware.applied_flux.applied_flux */
void fw_applied_flux(int32_t old, int32_t new_state, int32_t i_al, int32_t i_be, int32_t dt_f, int32_t vth_f,
                     int32_t *f_al, int32_t *f_be);
/* golden.firmware.fcs_law.flux_reference / deadbeat_voltage (nxt: VECTOR.NEXT); the deadbeat's sin, cos: of theta
 * (golden.fpga.cordic.sincos_q15), the output records' angle (Firmware._fcs_outputs), computed once */
void fw_flux_reference(const struct fw_fcs_params *p, int32_t i_s, int32_t *d, int32_t *q);
void fw_deadbeat_voltage(const struct fw_fcs_params *p, int32_t psi_al, int32_t psi_be, int32_t i_al, int32_t i_be,
                         int32_t before, int32_t vector, int32_t nxt, uint32_t theta, int32_t omega,
                         int32_t i_s, int32_t *v_d, int32_t *v_q, int32_t *sin_q15, int32_t *cos_q15);

/* The estimator plug-in interface (golden.firmware.estimator.Estimator), one entry per method in
 * fw_methods[] (control.c). Each member reads and writes only its own state block of fw_state and
 * parameter block of fw_params; step returns the angle and speed outputs. */
struct fw_est_ops {
    void (*step)(struct fw_state *st, const struct fw_params *p, const struct fw_meas *m, uint32_t *theta,
                 int32_t *omega);
    void (*turn)(struct fw_state *st, uint32_t delta);
    void (*sync)(struct fw_state *st, const struct fw_params *p, uint32_t theta, int32_t omega);
    int32_t (*i_d)(const struct fw_params *p);   /* d-current reference while in charge (RUN) */
    /* a flux-observing method (MethodInfo.flux): psi_al, psi_be, fcs_a1, fcs_a2, constrain after step
     * (Estimator's attributes); NULL for the others (all 0) */
    void (*flux)(const struct fw_state *st, struct fw_est_flux *f);
    /* the idle loop's work for the method (main.c, fw_idle: between the steps, interrupted by them): reads the
     * state, writes nothing (e.g. warms the step's code in the instruction cache); NULL for most */
    void (*idle)(const struct fw_state *st, const struct fw_params *p);
};

/* FW_IDLE_WARM: 1 where the idle loop warms a method's code (fw_hfo_idle): the SoC build with the accelerators (the
 * 003 drive's) and the host build (its tests); the build without them has neither the room nor the 003 drive at
 * its own rate (docs/boards.md) */
#if defined(FW_ACC) || !defined(__riscv)
#define FW_IDLE_WARM 1
#else
#define FW_IDLE_WARM 0
#endif

/* Set by a method's step when its idle op has work before the next step (fw_hfo_idle: below the 003 drive's fusion
 * band), cleared by fw_idle: the idle loop (main.c run) calls fw_idle only then, so at other times it runs no code
 * beyond its own (no instruction-cache line of a step evicted). */
extern volatile int32_t fw_idle_work;

#if FW_IDLE_WARM
/* The idle loop's work (main.c run, between the control steps, while fw_idle_work is set): each configured
 * method's idle op. */
void fw_idle(const struct fw_state *st, const struct fw_params *p);
#endif

/* Method sqw_bangbang (golden.firmware.sqw_bangbang.SquareWaveBangBang) */
void fw_sqw_step(struct fw_state *st, const struct fw_params *p, const struct fw_meas *m, uint32_t *theta,
                 int32_t *omega);
void fw_sqw_turn(struct fw_state *st, uint32_t delta);
void fw_sqw_sync(struct fw_state *st, const struct fw_params *p, uint32_t theta, int32_t omega);
int32_t fw_sqw_i_d(const struct fw_params *p);
/* Method rfo (golden.firmware.rfo.RotorFluxObserver) */
int32_t fw_rfo_correction(int32_t psi_f, int32_t mag);   /* golden.firmware.rfo step 5 */
/* golden.fixed: sat(c_div(n, d), bits) for d != 0, |n|, |d| < 2^63, 2 <= bits <= 22, without a 64-bit division */
int32_t fw_sat_div64(int64_t n, int64_t d, int32_t bits);
void fw_rfo_step(struct fw_state *st, const struct fw_params *p, const struct fw_meas *m, uint32_t *theta,
                 int32_t *omega);
void fw_rfo_turn(struct fw_state *st, uint32_t delta);
void fw_rfo_sync(struct fw_state *st, const struct fw_params *p, uint32_t theta, int32_t omega);
int32_t fw_rfo_i_d(const struct fw_params *p);
/* Method rot_bpf (golden.firmware.rot_bpf.RotatingBpf) */
void fw_rot_step(struct fw_state *st, const struct fw_params *p, const struct fw_meas *m, uint32_t *theta,
                 int32_t *omega);
void fw_rot_turn(struct fw_state *st, uint32_t delta);
void fw_rot_sync(struct fw_state *st, const struct fw_params *p, uint32_t theta, int32_t omega);
int32_t fw_rot_i_d(const struct fw_params *p);
/* Method eemf_smo (golden.firmware.eemf_smo.EemfSmo) */
void fw_smo_step(struct fw_state *st, const struct fw_params *p, const struct fw_meas *m, uint32_t *theta,
                 int32_t *omega);
void fw_smo_turn(struct fw_state *st, uint32_t delta);
void fw_smo_sync(struct fw_state *st, const struct fw_params *p, uint32_t theta, int32_t omega);
int32_t fw_smo_i_d(const struct fw_params *p);
/* Method sqw_cic (golden.firmware.sqw_cic.SquareWaveCic) */
void fw_cic_step(struct fw_state *st, const struct fw_params *p, const struct fw_meas *m, uint32_t *theta,
                 int32_t *omega);
void fw_cic_turn(struct fw_state *st, uint32_t delta);
void fw_cic_sync(struct fw_state *st, const struct fw_params *p, uint32_t theta, int32_t omega);
int32_t fw_cic_i_d(const struct fw_params *p);
/* Method hfo_proj (golden.firmware.hfo_proj.HybridFluxProjection) */
void fw_hfo_step(struct fw_state *st, const struct fw_params *p, const struct fw_meas *m, uint32_t *theta,
                 int32_t *omega);
void fw_hfo_turn(struct fw_state *st, uint32_t delta);
void fw_hfo_sync(struct fw_state *st, const struct fw_params *p, uint32_t theta, int32_t omega);
int32_t fw_hfo_i_d(const struct fw_params *p);
void fw_hfo_flux(const struct fw_state *st, struct fw_est_flux *f);
void fw_hfo_idle(const struct fw_state *st, const struct fw_params *p);

/* golden.firmware.supervisor.Firmware(params) and Firmware.step(win, speed_ref). fw_init keeps st->ident (the
 * caller sets it first: the identification program in its p, or NULL) and with a program starts in FW_IDENT.
 * Built with FW_NO_IDENT (the RISC-V image, firmware/Makefile) the executor is compiled out: fw_init clears
 * st->ident with the rest (the start-up as with NULL). */
void fw_init(struct fw_state *st, const struct fw_params *p);
void fw_emf_residual(const struct fw_prot_params *p, int32_t v_d, int32_t v_q, int32_t i_d, int32_t i_q,
                     int32_t omega, int32_t *e_d, int32_t *e_q);
int32_t fw_protect_step(struct fw_state *st, const struct fw_prot_params *p, int32_t v_d, int32_t v_q, int32_t i_d,
                        int32_t i_q, int32_t i_d_ref, int32_t i_q_ref, int32_t omega_f, int32_t speed_ref,
                        int32_t at_limit, int32_t hf_on, int32_t hf);
void fw_hf_learn(struct fw_state *st, const struct fw_prot_params *p, int32_t gamma_d);
int32_t fw_dc_link_check(struct fw_state *st, const struct fw_prot_params *p, uint32_t vdc);
int32_t fw_frozen_check(struct fw_state *st, const struct fw_prot_params *p, uint32_t frozen, uint32_t n_samples);
int32_t fw_slip_check(struct fw_state *st, const struct fw_prot_params *p, int32_t low_in_charge, int32_t gap,
                      int32_t omega_f, int32_t omega_hi);
void fw_dc_feedforward(struct fw_outputs *out, uint32_t vdc, int32_t ff_nom, int32_t ff_lo, int32_t ff_hi);
const char *fw_fault_name(int32_t code);
void fw_step(struct fw_state *st, const struct fw_params *p, const struct fw_window *win, int32_t speed_ref,
             struct fw_outputs *out);
int fw_reads_gamma(const struct fw_state *st, const struct fw_params *p);
int fw_uses_xs_tables(const struct fw_params *p);

#endif
