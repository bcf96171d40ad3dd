`default_nettype none
// tb_hfi_dsp: hfi_dsp with the ADC model and recorders, for the replay test (cocotb_tests/
// test_dsp_replay.py). The 100 MHz clock runs inside the simulator (Verilator --timing: no Python
// per cycle); the register writes come from the cocotb AXI4-Lite master (firmware replay). `hold` = 1
// holds the timing at its reset state (hfi_dsp's run = 0) while the registers stay writable, so a replay
// can configure the IP before tick 0 as the SoC firmware does; undriven (0 or z) the IP runs from reset.
// `tick` restarts with rst or hold, so tick 0 stays the first clock after either (docs/rtl.md).
// Records, as text files in the simulation directory:
//   gates.txt   "<tick> <mask>" at every change of the six gate outputs (tick = cycle since reset;
//               the gate pins show the golden mask of tick t in cycle t + PIN_LATENCY, docs/rtl.md)
//   convst.txt  "<tick>" of every CONVST rising edge (sampling tick t rises in cycle t + PIN_LATENCY)
module tb_hfi_dsp #(
    parameter ADC_BITS = 12,
    parameter CODES_FILE = "codes.hex",
    parameter ROT_INJ = 1,               // hfi_dsp's build options (docs/rtl.md; test_dsp_options.py)
    parameter DIFF_CIC = 1,
    parameter FCS_MPC = 1
) (
    output reg         clk,
    input  wire        rst,
    input  wire [7:0]  s_axil_awaddr,
    input  wire        s_axil_awvalid,
    output wire        s_axil_awready,
    input  wire [31:0] s_axil_wdata,
    input  wire [3:0]  s_axil_wstrb,
    input  wire        s_axil_wvalid,
    output wire        s_axil_wready,
    output wire [1:0]  s_axil_bresp,
    output wire        s_axil_bvalid,
    input  wire        s_axil_bready,
    input  wire [7:0]  s_axil_araddr,
    input  wire        s_axil_arvalid,
    output wire        s_axil_arready,
    output wire [31:0] s_axil_rdata,
    output wire [1:0]  s_axil_rresp,
    output wire        s_axil_rvalid,
    input  wire        s_axil_rready,
    output wire        irq,
    output wire [5:0]  gate,
    output reg  [63:0] tick,
    input  wire        sto,      // safety pins of hfi_dsp (0 unless a safety test drives them)
    input  wire        desat,
    output wire        drive_allowed,
    input  wire        hold,     // 1: hfi_dsp's run = 0 (configuration before tick 0); undriven: runs
    input  wire        flush     // 1: flush the record files (the test sets it before reading them)
);
    wire adc_convst, adc_cs_n, adc_sclk, adc_sdo_a, adc_sdo_b, adc_sdo_c;

    hfi_dsp #(.ADC_BITS(ADC_BITS), .ROT_INJ(ROT_INJ), .DIFF_CIC(DIFF_CIC), .FCS_MPC(FCS_MPC)) dut (
        .clk(clk), .rst(rst), .run(hold !== 1'b1),
        .s_axil_awaddr(s_axil_awaddr), .s_axil_awvalid(s_axil_awvalid), .s_axil_awready(s_axil_awready),
        .s_axil_wdata(s_axil_wdata), .s_axil_wstrb(s_axil_wstrb), .s_axil_wvalid(s_axil_wvalid),
        .s_axil_wready(s_axil_wready), .s_axil_bresp(s_axil_bresp), .s_axil_bvalid(s_axil_bvalid),
        .s_axil_bready(s_axil_bready), .s_axil_araddr(s_axil_araddr), .s_axil_arvalid(s_axil_arvalid),
        .s_axil_arready(s_axil_arready), .s_axil_rdata(s_axil_rdata), .s_axil_rresp(s_axil_rresp),
        .s_axil_rvalid(s_axil_rvalid), .s_axil_rready(s_axil_rready), .irq(irq), .gate(gate),
        .adc_convst(adc_convst), .adc_cs_n(adc_cs_n), .adc_sclk(adc_sclk),
        .adc_sdo_a(adc_sdo_a), .adc_sdo_b(adc_sdo_b), .adc_sdo_c(adc_sdo_c),
        .sto(sto), .desat(desat), .drive_allowed(drive_allowed)
    );

    adc_model #(.ADC_BITS(ADC_BITS), .CODES_FILE(CODES_FILE)) adc (
        .clk(clk), .adc_convst(adc_convst), .adc_cs_n(adc_cs_n), .adc_sclk(adc_sclk),
        .adc_sdo_a(adc_sdo_a), .adc_sdo_b(adc_sdo_b), .adc_sdo_c(adc_sdo_c)
    );

    integer fd_gates, fd_convst;
    reg [5:0] gate_q;
    reg convst_q;
    initial clk = 1'b0;
    always #5 clk = ~clk;

    initial begin
        fd_gates = $fopen("gates.txt", "w");
        fd_convst = $fopen("convst.txt", "w");
        gate_q = 6'd0;
        convst_q = 1'b0;
    end

    always @(posedge clk) begin
        tick <= (rst || hold === 1'b1) ? 64'd0 : tick + 64'd1;
        if (!rst) begin
            if (gate !== gate_q)
                $fwrite(fd_gates, "%0d %0d\n", tick, gate);
            if (adc_convst && !convst_q)
                $fwrite(fd_convst, "%0d\n", tick);
        end
        if (flush) begin
            $fflush(fd_gates);
            $fflush(fd_convst);
        end
        gate_q <= gate;
        convst_q <= adc_convst;
    end
endmodule
`default_nettype wire
