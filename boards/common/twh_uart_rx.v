// UART receiver, 8 data bits, no parity, LSB first, one stop bit checked.
//
// The pin is asynchronous: it passes twh_sync2 first. A falling edge starts
// a character; every bit, the start bit included, is decided by the
// majority of three samples taken around its middle (DIV/8 apart), so a
// single disturbed sample does not corrupt a byte. A start bit whose middle
// reads high was a glitch, not a character: the receiver returns to idle.
// A stop bit that reads low (noise, a wrong baud rate, a break) gives
// frame_err instead of valid. The receiver is ready for the next falling
// edge right after the middle of the stop bit, which tolerates a sender
// up to ~3 % faster or slower than BAUD.
`default_nettype none
module twh_uart_rx #(
    parameter integer CLK_HZ = 12_000_000,
    parameter integer BAUD   = 115_200
) (
    input  wire       clk,
    input  wire       rst,
    input  wire       rx,          // the pin, asynchronous, idle high
    output wire [7:0] data,        // the character, valid with `valid` only
    output reg        valid,       // one clock: a character with a good stop bit
    output reg        frame_err    // one clock: the stop bit read low
);
    localparam integer DIV = (CLK_HZ + BAUD / 2) / BAUD;  // clocks per bit
    localparam integer D   = DIV / 8;                     // sample spacing
    localparam integer S0  = DIV / 2 - D;                 // first sample
    localparam integer S1  = DIV / 2;                     // second
    localparam integer S2  = DIV / 2 + D;                 // third, and the decision
    localparam integer CW  = $clog2(DIV);
    localparam [CW-1:0] C_S0   = S0[CW-1:0];
    localparam [CW-1:0] C_S1   = S1[CW-1:0];
    localparam [CW-1:0] C_S2   = S2[CW-1:0];
    localparam [CW-1:0] C_LAST = DIV[CW-1:0] - 1'b1;

    // A rate error above 2 % leaves too little margin once the PC's own
    // error adds to it; fewer than 8 clocks per bit leave no room for three
    // distinct samples.
    generate
        if (DIV < 8) begin : g_bad_div
            twh_error_UART_needs_8_clocks_per_bit u_err ();
        end
        if (DIV * BAUD > CLK_HZ + CLK_HZ / 50 || DIV * BAUD < CLK_HZ - CLK_HZ / 50) begin : g_bad_rate
            twh_error_UART_BAUD_more_than_2_percent_off u_err ();
        end
    endgenerate

    wire rxs;
    twh_sync2 u_sync (.clk(clk), .rst(rst), .d(rx), .q(rxs));

    localparam [1:0] IDLE = 2'd0, START = 2'd1, DATA = 2'd2, STOP = 2'd3;
    reg [1:0]    state;
    reg [CW-1:0] cnt;          // clock within the current bit
    reg [2:0]    nbit;         // data bit being received
    reg [1:0]    smp;          // first two samples of the current bit
    reg [7:0]    shift;
    reg          rxs_d;        // previous synchronised level, for the edge

    // the third sample is the live one
    wire maj = (smp[0] & smp[1]) | (smp[0] & rxs) | (smp[1] & rxs);

    always @(posedge clk) begin
        valid     <= 1'b0;
        frame_err <= 1'b0;
        if (rst) begin
            state <= IDLE;
            cnt   <= {CW{1'b0}};
            nbit  <= 3'd0;
            smp   <= 2'b11;
            shift <= 8'd0;
            // the synchroniser also resets to 0: no edge until the line
            // has been seen high after reset
            rxs_d <= 1'b0;
        end else begin
            rxs_d <= rxs;
            if (state == IDLE) begin
                cnt <= {CW{1'b0}};
                // an edge, not a low level: a line held low (a break) must
                // not start one character after another
                if (rxs_d && !rxs)
                    state <= START;
            end else begin
                cnt <= (cnt == C_LAST) ? {CW{1'b0}} : cnt + 1'b1;
                if (cnt == C_S0) smp[0] <= rxs;
                if (cnt == C_S1) smp[1] <= rxs;
                if (cnt == C_S2) begin
                    case (state)
                        START: begin
                            if (maj) state <= IDLE;     // glitch, not a start bit
                            else begin
                                state <= DATA;
                                nbit  <= 3'd0;
                            end
                        end
                        DATA: begin
                            shift <= {maj, shift[7:1]};
                            nbit  <= nbit + 1'b1;
                            if (nbit == 3'd7) state <= STOP;
                        end
                        default: begin                  // STOP
                            valid     <= maj;
                            frame_err <= !maj;
                            state     <= IDLE;
                        end
                    endcase
                end
            end
        end
    end

    assign data = shift;
endmodule
`default_nettype wire
