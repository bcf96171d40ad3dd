// hfi_adc_scale: ADC offset and gain of the two phase-current channels (a, b), bit-true.
//
// Implements docs/spec.md section 3.1, golden model golden/fpga/adc_scale.py (adc_to_current):
//   x = (code - 2^(B-1)) * 2^(16-B)                        (offset binary -> left-aligned s16)
//   i = sat(round_shr((x - ADC_OFFSET) * ADC_GAIN, 14), 16) (s17 x u16 -> s33, then s16)
// The two channels are the two phase-current sensors of Benevieri et al. 2023 (the paper's two LEMs);
// i_c = -i_a - i_b is formed only by the overcurrent check (hfi_overcurrent.v).
//
// Ports
//   ADC_BITS            parameter, ADC resolution B, 1..16 (default 12)
//   start               one-cycle strobe: code_*, offset_*, gain_* are sampled in this cycle only
//   code_a, code_b      uB, offset binary (mid-scale 2^(B-1) = 0 A)
//   offset_a, offset_b  s16, ADC_OFFSET registers (current LSB, subtracted after left alignment)
//   gain_a, gain_b      u16 Q2.14, ADC_GAIN registers (16384 = 1.0)
//   done                one-cycle pulse exactly LATENCY (= 4) cycles after start
//   i_a, i_b            s16 phase currents (2^15 = I_FS); both updated in the done cycle and held
//                       until the next done (0 after reset)
//
// Timing (S = start cycle): S: x - offset of both channels registered (s17) with the gains (channel
// a into the multiplier's operand registers);
// S+1: product a; S+2: product b, result a rounded/saturated; S+3: outputs loaded; S+4: done.
// One multiplier (s17 x s17 -> s34, i.e. one 18x18 DSP) shared by the two channels.
// Throughput: a new start may come every 2 cycles (minimum start spacing 2; the system gives >= 40);
// results of overlapping conversions still appear in order, each LATENCY cycles after its start.
// A synchronous reset aborts any conversion in flight (no done for it) and clears the outputs.
`default_nettype none

module hfi_adc_scale #(
    parameter ADC_BITS = 12
) (
    input  wire                     clk,
    input  wire                     rst,
    input  wire                     start,
    input  wire [ADC_BITS-1:0]      code_a,
    input  wire [ADC_BITS-1:0]      code_b,
    input  wire signed [15:0]       offset_a,
    input  wire signed [15:0]       offset_b,
    input  wire [15:0]              gain_a,
    input  wire [15:0]              gain_b,
    output wire                     done,
    output reg  signed [15:0]       i_a,
    output reg  signed [15:0]       i_b
);
    localparam LATENCY = 4;     // cycles from start to done (see the header)

    // Offset binary -> two's complement: invert the MSB (code - 2^(B-1)), then left-align to 16 bits.
    localparam [ADC_BITS-1:0] MSB_MASK = ~({ADC_BITS{1'b1}} >> 1);
    wire [ADC_BITS-1:0] tc_a = code_a ^ MSB_MASK;
    wire [ADC_BITS-1:0] tc_b = code_b ^ MSB_MASK;
    /* verilator lint_off UNUSEDSIGNAL */  // the low ADC_BITS bits of the padding are never used
    wire [ADC_BITS+15:0] ext_a = {tc_a, 16'd0};
    wire [ADC_BITS+15:0] ext_b = {tc_b, 16'd0};
    /* verilator lint_on UNUSEDSIGNAL */
    wire signed [15:0] x_a = ext_a[ADC_BITS+15:ADC_BITS];    // (code - 2^(B-1)) * 2^(16-B), s16
    wire signed [15:0] x_b = ext_b[ADC_BITS+15:ADC_BITS];

    // Stage 0 (start cycle): d = x - ADC_OFFSET (s17); channel a goes straight into the multiplier's
    // operand registers, channel b (with its gain) waits one cycle in d_b, g_b.
    reg signed [16:0] d_b;
    reg        [15:0] g_b;
    // Start delay line: stage[0] = product a cycle, [1] = product b cycle, [2] = output load cycle,
    // [LATENCY-1] = done.
    reg [LATENCY-1:0] stage;
    wire s1 = stage[0];
    wire s2 = stage[1];
    wire s3 = stage[2];
    assign done = stage[LATENCY-1];

    // The shared multiplier: s17 x s17 (gain zero-extended) -> s34 (|product| < 2^32), between
    // registered operands (loaded in S for product a, in S+1 for product b) and prod: hfi_mul18's
    // registers (on ECP5 the product register is the MULT18X18D's own: docs/boards.md "Timing");
    // m_d_n, m_g_n are the operands' next values (0 under rst and between the products).
    reg  signed [16:0] m_d_n;
    reg        [15:0] m_g_n;
    always @(*) begin
        m_d_n = 17'sd0;
        m_g_n = 16'd0;
        if (!rst) begin
            if (start) begin
                m_d_n = {x_a[15], x_a} - {offset_a[15], offset_a};   // product a in S+1
                m_g_n = gain_a;
            end else if (s1) begin
                m_d_n = d_b;                                        // product b in S+2
                m_g_n = g_b;
            end
        end
    end
    /* verilator lint_off UNUSEDSIGNAL */  // |product| < 2^32: bits 35..34 are sign copies
    wire signed [35:0] m_p;
    /* verilator lint_on UNUSEDSIGNAL */
    hfi_mul18 u_mul (.clk(clk), .a({m_d_n[16], m_d_n}), .b({2'b00, m_g_n}), .p(m_p));
    wire signed [33:0] prod = m_p[33:0];

    // round_shr(prod, 14) then sat to s16.
    /* verilator lint_off UNUSEDSIGNAL */  // the 14 fraction bits below the rounding point are dropped
    wire signed [33:0] rnd = prod + 34'sd8192;
    /* verilator lint_on UNUSEDSIGNAL */
    // rnd[33:14] fits in s16 iff its bits 19..15 (rnd[33:29]) are all equal
    wire signed [15:0] scaled = (rnd[33:29] == {5{rnd[29]}}) ? rnd[29:14] :
                                (rnd[33] ? 16'sh8000 : 16'sh7FFF);
    reg  signed [15:0] res_a;   // channel a result, waiting for channel b

    always @(posedge clk) begin
        if (rst) begin
            stage <= {LATENCY{1'b0}};
            i_a <= 16'sd0;
            i_b <= 16'sd0;
            d_b <= 17'sd0;
            g_b <= 16'd0;
            res_a <= 16'sd0;
        end else begin
            stage <= {stage[LATENCY-2:0], start};
            if (start) begin
                d_b <= {x_b[15], x_b} - {offset_b[15], offset_b};
                g_b <= gain_b;
            end
            if (s2)
                res_a <= scaled;
            if (s3) begin
                i_a <= res_a;
                i_b <= scaled;
            end
        end
    end
endmodule

`default_nettype wire
