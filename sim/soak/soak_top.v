// Soak top for Verilator: twh_wb with CHANNELS lines, each resolved by
// tb_line (the same line the cocotb benches use) against the C++
// peripheral model's drive. The clock comes from the C++ harness, which
// steps it. The soak injects its faults in the peripheral's answers; the
// rig (make rig, docs/rig.md) also holds a line stuck (stuck_en, stuck_val:
// tb_line's fault, a bit a channel; the soak and the demo leave them 0). No
// glitches here.
`default_nettype none
module soak_top #(
    parameter integer CLK_HZ     = 4_000_000,
    parameter integer CHANNELS   = 3,
    parameter integer FIFO_DEPTH = 16
) (
    input  wire                clk,
    input  wire                rst,
    input  wire [10:0]         wb_adr_i,
    input  wire [31:0]         wb_dat_i,
    output wire [31:0]         wb_dat_o,
    input  wire                wb_we_i,
    input  wire [3:0]          wb_sel_i,
    input  wire                wb_stb_i,
    input  wire                wb_cyc_i,
    output wire                wb_ack_o,
    output wire                wb_err_o,
    output wire                irq,
    // the host's drive and the resolved line, per channel
    output wire [CHANNELS-1:0] line_o,
    output wire [CHANNELS-1:0] line_oe,
    output wire [CHANNELS-1:0] line,
    // the peripheral models' drive
    input  wire [CHANNELS-1:0] periph_o,
    input  wire [CHANNELS-1:0] periph_oe,
    // a stuck line: bit ch set holds line ch at stuck_val[ch]
    input  wire [CHANNELS-1:0] stuck_en,
    input  wire [CHANNELS-1:0] stuck_val
);
    twh_wb #(.CLK_HZ(CLK_HZ), .CHANNELS(CHANNELS), .FIFO_DEPTH(FIFO_DEPTH)) dut (
        .clk(clk), .rst(rst),
        .wb_adr_i(wb_adr_i), .wb_dat_i(wb_dat_i), .wb_dat_o(wb_dat_o),
        .wb_we_i(wb_we_i), .wb_sel_i(wb_sel_i), .wb_stb_i(wb_stb_i),
        .wb_cyc_i(wb_cyc_i), .wb_ack_o(wb_ack_o), .wb_err_o(wb_err_o),
        .irq(irq), .line_o(line_o), .line_oe(line_oe), .line_i(line)
    );

    genvar ch;
    generate
        for (ch = 0; ch < CHANNELS; ch = ch + 1) begin : g_line
            tb_line u_line (
                .host_o(line_o[ch]), .host_oe(line_oe[ch]),
                .periph_o(periph_o[ch]), .periph_oe(periph_oe[ch]),
                .stuck_en(stuck_en[ch]), .stuck_val(stuck_val[ch]), .glitch(1'b0),
                .line(line[ch])
            );
        end
    endgenerate
endmodule
`default_nettype wire
