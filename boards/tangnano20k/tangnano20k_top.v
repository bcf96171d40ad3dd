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
// combinationally, a driver fault latches the driver enable low until reset.
module tangnano20k_top #(
    parameter RAM_INIT = "",
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
    input  wire       adc_sdo_b
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
    hfi_soc #(.RAM_INIT(RAM_INIT)) u_soc (
        .clk(clk), .cpu_clk(cpu_clk), .rst(rst),
        .gate(soc_gate), .adc_convst(adc_convst), .adc_cs_n(adc_cs_n), .adc_sclk(adc_sclk),
        .adc_sdo_a(adc_sdo_a), .adc_sdo_b(adc_sdo_b), .uart_tx(uart_tx),
        .trace_valid(trace_valid), .trace_data(trace_data)
    );

    wire fault_s;
    reg  fault_latched = 1'b0;
    hfi_cdc_sync u_fault_sync (.clk(clk), .d(~fault_n), .q(fault_s));
    always @(posedge clk)
        if (rst)
            fault_latched <= 1'b0;
        else if (fault_s)
            fault_latched <= 1'b1;

    wire allow = sto_n && !fault_latched;
    assign gate = soc_gate & {6{allow}};
    assign drv_en = allow && !rst;
    assign led_n = ~{2'd0, |soc_gate, fault_latched, !sto_n, locked};

    wire unused = &{1'b0, trace_valid, trace_data};
endmodule
`default_nettype wire
