/* C-ABI wrapper of the modulator kernel (hls/src/hfi_modulator.cpp) for the C-simulation tests. */
#include <stdint.h>

/* cmp[3*i + x] = compare of leg x of hfi_modulator on vector i (top[i] != 0: carrier top, sign +1). */
void csim_modulator(int n, const int16_t *v_d, const int16_t *v_q, const int16_t *v_h, const int16_t *sin_q15,
                    const int16_t *cos_q15, const uint16_t *half, const uint8_t *top, uint16_t *cmp);
