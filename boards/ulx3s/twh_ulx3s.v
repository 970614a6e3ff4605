// ULX3S (ECP5 LFE5U-85F, CABGA381, 25 MHz) reference top: the 2-wire host
// core behind a UART bridge on the board's USB serial port (the FT231X on
// US1, docs/boards.md). Pins: constraints/ulx3s.lpf.
//
// The channel pins are those of boards/icebreaker/twh_icebreaker.v:
// twl_drv[k] (line_o, released with the line), twl_oe_n[k] (the external
// buffer's active-low enable), twl_sense[k] (the comparator's output). The
// tri-state buffer is inferred here and nowhere else. Reset: configuration
// and the FIRE1 button (the power button is left alone: holding it can
// switch the board off).
`default_nettype none
module twh_ulx3s #(
    parameter integer CHANNELS    = 3,       // 1..3
    parameter integer BAUD        = 115_200,
    // features of the core (twh_core; 1, the default, is the full set)
    parameter integer PROG_TIMING = 1,       // 0: timing fixed at the spec defaults
    parameter integer POLLING     = 1        // 0: no autonomous poller
) (
    input  wire       clk_25mhz,
    input  wire       btn_fire1,             // high when pressed
    input  wire       ftdi_txd,              // the FT231X transmits, we receive
    output wire       ftdi_rxd,              // we transmit
    output wire [7:0] led,                   // active high
    output wire       wifi_gpio0,
    output wire [2:0] twl_drv,
    output wire [2:0] twl_oe_n,
    input  wire [2:0] twl_sense
);
    localparam integer CLK_HZ = 25_000_000;

    generate
        if (CHANNELS < 1 || CHANNELS > 3) begin : g_bad_channels
            twh_error_board_CHANNELS_must_be_1_to_3 u_err ();
        end
    endgenerate

    // GPIO0 is the ESP32's boot strap; held high, as in the ULX3S reference
    // designs, so the ESP32 boots normally and does not restart the board.
    assign wifi_gpio0 = 1'b1;

    wire [CHANNELS-1:0] line_o, line_oe, line_i, led_line;
    wire led_uart, led_fault, led_irq, led_ready;

    twh_uart_host #(.CLK_HZ(CLK_HZ), .BAUD(BAUD), .CHANNELS(CHANNELS),
                    .PROG_TIMING(PROG_TIMING), .POLLING(POLLING)) u_host (
        .clk(clk_25mhz), .btn_rst(btn_fire1), .uart_rx(ftdi_txd), .uart_tx(ftdi_rxd),
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
