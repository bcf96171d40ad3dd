// C-ABI wrapper of hfi_window_dsp (tests/test_hls_window_dsp.py): copies one window into the kernel's
// fixed-size ap_types arrays, calls the kernel, copies the results back.
#include <time.h>

#include "csim_window_dsp.h"
#include "hfi_window_dsp.h"

namespace {

struct Window {
    ap_uint<16> adc_a[HFI_WINDOW_MAX], adc_b[HFI_WINDOW_MAX];
    s16 w[HFI_WINDOW_MAX];
    bool keep[HFI_WINDOW_MAX];
    s16 i_d[HFI_WINDOW_MAX], i_q[HFI_WINDOW_MAX];
    hfi_adc_cfg cfg;
    hfi_window_result result;
};

void load(Window &win, int n, const uint16_t *adc_a, const uint16_t *adc_b, const int16_t *w,
          const uint8_t *keep, int bits, int16_t offset_a, int16_t offset_b, uint16_t gain_a, uint16_t gain_b) {
    for (int k = 0; k < n; k++) {
        win.adc_a[k] = adc_a[k];
        win.adc_b[k] = adc_b[k];
        win.w[k] = w[k];
        win.keep[k] = keep[k] != 0;
    }
    win.cfg.bits = bits;
    win.cfg.offset_a = offset_a;
    win.cfg.offset_b = offset_b;
    win.cfg.gain_a = gain_a;
    win.cfg.gain_b = gain_b;
}

void run(Window &win, int n, int16_t sin_q15, int16_t cos_q15) {
    hfi_window_dsp(win.adc_a, win.adc_b, win.w, win.keep, n, win.cfg, sin_q15, cos_q15, win.i_d, win.i_q,
                   win.result);
}

}  // namespace

extern "C" int csim_window_dsp(int n, const uint16_t *adc_a, const uint16_t *adc_b, const int16_t *w,
                               const uint8_t *keep, int bits, int16_t offset_a, int16_t offset_b, uint16_t gain_a,
                               uint16_t gain_b, int16_t sin_q15, int16_t cos_q15, int16_t *i_d, int16_t *i_q,
                               int32_t *result) {
    if (n < 0 || n > HFI_WINDOW_MAX)
        return -1;
    static Window win;
    load(win, n, adc_a, adc_b, w, keep, bits, offset_a, offset_b, gain_a, gain_b);
    run(win, n, sin_q15, cos_q15);
    for (int k = 0; k < n; k++) {
        i_d[k] = win.i_d[k].to_int();
        i_q[k] = win.i_q[k].to_int();
    }
    const hfi_window_result &r = win.result;
    result[0] = r.gamma.to_int();
    result[1] = r.gamma_d.to_int();
    result[2] = r.sum_id.to_int();
    result[3] = r.sum_iq.to_int();
    result[4] = r.wsum.to_int();
    result[5] = r.n_samples.to_int();
    return 0;
}

extern "C" double csim_window_dsp_time(int repeat, int n, const uint16_t *adc_a, const uint16_t *adc_b,
                                       const int16_t *w, const uint8_t *keep, int bits, int16_t offset_a,
                                       int16_t offset_b, uint16_t gain_a, uint16_t gain_b, int16_t sin_q15,
                                       int16_t cos_q15) {
    if (n < 0 || n > HFI_WINDOW_MAX)
        return -1.0;
    static Window win;
    load(win, n, adc_a, adc_b, w, keep, bits, offset_a, offset_b, gain_a, gain_b);
    timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (int r = 0; r < repeat; r++)
        run(win, n, sin_q15, cos_q15);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    return (t1.tv_sec - t0.tv_sec) * 1e9 + (t1.tv_nsec - t0.tv_nsec);
}
