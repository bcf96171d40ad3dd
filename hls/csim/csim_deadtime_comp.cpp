// C-ABI wrapper of the dead-time compensation kernel (docs/spec.md 3.6), for tests/test_hls_deadtime_comp.py.
extern "C" {
#include "csim_deadtime_comp.h"
}
#include "hfi_deadtime_comp.h"

extern "C" void csim_deadtime_comp(int n, const uint16_t *cmp_in, const uint8_t *top, const uint16_t *half,
                                   const uint16_t *dead, const uint16_t *gain, const int16_t *i_d_ref,
                                   const int16_t *i_q_ref, const uint16_t *hf_amp, const int16_t *sin_q15,
                                   const int16_t *cos_q15, const uint32_t *recip_h, uint16_t *cmp_out) {
    for (int i = 0; i < n; i++) {
        u16 in[3];
        u16 out[3];
        for (int x = 0; x < 3; x++) {
            in[x] = cmp_in[3 * i + x];
        }
        hfi_deadtime_comp(in, top[i] != 0, half[i], dead[i], gain[i], i_d_ref[i], i_q_ref[i], hf_amp[i],
                          sin_q15[i], cos_q15[i], recip_h[i], out);
        for (int x = 0; x < 3; x++) {
            cmp_out[3 * i + x] = out[x].to_uint();
        }
    }
}
