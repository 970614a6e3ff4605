// UART transmitter, 8 data bits, no parity, LSB first, one stop bit.
// A byte is taken when valid and ready are both high; ready stays low
// until its stop bit has been sent in full.
`default_nettype none
module twh_uart_tx #(
    parameter integer CLK_HZ = 12_000_000,
    parameter integer BAUD   = 115_200
) (
    input  wire       clk,
    input  wire       rst,
    input  wire [7:0] data,
    input  wire       valid,
    output wire       ready,
    output reg        tx          // the pin, idle high
);
    localparam integer DIV = (CLK_HZ + BAUD / 2) / BAUD;
    localparam integer CW  = $clog2(DIV);
    localparam [CW-1:0] C_LAST = DIV[CW-1:0] - 1'b1;

    reg [CW-1:0] cnt;
    reg          at_last;    // cnt is C_LAST: the bit's last clock (a flip-flop, so the
                             // bit's end is not a compare in front of every enable)
    reg [3:0]    left;       // bits still to send after the current one
    reg [8:0]    shift;      // data bits and the stop bit still to send
    reg          busy;

    assign ready = !busy;

    always @(posedge clk) begin
        if (rst) begin
            busy  <= 1'b0;
            tx    <= 1'b1;
            cnt   <= {CW{1'b0}};
            at_last <= 1'b0;
            left  <= 4'd0;
            shift <= 9'h1FF;
        end else if (!busy) begin
            if (valid) begin
                busy  <= 1'b1;
                tx    <= 1'b0;                  // start bit
                shift <= {1'b1, data};
                left  <= 4'd9;
                cnt   <= {CW{1'b0}};
                at_last <= (C_LAST == {CW{1'b0}});
            end
        end else if (!at_last) begin
            cnt <= cnt + 1'b1;
            at_last <= (cnt == C_LAST - 1'b1);
        end else begin
            cnt <= {CW{1'b0}};
            at_last <= (C_LAST == {CW{1'b0}});
            if (left == 4'd0) begin
                busy <= 1'b0;                   // the stop bit is over
            end else begin
                tx    <= shift[0];
                shift <= {1'b1, shift[8:1]};
                left  <= left - 1'b1;
            end
        end
    end
endmodule
`default_nettype wire
