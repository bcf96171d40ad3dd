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
// Checks that the registers the SoC copies into the CPU clock (rtl/hfi_win_copy.v) hold when hfi_dsp says so:
// with win_copy_mask (bit i: the word at byte address 4*i is a window-copy register; the testbench drives
// golden.regmap.WINDOW_COPY; undriven 0: nothing checked) no masked word of hfi_dsp's reg_words may change in
// the clock window_tog flips nor in the WIN_HOLD clocks after it (hfi_win_copy takes them 2..3 CPU clocks
// after the flip). Changes while the timing reset acts (rst, or hold = 1: hfi_dsp's rst_dp, which also flips
// window_tog in the clock the registers take their reset values) are not errors. win_tog_flips counts the
// flips, win_copy_errors the violations (the first ones printed), win_hold_min is the fewest clocks from a flip
// to the next change of a masked word (all ones: none seen); all three restart with rst.
module tb_hfi_dsp #(
    parameter ADC_BITS = 12,
    parameter CODES_FILE = "codes.hex",
    parameter ROT_INJ = 1,               // hfi_dsp's build options (docs/rtl.md; test_dsp_options.py)
    parameter DIFF_CIC = 1,
    parameter FCS_MPC = 1,
    parameter WIN_HOLD = 64              // clocks after a window_tog flip in which no window-copy word may change
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
    input  wire        flush,    // 1: flush the record files (the test sets it before reading them)
    input  wire [63:0] win_copy_mask,    // the window-copy check (above)
    output reg  [31:0] win_tog_flips,
    output reg  [31:0] win_copy_errors,
    output reg  [31:0] win_hold_min
);
    wire adc_convst, adc_cs_n, adc_sclk, adc_sdo_a, adc_sdo_b, adc_sdo_c;
    wire [2047:0] reg_words;
    wire window_tog;

    hfi_dsp #(.ADC_BITS(ADC_BITS), .ROT_INJ(ROT_INJ), .DIFF_CIC(DIFF_CIC), .FCS_MPC(FCS_MPC)) dut (
        .clk(clk), .rst(rst), .run(hold !== 1'b1),
        .s_axil_awaddr(s_axil_awaddr), .s_axil_awvalid(s_axil_awvalid), .s_axil_awready(s_axil_awready),
        .s_axil_wdata(s_axil_wdata), .s_axil_wstrb(s_axil_wstrb), .s_axil_wvalid(s_axil_wvalid),
        .s_axil_wready(s_axil_wready), .s_axil_bresp(s_axil_bresp), .s_axil_bvalid(s_axil_bvalid),
        .s_axil_bready(s_axil_bready), .s_axil_araddr(s_axil_araddr), .s_axil_arvalid(s_axil_arvalid),
        .s_axil_arready(s_axil_arready), .s_axil_rdata(s_axil_rdata), .s_axil_rresp(s_axil_rresp),
        .s_axil_rvalid(s_axil_rvalid), .s_axil_rready(s_axil_rready), .irq(irq),
        .reg_words(reg_words), .window_tog(window_tog), .gate(gate),
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

    // ---- the window-copy check (header). Sampled at every rising edge: window_tog and reg_words as they
    // stood in the clock ending there, against the clock before; win_since = clocks since the last flip - 1.
    wire [2047:0] win_mask_bits;
    genvar wg;
    generate
        for (wg = 0; wg < 64; wg = wg + 1) begin : g_win_mask
            assign win_mask_bits[32*wg +: 32] = {32{win_copy_mask[wg]}};
        end
    endgenerate
    reg  [2047:0] win_words_q;
    reg           win_tog_q, win_flipped, tim_rst, tim_rst_q;
    reg  [31:0]   win_since;
    wire          win_flip = window_tog != win_tog_q;
    wire          win_change = |((reg_words ^ win_words_q) & win_mask_bits);
    wire [31:0]   win_dist = win_flip ? 32'd0 : win_since + 32'd1;   // clocks from the flip to this one
    initial begin
        win_tog_flips = 32'd0;
        win_copy_errors = 32'd0;
        win_hold_min = 32'hFFFFFFFF;
    end
    always @(posedge clk) begin
        tim_rst <= rst || hold === 1'b1;    // hfi_dsp's rst_dp: its registers reset at the edges it is high
        tim_rst_q <= tim_rst;
        win_tog_q <= window_tog;
        win_words_q <= reg_words;
        if (rst) begin
            win_tog_flips <= 32'd0;
            win_copy_errors <= 32'd0;
            win_hold_min <= 32'hFFFFFFFF;
            win_flipped <= 1'b0;
            win_since <= 32'd0;
        end else begin
            if (win_flip) begin
                win_tog_flips <= win_tog_flips + 32'd1;
                win_flipped <= 1'b1;
                win_since <= 32'd0;
            end else if (win_since != 32'hFFFFFFFE) begin
                win_since <= win_since + 32'd1;
            end
            // a change seen here was made at the edge before: by the timing reset if tim_rst_q (rst_dp in
            // the clock ending at that edge) is high
            if (win_change && !tim_rst_q && (win_flip || win_flipped)) begin
                if (win_dist < win_hold_min)
                    win_hold_min <= win_dist;
                if (win_dist <= WIN_HOLD) begin
                    win_copy_errors <= win_copy_errors + 32'd1;
                    if (win_copy_errors < 32'd5)
                        $display("tb_hfi_dsp: ERROR: tick %0d: a window-copy word changed %0d clocks after window_tog flip %0d (mask of changed words %h)",
                                 tick, win_dist, win_flip ? win_tog_flips + 32'd1 : win_tog_flips,
                                 win_changed_words(reg_words ^ win_words_q));
                end
            end
        end
    end

    function [63:0] win_changed_words(input [2047:0] x);
        integer k;
        begin
            for (k = 0; k < 64; k = k + 1)
                win_changed_words[k] = win_copy_mask[k] && x[32*k +: 32] != 32'd0;
        end
    endfunction
endmodule
`default_nettype wire
