`default_nettype none
// hfi_cordic: iterative rotation-mode CORDIC, sine and cosine of a u32 binary angle in Q1.15.
//
// Implements docs/spec.md section 3.3, bit for bit equal to golden/fpga/cordic.py
// (`sincos_q15(angle, WIDTH, ITERATIONS)` = `to_q15(cordic_sincos(angle, WIDTH, ITERATIONS))`).
// In the DSP path it computes the demodulation weight w = sin(-cw*pi/2) of each sample
// (Benevieri et al. 2023, eq. (15) and eq. (19); `golden.fpga.cordic.demod_weight`), with the paper's
// 32 bits / 32 clocks (WIDTH = ITERATIONS = 32).
//
// Algorithm (spec 3.3):
//   fold:  top two angle bits 01 or 10 (90..270 deg): z = angle - 2^31 and negate the results,
//          else z = angle read as s32; z lies in [-2^30, 2^30). In bits: z = {angle[30], angle[30:0]},
//          fold = angle[31] ^ angle[30].
//   start: x = x0 = round(K_N * 2^(WIDTH-2)) (K_N = prod_{i<N} 1/sqrt(1 + 2^-2i)), y = 0.
//   iteration i = 0 .. ITERATIONS-1, one per clock: d = +1 if z >= 0 else -1;
//          x' = x - d*(y >>> i), y' = y + d*(x >>> i), z' = z - d*ATAN[i],
//          ATAN[i] = round(atan(2^-i) * 2^32 / 2pi).
//   output: sin = y, cos = x in Q2.(WIDTH-2), negated if folded, then
//          Q1.15 = sat16(round_shr(v, WIDTH-17)) (round half up, saturate: +1.0 -> 32767).
//   x, y are sWIDTH registers (|x|, |y| stay about 2^(WIDTH-2), no overflow; golden docstring), z is
//   s32. ATAN[] and x0 are constant functions generated from the golden model into
//   rtl/hfi_cordic_tables.vh by scripts/gen_rtl_tables.py. No multiplier.
//
// Parameters:
//   WIDTH       data width of x, y: 17..32 (the Q1.15 conversion needs WIDTH >= 17), default 32.
//   ITERATIONS  number of CORDIC iterations (clocks): 1..WIDTH, default 32.
//   Out-of-range values are a build error (instance of the non-existent module
//   `hfi_cordic_bad_parameters_WIDTH_17_to_32_ITERATIONS_1_to_WIDTH`).
//
// Ports:
//   clk, rst     clock; synchronous active-high reset (aborts a computation: busy and done drop,
//                no done follows for it; sin_q15 = cos_q15 = 0 after reset).
//   start        in: start a computation of `angle` in this cycle. Accepted only when busy = 0;
//                a start while busy is ignored (the running computation is not disturbed).
//   angle        in, u32 binary angle (2^32 = one turn), sampled in the start cycle only.
//   busy         out: high from the cycle after an accepted start up to and including the cycle
//                before done (LATENCY - 1 cycles); low in the done cycle, so a new start may be
//                given in the done cycle itself (back to back) or any later cycle.
//   done         out: one-cycle pulse, exactly LATENCY cycles after the start cycle.
//   sin_q15      out, s16 Q1.15: sin(angle), valid from the done cycle, held until the next done.
//   cos_q15      out, s16 Q1.15: cos(angle), likewise.
//
// Timing: start in cycle t -> x, y, z loaded at the end of t; iterations at the ends of cycles
//   t+1 .. t+ITERATIONS; negate/round/saturate into the output registers at the end of
//   t+ITERATIONS+1; done (and the new outputs) in cycle t + LATENCY, LATENCY = ITERATIONS + 2.
//   Throughput: one result every LATENCY cycles (start in every done cycle).

module hfi_cordic #(
    parameter WIDTH = 32,
    parameter ITERATIONS = 32
) (
    input  wire               clk,
    input  wire               rst,
    input  wire               start,
    input  wire        [31:0] angle,
    output wire               busy,
    output reg                done,
    output reg  signed [15:0] sin_q15,
    output reg  signed [15:0] cos_q15
);

`include "hfi_cordic_tables.vh"

    // Cycles from the start cycle to the done cycle (the interface constant; the sequencer below
    // realizes it: 1 load + ITERATIONS rotations + 1 output stage).
    /* verilator lint_off UNUSEDPARAM */  // documentation / testbench constant, not used in logic
    localparam integer LATENCY = ITERATIONS + 2;
    /* verilator lint_on UNUSEDPARAM */

    // ---- parameter check (a clear build error on Verilator, Icarus and Yosys) ------------------------
    generate
        if (WIDTH < 17 || WIDTH > 32 || ITERATIONS < 1 || ITERATIONS > WIDTH) begin : g_bad_parameters
            hfi_cordic_bad_parameters_WIDTH_17_to_32_ITERATIONS_1_to_WIDTH u_error ();
        end
    endgenerate

    localparam integer SHIFT = WIDTH - 17;  // Q2.(WIDTH-2) -> Q1.15 right shift
    localparam integer AW = WIDTH + 1;      // output adder: -v needs one bit more than sWIDTH
    localparam [31:0] X0_32 = hfi_cordic_x0(WIDTH, ITERATIONS);
    localparam [WIDTH-1:0] X0 = X0_32[WIDTH-1:0];       // < 2^(WIDTH-2): fits sWIDTH
    localparam [31:0] LAST_32 = ITERATIONS - 1;
    localparam [4:0] LAST = LAST_32[4:0];                // index of the last iteration, 0..31
    // Rounding constant of round_shr(v, SHIFT): 2^(SHIFT-1), 0 for SHIFT = 0.
    localparam [AW-1:0] ONE = {{(AW - 1) {1'b0}}, 1'b1};
    localparam [AW-1:0] RND = (ONE << SHIFT) >> 1;

    // ---- state ---------------------------------------------------------------------------------------
    reg                    busy_r;   // a computation is running (rotating or in the output stage)
    reg                    rot;      // rotating (iterations left); 0 in the output-stage cycle
    reg              [4:0] iter;     // iteration index i
    reg                    neg;      // folded: negate the results
    reg signed [WIDTH-1:0] x, y;     // Q2.(WIDTH-2)
    reg signed      [31:0] z;        // residual angle, binary angle units

    assign busy = busy_r;

    // ---- one iteration (combinational) ---------------------------------------------------------------
    // ATAN[iter] comes from a register loaded one cycle ahead from its own counter (iter + 1), so no
    // adder precedes the table lookup (timing).
    reg              [4:0] iter_p1;  // iter + 1
    reg             [31:0] atan_i;   // ATAN[iter]
    wire               z_neg = z[31];      // d = -1
    // x - d*(y >>> i), y + d*(x >>> i), z - d*ATAN[i] as one adder each (timing: no multiplexer
    // after the carry chains): a subtraction adds the inverted operand and a carry of 1, which enters
    // through an extra low bit ({a, 1} + {b, c} carries c into bit 1). The operands are inverted
    // before the shift (~(v >>> i) = (~v) >>> i), so the inversion shares the first multiplexer level;
    // its control is a register of its own per operand (inv_y = ~z_neg for x - y_sh, inv_x = z_neg
    // for y - x_sh, loaded with z: fanout, no gate in front of the multiplexers).
    reg                    inv_y, inv_x;
    wire signed [WIDTH-1:0] y_op, x_op;  // (y ^ inv_y) >>> i, (x ^ inv_x) >>> i
`ifdef HFI_TARGET_ECP5
    // Lattice ECP5 (defined by scripts/synth_report.py for synth_ecp5): the shift as slice structures,
    // per operand bit an 8:1 multiplexer by i mod 8 (four LUT4s, each a 2:1 and the inversion, two
    // PFUMX, one L6MUX21: one slice pair) of the register bits, then a 4:1 by floor(i/8) (two LUT4s,
    // one PFUMX) of those results: two logic levels in front of the carry chains instead of the
    // four to five of the generic shifter's LUT mapping (docs/rtl.md "Timing"). Bit for bit the
    // generic expression of the #else branch (an arithmetic right shift: indices clamp at the sign).
    genvar gb, gq;
    generate
        for (gb = 0; gb < 2 * WIDTH; gb = gb + 1) begin : g_fine      // y bits 0..WIDTH-1, then x
            localparam integer K = gb % WIDTH;
            wire [WIDTH-1:0] v = (gb < WIDTH) ? y : x;
            wire             inv = (gb < WIDTH) ? inv_y : inv_x;
            wire [3:0]       m;
            wire             p0, p1, f;   // f = ((v ^ inv) >>> i[2:0])[K]
            for (gq = 0; gq < 4; gq = gq + 1) begin : g_l
                localparam integer I0 = (K + 2 * gq < WIDTH) ? K + 2 * gq : WIDTH - 1;
                localparam integer I1 = (K + 2 * gq + 1 < WIDTH) ? K + 2 * gq + 1 : WIDTH - 1;
                LUT4 #(.INIT(16'h35CA)) u_l (.A(v[I0]), .B(v[I1]), .C(iter[0]), .D(inv), .Z(m[gq]));
            end                                                        // Z = (C ? B : A) ^ D
            PFUMX u_p0 (.ALUT(m[1]), .BLUT(m[0]), .C0(iter[1]), .Z(p0));   // Z = C0 ? ALUT : BLUT
            PFUMX u_p1 (.ALUT(m[3]), .BLUT(m[2]), .C0(iter[1]), .Z(p1));
            L6MUX21 u_l6 (.D0(p0), .D1(p1), .SD(iter[2]), .Z(f));         // Z = SD ? D1 : D0
        end
        for (gb = 0; gb < 2 * WIDTH; gb = gb + 1) begin : g_coarse
            localparam integer J = gb % WIDTH;
            localparam integer B = gb - J;                             // 0 (y) or WIDTH (x)
            localparam integer J8 = (J + 8 < WIDTH) ? J + 8 : WIDTH - 1;
            localparam integer J16 = (J + 16 < WIDTH) ? J + 16 : WIDTH - 1;
            localparam integer J24 = (J + 24 < WIDTH) ? J + 24 : WIDTH - 1;
            wire a0, a1, o;
            LUT4 #(.INIT(16'hCACA)) u_a0 (.A(g_fine[B + J].f), .B(g_fine[B + J8].f), .C(iter[3]), .D(1'b0),
                                          .Z(a0));                     // Z = C ? B : A
            LUT4 #(.INIT(16'hCACA)) u_a1 (.A(g_fine[B + J16].f), .B(g_fine[B + J24].f), .C(iter[3]),
                                          .D(1'b0), .Z(a1));
            PFUMX u_p (.ALUT(a1), .BLUT(a0), .C0(iter[4]), .Z(o));
            if (gb < WIDTH) begin : g_y
                assign y_op[J] = o;
            end else begin : g_x
                assign x_op[J] = o;
            end
        end
    endgenerate
`else
    assign y_op = $signed(y ^ {WIDTH{inv_y}}) >>> iter;
    assign x_op = $signed(x ^ {WIDTH{inv_x}}) >>> iter;
`endif
    /* verilator lint_off UNUSEDSIGNAL */  // bit 0 of the sums is the carry-in helper
    wire [WIDTH:0] x_sum = {x, 1'b1} + {y_op, inv_y};
    wire [WIDTH:0] y_sum = {y, 1'b1} + {x_op, inv_x};
    wire [32:0]    z_sum = {z, 1'b1} + {atan_i ^ {32{~z_neg}}, ~z_neg};
    /* verilator lint_on UNUSEDSIGNAL */
    wire signed [WIDTH-1:0] x_next = x_sum[WIDTH:1];
    wire signed [WIDTH-1:0] y_next = y_sum[WIDTH:1];
    wire signed     [31:0] z_next = z_sum[32:1];

    // ---- output stage: optional negation, round half up, shift, saturate ----------------------------
    // -v + RND = ~v + (RND + 1): one adder. AW bits hold -v + RND without overflow.
    wire [AW-1:0] x_ext = {x[WIDTH-1], x};
    wire [AW-1:0] y_ext = {y[WIDTH-1], y};
    wire [AW-1:0] neg_ext = {{(AW - 1) {1'b0}}, neg};
    /* verilator lint_off UNUSEDSIGNAL */  // bits [SHIFT-1:0] are rounded off by design
    wire [AW-1:0] cos_sum = (neg ? ~x_ext : x_ext) + RND + neg_ext;
    wire [AW-1:0] sin_sum = (neg ? ~y_ext : y_ext) + RND + neg_ext;
    /* verilator lint_on UNUSEDSIGNAL */
    wire [17:0] cos_q = cos_sum[AW-1:SHIFT];  // round_shr(v, SHIFT): s18
    wire [17:0] sin_q = sin_sum[AW-1:SHIFT];

    // sat(q, 16) of an s18 value.
    function [15:0] sat16(input [17:0] q);
        begin
            if (!q[17] && q[16:15] != 2'b00) sat16 = 16'h7fff;
            else if (q[17] && q[16:15] != 2'b11) sat16 = 16'h8000;
            else sat16 = q[15:0];
        end
    endfunction

    // ---- sequencer -----------------------------------------------------------------------------------
    always @(posedge clk) begin
        if (rst) begin
            busy_r <= 1'b0;
            rot <= 1'b0;
            iter <= 5'd0;
            done <= 1'b0;
            sin_q15 <= 16'sd0;
            cos_q15 <= 16'sd0;
        end else begin
            done <= 1'b0;
            if (!busy_r) begin
                if (start) begin  // load: fold, x0, y0 = 0
                    busy_r <= 1'b1;
                    rot <= 1'b1;
                    iter <= 5'd0;
                end
            end else if (rot) begin  // iteration `iter`
                iter <= iter + 5'd1;
                if (iter == LAST) rot <= 1'b0;
            end else begin  // output stage
                busy_r <= 1'b0;
                done <= 1'b1;
                sin_q15 <= sat16(sin_q);
                cos_q15 <= sat16(cos_q);
            end
        end
    end

    // Datapath registers (no reset needed: loaded by every accepted start). The load is a synchronous
    // set/reset of x and y (constants), the rotation their enable: no gate after the adders.
    wire load = start & ~busy_r;
    always @(posedge clk) begin
        if (load) begin  // fold, x0, y0 = 0
            x <= X0;
            y <= {WIDTH{1'b0}};
        end else if (rot) begin
            x <= x_next;
            y <= y_next;
        end
    end
    always @(posedge clk) begin
        if (load) begin
            neg <= angle[31] ^ angle[30];
            z <= {angle[30], angle[30:0]};  // angle - 2^31 if folded, else angle as s32
            inv_y <= ~angle[30];            // the sign of the folded angle is angle[30]
            inv_x <= angle[30];
            iter_p1 <= 5'd1;
            atan_i <= hfi_cordic_atan(0);
        end else if (rot) begin
            z <= z_next;
            inv_y <= ~z_next[31];
            inv_x <= z_next[31];
            iter_p1 <= iter_p1 + 5'd1;
            atan_i <= hfi_cordic_atan({27'd0, iter_p1});
        end
    end

endmodule
`default_nettype wire
