/* main.c - the hfi_soc firmware: start-up, the control interrupt and the supervisor glue.
 *
 * Start-up: check the configuration block (fw_config.h), write the hfi_dsp configuration registers, log
 * "running", run a warm-up step in RUN (below), wait 32 CPU cycles (at least the carrier's H*STEP product of tick
 * clocks, docs/rtl.md), enable the window interrupt, set SOC CTRL.DSP_RUN (tick 0). Then run() only reports
 * mode changes: a log line on the UART (with the fault's name in FAULT) and SOC FW_STATUS (mode and fault code).
 *
 * Window interrupt (IRQ 3, once per PWM period, docs/spec.md 2.2): read the window results (the fault latches from
 * WIN_FAULT, as they stood at the window boundary; with
 * CIC_QA and CIC_QB only when the configuration runs the period square wave, CTRL.INJ_PER: two bus
 * reads saved otherwise, where they read 0 as golden's WindowResult has them; VECTOR and TOP_I likewise
 * only in the direct-vector mode, CTRL.DIRECT) and the speed reference (SPEED_REF mailbox), run fw_step()
 * (control.c, the golden firmware's arithmetic), write CTRL (with CTRL.DIRECT from the configuration; first,
 * as its ENABLE has the earliest deadline), the shadow registers (FCS_A and FCS_CTRL only in the
 * direct-vector mode) and COMMIT (before the deadline: the
 * commit takes effect at the next window boundary; a missed one counts in LATE_COUNT and the watchdog
 * trips after WDT_PERIODS), acknowledge, and send one trace record on the SoC trace port (fw_trace.h, docs/soc.md). The first interrupt
 * reports window -1 (the half period before the first boundary): the registers read, a warm-up step on a copy
 * of the state (it warms the caches), acknowledged; no register written, no trace record.
 * Core exceptions (illegal instruction, misaligned or faulting access, ebreak; crt0.S) turn the gates
 * off, log mcause and mepc, and stop the firmware; without commits the hardware watchdog would do so too.
 * Cycle counts come from the SoC's CYCLE_LO register (CPU clocks), so no core counter CSR is needed.
 *
 * Register access only through the generated headers hfi_regs.h and hfi_soc_regs.h (offsets and
 * field positions) at the bases of hfi_soc_platform.h (generated); every access is a 32-bit word access.
 */
#include <stdint.h>

#include "control.h"
#include "fw_config.h"
#include "fw_methods.h"
#include "fw_trace.h"
#include "hfi_regs.h"
#include "hfi_soc_platform.h"
#include "hfi_soc_regs.h"

#define DSP(reg) (*(volatile uint32_t *)(HFI_SOC_DSP_BASE + HFI_REGS__##reg##_offset))
#define SOC(reg) (*(volatile uint32_t *)(HFI_SOC_CTL_BASE + HFI_SOC__##reg##_offset))
#define FIELD(reg, fld, v) (((uint32_t)(v) << HFI_REGS__##reg##__##fld##_bp) & HFI_REGS__##reg##__##fld##_bm)
#define SOC_FIELD(reg, fld, v) (((uint32_t)(v) << HFI_SOC__##reg##__##fld##_bp) & HFI_SOC__##reg##__##fld##_bm)

#define IRQ_WINDOW (1u << HFI_SOC_IRQ_WINDOW)
#define TRACE_PUT(word) (SOC(TRACE) = (word))
#define CSR_IRQ_MASK 0xBC0          /* VexRiscv: enable mask of the external interrupt lines */
#ifdef FW_CFU
#define CSR_CFU_ENABLE (1u << 31)   /* the same CSR's bit 31 enables the CFU's custom instructions (fw_fx.h) */
#else
#define CSR_CFU_ENABLE 0u
#endif
#define MIE_MEIE (1u << 11)         /* mie: machine external interrupt enable */
#define MSTATUS_MIE (1u << 3)       /* mstatus: global interrupt enable */

/* The run's configuration, patched into the RAM image (zero here: the firmware then refuses to run). */
__attribute__((section(".config"), used)) struct fw_config fw_config;
#define cfg fw_config
#ifndef FW_NO_IDENT
/* The commissioning image (make IDENT=1, firmware/Makefile): the identification program, patched into the RAM image
 * by the host like fw_config (control.mode = "commission"; n_steps = 0: none, the drive starts as usual), and the
 * executor's sums, which the host reads back from the RAM at the end (hfi/rtl_backend.py). */
__attribute__((section(".ident"), used)) struct fw_ident fw_ident;
#endif
/* st.ident: NULL but in a commissioning image with a program (control.h). */
/* The state sits right after the configuration block (firmware/link.ld, .state): on data-cache lines of its own, apart
 * from the stack's and the hot parameters', wherever the code's size puts .bss (docs/soc.md, "The data cache"). */
static struct fw_state st __attribute__((section(".state")));
/* The handler's own variables follow the state's tables there: in .data and .bss their lines moved with the code's
 * size, and one build put them on the configuration block's first lines (a line each refilled every period). */
#define HANDLER_VAR __attribute__((section(".state_vars")))
static volatile int32_t shown_mode HANDLER_VAR = -1;
static volatile uint32_t shown_window HANDLER_VAR;
static volatile int32_t halted HANDLER_VAR;
static int read_gamma HANDLER_VAR;        /* fw_reads_gamma of the configuration, set once at the start */

static inline uint32_t rdcycle(void)
{
    return SOC(CYCLE_LO);
}

/* Enable the external interrupt lines in `lines` (and no other; the CFU stays enabled), then interrupts globally. */
static void irq_enable(uint32_t lines)
{
    /* -march=rv32im keeps the rv32im/ilp32 libgcc; the CSR instructions are Zicsr */
    __asm__ volatile(".option push\n.option arch, +zicsr\n"
                     "csrw %0, %1\ncsrs mie, %2\ncsrs mstatus, %3\n.option pop"
                     : : "i"(CSR_IRQ_MASK), "r"(lines | CSR_CFU_ENABLE), "r"(MIE_MEIE), "r"(MSTATUS_MIE));
}

/* Enable the fixed-point instructions (the core raises an illegal-instruction trap on them until then). */
static void cfu_enable(void)
{
    __asm__ volatile(".option push\n.option arch, +zicsr\ncsrw %0, %1\n.option pop"
                     : : "i"(CSR_IRQ_MASK), "r"(CSR_CFU_ENABLE));
}

/* ---------------------------------------------------------------- UART log */
static void uart_putc(char c)
{
    while (SOC(UART_STATUS) & HFI_SOC__UART_STATUS__TX_BUSY_bm)
        ;
    SOC(UART_DATA) = SOC_FIELD(UART_DATA, DATA, (uint8_t)c);
}

/* Not inlined: the idle loop waits in here while a log line goes out, and firmware/link.ld places it with run() on
 * lines the control steps barely use (a copy inlined into the log code would evict the step's code each period). */
static __attribute__((noinline)) void uart_puts(const char *s)
{
    while (*s)
        uart_putc(*s++);
}

static void uart_putu(uint32_t v)
{
    char buf[11];
    int i = 10;
    buf[i] = 0;
    do {
        buf[--i] = (char)('0' + v % 10u);
        v /= 10u;
    } while (v);
    uart_puts(buf + i);
}

static const char *const mode_names[] = {"CONVERGE", "POL_POS", "POL_NEG", "RELAX", "RUN", "FIXED", "FAULT",
                                         "IDENT", "DONE"};

/* ---------------------------------------------------------------- control interrupt */
static void gates_off(void)
{
    DSP(CTRL) = 0;
}

/* A step in `mode` on a copy of the state, writing nothing: the caches then hold that path's code and data. The
 * copy lives on this function's stack frame, only while it runs (a static copy took 1 KB of RAM the build without
 * the accelerators does not have; in control_step's frame it shifted every interrupt's stack by 1 KB, onto the
 * data cache's other lines: docs/soc.md). Window -1 runs it in the start-up mode from the registers as read in every
 * window, so the first control step (whose CTRL.ENABLE must land before the carrier bottom three quarters into its
 * period, docs/soc.md) does not take a cold-cache time; window 0's interrupt comes a period later. main runs it
 * in RUN, so the first step in RUN does not either. Not inlined: irq_handler stays within the step's lines. */
static __attribute__((noinline)) void warm_up(int32_t mode, const struct fw_window *win, int32_t speed_ref)
{
    if (st.ident)         /* commissioning: a step on a copy would still write the program's sums (through the pointer) */
        return;
    struct fw_state copy = st;
    struct fw_outputs unused;

    copy.mode = mode;
    fw_step(&copy, &cfg.fw, win, speed_ref, &unused);
}

static void control_step(void)
{
    uint32_t t0 = rdcycle();
    uint32_t count = DSP(WINDOW_COUNT);
    struct fw_window win;
    if (read_gamma) {                     /* only when something the step runs uses them (fw_reads_gamma) */
        win.gamma = (int32_t)DSP(GAMMA);
        win.gamma_d = (int32_t)DSP(GAMMA_D);
    } else {
        win.gamma = 0;
        win.gamma_d = 0;
    }
    win.sum_id = (int32_t)DSP(SUM_ID);
    win.sum_iq = (int32_t)DSP(SUM_IQ);
    win.n_samples = DSP(N_SAMPLES) & HFI_REGS__N_SAMPLES__VALUE_bm;
    win.inj_phase = DSP(INJ_PHASE);
    if (cfg.hw.inj_per) {                 /* the differencing/CIC block's outputs (spec 3.9) */
        win.cic_qa = (int32_t)DSP(CIC_QA);
        win.cic_qb = (int32_t)DSP(CIC_QB);
    } else {                              /* 0 without the period square wave, as in golden */
        win.cic_qa = 0;
        win.cic_qb = 0;
    }
    if (cfg.hw.direct) {                  /* the direct-vector mode's state and the top currents (spec 3.10, 3.11) */
        uint32_t top = DSP(TOP_I), vec = DSP(VECTOR);

        win.vector = (int32_t)((vec & HFI_REGS__VECTOR__STATE_bm) >> HFI_REGS__VECTOR__STATE_bp);
        win.vector_next = (int32_t)((vec & HFI_REGS__VECTOR__NEXT_bm) >> HFI_REGS__VECTOR__NEXT_bp);
        win.top_ia = (int32_t)(int16_t)(uint16_t)((top & HFI_REGS__TOP_I__I_ALPHA_bm) >> HFI_REGS__TOP_I__I_ALPHA_bp);
        win.top_ib = (int32_t)(int16_t)(uint16_t)((top & HFI_REGS__TOP_I__I_BETA_bm) >> HFI_REGS__TOP_I__I_BETA_bp);
    } else {                              /* read only by the fcs_mpc law and its estimator (0 as in golden) */
        win.vector = 0;
        win.vector_next = 0;
        win.top_ia = 0;
        win.top_ib = 0;
    }
    win.vdc = (DSP(VDC) & HFI_REGS__VDC__CODE_bm) >> HFI_REGS__VDC__CODE_bp;
    /* the fault latches as they stood at the window's boundary tick (WIN_FAULT, docs/spec.md 2.2 and 3.7), not the
     * live STATUS: the value does not depend on when this handler runs; same bit positions as in STATUS */
    win.status = DSP(WIN_FAULT) & (HFI_REGS__WIN_FAULT__OC_bm | HFI_REGS__WIN_FAULT__WDT_bm |
                                   HFI_REGS__WIN_FAULT__STO_bm | HFI_REGS__WIN_FAULT__DESAT_bm);
    win.frozen = DSP(WIN_ADC) & (HFI_REGS__WIN_ADC__FROZEN_A_bm | HFI_REGS__WIN_ADC__FROZEN_B_bm);
    int32_t speed_ref = (int32_t)DSP(SPEED_REF);

    if (count < 2u) {                     /* window -1: no control step, a warm-up */
        warm_up(st.mode, &win, speed_ref);
        DSP(IRQ_STATUS) = FIELD(IRQ_STATUS, WINDOW, 1);
        return;
    }
    struct fw_outputs o;
    fw_step(&st, &cfg.fw, &win, speed_ref, &o);

    /* CTRL first: its ENABLE takes effect at the next carrier bottom, three quarters of a period after the window
     * boundary (docs/spec.md 2.2), the others at the commit; the first step's ENABLE must make that bottom */
    DSP(CTRL) = FIELD(CTRL, ENABLE, o.enable) | FIELD(CTRL, INJ_EN, cfg.hw.inj_en) |
                FIELD(CTRL, INJ_ROT, cfg.hw.inj_rot) | FIELD(CTRL, INJ_PER, cfg.hw.inj_per) |
                FIELD(CTRL, DIRECT, cfg.hw.direct) | FIELD(CTRL, ADC_MODE, cfg.hw.adc_mode);
    DSP(V_DQ) = FIELD(V_DQ, V_D, o.v_d) | FIELD(V_DQ, V_Q, o.v_q);
    DSP(V_H) = FIELD(V_H, VALUE, o.v_h);
    DSP(SINCOS) = FIELD(SINCOS, SIN, o.sin) | FIELD(SINCOS, COS, o.cos);
    DSP(I_REF) = FIELD(I_REF, I_D, o.i_d_ref) | FIELD(I_REF, I_Q, o.i_q_ref);
    if (cfg.hw.direct) {                  /* the FCS-MPC choice's shadow registers (spec 3.10) */
        DSP(FCS_A) = FIELD(FCS_A, A1, o.fcs_a1) | FIELD(FCS_A, A2, o.fcs_a2);
        DSP(FCS_CTRL) = FIELD(FCS_CTRL, PHI_MIN, o.fcs_phi_min) | FIELD(FCS_CTRL, CONSTRAIN, o.fcs_constrain);
    }
    DSP(COMMIT) = FIELD(COMMIT, GO, 1);
    DSP(IRQ_STATUS) = FIELD(IRQ_STATUS, WINDOW, 1);
    uint32_t cycles = rdcycle() - t0;

    /* trace record (fw_trace.h, generated from hfi/soc_platform.py TRACE) */
    FW_TRACE_RECORD(TRACE_PUT, st, count - 2u, cycles);
    shown_window = count - 2u;
}

void irq_handler(uint32_t pending)
{
    if (pending & IRQ_WINDOW)
        control_step();
}

void exception_handler(uint32_t mcause, uint32_t mepc)
{
    gates_off();
    halted = 1;
    uart_puts("hfi_fw: core exception mcause ");
    uart_putu(mcause);
    uart_puts(" mepc ");
    uart_putu(mepc);
    uart_puts(", gates off, halted\n");
    for (;;)
        ;
}

/* ---------------------------------------------------------------- start-up */
static int config_ok(void)
{
    return cfg.hw.magic == FW_CONFIG_MAGIC && cfg.hw.version == FW_CONFIG_VERSION;
}

/* The optional FPGA blocks (build options, docs/rtl.md) that the configured methods need and this build lacks:
 * the missing CAPS bits of hfi_dsp in *dsp and of the accelerators in *acc (golden.build_options; the build
 * without accelerators computes in software and needs none of theirs). 0 when nothing is missing. */
static uint32_t missing_blocks(uint32_t *dsp, uint32_t *acc)
{
    static const uint32_t dsp_caps[FW_METHODS] = FW_METHOD_DSP_CAPS;
    static const uint32_t acc_caps[FW_METHODS] = FW_METHOD_ACC_CAPS;
    uint32_t lo = (uint32_t)cfg.fw.low < FW_METHODS ? (uint32_t)cfg.fw.low : 0;
    uint32_t hi = (uint32_t)cfg.fw.high < FW_METHODS ? (uint32_t)cfg.fw.high : 0;

    *dsp = (dsp_caps[lo] | dsp_caps[hi]) & ~DSP(CAPS);
#ifdef FW_ACC
    *acc = (acc_caps[lo] | acc_caps[hi]) & ~fw_acc_caps();
#else
    (void)acc_caps;
    *acc = 0;
#endif
    return *dsp | *acc;
}

/* A log line and SOC FW_STATUS for a mode change. Not inlined: it runs once per change, apart from run(). */
static __attribute__((noinline)) void show_mode(int32_t mode)
{
    SOC(FW_STATUS) = SOC_FIELD(FW_STATUS, MODE, mode) | SOC_FIELD(FW_STATUS, FAULT, *(volatile int32_t *)&st.fault);
    uart_puts("hfi_fw: window ");
    uart_putu(*(volatile uint32_t *)&shown_window);
    uart_puts(" mode ");
    uart_puts(mode >= 0 && mode <= FW_DONE ? mode_names[mode] : "?");
    if (mode == FW_FAULT) {
        uart_puts(" ");
        uart_puts(fw_fault_name(*(volatile int32_t *)&st.fault));
    }
    uart_puts("\n");
}

/* Start the DSP, then report mode changes and run the methods' idle work (fw_idle: e.g. the 003 step's code warmed
 * in the instruction cache before it is needed) forever (the idle loop). Not inlined, and placed by firmware/link.ld
 * right after the steps' code with uart_puts and fw_idle: their lines share the instruction cache with the 000
 * step's least used ones (fw_mtpa_lookup, run once per speed-loop period), so the idle loop, also while a log line
 * goes out, does not evict the control step's code between interrupts. */
static __attribute__((noinline, noreturn)) void run(void)
{
    uint32_t t0 = rdcycle();
    while (rdcycle() - t0 < 32u)          /* the carrier's H*STEP product (docs/rtl.md) */
        ;
    irq_enable(IRQ_WINDOW);
    SOC(CTRL) = SOC_FIELD(CTRL, DSP_RUN, 1);

    for (;;) {
        int32_t mode = *(volatile int32_t *)&st.mode;   /* written by the interrupt */
        if (mode != shown_mode && !halted) {
            shown_mode = mode;
            show_mode(mode);
        }
#if FW_IDLE_WARM
        if (fw_idle_work && mode != FW_FAULT)
            fw_idle(&st, &cfg.fw);
#endif
    }
}

int main(void)
{
    gates_off();
    cfu_enable();
    uart_puts("hfi_fw: start\n");
    if (!config_ok()) {
        uart_puts("hfi_fw: no valid configuration block (magic/version), gates stay off\n");
        for (;;)
            ;
    }
    uint32_t lack_dsp, lack_acc;
    if (missing_blocks(&lack_dsp, &lack_acc)) {
        /* short: the line must leave the UART before anyone gives up waiting (docs/rtl.md "Build options") */
        uart_puts("hfi_fw: build lacks the method's blocks: CAPS ");
        uart_putu(lack_dsp);
        uart_puts(", ACC CAPS ");
        uart_putu(lack_acc);
        uart_puts("; gates stay off\n");
        for (;;)
            ;
    }
#ifdef FW_NO_PROBE /* and FW_NO_XS: one line for both, the image's RAM has room for one (firmware/Makefile) */
    if (cfg.fw.prot.probe_min || fw_uses_xs_tables(&cfg.fw)) {
        uart_puts("hfi_fw: not in this image: protection.catch_probe, estimator.*.cross_saturation; gates stay off\n");
        for (;;)
            ;
    }
#endif
    DSP(PWM_HALF) = cfg.hw.pwm_half;
    DSP(CW_ANGLE_STEP) = cfg.hw.cw_angle_step;
    DSP(DEAD_TICKS) = cfg.hw.dead_ticks;
    DSP(OS_TICKS) = cfg.hw.os_ticks;
    DSP(BLANK_TICKS) = cfg.hw.blank_ticks;
    DSP(ADC_OFFSET) = cfg.hw.adc_offset;
    DSP(ADC_GAIN) = cfg.hw.adc_gain;
    DSP(OC_LIMIT) = cfg.hw.oc_limit;
    DSP(WDT_PERIODS) = cfg.hw.wdt_periods;
    DSP(DTC_GAIN) = cfg.hw.dtc_gain;
    DSP(HF_AMP) = cfg.hw.hf_amp;
    DSP(RECIP_H) = cfg.hw.recip_h;
    DSP(INJ_STEP) = cfg.hw.inj_step;
    DSP(CIC_M) = cfg.hw.cic_m;
    /* the safety registers (dead time, overcurrent limit, watchdog) stay as configured until reset */
    DSP(SAFETY_LOCK) = FIELD(SAFETY_LOCK, LOCK, 1);
    DSP(IRQ_ENABLE) = FIELD(IRQ_ENABLE, WINDOW, 1);
    /* before DSP_RUN: the period square wave's sign at tick 0's bottom follows CTRL.INJ_PER (docs/rtl.md);
     * CTRL.DIRECT from the first window boundary on (the direct-vector mode of the 003 method, spec 3.10) */
    DSP(CTRL) = FIELD(CTRL, INJ_EN, cfg.hw.inj_en) | FIELD(CTRL, INJ_ROT, cfg.hw.inj_rot) |
                FIELD(CTRL, INJ_PER, cfg.hw.inj_per) | FIELD(CTRL, DIRECT, cfg.hw.direct) |
                FIELD(CTRL, ADC_MODE, cfg.hw.adc_mode);
#ifndef FW_NO_IDENT
    st.ident = fw_ident.p.n_steps > 0 ? &fw_ident : 0;
#endif
    fw_init(&st, &cfg.fw);
    read_gamma = fw_reads_gamma(&st, &cfg.fw);
    /* the log lines before the warm-up and the start: the UART code then does not evict the first steps' code
     * from the instruction cache (a log line takes about 20 periods at 10 kHz) */
    uart_puts("hfi_fw: running\n");
    shown_mode = st.mode;
    show_mode(st.mode);
    /* the RUN path in the instruction cache too (the 16 KiB cache holds a method's whole step; docs/soc.md,
     * "Firmware budget"; the start-up path is warmed at window -1, control_step) */
    struct fw_window none = {0};

    warm_up(FW_RUN, &none, 0);
    run();
}
