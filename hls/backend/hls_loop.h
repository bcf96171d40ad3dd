/* Closed loop of the `hls` backend: the HLS kernels of hls/src (C simulation), the host build of the
 * firmware (firmware/src/control.c, out/firmware/host/libhfifw.so) and the C plant
 * (golden/plant/libhfiplant.so), window by window in native code, with the plant calls of the golden
 * loop (golden/closedloop.py) in the same order, so the traces are identical.
 *
 * The window sequencing around the plant (plant calls, gate-edge, sample and truth records, speed
 * reference per window, error messages) is sim/plant_loop.h, shared with the rtl backend's harness.
 *
 * C interface (cffi parses this header with its preprocessor lines stripped, together with
 * firmware/src/control.h, hls_window.h and sim/plant_records.h). Used by hfi/hls_backend.py. */
#ifndef HLS_LOOP_H
#define HLS_LOOP_H

#include <stdint.h>

#include "../../sim/plant_records.h"
#include "hls_window.h"

#ifdef __cplusplus
extern "C" {
#endif

struct plant;
struct fw_params;
struct fw_ident;
struct hls_loop;

/* Hardware configuration (golden.control_config.HardwareConfig, effective values) and the run. */
struct hls_setup {
    int32_t half;              /* PWM_HALF register (the effective H: hfi_effective_half) */
    int32_t dead_ticks;        /* DEAD_TICKS register (the dead time: max(DEAD_TICKS, dead_min)) */
    int32_t dead_min;          /* DEAD_MIN synthesis parameter, 1..65535 */
    int32_t os_ticks;          /* OS_TICKS register (used as at least os_min) */
    int32_t os_min;            /* OS_MIN of the hardware, 1..65535 */
    int32_t blank_ticks;       /* BLANK_TICKS */
    int32_t adc_mode;          /* ADC_MODE: 0 OS, 1 DS, 2 OS_BLANK, 3 as OS */
    int32_t adc_bits;          /* ADC resolution, 1..16 */
    int32_t adc_offset_a, adc_offset_b;   /* ADC_OFFSET, s16 */
    int32_t adc_gain_a, adc_gain_b;       /* ADC_GAIN, u16 Q2.14 */
    uint32_t cw_angle_step;    /* CW_ANGLE_STEP */
    int32_t dtc_gain;          /* DTC_GAIN, u16 (0: dead-time compensation off) */
    int32_t hf_amp;            /* HF_AMP, u15 */
    uint32_t recip_h;          /* RECIP_H */
    int32_t inj_rot;           /* CTRL.INJ_ROT: 1 = rotating injection (spec 3.5), 0 = square wave */
    int64_t inj_step;          /* INJ_STEP, u32: its phase advance per PWM period (int64, so a value
                                  outside 0..2^32-1 is refused with a message, not truncated) */
    int32_t inj_per;           /* CTRL.INJ_PER: 1 = the period square wave (spec 3.5; only with inj_rot = 0) */
    int32_t cic_m;             /* CIC_M, u8: the CIC's comb delay register (spec 3.9) */
    int32_t direct;            /* CTRL.DIRECT: 1 = the direct-vector mode (spec 3.10; VECTOR, TOP_I of 3.11) */
    int64_t ds_from_tick;      /* windows starting at or after this tick sample in DS mode (INT64_MAX: never) */
    int32_t oc_limit;          /* OC_LIMIT, u16: the hardware overcurrent comparator's limit (spec 3.7) */
    int32_t oc_gate_delay;     /* ticks from a tripping sample to all gates off, >= 1 (golden.fpga.overcurrent) */
    int32_t oc_fault_delay;    /* ticks from it to the first boundary whose WIN_FAULT shows it, >= 1 (same) */
    int32_t n_windows;         /* windows to run, >= 1 */
    const int32_t *speed_ref;  /* n_windows speed references (firmware input, one per window) */
};

/* Record kinds of hls_loop_count / hls_loop_copy. */
enum hls_kind { HLS_WINDOWS = 0, HLS_OUTPUTS = 1, HLS_TRUTH = 2, HLS_SAMPLES = 3, HLS_EDGES = 4 };

/* NULL and a message in err (err_len bytes) on a bad setup. The plant stays owned by the caller. */
struct hls_loop *hls_loop_create(const struct hls_setup *setup, const struct fw_params *fw, struct plant *plant,
                                 char *err, int err_len);
/* Gives the firmware the identification block `ident` (struct fw_ident, control.h: the program in ident->p, its
 * state in ident->s) and restarts it with fw_init, so it starts in FW_IDENT as the golden Firmware with
 * FirmwareParams.ident does. Only before the first window (returns -1 otherwise, and for NULL). The block stays
 * owned by the caller and must outlive the loop; the loop writes the executor's state into ident->s. Without
 * this call fw_state.ident stays NULL. */
int32_t hls_loop_set_ident(struct hls_loop *h, struct fw_ident *ident);
/* Runs up to n_windows more windows. Returns the number of windows done in total, -1 on an error
 * (hls_loop_error says which; the records up to it stay readable). */
int32_t hls_loop_run(struct hls_loop *h, int32_t n_windows);
const char *hls_loop_error(const struct hls_loop *h);
/* Records of one kind so far: struct hls_window (hls_window.h, generated from WINDOW_FIELDS), struct
 * fw_outputs (the firmware's writes after each window), struct plant_state (the plant at each window
 * end), struct adc_sample, struct gate_edge (sim/plant_records.h). */
int64_t hls_loop_count(const struct hls_loop *h, int32_t kind);
void hls_loop_copy(const struct hls_loop *h, int32_t kind, void *dst);
/* The firmware's polarity-flip flag (struct fw_state.flipped) now. */
int32_t hls_loop_flipped(const struct hls_loop *h);
/* Wall seconds spent inside the plant calls so far (plant_run, plant_advance, plant_get_state). */
double hls_loop_plant_seconds(const struct hls_loop *h);
void hls_loop_free(struct hls_loop *h);

#ifdef __cplusplus
}
#endif

#endif
