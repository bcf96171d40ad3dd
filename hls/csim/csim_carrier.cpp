// C-ABI wrappers of the carrier kernel (docs/spec.md 2.1) over arrays, for tests/test_hls_carrier.py.
extern "C" {
#include "csim_carrier.h"
}
#include "hfi_carrier.h"

extern "C" void csim_carrier_effective_half(int n, const uint16_t *reg, uint16_t *out) {
    for (int i = 0; i < n; i++) {
        out[i] = hfi_effective_half(reg[i]).to_uint();
    }
}

extern "C" void csim_carrier_counter(int n, const uint32_t *phase, const uint16_t *half, uint16_t *counter) {
    for (int i = 0; i < n; i++) {
        counter[i] = hfi_carrier_counter(phase[i], half[i]).to_uint();
    }
}

// The strobes of one tick packed into the flags byte of the header.
static uint8_t pack_flags(const hfi_carrier_out &o) {
    return uint8_t(o.rising) | uint8_t(o.at_bottom) << 1 | uint8_t(o.at_top) << 2 | uint8_t(o.at_boundary) << 3;
}

extern "C" void csim_carrier_run(int n, const uint16_t *half, uint32_t *phase, uint16_t *counter, uint8_t *flags) {
    hfi_carrier_state st;
    st.phase = 0;
    for (int t = 0; t < n; t++) {
        const hfi_carrier_out o = hfi_carrier_tick(st, half[t]);
        phase[t] = o.phase.to_uint();
        counter[t] = o.counter.to_uint();
        flags[t] = pack_flags(o);
    }
}
