// ADC trigger and blanking, docs/spec.md 2.3 (golden/fpga/adc_trigger.py; rtl/hfi_adc_trigger.v).
#include "hfi_adc_trigger.h"

// Saturation value of the blanking age counter: above every BLANK_TICKS (u16), never "recent".
static const ap_uint<17> HFI_BLANK_AGE_MAX = 0x1FFFF;

// golden.fpga.adc_trigger.effective_os_ticks (with OS_MIN given directly): max(OS_TICKS, OS_MIN).
u16 hfi_effective_os_ticks(u16 os_ticks_register, u16 os_min) {
#pragma HLS INLINE
    return os_ticks_register < os_min ? os_min : os_ticks_register;
}

// golden.fpga.adc_trigger.sample_phases as a per-tick decision:
//   DS: phi = 0 or phi = H;
//   OS, OS_BLANK, 3: phi = m*OS with phi <= 2H - OS_MIN; phi = 0 always.
// `os_ticks` is passed through hfi_effective_os_ticks (a no-op on an effective value), so a raw
// register value 0 is safe. The RTL replaces the modulo by a counter restarted at every bottom.
bool hfi_adc_trigger(ap_uint<17> phase, ap_uint<2> mode, u16 half, u16 os_ticks, u16 os_min) {
#pragma HLS INLINE off
    if (mode == HFI_MODE_DS) {
        return phase == 0 || phase == half;
    }
    const u16 os = hfi_effective_os_ticks(os_ticks, os_min);
    const ap_uint<18> reach = ap_uint<18>(phase) + os_min;           // phi + OS_MIN <= 2H
    const ap_uint<18> period = ap_uint<18>(half) << 1;
    return phase == 0 || (phase % os == 0 && reach <= period);
}

// Reset: no switching instant seen yet (the age is saturated, nothing is blanked).
void hfi_blank_reset(hfi_blank_state &st) {
    st.since = HFI_BLANK_AGE_MAX;
}

// golden.fpga.adc_trigger.blank_mask, one tick at a time: `since` = t - t_s of the latest switching
// instant t_s <= t (0 in the tick of the event), saturating; dropped iff BLANK_TICKS != 0 and
// since < BLANK_TICKS.
bool hfi_blank_tick(hfi_blank_state &st, bool sw_event, u16 blank_ticks) {
#pragma HLS INLINE off
    const ap_uint<17> age = st.since == HFI_BLANK_AGE_MAX ? HFI_BLANK_AGE_MAX : ap_uint<17>(st.since + 1);
    st.since = sw_event ? ap_uint<17>(0) : age;
    return hfi_blanked(st.since, blank_ticks);
}

// golden.fpga.adc_trigger.blank_mask from the distance to the latest switching instant.
bool hfi_blanked(ap_uint<64> ticks_since_switch, u16 blank_ticks) {
#pragma HLS INLINE
    return blank_ticks != 0 && ticks_since_switch < blank_ticks;
}
