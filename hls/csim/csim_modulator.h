/* C-ABI wrapper of the modulator kernel (hls/src/hfi_modulator.cpp) for the C-simulation tests. */
#include <stdint.h>

/* cmp[3*i + x] = compare of leg x of hfi_modulator on vector i (top[i] != 0: carrier top, sign +1).
 * rot[i] != 0: the rotating injection with (C, S) = (inj_cos[i], inj_sin[i]) (spec 3.5); rot[i] == 0 or
 * rot == NULL: the square wave (the kernel is still given inj_sin[i], inj_cos[i], which it must ignore).
 * inj_sin, inj_cos == NULL: 0. */
void csim_modulator(int n, const int16_t *v_d, const int16_t *v_q, const int16_t *v_h, const uint8_t *rot,
                    const int16_t *inj_sin, const int16_t *inj_cos, const int16_t *sin_q15,
                    const int16_t *cos_q15, const uint16_t *half, const uint8_t *top, uint16_t *cmp);
