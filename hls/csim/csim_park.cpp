// C-ABI wrappers of hfi_clarke and hfi_park over arrays (tests/test_hls_park.py).
#include "csim_park.h"
#include "hfi_park.h"

extern "C" void csim_park_clarke(int n, const int16_t *i_a, const int16_t *i_b, int16_t *i_alpha,
                                 int16_t *i_beta) {
    for (int k = 0; k < n; k++) {
        s16 al, be;
        hfi_clarke(i_a[k], i_b[k], al, be);
        i_alpha[k] = al.to_int();
        i_beta[k] = be.to_int();
    }
}

extern "C" void csim_park(int n, const int16_t *i_alpha, const int16_t *i_beta, const int16_t *s,
                          const int16_t *c, int16_t *i_d, int16_t *i_q) {
    for (int k = 0; k < n; k++) {
        s16 d, q;
        hfi_park(i_alpha[k], i_beta[k], s[k], c[k], d, q);
        i_d[k] = d.to_int();
        i_q[k] = q.to_int();
    }
}
