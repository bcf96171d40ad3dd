`default_nettype none
// hfi_cfu: the fixed-point instructions of the soft core (hfi/cfu.py gives each one's arithmetic; docs/soc.md,
// "The fixed-point instructions"). A 64-bit accumulator behind LiteX's CFU port of the VexRiscv
// (GenCoreDefault --cfu true: custom-0 R-type instructions, function_id = {funct7, funct3}, inputs rs1 and
// rs2, one 32-bit answer to rd, a valid/ready handshake each way), in the CPU clock:
//   funct3 MUL/MAC/MSU  acc = / += / -= (rs1 * rs2) >>> kb      (signed 32 x 32 -> 64)
//          ADD          acc += (rs1 <<< kb) + rs2
//          SET          acc = {rs1, rs2}
//          RND / FLR    answer sat(round_shr(acc, k), rs1[5:0]) / sat(acc >>> k, rs1[5:0])
//          DIV          answer sat(trunc(acc / {rs1, rs2}), w), w = k clamped to 2..32 (a zero divisor: the limit
//                       of acc's sign); acc is kept
// with k = funct7[5:0] and kb = k rounded down to a multiple of 8 (a byte shift: one level of multiplexers beside
// the accumulator's adder); saturation width 1..32, 0 and 33..63 answer the low word unsaturated. Every
// instruction is answered, in order: MUL..SET in the clock after the command (the CPU's memory stage, so they
// issue one per clock), RND/FLR three clocks after it (two stall clocks), DIV five clocks after it when the
// quotient saturates, else 5 + w (a restoring division, one quotient bit per clock).
// Accumulating instructions, one heavy element per stage (the CPU clock closes with its margin on the ECP5:
// docs/soc.md): 1 operands; 2 the product (or the ADD value (rs1 <<< kb) + rs2, or SET's); 3 acc updated by the
// byte-shifted product or the value. A read skips the product: its command loads its own registers (the rounding
// constant from k, the width), and in the next clock the read's sum is formed from what acc becomes in that clock
// (the instruction in stage 2 forwarded: acc, the stage's value and the rounding constant in one carry-save add
// and one carry chain), shifted by the whole bytes of k; then the rest of the shift (k mod 8) and the saturation,
// the answer. An instruction in stage 1 when a read is taken is in stage 2 in the read's first clock, so the sum
// holds every older instruction. A DIV is taken as a read with k = 0 (its sum is acc itself), and the divider
// (below) takes that sum: |n| and |d|, then |d| 2^(w-1) (the one variable shift), then w compare-and-subtract
// steps, one per clock (the first one found: the saturation, answered at once), then the sign.
// No command is taken while an RND/FLR/DIV is in flight or an answer waits for the CPU, so answers stay in order.
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
    wire is_div = op == `HFI_CFU_DIV;
    wire is_read = op == `HFI_CFU_RND || op == `HFI_CFU_FLR || is_div;   // answers a value, after stall clocks
    reg rd_busy;                                       // an RND/FLR/DIV from its command until its answer is taken
    reg rsp_is_read;                                   // the answer waiting is an RND/FLR/DIV's
    assign cmd_ready = !rd_busy && !(rsp_valid && !rsp_ready);
    wire fire = cmd_valid && cmd_ready;

    reg  signed [63:0] acc;

    // ---------------------------------------------------------------- stage 1: operands (accumulating only)
    reg               s1_v;
    reg  [2:0]        s1_op;
    reg  [5:3]        s1_k;                                    // the whole bytes of k
    reg  signed [31:0] s1_a, s1_b;
    wire signed [63:0] s1_prod = s1_a * s1_b;
    wire        [5:0]  s1_kb = {s1_k, 3'b000};

    // ---------------------------------------------------------------- stage 2: product, or the value
    reg               s2_v;
    reg  [2:0]        s2_op;
    reg  [5:3]        s2_k;                                    // the whole bytes of k
    reg  signed [63:0] s2_val;                                 // the product, (rs1 <<< kb) + rs2 (ADD), {rs1, rs2} (SET)
    wire        [5:0]  kb = {s2_k, 3'b000};
    wire signed [63:0] s2_shr = s2_val >>> kb;                 // byte shifts: 8 inputs per bit
    // what acc becomes in this clock, as acc_next (one adder per operation, then a multiplexer) and, for a read's
    // sum, as x + y + neg: x acc or 0 (MUL, SET), y what is added (MSU: its one's complement, and neg the one)
    reg  signed [63:0] acc_next;
    always @(*) begin
        acc_next = acc;
        if (s2_v)
            case (s2_op)
                `HFI_CFU_MUL: acc_next = s2_shr;
                `HFI_CFU_MAC: acc_next = acc + s2_shr;
                `HFI_CFU_MSU: acc_next = acc - s2_shr;
                `HFI_CFU_ADD: acc_next = acc + s2_val;
                `HFI_CFU_SET: acc_next = s2_val;
                default: ;
            endcase
    end
    wire replace = s2_v && (s2_op == `HFI_CFU_MUL || s2_op == `HFI_CFU_SET);
    wire signed [63:0] x = replace ? 64'sd0 : acc;
    wire signed [63:0] y = !s2_v ? 64'sd0 :
                           s2_op == `HFI_CFU_MUL || s2_op == `HFI_CFU_MAC ? s2_shr :
                           s2_op == `HFI_CFU_MSU ? ~s2_shr :
                           s2_op == `HFI_CFU_ADD || s2_op == `HFI_CFU_SET ? s2_val : 64'sd0;
    wire              neg = s2_v && s2_op == `HFI_CFU_MSU;

    // ---------------------------------------------------------------- a read: its registers, its sum
    reg               r_v;                                     // a read taken in the last clock
    reg               r_div;                                   // and it is a DIV
    reg  [5:0]        r_k, r_w;
    reg  signed [63:0] r_rc;                                   // the rounding constant (0 for FLR, k = 0)
    // acc_next + r_rc as one carry-save layer and one carry chain (neg enters the free carry bit 0)
    wire        [63:0] cs_s = x ^ y ^ r_rc;
    wire        [63:0] cs_c = {(x[62:0] & y[62:0]) | (x[62:0] & r_rc[62:0]) | (y[62:0] & r_rc[62:0]), neg};
    wire signed [63:0] r_sum = $signed(cs_s + cs_c);
    wire        [5:0]  r_kb = {r_k[5:3], 3'b000};

    // ---------------------------------------------------------------- stage 3: acc; the read's answer
    reg               s3_v;                                    // an RND/FLR/DIV's sum in stage 3
    reg               s3_div;                                  // a DIV's (its dividend: not answered here)
    reg  [2:0]        s3_k;                                    // k mod 8: the rest of the read's shift
    reg  signed [63:0] s3_sum, s3_hi;                          // (acc + rounding constant) >>> (k - k mod 8)
    reg               s3_sat;
    wire signed [63:0] value = s3_sum >>> s3_k;
    wire signed [63:0] lo = -s3_hi - 64'sd1;
    wire [31:0] answer = !s3_sat ? value[31:0] : value > s3_hi ? s3_hi[31:0] : value < lo ? lo[31:0] : value[31:0];

    // ---------------------------------------------------------------- DIV: a restoring division
    // Quotient bits from j = w-1 down to 0, each a compare of the remainder with |d| 2^j (dv_bs, shifted right by one
    // per clock): a bit at j = w-1 means |quotient| >= 2^(w-1), the saturation, answered at once.
    localparam [1:0] DV_IDLE = 2'd0, DV_SHIFT = 2'd1, DV_STEP = 2'd2, DV_SIGN = 2'd3;
    reg  [1:0]        dv_st;                                   // SHIFT: |n|, |d| ready; STEP: a compare per clock
    reg               dv_first;                                // the compare at j = w-1 (the saturation's)
    reg  [63:0]       dv_d;                                    // the divisor {rs1, rs2}, from the command
    reg  [5:0]        dv_w;                                    // the width, 2..32
    reg  [63:0]       dv_a, dv_b;                              // |n| (then the remainder), |d| (unsigned: 2^63 fits)
    reg  [94:0]       dv_bs;                                   // |d| 2^j
    reg               dv_neg;                                  // the quotient's sign
    reg  [31:0]       dv_q;
    reg  [31:0]       dv_satv;                                 // the saturated answer, -2^(w-1) or 2^(w-1) - 1
    reg  [4:0]        dv_n;                                    // compares left after this one
    wire [64:0]       dv_diff = {1'b0, dv_a} - {1'b0, dv_bs[63:0]};
    wire              dv_ge = dv_bs[94:64] == 31'd0 && !dv_diff[64];
    wire [5:0]        k_w = k < 6'd2 ? 6'd2 : k > 6'd32 ? 6'd32 : k;
    wire [5:0]        dv_w1 = dv_w - 6'd1;

    always @(posedge clk) begin
        if (rst) begin
            s1_v <= 1'b0;
            s2_v <= 1'b0;
            r_v <= 1'b0;
            s3_v <= 1'b0;
            acc <= 64'sd0;
            rd_busy <= 1'b0;
            rsp_valid <= 1'b0;
            rsp_is_read <= 1'b0;
            rsp_outputs_0 <= 32'd0;
            dv_st <= DV_IDLE;
        end else begin
            s1_v <= fire && !is_read;
            if (fire && !is_read) begin
                s1_op <= op;
                s1_k <= k[5:3];
                s1_a <= cmd_inputs_0;
                s1_b <= cmd_inputs_1;
            end
            r_v <= fire && is_read;
            r_div <= fire && is_div;
            if (fire && is_read) begin
                r_k <= is_div ? 6'd0 : k;
                r_w <= cmd_inputs_0[5:0];
                r_rc <= op == `HFI_CFU_RND && k != 6'd0 ? 64'sd1 <<< (k - 6'd1) : 64'sd0;
            end
            if (fire && is_div) begin
                dv_d <= {cmd_inputs_0, cmd_inputs_1};
                dv_w <= k_w;
            end
            s2_v <= s1_v;
            if (s1_v) begin
                s2_op <= s1_op;
                s2_k <= s1_k;
                case (s1_op)
                    `HFI_CFU_ADD: s2_val <= ({{32{s1_a[31]}}, s1_a} <<< s1_kb) + {{32{s1_b[31]}}, s1_b};
                    `HFI_CFU_SET: s2_val <= {s1_a, s1_b};
                    default: s2_val <= s1_prod;
                endcase
            end
            acc <= acc_next;
            s3_v <= r_v;
            s3_div <= r_div;
            if (r_v) begin
                s3_k <= r_k[2:0];
                s3_sum <= r_sum >>> r_kb;
                s3_hi <= (64'sd1 <<< (r_w - 6'd1)) - 64'sd1;
                s3_sat <= r_w != 6'd0 && r_w <= 6'd32;
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
            if (s3_v && !s3_div) begin
                rsp_valid <= 1'b1;
                rsp_is_read <= 1'b1;
                rsp_outputs_0 <= answer;
            end
            // the divider (a DIV's sum in stage 3 starts it; one command in flight at a time)
            case (dv_st)
                DV_SHIFT: begin
                    dv_bs <= {31'd0, dv_b} << dv_w1;
                    dv_satv <= dv_neg ? 32'd0 - (32'd1 << dv_w1) : (32'd1 << dv_w1) - 32'd1;
                    dv_q <= 32'd0;
                    dv_n <= dv_w1[4:0];
                    dv_first <= 1'b1;
                    dv_st <= DV_STEP;
                end
                DV_STEP: begin
                    dv_first <= 1'b0;
                    if (dv_first && dv_ge) begin                // |quotient| >= 2^(w-1): saturated
                        rsp_valid <= 1'b1;
                        rsp_is_read <= 1'b1;
                        rsp_outputs_0 <= dv_satv;
                        dv_st <= DV_IDLE;
                    end else begin
                        if (dv_ge)
                            dv_a <= dv_diff[63:0];
                        dv_q <= {dv_q[30:0], dv_ge};
                        dv_bs <= dv_bs >> 1;
                        dv_n <= dv_n - 5'd1;
                        if (dv_n == 5'd0)
                            dv_st <= DV_SIGN;
                    end
                end
                DV_SIGN: begin
                    rsp_valid <= 1'b1;
                    rsp_is_read <= 1'b1;
                    rsp_outputs_0 <= dv_neg ? 32'd0 - dv_q : dv_q;
                    dv_st <= DV_IDLE;
                end
                default: ;
            endcase
            if (s3_v && s3_div) begin
                dv_a <= s3_sum[63] ? 64'd0 - s3_sum : s3_sum;
                dv_b <= dv_d[63] ? 64'd0 - dv_d : dv_d;
                dv_neg <= s3_sum[63] ^ dv_d[63];
                dv_st <= DV_SHIFT;
            end
        end
    end
endmodule
`default_nettype wire
