`default_nettype none
// hfi_vector: iterative vectoring CORDIC, the angle and magnitude of a vector (x, y), bit for bit equal to
// golden/firmware/vector.py (`vector_angle(x, y)`, docs/spec.md 5.3): the firmware's fw_vector_angle, which
// the SoC build takes from this unit through hfi_soc_acc (firmware/src/fw_acc.c).
//
// Algorithm (golden.firmware.vector, 16 iterations, the ATAN table and x0 of the 32-bit rotation CORDIC
// hfi_cordic, from rtl/hfi_cordic_tables.vh):
//   input: x, y saturated to [-2^28, 2^28] (the golden function's precondition |x|, |y| <= 2^28, which its
//          callers meet by saturating; inputs beyond it give the result of the saturated vector here).
//   fold:  if x < 0: x, y = -x, -y and z = 2^31 (half a turn), else z = 0.
//   iteration i = 0 .. 15, one per clock: if y > 0: x, y, z = x + (y >>> i), y - (x >>> i), z + ATAN[i];
//          else: x, y, z = x - (y >>> i), y + (x >>> i), z - ATAN[i] (both from the old x and y).
//   output: angle = z (u32 binary angle, 2^32 = one turn), magnitude = (x * X0) >> 30, X0 = round(K_16 2^30)
//          (removes the CORDIC gain). x stays in 0 .. 2^30 (golden docstring), so x * X0 < 2^60 and the
//          magnitude < 2^30; one registered multiply (x is non-negative: an unsigned 31 x 30 product).
//   (0, 0) gives magnitude 0 and an angle of no meaning (the golden one: 0 - sum of ATAN[] mod 2^32).
//
// Ports:
//   clk, rst     clock; synchronous active-high reset (aborts a computation: busy and done drop, no done
//                follows for it; angle = mag = 0 after reset).
//   start        in: start a computation of (x, y) in this cycle; accepted only when busy = 0 (a start
//                while busy is ignored, the running computation is not disturbed).
//   x, y         in, s32, sampled in the start cycle only.
//   busy         out: high from the cycle after an accepted start to the cycle before done (LATENCY - 1
//                cycles); low in the done cycle, so a new start may be given in the done cycle.
//   done         out: one-cycle pulse, exactly LATENCY = 18 cycles after the start cycle.
//   angle        out, u32: valid from the done cycle, held until the next done.
//   mag          out, s32 (0 .. 2^30): likewise.
//
// Timing: start in cycle t -> saturated, folded operands loaded at the end of t; iterations at the ends
//   of t+1 .. t+16; the product into the output registers at the end of t+17; done in t+18.
module hfi_vector (
    input  wire               clk,
    input  wire               rst,
    input  wire               start,
    input  wire signed [31:0] x,
    input  wire signed [31:0] y,
    output wire               busy,
    output reg                done,
    output reg         [31:0] angle,
    output reg  signed [31:0] mag
);

`include "hfi_cordic_tables.vh"

    localparam integer ITERATIONS = 16;
    localparam [3:0] LAST = 4'd15;                              // index of the last iteration
    /* verilator lint_off UNUSEDPARAM */  // the interface constant, for testbenches and documentation
    localparam integer LATENCY = ITERATIONS + 2;
    /* verilator lint_on UNUSEDPARAM */
    localparam [31:0] X0 = hfi_cordic_x0(32, ITERATIONS);      // round(K_16 * 2^30) < 2^30
    localparam signed [31:0] LIMIT = 32'sd268435456;            // 2^28, golden INPUT_LIMIT

    // ---- input: saturate to +-2^28, then fold into the right half-plane -----------------------------
    function signed [31:0] sat28(input signed [31:0] v);
        begin
            if (v > LIMIT) sat28 = LIMIT;
            else if (v < -LIMIT) sat28 = -LIMIT;
            else sat28 = v;
        end
    endfunction
    wire signed [31:0] xs = sat28(x);
    wire signed [31:0] ys = sat28(y);
    wire               fold = xs[31];

    // ---- state --------------------------------------------------------------------------------------
    reg               busy_r;   // a computation is running (iterating or in the output stage)
    reg               rot;      // iterating; 0 in the output-stage cycle
    reg         [3:0] iter;     // iteration index i
    reg signed [31:0] xr, yr;   // |xr| < 2^30, |yr| < 2^30
    reg        [31:0] z;        // binary angle, wraps

    assign busy = busy_r;

    // ---- one iteration (combinational) ----------------------------------------------------------------
    wire               up = !yr[31] && yr != 32'sd0;        // y > 0
    wire signed [31:0] y_sh = yr >>> iter;
    wire signed [31:0] x_sh = xr >>> iter;
    wire        [31:0] atan_i = hfi_cordic_atan({28'd0, iter});
    wire signed [31:0] x_next = up ? xr + y_sh : xr - y_sh;
    wire signed [31:0] y_next = up ? yr - x_sh : yr + x_sh;
    wire        [31:0] z_next = up ? z + atan_i : z - atan_i;

    // ---- output: magnitude = (x * X0) >> 30 of a non-negative x < 2^30 ------------------------------
    /* verilator lint_off UNUSEDSIGNAL */  // the low 30 bits are shifted out, the top bit is 0
    wire [61:0] product = {31'd0, xr[30:0]} * {32'd0, X0[29:0]};
    /* verilator lint_on UNUSEDSIGNAL */

    // ---- sequencer ----------------------------------------------------------------------------------
    always @(posedge clk) begin
        if (rst) begin
            busy_r <= 1'b0;
            rot <= 1'b0;
            iter <= 4'd0;
            done <= 1'b0;
            angle <= 32'd0;
            mag <= 32'sd0;
        end else begin
            done <= 1'b0;
            if (!busy_r) begin
                if (start) begin
                    busy_r <= 1'b1;
                    rot <= 1'b1;
                    iter <= 4'd0;
                end
            end else if (rot) begin
                iter <= iter + 4'd1;
                if (iter == LAST) rot <= 1'b0;
            end else begin
                busy_r <= 1'b0;
                done <= 1'b1;
                angle <= z;
                mag <= {2'b00, product[59:30]};
            end
        end
    end

    // Datapath registers (no reset: loaded by every accepted start).
    always @(posedge clk) begin
        if (start && !busy_r) begin
            xr <= fold ? -xs : xs;
            yr <= fold ? -ys : ys;
            z <= fold ? 32'h8000_0000 : 32'd0;
        end else if (rot) begin
            xr <= x_next;
            yr <= y_next;
            z <= z_next;
        end
    end

endmodule
`default_nettype wire
