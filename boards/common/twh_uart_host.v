// Everything of a reference board top except its pads: the UART bridge
// mastering twh_wb, a reset from power-up and a button, and LED drivers.
// The board tops in boards/ add the pins, the 2-wire pads (the tri-state
// buffer is built there, never in here) and the LED polarity.
//
// Reset: held for 16 clocks after configuration (the flip-flops power up
// at zero) and for as long as the button is pressed; the button is an
// asynchronous pin and passes twh_sync2.
//
// LEDs (active high here): led_line[k] - channel k drives its line (each
// transaction is 18-21 ms; stretched so that a single one is seen),
// led_uart - the bridge carried out a request, led_fault - the bridge
// dropped or refused something (garbage, bad check byte, bus error),
// led_irq - the core's interrupt line, led_ready - out of reset. Stretched
// events stay lit for one to two periods of 2^STRETCH_W clocks (~45-90 ms
// at 12 MHz, ~40-80 ms at 25 MHz).
`default_nettype none
module twh_uart_host #(
    parameter integer CLK_HZ       = 12_000_000,
    parameter integer BAUD         = 115_200,
    parameter integer CHANNELS     = 3,
    parameter integer FIFO_DEPTH   = 16,
    parameter integer TIMEOUT_BITS = 1024,
    parameter integer PROG_TIMING  = 1,     // twh_core's features (1: the full set)
    parameter integer POLLING      = 1
) (
    input  wire                clk,
    input  wire                btn_rst,     // asynchronous, active high
    input  wire                uart_rx,
    output wire                uart_tx,
    output wire [CHANNELS-1:0] line_o,
    output wire [CHANNELS-1:0] line_oe,
    input  wire [CHANNELS-1:0] line_i,
    output wire [CHANNELS-1:0] led_line,
    output wire                led_uart,
    output wire                led_fault,
    output wire                led_irq,
    output wire                led_ready
);
    localparam integer STRETCH_W = $clog2(CLK_HZ / 24);

    // ------------------------------------------------------------ reset
    reg  [4:0] por = 5'd0;
    wire       btn_s;
    twh_sync2 u_btn (.clk(clk), .rst(1'b0), .d(btn_rst), .q(btn_s));
    always @(posedge clk) begin
        if (btn_s)
            por <= 5'd0;
        else if (!por[4])
            por <= por + 1'b1;
    end
    wire rst = !por[4];

    // ------------------------------------------------------------ bridge + core
    wire [9:0]  wb_adr;
    wire [31:0] wb_dat_w, wb_dat_r;
    wire        wb_we, wb_stb, wb_cyc, wb_ack, wb_err;
    wire [3:0]  wb_sel;
    wire        irq, activity, fault;

    twh_uart_bridge #(.CLK_HZ(CLK_HZ), .BAUD(BAUD), .TIMEOUT_BITS(TIMEOUT_BITS)) u_bridge (
        .clk(clk), .rst(rst), .uart_rx(uart_rx), .uart_tx(uart_tx),
        .wb_adr_o(wb_adr), .wb_dat_o(wb_dat_w), .wb_dat_i(wb_dat_r),
        .wb_we_o(wb_we), .wb_sel_o(wb_sel), .wb_stb_o(wb_stb), .wb_cyc_o(wb_cyc),
        .wb_ack_i(wb_ack), .wb_err_i(wb_err), .irq(irq),
        .activity(activity), .fault(fault)
    );

    twh_wb #(.CLK_HZ(CLK_HZ), .CHANNELS(CHANNELS), .FIFO_DEPTH(FIFO_DEPTH),
             .PROG_TIMING(PROG_TIMING), .POLLING(POLLING)) u_twh (
        .clk(clk), .rst(rst),
        .wb_adr_i({1'b0, wb_adr}), .wb_dat_i(wb_dat_w), .wb_dat_o(wb_dat_r),
        .wb_we_i(wb_we), .wb_sel_i(wb_sel), .wb_stb_i(wb_stb), .wb_cyc_i(wb_cyc),
        .wb_ack_o(wb_ack), .wb_err_o(wb_err),
        .irq(irq), .line_o(line_o), .line_oe(line_oe), .line_i(line_i)
    );

    // ------------------------------------------------------------ LEDs
    // One shared period counter; each stretched LED keeps two bits: an event
    // seen in this period, and whether the last period had one.
    localparam integer NS = CHANNELS + 2;
    reg  [STRETCH_W-1:0] period;
    reg  [NS-1:0]        seen, shown;
    wire [NS-1:0]        event_now = {fault, activity, line_oe};
    wire                 wrap = &period;
    always @(posedge clk) begin
        if (rst) begin
            period <= {STRETCH_W{1'b0}};
            seen   <= {NS{1'b0}};
            shown  <= {NS{1'b0}};
        end else begin
            period <= period + 1'b1;
            if (wrap) begin
                shown <= seen | event_now;
                seen  <= {NS{1'b0}};
            end else begin
                seen <= seen | event_now;
            end
        end
    end
    wire [NS-1:0] lit = shown | seen | event_now;
    assign led_line  = lit[CHANNELS-1:0];
    assign led_uart  = lit[CHANNELS];
    assign led_fault = lit[CHANNELS+1];
    assign led_irq   = irq;
    assign led_ready = !rst;
endmodule
`default_nettype wire
