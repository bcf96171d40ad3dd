/* C-ABI wrapper of the dead-time compensation kernel (hls/src/hfi_deadtime_comp.cpp) for the tests. */
#include <stdint.h>

/* cmp_out[3*i + x] = leg x of hfi_deadtime_comp on vector i (cmp_in[3*i + x]; top[i] != 0: falling half). */
void csim_deadtime_comp(int n, const uint16_t *cmp_in, const uint8_t *top, const uint16_t *half, const uint16_t *dead,
                        const uint16_t *gain, const int16_t *i_d_ref, const int16_t *i_q_ref, const uint16_t *hf_amp,
                        const int16_t *sin_q15, const int16_t *cos_q15, const uint32_t *recip_h, uint16_t *cmp_out);
