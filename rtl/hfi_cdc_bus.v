`default_nettype none
// hfi_cdc_bus: one bus access at a time from the clock s_clk (the CPU side) to the clock m_clk (the
// DSP side), for any ratio and phase of the two clocks (docs/soc.md, "Clocks"). Both sides speak the
// native valid/ready protocol of the SoC (a master holds valid and its address, data and strobes
// until ready, which is high for one clock; wstrb = 0 is a read).
//
// Two-phase toggle handshake with bundled data, the standard pattern:
//  1. s side: an access that arrives while idle is copied into hold registers, then req flips;
//  2. m side: req, through a two-flop synchronizer, differs from ack: the access is issued on the m
//     bus from the hold registers (stable since step 1, before req flipped); when m_ready comes, the
//     read data is kept in a hold register and ack flips;
//  3. s side: ack, through a two-flop synchronizer, equals req again: s_ready for one clock with the
//     held read data (stable since before ack flipped).
// Each hold register is written by one side only and read by the other only while it is stable, so
// no multi-bit value is ever sampled while it changes. Latency: about 3 s clocks + 3 m clocks + the
// m bus. Reset: both sides must be reset together (hfi_soc holds rst for >= 20 clocks of the slower
// clock): a reset seen by one side only leaves the toggles unequal, and the m bus would then repeat the
// last access or issue a stray one (cocotb_tests/test_cdc_bus.py checks resets of both sides).
module hfi_cdc_bus #(
    parameter AW = 8
) (
    // CPU side
    input  wire          s_clk,
    input  wire          s_rst,
    input  wire          s_valid,
    input  wire [AW-1:0] s_addr,
    input  wire [31:0]   s_wdata,
    input  wire [3:0]    s_wstrb,
    output reg           s_ready,
    output reg  [31:0]   s_rdata,
    // DSP side
    input  wire          m_clk,
    input  wire          m_rst,
    output reg           m_valid,
    output reg  [AW-1:0] m_addr,
    output reg  [31:0]   m_wdata,
    output reg  [3:0]    m_wstrb,
    input  wire          m_ready,
    input  wire [31:0]   m_rdata
);
    // ---- s side
    reg          req;
    reg          busy;
    reg [AW-1:0] hold_addr;
    reg [31:0]   hold_wdata;
    reg [3:0]    hold_wstrb;
    wire         ack_s;
    reg          ack;               // m side
    reg [31:0]   hold_rdata;        // m side

    hfi_cdc_sync u_ack_sync (.clk(s_clk), .d(ack), .q(ack_s));

    always @(posedge s_clk) begin
        if (s_rst) begin
            req <= 1'b0;
            busy <= 1'b0;
            s_ready <= 1'b0;
            s_rdata <= 32'd0;
            hold_addr <= {AW{1'b0}};
            hold_wdata <= 32'd0;
            hold_wstrb <= 4'd0;
        end else begin
            s_ready <= 1'b0;
            if (!busy && s_valid && !s_ready) begin
                hold_addr <= s_addr;
                hold_wdata <= s_wdata;
                hold_wstrb <= s_wstrb;
                req <= ~req;
                busy <= 1'b1;
            end else if (busy && ack_s == req) begin
                s_rdata <= hold_rdata;
                s_ready <= 1'b1;
                busy <= 1'b0;
            end
        end
    end

    // ---- m side
    wire req_m;
    hfi_cdc_sync u_req_sync (.clk(m_clk), .d(req), .q(req_m));

    always @(posedge m_clk) begin
        if (m_rst) begin
            ack <= 1'b0;
            m_valid <= 1'b0;
            m_addr <= {AW{1'b0}};
            m_wdata <= 32'd0;
            m_wstrb <= 4'd0;
            hold_rdata <= 32'd0;
        end else if (m_valid) begin
            if (m_ready) begin
                m_valid <= 1'b0;
                hold_rdata <= m_rdata;
                ack <= ~ack;
            end
        end else if (req_m != ack) begin
            m_valid <= 1'b1;
            m_addr <= hold_addr;
            m_wdata <= hold_wdata;
            m_wstrb <= hold_wstrb;
        end
    end
endmodule
`default_nettype wire
