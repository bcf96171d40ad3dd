// C-ABI wrapper of the modulator kernel (docs/spec.md 3.5), for tests/test_hls_modulator.py.
extern "C" {
#include "csim_modulator.h"
}
#include "hfi_modulator.h"

extern "C" void csim_modulator(int n, const int16_t *v_d, const int16_t *v_q, const int16_t *v_h,
                               const uint8_t *rot, const int16_t *inj_sin, const int16_t *inj_cos,
                               const int16_t *sin_q15, const int16_t *cos_q15, const uint16_t *half,
                               const uint8_t *top, uint16_t *cmp) {
    for (int i = 0; i < n; i++) {
        const bool r = rot != nullptr && rot[i] != 0;
        const int16_t s_r = inj_sin != nullptr ? inj_sin[i] : 0, c_r = inj_cos != nullptr ? inj_cos[i] : 0;
        u16 out[3];
        hfi_modulator(v_d[i], v_q[i], v_h[i], r, s_r, c_r, sin_q15[i], cos_q15[i], half[i], top[i] != 0, out);
        for (int x = 0; x < 3; x++) {
            cmp[3 * i + x] = out[x].to_uint();
        }
    }
}
