// hfi_park: Clarke then Park transform of the two sampled phase currents, bit-true.
//
// Implements docs/spec.md section 3.2, golden model golden/fpga/park.py (clarke, then park):
//   i_alpha = i_a
//   i_beta  = sat(round_shr((i_a + 2*i_b) * 18919, 15), 16)        (s18 x u15 -> s33)
//   i_d     = sat(round_shr(i_alpha*COS + i_beta*SIN, 15), 16)     (s16 x s16 -> s31, sum s33)
//   i_q     = sat(round_shr(i_beta*COS - i_alpha*SIN, 15), 16)
// i_q is the i_q^ of Benevieri et al. 2023, eq. (19) (demodulated by hfi_demodulator.v); i_d feeds
// GAMMA_D. The sums are kept in 34 bits: i_alpha*COS + i_beta*SIN reaches 2^31 (all four at -32768),
// one more than s32 holds (the spec's "sum s32" is one bit short; the golden model sums exactly).
//
// Ports
//   start             one-cycle strobe: i_a, i_b, sin_q15, cos_q15 are sampled in this cycle only
//   i_a, i_b          s16 phase currents (2^15 = I_FS)
//   sin_q15, cos_q15  s16 Q1.15 SIN, COS of the estimated angle (active registers)
//   done              one-cycle pulse exactly LATENCY (= 7) cycles after start
//   i_d, i_q          s16, both updated in the done cycle and held until the next done (0 after reset)
//   i_alpha, i_beta   s16 Clarke currents of the same transform (registers of the data path): valid in
//                     its done cycle (i_alpha from S+1, i_beta from S+3), held until the next start
//                     (i_alpha) / two cycles after it (i_beta); 0 after reset. hfi_dsp taps them for the
//                     carrier-bottom sample (hfi_diff_cic, spec 3.9).
//
// Timing (S = start cycle), one shared multiplier (s18 x s16 -> s34, one 18x18 DSP) between
// registered operands and a registered product:
//   S: inputs registered, t = i_a + 2*i_b (s18);  S+1: t*18919;  S+2: i_alpha*COS, i_beta registered;
//   S+3: i_alpha*SIN, acc_d = i_alpha*COS;  S+4: i_beta*SIN, acc_q = -i_alpha*SIN;
//   S+5: i_beta*COS, acc_d += i_beta*SIN;   S+6: outputs loaded (acc_q + i_beta*COS);  S+7: done.
// Throughput: a new start may come every 5 cycles (minimum start spacing 5; the system gives >= 40);
// overlapping transforms complete in order, each LATENCY cycles after its start.
// A synchronous reset aborts any transform in flight (no done for it) and clears the outputs.
`default_nettype none

module hfi_park (
    input  wire               clk,
    input  wire               rst,
    input  wire               start,
    input  wire signed [15:0] i_a,
    input  wire signed [15:0] i_b,
    input  wire signed [15:0] sin_q15,
    input  wire signed [15:0] cos_q15,
    output wire               done,
    output reg  signed [15:0] i_d,
    output reg  signed [15:0] i_q,
    output wire signed [15:0] i_alpha,
    output wire signed [15:0] i_beta
);
    localparam LATENCY = 7;                 // cycles from start to done (see the header)
    localparam signed [15:0] INV_SQRT3_Q15 = 16'sd18919;   // round(2^15/sqrt(3)), u15

    // Start delay line: stage[k-1] is high in cycle S+k.
    reg [LATENCY-1:0] stage;
    assign done = stage[LATENCY-1];

    // Inputs captured at start.
    reg signed [15:0] al_r;                 // i_alpha = i_a
    reg signed [15:0] sin_r, cos_r;
    reg signed [15:0] be_r;                 // i_beta (registered in S+2)
    assign i_alpha = al_r;
    assign i_beta = be_r;

    // Operands of the shared multiplier, registered: the operands used in cycle S+k are selected in
    // cycle S+k-1 (so the multiplier sits between two registers; the product schedule is unchanged).
    // The operand registers and the product register are hfi_mul18's (on ECP5 the product register is
    // the MULT18X18D's own: docs/boards.md "Timing"); m_x_n, m_y_n are the operands' next values.
    reg  signed [17:0] m_x_n;
    reg  signed [15:0] m_y_n;
    /* verilator lint_off UNUSEDSIGNAL */  // |product| < 2^31: bits 35..34 are sign copies
    wire signed [35:0] m_p;
    /* verilator lint_on UNUSEDSIGNAL */
    wire signed [33:0] prod = m_p[33:0];    // registered product
    hfi_mul18 u_mul (.clk(clk), .a(m_x_n), .b({{2{m_y_n[15]}}, m_y_n}), .p(m_p));
    // operands of the next cycle (0 under rst and between the products: the idle multiplier stays still)
    always @(*) begin
        m_x_n = 18'sd0;
        m_y_n = 16'sd0;
        if (!rst) begin
            if (start) begin                // for S+1: Clarke product (i_a + 2*i_b)*18919
                m_x_n = {{2{i_a[15]}}, i_a} + {i_b[15], i_b, 1'b0};
                m_y_n = INV_SQRT3_Q15;
            end else if (stage[0]) begin    // for S+2: i_alpha*COS
                m_x_n = {{2{al_r[15]}}, al_r};
                m_y_n = cos_r;
            end else if (stage[1]) begin    // for S+3: i_alpha*SIN
                m_x_n = {{2{al_r[15]}}, al_r};
                m_y_n = sin_r;
            end else if (stage[2]) begin    // for S+4: i_beta*SIN
                m_x_n = {{2{be_r[15]}}, be_r};
                m_y_n = sin_r;
            end else if (stage[3]) begin    // for S+5: i_beta*COS
                m_x_n = {{2{be_r[15]}}, be_r};
                m_y_n = cos_r;
            end
        end
    end

    // acc_d = i_alpha*COS + i_beta*SIN + 2^14, acc_q = i_beta*COS - i_alpha*SIN + 2^14 (the rounding
    // constant of round_shr(., 15) is added when an accumulation starts, not after its last term)
    reg signed [33:0] acc_d, acc_q;
    localparam signed [33:0] HALF_LSB = 34'sd16384;

    // Saturation to s16 of v >> 15 (v already holds the rounding constant): sat(floor(v / 2^15), 16).
    function signed [15:0] sat15;
        /* verilator lint_off UNUSEDSIGNAL */  // the 15 bits below the rounding point are dropped
        input signed [33:0] v;
        /* verilator lint_on UNUSEDSIGNAL */
        begin
            if (v[33:30] == {4{v[30]}})
                sat15 = v[30:15];
            else
                sat15 = v[33] ? 16'sh8000 : 16'sh7FFF;
        end
    endfunction

    wire signed [33:0] be_rnd = prod + HALF_LSB;     // in S+2: (i_a + 2 i_b)*18919 + 2^14
    wire signed [33:0] q_sum  = acc_q + prod;        // in S+6: i_beta*COS - i_alpha*SIN + 2^14
    wire signed [33:0] d_fin  = acc_d;

    always @(posedge clk) begin
        if (rst) begin
            stage <= {LATENCY{1'b0}};
            al_r <= 16'sd0;
            sin_r <= 16'sd0;
            cos_r <= 16'sd0;
            be_r <= 16'sd0;
            acc_d <= 34'sd0;
            acc_q <= 34'sd0;
            i_d <= 16'sd0;
            i_q <= 16'sd0;
        end else begin
            stage <= {stage[LATENCY-2:0], start};
            if (start) begin
                al_r <= i_a;
                sin_r <= sin_q15;
                cos_r <= cos_q15;
            end
            if (stage[1])                   // prod = (i_a + 2 i_b)*18919
                be_r <= sat15(be_rnd);
            if (stage[2])                   // prod = i_alpha*COS
                acc_d <= prod + HALF_LSB;
            if (stage[3])                   // prod = i_alpha*SIN
                acc_q <= HALF_LSB - prod;
            if (stage[4])                   // prod = i_beta*SIN
                acc_d <= acc_d + prod;
            if (stage[5]) begin             // prod = i_beta*COS
                i_d <= sat15(d_fin);
                i_q <= sat15(q_sum);
            end
        end
    end
endmodule

`default_nettype wire
