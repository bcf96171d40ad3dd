// Dead-time compensation, docs/spec.md 3.6 (golden/fpga/deadtime_comp.py): applied to the
// modulator's compares at each latch when DTC_GAIN != 0.
#ifndef HFI_DEADTIME_COMP_H
#define HFI_DEADTIME_COMP_H
#include "hfi_fixed.h"

// top: falling half (sgn = +1); dead: effective dead time D; gain: DTC_GAIN (u16, Q8); hf_amp:
// HF_AMP (u15); recip_h: RECIP_H = round(2^32 / H).
void hfi_deadtime_comp(const u16 cmp_in[3], bool top, u16 half, u16 dead, u16 gain, s16 i_d_ref,
                       s16 i_q_ref, ap_uint<15> hf_amp, s16 sin_q15, s16 cos_q15, u32 recip_h,
                       u16 cmp_out[3]);

#endif
