// Test-bench top for the iCEBreaker board top (boards/icebreaker), as the
// board sees its world: the 12 MHz oscillator, the FTDI's UART lines, the
// user button, the LEDs, and per channel the reference front end
// (docs/integration.md) in front of a simulated 2-wire line (tb_line).
//
// Front end per channel k: the three-state buffer drives the line with
// twl_drv[k] while twl_oe_n[k] is low; the comparator gives the line's level
// back on twl_sense[k]. The per-channel flat signals (line_o_k, line_oe_k,
// line_k, periph_*_k, ...) are those of tb_core.v, so the peripheral model
// and the spec monitor attach the same way (tb/boardtb.py).
//
// pad_errors counts, at every falling clock edge, each channel whose drive
// pad disagrees with its buffer enable: driven while the buffer is off, or
// released (Z) while it is on. The top builds that pad; nothing else does.
`timescale 1ns/1ps
`default_nettype none
module tb_board #(
    parameter integer CHANNELS = 3,
    parameter integer BAUD     = 115_200
) (
    input  wire        uart_rx,        // PC -> board (the FTDI's TXD)
    output wire        uart_tx,        // board -> PC
    input  wire        btn_n,
    output wire        led_red_n,
    output wire        led_green_n,
    output wire [4:0]  led_brk,
    output reg  [15:0] pad_errors,
    // channel 0
    output wire line_o_0, output wire line_oe_0, output wire line_0,
    input  wire periph_o_0, input wire periph_oe_0,
    input  wire stuck_en_0, input wire stuck_val_0, input wire glitch_0,
    // channel 1
    output wire line_o_1, output wire line_oe_1, output wire line_1,
    input  wire periph_o_1, input wire periph_oe_1,
    input  wire stuck_en_1, input wire stuck_val_1, input wire glitch_1,
    // channel 2
    output wire line_o_2, output wire line_oe_2, output wire line_2,
    input  wire periph_o_2, input wire periph_oe_2,
    input  wire stuck_en_2, input wire stuck_val_2, input wire glitch_2
);
    localparam real HALF_NS = 1.0e9 / (2.0 * 12_000_000);
    reg clk = 1'b0;
    always #(HALF_NS) clk = ~clk;

    wire [2:0] drv, oe_n;
    wire [2:0] sense = {line_2, line_1, line_0};

    twh_icebreaker #(.CHANNELS(CHANNELS), .BAUD(BAUD)) dut (
        .clk_12m(clk), .btn_n(btn_n), .uart_rx(uart_rx), .uart_tx(uart_tx),
        .led_red_n(led_red_n), .led_green_n(led_green_n), .led_brk(led_brk),
        .twl_drv(drv), .twl_oe_n(oe_n), .twl_sense(sense)
    );

    // the buffer's input: a released pad reads as 0 (it is not enabled then)
    assign line_o_0 = (drv[0] === 1'b1);
    assign line_o_1 = (drv[1] === 1'b1);
    assign line_o_2 = (drv[2] === 1'b1);
    assign line_oe_0 = !oe_n[0];
    assign line_oe_1 = !oe_n[1];
    assign line_oe_2 = !oe_n[2];

    tb_line #(.PIN_LOG("pins_0.log"), .LINE_LOG("line_0.log")) u_line0 (
        .host_o(line_o_0), .host_oe(line_oe_0), .periph_o(periph_o_0), .periph_oe(periph_oe_0),
        .stuck_en(stuck_en_0), .stuck_val(stuck_val_0), .glitch(glitch_0), .line(line_0)
    );
    tb_line #(.PIN_LOG("pins_1.log"), .LINE_LOG("line_1.log")) u_line1 (
        .host_o(line_o_1), .host_oe(line_oe_1), .periph_o(periph_o_1), .periph_oe(periph_oe_1),
        .stuck_en(stuck_en_1), .stuck_val(stuck_val_1), .glitch(glitch_1), .line(line_1)
    );
    tb_line #(.PIN_LOG("pins_2.log"), .LINE_LOG("line_2.log")) u_line2 (
        .host_o(line_o_2), .host_oe(line_oe_2), .periph_o(periph_o_2), .periph_oe(periph_oe_2),
        .stuck_en(stuck_en_2), .stuck_val(stuck_val_2), .glitch(glitch_2), .line(line_2)
    );

    // +vcd=<file>: a VCD of the board's pins and the bridge (debugging)
    reg [1023:0] vcd_file;
    initial begin
        if ($value$plusargs("vcd=%s", vcd_file)) begin
            $dumpfile(vcd_file);
            $dumpvars(0, uart_rx, uart_tx, btn_n, led_brk, drv, oe_n, sense, dut.u_host.u_bridge);
        end
    end

    integer k;
    initial pad_errors = 16'd0;
    always @(negedge clk) begin
        for (k = 0; k < 3; k = k + 1) begin
            if (oe_n[k] === 1'b1 ? (drv[k] !== 1'bz)
                                 : (oe_n[k] !== 1'b0 || (drv[k] !== 1'b0 && drv[k] !== 1'b1)))
                pad_errors = pad_errors + 16'd1;
        end
    end
endmodule
`default_nettype wire
