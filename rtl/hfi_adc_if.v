`default_nettype none
// hfi_adc_if -- interface to a serial, three-channel, simultaneous-sampling SAR ADC
//
// The paper oversamples two phase currents (two LEM sensors) every 1 us (Benevieri et al. 2023,
// Sec. IV; docs/spec.md 2.3 OS mode, 3.1), both at the same instant; a third channel converts the
// dc-link voltage (through a divider) at that instant too (docs/spec.md 3.12). This module starts one
// conversion per `start` tick and reads the three channels back over three serial data
// lanes (SDOA, SDOB, SDOC) that share one SCLK, MSB first, while CS_N is low. No arithmetic, no multiplier.
// Golden counterpart: none (the plant's ADC); the codes are passed through unchanged, `uB` offset
// binary (docs/spec.md section 3, ADC code format), to hfi_adc_scale (spec 3.1); code_c, unipolar
// (code 0 = 0 V), to the VDC register (spec 3.12).
//
// Parameters
//   ADC_BITS   1..16  bits per channel (B)
//   CONV_TICKS >= 1   conversion time t_CONV in clocks: CONVST rising edge -> CS_N falling edge
//   SCLK_HALF  >= 1   SCLK half period in clocks (f_SCLK = f_clk / (2*SCLK_HALF))
//   Out-of-range values stop elaboration (an instance of a module that does not exist, named after
//   the violated rule: a Verilog-2005 elaboration check that Verilator, Icarus and Yosys all honour).
//
// Ports
//   clk, rst      clock (100 MHz by default), synchronous active-high reset
//   start         sampling-instant tick (one-cycle pulse, from hfi_adc_trigger); taken only when
//                 busy = 0 in that cycle, ignored (no effect at all, not counted) while busy = 1.
//                 The system spaces the ticks by >= OS_MIN >= CYCLE, so none is ever lost there.
//   adc_convst    CONVST (registered): rises in the cycle after an accepted start (docs/rtl.md: the
//                 sampling instant of the sample taken at tick t is the CONVST rising edge in
//                 cycle t+1), stays high for the conversion, CONV_TICKS clocks
//   adc_cs_n      CS, active low (registered): low for the read-out of the three channels
//   adc_sclk      SCLK (registered), idles low; B pulses per conversion
//   adc_sdo_a/b/c serial data of channel A/B/C from the ADC (MSB first)
//   busy          1 from the cycle after an accepted start until the cycle before done (a function
//                 of registers only, no path from start)
//   done          one-cycle pulse: code_a/b/c hold the new conversion from this cycle on
//   code_a/b/c    uB ADC codes (registered, held until the next done; 0 after reset)
//
// Protocol and timing (t = cycle of the accepted start, C = CONV_TICKS, H = SCLK_HALF, B = ADC_BITS,
// c0 = t + 1 + C the cycle in which CS_N is low first; one column per clock, here C = 3, H = 1, B = 3):
//
//   cycle      t   t+1 t+2 t+3 c0  +1  +2  +3  +4  +5  +6  +7 (=t+LATENCY)
//   start     _/‾‾‾\______________________________________________
//   adc_convst ____/‾‾‾‾‾‾‾‾‾‾‾\___________________________________   high C clocks = t_CONV
//   adc_cs_n  ‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾\_______________________/‾‾‾‾‾‾‾‾   low 2*B*H + 1 clocks
//   adc_sclk  _____________________/‾‾‾\___/‾‾‾\___/‾‾‾\________   rising k at c0+(2k+1)H
//   adc_sdo   xxxxxxxxxxxxxxxxxxxxx< MSB  >< B-2  >< LSB  >xxxxx   ADC shifts on SCLK falling edges
//   captured                               ^       ^       ^       pin sampled at c0+(2k+2)H
//   done      ___________________________________________/‾‾‾\_   one clock
//   busy      _____/‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾\_____   a start in the done cycle is taken
//
//   * The CONVST rising edge is the sampling instant (track-to-hold of every channel). CONVST stays
//     high for C clocks (t_CONV, also a generous CONVST pulse width); CS_N falls when it falls.
//   * The ADC drives the MSB after CS_N falls (t_EN) and each next bit after an SCLK falling edge
//     (t_DSDO); it keeps a bit at least t_HSDO after the next falling edge.
//   * Capture ("delayed sampling"): bit k (k = 0 is the MSB) is sampled into the input register at
//     the clock edge that drives SCLK falling edge k, i.e. one full SCLK period after the falling edge
//     (or CS_N edge) that launched it. Set-up budget: t_co(FPGA) + 2*t_pcb + max(t_EN, t_DSDO) + t_su
//     <= 2*H clocks (20 ns at the defaults); hold: t_co,min + 2*t_pcb,min + t_HSDO > t_h. The data
//     lanes are synchronous to our own SCLK, so one input register per lane (IOB flip-flop) is the
//     whole "synchroniser": no metastability stage, the timing above is deterministic. The
//     cocotb BFM (cocotb_tests/adc_bfm.py) models the worst case: each bit is valid only from the
//     SCLK rising edge after its launch until just after the next falling edge.
//   * The last bit is captured at the last SCLK falling edge, CS_N rises one clock later (so the
//     last bit is held by t_HSDO, not by the CS-to-high-Z time), and done follows in that cycle.
//   * t_QUIET (CS_N high to the next CONVST rising edge) >= 1 clock.
//
// Latency and throughput (fixed, independent of data):
//   LATENCY = C + 2*B*H + 2 clocks from the start cycle to the done cycle;
//   CYCLE   = LATENCY: the next start is accepted in the done cycle (busy = 0 there).
//   Defaults (B = 12, C = 12, H = 1, 100 MHz): t_CONV = 120 ns, f_SCLK = 50 MHz,
//   LATENCY = CYCLE = 38 clocks (380 ns) <= OS_MIN = 40, i.e. up to 2.6 MSPS per channel.
//   (B = 16: 46 clocks, so a 16-bit part at these settings needs OS_MIN >= 46; docs/rtl.md:
//   OS_MIN = max(ITERATIONS + 8, ADC_CYCLE).)
//
// Part class: simultaneous-sampling 12..16-bit SAR ADCs with one serial data lane per channel in the
// 2..5 MSPS range (AD7380-4/AD7381-4 class: four channels, one left unused). The defaults suit a 12-bit part of that class with
// t_CONV <= 120 ns, f_SCLK >= 50 MHz, t_EN and t_DSDO small enough for the 20 ns set-up budget
// above. These numbers are the design target, not taken from one datasheet: for the chosen part,
// check t_CONV, t_EN, t_DSDO, t_HSDO, t_QUIET and the SCLK limits and set CONV_TICKS / SCLK_HALF
// (e.g. t_CONV = 190 ns -> CONV_TICKS = 19); check also that it starts a conversion on a CONVST/CNV
// edge (not on the CS falling edge), reads the current (not the previous) conversion in the frame
// and shifts on the SCLK falling edge -- otherwise the sequence (or the SCLK polarity) must change.
//
// Reset: a synchronous reset returns every output to idle at once (CONVST low, CS_N high, SCLK low;
// a read in progress ends early: the ADC sees CS rise before the last bit, an aborted read, which
// the BFM accepts while the host is in reset; check the chosen part allows it). A conversion already
// started inside the ADC keeps running for t_CONV: the first start after a reset must come at
// least CONV_TICKS clocks after the last CONVST rising edge (e.g. rst held high >= CONV_TICKS
// clocks), or the ADC sees a CONVST while it is still converting.
//
// Multipliers: none.

module hfi_adc_if #(
    parameter integer ADC_BITS   = 12,
    parameter integer CONV_TICKS = 12,
    parameter integer SCLK_HALF  = 1,
    parameter integer MAX_CYCLE  = 65535   // the parent's start spacing (hfi_dsp: OS_MIN); CYCLE must fit
) (
    input  wire                clk,
    input  wire                rst,
    input  wire                start,
    output reg                 adc_convst,
    output reg                 adc_cs_n,
    output reg                 adc_sclk,
    input  wire                adc_sdo_a,
    input  wire                adc_sdo_b,
    input  wire                adc_sdo_c,
    output wire                busy,
    output reg                 done,
    output reg  [ADC_BITS-1:0] code_a,
    output reg  [ADC_BITS-1:0] code_b,
    output reg  [ADC_BITS-1:0] code_c
);

    // ---- fixed timing (see the header) ----
    localparam integer LATENCY = CONV_TICKS + 2 * ADC_BITS * SCLK_HALF + 2;
    localparam integer CYCLE   = LATENCY;   // start spacing needed; checked against MAX_CYCLE

    // ---- elaboration-time parameter checks ----
    generate
        if (ADC_BITS < 1 || ADC_BITS > 16) begin : g_bad_adc_bits
            hfi_adc_if_error_ADC_BITS_must_be_1_to_16 u_error ();
        end
        if (CONV_TICKS < 1) begin : g_bad_conv_ticks
            hfi_adc_if_error_CONV_TICKS_must_be_at_least_1 u_error ();
        end
        if (SCLK_HALF < 1) begin : g_bad_sclk_half
            hfi_adc_if_error_SCLK_HALF_must_be_at_least_1 u_error ();
        end
        if (CYCLE > MAX_CYCLE) begin : g_bad_cycle
            hfi_adc_if_error_CYCLE_exceeds_MAX_CYCLE_raise_OS_MIN u_error ();
        end
    endgenerate

    // ---- counters ----
    localparam integer CNT_MAX = ((CONV_TICKS > SCLK_HALF) ? CONV_TICKS : SCLK_HALF) - 1;
    localparam integer CNT_W   = (CNT_MAX < 1) ? 1 : $clog2(CNT_MAX + 1);
    localparam integer TOG_W   = $clog2(2 * ADC_BITS);          // holds 2B - 1 (B = 1: 1 bit)
    localparam integer CONV_LOAD = CONV_TICKS - 1;
    localparam integer HALF_LOAD = SCLK_HALF - 1;
    localparam integer TOG_LOAD  = 2 * ADC_BITS - 1;

    localparam [1:0] S_IDLE = 2'd0,   // waiting for start
                     S_CONV = 2'd1,   // CONVST high, C clocks
                     S_READ = 2'd2,   // CS_N low, 2B SCLK half periods
                     S_LAST = 2'd3;   // last bit in the input register, CS_N still low

    reg [1:0]       state;
    reg [CNT_W-1:0] cnt;      // clocks left in the current conversion / SCLK half period, minus 1
    reg [TOG_W-1:0] tog;      // SCLK toggles left in the read, minus 1
    /* verilator lint_off UNUSEDSIGNAL */  // cap drives the shift registers, absent when ADC_BITS = 1
    reg             cap;      // the input registers hold a data bit (captured at the last edge)
    /* verilator lint_on UNUSEDSIGNAL */
    reg             sdo_a_q;  // input registers (IOB): the SDO pins, sampled every clock
    reg             sdo_b_q;
    reg             sdo_c_q;

    assign busy = (state != S_IDLE);

    always @(posedge clk) begin
        if (rst) begin
            state      <= S_IDLE;
            cnt        <= {CNT_W{1'b0}};
            tog        <= {TOG_W{1'b0}};
            cap        <= 1'b0;
            adc_convst <= 1'b0;
            adc_cs_n   <= 1'b1;
            adc_sclk   <= 1'b0;
            done       <= 1'b0;
            sdo_a_q    <= 1'b0;
            sdo_b_q    <= 1'b0;
            sdo_c_q    <= 1'b0;
        end else begin
            sdo_a_q <= adc_sdo_a;
            sdo_b_q <= adc_sdo_b;
            sdo_c_q <= adc_sdo_c;
            done    <= 1'b0;
            cap     <= 1'b0;
            case (state)
                S_IDLE: if (start) begin
                    adc_convst <= 1'b1;
                    cnt        <= CONV_LOAD[CNT_W-1:0];
                    state      <= S_CONV;
                end
                S_CONV: if (cnt == {CNT_W{1'b0}}) begin
                    adc_convst <= 1'b0;
                    adc_cs_n   <= 1'b0;
                    cnt        <= HALF_LOAD[CNT_W-1:0];
                    tog        <= TOG_LOAD[TOG_W-1:0];
                    state      <= S_READ;
                end else begin
                    cnt <= cnt - 1'b1;
                end
                S_READ: if (cnt == {CNT_W{1'b0}}) begin
                    adc_sclk <= ~adc_sclk;
                    cap      <= adc_sclk;             // a falling SCLK edge: the pin holds a bit now
                    cnt      <= HALF_LOAD[CNT_W-1:0];
                    if (tog == {TOG_W{1'b0}}) state <= S_LAST;
                    else                      tog   <= tog - 1'b1;
                end else begin
                    cnt <= cnt - 1'b1;
                end
                default: begin                        // S_LAST: the last bit is in sdo_*_q
                    adc_cs_n <= 1'b1;
                    done     <= 1'b1;
                    state    <= S_IDLE;
                end
            endcase
        end
    end

    // ---- shift registers and outputs ----
    // sh_* collects the first B-1 bits (MSB first); the output takes them with the last bit.
    generate
        if (ADC_BITS == 1) begin : g_one_bit
            always @(posedge clk) begin
                if (rst) begin
                    code_a <= 1'b0;
                    code_b <= 1'b0;
                    code_c <= 1'b0;
                end else if (state == S_LAST) begin
                    code_a <= sdo_a_q;
                    code_b <= sdo_b_q;
                    code_c <= sdo_c_q;
                end
            end
        end else begin : g_shift
            reg  [ADC_BITS-2:0] sh_a;
            reg  [ADC_BITS-2:0] sh_b;
            reg  [ADC_BITS-2:0] sh_c;
            wire [ADC_BITS-1:0] next_a = {sh_a, sdo_a_q};
            wire [ADC_BITS-1:0] next_b = {sh_b, sdo_b_q};
            wire [ADC_BITS-1:0] next_c = {sh_c, sdo_c_q};
            always @(posedge clk) begin
                if (rst) begin
                    sh_a   <= {(ADC_BITS-1){1'b0}};
                    sh_b   <= {(ADC_BITS-1){1'b0}};
                    sh_c   <= {(ADC_BITS-1){1'b0}};
                    code_a <= {ADC_BITS{1'b0}};
                    code_b <= {ADC_BITS{1'b0}};
                    code_c <= {ADC_BITS{1'b0}};
                end else begin
                    if (cap) begin
                        sh_a <= next_a[ADC_BITS-2:0];
                        sh_b <= next_b[ADC_BITS-2:0];
                        sh_c <= next_c[ADC_BITS-2:0];
                    end
                    if (state == S_LAST) begin
                        code_a <= next_a;
                        code_b <= next_b;
                        code_c <= next_c;
                    end
                end
            end
        end
    endgenerate

endmodule
`default_nettype wire
