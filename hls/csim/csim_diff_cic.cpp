// C-ABI wrapper of the differencing / CIC kernel over a step sequence (tests/test_hls_diff_cic.py).
#include "csim_diff_cic.h"
#include "hfi_diff_cic.h"

extern "C" void csim_diff_cic_run(int n, const uint8_t *reset, const int16_t *i_alpha, const int16_t *i_beta,
                                  const uint8_t *plus, const uint8_t *cic_m, int32_t *q_a, int32_t *q_b,
                                  int32_t *e_a, int32_t *e_b) {
    hfi_diff_cic_state st;
    hfi_diff_cic_reset(st);
    for (int k = 0; k < n; k++) {
        if (reset && reset[k])
            hfi_diff_cic_reset(st);
        s21 qa, qb;
        s17 ea, eb;
        hfi_diff_cic_step(st, i_alpha[k], i_beta[k], plus[k] != 0, cic_m[k], qa, qb, ea, eb);
        q_a[k] = qa.to_int();
        q_b[k] = qb.to_int();
        e_a[k] = ea.to_int();
        e_b[k] = eb.to_int();
    }
}
