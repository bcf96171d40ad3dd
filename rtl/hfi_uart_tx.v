`default_nettype none
// hfi_uart_tx: transmit-only UART, 8 data bits, no parity, 1 stop bit (8N1), LSB first.
// `start` with `data` begins a byte when idle (ignored while busy); `div` = clock cycles per bit,
// read when a byte starts (values below 16 act as 16). The line idles high.
module hfi_uart_tx (
    input  wire        clk,
    input  wire        rst,
    input  wire        start,
    input  wire [7:0]  data,
    input  wire [15:0] div,
    output wire        busy,
    output wire        tx
);
    reg [9:0]  shift;        // stop bit, 8 data bits, start bit (sent from bit 0)
    reg [3:0]  bits_left;
    reg [15:0] period, count;
    assign busy = bits_left != 4'd0;
    assign tx = busy ? shift[0] : 1'b1;

    always @(posedge clk) begin
        if (rst) begin
            bits_left <= 4'd0;
            shift <= 10'h3FF;
            period <= 16'd16;
            count <= 16'd0;
        end else if (!busy) begin
            if (start) begin
                shift <= {1'b1, data, 1'b0};
                bits_left <= 4'd10;
                period <= (div < 16'd16) ? 16'd16 : div;
                count <= 16'd1;
            end
        end else if (count == period) begin
            count <= 16'd1;
            shift <= {1'b1, shift[9:1]};
            bits_left <= bits_left - 4'd1;
        end else begin
            count <= count + 16'd1;
        end
    end
endmodule
`default_nettype wire
