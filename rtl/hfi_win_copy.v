`default_nettype none
// hfi_win_copy: the CPU's copy of the window-result registers of hfi_dsp (docs/soc.md, "Clocks and the
// crossing"). The registers with the RDL property window_copy (rtl/regs/hfi_regs.rdl; the generated mask
// HFI_WINDOW_COPY_WORDS of rtl/regs/hfi_regs_map.vh) are set by hfi_dsp between the window boundary and the window
// interrupt and hold until the next boundary. A read of one of them through hfi_cdc_bus costs about 10 CPU
// clocks; here it is answered in one, like the SoC control block.
//
// Bundled data with a toggle, the same pattern as hfi_cdc_bus: src_tog flips (in the source clock) in the
// clock after the copied words have taken their window's values (in the same clock when hfi_dsp's timing reset
// gives them their reset values, as hfi_cdc_bus's req flips with its hold registers); it reaches clk through a two-flop
// synchronizer, and in the clock after the synchronized toggle changes, every copied word is taken from
// src at once. The words have then been stable for at least two clk clocks, and they stay stable until the
// next window boundary, a PWM period minus the interrupt latency later (spec 2.2), which is far longer
// than the three clk clocks the copy needs. So no multi-bit value is sampled while it changes, for any
// clock ratio and phase. The copy reaches clk before the window interrupt does (the interrupt's path is a
// source clock longer, and the core needs several clocks to enter its handler).
//
// Reads (wstrb = 0) of a copied word: hit = 1 (combinational, for the SoC's decode), ready one clock after
// sel (held by the master until ready), rdata the word of the copy as it stood at that clock's edge.
// After rst every copied word reads 0 (as hfi_dsp's after its reset) until the first window.
// Writes and the other words go through hfi_cdc_bus (the parent decodes hit). The copied registers are
// read-only, so a write to them changes nothing either way.
module hfi_win_copy (
    input  wire          clk,
    input  wire          rst,
    // the source, in another clock: word i = the read value of the register at byte address 4*i
    input  wire [2047:0] src,
    input  wire          src_tog,
    // the read port, in clk
    input  wire          sel,
    input  wire [7:0]    addr,
    output wire          hit,
    output reg           ready,
    output reg  [31:0]   rdata
);
/* verilator lint_off UNUSEDPARAM */  // the generated map lists every register; one mask is needed here
`include "regs/hfi_regs_map.vh"
/* verilator lint_on UNUSEDPARAM */
    localparam [63:0] WORDS = HFI_WINDOW_COPY_WORDS;   // bit i: a copy of the word at byte address 4*i

    wire tog_s;
    reg  tog_q;
    hfi_cdc_sync u_tog_sync (.clk(clk), .d(src_tog), .q(tog_s));
    wire take = tog_s != tog_q;

    reg [2047:0] copy;
    integer i;
    always @(posedge clk) begin
        if (rst) begin
            tog_q <= 1'b0;
            copy <= 2048'd0;
        end else begin
            tog_q <= tog_s;
            if (take)
                for (i = 0; i < 64; i = i + 1)
                    if (WORDS[i])
                        copy[32*i +: 32] <= src[32*i +: 32];
        end
    end

    assign hit = WORDS[addr[7:2]] && addr[1:0] == 2'b00;
    reg [31:0] word;
    always @(*) begin
        word = 32'd0;
        for (i = 0; i < 64; i = i + 1)
            if (WORDS[i] && addr[7:2] == i[5:0])
                word = copy[32*i +: 32];
    end
    always @(posedge clk) begin
        if (rst) begin
            ready <= 1'b0;
            rdata <= 32'd0;
        end else begin
            ready <= sel && hit && !ready;
            rdata <= word;
        end
    end
endmodule
`default_nettype wire
