// FCS-MPC vector choice of the direct-vector mode (CTRL.DIRECT), docs/spec.md 3.10
// (golden/fpga/fcs_mpc.py choose_vector, golden/fpga/modulator.py direct_state / direct_compares).
#ifndef HFI_FCS_MPC_H
#define HFI_FCS_MPC_H
#include "hfi_fixed.h"

// v_al, v_be: the modulator's inverse Park without injection (s18); sin_q15, cos_q15: SIN, COS; a1, a2:
// FCS_A (s16 Q12); phi_min: FCS_CTRL.PHI_MIN; constrain: FCS_CTRL.CONSTRAIN; state_now: the state applied
// now (0..7). Returns the state for the next period (bit 0 = phase a).
ap_uint<3> hfi_fcs_choose(ap_int<18> v_al, ap_int<18> v_be, s16 sin_q15, s16 cos_q15, s16 a1, s16 a2,
                          u16 phi_min, bool constrain, ap_uint<3> state_now);

// The carrier-top latch of the direct-vector mode: the state from the active registers (inverse Park
// of V_D, V_Q without injection, then hfi_fcs_choose) and the compares of both halves, cmp[x] = H if
// bit x of the state is set, else 0 (no dead-time compensation).
ap_uint<3> hfi_modulator_direct(s16 v_d, s16 v_q, s16 sin_q15, s16 cos_q15, s16 a1, s16 a2, u16 phi_min,
                                bool constrain, ap_uint<3> state_now, u16 half, u16 cmp[3]);

#endif
