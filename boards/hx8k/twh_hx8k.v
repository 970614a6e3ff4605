// iCE40-HX8K breakout board (HX8K-CT256, 12 MHz) reference top: the 2-wire
// host core behind a UART bridge on the board's FTDI serial port
// (docs/boards.md). Pins: constraints/hx8k.pcf.
//
// The channel pins are those of boards/icebreaker/twh_icebreaker.v:
// twl_drv[k] (line_o, released with the line), twl_oe_n[k] (the external
// buffer's active-low enable), twl_sense[k] (the comparator's output). The
// tri-state buffer is inferred here and nowhere else. The board has no
// user button: reset comes from configuration (and the CRESET button,
// which reconfigures the FPGA).
`default_nettype none
module twh_hx8k #(
    parameter integer CHANNELS    = 3,       // 1..3
    parameter integer BAUD        = 115_200,
    // features of the core (twh_core; 1, the default, is the full set)
    parameter integer PROG_TIMING = 1,       // 0: timing fixed at the spec defaults
    parameter integer POLLING     = 1        // 0: no autonomous poller
) (
    input  wire       clk_12m,
    input  wire       uart_rx,               // from the FTDI (its TXD)
    output wire       uart_tx,               // to the FTDI (its RXD)
    output wire [7:0] led,                   // D2..D9, active high
    output wire [2:0] twl_drv,
    output wire [2:0] twl_oe_n,
    input  wire [2:0] twl_sense
);
    localparam integer CLK_HZ = 12_000_000;

    generate
        if (CHANNELS < 1 || CHANNELS > 3) begin : g_bad_channels
            twh_error_board_CHANNELS_must_be_1_to_3 u_err ();
        end
    endgenerate

    wire [CHANNELS-1:0] line_o, line_oe, line_i, led_line;
    wire led_uart, led_fault, led_irq, led_ready;

    twh_uart_host #(.CLK_HZ(CLK_HZ), .BAUD(BAUD), .CHANNELS(CHANNELS),
                    .PROG_TIMING(PROG_TIMING), .POLLING(POLLING)) u_host (
        .clk(clk_12m), .btn_rst(1'b0), .uart_rx(uart_rx), .uart_tx(uart_tx),
        .line_o(line_o), .line_oe(line_oe), .line_i(line_i),
        .led_line(led_line), .led_uart(led_uart), .led_fault(led_fault),
        .led_irq(led_irq), .led_ready(led_ready)
    );

    genvar k;
    generate
        for (k = 0; k < 3; k = k + 1) begin : g_pin
            if (k < CHANNELS) begin : g_used
                // a generic three-state gate: synthesis puts it into the pad
                bufif1 u_pad (twl_drv[k], line_o[k], line_oe[k]);
                assign twl_oe_n[k] = !line_oe[k];
                assign line_i[k]   = twl_sense[k];
                assign led[k]      = led_line[k];
            end else begin : g_absent
                bufif1 u_pad (twl_drv[k], 1'b0, 1'b0);
                assign twl_oe_n[k] = 1'b1;
                assign led[k]      = 1'b0;
            end
        end
    endgenerate
    wire sense_unused = &{1'b0, twl_sense};

    assign led[3] = led_uart;
    assign led[4] = led_irq;
    assign led[5] = led_fault;
    assign led[6] = 1'b0;
    assign led[7] = led_ready;
endmodule
`default_nettype wire
