`default_nettype none
// hfi_ram: the SoC's program and data RAM, 32-bit words: one write port with byte strobes and two read
// ports (a, b) with one clock latency. hfi_soc drives the write port and read port b with the same
// address (the CPU's data bus) and read port a alone (its instruction bus), so the synthesizer maps it
// to true dual-port block RAM. A read of the word being written in the same clock returns the old word.
// Initialised from a $readmemh file (one 32-bit hex word per line, word 0 first): the INIT_FILE
// parameter, or in simulation the plusarg +ram=<file> (overrides the parameter per run).
module hfi_ram #(
    parameter WORDS = 8192,
    parameter INIT_FILE = ""
) (
    input  wire                     clk,
    input  wire [3:0]               wstrb,
    input  wire [$clog2(WORDS)-1:0] waddr,
    input  wire [31:0]              wdata,
    input  wire                     ren,
    input  wire [$clog2(WORDS)-1:0] raddr,
    output reg  [31:0]              rdata,
    input  wire                     ren_b,
    input  wire [$clog2(WORDS)-1:0] raddr_b,
    output reg  [31:0]              rdata_b
);
    reg [31:0] mem [0:WORDS-1];

`ifndef SYNTHESIS
    reg [1023:0] plusarg_file;
    initial begin
        if ($value$plusargs("ram=%s", plusarg_file))
            $readmemh(plusarg_file, mem);
        else if (INIT_FILE != "")
            $readmemh(INIT_FILE, mem);
    end
`else
    initial
        if (INIT_FILE != "")
            $readmemh(INIT_FILE, mem);
`endif

    always @(posedge clk) begin
        if (wstrb[0]) mem[waddr][7:0] <= wdata[7:0];
        if (wstrb[1]) mem[waddr][15:8] <= wdata[15:8];
        if (wstrb[2]) mem[waddr][23:16] <= wdata[23:16];
        if (wstrb[3]) mem[waddr][31:24] <= wdata[31:24];
        if (ren)
            rdata <= mem[raddr];
        if (ren_b)
            rdata_b <= mem[raddr_b];
    end
endmodule
`default_nettype wire
