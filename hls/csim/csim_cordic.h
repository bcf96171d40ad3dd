/* C-ABI wrappers of the CORDIC kernels (hls/include/hfi_cordic_impl.h, hls/src/hfi_cordic.cpp) for the
 * C-simulation tests. */
#ifndef CSIM_CORDIC_H
#define CSIM_CORDIC_H
#include <stdint.h>
#ifdef __cplusplus
extern "C" {
#endif

/* hfi_cordic_sincos<width, iterations> and hfi_to_q15<width> of angle[k] for k < n: raw Q2.(width-2)
 * sin/cos and their Q1.15 forms. Returns 0, or -1 (nothing written) if (width, iterations) is not one
 * of the instantiated points (csim_cordic_points). */
int csim_cordic_sincos(int width, int iterations, int n, const uint32_t *angle, int32_t *sin_raw,
                       int32_t *cos_raw, int16_t *sin_q15, int16_t *cos_q15);
/* The instantiated (width, iterations) points: writes up to max of them, returns their number. */
int csim_cordic_points(int max, int *width, int *iterations);
/* q15[k] = hfi_to_q15<width>(v[k]) for k < n (v[k] an s<width> value). Returns 0, or -1 if width is
 * not in 17..32. */
int csim_cordic_to_q15(int width, int n, const int32_t *v, int16_t *q15);
/* hfi_sincos_q15(angle[k]) for k < n. */
void csim_cordic_sincos_q15(int n, const uint32_t *angle, int16_t *sin_q15, int16_t *cos_q15);
/* w[k] = hfi_demod_weight(counter[k], half[k], step[k]) for k < n. */
void csim_cordic_demod_weight(int n, const uint16_t *counter, const uint16_t *half, const uint32_t *step,
                              int16_t *w);

#ifdef __cplusplus
}
#endif
#endif
