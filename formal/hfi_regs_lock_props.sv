`default_nettype none
// Formal wrapper of rtl/hfi_regs.v for SAFETY_LOCK.LOCK (SymbiYosys: formal/hfi_regs_lock.sby,
// scripts/prove.py).
//
// Every input of hfi_regs is a free input of this wrapper: the whole AXI4-Lite slave side (addresses,
// data, strobes, valids and readies) and every hardware status input; rst is free too.  The one
// assumption is the AXI4 master rule hfi_regs relies on (it registers AW/W/AR before accepting them):
// a VALID not yet accepted stays high, with the same address/data/strobes, in the next clock.  ADDR_BITS = 8 (as in hfi_dsp).  Proven by k-induction
// (sby mode prove, smtbmc) for all input sequences:
//   (o) the lock bit of the RTL (dut.r_safety_lock, observed as lock_obs) equals a reference model:
//       0 after rst, set by a write handshake to SAFETY_LOCK with WSTRB[0] and WDATA[0] set (w1s),
//       cleared by nothing but rst;
//   (i)   once LOCK is 1 it stays 1 until rst (in every clock without rst);
//   (ii)  while LOCK is 1, dead_ticks, oc_limit and wdt_periods do not change in a clock without rst,
//         whatever the bus does (in particular no bus write changes a safety register);
//   (iii) a write handshake to DEAD_TICKS, OC_LIMIT or WDT_PERIODS while LOCK is 1 is answered in the
//         next clock with BVALID and BRESP = SLVERR (2'b10).
// The cover task shows the properties are not vacuous: DEAD_TICKS written (value changed), LOCK set,
// then a write to DEAD_TICKS answered SLVERR with DEAD_TICKS unchanged.
//
// Observing the lock: Yosys' read_verilog (without Verific) has no hierarchical references (a
// "dut.r_safety_lock" here becomes an undriven implicit wire), and the RTL gets no extra port for the
// proof.  So lock_obs is a plain undriven wire of this wrapper, and formal/hfi_regs_lock.sby connects
// it to the flattened register after `flatten` (connect -nounset -set lock_obs dut.r_safety_lock);
// if the register is renamed, that command fails and so does the proof (never a silent free input).
module hfi_regs_lock_props (
    input wire        clk,
    input wire        rst,
    input wire [7:0]  s_axil_awaddr,
    input wire        s_axil_awvalid,
    input wire [31:0] s_axil_wdata,
    input wire [3:0]  s_axil_wstrb,
    input wire        s_axil_wvalid,
    input wire        s_axil_bready,
    input wire [7:0]  s_axil_araddr,
    input wire        s_axil_arvalid,
    input wire        s_axil_rready,
    input wire        status_fault_oc,
    input wire        status_fault_wdt,
    input wire        status_outputs_on,
    input wire        status_commit_pending,
    input wire        status_fault_sto,
    input wire        status_fault_desat,
    input wire        status_sto_active,
    input wire        status_desat_active,
    input wire        irq_window_set,
    input wire [31:0] gamma,
    input wire [31:0] gamma_d,
    input wire [31:0] sum_id,
    input wire [31:0] sum_iq,
    input wire [31:0] wsum,
    input wire [15:0] n_samples,
    input wire [31:0] window_count,
    input wire [15:0] late_count,
    input wire [31:0] inj_phase,
    input wire [31:0] cic_qa,
    input wire [31:0] cic_qb,
    input wire [31:0] env_a,
    input wire [31:0] env_b,
    input wire [2:0]  vector_state,
    input wire [15:0] top_i_alpha,
    input wire [15:0] top_i_beta
);
`include "regs/hfi_regs_map.vh"

    wire        s_axil_awready, s_axil_wready, s_axil_bvalid, s_axil_arready, s_axil_rvalid;
    wire [1:0]  s_axil_bresp, s_axil_rresp;
    wire [31:0] s_axil_rdata;
    wire        ctrl_enable, ctrl_inj_en, fault_clear, commit_go, irq;
    wire [1:0]  ctrl_adc_mode;
    wire [15:0] pwm_half, dead_ticks, os_ticks, blank_ticks, adc_offset_a, adc_offset_b, adc_gain_a,
                adc_gain_b, oc_limit, wdt_periods, v_d, v_q, sin_q15, cos_q15, dtc_gain, i_d_ref, i_q_ref;
    wire [14:0] v_h, hf_amp;
    wire [31:0] cw_angle_step, recip_h;

    hfi_regs #(.ADDR_BITS(8)) dut (
        .clk(clk), .rst(rst),
        .s_axil_awaddr(s_axil_awaddr), .s_axil_awvalid(s_axil_awvalid), .s_axil_awready(s_axil_awready),
        .s_axil_wdata(s_axil_wdata), .s_axil_wstrb(s_axil_wstrb), .s_axil_wvalid(s_axil_wvalid),
        .s_axil_wready(s_axil_wready), .s_axil_bresp(s_axil_bresp), .s_axil_bvalid(s_axil_bvalid),
        .s_axil_bready(s_axil_bready), .s_axil_araddr(s_axil_araddr), .s_axil_arvalid(s_axil_arvalid),
        .s_axil_arready(s_axil_arready), .s_axil_rdata(s_axil_rdata), .s_axil_rresp(s_axil_rresp),
        .s_axil_rvalid(s_axil_rvalid), .s_axil_rready(s_axil_rready),
        .ctrl_enable(ctrl_enable), .ctrl_inj_en(ctrl_inj_en), .ctrl_adc_mode(ctrl_adc_mode),
        .fault_clear(fault_clear), .commit_go(commit_go), .pwm_half(pwm_half), .dead_ticks(dead_ticks),
        .os_ticks(os_ticks), .blank_ticks(blank_ticks), .cw_angle_step(cw_angle_step),
        .adc_offset_a(adc_offset_a), .adc_offset_b(adc_offset_b), .adc_gain_a(adc_gain_a),
        .adc_gain_b(adc_gain_b), .oc_limit(oc_limit), .wdt_periods(wdt_periods), .v_d(v_d), .v_q(v_q),
        .v_h(v_h), .sin_q15(sin_q15), .cos_q15(cos_q15), .dtc_gain(dtc_gain), .hf_amp(hf_amp),
        .recip_h(recip_h), .i_d_ref(i_d_ref), .i_q_ref(i_q_ref),
        .status_fault_oc(status_fault_oc), .status_fault_wdt(status_fault_wdt),
        .status_outputs_on(status_outputs_on), .status_commit_pending(status_commit_pending),
        .status_fault_sto(status_fault_sto), .status_fault_desat(status_fault_desat),
        .status_sto_active(status_sto_active), .status_desat_active(status_desat_active),
        .irq_window_set(irq_window_set), .gamma(gamma), .gamma_d(gamma_d), .sum_id(sum_id),
        .sum_iq(sum_iq), .wsum(wsum), .n_samples(n_samples), .window_count(window_count),
        .late_count(late_count), .inj_phase(inj_phase), .cic_qa(cic_qa), .cic_qb(cic_qb), .env_a(env_a),
        .env_b(env_b), .vector_state(vector_state),
        .top_i_alpha(top_i_alpha), .top_i_beta(top_i_beta), .irq(irq));

    // dut.r_safety_lock: connected by the sby script after flatten (see the header)
    (* keep *) wire lock_obs;

    // a write handshake (AW and W accepted together) and its target
    wire wr_hs = s_axil_awvalid && s_axil_awready && s_axil_wvalid && s_axil_wready;
    wire wr_safety_reg = s_axil_awaddr == HFI_DEAD_TICKS_ADDR || s_axil_awaddr == HFI_OC_LIMIT_ADDR
                      || s_axil_awaddr == HFI_WDT_PERIODS_ADDR;
    wire wr_lock_1 = wr_hs && s_axil_awaddr == HFI_SAFETY_LOCK_ADDR
                  && s_axil_wstrb[HFI_SAFETY_LOCK_LOCK_LSB / 8] && s_axil_wdata[HFI_SAFETY_LOCK_LOCK_LSB];

    // ---------------------------------------------------------------- history
    reg        f_past = 1'b0;
    reg        lock_m = 1'b0;             // reference model of SAFETY_LOCK.LOCK
    reg        past_rst = 1'b0, past_lock = 1'b0, past_wr_locked = 1'b0;
    reg [15:0] past_dead_ticks = 16'd0, past_oc_limit = 16'd0, past_wdt_periods = 16'd0;
    always @(posedge clk) begin
        f_past           <= 1'b1;
        lock_m           <= rst ? 1'b0 : (lock_m | wr_lock_1);
        past_rst         <= rst;
        past_lock        <= lock_obs;
        past_wr_locked   <= wr_hs && wr_safety_reg;
        past_dead_ticks  <= dead_ticks;
        past_oc_limit    <= oc_limit;
        past_wdt_periods <= wdt_periods;
    end

    // the first cycle starts in reset (the registers have no initial value in the RTL)
    always @(*) if (!f_past) assume(rst);

    // AXI4 master rule: VALID and its payload held until READY
    reg        p_aw = 1'b0, p_w = 1'b0, p_ar = 1'b0;
    reg [7:0]  p_awaddr = 8'd0, p_araddr = 8'd0;
    reg [31:0] p_wdata = 32'd0;
    reg [3:0]  p_wstrb = 4'd0;
    always @(posedge clk) begin
        p_aw     <= !rst && s_axil_awvalid && !s_axil_awready;
        p_w      <= !rst && s_axil_wvalid && !s_axil_wready;
        p_ar     <= !rst && s_axil_arvalid && !s_axil_arready;
        p_awaddr <= s_axil_awaddr;
        p_araddr <= s_axil_araddr;
        p_wdata  <= s_axil_wdata;
        p_wstrb  <= s_axil_wstrb;
    end
    always @(*) if (f_past && !rst) begin
        if (p_aw) assume (s_axil_awvalid && s_axil_awaddr == p_awaddr);
        if (p_w)  assume (s_axil_wvalid && s_axil_wdata == p_wdata && s_axil_wstrb == p_wstrb);
        if (p_ar) assume (s_axil_arvalid && s_axil_araddr == p_araddr);
    end

    always @(*) if (f_past) begin
        assert (lock_obs == lock_m);                                   // (o)
        if (past_lock && !past_rst) begin
            assert (lock_obs);                                         // (i)
            assert (dead_ticks == past_dead_ticks);                    // (ii)
            assert (oc_limit == past_oc_limit);
            assert (wdt_periods == past_wdt_periods);
            if (past_wr_locked)                                        // (iii)
                assert (s_axil_bvalid && s_axil_bresp == 2'b10);
        end
    end

    // ---------------------------------------------------------------- cover
    // DEAD_TICKS changed by a write -> LOCK set -> a write to DEAD_TICKS (all strobes, another value)
    // answered SLVERR, DEAD_TICKS unchanged; rst restarts the sequence
    reg [1:0]  stage = 2'd0;
    reg [15:0] past_wdata = 16'd0;
    reg        past_full = 1'b0, past_wr_dead = 1'b0;
    always @(posedge clk) begin
        past_wdata   <= s_axil_wdata[15:0];
        past_full    <= s_axil_wstrb == 4'hF;
        past_wr_dead <= wr_hs && s_axil_awaddr == HFI_DEAD_TICKS_ADDR;
        if (rst)
            stage <= 2'd0;
        else case (stage)
            2'd0: if (f_past && !past_rst && dead_ticks != past_dead_ticks) stage <= 2'd1;
            2'd1: if (lock_obs) stage <= 2'd2;
            default: ;
        endcase
    end
    always @(*) cover (stage == 2'd2 && !past_rst && past_wr_dead && past_full && past_wdata != dead_ticks
                       && s_axil_bvalid && s_axil_bresp == 2'b10);
endmodule

`default_nettype wire
