// Simulation top of the LiteX drop-in proof (docs/soc.md): the SoC LiteX
// generated (twh_soc, build/soc/sim/gateware/twh_soc.v) with each of its
// three 2-wire lines resolved by tb_line (the line the cocotb benches and
// the soak use) against the drive of soc/sim_main.cpp's peripheral models.
// The UART is LiteX's stream model: its bytes go to the harness.
`default_nettype none
module sim_top #(
    parameter integer CHANNELS = 3
) (
    input  wire                clk,
    input  wire                rst,
    // the SoC's UART (RS232PHYModel): source = bytes the CPU sends
    output wire                uart_valid,
    input  wire                uart_ready,
    output wire [7:0]          uart_data,
    // the host's drive and the resolved line, per channel
    output wire [CHANNELS-1:0] line_o,
    output wire [CHANNELS-1:0] line_oe,
    output wire [CHANNELS-1:0] line,
    // the peripheral models' drive
    input  wire [CHANNELS-1:0] periph_o,
    input  wire [CHANNELS-1:0] periph_oe
);
    wire uart_sink_ready;   // nothing is ever sent to the SoC

    twh_soc u_soc (
        .sys_clk(clk), .sys_rst(rst),
        .serial_source_valid(uart_valid), .serial_source_ready(uart_ready),
        .serial_source_data(uart_data),
        .serial_sink_valid(1'b0), .serial_sink_ready(uart_sink_ready), .serial_sink_data(8'd0),
        .twh_line_o(line_o), .twh_line_oe(line_oe), .twh_line_i(line)
    );

    wire unused = uart_sink_ready;

    genvar ch;
    generate
        for (ch = 0; ch < CHANNELS; ch = ch + 1) begin : g_line
            tb_line u_line (
                .host_o(line_o[ch]), .host_oe(line_oe[ch]),
                .periph_o(periph_o[ch]), .periph_oe(periph_oe[ch]),
                .stuck_en(1'b0), .stuck_val(1'b0), .glitch(1'b0),
                .line(line[ch])
            );
        end
    endgenerate
endmodule
`default_nettype wire
