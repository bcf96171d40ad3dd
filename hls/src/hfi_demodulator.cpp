// Demodulator and window sums: docs/spec.md 3.4, golden.fpga.demodulator (demodulate, latch_window).
#include "hfi_demodulator.h"

// Largest N_SAMPLES (u16): golden.fpga.demodulator.N_MAX.
static const ap_uint<16> HFI_N_MAX = 0xFFFF;

void hfi_demod_clear(hfi_demod_acc &acc) {
#pragma HLS INLINE
    acc.acc_q = 0;
    acc.acc_d = 0;
    acc.sum_d = 0;
    acc.sum_q = 0;
    acc.wsum = 0;
    acc.n = 0;
}

// One kept sample: acc_q += i_q*w, acc_d += i_d*w (s16 x s16 -> s32 into s48: fewer than 65535 samples
// x 2^30 < 2^47, no overflow), sum_d += i_d, sum_q += i_q, wsum += w (s33), n += 1 held at 65535
// (golden demodulate: N_SAMPLES = min(n, 65535)).
void hfi_demod_sample(hfi_demod_acc &acc, s16 i_d, s16 i_q, s16 w) {
#pragma HLS INLINE
    const ap_int<32> pq = hfi_mul(i_q, w), pd = hfi_mul(i_d, w);
    acc.acc_q += pq;
    acc.acc_d += pd;
    acc.sum_d += i_d;
    acc.sum_q += i_q;
    acc.wsum += w;
    if (acc.n != HFI_N_MAX)
        acc.n++;
}

// golden.fpga.demodulator.latch_window: GAMMA = sat(shr(acc_q, 15), 32), GAMMA_D = sat(shr(acc_d, 15), 32),
// SUM_ID = sat(sum_d, 32), SUM_IQ = sat(sum_q, 32), WSUM = sat(wsum, 32), N_SAMPLES = n.
hfi_window_result hfi_demod_latch(const hfi_demod_acc &acc) {
#pragma HLS INLINE
    hfi_window_result r;
    r.gamma = hfi_sat<32>(hfi_shr<15>(acc.acc_q));
    r.gamma_d = hfi_sat<32>(hfi_shr<15>(acc.acc_d));
    r.sum_id = hfi_sat<32>(acc.sum_d);
    r.sum_iq = hfi_sat<32>(acc.sum_q);
    r.wsum = hfi_sat<32>(acc.wsum);
    r.n_samples = acc.n;
    return r;
}
