// Where the two 16-bit fields of a channel timing register lie against
// their spec windows (section 4 table, twh_defs.vh): below the minimum,
// above the maximum, or inside (both flags 0).
//
// One instance in twh_core checks every timing write for every channel:
// the register picks the constants, so four comparators serve all three
// registers. twh_channel keeps the flags beside each value and twh_link
// clamps by them, so the engine needs no comparator of its own on the path
// into its phase counter. A stand-alone twh_link takes its flags from an
// instance per register (tb/tb_link.v shows how).
`default_nettype none
`include "twh_defs.vh"
module twh_window (
    input  wire [1:0]  sel,     // 0 TIMING0 {sync, charge}, 1 TIMING1 {execute, preamble},
                                // 2 TIMING2 {turnaround, listen}; 3: no window (flags 0)
    input  wire [31:0] value,
    output wire        lo_below,
    output wire        lo_above,
    output wire        hi_below,
    output wire        hi_above
);
    reg [15:0] lo_min, lo_max, hi_min, hi_max;
    always @(*) begin
        case (sel)
            2'd0: begin
                lo_min = `TWH_CHARGE_MIN;     lo_max = `TWH_US_MAX;
                hi_min = `TWH_SYNC_MIN;       hi_max = `TWH_SYNC_MAX;
            end
            2'd1: begin
                lo_min = `TWH_PREAMBLE_MIN;   lo_max = `TWH_PREAMBLE_MAX;
                hi_min = `TWH_EXECUTE_MIN;    hi_max = `TWH_EXECUTE_MAX;
            end
            2'd2: begin
                lo_min = `TWH_LISTEN_MIN;     lo_max = `TWH_US_MAX;
                hi_min = `TWH_TURNAROUND_MIN; hi_max = `TWH_US_MAX;
            end
            default: begin
                lo_min = 16'd0;               lo_max = `TWH_US_MAX;
                hi_min = 16'd0;               hi_max = `TWH_US_MAX;
            end
        endcase
    end
    assign lo_below = value[15:0]  < lo_min;
    assign lo_above = value[15:0]  > lo_max;
    assign hi_below = value[31:16] < hi_min;
    assign hi_above = value[31:16] > hi_max;
endmodule
`default_nettype wire
