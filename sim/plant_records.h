/* plant_records.h - what a closed-loop backend records at the plant's pins, one entry per event
 * (sim/plant_loop.h). The rtl (sim/soc_sim.h) and hls (hls/backend/hls_loop.h) backends hand these
 * records to Python; cffi parses this header (preprocessor lines stripped): plain declarations only. */
#ifndef HFI_PLANT_RECORDS_H
#define HFI_PLANT_RECORDS_H

#include <stdint.h>

/* A gate-mask change: the mask in effect after the tick. */
struct gate_edge {
    int64_t tick;
    int64_t mask;
};

/* One ADC conversion: the codes of channels a and b (phase currents) and of the dc-link channel. */
struct adc_sample {
    int64_t tick;
    int32_t adc_a;
    int32_t adc_b;
    int32_t adc_vdc;
    int32_t pad;    /* explicit: the record is 24 bytes on every ABI */
};

#endif
