`default_nettype none
`include "hfi_soc_platform.vh"
// hfi_soc: the 002 system on one FPGA (docs/soc.md). A PicoRV32 soft core (RV32IM with the fast
// multiplier, the divider and its interrupt controller; from the pythondata-cpu-picorv32 package,
// not part of this repository) runs the firmware (firmware/) from the on-chip RAM and closes the
// loop through the hfi_dsp peripheral once per PWM period, on the window interrupt.
//
// Memory map (byte addresses, decoded on address bits 31:28; the pages and the parameter defaults
// come from rtl/hfi_soc_platform.vh, generated from hfi/soc_platform.py):
//   0x0000_0000  RAM, RAM_BYTES (program, data, stack; $readmemh image RAM_INIT or +ram=<file>)
//   0x1000_0000  hfi_dsp registers (AXI4-Lite through picorv32_axi_adapter; docs/registers.md)
//   0x2000_0000  SoC control block hfi_soc_ctl (docs/soc_registers.md)
//   elsewhere    reads return 0, writes are ignored (one-clock answer; no bus error)
// Interrupts: PicoRV32 irq[3] (HFI_SOC_IRQ_WINDOW) = hfi_dsp window interrupt (level; the firmware clears it through
// IRQ_STATUS). irq[1] (illegal instruction, ebreak) and irq[2] (misaligned access) are the core's.
module hfi_soc #(
    parameter RAM_BYTES = `HFI_SOC_RAM_BYTES,
    parameter RAM_INIT = "",
    // hfi_dsp parameters (rtl/hfi_dsp.v)
    parameter ADC_BITS = `HFI_SOC_ADC_BITS,
    parameter ADC_CONV_TICKS = 12,
    parameter ADC_SCLK_HALF = 1,
    parameter CORDIC_WIDTH = 32,
    parameter CORDIC_ITERATIONS = 32,
    parameter DEAD_MIN = `HFI_SOC_DEAD_MIN,
    parameter IRQ_LATENCY = `HFI_SOC_IRQ_LATENCY,
    parameter OS_MIN = `HFI_SOC_OS_MIN
) (
    input  wire        clk,
    input  wire        rst,
    output wire [5:0]  gate,
    output wire        adc_convst,
    output wire        adc_cs_n,
    output wire        adc_sclk,
    input  wire        adc_sdo_a,
    input  wire        adc_sdo_b,
    output wire        uart_tx,
    output wire        trap,
    output wire        trace_valid,
    output wire [31:0] trace_data
);
    localparam RAM_WORDS = RAM_BYTES / 4;
    localparam RAM_AW = $clog2(RAM_WORDS);
    localparam IRQ_WINDOW = `HFI_SOC_IRQ_WINDOW;
    localparam PB = `HFI_SOC_PAGE_BITS;     // address bits 31:32-PB select the target

    generate
        if (RAM_BYTES < 1024 || (RAM_BYTES & (RAM_BYTES - 1)) != 0) begin : bad_ram
            hfi_soc_parameter_error_RAM_BYTES_must_be_a_power_of_two_of_at_least_1024 bad();
        end
    endgenerate

    // ---------------------------------------------------------------- CPU
    wire        mem_valid, mem_instr, mem_ready, mem_la_read;
    wire [31:0] mem_addr, mem_wdata, mem_rdata, mem_la_addr;
    wire [3:0]  mem_wstrb;
    wire        dsp_irq;
    wire [31:0] cpu_irq = {28'd0, dsp_irq, 3'd0};
    // unused outputs of the core and the AXI adapter
    wire        nc_la_write, nc_pcpi_valid, nc_trace_valid;
    wire [31:0] nc_la_wdata, nc_pcpi_insn, nc_pcpi_rs1, nc_pcpi_rs2, nc_eoi;
    wire [3:0]  nc_la_wstrb;
    wire [35:0] nc_trace_data;
    wire [2:0]  nc_awprot, nc_arprot;

    picorv32 #(
        .ENABLE_COUNTERS(1), .ENABLE_COUNTERS64(1), .ENABLE_REGS_16_31(1), .ENABLE_REGS_DUALPORT(1),
        .BARREL_SHIFTER(1), .COMPRESSED_ISA(0), .CATCH_MISALIGN(1), .CATCH_ILLINSN(1),
        .ENABLE_PCPI(0), .ENABLE_MUL(0), .ENABLE_FAST_MUL(1), .ENABLE_DIV(1),
        .ENABLE_IRQ(1), .ENABLE_IRQ_QREGS(1), .ENABLE_IRQ_TIMER(0), .ENABLE_TRACE(0),
        .MASKED_IRQ(32'h0000_0000), .LATCHED_IRQ(~(32'd1 << IRQ_WINDOW)),
        .PROGADDR_RESET(32'h0000_0000), .PROGADDR_IRQ(32'h0000_0010), .STACKADDR(RAM_BYTES)
    ) u_cpu (
        .clk(clk), .resetn(~rst), .trap(trap),
        .mem_valid(mem_valid), .mem_instr(mem_instr), .mem_ready(mem_ready),
        .mem_addr(mem_addr), .mem_wdata(mem_wdata), .mem_wstrb(mem_wstrb), .mem_rdata(mem_rdata),
        .mem_la_read(mem_la_read), .mem_la_write(nc_la_write), .mem_la_addr(mem_la_addr),
        .mem_la_wdata(nc_la_wdata), .mem_la_wstrb(nc_la_wstrb),
        .pcpi_valid(nc_pcpi_valid), .pcpi_insn(nc_pcpi_insn), .pcpi_rs1(nc_pcpi_rs1), .pcpi_rs2(nc_pcpi_rs2),
        .pcpi_wr(1'b0), .pcpi_rd(32'd0), .pcpi_wait(1'b0), .pcpi_ready(1'b0),
        .irq(cpu_irq), .eoi(nc_eoi),
        .trace_valid(nc_trace_valid), .trace_data(nc_trace_data)
    );

    // ---------------------------------------------------------------- address decode
    wire sel_ram = mem_valid && mem_addr[31:32-PB] == `HFI_SOC_RAM_PAGE && mem_addr[31-PB:0] < RAM_BYTES;
    wire sel_dsp = mem_valid && mem_addr[31:32-PB] == `HFI_SOC_DSP_PAGE;
    wire sel_ctl = mem_valid && mem_addr[31:32-PB] == `HFI_SOC_CTL_PAGE;
    wire sel_none = mem_valid && !sel_ram && !sel_dsp && !sel_ctl;

    // RAM without wait states: every transfer of the core is announced one clock ahead on the
    // look-ahead interface (mem_la_read with mem_la_addr), so the block RAM reads the word then and the
    // transfer completes in the clock mem_valid rises; a write is done in that clock.
    reg         none_ready;
    wire [31:0] ram_rdata;
    wire        la_ram = mem_la_addr[31:32-PB] == `HFI_SOC_RAM_PAGE && mem_la_addr[31-PB:0] < RAM_BYTES;
    wire        ram_ready = sel_ram;
    hfi_ram #(.WORDS(RAM_WORDS), .INIT_FILE(RAM_INIT)) u_ram (
        .clk(clk), .wstrb(sel_ram ? mem_wstrb : 4'd0), .waddr(mem_addr[RAM_AW+1:2]), .wdata(mem_wdata),
        .ren(mem_la_read && la_ram), .raddr(mem_la_addr[RAM_AW+1:2]), .rdata(ram_rdata)
    );
    always @(posedge clk)
        none_ready <= !rst && sel_none && !none_ready;

    // hfi_dsp through the core's AXI4-Lite adapter
    wire        dsp_ready;
    wire [31:0] dsp_rdata;
    wire        awvalid, awready, wvalid, wready, bvalid, bready, arvalid, arready, rvalid, rready;
    wire [31:0] awaddr, araddr, wdata, rdata;
    wire [3:0]  wstrb;
    wire [1:0]  bresp_unused, rresp_unused;
    picorv32_axi_adapter u_axi (
        .clk(clk), .resetn(~rst),
        .mem_axi_awvalid(awvalid), .mem_axi_awready(awready), .mem_axi_awaddr(awaddr), .mem_axi_awprot(nc_awprot),
        .mem_axi_wvalid(wvalid), .mem_axi_wready(wready), .mem_axi_wdata(wdata), .mem_axi_wstrb(wstrb),
        .mem_axi_bvalid(bvalid), .mem_axi_bready(bready),
        .mem_axi_arvalid(arvalid), .mem_axi_arready(arready), .mem_axi_araddr(araddr), .mem_axi_arprot(nc_arprot),
        .mem_axi_rvalid(rvalid), .mem_axi_rready(rready), .mem_axi_rdata(rdata),
        .mem_valid(sel_dsp), .mem_instr(mem_instr), .mem_ready(dsp_ready),
        .mem_addr(mem_addr), .mem_wdata(mem_wdata), .mem_wstrb(mem_wstrb), .mem_rdata(dsp_rdata)
    );

    wire dsp_run;
    hfi_dsp #(
        .ADC_BITS(ADC_BITS), .ADC_CONV_TICKS(ADC_CONV_TICKS), .ADC_SCLK_HALF(ADC_SCLK_HALF),
        .CORDIC_WIDTH(CORDIC_WIDTH), .CORDIC_ITERATIONS(CORDIC_ITERATIONS), .DEAD_MIN(DEAD_MIN),
        .IRQ_LATENCY(IRQ_LATENCY), .OS_MIN(OS_MIN)
    ) u_dsp (
        .clk(clk), .rst(rst), .run(dsp_run),
        .s_axil_awaddr(awaddr[7:0]), .s_axil_awvalid(awvalid), .s_axil_awready(awready),
        .s_axil_wdata(wdata), .s_axil_wstrb(wstrb), .s_axil_wvalid(wvalid), .s_axil_wready(wready),
        .s_axil_bresp(bresp_unused), .s_axil_bvalid(bvalid), .s_axil_bready(bready),
        .s_axil_araddr(araddr[7:0]), .s_axil_arvalid(arvalid), .s_axil_arready(arready),
        .s_axil_rdata(rdata), .s_axil_rresp(rresp_unused), .s_axil_rvalid(rvalid), .s_axil_rready(rready),
        .irq(dsp_irq), .gate(gate),
        .adc_convst(adc_convst), .adc_cs_n(adc_cs_n), .adc_sclk(adc_sclk),
        .adc_sdo_a(adc_sdo_a), .adc_sdo_b(adc_sdo_b)
    );

    // SoC control block
    wire        ctl_ready;
    wire [31:0] ctl_rdata;
    hfi_soc_ctl u_ctl (
        .clk(clk), .rst(rst), .sel(sel_ctl), .addr(mem_addr[7:0]), .wstrb(mem_wstrb), .wdata(mem_wdata),
        .rdata(ctl_rdata), .ready(ctl_ready), .dsp_run(dsp_run), .uart_tx(uart_tx),
        .trace_valid(trace_valid), .trace_data(trace_data)
    );

    assign mem_ready = ram_ready | dsp_ready | ctl_ready | none_ready;
    assign mem_rdata = ram_ready ? ram_rdata : dsp_ready ? dsp_rdata : ctl_ready ? ctl_rdata : 32'd0;

    wire unused = &{1'b0, bresp_unused, rresp_unused, awaddr[31:8], araddr[31:8], nc_la_write, nc_pcpi_valid,
                    nc_trace_valid, nc_la_wdata, nc_pcpi_insn, nc_pcpi_rs1, nc_pcpi_rs2, nc_eoi, nc_la_wstrb,
                    nc_trace_data, nc_awprot, nc_arprot, mem_addr[31-PB:RAM_AW+2], mem_la_addr[1:0], mem_addr[1:0]};
endmodule
`default_nettype wire
