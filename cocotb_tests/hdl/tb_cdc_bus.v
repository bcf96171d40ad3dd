`default_nettype none
// tb_cdc_bus: test wrapper of cocotb_tests/test_cdc_bus.py (testbench cocotb_tests/tb_cdc_bus.py).
//  * hfi_cdc_bus (AW = 8, as in hfi_soc) between the clocks s_clk and m_clk, every bus port brought out
//    unchanged. Its two resets come from one asynchronous `rst` through one hfi_cdc_sync per clock
//    (RESET_VALUE = 1), exactly as hfi_soc makes rst_cpu and rst_dsp; they are brought out as s_rst and
//    m_rst so the testbench sees when each side leaves reset.
//  * Three hfi_cdc_sync on their own clock y_clk with one input y_d: STAGES = 2 with RESET_VALUE 0
//    (y_q2) and 1 (y_q2r), and STAGES = 3 (y_q3).
// One build per simulator serves every test of the testbench.
module tb_cdc_bus (
    input  wire        s_clk,
    input  wire        m_clk,
    input  wire        rst,
    output wire        s_rst,
    output wire        m_rst,
    // s side (CPU)
    input  wire        s_valid,
    input  wire [7:0]  s_addr,
    input  wire [31:0] s_wdata,
    input  wire [3:0]  s_wstrb,
    output wire        s_ready,
    output wire [31:0] s_rdata,
    // m side (DSP)
    output wire        m_valid,
    output wire [7:0]  m_addr,
    output wire [31:0] m_wdata,
    output wire [3:0]  m_wstrb,
    input  wire        m_ready,
    input  wire [31:0] m_rdata,
    // hfi_cdc_sync alone
    input  wire        y_clk,
    input  wire        y_d,
    output wire        y_q2,
    output wire        y_q2r,
    output wire        y_q3
);
    hfi_cdc_sync #(.RESET_VALUE(1'b1)) u_rst_s (.clk(s_clk), .d(rst), .q(s_rst));
    hfi_cdc_sync #(.RESET_VALUE(1'b1)) u_rst_m (.clk(m_clk), .d(rst), .q(m_rst));

    hfi_cdc_bus #(.AW(8)) u_bus (
        .s_clk(s_clk), .s_rst(s_rst), .s_valid(s_valid), .s_addr(s_addr), .s_wdata(s_wdata),
        .s_wstrb(s_wstrb), .s_ready(s_ready), .s_rdata(s_rdata),
        .m_clk(m_clk), .m_rst(m_rst), .m_valid(m_valid), .m_addr(m_addr), .m_wdata(m_wdata),
        .m_wstrb(m_wstrb), .m_ready(m_ready), .m_rdata(m_rdata)
    );

    hfi_cdc_sync #(.STAGES(2), .RESET_VALUE(1'b0)) u_sync2 (.clk(y_clk), .d(y_d), .q(y_q2));
    hfi_cdc_sync #(.STAGES(2), .RESET_VALUE(1'b1)) u_sync2r (.clk(y_clk), .d(y_d), .q(y_q2r));
    hfi_cdc_sync #(.STAGES(3), .RESET_VALUE(1'b0)) u_sync3 (.clk(y_clk), .d(y_d), .q(y_q3));
endmodule
`default_nettype wire
