/* C-ABI wrapper of hfi_window_dsp (hls/src/hfi_window_dsp.cpp) for the C-simulation tests. */
#ifndef CSIM_WINDOW_DSP_H
#define CSIM_WINDOW_DSP_H
#include <stdint.h>
#ifdef __cplusplus
extern "C" {
#endif

/* hfi_window_dsp of one window of n samples (0..3277, HFI_WINDOW_MAX; -1 and nothing written otherwise).
 * keep[k] != 0: the sample enters the demodulator. Writes the Park currents i_d[k], i_q[k] (k < n) and
 * result[0..5] = GAMMA, GAMMA_D, SUM_ID, SUM_IQ, WSUM, N_SAMPLES; returns 0. */
int csim_window_dsp(int n, const uint16_t *adc_a, const uint16_t *adc_b, const int16_t *w, const uint8_t *keep,
                    int bits, int16_t offset_a, int16_t offset_b, uint16_t gain_a, uint16_t gain_b,
                    int16_t sin_q15, int16_t cos_q15, int16_t *i_d, int16_t *i_q, int32_t *result);
/* Runs csim_window_dsp's kernel call `repeat` times on the same window (after one copy of the inputs)
 * and returns the kernel time in nanoseconds (CLOCK_MONOTONIC), for the per-sample timing print. */
double csim_window_dsp_time(int repeat, int n, const uint16_t *adc_a, const uint16_t *adc_b, const int16_t *w,
                            const uint8_t *keep, int bits, int16_t offset_a, int16_t offset_b, uint16_t gain_a,
                            uint16_t gain_b, int16_t sin_q15, int16_t cos_q15);

#ifdef __cplusplus
}
#endif
#endif
