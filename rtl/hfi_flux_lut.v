`default_nettype none
// hfi_flux_lut: flux-map look-up table with incremental inductances and their derivatives along the
// rotation, a hardware accelerator beside the RISC-V soft core. It reads its five tables from the SoC's
// main RAM (where the firmware's configuration block holds them) through the RAM's data port.
//
// Implements the firmware's flux LUT of the 003 estimator (Varatharajan et al. 2020, Fig. 2,
// eqs. (8), (12)), bit for bit equal to golden/firmware/flux_lut.py `lut_point(lut, i_d, i_q)` (C twin:
// firmware/src/control.c `fw_lut_point`); `lut_flux` is the (lam_d, lam_q) of the same operation.
// The golden module docstring is the specification; in short, with x = warp(|i_d|), y = warp(|i_q|),
// warp(v) = v < knee ? v : knee + ((v - knee) >> coarse):
//   c = min(x >> shift, n_d - 2), fx = x - (c << shift)       (r, fy likewise with n_q)
//   k = r*n_d + c; corners t00 = t[k], t01 = t[k+1], t10 = t[k+n_d], t11 = t[k+n_d+1]
//   bilinear(t, fx, fy): a = t00 + shr((t01-t00) fx, s), b = t10 + shr((t11-t10) fx, s),
//                        a + shr((b-a) fy, s)
//   lam_d = sd * (bilinear(t_d, fx, fy) << f_shift), lam_q = sq * (...)   (fx, fy beyond 2^s:
//                                                                         extrapolation)
//   fxc = min(fx, 2^s), fyc = min(fy, 2^s):
//   l_d = bilinear(t_ld, fxc, fyc), l_q = bilinear(t_lq, ...), l_dq = sd sq bilinear(t_ldq, ...)
//   gx = (t01-t00)(2^s-fyc) + (t11-t10) fyc, gy = (t10-t00)(2^s-fxc) + (t11-t01) fxc (per table)
//   dl_d = shr(-i_q sd gx(t_ld) wx + i_d sq gy(t_ld) wy, 2s + coarse)  (dl_q from t_lq)
//   dl_dq = shr(-|i_q| gx(t_ldq) wx + |i_d| gy(t_ldq) wy, 2s + coarse)
//   sd = sgn i_d, sq = sgn i_q (+1 for 0), wx = 2^coarse if |i_d| < knee else 1, wy likewise.
//
// Algorithm (one shared multiplier, a fixed schedule of 30 products):
//   With d1 = t01-t00, e1 = t10-t00, D = t11-t10-t01+t00 (the cell's second difference):
//   gx = (d1 << s) + D fyc, gy = (e1 << s) + D fxc, and (t11-t10) fxc = d1 fxc + D fxc, so an
//   inductance table takes 4 products (d1 fxc, D fxc, D fyc, (b-a) fyc), a flux table 3
//   (d1 fx, (t11-t10) fx, (b-a) fy). The derivative numerators b * g (|b| <= 2^18, g up to s45)
//   are split g = g_hi 2^21 + g_lo (g_lo unsigned 21 bits): 2 products each, 4 per table, summed
//   into an accumulator with the shifts 21 and log2(wx) / log2(wy) (shifting the product is exact).
//   Total 2*3 + 3*4 + 3*4 = 30 products, one issued per clock, on one signed 36 x 20 multiplier
//   (operands registered, product registered: 2 cycles; ECP5: 4 MULT18X18D).
//   Tables: 4 corners x 5 tables = 20 reads of the RAM, one per clock (pipelined through the RAM's
//   one-clock read latency), in the order corner 00 of t_d, t_q, t_ld, t_lq, t_ldq, then corner 01 of
//   the five, then 10, then 11. Read address: the table's byte base + 2 index (t_d, t_q) or + 4 index,
//   word = byte >> 2; an int16 entry is the half of its word selected by byte bit 1 (little endian),
//   sign-extended. r*n_d is a shift-and-add (no multiplier). No block RAM of its own.
//
// Parameters:
//   RAM_AW      word-address width of the RAM (default 14: 64 KiB of 32-bit words); the bases are
//               RAM_AW + 2 bit byte addresses, mem_addr an RAM_AW bit word address. Byte addresses
//               wrap modulo 2^(RAM_AW + 2) (a table must lie inside the RAM).
//
// Ports:
//   clk, rst     clock; synchronous active-high reset: aborts a look-up (busy, done and mem_en drop, no
//                done follows for it), outputs to 0.
//   base_d, base_q, base_ld, base_lq, base_ldq
//                byte address in the RAM of entry 0 of t_d, t_q (int16: entry i at base + 2 i; any even
//                base, 2 mod 4 allowed), t_ld, t_lq, t_ldq (int32: entry i at base + 4 i; base a
//                multiple of 4). Entry index = r*n_d + c (golden order). Read in the busy cycles only
//                (cycles 6..25 of a look-up), held stable by the user while busy; the tables' contents
//                likewise (they are read in cycles 7..26).
//   mem_en, mem_addr, mem_rdata
//                read port of the RAM: synchronous, one clock latency (mem_rdata in cycle t + 1 is the
//                word at mem_addr of cycle t when mem_en was high in t; hfi_ram's port b). mem_en and
//                mem_addr are registers; mem_en is high in exactly 20 cycles of a look-up (cycles 7..26
//                after the start cycle) and low whenever busy is low (and in the cycle after a reset);
//                mem_addr is unspecified while mem_en is low. mem_rdata is used only in the cycle after
//                each mem_en cycle (cycles 8..27). Why the port is free then: in the SoC the CPU's
//                LUT_IQ write that starts the look-up is held (not answered) until done, so the CPU
//                waits on its data bus and makes no RAM access while the unit reads (hfi_soc_acc,
//                hfi_soc).
//   n_d, n_q, shift, knee, coarse, f_shift
//                the golden FluxLut fields; read in the busy cycles only, held stable by the user
//                while busy (the start cycle itself does not read them).
//   start        start a look-up of (i_d, i_q), sampled in this cycle. Accepted only when busy = 0;
//                a start while busy is ignored.
//   busy         high from the cycle after an accepted start up to the cycle before done
//                (LATENCY - 1 cycles); low in the done cycle: a start in the done cycle is accepted.
//   done         one-cycle pulse, exactly LATENCY = 59 cycles after the start cycle.
//   lam_d .. dl_dq  s64, the LutPoint fields, valid from the done cycle, held until the next done.
//
// Timing (cycle 0 = start cycle; register loads at the end of the named cycle):
//   0 i_d, i_q; 1 |i|, signs, derivative multiplicands; 2 |i| < knee, (|i| - knee) >> coarse;
//   3 warp x, y; 4 c, r, fx, fy; 5 fxc, fyc, partial sums of r*n_d (+c); 6 k; 7 k+1, k+n_d, k+n_d+1;
//   6..25 read addresses (mem_addr, mem_en loaded; read j: table j mod 5, corner j div 5, computed in
//   6 + j from k = the partial sums' sum or the registered k+1, k+n_d, k+n_d+1); 7..26 mem_en high;
//   8..27 mem_rdata captured into the corner registers; 28 d1, e1, D of the inductance tables;
//   products issued at 26..55: 26,27 d1 fx (t_d, t_q); 28..30 d1 fxc (t_ld, t_lq, t_ldq);
//   31,32 (t11-t10) fx; 33..35 D fxc; 36..38 D fyc; 39..50 the derivative products
//   (per table gx_lo bx, gx_hi bx, gy_lo by, gy_hi by); 51,52 (b-a) fy; 53..55 (b-a) fyc;
//   each product is in the product register P during issue + 2 and used there (the derivative
//   products: shifted there into psh, accumulated at issue + 3).
//   Shared shifters instead of one per table: e1 << s, d1 << s one cycle ahead of the gy, gx sums
//   (34..39); shr((t11-t10) fxc, s) of the inductance tables in 38..40 (b in 39..41); each derivative
//   accumulator shifted by 2s + coarse after its last sum (46, 50, 54); the flux's
//   sgn * (lam << f_shift) in 55 (lam_d), 56 (lam_q). 58 output registers, done = 1 in cycle 59.
//   LATENCY = 59 cycles (1.18 us at 50 MHz). Throughput one look-up per 59 cycles.
//   (The schedule after the reads is the one of the earlier block-RAM version shifted by 16 cycles:
//   the last inductance corner is in its register from cycle 28 instead of 12.)
//
// Validity ranges (the C twin's, control.h; the test draws within them):
//   |i_d|, |i_q| <= 2^18; n_d, n_q 2..64 with n_d n_q <= 1024 (golden LUT_MAX_POINTS: the corner
//   indices are 10 bits); shift <= 12; coarse <= 7 (the spec: <= 4); f_shift any (the spec: <= 16);
//   knee any value (compared on 32 bits); flux tables s16; inductance tables any s32 (the spec:
//   |t| < 2^28); table bases as above, every entry inside the RAM.
//   Outside these the results are unspecified.
//
// Widths (every intermediate exact over the ranges above; s = shift, fx, fy <= 2^18, fxc, fyc <= 2^s):
//   x, y, fx, fy <= 2^18: 19 bits unsigned; fxc, fyc <= 2^12: 13 bits; multiplier B operands
//   (fx, fy, fxc, fyc, +-i) in s20.
//   flux: |t01-t00| < 2^16 -> |d1 fx| < 2^34, |a|, |b| < 2^34 + 2^15 (s36);
//     |b-a| <= |t10-t00| + |t11-t10-t01+t00| fx 2^-s + 1 < 2^16 + 2^17 2^18 <= 2^35 (s36 operand);
//     |(b-a) fy| < 2^53, lam < 2^54 (s64 reg). lam << f_shift is returned modulo 2^64: it exceeds
//     int64 only for shift <= 3 far beyond the grid (|lam| < 2^(53 - 2s)), where golden's Python
//     integers are unbounded and the C twin's int64 overflows.
//   inductance (any s32): a, b, l between the corners (s32); |d1|, |e1| < 2^32 (s33),
//     |D| < 2^33 (s34); |d1 fxc|, |D fxc| < 2^45; |gx|, |gy| <= max|t_ij - t_kl| 2^s < 2^44 (s46 regs);
//     |g_hi| < 2^24 (s36 operand), g_lo < 2^21; |b g_hi| < 2^42, shifted by <= 21 + 7;
//     the numerator |.| < 2 * 2^18 2^44 2^7 = 2^70 (s72 accumulator); dl = acc >>> (2s + coarse)
//     with |dl| < 2^(52 - s): int64.
//   Largest product: s36 x s20 -> s56 (|.| < 2^53). Shifts: P >>> s, P <<< (21 + coarse) (<= 28),
//   acc >>> (2s + coarse) (<= 31, 5 bits), lam <<< f_shift (mod 2^64).

module hfi_flux_lut #(
    parameter RAM_AW = 14                   // word-address width of the RAM (64 KiB of 32-bit words)
) (
    input  wire               clk,
    input  wire               rst,
    input  wire [RAM_AW+1:0]  base_d,
    input  wire [RAM_AW+1:0]  base_q,
    input  wire [RAM_AW+1:0]  base_ld,
    input  wire [RAM_AW+1:0]  base_lq,
    input  wire [RAM_AW+1:0]  base_ldq,
    output wire               mem_en,
    output wire [RAM_AW-1:0]  mem_addr,
    input  wire [31:0]        mem_rdata,
    input  wire        [6:0]  n_d,
    input  wire        [6:0]  n_q,
    input  wire        [3:0]  shift,
    input  wire        [31:0] knee,
    input  wire        [2:0]  coarse,
    input  wire        [4:0]  f_shift,
    input  wire               start,
    input  wire signed [31:0] i_d,
    input  wire signed [31:0] i_q,
    output wire               busy,
    output reg                done,
    output reg  signed [63:0] lam_d, lam_q, l_d, l_q, l_dq, dl_d, dl_q, dl_dq
);

    // Cycles from the start cycle to the done cycle (documentation / testbench constant).
    /* verilator lint_off UNUSEDPARAM */
    localparam integer LATENCY = 59;
    /* verilator lint_on UNUSEDPARAM */

    localparam integer IW = 10;           // table index width (n_d n_q <= 1024)
    localparam integer BW = RAM_AW + 2;   // byte-address width

    // ---- schedule (cycle numbers after the start cycle) ----------------------------------------------
    localparam [5:0] S_ABS = 6'd1, S_KNEE = 6'd2, S_WARP = 6'd3, S_CELL = 6'd4, S_FRAC = 6'd5,
                     S_K = 6'd6, S_RD0 = 6'd7, S_DIFF = 6'd28, S_LAST = 6'd58;
    localparam [5:0] S_ADR = 6'd6,        // read address j (0..19) computed in S_ADR + j, RAM read in
                                          // S_ADR + j + 1, mem_rdata captured in S_ADR + j + 2
                     S_NRD = 6'd20;       // reads per look-up
    localparam [5:0] S_B = 6'd38,         // bsh of the inductance lane j loaded in S_B + j, b in S_B + j + 1
                     S_DL = 6'd46,        // acc of lane j shifted to dl in S_DL + 4 j (after its last sum)
                     S_LAM = 6'd55;       // lam of flux lane j transformed in S_LAM + j
    // products: the block-RAM version's schedule + 16 (nsel below relies on I_N's low 4 bits only)
    localparam [5:0] I_F1 = 6'd26, I_L1 = 6'd28, I_F2 = 6'd31, I_DX = 6'd33, I_DY = 6'd36, I_N = 6'd39,
                     I_F3 = 6'd51, I_L3 = 6'd53;
    localparam [5:0] WB = 6'd2;           // a product issued in cycle t is in P during t + 2

    localparam integer GW = 46;           // gx, gy, d1 fxc registers
    localparam integer ACW = 72;          // derivative accumulators

    // ---- control ---------------------------------------------------------------------------------------
    reg       busy_r;
    reg [5:0] st;                         // cycle number of the running look-up (1 .. S_LAST)
    assign busy = busy_r;

    always @(posedge clk) begin
        if (rst) begin
            busy_r <= 1'b0;
            st <= 6'd0;
        end else if (!busy_r) begin
            if (start) begin
                busy_r <= 1'b1;
                st <= 6'd1;
            end
        end else begin
            st <= st + 6'd1;
            if (st == S_LAST)
                busy_r <= 1'b0;
        end
    end

    // en(t): the running look-up is in cycle t
    wire [63:0] at;                       // one-hot of st while busy
    genvar gi;
    generate
        for (gi = 0; gi < 64; gi = gi + 1) begin : g_at
            localparam [5:0] T = gi;
            assign at[gi] = busy_r && st == T;
        end
    endgenerate

    // ---- cell: warp, cell index, fractions -------------------------------------------------------------
    reg signed [31:0] id_r, iq_r;
    reg               sd, sq;             // i_d < 0, i_q < 0
    reg        [18:0] ax, ay;             // |i_d|, |i_q| (<= 2^18)
    reg signed [19:0] bx_s, by_s;         // -i_q sd, i_d sq
    reg signed [19:0] bx_a, by_a;         // -|i_q|, |i_d|
    reg               ltx, lty;           // |i| < knee
    reg        [18:0] ex, ey;             // (|i| - knee) >> coarse (used when |i| >= knee)
    reg        [18:0] x, y;               // warped coordinates
    reg         [5:0] c, r;               // cell column, row
    reg        [18:0] fx, fy;             // fractions (beyond 2^s outside the grid)
    reg        [12:0] fxc, fyc;           // fractions clamped to 2^s
    reg        [12:0] rna, rnb;           // partial sums of r*n_d + c
    reg        [12:0] k;                  // first corner
    reg      [IW-1:0] k1, kn, kn1;        // k + 1, k + n_d, k + n_d + 1
    reg        [18:0] nd2s, nq2s;         // (n_d - 2) << s, (n_q - 2) << s (configuration, every cycle)

    wire       [12:0] one = 13'd1 << shift;
    wire       [18:0] mask = {6'd0, one - 13'd1};
    wire        [6:0] nd2 = n_d - 7'd2;
    wire        [6:0] nq2 = n_q - 7'd2;
    wire       [31:0] id_abs = id_r[31] ? -id_r : id_r;
    wire       [31:0] iq_abs = iq_r[31] ? -iq_r : iq_r;
    wire       [31:0] id_neg = -id_r;
    wire       [31:0] iq_neg = -iq_r;
    wire       [18:0] qx = x >> shift;
    wire       [18:0] qy = y >> shift;
    wire              limx = qx > {12'd0, nd2};
    wire              limy = qy > {12'd0, nq2};
    wire       [18:0] dkx = ax - knee[18:0];
    wire       [18:0] dky = ay - knee[18:0];

    // r * n_d as a shift-and-add (r <= 62, n_d <= 64: the product < 2^13)
    wire       [12:0] r13 = {7'd0, r};
    wire       [12:0] pp0 = n_d[0] ? r13 : 13'd0;
    wire       [12:0] pp1 = n_d[1] ? r13 << 1 : 13'd0;
    wire       [12:0] pp2 = n_d[2] ? r13 << 2 : 13'd0;
    wire       [12:0] pp3 = n_d[3] ? r13 << 3 : 13'd0;
    wire       [12:0] pp4 = n_d[4] ? r13 << 4 : 13'd0;
    wire       [12:0] pp5 = n_d[5] ? r13 << 5 : 13'd0;
    wire       [12:0] pp6 = (n_d[6] ? r13 << 6 : 13'd0) | {7'd0, c};   // low 6 bits of r << 6 are 0

    wire       [12:0] k_sum = rna + rnb;
    wire       [12:0] k_1 = k + 13'd1;                    // corner indices: < n_d n_q <= 1024
    wire       [12:0] k_n = k + {6'd0, n_d};
    wire       [12:0] k_n1 = k + {6'd0, n_d} + 13'd1;

    always @(posedge clk) begin
        nd2s <= {12'd0, nd2} << shift;
        nq2s <= {12'd0, nq2} << shift;
        if (!busy_r && start) begin
            id_r <= i_d;
            iq_r <= i_q;
        end
        if (at[S_ABS]) begin
            sd <= id_r[31];
            sq <= iq_r[31];
            ax <= id_abs[18:0];
            ay <= iq_abs[18:0];
            bx_s <= id_r[31] ? iq_r[19:0] : iq_neg[19:0];
            by_s <= iq_r[31] ? id_neg[19:0] : id_r[19:0];
            bx_a <= iq_r[31] ? iq_r[19:0] : iq_neg[19:0];
            by_a <= id_abs[19:0];
        end
        if (at[S_KNEE]) begin
            ltx <= {13'd0, ax} < knee;
            lty <= {13'd0, ay} < knee;
            ex <= dkx >> coarse;
            ey <= dky >> coarse;
        end
        if (at[S_WARP]) begin
            x <= ltx ? ax : knee[18:0] + ex;
            y <= lty ? ay : knee[18:0] + ey;
        end
        if (at[S_CELL]) begin
            c <= limx ? nd2[5:0] : qx[5:0];
            r <= limy ? nq2[5:0] : qy[5:0];
            fx <= limx ? x - nd2s : x & mask;
            fy <= limy ? y - nq2s : y & mask;
        end
        if (at[S_FRAC]) begin
            fxc <= (fx > {6'd0, one}) ? one : fx[12:0];
            fyc <= (fy > {6'd0, one}) ? one : fy[12:0];
            rna <= (pp0 + pp1) + (pp2 + pp3);
            rnb <= (pp4 + pp5) + pp6;
        end
        if (at[S_K])
            k <= k_sum;
        if (at[S_RD0]) begin
            k1 <= k_1[IW-1:0];
            kn <= k_n[IW-1:0];
            kn1 <= k_n1[IW-1:0];
        end
    end
    /* verilator lint_off UNUSEDSIGNAL */  // |i|, -i above bit 19 are 0 / sign copies in range; k < 2^IW
    wire unused_ok = &{1'b0, id_abs[31:20], iq_abs[31:19], id_neg[31:20], iq_neg[31:20], k_sum[12:IW], k_1[12:IW], k_n[12:IW], k_n1[12:IW]};
    /* verilator lint_on UNUSEDSIGNAL */

    // ---- tables: 20 reads of the RAM (corner-major: 00 of the five tables, 01, 10, 11) ------------------
    // Address stage (cycle S_ADR + j): table rt, corner rc of read j; the byte address base + 2 / 4 index
    // into mem_addr (its word) and ha (its half). Corner 00 takes k_sum (= k; stable from cycle 6 on,
    // needed in 6 before k is registered), the others the registered k + 1, k + n_d, k + n_d + 1 (from 8).
    wire              rd_go = busy_r && st >= S_ADR && st < S_ADR + S_NRD;
    reg         [2:0] rt;                 // table 0..4 of the address computed in this cycle
    reg         [1:0] rc;                 // its corner 0..3 (00, 01, 10, 11)
    always @(posedge clk) begin
        if (!busy_r) begin
            rt <= 3'd0;
            rc <= 2'd0;
        end else if (rd_go) begin
            rt <= (rt == 3'd4) ? 3'd0 : rt + 3'd1;
            if (rt == 3'd4)
                rc <= rc + 2'd1;
        end
    end
    reg      [IW-1:0] ridx;
    reg      [BW-1:0] rbase;
    always @* begin
        case (rc)
            2'd0:    ridx = k_sum[IW-1:0];
            2'd1:    ridx = k1;
            2'd2:    ridx = kn;
            default: ridx = kn1;
        endcase
        case (rt)
            3'd0:    rbase = base_d;
            3'd1:    rbase = base_q;
            3'd2:    rbase = base_ld;
            3'd3:    rbase = base_lq;
            default: rbase = base_ldq;
        endcase
    end
    wire              r16 = rt[2:1] == 2'b00;                 // t_d, t_q: int16 entries
    wire   [IW+BW+1:0] roff = {{BW{1'b0}}, r16 ? {1'b0, ridx, 1'b0} : {ridx, 2'b00}};
    wire     [BW-1:0] rbyte = rbase + roff[BW-1:0];           // modulo 2^BW
    /* verilator lint_off UNUSEDSIGNAL */  // the offset above the address width; byte bit 0 (even bases)
    wire unused_rd = &{1'b0, roff[IW+BW+1:BW], rbyte[0]};
    /* verilator lint_on UNUSEDSIGNAL */

    reg               mem_en_r;           // RAM read in this cycle
    reg  [RAM_AW-1:0] mem_addr_r;
    reg               ha, hd;             // byte bit 1 of the read (ha), of the word in mem_rdata (hd)
    reg         [2:0] dt;                 // table, corner of the word in mem_rdata
    reg         [1:0] dc;
    reg         [2:0] at_t;               // table, corner of the read in this cycle
    reg         [1:0] at_c;
    reg               dv;                 // mem_rdata holds a read of this look-up
    assign mem_en = mem_en_r;
    assign mem_addr = mem_addr_r;
    always @(posedge clk) begin
        if (rst) begin
            mem_en_r <= 1'b0;
            dv <= 1'b0;
        end else begin
            mem_en_r <= rd_go;
            dv <= mem_en_r;
        end
        if (rd_go) begin
            mem_addr_r <= rbyte[BW-1:2];
            ha <= rbyte[1];
            at_t <= rt;
            at_c <= rc;
        end
        hd <= ha;
        dt <= at_t;
        dc <= at_c;
    end
    wire              cap = busy_r && dv;
    wire       [15:0] rd_h = hd ? mem_rdata[31:16] : mem_rdata[15:0];
    wire signed [31:0] rd16 = {{16{rd_h[15]}}, rd_h};        // int16 entry, sign-extended
    wire signed [31:0] rd32 = mem_rdata;

    wire [5*32-1:0] c00_v, c01_v, c10_v, c11_v;    // corners, sign-extended to s32, lane = table
    genvar gj;
    generate
        for (gj = 0; gj < 5; gj = gj + 1) begin : g_tab
            localparam [2:0] TID = gj;
            wire signed [31:0]  rdx = (gj < 2) ? rd16 : rd32;
            reg  signed [31:0]  t00, t01, t10, t11;
            always @(posedge clk) begin
                if (cap && dt == TID) begin
                    case (dc)
                        2'd0:    t00 <= rdx;
                        2'd1:    t01 <= rdx;
                        2'd2:    t10 <= rdx;
                        default: t11 <= rdx;
                    endcase
                end
            end
            assign c00_v[gj*32 +: 32] = t00;
            assign c01_v[gj*32 +: 32] = t01;
            assign c10_v[gj*32 +: 32] = t10;
            assign c11_v[gj*32 +: 32] = t11;
        end
    endgenerate

    // ---- the shared multiplier -----------------------------------------------------------------------
    reg  signed [35:0] mA, A_r;
    reg  signed [19:0] mB, B_r;
    reg  signed [55:0] P;                 // product of the operands issued two cycles before
    always @(posedge clk) begin
        A_r <= mA;
        B_r <= mB;
        P <= A_r * B_r;
    end
    wire signed [55:0] Psh = P >>> shift;
    wire signed [19:0] fx20 = {1'b0, fx};
    wire signed [19:0] fy20 = {1'b0, fy};
    wire signed [19:0] fxc20 = {7'd0, fxc};
    wire signed [19:0] fyc20 = {7'd0, fyc};

    // ---- flux lanes (0 t_d, 1 t_q) -------------------------------------------------------------------
    wire [2*36-1:0] fdiff01_v, fdiff11_v, fba_v;   // issue operands: t01-t00, t11-t10, b-a
    wire [2*64-1:0] lam_v;
    // shared final transform of the flux: sgn * (lam << f_shift) mod 2^64, lane 0 in S_LAM, 1 in S_LAM + 1
    wire               lam_sel1 = st == S_LAM + 6'd1;
    wire signed [63:0] lam_in = lam_sel1 ? lam_v[64 +: 64] : lam_v[0 +: 64];
    wire signed [63:0] lam_shl = lam_in <<< f_shift;
    wire signed [63:0] lam_tr = (lam_sel1 ? sq : sd) ? -lam_shl : lam_shl;
    generate
        for (gj = 0; gj < 2; gj = gj + 1) begin : g_flux
            localparam [5:0] J = gj;
            wire signed [31:0] t00 = c00_v[gj*32 +: 32], t01 = c01_v[gj*32 +: 32];
            wire signed [31:0] t10 = c10_v[gj*32 +: 32], t11 = c11_v[gj*32 +: 32];
            reg  signed [35:0] a, b;
            reg  signed [63:0] lam;
            always @(posedge clk) begin
                if (at[I_F1 + J + WB]) a <= {{4{t00[31]}}, t00} + Psh[35:0];
                if (at[I_F2 + J + WB]) b <= {{4{t10[31]}}, t10} + Psh[35:0];
                if (at[I_F3 + J + WB]) lam <= {{28{a[35]}}, a} + {{8{Psh[55]}}, Psh};
                if (at[S_LAM + J]) lam <= lam_tr;
            end
            wire signed [35:0] d01 = {{4{t01[31]}}, t01} - {{4{t00[31]}}, t00};   // s17 values
            wire signed [35:0] d11 = {{4{t11[31]}}, t11} - {{4{t10[31]}}, t10};
            wire signed [35:0] ba = b - a;          // |b - a| < 2^35
            assign fdiff01_v[gj*36 +: 36] = d01;
            assign fdiff11_v[gj*36 +: 36] = d11;
            assign fba_v[gj*36 +: 36] = ba;
            assign lam_v[gj*64 +: 64] = lam;
        end
    endgenerate

    // ---- inductance lanes (0 t_ld, 1 t_lq, 2 t_ldq) --------------------------------------------------
    wire [3*36-1:0] ldiff01_v, lD_v, lba_v, gxlo_v, gxhi_v, gylo_v, gyhi_v;
    wire [3*32-1:0] l_v;
    wire [3*ACW-1:0] acc_v;
    reg  signed [ACW-1:0] psh;            // shifted derivative product (for the accumulators)
    reg  signed [ACW-1:0] P72;
    reg         [4:0]     acc_sh;         // its shift: 21 * hi + (x part ? log2 wx : log2 wy)
    reg         [3:0]     nsel;           // product index 0..11 of the derivative products
    always @* begin
        nsel = st[3:0] - (I_N[3:0] + WB[3:0]);
        acc_sh = (nsel[0] ? 5'd21 : 5'd0) + {2'd0, (nsel[1] ? lty : ltx) ? coarse : 3'd0};
        P72 = {{(ACW - 56){P[55]}}, P};
    end
    wire [3:0] nsel_p = st[3:0] - (I_N[3:0] + WB[3:0] + 4'd1);     // of psh, one cycle later
    /* verilator lint_off UNUSEDSIGNAL */
    wire unused_nsel = &{1'b0, nsel[3:2], nsel_p[1:0]};
    /* verilator lint_on UNUSEDSIGNAL */
    always @(posedge clk)
        psh <= P72 <<< acc_sh;

    // shared shifters of the inductance lanes (their uses fall in different cycles)
    wire [3*33-1:0] d1_v, e1_v;
    wire [3*GW-1:0] pd2_v;
    reg  signed [32:0] gb_in;             // e1 of lane j for gy in I_DX + j + WB, d1 for gx in I_DY + j + WB
    reg  signed [GW-1:0] gb;              // gb_in << s, loaded one cycle ahead
    reg  signed [GW-1:0] pd2_in;
    /* verilator lint_off UNUSEDSIGNAL */  // pd2 >>> s lies between 0 and t11 - t10: b = t10 + it is s32
    reg  signed [GW-1:0] bsh;             // pd2 >>> s of lane j, loaded in S_B + j
    /* verilator lint_on UNUSEDSIGNAL */
    reg  signed [ACW-1:0] acc_in;
    always @* begin
        case (st)
            I_DX + WB - 6'd1:          gb_in = e1_v[0 +: 33];
            I_DX + WB:                 gb_in = e1_v[33 +: 33];
            I_DX + WB + 6'd1:          gb_in = e1_v[66 +: 33];
            I_DY + WB - 6'd1:          gb_in = d1_v[0 +: 33];
            I_DY + WB:                 gb_in = d1_v[33 +: 33];
            default:                   gb_in = d1_v[66 +: 33];
        endcase
        case (st)
            S_B:                       pd2_in = pd2_v[0 +: GW];
            S_B + 6'd1:                pd2_in = pd2_v[GW +: GW];
            default:                   pd2_in = pd2_v[2*GW +: GW];
        endcase
        case (st)
            S_DL:                      acc_in = acc_v[0 +: ACW];
            S_DL + 6'd4:               acc_in = acc_v[ACW +: ACW];
            default:                   acc_in = acc_v[2*ACW +: ACW];
        endcase
    end
    wire signed [ACW-1:0] dl_sh = acc_in >>> dl_shift;     // |.| < 2^52
    wire        [4:0]     dl_shift = {shift, 1'b0} + {2'd0, coarse};   // 2s + coarse <= 31
    always @(posedge clk) begin
        gb <= {{(GW - 33){gb_in[32]}}, gb_in} <<< shift;
        bsh <= pd2_in >>> shift;
    end

    generate
        for (gj = 0; gj < 3; gj = gj + 1) begin : g_ind
            localparam [5:0] J = gj;
            wire signed [31:0] t00 = c00_v[(gj+2)*32 +: 32], t01 = c01_v[(gj+2)*32 +: 32];
            wire signed [31:0] t10 = c10_v[(gj+2)*32 +: 32], t11 = c11_v[(gj+2)*32 +: 32];
            reg  signed [32:0] d1, e1;          // t01 - t00, t10 - t00
            reg  signed [33:0] dd;              // t11 - t10 - t01 + t00
            reg  signed [31:0] a, b, l;
            reg  signed [GW-1:0] pd1, pd2, gx, gy;
            reg  signed [ACW-1:0] acc;
            wire signed [32:0] d01 = {t01[31], t01} - {t00[31], t00};
            wire signed [32:0] d11 = {t11[31], t11} - {t10[31], t10};
            wire signed [32:0] d10 = {t10[31], t10} - {t00[31], t00};
            wire acc_en = busy_r && st >= I_N + WB + 6'd1 && st <= I_N + WB + 6'd12 && nsel_p[3:2] == J[1:0];
            always @(posedge clk) begin
                if (at[S_DIFF]) begin
                    d1 <= d01;
                    e1 <= d10;
                    dd <= d11 - d01;
                end
                if (at[I_L1 + J + WB]) begin
                    a <= t00 + $signed(Psh[31:0]);        // between t00 and t01
                    pd1 <= P[GW-1:0];            // d1 fxc
                end
                if (at[I_DX + J + WB]) begin
                    pd2 <= pd1 + P[GW-1:0];      // (t11 - t10) fxc
                    gy <= gb + P[GW-1:0];        // (e1 << s) + D fxc
                end
                if (at[I_DY + J + WB])
                    gx <= gb + P[GW-1:0];        // (d1 << s) + D fyc
                if (at[S_B + J + 6'd1])
                    b <= t10 + bsh[31:0];        // t10 + shr((t11 - t10) fxc, s): between t10 and t11
                if (at[I_L3 + J + WB])
                    l <= a + $signed(Psh[31:0]);
                if (at[1])
                    acc <= {ACW{1'b0}};
                else if (acc_en)
                    acc <= acc + psh;
                else if (at[S_DL + 6'd4 * J])
                    acc <= dl_sh;                // dl = shr(acc, 2s + coarse)
            end
            wire signed [35:0] ba = {{4{b[31]}}, b} - {{4{a[31]}}, a};
            /* verilator lint_off UNUSEDSIGNAL */  // |g >>> 21| < 2^24: bits 45:36 are sign copies
            wire signed [GW-1:0] gx_hi = gx >>> 21;
            wire signed [GW-1:0] gy_hi = gy >>> 21;
            /* verilator lint_on UNUSEDSIGNAL */
            assign ldiff01_v[gj*36 +: 36] = {{3{d01[32]}}, d01};
            assign lD_v[gj*36 +: 36] = {{2{dd[33]}}, dd};
            assign lba_v[gj*36 +: 36] = ba;
            assign gxlo_v[gj*36 +: 36] = {15'd0, gx[20:0]};
            assign gxhi_v[gj*36 +: 36] = gx_hi[35:0];
            assign gylo_v[gj*36 +: 36] = {15'd0, gy[20:0]};
            assign gyhi_v[gj*36 +: 36] = gy_hi[35:0];
            assign l_v[gj*32 +: 32] = l;
            assign acc_v[gj*ACW +: ACW] = acc;
            assign d1_v[gj*33 +: 33] = d1;
            assign e1_v[gj*33 +: 33] = e1;
            assign pd2_v[gj*GW +: GW] = pd2;
        end
    endgenerate

    // ---- operand selection (one product per cycle) ---------------------------------------------------
    always @* begin
        mA = 36'sd0;
        mB = 20'sd0;
        case (st)
            I_F1:          begin mA = fdiff01_v[0 +: 36];  mB = fx20; end
            I_F1 + 6'd1:   begin mA = fdiff01_v[36 +: 36]; mB = fx20; end
            I_L1:          begin mA = ldiff01_v[0 +: 36];  mB = fxc20; end
            I_L1 + 6'd1:   begin mA = ldiff01_v[36 +: 36]; mB = fxc20; end
            I_L1 + 6'd2:   begin mA = ldiff01_v[72 +: 36]; mB = fxc20; end
            I_F2:          begin mA = fdiff11_v[0 +: 36];  mB = fx20; end
            I_F2 + 6'd1:   begin mA = fdiff11_v[36 +: 36]; mB = fx20; end
            I_DX:          begin mA = lD_v[0 +: 36];       mB = fxc20; end
            I_DX + 6'd1:   begin mA = lD_v[36 +: 36];      mB = fxc20; end
            I_DX + 6'd2:   begin mA = lD_v[72 +: 36];      mB = fxc20; end
            I_DY:          begin mA = lD_v[0 +: 36];       mB = fyc20; end
            I_DY + 6'd1:   begin mA = lD_v[36 +: 36];      mB = fyc20; end
            I_DY + 6'd2:   begin mA = lD_v[72 +: 36];      mB = fyc20; end
            I_N:           begin mA = gxlo_v[0 +: 36];     mB = bx_s; end
            I_N + 6'd1:    begin mA = gxhi_v[0 +: 36];     mB = bx_s; end
            I_N + 6'd2:    begin mA = gylo_v[0 +: 36];     mB = by_s; end
            I_N + 6'd3:    begin mA = gyhi_v[0 +: 36];     mB = by_s; end
            I_N + 6'd4:    begin mA = gxlo_v[36 +: 36];    mB = bx_s; end
            I_N + 6'd5:    begin mA = gxhi_v[36 +: 36];    mB = bx_s; end
            I_N + 6'd6:    begin mA = gylo_v[36 +: 36];    mB = by_s; end
            I_N + 6'd7:    begin mA = gyhi_v[36 +: 36];    mB = by_s; end
            I_N + 6'd8:    begin mA = gxlo_v[72 +: 36];    mB = bx_a; end
            I_N + 6'd9:    begin mA = gxhi_v[72 +: 36];    mB = bx_a; end
            I_N + 6'd10:   begin mA = gylo_v[72 +: 36];    mB = by_a; end
            I_N + 6'd11:   begin mA = gyhi_v[72 +: 36];    mB = by_a; end
            I_F3:          begin mA = fba_v[0 +: 36];      mB = fy20; end
            I_F3 + 6'd1:   begin mA = fba_v[36 +: 36];     mB = fy20; end
            I_L3:          begin mA = lba_v[0 +: 36];      mB = fyc20; end
            I_L3 + 6'd1:   begin mA = lba_v[36 +: 36];     mB = fyc20; end
            I_L3 + 6'd2:   begin mA = lba_v[72 +: 36];     mB = fyc20; end
            default:       begin mA = 36'sd0;              mB = 20'sd0; end
        endcase
    end

    // ---- outputs -------------------------------------------------------------------------------------
    wire signed [31:0] ldq32 = l_v[64 +: 32];
    wire signed [63:0] ldq64 = {{32{ldq32[31]}}, ldq32};
    /* verilator lint_off UNUSEDSIGNAL */  // |dl| < 2^52: the top bits are sign copies
    wire unused_dl = &{1'b0, acc_v[ACW-1:64], acc_v[2*ACW-1:ACW+64], acc_v[3*ACW-1:2*ACW+64]};
    /* verilator lint_on UNUSEDSIGNAL */

    always @(posedge clk) begin
        if (rst) begin
            done <= 1'b0;
            lam_d <= 64'sd0; lam_q <= 64'sd0; l_d <= 64'sd0; l_q <= 64'sd0; l_dq <= 64'sd0;
            dl_d <= 64'sd0; dl_q <= 64'sd0; dl_dq <= 64'sd0;
        end else begin
            done <= at[S_LAST];
            if (at[S_LAST]) begin
                lam_d <= lam_v[0 +: 64];
                lam_q <= lam_v[64 +: 64];
                l_d <= {{32{l_v[31]}}, l_v[0 +: 32]};
                l_q <= {{32{l_v[63]}}, l_v[32 +: 32]};
                l_dq <= (sd ^ sq) ? -ldq64 : ldq64;
                dl_d <= acc_v[0 +: 64];
                dl_q <= acc_v[ACW +: 64];
                dl_dq <= acc_v[2*ACW +: 64];
            end
        end
    end

endmodule
`default_nettype wire
