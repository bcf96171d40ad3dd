`default_nettype none
// hfi_gate_gen: ideal switch signals of the three legs, dead time, six registered gate signals.
//
// Implements docs/spec.md 2.4 (golden/fpga/gate_generator.py, GateGenerator) with the double update of
// spec 2.1 (compares latched at the bottom for the rising half, at the top for the falling half;
// Benevieri et al. 2023, eqs. (14)-(15): the injection sign flips with the carrier slope, so each
// half has its own compare).
//
// Ports:
//   phase u17, half u16   carrier phase phi and effective H of the current tick (hfi_carrier).
//   at_bottom, at_top     phi == 0 / phi == H strobes of the current tick.
//   cmp_bot_x u16         compare of leg x latched in the at_bottom tick (used for the rising half,
//                         that tick included); cmp_top_x u16: latched in the at_top tick (falling half).
//   dead_reg u16          DEAD_TICKS; the dead time used is D = max(dead_reg, DEAD_MIN), read live
//                         (a value present in tick t applies to every turn-on still waiting in tick t;
//                         the golden model fixes D when it schedules a turn-on: identical whenever
//                         DEAD_TICKS changes while no turn-on is waiting, e.g. while disabled).
//   enable                level: gates may conduct while 1 (the top changes it only at bottoms).
//   kill                  any cycle: while high, all gates are off in the next cycle (a fault).
//   gate[5:0]             bit 2x = high switch of leg x, 2x+1 = low switch (x = a, b, c = 0, 1, 2);
//                         registered: gate in cycle t+1 = golden gate mask of tick t (GATE_LATENCY = 1).
//   s[2:0]                ideal switch signals of the current tick (combinational).
//   sw_event              some s changed at this tick vs the previous tick (before tick 0 s = 0).
// Latency: gate 1 cycle (registered), s/sw_event 0.  Throughput: one tick per clock.  Multipliers: 0.
// Carrier inputs: phase, half, at_bottom and at_top must come from hfi_carrier (as in hfi_dsp and the
// testbench): phi counts up by one per tick and restarts at 0 in the at_bottom tick, H changes only in
// at_bottom ticks (and is >= 1), at_top is phi == H, and cmp_top_{a,b,c} hold their value in the tick
// before an at_top tick (in hfi_dsp the modulator writes them 104 cycles after a zero crossing, the top
// comes H/2 >= 256 ticks after it). The switch signals of the ticks between the
// strobes are computed one tick ahead from these rules (timing, below); the dead-time logic, and so the
// safety of formal/hfi_gate_gen.sby, holds for any input sequence.
//
// Ideal switch signal (spec 2.4): s = 1 iff c < cmp on the rising half (phi < H, c = phi) or
// c <= cmp on the falling half (c = P - phi).  A compare > half behaves exactly as cmp = half
// (s = 1 for the whole half): the comparison saturates by itself, so no explicit clamp is needed.
// Timing structure: the compares of a tick that is neither a bottom nor a top are evaluated in the
// cycle before, from phi + 1 and the compares latched by then, and registered as "s changes" (chg_q,
// against that tick's s); only the strobe ticks use the ports directly: at a bottom s = (cmp_bot != 0)
// (c = 0), at a top s = (cmp_top >= H) (c = H). Everything downstream is written in terms of
// chg = s ^ s_q (restart, the mask, sw_event), which is a small mux after a register, an OR tree or one
// carry chain.
//
// Dead time (spec 2.4): per leg, el = ticks since the latest of the last change of s and the last
// rise of en = enable & ~kill (a saturating 16-bit counter, 0 in the tick of the change/rise).  The
// switch selected by s is on in tick t iff en(t) and el(t) >= D; it is off at once when s leaves it or
// en drops.  Hence a pulse of s of at most D ticks never turns on, and the two switches of a leg are
// never on together (the mask bits are s & on and ~s & on).  kill acts as enable = 0 (the dead time
// runs again from its release).  rst turns every gate off in the next cycle and restarts from s = 0,
// en = 0 (an enable high right after reset is a rise: the dead time runs from tick 0).
// The counter is kept as el + 1 of the previous tick = restart_q ? 1 : inc_q, with restart_q the
// restart of the previous tick and inc_q the saturating increment of the previous counter: the restart
// of this tick (from s) only goes into a one-bit register, never into the 16-bit counter.
// Safety proven for every input sequence in formal/hfi_gate_gen.sby (see formal/hfi_gate_gen_props.sv).
// DEAD_MIN is a synthesis parameter, 1..65535 (default 50).
module hfi_gate_gen #(
    parameter DEAD_MIN = 50
) (
    input  wire        clk,
    input  wire        rst,
    input  wire [16:0] phase,
    input  wire [15:0] half,
    input  wire        at_bottom,
    input  wire        at_top,
    input  wire [15:0] cmp_bot_a,
    input  wire [15:0] cmp_bot_b,
    input  wire [15:0] cmp_bot_c,
    input  wire [15:0] cmp_top_a,
    input  wire [15:0] cmp_top_b,
    input  wire [15:0] cmp_top_c,
    input  wire [15:0] dead_reg,
    input  wire        enable,
    input  wire        kill,
    output reg  [5:0]  gate,
    output wire [2:0]  s,
    output wire        sw_event
);
    localparam [15:0] DEAD_MIN16 = DEAD_MIN[15:0];

    // latched compares {c, b, a}
    reg  [47:0] cmp_rise_q;
    reg  [47:0] cmp_fall_q;
    wire [47:0] cmp_rise = at_bottom ? {cmp_bot_c, cmp_bot_b, cmp_bot_a} : cmp_rise_q;
    wire [47:0] cmp_fall = at_top    ? {cmp_top_c, cmp_top_b, cmp_top_a} : cmp_fall_q;

    // The next tick if it is neither a bottom nor a top: phi + 1, the same H, the compares latched by
    // the end of this tick (cmp_rise, cmp_fall).  Rising half: phi + 1 < H.  Falling half:
    // s = (P - (phi + 1) <= cf) <=> T = 2H - phi - cf - 2 < 0, evaluated as one 19-bit sum
    // 2H + ~phi + ~cf (a carry-save level, then a single carry chain); -2^18 < T < 2^18: the sign bit
    // is exact.
    wire [16:0] ph1       = phase + 17'd1;
    // H of the previous tick (a local copy: fanout): H of this tick outside a bottom tick, where the
    // next tick is rising for any H >= 1 and the falling compare is not used
    reg  [15:0] half_q;
    reg  [2:0]  top_ge_q;  // per leg: cmp_top_x >= H, registered the tick before (below)
    wire        rising_n  = at_bottom | (ph1 < {1'b0, half_q});
    wire [18:0] f_x = {2'b00, half_q, 1'b0};
    wire [18:0] f_y = ~{2'b00, phase};

    wire        en   = enable & ~kill;

    reg  [2:0]  s_q;       // s of the previous tick
    reg  [2:0]  chg_q;     // s ^ s_q of this tick if it is neither a bottom nor a top (the tick before)
    reg         en_q;      // en of the previous tick
    reg  [2:0]  rs_q;      // per leg: restart in the previous tick
    reg  [47:0] inc_q;     // per leg {c, b, a}: saturating increment of el_q of the previous tick
    wire        en_rise = en & ~en_q;
    wire [5:0]  mask;
    wire [2:0]  pre_n;
    wire [2:0]  restart;
    wire [2:0]  chg;       // s changes in this tick (s ^ s_q)
    wire [47:0] inc_n;

    genvar x;
    generate
        for (x = 0; x < 3; x = x + 1) begin : leg
            wire [15:0] cr = cmp_rise[16*x +: 16];
            wire [15:0] cf = cmp_fall[16*x +: 16];
            wire [15:0] cb = x == 0 ? cmp_bot_a : x == 1 ? cmp_bot_b : cmp_bot_c;
            wire [18:0] f_z = ~{3'b000, cf};
            wire [18:0] f_s = f_x ^ f_y ^ f_z;
            wire [18:0] f_c = {(f_x[17:0] & f_y[17:0]) | (f_x[17:0] & f_z[17:0]) | (f_y[17:0] & f_z[17:0]),
                               1'b0};
            /* verilator lint_off UNUSEDSIGNAL */               // only the sign of T is used
            wire [18:0] f_t = f_s + f_c;                         // T mod 2^19
            /* verilator lint_on UNUSEDSIGNAL */
            assign pre_n[x] = rising_n ? (ph1 < {1'b0, cr}) : f_t[18];
            // s: bottom c = 0 < cmp; top c = H <= cmp; else the value computed the tick before
            // (at a top, ct >= H is the compare registered the tick before: top_ge_q)
            assign chg[x] = at_bottom ? ((cb != 16'd0) ^ s_q[x]) : at_top ? (top_ge_q[x] ^ s_q[x]) : chg_q[x];
            assign s[x] = chg[x] ^ s_q[x];
            assign restart[x] = chg[x] | en_rise;
            // el_q = el of the previous tick + 1 (saturating) = rs_q ? 1 : inc_q; el = restart ? 0 : el_q;
            // el >= D with D = max(dead_reg, DEAD_MIN) >= 1 is false after a restart, else el_q >= dead_reg
            // and el_q >= DEAD_MIN (compares of registers and the register input only, in parallel with s)
            wire [15:0] incq    = inc_q[16*x +: 16];
            wire [15:0] elq     = rs_q[x] ? 16'd1 : incq;
            wire        ge      = (elq >= dead_reg) && (elq >= DEAD_MIN16);
            // on = en & ~restart & ge; without a restart s = s_q
            wire        on      = en & ~en_rise & ge & ~chg[x];
            assign mask[2*x]     = on & s_q[x];
            assign mask[2*x + 1] = on & ~s_q[x];
            assign inc_n[16*x +: 16] = rs_q[x] ? 16'd2 : ((incq == 16'hFFFF) ? incq : incq + 16'd1);
        end
    endgenerate

    assign sw_event = |chg;

    // cmp_top_x >= H of the previous tick, per leg: at a top tick the compares and H are those of the
    // tick before (input rule above), so this is the top's ct >= H as a register (timing: the 17-bit
    // compare is off the path sw_event -> the trigger's keep)
    always @(posedge clk) begin
        half_q <= half;
        top_ge_q <= {cmp_top_c >= half, cmp_top_b >= half, cmp_top_a >= half};
    end

    always @(posedge clk) begin
        if (rst) begin
            gate       <= 6'd0;
            s_q        <= 3'd0;
            chg_q      <= 3'd0;
            en_q       <= 1'b0;
            rs_q       <= 3'd0;
            inc_q      <= 48'd0;
            cmp_rise_q <= 48'd0;
            cmp_fall_q <= 48'd0;
        end else begin
            gate       <= mask;
            s_q        <= s;
            chg_q      <= pre_n ^ s;
            en_q       <= en;
            rs_q       <= restart;
            inc_q      <= inc_n;
            cmp_rise_q <= cmp_rise;
            cmp_fall_q <= cmp_fall;
        end
    end
endmodule

`default_nettype wire
