`default_nettype none
// hfi_dsp: the FPGA data path of the 002 system (Benevieri et al. 2023, Fig. 1 and Sec. II-B) as an
// AXI4-Lite peripheral with one interrupt: PWM carrier with square-wave injection, dead-time gate
// generator, ADC trigger and serial ADC interface, offset/gain, Clarke/Park, CORDIC demodulation
// weights, the eps integrator reset on every carrier rising zero crossing, the window sums, the
// overcurrent trip and the firmware watchdog. docs/rtl.md describes the timing; docs/spec.md the
// arithmetic; docs/registers.md the registers. Every block equals its golden model bit for bit
// (cocotb_tests/), and the whole IP replays the golden closed loop (cocotb_tests/test_dsp_replay.py).
//
// Parameters
//   ADC_BITS, ADC_CONV_TICKS, ADC_SCLK_HALF  serial ADC (hfi_adc_if): resolution, conversion time,
//                                            SCLK half period [clocks]
//   CORDIC_WIDTH, CORDIC_ITERATIONS          demodulation-weight CORDIC (spec 3.3)
//   DEAD_MIN                                 dead-time floor [clocks] (spec 2.4)
//   IRQ_LATENCY                              window interrupt, clocks after the window boundary
//   OS_MIN                                   shortest sampling interval (spec 2.3); must be at least
//                                            max(CORDIC_ITERATIONS + 8, ADC cycle): checked below and
//                                            in hfi_adc_if (MAX_CYCLE); a 16-bit ADC at the default
//                                            timing needs OS_MIN >= 46
//   ROT_INJ, DIFF_CIC, FCS_MPC               build options (docs/rtl.md "Build options"), 1 = the block
//                                            is built: the rotating injection's sin/cos CORDIC, the
//                                            differencing/CIC block, the FCS-MPC vector choice. 0 leaves
//                                            it out: its results are 0 (no rotating voltage; CIC_QA/QB,
//                                            ENV_A/B read 0; the direct mode applies state 0). CAPS reads them.
//
// Window bookkeeping (docs/rtl.md): every sample carries the parity of the window of its sampling
// tick and its OS_BLANK keep flag through the pipeline. The Park unit rotates it with the SIN/COS
// committed for that window (two banks, by parity); the demodulator latches the previous window when
// the first sample of a new window arrives, or at the window deadline (IRQ_LATENCY - 8 clocks after
// the boundary) if none has arrived yet. So no latency constant of another module is repeated here.
//
// Period square wave and the differencing/CIC block (docs/spec.md 3.5 and 3.9; Xue et al. 2022): the
// sign S of CTRL.INJ_PER lives here (inj_s: decided at the boundary, flipped at the bottom, see the
// section below); the sample of every carrier bottom carries a tag through the ADC, scale and Park
// stages, and its Clarke currents (hfi_park's i_alpha, i_beta) step hfi_diff_cic with the `plus` and
// CIC_M captured in its bottom tick. The block's outputs are latched at the next window boundary into
// CIC_QA/QB, ENV_A/B (with INJ_PHASE).
//
// Carrier-top sample (docs/spec.md 3.11): the sample of every carrier top (phase H; DS always, OS when H
// is a multiple of OS_TICKS) carries a second tag; when hfi_park is done with it and it is not blanked
// (OS_BLANK keep flag), its Clarke currents are held (top_ia_h, top_ib_h) and latched at the next window
// boundary into TOP_I with the other window results (a window without a top sample keeps TOP_I).
//
// DC-link voltage (docs/spec.md 3.12): the ADC's third channel converts with every sample; the code of
// the carrier-bottom sample (the bottom tag) is held and latched at the next window boundary into VDC.
//
// Window faults (docs/spec.md 2.2, 3.7): the four fault latches of STATUS as they read in the boundary
// tick are held and copied into WIN_FAULT with WINDOW_COUNT, so the firmware reads them at a fixed instant.
//
// Frozen ADC channels (docs/spec.md 3.13): every conversion's raw codes of the two current lanes are compared
// with the first conversion of its window (by the window parity tag, in the ADC's done cycle); per lane, "all
// equal, at least 2 conversions" is copied into WIN_ADC with WIN_FAULT.
module hfi_dsp #(
    parameter ADC_BITS = 12,
    parameter ADC_CONV_TICKS = 12,
    parameter ADC_SCLK_HALF = 1,
    parameter CORDIC_WIDTH = 32,
    parameter CORDIC_ITERATIONS = 32,
    parameter DEAD_MIN = 50,
    parameter IRQ_LATENCY = 400,
    parameter OS_MIN = 40,
    parameter ROT_INJ = 1,
    parameter DIFF_CIC = 1,
    parameter FCS_MPC = 1
) (
    input  wire        clk,
    input  wire        rst,
    // timing enable: 0 holds the carrier, sampling, windows and gates at their reset state while the
    // registers stay writable; the carrier's tick 0 is the second clock with rst = 0 and run = 1
    // (the timing reset is registered; pins: PIN_LATENCY, docs/rtl.md).
    // Tie to 1 to start at reset.
    input  wire        run,
    // AXI4-Lite slave (byte addresses 0x00..0xFF)
    input  wire [7:0]  s_axil_awaddr,
    input  wire        s_axil_awvalid,
    output wire        s_axil_awready,
    input  wire [31:0] s_axil_wdata,
    input  wire [3:0]  s_axil_wstrb,
    input  wire        s_axil_wvalid,
    output wire        s_axil_wready,
    output wire [1:0]  s_axil_bresp,
    output wire        s_axil_bvalid,
    input  wire        s_axil_bready,
    input  wire [7:0]  s_axil_araddr,
    input  wire        s_axil_arvalid,
    output wire        s_axil_arready,
    output wire [31:0] s_axil_rdata,
    output wire [1:0]  s_axil_rresp,
    output wire        s_axil_rvalid,
    input  wire        s_axil_rready,
    output wire        irq,
    // for a copy of the window results in another clock (hfi_soc: rtl/hfi_win_copy.v): every register's
    // read value (word i = byte address 4*i, as hfi_regs answers a read) and a toggle that flips in the
    // clock after the registers with the RDL property window_copy (rtl/regs/hfi_regs.rdl) have taken the
    // window's values (with IRQ_STATUS.WINDOW's set), and in the clock they take their reset values when
    // run falls; they hold from each flip until the next window boundary
    output wire [2047:0] reg_words,
    output reg         window_tog,
    // gate signals: bit 2x = high switch of leg x, 2x+1 = low switch (a, b, c = 0, 1, 2)
    output wire [5:0]  gate,
    // serial simultaneous-sampling ADC (phases a and b, the dc link)
    output wire        adc_convst,
    output wire        adc_cs_n,
    output wire        adc_sclk,
    input  wire        adc_sdo_a,
    input  wire        adc_sdo_b,
    input  wire        adc_sdo_c,
    // safety pins (asynchronous, active high; docs/spec.md 3.8, hfi_safety): Safe Torque Off request
    // and gate-driver fault (DESAT); drive_allowed is for the gate driver's enable pin
    input  wire        sto,
    input  wire        desat,
    output wire        drive_allowed
);
    // ---------------------------------------------------------------- parameter checks
    generate
        if (IRQ_LATENCY < 64 || IRQ_LATENCY > 500) begin : bad_irq_latency
            hfi_dsp_parameter_error_IRQ_LATENCY_must_be_64_to_500 bad();
        end
        if (OS_MIN < CORDIC_ITERATIONS + 8) begin : bad_os_min
            hfi_dsp_parameter_error_OS_MIN_below_CORDIC_ITERATIONS_plus_8 bad();
        end
    endgenerate

    // ---------------------------------------------------------------- reset of the timing
    // Everything but the register block: a register, so that the timing reset reaches the whole
    // data path from one flip-flop (SoC timing, docs/boards.md); hence tick 0 is the second clock
    // with rst = 0 and run = 1, and PIN_LATENCY (hfi/soc_platform.py) counts that clock.
    // One copy per block (a reset tree: the same flip-flop input, so every copy switches in the same
    // clock; `keep` so that synthesis does not merge them): the placer puts each next to its block
    // instead of one net with hundreds of loads across the die (ULX3S timing, docs/boards.md).
    // No name may end in _gold or _gate: Yosys' equiv_make (the ECP5 target-equivalence proof of
    // scripts/synth_report.py) names its copies of a wire x as x_gold and x_gate and stops on a clash.
    (* keep *) reg rst_dp, rst_car, rst_mod, rst_gates, rst_trg, rst_adc, rst_park, rst_dm;
    always @(posedge clk)
        {rst_dp, rst_car, rst_mod, rst_gates, rst_trg, rst_adc, rst_park, rst_dm} <= {8{rst | ~run}};

    // ---------------------------------------------------------------- registers
    wire        ctrl_enable, ctrl_inj_en, ctrl_inj_rot, ctrl_inj_per, ctrl_direct, fault_clear, commit_go;
    wire signed [15:0] sh_fcs_a1, sh_fcs_a2;   // FCS_A, FCS_CTRL (shadow; spec 3.10)
    wire [15:0] sh_fcs_phi_min;
    wire        sh_fcs_constrain;
    reg  [2:0]  vector_q;                 // VECTOR: latched at the boundary
    wire [2:0]  mod_state;                // the direct-vector mode's state applied (modulator)
    wire [1:0]  ctrl_adc_mode;
    wire [15:0] pwm_half_reg, dead_ticks, os_ticks, blank_ticks, adc_gain_a, adc_gain_b, oc_limit,
                wdt_periods, dtc_gain;
    wire [31:0] cw_step_reg, recip_h, inj_step;
    wire [7:0]  cic_m_reg;
    reg  [31:0] inj_phase_q;
    reg  signed [20:0] cic_qa_q, cic_qb_q;   // CIC_QA, CIC_QB, ENV_A, ENV_B: latched at the boundary
    reg  signed [16:0] env_a_q, env_b_q;
    reg  signed [15:0] top_ia_q, top_ib_q;   // TOP_I: latched at the boundary
    reg  [15:0] vdc_q;                       // VDC: latched at the boundary
    reg  [3:0]  win_fault_q;                 // WIN_FAULT {DESAT, STO, WDT, OC}: copied with the window results
    reg  [1:0]  win_adc_q;                   // WIN_ADC {FROZEN_B, FROZEN_A}: copied with the window results
    wire signed [15:0] adc_offset_a, adc_offset_b, sh_v_d, sh_v_q, sh_sin, sh_cos, sh_i_d_ref, sh_i_q_ref;
    wire [14:0] sh_v_h, hf_amp;
    wire signed [31:0] gamma, gamma_d, sum_id, sum_iq, wsum;
    wire [15:0] n_samples;
    reg  [31:0] window_count;
    reg  [15:0] late_count;
    wire        fault_oc, fault_wdt, fault_sto, fault_desat, sto_s, desat_s;
    reg         commit_pending, irq_window_set;
    wire        outputs_on;

    hfi_regs #(.ROT_INJ(ROT_INJ), .DIFF_CIC(DIFF_CIC), .FCS_MPC(FCS_MPC)) u_regs (
        .clk(clk), .rst(rst),
        .s_axil_awaddr(s_axil_awaddr), .s_axil_awvalid(s_axil_awvalid), .s_axil_awready(s_axil_awready),
        .s_axil_wdata(s_axil_wdata), .s_axil_wstrb(s_axil_wstrb), .s_axil_wvalid(s_axil_wvalid),
        .s_axil_wready(s_axil_wready), .s_axil_bresp(s_axil_bresp), .s_axil_bvalid(s_axil_bvalid),
        .s_axil_bready(s_axil_bready), .s_axil_araddr(s_axil_araddr), .s_axil_arvalid(s_axil_arvalid),
        .s_axil_arready(s_axil_arready), .s_axil_rdata(s_axil_rdata), .s_axil_rresp(s_axil_rresp),
        .s_axil_rvalid(s_axil_rvalid), .s_axil_rready(s_axil_rready),
        .ctrl_enable(ctrl_enable), .ctrl_inj_en(ctrl_inj_en), .ctrl_inj_rot(ctrl_inj_rot),
        .ctrl_inj_per(ctrl_inj_per), .ctrl_direct(ctrl_direct), .ctrl_adc_mode(ctrl_adc_mode),
        .fault_clear(fault_clear), .commit_go(commit_go),
        .pwm_half(pwm_half_reg), .dead_ticks(dead_ticks), .os_ticks(os_ticks), .blank_ticks(blank_ticks),
        .cw_angle_step(cw_step_reg), .adc_offset_a(adc_offset_a), .adc_offset_b(adc_offset_b),
        .adc_gain_a(adc_gain_a), .adc_gain_b(adc_gain_b), .oc_limit(oc_limit), .wdt_periods(wdt_periods),
        .v_d(sh_v_d), .v_q(sh_v_q), .v_h(sh_v_h), .sin_q15(sh_sin), .cos_q15(sh_cos),
        .dtc_gain(dtc_gain), .hf_amp(hf_amp), .recip_h(recip_h), .i_d_ref(sh_i_d_ref), .i_q_ref(sh_i_q_ref),
        .inj_step(inj_step), .inj_phase(inj_phase_q), .cic_m(cic_m_reg),
        .fcs_a1(sh_fcs_a1), .fcs_a2(sh_fcs_a2), .fcs_phi_min(sh_fcs_phi_min), .fcs_constrain(sh_fcs_constrain),
        .vector_state(vector_q), .vector_next(mod_state), .top_i_alpha(top_ia_q), .top_i_beta(top_ib_q),
        .vdc_code(vdc_q),
        .win_fault_oc(win_fault_q[0]), .win_fault_wdt(win_fault_q[1]), .win_fault_sto(win_fault_q[2]),
        .win_fault_desat(win_fault_q[3]),
        .win_adc_frozen_a(win_adc_q[0]), .win_adc_frozen_b(win_adc_q[1]),
        .cic_qa({{11{cic_qa_q[20]}}, cic_qa_q}), .cic_qb({{11{cic_qb_q[20]}}, cic_qb_q}),
        .env_a({{15{env_a_q[16]}}, env_a_q}), .env_b({{15{env_b_q[16]}}, env_b_q}),
        .status_fault_oc(fault_oc), .status_fault_wdt(fault_wdt), .status_outputs_on(outputs_on),
        .status_fault_sto(fault_sto), .status_fault_desat(fault_desat), .status_sto_active(sto_s),
        .status_desat_active(desat_s),
        .status_commit_pending(commit_pending), .irq_window_set(irq_window_set),
        .gamma(gamma), .gamma_d(gamma_d), .sum_id(sum_id), .sum_iq(sum_iq), .wsum(wsum),
        .n_samples(n_samples), .window_count(window_count), .late_count(late_count), .irq(irq),
        .read_words(reg_words)
    );

    // ---------------------------------------------------------------- carrier (spec 2.1)
    wire [16:0] phase;
    wire [15:0] counter, half;
    wire        rising, at_bottom, at_top, at_zc;
    wire [31:0] cw_angle;
    hfi_carrier u_carrier (
        .clk(clk), .rst(rst_car), .pwm_half_reg(pwm_half_reg), .cw_step_reg(cw_step_reg),
        .phase(phase), .counter(counter), .half(half), .rising(rising), .at_bottom(at_bottom),
        .at_top(at_top), .at_zc(at_zc), .cw_angle(cw_angle)
    );

    // ---------------------------------------------------------------- commit at the window boundary (spec 2.2)
    // Active copies of the shadow registers; INJ_EN is applied at every boundary.
    reg signed [15:0] act_v_d, act_v_q, act_sin, act_cos, act_i_d_ref, act_i_q_ref;
    reg [14:0] act_v_h;
    reg        act_inj_en, act_inj_rot;
    reg        act_direct;              // CTRL.DIRECT, applied at every boundary
    reg signed [15:0] act_fcs_a1, act_fcs_a2;
    reg [15:0] act_fcs_phi_min;
    reg        act_fcs_constrain;
    reg        win_parity;              // parity of the window of the current tick (window -1: 1)
    reg signed [15:0] bank_sin [0:1];   // SIN/COS of the last windows of each parity, for Park
    reg signed [15:0] bank_cos [0:1];
    reg [15:0] windows_without_commit;
    reg        zc_d1;                   // the cycle after a boundary: the modulator starts

    always @(posedge clk) begin
        if (rst_dp) begin
            act_v_d <= 16'sd0; act_v_q <= 16'sd0; act_v_h <= 15'd0;
            act_sin <= 16'sd0; act_cos <= 16'sd32767;
            act_i_d_ref <= 16'sd0; act_i_q_ref <= 16'sd0;
            act_inj_en <= 1'b0;
            act_inj_rot <= 1'b0;
            act_direct <= 1'b0;
            act_fcs_a1 <= 16'sd0; act_fcs_a2 <= 16'sd0; act_fcs_phi_min <= 16'd0; act_fcs_constrain <= 1'b0;
            vector_q <= 3'd0;
            win_parity <= 1'b1;
            bank_sin[0] <= 16'sd0; bank_cos[0] <= 16'sd32767;
            bank_sin[1] <= 16'sd0; bank_cos[1] <= 16'sd32767;
            commit_pending <= 1'b0;
            late_count <= 16'd0;
            windows_without_commit <= 16'd0;
            zc_d1 <= 1'b0;
        end else begin
            zc_d1 <= at_zc;
            if (commit_go)
                commit_pending <= 1'b1;
            if (at_zc) begin
                win_parity <= ~win_parity;
                act_inj_en <= ctrl_inj_en;
                act_inj_rot <= ctrl_inj_en & ctrl_inj_rot;
                act_direct <= ctrl_direct;
                // VECTOR: the state set by the latest latches (the modulator's next one is computed from
                // the following cycle on and kept 105 cycles later)
                vector_q <= mod_state;
                if (commit_pending || commit_go) begin
                    commit_pending <= 1'b0;
                    act_v_d <= sh_v_d; act_v_q <= sh_v_q; act_v_h <= sh_v_h;
                    act_sin <= sh_sin; act_cos <= sh_cos;
                    act_i_d_ref <= sh_i_d_ref; act_i_q_ref <= sh_i_q_ref;
                    act_fcs_a1 <= sh_fcs_a1; act_fcs_a2 <= sh_fcs_a2;
                    act_fcs_phi_min <= sh_fcs_phi_min; act_fcs_constrain <= sh_fcs_constrain;
                    bank_sin[~win_parity] <= sh_sin; bank_cos[~win_parity] <= sh_cos;
                    windows_without_commit <= 16'd0;
                end else begin
                    bank_sin[~win_parity] <= act_sin; bank_cos[~win_parity] <= act_cos;
                    if (late_count != 16'hFFFF)
                        late_count <= late_count + 16'd1;
                    if (windows_without_commit != 16'hFFFF)
                        windows_without_commit <= windows_without_commit + 16'd1;
                end
            end
        end
    end

    // ---------------------------------------------------------------- rotating injection (spec 3.5)
    // golden/fpga/rot_injection.py: the accumulator inj_acc (0 after reset); at a boundary with the
    // rotating injection on, the sets computed there use phi = inj_acc and inj_acc advances by
    // INJ_STEP; off, phi and inj_acc are 0. INJ_PHASE latches phi at the next boundary. The CORDIC
    // computes sin/cos of inj_acc, the next boundary's phi, in the cycles after each boundary (and
    // after reset), so the modulator finds them ready when it starts (zc_d1): one sin/cos per period.
    reg  [31:0] inj_acc, inj_phi;
    reg         inj_init;                // the first cycle after reset: sin/cos of inj_acc = 0
    wire signed [15:0] inj_sin, inj_cos;
    always @(posedge clk) begin
        if (rst_dp) begin
            inj_acc <= 32'd0;
            inj_phi <= 32'd0;
            inj_phase_q <= 32'd0;
            inj_init <= 1'b1;
        end else begin
            inj_init <= 1'b0;
            if (at_zc) begin
                inj_phase_q <= inj_phi;
                if (ctrl_inj_en & ctrl_inj_rot) begin
                    inj_phi <= inj_acc;
                    inj_acc <= inj_acc + inj_step;
                end else begin
                    inj_phi <= 32'd0;
                    inj_acc <= 32'd0;
                end
            end
        end
    end
    generate
        if (ROT_INJ != 0) begin : g_rot_inj
            hfi_cordic #(.WIDTH(32), .ITERATIONS(16)) u_inj_cordic (
                .clk(clk), .rst(rst_dp), .start(zc_d1 | inj_init), .angle(inj_acc),
                /* verilator lint_off PINCONNECTEMPTY */
                .busy(), .done(),
                /* verilator lint_on PINCONNECTEMPTY */
                .sin_q15(inj_sin), .cos_q15(inj_cos)
            );
        end else begin : g_no_rot_inj          // build option: the rotating vector is 0
            assign inj_sin = 16'sd0;
            assign inj_cos = 16'sd0;
            wire unused_rot = inj_init;
        end
    endgenerate

    // ---------------------------------------------------------------- period square wave (spec 3.5)
    // golden/closedloop.py inj_sign. The mode (CTRL.INJ_PER and not INJ_ROT) is latched at every window
    // boundary into per_act, which follows the register while the timing is held in reset (so the value
    // written before tick 0 rules tick 0's bottom, as ADC_MODE does). inj_s is S (1: +1, 0: -1) of the
    // current PWM period: +1 after reset; at every carrier bottom S <= per_act ? -S : +1 (+1 while the
    // mode is off). The sign of a bottom is decided at the boundary before it: the modulator starts
    // (zc_d1) after the boundary of window k, when inj_s is S_k (the bottom k*P has passed) and
    // per_act the mode of this window; its top set (period k) uses S_k and its bottom set (period k+1,
    // latched at (k+1)*P, where inj_s becomes -S_k with the same per_act) -S_k. S_k = +1 is the plain
    // square wave's pair of signs, so the modulator only swaps them: inj_neg = per_act & (S_k = -1).
    // plus_bot: at each bottom, the period ending there ran S = +1 with the mode on (DiffCic.step's
    // plus); cic_m_bot: CIC_M in that bottom tick. Both hold for a whole period, until the bottom sample
    // reaches hfi_diff_cic (a few tens of clocks later), so the sample needs no tag for them.
    wire per_mode = ctrl_inj_per & ~ctrl_inj_rot;
    reg  per_act, inj_s, plus_bot;
    reg  [7:0] cic_m_bot;
    always @(posedge clk) begin
        if (at_bottom)
            cic_m_bot <= cic_m_reg;
        if (rst_dp) begin
            per_act <= per_mode;
            inj_s <= 1'b1;
            plus_bot <= 1'b0;
        end else begin
            if (at_zc)
                per_act <= per_mode;
            if (at_bottom) begin
                plus_bot <= per_act & inj_s;
                inj_s <= per_act ? ~inj_s : 1'b1;
            end
        end
    end

    // ---------------------------------------------------------------- modulator (spec 3.5, 3.6)
    wire [15:0] dead_eff = (dead_ticks < DEAD_MIN) ? DEAD_MIN[15:0] : dead_ticks;
    wire [15:0] cmp_top_a, cmp_top_b, cmp_top_c, cmp_bot_a, cmp_bot_b, cmp_bot_c;
    wire        mod_busy, mod_done;
    hfi_modulator #(.FCS_MPC(FCS_MPC)) u_modulator (
        .clk(clk), .rst(rst_mod), .start(zc_d1),
        .v_d(act_v_d), .v_q(act_v_q), .v_h(act_inj_en ? {1'b0, act_v_h} : 16'sd0),
        .rot(act_inj_rot), .inj_neg(per_act & ~inj_s), .inj_sin(inj_sin), .inj_cos(inj_cos),
        .direct(act_direct), .fcs_a1(act_fcs_a1), .fcs_a2(act_fcs_a2), .fcs_phi_min(act_fcs_phi_min),
        .fcs_constrain(act_fcs_constrain), .state(mod_state),
        .sin_q15(act_sin), .cos_q15(act_cos), .i_d_ref(act_i_d_ref), .i_q_ref(act_i_q_ref),
        .half(half), .dead(dead_eff), .dtc_gain(dtc_gain), .hf_amp(hf_amp), .recip_h(recip_h),
        .cmp_top_a(cmp_top_a), .cmp_top_b(cmp_top_b), .cmp_top_c(cmp_top_c),
        .cmp_bot_a(cmp_bot_a), .cmp_bot_b(cmp_bot_b), .cmp_bot_c(cmp_bot_c),
        .busy(mod_busy), .done(mod_done)
    );

    // ---------------------------------------------------------------- enable, faults, gates (spec 2.4, 3.7, 3.8)
    wire       gen_enable, kill, oc_trip;
    wire       wdt_expired = wdt_periods != 16'd0 && windows_without_commit >= wdt_periods;
    wire [2:0] ideal_s;
    wire [5:0] gate_gen_out;
    wire       sw_event;
    hfi_gate_gen #(.DEAD_MIN(DEAD_MIN)) u_gate_gen (
        .clk(clk), .rst(rst_gates), .phase(phase), .half(half), .at_bottom(at_bottom), .at_top(at_top),
        .cmp_bot_a(cmp_bot_a), .cmp_bot_b(cmp_bot_b), .cmp_bot_c(cmp_bot_c),
        .cmp_top_a(cmp_top_a), .cmp_top_b(cmp_top_b), .cmp_top_c(cmp_top_c),
        .dead_reg(dead_ticks), .enable(gen_enable), .kill(kill),
        .gate(gate_gen_out), .s(ideal_s), .sw_event(sw_event)
    );
    // Fault latches, STO/DESAT and the output register (docs/rtl.md, PIN_LATENCY = 3): the pins are
    // driven straight from flip-flops, and the gates keep the same one-tick offset to the sampling
    // instants as CONVST (below).
    hfi_safety u_safety (
        .clk(clk), .rst(rst_gates), .sto(sto), .desat(desat), .oc_trip(oc_trip), .wdt_expired(wdt_expired),
        .fault_clear(fault_clear), .ctrl_enable(ctrl_enable), .at_bottom(at_bottom), .gate_in(gate_gen_out),
        .gate(gate), .kill(kill), .enable(gen_enable), .sto_s(sto_s), .desat_s(desat_s),
        .fault_oc(fault_oc), .fault_wdt(fault_wdt), .fault_sto(fault_sto), .fault_desat(fault_desat),
        .outputs_on(outputs_on), .drive_allowed(drive_allowed)
    );

    // ---------------------------------------------------------------- sampling (spec 2.3)
    wire sample, sample_keep;
    wire [1:0] adc_mode_used;
    hfi_adc_trigger #(.OS_MIN(OS_MIN)) u_trigger (
        .clk(clk), .rst(rst_trg), .phase(phase), .half(half), .at_zc(at_zc), .at_bottom(at_bottom),
        .mode_reg(ctrl_adc_mode), .os_ticks_reg(os_ticks), .blank_ticks_reg(blank_ticks),
        .sw_event(sw_event), .sample(sample), .keep(sample_keep), .mode(adc_mode_used)
    );
    // Window parity of the sampling tick: a sample at the boundary tick belongs to the new window.
    // The sampling instant, its flags and its weight angle are registered once before they start the
    // ADC and the CORDIC (timing: the trigger's blanking depends on this tick's switch events), so
    // CONVST of the sample of tick t rises with the gate mask of tick t (PIN_LATENCY, docs/rtl.md).
    reg sample_q, keep_q, parity_q, bot_q, top_q;
    reg [31:0] angle_q;
    always @(posedge clk) begin
        sample_q <= rst_dp ? 1'b0 : sample;
        keep_q <= sample_keep;
        bot_q <= at_bottom;             // the sample of a carrier bottom (every ADC mode takes it)
        top_q <= at_top;                // the sample of a carrier top (spec 3.11: DS, OS on the grid)
        parity_q <= at_zc ? ~win_parity : win_parity;
        angle_q <= cw_angle;
    end

    // ---- current path: serial ADC -> offset/gain -> (overcurrent) -> Clarke/Park
    wire [ADC_BITS-1:0] code_a, code_b, code_c;
    wire adc_busy, adc_done;
    hfi_adc_if #(.ADC_BITS(ADC_BITS), .CONV_TICKS(ADC_CONV_TICKS), .SCLK_HALF(ADC_SCLK_HALF),
                 .MAX_CYCLE(OS_MIN)) u_adc (
        .clk(clk), .rst(rst_adc), .start(sample_q), .adc_convst(adc_convst), .adc_cs_n(adc_cs_n),
        .adc_sclk(adc_sclk), .adc_sdo_a(adc_sdo_a), .adc_sdo_b(adc_sdo_b), .adc_sdo_c(adc_sdo_c),
        .busy(adc_busy), .done(adc_done), .code_a(code_a), .code_b(code_b), .code_c(code_c)
    );
    reg tag_adc_keep, tag_adc_par, tag_adc_bot, tag_adc_top;   // tags of the sample in the ADC
    always @(posedge clk)
        if (sample_q && !adc_busy) begin
            tag_adc_keep <= keep_q;
            tag_adc_par <= parity_q;
            tag_adc_bot <= bot_q;
            tag_adc_top <= top_q;
        end

    wire signed [15:0] i_a, i_b;
    wire scale_done;
    hfi_adc_scale #(.ADC_BITS(ADC_BITS)) u_scale (
        .clk(clk), .rst(rst_adc), .start(adc_done), .code_a(code_a), .code_b(code_b),
        .offset_a(adc_offset_a), .offset_b(adc_offset_b), .gain_a(adc_gain_a), .gain_b(adc_gain_b),
        .done(scale_done), .i_a(i_a), .i_b(i_b)
    );
    reg tag_scale_keep, tag_scale_par, tag_scale_bot, tag_scale_top;
    always @(posedge clk)
        if (adc_done) begin
            tag_scale_keep <= tag_adc_keep;
            tag_scale_par <= tag_adc_par;
            tag_scale_bot <= tag_adc_bot;
            tag_scale_top <= tag_adc_top;
        end

    hfi_overcurrent u_oc (
        .clk(clk), .rst(rst_adc), .valid(scale_done), .i_a(i_a), .i_b(i_b), .limit(oc_limit), .trip(oc_trip)
    );

    wire signed [15:0] i_d, i_q, i_alpha, i_beta;
    wire park_done;
    hfi_park u_park (
        .clk(clk), .rst(rst_park), .start(scale_done), .i_a(i_a), .i_b(i_b),
        .sin_q15(bank_sin[tag_scale_par]), .cos_q15(bank_cos[tag_scale_par]),
        .done(park_done), .i_d(i_d), .i_q(i_q), .i_alpha(i_alpha), .i_beta(i_beta)
    );
    reg tag_park_keep, tag_park_par, tag_park_bot, tag_park_top;
    always @(posedge clk)
        if (scale_done) begin
            tag_park_keep <= tag_scale_keep;
            tag_park_par <= tag_scale_par;
            tag_park_bot <= tag_scale_bot;
            tag_park_top <= tag_scale_top;
        end

    // ---- differencing and CIC of the carrier-bottom samples (spec 3.9, golden/fpga/diff_cic.py)
    // One step per bottom sample, in the cycle hfi_park is done with it (its Clarke currents are valid
    // then); plus and CIC_M of its bottom tick (above). The sample at tick 0 (window -1) is the first
    // after reset: it only fills the previous sample (the golden loop, which starts at window 0, takes
    // the one at tick P as its first; the state is the same, since the period ending at P has S = -1,
    // or the mode is off and no difference is ever kept). The outputs are latched at the next window
    // boundary, H/2 >= 256 clocks after the bottom (the step completes a few tens of clocks after it:
    // checked below).
    wire signed [20:0] cic_q_a, cic_q_b;
    wire signed [16:0] cic_e_a, cic_e_b;
    wire cic_done;
    generate
        if (DIFF_CIC != 0) begin : g_diff_cic
            hfi_diff_cic u_diff_cic (
                .clk(clk), .rst(rst_park), .in_valid(park_done & tag_park_bot), .i_alpha(i_alpha),
                .i_beta(i_beta), .plus(plus_bot), .cic_m(cic_m_bot), .q_a(cic_q_a), .q_b(cic_q_b),
                .e_a(cic_e_a), .e_b(cic_e_b), .out_valid(cic_done)
            );
        end else begin : g_no_diff_cic          // build option: CIC_QA/QB, ENV_A/B read 0
            assign cic_q_a = 21'sd0;
            assign cic_q_b = 21'sd0;
            assign cic_e_a = 17'sd0;
            assign cic_e_b = 17'sd0;
            assign cic_done = park_done & tag_park_bot;   // no step to wait for
            wire unused_cic = &{1'b0, plus_bot, cic_m_bot};
        end
    endgenerate
    always @(posedge clk) begin
        if (rst_dp) begin
            cic_qa_q <= 21'sd0; cic_qb_q <= 21'sd0;
            env_a_q <= 17'sd0; env_b_q <= 17'sd0;
        end else if (at_zc) begin
            cic_qa_q <= cic_q_a; cic_qb_q <= cic_q_b;
            env_a_q <= cic_e_a; env_b_q <= cic_e_b;
        end
    end

    // ---- carrier-top sample (spec 3.11, golden/closedloop.py _top_sample): TOP_I
    // The Clarke currents of the top sample (phase H), held in the cycle hfi_park is done with it unless
    // OS_BLANK dropped it (keep = 0: blanked samples still pass through the pipeline), and latched at
    // the next window boundary, 3H/2 >= 768 clocks after the top (checked below). A window without a
    // kept top sample leaves the hold, so TOP_I keeps the previous value; 0 after reset. Every mode.
    reg signed [15:0] top_ia_h, top_ib_h;
    always @(posedge clk) begin
        if (rst_dp) begin
            top_ia_h <= 16'sd0; top_ib_h <= 16'sd0;
            top_ia_q <= 16'sd0; top_ib_q <= 16'sd0;
        end else begin
            if (park_done && tag_park_top && tag_park_keep) begin
                top_ia_h <= i_alpha; top_ib_h <= i_beta;
            end
            if (at_zc) begin
                top_ia_q <= top_ia_h; top_ib_q <= top_ib_h;
            end
        end
    end

    // ---- dc-link voltage (spec 3.12, golden/closedloop.py): VDC
    // The third channel's code of the carrier-bottom sample, held when the ADC is done with it (a few
    // tens of clocks after the bottom) and latched at the next window boundary, H/2 >= 256 clocks after
    // the bottom (the CIC check below covers the longer path of the same sample). Every mode; 0 after reset.
    /* verilator lint_off UNUSEDSIGNAL */  // the top ADC_BITS bits of the extension are never used
    wire [ADC_BITS+15:0] code_c_ext = {16'd0, code_c};
    /* verilator lint_on UNUSEDSIGNAL */
    reg [15:0] vdc_h;
    always @(posedge clk) begin
        if (rst_dp) begin
            vdc_h <= 16'd0;
            vdc_q <= 16'd0;
        end else begin
            if (adc_done && tag_adc_bot)
                vdc_h <= code_c_ext[15:0];
            if (at_zc)
                vdc_q <= vdc_h;
        end
    end

    // ---- weight path: CORDIC of the carrier angle of the sampling tick (spec 3.3, eq. (19))
    wire signed [15:0] w_sin, w_cos_unused;
    wire cordic_busy, cordic_done;
    hfi_cordic #(.WIDTH(CORDIC_WIDTH), .ITERATIONS(CORDIC_ITERATIONS)) u_cordic (
        .clk(clk), .rst(rst_park), .start(sample_q), .angle(angle_q), .busy(cordic_busy), .done(cordic_done),
        .sin_q15(w_sin), .cos_q15(w_cos_unused)
    );

    // ---- join the current and the weight of one sample; window bookkeeping
    // The sample joins in the cycle its later half arrives. Its operands need no capture register:
    // hfi_park and hfi_cordic hold their results until their next done, and the tags of the Park stage
    // until the next sample's scale_done, none of which can come before the join (one sample per stage
    // at a time: the checks at the end; the next scale_done is OS_MIN - 7 or more cycles after this
    // park_done, and OS_MIN + L_ADC + 4 - ITERATIONS - 2 >= 10 cycles after this cordic_done).
    reg got_i, got_w;
    wire join_both = (got_i | park_done) & (got_w | cordic_done);
    always @(posedge clk) begin
        if (rst_dp) begin
            got_i <= 1'b0; got_w <= 1'b0;
        end else if (join_both) begin
            got_i <= 1'b0; got_w <= 1'b0;
        end else begin
            if (park_done) got_i <= 1'b1;
            if (cordic_done) got_w <= 1'b1;
        end
    end
    wire signed [15:0] dm_i_d = i_d;
    wire signed [15:0] dm_i_q = i_q;
    wire signed [15:0] dm_w = w_sin;
    wire dm_keep = tag_park_keep;
    wire dm_par = tag_park_par;

    // The demodulator accumulates the window of parity acc_parity; a sample of the other parity, or
    // the deadline of the window, ends it (latch).
    reg acc_parity;
    reg [15:0] since_zc;
    reg at_deadline;                    // since_zc == IRQ_LATENCY - 8 (registered: one cycle before)
    wire sample_ends = join_both && dm_par != acc_parity;
    wire deadline_ends = at_deadline && acc_parity != win_parity;
    wire demod_latch = sample_ends | deadline_ends;
    // the clock the window results are copied for the firmware (WINDOW_COUNT, WIN_FAULT, WIN_ADC), IRQ_LATENCY
    // after the boundary; IRQ_STATUS.WINDOW is set in the next one
    wire results_copy = since_zc == IRQ_LATENCY - 1;
    wire demod_latched;
    always @(posedge clk) begin
        if (rst_dp) begin
            acc_parity <= 1'b1;
            since_zc <= 16'hFFFF;
            at_deadline <= 1'b0;
            irq_window_set <= 1'b0;
            window_count <= 32'd0;
        end else begin
            since_zc <= at_zc ? 16'd0 : (since_zc == 16'hFFFF ? since_zc : since_zc + 16'd1);
            at_deadline <= !at_zc && since_zc == IRQ_LATENCY - 9;      // IRQ_LATENCY - 9 >= 55
            if (demod_latch)
                acc_parity <= ~acc_parity;
            irq_window_set <= results_copy;
            if (results_copy)
                window_count <= window_count + 32'd1;
        end
    end

    // window_tog (the port's comment above): flips with irq_window_set, one clock after WINDOW_COUNT, WIN_FAULT
    // and WIN_ADC took their values (the demodulator's, INJ_PHASE, CIC_*, ENV_*, TOP_I and VDC did so earlier in
    // the window), and in the clock the timing reset takes effect (rst_dp rose a clock before)
    reg rst_dp_q;
    always @(posedge clk) begin
        if (rst) begin
            window_tog <= 1'b0;
            rst_dp_q <= 1'b1;
        end else begin
            rst_dp_q <= rst_dp;
            if (irq_window_set || (rst_dp && !rst_dp_q))
                window_tog <= ~window_tog;
        end
    end

    // ---- window faults (spec 2.2, 3.7): WIN_FAULT
    // The fault latches (STATUS.FAULT_OC, FAULT_WDT, FAULT_STO, FAULT_DESAT) as they read in the boundary
    // tick, held in win_fault_b and copied to WIN_FAULT in the clock WINDOW_COUNT increments (IRQ_LATENCY
    // after the boundary, before IRQ_STATUS.WINDOW): the firmware's read of window k gives the faults latched
    // by the end of window k, whenever its handler runs within the next period. A fault that reads 1 from the
    // boundary tick on counts in the window that ends there. 0 after reset.
    reg [3:0] win_fault_b;
    always @(posedge clk) begin
        if (rst_dp) begin
            win_fault_b <= 4'd0;
            win_fault_q <= 4'd0;
        end else begin
            if (at_zc)
                win_fault_b <= {fault_desat, fault_sto, fault_wdt, fault_oc};
            if (results_copy)
                win_fault_q <= win_fault_b;
        end
    end

    // ---- frozen ADC channels (spec 3.13): WIN_ADC
    // Per current lane, whether every conversion of a window returned one raw code (hfi_adc_if's code_a, code_b,
    // before hfi_adc_scale). Every conversion counts, blanked or not (the set hfi_overcurrent sees, spec 3.7),
    // taken in its done cycle with its window parity tag (tag_adc_par: the parity of its sampling tick, the one
    // the demodulator's samples carry). The window of parity fz_par holds: its conversions so far (fz_n, saturating
    // at 2), the codes of its first one (fz_ref_a/b) and whether a later one differed (fz_dif_a/b). As for the
    // demodulator's latch (above): a conversion of the other parity ends the window and is the first of the next
    // one; the window deadline ends it if none has arrived by then (the next window's first conversion comes
    // later, e.g. DS: the top, H/2 after the boundary). The flags of the ended window (1: at least 2 conversions,
    // none differed) are held in win_adc_b and copied to WIN_ADC with WIN_FAULT, in the clock WINDOW_COUNT
    // increments; the ending comes first (the deadline is 7 clocks before). Window -1 holds the conversions from
    // tick 0 to the first boundary. 0 after reset.
    reg        fz_par;                      // parity of the window being collected (window -1: 1)
    reg [1:0]  fz_n;                        // its conversions: 0, 1, 2 or more
    reg [ADC_BITS-1:0] fz_ref_a, fz_ref_b;  // its first conversion's codes
    reg        fz_dif_a, fz_dif_b;          // a later conversion returned another code
    reg [1:0]  win_adc_b;                   // {FROZEN_B, FROZEN_A} of the window ended last
    wire fz_end = (adc_done && tag_adc_par != fz_par) || (at_deadline && fz_par != win_parity);
    always @(posedge clk) begin
        if (rst_dp) begin
            fz_par <= 1'b1;
            fz_n <= 2'd0;
            fz_ref_a <= {ADC_BITS{1'b0}}; fz_ref_b <= {ADC_BITS{1'b0}};
            fz_dif_a <= 1'b0; fz_dif_b <= 1'b0;
            win_adc_b <= 2'd0;
            win_adc_q <= 2'd0;
        end else begin
            if (fz_end) begin
                fz_par <= ~fz_par;
                win_adc_b <= {fz_n[1] & ~fz_dif_b, fz_n[1] & ~fz_dif_a};
            end
            if (adc_done && (fz_end || fz_n == 2'd0)) begin          // the first conversion of a window
                fz_n <= 2'd1;
                fz_ref_a <= code_a; fz_ref_b <= code_b;
                fz_dif_a <= 1'b0; fz_dif_b <= 1'b0;
            end else if (adc_done) begin
                fz_n <= 2'd2;
                fz_dif_a <= fz_dif_a | (code_a != fz_ref_a);
                fz_dif_b <= fz_dif_b | (code_b != fz_ref_b);
            end else if (fz_end) begin                               // the deadline: an empty window so far
                fz_n <= 2'd0;
                fz_dif_a <= 1'b0; fz_dif_b <= 1'b0;
            end
            if (results_copy)
                win_adc_q <= win_adc_b;
        end
    end

    hfi_demodulator u_demod (
        .clk(clk), .rst(rst_dm), .valid(join_both), .keep(dm_keep), .i_d(dm_i_d), .i_q(dm_i_q), .w(dm_w),
        .latch(demod_latch), .gamma(gamma), .gamma_d(gamma_d), .sum_id(sum_id), .sum_iq(sum_iq),
        .wsum(wsum), .n_samples(n_samples), .latched(demod_latched)
    );

`ifndef SYNTHESIS
    // Simulation checks of the pipeline assumptions (docs/rtl.md): one sample per stage at a time; the
    // step of a bottom sample is done before the next window boundary latches it.
    reg cic_pending;                    // a bottom sample is between its sampling instant and its step
    reg top_pending;                    // a top sample is between its sampling instant and its Clarke currents
    always @(posedge clk) begin
        cic_pending <= rst_dp ? 1'b0 : (sample_q && bot_q) ? 1'b1 : cic_done ? 1'b0 : cic_pending;
        top_pending <= rst_dp ? 1'b0 : (sample_q && top_q) ? 1'b1 : (park_done && tag_park_top) ? 1'b0
                                     : top_pending;
    end
    always @(posedge clk) begin
        if (!rst_dp && at_zc && cic_pending)
            $error("hfi_dsp: the CIC step of a carrier-bottom sample was not done by the window boundary");
        if (!rst_dp && at_zc && top_pending)
            $error("hfi_dsp: the Clarke currents of a carrier-top sample were not ready by the window boundary");
        if (!rst_dp && got_w && cordic_done && !join_both)
            $error("hfi_dsp: a CORDIC weight arrived before the current of the previous sample");
        if (!rst_dp && got_i && park_done && !join_both)
            $error("hfi_dsp: a current arrived before the weight of the previous sample");
        if (!rst_dp && sample_q && (adc_busy || cordic_busy))
            $error("hfi_dsp: sampling instant while the ADC or the CORDIC is busy (OS_MIN too small)");
        if (!rst_dp && at_deadline && adc_done && tag_adc_par != win_parity)
            $error("hfi_dsp: a conversion of the previous window arrived at the window deadline");
        if (!rst_dp && at_deadline && join_both && dm_par != win_parity)
            $error("hfi_dsp: a sample of the previous window arrived after the window deadline");
    end
`endif

    // Unused outputs of the blocks (kept for debug visibility in waveforms).
    wire unused = &{1'b0, counter, rising, mod_busy, mod_done, ideal_s, adc_mode_used, w_cos_unused,
                    demod_latched, cic_done};
endmodule
`default_nettype wire
