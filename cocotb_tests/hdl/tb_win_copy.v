`default_nettype none
// tb_win_copy: test wrapper of cocotb_tests/test_win_copy.py (testbench cocotb_tests/tb_win_copy.py).
//  * hfi_win_copy in the clock s_clk (the CPU's), every read port brought out unchanged. Its reset comes from
//    one asynchronous `rst` through an hfi_cdc_sync (RESET_VALUE = 1), exactly as hfi_soc makes rst_cpu.
//  * The source in the clock m_clk (hfi_dsp's place): two registers loaded at every rising edge of m_clk
//    from src_next and tog_next, which the testbench drives between the edges (so src and src_tog change
//    at m edges, as flops of hfi_dsp do, also when an s edge falls at the same instant). src_tog is 0 while
//    m_rst (rst through an hfi_cdc_sync in m_clk, as hfi_soc's rst_dsp) is sampled high, as hfi_dsp's
//    window_tog; the words are not reset (the testbench keeps junk in them: the copy must read 0 after a
//    reset whatever the source holds, until the first toggle).
// s_rst, m_rst, src and src_tog are brought out so the testbench sees when each side leaves reset and
// can check its own source against what the registers did.
module tb_win_copy (
    input  wire          s_clk,
    input  wire          m_clk,
    input  wire          rst,
    output wire          s_rst,
    output wire          m_rst,
    // source (m_clk)
    input  wire [2047:0] src_next,
    input  wire          tog_next,
    output reg  [2047:0] src,
    output reg           src_tog,
    // read port (s_clk)
    input  wire          sel,
    input  wire [7:0]    addr,
    output wire          hit,
    output wire          ready,
    output wire [31:0]   rdata
);
    hfi_cdc_sync #(.RESET_VALUE(1'b1)) u_rst_s (.clk(s_clk), .d(rst), .q(s_rst));
    hfi_cdc_sync #(.RESET_VALUE(1'b1)) u_rst_m (.clk(m_clk), .d(rst), .q(m_rst));

    initial begin
        src = 2048'd0;
        src_tog = 1'b0;
    end
    always @(posedge m_clk) begin
        src <= src_next;
        src_tog <= m_rst ? 1'b0 : tog_next;
    end

    hfi_win_copy u_copy (
        .clk(s_clk), .rst(s_rst), .src(src), .src_tog(src_tog),
        .sel(sel), .addr(addr), .hit(hit), .ready(ready), .rdata(rdata)
    );
endmodule
`default_nettype wire
