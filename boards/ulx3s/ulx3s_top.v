`default_nettype none
// ulx3s_top: hfi_soc on the Radiona ULX3S (LFE5U-85F-6 CABGA381; docs/boards.md has the pinout table,
// the wiring of a gate-driver board and a dual-lane ADC, and how firmware reaches the board).
//
// Clocks: the 25 MHz oscillator through one EHXPLLL (board_pll, generated at build time by
// yowasp-ecppll from hfi/soc_platform.py: the tick clock and the CPU clock, one VCO).
// Reset: FIRE1 pressed, or the PLL not locked, held for RESET_CLOCKS oscillator clocks after both
// are fine (hfi_soc synchronizes it into each of its clocks).
// Board-level interlocks, independent of the SoC's logic and registers (docs/boards.md):
//  - STO (sto_n low, or the pin open: pulled down) forces every gate pin low in the same instant
//    (a combinational AND at the pads) and the driver enable low;
//    and hfi_dsp latches STATUS.FAULT_STO (gates off 3 clocks later by the synchronized path);
//  - a driver fault (fault_n low: DESAT or undervoltage of the gate driver) latches
//    STATUS.FAULT_DESAT in hfi_dsp: gates and driver enable off until the firmware re-arms
//    (CTRL.FAULT_CLEAR, docs/spec.md 3.8) with the fault released, or a reset.
module ulx3s_top #(
    parameter RAM_INIT = "",
    parameter ACC = 1,                 // hfi_soc's accelerators (scripts/bitstream.py sets it per board)
    parameter CFU = 1,                 // hfi_soc's fixed-point unit (scripts/bitstream.py sets it per board)
    parameter RESET_CLOCKS = 255
) (
    input  wire       clk_25mhz,
    input  wire [6:0] btn,          // btn[1] = FIRE1: reset
    output wire [7:0] led,
    output wire       ftdi_rxd,     // the FPGA transmits the log UART to the FTDI
    // gate-driver header (J1): gate[2x] high switch of leg x, gate[2x+1] low switch
    output wire [5:0] gate,
    output wire       drv_en,
    input  wire       sto_n,
    input  wire       fault_n,
    // dual-lane serial ADC (J1)
    output wire       adc_convst,
    output wire       adc_cs_n,
    output wire       adc_sclk,
    input  wire       adc_sdo_a,
    input  wire       adc_sdo_b,
    input  wire       adc_sdo_c
);
    wire clk, cpu_clk, locked;
    board_pll u_pll (.clkin(clk_25mhz), .clkout0(clk), .clkout1(cpu_clk), .locked(locked));

    // reset: FIRE1 or no lock, stretched on the oscillator clock
    reg [7:0] rst_count = 8'd0;
    reg       rst = 1'b1;
    always @(posedge clk_25mhz) begin
        if (btn[1] || !locked) begin
            rst_count <= 8'd0;
            rst <= 1'b1;
        end else if (rst_count != RESET_CLOCKS[7:0]) begin
            rst_count <= rst_count + 8'd1;
        end else begin
            rst <= 1'b0;
        end
    end

    wire [5:0] soc_gate;
    wire       drive_allowed;
    wire       trace_valid;
    wire [31:0] trace_data;
    hfi_soc #(.RAM_INIT(RAM_INIT), .ACC(ACC), .CFU(CFU)) u_soc (
        .clk(clk), .cpu_clk(cpu_clk), .rst(rst),
        .gate(soc_gate), .sto(!sto_n), .desat(!fault_n), .drive_allowed(drive_allowed),
        .adc_convst(adc_convst), .adc_cs_n(adc_cs_n), .adc_sclk(adc_sclk),
        .adc_sdo_a(adc_sdo_a), .adc_sdo_b(adc_sdo_b), .adc_sdo_c(adc_sdo_c), .uart_tx(ftdi_rxd),
        .trace_valid(trace_valid), .trace_data(trace_data)
    );

    // driver fault: latched in the tick clock domain after a two-flop synchronizer
    // STO also acts here, combinationally (no clock, no logic in between): the gate pins are low
    // while sto_n is low, even before hfi_dsp's synchronized path removes the gates (3 clocks).
    // DESAT/driver faults are latched in hfi_dsp (STATUS.FAULT_DESAT), which holds drive_allowed low
    // until the firmware re-arms (CTRL.FAULT_CLEAR with the fault released).
    assign gate = soc_gate & {6{sto_n}};
    assign drv_en = sto_n && drive_allowed && !rst;

    assign led = {4'd0, |soc_gate, !drive_allowed, !sto_n, locked};

    wire unused = &{1'b0, btn[6:2], btn[0], trace_valid, trace_data};
endmodule
`default_nettype wire
