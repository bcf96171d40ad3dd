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
// Latency: none (all outputs describe the current tick; counter/strobes are decoded from the
// registered phase and half).  Throughput: one tick per clock.  Multipliers: 0.
//
// Register changes (docs/rtl.md "PWM_HALF and CW_ANGLE_STEP take effect at a carrier bottom"):
//   A bit-serial shift-add multiplier (one bit of H per clock) computes H*STEP mod 2^32 of the
//   register inputs: a load cycle, 16 add cycles, so a product is ready 17 clocks after its operands
//   appeared.  Whenever (effective_half(pwm_half_reg), cw_step_reg) differs from the operands in
//   progress the multiplier restarts with the new values (a computation is never finished with stale
//   operands); when it completes, the triple (H, STEP, H*STEP) is stored as "ready".  At each bottom
//   the carrier takes H, STEP and H*STEP from the ready triple.
//   Exact rule: if the inputs take a new value in cycle w (present on the ports from cycle w on) and
//   keep it during cycles w..w+16, the new H and STEP are used from the first bottom at tick
//   b >= w + 18 (the bottom at b is prepared in cycle b-1 from the ready triple, which holds the new
//   product from cycle w+17).  A bottom before w + 18 still uses the previous values (consistently:
//   H, STEP and product always belong together).  A value changed again within 17 cycles is never
//   applied; the next one follows the same rule from its own write cycle.
//
// Weight angle: a = H*STEP - m with m = 2c*STEP mod 2^32 kept incrementally (+2*STEP per tick on
// the rising half, -2*STEP on the falling half, exactly 0 again at every bottom) and hs = H*STEP
// reloaded at each bottom; exact modulo 2^32, no multiplier.
//
// Reset: while rst is high, phase = 0 and H, STEP are loaded directly from the register inputs
// (tick 0 uses effective_half(pwm_half_reg) and cw_step_reg of the reset cycles); the rising edge of
// rst restarts the serial multiplier with those values.  cw_angle is right from tick 0 if rst is held
// for at least RESET_CYCLES_MIN = 18 cycles with stable register inputs (the product is then ready
// during the last reset cycle).  After a shorter reset, phase/half/strobes are still right from
// tick 0 and cw_angle becomes right as soon as the product of the H and STEP in use is ready (at the
// latest 17 cycles after the inputs settle): hs is also refreshed whenever the ready triple matches
// the (H, STEP) in use.

module hfi_carrier (
    input  wire        clk,
    input  wire        rst,
    input  wire [15:0] pwm_half_reg,
    input  wire [31:0] cw_step_reg,
    output reg  [16:0] phase,
    output wire [15:0] counter,
    output reg  [15:0] half,
    output wire        rising,
    output wire        at_bottom,
    output wire        at_top,
    output wire        at_zc,
    output reg  [31:0] cw_angle
);
    localparam [15:0] REGISTER_HALF_MIN = 16'd512;  // golden carrier.REGISTER_HALF_MIN

    // effective_half(): clear the LSB, raise anything below 512 to 512
    wire [15:0] eff_half_in = (pwm_half_reg < REGISTER_HALF_MIN) ? REGISTER_HALF_MIN
                                                                 : {pwm_half_reg[15:1], 1'b0};

    // ---- bit-serial multiplier H*STEP mod 2^32 (16 add cycles + 1 load cycle) ----------------
    reg  [15:0] mul_h;     // operands of the product in progress (or last completed)
    reg  [31:0] mul_s;
    reg  [15:0] mul_q;     // multiplier bits not yet consumed (LSB first)
    reg  [31:0] mul_d;     // multiplicand shifted to the weight of mul_q[0]
    reg  [31:0] mul_acc;   // partial product mod 2^32
    reg  [3:0]  mul_cnt;   // add cycles done
    reg         mul_busy;
    reg  [15:0] rdy_h;     // ready triple (H, STEP, H*STEP): the last completed product
    reg  [31:0] rdy_s;
    reg  [31:0] rdy_p;
    reg         rst_q;     // rst of the previous cycle (restart the product on the rising edge of rst)
    wire [31:0] mul_sum = mul_acc + (mul_q[0] ? mul_d : 32'd0);

    always @(posedge clk) begin
        rst_q <= rst;
        // Written as "equal -> keep going, else restart" so that unknown operands (simulation
        // start) restart the product.
        if ({eff_half_in, cw_step_reg} == {mul_h, mul_s} && !(rst && !rst_q)) begin
            if (mul_busy) begin
                mul_acc <= mul_sum;
                mul_d   <= {mul_d[30:0], 1'b0};
                mul_q   <= {1'b0, mul_q[15:1]};
                mul_cnt <= mul_cnt + 4'd1;
                if (mul_cnt == 4'd15) begin
                    mul_busy <= 1'b0;
                    rdy_h    <= mul_h;
                    rdy_s    <= mul_s;
                    rdy_p    <= mul_sum;
                end
            end
        end else begin
            mul_h    <= eff_half_in;
            mul_s    <= cw_step_reg;
            mul_q    <= eff_half_in;
            mul_d    <= cw_step_reg;
            mul_acc  <= 32'd0;
            mul_cnt  <= 4'd0;
            mul_busy <= 1'b1;
        end
    end

    // ---- carrier ------------------------------------------------------------------------------
    reg  [31:0] step;      // STEP in use
    reg  [31:0] hs;        // H*STEP mod 2^32 of the (half, step) in use
    reg  [31:0] m2cs;      // 2*c*STEP mod 2^32 of the current tick

    wire [16:0] period  = {half, 1'b0};
    assign rising    = phase < {1'b0, half};
    assign at_bottom = (phase == 17'd0);
    assign at_top    = (phase == {1'b0, half});
    assign at_zc     = (phase == {2'b00, half[15:1]});
    wire [15:0] fall_count = period[15:0] - phase[15:0];   // P - phi <= H < 2^16: exact mod 2^16
    assign counter   = rising ? phase[15:0] : fall_count;

    // last tick of the period (>= so that any out-of-range phase also returns to 0)
    wire wrap = (phase >= period - 17'd1);

    reg  [16:0] phase_n;
    reg  [15:0] half_n;
    reg  [31:0] step_n;
    reg  [31:0] hs_n;
    reg  [31:0] m2cs_n;
    wire [31:0] two_step = {step[30:0], 1'b0};

    always @(*) begin
        if (rst) begin
            phase_n = 17'd0;
            half_n  = eff_half_in;
            step_n  = cw_step_reg;
            m2cs_n  = 32'd0;
        end else if (wrap) begin                 // next tick is a bottom: apply the ready triple
            phase_n = 17'd0;
            half_n  = rdy_h;
            step_n  = rdy_s;
            m2cs_n  = 32'd0;
        end else begin
            phase_n = phase + 17'd1;
            half_n  = half;
            step_n  = step;
            m2cs_n  = rising ? m2cs + two_step : m2cs - two_step;   // c rises / falls by 1
        end
        // the product of the pair in use, as soon as it is known (always at a bottom)
        if (rdy_h == half_n && rdy_s == step_n)
            hs_n = rdy_p;
        else
            hs_n = hs;
    end

    always @(posedge clk) begin
        phase    <= phase_n;
        half     <= half_n;
        step     <= step_n;
        hs       <= hs_n;
        m2cs     <= m2cs_n;
        cw_angle <= hs_n - m2cs_n;
    end
endmodule

`default_nettype wire
