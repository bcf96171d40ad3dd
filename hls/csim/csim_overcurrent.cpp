// C-ABI wrapper of hfi_overcurrent over arrays (tests/test_hls_overcurrent.py).
#include "csim_overcurrent.h"
#include "hfi_overcurrent.h"

extern "C" void csim_overcurrent(int n, const int16_t *i_a, const int16_t *i_b, const uint16_t *limit,
                                 uint8_t *trip) {
    for (int k = 0; k < n; k++)
        trip[k] = hfi_overcurrent(i_a[k], i_b[k], limit[k]) ? 1 : 0;
}
