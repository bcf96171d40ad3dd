// Modulator, docs/spec.md 3.5 (golden/fpga/modulator.py): one call at each compare latch (carrier
// bottom: top = false, sgn = -1; carrier top: top = true, sgn = +1).
#ifndef HFI_MODULATOR_H
#define HFI_MODULATOR_H
#include "hfi_fixed.h"

// v_h: V_H, u15 in an s16 (0..32767); half: effective H. cmp[x]: compare of leg x, 0..H.
void hfi_modulator(s16 v_d, s16 v_q, s16 v_h, s16 sin_q15, s16 cos_q15, u16 half, bool top, u16 cmp[3]);

#endif
