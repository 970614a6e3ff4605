// iCEBreaker (iCE40UP5K-SG48, 12 MHz) reference top: the 2-wire host core
// behind a UART bridge on the board's FTDI serial port (docs/boards.md).
// Pins: constraints/icebreaker.pcf.
//
// Per channel k the reference front end of docs/integration.md gets three
// pins on one 6-pin PMOD row (with that row's GND and 3.3 V):
//   twl_drv[k]   the level to drive (line_o), released (high impedance)
//                whenever the core releases the line, so a bare resistor
//                front end works as well as the buffer;
//   twl_oe_n[k]  enable of the external three-state buffer (74LVC1G125,
//                active low): high while the core releases the line;
//   twl_sense[k] the line as seen by the front end's comparator.
// The tri-state buffer is inferred here, at the top, and nowhere else.
// Channels the build does not have (CHANNELS < 3) keep their pins released.
`default_nettype none
module twh_icebreaker #(
    parameter integer CHANNELS    = 3,       // 1..3
    parameter integer BAUD        = 115_200,
    // features of the core (twh_core; 1, the default, is the full set)
    parameter integer PROG_TIMING = 1,       // 0: timing fixed at the spec defaults
    parameter integer POLLING     = 1        // 0: no autonomous poller
) (
    input  wire       clk_12m,
    input  wire       btn_n,                 // user button, low when pressed
    input  wire       uart_rx,               // from the FTDI (its TXD)
    output wire       uart_tx,               // to the FTDI (its RXD)
    output wire       led_red_n,             // fault (stretched)
    output wire       led_green_n,           // running (out of reset)
    output wire [4:0] led_brk,               // break-off LEDs: 1-3 channel
                                             // activity, 4 UART, 5 IRQ
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
        .clk(clk_12m), .btn_rst(!btn_n), .uart_rx(uart_rx), .uart_tx(uart_tx),
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
                assign led_brk[k]  = led_line[k];
            end else begin : g_absent
                bufif1 u_pad (twl_drv[k], 1'b0, 1'b0);
                assign twl_oe_n[k] = 1'b1;
                assign led_brk[k]  = 1'b0;
            end
        end
    endgenerate
    wire sense_unused = &{1'b0, twl_sense};

    assign led_brk[3]  = led_uart;
    assign led_brk[4]  = led_irq;
    assign led_red_n   = !led_fault;
    assign led_green_n = !led_ready;
endmodule
`default_nettype wire
