// One integration window through the sample path: golden.fpga.window_dsp.window_dsp, i.e. the chain
// adc_to_current (spec 3.1) -> clarke -> park (spec 3.2) -> demodulate of the kept samples (spec 3.4).
#include "hfi_window_dsp.h"
#include "hfi_adc_scale.h"
#include "hfi_park.h"

void hfi_window_dsp(const ap_uint<16> adc_a[HFI_WINDOW_MAX], const ap_uint<16> adc_b[HFI_WINDOW_MAX],
                    const s16 w[HFI_WINDOW_MAX], const bool keep[HFI_WINDOW_MAX], ap_uint<12> n,
                    const hfi_adc_cfg &cfg, s16 sin_q15, s16 cos_q15,
                    s16 i_d[HFI_WINDOW_MAX], s16 i_q[HFI_WINDOW_MAX], hfi_window_result &result) {
#pragma HLS INTERFACE mode=s_axilite port=return
#pragma HLS INTERFACE mode=s_axilite port=n
#pragma HLS INTERFACE mode=s_axilite port=cfg
#pragma HLS INTERFACE mode=s_axilite port=sin_q15
#pragma HLS INTERFACE mode=s_axilite port=cos_q15
#pragma HLS INTERFACE mode=s_axilite port=result
    hfi_demod_acc acc;
    hfi_demod_clear(acc);
    for (int k = 0; k < HFI_WINDOW_MAX; k++) {
#pragma HLS PIPELINE II=1
#pragma HLS LOOP_TRIPCOUNT min=0 max=3277
        if (k >= n)
            break;
        const s16 i_a = hfi_adc_scale(adc_a[k], cfg.bits, cfg.offset_a, cfg.gain_a);
        const s16 i_b = hfi_adc_scale(adc_b[k], cfg.bits, cfg.offset_b, cfg.gain_b);
        s16 i_alpha, i_beta, d, q;
        hfi_clarke(i_a, i_b, i_alpha, i_beta);
        hfi_park(i_alpha, i_beta, sin_q15, cos_q15, d, q);
        i_d[k] = d;
        i_q[k] = q;
        if (keep[k])
            hfi_demod_sample(acc, d, q, w[k]);
    }
    result = hfi_demod_latch(acc);
}
