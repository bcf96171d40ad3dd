/* C-ABI wrapper of hfi_adc_frozen (hls/src/hfi_adc_frozen.cpp) for the C-simulation tests. */
#ifndef CSIM_ADC_FROZEN_H
#define CSIM_ADC_FROZEN_H
#include <stdint.h>
#ifdef __cplusplus
extern "C" {
#endif

/* hfi_adc_frozen of the n codes of each lane (n <= 4096). */
int csim_adc_frozen(const uint16_t *adc_a, const uint16_t *adc_b, int n);

#ifdef __cplusplus
}
#endif
#endif
