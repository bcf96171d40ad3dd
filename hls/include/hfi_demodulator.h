// Demodulator and window sums, docs/spec.md 3.4 (golden/fpga/demodulator.py): one accumulate per
// kept sample, one latch + clear at each window boundary (the carrier rising zero crossing).
#ifndef HFI_DEMODULATOR_H
#define HFI_DEMODULATOR_H
#include "hfi_fixed.h"

struct hfi_demod_acc {
    ap_int<48> acc_q, acc_d;     // sum of i_q*w, i_d*w
    ap_int<33> sum_d, sum_q, wsum;
    ap_uint<16> n;
};

struct hfi_window_result {      // the status registers GAMMA .. N_SAMPLES
    s32 gamma, gamma_d, sum_id, sum_iq, wsum;
    ap_uint<16> n_samples;
};

void hfi_demod_clear(hfi_demod_acc &acc);
void hfi_demod_sample(hfi_demod_acc &acc, s16 i_d, s16 i_q, s16 w);
// The latched window result of the accumulators (the caller clears them for the next window).
hfi_window_result hfi_demod_latch(const hfi_demod_acc &acc);

#endif
