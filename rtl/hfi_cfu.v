`default_nettype none
// hfi_cfu: the fixed-point instructions of the soft core (hfi/cfu.py gives each one's arithmetic; docs/soc.md,
// "The fixed-point instructions"). A 64-bit accumulator behind LiteX's CFU port of the VexRiscv
// (GenCoreDefault --cfu true: custom-0 R-type instructions, function_id = {funct7, funct3}, inputs rs1 and
// rs2, one 32-bit answer to rd, a valid/ready handshake each way), in the CPU clock:
//   funct3 MUL/MAC/MSU  acc = / += / -= (rs1 * rs2) >>> k      (signed 32 x 32 -> 64, k = funct7[5:0])
//          ADD          acc += (rs1 <<< k) + rs2
//          SET          acc = {rs1, rs2}
//          RND / FLR    answer sat(round_shr(acc, k), rs1[5:0]) / sat(acc >>> k, rs1[5:0])
// (saturation width 1..32; 0 and 33..63 answer the low word unsaturated); funct3 7 is reserved: it answers 0
// and leaves acc. Every instruction is answered: MUL..SET in the clock after the command (the CPU's memory
// stage, so they issue one per clock), RND/FLR three clocks after it (two stall clocks), in order.
// Pipeline: stage 1 holds the operands and forms the product (or the ADD/SET value); stage 2 shifts it and
// updates acc, or, for RND/FLR, forms the answer from acc, which then holds every older instruction. No
// command is taken while an RND/FLR is in flight or an answer waits for the CPU, so answers stay in order.
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
    wire signed [63:0] s1_add = ($signed({{32{s1_a[31]}}, s1_a}) <<< s1_k) + $signed({{32{s1_b[31]}}, s1_b});
    wire        [63:0] s1_set = {s1_a, s1_b};

    // ---------------------------------------------------------------- stage 2: shift and accumulate, or answer
    reg               s2_v;
    reg  [2:0]        s2_op;
    reg  [5:0]        s2_k;
    reg  signed [63:0] s2_val;                         // the product, the ADD/SET value, or rs1 of an RND/FLR
    reg  signed [63:0] acc;
    wire signed [63:0] s2_shifted = s2_val >>> s2_k;
    wire signed [63:0] rounded = s2_k == 6'd0 ? acc : ((acc + (64'sd1 <<< (s2_k - 6'd1))) >>> s2_k);
    wire signed [63:0] value = s2_op == `HFI_CFU_RND ? rounded : (acc >>> s2_k);
    wire        [5:0]  width = s2_val[5:0];
    wire signed [63:0] hi = (64'sd1 <<< (width - 6'd1)) - 64'sd1;
    wire signed [63:0] lo = -hi - 64'sd1;
    wire saturating = width != 6'd0 && width <= 6'd32;
    wire [31:0] answer = !saturating ? value[31:0] : value > hi ? hi[31:0] : value < lo ? lo[31:0] : value[31:0];

    always @(posedge clk) begin
        if (rst) begin
            s1_v <= 1'b0;
            s2_v <= 1'b0;
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
                    `HFI_CFU_ADD: s2_val <= s1_add;
                    `HFI_CFU_SET: s2_val <= s1_set;
                    `HFI_CFU_RND, `HFI_CFU_FLR: s2_val <= {{32{s1_a[31]}}, s1_a};
                    default: s2_val <= s1_prod;
                endcase
            end
            if (s2_v) begin
                case (s2_op)
                    `HFI_CFU_MUL: acc <= s2_shifted;
                    `HFI_CFU_MAC: acc <= acc + s2_shifted;
                    `HFI_CFU_MSU: acc <= acc - s2_shifted;
                    `HFI_CFU_ADD: acc <= acc + s2_val;
                    `HFI_CFU_SET: acc <= s2_val;
                    default: ;
                endcase
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
            if (s2_v && (s2_op == `HFI_CFU_RND || s2_op == `HFI_CFU_FLR)) begin
                rsp_valid <= 1'b1;
                rsp_is_read <= 1'b1;
                rsp_outputs_0 <= answer;
            end
        end
    end
endmodule
`default_nettype wire
