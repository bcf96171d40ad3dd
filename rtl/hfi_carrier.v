`default_nettype none
// hfi_carrier: up/down PWM carrier, strobes and demodulation weight angle.
//
// Implements docs/spec.md 2.1 (golden/fpga/carrier.py) and the weight angle of spec 3.3
// (golden/fpga/cordic.py::demod_weight: a = uwrap((H - 2c) * CW_ANGLE_STEP, 32)); Benevieri et al.
// 2023, eq. (15): cw = 2c/H - 1, a ~ -cw * 2^30 (a quarter turn at the bottom).
//
// Ports (all registered outputs are the values of the current tick, docs/rtl.md "Tick numbering"):
//   pwm_half_reg  u16  PWM_HALF register; the effective half period is golden effective_half():
//                      LSB cleared, values below 512 run as 512 (so H is even, 512..65534).
//   cw_step_reg   u32  CW_ANGLE_STEP register.
//   phase         u17  phi = t mod P, 0..2H-1 (P = 2H); 0 in tick 0 (first cycle after rst).
//   counter       u16  c = phi on the rising half, P - phi on the falling half (0..H).
//   half          u16  effective H in use (applied at bottoms).
//   rising              phi < H;  at_bottom: phi == 0;  at_top: phi == H;
//   at_zc               phi == H/2 (carrier rising zero crossing = window boundary).
//   cw_angle      u32  uwrap((H - 2c) * STEP, 32) of this tick, H and STEP those applied at the last
//                      bottom (a binary angle: wraps modulo 2^32 by definition, spec 1).
// Latency: none (all outputs describe the current tick; counter, strobes and angle are registers
// whose next values are computed one tick ahead).  Throughput: one tick per clock.  Multipliers: 0.
//
// Timing structure (Fmax): the counter c is kept as a register (up on the rising half, down on the
// falling half, 0 at every bottom); the strobes of the next tick are registered, including `last`
// (the next tick is a bottom), so the bottom reload (half, step, hs) is a plain mux of registers. The
// equality compares behind the strobes are themselves evaluated one tick earlier (c == H - 2,
// c == H/2 - 2 on the rising half, c == 3 on the falling half, registered in eq_top, eq_zc, eq_two),
// so a strobe is one gate after registers.  The angle is kept directly: a_next = a -/+ 2*STEP
// (rising/falling) while hs is unchanged, or hs_next - m2cs_next (one carry-save level + one 32-bit
// chain) when hs is (re)loaded from the ready product; the 48-bit "ready triple matches the pair in
// use" compare is registered (eq_rdy, evaluated from the next values) and only selects the result.
//
// Register changes (docs/rtl.md "PWM_HALF and CW_ANGLE_STEP take effect at a carrier bottom"):
//   A bit-serial shift-add multiplier (one bit of H per clock) computes H*STEP mod 2^32 of the
//   register inputs: a load cycle, 16 add cycles, so a product completes 17 clocks after its operands
//   appeared, and one pipeline stage (ld, timing) later it is the ready triple.  Whenever (effective_half(pwm_half_reg), cw_step_reg) differs from the operands in
//   progress the multiplier restarts with the new values (a computation is never finished with stale
//   operands); when it completes, the triple (H, STEP, H*STEP) is stored as "ready".  At each bottom
//   the carrier takes H, STEP and H*STEP from the ready triple.
//   The ports are registered first (x_h, x_s: timing), so the multiplier sees a write one clock later.
//   Exact rule: if the inputs take a new value in cycle w (present on the ports from cycle w on) and
//   keep it during cycles w..w+17, the new H and STEP are used from the first bottom at tick
//   b >= w + 20 (the bottom at b is prepared in cycle b-1 from the ready triple, which holds the new
//   product from cycle w+19).  A bottom before w + 20 still uses the previous values (consistently:
//   H, STEP and product always belong together).  A value changed again within 17 cycles is never
//   applied; the next one follows the same rule from its own write cycle (x_h, x_s count: a value
//   present for one cycle only still restarts the product).
//
// Weight angle: a = H*STEP - m with m = 2c*STEP mod 2^32 kept incrementally (+2*STEP per tick on
// the rising half, -2*STEP on the falling half, exactly 0 again at every bottom) and hs = H*STEP
// reloaded at each bottom; exact modulo 2^32, no multiplier.  The serial multiplier runs MSB first
// (acc = 2*acc + h_bit*STEP), so no shifted copy of STEP is stored.
//
// Reset: while rst is high, phase = 0 and H, STEP are loaded from the register inputs of two cycles
// before (the multiplier's operand registers, which take x_h, x_s; tick 0 uses
// effective_half(pwm_half_reg) and cw_step_reg of the third-last reset cycle: timing, the compare with
// the ready triple is then a register); the rising edge of
// rst restarts the serial multiplier with those values.  cw_angle is right from tick 0 if rst is held
// for at least RESET_CYCLES_MIN = 20 cycles with stable register inputs (the product is then ready
// during the last reset cycle).  After a shorter reset, phase/half/strobes are still right from
// tick 0 and cw_angle becomes right as soon as the product of the H and STEP in use is ready (at the
// latest 19 cycles after the inputs settle): hs is also refreshed whenever the ready triple matches
// the (H, STEP) in use.

module hfi_carrier (
    input  wire        clk,
    input  wire        rst,
    input  wire [15:0] pwm_half_reg,
    input  wire [31:0] cw_step_reg,
    output reg  [16:0] phase,
    output reg  [15:0] counter,
    output reg  [15:0] half,
    output reg         rising,
    output reg         at_bottom,
    output reg         at_top,
    output reg         at_zc,
    output reg  [31:0] cw_angle
);
    // The register inputs, one clock late (timing): everything below runs on x_h, x_s, and the
    // operand compare of the serial multiplier (op_eq: "the inputs equal the operands in progress")
    // becomes a register, evaluated a clock ahead from the ports and these copies (the compare of a
    // 32-bit STEP feeding the multiplier's restart was the tick clock's critical path on the ULX3S,
    // docs/boards.md). The module is the former one with its inputs delayed by one clock: a write
    // applies one clock later (RESET_CYCLES_MIN and the apply rule 20 instead of 19).
    reg  [15:0] x_h;
    reg  [31:0] x_s;
    // effective_half() (golden carrier.effective_half): clear the LSB, raise anything below
    // REGISTER_HALF_MIN = 512 to 512
    wire [15:0] eff_half_in = (x_h[15:9] == 7'd0) ? 16'd512 : {x_h[15:1], 1'b0};
    wire        unused_lsb  = x_h[0];   // cleared by effective_half()

    // ---- bit-serial multiplier H*STEP mod 2^32 (1 load cycle + 16 add cycles, MSB first) -----
    reg  [15:0] mul_h;     // operands of the product in progress (or last completed)
    reg  [31:0] mul_s;
    reg  [15:0] mul_q;     // multiplier bits not yet consumed (MSB first: mul_q[15] is next)
    reg  [30:0] mul_acc;   // partial product mod 2^31 (its bit 31 would be shifted out)
    reg  [3:0]  mul_cnt;   // add cycles done
    reg         mul_busy;
    reg  [15:0] rdy_h;     // ready triple (H, STEP, H*STEP): the last completed product
    reg  [15:0] rdy_hm2;   // rdy_h - 2 and rdy_h/2 - 2 (strobe targets of rdy_h, loaded with it)
    reg  [15:0] rdy_zm2;
    reg  [31:0] rdy_s;
    reg  [31:0] rdy_p;
    reg         rst_q;     // rst of the previous cycle (restart the product on the rising edge of rst)
    reg         mul_h512;  // mul_h == 512
    wire [31:0] mul_sum = {mul_acc, 1'b0} + (mul_q[15] ? mul_s : 32'd0);
    // The inputs equal the operands in progress: effective_half(pwm_half_reg) == mul_h (mul_h is always
    // an effective half: even, >= 512, so the raw register's LSB does not matter) and STEP == mul_s.
    // Written as "equal -> keep going, else restart" so that unknown operands (simulation start)
    // restart the product.
    wire        small_in = x_h[15:9] == 7'd0;
    // op_eq of this cycle, (small_in ? mul_h512 : x_h[15:1] == mul_h[15:1]) && x_s == mul_s, from the
    // cycle before: then x_h, x_s are the ports and mul_h, mul_h512, mul_s take eff(x_h), its flag, x_s.
    // eff(x_h)[15:1] is 256 if x_h is small, else x_h[15:1]: compared without the clamp in front (timing)
    reg         op_eq;
    wire        small_port = pwm_half_reg[15:9] == 7'd0;
    wire        x_h512     = small_in || x_h[15:1] == 15'd256;
    wire        port_eq_x  = small_in ? pwm_half_reg[15:1] == 15'd256 : pwm_half_reg[15:1] == x_h[15:1];
    wire        op_eq_n    = (small_port ? x_h512 : port_eq_x) && cw_step_reg == x_s;
    wire        mul_keep = op_eq && !(rst && !rst_q);
    reg         mul_last;  // mul_busy && mul_cnt == 15 (registered: the add cycle that completes)
    wire        mul_done = mul_keep && mul_last;                       // the product completes
    reg         ld;        // mul_done of the previous cycle: the ready triple is loaded from ld_*
    reg  [15:0] ld_h;
    reg  [31:0] ld_s, ld_p;
    reg         ld_h512, rdy_h512;   // ld_h == 512, rdy_h == 512 (loaded with them)

    always @(posedge clk) begin
        x_h   <= pwm_half_reg;
        x_s   <= cw_step_reg;
        op_eq <= op_eq_n;
        rst_q <= rst;
        // The operands take the inputs in every cycle: they change only where the product restarts
        // (op_eq false: loaded from the inputs) and are equal to the inputs where it goes on
        // (timing: no restart enable on them).
        mul_h    <= eff_half_in;
        mul_h512 <= x_h512;
        mul_s    <= x_s;
        mul_last <= mul_keep && mul_busy && mul_cnt == 4'd14;
        if (mul_keep) begin
            if (mul_busy) begin
                mul_acc <= mul_sum[30:0];
                mul_q   <= {mul_q[14:0], 1'b0};
                mul_cnt <= mul_cnt + 4'd1;
                if (mul_cnt == 4'd15)
                    mul_busy <= 1'b0;
            end
        end else begin
            mul_q    <= eff_half_in;
            mul_acc  <= 31'd0;
            mul_cnt  <= 4'd0;
            mul_busy <= 1'b1;
        end
        // one pipeline stage between the completion and the ready triple (timing: mul_done is the
        // end of the operand compare, the triple is 113 clock enables)
        ld      <= mul_done;
        ld_h    <= mul_h;
        ld_h512 <= mul_h512;
        ld_s    <= mul_s;
        ld_p    <= mul_sum;
        if (ld) begin
            rdy_h <= ld_h;
            rdy_h512 <= ld_h512;
            rdy_hm2 <= ld_h - 16'd2;
            rdy_zm2 <= {1'b0, ld_h[15:1]} - 16'd2;
            rdy_s <= ld_s;
            rdy_p <= ld_p;
        end
    end

    // ---- carrier ------------------------------------------------------------------------------
    reg  [31:0] step;      // STEP in use
    reg  [31:0] hs;        // H*STEP mod 2^32 of the (half, step) in use (once known)
    reg  [31:0] m2cs;      // 2*c*STEP mod 2^32 of the current tick
    reg         last;      // this tick is the last of the period (phi = 2H - 1): the next is a bottom
    reg  [15:0] top_m2;    // H - 2 and H/2 - 2 of the half period in use (strobe targets, a tick ahead)
    reg  [15:0] zc_m2;
    reg         eq_top;    // c == H - 1 (valid on the rising half outside a bottom tick)
    reg         eq_zc;     // c == H/2 - 1 (likewise)
    reg         eq_two;    // c == 2 (valid on the falling half outside a bottom tick)
    reg         done_q;    // ld of the previous tick (the ready triple changed)
    reg         emp_q;     // {rdy_h, rdy_s} == {half, step} of this tick if done_q (else not used),
                           // evaluated the tick before
    reg         emp_r_q;   // {mul_h, mul_s} == {rdy_h, rdy_s} of the previous tick
    reg         emp_h_q;   // {mul_h, mul_s} == {half, step} of the previous tick
    reg         last_q;    // last of the previous tick
    reg         erp_q;     // {rdy_h, rdy_s} of the previous tick == {half, step} of this tick

    wire        bottom_n = rst | last;                            // the next tick is a bottom
    wire [15:0] c_step   = rising ? counter + 16'd1 : counter - 16'd1;
    wire [15:0] c_n      = bottom_n ? 16'd0 : c_step;             // counter of the next tick
    // strobes of the next tick (half is unchanged unless the next tick is a bottom, where c_n = 0):
    // c + 1 == H <=> c == H - 1 (rising, c < H), c - 1 == 1 <=> c == 2 (falling), these equalities
    // registered the tick before: c + 1 == H - 1 (rising: the next tick is rising or the top, where
    // eq_top is not used), c - 1 == 2 (falling: the next tick is falling or a bottom). After a bottom
    // (c = 0) none holds (H >= 512).
    wire        top_n    = !bottom_n && rising && eq_top;
    wire        zc_n     = !bottom_n && rising && eq_zc;
    wire        last_n   = !bottom_n && !rising && eq_two;
    wire        rising_n = bottom_n | (rising & ~top_n);

    // pair in use next tick; does the ready triple describe it (then its product is hs)?
    // under rst the pair is the register inputs of the previous cycle (the operand registers mul_h,
    // mul_s), so that its compare with the ready triple is a register (rdy_in_q: timing)
    wire [15:0] half_n   = rst ? mul_h : (last ? rdy_h : half);
    wire [31:0] step_n   = rst ? mul_s : (last ? rdy_s : step);
    // {rdy_h, rdy_s} == {half, step}: the ready triple of this tick is the operands of the previous
    // tick if the product completed then, else unchanged, so the equality is registered the tick
    // before for both cases (emp_q, erp_q; the pair of the next tick is the register inputs under rst,
    // the ready triple at a bottom, else unchanged) and done_q selects.
    wire        eq_rdy   = done_q ? emp_q : erp_q;
    // rdy_in_q: the ready triple of this cycle == {mul_h, mul_s} (the pair under rst), registered the
    // cycle before from the triple of this cycle (ld ? ld_* : rdy_*) and the register inputs then
    reg         rdy_in_q;
    // {X_h, X_s} == {eff_half_in, cw_step_reg} for X = ld, rdy without the clamp of eff_half_in in front
    // of the compare (timing; as op_eq): X_h is an effective half (even, >= 512, or 0 before the first
    // product, which equals no effective half), so it equals eff_half_in iff X_h == 512 when the
    // register is below 512, else iff its bits 15..1 equal the register's
    wire        in_eq_ld  = (small_in ? ld_h512 : (x_h[15:1] == ld_h[15:1])) && x_s == ld_s;
    wire        in_eq_rdy = (small_in ? rdy_h512 : (x_h[15:1] == rdy_h[15:1])) && x_s == rdy_s;
    wire        match    = rst ? rdy_in_q : (last | eq_rdy);
    // hs and the angle of the next tick by case (timing: the compare of the ready triple against the
    // register inputs, needed under rst only, is one multiplexer from the registers): under rst both
    // are hs_n = (match ? rdy_p : hs) (a bottom, m2cs_n = 0); else see angle_n below.
    wire [31:0] rst_hs   = rdy_in_q ? rdy_p : hs;
    wire [31:0] hs_n     = rst ? rst_hs : ((last | eq_rdy) ? rdy_p : hs);
    // (the triple loaded at the end of this tick, if ld, is {ld_h, ld_s}; the pair of the next tick is
    // the register inputs under rst, the ready triple at a bottom, else unchanged)
    // emp_n is used only where ld (done_q of the next tick). There the three compares are registers
    // (timing: a 48-bit compare against a multiplexer of three pairs was the tick clock's critical
    // path, docs/boards.md), because the product completed in the cycle before (mul_done):
    //   - {ld_h, ld_s} is {mul_h, mul_s} of the previous tick (taken in every cycle), and equals
    //     {mul_h, mul_s} of this tick (the product went on: the inputs equalled the operands): the
    //     rst case is true;
    //   - the ready triple did not change in the previous tick (no two completions in a row): the last
    //     case is emp_r_q;
    //   - {half, step} of this tick is the previous tick's pair of the next tick (rst_q: {mul_h,
    //     mul_s}, equal; last_q: {rdy_h, rdy_s}; else unchanged).
    wire        emp_n    = rst | (last ? emp_r_q : (rst_q | (last_q ? emp_r_q : emp_h_q)));
    // erp of the next tick: rst: the ready triple against the register inputs; at a bottom the pair
    // becomes the ready triple; else {rdy_h, rdy_s} == {half, step} of this tick: in all cases, match

    // m2cs of the next tick: m2cs + d with d = +2*STEP rising, -2*STEP falling; 0 at a bottom
    wire [31:0] two_step = {step[30:0], 1'b0};
    // (each +/- as one adder: the subtraction adds the inverted operand with a carry of 1 into an
    // extra low bit, {a, 1} + {b, c}; no multiplexer after the carry chains)
    /* verilator lint_off UNUSEDSIGNAL */  // bit 0 of the sums is the carry-in helper
    wire [32:0] m2cs_s   = {m2cs, 1'b1} + {two_step ^ {32{~rising}}, ~rising};
    wire [32:0] keep_s   = {cw_angle, 1'b1} + {two_step ^ {32{rising}}, rising};
    /* verilator lint_on UNUSEDSIGNAL */
    wire [31:0] m2cs_n   = bottom_n ? 32'd0 : m2cs_s[32:1];
    // angle of the next tick, a_n = hs_n - m2cs_n:
    //   hs kept:     (hs - m2cs) - d = cw_angle - d  (cw_angle = hs - m2cs is an invariant)
    //   hs reloaded: rdy_p - m2cs - d = rdy_p + ~m2cs + e + k with e = ~two_step, k = 2 (rising)
    //                or e = two_step, k = 1 (falling); as one carry-save level and one adder
    wire [31:0] keep_a   = keep_s[32:1];
    wire [31:0] csa_x    = rdy_p;
    wire [31:0] csa_y    = ~m2cs;
    wire [31:0] csa_z    = rising ? ~two_step : two_step;
    wire [31:0] csa_s    = csa_x ^ csa_y ^ csa_z;
    wire [31:0] csa_c    = {(csa_x[30:0] & csa_y[30:0]) | (csa_x[30:0] & csa_z[30:0])
                            | (csa_y[30:0] & csa_z[30:0]), 1'b1};   // the +1 of ~m2cs in bit 0
    /* verilator lint_off UNUSEDSIGNAL */
    wire [32:0] load_s   = {csa_s, 1'b1} + {csa_c, rising};       // + the +1 of ~two_step (rising)
    /* verilator lint_on UNUSEDSIGNAL */
    wire [31:0] load_a   = load_s[32:1];
    wire [31:0] angle_n  = rst ? rst_hs : last ? rdy_p : (eq_rdy ? load_a : keep_a);

    always @(posedge clk) begin
        phase     <= bottom_n ? 17'd0 : phase + 17'd1;
        counter   <= c_n;
        rising    <= rising_n;
        at_bottom <= bottom_n;
        at_top    <= top_n;
        at_zc     <= zc_n;
        last      <= last_n;
        half      <= half_n;
        // half_n - 2, half_n/2 - 2 from the three sources (no subtraction after the multiplexer)
        top_m2    <= rst ? mul_h - 16'd2 : last ? rdy_hm2 : top_m2;
        zc_m2     <= rst ? {1'b0, mul_h[15:1]} - 16'd2 : last ? rdy_zm2 : zc_m2;
        rdy_in_q  <= ld ? in_eq_ld : in_eq_rdy;
        eq_top    <= !bottom_n && rising && counter == top_m2;
        eq_zc     <= !bottom_n && rising && counter == zc_m2;
        eq_two    <= !bottom_n && !rising && counter == 16'd3;
        done_q    <= ld;
        emp_q     <= emp_n;
        emp_r_q   <= {mul_h, mul_s} == {rdy_h, rdy_s};
        emp_h_q   <= {mul_h, mul_s} == {half, step};
        last_q    <= last;
        erp_q     <= match;
        step      <= step_n;
        hs        <= hs_n;
        m2cs      <= m2cs_n;
        cw_angle  <= angle_n;
    end
endmodule

`default_nettype wire
