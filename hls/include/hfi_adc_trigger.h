// ADC trigger and blanking, docs/spec.md 2.3 (golden/fpga/adc_trigger.py).
#ifndef HFI_ADC_TRIGGER_H
#define HFI_ADC_TRIGGER_H
#include "hfi_fixed.h"

const int HFI_MODE_OS = 0;
const int HFI_MODE_DS = 1;
const int HFI_MODE_OS_BLANK = 2;

// The oversampling interval the hardware uses: OS_TICKS, at least os_min.
u16 hfi_effective_os_ticks(u16 os_ticks_register, u16 os_min);

// Whether phase phi (0..2H-1) of a period is a sampling instant in ADC_MODE `mode` (3 = as OS),
// with the effective OS_TICKS. One call per tick.
bool hfi_adc_trigger(ap_uint<17> phase, ap_uint<2> mode, u16 half, u16 os_ticks, u16 os_min);

// Blanking (OS_BLANK): a sample is dropped if some leg's ideal switch signal changed
// 0 <= t - t_s < BLANK_TICKS ticks before it. The state counts the ticks since the last change.
struct hfi_blank_state {
    ap_uint<17> since;           // ticks since the last switching instant, saturating (reset: saturated)
};
void hfi_blank_reset(hfi_blank_state &st);
// One tick: sw_event = some ideal switch signal changed at this tick. Returns true if a sample taken
// at this tick is dropped.
bool hfi_blank_tick(hfi_blank_state &st, bool sw_event, u16 blank_ticks);
// The same decision from the distance to the last switching instant (event-driven callers).
bool hfi_blanked(ap_uint<64> ticks_since_switch, u16 blank_ticks);

#endif
