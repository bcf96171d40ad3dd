// C-ABI wrapper of hfi_adc_scale over arrays (tests/test_hls_adc_scale.py).
#include "csim_adc_scale.h"
#include "hfi_adc_scale.h"

extern "C" void csim_adc_scale(int n, int bits, const uint16_t *code, const int16_t *offset,
                               const uint16_t *gain, int16_t *i) {
    for (int k = 0; k < n; k++)
        i[k] = hfi_adc_scale(code[k], bits, offset[k], gain[k]).to_int();
}
