/* soc_sim.h - closed-loop co-simulation of hfi_soc (Verilator) with the C plant (docs/soc.md).
 *
 * The clock, the serial ADC and the plant run inside this library: per clock it evaluates the
 * Verilated hfi_soc, applies gate changes to the plant, answers ADC conversions with plant samples,
 * advances the plant to every window boundary and records what the golden closed loop records.
 * Python (hfi/rtl_backend.py) creates the plant with golden.plant, calls soc_sim_run() in chunks
 * (progress output) and copies the records out. The plant calls, the gate-edge, sample and truth
 * records are those of sim/plant_loop.h (shared with the hls backend). cffi parses this header and
 * plant_records.h (preprocessor lines are stripped): plain declarations only.
 *
 * Clocks: `clk` (the tick clock) and `cpu_clk`, which rises with every cpu_div-th rising edge of clk
 * (aligned edges, as from one PLL). Ticks: tick 0 is the first clock with DSP_RUN = 1 in the DSP's
 * clock (docs/rtl.md); a pin change seen in clock c belongs to tick c - tick0 - HFI_SOC_PIN_LATENCY
 * (gate pins and CONVST alike). Cycle counts are tick clocks. Samples before the first
 * window (tick < H/2) are answered with the mid-scale code without calling the plant (the golden loop
 * starts sampling at the first window).
 */
#ifndef HFI_SOC_SIM_H
#define HFI_SOC_SIM_H

#include <stdint.h>

#include "plant_records.h"

struct plant;
struct plant_state;
struct soc_sim;

struct soc_sim_setup {
    const char *ram_hex;          /* RAM image ($readmemh text), given to the RAM as +ram=<file> */
    const char *fst_path;         /* FST waveform file, or NULL (needs the library built with FST) */
    long long fst_from_tick;      /* waveform window [from, to) in ticks (before tick 0: from reset) */
    long long fst_to_tick;
    long long half;               /* carrier half period H [ticks] (the scenario's PWM_HALF) */
    long long n_windows;          /* windows to simulate; the run ends after the last trace record */
    const int32_t *speed_ref;     /* n_windows values, written to SPEED_REF at each window interrupt */
    int adc_bits;                 /* ADC resolution (bits shifted out per conversion; codes are checked) */
    int uart_div;                 /* CPU clock cycles per UART bit (UART_DIV) */
    int cpu_div;                  /* the CPU clock is the tick clock divided by this (>= 1; hfi.soc_platform) */
    int trace_words;              /* words per firmware trace record */
};

/* What the co-simulation records (one entry per event), besides gate_edge and adc_sample. */
/* An access of hfi_dsp: a write on its AXI4-Lite port, or a read on the CPU's bus (through the crossing or from
 * the window-result copy, rtl/hfi_win_copy.v), in the clock it completes */
struct soc_bus { long long tick; uint32_t addr; uint32_t data; };
/* Window interrupt: its tick, the tick of the next COMMIT write (-1: none before the next interrupt),
 * and as the interrupt rises: the six compares the modulator computed at this window's boundary (top
 * a, b, c, bottom a, b, c), LATE_COUNT, the ADC mode the sampling of this window uses, and ENV_A, ENV_B
 * of the window it reports (the differencing/CIC block's envelope, latched at that window's end; read
 * here rather than by the firmware, whose estimator uses only CIC_QA/QB: no CPU cycles for them), and GAMMA,
 * GAMMA_D, WSUM of that window (the square-wave demodulator's: the firmware reads GAMMA and GAMMA_D only when
 * something it runs uses them, WSUM never). */
struct soc_irq { long long tick; long long commit_tick; int32_t cmp[6]; int32_t late_count; int32_t adc_mode;
                 int32_t env[2]; int32_t dem[3]; };

enum soc_record {
    SOC_EDGES = 0,     /* struct gate_edge: gate-mask changes */
    SOC_SAMPLES = 1,   /* struct adc_sample: ADC conversions from the first window on */
    SOC_TRUTH = 2,     /* struct plant_state: plant state at every window end */
    SOC_TRACE = 3,     /* uint32_t: firmware trace words */
    SOC_WRITES = 4,    /* struct soc_bus: register writes */
    SOC_READS = 5,     /* struct soc_bus: register reads */
    SOC_IRQS = 6,      /* struct soc_irq: window interrupts (commit_tick -1: none before the next) */
    SOC_UART = 7,      /* uint8_t: bytes sent on the log UART */
    /* Firmware profile (only in the library built with HFI_PROFILE; count 0 otherwise), one uint64_t per
     * RAM word (HFI_SOC_RAM_BYTES / 4 entries, word i at byte address HFI_SOC_RAM_BASE + 4 i), summed over
     * the CPU clocks from tick 0 on: */
    SOC_PROF_CYCLES = 8,  /* CPU clocks whose last pipeline stage holds the instruction at that word (a stall
                           * counts to the instruction that retired last before it) */
    SOC_PROF_FETCH = 9,   /* instruction-bus beats (cache line refills) that read that word */
    SOC_PROF_DFETCH = 10  /* data-bus read beats from the RAM (data cache line refills) that read that word */
};

/* The library's whole interface: everything else in it is built hidden (-fvisibility=hidden, hfi/rtl_backend.py) */
#pragma GCC visibility push(default)
/* Returns NULL and a message in err on a bad setup. */
struct soc_sim *soc_sim_create(const struct soc_sim_setup *setup, struct plant *plant, char *err, int err_len);
void soc_sim_free(struct soc_sim *sim);
/* Runs at most max_cycles tick clocks. Returns 1 when the run is complete, 0 when it is not yet, -2 when
 * the plant refused an event or gave an ADC code outside the ADC's range (message in soc_sim_error), -3
 * when tick 0 did not come within 10^6 clocks (firmware did not start: see the UART log), -4 on a
 * timeout (no trace record for 4 periods: a stopped firmware, e.g. after a core exception). */
int soc_sim_run(struct soc_sim *sim, long long max_cycles);
const char *soc_sim_error(const struct soc_sim *sim);
long long soc_sim_cycles(const struct soc_sim *sim);  /* tick clocks since reset */
/* Copies n words of the SoC RAM from byte address `addr` (word aligned) into dst, as they are now (the firmware's
 * data after a run: the commissioning image's sums). Returns 0, or -1 for a range outside the RAM. */
int soc_sim_read_ram(const struct soc_sim *sim, unsigned addr, unsigned n, unsigned *dst);
/* Number of records of a kind, and a copy of records [from, from + n) into dst. */
long long soc_sim_count(const struct soc_sim *sim, int kind);
int soc_sim_copy(const struct soc_sim *sim, int kind, long long from, long long n, void *dst);
#pragma GCC visibility pop

#endif
