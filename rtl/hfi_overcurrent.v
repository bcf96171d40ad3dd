// hfi_overcurrent: hardware overcurrent comparator, |i_a|, |i_b| or |i_c| > OC_LIMIT.
//
// Implements docs/spec.md section 3.7 (no golden module: the golden closed loop models the firmware's
// software limit; the cocotb testbench holds the reference function). Two phase currents are sensed
// (Benevieri et al. 2023, two LEMs); the third is i_c = -i_a - i_b.
//
// Ports
//   valid         one-cycle strobe: i_a, i_b are a processed sample (hfi_adc_scale output)
//   i_a, i_b      s16 phase currents (2^15 = I_FS)
//   limit         u16 OC_LIMIT register (current LSB), compared as an unsigned value
//   trip          registered one-cycle pulse in the cycle after a valid sample with
//                 |i_a| > limit or |i_b| > limit or |i_c| > limit (the fault latch is elsewhere)
//
// Widths: i_c = -i_a - i_b lies in -65534..65536. Spec 3.1 calls it s17; 65536 (i_a = i_b = -32768)
// is not an s17 value (it would wrap to -65536, whose magnitude is the same, so an s17 i_c works only
// if the magnitude is taken in 18 bits). Here the sum and the +-limit comparisons are exact in s18
// (|i_a|, |i_b| <= 32768, |i_c| <= 65536) and compared with the zero-extended u16 limit, so
// |-32768| = 32768 trips for any limit <= 32767 and only i_c can exceed a limit >= 32768
// (65536 > 65535 trips even at the largest limit).
// Latency 1 (trip in the cycle after valid); throughput one sample per cycle. No multiplier.
`default_nettype none

module hfi_overcurrent (
    input  wire               clk,
    input  wire               rst,
    input  wire               valid,
    input  wire signed [15:0] i_a,
    input  wire signed [15:0] i_b,
    input  wire        [15:0] limit,
    output reg                trip
);
    wire signed [17:0] a = {{2{i_a[15]}}, i_a};
    wire signed [17:0] b = {{2{i_b[15]}}, i_b};
    wire signed [17:0] lim     = $signed({2'b00, limit});
    wire signed [17:0] neg_lim = -lim;                   // -65535..0

    // |x| > L  <=>  x > L or x < -L; for i_c = -(i_a + i_b) the same test on s = i_a + i_b, whose two
    // compares are single three-operand sums (one carry-save level, one carry chain: timing):
    //   s > L  <=> a + b - L - 1 >= 0 <=> a + b + ~L >= 0;   s < -L <=> a + b + L < 0
    // in 19 bits (-65536 - 65535 .. 65534 + 65535 fits), no absolute values.
    wire [18:0] a19 = {{3{i_a[15]}}, i_a};
    wire [18:0] b19 = {{3{i_b[15]}}, i_b};
    wire [18:0] l19 = {3'b000, limit};
    wire [18:0] nl19 = ~l19;
    wire [18:0] hs_s = a19 ^ b19 ^ nl19;
    wire [18:0] hs_c = {(a19[17:0] & b19[17:0]) | (a19[17:0] & nl19[17:0]) | (b19[17:0] & nl19[17:0]), 1'b0};
    wire [18:0] ls_s = a19 ^ b19 ^ l19;
    wire [18:0] ls_c = {(a19[17:0] & b19[17:0]) | (a19[17:0] & l19[17:0]) | (b19[17:0] & l19[17:0]), 1'b0};
    /* verilator lint_off UNUSEDSIGNAL */                // only the signs are used
    wire [18:0] hs_t = hs_s + hs_c;                      // a + b - L - 1 (mod 2^19)
    wire [18:0] ls_t = ls_s + ls_c;                      // a + b + L
    /* verilator lint_on UNUSEDSIGNAL */
    wire over = (a > lim) | (a < neg_lim) | (b > lim) | (b < neg_lim) | !hs_t[18] | ls_t[18];

    always @(posedge clk) begin
        if (rst)
            trip <= 1'b0;
        else
            trip <= valid & over;
    end
endmodule

`default_nettype wire
