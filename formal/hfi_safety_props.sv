`default_nettype none
// Formal wrapper of rtl/hfi_safety.v with rtl/hfi_gate_gen.v behind it (SymbiYosys:
// formal/hfi_safety.sby, scripts/prove.py).
//
// The two blocks are wired exactly as in rtl/hfi_dsp.v (u_gate_gen, u_safety): gate_gen.enable =
// safety.enable, gate_gen.kill = safety.kill, safety.gate_in = gate_gen.gate, one rst for both.  Every
// other input is a free input of this wrapper: the carrier (phase, half, at_bottom, at_top, also
// inconsistent with each other), the six compares, dead_reg, the pins sto and desat, oc_trip,
// wdt_expired, fault_clear, ctrl_enable and rst can take any value in any cycle ("for any register
// and firmware state").  Proven by k-induction (sby mode prove, smtbmc) for all input sequences:
//   (a) STO => all gates off in the next clock:
//       (a1) sto_s (the synchronized STO, hfi_safety output) high in clock t => gate == 0 in t+1;
//       (a2) at the pin: sto high in clock t-2 => gate == 0 in clock t+1 (3 clocks pin -> gates off).
//            This is the exact formulation for the 2-flop synchronizer: (a0) below proves
//            sto_s(t) == sto(t-2) from the third clock on (0 before: the flops' configuration value),
//            so (a2) is (a1) moved to the pin, and it needs STO for one clock only (not for the three
//            clocks t..t+2).  The cover task shows it is tight: with STO high only since clock t-1
//            a gate can still be on in clock t+1.
//   (b) the STO and DESAT latches:
//       fault_sto falls only in the clock after a clock with fault_clear = 1 and sto_s = 0, or after
//       rst; sto_s high (without rst) sets fault_sto in the next clock; the same for fault_desat with
//       desat_s.  While fault_sto or fault_desat is 1 (or sto_s, desat_s), drive_allowed == 0 in that
//       clock and gate == 0 in the next clock.  (Any kill, rst => gate == 0 next clock, as well.)
//   (c) no shoot-through at the final gate output (hfi_safety.gate): never gate[2x] & gate[2x+1], and
//       a gate of a leg turns on only after the other gate of that leg has been off for at least
//       DEAD_MIN full cycles (property (b) of formal/hfi_gate_gen_props.sv, at the pins).
// The cover task shows the properties are not vacuous: gates on, STO, gates off, FAULT_CLEAR with
// STO released, gates on again, with no rst in between (the re-arm works).
module hfi_safety_props #(
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
    input wire        sto,
    input wire        desat,
    input wire        oc_trip,
    input wire        wdt_expired,
    input wire        fault_clear,
    input wire        ctrl_enable
);
    wire [5:0] gate_in;        // hfi_gate_gen output (gate_gen_out in hfi_dsp)
    wire [5:0] gate;           // the final gate outputs
    wire [2:0] s;
    wire       sw_event;
    wire       kill, enable, sto_s, desat_s, fault_oc, fault_wdt, fault_sto, fault_desat;
    wire       outputs_on, drive_allowed;

    hfi_gate_gen #(.DEAD_MIN(DEAD_MIN)) u_gate_gen (
        .clk(clk), .rst(rst), .phase(phase), .half(half), .at_bottom(at_bottom), .at_top(at_top),
        .cmp_bot_a(cmp_bot_a), .cmp_bot_b(cmp_bot_b), .cmp_bot_c(cmp_bot_c),
        .cmp_top_a(cmp_top_a), .cmp_top_b(cmp_top_b), .cmp_top_c(cmp_top_c),
        .dead_reg(dead_reg), .enable(enable), .kill(kill),
        .gate(gate_in), .s(s), .sw_event(sw_event));

    hfi_safety u_safety (
        .clk(clk), .rst(rst), .sto(sto), .desat(desat), .oc_trip(oc_trip), .wdt_expired(wdt_expired),
        .fault_clear(fault_clear), .ctrl_enable(ctrl_enable), .at_bottom(at_bottom), .gate_in(gate_in),
        .gate(gate), .kill(kill), .enable(enable), .sto_s(sto_s), .desat_s(desat_s),
        .fault_oc(fault_oc), .fault_wdt(fault_wdt), .fault_sto(fault_sto), .fault_desat(fault_desat),
        .outputs_on(outputs_on), .drive_allowed(drive_allowed));

    // ---------------------------------------------------------------- history
    // hist[6*i +: 6] = final gate of i+1 cycles ago, hist_in the same for gate_in (i = 0..DEAD_MIN-1);
    // zero before the first cycle
    reg [6*DEAD_MIN-1:0] hist = 0, hist_in = 0;
    reg [1:0]  cyc = 2'd0;     // clocks since the start, saturating at 3
    reg        f_past = 1'b0;
    reg [2:0]  sto_d = 3'd0, desat_d = 3'd0;   // pin of 1, 2, 3 clocks ago
    reg        past_rst = 1'b0, past_kill = 1'b0, past_sto_s = 1'b0, past_desat_s = 1'b0;
    reg        past_fault_sto = 1'b0, past_fault_desat = 1'b0, past_fault_clear = 1'b0;
    reg [5:0]  past_gate_in = 6'd0;
    always @(posedge clk) begin
        hist             <= {hist[6*DEAD_MIN-7:0], gate};
        hist_in          <= {hist_in[6*DEAD_MIN-7:0], gate_in};
        cyc              <= (cyc == 2'd3) ? cyc : cyc + 2'd1;
        f_past           <= 1'b1;
        sto_d            <= {sto_d[1:0], sto};
        desat_d          <= {desat_d[1:0], desat};
        past_rst         <= rst;
        past_kill        <= kill;
        past_sto_s       <= sto_s;
        past_desat_s     <= desat_s;
        past_fault_sto   <= fault_sto;
        past_fault_desat <= fault_desat;
        past_fault_clear <= fault_clear;
        past_gate_in     <= gate_in;
    end

    // gate bits that were on in any of the last DEAD_MIN cycles
    reg [5:0] recent, recent_in;
    integer i;
    always @(*) begin
        recent = 6'd0;
        recent_in = 6'd0;
        for (i = 0; i < DEAD_MIN; i = i + 1) begin
            recent = recent | hist[6*i +: 6];
            recent_in = recent_in | hist_in[6*i +: 6];
        end
    end

    // the first cycle starts in reset (the gate registers have no initial value in the RTL; the
    // synchronizers have no reset and start at their configuration value 0)
    always @(*) if (!f_past) assume(rst);

    // ---------------------------------------------------------------- (a) STO => gates off
    // (a0) the synchronizers: sto_s(t) = sto(t-2), 0 in the first two clocks (golden/fpga/safety.py)
    always @(*) begin
        assert (sto_s == ((cyc >= 2'd2) ? sto_d[1] : 1'b0));
        assert (desat_s == ((cyc >= 2'd2) ? desat_d[1] : 1'b0));
    end
    always @(*) if (f_past) begin
        if (past_sto_s) assert (gate == 6'd0);                         // (a1)
        if (sto_d[2]) assert (gate == 6'd0);                          // (a2) sto(t-2) => gate(t+1) == 0
        if (desat_d[2]) assert (gate == 6'd0);                        //      the same for DESAT
        if (past_rst || past_kill) assert (gate == 6'd0);              // any kill / rst
    end

    // ---------------------------------------------------------------- (b) the STO / DESAT latches
    always @(*) if (f_past) begin
        // falls only after fault_clear with the input released, or after rst
        if (past_fault_sto && !fault_sto) assert (past_rst || (past_fault_clear && !past_sto_s));
        if (past_fault_desat && !fault_desat) assert (past_rst || (past_fault_clear && !past_desat_s));
        // set by the synchronized input
        if (!past_rst && past_sto_s) assert (fault_sto);
        if (!past_rst && past_desat_s) assert (fault_desat);
        // a latched fault: gates off in the next clock
        if (past_fault_sto || past_fault_desat) assert (gate == 6'd0);
    end
    always @(*) if (fault_sto || fault_desat || sto_s || desat_s) assert (!drive_allowed);

    // ---------------------------------------------------------------- (c) no shoot-through
    genvar x;
    generate
        for (x = 0; x < 3; x = x + 1) begin : leg
            always @(*) if (f_past) begin
                assert (!(gate[2*x] && gate[2*x + 1]));                 // (c) at the pins
                if (gate[2*x + 1]) assert (!recent[2*x]);               // (c) low on: high off DEAD_MIN cycles
                if (gate[2*x])     assert (!recent[2*x + 1]);           // (c) high on: low off DEAD_MIN cycles
                // strengthening invariants for the induction: the gate generator output satisfies
                // the same (formal/hfi_gate_gen.sby proves it on its own) ...
                assert (!(gate_in[2*x] && gate_in[2*x + 1]));
                if (gate_in[2*x + 1]) assert (!recent_in[2*x]);
                if (gate_in[2*x])     assert (!recent_in[2*x + 1]);
            end
        end
    endgenerate
    // ... and the output register only passes or clears it: gate(t+1) is gate_in(t) or 0
    always @(*) if (f_past) assert ((gate & ~past_gate_in) == 6'd0);

    // ---------------------------------------------------------------- cover
    // gates on -> STO (synchronized) while on -> gates off -> FAULT_CLEAR accepted (fault_sto set,
    // sto_s released) -> gates on again; rst restarts the sequence
    reg [2:0] stage = 3'd0;
    always @(posedge clk) begin
        if (rst)
            stage <= 3'd0;
        else case (stage)
            3'd0: if (gate != 6'd0) stage <= 3'd1;
            3'd1: if (gate != 6'd0 && sto_s) stage <= 3'd2;
            3'd2: if (gate == 6'd0) stage <= 3'd3;
            3'd3: if (fault_sto && fault_clear && !sto_s) stage <= 3'd4;
            default: ;
        endcase
    end
    always @(*) cover (stage == 3'd4 && !fault_sto && gate != 6'd0);
    // (a2) is tight: STO high since clock t-1 only (not t-2), and a gate still on in clock t+1
    always @(*) cover (cyc == 2'd3 && sto_d[1] && !sto_d[2] && gate != 6'd0);
endmodule

`default_nettype wire
