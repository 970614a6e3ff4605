// Where the two 16-bit fields of a channel timing register lie against
// their spec windows (section 4 table, twh_defs.vh): below the minimum,
// above the maximum, or inside (both flags 0).
//
// One instance in twh_core checks every timing write for every channel;
// twh_timing keeps the flags beside each value and clamps by them, so the
// engine needs no comparator of its own on the path into its phase
// counter. A stand-alone twh_engine behind its own twh_timing takes its
// flags from an instance per register (tb/tb_link.v shows how).
//
// Each bound is a constant, so each comparison is written as plain logic
// (below): synthesis makes a few LUTs of it instead of a 16-bit carry
// chain, and the register only picks among the results.
`default_nettype none
`include "twh_defs.vh"
module twh_window (
    input  wire [1:0]  sel,     // 0 TIMING0 {sync, charge}, 1 TIMING1 {execute, preamble},
                                // 2 TIMING2 {turnaround, listen}; 3: no window (flags 0)
    input  wire [31:0] value,
    output reg         lo_below,
    output reg         lo_above,
    output reg         hi_below,
    output reg         hi_above
);
    // v < c, decided at the highest bit where they differ; called with a
    // constant c only, so it folds into logic of v
    function lt;
        input [15:0] v, c;
        integer i;
        reg     found;
        begin
            lt    = 1'b0;
            found = 1'b0;
            for (i = 15; i >= 0; i = i - 1) begin
                if (!found && v[i] != c[i]) begin
                    lt    = c[i];
                    found = 1'b1;
                end
            end
        end
    endfunction

    wire [15:0] lo = value[15:0], hi = value[31:16];
    // v > c is written !(v < c + 1), c + 1 a constant too
    always @(*) begin
        case (sel)
            2'd0: begin
                lo_below = lt(lo, `TWH_CHARGE_MIN);      lo_above = 1'b0;   // no maximum
                hi_below = lt(hi, `TWH_SYNC_MIN);        hi_above = !lt(hi, `TWH_SYNC_MAX + 16'd1);
            end
            2'd1: begin
                lo_below = lt(lo, `TWH_PREAMBLE_MIN);    lo_above = !lt(lo, `TWH_PREAMBLE_MAX + 16'd1);
                hi_below = lt(hi, `TWH_EXECUTE_MIN);     hi_above = !lt(hi, `TWH_EXECUTE_MAX + 16'd1);
            end
            2'd2: begin
                lo_below = lt(lo, `TWH_LISTEN_MIN);      lo_above = 1'b0;
                hi_below = lt(hi, `TWH_TURNAROUND_MIN);  hi_above = 1'b0;
            end
            default: begin
                lo_below = 1'b0;                         lo_above = 1'b0;
                hi_below = 1'b0;                         hi_above = 1'b0;
            end
        endcase
    end

`ifdef FORMAL
    // formal/twh_window.sby: the flags are the plain comparisons with the
    // spec table's bounds, written out here, for every value and register
    always @(*) begin
        case (sel)
            2'd0: assert({hi_above, hi_below, lo_above, lo_below} ==
                         {hi > 16'd1100, hi < 16'd900, 1'b0, lo < 16'd7000});
            2'd1: assert({hi_above, hi_below, lo_above, lo_below} ==
                         {hi > 16'd10000, hi < 16'd3500, lo > 16'd2200, lo < 16'd1800});
            2'd2: assert({hi_above, hi_below, lo_above, lo_below} ==
                         {1'b0, hi < 16'd2000, 1'b0, lo < 16'd2000});
            default: assert({hi_above, hi_below, lo_above, lo_below} == 4'd0);
        endcase
    end
`endif
endmodule
`default_nettype wire
