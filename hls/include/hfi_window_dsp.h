// One integration window through the sample path (golden/fpga/window_dsp.py): ADC scale -> Clarke ->
// Park -> demodulator, pipelined one sample per clock; the top function a Vitis user synthesizes for
// the data path.
#ifndef HFI_WINDOW_DSP_H
#define HFI_WINDOW_DSP_H
#include "hfi_demodulator.h"

// Most samples in one window: OS_TICKS >= OS_MIN = 40 ticks and P <= 131068 ticks (spec 2.3).
const int HFI_WINDOW_MAX = 3277;

struct hfi_adc_cfg {
    ap_uint<5> bits;             // ADC resolution B, 1..16
    s16 offset_a, offset_b;      // ADC_OFFSET of phases a and b
    u16 gain_a, gain_b;          // ADC_GAIN of phases a and b (Q2.14)
};

// n samples (0..HFI_WINDOW_MAX) with their ADC codes, weights and keep flags (false: blanked, the
// sample is transformed but does not enter the demodulator). sin_q15/cos_q15: the active SIN/COS.
// i_d/i_q receive every sample's Park currents.
void hfi_window_dsp(const ap_uint<16> adc_a[HFI_WINDOW_MAX], const ap_uint<16> adc_b[HFI_WINDOW_MAX],
                    const s16 w[HFI_WINDOW_MAX], const bool keep[HFI_WINDOW_MAX], ap_uint<12> n,
                    const hfi_adc_cfg &cfg, s16 sin_q15, s16 cos_q15,
                    s16 i_d[HFI_WINDOW_MAX], s16 i_q[HFI_WINDOW_MAX], hfi_window_result &result);

#endif
