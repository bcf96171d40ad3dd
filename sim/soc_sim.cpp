// soc_sim.cpp - closed-loop co-simulation of hfi_soc with the C plant (API: soc_sim.h, docs/soc.md).
//
// Per clock: evaluate the Verilated SoC (rising edge, then falling edge), then look at its pins; the
// plant calls and their records are those of PlantLoop (plant_loop.h, shared with the hls backend):
//  - window boundary of the event tick: end the window (the plant's state is its truth);
//  - gate pins changed: apply the new mask to the plant (tick - PIN_LATENCY);
//  - ADC: the protocol of cocotb_tests/hdl/adc_model.v (the replay's ADC model): a CONVST rising
//    edge takes a plant sample (tick - CONVST latency), CS_N falling shifts out the MSB, each SCLK
//    falling edge the next bit, every change one clock after the pin edge;
//  - the AXI4-Lite writes of hfi_dsp, the CPU's reads of hfi_dsp's page, the window interrupt (SPEED_REF is written for
//    the reported window, as the host would), the trace port, the UART line.
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "Vhfi_soc.h"
#include "Vhfi_soc___024root.h"
#include "verilated.h"
#ifdef HFI_FST
#include "verilated_fst_c.h"
#endif

#include "plant_loop.h"

extern "C" {
#include "hfi_regs.h"
#include "hfi_soc_platform.h"
#include "soc_sim.h"
}

namespace {
// hfi_dsp's gate pins and CONVST show tick t in clock t + HFI_SOC_PIN_LATENCY (one latency for both:
// the pins of one clock carry the events of one tick, applied in the golden order: window boundary,
// gate change, sample; hfi/soc_platform.py, docs/rtl.md)
constexpr long long PIN_LATENCY = HFI_SOC_PIN_LATENCY;
constexpr long long START_LIMIT = 1000000;
}

struct soc_sim {
    explicit soc_sim(const soc_sim_setup &setup, plant *pl)
        : s(setup), loop(pl, setup.half, setup.n_windows, setup.speed_ref, setup.adc_bits) {}
    VerilatedContext ctx;
    Vhfi_soc *top = nullptr;
#ifdef HFI_FST
    VerilatedFstC *fst = nullptr;
#endif
    bool fst_on = false;
    soc_sim_setup s;
    PlantLoop loop;
    std::string error;

    long long cycle = 0;        // clocks since reset released
    long long tick0 = -1;       // cycle of tick 0 (-1: not yet)
    long long irqs = 0;

    // pins seen after the previous two rising edges (for the ADC protocol)
    bool convst_q = false, convst_qq = false, cs_q = true, cs_qq = true, sclk_q = false, sclk_qq = false;
    int gate_q = 0;
    int pair_a = 0, pair_b = 0, pair_c = 0, bitpos = 0;   // the codes of lanes A, B, C being read out
    bool irq_q = false;
    bool aw_done = false, w_done = false;
    uint32_t aw_addr = 0, w_data = 0;

    // UART receiver
    int uart_state = 0;      // 0 idle, 1 start bit, 2.. data bits, 10 stop
    long long uart_count = 0;
    int uart_byte = 0;
    bool tx_q = true;

    std::vector<uint32_t> trace;
    std::vector<soc_bus> writes, reads;
    std::vector<soc_irq> irq_log;
    std::vector<uint8_t> uart;
    std::vector<uint64_t> prof_cycles, prof_fetch, prof_dfetch;   // SOC_PROF_*: empty unless HFI_PROFILE
    bool prof_line = false;                          // a whole I$ line refill seen since the profile started
};

extern "C" struct soc_sim *soc_sim_create(const struct soc_sim_setup *setup, struct plant *plant, char *err,
                                          int err_len)
{
    if (!setup || !plant) {
        set_message(err, err_len, "soc_sim_create: setup and plant are required");
        return nullptr;
    }
    if (!setup->ram_hex || !*setup->ram_hex) {
        set_message(err, err_len, "soc_sim_create: no RAM image");
        return nullptr;
    }
    const std::string bad = PlantLoop::check(setup->half, setup->n_windows, setup->speed_ref, setup->adc_bits);
    if (!bad.empty()) {
        set_message(err, err_len, "soc_sim_create: " + bad);
        return nullptr;
    }
    if (setup->uart_div < 16 || setup->trace_words < 1 || setup->cpu_div < 1) {
        set_message(err, err_len, "soc_sim_create: uart_div >= 16, trace_words >= 1 and cpu_div >= 1 are required");
        return nullptr;
    }
#ifndef HFI_FST
    if (setup->fst_path) {
        set_message(err, err_len, "soc_sim_create: this library was built without FST support");
        return nullptr;
    }
#endif
    auto *sim = new soc_sim(*setup, plant);
    std::string plusarg = std::string("+ram=") + setup->ram_hex;
    const char *argv[] = {"soc_sim", plusarg.c_str()};
    sim->ctx.commandArgs(2, argv);
    sim->ctx.traceEverOn(setup->fst_path != nullptr);
    sim->top = new Vhfi_soc(&sim->ctx, "hfi_soc");
#ifdef HFI_PROFILE
    sim->prof_cycles.assign(HFI_SOC_RAM_BYTES / 4, 0);
    sim->prof_fetch.assign(HFI_SOC_RAM_BYTES / 4, 0);
    sim->prof_dfetch.assign(HFI_SOC_RAM_BYTES / 4, 0);
#endif
#ifdef HFI_FST
    if (setup->fst_path) {
        sim->fst = new VerilatedFstC();
        sim->top->trace(sim->fst, 99);
        sim->fst->open(setup->fst_path);
    }
#endif
    sim->top->clk = 0;
    sim->top->cpu_clk = 0;
    sim->top->rst = 1;
    sim->top->adc_sdo_a = 0;
    sim->top->adc_sdo_b = 0;
    sim->top->adc_sdo_c = 0;
    sim->top->sto = 0;        // safety pins released (the closed loop does not exercise them)
    sim->top->desat = 0;
    for (int i = 0; i < 20 * setup->cpu_div; i++) {   // reset: >= 20 clocks of the slower clock (docs/rtl.md)
        sim->top->clk = 1;
        sim->top->cpu_clk = i % setup->cpu_div == 0;
        sim->top->eval();
        sim->top->clk = 0;
        sim->top->cpu_clk = setup->cpu_div == 1 ? 0 : sim->top->cpu_clk;
        sim->top->eval();
    }
    sim->top->rst = 0;
    return sim;
}

extern "C" void soc_sim_free(struct soc_sim *sim)
{
    if (!sim)
        return;
#ifdef HFI_FST
    if (sim->fst) {
        sim->fst->close();
        delete sim->fst;
    }
#endif
    sim->top->final();
    delete sim->top;
    delete sim;
}

static int plant_error(soc_sim *sim)
{
    sim->error = sim->loop.error();
    return -2;
}

// One clock. Returns 0, or a negative soc_sim_run code.
static int clock_once(soc_sim *sim)
{
    Vhfi_soc *top = sim->top;
    Vhfi_soc___024root *r = top->rootp;
    const int div = sim->s.cpu_div;
    const bool cpu_edge = sim->cycle % div == 0;   // cpu_clk rises with this clock
    top->clk = 1;
    top->cpu_clk = div == 1 ? 1 : (sim->cycle % div) < (div + 1) / 2;
    top->eval();
    sim->cycle++;
    long long c = sim->cycle;
#ifdef HFI_FST
    long long now_tick = sim->tick0 < 0 ? -1 : c - sim->tick0;
    bool dump = sim->fst && (sim->tick0 < 0 ? sim->s.fst_from_tick < 0 : (now_tick >= sim->s.fst_from_tick &&
                                                                           now_tick < sim->s.fst_to_tick));
    if (dump)
        sim->fst->dump((uint64_t)(2 * c) * 5000);
#endif
    if (sim->tick0 < 0 && r->hfi_soc__DOT__dsp_run)
        sim->tick0 = c;

    // ---- plant events of the tick seen at the pins
    bool convst = top->adc_convst, cs = top->adc_cs_n, sclk = top->adc_sclk;
    int gate = top->gate;
    if (sim->tick0 >= 0) {
        const long long te = c - sim->tick0 - PIN_LATENCY;
        if (te == sim->loop.next_window_end() && !sim->loop.end_window())
            return plant_error(sim);
        if (gate != sim->gate_q && !sim->loop.set_gates(te, gate))
            return plant_error(sim);
        if (convst && !sim->convst_q) {          // sampling instant: the plant's sample of this tick
            if (te >= sim->loop.window_start(0)) {
                if (!sim->loop.sample(te, &sim->pair_a, &sim->pair_b, &sim->pair_c))
                    return plant_error(sim);
            } else {                              // before the first window: 0 A, 0 V (no plant sample)
                sim->pair_a = sim->pair_b = sim->loop.mid_code();
                sim->pair_c = 0;
            }
        }
    } else if (gate != 0 || convst) {
        sim->error = "gate or CONVST pins active before tick 0";
        return -2;
    }
    // ---- ADC model: read-out decisions on the pins of the previous clock, outputs change now
    if (!sim->cs_q && sim->cs_qq) {
        sim->bitpos = sim->s.adc_bits - 1;
        top->adc_sdo_a = (sim->pair_a >> sim->bitpos) & 1;
        top->adc_sdo_b = (sim->pair_b >> sim->bitpos) & 1;
        top->adc_sdo_c = (sim->pair_c >> sim->bitpos) & 1;
    } else if (!sim->cs_q && !sim->sclk_q && sim->sclk_qq && sim->bitpos > 0) {
        sim->bitpos--;
        top->adc_sdo_a = (sim->pair_a >> sim->bitpos) & 1;
        top->adc_sdo_b = (sim->pair_b >> sim->bitpos) & 1;
        top->adc_sdo_c = (sim->pair_c >> sim->bitpos) & 1;
    }
    sim->convst_qq = sim->convst_q;
    sim->convst_q = convst;
    sim->cs_qq = sim->cs_q;
    sim->cs_q = cs;
    sim->sclk_qq = sim->sclk_q;
    sim->sclk_q = sclk;
    sim->gate_q = gate;

    // ---- bus, interrupt, trace, UART
    long long tk = sim->tick0 < 0 ? -1 : c - sim->tick0;
    bool irq = r->hfi_soc__DOT__dsp_irq;
    if (irq && !sim->irq_q) {
        long long k = sim->irqs - 1;      // interrupt j reports window j - 1
        if (k >= 0 && k < sim->loop.n_windows())
            r->hfi_soc__DOT__u_dsp__DOT__u_regs__DOT__r_speed_ref = (uint32_t)sim->loop.speed_ref(k);
        soc_irq rec{tk, -1, {}, (int32_t)r->hfi_soc__DOT__u_dsp__DOT__late_count,
                    (int32_t)r->hfi_soc__DOT__u_dsp__DOT__adc_mode_used};
        rec.cmp[0] = r->hfi_soc__DOT__u_dsp__DOT__cmp_top_a;
        rec.cmp[1] = r->hfi_soc__DOT__u_dsp__DOT__cmp_top_b;
        rec.cmp[2] = r->hfi_soc__DOT__u_dsp__DOT__cmp_top_c;
        rec.cmp[3] = r->hfi_soc__DOT__u_dsp__DOT__cmp_bot_a;
        rec.cmp[4] = r->hfi_soc__DOT__u_dsp__DOT__cmp_bot_b;
        rec.cmp[5] = r->hfi_soc__DOT__u_dsp__DOT__cmp_bot_c;
        // ENV_A, ENV_B as latched at the boundary of the window this interrupt reports (s17 registers,
        // sign-extended here); the harness samples them so the firmware spends no bus reads on values
        // it does not use (soc_sim.h, struct soc_irq)
        rec.env[0] = (int32_t)((uint32_t)r->hfi_soc__DOT__u_dsp__DOT__env_a_q << 15) >> 15;
        rec.env[1] = (int32_t)((uint32_t)r->hfi_soc__DOT__u_dsp__DOT__env_b_q << 15) >> 15;
        // GAMMA, GAMMA_D, WSUM of that window (latched two clocks before the interrupt rises), for the same reason
        rec.dem[0] = (int32_t)r->hfi_soc__DOT__u_dsp__DOT__gamma;
        rec.dem[1] = (int32_t)r->hfi_soc__DOT__u_dsp__DOT__gamma_d;
        rec.dem[2] = (int32_t)r->hfi_soc__DOT__u_dsp__DOT__wsum;
        sim->irq_log.push_back(rec);
        sim->irqs++;
    }
    sim->irq_q = irq;
    if (r->hfi_soc__DOT__awvalid && r->hfi_soc__DOT__awready) {
        sim->aw_done = true;
        sim->aw_addr = r->hfi_soc__DOT__awaddr & 0xFF;
    }
    if (r->hfi_soc__DOT__wvalid && r->hfi_soc__DOT__wready) {
        sim->w_done = true;
        sim->w_data = r->hfi_soc__DOT__wdata;
    }
    if (sim->aw_done && sim->w_done) {
        sim->writes.push_back(soc_bus{tk, sim->aw_addr, sim->w_data});
        if (sim->aw_addr == HFI_REGS__COMMIT_offset && !sim->irq_log.empty() && sim->irq_log.back().commit_tick < 0)
            sim->irq_log.back().commit_tick = tk;
        sim->aw_done = sim->w_done = false;
    }
    // reads of hfi_dsp's page on the CPU's bus, in the CPU clock in which they complete: through the crossing or
    // from the window-result copy (rtl/hfi_win_copy.v), as the firmware sees them
    if (cpu_edge && r->hfi_soc__DOT__sel_dsp && !r->hfi_soc__DOT__d_we &&
        (r->hfi_soc__DOT__dsp_ready || r->hfi_soc__DOT__win_ready))
        sim->reads.push_back(soc_bus{tk, (uint32_t)(r->hfi_soc__DOT__d_adr << 2) & 0xFFu, r->hfi_soc__DOT__d_rdat});
    if (cpu_edge && top->trace_valid)            // a CPU-clock output: one record per CPU clock
        sim->trace.push_back(top->trace_data);
#ifdef HFI_PROFILE
    if (cpu_edge && sim->tick0 >= 0) {           // the core's state after this CPU clock edge
        const uint32_t words = HFI_SOC_RAM_BYTES / 4;
        uint32_t pc_word = (r->hfi_soc__DOT__u_cpu__DOT__lastStagePc - HFI_SOC_RAM_BASE) / 4;
        if (pc_word < words)
            sim->prof_cycles[pc_word]++;
        if (r->hfi_soc__DOT__i_ack) {            // a refill beat: the RAM word it delivers
            uint32_t w = r->hfi_soc__DOT__i_adr - HFI_SOC_RAM_BASE / 4;
            if (w % 8 == 0)                      // a refill starts (8-word lines, from their first word):
                sim->prof_line = true;           // a line half refilled when the profile starts is not counted
            if (sim->prof_line && w < words)
                sim->prof_fetch[w]++;
        }
        if (r->hfi_soc__DOT__d_ack_ram && !r->hfi_soc__DOT__d_we) {   // a data read beat from the RAM (a refill)
            uint32_t w = r->hfi_soc__DOT__d_adr - HFI_SOC_RAM_BASE / 4;
            if (w < words)
                sim->prof_dfetch[w]++;
        }
    }
#endif
    bool tx = top->uart_tx;
    const long long bit = (long long)sim->s.uart_div * div;   // tick clocks per UART bit
    if (sim->uart_state == 0) {
        if (!tx && sim->tx_q) {
            sim->uart_state = 1;
            sim->uart_count = bit / 2;
            sim->uart_byte = 0;
        }
    } else if (--sim->uart_count == 0) {
        if (sim->uart_state == 1) {
            sim->uart_state = tx ? 0 : 2;         // a glitch is no start bit
            sim->uart_count = bit;
        } else if (sim->uart_state < 10) {
            sim->uart_byte |= (tx ? 1 : 0) << (sim->uart_state - 2);
            sim->uart_state++;
            sim->uart_count = bit;
        } else {
            sim->uart.push_back((uint8_t)sim->uart_byte);
            sim->uart_state = 0;
        }
    }
    sim->tx_q = tx;

    top->clk = 0;
    if (div == 1)
        top->cpu_clk = 0;
    top->eval();
#ifdef HFI_FST
    if (dump)
        sim->fst->dump((uint64_t)(2 * c + 1) * 5000);
#endif
    return 0;
}

extern "C" int soc_sim_run(struct soc_sim *sim, long long max_cycles)
{
    const long long need = sim->loop.n_windows() * sim->s.trace_words;
    const long long period = sim->loop.period();
    const long long end_tick = sim->loop.window_end(sim->loop.n_windows() - 1);
    for (long long i = 0; i < max_cycles; i++) {
        if ((long long)sim->trace.size() >= need) {
#ifdef HFI_PROFILE
            // The run ends at the last trace record's store, which may come while the instruction cache
            // refills a line: finish that refill (at most a line of beats), so the fetch counts stay whole
            // lines whatever the code layout.
            for (int k = 0; k < 64 * sim->s.cpu_div && sim->top->rootp->hfi_soc__DOT__i_cyc; k++) {
                int st = clock_once(sim);
                if (st != 0)
                    return st;
            }
#endif
            return 1;
        }
        int st = clock_once(sim);
        if (st != 0)
            return st;
        if (sim->tick0 < 0 && sim->cycle > START_LIMIT) {
            sim->error = "tick 0 (SOC CTRL.DSP_RUN) did not come within 10^6 clocks";
            return -3;
        }
        if (sim->tick0 >= 0 && sim->cycle - sim->tick0 > end_tick + 4 * period) {
            sim->error = "no trace record for 4 periods after the last window: the firmware stopped (a core "
                         "exception) or its control step takes longer than a PWM period (scripts/fw_profile.py "
                         "measures it on a slower copy of the scenario)";
            return -4;
        }
    }
    return (long long)sim->trace.size() >= need ? 1 : 0;
}

extern "C" const char *soc_sim_error(const struct soc_sim *sim) { return sim->error.c_str(); }
extern "C" long long soc_sim_cycles(const struct soc_sim *sim) { return sim->cycle; }

extern "C" int soc_sim_read_ram(const struct soc_sim *sim, unsigned addr, unsigned n, unsigned *dst)
{
    const auto &mem = sim->top->rootp->hfi_soc__DOT__u_ram__DOT__mem;
    const unsigned long long words = mem.size();
    if (addr % 4 || addr / 4 + (unsigned long long)n > words)
        return -1;
    for (unsigned i = 0; i < n; i++)
        dst[i] = mem[addr / 4 + i];
    return 0;
}

extern "C" long long soc_sim_count(const struct soc_sim *sim, int kind)
{
    switch (kind) {
    case SOC_EDGES: return (long long)sim->loop.edges.size();
    case SOC_SAMPLES: return (long long)sim->loop.samples.size();
    case SOC_TRUTH: return (long long)sim->loop.truth.size();
    case SOC_TRACE: return (long long)sim->trace.size();
    case SOC_WRITES: return (long long)sim->writes.size();
    case SOC_READS: return (long long)sim->reads.size();
    case SOC_IRQS: return (long long)sim->irq_log.size();
    case SOC_UART: return (long long)sim->uart.size();
    case SOC_PROF_CYCLES: return (long long)sim->prof_cycles.size();
    case SOC_PROF_FETCH: return (long long)sim->prof_fetch.size();
    case SOC_PROF_DFETCH: return (long long)sim->prof_dfetch.size();
    default: return -1;
    }
}

extern "C" int soc_sim_copy(const struct soc_sim *sim, int kind, long long from, long long n, void *dst)
{
    switch (kind) {
    case SOC_EDGES: return copy_records(sim->loop.edges, from, n, dst);
    case SOC_SAMPLES: return copy_records(sim->loop.samples, from, n, dst);
    case SOC_TRUTH: return copy_records(sim->loop.truth, from, n, dst);
    case SOC_TRACE: return copy_records(sim->trace, from, n, dst);
    case SOC_WRITES: return copy_records(sim->writes, from, n, dst);
    case SOC_READS: return copy_records(sim->reads, from, n, dst);
    case SOC_IRQS: return copy_records(sim->irq_log, from, n, dst);
    case SOC_UART: return copy_records(sim->uart, from, n, dst);
    case SOC_PROF_CYCLES: return copy_records(sim->prof_cycles, from, n, dst);
    case SOC_PROF_FETCH: return copy_records(sim->prof_fetch, from, n, dst);
    case SOC_PROF_DFETCH: return copy_records(sim->prof_dfetch, from, n, dst);
    default: return -1;
    }
}
