// Carrier, docs/spec.md 2.1 (golden/fpga/carrier.py; per-tick behaviour of rtl/hfi_carrier.v).
#include "hfi_carrier.h"

// Smallest half period the hardware runs (golden.fpga.carrier.REGISTER_HALF_MIN).
static const int HFI_REGISTER_HALF_MIN = 512;

// golden.fpga.carrier.effective_half: LSB cleared, values below 512 run as 512.
u16 hfi_effective_half(u16 pwm_half_register) {
#pragma HLS INLINE
    const u16 even = pwm_half_register & u16(0xFFFE);
    return even < HFI_REGISTER_HALF_MIN ? u16(HFI_REGISTER_HALF_MIN) : even;
}

// golden.fpga.carrier.counter: c = phi on the rising half (phi < H), c = 2H - phi on the falling half.
u16 hfi_carrier_counter(ap_uint<17> phase, u16 half) {
#pragma HLS INLINE
    const ap_uint<17> period = ap_uint<17>(half) << 1;
    return phase < half ? u16(phase) : u16(period - phase);
}

// One tick of the free-running phase counter (spec 2.1: period k starts at k*2H, phi = t mod 2H).
// `half` may change only at a carrier bottom (the RTL reloads it there); the phase wraps to the next
// bottom after its last tick 2H - 1.
hfi_carrier_out hfi_carrier_tick(hfi_carrier_state &st, u16 half) {
#pragma HLS INLINE off
    const ap_uint<17> period = ap_uint<17>(half) << 1;
    const ap_uint<17> phase = st.phase;
    hfi_carrier_out out;
    out.phase = phase;
    out.counter = hfi_carrier_counter(phase, half);
    out.rising = phase < half;
    out.at_bottom = phase == 0;
    out.at_top = phase == half;
    out.at_boundary = phase == (half >> 1);
    const ap_uint<18> next = ap_uint<18>(phase) + 1;
    st.phase = next >= period ? ap_uint<17>(0) : ap_uint<17>(next);
    return out;
}
