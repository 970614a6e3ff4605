// One simulated 2-wire line: a stuck-line fault overrides everything;
// otherwise the host drives when host_oe is high, else the peripheral model
// when periph_oe is high, else the front end's pull-down reads low. `glitch`
// is OR-ed on top so a test can inject spikes anywhere.
//
// Logs for the Python side of the bench, which reads them in bulk instead of
// waking on every carrier edge (two wake-ups a microsecond per line cost more
// than simulating the core):
// - PIN_LOG: one line per change of the host's drive, "<ps> <host_oe>
//   <host_o>", for the spec monitor (tb/spec_monitor.py);
// - LINE_LOG: the time in ps of every rising edge of `line`, for the
//   peripheral model (tb/periph_model.py), with `carrier`: high from a rising
//   edge until QUIET_PS pass without one, so the model wakes twice a burst.
// Each line is flushed, so a read sees everything up to the current time
// step. "" logs nothing. Under Verilator the logs exist only with
// TWH_LINE_LOG defined (the cocotb benches, tb/simrun.py, with --timing):
// the Verilated soak and SoC use this line without them.
`default_nettype none
module tb_line #(
    // used only with the logs (the logs and the carrier flag serve cocotb)
    /* verilator lint_off UNUSEDPARAM */
    parameter PIN_LOG  = "",
    parameter LINE_LOG = ""
    /* verilator lint_on UNUSEDPARAM */
) (
    input  wire host_o,
    input  wire host_oe,
    input  wire periph_o,
    input  wire periph_oe,
    input  wire stuck_en,
    input  wire stuck_val,
    input  wire glitch,
    output wire line
);
    assign line = stuck_en ? stuck_val
                : ((host_oe ? host_o : (periph_oe ? periph_o : 1'b0)) | glitch);

`ifdef VERILATOR
`ifdef TWH_LINE_LOG
`define TWH_LINE_LOGS
`endif
`else
`define TWH_LINE_LOGS
`endif
`ifdef TWH_LINE_LOGS
    // the conversions round to the nearest picosecond, as meant; the wait's
    // length is worked out at run time
    /* verilator lint_off REALCVT */
    /* verilator lint_off ZERODLY */
    localparam [63:0] QUIET_PS = 64'd2_000_000;
    integer    pin_fd  = 0;
    integer    line_fd = 0;
    reg [63:0] pin_ps, rise_ps, now_ps;     // times in ps (rounded to the nearest)
    reg        carrier = 1'b0;
    initial begin
        rise_ps = 64'd0;
        if (PIN_LOG != "")  pin_fd  = $fopen(PIN_LOG, "w");
        if (LINE_LOG != "") line_fd = $fopen(LINE_LOG, "w");
    end
    always @(host_o or host_oe) if (pin_fd != 0) begin
        pin_ps = $realtime * 1000.0;
        $fwrite(pin_fd, "%0d %b %b\n", pin_ps, host_oe, host_o);
        $fflush(pin_fd);
    end
    always @(posedge line) if (line_fd != 0 && line === 1'b1) begin
        rise_ps = $realtime * 1000.0;
        $fwrite(line_fd, "%0d\n", rise_ps);
        $fflush(line_fd);
        carrier = 1'b1;
    end
    // one wake-up per QUIET_PS while the carrier runs, none per edge; the
    // waits are whole picoseconds (a sub-ps one would round to #0 for ever)
    always @(posedge carrier) begin
        now_ps = $realtime * 1000.0;
        while (now_ps - rise_ps < QUIET_PS) begin
            #((QUIET_PS - (now_ps - rise_ps)) / 1000.0);
            now_ps = $realtime * 1000.0;
        end
        carrier = 1'b0;
    end
    /* verilator lint_on ZERODLY */
    /* verilator lint_on REALCVT */
`endif
endmodule
`default_nettype wire
