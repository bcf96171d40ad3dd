/* C-ABI wrappers of the gate generator kernels (hls/src/hfi_gate_gen.cpp) for the C-simulation tests. */
#include <stdint.h>

/* out[i] = hfi_effective_dead(reg[i], dead_min[i]). */
void csim_gate_gen_effective_dead(int n, const uint16_t *reg, const uint16_t *dead_min, uint16_t *out);
/* n_halves * half ticks from reset: hfi_carrier_tick gives the phase, the compares cmps[3*k + x] of half
   period k are latched at its start (bottom: rising half, top: falling half), hfi_ideal_switch gives s
   (s[t], bit x = leg x) and hfi_gate_tick the mask of each tick with en[t] and the effective dead[t]. */
void csim_gate_gen_carrier_run(int n_halves, uint16_t half, const uint16_t *cmps, const uint8_t *en,
                               const uint16_t *dead, uint8_t *s, uint8_t *mask);
/* n ticks of hfi_gate_tick from hfi_gate_reset: mask[t] and the state after the tick, el[3*t + x]. */
void csim_gate_gen_run(int n, const uint8_t *s, const uint8_t *en, const uint16_t *dead, uint8_t *mask, uint16_t *el);
/* n_seg segments of hfi_gate_advance from hfi_gate_reset, segment k with len[k] ticks: the mask of its
   first tick, on_at[3*k + x] and the state after it, el[3*k + x]. */
void csim_gate_gen_advance(int n_seg, const uint8_t *s, const uint8_t *en, const uint16_t *dead, const uint32_t *len,
                           uint8_t *mask_first, uint32_t *on_at, uint16_t *el);
