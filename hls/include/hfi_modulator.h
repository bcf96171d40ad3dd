// Modulator, docs/spec.md 3.5 (golden/fpga/modulator.py): one call at each compare latch (carrier
// bottom: top = false, sgn = -1; carrier top: top = true, sgn = +1).
#ifndef HFI_MODULATOR_H
#define HFI_MODULATOR_H
#include "hfi_fixed.h"

// v_h: V_H, u15 in an s16 (0..32767); half: effective H. cmp[x]: compare of leg x, 0..H.
// rot: the rotating injection (CTRL.INJ_ROT with INJ_EN, spec 3.5): V_H is then the amplitude of the
// vector V_H (inj_cos, inj_sin) added in the stationary frame, (inj_sin, inj_cos) = sincos_q15(phi) of
// the injection phase (golden compares(..., rot=(inj_cos, inj_sin))); rot = false: the square wave
// V_D + sgn*V_H on the estimated d-axis (golden rot=None), inj_sin and inj_cos unused.
void hfi_modulator(s16 v_d, s16 v_q, s16 v_h, bool rot, s16 inj_sin, s16 inj_cos, s16 sin_q15, s16 cos_q15,
                   u16 half, bool top, u16 cmp[3]);

#endif
