// Carrier, docs/spec.md 2.1 (golden/fpga/carrier.py): the free-running triangle, one call per tick.
#ifndef HFI_CARRIER_H
#define HFI_CARRIER_H
#include "hfi_fixed.h"

// The half period the hardware uses for a PWM_HALF register value: LSB cleared, at least 512.
u16 hfi_effective_half(u16 pwm_half_register);

// Counter c at phase phi in [0, 2H): phi on the rising half, 2H - phi on the falling half.
u16 hfi_carrier_counter(ap_uint<17> phase, u16 half);

struct hfi_carrier_state {
    ap_uint<17> phase;           // phi of the next tick (reset: 0, the first carrier bottom)
};

struct hfi_carrier_out {
    ap_uint<17> phase;           // phi of this tick
    u16 counter;                 // c of this tick
    bool rising;                 // phi < H
    bool at_bottom;              // phi == 0: compare latch of the rising half, ENABLE takes effect
    bool at_top;                 // phi == H: compare latch of the falling half
    bool at_boundary;            // phi == H/2: window boundary (integrator reset, commit, interrupt)
};

// One tick with the effective half period `half`.
hfi_carrier_out hfi_carrier_tick(hfi_carrier_state &st, u16 half);

#endif
