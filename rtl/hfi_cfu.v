`default_nettype none
// hfi_cfu: the fixed-point instructions of the soft core (hfi/cfu.py gives each one's arithmetic; docs/soc.md,
// "The fixed-point instructions"). A 64-bit accumulator behind LiteX's CFU port of the VexRiscv
// (GenCoreDefault --cfu true: custom-0 R-type instructions, function_id = {funct7, funct3}, inputs rs1 and
// rs2, one 32-bit answer to rd, a valid/ready handshake each way), in the CPU clock:
//   funct3 MUL/MAC/MSU  acc = / += / -= (rs1 * rs2) >>> kb      (signed 32 x 32 -> 64)
//          ADD          acc += (rs1 <<< kb) + rs2
//          SET          acc = {rs1, rs2}
//          RND / FLR    answer sat(round_shr(acc, k), rs1[5:0]) / sat(acc >>> k, rs1[5:0])
// with k = funct7[5:0] and kb = k rounded down to a multiple of 8 (a byte shift: one level of multiplexers beside
// the accumulator's adder); saturation width 1..32, 0 and 33..63 answer the low word unsaturated; funct3 7 is
// reserved: it answers 0 and leaves acc. Every instruction is answered, in order: MUL..SET in the clock after the
// command (the CPU's memory stage, so they issue one per clock), RND/FLR four clocks after it (three stall clocks).
// Pipeline, one heavy element per stage (the CPU clock closes with its margin on the ECP5: docs/soc.md):
//   1 operands; 2 the product (or the ADD/SET value; for RND/FLR the rounding constant and the saturation's
//   bound); 3 acc updated by the byte-shifted product, or for RND/FLR acc plus the rounding constant, shifted by
//   the whole bytes of k (acc then holds every older instruction); 4 RND/FLR: the rest of the shift (k mod 8)
//   and the saturation, the answer.
// No command is taken while an RND/FLR is in flight or an answer waits for the CPU, so answers stay in order.
module hfi_cfu (
    input  wire        clk,
    input  wire        rst,
    input  wire        cmd_valid,
    output wire        cmd_ready,
    /* verilator lint_off UNUSEDSIGNAL */
    input  wire [9:0]  cmd_function_id,            // {funct7, funct3}; funct7[6] is ignored (k = funct7[5:0])
    /* verilator lint_on UNUSEDSIGNAL */
    input  wire [31:0] cmd_inputs_0,
    input  wire [31:0] cmd_inputs_1,
    output reg         rsp_valid,
    input  wire        rsp_ready,
    output reg  [31:0] rsp_outputs_0
);
`include "hfi_soc_platform.vh"

    wire [2:0] op = cmd_function_id[2:0];
    wire [5:0] k = cmd_function_id[8:3];
    wire is_read = op == `HFI_CFU_RND || op == `HFI_CFU_FLR;
    reg rd_busy;                                       // an RND/FLR from its command until its answer is taken
    reg rsp_is_read;                                   // the answer waiting is an RND/FLR's
    assign cmd_ready = !rd_busy && !(rsp_valid && !rsp_ready);
    wire fire = cmd_valid && cmd_ready;

    // ---------------------------------------------------------------- stage 1: operands
    reg               s1_v;
    reg  [2:0]        s1_op;
    reg  [5:0]        s1_k;
    reg  signed [31:0] s1_a, s1_b;
    wire signed [63:0] s1_prod = s1_a * s1_b;
    wire        [5:0]  s1_w = s1_a[5:0];                       // RND/FLR: the saturation width
    wire               s1_rnd = s1_op == `HFI_CFU_RND && s1_k != 6'd0;

    // ---------------------------------------------------------------- stage 2: product, or the read's constants
    reg               s2_v;
    reg  [2:0]        s2_op;
    reg  [5:0]        s2_k;
    reg  signed [63:0] s2_val;                                 // the product, rs1 (ADD) or {rs1, rs2} (SET)
    reg  signed [31:0] s2_b;                                   // ADD: rs2
    reg  signed [63:0] s2_rc, s2_hi;                           // RND/FLR: rounding constant, upper bound
    reg               s2_sat;                                  // RND/FLR: the width is 1..32
    wire        [5:0]  kb = {s2_k[5:3], 3'b000};
    wire signed [63:0] s2_shr = s2_val >>> kb;                 // byte shifts: 8 inputs per bit
    wire signed [63:0] s2_add = (s2_val <<< kb) + $signed({{32{s2_b[31]}}, s2_b});
    wire              s2_read = s2_op == `HFI_CFU_RND || s2_op == `HFI_CFU_FLR;

    // ---------------------------------------------------------------- stage 3: acc, or the read's sum
    reg  signed [63:0] acc;
    reg               s3_v;                                    // an RND/FLR in stage 4
    reg  [2:0]        s3_k;                                    // k mod 8: the rest of the read's shift
    reg  signed [63:0] s3_sum, s3_hi;                          // (acc + rounding constant) >>> (k - k mod 8)
    reg               s3_sat;

    // ---------------------------------------------------------------- stage 4: the answer
    wire signed [63:0] value = s3_sum >>> s3_k;
    wire signed [63:0] lo = -s3_hi - 64'sd1;
    wire [31:0] answer = !s3_sat ? value[31:0] : value > s3_hi ? s3_hi[31:0] : value < lo ? lo[31:0] : value[31:0];

    always @(posedge clk) begin
        if (rst) begin
            s1_v <= 1'b0;
            s2_v <= 1'b0;
            s3_v <= 1'b0;
            acc <= 64'sd0;
            rd_busy <= 1'b0;
            rsp_valid <= 1'b0;
            rsp_is_read <= 1'b0;
            rsp_outputs_0 <= 32'd0;
        end else begin
            s1_v <= fire;
            if (fire) begin
                s1_op <= op;
                s1_k <= k;
                s1_a <= cmd_inputs_0;
                s1_b <= cmd_inputs_1;
            end
            s2_v <= s1_v;
            if (s1_v) begin
                s2_op <= s1_op;
                s2_k <= s1_k;
                case (s1_op)
                    `HFI_CFU_ADD: s2_val <= {{32{s1_a[31]}}, s1_a};
                    `HFI_CFU_SET: s2_val <= {s1_a, s1_b};
                    default: s2_val <= s1_prod;
                endcase
                s2_b <= s1_b;
                s2_rc <= s1_rnd ? 64'sd1 <<< (s1_k - 6'd1) : 64'sd0;
                s2_hi <= (64'sd1 <<< (s1_w - 6'd1)) - 64'sd1;
                s2_sat <= s1_w != 6'd0 && s1_w <= 6'd32;
            end
            s3_v <= s2_v && s2_read;
            if (s2_v) begin
                case (s2_op)
                    `HFI_CFU_MUL: acc <= s2_shr;
                    `HFI_CFU_MAC: acc <= acc + s2_shr;
                    `HFI_CFU_MSU: acc <= acc - s2_shr;
                    `HFI_CFU_ADD: acc <= acc + s2_add;
                    `HFI_CFU_SET: acc <= s2_val;
                    default: ;
                endcase
                s3_k <= s2_k[2:0];
                s3_sum <= (acc + s2_rc) >>> kb;
                s3_hi <= s2_hi;
                s3_sat <= s2_sat;
            end
            // answers: at most one is made per clock (a command is not taken while an RND/FLR is in flight)
            if (rsp_valid && rsp_ready) begin
                rsp_valid <= 1'b0;
                if (rsp_is_read)
                    rd_busy <= 1'b0;
            end
            if (fire && is_read)
                rd_busy <= 1'b1;
            if (fire && !is_read) begin
                rsp_valid <= 1'b1;
                rsp_is_read <= 1'b0;
                rsp_outputs_0 <= 32'd0;
            end
            if (s3_v) begin
                rsp_valid <= 1'b1;
                rsp_is_read <= 1'b1;
                rsp_outputs_0 <= answer;
            end
        end
    end
endmodule
`default_nettype wire
