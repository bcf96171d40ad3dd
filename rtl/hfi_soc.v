`default_nettype none
`include "hfi_soc_platform.vh"
// hfi_soc: the 002 system on one FPGA (docs/soc.md). A VexRiscv soft core (RV32IM, 4 KiB instruction
// and data caches, single-cycle multiplier; the variant file named by hfi/soc_platform.py CPU_VARIANT
// from the pythondata-cpu-vexriscv package, not part of this repository) runs the firmware (firmware/)
// from the on-chip RAM and closes the loop through the hfi_dsp peripheral once per PWM period, on the
// window interrupt.
//
// Two clocks (docs/soc.md, "Clocks"): `clk` is the tick clock of hfi_dsp (100 MHz: the 10 ns gate
// resolution and the 1 us sampling grid of docs/spec.md); `cpu_clk` runs the core, the RAM and
// hfi_soc_ctl (50 MHz on the boards, any ratio works). They cross in hfi_cdc_bus (register accesses, a
// toggle handshake) and hfi_cdc_sync (the window interrupt, the DSP run switch and the resets).
// `rst` may be asynchronous to both; it is held for >= 20 clocks of the slower one.
//
// Memory map (byte addresses, decoded on address bits 31:28; the pages and the parameter defaults
// come from rtl/hfi_soc_platform.vh, generated from hfi/soc_platform.py; the peripherals sit in the
// upper half, which the core's data cache treats as I/O):
//   RAM page    RAM, RAM_BYTES (program, data, stack; $readmemh image RAM_INIT or +ram=<file>)
//   DSP page    hfi_dsp registers (AXI4-Lite behind the crossing; docs/registers.md)
//   CTL page    SoC control block hfi_soc_ctl (docs/soc_registers.md)
//   ACC page    arithmetic accelerators hfi_soc_acc, in cpu_clk (docs/acc_registers.md)
//   elsewhere   reads return 0, writes are ignored (one-clock answer; no bus error); an instruction
//               fetch outside the RAM is a bus error (the core's instruction access fault)
// Interrupt: externalInterruptArray[HFI_SOC_IRQ_WINDOW] = hfi_dsp window interrupt (a level; the
// firmware clears it through IRQ_STATUS). The core's exceptions go to the firmware's trap handler.
module hfi_soc #(
    parameter RAM_BYTES = `HFI_SOC_RAM_BYTES,
    parameter RAM_INIT = "",
    // 1: the arithmetic accelerators hfi_soc_acc on the ACC page; 0: none, the page reads 0 like an unmapped
    // one (a smaller SoC for small parts; its firmware is built without FW_ACC, docs/boards.md)
    parameter ACC = 1,
    // 1: the fixed-point unit hfi_cfu on the core's CFU port; 0: none, a custom-0 instruction answers 0 in the next
    // clock (a smaller SoC for small parts; its firmware is built without FW_CFU and issues none, docs/boards.md)
    parameter CFU = 1,
    // hfi_dsp parameters (rtl/hfi_dsp.v)
    parameter ADC_BITS = `HFI_SOC_ADC_BITS,
    parameter ADC_CONV_TICKS = 12,
    parameter ADC_SCLK_HALF = 1,
    parameter CORDIC_WIDTH = 32,
    parameter CORDIC_ITERATIONS = 32,
    parameter DEAD_MIN = `HFI_SOC_DEAD_MIN,
    parameter IRQ_LATENCY = `HFI_SOC_IRQ_LATENCY,
    parameter OS_MIN = `HFI_SOC_OS_MIN,
    // build options (docs/rtl.md "Build options"): hfi_dsp's optional blocks and the flux-map look-up unit
    // of hfi_soc_acc; 0 leaves the block out (CAPS of each register map says which are in)
    parameter ROT_INJ = 1,
    parameter DIFF_CIC = 1,
    parameter FCS_MPC = 1,
    parameter FLUX_LUT = 1
) (
    input  wire        clk,
    input  wire        cpu_clk,
    input  wire        rst,
    output wire [5:0]  gate,
    // safety pins of hfi_dsp (asynchronous, active high; docs/spec.md 3.8): Safe Torque Off request,
    // gate-driver fault (DESAT); drive_allowed for the gate driver's enable pin
    input  wire        sto,
    input  wire        desat,
    output wire        drive_allowed,
    output wire        adc_convst,
    output wire        adc_cs_n,
    output wire        adc_sclk,
    input  wire        adc_sdo_a,
    input  wire        adc_sdo_b,
    input  wire        adc_sdo_c,
    output wire        uart_tx,
    output wire        trace_valid,
    output wire [31:0] trace_data
);
    localparam RAM_WORDS = RAM_BYTES / 4;
    localparam RAM_AW = $clog2(RAM_WORDS);
    localparam PB = `HFI_SOC_PAGE_BITS;     // address bits 31:32-PB select the target

    generate
        if (RAM_BYTES < 1024 || (RAM_BYTES & (RAM_BYTES - 1)) != 0) begin : bad_ram
            hfi_soc_parameter_error_RAM_BYTES_must_be_a_power_of_two_of_at_least_1024 bad();
        end
    endgenerate

    // ---------------------------------------------------------------- resets, one per clock
    wire rst_cpu, rst_dsp;
    hfi_cdc_sync #(.RESET_VALUE(1'b1)) u_rst_cpu (.clk(cpu_clk), .d(rst), .q(rst_cpu));
    hfi_cdc_sync #(.RESET_VALUE(1'b1)) u_rst_dsp (.clk(clk), .d(rst), .q(rst_dsp));

    // ---------------------------------------------------------------- CPU (cpu_clk)
    wire        i_cyc, i_stb, i_we, d_cyc, d_stb, d_we;
    wire [29:0] i_adr, d_adr;
    wire [31:0] i_wdat, d_wdat, d_rdat;
    wire [3:0]  i_sel, d_sel;
    wire [2:0]  i_cti, d_cti;
    wire [1:0]  i_bte, d_bte;
    reg         i_ack, i_err, d_ack_ram, d_ack_none;
    wire        d_ack;
    wire [31:0] ram_idat;
    wire        dsp_irq, irq_cpu;
    wire        cfu_cmd_valid, cfu_cmd_ready, cfu_rsp_valid, cfu_rsp_ready;
    wire [9:0]  cfu_function_id;
    wire [31:0] cfu_in0, cfu_in1, cfu_out;

    VexRiscv u_cpu (
        .clk(cpu_clk), .reset(rst_cpu),
        .externalResetVector(`HFI_SOC_RAM_BASE),
        .timerInterrupt(1'b0), .softwareInterrupt(1'b0),
        .externalInterruptArray({{(31 - `HFI_SOC_IRQ_WINDOW){1'b0}}, irq_cpu, {`HFI_SOC_IRQ_WINDOW{1'b0}}}),
        .iBusWishbone_CYC(i_cyc), .iBusWishbone_STB(i_stb), .iBusWishbone_ACK(i_ack), .iBusWishbone_WE(i_we),
        .iBusWishbone_ADR(i_adr), .iBusWishbone_DAT_MISO(ram_idat), .iBusWishbone_DAT_MOSI(i_wdat),
        .iBusWishbone_SEL(i_sel), .iBusWishbone_ERR(i_err), .iBusWishbone_CTI(i_cti), .iBusWishbone_BTE(i_bte),
        .dBusWishbone_CYC(d_cyc), .dBusWishbone_STB(d_stb), .dBusWishbone_ACK(d_ack), .dBusWishbone_WE(d_we),
        .dBusWishbone_ADR(d_adr), .dBusWishbone_DAT_MISO(d_rdat), .dBusWishbone_DAT_MOSI(d_wdat),
        .dBusWishbone_SEL(d_sel), .dBusWishbone_ERR(1'b0), .dBusWishbone_CTI(d_cti), .dBusWishbone_BTE(d_bte),
        .CfuPlugin_bus_cmd_valid(cfu_cmd_valid), .CfuPlugin_bus_cmd_ready(cfu_cmd_ready),
        .CfuPlugin_bus_cmd_payload_function_id(cfu_function_id), .CfuPlugin_bus_cmd_payload_inputs_0(cfu_in0),
        .CfuPlugin_bus_cmd_payload_inputs_1(cfu_in1), .CfuPlugin_bus_rsp_valid(cfu_rsp_valid),
        .CfuPlugin_bus_rsp_ready(cfu_rsp_ready), .CfuPlugin_bus_rsp_payload_outputs_0(cfu_out)
    );
    // the fixed-point instructions (custom-0) of the core's CFU port (hfi/cfu.py, docs/soc.md)
    generate
        if (CFU != 0) begin : g_cfu
            hfi_cfu u_cfu (
                .clk(cpu_clk), .rst(rst_cpu), .cmd_valid(cfu_cmd_valid), .cmd_ready(cfu_cmd_ready),
                .cmd_function_id(cfu_function_id), .cmd_inputs_0(cfu_in0), .cmd_inputs_1(cfu_in1),
                .rsp_valid(cfu_rsp_valid), .rsp_ready(cfu_rsp_ready), .rsp_outputs_0(cfu_out)
            );
        end else begin : g_no_cfu
            reg rsp_pending;   // one instruction at a time, answered 0 in the clock after it is taken
            always @(posedge cpu_clk)
                rsp_pending <= !rst_cpu && ((cfu_cmd_valid && cfu_cmd_ready) || (rsp_pending && !cfu_rsp_ready));
            assign cfu_cmd_ready = !rsp_pending;
            assign cfu_rsp_valid = rsp_pending;
            assign cfu_out = 32'd0;
            wire unused_cfu = &{1'b0, cfu_function_id, cfu_in0, cfu_in1};
        end
    endgenerate
    hfi_cdc_sync u_irq_sync (.clk(cpu_clk), .d(dsp_irq), .q(irq_cpu));

    // ---------------------------------------------------------------- address decode (Wishbone)
    // Single reads: ACK one clock after STB (ACK <= STB && !ACK); a RAM write is acknowledged in the
    // clock of its STB (the block RAM writes at the clock edge that ends it). The caches' line refills are
    // incrementing bursts (CTI = 3'b010 until the last beat, 3'b111): the RAM answers them one word per
    // clock (registered feedback: while a beat is acknowledged it already reads the next address). The
    // data bus drives the write port and read port b with one address (d_raddr = d_adr unless a read
    // burst continues), so the RAM stays one true dual-port block RAM.
    localparam [2:0] CTI_INCR = 3'b010;
    wire [31:0] i_byte = {i_adr, 2'b00};
    wire [31:0] d_byte = {d_adr, 2'b00};
    wire i_req = i_cyc && i_stb;
    wire d_req = d_cyc && d_stb;
    wire i_ram = i_byte[31:32-PB] == `HFI_SOC_RAM_PAGE && i_byte[31-PB:0] < RAM_BYTES;
    wire sel_ram = d_req && d_byte[31:32-PB] == `HFI_SOC_RAM_PAGE && d_byte[31-PB:0] < RAM_BYTES;
    wire sel_dsp = d_req && d_byte[31:32-PB] == `HFI_SOC_DSP_PAGE;
    wire sel_ctl = d_req && d_byte[31:32-PB] == `HFI_SOC_CTL_PAGE;
    wire sel_acc = ACC != 0 && d_req && d_byte[31:32-PB] == `HFI_SOC_ACC_PAGE;
    wire sel_none = d_req && !sel_ram && !sel_dsp && !sel_ctl && !sel_acc;
    wire [3:0] d_wstrb = d_we ? d_sel : 4'd0;
    wire i_burst = i_cti == CTI_INCR;
    wire d_burst = d_cti == CTI_INCR && !d_we;
    wire d_wack_ram = sel_ram && d_we;     // a RAM write completes in its clock (the block RAM takes it at the edge)
    wire [RAM_AW-1:0] i_raddr = i_adr[RAM_AW-1:0] + {{(RAM_AW-1){1'b0}}, i_ack && i_burst};
    wire [RAM_AW-1:0] d_raddr = d_adr[RAM_AW-1:0] + {{(RAM_AW-1){1'b0}}, d_ack_ram && d_burst};

    // Port b is the data bus's, and the accelerators' flux-map unit reads its tables through it while the
    // CPU waits on that unit (hfi_soc_acc: acc_mem_en only then, so no CPU access coincides).
    wire [31:0] ram_ddat;
    wire        acc_mem_en;
    wire [RAM_AW-1:0] acc_mem_addr;
    wire [RAM_AW-1:0] b_addr = acc_mem_en ? acc_mem_addr : d_raddr;
    hfi_ram #(.WORDS(RAM_WORDS), .INIT_FILE(RAM_INIT)) u_ram (
        .clk(cpu_clk), .ren(i_req && i_ram), .raddr(i_raddr), .rdata(ram_idat),
        .wstrb(sel_ram ? d_wstrb : 4'd0), .wdata(d_wdat),
        .ren_b(sel_ram || acc_mem_en), .addr_b(b_addr), .rdata_b(ram_ddat)
    );
    always @(posedge cpu_clk) begin
        if (rst_cpu) begin
            i_ack <= 1'b0;
            i_err <= 1'b0;
            d_ack_ram <= 1'b0;
            d_ack_none <= 1'b0;
        end else begin
            i_ack <= i_req && i_ram && (!i_ack || i_burst);
            i_err <= i_req && !i_ram && !i_err;
            d_ack_ram <= sel_ram && !d_we && (!d_ack_ram || d_burst);
            d_ack_none <= sel_none && !d_ack_none;
        end
    end

    // SoC control block
    wire        ctl_ready, ctl_dsp_run;
    wire [31:0] ctl_rdata;
    hfi_soc_ctl u_ctl (
        .clk(cpu_clk), .rst(rst_cpu), .sel(sel_ctl), .addr(d_byte[7:0]), .wstrb(d_wstrb), .wdata(d_wdat),
        .rdata(ctl_rdata), .ready(ctl_ready), .dsp_run(ctl_dsp_run), .uart_tx(uart_tx),
        .trace_valid(trace_valid), .trace_data(trace_data)
    );

    // the arithmetic accelerators (the firmware's sin/cos and flux-map look-up, in the CPU clock)
    wire        acc_ready;
    wire [31:0] acc_rdata;
    generate
        if (ACC != 0) begin : g_acc
            hfi_soc_acc #(.RAM_AW(RAM_AW), .FLUX_LUT(FLUX_LUT)) u_acc (
                .clk(cpu_clk), .rst(rst_cpu), .sel(sel_acc), .addr(d_byte[7:0]), .wstrb(d_wstrb),
                .wdata(d_wdat), .rdata(acc_rdata), .ready(acc_ready),
                .mem_en(acc_mem_en), .mem_addr(acc_mem_addr), .mem_rdata(ram_ddat)
            );
        end else begin : g_no_acc
            assign acc_rdata = 32'd0;
            assign acc_ready = 1'b0;
            assign acc_mem_en = 1'b0;
            assign acc_mem_addr = {RAM_AW{1'b0}};
        end
    endgenerate

    // hfi_dsp: the crossing into clk, then PicoRV32's native-to-AXI4-Lite adapter (from the
    // pythondata-cpu-picorv32 package) in front of hfi_dsp's AXI4-Lite slave
    // The window-result registers are read from the CPU's copy (one clock), every other access crosses.
    wire        win_hit, win_ready;
    wire [31:0] win_rdata;
    wire [2047:0] dsp_words;
    wire        dsp_window_tog;
    wire        sel_win = sel_dsp && !d_we && win_hit;
    hfi_win_copy u_win_copy (
        .clk(cpu_clk), .rst(rst_cpu), .src(dsp_words), .src_tog(dsp_window_tog),
        .sel(sel_win), .addr(d_byte[7:0]), .hit(win_hit), .ready(win_ready), .rdata(win_rdata)
    );
    wire        dsp_ready;
    wire [31:0] dsp_rdata;
    wire        m_valid, m_ready;
    wire [7:0]  m_addr;
    wire [31:0] m_wdata, m_rdata;
    wire [3:0]  m_wstrb;
    hfi_cdc_bus #(.AW(8)) u_cdc (
        .s_clk(cpu_clk), .s_rst(rst_cpu), .s_valid(sel_dsp && !sel_win), .s_addr(d_byte[7:0]), .s_wdata(d_wdat),
        .s_wstrb(d_wstrb), .s_ready(dsp_ready), .s_rdata(dsp_rdata),
        .m_clk(clk), .m_rst(rst_dsp), .m_valid(m_valid), .m_addr(m_addr), .m_wdata(m_wdata),
        .m_wstrb(m_wstrb), .m_ready(m_ready), .m_rdata(m_rdata)
    );

    assign d_ack = d_ack_ram | d_wack_ram | dsp_ready | win_ready | ctl_ready | acc_ready | d_ack_none;
    assign d_rdat = d_ack_ram ? ram_ddat : dsp_ready ? dsp_rdata : win_ready ? win_rdata : ctl_ready ? ctl_rdata
                  : acc_ready ? acc_rdata : 32'd0;

    // ---------------------------------------------------------------- DSP (clk)
    wire        awvalid, awready, wvalid, wready, bvalid, bready, arvalid, arready, rvalid, rready;
    wire [31:0] awaddr, araddr, wdata, rdata;
    wire [3:0]  wstrb;
    wire [1:0]  bresp_unused, rresp_unused;
    wire [2:0]  nc_awprot, nc_arprot;
    picorv32_axi_adapter u_axi (
        .clk(clk), .resetn(~rst_dsp),
        .mem_axi_awvalid(awvalid), .mem_axi_awready(awready), .mem_axi_awaddr(awaddr), .mem_axi_awprot(nc_awprot),
        .mem_axi_wvalid(wvalid), .mem_axi_wready(wready), .mem_axi_wdata(wdata), .mem_axi_wstrb(wstrb),
        .mem_axi_bvalid(bvalid), .mem_axi_bready(bready),
        .mem_axi_arvalid(arvalid), .mem_axi_arready(arready), .mem_axi_araddr(araddr), .mem_axi_arprot(nc_arprot),
        .mem_axi_rvalid(rvalid), .mem_axi_rready(rready), .mem_axi_rdata(rdata),
        .mem_valid(m_valid), .mem_instr(1'b0), .mem_ready(m_ready),
        .mem_addr({24'd0, m_addr}), .mem_wdata(m_wdata), .mem_wstrb(m_wstrb), .mem_rdata(m_rdata)
    );

    wire dsp_run;   // SOC CTRL.DSP_RUN in clk (tick 0 is its first clock high, docs/rtl.md)
    hfi_cdc_sync u_run_sync (.clk(clk), .d(ctl_dsp_run), .q(dsp_run));
    hfi_dsp #(
        .ADC_BITS(ADC_BITS), .ADC_CONV_TICKS(ADC_CONV_TICKS), .ADC_SCLK_HALF(ADC_SCLK_HALF),
        .CORDIC_WIDTH(CORDIC_WIDTH), .CORDIC_ITERATIONS(CORDIC_ITERATIONS), .DEAD_MIN(DEAD_MIN),
        .IRQ_LATENCY(IRQ_LATENCY), .OS_MIN(OS_MIN), .ROT_INJ(ROT_INJ), .DIFF_CIC(DIFF_CIC), .FCS_MPC(FCS_MPC)
    ) u_dsp (
        .clk(clk), .rst(rst_dsp), .run(dsp_run),
        .s_axil_awaddr(awaddr[7:0]), .s_axil_awvalid(awvalid), .s_axil_awready(awready),
        .s_axil_wdata(wdata), .s_axil_wstrb(wstrb), .s_axil_wvalid(wvalid), .s_axil_wready(wready),
        .s_axil_bresp(bresp_unused), .s_axil_bvalid(bvalid), .s_axil_bready(bready),
        .s_axil_araddr(araddr[7:0]), .s_axil_arvalid(arvalid), .s_axil_arready(arready),
        .s_axil_rdata(rdata), .s_axil_rresp(rresp_unused), .s_axil_rvalid(rvalid), .s_axil_rready(rready),
        .irq(dsp_irq), .reg_words(dsp_words), .window_tog(dsp_window_tog), .gate(gate),
        .adc_convst(adc_convst), .adc_cs_n(adc_cs_n), .adc_sclk(adc_sclk),
        .adc_sdo_a(adc_sdo_a), .adc_sdo_b(adc_sdo_b), .adc_sdo_c(adc_sdo_c),
        .sto(sto), .desat(desat), .drive_allowed(drive_allowed)
    );

    wire unused = &{1'b0, bresp_unused, rresp_unused, awaddr[31:8], araddr[31:8], nc_awprot, nc_arprot,
                    i_we, i_wdat, i_sel, i_bte, d_bte, i_adr[29:RAM_AW], d_adr[29:RAM_AW],
                    d_byte[31-PB:8]};
endmodule
`default_nettype wire
