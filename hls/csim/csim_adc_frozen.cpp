// C-ABI wrapper of hfi_adc_frozen (tests/test_hls_adc_frozen.py).
#include "csim_adc_frozen.h"
#include "hfi_adc_frozen.h"

extern "C" int csim_adc_frozen(const uint16_t *adc_a, const uint16_t *adc_b, int n) {
    static ap_uint<16> a[4096], b[4096];
    for (int i = 0; i < n; i++) {
        a[i] = adc_a[i];
        b[i] = adc_b[i];
    }
    return int(hfi_adc_frozen(a, b, n));
}
