`default_nettype none
// hfi_soc_ctl: the SoC control block (registers: rtl/regs/hfi_soc.rdl, docs/soc_registers.md):
// identification, the hfi_dsp run switch, the 64-bit cycle counter, the log UART, the debug trace
// port and the firmware's status word. Native PicoRV32-style bus: `sel` for one access, answered with `ready` one clock later.
// Writes store the whole 32-bit word whatever the byte strobes (the firmware writes words only).
module hfi_soc_ctl (
    input  wire        clk,
    input  wire        rst,
    input  wire        sel,
    input  wire [7:0]  addr,
    input  wire [3:0]  wstrb,
    input  wire [31:0] wdata,
    output reg  [31:0] rdata,
    output reg         ready,
    output reg         dsp_run,
    output wire        uart_tx,
    output reg         trace_valid,
    output reg  [31:0] trace_data
);
/* verilator lint_off UNUSEDPARAM */
`include "regs/hfi_soc_map.vh"
/* verilator lint_on UNUSEDPARAM */

    wire write = sel && !ready && wstrb != 4'd0;
    wire read = sel && !ready && wstrb == 4'd0;

    reg [63:0] cycles;
    reg [31:0] cycle_hi;
    reg [15:0] uart_div;
    reg [SOC_FW_STATUS_MODE_WIDTH-1:0] fw_mode;
    reg [SOC_FW_STATUS_FAULT_WIDTH-1:0] fw_fault;
    wire [31:0] fw_status = ({{(32 - SOC_FW_STATUS_MODE_WIDTH){1'b0}}, fw_mode} << SOC_FW_STATUS_MODE_LSB)
                          | ({{(32 - SOC_FW_STATUS_FAULT_WIDTH){1'b0}}, fw_fault} << SOC_FW_STATUS_FAULT_LSB);
    wire uart_busy;

    hfi_uart_tx u_uart (
        .clk(clk), .rst(rst), .start(write && addr == SOC_UART_DATA_ADDR), .data(wdata[7:0]),
        .div(uart_div), .busy(uart_busy), .tx(uart_tx)
    );

    always @(posedge clk) begin
        if (rst) begin
            ready <= 1'b0;
            rdata <= 32'd0;
            dsp_run <= SOC_CTRL_DSP_RUN_RESET;
            cycles <= 64'd0;
            cycle_hi <= 32'd0;
            uart_div <= SOC_UART_DIV_VALUE_RESET;
            fw_mode <= SOC_FW_STATUS_MODE_RESET;
            fw_fault <= SOC_FW_STATUS_FAULT_RESET;
            trace_valid <= 1'b0;
            trace_data <= 32'd0;
        end else begin
            cycles <= cycles + 64'd1;
            ready <= sel && !ready;
            trace_valid <= write && addr == SOC_TRACE_ADDR;
            if (write && addr == SOC_TRACE_ADDR)
                trace_data <= wdata;
            if (write && addr == SOC_CTRL_ADDR)
                dsp_run <= wdata[SOC_CTRL_DSP_RUN_LSB];
            if (write && addr == SOC_UART_DIV_ADDR)
                uart_div <= wdata[SOC_UART_DIV_VALUE_LSB +: SOC_UART_DIV_VALUE_WIDTH];
            if (write && addr == SOC_FW_STATUS_ADDR) begin
                fw_mode <= wdata[SOC_FW_STATUS_MODE_LSB +: SOC_FW_STATUS_MODE_WIDTH];
                fw_fault <= wdata[SOC_FW_STATUS_FAULT_LSB +: SOC_FW_STATUS_FAULT_WIDTH];
            end
            if (read && addr == SOC_CYCLE_LO_ADDR)
                cycle_hi <= cycles[63:32];
            if (read) begin
                case (addr)
                    SOC_ID_ADDR:          rdata <= SOC_ID_VALUE_RESET;
                    SOC_CTRL_ADDR:        rdata <= {31'd0, dsp_run};
                    SOC_CYCLE_LO_ADDR:    rdata <= cycles[31:0];
                    SOC_CYCLE_HI_ADDR:    rdata <= cycle_hi;
                    SOC_UART_STATUS_ADDR: rdata <= {31'd0, uart_busy};
                    SOC_UART_DIV_ADDR:    rdata <= {16'd0, uart_div};
                    SOC_FW_STATUS_ADDR:   rdata <= fw_status;
                    default:              rdata <= 32'd0;
                endcase
            end
        end
    end
endmodule
`default_nettype wire
