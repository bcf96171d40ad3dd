// Sample differencing, envelope by sample-rate conversion and CIC interpolation, docs/spec.md 3.9
// (golden/fpga/diff_cic.py; Xue et al. 2022, Sec. 3.1-3.2, eqs. (7)-(8), Figs. 4 and 8): one step per
// PWM period, on the stationary-frame current of the carrier-bottom sample.
//
// Per component: d = i - p (eq. (7) without its 1/2, s17) across a period with +V_H (plus) becomes the
// held envelope e (the first sample after reset only fills p); comb c = e - x[M-1] on the delay line x
// (x[0] the newest), x shifts in e, integrator y = wrap(y + c, 21) (eq. (8), one stage): q = y is the sum
// of the last M held envelope values. A change of the clamped comb delay M clears x and y.
#ifndef HFI_DIFF_CIC_H
#define HFI_DIFF_CIC_H
#include "hfi_fixed.h"

static const int HFI_CIC_M_MAX = 16;    // golden.fpga.diff_cic.M_MAX: the delay line's length

typedef ap_int<17> s17;                 // a difference and the held envelope (D_BITS)
typedef ap_int<21> s21;                 // the integrator (Y_BITS): M_MAX values of 17 bits fit

struct hfi_diff_cic_state {
    bool valid;                          // a previous sample p exists
    s16 p[2];                            // previous bottom sample (alpha, beta)
    s17 e[2];                            // held envelope
    s17 x[2][HFI_CIC_M_MAX];             // comb delay line, x[k][0] the newest
    s21 y[2];                            // integrator (wraps, two's complement)
    ap_uint<5> m;                        // comb delay in use (reset: 0, none)
};

// Reset: no previous sample, everything 0, no comb delay in use.
void hfi_diff_cic_reset(hfi_diff_cic_state &st);

// The comb delay in use for a CIC_M register value: 0 as 1, above M_MAX as M_MAX.
ap_uint<5> hfi_cic_m(ap_uint<8> cic_m_reg);

// One carrier-bottom sample (golden DiffCic.step): current (i_alpha, i_beta), plus = the period that
// ended at this sample ran +V_H, cic_m = the CIC_M register. Outputs q = y and the held envelope e.
void hfi_diff_cic_step(hfi_diff_cic_state &st, s16 i_alpha, s16 i_beta, bool plus, ap_uint<8> cic_m,
                       s21 &q_a, s21 &q_b, s17 &e_a, s17 &e_b);

#endif
