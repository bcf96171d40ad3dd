// hfi_mul18: 18x18 signed multiplier with registered operands and a registered product,
//   p(t) = a(t-2) * b(t-2)          (36 bits, exact; latency 2 clocks, one result per clock)
// the `a_r <= a; b_r <= b; p_r <= a_r * b_r` pipeline of hfi_modulator and hfi_deadtime_comp.
// No reset and no enable: the registers take their inputs in every cycle (the users mark their
// results valid themselves); after configuration they hold 0 on ECP5 and in simulation they are
// never read before two inputs have passed.
//
// Lattice ECP5 (HFI_TARGET_ECP5, defined by scripts/synth_report.py for synth_ecp5): the operand
// registers in the fabric and one MULT18X18D with its output register (P on CLK0) in use. Yosys maps a
// `*` to a MULT18X18D with every register bypassed and leaves the product register in the fabric, so
// a path was slice register -> route -> 3.9 ns in the block -> route -> slice register; with P
// registered in the block it ends there. (The block's input registers as well were tried: then the
// operand logic, a multiplexer and a subtraction, had to reach the block in one cycle, and that path
// got longer than the one saved; docs/boards.md "Timing".) Yosys 0.70's abc9 stops on a MULT18X18D
// cell with parameters: the ECP5 flow of scripts/synth_report.py sets the REG_*_CLK parameters aside
// while abc9 runs, so this instance sets no other parameter. Bit for bit the generic code of the
// #else branch: scripts/synth_report.py proves the ECP5 RTL equal to the generic RTL (Yosys equiv,
// with the block's simulation model cocotb_tests/hdl/ecp5_mult18x18d_sim.v), and the gate-level
// replay runs the block's model.

`default_nettype none

module hfi_mul18 (
    input  wire               clk,
    input  wire signed [17:0] a,
    input  wire signed [17:0] b,
    output wire signed [35:0] p
);
`ifdef HFI_TARGET_ECP5
    reg signed [17:0] a_r, b_r;      // the operand registers in the fabric, next to the operand logic
    always @(posedge clk) begin
        a_r <= a;
        b_r <= b;
    end
    MULT18X18D #(    // every other parameter at its default: CE0, RST0, synchronous reset, no cascade
        .REG_OUTPUT_CLK("CLK0")
    ) u_dsp (
        .A17(a_r[17]), .A16(a_r[16]), .A15(a_r[15]), .A14(a_r[14]), .A13(a_r[13]), .A12(a_r[12]),
        .A11(a_r[11]), .A10(a_r[10]), .A9(a_r[9]), .A8(a_r[8]), .A7(a_r[7]), .A6(a_r[6]),
        .A5(a_r[5]), .A4(a_r[4]), .A3(a_r[3]), .A2(a_r[2]), .A1(a_r[1]), .A0(a_r[0]),
        .B17(b_r[17]), .B16(b_r[16]), .B15(b_r[15]), .B14(b_r[14]), .B13(b_r[13]), .B12(b_r[12]),
        .B11(b_r[11]), .B10(b_r[10]), .B9(b_r[9]), .B8(b_r[8]), .B7(b_r[7]), .B6(b_r[6]),
        .B5(b_r[5]), .B4(b_r[4]), .B3(b_r[3]), .B2(b_r[2]), .B1(b_r[1]), .B0(b_r[0]),
        .C17(1'b0), .C16(1'b0), .C15(1'b0), .C14(1'b0), .C13(1'b0), .C12(1'b0), .C11(1'b0),
        .C10(1'b0), .C9(1'b0), .C8(1'b0), .C7(1'b0), .C6(1'b0), .C5(1'b0), .C4(1'b0), .C3(1'b0),
        .C2(1'b0), .C1(1'b0), .C0(1'b0),
        .SIGNEDA(1'b1), .SIGNEDB(1'b1), .SOURCEA(1'b0), .SOURCEB(1'b0),
        .CLK3(1'b0), .CLK2(1'b0), .CLK1(1'b0), .CLK0(clk),
        .CE3(1'b0), .CE2(1'b0), .CE1(1'b0), .CE0(1'b1),
        .RST3(1'b0), .RST2(1'b0), .RST1(1'b0), .RST0(1'b0),
        .P35(p[35]), .P34(p[34]), .P33(p[33]), .P32(p[32]), .P31(p[31]), .P30(p[30]), .P29(p[29]),
        .P28(p[28]), .P27(p[27]), .P26(p[26]), .P25(p[25]), .P24(p[24]), .P23(p[23]), .P22(p[22]),
        .P21(p[21]), .P20(p[20]), .P19(p[19]), .P18(p[18]), .P17(p[17]), .P16(p[16]), .P15(p[15]),
        .P14(p[14]), .P13(p[13]), .P12(p[12]), .P11(p[11]), .P10(p[10]), .P9(p[9]), .P8(p[8]),
        .P7(p[7]), .P6(p[6]), .P5(p[5]), .P4(p[4]), .P3(p[3]), .P2(p[2]), .P1(p[1]), .P0(p[0]),
        .SIGNEDP()
    );
`else
    reg signed [17:0] a_r, b_r;
    reg signed [35:0] p_r;
    always @(posedge clk) begin
        a_r <= a;
        b_r <= b;
        p_r <= a_r * b_r;
    end
    assign p = p_r;
`endif
endmodule

`default_nettype wire
