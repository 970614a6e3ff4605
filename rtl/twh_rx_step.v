// The receiver's step, once a microsecond (the time-shared engine applies
// it to a channel's receiver word at the channel's visit in listen): the
// spec's 31.25 kbps 8N2 answer sampled at 11, 15 and 19 us into each 32 us
// bit, the majority of the three taken, the start bit re-checked (a false
// start goes back to waiting), one stop bit checked; a start needs 16
// marks first (half a bit of carrier) or a character before it; a stop
// bit read low ends the answer, as a break when the character was all
// zeros, else as a framing error. `dec` is twh_rx_dec's of `rx`, taken a
// clock earlier; `env` is the line as the visit reads it (carrier seen).
`default_nettype none
`include "twh_defs.vh"
module twh_rx_step (
    input  wire [`TWH_RX_W-1:0] rx,
    input  wire [8:0]           dec,
    input  wire                 env,
    output reg  [`TWH_RX_W-1:0] rx_n
);
    wire [23:1] sh  = rx[`TWH_RX_SH + 1 +: 23];   // (bit 0 shifts out)
    wire [4:0]  sub = rx[`TWH_RX_SB +: 5];
    wire [4:0]  mk  = rx[`TWH_RX_MK +: 5];
    wire [3:0]  bn  = rx[`TWH_RX_BN +: 4];
    wire [1:0]  vt  = rx[`TWH_RX_VT +: 2];
    wire [1:0]  nb  = rx[`TWH_RX_NB +: 2];
    wire        ac  = rx[`TWH_RX_AC];
    // two votes of three: vt + env >= 2, as logic (an adder and compare
    // became an iCE40 carry chain)
    wire        bit_val = vt[1] || (vt[0] && env);
    always @(*) begin
        rx_n = rx;
        // a data bit (dec[8]: not done, in a character, at the bit's
        // verdict, neither its start nor its stop bit)
        if (dec[8]) rx_n[`TWH_RX_SH +: 24] = {bit_val, sh[23:1]};
        if (!dec[0]) begin
            rx_n[`TWH_RX_MK +: 5] = !env ? 5'd0 : dec[2] ? mk : mk + 5'd1;
            if (!ac) begin
                if (!env && dec[1]) begin
                    rx_n[`TWH_RX_AC]      = 1'b1;
                    rx_n[`TWH_RX_SB +: 5] = 5'd1;
                    rx_n[`TWH_RX_BN +: 4] = 4'd0;
                end
            end else begin
                rx_n[`TWH_RX_SB +: 5] = sub + 5'd1;
                if (dec[5]) rx_n[`TWH_RX_BN +: 4] = bn + 4'd1;
                if (dec[3]) rx_n[`TWH_RX_VT +: 2] = vt + {1'b0, env};
                if (dec[4]) begin
                    rx_n[`TWH_RX_VT +: 2] = 2'd0;
                    if (dec[6]) begin
                        // a false start; else the character goes on
                        if (bit_val) rx_n[`TWH_RX_AC] = 1'b0;
                    end else if (dec[7]) begin
                        // the stop bit (a data bit is dec[8]'s, above)
                        rx_n[`TWH_RX_AC] = 1'b0;
                        if (bit_val)              rx_n[`TWH_RX_NB +: 2] = nb + 2'd1;
                        else if (sh[23:16] == 8'd0) rx_n[`TWH_RX_EN] = 1'b1;
                        else                      rx_n[`TWH_RX_FE] = 1'b1;
                    end
                end
            end
        end
    end
endmodule
`default_nettype wire
