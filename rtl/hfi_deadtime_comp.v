// hfi_deadtime_comp: dead-time compensation of one compare set (legs a, b, c), bit-exact with
// golden/fpga/deadtime_comp.py `compensate` (docs/spec.md, section 3.6; the project's addition, not in
// Benevieri et al. 2023, which ran its 4 us dead time uncompensated).
//
// For each leg x, with cmp_x the uncompensated compare (0..H) of the half period:
//   hf   = round_shr(HF_AMP * (2*cmp_x - H) * RECIP_H, 32)   predicted HF d-current at the edge (the
//                                                             triangle in phase with -cw, eq. (17))
//   i_d  = I_D_REF - hf,  i_q = I_Q_REF
//   i_al = round_shr(i_d*COS - i_q*SIN, 15),  i_be = round_shr(i_d*SIN + i_q*COS, 15)
//   i_x  = i_al (a),  round_shr(-i_al*2^14 +/- i_be*28378, 15) (b: +, c: -)
//   c    = clamp(shr(i_x * DTC_GAIN, 8), -D, D)
//   cmp' = clamp(cmp_x + (sign_top ? max(c, 0) : min(c, 0)), 0, H)
// DTC_GAIN = 0 gives c = 0 and cmp' = cmp_x (the identity), so a caller needs no bypass.
//
// Ports:
//   start              one-cycle request, accepted when not busy (a start while busy is ignored);
//                      sign_top and cmp_{a,b,c}_in are sampled in the start cycle
//   sign_top           1: sign +1 (compares latched at the carrier top, falling half),
//                      0: sign -1 (carrier bottom, rising half)
//   cmp_{a,b,c}_in u16 uncompensated compares, each in 0..H (precondition: the widths below rely on it)
//   half     u16       H, the effective half period (even, 4..65534)
//   dead     u16       D, the effective dead time in ticks
//   gain     u16       DTC_GAIN (ticks per current LSB, Q8)
//   i_d_ref, i_q_ref   s16 current references (I_D_REF, I_Q_REF)
//   hf_amp   u15       HF_AMP, the predicted HF d-current amplitude
//   sin_q15, cos_q15   s16 Q1.15 SIN, COS of the active angle
//   recip_h  u32       RECIP_H (round(2^32/H) in the firmware; any u32 value is computed exactly)
//                      half .. recip_h are read while busy and must be held stable from the start cycle
//                      to done (hfi_modulator holds them in its sampled registers)
//   cmp_{a,b,c}  u16   compensated compares; valid from done until the next accepted start (the
//                      registers that sampled the inputs, overwritten by the results)
//   busy, done         busy from the cycle after an accepted start to the cycle before done; done is
//                      a one-cycle pulse LATENCY = 37 cycles after start (start in cycle 0, done in
//                      cycle 37); a start in the done cycle is accepted (one set per 37 cycles).
//
// Architecture: one 18x18 signed multiplier (the module's only `*`), a 64-bit accumulator and a fixed
// micro-program of 34 issue slots (`uop` table). Wide products are split into 17-bit unsigned low
// digits (an s18 operand) and a signed top digit, the partial products shifted by 0, 17 or 34 bits.
// Each sum starts from an initial value that already holds its rounding constant (and its other
// terms), so every quantity is written back rounded, without a further adder:
//   i_d    = (I_D_REF*2^32 + 2^31 - 1 - K*(2cmp-H)) >>> 32       (= I_D_REF - round_shr(K*(2cmp-H), 32))
//   i_al   = (2^14 - i_q*SIN + i_d*COS) >>> 15                   (leg a: i_x, saturated)
//   1-i_al = (3*2^14 - 1 + i_q*SIN - i_d*COS) >>> 15             (legs b, c; 1 - floor(y) = floor(-y) + 1)
//   i_be   = (2^14 + i_q*COS + i_d*SIN) >>> 15
//   i_x    = ((1-i_al)*2^14 +/- i_be*28378) >>> 15               (legs b, c)
//   m      = clamp(shr(i_x*gain, 8), 0, D)          top:    cmp' = min(cmp + m, H)
//   m      = clamp((255 - i_x*gain) >>> 8, 0, D)    bottom: cmp' = max(cmp - m, 0)
//            (-min(c, 0) = clamp(-floor(x/256), 0, D) and -floor(x/256) = floor((255 - x)/256))
// with K = HF_AMP*RECIP_H and the constant parts 2^14 -/+ i_q*SIN, 2^14 + i_q*COS computed once per set.
// Pipeline: issue (operand mux, product register p_r) -> accumulate (acc) -> write-back to a 16 x 32
// register file (distributed RAM: 1 write, 2 asynchronous read ports) or to the compare registers; a
// written value is an operand 3 slots after its last product's issue, an initial value 2 slots after.
// The legs are interleaved so the multiplier issues in every slot.
//
// Widths (worst case over all register values, cmp_x in 0..H): K < 2^47; |K*(2cmp-H)| <=
// 32767*(2^32-1)*65534 < 2^63 - 2^49, so the i_d sum fits s64, |hf| <= 2147352578 and |i_d| <=
// 2147385346 (s32); |i_al|, |i_be| <= 2147418114 (s32); |i_x| < 2^33 (s34 in acc[48:15]). Saturating
// i_x to s25 (+-(2^24-1)) does not change c: for DTC_GAIN >= 1, |i_x| >= 2^24 - 1 already gives
// shr(i_x*gain, 8) >= 65535 >= D or <= -65536 < -D, so the clamp to +-D selects the same value. The gain
// sums fit s42.
// Multipliers: 1 (18x18 signed: one MULT18X18D on ECP5, one DSP48E1 on 7-series).

`default_nettype none

module hfi_deadtime_comp (
    input  wire               clk,
    input  wire               rst,
    input  wire               start,
    input  wire               sign_top,
    input  wire        [15:0] cmp_a_in,
    input  wire        [15:0] cmp_b_in,
    input  wire        [15:0] cmp_c_in,
    input  wire        [15:0] half,
    input  wire        [15:0] dead,
    input  wire        [15:0] gain,
    input  wire signed [15:0] i_d_ref,
    input  wire signed [15:0] i_q_ref,
    input  wire        [14:0] hf_amp,
    input  wire signed [15:0] sin_q15,
    input  wire signed [15:0] cos_q15,
    input  wire        [31:0] recip_h,
    output wire        [15:0] cmp_a,
    output wire        [15:0] cmp_b,
    output wire        [15:0] cmp_c,
    output reg                busy,
    output reg                done
);

    localparam integer ACC_W = 64;
    localparam [5:0] LAST_ISSUE = 6'd33;            // last issue slot of the micro-program
    localparam [5:0] LAST_STEP = LAST_ISSUE + 6'd2; // its write-back (issue -> p_r -> acc -> write)

    // Operand A (18-bit signed multiplier input)
    localparam [2:0] A_HF = 3'd0,    // HF_AMP (u15)
                     A_IQ = 3'd1,    // I_Q_REF (s16)
                     A_K0 = 3'd2,    // K[16:0]  (u17)
                     A_K1 = 3'd3,    // K[33:17] (u17)
                     A_K2 = 3'd4,    // K[46:34] (u13)
                     A_R0 = 3'd5,    // register file word [16:0] (u17), port A
                     A_R1 = 3'd6;    // register file word >>> 17 (s15), port A
    // Operand B (18-bit signed multiplier input)
    localparam [2:0] B_RH0 = 3'd0,   // RECIP_H[16:0]  (u17)
                     B_RH1 = 3'd1,   // RECIP_H[31:17] (u15)
                     B_SIN = 3'd2,   // SIN (s16)
                     B_COS = 3'd3,   // COS (s16)
                     B_DIF = 3'd4,   // 2*cmp_x - H (s17) of the leg
                     B_SQ3 = 3'd5,   // 28378 = round(2^15*sqrt(3)/2)
                     B_GN = 3'd6;    // DTC_GAIN (u16); the product is added at the top, subtracted at the bottom
    // Accumulator initial value of the first product of a sum (I_CONT: keep accumulating)
    localparam [2:0] I_CONT = 3'd0,
                     I_R14 = 3'd1,   // 2^14
                     I_C3 = 3'd2,    // 3*2^14 - 1
                     I_ID = 3'd3,    // I_D_REF*2^32 + 2^31 - 1
                     I_RF = 3'd4,    // register file word (port B)
                     I_X = 3'd5,     // register file word (port B) * 2^14
                     I_G = 3'd6,     // 0 at the top, 255 at the bottom
                     I_ZERO = 3'd7;  // 0
    // Write-back
    localparam [2:0] W_NONE = 3'd0,
                     W_RF = 3'd1,    // register file word <= acc >>> (0, 15 or 32) (32 bits)
                     W_IX = 3'd2,    // register file word <= sat25(acc >>> 15)
                     W_CMP = 3'd3,   // compare register of the leg <= compensated compare
                     W_K = 3'd4;     // K <= acc
    localparam [1:0] WS0 = 2'd0, WS15 = 2'd1, WS32 = 2'd2;   // write-back shift
    localparam [1:0] SH0 = 2'd0, SH17 = 2'd1, SH34 = 2'd2;   // product shift
    localparam ADD = 1'b0, SUB = 1'b1;
    localparam [1:0] LA = 2'd0, LB = 2'd1, LC = 2'd2;
    // Register file words: per-set constants, then per leg
    localparam [3:0] R_ALB = 4'd0,   // 2^14 - i_q*SIN
                     R_NALB = 4'd1,  // 3*2^14 - 1 + i_q*SIN
                     R_BEB = 4'd2,   // 2^14 + i_q*COS
                     R_IDA = 4'd3, R_IDB = 4'd4, R_IDC = 4'd5,   // i_d
                     R_NB = 4'd6, R_NC = 4'd7,                   // 1 - i_al (legs b, c)
                     R_BE_B = 4'd8, R_BE_C = 4'd9,              // i_be (legs b, c)
                     R_IXA = 4'd10, R_IXB = 4'd11, R_IXC = 4'd12;  // i_x, saturated to s25
    localparam [3:0] R_0 = 4'd0;     // unused address field

    // ---------------------------------------------------------------- sequencer
    reg [5:0] st;
    always @(posedge clk) begin
        if (rst) begin
            busy <= 1'b0;
            done <= 1'b0;
            st <= 6'd0;
        end else begin
            done <= 1'b0;
            if (busy) begin
                if (st == LAST_STEP) begin
                    busy <= 1'b0;
                    done <= 1'b1;
                    st <= 6'd0;
                end else begin
                    st <= st + 6'd1;
                end
            end else if (start) begin
                busy <= 1'b1;
                st <= 6'd0;
            end
        end
    end
    wire accept = start && !busy;
    wire issue = busy && (st <= LAST_ISSUE);

    // ---------------------------------------------------------------- micro-program
    // {A, B, leg, initial value, add/sub, product shift, register A (operand), register B (initial
    //  value of the first product, or destination of the last), write-back, write-back shift}
    reg [26:0] uop;
    always @* begin
        case (st)
            // K = HF_AMP*RECIP_H; 2^14 - i_q*SIN, 3*2^14 - 1 + i_q*SIN, 2^14 + i_q*COS
            6'd0:  uop = {A_HF, B_RH0, LA, I_ZERO, ADD, SH0,  R_0,     R_0,     W_NONE, WS0};
            6'd1:  uop = {A_HF, B_RH1, LA, I_CONT, ADD, SH17, R_0,     R_0,     W_K,    WS0};
            6'd2:  uop = {A_IQ, B_SIN, LA, I_R14,  SUB, SH0,  R_0,     R_ALB,   W_RF,   WS0};
            6'd3:  uop = {A_IQ, B_SIN, LA, I_C3,   ADD, SH0,  R_0,     R_NALB,  W_RF,   WS0};
            6'd4:  uop = {A_IQ, B_COS, LA, I_R14,  ADD, SH0,  R_0,     R_BEB,   W_RF,   WS0};
            // i_d of legs a, b: (I_D_REF*2^32 + 2^31 - 1 - K*(2cmp-H)) >>> 32
            6'd5:  uop = {A_K0, B_DIF, LA, I_ID,   SUB, SH0,  R_0,     R_0,     W_NONE, WS0};
            6'd6:  uop = {A_K1, B_DIF, LA, I_CONT, SUB, SH17, R_0,     R_0,     W_NONE, WS0};
            6'd7:  uop = {A_K2, B_DIF, LA, I_CONT, SUB, SH34, R_0,     R_IDA,   W_RF,   WS32};
            6'd8:  uop = {A_K0, B_DIF, LB, I_ID,   SUB, SH0,  R_0,     R_0,     W_NONE, WS0};
            6'd9:  uop = {A_K1, B_DIF, LB, I_CONT, SUB, SH17, R_0,     R_0,     W_NONE, WS0};
            6'd10: uop = {A_K2, B_DIF, LB, I_CONT, SUB, SH34, R_0,     R_IDB,   W_RF,   WS32};
            // leg a: i_x = i_al
            6'd11: uop = {A_R0, B_COS, LA, I_RF,   ADD, SH0,  R_IDA,   R_ALB,   W_NONE, WS0};
            6'd12: uop = {A_R1, B_COS, LA, I_CONT, ADD, SH17, R_IDA,   R_IXA,   W_IX,   WS15};
            // i_d of leg c
            6'd13: uop = {A_K0, B_DIF, LC, I_ID,   SUB, SH0,  R_0,     R_0,     W_NONE, WS0};
            6'd14: uop = {A_K1, B_DIF, LC, I_CONT, SUB, SH17, R_0,     R_0,     W_NONE, WS0};
            6'd15: uop = {A_K2, B_DIF, LC, I_CONT, SUB, SH34, R_0,     R_IDC,   W_RF,   WS32};
            // legs b, c: 1 - i_al and i_be
            6'd16: uop = {A_R0, B_COS, LB, I_RF,   SUB, SH0,  R_IDB,   R_NALB,  W_NONE, WS0};
            6'd17: uop = {A_R1, B_COS, LB, I_CONT, SUB, SH17, R_IDB,   R_NB,    W_RF,   WS15};
            6'd18: uop = {A_R0, B_SIN, LB, I_RF,   ADD, SH0,  R_IDB,   R_BEB,   W_NONE, WS0};
            6'd19: uop = {A_R1, B_SIN, LB, I_CONT, ADD, SH17, R_IDB,   R_BE_B, W_RF,   WS15};
            6'd20: uop = {A_R0, B_COS, LC, I_RF,   SUB, SH0,  R_IDC,   R_NALB,  W_NONE, WS0};
            6'd21: uop = {A_R1, B_COS, LC, I_CONT, SUB, SH17, R_IDC,   R_NC,    W_RF,   WS15};
            6'd22: uop = {A_R0, B_SIN, LC, I_RF,   ADD, SH0,  R_IDC,   R_BEB,   W_NONE, WS0};
            6'd23: uop = {A_R1, B_SIN, LC, I_CONT, ADD, SH17, R_IDC,   R_BE_C,  W_RF,   WS15};
            // leg a: the compensated compare
            6'd24: uop = {A_R0, B_GN,  LA, I_G,    ADD, SH0,  R_IXA,   R_0,     W_NONE, WS0};
            6'd25: uop = {A_R1, B_GN,  LA, I_CONT, ADD, SH17, R_IXA,   R_0,     W_CMP,  WS0};
            // legs b (+), c (-): i_x = ((1 - i_al)*2^14 +/- i_be*28378) >>> 15
            6'd26: uop = {A_R0, B_SQ3, LB, I_X,    ADD, SH0,  R_BE_B, R_NB,    W_NONE, WS0};
            6'd27: uop = {A_R1, B_SQ3, LB, I_CONT, ADD, SH17, R_BE_B, R_IXB,   W_IX,   WS15};
            6'd28: uop = {A_R0, B_SQ3, LC, I_X,    SUB, SH0,  R_BE_C,  R_NC,    W_NONE, WS0};
            6'd29: uop = {A_R1, B_SQ3, LC, I_CONT, SUB, SH17, R_BE_C,  R_IXC,   W_IX,   WS15};
            // legs b, c: the compensated compares
            6'd30: uop = {A_R0, B_GN,  LB, I_G,    ADD, SH0,  R_IXB,   R_0,     W_NONE, WS0};
            6'd31: uop = {A_R1, B_GN,  LB, I_CONT, ADD, SH17, R_IXB,   R_0,     W_CMP,  WS0};
            6'd32: uop = {A_R0, B_GN,  LC, I_G,    ADD, SH0,  R_IXC,   R_0,     W_NONE, WS0};
            6'd33: uop = {A_R1, B_GN,  LC, I_CONT, ADD, SH17, R_IXC,   R_0,     W_CMP,  WS0};
            default: uop = {A_HF, B_RH0, LA, I_ZERO, ADD, SH0, R_0,    R_0,     W_NONE, WS0};
        endcase
    end
    wire [2:0] u_a = uop[26:24];
    wire [2:0] u_b = uop[23:21];
    wire [1:0] u_leg = uop[20:19];
    wire [2:0] u_init = uop[18:16];
    wire       u_neg = uop[15];
    wire [1:0] u_sh = uop[14:13];
    wire [3:0] u_ra = uop[12:9];
    wire [3:0] u_rb = uop[8:5];
    wire [2:0] u_wb = uop[4:2];
    wire [1:0] u_ws = uop[1:0];

    // ---------------------------------------------------------------- storage
    reg        [46:0] k_r;            // HF_AMP * RECIP_H
    reg signed [31:0] rf [0:15];      // register file (distributed RAM)
    reg        [15:0] cmp_ra, cmp_rb, cmp_rc;   // sampled compares, then the compensated ones
    reg               top_r;                    // sampled sign_top
    assign cmp_a = cmp_ra;
    assign cmp_b = cmp_rb;
    assign cmp_c = cmp_rc;

    // ---------------------------------------------------------------- issue: operands, product
    wire signed [31:0] rf_a = rf[u_ra];
    wire        [15:0] cmp_i = (u_leg == LA) ? cmp_ra : (u_leg == LB) ? cmp_rb : cmp_rc;
    reg signed [17:0] mul_a, mul_b;
    always @* begin
        case (u_a)
            A_HF:    mul_a = {3'b000, hf_amp};
            A_IQ:    mul_a = {{2{i_q_ref[15]}}, i_q_ref};
            A_K0:    mul_a = {1'b0, k_r[16:0]};
            A_K1:    mul_a = {1'b0, k_r[33:17]};
            A_K2:    mul_a = {5'd0, k_r[46:34]};
            A_R0:    mul_a = {1'b0, rf_a[16:0]};
            default: mul_a = {{3{rf_a[31]}}, rf_a[31:17]};              // A_R1
        endcase
        case (u_b)
            B_RH0:   mul_b = {1'b0, recip_h[16:0]};
            B_RH1:   mul_b = {3'b000, recip_h[31:17]};
            B_SIN:   mul_b = {{2{sin_q15[15]}}, sin_q15};
            B_COS:   mul_b = {{2{cos_q15[15]}}, cos_q15};
            B_DIF:   mul_b = {1'b0, cmp_i, 1'b0} - {2'b00, half};        // in -H..H for cmp in 0..H
            B_SQ3:   mul_b = 18'sd28378;
            default: mul_b = {2'b00, gain};                              // B_GN
        endcase
    end

    reg signed [35:0] p_r;
    reg        s1_v, s2_v;
    reg  [1:0] s1_leg, s2_leg;
    reg  [2:0] s1_init;
    reg        s1_neg;
    reg  [1:0] s1_sh;
    reg  [3:0] s1_rb, s2_rb;
    reg  [2:0] s1_wb, s2_wb;
    reg  [1:0] s1_ws, s2_ws;
    always @(posedge clk) begin
        p_r <= mul_a * mul_b;                    // the module's one multiplier (18x18 signed)
        s1_leg <= u_leg;
        s1_init <= u_init;
        s1_neg <= (u_b == B_GN) ? !top_r : u_neg;
        s1_sh <= u_sh;
        s1_rb <= u_rb;
        s1_wb <= u_wb;
        s1_ws <= u_ws;
        s2_leg <= s1_leg;
        s2_rb <= s1_rb;
        s2_wb <= s1_wb;
        s2_ws <= s1_ws;
        if (rst) begin
            s1_v <= 1'b0;
            s2_v <= 1'b0;
        end else begin
            s1_v <= issue;
            s2_v <= s1_v;
        end
    end

    // ---------------------------------------------------------------- accumulate
    reg signed [ACC_W-1:0] acc;
    wire signed [ACC_W-1:0] p_ext = {{(ACC_W - 36){p_r[35]}}, p_r};
    reg signed [ACC_W-1:0] p_sh;
    always @* begin
        case (s1_sh)
            SH17:    p_sh = p_ext <<< 17;
            SH34:    p_sh = p_ext <<< 34;
            default: p_sh = p_ext;
        endcase
    end
    wire signed [31:0] rf_b = rf[s1_rb];
    reg signed [ACC_W-1:0] base;
    always @* begin
        case (s1_init)
            I_R14:   base = 64'sd16384;
            I_C3:    base = 64'sd49151;
            I_ID:    base = {{(ACC_W - 48){i_d_ref[15]}}, i_d_ref, 32'h7FFF_FFFF};
            I_RF:    base = {{(ACC_W - 32){rf_b[31]}}, rf_b};
            I_X:     base = {{(ACC_W - 46){rf_b[31]}}, rf_b, 14'd0};
            I_G:     base = top_r ? 64'sd0 : 64'sd255;
            I_ZERO:  base = 64'sd0;
            default: base = acc;                                        // I_CONT
        endcase
    end
    always @(posedge clk) begin
        if (s1_v) acc <= s1_neg ? base - p_sh : base + p_sh;
    end

    // ---------------------------------------------------------------- write-back
    // Slices of acc (bounds in the header): i_d = acc[63:32]; round_shr(.., 15) results acc[48:15]
    // (s34 for i_x, s32 otherwise); the gain term acc[41:8] (s34).
    /* verilator lint_off UNUSEDSIGNAL */
    wire signed [33:0] r15 = acc[48:15];
    wire signed [33:0] g8 = acc[41:8];
    /* verilator lint_on UNUSEDSIGNAL */
    wire r15_ovf = !((&r15[33:24]) || !(|r15[33:24]));       // outside -2^24 .. 2^24-1
    wire signed [24:0] r15_sat = !r15_ovf ? r15[24:0] : r15[33] ? -25'sd16777215 : 25'sd16777215;
    reg signed [31:0] wdata;
    always @* begin
        case (s2_ws)
            WS15:    wdata = (s2_wb == W_IX) ? {{7{r15_sat[24]}}, r15_sat} : r15[31:0];
            WS32:    wdata = acc[63:32];
            default: wdata = acc[31:0];
        endcase
    end
    always @(posedge clk) begin
        if (s2_v && (s2_wb == W_RF || s2_wb == W_IX)) rf[s2_rb] <= wdata;
    end
    // m = clamp(g8, 0, D); top: min(cmp + m, H), bottom: max(cmp - m, 0)
    wire        g8_pos = !g8[33] && (|g8[33:0]);
    wire        g8_big = (|g8[32:16]) || (g8[15:0] > dead);
    wire [15:0] m = !g8_pos ? 16'd0 : g8_big ? dead : g8[15:0];
    wire [15:0] cmp_o = (s2_leg == LA) ? cmp_ra : (s2_leg == LB) ? cmp_rb : cmp_rc;
    wire [16:0] cmp_sum = top_r ? {1'b0, cmp_o} + {1'b0, m} : {1'b0, cmp_o} - {1'b0, m};
    wire [15:0] cmp_new = top_r ? ((cmp_sum > {1'b0, half}) ? half : cmp_sum[15:0])
                                : (cmp_sum[16] ? 16'd0 : cmp_sum[15:0]);
    always @(posedge clk) begin
        if (accept) begin
            cmp_ra <= cmp_a_in;
            cmp_rb <= cmp_b_in;
            cmp_rc <= cmp_c_in;
            top_r <= sign_top;
        end else if (s2_v && s2_wb == W_CMP) begin
            case (s2_leg)
                LA:      cmp_ra <= cmp_new;
                LB:      cmp_rb <= cmp_new;
                default: cmp_rc <= cmp_new;
            endcase
        end
        if (s2_v && s2_wb == W_K) k_r <= acc[46:0];
    end

endmodule

`default_nettype wire
