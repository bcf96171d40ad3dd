`default_nettype none
// tb_soc_ctl_ram: test wrapper of cocotb_tests/test_soc_ctl.py. The SoC control block hfi_soc_ctl
// (with its UART hfi_uart_tx) and the RAM hfi_ram side by side on one clock, every port brought out
// unchanged (RAM ports with the prefix ram_), so one build per simulator serves both testbenches.
// RAM_INIT is the $readmemh image of the RAM (written by the test into its build directory).
module tb_soc_ctl_ram #(
    parameter RAM_WORDS = 256,
    parameter RAM_INIT = ""
) (
    input  wire                         clk,
    input  wire                         rst,
    // hfi_soc_ctl: native PicoRV32-style bus and outputs
    input  wire                         sel,
    input  wire [7:0]                   addr,
    input  wire [3:0]                   wstrb,
    input  wire [31:0]                  wdata,
    output wire [31:0]                  rdata,
    output wire                         ready,
    output wire                         dsp_run,
    output wire                         uart_tx,
    output wire                         trace_valid,
    output wire [31:0]                  trace_data,
    // hfi_ram
    input  wire [3:0]                   ram_wstrb,
    input  wire [$clog2(RAM_WORDS)-1:0] ram_waddr,
    input  wire [31:0]                  ram_wdata,
    input  wire                         ram_ren,
    input  wire [$clog2(RAM_WORDS)-1:0] ram_raddr,
    output wire [31:0]                  ram_rdata
);
    hfi_soc_ctl u_ctl (
        .clk(clk), .rst(rst), .sel(sel), .addr(addr), .wstrb(wstrb), .wdata(wdata), .rdata(rdata),
        .ready(ready), .dsp_run(dsp_run), .uart_tx(uart_tx), .trace_valid(trace_valid),
        .trace_data(trace_data)
    );

    wire [31:0] ram_rdata_b;   // read port b: the CPU data bus in hfi_soc, unused here
    wire unused = &{1'b0, ram_rdata_b};
    hfi_ram #(.WORDS(RAM_WORDS), .INIT_FILE(RAM_INIT)) u_ram (
        .clk(clk), .ren(ram_ren), .raddr(ram_raddr), .rdata(ram_rdata),
        .wstrb(ram_wstrb), .wdata(ram_wdata), .ren_b(1'b0), .addr_b(ram_waddr), .rdata_b(ram_rdata_b)
    );
endmodule
`default_nettype wire
