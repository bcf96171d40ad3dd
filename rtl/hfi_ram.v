`default_nettype none
// hfi_ram: the SoC's program and data RAM, 32-bit words, true dual port with one clock read latency:
// port a reads (the CPU's instruction bus), port b writes with byte strobes and reads at one address
// (`addr_b`: the data bus, and the accelerators' table reads while the CPU waits; hfi_soc). The result of
// a read that collides with a write in the same clock (port b's own read during its write, or port a at
// the address port b writes) is not used by the SoC: the data bus takes read data only for reads, and no
// code is written while it runs. The memory says so to the synthesizer (`no_rw_check`): without it
// Yosys emulated read-first behaviour and replicated the RAM for the two ports, 64 block RAMs for
// 64 KiB on both ECP5 and Gowin instead of 32 (docs/boards.md). Simulation keeps the Verilog order (a
// colliding read returns the old word).
// Initialised from a $readmemh file (one 32-bit hex word per line, word 0 first): the INIT_FILE
// parameter, or in simulation the plusarg +ram=<file> (overrides the parameter per run).
module hfi_ram #(
    parameter WORDS = 8192,
    parameter INIT_FILE = ""
) (
    input  wire                     clk,
    input  wire                     ren,
    input  wire [$clog2(WORDS)-1:0] raddr,
    output reg  [31:0]              rdata,
    input  wire [3:0]               wstrb,
    input  wire [31:0]              wdata,
    input  wire                     ren_b,
    input  wire [$clog2(WORDS)-1:0] addr_b,
    output reg  [31:0]              rdata_b
);
    (* no_rw_check *) reg [31:0] mem [0:WORDS-1];

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
        if (wstrb[0]) mem[addr_b][7:0] <= wdata[7:0];
        if (wstrb[1]) mem[addr_b][15:8] <= wdata[15:8];
        if (wstrb[2]) mem[addr_b][23:16] <= wdata[23:16];
        if (wstrb[3]) mem[addr_b][31:24] <= wdata[31:24];
        if (ren)
            rdata <= mem[raddr];
        if (ren_b)
            rdata_b <= mem[addr_b];
    end
endmodule
`default_nettype wire
