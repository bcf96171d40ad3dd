/* C-ABI wrapper of the demodulator kernels (hls/src/hfi_demodulator.cpp) for the C-simulation tests. */
#ifndef CSIM_DEMODULATOR_H
#define CSIM_DEMODULATOR_H
#include <stdint.h>
#ifdef __cplusplus
extern "C" {
#endif

/* Runs a sequence of n events from reset (cleared accumulators). kind[k]: 0 a sample (i_d[k], i_q[k], w[k]
 * enter hfi_demod_sample if keep[k] != 0, else it is blanked), 1 a window boundary (hfi_demod_latch,
 * then hfi_demod_clear), 2 a reset (hfi_demod_clear). The j-th latch writes results[6*j .. 6*j+5] =
 * GAMMA, GAMMA_D, SUM_ID, SUM_IQ, WSUM, N_SAMPLES. Returns the number of latches, or -1 for an unknown kind
 * (at that event). */
int csim_demodulator_run(int n, const uint8_t *kind, const uint8_t *keep, const int16_t *i_d,
                         const int16_t *i_q, const int16_t *w, int32_t *results);

#ifdef __cplusplus
}
#endif
#endif
