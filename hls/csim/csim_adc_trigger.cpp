// C-ABI wrappers of the ADC trigger kernels (docs/spec.md 2.3), for tests/test_hls_adc_trigger.py.
extern "C" {
#include "csim_adc_trigger.h"
}
#include "hfi_adc_trigger.h"

extern "C" void csim_adc_trigger_effective_os(int n, const uint16_t *reg, const uint16_t *os_min, uint16_t *out) {
    for (int i = 0; i < n; i++) {
        out[i] = hfi_effective_os_ticks(reg[i], os_min[i]).to_uint();
    }
}

extern "C" void csim_adc_trigger_period(int mode, uint16_t half, uint16_t os_ticks, uint16_t os_min, uint8_t *hit) {
    const int period = 2 * int(half);
    for (int phi = 0; phi < period; phi++) {
        hit[phi] = hfi_adc_trigger(phi, mode, half, os_ticks, os_min);
    }
}

extern "C" void csim_adc_trigger_blank_run(int n, const uint8_t *sw_event, const uint16_t *blank_ticks,
                                           uint8_t *dropped) {
    hfi_blank_state st;
    hfi_blank_reset(st);
    for (int t = 0; t < n; t++) {
        dropped[t] = hfi_blank_tick(st, sw_event[t] != 0, blank_ticks[t]);
    }
}

extern "C" void csim_adc_trigger_blanked(int n, const uint64_t *since, const uint16_t *blank_ticks, uint8_t *dropped) {
    for (int i = 0; i < n; i++) {
        dropped[i] = hfi_blanked(since[i], blank_ticks[i]);
    }
}
