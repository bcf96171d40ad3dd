// The hardware overcurrent comparator, docs/spec.md 3.7 (golden/fpga/overcurrent.py). One call per sample.
#ifndef HFI_OVERCURRENT_H
#define HFI_OVERCURRENT_H
#include "hfi_fixed.h"

// |i_a| > limit, |i_b| > limit or |i_a + i_b| > limit (i_c = -i_a - i_b, exact in 18 bits).
bool hfi_overcurrent(s16 i_a, s16 i_b, u16 limit);

#endif
