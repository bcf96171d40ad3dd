`default_nettype none
// tb_soc_bus_fuzz: the SoC's two native-bus slaves, hfi_soc_ctl and hfi_soc_acc (with hfi_ram on the
// accelerator's data port, as in hfi_soc and tb_soc_acc_ram.v), behind a 9-bit address decode (bit 8 =
// 0: ctl page, 1: acc page), a command-driven bus master and a per-cycle checker, for the SoC bus fuzzer
// (cocotb_tests/test_soc_bus_fuzz.py, docs/fuzz.md). The 100 MHz clock runs inside the simulator
// (Verilator --timing); no Python runs per clock.
//
// Master (the CPU's data bus, hfi_soc's convention): it takes the next command (cmd_*, new when cmd_seq
// differs from the last one taken) when it is idle or in the edge that completes the previous access,
// so that accesses follow back to back (sel high again in the clock after ready). A command: cmd_gap
// idle clocks, then either an access (sel with addr, wstrb, wdata held until ready is seen at a rising
// edge; wstrb = 0 is a read) or, with cmd_rst, a reset of cmd_rst_len clocks. An access with cmd_abort
// = n > 0 not answered after n clocks is withdrawn by a reset of cmd_rst_len clocks (a reset in the
// middle of a look-up). Each take toggles take_toggle; each completion (ready, or the end of the reset)
// toggles rsp_toggle, and an answer or an abort latches rsp_* (rdata as hfi_soc muxes it, the clocks
// the access waited, aborted, the ctl cycle count in the clock the access was presented).
//
// Checker, every rising edge after the first reset, cycle c = the cycle the edge ends; cycles with the
// reset high are not checked (the reset withdraws the access):
//   ready  ready of a slave without its sel pending: its sel high in c and also in c - 1 without
//          ready (so: no ready without sel, none for the other page, no second ready for one access)
//   bound  a slave keeps sel waiting: more than CTL_BOUND (hfi_soc_ctl: 1, "answered one clock
//          later") or ACC_BOUND consecutive clocks with sel and no ready; counted once per access
//   mem    the accelerator's mem_en high while the bus does not hold a LUT_IQ write to it (sel, wstrb
//          != 0, not yet answered: docs/acc_registers.md, hfi_flux_lut.v), or a look-up whose write
//          is answered after other than LUT_MEM_CYCLES mem_en clocks
//   trace  hfi_soc_ctl's trace_valid / trace_data not the TRACE write of the previous clock
// bus_max_ctl / bus_max_acc are the longest waits seen (clocks with sel and no ready per access).
// Self-test: inject_ready shows the checker a ready of the ctl page, inject_mem an accelerator mem_en
// (not the DUT's pins); clear zeroes the counters.
module tb_soc_bus_fuzz #(
    parameter RAM_AW = 12,
    parameter RAM_INIT = "",
    parameter CTL_BOUND = 1,
    parameter ACC_BOUND = 64,
    parameter LUT_MEM_CYCLES = 20
) (
    output reg         clk,
    input  wire        rst_ext,
    // command from cocotb
    input  wire        cmd_seq,
    input  wire [8:0]  cmd_addr,
    input  wire [3:0]  cmd_wstrb,
    input  wire [31:0] cmd_wdata,
    input  wire [15:0] cmd_gap,
    input  wire        cmd_rst,
    input  wire [7:0]  cmd_rst_len,
    input  wire [7:0]  cmd_abort,
    output reg         take_toggle,
    output reg         rsp_toggle,
    output reg  [31:0] rsp_rdata,
    output reg  [7:0]  rsp_wait,
    output reg         rsp_aborted,
    output reg  [63:0] rsp_cycle,
    output wire        dsp_run,
    // checker
    input  wire        inject_ready,
    input  wire        inject_mem,
    input  wire        clear,
    output reg  [63:0] cycles,
    output reg  [31:0] viol_ready,
    output reg  [31:0] viol_bound,
    output reg  [31:0] viol_mem,
    output reg  [31:0] viol_trace,
    output reg  [7:0]  bus_max_ctl,
    output reg  [7:0]  bus_max_acc,
    output reg  [63:0] cov_mem,         // clocks with mem_en
    output reg  [31:0] cov_lut,         // look-ups answered
    output reg  [31:0] cov_lut_abort,   // resets while a look-up ran
    output reg  [31:0] cov_b2b,         // accesses presented in the clock after the previous ready
    output reg  [31:0] cov_trace        // trace_valid pulses
);
    localparam [1:0] IDLE = 2'd0, GAP = 2'd1, BUS = 2'd2, RST = 2'd3;
    localparam [7:0] ACC_LUT_IQ = 8'h28, CTL_TRACE = 8'h1C;

    initial clk = 1'b0;
    always #5 clk = ~clk;

    // ---------------------------------------------------------------- master
    reg [1:0]  st;
    reg        taken_seq, sel_m, kind_rst;
    reg [8:0]  a_m;
    reg [3:0]  s_m;
    reg [31:0] d_m;
    reg [15:0] gap_cnt;
    reg [7:0]  rst_len, abort_at, wait_cnt, rst_cnt;
    reg        rst_int;
    reg [63:0] cur_cycle;                  // since_rst in the clock the access was presented
    reg [63:0] since_rst;                  // hfi_soc_ctl's cycle counter, independently
    wire rst = rst_ext | rst_int;
    wire sel_ctl = sel_m & ~a_m[8];
    wire sel_acc = sel_m & a_m[8];
    wire ctl_ready, acc_ready;
    wire [31:0] ctl_rdata, acc_rdata;
    wire ready_any = ctl_ready | acc_ready;
    wire have_cmd = cmd_seq != taken_seq;
    // the master can take a command in this edge: idle, or completing an access or a reset
    wire free = st == IDLE || (st == BUS && ready_any) || (st == RST && rst_cnt <= 8'd1);

    always @(posedge clk) begin
        since_rst <= rst ? 64'd0 : since_rst + 64'd1;
        if (rst_ext) begin
            st <= IDLE;
            sel_m <= 1'b0;
            rst_int <= 1'b0;
            taken_seq <= cmd_seq;
            take_toggle <= 1'b0;
            rsp_toggle <= 1'b0;
            {rsp_rdata, rsp_wait, rsp_aborted, rsp_cycle} <= 0;
        end else begin
            case (st)
                IDLE: ;
                GAP:
                    if (gap_cnt <= 16'd1) begin
                        if (kind_rst) begin
                            rst_int <= 1'b1;
                            rst_cnt <= rst_len;
                            st <= RST;
                        end else begin
                            sel_m <= 1'b1;
                            wait_cnt <= 8'd0;
                            cur_cycle <= since_rst + 64'd1;
                            st <= BUS;
                        end
                    end else
                        gap_cnt <= gap_cnt - 16'd1;
                BUS:
                    if (ready_any) begin
                        rsp_rdata <= ctl_ready ? ctl_rdata : acc_ready ? acc_rdata : 32'd0;
                        rsp_wait <= wait_cnt;
                        rsp_cycle <= cur_cycle;
                        rsp_aborted <= 1'b0;
                        rsp_toggle <= ~rsp_toggle;
                        sel_m <= 1'b0;
                        st <= IDLE;
                    end else if (abort_at != 8'd0 && wait_cnt + 8'd1 == abort_at) begin
                        sel_m <= 1'b0;
                        rst_int <= 1'b1;
                        rst_cnt <= rst_len;
                        rsp_wait <= wait_cnt + 8'd1;
                        rsp_aborted <= 1'b1;
                        st <= RST;
                    end else
                        wait_cnt <= wait_cnt + {7'd0, wait_cnt != 8'hFF};
                RST:
                    if (rst_cnt <= 8'd1) begin
                        rst_int <= 1'b0;
                        rsp_toggle <= ~rsp_toggle;
                        st <= IDLE;
                    end else
                        rst_cnt <= rst_cnt - 8'd1;
            endcase
            if (free && have_cmd) begin
                taken_seq <= cmd_seq;
                take_toggle <= ~take_toggle;
                a_m <= cmd_addr;
                s_m <= cmd_wstrb;
                d_m <= cmd_wdata;
                kind_rst <= cmd_rst;
                rst_len <= cmd_rst_len == 8'd0 ? 8'd1 : cmd_rst_len;
                abort_at <= cmd_abort;
                if (cmd_gap != 16'd0 || cmd_rst) begin
                    gap_cnt <= cmd_gap;
                    st <= GAP;
                end else begin
                    sel_m <= 1'b1;
                    wait_cnt <= 8'd0;
                    cur_cycle <= rst ? 64'd0 : since_rst + 64'd1;
                    st <= BUS;
                end
            end
        end
    end

    // ---------------------------------------------------------------- the slaves
    wire        trace_valid, uart_tx, mem_en;
    wire [31:0] trace_data;
    wire [RAM_AW-1:0] mem_addr;
    wire [31:0] mem_rdata, unused_a;
    hfi_soc_ctl u_ctl (
        .clk(clk), .rst(rst), .sel(sel_ctl), .addr(a_m[7:0]), .wstrb(s_m), .wdata(d_m),
        .rdata(ctl_rdata), .ready(ctl_ready), .dsp_run(dsp_run), .uart_tx(uart_tx),
        .trace_valid(trace_valid), .trace_data(trace_data)
    );
    hfi_soc_acc #(.RAM_AW(RAM_AW)) u_acc (
        .clk(clk), .rst(rst), .sel(sel_acc), .addr(a_m[7:0]), .wstrb(s_m), .wdata(d_m),
        .rdata(acc_rdata), .ready(acc_ready), .mem_en(mem_en), .mem_addr(mem_addr), .mem_rdata(mem_rdata)
    );
    hfi_ram #(.WORDS(1 << RAM_AW), .INIT_FILE(RAM_INIT)) u_ram (
        .clk(clk), .ren(1'b0), .raddr({RAM_AW{1'b0}}), .rdata(unused_a),
        .wstrb(4'd0), .wdata(32'd0), .ren_b(mem_en), .addr_b(mem_addr), .rdata_b(mem_rdata)
    );

    // ---------------------------------------------------------------- checker
    reg        armed;
    reg        pend_ctl_q, pend_acc_q;   // sel high and no ready in c - 1
    reg        ready_q;                   // some ready in c - 1
    reg [7:0]  w_ctl, w_acc;              // consecutive clocks with sel and no ready, before c
    reg [7:0]  mem_cnt;                   // mem_en clocks of the running look-up
    reg        trace_exp;
    reg [31:0] trace_exp_data;
    wire ctl_ready_seen = ctl_ready | inject_ready;
    wire mem_seen = mem_en | inject_mem;
    wire iq_pending = sel_acc && a_m[7:0] == ACC_LUT_IQ && s_m != 4'd0 && !acc_ready;
    wire [7:0] w_ctl_now = sel_ctl && !ctl_ready ? w_ctl + {7'd0, w_ctl != 8'hFF} : 8'd0;
    wire [7:0] w_acc_now = sel_acc && !acc_ready ? w_acc + {7'd0, w_acc != 8'hFF} : 8'd0;
    wire bad_ready = (ctl_ready_seen && !(sel_ctl && pend_ctl_q)) || (acc_ready && !(sel_acc && pend_acc_q));
    wire lut_answer = sel_acc && acc_ready && a_m[7:0] == ACC_LUT_IQ && s_m != 4'd0;
    wire [7:0] mem_cnt_now = mem_cnt + {7'd0, mem_en};
    wire abort_now = st == BUS && !ready_any && abort_at != 8'd0 && wait_cnt + 8'd1 == abort_at;
    wire ctl_trace_wr = sel_ctl && !ctl_ready && s_m != 4'd0 && a_m[7:0] == CTL_TRACE;

    initial begin
        armed = 1'b0;
        {cycles, viol_ready, viol_bound, viol_mem, viol_trace, bus_max_ctl, bus_max_acc} = 0;
        {cov_mem, cov_lut, cov_lut_abort, cov_b2b, cov_trace} = 0;
    end

    always @(posedge clk) begin
        if (rst_ext)
            armed <= 1'b1;
        if (clear) begin
            {cycles, viol_ready, viol_bound, viol_mem, viol_trace, bus_max_ctl, bus_max_acc} <= 0;
            {cov_mem, cov_lut, cov_lut_abort, cov_b2b, cov_trace} <= 0;
        end else if (armed && !rst) begin
            cycles <= cycles + 64'd1;
            if (bad_ready) viol_ready <= viol_ready + 32'd1;
            viol_bound <= viol_bound + {31'd0, w_ctl_now == CTL_BOUND[7:0] + 8'd1}
                                     + {31'd0, w_acc_now == ACC_BOUND[7:0] + 8'd1};
            if ((mem_seen && !iq_pending) || (lut_answer && mem_cnt_now != LUT_MEM_CYCLES[7:0]))
                viol_mem <= viol_mem + 32'd1;
            if (trace_valid != trace_exp || (trace_exp && trace_data != trace_exp_data))
                viol_trace <= viol_trace + 32'd1;
            if (ctl_ready && w_ctl > bus_max_ctl) bus_max_ctl <= w_ctl;
            if (acc_ready && w_acc > bus_max_acc) bus_max_acc <= w_acc;
            if (mem_en) cov_mem <= cov_mem + 64'd1;
            if (lut_answer) cov_lut <= cov_lut + 32'd1;
            if (sel_m && ready_q) cov_b2b <= cov_b2b + 32'd1;
            if (trace_valid) cov_trace <= cov_trace + 32'd1;
            if (abort_now && iq_pending) cov_lut_abort <= cov_lut_abort + 32'd1;
        end
        pend_ctl_q <= !rst && sel_ctl && !ctl_ready;
        pend_acc_q <= !rst && sel_acc && !acc_ready;
        ready_q <= !rst && ready_any;
        w_ctl <= rst ? 8'd0 : w_ctl_now;
        w_acc <= rst ? 8'd0 : w_acc_now;
        mem_cnt <= rst || lut_answer ? 8'd0 : mem_cnt_now;
        trace_exp <= !rst && ctl_trace_wr;
        trace_exp_data <= d_m;
    end
    wire unused = &{1'b0, unused_a, uart_tx};
endmodule
`default_nettype wire
