// hfi_fcs_mpc: the FCS-MPC vector choice of the direct-vector mode (CTRL.DIRECT), bit-exact with
// golden/fpga/fcs_mpc.py `choose_vector` (docs/spec.md 3.10; Varatharajan et al. 2020, eqs. (15),
// (30)-(32)):
//   for the six active vectors j = 0..5 (states 001, 011, 010, 110, 100, 101; VX_j, VY_j the rounded
//   (2/3) 2^15 (cos, sin)(60 deg j), K_j = VX_j^2 + VY_j^2):
//     vd_j = round_shr(VX_j*COS + VY_j*SIN, 15), vq_j = round_shr(VY_j*COS - VX_j*SIN, 15)
//     p_j  = round_shr(A1*vq_j - A2*vd_j, 12)
//     d_j  = K_j - 2 (v_al*VX_j + v_be*VY_j)                  (d_0 = 0 for the zero vector)
//   eligible_j = |p_j| > PHI_MIN with CONSTRAIN, else every state (the zero vector included); if no
//   active vector is eligible under CONSTRAIN, the constraint is dropped. The least d wins (zero first,
//   then j = 0..5, the first of equals); the zero vector is 111 if two or three legs of state_now are
//   high, else 000.
// Two candidates run side by side: `ca` (the constrained choice: eligible active vectors only) and `cb`
// (the unconstrained one: the zero vector first, then every active vector); the result is ca if
// CONSTRAIN and some vector was eligible, else cb: exactly the golden rule.
//
// Ports:
//   v_al, v_be         s18                 the modulator's inverse Park, without injection
//   sin_q15, cos_q15   s16 Q1.15           SIN, COS
//   a1, a2             s16 Q12             FCS_A
//   phi_min            u16                 FCS_CTRL.PHI_MIN
//   constrain          1 bit               FCS_CTRL.CONSTRAIN
//   state_now          3 bits              the state applied now
//   state              3 bits              the choice (bit 0 = phase a); held between done pulses
// Timing: the inputs are sampled in the cycle `start` is high (cycle 0) if not busy (a start while busy
// is ignored); busy in cycles 1..LATENCY-1; `state` changes and done is high in cycle LATENCY = 69
// (step t of vector j runs in cycle 1 + 11 j + t, the last comparison in cycle 66, its update in 67).
// Reset (synchronous): state = 0, busy and done clear.
//
// Schedule: one 18x18 signed multiplier (hfi_mul18, product two cycles after its operands) and one
// accumulator; 11 steps per vector j (t = 0..10), at most one two-input addition per step:
//   t0 VX*C   t1 VY*S   t2 VY*C, acc = p + 2^14   t3 VX*S, vd = (acc + p) >>> 15
//   t4 VX*v_al, acc = p + 2^14   t5 VY*v_be, vq = (acc - p) >>> 15   t6 A1*vq, acc = p
//   t7 A2*vd, sd = acc + p   t8 acc = p + 2^11, d = K - 2 sd
//   t9 pj = (acc - p) >>> 12, the two d comparisons   t10 eligibility (pj against +-PHI_MIN)
// and the candidates updated in the cycle after t10 (t0 of the next vector; after the last vector, cycle 67).
// (The comparisons are registered before the candidates' clock enables: pj -> compare -> enables was the
// tick clock's critical path on the ULX3S, 91.1 MHz, and with the d comparisons moved to t9 still 102.8.)
// Widths: |vd_j|, |vq_j| <= 29842 (s16); the p_j sum < 2^31 in magnitude, p_j s20 (any A1, A2); d_j
// within +-8.4e9 for |v_al|, |v_be| < 2^17 (s35; 38 bits are kept).

`default_nettype none

module hfi_fcs_mpc (
    input  wire               clk,
    input  wire               rst,
    input  wire               start,
    input  wire signed [17:0] v_al,
    input  wire signed [17:0] v_be,
    input  wire signed [15:0] sin_q15,
    input  wire signed [15:0] cos_q15,
    input  wire signed [15:0] a1,
    input  wire signed [15:0] a2,
    input  wire        [15:0] phi_min,
    input  wire               constrain,
    input  wire        [2:0]  state_now,
    output reg         [2:0]  state,
    output wire               busy,
    output reg                done
);

    localparam [6:0] LATENCY = 7'd69;

    reg [6:0] cnt;                                   // 0 idle, 1..LATENCY-1 busy
    reg       busy_r;                                // cnt != 0, kept as a flip-flop: accept (start, !busy)
    assign busy = busy_r;                            // resets the schedule, which was the ULX3S seed 3 path
    wire accept = start && !busy;

    reg signed [17:0] al_r, be_r;
    reg signed [15:0] sin_r, cos_r, a1_r, a2_r;
    reg        [15:0] phi_r;
    reg signed [24:0] nphi_r;                        // -PHI_MIN
    reg               con_r;
    reg        [2:0]  now_r;
    always @(posedge clk) begin
        if (accept) begin
            al_r <= v_al;
            be_r <= v_be;
            sin_r <= sin_q15;
            cos_r <= cos_q15;
            a1_r <= a1;
            a2_r <= a2;
            phi_r <= phi_min;
            nphi_r <= -$signed({9'd0, phi_min});
            con_r <= constrain;
            now_r <= state_now;
        end
    end

    // step t (0..10) of vector j (0..5); run from cycle 1 to cycle 66
    reg [3:0] t;
    reg [2:0] j;
    reg       run;
    always @(posedge clk) begin
        if (rst) begin
            run <= 1'b0;
            t <= 4'd0;
            j <= 3'd0;
        end else if (accept) begin
            run <= 1'b1;
            t <= 4'd0;
            j <= 3'd0;
        end else if (run) begin
            if (t == 4'd10) begin
                t <= 4'd0;
                j <= j + 3'd1;
                if (j == 3'd5) run <= 1'b0;
            end else begin
                t <= t + 4'd1;
            end
        end
    end

    // constants of vector j
    reg signed [17:0] vx, vy;
    reg        [29:0] kj;
    reg        [2:0]  sj;
    always @* begin
        case (j)
            3'd0: begin vx = 18'sd21845;  vy = 18'sd0;      kj = 30'd477204025; sj = 3'b001; end
            3'd1: begin vx = 18'sd10923;  vy = 18'sd18919;  kj = 30'd477240490; sj = 3'b011; end
            3'd2: begin vx = -18'sd10923; vy = 18'sd18919;  kj = 30'd477240490; sj = 3'b010; end
            3'd3: begin vx = -18'sd21845; vy = 18'sd0;      kj = 30'd477204025; sj = 3'b110; end
            3'd4: begin vx = -18'sd10923; vy = -18'sd18919; kj = 30'd477240490; sj = 3'b100; end
            default: begin vx = 18'sd10923; vy = -18'sd18919; kj = 30'd477240490; sj = 3'b101; end
        endcase
    end

    reg signed [15:0] vd, vq;
    reg signed [17:0] mul_a, mul_b;
    always @* begin
        case (t)
            4'd0: begin mul_a = vx; mul_b = {{2{cos_r[15]}}, cos_r}; end
            4'd1: begin mul_a = vy; mul_b = {{2{sin_r[15]}}, sin_r}; end
            4'd2: begin mul_a = vy; mul_b = {{2{cos_r[15]}}, cos_r}; end
            4'd3: begin mul_a = vx; mul_b = {{2{sin_r[15]}}, sin_r}; end
            4'd4: begin mul_a = vx; mul_b = al_r; end
            4'd5: begin mul_a = vy; mul_b = be_r; end
            4'd6: begin mul_a = {{2{a1_r[15]}}, a1_r}; mul_b = {{2{vq[15]}}, vq}; end
            default: begin mul_a = {{2{a2_r[15]}}, a2_r}; mul_b = {{2{vd[15]}}, vd}; end
        endcase
    end
    wire signed [35:0] p;
    hfi_mul18 u_mul (.clk(clk), .a(mul_a), .b(mul_b), .p(p));

    reg signed [37:0] acc, sd, d;
    reg signed [23:0] pj;
    wire signed [37:0] pw = {{2{p[35]}}, p};
    /* verilator lint_off UNUSEDSIGNAL */
    wire signed [37:0] sum_add = acc + pw;
    wire signed [37:0] sum_sub = acc - pw;
    /* verilator lint_on UNUSEDSIGNAL */
    always @(posedge clk) begin
        if (run) begin
            case (t)
                4'd2, 4'd4: acc <= pw + 38'sd16384;
                4'd3: vd <= sum_add[30:15];
                4'd5: vq <= sum_sub[30:15];
                4'd6: acc <= pw;
                4'd7: sd <= sum_add;
                4'd8: begin
                    acc <= pw + 38'sd2048;
                    d <= $signed({8'd0, kj}) - (sd <<< 1);
                end
                4'd9: pj <= sum_sub[35:12];
                default: ;
            endcase
        end
    end

    // t9: d against the candidates (final since the update after t10 of the previous vector); t10: the
    // eligibility; the cycle after t10: the update from these registered flags
    wire signed [24:0] phi_s = {9'd0, phi_r};
    wire signed [24:0] pj_w = {pj[23], pj};
    reg        ca_ok;                                // the constrained candidate exists
    reg [2:0]  ca_s, cb_s;                           // candidates (cb_s = 0: the zero vector)
    reg signed [37:0] ca_d, cb_d;
    reg        a_better, b_better;                   // t9: !ca_ok || d < ca_d, d < cb_d
    reg        elig_r, upd;                          // t10: |pj| > PHI_MIN; the update is due
    reg [2:0]  sj_r;                                 // (j moves on after t10; d holds until the next t8)
    always @(posedge clk) begin
        if (run && t == 4'd9) begin
            a_better <= !ca_ok || d < ca_d;
            b_better <= d < cb_d;
        end
        upd <= run && t == 4'd10;
        if (run && t == 4'd10) begin
            elig_r <= (pj_w > phi_s) || (pj_w < nphi_r);
            sj_r <= sj;
        end
    end
    always @(posedge clk) begin
        if (accept) begin
            ca_ok <= 1'b0;
            cb_s <= 3'b000;
            cb_d <= 38'sd0;
        end else if (upd) begin
            if (elig_r && a_better) begin
                ca_ok <= 1'b1;
                ca_s <= sj_r;
                ca_d <= d;
            end
            if (b_better) begin
                cb_s <= sj_r;
                cb_d <= d;
            end
        end
    end

    // result
    wire [2:0] zero_s = ((now_r[0] & now_r[1]) | (now_r[0] & now_r[2]) | (now_r[1] & now_r[2])) ? 3'b111 : 3'b000;
    wire [2:0] pick = (con_r && ca_ok) ? ca_s : cb_s;
    always @(posedge clk) begin
        if (rst) begin
            cnt <= 7'd0;
            busy_r <= 1'b0;
            done <= 1'b0;
            state <= 3'd0;
        end else begin
            done <= 1'b0;
            if (accept) begin
                cnt <= 7'd1;
                busy_r <= 1'b1;
            end else if (busy) begin
                cnt <= (cnt == LATENCY - 7'd1) ? 7'd0 : cnt + 7'd1;
                if (cnt == LATENCY - 7'd1) begin
                    busy_r <= 1'b0;
                    done <= 1'b1;
                    state <= (pick == 3'b000) ? zero_s : pick;
                end
            end
        end
    end

endmodule

`default_nettype wire
