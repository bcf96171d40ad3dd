`default_nettype none
// tb_reg_fuzz: hfi_dsp with the ADC model and a per-cycle safety and bus checker, for the register
// fuzzer (cocotb_tests/test_reg_fuzz.py, docs/fuzz.md). The 100 MHz clock runs inside the simulator
// (Verilator --timing); the bus master is cocotb (cocotbext-axi) on the m_axil_* ports, clocked by
// clk_m (below); the checker is plain Verilog on the DUT's side of the bus (s_axil_*), so that every
// clock is checked without a Python callback per cycle.
//
// Every rising edge after the first reset checks the cycle that it ends ("cycle c"):
//   shoot    a leg with both switches on: gate[2x] & gate[2x+1]
//   kill     a gate pin on while a gate must be off (docs/spec.md 3.8, golden/fpga/safety.py): the gate
//            register loads 0 in a clock with kill, so gate(c) = 0 when a fault latch (FAULT_OC/WDT/
//            STO/DESAT) was set in cycle c - 1, or when the STO or DESAT pin was high in cycle c - 3
//            (two synchronizer flops and the gate register: 3 clocks after the pin)
//   drive    drive_allowed(c) != ~(FAULT_STO | FAULT_DESAT | sto(c - 2) | desat(c - 2))
//   bus      the slave keeps a master waiting more than BUS_BOUND consecutive cycles: a write
//            presented (AWVALID & WVALID) or accepted and not yet answered, with no BVALID; a read
//            presented or accepted, with no RVALID (back-pressure of the master, BREADY/RREADY low
//            while VALID waits, does not count)
//   proto    BVALID/RVALID without an accepted request, a response that drops or changes before
//            its READY, or a response code other than OKAY/SLVERR
// Each class has its own violation counter; bus_max is the longest wait seen (hfi_regs: 2 cycles).
// The coverage counters show that the fuzzer reached the states the invariants are about.
// Self-test (checker_self_test in tb_reg_fuzz.py): inject_shoot ORs 0b000011 (leg a, both switches)
// and inject_gate ORs 0b000001 into the gate vector the checker sees (not into the DUT's pins);
// clear zeroes the counters.
module tb_reg_fuzz #(
    parameter ADC_BITS = 12,
    parameter CODES_FILE = "codes.hex",
    parameter BUS_BOUND = 32,
    parameter BUS_SKEW = 1,       // [ns] clk_m leads clk (period 10 ns)
    parameter BUS_DELAY = 2       // [ns] master -> DUT; more than BUS_SKEW, less than 5 - BUS_SKEW
) (
    output reg         clk,
    output reg         clk_m,    // the bus master's clock: rises BUS_SKEW before clk
    input  wire        rst,
    input  wire [7:0]  m_axil_awaddr,
    input  wire        m_axil_awvalid,
    output wire        m_axil_awready,
    input  wire [31:0] m_axil_wdata,
    input  wire [3:0]  m_axil_wstrb,
    input  wire        m_axil_wvalid,
    output wire        m_axil_wready,
    output wire [1:0]  m_axil_bresp,
    output wire        m_axil_bvalid,
    input  wire        m_axil_bready,
    input  wire [7:0]  m_axil_araddr,
    input  wire        m_axil_arvalid,
    output wire        m_axil_arready,
    output wire [31:0] m_axil_rdata,
    output wire [1:0]  m_axil_rresp,
    output wire        m_axil_rvalid,
    input  wire        m_axil_rready,
    output wire        irq,
    output wire [5:0]  gate,
    input  wire        sto,
    input  wire        desat,
    output wire        drive_allowed,
    input  wire        inject_shoot,
    input  wire        inject_gate,
    input  wire        clear,
    // checker results
    output reg  [63:0] cycles,
    output reg  [31:0] viol_shoot,
    output reg  [31:0] viol_kill,
    output reg  [31:0] viol_drive,
    output reg  [31:0] viol_bus,
    output reg  [31:0] viol_proto,
    output reg  [7:0]  bus_max,
    // coverage
    output reg  [63:0] cov_gates_on,     // cycles with a gate pin on
    output reg  [63:0] cov_kill,         // cycles in which the checker required all gates off
    output reg  [31:0] cov_wr_on,        // writes accepted while OUTPUTS_ON
    output reg  [31:0] cov_oc,           // rising edges of FAULT_OC, FAULT_WDT, FAULT_STO, FAULT_DESAT
    output reg  [31:0] cov_wdt,
    output reg  [31:0] cov_sto,
    output reg  [31:0] cov_desat
);
    localparam [7:0] BUS_LIMIT = BUS_BOUND[7:0] + 8'd1;   // the first wait that is a violation
    wire adc_convst, adc_cs_n, adc_sclk, adc_sdo_a, adc_sdo_b, adc_sdo_c;

    // The bus master (cocotbext-axi) samples and drives at the rising edge of clk_m, BUS_SKEW before
    // the DUT's edge: it reads the slave's outputs of the cycle that the DUT's edge ends (a RisingEdge
    // of clk itself, under this simulator, shows values already updated by that edge), and its
    // requests reach the DUT BUS_DELAY after it drives them, after that edge, so the DUT samples them
    // at the next one, as AXI requires. The checker watches the DUT's side (s_axil_*).
    wire [7:0]  #(BUS_DELAY) s_axil_awaddr = m_axil_awaddr;
    wire [7:0]  #(BUS_DELAY) s_axil_araddr = m_axil_araddr;
    wire [31:0] #(BUS_DELAY) s_axil_wdata = m_axil_wdata;
    wire [3:0]  #(BUS_DELAY) s_axil_wstrb = m_axil_wstrb;
    wire        #(BUS_DELAY) s_axil_awvalid = m_axil_awvalid;
    wire        #(BUS_DELAY) s_axil_wvalid = m_axil_wvalid;
    wire        #(BUS_DELAY) s_axil_bready = m_axil_bready;
    wire        #(BUS_DELAY) s_axil_arvalid = m_axil_arvalid;
    wire        #(BUS_DELAY) s_axil_rready = m_axil_rready;
    wire        s_axil_awready, s_axil_wready, s_axil_bvalid, s_axil_arready, s_axil_rvalid;
    wire [1:0]  s_axil_bresp, s_axil_rresp;
    wire [31:0] s_axil_rdata;
    assign {m_axil_awready, m_axil_wready, m_axil_bresp, m_axil_bvalid, m_axil_arready, m_axil_rdata,
            m_axil_rresp, m_axil_rvalid} = {s_axil_awready, s_axil_wready, s_axil_bresp, s_axil_bvalid,
                                            s_axil_arready, s_axil_rdata, s_axil_rresp, s_axil_rvalid};

    wire [2047:0] reg_words_nc;     // the SoC's window-copy outputs (rtl/hfi_win_copy.v): checked by tb_hfi_dsp.v
    wire          window_tog_nc;
    hfi_dsp #(.ADC_BITS(ADC_BITS)) dut (
        .clk(clk), .rst(rst), .run(1'b1), .reg_words(reg_words_nc), .window_tog(window_tog_nc),
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

    initial begin
        clk = 1'b0;
        clk_m = 1'b0;
        #(5 - BUS_SKEW);             // clk rises at 5, 15, ...; clk_m at 5 - BUS_SKEW, 15 - BUS_SKEW, ...
        forever begin
            clk_m = ~clk_m;
            #5;
        end
    end
    always #5 clk = ~clk;

    // the fault latches of hfi_dsp (the STATUS bits FAULT_OC/WDT/STO/DESAT)
    wire [3:0] faults = {dut.fault_desat, dut.fault_sto, dut.fault_wdt, dut.fault_oc};
    wire [5:0] gate_seen = gate | (inject_shoot ? 6'b000011 : 6'b0) | (inject_gate ? 6'b000001 : 6'b0);
    wire shoot = |(gate_seen & (gate_seen >> 1) & 6'b010101);

    reg        armed;          // a reset has been seen: the DUT's state is defined
    reg [2:0]  sto_h, desat_h; // [k]: the pin in cycle c - 1 - k (before this edge's update)
    reg        fault_q;        // a fault latch was set in cycle c - 1
    reg [3:0]  faults_q;
    reg [7:0]  w_wait, r_wait;
    reg        w_out, r_out;   // a request accepted and not yet answered
    reg        b_hold, r_hold; // a response waited for its READY in the previous cycle
    reg [1:0]  bresp_q, rresp_q;
    reg [31:0] rdata_q;

    wire kill_need = fault_q | sto_h[2] | desat_h[2];
    wire drive_exp = ~(dut.fault_sto | dut.fault_desat | sto_h[1] | desat_h[1]);
    wire w_owed = (s_axil_awvalid & s_axil_wvalid | w_out) & ~s_axil_bvalid;
    wire r_owed = (s_axil_arvalid | r_out) & ~s_axil_rvalid;
    // the wait of this cycle (consecutive owed cycles, this one included); saturates at 255
    wire [7:0] w_now = w_owed ? w_wait + {7'd0, w_wait != 8'hFF} : 8'd0;
    wire [7:0] r_now = r_owed ? r_wait + {7'd0, r_wait != 8'hFF} : 8'd0;
    wire [7:0] wait_now = w_now > r_now ? w_now : r_now;
    wire aw_hs = s_axil_awvalid & s_axil_awready;
    wire b_hs = s_axil_bvalid & s_axil_bready;
    wire ar_hs = s_axil_arvalid & s_axil_arready;
    wire r_hs = s_axil_rvalid & s_axil_rready;
    wire proto = (s_axil_bvalid & ~w_out) | (s_axil_rvalid & ~r_out)
                 | (b_hold & (~s_axil_bvalid | s_axil_bresp != bresp_q))
                 | (r_hold & (~s_axil_rvalid | s_axil_rresp != rresp_q | s_axil_rdata != rdata_q))
                 | (s_axil_bvalid & s_axil_bresp[0]) | (s_axil_rvalid & s_axil_rresp[0]);

    initial begin
        armed = 1'b0;
        {cycles, viol_shoot, viol_kill, viol_drive, viol_bus, viol_proto, bus_max} = 0;
        {cov_gates_on, cov_kill, cov_wr_on, cov_oc, cov_wdt, cov_sto, cov_desat} = 0;
    end

    always @(posedge clk) begin
        if (rst)
            armed <= 1'b1;
        if (clear) begin
            {cycles, viol_shoot, viol_kill, viol_drive, viol_bus, viol_proto, bus_max} <= 0;
            {cov_gates_on, cov_kill, cov_wr_on, cov_oc, cov_wdt, cov_sto, cov_desat} <= 0;
        end else if (armed) begin
            cycles <= cycles + 64'd1;
            if (shoot) viol_shoot <= viol_shoot + 32'd1;
            if (kill_need && gate_seen != 6'd0) viol_kill <= viol_kill + 32'd1;
            if (drive_allowed != drive_exp) viol_drive <= viol_drive + 32'd1;
            viol_bus <= viol_bus + {31'd0, w_now == BUS_LIMIT} + {31'd0, r_now == BUS_LIMIT};
            if (proto) viol_proto <= viol_proto + 32'd1;
            if (wait_now > bus_max) bus_max <= wait_now;
            if (gate != 6'd0) cov_gates_on <= cov_gates_on + 64'd1;
            if (kill_need) cov_kill <= cov_kill + 64'd1;
            if (aw_hs && dut.outputs_on) cov_wr_on <= cov_wr_on + 32'd1;
            if (faults[0] && !faults_q[0]) cov_oc <= cov_oc + 32'd1;
            if (faults[1] && !faults_q[1]) cov_wdt <= cov_wdt + 32'd1;
            if (faults[2] && !faults_q[2]) cov_sto <= cov_sto + 32'd1;
            if (faults[3] && !faults_q[3]) cov_desat <= cov_desat + 32'd1;
        end
        sto_h <= {sto_h[1:0], sto};
        desat_h <= {desat_h[1:0], desat};
        fault_q <= |faults;
        faults_q <= faults;
        w_wait <= w_now;
        r_wait <= r_now;
        w_out <= rst ? 1'b0 : (w_out & ~b_hs) | aw_hs;
        r_out <= rst ? 1'b0 : (r_out & ~r_hs) | ar_hs;
        b_hold <= s_axil_bvalid & ~s_axil_bready;
        r_hold <= s_axil_rvalid & ~s_axil_rready;
        bresp_q <= s_axil_bresp;
        rresp_q <= s_axil_rresp;
        rdata_q <= s_axil_rdata;
    end
endmodule
`default_nettype wire
