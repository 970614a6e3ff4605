// Whether a receiver word's three data bytes carry a good checksum (the
// third the checksum of the first two, NOTES.md): the time-shared engine
// computes it as it writes a channel's word and stores it with the word's
// flags, so that the answer's verdict, decoded a clock before the step
// (twh_rx_dec), needs no adder and no data bits at that clock; the data
// bits are read a clock later, with the step.
`default_nettype none
`include "twh_defs.vh"
module twh_rx_sum (
    // verilator lint_off UNUSEDSIGNAL
    input  wire [`TWH_RX_W-1:0] rx,     // (only the data bits)
    // verilator lint_on UNUSEDSIGNAL
    output wire                 ok
);
    wire [23:0] sh = rx[`TWH_RX_SH +: 24];
    wire [7:0]  chk;
    twh_checksum u_chk (.a(sh[7:0]), .b(sh[15:8]), .c(8'd0), .chk(chk));
    assign ok = (chk == sh[23:16]);
endmodule
`default_nettype wire
