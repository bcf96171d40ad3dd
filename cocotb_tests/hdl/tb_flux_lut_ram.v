`default_nettype none
// tb_flux_lut_ram: test wrapper of cocotb_tests/test_flux_lut.py. hfi_flux_lut reading its tables from
// hfi_ram's port b, wired as hfi_soc wires the data port: one address for the write port and read
// port b, the unit's mem_addr while its mem_en is high, else the testbench's ram_addr (the CPU's data
// bus in the SoC). The testbench writes the tables through the write port (ram_wstrb, ram_addr,
// ram_wdata) while the unit is idle.
// Checks for the testbench (no per-clock Python needed):
//   bad_en   sticky: set by a clock in which mem_en was high while busy was low (0 from time 0 on);
//   reads    clocks with mem_en high, counted from time 0 (32 bits, wraps);
//   mem_rdata to the unit is the RAM's word only in the clock after a mem_en clock, else an LFSR's
//   junk (the unit must use mem_rdata only then).
module tb_flux_lut_ram #(
    parameter RAM_AW = 14
) (
    input  wire               clk,
    input  wire               rst,
    // RAM write port (testbench)
    input  wire         [3:0] ram_wstrb,
    input  wire [RAM_AW-1:0]  ram_addr,
    input  wire        [31:0] ram_wdata,
    // hfi_flux_lut
    input  wire [RAM_AW+1:0]  base_d,
    input  wire [RAM_AW+1:0]  base_q,
    input  wire [RAM_AW+1:0]  base_ld,
    input  wire [RAM_AW+1:0]  base_lq,
    input  wire [RAM_AW+1:0]  base_ldq,
    input  wire        [6:0]  n_d,
    input  wire        [6:0]  n_q,
    input  wire        [3:0]  shift,
    input  wire        [31:0] knee,
    input  wire        [2:0]  coarse,
    input  wire        [4:0]  f_shift,
    input  wire               start,
    input  wire signed [31:0] i_d,
    input  wire signed [31:0] i_q,
    output wire               busy,
    output wire               done,
    output wire signed [63:0] lam_d, lam_q, l_d, l_q, l_dq, dl_d, dl_q, dl_dq,
    output wire               mem_en,
    output reg                bad_en,
    output reg         [31:0] reads
);
    wire [RAM_AW-1:0] mem_addr;
    wire [RAM_AW-1:0] b_addr = mem_en ? mem_addr : ram_addr;
    wire       [31:0] ram_rdata_b;
    reg               rd_v;               // ram_rdata_b holds a read of the unit
    reg        [31:0] junk;               // LFSR
    wire       [31:0] mem_rdata = rd_v ? ram_rdata_b : junk;

    initial begin
        bad_en = 1'b0;
        reads = 32'd0;
        rd_v = 1'b0;
        junk = 32'h1234_5679;
    end
    always @(posedge clk) begin
        rd_v <= mem_en;
        junk <= {junk[30:0], junk[31] ^ junk[21] ^ junk[1] ^ junk[0]};
        if (mem_en && !busy)
            bad_en <= 1'b1;
        if (mem_en)
            reads <= reads + 32'd1;
    end

    wire [31:0] ram_rdata_a;              // read port a: the instruction bus in hfi_soc, unused here
    /* verilator lint_off UNUSEDSIGNAL */
    wire unused = &{1'b0, ram_rdata_a};
    /* verilator lint_on UNUSEDSIGNAL */
    hfi_ram #(.WORDS(1 << RAM_AW)) u_ram (
        .clk(clk), .ren(1'b0), .raddr(b_addr), .rdata(ram_rdata_a),
        .wstrb(ram_wstrb), .wdata(ram_wdata), .ren_b(mem_en), .addr_b(b_addr), .rdata_b(ram_rdata_b)
    );

    hfi_flux_lut #(.RAM_AW(RAM_AW)) u_lut (
        .clk(clk), .rst(rst),
        .base_d(base_d), .base_q(base_q), .base_ld(base_ld), .base_lq(base_lq), .base_ldq(base_ldq),
        .mem_en(mem_en), .mem_addr(mem_addr), .mem_rdata(mem_rdata),
        .n_d(n_d), .n_q(n_q), .shift(shift), .knee(knee), .coarse(coarse), .f_shift(f_shift),
        .start(start), .i_d(i_d), .i_q(i_q), .busy(busy), .done(done),
        .lam_d(lam_d), .lam_q(lam_q), .l_d(l_d), .l_q(l_q), .l_dq(l_dq), .dl_d(dl_d), .dl_q(dl_q), .dl_dq(dl_dq)
    );
endmodule
`default_nettype wire
