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
//   chain              sampled with start: 1 makes the unit start again by itself in its done cycle, with
//                      sign_top 0 and the cmp_{a,b,c}_in of that cycle (hfi_modulator's top set, then its
//                      bottom set: the done -> start loop then stays inside this module, timing); a start
//                      in that cycle is the same request
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
//                      a one-cycle pulse LATENCY = 39 cycles after start (start in cycle 0, done and
//                      the results in cycle 39); a start in the done cycle is accepted (throughput one
//                      set per 39 cycles). A synchronous reset abandons a computation (no done).
//
// Architecture: one 18x18 signed multiplier (the module's only `*`) with registered operands and
// product, a 49-bit accumulator, and a fixed micro-program of 34 issue slots (the `uop` table, one
// product per slot). Wide operands are split into a 17-bit unsigned low digit (an s18 operand) and a
// signed high digit whose product is shifted by 17. Each sum starts from an initial value that holds
// its rounding constant (and its constant terms), so every result is written back already rounded,
// by a plain slice of the accumulator:
//   i_d    = ((((I_D_REF*2^32 + 2^31 - 1 - K0*D) >>> 17) - K1*D) - K2*D*2^17) >>> 15
//          = (I_D_REF*2^32 + 2^31 - 1 - K*D) >>> 32 = I_D_REF - round_shr(K*D, 32)
//            with D = 2cmp - H, K = HF_AMP*RECIP_H = K2*2^34 + K1*2^17 + K0 (the nested floors are
//            exact: floor((x + 2^17*y)/2^32) = floor((floor(x/2^17) + y)/2^15) for integer y)
//   i_al   = (2^14 - i_q*SIN + i_d*COS) >>> 15                   (leg a: i_x)
//   1-i_al = (3*2^14 - 1 + i_q*SIN - i_d*COS) >>> 15             (legs b, c: 1 - floor(y/2^15) =
//                                                                 floor((2^16 - 1 - y)/2^15))
//   i_be   = (2^14 + i_q*COS + i_d*SIN) >>> 15
//   i_x    = ((1 - i_al)*2^14 +/- i_be*28378) >>> 15             (legs b, c)
//   top:    m = clamp(shr(i_x*gain, 8), 0, D),        cmp' = min(cmp + m, H)
//   bottom: m = clamp((255 - i_x*gain) >>> 8, 0, D),  cmp' = max(cmp - m, 0)
//           (-min(c, 0) = clamp(-floor(x/256), 0, D) and -floor(x/256) = floor((255 - x)/256))
// K and the constant parts 2^14 - i_q*SIN, 3*2^14 - 1 + i_q*SIN, 2^14 + i_q*COS are computed first
// (slots 0..4); the legs are interleaved so that the multiplier issues in every slot.
// Pipeline of a slot issued in cycle t: operand registers (t), product (t+1), accumulator (t+2),
// write-back of a finished sum (t+3); a compare: m (t+3), compensated compare (t+4). A written value is
// an operand from slot t+4 on and an initial value from slot t+3 on (the table respects both).
//
// Widths (worst case over all register values, cmp_x in 0..H): K < 2^47; |K*D| <= 32767*(2^32-1)*65534
// < 2^63, so |hf| <= 2147352578, |i_d| <= 2147385346 (s32); the i_d sum is below 2^48 before its
// >>> 17 and below 2^47 after; |i_al|, |i_be| <= 2147418114 (s32), their sums < 2^47; |i_x| < 2^33
// (s34 in acc[48:15]). Saturating i_x to +-(2^24 - 1) does not change c: for DTC_GAIN >= 1,
// |i_x| >= 2^24 - 1 already gives shr(i_x*gain, 8) >= 65535 >= D or <= -65536 < -D, so the clamp to
// +-D selects the same value; the gain sums then fit s42 (g8 = acc[41:8]).
// Multipliers: 1 (18x18 signed: one MULT18X18D on ECP5, one DSP48E1 on 7-series).

`default_nettype none

module hfi_deadtime_comp (
    input  wire               clk,
    input  wire               rst,
    input  wire               start,
    input  wire               chain,
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

    localparam integer ACC_W = 49;
    localparam [5:0] LAST_ISSUE = 6'd33;            // last issue slot of the micro-program
    localparam [5:0] LAST_STEP = LAST_ISSUE + 6'd4; // its compare (issue -> operands -> product -> acc
                                                    // -> m -> compare)

    // Operand A (18-bit signed multiplier input)
    localparam [2:0] A_HF = 3'd0,    // HF_AMP (u15)
                     A_IQ = 3'd1,    // I_Q_REF (s16)
                     A_K0 = 3'd2,    // K[16:0]  (u17)
                     A_K1 = 3'd3,    // K[33:17] (u17)
                     A_K2 = 3'd4,    // K[46:34] (u13)
                     A_Q0 = 3'd5,    // [16:0] (u17) of the leg's i_d, i_be or i_x
                     A_Q1 = 3'd6;    // >>> 17 (s15) of the leg's i_d, i_be or i_x
    // Operand B (18-bit signed multiplier input)
    localparam [2:0] B_RH0 = 3'd0,   // RECIP_H[16:0]  (u17)
                     B_RH1 = 3'd1,   // RECIP_H[31:17] (u15)
                     B_SIN = 3'd2,   // SIN (s16)
                     B_COS = 3'd3,   // COS (s16)
                     B_DIF = 3'd4,   // 2*cmp_x - H (s17) of the leg
                     B_SQ3 = 3'd5,   // 28378 = round(2^15*sqrt(3)/2)
                     B_GN = 3'd6;    // DTC_GAIN (u16); the product is added at the top, subtracted at the bottom
    // Accumulator initial value of the first product of a sum (I_CONT: keep accumulating)
    localparam [3:0] I_CONT = 4'd0,
                     I_ZG = 4'd1,    // 0; 255 if the product is subtracted (gain sums at the bottom)
                     I_R14 = 4'd2,   // 2^14
                     I_C3 = 4'd3,    // 3*2^14 - 1
                     I_ID = 4'd4,    // I_D_REF*2^32 + 2^31 - 1
                     I_SHR = 4'd5,   // acc >>> 17 (the i_d sum, digit by digit)
                     I_AL = 4'd6,    // 2^14 - i_q*SIN (leg a), 3*2^14 - 1 + i_q*SIN (legs b, c)
                     I_BE = 4'd7,    // 2^14 + i_q*COS
                     I_X = 4'd8;     // (1 - i_al)*2^14 of the leg (b, c)
    // Write-back destination
    localparam [3:0] W_NONE = 4'd0,
                     W_K = 4'd1,     // K = acc (u47)
                     W_AB = 4'd2,    // 2^14 - i_q*SIN = acc; W_NB, W_BB likewise
                     W_NB = 4'd3,
                     W_BB = 4'd4,
                     W_ID = 4'd5,    // i_d = acc >>> 15 (after the >>> 17 of I_SHR)
                     W_NAL = 4'd6,   // 1 - i_al = acc >>> 15 (legs b, c)
                     W_BE = 4'd7,    // i_be = acc >>> 15 (legs b, c)
                     W_IX = 4'd8,    // i_x = sat25(acc >>> 15)
                     W_CMP = 4'd9;   // compensated compare of the leg
    localparam SH0 = 1'b0, SH17 = 1'b1;                       // product shift
    localparam ADD = 1'b0, SUB = 1'b1;
    localparam [1:0] LA = 2'd0, LB = 2'd1, LC = 2'd2;
    // The quantity of the leg whose digits operands A_Q0, A_Q1 take
    localparam [1:0] Q_ID = 2'd0, Q_BE = 2'd1, Q_IX = 2'd2;

    // ---------------------------------------------------------------- sequencer
    // st_next = the step of the next cycle (0 when idle), kept as a register of its own one cycle
    // ahead (st_nq): in each branch below it is (busy && st != LAST_STEP) ? st + 1 : 0 of the state
    // being loaded (timing: the micro-program word is then a table lookup of a register)
    reg [5:0] st, st_nq;
    reg       chain_q;                          // the accepted start asked for the chained one
    // the chained start, done && chain_q, as a register of its own set with done (chain_q does not
    // change while busy; timing: the start logic then takes flip-flops only, docs/boards.md)
    reg       again;
    wire      start_e = start || again;
    wire      accept  = start_e && !busy;
    always @(posedge clk) begin
        if (rst) begin
            busy <= 1'b0;
            done <= 1'b0;
            st <= 6'd0;
            st_nq <= 6'd0;
            chain_q <= 1'b0;
            again <= 1'b0;
        end else begin
            done <= 1'b0;
            again <= 1'b0;
            if (accept)
                chain_q <= chain && !again;
            if (busy) begin
                if (st == LAST_STEP) begin
                    busy <= 1'b0;
                    done <= 1'b1;
                    again <= chain_q;
                    st <= 6'd0;
                    st_nq <= 6'd0;
                end else begin
                    st <= st + 6'd1;
                    st_nq <= (st == LAST_STEP - 6'd1) ? 6'd0 : st + 6'd2;
                end
            end else if (start_e) begin
                busy <= 1'b1;
                st <= 6'd0;
                st_nq <= 6'd1;
            end else begin
                st_nq <= 6'd0;
            end
        end
    end
    wire issue = busy && (st <= LAST_ISSUE);

    // ---------------------------------------------------------------- micro-program
    // {operand A, operand B, leg, quantity of the leg (operands A_Q0/A_Q1), initial value, add/sub,
    //  product shift, write-back}
    // The word of step st is registered (uop) from the step of the next cycle (st_nq, timing): st
    // is 0 whenever the unit is idle.
    reg [19:0] uop_n, uop;
    always @(posedge clk)
        uop <= uop_n;
    always @* begin
        case (rst ? 6'd0 : st_nq)
            // K = HF_AMP*RECIP_H; 2^14 - i_q*SIN, 3*2^14 - 1 + i_q*SIN, 2^14 + i_q*COS
            6'd0:  uop_n = {A_HF,  B_RH0, LA, Q_ID, I_ZG,   ADD, SH0,  W_NONE};
            6'd1:  uop_n = {A_HF,  B_RH1, LA, Q_ID, I_CONT, ADD, SH17, W_K};
            6'd2:  uop_n = {A_IQ,  B_SIN, LA, Q_ID, I_R14,  SUB, SH0,  W_AB};
            6'd3:  uop_n = {A_IQ,  B_SIN, LA, Q_ID, I_C3,   ADD, SH0,  W_NB};
            6'd4:  uop_n = {A_IQ,  B_COS, LA, Q_ID, I_R14,  ADD, SH0,  W_BB};
            // i_d of legs a, b, c: ((((I_D_REF*2^32 + 2^31 - 1 - K0*D) >>> 17) - K1*D) - K2*D*2^17) >>> 15
            // with D = 2cmp - H, = (I_D_REF*2^32 + 2^31 - 1 - K*D) >>> 32 = I_D_REF - round_shr(K*D, 32)
            6'd5:  uop_n = {A_K0,  B_DIF, LA, Q_ID, I_ID,   SUB, SH0,  W_NONE};
            6'd6:  uop_n = {A_K1,  B_DIF, LA, Q_ID, I_SHR,  SUB, SH0,  W_NONE};
            6'd7:  uop_n = {A_K2,  B_DIF, LA, Q_ID, I_CONT, SUB, SH17, W_ID};
            6'd8:  uop_n = {A_K0,  B_DIF, LB, Q_ID, I_ID,   SUB, SH0,  W_NONE};
            6'd9:  uop_n = {A_K1,  B_DIF, LB, Q_ID, I_SHR,  SUB, SH0,  W_NONE};
            6'd10: uop_n = {A_K2,  B_DIF, LB, Q_ID, I_CONT, SUB, SH17, W_ID};
            6'd11: uop_n = {A_K0,  B_DIF, LC, Q_ID, I_ID,   SUB, SH0,  W_NONE};
            6'd12: uop_n = {A_K1,  B_DIF, LC, Q_ID, I_SHR,  SUB, SH0,  W_NONE};
            6'd13: uop_n = {A_K2,  B_DIF, LC, Q_ID, I_CONT, SUB, SH17, W_ID};
            // leg a: i_x = i_al = (2^14 - i_q*SIN + i_d*COS) >>> 15
            6'd14: uop_n = {A_Q0,  B_COS, LA, Q_ID, I_AL,   ADD, SH0,  W_NONE};
            6'd15: uop_n = {A_Q1,  B_COS, LA, Q_ID, I_CONT, ADD, SH17, W_IX};
            // legs b, c: i_be = (2^14 + i_q*COS + i_d*SIN) >>> 15,
            // 1 - i_al = (3*2^14 - 1 + i_q*SIN - i_d*COS) >>> 15
            6'd16: uop_n = {A_Q0,  B_SIN, LB, Q_ID, I_BE,   ADD, SH0,  W_NONE};
            6'd17: uop_n = {A_Q1,  B_SIN, LB, Q_ID, I_CONT, ADD, SH17, W_BE};
            6'd18: uop_n = {A_Q0,  B_SIN, LC, Q_ID, I_BE,   ADD, SH0,  W_NONE};
            6'd19: uop_n = {A_Q1,  B_SIN, LC, Q_ID, I_CONT, ADD, SH17, W_BE};
            6'd20: uop_n = {A_Q0,  B_COS, LB, Q_ID, I_AL,   SUB, SH0,  W_NONE};
            6'd21: uop_n = {A_Q1,  B_COS, LB, Q_ID, I_CONT, SUB, SH17, W_NAL};
            6'd22: uop_n = {A_Q0,  B_COS, LC, Q_ID, I_AL,   SUB, SH0,  W_NONE};
            6'd23: uop_n = {A_Q1,  B_COS, LC, Q_ID, I_CONT, SUB, SH17, W_NAL};
            // legs b (+), c (-): i_x = ((1 - i_al)*2^14 +/- i_be*28378) >>> 15
            6'd24: uop_n = {A_Q0,  B_SQ3, LB, Q_BE, I_X,    ADD, SH0,  W_NONE};
            6'd25: uop_n = {A_Q1,  B_SQ3, LB, Q_BE, I_CONT, ADD, SH17, W_IX};
            6'd26: uop_n = {A_Q0,  B_SQ3, LC, Q_BE, I_X,    SUB, SH0,  W_NONE};
            6'd27: uop_n = {A_Q1,  B_SQ3, LC, Q_BE, I_CONT, SUB, SH17, W_IX};
            // the compensated compares: i_x*DTC_GAIN (+ at the top, 255 - .. at the bottom), m, cmp'
            6'd28: uop_n = {A_Q0,  B_GN,  LA, Q_IX, I_ZG,   ADD, SH0,  W_NONE};
            6'd29: uop_n = {A_Q1,  B_GN,  LA, Q_IX, I_CONT, ADD, SH17, W_CMP};
            6'd30: uop_n = {A_Q0,  B_GN,  LB, Q_IX, I_ZG,   ADD, SH0,  W_NONE};
            6'd31: uop_n = {A_Q1,  B_GN,  LB, Q_IX, I_CONT, ADD, SH17, W_CMP};
            6'd32: uop_n = {A_Q0,  B_GN,  LC, Q_IX, I_ZG,   ADD, SH0,  W_NONE};
            6'd33: uop_n = {A_Q1,  B_GN,  LC, Q_IX, I_CONT, ADD, SH17, W_CMP};
            default: uop_n = {A_HF, B_RH0, LA, Q_ID, I_ZG, ADD, SH0, W_NONE};
        endcase
    end
    wire [2:0] u_a = uop[19:17];
    wire [2:0] u_b = uop[16:14];
    wire [1:0] u_leg = uop[13:12];
    wire [1:0] u_q = uop[11:10];
    wire [3:0] u_init = uop[9:6];
    wire       u_neg = uop[5];
    wire       u_sh = uop[4];
    wire [3:0] u_wb = uop[3:0];

    // ---------------------------------------------------------------- storage
    reg        [46:0] k_r;                      // HF_AMP * RECIP_H
    reg signed [31:0] ab_r, nb_r, bb_r;         // 2^14 - i_q*SIN, 3*2^14 - 1 + i_q*SIN, 2^14 + i_q*COS
    reg signed [31:0] id_r [0:2];               // i_d per leg
    reg signed [31:0] nal_r [0:1];              // 1 - i_al of legs b (0), c (1)
    reg signed [31:0] be_r [0:1];               // i_be of legs b (0), c (1)
    reg signed [24:0] ix_r [0:2];               // i_x per leg, saturated to +-(2^24 - 1)
    reg        [15:0] cmp_ra, cmp_rb, cmp_rc;   // sampled compares, then the compensated ones
    reg               top_r;                    // sampled sign_top
    assign cmp_a = cmp_ra;
    assign cmp_b = cmp_rb;
    assign cmp_c = cmp_rc;

    // ---------------------------------------------------------------- issue: operands, product
    // 2 cmp - H per leg, formed when the compares are sampled (timing: the subtraction was on the path from
    // the micro-program word to the multiplier's operand register). B_DIF is read in slots 5..13 only, before
    // W_CMP rewrites a compare (slots 29..33), and half is held from the start cycle: the same values.
    reg  signed [17:0] dif_ra, dif_rb, dif_rc;
    wire signed [17:0] dif_i = (u_leg == LA) ? dif_ra : (u_leg == LB) ? dif_rb : dif_rc;
    wire signed [31:0] id_i = id_r[u_leg];
    wire signed [31:0] be_i = be_r[u_leg == LC];
    wire signed [24:0] ix_i = ix_r[u_leg];
    // the per-leg quantity that operand A digits are taken from (i_d, i_be or i_x)
    wire signed [31:0] q_i = (u_q == Q_ID) ? id_i : (u_q == Q_BE) ? be_i : {{7{ix_i[24]}}, ix_i};
    reg signed [17:0] mul_a, mul_b;
    always @* begin
        case (u_a)
            A_HF:    mul_a = {3'b000, hf_amp};
            A_IQ:    mul_a = {{2{i_q_ref[15]}}, i_q_ref};
            A_K0:    mul_a = {1'b0, k_r[16:0]};
            A_K1:    mul_a = {1'b0, k_r[33:17]};
            A_K2:    mul_a = {5'd0, k_r[46:34]};
            A_Q0:    mul_a = {1'b0, q_i[16:0]};
            default: mul_a = {{3{q_i[31]}}, q_i[31:17]};                 // A_Q1
        endcase
        case (u_b)
            B_RH0:   mul_b = {1'b0, recip_h[16:0]};
            B_RH1:   mul_b = {3'b000, recip_h[31:17]};
            B_SIN:   mul_b = {{2{sin_q15[15]}}, sin_q15};
            B_COS:   mul_b = {{2{cos_q15[15]}}, cos_q15};
            B_DIF:   mul_b = dif_i;                                      // 2 cmp - H, in -H..H
            B_SQ3:   mul_b = 18'sd28378;
            default: mul_b = {2'b00, gain};                              // B_GN
        endcase
    end

    // stage 0: operand registers (the multiplier's inputs come straight from flip-flops)
    reg        s0_v;
    reg  [1:0] s0_leg;
    reg  [3:0] s0_init;
    reg        s0_neg;
    reg        s0_sh;
    reg  [3:0] s0_wb;
    // stage 1: product (operand and product registers in hfi_mul18)
    wire signed [35:0] p_r;
    hfi_mul18 u_mul (.clk(clk), .a(mul_a), .b(mul_b), .p(p_r));
    reg        s1_v, s2_v;
    reg  [1:0] s1_leg, s2_leg;
    reg  [3:0] s1_init;
    reg        s1_neg;
    reg        s1_sh;
    reg  [3:0] s1_wb, s2_wb;
    always @(posedge clk) begin
        s0_leg <= u_leg;
        s0_init <= u_init;
        s0_neg <= (u_b == B_GN) ? !top_r : u_neg;    // gain products: + at the top, - at the bottom
        s0_sh <= u_sh;
        s0_wb <= u_wb;
        s1_leg <= s0_leg;
        s1_init <= s0_init;
        s1_neg <= s0_neg;
        s1_sh <= s0_sh;
        s1_wb <= s0_wb;
        s2_leg <= s1_leg;
        s2_wb <= s1_wb;
        if (rst) begin
            s0_v <= 1'b0;
            s1_v <= 1'b0;
            s2_v <= 1'b0;
        end else begin
            s0_v <= issue;
            s1_v <= s0_v;
            s2_v <= s1_v;
        end
    end

    // ---------------------------------------------------------------- accumulate
    reg signed [ACC_W-1:0] acc;
    wire signed [ACC_W-1:0] p_ext = {{(ACC_W - 36){p_r[35]}}, p_r};
    wire signed [ACC_W-1:0] p_sh = s1_sh ? p_ext <<< 17 : p_ext;
    // Initial values that do not depend on acc are selected one stage early, in stage 0, into base_r
    // (timing): they are read one cycle before the accumulation, so a written value is an initial value
    // from slot t+3 on (the table respects it: the nearest case is 1 - i_al of leg b, written by slot
    // 21 and used by slot 24, of leg c by 23 and 26).
    wire signed [31:0] al_base = (s0_leg == LA) ? ab_r : nb_r;
    wire signed [31:0] nal_base = nal_r[s0_leg == LC];
    reg signed [ACC_W-1:0] base_n, base_r;
    always @* begin
        case (s0_init)
            I_ZG:    base_n = s0_neg ? 49'sd255 : 49'sd0;
            I_R14:   base_n = 49'sd16384;
            I_C3:    base_n = 49'sd49151;
            I_ID:    base_n = {{(ACC_W - 48){i_d_ref[15]}}, i_d_ref, 32'h7FFF_FFFF};
            I_AL:    base_n = {{(ACC_W - 32){al_base[31]}}, al_base};
            I_BE:    base_n = {{(ACC_W - 32){bb_r[31]}}, bb_r};
            default: base_n = {{(ACC_W - 46){nal_base[31]}}, nal_base, 14'd0};   // I_X
        endcase
    end
    always @(posedge clk)
        base_r <= base_n;
    wire signed [ACC_W-1:0] base = (s1_init == I_CONT) ? acc : (s1_init == I_SHR) ? acc >>> 17 : base_r;
    // one adder: base - p = base + ~p + 1 (the +1 as the carry into an extra low bit)
    wire signed [ACC_W-1:0] p_op = p_sh ^ {ACC_W{s1_neg}};
    /* verilator lint_off UNUSEDSIGNAL */  // bit 0 is the carry-in helper
    wire [ACC_W:0] acc_s = {base, 1'b1} + {p_op, s1_neg};
    /* verilator lint_on UNUSEDSIGNAL */
    always @(posedge clk) begin
        if (s1_v) acc <= acc_s[ACC_W:1];
    end

    // ---------------------------------------------------------------- write-back
    // Slices of acc (bounds in the header): acc >>> 15 results acc[48:15] (s34 for i_x, s32
    // otherwise); the gain term acc[41:8] (s34).
    /* verilator lint_off UNUSEDSIGNAL */
    wire signed [33:0] r15 = acc[48:15];
    wire signed [33:0] g8 = acc[41:8];
    /* verilator lint_on UNUSEDSIGNAL */
    wire r15_ovf = !((&r15[33:24]) || !(|r15[33:24]));       // outside -2^24 .. 2^24-1
    wire signed [24:0] r15_sat = !r15_ovf ? r15[24:0] : r15[33] ? -25'sd16777215 : 25'sd16777215;
    // W_CMP, two stages. Stage 3: m = clamp(g8, 0, D), the compare c0 of the leg and its limit
    // (top: H - c0, bottom: c0); stage 4: top: c0 + m > H ? H : c0 + m, bottom: c0 - m < 0 ? 0 : c0 - m.
    // (g8 = 0 needs no case of its own: it is not big, so m = g8[15:0] = 0; the zeroing is then the
    // sign bit alone, a register bit: timing, it drives the reset of the 16 m_r flip-flops)
    wire        g8_big = (|g8[32:16]) || (g8[15:0] > dead);
    wire [15:0] cmp_o = (s2_leg == LA) ? cmp_ra : (s2_leg == LB) ? cmp_rb : cmp_rc;
    reg  [15:0] m_r, c0_r, lim_r;
    reg         s3_v;
    reg   [1:0] s3_leg;
    always @(posedge clk) begin
        m_r <= g8[33] ? 16'd0 : g8_big ? dead : g8[15:0];
        c0_r <= cmp_o;
        lim_r <= top_r ? half - cmp_o : cmp_o;
        s3_leg <= s2_leg;
        s3_v <= !rst && s2_v && s2_wb == W_CMP;
    end
    wire [15:0] cmp_new = (m_r > lim_r) ? (top_r ? half : 16'd0) : top_r ? c0_r + m_r : c0_r - m_r;
    always @(posedge clk) begin
        if (s2_v) begin
            case (s2_wb)
                W_K:  k_r <= acc[46:0];
                W_AB: ab_r <= acc[31:0];
                W_NB: nb_r <= acc[31:0];
                W_BB: bb_r <= acc[31:0];
                W_ID: id_r[s2_leg] <= r15[31:0];
                W_NAL: nal_r[s2_leg == LC] <= r15[31:0];
                W_BE: be_r[s2_leg == LC] <= r15[31:0];
                W_IX: ix_r[s2_leg] <= r15_sat;
                default: ;
            endcase
        end
    end
    always @(posedge clk) begin
        if (accept) begin
            cmp_ra <= cmp_a_in;
            cmp_rb <= cmp_b_in;
            cmp_rc <= cmp_c_in;
            dif_ra <= {1'b0, cmp_a_in, 1'b0} - {2'b00, half};
            dif_rb <= {1'b0, cmp_b_in, 1'b0} - {2'b00, half};
            dif_rc <= {1'b0, cmp_c_in, 1'b0} - {2'b00, half};
            top_r <= sign_top && !again;
        end else if (s3_v) begin
            case (s3_leg)
                LA:      cmp_ra <= cmp_new;
                LB:      cmp_rb <= cmp_new;
                default: cmp_rc <= cmp_new;
            endcase
        end
    end

endmodule

`default_nettype wire
