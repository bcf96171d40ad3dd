`default_nettype none
// hfi_cdc_sync: a level crossing into the clock `clk`: STAGES flip-flops in series (the standard
// two-flop synchronizer for STAGES = 2). For signals that are levels held for many clocks of both
// sides (the window interrupt, the DSP run switch, a reset request); a pulse or a bundle of bits needs
// hfi_cdc_bus. In synthesis the flops keep their order and are not merged (async_reg hints the tools).
module hfi_cdc_sync #(
    parameter STAGES = 2,
    parameter RESET_VALUE = 1'b0
) (
    input  wire clk,
    input  wire d,
    output wire q
);
    generate
        if (STAGES < 2) begin : bad_stages
            hfi_cdc_sync_parameter_error_STAGES_must_be_at_least_2 bad();
        end
    endgenerate

    (* async_reg = "true" *) reg [STAGES-1:0] chain;
    initial chain = {STAGES{RESET_VALUE}};   // the configuration value of the FPGA's flops
    always @(posedge clk)
        chain <= {chain[STAGES-2:0], d};
    assign q = chain[STAGES-1];
endmodule
`default_nettype wire
