/* fw_config.h - the configuration block of one run, at the symbol fw_config in the RAM image.
 *
 * The firmware is built once; hfi/rtl_backend.py (config_block, ram_image) writes each scenario's
 * values into this block of the RAM image (cffi parses control.h and this header, so the layout is
 * written only here).
 * The firmware refuses to start (gates stay off, a message on the UART) unless magic and version
 * match. Register values are the raw register words of docs/registers.md.
 */
#ifndef HFI_FW_CONFIG_H
#define HFI_FW_CONFIG_H

#include <stdint.h>
#include "control.h"

/* Identification of the block: "HFIC" and the layout version. */
enum fw_config_id { FW_CONFIG_MAGIC = 0x43494648, FW_CONFIG_VERSION = 14 };

/* hfi_dsp start-up register values (golden.control_config.HardwareConfig) and the control flags. */
struct fw_hw_config {
    uint32_t magic;         /* FW_CONFIG_MAGIC */
    uint32_t version;       /* FW_CONFIG_VERSION */
    uint32_t pwm_half;      /* PWM_HALF */
    uint32_t dead_ticks;    /* DEAD_TICKS */
    uint32_t os_ticks;      /* OS_TICKS */
    uint32_t blank_ticks;   /* BLANK_TICKS */
    uint32_t cw_angle_step; /* CW_ANGLE_STEP */
    uint32_t adc_offset;    /* ADC_OFFSET (packed A, B) */
    uint32_t adc_gain;      /* ADC_GAIN (packed A, B) */
    uint32_t oc_limit;      /* OC_LIMIT */
    uint32_t wdt_periods;   /* WDT_PERIODS */
    uint32_t dtc_gain;      /* DTC_GAIN */
    uint32_t hf_amp;        /* HF_AMP */
    uint32_t recip_h;       /* RECIP_H */
    uint32_t adc_mode;      /* CTRL.ADC_MODE */
    uint32_t inj_en;        /* CTRL.INJ_EN */
    uint32_t inj_rot;       /* CTRL.INJ_ROT */
    uint32_t inj_step;      /* INJ_STEP */
    uint32_t inj_per;       /* CTRL.INJ_PER: the period square wave; the window reads CIC_QA/QB only with it */
    uint32_t cic_m;         /* CIC_M */
    uint32_t direct;        /* CTRL.DIRECT: the direct-vector mode (003, law fcs_mpc); the window reads VECTOR and
                             * TOP_I and the step writes FCS_A and FCS_CTRL only with it */
};

struct fw_config {
    struct fw_hw_config hw;
    struct fw_params fw;
};

#endif
