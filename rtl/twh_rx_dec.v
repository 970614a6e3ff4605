// What the receiver's step and the answer's verdict read of a receiver
// word (the layout of twh_defs.vh, TWH_RX_*), decoded a clock before the
// step: the time-shared engine decodes the word as it leaves the state RAM
// and registers the flags beside it, so that the step itself is only the
// multiplexers they select (the receiver's step was the engine's longest
// path on the ECP5 and the UP5K). The data bits are not read here: the
// checksum's verdict comes in as `sum_ok` (twh_rx_sum of the same word,
// which the engine stores with it).
`default_nettype none
`include "twh_defs.vh"
module twh_rx_dec (
    // verilator lint_off UNUSEDSIGNAL
    input  wire [`TWH_RX_W-1:0] rx,     // (not its data bits or votes: the step's alone)
    // verilator lint_on UNUSEDSIGNAL
    input  wire       sync_low,   // the line was read low during sync
    input  wire       pre_high,   // ... and high during preamble
    input  wire       sum_ok,     // twh_rx_sum of rx: the third byte is the
                                  // checksum of the first two
    // for twh_rx_step: [0] the answer is done (three characters, a framing
    // error or a break), [1] a start bit may begin (a character came, or
    // 16 marks), [2] 16 marks, [3] a vote sample (11 or 15 ticks into the
    // bit), [4] the bit's verdict (19), [5] the bit's last tick (31),
    // [6] the start bit, [7] the stop bit, [8] a data bit's verdict (the
    // step shifts it in: its whole condition here, so that the data bits'
    // multiplexer has one select from a flip-flop, where five of them had
    // stood in front of it on the UP5K's one-channel path)
    output wire [8:0] dec,
    // the answer as it stands, were listen to end now (the precedence
    // formal/twh_rx.sby's equiv states); its data is the answer's when OK
    // or BAD_CHECKSUM
    output reg  [3:0] status
);
    wire [4:0]  sub = rx[`TWH_RX_SB +: 5];
    wire [4:0]  mk  = rx[`TWH_RX_MK +: 5];
    wire [3:0]  bn  = rx[`TWH_RX_BN +: 4];
    wire [1:0]  nb  = rx[`TWH_RX_NB +: 2];
    wire        ac  = rx[`TWH_RX_AC];
    wire        fe  = rx[`TWH_RX_FE];
    wire        en  = rx[`TWH_RX_EN];

    wire   done   = (nb == 2'd3) || fe || en;
    assign dec[0] = done;
    assign dec[1] = (nb != 2'd0) || (mk == 5'd16);
    assign dec[2] = mk == 5'd16;
    assign dec[3] = (sub == 5'd11) || (sub == 5'd15);
    wire   vrd    = sub == 5'd19;       // the bit's verdict
    wire   b_st   = bn == 4'd0;         // the start bit
    wire   b_sp   = bn == 4'd9;         // the stop bit
    assign dec[4] = vrd;
    assign dec[5] = sub == 5'd31;
    assign dec[6] = b_st;
    assign dec[7] = b_sp;
    // (not done: its stop bit, framing error or break clears ac anyway,
    // but so the engine's proof needs no invariant for it)
    assign dec[8] = !done && ac && vrd && !b_st && !b_sp;

    // a start bit passed its re-check (the word keeps no flag of its own:
    // a character came, the answer ended, or one is past its start's
    // re-check at 19 us), which tells a short answer from none
    // (sub >= 20 as a map, bit k: k >= 20; a compare with a constant became
    // an iCE40 carry chain)
    localparam [31:0] SUB_GE20 = ~((32'd1 << 20) - 32'd1);
    wire st = (nb != 2'd0) || fe || en || (ac && (bn != 4'd0 || SUB_GE20[sub]));
    // the checksum's verdict is the last choice, not inside the chain of
    // the others (when its adder was here, it was the slowest input)
    wire full = sync_low && pre_high && !fe && (nb == 2'd3);
    reg [3:0] other;
    always @(*) begin
        if (!sync_low)         other = `TWH_ST_LINE_STUCK_HIGH;
        else if (!pre_high)    other = `TWH_ST_LINE_STUCK_LOW;
        else if (fe)           other = `TWH_ST_FRAMING;
        else if (st)           other = `TWH_ST_SHORT_RESPONSE;
        else                   other = `TWH_ST_NO_RESPONSE;
        if (full)              status = sum_ok ? `TWH_ST_OK : `TWH_ST_BAD_CHECKSUM;
        else                   status = other;
    end
endmodule
`default_nettype wire
