// hfi_diff_cic: sample differencing, envelope (sample-rate conversion R = 1/2) and one-stage CIC
// interpolation of the carrier-bottom currents, bit-true.
//
// Implements docs/spec.md section 3.9, golden model golden/fpga/diff_cic.py (DiffCic.step, cic_m;
// M_MAX = 16, D_BITS = 17, Y_BITS = 21). Xue et al. 2022, eqs. (7)-(8), Fig. 4 and Fig. 8: once per
// PWM period (in_valid, the sample at the carrier bottom), per component k in {alpha, beta}:
//   M  = clamp(cic_m) in 1..16: 0 -> 1, above 16 -> 16 (the documented safe behaviour of CIC_M, a u8
//        register); if M differs from the M in use, the delay line and the integrators are cleared and
//        M becomes the one in use (a rate change restarts the filter; p and e are kept). The M in use
//        after reset is "none" (0), so the first step always starts a cleared filter.
//   d  = i - p                (eq. (7) without its factor 1/2; s17, |d| <= 65535), p = previous sample
//   e  = d if (a previous sample exists) & plus, else e holds      (Fig. 4: envelope, s17)
//   p  = i                    (the first step after reset only fills p: e stays 0)
//   c  = e - x[M-1]           (comb, eq. (8) in the equivalent form of Fig. 8; x[0] the newest entry of
//                              the 16-entry delay line, entries not written since a clear read 0; s18)
//   x  = {e, x[0..14]}        (shift in e)
//   y  = wrap(y + c, 21)      (integrator, two's complement; q = y is the sum of the last M values of
//                              e, which lies in s21, so the wrapped output is exact)
// Outputs: q_a, q_b = y (s21), e_a, e_b = e (s17) of the last step, 0 after reset, all four updated in
// the cycle before out_valid and held until the next step's out_valid.
//
// Ports
//   in_valid           one-cycle strobe per carrier-bottom sample: i_alpha, i_beta, plus and cic_m are
//                      sampled in this cycle only (cic_m is clamped as it is sampled)
//   i_alpha, i_beta    s16 stationary-frame currents (spec 3.2)
//   plus               the period that ended at this sample ran +V_H (DiffCic.step's plus)
//   cic_m              u8 CIC_M register
//   q_a, q_b           s21 CIC outputs (gain M);  e_a, e_b  s17 held envelope
//   out_valid          one-cycle pulse exactly LATENCY (= 4) cycles after in_valid
//
// Implementation: the delay line is a circular buffer of 16 x 34 bits (both components in one word;
// written in one place, read at one address with no reset: small distributed RAM, 9 x TRELLIS_DPR16X4
// on ECP5) with a write pointer wp; x[M-1] is the word at wp - M (mod 16), written M steps ago. A clear
// does not touch the RAM: the fill count n (0..16, saturating) counts the words written since the last
// clear (or reset), and x[M-1] reads as 0 unless M <= n. The integrators are the q registers themselves.
// Timing (S = in_valid cycle), every adder between registers:
//   S:   inputs registered, M clamped;
//   S+1: d = i - p, e (hold register), p, M in use, the rate-change flag, the RAM word at wp - M and
//        its validity (M <= n, no rate change) registered;
//   S+2: comb c = e - x[M-1] registered; e written at wp, wp += 1, n updated;
//   S+3: q = (rate change ? 0 : q) + c (21-bit wrap), e_a/e_b = e;  S+4: out_valid.
// Throughput: in_valid may come every 2 cycles (minimum spacing 2: a step's first stage needs wp and n
// of the step before; the system gives a PWM period, >= 64 cycles); each step completes LATENCY
// cycles after its in_valid, in order.
// A synchronous reset aborts a step in flight (no out_valid for it), ignores an in_valid in the reset
// cycle and gives the state of DiffCic(): no previous sample, p = e = 0, delay line and integrators
// cleared (n = 0), no M in use, outputs 0.
`default_nettype none

module hfi_diff_cic (
    input  wire               clk,
    input  wire               rst,
    input  wire               in_valid,
    input  wire signed [15:0] i_alpha,
    input  wire signed [15:0] i_beta,
    input  wire               plus,
    input  wire        [7:0]  cic_m,
    output reg  signed [20:0] q_a,
    output reg  signed [20:0] q_b,
    output reg  signed [16:0] e_a,
    output reg  signed [16:0] e_b,
    output reg                out_valid
);
    /* verilator lint_off UNUSEDPARAM */  // documents the fixed pipeline below (s1, s2, s3, out_valid)
    localparam LATENCY = 4;                 // cycles from in_valid to out_valid
    /* verilator lint_on UNUSEDPARAM */
    localparam [4:0] M_MAX = 5'd16;

    // Stage flags: s1 high in S+1, s2 in S+2, s3 in S+3.
    reg               s1, s2, s3;

    // Stage S: the sampled inputs and the clamped M (1..16).
    reg signed [15:0] r_ia, r_ib;
    reg               r_plus;
    reg        [4:0]  r_m;
    wire       [4:0]  m_clamped = (cic_m == 8'd0) ? 5'd1 : (cic_m > {3'd0, M_MAX}) ? M_MAX : cic_m[4:0];

    // Step state (golden DiffCic: valid, p, e, m; the delay line and y below).
    reg               have_p;               // DiffCic.valid: a previous sample exists
    reg signed [15:0] p_a, p_b;
    reg signed [16:0] eh_a, eh_b;           // the held envelope e (updated in S+1)
    reg        [4:0]  m_use;                // the M in use, 0 after reset (none)

    // Delay line: circular buffer, word = {e_b, e_a}; wp the next word to write; n the words written
    // since the last clear, saturating at 16.
    reg        [33:0] dline [0:15];
    reg        [3:0]  wp;
    reg        [4:0]  n;

    // Stage S+1 -> S+2 / S+3.
    reg               chg1, chg2;           // the step changed M: clear the delay line / integrators
    reg        [33:0] xr;                   // the word at wp - M (x[M-1] if xv)
    reg               xv;                   // x[M-1] was written since the last clear
    reg signed [17:0] c_a, c_b;             // comb outputs (|c| <= 131070)

    // S+1: eq. (7) and the envelope.
    wire signed [16:0] d_a = {r_ia[15], r_ia} - {p_a[15], p_a};
    wire signed [16:0] d_b = {r_ib[15], r_ib} - {p_b[15], p_b};
    wire               take = have_p & r_plus;
    wire       [3:0]   ra = wp - r_m[3:0];  // wp - M mod 16 (M = 16: wp, the oldest word)

    // S+2: the comb, x[M-1] = 0 unless written since the last clear.
    wire signed [16:0] x_a = xv ? xr[16:0] : 17'sd0;
    wire signed [16:0] x_b = xv ? xr[33:17] : 17'sd0;

    // S+3: the integrators (wrapping adds of 21 bits; cleared first on a rate change).
    wire signed [20:0] y_a = chg2 ? 21'sd0 : q_a;
    wire signed [20:0] y_b = chg2 ? 21'sd0 : q_b;

    always @(posedge clk) begin
        if (s2 && !rst)
            dline[wp] <= {eh_b, eh_a};
    end

    always @(posedge clk) begin
        if (rst) begin
            s1 <= 1'b0;
            s2 <= 1'b0;
            s3 <= 1'b0;
            out_valid <= 1'b0;
            r_ia <= 16'sd0;
            r_ib <= 16'sd0;
            r_plus <= 1'b0;
            r_m <= 5'd1;
            have_p <= 1'b0;
            p_a <= 16'sd0;
            p_b <= 16'sd0;
            eh_a <= 17'sd0;
            eh_b <= 17'sd0;
            m_use <= 5'd0;
            wp <= 4'd0;
            n <= 5'd0;
            chg1 <= 1'b0;
            chg2 <= 1'b0;
            xr <= 34'd0;
            xv <= 1'b0;
            c_a <= 18'sd0;
            c_b <= 18'sd0;
            q_a <= 21'sd0;
            q_b <= 21'sd0;
            e_a <= 17'sd0;
            e_b <= 17'sd0;
        end else begin
            s1 <= in_valid;
            s2 <= s1;
            s3 <= s2;
            out_valid <= s3;

            // S: sample the inputs, clamp M.
            if (in_valid) begin
                r_ia <= i_alpha;
                r_ib <= i_beta;
                r_plus <= plus;
                r_m <= m_clamped;
            end

            // S+1: rate, difference, envelope; read x[M-1].
            if (s1) begin
                if (take) begin
                    eh_a <= d_a;
                    eh_b <= d_b;
                end
                p_a <= r_ia;
                p_b <= r_ib;
                have_p <= 1'b1;
                m_use <= r_m;
                chg1 <= (r_m != m_use);
                xv <= (r_m == m_use) && (r_m <= n);
                xr <= dline[ra];
            end

            // S+2: comb; shift e into the delay line (the RAM write above).
            if (s2) begin
                c_a <= {eh_a[16], eh_a} - {x_a[16], x_a};
                c_b <= {eh_b[16], eh_b} - {x_b[16], x_b};
                chg2 <= chg1;
                wp <= wp + 4'd1;
                n <= chg1 ? 5'd1 : (n == M_MAX) ? M_MAX : n + 5'd1;
            end

            // S+3: integrators, outputs.
            if (s3) begin
                q_a <= y_a + {{3{c_a[17]}}, c_a};
                q_b <= y_b + {{3{c_b[17]}}, c_b};
                e_a <= eh_a;
                e_b <= eh_b;
            end
        end
    end
endmodule

`default_nettype wire
