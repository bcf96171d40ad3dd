// C-ABI wrapper of the FCS-MPC kernel (docs/spec.md 3.10), for tests/test_hls_fcs_mpc.py.
extern "C" {
#include "csim_fcs_mpc.h"
}
#include "hfi_fcs_mpc.h"

extern "C" void csim_fcs_choose(int n, const int32_t *v_al, const int32_t *v_be, const int16_t *sin_q15,
                                const int16_t *cos_q15, const int16_t *a1, const int16_t *a2,
                                const uint16_t *phi_min, const uint8_t *constrain, const uint8_t *state_now,
                                uint8_t *state) {
    for (int i = 0; i < n; i++) {
        state[i] = hfi_fcs_choose(v_al[i], v_be[i], sin_q15[i], cos_q15[i], a1[i], a2[i], phi_min[i],
                                  constrain[i] != 0, state_now[i]).to_uint();
    }
}

extern "C" void csim_modulator_direct(int n, const int16_t *v_d, const int16_t *v_q, const int16_t *sin_q15,
                                      const int16_t *cos_q15, const int16_t *a1, const int16_t *a2,
                                      const uint16_t *phi_min, const uint8_t *constrain, const uint16_t *half,
                                      uint8_t state0, uint8_t *state, uint16_t *cmp) {
    ap_uint<3> s = state0;
    for (int i = 0; i < n; i++) {
        u16 out[3];
        s = hfi_modulator_direct(v_d[i], v_q[i], sin_q15[i], cos_q15[i], a1[i], a2[i], phi_min[i],
                                 constrain[i] != 0, s, half[i], out);
        state[i] = s.to_uint();
        for (int x = 0; x < 3; x++) {
            cmp[3 * i + x] = out[x].to_uint();
        }
    }
}
