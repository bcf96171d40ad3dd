`default_nettype none
// hfi_soc_acc: the SoC's arithmetic accelerators in the CPU clock (registers: rtl/regs/hfi_acc.rdl,
// docs/acc_registers.md; docs/soc.md, "Accelerators"). Each unit computes one of the firmware's own
// functions bit for bit, so the firmware on the SoC calls the unit where the host build of the same C
// calls the software (firmware/src/fw_acc.c):
//   - sine/cosine: hfi_cordic with WIDTH 32 and 16 iterations = golden.fpga.cordic.sincos_q15(angle) =
//     fw_sincos_q15 (18 CPU clocks from the SIN_ANGLE write to the result);
//   - angle and magnitude of a vector: hfi_vector = golden.firmware.vector.vector_angle(x, y) =
//     fw_vector_angle (18 CPU clocks from the VEC_Y write to the result; VEC_X holds x);
//   - flux-map look-up: hfi_flux_lut = golden.firmware.flux_lut.lut_point = fw_lut_point; it reads the
//     tables from the SoC RAM, where the firmware's configuration block holds them (LUT_BASE_*), through
//     the RAM's data port (mem_*): the LUT_IQ write that starts a look-up is answered only when the
//     look-up is done, so the CPU waits on its data bus and the port is free (mem_en is high only then).
// Native PicoRV32-style bus as hfi_soc_ctl: `sel` for one access, answered with `ready`. An access that
// must wait for a unit is answered when the unit is done, so the firmware never polls: a SIN_ANGLE write
// or a SINCOS read waits while the CORDIC computes, an access to VEC_* while the vectoring CORDIC does; the
// LUT_IQ write waits for its look-up (above).
// Writes store the whole word.
module hfi_soc_acc #(
    parameter RAM_AW = 14,                      // word-address width of the SoC RAM
    // build option (docs/rtl.md "Build options"): 0 leaves the flux-map look-up unit out; a LUT_IQ write
    // is then answered in the next clock, the results read 0, the RAM port stays idle; CAPS reads it
    parameter FLUX_LUT = 1
) (
    input  wire              clk,
    input  wire              rst,
    input  wire              sel,
    input  wire [7:0]        addr,
    input  wire [3:0]        wstrb,
    input  wire [31:0]       wdata,
    output reg  [31:0]       rdata,
    output reg               ready,
    // the SoC RAM's data port, used only while the CPU waits on a LUT_IQ write
    output wire              mem_en,
    output wire [RAM_AW-1:0] mem_addr,
    input  wire [31:0]       mem_rdata
);
/* verilator lint_off UNUSEDPARAM */
`include "regs/hfi_acc_map.vh"
/* verilator lint_on UNUSEDPARAM */

    // ---------------------------------------------------------------- bus
    wire is_sin = addr == ACC_SIN_ANGLE_ADDR || addr == ACC_SINCOS_ADDR;
    wire is_vec = addr == ACC_VEC_X_ADDR || addr == ACC_VEC_Y_ADDR || addr == ACC_VEC_ANGLE_ADDR
                  || addr == ACC_VEC_MAG_ADDR;
    reg sc_run;                                   // sine/cosine: from the start to the done cycle (exclusive)
    reg vec_run;                                  // vector: likewise
    reg lut_run;                                  // look-up: likewise
    // An access is taken (`take`: its write stored, its read data registered) when its unit is free;
    // it is answered (`go`: ready in the next clock) then, except the LUT_IQ write, answered at lut_done.
    wire is_iq = addr == ACC_LUT_IQ_ADDR && wstrb != 4'd0;
    wire take = sel && !ready && !lut_run && !(is_sin && sc_run) && !(is_vec && vec_run);
    wire write = take && wstrb != 4'd0;
    wire read = take && wstrb == 4'd0;
    wire sc_start = write && addr == ACC_SIN_ANGLE_ADDR;
    wire vec_start = write && addr == ACC_VEC_Y_ADDR;
    wire lut_start = write && is_iq;
    wire lut_done;
    wire go = (take && !is_iq) || lut_done;

    // ---------------------------------------------------------------- sine and cosine
    wire sc_done;
    wire signed [15:0] sc_sin, sc_cos;
    /* verilator lint_off PINCONNECTEMPTY */
    hfi_cordic #(.WIDTH(32), .ITERATIONS(16)) u_sincos (
        .clk(clk), .rst(rst), .start(sc_start), .angle(wdata), .busy(), .done(sc_done),
        .sin_q15(sc_sin), .cos_q15(sc_cos)
    );
    /* verilator lint_on PINCONNECTEMPTY */

    // ---------------------------------------------------------------- angle and magnitude of a vector
    reg [31:0] vec_x;
    wire vec_done;
    wire [31:0] vec_angle;
    wire signed [31:0] vec_mag;
    /* verilator lint_off PINCONNECTEMPTY */
    hfi_vector u_vector (
        .clk(clk), .rst(rst), .start(vec_start), .x(vec_x), .y(wdata), .busy(), .done(vec_done),
        .angle(vec_angle), .mag(vec_mag)
    );
    /* verilator lint_on PINCONNECTEMPTY */

    // ---------------------------------------------------------------- flux-map look-up
    reg [6:0] n_d, n_q;
    reg [3:0] shift;
    reg [2:0] coarse;
    reg [4:0] f_shift;
    reg [31:0] knee, id;
    reg [RAM_AW+1:0] base_d, base_q, base_ld, base_lq, base_ldq;
    wire signed [63:0] lam_d, lam_q, dl_d, dl_q, dl_dq;
    // l_d, l_q, l_dq interpolate the s28 inductance tables with fractions in 0..1: they fit s32, the
    // registers L_D, L_Q, L_DQ carry bits 31:0 (docs/acc_registers.md)
    /* verilator lint_off UNUSEDSIGNAL */
    wire signed [63:0] l_d, l_q, l_dq;
    /* verilator lint_on UNUSEDSIGNAL */
    generate
        if (FLUX_LUT != 0) begin : g_lut
            /* verilator lint_off PINCONNECTEMPTY */
            hfi_flux_lut #(.RAM_AW(RAM_AW)) u_lut (
                .clk(clk), .rst(rst),
                .base_d(base_d), .base_q(base_q), .base_ld(base_ld), .base_lq(base_lq), .base_ldq(base_ldq),
                .mem_en(mem_en), .mem_addr(mem_addr), .mem_rdata(mem_rdata),
                .n_d(n_d), .n_q(n_q), .shift(shift), .knee(knee), .coarse(coarse), .f_shift(f_shift),
                .start(lut_start), .i_d(id), .i_q(wdata), .busy(), .done(lut_done),
                .lam_d(lam_d), .lam_q(lam_q), .l_d(l_d), .l_q(l_q), .l_dq(l_dq), .dl_d(dl_d), .dl_q(dl_q),
                .dl_dq(dl_dq)
            );
            /* verilator lint_on PINCONNECTEMPTY */
        end else begin : g_no_lut               // build option: answered the clock after the start
            assign lut_done = lut_run;
            assign mem_en = 1'b0;
            assign mem_addr = {RAM_AW{1'b0}};
            assign {lam_d, lam_q, l_d, l_q, l_dq, dl_d, dl_q, dl_dq} = {8{64'sd0}};
            wire unused_lut = &{1'b0, mem_rdata, n_d, n_q, shift, coarse, f_shift, knee, id, base_d, base_q,
                                base_ld, base_lq, base_ldq};
        end
    endgenerate

    always @(posedge clk) begin
        if (rst) begin
            ready <= 1'b0;
            rdata <= 32'd0;
            sc_run <= 1'b0;
            vec_run <= 1'b0;
            vec_x <= 32'd0;
            lut_run <= 1'b0;
            n_d <= ACC_LUT_CFG_N_D_RESET;
            n_q <= ACC_LUT_CFG_N_Q_RESET;
            shift <= ACC_LUT_CFG_SHIFT_RESET;
            coarse <= ACC_LUT_CFG_COARSE_RESET;
            f_shift <= ACC_LUT_CFG_F_SHIFT_RESET;
            knee <= 32'd0;
            id <= 32'd0;
            base_d <= 0;
            base_q <= 0;
            base_ld <= 0;
            base_lq <= 0;
            base_ldq <= 0;
        end else begin
            ready <= go;
            sc_run <= sc_start || (sc_run && !sc_done);
            vec_run <= vec_start || (vec_run && !vec_done);
            lut_run <= lut_start || (lut_run && !lut_done);
            if (write) begin
                case (addr)
                    ACC_LUT_CFG_ADDR: begin
                        n_d <= wdata[ACC_LUT_CFG_N_D_LSB +: ACC_LUT_CFG_N_D_WIDTH];
                        n_q <= wdata[ACC_LUT_CFG_N_Q_LSB +: ACC_LUT_CFG_N_Q_WIDTH];
                        shift <= wdata[ACC_LUT_CFG_SHIFT_LSB +: ACC_LUT_CFG_SHIFT_WIDTH];
                        coarse <= wdata[ACC_LUT_CFG_COARSE_LSB +: ACC_LUT_CFG_COARSE_WIDTH];
                        f_shift <= wdata[ACC_LUT_CFG_F_SHIFT_LSB +: ACC_LUT_CFG_F_SHIFT_WIDTH];
                    end
                    ACC_VEC_X_ADDR:       vec_x <= wdata;
                    ACC_LUT_KNEE_ADDR:    knee <= wdata;
                    ACC_LUT_ID_ADDR:      id <= wdata;
                    ACC_LUT_BASE_D_ADDR:   base_d <= wdata[RAM_AW+1:0];
                    ACC_LUT_BASE_Q_ADDR:   base_q <= wdata[RAM_AW+1:0];
                    ACC_LUT_BASE_LD_ADDR:  base_ld <= wdata[RAM_AW+1:0];
                    ACC_LUT_BASE_LQ_ADDR:  base_lq <= wdata[RAM_AW+1:0];
                    ACC_LUT_BASE_LDQ_ADDR: base_ldq <= wdata[RAM_AW+1:0];
                    default: ;
                endcase
            end
            if (read) begin
                case (addr)
                    ACC_SINCOS_ADDR:      rdata <= {sc_cos, sc_sin};
                    ACC_VEC_ANGLE_ADDR:   rdata <= vec_angle;
                    ACC_VEC_MAG_ADDR:     rdata <= vec_mag;
                    ACC_CAPS_ADDR:        rdata <= {31'd0, FLUX_LUT != 0} << ACC_CAPS_FLUX_LUT_LSB;
                    ACC_LUT_CFG_ADDR:     rdata <= {3'd0, f_shift, 1'b0, coarse, shift, 1'b0, n_q, 1'b0, n_d};
                    ACC_LUT_KNEE_ADDR:    rdata <= knee;
                    ACC_LUT_BASE_D_ADDR:   rdata <= {{(30-RAM_AW){1'b0}}, base_d};
                    ACC_LUT_BASE_Q_ADDR:   rdata <= {{(30-RAM_AW){1'b0}}, base_q};
                    ACC_LUT_BASE_LD_ADDR:  rdata <= {{(30-RAM_AW){1'b0}}, base_ld};
                    ACC_LUT_BASE_LQ_ADDR:  rdata <= {{(30-RAM_AW){1'b0}}, base_lq};
                    ACC_LUT_BASE_LDQ_ADDR: rdata <= {{(30-RAM_AW){1'b0}}, base_ldq};
                    ACC_LUT_ID_ADDR:      rdata <= id;
                    ACC_LAM_D_LO_ADDR:    rdata <= lam_d[31:0];
                    ACC_LAM_D_HI_ADDR:    rdata <= lam_d[63:32];
                    ACC_LAM_Q_LO_ADDR:    rdata <= lam_q[31:0];
                    ACC_LAM_Q_HI_ADDR:    rdata <= lam_q[63:32];
                    ACC_L_D_ADDR:         rdata <= l_d[31:0];
                    ACC_L_Q_ADDR:         rdata <= l_q[31:0];
                    ACC_L_DQ_ADDR:        rdata <= l_dq[31:0];
                    ACC_DL_D_LO_ADDR:     rdata <= dl_d[31:0];
                    ACC_DL_D_HI_ADDR:     rdata <= dl_d[63:32];
                    ACC_DL_Q_LO_ADDR:     rdata <= dl_q[31:0];
                    ACC_DL_Q_HI_ADDR:     rdata <= dl_q[63:32];
                    ACC_DL_DQ_LO_ADDR:    rdata <= dl_dq[31:0];
                    ACC_DL_DQ_HI_ADDR:    rdata <= dl_dq[63:32];
                    default:              rdata <= 32'd0;
                endcase
            end
        end
    end
endmodule
`default_nettype wire
