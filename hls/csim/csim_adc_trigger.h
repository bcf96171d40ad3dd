/* C-ABI wrappers of the ADC trigger kernels (hls/src/hfi_adc_trigger.cpp) for the C-simulation tests. */
#include <stdint.h>

/* out[i] = hfi_effective_os_ticks(reg[i], os_min[i]). */
void csim_adc_trigger_effective_os(int n, const uint16_t *reg, const uint16_t *os_min, uint16_t *out);
/* hit[phi] = hfi_adc_trigger(phi, mode, half, os_ticks, os_min) for every phase phi of one period (2*half). */
void csim_adc_trigger_period(int mode, uint16_t half, uint16_t os_ticks, uint16_t os_min, uint8_t *hit);
/* n ticks of hfi_blank_tick from hfi_blank_reset; dropped[t] is its result for tick t. */
void csim_adc_trigger_blank_run(int n, const uint8_t *sw_event, const uint16_t *blank_ticks, uint8_t *dropped);
/* dropped[i] = hfi_blanked(since[i], blank_ticks[i]). */
void csim_adc_trigger_blanked(int n, const uint64_t *since, const uint16_t *blank_ticks, uint8_t *dropped);
