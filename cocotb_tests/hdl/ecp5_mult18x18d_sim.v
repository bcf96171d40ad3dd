`default_nettype none
// MULT18X18D: simulation model of the ECP5 sysDSP 18x18 multiplier, for the gate-level replay
// (scripts/gatelevel.py, docs/rtl.md "Gate-level replay") and the proof that the ECP5 RTL equals the
// generic RTL (scripts/synth_report.py target_equivalence). Yosys ships only a blackbox of this cell
// (share/ecp5/cells_bb.v); every other cell of the hfi_dsp netlist has its model in
// share/ecp5/cells_sim.v. This model covers the two configurations the project's netlists contain:
// the one synth_ecp5 emits for a `*` (share/lattice/dsp_map_18x18.v: every register bypassed) and
// rtl/hfi_mul18.v's (A, B and P registered on CLK0 with CE0 and RST0). P = A * B, 36 bits, each
// operand signed or unsigned by SIGNEDA / SIGNEDB; a register of A, B, the pipeline or P is used when
// its REG_*_CLK is "CLK0" and bypassed when it is "NONE"; it loads while CE0 is high and clears on a
// rising CLK0 edge with RST0 high (RESETMODE "SYNC"), the behaviour of Lattice FPGA-TN-02205 (ECP5
// sysDSP usage guide). No cascade (SOURCEA = SOURCEB = 0), C unused, GSR not modelled (registers
// start at 0). Any other configuration stops the simulation (outside synthesis).
module MULT18X18D (
    input  wire A17, A16, A15, A14, A13, A12, A11, A10, A9, A8, A7, A6, A5, A4, A3, A2, A1, A0,
    input  wire B17, B16, B15, B14, B13, B12, B11, B10, B9, B8, B7, B6, B5, B4, B3, B2, B1, B0,
    input  wire C17, C16, C15, C14, C13, C12, C11, C10, C9, C8, C7, C6, C5, C4, C3, C2, C1, C0,
    input  wire SIGNEDA, SIGNEDB, SOURCEA, SOURCEB,
    input  wire CLK3, CLK2, CLK1, CLK0, CE3, CE2, CE1, CE0, RST3, RST2, RST1, RST0,
    output wire P35, P34, P33, P32, P31, P30, P29, P28, P27, P26, P25, P24, P23, P22, P21, P20, P19, P18,
    output wire P17, P16, P15, P14, P13, P12, P11, P10, P9, P8, P7, P6, P5, P4, P3, P2, P1, P0,
    output wire SIGNEDP
);
    parameter REG_INPUTA_CLK = "NONE";
    parameter REG_INPUTA_CE = "CE0";
    parameter REG_INPUTA_RST = "RST0";
    parameter REG_INPUTB_CLK = "NONE";
    parameter REG_INPUTB_CE = "CE0";
    parameter REG_INPUTB_RST = "RST0";
    parameter REG_INPUTC_CLK = "NONE";
    parameter REG_INPUTC_CE = "CE0";
    parameter REG_INPUTC_RST = "RST0";
    parameter REG_PIPELINE_CLK = "NONE";
    parameter REG_PIPELINE_CE = "CE0";
    parameter REG_PIPELINE_RST = "RST0";
    parameter REG_OUTPUT_CLK = "NONE";
    parameter REG_OUTPUT_CE = "CE0";
    parameter REG_OUTPUT_RST = "RST0";
    parameter CLK0_DIV = "ENABLED";
    parameter CLK1_DIV = "ENABLED";
    parameter CLK2_DIV = "ENABLED";
    parameter CLK3_DIV = "ENABLED";
    parameter HIGHSPEED_CLK = "NONE";
    parameter GSR = "ENABLED";
    parameter CAS_MATCH_REG = "FALSE";
    parameter SOURCEB_MODE = "B_SHIFT";
    parameter MULT_BYPASS = "DISABLED";
    parameter RESETMODE = "SYNC";

    wire [17:0] a = {A17, A16, A15, A14, A13, A12, A11, A10, A9, A8, A7, A6, A5, A4, A3, A2, A1, A0};
    wire [17:0] b = {B17, B16, B15, B14, B13, B12, B11, B10, B9, B8, B7, B6, B5, B4, B3, B2, B1, B0};
    reg  [17:0] a_q, b_q;
    reg  [35:0] m_q, p_q;
    wire [17:0] a_in = (REG_INPUTA_CLK == "CLK0") ? a_q : a;
    wire [17:0] b_in = (REG_INPUTB_CLK == "CLK0") ? b_q : b;
    // the product as four 18x18 cases, so that with SIGNEDA = SIGNEDB = 1 tied it is the same signed
    // 18x18 `*` as the generic RTL's (the equivalence proof then matches it structurally)
    wire signed [35:0] m_ss = $signed(a_in) * $signed(b_in);
    wire signed [36:0] m_su = $signed(a_in) * $signed({1'b0, b_in});
    wire signed [36:0] m_us = $signed({1'b0, a_in}) * $signed(b_in);
    wire        [35:0] m_uu = a_in * b_in;
    wire        [35:0] m_full = (SIGNEDA && SIGNEDB) ? m_ss : SIGNEDA ? m_su[35:0] : SIGNEDB ? m_us[35:0] : m_uu;
    wire [35:0] m = (REG_PIPELINE_CLK == "CLK0") ? m_q : m_full;
    wire [35:0] p = (REG_OUTPUT_CLK == "CLK0") ? p_q : m;
    always @(posedge CLK0) begin
        if (RST0) begin
            a_q <= 18'd0;
            b_q <= 18'd0;
            m_q <= 36'd0;
            p_q <= 36'd0;
        end else if (CE0) begin
            a_q <= a;
            b_q <= b;
            m_q <= m_full;
            p_q <= m;
        end
    end
    assign {P35, P34, P33, P32, P31, P30, P29, P28, P27, P26, P25, P24, P23, P22, P21, P20, P19, P18,
            P17, P16, P15, P14, P13, P12, P11, P10, P9, P8, P7, P6, P5, P4, P3, P2, P1, P0} = p;
    assign SIGNEDP = SIGNEDA | SIGNEDB;

`ifndef SYNTHESIS
    initial begin   // after configuration (GSR) the registers hold 0
        a_q = 18'd0;
        b_q = 18'd0;
        m_q = 36'd0;
        p_q = 36'd0;
    end

    function automatic ok_reg(input [8*8-1:0] clk_sel, input [8*8-1:0] ce, input [8*8-1:0] rst);
        ok_reg = (clk_sel == "NONE") || (clk_sel == "CLK0" && ce == "CE0" && rst == "RST0");
    endfunction
    initial begin
        if (!ok_reg(REG_INPUTA_CLK, REG_INPUTA_CE, REG_INPUTA_RST)
                || !ok_reg(REG_INPUTB_CLK, REG_INPUTB_CE, REG_INPUTB_RST)
                || !ok_reg(REG_PIPELINE_CLK, REG_PIPELINE_CE, REG_PIPELINE_RST)
                || !ok_reg(REG_OUTPUT_CLK, REG_OUTPUT_CE, REG_OUTPUT_RST)
                || REG_INPUTC_CLK != "NONE" || MULT_BYPASS != "DISABLED" || RESETMODE != "SYNC") begin
            $display("MULT18X18D %m: configuration not modelled (registers other than CLK0/CE0/RST0, C, bypass)");
            $fatal(1);
        end
    end

    always @(SOURCEA or SOURCEB)
        if (SOURCEA !== 1'b0 || SOURCEB !== 1'b0) begin
            $display("MULT18X18D %m: SOURCEA/SOURCEB (cascade input) not modelled");
            $fatal(1);
        end
`endif
endmodule
`default_nettype wire
