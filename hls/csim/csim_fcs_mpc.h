/* C-ABI wrapper of the FCS-MPC kernel (hls/src/hfi_fcs_mpc.cpp) for the C-simulation tests. */
#include <stdint.h>

/* state[i] = hfi_fcs_choose on vector i (v_al, v_be: s18 in an int32). */
void csim_fcs_choose(int n, const int32_t *v_al, const int32_t *v_be, const int16_t *sin_q15,
                     const int16_t *cos_q15, const int16_t *a1, const int16_t *a2, const uint16_t *phi_min,
                     const uint8_t *constrain, const uint8_t *state_now, uint8_t *state);

/* A sequence of carrier-top latches of the direct-vector mode, the state carried from one to the next
 * from state0: state[i] and cmp[3*i + x] of hfi_modulator_direct on vector i. */
void csim_modulator_direct(int n, const int16_t *v_d, const int16_t *v_q, const int16_t *sin_q15,
                           const int16_t *cos_q15, const int16_t *a1, const int16_t *a2,
                           const uint16_t *phi_min, const uint8_t *constrain, const uint16_t *half,
                           uint8_t state0, uint8_t *state, uint16_t *cmp);
