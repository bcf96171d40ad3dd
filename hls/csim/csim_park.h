/* C-ABI wrappers of hfi_clarke and hfi_park (hls/src/hfi_park.cpp) for the C-simulation tests. */
#ifndef CSIM_PARK_H
#define CSIM_PARK_H
#include <stdint.h>
#ifdef __cplusplus
extern "C" {
#endif

/* hfi_clarke(i_a[k], i_b[k]) -> (i_alpha[k], i_beta[k]) for k < n. */
void csim_park_clarke(int n, const int16_t *i_a, const int16_t *i_b, int16_t *i_alpha, int16_t *i_beta);
/* hfi_park(i_alpha[k], i_beta[k], s[k], c[k]) -> (i_d[k], i_q[k]) for k < n. */
void csim_park(int n, const int16_t *i_alpha, const int16_t *i_beta, const int16_t *s, const int16_t *c,
               int16_t *i_d, int16_t *i_q);

#ifdef __cplusplus
}
#endif
#endif
