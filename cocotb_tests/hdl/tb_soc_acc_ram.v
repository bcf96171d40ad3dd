`default_nettype none
// tb_soc_acc_ram: test wrapper of cocotb_tests/test_soc_acc.py. The accelerators hfi_soc_acc with the RAM
// hfi_ram on its data port as in hfi_soc (the unit reads the flux-map tables through port b while the bus
// waits on its LUT_IQ write; nothing else uses port b here). RAM_INIT is the $readmemh image holding the
// tables (written by the test into its build directory); mem_en is brought out for the test's check.
module tb_soc_acc_ram #(
    parameter RAM_AW = 12,
    parameter RAM_INIT = ""
) (
    input  wire        clk,
    input  wire        rst,
    input  wire        sel,
    input  wire [7:0]  addr,
    input  wire [3:0]  wstrb,
    input  wire [31:0] wdata,
    output wire [31:0] rdata,
    output wire        ready,
    output wire        mem_en
);
    wire [RAM_AW-1:0] mem_addr;
    wire [31:0] mem_rdata, unused_a;
    hfi_soc_acc #(.RAM_AW(RAM_AW)) u_acc (
        .clk(clk), .rst(rst), .sel(sel), .addr(addr), .wstrb(wstrb), .wdata(wdata), .rdata(rdata),
        .ready(ready), .mem_en(mem_en), .mem_addr(mem_addr), .mem_rdata(mem_rdata)
    );
    hfi_ram #(.WORDS(1 << RAM_AW), .INIT_FILE(RAM_INIT)) u_ram (
        .clk(clk), .ren(1'b0), .raddr({RAM_AW{1'b0}}), .rdata(unused_a),
        .wstrb(4'd0), .wdata(32'd0), .ren_b(mem_en), .addr_b(mem_addr), .rdata_b(mem_rdata)
    );
    wire unused = &{1'b0, unused_a};
endmodule
`default_nettype wire
