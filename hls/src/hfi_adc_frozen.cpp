// Frozen ADC lanes of a window: docs/spec.md 3.13, golden.fpga.adc_frozen.frozen_lanes. One comparison per
// conversion and lane against the window's first code, and a sticky "differs" bit.
#include "hfi_adc_frozen.h"

ap_uint<2> hfi_adc_frozen(const ap_uint<16> *adc_a, const ap_uint<16> *adc_b, int n) {
    if (n < 2) return 0;
    bool differs_a = false, differs_b = false;
    for (int i = 1; i < n; i++) {
#pragma HLS PIPELINE II = 1
        differs_a = differs_a || adc_a[i] != adc_a[0];
        differs_b = differs_b || adc_b[i] != adc_b[0];
    }
    ap_uint<2> r = 0;
    r[0] = !differs_a;
    r[1] = !differs_b;
    return r;
}
