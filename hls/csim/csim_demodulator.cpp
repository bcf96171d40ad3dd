// C-ABI wrapper of the demodulator kernels over an event sequence (tests/test_hls_demodulator.py).
#include "csim_demodulator.h"
#include "hfi_demodulator.h"

namespace {

void store(const hfi_window_result &r, int32_t *out) {
    out[0] = r.gamma.to_int();
    out[1] = r.gamma_d.to_int();
    out[2] = r.sum_id.to_int();
    out[3] = r.sum_iq.to_int();
    out[4] = r.wsum.to_int();
    out[5] = r.n_samples.to_int();
}

}  // namespace

extern "C" int csim_demodulator_run(int n, const uint8_t *kind, const uint8_t *keep, const int16_t *i_d,
                                    const int16_t *i_q, const int16_t *w, int32_t *results) {
    hfi_demod_acc acc;
    hfi_demod_clear(acc);
    int latches = 0;
    for (int k = 0; k < n; k++) {
        switch (kind[k]) {
        case 0:
            if (keep[k])
                hfi_demod_sample(acc, i_d[k], i_q[k], w[k]);
            break;
        case 1:
            store(hfi_demod_latch(acc), results + 6 * latches);
            latches++;
            hfi_demod_clear(acc);
            break;
        case 2:
            hfi_demod_clear(acc);
            break;
        default:
            return -1;
        }
    }
    return latches;
}
