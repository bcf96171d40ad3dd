`default_nettype none
// hfi_safety: the hardware safety logic of hfi_dsp - STO (Safe Torque Off) and driver-fault (DESAT)
// inputs, the fault latches, the output enable and the gate output register.
//
// Implements docs/spec.md 3.8; golden model golden/fpga/safety.py (SafetyLogic, clock by clock),
// compared bit for bit in cocotb_tests/test_safety.py; proven in formal/hfi_safety.sby:
//   STO (synchronized) in clock t => all gates off in clock t+1, for any register and firmware state;
//   a latched STO/DESAT fault is cleared only by fault_clear while its input is released;
//   with hfi_gate_gen behind it, never both switches of a leg on, for any input sequence.
//
// Ports
//   sto, desat       asynchronous pins, active high (torque off requested / driver fault); each goes
//                    through a two-flop synchronizer (hfi_cdc_sync): sto_s(t) = sto(t-2)
//   oc_trip          one-clock pulse of hfi_overcurrent;  wdt_expired: level, watchdog run out
//   fault_clear      one-clock pulse, CTRL.FAULT_CLEAR;  ctrl_enable: CTRL.ENABLE;  at_bottom: carrier
//   gate_in[5:0]     hfi_gate_gen output
//   gate[5:0]        registered: 0 in the clock after rst or kill, else gate_in of the clock before
//   kill             any fault latched or STO/DESAT active: to hfi_gate_gen.kill
//   enable           to hfi_gate_gen.enable (CTRL.ENABLE applied at carrier bottoms, 0 while kill)
//   fault_*          the latches (STATUS);  sto_s, desat_s: the synchronized inputs (STATUS)
//   outputs_on       STATUS.OUTPUTS_ON;  drive_allowed: for the gate driver's enable pin
// Latency: sto/desat pin -> gate off 3 clocks (2 synchronizer + the output register); fault latch ->
// gate off 1 clock. Reset: rst clears the latches, the enable and the gates; the synchronizers have
// no reset (their configuration value is 0).
module hfi_safety (
    input  wire       clk,
    input  wire       rst,
    input  wire       sto,
    input  wire       desat,
    input  wire       oc_trip,
    input  wire       wdt_expired,
    input  wire       fault_clear,
    input  wire       ctrl_enable,
    input  wire       at_bottom,
    input  wire [5:0] gate_in,
    output reg  [5:0] gate,
    output wire       kill,
    output wire       enable,
    output wire       sto_s,
    output wire       desat_s,
    output reg        fault_oc,
    output reg        fault_wdt,
    output reg        fault_sto,
    output reg        fault_desat,
    output wire       outputs_on,
    output wire       drive_allowed
);
    hfi_cdc_sync u_sto_sync   (.clk(clk), .d(sto),   .q(sto_s));
    hfi_cdc_sync u_desat_sync (.clk(clk), .d(desat), .q(desat_s));

    reg  en_applied;
    wire fault = fault_oc | fault_wdt | fault_sto | fault_desat;
    assign kill = fault | sto_s | desat_s;
    wire en_now = at_bottom ? ctrl_enable : en_applied;   // CTRL.ENABLE applies at a bottom
    assign enable = en_now & ~kill;
    assign outputs_on = en_applied & ~fault;
    assign drive_allowed = ~(fault_sto | fault_desat | sto_s | desat_s);

    always @(posedge clk)
        gate <= (rst | kill) ? 6'd0 : gate_in;

    // a set in the same clock as fault_clear wins: an input still active cannot be cleared
    always @(posedge clk) begin
        if (rst) begin
            fault_oc <= 1'b0;
            fault_wdt <= 1'b0;
            fault_sto <= 1'b0;
            fault_desat <= 1'b0;
            en_applied <= 1'b0;
        end else begin
            fault_oc <= (fault_oc & ~fault_clear) | oc_trip;
            fault_wdt <= (fault_wdt & ~fault_clear) | wdt_expired;
            fault_sto <= (fault_sto & ~fault_clear) | sto_s;
            fault_desat <= (fault_desat & ~fault_clear) | desat_s;
            if (kill)
                en_applied <= 1'b0;
            else if (at_bottom)
                en_applied <= ctrl_enable;
        end
    end
endmodule
`default_nettype wire
