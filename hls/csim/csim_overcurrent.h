/* C-ABI wrapper of hfi_overcurrent (hls/src/hfi_overcurrent.cpp) for the C-simulation tests. */
#ifndef CSIM_OVERCURRENT_H
#define CSIM_OVERCURRENT_H
#include <stdint.h>
#ifdef __cplusplus
extern "C" {
#endif

/* trip[k] = hfi_overcurrent(i_a[k], i_b[k], limit[k]) for k < n. */
void csim_overcurrent(int n, const int16_t *i_a, const int16_t *i_b, const uint16_t *limit, uint8_t *trip);

#ifdef __cplusplus
}
#endif
#endif
