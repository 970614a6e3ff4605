// UART-to-Wishbone bridge: a PC masters the core's registers over a serial
// port (8N1, BAUD). The protocol is in docs/boards.md; in short, with every
// request ending in a check byte C = ~(sum of its other bytes) (the 2-wire
// link's own checksum rule):
//
//   read    'R' A C               -> S D0 D1 D2 D3   (D little endian)
//   write   'W' A D0 D1 D2 D3 C   -> S
//   status  'S'                   -> S
//
// A is the word address (byte address / 4): a 1 KiB window, the core's
// global registers and channels 0-27 (register map version 2). S = {4'hA,
// DROPPED, IRQ, FRAME_ERR, BUS_ERR}: BUS_ERR - the access was made and
// answered with an error; FRAME_ERR - the check
// byte was wrong and nothing was done (a read still answers four zero
// bytes, so every answer has the length its opcode promises); IRQ - the
// core's irq line; DROPPED - bytes were discarded since the last answer.
//
// Garbage: outside a request any byte other than the three opcodes is
// dropped. A request that stops half way is dropped after TIMEOUT_BITS bit
// times of silence, and at once on a character with a bad stop bit (so a
// break resets the parser). Bytes that arrive while an answer is being
// sent are dropped. A PC therefore always resynchronises by staying silent
// for TIMEOUT_BITS bit times and flushing its input.
`default_nettype none
module twh_uart_bridge #(
    parameter integer CLK_HZ       = 12_000_000,
    parameter integer BAUD         = 115_200,
    parameter integer TIMEOUT_BITS = 1024
) (
    input  wire        clk,
    input  wire        rst,
    input  wire        uart_rx,     // pin, asynchronous
    output wire        uart_tx,     // pin
    // Wishbone B4 classic master, 32-bit, byte addresses
    output wire [9:0]  wb_adr_o,
    output wire [31:0] wb_dat_o,
    input  wire [31:0] wb_dat_i,
    output wire        wb_we_o,
    output wire [3:0]  wb_sel_o,
    output reg         wb_stb_o,
    output wire        wb_cyc_o,
    input  wire        wb_ack_i,
    input  wire        wb_err_i,
    input  wire        irq,
    output reg         activity,    // one clock: a request was carried out
    output reg         fault        // one clock: something was dropped or refused
);
    localparam integer DIV  = (CLK_HZ + BAUD / 2) / BAUD;
    localparam integer TMO  = TIMEOUT_BITS * DIV;
    localparam integer TW   = $clog2(TMO + 1);
    localparam [TW-1:0] C_TMO = TMO[TW-1:0];

    localparam [7:0] OP_READ = 8'h52, OP_WRITE = 8'h57, OP_STATUS = 8'h53;

    wire [7:0] rx_byte;
    wire       rx_strobe, rx_bad;
    twh_uart_rx #(.CLK_HZ(CLK_HZ), .BAUD(BAUD)) u_rx (
        .clk(clk), .rst(rst), .rx(uart_rx),
        .data(rx_byte), .valid(rx_strobe), .frame_err(rx_bad)
    );
    // The parser takes each character a clock after the receiver, with its
    // opcode already decoded: the parser's enables then start from
    // flip-flops, with no byte compare in front of them (the iCEBreaker
    // top's critical path on the UP5K ran from the received byte through
    // the opcode compare into the parser's state).
    reg [7:0] rx_data;
    reg       rx_valid, rx_ferr;
    reg       op_rw, op_w, op_s;     // rx_data is 'R' or 'W', 'W', 'S'
    always @(posedge clk) begin
        rx_valid <= !rst && rx_strobe;
        rx_ferr  <= !rst && rx_bad;
        if (rx_strobe) begin
            rx_data <= rx_byte;
            op_rw   <= (rx_byte == OP_READ) || (rx_byte == OP_WRITE);
            op_w    <= (rx_byte == OP_WRITE);
            op_s    <= (rx_byte == OP_STATUS);
        end
    end

    reg  [7:0] tx_data;
    reg        tx_valid;
    wire       tx_ready;
    twh_uart_tx #(.CLK_HZ(CLK_HZ), .BAUD(BAUD)) u_tx (
        .clk(clk), .rst(rst), .data(tx_data), .valid(tx_valid),
        .ready(tx_ready), .tx(uart_tx)
    );

    localparam [1:0] S_RECV = 2'd0, S_BUS = 2'd1, S_ANSWER = 2'd2, S_SEND = 2'd3;
    reg [1:0]    state;
    reg          in_req;     // a read or write request is being received
    reg          is_write;
    reg [2:0]    idx;        // bytes of the request received after the opcode
    reg [7:0]    sum;
    reg [7:0]    adr;
    reg [31:0]   dat;        // write data in, read data out
    reg [2:0]    left;       // answer bytes still to send after tx_data
    reg          bus_err, frame_err, dropped;
    reg          chk;        // the request is complete: its sum is checked next
    // clocks left before a request that stopped arriving is dropped: a
    // down-counter with its zero registered, so no wide compare sits on
    // the path into the request state
    reg [TW-1:0] idle;
    reg          idle_out;   // idle == 0: the next idle clock times out

    wire last_byte = is_write ? (idx == 3'd5) : (idx == 3'd1);
    wire [7:0] status = {4'hA, dropped, irq, frame_err, bus_err};
    // one shift for both directions: write data comes in at the top, read
    // data leaves at the bottom
    wire       shift_in  = (state == S_RECV) && rx_valid && in_req && idx != 3'd0 && !last_byte;
    wire       shift_out = (state == S_SEND) && tx_valid && tx_ready && left != 3'd0;

    // the request registers hold still while the strobe is up
    assign wb_adr_o = {adr, 2'b00};
    assign wb_dat_o = dat;
    assign wb_we_o  = is_write;
    assign wb_cyc_o = wb_stb_o;
    assign wb_sel_o = 4'hF;

    always @(posedge clk) begin
        activity <= 1'b0;
        fault    <= 1'b0;
        if (rst) begin
            state     <= S_RECV;
            in_req    <= 1'b0;
            is_write  <= 1'b0;
            idx       <= 3'd0;
            sum       <= 8'd0;
            adr       <= 8'd0;
            dat       <= 32'd0;
            left      <= 3'd0;
            bus_err   <= 1'b0;
            frame_err <= 1'b0;
            dropped   <= 1'b0;
            chk       <= 1'b0;
            idle      <= C_TMO;
            idle_out  <= 1'b0;
            tx_data   <= 8'd0;
            tx_valid  <= 1'b0;
            wb_stb_o  <= 1'b0;
        end else begin
            if (shift_in || shift_out)
                dat <= {rx_data, dat[31:8]};
            case (state)
            S_RECV: begin
                if (chk) begin
                    // one clock after the last byte (the next is a whole
                    // character away): the sum, now a register, must be FF
                    chk <= 1'b0;
                    if (sum != 8'hFF) begin
                        frame_err <= 1'b1;
                        fault     <= 1'b1;
                        state     <= S_ANSWER;
                    end else begin
                        wb_stb_o <= 1'b1;
                        activity <= 1'b1;
                        state    <= S_BUS;
                    end
                end else if (rx_ferr) begin
                    // a broken character: whatever request it belonged to
                    // cannot be trusted
                    in_req  <= 1'b0;
                    dropped <= 1'b1;
                    fault   <= 1'b1;
                end else if (rx_valid && !in_req) begin
                    sum  <= rx_data;
                    idx  <= 3'd0;
                    idle     <= C_TMO;
                    idle_out <= 1'b0;
                    if (op_rw) begin
                        in_req   <= 1'b1;
                        is_write <= op_w;
                    end else if (op_s) begin
                        is_write  <= 1'b1;           // answer: the status byte only
                        frame_err <= 1'b0;
                        bus_err   <= 1'b0;
                        activity  <= 1'b1;
                        state     <= S_ANSWER;
                    end else begin
                        dropped <= 1'b1;
                        fault   <= 1'b1;
                    end
                end else if (rx_valid) begin
                    idx  <= idx + 1'b1;
                    sum  <= sum + rx_data;
                    idle     <= C_TMO;
                    idle_out <= 1'b0;
                    if (idx == 3'd0)
                        adr <= rx_data;
                    if (last_byte) begin
                        in_req    <= 1'b0;
                        bus_err   <= 1'b0;
                        frame_err <= 1'b0;
                        chk       <= 1'b1;
                    end
                end else if (in_req) begin
                    if (idle_out) begin
                        in_req  <= 1'b0;
                        dropped <= 1'b1;
                        fault   <= 1'b1;
                    end else begin
                        idle     <= idle - 1'b1;
                        idle_out <= (idle == {{(TW-1){1'b0}}, 1'b1});
                    end
                end
            end
            S_BUS: begin
                if (wb_ack_i || wb_err_i) begin
                    wb_stb_o <= 1'b0;
                    bus_err  <= wb_err_i;
                    fault    <= wb_err_i;
                    dat      <= wb_dat_i;
                    state    <= S_ANSWER;
                end
            end
            S_ANSWER: begin
                tx_data  <= status;
                tx_valid <= 1'b1;
                left     <= is_write ? 3'd0 : 3'd4;
                dropped  <= 1'b0;          // reported by this status byte
                state    <= S_SEND;
            end
            default: begin                 // S_SEND
                if (tx_valid && tx_ready) begin
                    if (left == 3'd0) begin
                        tx_valid <= 1'b0;
                        state    <= S_RECV;
                    end else begin
                        // a refused access answers zeros, not stale data
                        tx_data <= (bus_err || frame_err) ? 8'd0 : dat[7:0];
                        left    <= left - 1'b1;
                    end
                end
            end
            endcase
            // the parser is not listening while it answers
            if (state != S_RECV && (rx_valid || rx_ferr)) begin
                dropped <= 1'b1;
                fault   <= 1'b1;
            end
        end
    end
endmodule
`default_nettype wire
