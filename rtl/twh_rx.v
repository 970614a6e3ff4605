// UART receiver for the peripheral's 3-byte answer, on the demodulated
// envelope, timed by the 1 us carrier tick.
//
// - The first start bit counts only after at least half a bit (16 us) of
//   mark, so a line that merely wakes up or a lone glitch is not a start.
// - Each bit is the majority of three samples 11, 15 and 19 us after the
//   start edge was seen (the envelope edge lags the real edge by ~1 us, and
//   the spread keeps a glitch-stretched envelope pulse to one vote). The
//   start bit is re-checked this way, so a false start is dropped.
// - One stop bit is checked; the next start is hunted right after it, so a
//   sender with one or two stop bits is accepted. A 0 stop bit ends
//   reception with `frame_err`, except after eight 0 data bits: in on-off
//   keying a sender that stops keying leaves the line at 0, and a whole
//   character of 0s (a break) means the answer ended: reception stops and
//   the answer counts as short, not as a framing error.
// - 30.75-31.75 kbps: after 9.5 bits the sampling drift is at most ~5 us.
// Clearing `en` (outside the listen phase) clears everything.
`default_nettype none
module twh_rx (
    input  wire        clk,
    input  wire        rst,
    input  wire        en,
    input  wire        tick,
    input  wire        env,
    output reg  [1:0]  nbytes,      // complete bytes received (0-3)
    output reg  [23:0] bytes,       // received bytes, first in [23:16]
    output reg         started,     // a start bit passed its re-check
    output reg         frame_err
);
    reg       ended;      // the line went silent (a break) mid-answer
    reg       active;     // inside a character
    reg       more;       // a good stop bit was seen: next start needs no mark
    reg [4:0] mark;       // consecutive mark ticks, saturating at 16
    reg [4:0] sub;        // ticks since the start edge, within the bit
    reg [3:0] bitn;       // 0 start, 1-8 data, 9 stop
    reg [1:0] votes;      // ones among the samples of this bit
    reg [7:0] sh;

    wire done = (nbytes == 2'd3) || frame_err || ended;
    wire vote_tick = (sub == 5'd11) || (sub == 5'd15) || (sub == 5'd19);
    // the third sample completes the vote
    wire bit_val = (votes + {1'b0, env}) >= 2'd2;

    always @(posedge clk) begin
        if (rst || !en) begin
            nbytes    <= 2'd0;
            bytes     <= 24'd0;
            started   <= 1'b0;
            frame_err <= 1'b0;
            ended     <= 1'b0;
            active    <= 1'b0;
            more      <= 1'b0;
            mark      <= 5'd0;
            sub       <= 5'd0;
            bitn      <= 4'd0;
            votes     <= 2'd0;
            sh        <= 8'd0;
        end else if (tick && !done) begin
            if (!env)                mark <= 5'd0;
            else if (mark != 5'd16)  mark <= mark + 1'b1;

            if (!active) begin
                if (!env && (more || mark == 5'd16)) begin
                    active <= 1'b1;
                    sub    <= 5'd1;
                    bitn   <= 4'd0;
                    votes  <= 2'd0;
                end
            end else begin
                sub <= sub + 1'b1;
                if (sub == 5'd31) begin
                    bitn  <= bitn + 1'b1;
                    votes <= 2'd0;
                end
                if (vote_tick && sub != 5'd19) votes <= votes + {1'b0, env};
                if (sub == 5'd19) begin
                    case (bitn)
                        4'd0: begin
                            if (bit_val) active <= 1'b0;    // false start
                            else         started <= 1'b1;
                        end
                        4'd9: begin
                            active <= 1'b0;
                            if (bit_val) begin
                                more   <= 1'b1;
                                nbytes <= nbytes + 1'b1;
                                bytes  <= {bytes[15:0], sh};
                            end else if (sh == 8'd0) begin
                                ended     <= 1'b1;
                            end else begin
                                frame_err <= 1'b1;
                            end
                        end
                        default: sh <= {bit_val, sh[7:1]};
                    endcase
                end
            end
        end
    end
endmodule
`default_nettype wire
