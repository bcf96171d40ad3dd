// hfi_demodulator: eps integrator and window sums with the window-boundary sample-and-hold.
//
// Implements docs/spec.md section 3.4, golden model golden/fpga/demodulator.py (demodulate and
// latch_window). Benevieri et al. 2023, Sec. II-B, eq. (19): eps = i_q^ * sin(-cw*pi/2), gamma = sum of
// eps over one period (the integrator reset on the carrier rising zero crossing).
//
// Per accepted sample (valid & keep):  acc_q += i_q*w, acc_d += i_d*w (s48), sum_d += i_d,
//   sum_q += i_q, wsum += w (s33), n += 1 (u16, saturating at 65535; the sums go on).
// A sample with valid & ~keep (blanked) is ignored.
// latch (one-cycle strobe) ends the window; the outputs become
//   gamma   = sat(shr(acc_q, 15), 32)    gamma_d = sat(shr(acc_d, 15), 32)
//   sum_id  = sat(sum_d, 32)   sum_iq = sat(sum_q, 32)   wsum = sat(wsum, 32)   n_samples = n
// of the samples whose valid came BEFORE the latch cycle, and the accumulators restart. A sample whose
// valid is in the latch cycle is the first sample of the new window.
//
// Ports
//   valid, keep        sample strobe and its keep flag (keep = 0: blanked sample, ignored)
//   i_d, i_q           s16 Park currents (hfi_park.v outputs)
//   w                  s16 Q1.15 demodulation weight (hfi_cordic.v)
//   latch              one-cycle window-boundary strobe
//   gamma, gamma_d     s32 (current LSB x samples), eq. (19)
//   sum_id, sum_iq     s32 (current LSB); wsum s32 (Q1.15)
//   n_samples          u16, accepted samples of the window, saturated at 65535
//   latched            one-cycle pulse: the outputs above were updated in this cycle (held otherwise)
//
// Timing: the products i_q*w, i_d*w are registered in the cycle after valid (two multipliers, s16 x s16
// -> s32) and added in the next one; the sums and n are updated in the cycle after valid. The window
// membership is decided by the cycle of valid relative to latch: a product still in the pipeline at
// the latch is added to the latched value, not to the new window. latched (and the new outputs)
// come LATENCY = 2 cycles after latch (latch cycle L: snapshot at the end of L, outputs at the end of
// L+1). Throughput: one sample per cycle (minimum sample spacing 1; the system gives >= 40); latches
// may come in any cycles, even consecutive ones (a window of 0 samples latches zeros and n = 0).
// Range: the s48 accumulators and s33 sums are exact for windows of up to 2^17 - 1 samples (the spec
// bounds a window below 65535 samples), so the saturations only act beyond the specified range.
// A synchronous reset clears the window, the pipeline and the outputs; the first window starts in the
// cycle after rst is released.
`default_nettype none

module hfi_demodulator (
    input  wire               clk,
    input  wire               rst,
    input  wire               valid,
    input  wire               keep,
    input  wire signed [15:0] i_d,
    input  wire signed [15:0] i_q,
    input  wire signed [15:0] w,
    input  wire               latch,
    output reg  signed [31:0] gamma,
    output reg  signed [31:0] gamma_d,
    output reg  signed [31:0] sum_id,
    output reg  signed [31:0] sum_iq,
    output reg  signed [31:0] wsum,
    output reg         [15:0] n_samples,
    output reg                latched
);
    /* verilator lint_off UNUSEDPARAM */  // documents the fixed pipeline below (snapshot, outputs)
    localparam LATENCY = 2;                 // cycles from latch to latched
    /* verilator lint_on UNUSEDPARAM */
    localparam [15:0] N_MAX = 16'hFFFF;

    wire take = valid & keep;               // an accepted sample in this cycle

    // Product stage (the two multipliers), registered in the cycle after valid.
    reg               p_v;                  // products valid (an accepted sample one cycle ago)
    reg signed [31:0] p_q, p_d;             // i_q*w, i_d*w (|product| <= 2^30)

    // Window state.
    reg signed [47:0] acc_q, acc_d;         // sum i_q*w, sum i_d*w (s48)
    reg signed [32:0] s_d, s_q, s_w;        // sum i_d, sum i_q, sum w (s33)
    reg        [15:0] n;

    // Next values before a latch: the product of the sample one cycle ago joins its window here.
    wire signed [47:0] acc_q_nx = acc_q + (p_v ? {{16{p_q[31]}}, p_q} : 48'sd0);
    wire signed [47:0] acc_d_nx = acc_d + (p_v ? {{16{p_d[31]}}, p_d} : 48'sd0);
    // Sums of the new cycle's sample, onto the current window (or onto 0 if this cycle latches).
    wire signed [32:0] s_d_base = latch ? 33'sd0 : s_d;
    wire signed [32:0] s_q_base = latch ? 33'sd0 : s_q;
    wire signed [32:0] s_w_base = latch ? 33'sd0 : s_w;
    wire        [15:0] n_base   = latch ? 16'd0 : n;

    // Snapshot of the finished window (taken at the end of the latch cycle).
    reg               l_v;                  // snapshot taken one cycle ago
    reg signed [32:0] l_g_q, l_g_d;         // shr(acc, 15): the top 33 bits of the s48 sums
    reg signed [32:0] l_s_d, l_s_q, l_s_w;
    reg        [15:0] l_n;

    // sat(v, 32) of an s33.
    function signed [31:0] sat32;
        input signed [32:0] v;
        begin
            if (v[32] != v[31])
                sat32 = v[32] ? 32'sh80000000 : 32'sh7FFFFFFF;
            else
                sat32 = v[31:0];
        end
    endfunction

    always @(posedge clk) begin
        if (rst) begin
            p_v <= 1'b0;
            p_q <= 32'sd0;
            p_d <= 32'sd0;
            acc_q <= 48'sd0;
            acc_d <= 48'sd0;
            s_d <= 33'sd0;
            s_q <= 33'sd0;
            s_w <= 33'sd0;
            n <= 16'd0;
            l_v <= 1'b0;
            l_g_q <= 33'sd0;
            l_g_d <= 33'sd0;
            l_s_d <= 33'sd0;
            l_s_q <= 33'sd0;
            l_s_w <= 33'sd0;
            l_n <= 16'd0;
            gamma <= 32'sd0;
            gamma_d <= 32'sd0;
            sum_id <= 32'sd0;
            sum_iq <= 32'sd0;
            wsum <= 32'sd0;
            n_samples <= 16'd0;
            latched <= 1'b0;
        end else begin
            // Products of this cycle's sample (the two multipliers).
            p_v <= take;
            p_q <= i_q * w;
            p_d <= i_d * w;

            // Window boundary: snapshot the finished window, restart the accumulators.
            l_v <= latch;
            if (latch) begin
                l_g_q <= acc_q_nx[47:15];   // shr(acc_q, 15), s33
                l_g_d <= acc_d_nx[47:15];
                l_s_d <= s_d;
                l_s_q <= s_q;
                l_s_w <= s_w;
                l_n <= n;
                acc_q <= 48'sd0;
                acc_d <= 48'sd0;
            end else begin
                acc_q <= acc_q_nx;
                acc_d <= acc_d_nx;
            end

            // Sums and count: a sample in the latch cycle opens the new window.
            if (take) begin
                s_d <= s_d_base + {{17{i_d[15]}}, i_d};
                s_q <= s_q_base + {{17{i_q[15]}}, i_q};
                s_w <= s_w_base + {{17{w[15]}}, w};
                n <= (n_base == N_MAX) ? N_MAX : n_base + 16'd1;
            end else begin
                s_d <= s_d_base;
                s_q <= s_q_base;
                s_w <= s_w_base;
                n <= n_base;
            end

            // Output registers from the snapshot: loaded, with 'latched', LATENCY = 2 cycles after latch.
            latched <= l_v;
            if (l_v) begin
                gamma <= sat32(l_g_q);
                gamma_d <= sat32(l_g_d);
                sum_id <= sat32(l_s_d);
                sum_iq <= sat32(l_s_q);
                wsum <= sat32(l_s_w);
                n_samples <= l_n;
            end
        end
    end
endmodule

`default_nettype wire
