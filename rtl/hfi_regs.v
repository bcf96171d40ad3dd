`default_nettype none
// hfi_regs: AXI4-Lite register block of hfi_dsp (docs/registers.md, docs/spec.md section 4).
//
// Addresses, field positions, widths and reset values come from rtl/regs/hfi_regs_map.vh, generated
// from the SystemRDL source rtl/regs/hfi_regs.rdl by scripts/gen_regs.py; cocotb_tests/tb_regs.py
// checks every register's reset value and access type against golden/regmap.py (same source).
//
// Bus: AXI4-Lite slave, 32-bit data, ADDR_BITS-bit byte addresses (ADDR_BITS >= 8: the map spans
// 0x00-0xFF). Every address bit is decoded: an address that is not word aligned, not in the map or
// (ADDR_BITS > 8) has a bit above bit 7 set is outside the map (no aliasing).
//  - Write: AW and W are accepted together (AWREADY = WREADY) in the clock after both are seen valid,
//    while no response is pending; the response BVALID follows in the next cycle. WSTRB selects
//    bytes. (Registered first: timing in the SoC. A master must hold VALID until READY, AXI4.)
//  - Read: ARREADY rises in the clock after ARVALID is seen (the address is registered first, so the
//    read multiplexer starts from flip-flops: timing in the SoC, where ARADDR comes through the
//    bus adapter's logic), while no read data is pending; RDATA/RVALID in the cycle after the
//    handshake, with the values just before the handshake edge.
//  - An address outside the map answers SLVERR (reads return 0, writes change nothing).
//  - A write to a register locked by SAFETY_LOCK.LOCK (the RDL's swwel: DEAD_TICKS, OC_LIMIT,
//    WDT_PERIODS, list generated as hfi_locked_by_safety_lock_lock) while the lock is 1 changes
//    nothing and answers SLVERR. LOCK is write-1-to-set and cleared only by rst (docs/spec.md 3.8).
// Access types (from the RDL): rw storage; ro (hardware values); w1p (write 1: one-clock pulse,
// reads 0: CTRL.FAULT_CLEAR, COMMIT.GO); w1c (IRQ_STATUS.WINDOW: hardware set wins over a clear);
// w1s (SAFETY_LOCK.LOCK).
// The interrupt line irq = |(IRQ_STATUS & IRQ_ENABLE), registered.
module hfi_regs #(
    parameter ADDR_BITS = 8,
    // the optional blocks of the build (hfi_dsp's parameters of the same names), read in CAPS
    parameter ROT_INJ = 1,
    parameter DIFF_CIC = 1,
    parameter FCS_MPC = 1
) (
    input  wire        clk,
    input  wire        rst,
    // AXI4-Lite slave
    input  wire [ADDR_BITS-1:0] s_axil_awaddr,
    input  wire        s_axil_awvalid,
    output wire        s_axil_awready,
    input  wire [31:0] s_axil_wdata,
    input  wire [3:0]  s_axil_wstrb,
    input  wire        s_axil_wvalid,
    output wire        s_axil_wready,
    output reg  [1:0]  s_axil_bresp,
    output reg         s_axil_bvalid,
    input  wire        s_axil_bready,
    input  wire [ADDR_BITS-1:0] s_axil_araddr,
    input  wire        s_axil_arvalid,
    output wire        s_axil_arready,
    output reg  [31:0] s_axil_rdata,
    output reg  [1:0]  s_axil_rresp,
    output reg         s_axil_rvalid,
    input  wire        s_axil_rready,
    // software -> hardware
    output wire        ctrl_enable,
    output wire        ctrl_inj_en,
    output wire        ctrl_inj_rot,
    output wire        ctrl_inj_per,
    output wire        ctrl_direct,
    output wire [1:0]  ctrl_adc_mode,
    output reg         fault_clear,       // one-clock pulse
    output reg         commit_go,         // one-clock pulse
    output wire [15:0] pwm_half,
    output wire [15:0] dead_ticks,
    output wire [15:0] os_ticks,
    output wire [15:0] blank_ticks,
    output wire [31:0] cw_angle_step,
    output wire signed [15:0] adc_offset_a,
    output wire signed [15:0] adc_offset_b,
    output wire [15:0] adc_gain_a,
    output wire [15:0] adc_gain_b,
    output wire [15:0] oc_limit,
    output wire [15:0] wdt_periods,
    output wire signed [15:0] v_d,
    output wire signed [15:0] v_q,
    output wire [14:0] v_h,
    output wire signed [15:0] sin_q15,
    output wire signed [15:0] cos_q15,
    output wire [15:0] dtc_gain,
    output wire [14:0] hf_amp,
    output wire [31:0] recip_h,
    output wire signed [15:0] i_d_ref,
    output wire signed [15:0] i_q_ref,
    output wire [31:0] inj_step,
    output wire [7:0]  cic_m,
    output wire signed [15:0] fcs_a1,
    output wire signed [15:0] fcs_a2,
    output wire [15:0] fcs_phi_min,
    output wire        fcs_constrain,
    // hardware -> software
    input  wire        status_fault_oc,
    input  wire        status_fault_wdt,
    input  wire        status_outputs_on,
    input  wire        status_commit_pending,
    input  wire        status_fault_sto,
    input  wire        status_fault_desat,
    input  wire        status_sto_active,
    input  wire        status_desat_active,
    input  wire        irq_window_set,    // one-clock pulse: window results latched
    input  wire [31:0] gamma,
    input  wire [31:0] gamma_d,
    input  wire [31:0] sum_id,
    input  wire [31:0] sum_iq,
    input  wire [31:0] wsum,
    input  wire [15:0] n_samples,
    input  wire [31:0] window_count,
    input  wire [15:0] late_count,
    input  wire [31:0] inj_phase,
    input  wire [31:0] cic_qa,            // CIC_QA ... ENV_B: sign-extended by hfi_dsp
    input  wire [31:0] cic_qb,
    input  wire [31:0] env_a,
    input  wire [31:0] env_b,
    input  wire [2:0]  vector_state,      // VECTOR.STATE
    input  wire [2:0]  vector_next,       // VECTOR.NEXT (the modulator's state for the next top, not latched)
    input  wire [15:0] top_i_alpha,       // TOP_I.I_ALPHA, TOP_I.I_BETA (s16 each)
    input  wire [15:0] top_i_beta,
    input  wire [15:0] vdc_code,          // VDC.CODE (u16)
    input  wire        win_fault_oc,      // WIN_FAULT.OC ... DESAT: the fault latches at the window boundary,
    input  wire        win_fault_wdt,     // latched by hfi_dsp with the window results (spec 2.2, 3.7)
    input  wire        win_fault_sto,
    input  wire        win_fault_desat,
    input  wire        win_adc_frozen_a,  // WIN_ADC.FROZEN_A, FROZEN_B: every conversion of the window returned one
    input  wire        win_adc_frozen_b,  // raw code on lane A / B, latched by hfi_dsp with the window results (3.13)
    output reg         irq,
    // every word as a read returns it (word i = byte address 4*i; unmapped words and COMMIT 0), for the SoC's
    // copy of the window results (rtl/hfi_win_copy.v)
    output wire [2047:0] read_words
);
/* verilator lint_off UNUSEDPARAM */  // the generated map lists every field; not all are needed here
`include "regs/hfi_regs_map.vh"
/* verilator lint_on UNUSEDPARAM */

    localparam [1:0] RESP_OKAY = 2'b00, RESP_SLVERR = 2'b10;

    // ---------------------------------------------------------------- storage (rw fields)
    reg [31:0] r_ctrl, r_irq_status, r_irq_enable, r_pwm_half, r_dead_ticks, r_os_ticks, r_blank_ticks,
               r_cw_angle_step, r_adc_offset, r_adc_gain, r_oc_limit, r_wdt_periods, r_v_dq, r_v_h,
               r_sincos, r_speed_ref, r_dtc_gain, r_hf_amp, r_recip_h, r_i_ref, r_inj_step, r_cic_m,
               r_fcs_a, r_fcs_ctrl;
    reg        r_safety_lock;

    // Field mask and reset word of a register, from the generated constants.
    function [31:0] fmask(input integer lsb, input integer width);
        begin
            fmask = (width >= 32) ? 32'hFFFFFFFF : (((32'h1 << width) - 32'h1) << lsb);
        end
    endfunction

    localparam [31:0] M_CTRL = fmask(HFI_CTRL_ENABLE_LSB, HFI_CTRL_ENABLE_WIDTH)
                             | fmask(HFI_CTRL_INJ_EN_LSB, HFI_CTRL_INJ_EN_WIDTH)
                             | fmask(HFI_CTRL_ADC_MODE_LSB, HFI_CTRL_ADC_MODE_WIDTH)
                             | fmask(HFI_CTRL_INJ_ROT_LSB, HFI_CTRL_INJ_ROT_WIDTH)
                             | fmask(HFI_CTRL_INJ_PER_LSB, HFI_CTRL_INJ_PER_WIDTH)
                             | fmask(HFI_CTRL_DIRECT_LSB, HFI_CTRL_DIRECT_WIDTH);
    localparam [31:0] RST_CTRL = ({31'd0, HFI_CTRL_ENABLE_RESET} << HFI_CTRL_ENABLE_LSB)
                               | ({31'd0, HFI_CTRL_INJ_EN_RESET} << HFI_CTRL_INJ_EN_LSB)
                               | ({30'd0, HFI_CTRL_ADC_MODE_RESET} << HFI_CTRL_ADC_MODE_LSB)
                               | ({31'd0, HFI_CTRL_INJ_ROT_RESET} << HFI_CTRL_INJ_ROT_LSB)
                               | ({31'd0, HFI_CTRL_INJ_PER_RESET} << HFI_CTRL_INJ_PER_LSB)
                               | ({31'd0, HFI_CTRL_DIRECT_RESET} << HFI_CTRL_DIRECT_LSB);
    localparam [31:0] M_IRQ = fmask(HFI_IRQ_STATUS_WINDOW_LSB, HFI_IRQ_STATUS_WINDOW_WIDTH);
    localparam [31:0] M_U16 = 32'h0000FFFF, M_U15 = 32'h00007FFF, M_U8 = 32'h000000FF, M_ALL = 32'hFFFFFFFF;
    localparam [31:0] RST_IRQ_ENABLE = {31'd0, HFI_IRQ_ENABLE_WINDOW_RESET} << HFI_IRQ_ENABLE_WINDOW_LSB;
    localparam [31:0] RST_ADC_OFFSET = {HFI_ADC_OFFSET_B_RESET, HFI_ADC_OFFSET_A_RESET};
    localparam [31:0] RST_ADC_GAIN = {HFI_ADC_GAIN_B_RESET, HFI_ADC_GAIN_A_RESET};
    localparam [31:0] RST_V_DQ = {HFI_V_DQ_V_Q_RESET, HFI_V_DQ_V_D_RESET};
    localparam [31:0] RST_SINCOS = {HFI_SINCOS_COS_RESET, HFI_SINCOS_SIN_RESET};
    localparam [31:0] RST_FCS_A = {HFI_FCS_A_A2_RESET, HFI_FCS_A_A1_RESET};
    localparam [31:0] RST_FCS_CTRL = ({31'd0, HFI_FCS_CTRL_CONSTRAIN_RESET} << HFI_FCS_CTRL_CONSTRAIN_LSB)
                                   | {16'd0, HFI_FCS_CTRL_PHI_MIN_RESET};
    localparam [31:0] M_FCS_CTRL = fmask(HFI_FCS_CTRL_PHI_MIN_LSB, HFI_FCS_CTRL_PHI_MIN_WIDTH)
                                 | fmask(HFI_FCS_CTRL_CONSTRAIN_LSB, HFI_FCS_CTRL_CONSTRAIN_WIDTH);
    localparam [31:0] RST_I_REF = {HFI_I_REF_I_Q_RESET, HFI_I_REF_I_D_RESET};

    // ---------------------------------------------------------------- write channel
    // AW and W are registered first (AXI: address, data and strobes are stable while VALID waits for
    // READY) and accepted one clock later: every write enable then starts from flip-flops (timing in
    // the SoC, where the VALIDs come through the bus adapter's logic). A master must hold VALID
    // until READY (AXI4 rule): the write uses what was presented in the clock before the handshake.
    // The address is decoded while it is registered: a one-hot word select (aligned, upper bits zero),
    // whether it names a register of the map and whether SAFETY_LOCK covers it.  Each clock enable in
    // the acceptance clock is then one select bit, WSTRB, the lock and the handshake: one LUT level
    // from flip-flops (timing on the large ECP5 die, where these nets cross it).
    localparam N_WORDS = 64;
    reg       aw_seen;
    reg [N_WORDS-1:0] wr_sel_q;
    reg       wr_known_q, wr_lockable_q;
    reg [31:0] wdata_q;
    reg [3:0] wstrb_q;
    wire wr_fire = aw_seen & ~s_axil_bvalid;
    assign s_axil_awready = wr_fire;
    assign s_axil_wready = wr_fire;
    // The map is decoded on 8 address bits; with ADDR_BITS > 8 an address with any upper bit set is
    // outside the map (SLVERR, no aliasing of the 256-byte map over the wider window).
    wire [7:0] wr_addr, rd_addr;
    wire wr_hi_zero, rd_hi_zero;
    generate
        if (ADDR_BITS > 8) begin : g_wide_addr
            assign wr_addr = s_axil_awaddr[7:0];
            assign rd_addr = s_axil_araddr[7:0];
            assign wr_hi_zero = ~|s_axil_awaddr[ADDR_BITS-1:8];
            assign rd_hi_zero = ~|s_axil_araddr[ADDR_BITS-1:8];
        end else begin : g_narrow_addr
            assign wr_addr = {{(8 - ADDR_BITS){1'b0}}, s_axil_awaddr};
            assign rd_addr = {{(8 - ADDR_BITS){1'b0}}, s_axil_araddr};
            assign wr_hi_zero = 1'b1;
            assign rd_hi_zero = 1'b1;
        end
    endgenerate
    always @(posedge clk) begin
        aw_seen <= ~rst & s_axil_awvalid & s_axil_wvalid & ~wr_fire;
        wr_sel_q <= (wr_hi_zero && wr_addr[1:0] == 2'd0) ? ({{(N_WORDS-1){1'b0}}, 1'b1} << wr_addr[7:2])
                                                          : {N_WORDS{1'b0}};
        wr_known_q <= wr_hi_zero && known_addr(wr_addr);
        wr_lockable_q <= hfi_locked_by_safety_lock_lock(wr_addr);
        wdata_q <= s_axil_wdata;
        wstrb_q <= s_axil_wstrb;
    end
    // a write to a register of the map that SAFETY_LOCK does not hold (other addresses: SLVERR, no effect)
    wire wr_locked = r_safety_lock & wr_lockable_q;
    // the write enable of the word at each address (one select bit, the lock folded to a constant)
    wire [N_WORDS-1:0] wr_en;
    genvar we;
    generate
        for (we = 0; we < N_WORDS; we = we + 1) begin : g_wr_en
            localparam [7:0] WORD_ADDR = 4 * we;
            assign wr_en[we] = wr_fire & wr_sel_q[we]
                               & ~(r_safety_lock & hfi_locked_by_safety_lock_lock(WORD_ADDR));
        end
    endgenerate
    wire [31:0] byte_mask = {{8{wstrb_q[3]}}, {8{wstrb_q[2]}}, {8{wstrb_q[1]}},
                             {8{wstrb_q[0]}}};   // IRQ_STATUS w1c

    // Byte b of a written rw register: the written data of its fields, 0 elsewhere.  Bits outside the
    // fields reset to 0 and are only ever written 0, so this equals "written fields, rest kept" and
    // Yosys drops them; each written byte is a clock enable (wr_en & address & WSTRB[b]) of plain
    // data flip-flops instead of a read-modify-write mux per bit.
    function [7:0] wd_bytes(input integer b, input [31:0] field_mask);
        wd_bytes = wdata_q[8*b +: 8] & field_mask[8*b +: 8];
    endfunction
    integer b;

    function known_addr(input [7:0] a);
        case (a)
            HFI_ID_ADDR, HFI_VERSION_ADDR, HFI_CTRL_ADDR, HFI_STATUS_ADDR, HFI_IRQ_STATUS_ADDR,
            HFI_IRQ_ENABLE_ADDR, HFI_PWM_HALF_ADDR, HFI_DEAD_TICKS_ADDR, HFI_OS_TICKS_ADDR,
            HFI_BLANK_TICKS_ADDR, HFI_CW_ANGLE_STEP_ADDR, HFI_ADC_OFFSET_ADDR, HFI_ADC_GAIN_ADDR,
            HFI_OC_LIMIT_ADDR, HFI_WDT_PERIODS_ADDR, HFI_V_DQ_ADDR, HFI_V_H_ADDR, HFI_SINCOS_ADDR,
            HFI_COMMIT_ADDR, HFI_GAMMA_ADDR, HFI_GAMMA_D_ADDR, HFI_SUM_ID_ADDR, HFI_SUM_IQ_ADDR,
            HFI_WSUM_ADDR, HFI_N_SAMPLES_ADDR, HFI_WINDOW_COUNT_ADDR, HFI_LATE_COUNT_ADDR,
            HFI_SPEED_REF_ADDR, HFI_DTC_GAIN_ADDR, HFI_HF_AMP_ADDR, HFI_RECIP_H_ADDR, HFI_I_REF_ADDR,
            HFI_SAFETY_LOCK_ADDR, HFI_INJ_STEP_ADDR, HFI_INJ_PHASE_ADDR, HFI_CIC_M_ADDR, HFI_CIC_QA_ADDR,
            HFI_CIC_QB_ADDR, HFI_ENV_A_ADDR, HFI_ENV_B_ADDR, HFI_FCS_A_ADDR, HFI_FCS_CTRL_ADDR,
            HFI_VECTOR_ADDR, HFI_TOP_I_ADDR, HFI_VDC_ADDR, HFI_CAPS_ADDR, HFI_WIN_FAULT_ADDR,
            HFI_WIN_ADC_ADDR:
                known_addr = 1'b1;
            default: known_addr = 1'b0;
        endcase
    endfunction

    wire wr_irq_status = wr_en[HFI_IRQ_STATUS_ADDR / 4];
    wire [31:0] irq_clear = wr_irq_status ? (wdata_q & byte_mask & M_IRQ) : 32'd0;

    always @(posedge clk) begin
        if (rst) begin
            r_ctrl <= RST_CTRL;
            r_irq_status <= 32'd0;
            r_irq_enable <= RST_IRQ_ENABLE;
            r_pwm_half <= {16'd0, HFI_PWM_HALF_VALUE_RESET};
            r_dead_ticks <= {16'd0, HFI_DEAD_TICKS_VALUE_RESET};
            r_os_ticks <= {16'd0, HFI_OS_TICKS_VALUE_RESET};
            r_blank_ticks <= {16'd0, HFI_BLANK_TICKS_VALUE_RESET};
            r_cw_angle_step <= HFI_CW_ANGLE_STEP_VALUE_RESET;
            r_adc_offset <= RST_ADC_OFFSET;
            r_adc_gain <= RST_ADC_GAIN;
            r_oc_limit <= {16'd0, HFI_OC_LIMIT_VALUE_RESET};
            r_wdt_periods <= {16'd0, HFI_WDT_PERIODS_VALUE_RESET};
            r_v_dq <= RST_V_DQ;
            r_v_h <= {17'd0, HFI_V_H_VALUE_RESET};
            r_sincos <= RST_SINCOS;
            r_speed_ref <= HFI_SPEED_REF_VALUE_RESET;
            r_dtc_gain <= {16'd0, HFI_DTC_GAIN_VALUE_RESET};
            r_hf_amp <= {17'd0, HFI_HF_AMP_VALUE_RESET};
            r_recip_h <= HFI_RECIP_H_VALUE_RESET;
            r_i_ref <= RST_I_REF;
            r_inj_step <= HFI_INJ_STEP_VALUE_RESET;
            r_cic_m <= {24'd0, HFI_CIC_M_VALUE_RESET};
            r_fcs_a <= RST_FCS_A;
            r_fcs_ctrl <= RST_FCS_CTRL;
            r_safety_lock <= HFI_SAFETY_LOCK_LOCK_RESET;
            fault_clear <= 1'b0;
            commit_go <= 1'b0;
            s_axil_bvalid <= 1'b0;
            s_axil_bresp <= RESP_OKAY;
        end else begin
            fault_clear <= 1'b0;
            commit_go <= 1'b0;
            // w1c with hardware set winning (precedence = hw)
            r_irq_status <= (r_irq_status & ~irq_clear) | ({31'd0, irq_window_set} << HFI_IRQ_STATUS_WINDOW_LSB);
            if (s_axil_bvalid && s_axil_bready)
                s_axil_bvalid <= 1'b0;
            if (wr_fire) begin
                s_axil_bvalid <= 1'b1;
                s_axil_bresp <= (wr_known_q && !wr_locked) ? RESP_OKAY : RESP_SLVERR;
            end
            if (wr_en[HFI_CTRL_ADDR / 4]) begin
                for (b = 0; b < 4; b = b + 1)
                    if (wstrb_q[b]) r_ctrl[8*b +: 8] <= wd_bytes(b, M_CTRL);
                fault_clear <= wstrb_q[HFI_CTRL_FAULT_CLEAR_LSB / 8]
                               & wdata_q[HFI_CTRL_FAULT_CLEAR_LSB];
            end
            if (wr_en[HFI_IRQ_ENABLE_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_irq_enable[8*b +: 8] <= wd_bytes(b, M_IRQ);
            if (wr_en[HFI_PWM_HALF_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_pwm_half[8*b +: 8] <= wd_bytes(b, M_U16);
            if (wr_en[HFI_DEAD_TICKS_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_dead_ticks[8*b +: 8] <= wd_bytes(b, M_U16);
            if (wr_en[HFI_OS_TICKS_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_os_ticks[8*b +: 8] <= wd_bytes(b, M_U16);
            if (wr_en[HFI_BLANK_TICKS_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_blank_ticks[8*b +: 8] <= wd_bytes(b, M_U16);
            if (wr_en[HFI_CW_ANGLE_STEP_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_cw_angle_step[8*b +: 8] <= wd_bytes(b, M_ALL);
            if (wr_en[HFI_ADC_OFFSET_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_adc_offset[8*b +: 8] <= wd_bytes(b, M_ALL);
            if (wr_en[HFI_ADC_GAIN_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_adc_gain[8*b +: 8] <= wd_bytes(b, M_ALL);
            if (wr_en[HFI_OC_LIMIT_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_oc_limit[8*b +: 8] <= wd_bytes(b, M_U16);
            if (wr_en[HFI_WDT_PERIODS_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_wdt_periods[8*b +: 8] <= wd_bytes(b, M_U16);
            if (wr_en[HFI_V_DQ_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_v_dq[8*b +: 8] <= wd_bytes(b, M_ALL);
            if (wr_en[HFI_V_H_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_v_h[8*b +: 8] <= wd_bytes(b, M_U15);
            if (wr_en[HFI_SINCOS_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_sincos[8*b +: 8] <= wd_bytes(b, M_ALL);
            if (wr_en[HFI_COMMIT_ADDR / 4]) commit_go <= wstrb_q[HFI_COMMIT_GO_LSB / 8] & wdata_q[HFI_COMMIT_GO_LSB];
            if (wr_en[HFI_SPEED_REF_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_speed_ref[8*b +: 8] <= wd_bytes(b, M_ALL);
            if (wr_en[HFI_DTC_GAIN_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_dtc_gain[8*b +: 8] <= wd_bytes(b, M_U16);
            if (wr_en[HFI_HF_AMP_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_hf_amp[8*b +: 8] <= wd_bytes(b, M_U15);
            if (wr_en[HFI_RECIP_H_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_recip_h[8*b +: 8] <= wd_bytes(b, M_ALL);
            if (wr_en[HFI_I_REF_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_i_ref[8*b +: 8] <= wd_bytes(b, M_ALL);
            if (wr_en[HFI_INJ_STEP_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_inj_step[8*b +: 8] <= wd_bytes(b, M_ALL);
            if (wr_en[HFI_CIC_M_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_cic_m[8*b +: 8] <= wd_bytes(b, M_U8);
            if (wr_en[HFI_FCS_A_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_fcs_a[8*b +: 8] <= wd_bytes(b, M_ALL);
            if (wr_en[HFI_FCS_CTRL_ADDR / 4]) for (b = 0; b < 4; b = b + 1) if (wstrb_q[b]) r_fcs_ctrl[8*b +: 8] <= wd_bytes(b, M_FCS_CTRL);
            if (wr_en[HFI_SAFETY_LOCK_ADDR / 4])
                if (wstrb_q[HFI_SAFETY_LOCK_LOCK_LSB / 8] & wdata_q[HFI_SAFETY_LOCK_LOCK_LSB])
                    r_safety_lock <= 1'b1;
        end
    end

    // ---------------------------------------------------------------- read channel
    // ARADDR is stable while ARVALID waits for ARREADY (AXI): register it, accept one clock later
    reg [7:0] rd_addr_q;
    reg       rd_hi_zero_q, ar_seen;
    assign s_axil_arready = ar_seen & ~s_axil_rvalid;
    always @(posedge clk) begin
        rd_addr_q <= rd_addr;
        rd_hi_zero_q <= rd_hi_zero;
        ar_seen <= ~rst & s_axil_arvalid & ~s_axil_arready;
    end
    wire [31:0] status_word = ({31'd0, status_fault_oc} << HFI_STATUS_FAULT_OC_LSB)
                            | ({31'd0, status_fault_wdt} << HFI_STATUS_FAULT_WDT_LSB)
                            | ({31'd0, status_outputs_on} << HFI_STATUS_OUTPUTS_ON_LSB)
                            | ({31'd0, status_commit_pending} << HFI_STATUS_COMMIT_PENDING_LSB)
                            | ({31'd0, status_fault_sto} << HFI_STATUS_FAULT_STO_LSB)
                            | ({31'd0, status_fault_desat} << HFI_STATUS_FAULT_DESAT_LSB)
                            | ({31'd0, status_sto_active} << HFI_STATUS_STO_ACTIVE_LSB)
                            | ({31'd0, status_desat_active} << HFI_STATUS_DESAT_ACTIVE_LSB);
    // Read data: the readable words form a table indexed by the word address (rd_addr[7:2]); the
    // table is built from the generated map (a case on a constant address per entry, so each entry is
    // plain wiring), and the read selects one word of it (below).  Unaligned or unmapped addresses and
    // COMMIT (w1p) read 0.
    wire [32*N_WORDS-1:0] rd_table;
    genvar wi;
    generate
        for (wi = 0; wi < N_WORDS; wi = wi + 1) begin : g_rd_table
            localparam [7:0] A = wi * 4;
            reg [31:0] w;
            always @(*) begin
                case (A)
                    HFI_ID_ADDR: w = HFI_ID_VALUE_RESET;
                    HFI_VERSION_ADDR: w = {HFI_VERSION_MAJOR_RESET, HFI_VERSION_MINOR_RESET};
                    HFI_CTRL_ADDR: w = r_ctrl;
                    HFI_STATUS_ADDR: w = status_word;
                    HFI_IRQ_STATUS_ADDR: w = r_irq_status;
                    HFI_IRQ_ENABLE_ADDR: w = r_irq_enable;
                    HFI_PWM_HALF_ADDR: w = r_pwm_half;
                    HFI_DEAD_TICKS_ADDR: w = r_dead_ticks;
                    HFI_OS_TICKS_ADDR: w = r_os_ticks;
                    HFI_BLANK_TICKS_ADDR: w = r_blank_ticks;
                    HFI_CW_ANGLE_STEP_ADDR: w = r_cw_angle_step;
                    HFI_ADC_OFFSET_ADDR: w = r_adc_offset;
                    HFI_ADC_GAIN_ADDR: w = r_adc_gain;
                    HFI_OC_LIMIT_ADDR: w = r_oc_limit;
                    HFI_WDT_PERIODS_ADDR: w = r_wdt_periods;
                    HFI_V_DQ_ADDR: w = r_v_dq;
                    HFI_V_H_ADDR: w = r_v_h;
                    HFI_SINCOS_ADDR: w = r_sincos;
                    HFI_GAMMA_ADDR: w = gamma;
                    HFI_GAMMA_D_ADDR: w = gamma_d;
                    HFI_SUM_ID_ADDR: w = sum_id;
                    HFI_SUM_IQ_ADDR: w = sum_iq;
                    HFI_WSUM_ADDR: w = wsum;
                    HFI_N_SAMPLES_ADDR: w = {16'd0, n_samples};
                    HFI_WINDOW_COUNT_ADDR: w = window_count;
                    HFI_LATE_COUNT_ADDR: w = {16'd0, late_count};
                    HFI_SPEED_REF_ADDR: w = r_speed_ref;
                    HFI_DTC_GAIN_ADDR: w = r_dtc_gain;
                    HFI_HF_AMP_ADDR: w = r_hf_amp;
                    HFI_RECIP_H_ADDR: w = r_recip_h;
                    HFI_I_REF_ADDR: w = r_i_ref;
                    HFI_INJ_STEP_ADDR: w = r_inj_step;
                    HFI_INJ_PHASE_ADDR: w = inj_phase;
                    HFI_CIC_M_ADDR: w = r_cic_m;
                    HFI_CIC_QA_ADDR: w = cic_qa;
                    HFI_CIC_QB_ADDR: w = cic_qb;
                    HFI_ENV_A_ADDR: w = env_a;
                    HFI_ENV_B_ADDR: w = env_b;
                    HFI_FCS_A_ADDR: w = r_fcs_a;
                    HFI_FCS_CTRL_ADDR: w = r_fcs_ctrl;
                    HFI_VECTOR_ADDR: w = {25'd0, vector_next, 1'b0, vector_state};
                    HFI_TOP_I_ADDR: w = ({16'd0, top_i_alpha} << HFI_TOP_I_I_ALPHA_LSB)
                                      | ({16'd0, top_i_beta} << HFI_TOP_I_I_BETA_LSB);
                    HFI_VDC_ADDR: w = {16'd0, vdc_code} << HFI_VDC_CODE_LSB;
                    HFI_CAPS_ADDR: w = ({31'd0, ROT_INJ != 0} << HFI_CAPS_ROT_INJ_LSB)
                                     | ({31'd0, DIFF_CIC != 0} << HFI_CAPS_DIFF_CIC_LSB)
                                     | ({31'd0, FCS_MPC != 0} << HFI_CAPS_FCS_MPC_LSB);
                    HFI_WIN_FAULT_ADDR: w = ({31'd0, win_fault_oc} << HFI_WIN_FAULT_OC_LSB)
                                          | ({31'd0, win_fault_wdt} << HFI_WIN_FAULT_WDT_LSB)
                                          | ({31'd0, win_fault_sto} << HFI_WIN_FAULT_STO_LSB)
                                          | ({31'd0, win_fault_desat} << HFI_WIN_FAULT_DESAT_LSB);
                    HFI_WIN_ADC_ADDR: w = ({31'd0, win_adc_frozen_a} << HFI_WIN_ADC_FROZEN_A_LSB)
                                        | ({31'd0, win_adc_frozen_b} << HFI_WIN_ADC_FROZEN_B_LSB);
                    HFI_SAFETY_LOCK_ADDR: w = {31'd0, r_safety_lock} << HFI_SAFETY_LOCK_LOCK_LSB;
                    default: w = 32'd0;   // COMMIT (w1p) and unmapped addresses read 0
                endcase
            end
            assign rd_table[32*wi +: 32] = w;
        end
    endgenerate
    assign read_words = rd_table;
    // The word is selected by a one-hot register decoded with the address (rd_sel_q, same timing as
    // rd_addr_q): an AND-OR of the table instead of a 64-way multiplexer on the index (timing in the
    // SoC: the synthesized multiplexer was a chain of seven LUTs). No bit set: 0.
    reg  [N_WORDS-1:0] rd_sel_q;
    always @(posedge clk)
        rd_sel_q <= (rd_hi_zero && rd_addr[1:0] == 2'b00) ? ({{(N_WORDS-1){1'b0}}, 1'b1} << rd_addr[7:2])
                                                          : {N_WORDS{1'b0}};
    reg  [31:0] rd_word;
    integer wj;
    always @* begin
        rd_word = 32'd0;
        for (wj = 0; wj < N_WORDS; wj = wj + 1)
            rd_word = rd_word | (rd_table[32*wj +: 32] & {32{rd_sel_q[wj]}});
    end

    always @(posedge clk) begin
        if (rst) begin
            s_axil_rvalid <= 1'b0;
            s_axil_rdata <= 32'd0;
            s_axil_rresp <= RESP_OKAY;
            irq <= 1'b0;
        end else begin
            irq <= |(r_irq_status & r_irq_enable & M_IRQ);
            if (s_axil_rvalid && s_axil_rready)
                s_axil_rvalid <= 1'b0;
            if (s_axil_arready) begin   // ARVALID is high: it was in the clock before (ar_seen) and is held
                s_axil_rvalid <= 1'b1;
                s_axil_rdata <= rd_word;
                s_axil_rresp <= (rd_hi_zero_q && known_addr(rd_addr_q)) ? RESP_OKAY : RESP_SLVERR;
            end
        end
    end

    // ---------------------------------------------------------------- field outputs
    assign ctrl_enable = r_ctrl[HFI_CTRL_ENABLE_LSB];
    assign ctrl_inj_en = r_ctrl[HFI_CTRL_INJ_EN_LSB];
    assign ctrl_inj_rot = r_ctrl[HFI_CTRL_INJ_ROT_LSB];
    assign ctrl_inj_per = r_ctrl[HFI_CTRL_INJ_PER_LSB];
    assign ctrl_adc_mode = r_ctrl[HFI_CTRL_ADC_MODE_LSB +: 2];
    assign pwm_half = r_pwm_half[15:0];
    assign dead_ticks = r_dead_ticks[15:0];
    assign os_ticks = r_os_ticks[15:0];
    assign blank_ticks = r_blank_ticks[15:0];
    assign cw_angle_step = r_cw_angle_step;
    assign adc_offset_a = r_adc_offset[HFI_ADC_OFFSET_A_LSB +: 16];
    assign adc_offset_b = r_adc_offset[HFI_ADC_OFFSET_B_LSB +: 16];
    assign adc_gain_a = r_adc_gain[HFI_ADC_GAIN_A_LSB +: 16];
    assign adc_gain_b = r_adc_gain[HFI_ADC_GAIN_B_LSB +: 16];
    assign oc_limit = r_oc_limit[15:0];
    assign wdt_periods = r_wdt_periods[15:0];
    assign v_d = r_v_dq[HFI_V_DQ_V_D_LSB +: 16];
    assign v_q = r_v_dq[HFI_V_DQ_V_Q_LSB +: 16];
    assign v_h = r_v_h[14:0];
    assign sin_q15 = r_sincos[HFI_SINCOS_SIN_LSB +: 16];
    assign cos_q15 = r_sincos[HFI_SINCOS_COS_LSB +: 16];
    assign dtc_gain = r_dtc_gain[15:0];
    assign hf_amp = r_hf_amp[14:0];
    assign recip_h = r_recip_h;
    assign i_d_ref = r_i_ref[HFI_I_REF_I_D_LSB +: 16];
    assign i_q_ref = r_i_ref[HFI_I_REF_I_Q_LSB +: 16];
    assign inj_step = r_inj_step;
    assign cic_m = r_cic_m[7:0];
    assign ctrl_direct = r_ctrl[HFI_CTRL_DIRECT_LSB];
    assign fcs_a1 = r_fcs_a[HFI_FCS_A_A1_LSB +: 16];
    assign fcs_a2 = r_fcs_a[HFI_FCS_A_A2_LSB +: 16];
    assign fcs_phi_min = r_fcs_ctrl[HFI_FCS_CTRL_PHI_MIN_LSB +: 16];
    assign fcs_constrain = r_fcs_ctrl[HFI_FCS_CTRL_CONSTRAIN_LSB];
endmodule
`default_nettype wire
