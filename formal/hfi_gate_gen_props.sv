`default_nettype none
// Formal wrapper of rtl/hfi_gate_gen.v (SymbiYosys: formal/hfi_gate_gen.sby, scripts/prove.py).
//
// Every input of hfi_gate_gen is a free input of this wrapper: phase, half, at_bottom, at_top (also
// inconsistent with each other), the six compares, dead_reg, enable, kill and rst can take any value
// in any cycle.  Proven by k-induction (sby mode prove, smtbmc) for all input sequences:
//   (a) never gate[2x] & gate[2x+1] (both switches of a leg on together);
//   (b) a gate of a leg turns on only after the other gate of that leg has been off for at least
//       DEAD_MIN full cycles (equivalently: after any gate turns off, the other one stays off for at
//       least DEAD_MIN cycles) - a safe dead time, whatever DEAD_TICKS says;
//   (c) kill in cycle t -> all gates off in cycle t+1;  rst in cycle t -> all gates off in t+1;
//       enable low in cycle t -> all gates off in cycle t+1.
// The cover task shows the properties are not vacuous: a leg switches high -> low -> high with the
// dead time in between.
module hfi_gate_gen_props #(
    parameter DEAD_MIN = 4
) (
    input wire        clk,
    input wire        rst,
    input wire [16:0] phase,
    input wire [15:0] half,
    input wire        at_bottom,
    input wire        at_top,
    input wire [15:0] cmp_bot_a,
    input wire [15:0] cmp_bot_b,
    input wire [15:0] cmp_bot_c,
    input wire [15:0] cmp_top_a,
    input wire [15:0] cmp_top_b,
    input wire [15:0] cmp_top_c,
    input wire [15:0] dead_reg,
    input wire        enable,
    input wire        kill
);
    wire [5:0] gate;
    wire [2:0] s;
    wire       sw_event;

    hfi_gate_gen #(.DEAD_MIN(DEAD_MIN)) dut (
        .clk(clk), .rst(rst), .phase(phase), .half(half), .at_bottom(at_bottom), .at_top(at_top),
        .cmp_bot_a(cmp_bot_a), .cmp_bot_b(cmp_bot_b), .cmp_bot_c(cmp_bot_c),
        .cmp_top_a(cmp_top_a), .cmp_top_b(cmp_top_b), .cmp_top_c(cmp_top_c),
        .dead_reg(dead_reg), .enable(enable), .kill(kill),
        .gate(gate), .s(s), .sw_event(sw_event));

    // hist[6*i +: 6] = gate of i+1 cycles ago (i = 0..DEAD_MIN-1); zero before the first cycle
    reg [6*DEAD_MIN-1:0] hist = 0;
    reg        f_past = 1'b0;
    reg        past_rst = 1'b0, past_kill = 1'b0, past_enable = 1'b1;
    always @(posedge clk) begin
        hist        <= {hist[6*DEAD_MIN-7:0], gate};
        f_past      <= 1'b1;
        past_rst    <= rst;
        past_kill   <= kill;
        past_enable <= enable;
    end

    // gate bits that were on in any of the last DEAD_MIN cycles
    reg [5:0] recent;
    integer i;
    always @(*) begin
        recent = 6'd0;
        for (i = 0; i < DEAD_MIN; i = i + 1)
            recent = recent | hist[6*i +: 6];
    end

    // the first cycle starts in reset (the gate register has no initial value in the RTL)
    always @(*) if (!f_past) assume(rst);

    genvar x;
    generate
        for (x = 0; x < 3; x = x + 1) begin : leg
            always @(*) if (f_past) begin
                assert (!(gate[2*x] && gate[2*x + 1]));                 // (a)
                if (gate[2*x + 1]) assert (!recent[2*x]);               // (b) low on: high off DEAD_MIN cycles
                if (gate[2*x])     assert (!recent[2*x + 1]);           // (b) high on: low off DEAD_MIN cycles
            end
        end
    endgenerate

    always @(*) if (f_past && (past_rst || past_kill || !past_enable)) assert (gate == 6'd0);   // (c)

    // non-vacuity: leg a goes high -> low -> high (both turn-ons after a dead time)
    reg [1:0] seen = 2'd0;
    always @(posedge clk) begin
        if (gate[0] && seen == 2'd0) seen <= 2'd1;
        if (gate[1] && seen == 2'd1) seen <= 2'd2;
    end
    always @(*) cover (seen == 2'd2 && gate[0]);
endmodule

`default_nettype wire
