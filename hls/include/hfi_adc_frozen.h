// Frozen ADC lanes of a window, docs/spec.md 3.13 (golden/fpga/adc_frozen.py): WIN_ADC.
#ifndef HFI_ADC_FROZEN_H
#define HFI_ADC_FROZEN_H
#include "hfi_fixed.h"

// Bit 0 (FROZEN_A): n >= 2 and every code of adc_a equals the first; bit 1 (FROZEN_B) the same for adc_b.
ap_uint<2> hfi_adc_frozen(const ap_uint<16> *adc_a, const ap_uint<16> *adc_b, int n);

#endif
