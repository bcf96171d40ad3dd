// ADC offset and scale, docs/spec.md 3.1 (golden/fpga/adc_scale.py). One call per ADC sample.
#ifndef HFI_ADC_SCALE_H
#define HFI_ADC_SCALE_H
#include "hfi_fixed.h"

// code: B-bit offset-binary ADC code (0..2^B-1); bits: B, 1..16; offset: ADC_OFFSET (s16, current
// LSB); gain: ADC_GAIN (u16 Q2.14). Returns the phase current, s16 (2^15 = full scale).
s16 hfi_adc_scale(ap_uint<16> code, ap_uint<5> bits, s16 offset, u16 gain);

#endif
