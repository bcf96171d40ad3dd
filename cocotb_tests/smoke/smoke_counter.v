// Toolchain smoke-test DUT: a free-running counter with enable and synchronous reset.
// Used only by cocotb_tests/test_smoke_toolchain.py (cocotb + Verilator / Icarus).
`resetall
`timescale 1ns/1ps
`default_nettype none

module smoke_counter #(
    parameter WIDTH = 8
) (
    input  wire             clk,
    input  wire             rst,    // synchronous, active high
    input  wire             en,
    output reg  [WIDTH-1:0] count
);
    always @(posedge clk) begin
        if (rst)
            count <= {WIDTH{1'b0}};
        else if (en)
            count <= count + 1'b1;
    end
endmodule

`default_nettype wire
