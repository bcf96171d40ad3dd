// Clarke and Park transforms, docs/spec.md 3.2 (golden/fpga/park.py). One call per sample.
#ifndef HFI_PARK_H
#define HFI_PARK_H
#include "hfi_fixed.h"

void hfi_clarke(s16 i_a, s16 i_b, s16 &i_alpha, s16 &i_beta);
void hfi_park(s16 i_alpha, s16 i_beta, s16 sin_q15, s16 cos_q15, s16 &i_d, s16 &i_q);

#endif
