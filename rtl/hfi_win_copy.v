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
//
// The copy holds only the N copied words, packed in address order (slot k: the k-th set bit of the mask).
// A table made at elaboration from the mask gives each word address its slot: the take packs src by it, and a
// read is one look-up and one 32-bit selection (instead of a compare per copied word in every clock, which cost
// the co-simulation 10 % of its speed; docs/soc.md).
// After rst every copied word reads 0 (as hfi_dsp's after its reset) until the first window.
// Writes and the other words go through hfi_cdc_bus (the parent decodes hit). The copied registers are
// read-only, so a write to them changes nothing either way.
module hfi_win_copy (
    input  wire          clk,
    input  wire          rst,
    // the source, in another clock: word i = the read value of the register at byte address 4*i
    /* verilator lint_off UNUSEDSIGNAL */    // only the copied words are read
    input  wire [2047:0] src,
    /* verilator lint_on UNUSEDSIGNAL */
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

    // the number of copied words, and the slot of each word address
    function integer copied(input [63:0] m);
        integer j;
        begin
            copied = 0;
            for (j = 0; j < 64; j = j + 1)
                copied = copied + {31'd0, m[j]};
        end
    endfunction
    localparam integer N = copied(WORDS);
    function [7*64-1:0] slot_of_address(input [63:0] m);   // word address a: bits 7a +: 7 = {copied, slot}
        integer j;
        reg [5:0] k;
        begin
            slot_of_address = {7*64{1'b0}};
            k = 6'd0;
            for (j = 0; j < 64; j = j + 1)
                if (m[j]) begin
                    slot_of_address[7*j +: 7] = {1'b1, k};
                    k = k + 6'd1;
                end
        end
    endfunction
    localparam [7*64-1:0] SLOT = slot_of_address(WORDS);

    wire tog_s;
    reg  tog_q;
    hfi_cdc_sync u_tog_sync (.clk(clk), .d(src_tog), .q(tog_s));
    wire take = tog_s != tog_q;

    wire [32*N-1:0] src_words;                          // the copied words of src, packed by slot
    genvar g;
    generate
        for (g = 0; g < 64; g = g + 1) begin : g_src
            if (WORDS[g]) begin : g_word
                assign src_words[32*SLOT[7*g +: 6] +: 32] = src[32*g +: 32];
            end
        end
    endgenerate
    reg [32*N-1:0] copy;
    always @(posedge clk) begin
        if (rst) begin
            tog_q <= 1'b0;
            copy <= {32*N{1'b0}};
        end else begin
            tog_q <= tog_s;
            if (take)
                copy <= src_words;
        end
    end

    wire [6:0] entry = SLOT[7*addr[7:2] +: 7];         // {copied, slot}
    assign hit = entry[6] && addr[1:0] == 2'b00;
    always @(posedge clk) begin
        if (rst) begin
            ready <= 1'b0;
            rdata <= 32'd0;
        end else begin
            ready <= sel && hit && !ready;
            rdata <= copy[32*entry[5:0] +: 32];
        end
    end
endmodule
`default_nettype wire
