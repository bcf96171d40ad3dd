`default_nettype none
// tangnano20k_top: hfi_soc on the Sipeed Tang Nano 20K (Gowin GW2AR-LV18QN88C8/I7; docs/boards.md).
//
// Clocks: the 27 MHz crystal through two rPLLs (tick_pll, cpu_pll, generated at build time by
// Apycula's gowin_pll from hfi/soc_platform.py). 27 MHz gives no exact 100 MHz: the tick clock is
// 100.286 MHz (PFD 3.857 MHz x 26), 0.29 % fast, so every time of docs/spec.md scales by 1/1.00286
// (PWM 5.014 kHz instead of 5 kHz); the firmware's configuration is the 100 MHz one. The CPU clock
// comes from the second PLL, unrelated in phase: the SoC's crossing does not need related clocks.
// Reset: S1 pressed, or a PLL not locked, held for RESET_CLOCKS crystal clocks.
// Board-level interlocks as on the ULX3S (ulx3s_top.v): STO forces the gate pins low
// combinationally; STO and driver faults latch in hfi_dsp (STATUS.FAULT_STO/FAULT_DESAT) and hold the
// gates and the driver enable off until the firmware re-arms (docs/spec.md 3.8).
module tangnano20k_top #(
    parameter RAM_INIT = "",
    parameter ACC = 1,                 // hfi_soc's accelerators (scripts/bitstream.py sets it per board)
    parameter CFU = 1,                 // hfi_soc's fixed-point unit (scripts/bitstream.py sets it per board)
    parameter RESET_CLOCKS = 255
) (
    input  wire       clk_27mhz,
    input  wire       s1,           // reset button
    output wire [5:0] led_n,        // active low
    output wire       uart_tx,      // to the BL616 USB serial
    output wire [5:0] gate,
    output wire       drv_en,
    input  wire       sto_n,
    input  wire       fault_n,
    output wire       adc_convst,
    output wire       adc_cs_n,
    output wire       adc_sclk,
    input  wire       adc_sdo_a,
    input  wire       adc_sdo_b,
    input  wire       adc_sdo_c
);
    wire clk, cpu_clk, tick_locked, cpu_locked;
    tick_pll u_tick_pll (.clock_in(clk_27mhz), .clock_out(clk), .locked(tick_locked));
    cpu_pll u_cpu_pll (.clock_in(clk_27mhz), .clock_out(cpu_clk), .locked(cpu_locked));
    wire locked = tick_locked && cpu_locked;

    reg [7:0] rst_count = 8'd0;
    reg       rst = 1'b1;
    always @(posedge clk_27mhz) begin
        if (s1 || !locked) begin
            rst_count <= 8'd0;
            rst <= 1'b1;
        end else if (rst_count != RESET_CLOCKS[7:0]) begin
            rst_count <= rst_count + 8'd1;
        end else begin
            rst <= 1'b0;
        end
    end

    wire [5:0]  soc_gate;
    wire        trace_valid;
    wire [31:0] trace_data;
    hfi_soc #(.RAM_INIT(RAM_INIT), .ACC(ACC), .CFU(CFU)) u_soc (
        .clk(clk), .cpu_clk(cpu_clk), .rst(rst),
        .gate(soc_gate), .sto(!sto_n), .desat(!fault_n), .drive_allowed(drive_allowed),
        .adc_convst(adc_convst), .adc_cs_n(adc_cs_n), .adc_sclk(adc_sclk),
        .adc_sdo_a(adc_sdo_a), .adc_sdo_b(adc_sdo_b), .adc_sdo_c(adc_sdo_c), .uart_tx(uart_tx),
        .trace_valid(trace_valid), .trace_data(trace_data)
    );

    // STO also acts here, combinationally (no clock, no logic in between): the gate pins are low
    // while sto_n is low, even before hfi_dsp's synchronized path removes the gates (3 clocks).
    // DESAT/driver faults are latched in hfi_dsp (STATUS.FAULT_DESAT), which holds drive_allowed low
    // until the firmware re-arms (CTRL.FAULT_CLEAR with the fault released).
    assign gate = soc_gate & {6{sto_n}};
    assign drv_en = sto_n && drive_allowed && !rst;
    assign led_n = ~{2'd0, |soc_gate, !drive_allowed, !sto_n, locked};

    wire unused = &{1'b0, trace_valid, trace_data};
endmodule
`default_nettype wire
