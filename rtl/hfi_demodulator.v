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
// Timing: every input goes straight into a register (stage r: the sample, its keep flag, the latch
// strobe), so no logic of the caller precedes the arithmetic. The products i_q*w, i_d*w are formed from
// the stage-r registers (two multipliers, s16 x s16 -> s32) and registered; the sums and n are updated
// from stage r. A sample whose valid is in cycle c is in the sums at the end of c+1 and in the product
// sums at the end of c+2. The window membership is decided by the cycle of valid relative to latch: the
// latch acts one cycle later (latch_d, cycle L+1 for a latch in cycle L), when every sample of the
// ended window (valid up to L-1) is either summed or in the product register, and every later sample
// still in stage r: the outputs are loaded directly from the sums (the product sums with the product
// register added) at the end of L+1 and the accumulators restart with the stage-r sample. latched (and
// the new outputs) come LATENCY = 2 cycles after latch. Throughput: one sample per cycle (minimum
// sample spacing 1; the system gives >= 40); latches may come in any cycles, even consecutive ones (a
// window of 0 samples latches zeros and n = 0).
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
    /* verilator lint_off UNUSEDPARAM */  // documents the fixed pipeline below (latch_d, outputs)
    localparam LATENCY = 2;                 // cycles from latch to latched
    /* verilator lint_on UNUSEDPARAM */
    localparam [15:0] N_MAX = 16'hFFFF;

    // Stage r: the inputs of this cycle, registered.
    reg               r_v;                  // an accepted sample (valid & keep) one cycle ago
    reg signed [15:0] r_id, r_iq, r_w;
    reg               latch_d;              // latch one cycle ago: the window ends now (see Timing)

    // Product stage (the two multipliers), from stage r.
    reg               p_v;                  // products valid (an accepted sample two cycles ago)
    reg signed [31:0] p_q, p_d;             // i_q*w, i_d*w (|product| <= 2^30)

    // Window state: the sums hold the samples up to two cycles ago (products: three cycles ago).
    reg signed [47:0] acc_q, acc_d;         // sum i_q*w, sum i_d*w (s48)
    reg signed [32:0] s_d, s_q, s_w;        // sum i_d, sum i_q, sum w (s33)
    reg        [15:0] n;

    // The window so far, with the sample of the product register / of stage r.
    wire signed [47:0] acc_q_nx = acc_q + (p_v ? {{16{p_q[31]}}, p_q} : 48'sd0);
    wire signed [47:0] acc_d_nx = acc_d + (p_v ? {{16{p_d[31]}}, p_d} : 48'sd0);
    wire signed [32:0] r_d = r_v ? {{17{r_id[15]}}, r_id} : 33'sd0;
    wire signed [32:0] r_q = r_v ? {{17{r_iq[15]}}, r_iq} : 33'sd0;
    wire signed [32:0] r_ww = r_v ? {{17{r_w[15]}}, r_w} : 33'sd0;
    wire        [15:0] n_nx = (r_v && n != N_MAX) ? n + 16'd1 : n;

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
            r_v <= 1'b0;
            r_id <= 16'sd0;
            r_iq <= 16'sd0;
            r_w <= 16'sd0;
            latch_d <= 1'b0;
            p_v <= 1'b0;
            p_q <= 32'sd0;
            p_d <= 32'sd0;
            acc_q <= 48'sd0;
            acc_d <= 48'sd0;
            s_d <= 33'sd0;
            s_q <= 33'sd0;
            s_w <= 33'sd0;
            n <= 16'd0;
            gamma <= 32'sd0;
            gamma_d <= 32'sd0;
            sum_id <= 32'sd0;
            sum_iq <= 32'sd0;
            wsum <= 32'sd0;
            n_samples <= 16'd0;
            latched <= 1'b0;
        end else begin
            r_v <= valid & keep;
            r_id <= i_d;
            r_iq <= i_q;
            r_w <= w;
            latch_d <= latch;
            // Products of the stage-r sample (the two multipliers).
            p_v <= r_v;
            p_q <= r_iq * r_w;
            p_d <= r_id * r_w;

            // latch_d: the window of every sample before the latch cycle is complete here: load the
            // outputs (shr(acc, 15): the top 33 bits of the s48 sums), restart with the stage-r sample
            // (valid in the latch cycle or later) and an empty product sum.
            latched <= latch_d;
            if (latch_d) begin
                gamma <= sat32(acc_q_nx[47:15]);
                gamma_d <= sat32(acc_d_nx[47:15]);
                sum_id <= sat32(s_d);
                sum_iq <= sat32(s_q);
                wsum <= sat32(s_w);
                n_samples <= n;
                acc_q <= 48'sd0;
                acc_d <= 48'sd0;
                s_d <= r_d;
                s_q <= r_q;
                s_w <= r_ww;
                n <= {15'd0, r_v};
            end else begin
                acc_q <= acc_q_nx;
                acc_d <= acc_d_nx;
                s_d <= s_d + r_d;
                s_q <= s_q + r_q;
                s_w <= s_w + r_ww;
                n <= n_nx;
            end
        end
    end
endmodule

`default_nettype wire
