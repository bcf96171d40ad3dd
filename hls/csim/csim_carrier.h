/* C-ABI wrappers of the carrier kernel (hls/src/hfi_carrier.cpp) for the C-simulation tests. */
#include <stdint.h>

/* out[i] = hfi_effective_half(reg[i]). */
void csim_carrier_effective_half(int n, const uint16_t *reg, uint16_t *out);
/* counter[i] = hfi_carrier_counter(phase[i], half[i]). */
void csim_carrier_counter(int n, const uint32_t *phase, const uint16_t *half, uint16_t *counter);
/* n ticks of hfi_carrier_tick from reset with the half period half[t] of each tick; flags[t]: bit 0
   rising, bit 1 at_bottom, bit 2 at_top, bit 3 at_boundary. */
void csim_carrier_run(int n, const uint16_t *half, uint32_t *phase, uint16_t *counter, uint8_t *flags);
