// C-ABI wrappers of the gate generator kernels (docs/spec.md 2.4), for tests/test_hls_gate_gen.py.
extern "C" {
#include "csim_gate_gen.h"
}
#include "hfi_carrier.h"
#include "hfi_gate_gen.h"

extern "C" void csim_gate_gen_effective_dead(int n, const uint16_t *reg, const uint16_t *dead_min, uint16_t *out) {
    for (int i = 0; i < n; i++) {
        out[i] = hfi_effective_dead(reg[i], dead_min[i]).to_uint();
    }
}

extern "C" void csim_gate_gen_carrier_run(int n_halves, uint16_t half, const uint16_t *cmps, const uint8_t *en,
                                          const uint16_t *dead, uint8_t *s, uint8_t *mask) {
    hfi_carrier_state car;
    car.phase = 0;
    hfi_gate_state st;
    hfi_gate_reset(st);
    u16 rise[3] = {0, 0, 0};
    u16 fall[3] = {0, 0, 0};
    const int n = n_halves * int(half);
    for (int t = 0; t < n; t++) {
        const hfi_carrier_out o = hfi_carrier_tick(car, half);
        const int k = t / int(half);                     // half period of this tick
        for (int x = 0; x < 3; x++) {
            if (o.at_bottom) {
                rise[x] = cmps[3 * k + x];
            }
            if (o.at_top) {
                fall[x] = cmps[3 * k + x];
            }
        }
        ap_uint<3> sw = 0;
        for (int x = 0; x < 3; x++) {
            sw[x] = hfi_ideal_switch(o.phase, half, rise[x], fall[x]);
        }
        s[t] = sw.to_uint();
        mask[t] = hfi_gate_tick(st, sw, en[t] != 0, dead[t]).to_uint();
    }
}

extern "C" void csim_gate_gen_run(int n, const uint8_t *s, const uint8_t *en, const uint16_t *dead, uint8_t *mask,
                                  uint16_t *el) {
    hfi_gate_state st;
    hfi_gate_reset(st);
    for (int t = 0; t < n; t++) {
        mask[t] = hfi_gate_tick(st, s[t], en[t] != 0, dead[t]).to_uint();
        for (int x = 0; x < 3; x++) {
            el[3 * t + x] = st.el[x].to_uint();
        }
    }
}

extern "C" void csim_gate_gen_advance(int n_seg, const uint8_t *s, const uint8_t *en, const uint16_t *dead,
                                      const uint32_t *len, uint8_t *mask_first, uint32_t *on_at, uint16_t *el) {
    hfi_gate_state st;
    hfi_gate_reset(st);
    for (int k = 0; k < n_seg; k++) {
        ap_uint<32> on[3];
        mask_first[k] = hfi_gate_advance(st, s[k], en[k] != 0, dead[k], len[k], on).to_uint();
        for (int x = 0; x < 3; x++) {
            on_at[3 * k + x] = on[x].to_uint();
            el[3 * k + x] = st.el[x].to_uint();
        }
    }
}
