`default_nettype none
// hfi_adc_trigger: ADC sampling instants (OS / DS / OS_BLANK) and the keep flag of each sample.
//
// Implements docs/spec.md 2.3 (golden/fpga/adc_trigger.py: sample_phases, blank_mask); Benevieri et
// al. 2023, Sec. II-B (1 us current oversampling) and Fig. 8 (blanking after the switching instants).
//
// Ports (inputs are the carrier's values of the current tick, rtl/hfi_carrier.v):
//   phase        u17  phi = t mod P (0..2H-1);   half: u16 effective H;
//   at_zc             phi == H/2 (window boundary);  at_bottom: phi == 0.
//   mode_reg     u2   CTRL.ADC_MODE: 0 OS, 1 DS, 2 OS_BLANK, 3 reserved (runs as OS).
//   os_ticks_reg u16  OS_TICKS; the interval used is max(OS_TICKS, OS_MIN) (golden effective_os_ticks).
//   blank_ticks_reg u16 BLANK_TICKS (0: nothing is dropped).
//   sw_event          some leg's ideal switch signal changed in this tick (hfi_gate_gen.sw_event).
//   sample            high in the tick of a sampling instant (the ADC CONVST rises one cycle later).
//   keep              valid with sample: 0 when OS_BLANK drops the sample (blank_mask), else 1.
//   mode         u2   the ADC_MODE in use in this tick.
// Latency: none; sample/keep/mode describe the current tick (combinational from the inputs of this
// tick and registered state).  Throughput: one tick per clock.  Multipliers: 0.
//
// Sampling instants of a tick with phase phi (golden sample_phases(mode, H, OS, OS_MIN)):
//   OS, OS_BLANK, 3: phi = m*OS (m = 0, 1, ...) with phi <= P - OS_MIN; phi = 0 is always taken.
//                    Implemented with a counter of phi mod OS restarted at every bottom.
//   DS:              phi = 0 and phi = H.
// Blanking (golden blank_mask): a sample at tick t is dropped iff BLANK_TICKS != 0 and some switch
// event happened at t_s with 0 <= t - t_s < BLANK_TICKS.  The age of the latest event is counted
// (saturating at 65535, which is never < BLANK_TICKS); events are tracked in every mode, so the events
// of previous windows (and those before an OS_BLANK window started) are included.
//
// When the registers apply (decisions of this module, documented in docs/rtl.md terms):
//   ADC_MODE and BLANK_TICKS: at window boundaries.  The value present on the port in the at_zc tick
//     is used from that tick (the boundary sample is the first of the new window) to the tick before
//     the next boundary; after rst the value present during reset is used from tick 0.
//   OS_TICKS: at carrier bottoms (the OS sequence restarts at every period start): the value present
//     in the bottom tick (tick 0 included) is used for that whole period.
//   OS_MIN is a synthesis parameter, 1..65535 (default 40 = 32 CORDIC iterations + 8).
// Carrier inputs: phase, half, at_zc and at_bottom must come from hfi_carrier (as in hfi_dsp and the
// testbench): H changes only in at_bottom ticks, where phi = 0. Timing structure: the quantities of the
// OS instants (phi mod OS is 0, the bound P - OS_MIN) and the age of the latest switch event are
// registered the tick before, so sample and keep are a few gates after registers, one compare each.
module hfi_adc_trigger #(
    parameter OS_MIN = 40
) (
    input  wire        clk,
    input  wire        rst,
    input  wire [16:0] phase,
    input  wire [15:0] half,
    input  wire        at_zc,
    input  wire        at_bottom,
    input  wire [1:0]  mode_reg,
    input  wire [15:0] os_ticks_reg,
    input  wire [15:0] blank_ticks_reg,
    input  wire        sw_event,
    output wire        sample,
    output wire        keep,
    output wire [1:0]  mode
);
    localparam [1:0]  MODE_DS       = 2'd1;
    localparam [1:0]  MODE_OS_BLANK = 2'd2;
    localparam [15:0] OS_MIN16      = OS_MIN[15:0];

    wire [15:0] os_in = (os_ticks_reg < OS_MIN16) ? OS_MIN16 : os_ticks_reg;

    reg  [1:0]  mode_q;     // mode of the current window (latched at the boundary)
    reg  [15:0] blank_q;    // BLANK_TICKS of the current window
    reg  [15:0] os_q;       // OS interval of the current period (latched at the bottom)
    reg  [15:0] os_pos_q;   // phi mod OS for the current tick (not used in the bottom tick)
    reg  [15:0] os_m1_q;    // os_q - 1 (os_q >= OS_MIN >= 1)
    reg         os_zero_q;  // os_pos_q == 0
    reg  signed [18:0] lim_q;   // 2H - OS_MIN of the previous tick (= this tick's unless at a bottom)
    // Ticks since the latest switch event before this tick, saturating: age_now = ev_q ? 1 : inc_q, with
    // ev_q the previous tick's sw_event and inc_q the saturating increment of the previous age_now (the
    // gate generator's same-tick sw_event only enters the one-bit ev_q).
    reg         ev_q;
    reg  [15:0] inc_q;

    assign mode = at_zc ? mode_reg : mode_q;
    wire [15:0] blank  = at_zc ? blank_ticks_reg : blank_q;
    wire [15:0] os_now = at_bottom ? os_in : os_q;

    // OS instants: phi mod OS == 0 and phi + OS_MIN <= P (phi = 0 always). Outside the bottom tick H
    // is the one of the previous tick: phi + OS_MIN <= 2H <=> phi <= lim_q.
    wire os_in_range = $signed({2'b00, phase}) <= lim_q;
    wire os_hit      = at_bottom || (os_zero_q && os_in_range);
    wire ds_hit      = at_bottom || (phase == {1'b0, half});
    assign sample    = (mode == MODE_DS) ? ds_hit : os_hit;

    // blanking: an event in this tick or one less than BLANK_TICKS ticks ago
    wire [15:0] age_now = ev_q ? 16'd1 : inc_q;
    // keep = !(on & (sw_event | recent)) with on = OS_BLANK mode and BLANK_TICKS != 0, both formed for
    // the registers of the boundary tick and for those of the window and selected before sw_event
    // enters (timing: sw_event is the latest input, one gate from keep)
    wire recent_z = ev_q ? (blank_ticks_reg > 16'd1) : (inc_q < blank_ticks_reg);
    wire recent_w = ev_q ? (blank_q > 16'd1) : (inc_q < blank_q);
    wire on_z = mode_reg == MODE_OS_BLANK && blank_ticks_reg != 16'd0;
    wire on_w = mode_q == MODE_OS_BLANK && blank_q != 16'd0;
    wire on = at_zc ? on_z : on_w;
    wire on_recent = at_zc ? (on_z && recent_z) : (on_w && recent_w);
    assign keep  = !(on && sw_event) && !on_recent;

    // os_q - 1 of the next tick (os_q changes at bottoms only)
    wire [15:0] os_in_m1 = (os_ticks_reg < OS_MIN16) ? OS_MIN16 - 16'd1 : os_ticks_reg - 16'd1;
    // phi mod OS of the next tick: restarts at 0 in a bottom tick (then 1 next), wraps at os_now
    // (os_pos_q < os_q: os_pos_q + 1 == os_q <=> os_pos_q == os_q - 1, and os_pos_q + 1 < 2^16)
    wire        os_wrap    = at_bottom ? (os_in == 16'd1) : (os_pos_q == os_m1_q);
    wire [15:0] os_pos_n   = os_wrap ? 16'd0 : at_bottom ? 16'd1 : os_pos_q + 16'd1;

    always @(posedge clk) begin
        if (rst) begin
            mode_q    <= mode_reg;
            blank_q   <= blank_ticks_reg;
            os_q      <= os_in;
            os_m1_q   <= os_in_m1;
            os_pos_q  <= 16'd0;
            os_zero_q <= 1'b1;
            ev_q      <= 1'b0;
            inc_q     <= 16'hFFFF;
        end else begin
            mode_q    <= mode;
            blank_q   <= blank;
            os_q      <= os_now;
            if (at_bottom)
                os_m1_q <= os_in_m1;
            os_pos_q  <= os_pos_n;
            os_zero_q <= os_wrap;
            ev_q      <= sw_event;
            inc_q     <= (age_now == 16'hFFFF) ? age_now : age_now + 16'd1;
        end
        lim_q <= $signed({2'b00, half, 1'b0}) - $signed({3'b000, OS_MIN16});
    end
endmodule

`default_nettype wire
