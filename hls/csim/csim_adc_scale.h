/* C-ABI wrapper of hfi_adc_scale (hls/src/hfi_adc_scale.cpp) for the C-simulation tests. */
#ifndef CSIM_ADC_SCALE_H
#define CSIM_ADC_SCALE_H
#include <stdint.h>
#ifdef __cplusplus
extern "C" {
#endif

/* i[k] = hfi_adc_scale(code[k], bits, offset[k], gain[k]) for k < n. */
void csim_adc_scale(int n, int bits, const uint16_t *code, const int16_t *offset, const uint16_t *gain,
                    int16_t *i);

#ifdef __cplusplus
}
#endif
#endif
