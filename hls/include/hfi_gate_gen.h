// Dead-time gate generator, docs/spec.md 2.4 (golden/fpga/gate_generator.py, rtl/hfi_gate_gen.v).
//
// Per leg x the ideal switch signal s_x comes from the carrier and the latched compares; the switch
// it selects turns on D ticks after the latest of: the last change of s_x, the enabling of the
// outputs; it turns off at the tick s_x leaves it. Gate mask: bit 2x = high switch, 2x+1 = low.
#ifndef HFI_GATE_GEN_H
#define HFI_GATE_GEN_H
#include "hfi_fixed.h"

// The dead time the hardware uses: max(DEAD_TICKS, DEAD_MIN).
u16 hfi_effective_dead(u16 dead_ticks_register, u16 dead_min);

// Ideal switch signal of one leg at phase phi: phi < cmp_rise on the rising half,
// 2H - phi <= cmp_fall on the falling half.
bool hfi_ideal_switch(ap_uint<17> phase, u16 half, u16 cmp_rise, u16 cmp_fall);

struct hfi_gate_state {
    ap_uint<3> s_q;              // s of the previous tick
    bool en_q;                   // enable of the previous tick
    ap_uint<16> el[3];           // ticks since the last restart of each leg (saturating)
};
void hfi_gate_reset(hfi_gate_state &st);

// One tick with ideal switch signals s (bit x = leg x), enable en and the effective dead time.
// Returns the gate mask of this tick.
ap_uint<6> hfi_gate_tick(hfi_gate_state &st, ap_uint<3> s, bool en, u16 dead);

// n >= 1 ticks during which s and en stay constant: the same state update as n calls of
// hfi_gate_tick, in one step. Returns the mask of the first tick; on_at[x] is the offset (0..n-1)
// of the tick at which leg x's selected switch turns on within the n ticks, or n if it does not.
ap_uint<6> hfi_gate_advance(hfi_gate_state &st, ap_uint<3> s, bool en, u16 dead, ap_uint<32> n,
                            ap_uint<32> on_at[3]);

#endif
