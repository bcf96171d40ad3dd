/* C-ABI wrapper of the differencing / CIC kernel (hls/src/hfi_diff_cic.cpp) for the C-simulation tests. */
#ifndef CSIM_DIFF_CIC_H
#define CSIM_DIFF_CIC_H
#include <stdint.h>
#ifdef __cplusplus
extern "C" {
#endif

/* n steps of hfi_diff_cic_step from hfi_diff_cic_reset: step k with i_alpha[k], i_beta[k], plus[k] != 0 and
 * the CIC_M register cic_m[k]; q_a[k], q_b[k], e_a[k], e_b[k] are its outputs (sign-extended). If reset is
 * not NULL, reset[k] != 0 resets the state before step k. */
void csim_diff_cic_run(int n, const uint8_t *reset, const int16_t *i_alpha, const int16_t *i_beta,
                       const uint8_t *plus, const uint8_t *cic_m, int32_t *q_a, int32_t *q_b, int32_t *e_a,
                       int32_t *e_b);

#ifdef __cplusplus
}
#endif
#endif
