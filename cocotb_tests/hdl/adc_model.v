`default_nettype none
// adc_model: simulation model of the serial three-lane simultaneous-sampling ADC of hfi_adc_if
// (protocol in rtl/hfi_adc_if.v: lanes A, B = phase currents, C = dc-link voltage), for the replay of a
// golden closed loop through hfi_dsp.
// Each CONVST rising edge takes the next code triple from CODES_FILE ($readmemh, one 48-bit
// "ccccaaaabbbb" hex word per line, in conversion order: C in bits [32 +: ADC_BITS], A in [16 +:
// ADC_BITS], B in [0 +: ADC_BITS]; a shorter word is zero-extended, so an "aaaabbbb" word has C = 0);
// the triple is shifted out MSB first, the first bit when CS_N falls, each next bit after an SCLK falling
// edge (all changes one clock after the pin edge), on the three lanes at once.
// Past the end of the file the model returns mid-scale (0 A) on A and B and 0 on C.
// Test bench only: not synthesizable.
module adc_model #(
    parameter ADC_BITS = 12,
    parameter MAX_CODES = 1 << 20,
    parameter CODES_FILE = "codes.hex"
) (
    input  wire clk,
    input  wire adc_convst,
    input  wire adc_cs_n,
    input  wire adc_sclk,
    output reg  adc_sdo_a,
    output reg  adc_sdo_b,
    output reg  adc_sdo_c
);
    reg [47:0] codes [0:MAX_CODES-1];
    reg [31:0] count;
    reg [ADC_BITS-1:0] word_a, word_b, word_c;
    reg convst_q, cs_q, sclk_q;
    integer bitpos, i;

    initial begin
        for (i = 0; i < MAX_CODES; i = i + 1)
            codes[i] = {16'd0, {2{16'd1 << (ADC_BITS - 1)}}};
        $readmemh(CODES_FILE, codes);
        count = 0;
        convst_q = 0; cs_q = 1; sclk_q = 0;
        adc_sdo_a = 0; adc_sdo_b = 0; adc_sdo_c = 0;
        bitpos = 0;
    end

    always @(posedge clk) begin
        convst_q <= adc_convst;
        cs_q <= adc_cs_n;
        sclk_q <= adc_sclk;
        if (adc_convst && !convst_q) begin
            word_c <= codes[count][32 +: ADC_BITS];
            word_a <= codes[count][16 +: ADC_BITS];
            word_b <= codes[count][0 +: ADC_BITS];
            count <= count + 1;
        end
        if (!adc_cs_n && cs_q) begin
            bitpos = ADC_BITS - 1;
            adc_sdo_a <= word_a[bitpos];
            adc_sdo_b <= word_b[bitpos];
            adc_sdo_c <= word_c[bitpos];
        end else if (!adc_cs_n && !adc_sclk && sclk_q && bitpos > 0) begin
            bitpos = bitpos - 1;
            adc_sdo_a <= word_a[bitpos];
            adc_sdo_b <= word_b[bitpos];
            adc_sdo_c <= word_c[bitpos];
        end
    end
endmodule
`default_nettype wire
