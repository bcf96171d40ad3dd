// hfi_modulator: compares of the next carrier top (sign +1) and bottom (sign -1) half periods, each
// followed by the dead-time compensation; bit-exact with the golden chain of
// golden/closedloop.py `ClosedLoop._compares`:
//   cmps = compares(V_D, V_Q, V_H, SIN, COS, H, sign)                (golden/fpga/modulator.py, spec 3.5)
//   if DTC_GAIN != 0: cmps = compensate(cmps, sign, H, D, DTC_GAIN, I_D_REF, I_Q_REF, HF_AMP,
//                                       SIN, COS, RECIP_H)          (golden/fpga/deadtime_comp.py, 3.6)
// Per sign (spec 3.5):
//   rot = 0: vd = V_D + sign*V_H (s17), vq = V_Q, vr = 0    square-wave injection on the estimated
//            d-axis, the paper's v_dh = V_h * -sign(d cw/dt) (Benevieri et al. 2023, eq. (14))
//   rot = 1: vd = V_D, vq = V_Q, vr = V_H                   rotating injection V_H (C, S) in the
//            stationary frame (Tap et al. 2023, eq. (9)); C, S = inj_cos, inj_sin
//   inj_neg (rot = 0): the injection's sign is -sign instead (the top set gets V_D - V_H, the bottom
//            set V_D + V_H): the period square wave of CTRL.INJ_PER with S = -1 (spec 3.5; golden
//            _compares(..., inj_sign)). S = +1 is the plain square wave's pair of signs, so the
//            caller sets inj_neg = INJ_PER mode & (S of this period = -1). The dead-time compensation
//            keeps the half's own sign either way.
//   v_al = round_shr(vd*COS - vq*SIN + vr*C, 15), v_be = round_shr(vd*SIN + vq*COS + vr*S, 15)
//                                                      inverse Park plus the rotating vector
//   v_a = v_al, v_b/c = round_shr(-v_al*2^14 +/- v_be*28378, 15)                      inverse Clarke
//   off = shr(max + min, 1), v_x' = v_x - off                                         min-max
//   cmp_x = clamp(H/2 + round_shr(v_x'*H, 15), 0, H)               (over-modulation clipped per leg)
// Direct-vector mode (direct = 1, CTRL.DIRECT; spec 3.10, golden/closedloop.py with HardwareConfig.direct):
//   vd = V_D for both sets, vr = 0 (no injection of any kind); the top program's v_al, v_be go to the
//   hfi_fcs_mpc instance (the FCS-MPC choice, golden modulator.direct_state = fcs_mpc.choose_vector)
//   with SIN, COS, FCS_A, FCS_CTRL and the state applied now (`state`); both output sets are
//   cmp_x = H if bit x of the chosen state is set, else 0 (golden modulator.direct_compares), without
//   the dead-time compensation, and `state` takes the chosen state (0 after a computation without the
//   mode, and in reset).
// The compensation with DTC_GAIN = 0 is the identity (c = 0, cmp already in 0..H), so the module
// always runs it and the `DTC_GAIN != 0` test of the golden chain needs no hardware.
//
// Ports:
//   v_d, v_q          s16 (2^15 = V_dc)        V_D, V_Q registers
//   v_h               u15 in s16 (0..32767)    V_H (0 while injection is off)
//   rot               1 bit                    rotating injection (CTRL.INJ_ROT with INJ_EN)
//   inj_neg           1 bit                    square wave with the signs swapped (above; ignored if rot)
//   inj_sin, inj_cos  s16 Q1.15                S, C of the rotating injection's phase (spec 3.5)
//   sin_q15, cos_q15  s16 Q1.15                SIN, COS of the estimated angle
//   i_d_ref, i_q_ref  s16                      current references for the compensation
//   half              u16, even, 512..65534    H, the effective carrier half period [ticks]
//   dead              u16, >= 1                D, the effective dead time [ticks]
//   dtc_gain          u16                      DTC_GAIN (Q8 ticks per current LSB, 0 = off)
//   hf_amp            u15                      HF_AMP
//   recip_h           u32                      RECIP_H (round(2^32/H); any value is computed exactly)
//   cmp_top_{a,b,c}   u16 (0..H)               compares for sign +1 (latched at the carrier top)
//   cmp_bot_{a,b,c}   u16 (0..H)               compares for sign -1 (latched at the carrier bottom)
//   direct            1 bit                    direct-vector mode (above)
//   fcs_a1, fcs_a2    s16 Q12                  FCS_A (direct mode)
//   fcs_phi_min       u16                      FCS_CTRL.PHI_MIN (direct mode)
//   fcs_constrain     1 bit                    FCS_CTRL.CONSTRAIN (direct mode)
//   state             3 bits                   the direct mode's state applied by the outputs (bit 0 = a;
//                                              0 without the mode); changes with them, in cycle LATENCY
// Timing: every input is sampled in the cycle `start` is high (cycle 0) if the unit is not busy; a
// start while busy is ignored (no queueing). busy is high in cycles 1..LATENCY-1; the six outputs all
// change together in cycle LATENCY = 105, when done is high for one cycle (and busy is low, so a start
// in the done cycle is accepted: back to back, one pair of compare sets per 105 cycles). The outputs
// hold their values between done pulses.
// Reset (synchronous): in every cycle with rst high the six outputs load half >> 1 of the `half` input
// of that cycle (the compares that the reset register values V = 0 give, rtl.md "After reset the
// compares are H/2"); busy and done clear and a computation in progress is abandoned (no done).
//
// Architecture: one 18x18 signed multiplier (this module's only `*`) and a 36-bit accumulator run a
// 22-slot micro-program (the `uop` table) per sign, first for the top set (cycles 1..22), then for the
// bottom set (23..44), with the same registers. Each sum starts from an initial value that holds its
// rounding constant (2^14; H/2*2^15 + 2^14 for a compare), so results are written back rounded:
//   v_be = (2^14 + vd*SIN + vq*COS + vr*S) >>> 15   v_al = (2^14 + vd*COS - vq*SIN + vr*C) >>> 15
//   v_b  = (2^14 + v_be*28378 - v_al*16384) >>> 15  v_c  = (2^14 - v_be*28378 - v_al*16384) >>> 15
//   cmp_x = clamp((H/2*2^15 + 2^14 - off*H + v_x*H) >>> 15, 0, H)     ((v_x - off)*H as two products;
//                                                     H/2*2^15 is a multiple of 2^15, so this is
//                                                     H/2 + round_shr(v_x'*H, 15))
// The min-max unit registers max and min of v_a, v_b, v_c (three comparisons; a tie selects equal
// values, so the golden order of the comparisons does not matter) and off = (max + min) >>> 1 is an
// operand. Pipeline of a slot issued in cycle t (as in hfi_deadtime_comp): operand registers (t),
// product (t+1), accumulator (t+2), write-back (t+3); the table waits for every result it uses.
// The hfi_deadtime_comp instance (its own multiplier; LATENCY 39) compensates the top set (start in
// cycle 26, after its last compare is written; done in 65, when the results are kept and the bottom
// set starts) and then the bottom set (done in 104); the outputs are written at the end of cycle 104.
// Widths (golden/fpga/modulator.py): vd s17; v_al, v_be within +-98303 in both modes (the Park sums
// stay within 3*2^30) and v_b, v_c within +-101517 (s18); off s18; the sums fit s34 (the compare sum:
// |H/2*2^15| < 2^30, |off*H|, |v_x*H| < 2^33).
// Multipliers: 3 `*` in all: one 18x18 signed here, one in hfi_deadtime_comp and one in hfi_fcs_mpc
// (one MULT18X18D / DSP48E1 each). The vector choice runs in cycles 12..80 (T_FCS below) in both modes.

`default_nettype none

module hfi_modulator #(
    parameter FCS_MPC = 1       // 0: no vector choice (build option, hfi_dsp): the direct mode applies state 0
) (
    input  wire               clk,
    input  wire               rst,
    input  wire               start,
    input  wire signed [15:0] v_d,
    input  wire signed [15:0] v_q,
    input  wire signed [15:0] v_h,
    input  wire               rot,
    input  wire               inj_neg,
    input  wire signed [15:0] inj_sin,
    input  wire signed [15:0] inj_cos,
    input  wire               direct,
    input  wire signed [15:0] fcs_a1,
    input  wire signed [15:0] fcs_a2,
    input  wire        [15:0] fcs_phi_min,
    input  wire               fcs_constrain,
    output reg         [2:0]  state,
    input  wire signed [15:0] sin_q15,
    input  wire signed [15:0] cos_q15,
    input  wire signed [15:0] i_d_ref,
    input  wire signed [15:0] i_q_ref,
    input  wire        [15:0] half,
    input  wire        [15:0] dead,
    input  wire        [15:0] dtc_gain,
    input  wire        [14:0] hf_amp,
    input  wire        [31:0] recip_h,
    output reg         [15:0] cmp_top_a,
    output reg         [15:0] cmp_top_b,
    output reg         [15:0] cmp_top_c,
    output reg         [15:0] cmp_bot_a,
    output reg         [15:0] cmp_bot_b,
    output reg         [15:0] cmp_bot_c,
    output wire               busy,
    output reg                done
);

    localparam [6:0] LATENCY = 7'd105;              // start -> done (cycles)
    localparam [6:0] T_DTC_TOP = 7'd26;             // the top set enters hfi_deadtime_comp
    localparam [6:0] T_LAST = LATENCY - 7'd1;       // the bottom set is compensated in this cycle
    localparam [4:0] SLOTS = 5'd22;                 // micro-program slots per sign

    // Operand A
    localparam [2:0] A_VD = 3'd0, A_VQ = 3'd1, A_BE = 3'd2, A_VA = 3'd3, A_VB = 3'd4, A_VC = 3'd5,
                     A_OFF = 3'd6, A_VR = 3'd7;
    // Operand B
    localparam [2:0] B_SIN = 3'd0, B_COS = 3'd1, B_SQ3 = 3'd2, B_M16K = 3'd3, B_H = 3'd4, B_CR = 3'd5,
                     B_SR = 3'd6;
    // Accumulator initial value of the first product of a sum
    localparam [1:0] I_CONT = 2'd0, I_R14 = 2'd1, I_CMP = 2'd2;
    // Write-back destination (W_MM: no product; the min-max unit registers max and min)
    localparam [3:0] W_NONE = 4'd0, W_BE = 4'd1, W_VA = 4'd2, W_VB = 4'd3, W_VC = 4'd4, W_CA = 4'd5,
                     W_CB = 4'd6, W_CC = 4'd7, W_MM = 4'd8;
    localparam ADD = 1'b0, SUB = 1'b1;
    localparam NOP = 1'b0, ISS = 1'b1;

    // ---------------------------------------------------------------- sequencer, sampled inputs
    reg [6:0] cnt;                                   // 0 idle, 1..LATENCY-1 busy
    // busy == (cnt != 0), a flip-flop set with cnt (timing: the compare of cnt in front of accept, which
    // resets the micro-program counter, was the tick clock's critical path on a ULX3S seed, docs/boards.md)
    reg busy_r;
    assign busy = busy_r;
    wire accept = start && !busy_r;

    reg signed [15:0] v_q_r, sin_r, cos_r, i_d_ref_r, i_q_ref_r, cr_r, sr_r;
    reg signed [16:0] vd_top, vd_bot;                // vd = V_D + V_H (sign +1), V_D - V_H (sign -1);
                                                     // swapped with inj_neg
    reg signed [15:0] vr_r;                          // vr: V_H (rotating injection) or 0
    reg        [15:0] half_r, dead_r, gain_r;
    reg        [14:0] hf_amp_r;
    reg        [31:0] recip_h_r;
    reg               direct_r, constrain_r;         // direct-vector mode and its FCS_A, FCS_CTRL
    reg signed [15:0] a1_r, a2_r;
    reg        [15:0] phi_min_r;
    wire signed [16:0] vd_plus = {v_d[15], v_d} + (rot ? 17'sd0 : {v_h[15], v_h});
    wire signed [16:0] vd_minus = {v_d[15], v_d} - (rot ? 17'sd0 : {v_h[15], v_h});
    always @(posedge clk) begin
        if (accept) begin
            // formed when sampled (timing: no adder before the operand); inj_neg selects after the adders
            vd_top <= direct ? {v_d[15], v_d} : (inj_neg && !rot) ? vd_minus : vd_plus;
            vd_bot <= direct ? {v_d[15], v_d} : (inj_neg && !rot) ? vd_plus : vd_minus;
            vr_r <= (rot && !direct) ? v_h : 16'sd0;
            direct_r <= direct;
            a1_r <= fcs_a1;
            a2_r <= fcs_a2;
            phi_min_r <= fcs_phi_min;
            constrain_r <= fcs_constrain;
            cr_r <= inj_cos;
            sr_r <= inj_sin;
            v_q_r <= v_q;
            sin_r <= sin_q15;
            cos_r <= cos_q15;
            i_d_ref_r <= i_d_ref;
            i_q_ref_r <= i_q_ref;
            half_r <= half;
            dead_r <= dead;
            gain_r <= dtc_gain;
            hf_amp_r <= hf_amp;
            recip_h_r <= recip_h;
        end
    end

    // micro-program counter: slot ms of the top (mbot = 0) or bottom (mbot = 1) program
    reg [4:0] ms;
    reg       mrun, mbot;
    always @(posedge clk) begin
        if (rst) begin
            mrun <= 1'b0;
            mbot <= 1'b0;
            ms <= 5'd0;
        end else if (accept) begin
            mrun <= 1'b1;
            mbot <= 1'b0;
            ms <= 5'd0;
        end else if (mrun) begin
            if (ms == SLOTS - 5'd1) begin
                ms <= 5'd0;
                mbot <= 1'b1;
                if (mbot) mrun <= 1'b0;
            end else begin
                ms <= ms + 5'd1;
            end
        end
    end

    // ---------------------------------------------------------------- micro-program (one sign)
    // {issue, A, B, initial value, add/sub, write-back}. The word of slot ms is registered (uop) from
    // the slot of the next cycle (timing): ms is 0 whenever the program does not run.
    wire [4:0] ms_next = mrun ? ((ms == SLOTS - 5'd1) ? 5'd0 : ms + 5'd1) : 5'd0;
    reg [13:0] uop_n, uop;
    always @(posedge clk)
        uop <= uop_n;
    always @* begin
        case (rst ? 5'd0 : ms_next)
            5'd0:  uop_n = {ISS, A_VD,  B_SIN,  I_R14,  ADD, W_NONE};
            5'd1:  uop_n = {ISS, A_VQ,  B_COS,  I_CONT, ADD, W_NONE};
            5'd2:  uop_n = {ISS, A_VR,  B_SR,   I_CONT, ADD, W_BE};     // v_be
            5'd3:  uop_n = {ISS, A_VD,  B_COS,  I_R14,  ADD, W_NONE};
            5'd4:  uop_n = {ISS, A_VQ,  B_SIN,  I_CONT, SUB, W_NONE};
            5'd5:  uop_n = {ISS, A_VR,  B_CR,   I_CONT, ADD, W_VA};     // v_al = v_a
            5'd8:  uop_n = {ISS, A_BE,  B_SQ3,  I_R14,  ADD, W_NONE};
            5'd9:  uop_n = {ISS, A_VA,  B_M16K, I_CONT, ADD, W_VB};     // v_b
            5'd10: uop_n = {ISS, A_BE,  B_SQ3,  I_R14,  SUB, W_NONE};
            5'd11: uop_n = {ISS, A_VA,  B_M16K, I_CONT, ADD, W_VC};     // v_c
            5'd15: uop_n = {NOP, A_VD,  B_SIN,  I_CONT, ADD, W_MM};     // max, min
            5'd16: uop_n = {ISS, A_OFF, B_H,    I_CMP,  SUB, W_NONE};
            5'd17: uop_n = {ISS, A_VA,  B_H,    I_CONT, ADD, W_CA};     // cmp_a
            5'd18: uop_n = {ISS, A_OFF, B_H,    I_CMP,  SUB, W_NONE};
            5'd19: uop_n = {ISS, A_VB,  B_H,    I_CONT, ADD, W_CB};     // cmp_b
            5'd20: uop_n = {ISS, A_OFF, B_H,    I_CMP,  SUB, W_NONE};
            5'd21: uop_n = {ISS, A_VC,  B_H,    I_CONT, ADD, W_CC};     // cmp_c
            default: uop_n = {NOP, A_VD, B_SIN, I_CONT, ADD, W_NONE};   // 6, 7, 12..14: wait for a result
        endcase
    end
    wire       u_iss = mrun && uop[13];
    wire [2:0] u_a = uop[12:10];
    wire [2:0] u_b = uop[9:7];
    wire [1:0] u_init = uop[6:5];
    wire       u_neg = uop[4];
    wire [3:0] u_wb = uop[3:0];

    // ---------------------------------------------------------------- data path
    reg signed [17:0] be, va, vb, vc;                // v_be, v_a, v_b, v_c (s18)
    reg signed [17:0] hi, lo;                        // max and min of v_a, v_b, v_c
    reg signed [17:0] hi_ab, lo_ab;                  // max and min of v_a, v_b of the previous cycle
    /* verilator lint_off UNUSEDSIGNAL */
    wire signed [18:0] mm_sum = {hi[17], hi} + {lo[17], lo};   // bit 0 dropped: shr by 1
    /* verilator lint_on UNUSEDSIGNAL */
    wire signed [17:0] off = mm_sum[18:1];           // shr(max + min, 1), an operand (s18)
    reg        [15:0] cmp_a, cmp_b, cmp_c;           // compares of the set being computed
    wire signed [16:0] vd = mbot ? vd_bot : vd_top;
    reg signed [17:0] mul_a, mul_b;
    always @* begin
        case (u_a)
            A_VD:    mul_a = {vd[16], vd};
            A_VQ:    mul_a = {{2{v_q_r[15]}}, v_q_r};
            A_BE:    mul_a = be;
            A_VA:    mul_a = va;
            A_VB:    mul_a = vb;
            A_VC:    mul_a = vc;
            A_OFF:   mul_a = off;
            default: mul_a = {{2{vr_r[15]}}, vr_r};                    // A_VR
        endcase
        case (u_b)
            B_SIN:   mul_b = {{2{sin_r[15]}}, sin_r};
            B_COS:   mul_b = {{2{cos_r[15]}}, cos_r};
            B_SQ3:   mul_b = 18'sd28378;                              // round(2^15*sqrt(3)/2)
            B_M16K:  mul_b = -18'sd16384;
            B_CR:    mul_b = {{2{cr_r[15]}}, cr_r};
            B_SR:    mul_b = {{2{sr_r[15]}}, sr_r};
            default: mul_b = {2'b00, half_r};                         // B_H
        endcase
    end

    // stage 0: operand registers, stage 1: product (both in hfi_mul18); stage 2: accumulator; then
    // write-back
    wire signed [35:0] p_r;                          // the module's one multiplier (18x18 signed)
    hfi_mul18 u_mul (.clk(clk), .a(mul_a), .b(mul_b), .p(p_r));
    reg        s0_v, s1_v, s2_v;
    reg  [1:0] s0_init, s1_init;
    reg        s0_neg, s1_neg;
    reg  [3:0] s0_wb, s1_wb, s2_wb;
    always @(posedge clk) begin
        s0_init <= u_init;
        s0_neg <= u_neg;
        s0_wb <= u_wb;
        s1_init <= s0_init;
        s1_neg <= s0_neg;
        s1_wb <= s0_wb;
        s2_wb <= s1_wb;
        if (rst) begin
            s0_v <= 1'b0;
            s1_v <= 1'b0;
            s2_v <= 1'b0;
        end else begin
            s0_v <= u_iss;
            s1_v <= s0_v;
            s2_v <= s1_v;
        end
    end

    reg signed [35:0] acc;
    reg signed [35:0] base;
    always @* begin
        case (s1_init)
            I_R14:   base = 36'sd16384;
            I_CMP:   base = {6'd0, half_r[15:1], 15'h4000};             // H/2*2^15 + 2^14
            default: base = acc;                                        // I_CONT
        endcase
    end
    wire signed [35:0] p_op = p_r ^ {36{s1_neg}};    // one adder: base - p = base + ~p + 1
    /* verilator lint_off UNUSEDSIGNAL */              // bit 0: the +1 enters as its carry
    wire [36:0] acc_s = {base, 1'b1} + {p_op, s1_neg};
    /* verilator lint_on UNUSEDSIGNAL */
    always @(posedge clk) begin
        if (s1_v) acc <= acc_s[36:1];
    end

    // write-back: round_shr results acc[32:15] (s18); compares acc[35:15] clamped to 0..H
    /* verilator lint_off UNUSEDSIGNAL */
    wire signed [20:0] r15 = acc[35:15];
    /* verilator lint_on UNUSEDSIGNAL */
    wire [15:0] cmp_new = r15[20] ? 16'd0 : (r15 > $signed({5'd0, half_r})) ? half_r : r15[15:0];
    // min-max (three comparisons; ties select equal values): max and min of v_a, v_b are registered
    // in every cycle (v_b is final two cycles before the W_MM slot, v_c in it), then compared with
    // v_c in the W_MM slot.
    wire gab = va > vb;
    always @(posedge clk) begin
        hi_ab <= gab ? va : vb;
        lo_ab <= gab ? vb : va;
        if (mrun && u_wb == W_MM) begin
            hi <= (hi_ab > vc) ? hi_ab : vc;
            lo <= (lo_ab > vc) ? vc : lo_ab;
        end
        if (s2_v) begin
            case (s2_wb)
                W_BE: be <= r15[17:0];
                W_VA: va <= r15[17:0];
                W_VB: vb <= r15[17:0];
                W_VC: vc <= r15[17:0];
                W_CA: cmp_a <= cmp_new;
                W_CB: cmp_b <= cmp_new;
                W_CC: cmp_c <= cmp_new;
                default: ;
            endcase
        end
    end

    // ---------------------------------------------------------------- dead-time compensation
    // Top set: start in cycle T_DTC_TOP = 26 (its last compare is written at the end of cycle 25);
    // bottom set: start in the cycle the top one is done (65; the bottom compares are written by the
    // end of cycle 47). The instance samples the compares and sign_top at its start (sign +1 for the
    // first start, -1 for the one in the done cycle of the top set); the other inputs are the sampled
    // registers, stable while it runs.
    reg dtc_bot;                                     // the bottom set is in the DTC
    wire dtc_done;
    reg  top_go;                                     // cnt == T_DTC_TOP, registered the cycle before
    // the top set starts on top_go with chain = 1: the unit starts the bottom set itself in its done cycle
    // (sign -1, the bottom compares of that cycle; timing: no done -> start loop through this module)
    wire [15:0] dtc_a, dtc_b, dtc_c;
    reg  [15:0] top_a, top_b, top_c;                 // compensated top set, until done
    hfi_deadtime_comp u_dtc (
        .clk(clk),
        .rst(rst),
        .start(top_go),
        .chain(1'b1),
        .sign_top(1'b1),
        .cmp_a_in(cmp_a),
        .cmp_b_in(cmp_b),
        .cmp_c_in(cmp_c),
        .half(half_r),
        .dead(dead_r),
        .gain(gain_r),
        .i_d_ref(i_d_ref_r),
        .i_q_ref(i_q_ref_r),
        .hf_amp(hf_amp_r),
        .sin_q15(sin_r),
        .cos_q15(cos_r),
        .recip_h(recip_h_r),
        .cmp_a(dtc_a),
        .cmp_b(dtc_b),
        .cmp_c(dtc_c),
        /* verilator lint_off PINCONNECTEMPTY */
        .busy(),                                     // the schedule is fixed: done sequences it
        /* verilator lint_on PINCONNECTEMPTY */
        .done(dtc_done)
    );

    // ---------------------------------------------------------------- direct-vector mode (spec 3.10)
    // The top program's v_al, v_be (written by the end of cycle 9, without injection in this mode; the
    // bottom program overwrites be from cycle 28) enter the vector choice in cycle T_FCS; it is done in
    // cycle T_FCS + 69 = 81 < T_LAST. The choice runs in both modes; only direct_r uses it.
    localparam [6:0] T_FCS = 7'd12;
    reg  fcs_go;
    wire [2:0] fcs_state;
    generate
        if (FCS_MPC != 0) begin : g_fcs
            hfi_fcs_mpc u_fcs (
                .clk(clk), .rst(rst), .start(fcs_go), .v_al(va), .v_be(be), .sin_q15(sin_r),
                .cos_q15(cos_r), .a1(a1_r), .a2(a2_r), .phi_min(phi_min_r), .constrain(constrain_r),
                .state_now(state), .state(fcs_state),
                /* verilator lint_off PINCONNECTEMPTY */
                .busy(), .done()
                /* verilator lint_on PINCONNECTEMPTY */
            );
        end else begin : g_no_fcs
            assign fcs_state = 3'd0;
            wire unused_fcs = &{1'b0, fcs_go, a1_r, a2_r, phi_min_r, constrain_r};
        end
    endgenerate
    wire [15:0] dir_a = fcs_state[0] ? half_r : 16'd0;
    wire [15:0] dir_b = fcs_state[1] ? half_r : 16'd0;
    wire [15:0] dir_c = fcs_state[2] ? half_r : 16'd0;

    // ---------------------------------------------------------------- control, outputs
    always @(posedge clk) begin
        if (dtc_done && !dtc_bot) begin              // cycle 65
            top_a <= dtc_a;
            top_b <= dtc_b;
            top_c <= dtc_c;
        end
        // cnt is T_DTC_TOP in the next cycle iff it is T_DTC_TOP - 1 now (it counts up by one while
        // busy, T_DTC_TOP - 1 is neither 0 nor T_LAST, and an accept loads 1): timing, the start of the
        // compensation then comes from flip-flops
        top_go <= !rst && cnt == T_DTC_TOP - 7'd1;
        fcs_go <= !rst && cnt == T_FCS - 7'd1;
        busy_r <= !rst && (accept || (busy_r && cnt != T_LAST));
        if (rst) begin
            cnt <= 7'd0;
            done <= 1'b0;
            dtc_bot <= 1'b0;
            state <= 3'd0;
            cmp_top_a <= {1'b0, half[15:1]};
            cmp_top_b <= {1'b0, half[15:1]};
            cmp_top_c <= {1'b0, half[15:1]};
            cmp_bot_a <= {1'b0, half[15:1]};
            cmp_bot_b <= {1'b0, half[15:1]};
            cmp_bot_c <= {1'b0, half[15:1]};
        end else begin
            done <= 1'b0;
            if (accept) begin
                cnt <= 7'd1;
                dtc_bot <= 1'b0;
            end else if (busy) begin
                cnt <= (cnt == T_LAST) ? 7'd0 : cnt + 7'd1;
                if (dtc_done) dtc_bot <= 1'b1;
                if (cnt == T_LAST) begin             // the bottom set is done in this cycle
                    done <= 1'b1;
                    state <= direct_r ? fcs_state : 3'd0;
                    cmp_top_a <= direct_r ? dir_a : top_a;
                    cmp_top_b <= direct_r ? dir_b : top_b;
                    cmp_top_c <= direct_r ? dir_c : top_c;
                    cmp_bot_a <= direct_r ? dir_a : dtc_a;
                    cmp_bot_b <= direct_r ? dir_b : dtc_b;
                    cmp_bot_c <= direct_r ? dir_c : dtc_c;
                end
            end
        end
    end

endmodule

`default_nettype wire
