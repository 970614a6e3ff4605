// Test-bench top for the bus-attached core with many channels (register map
// version 2: up to 32): twh_wb with CHANNELS lines, each resolved by its own
// tb_line inside a tb_engine_ch (tb/tb_engine.v), whose regs the peripheral
// models drive (tb/coretb.py finds them as g_ch[n].u_ch). tb_core.v keeps
// its flat per-channel scalars for up to eight channels (the waveform views
// and `make demo` read them); this top is for the 16- and 32-cell cases.
`timescale 1ns/1ps
`default_nettype none
module tb_core_many #(
    parameter integer CLK_HZ     = 32_000_000,
    parameter integer CHANNELS   = 32,
    parameter integer FIFO_DEPTH = 16,
    parameter integer PROG_TIMING = 1,
    parameter integer POLLING    = 1,
    parameter integer BUS        = 0         // Wishbone only (CoreTB reads it)
) (
    input  wire        rst,
    input  wire [10:0] wb_adr_i,
    input  wire [31:0] wb_dat_i,
    output wire [31:0] wb_dat_o,
    input  wire        wb_we_i,
    input  wire [3:0]  wb_sel_i,
    input  wire        wb_stb_i,
    input  wire        wb_cyc_i,
    output wire        wb_ack_o,
    output wire        wb_err_o,
    output wire        irq
);
    reg clk = 1'b0;
    localparam real HALF_NS = 1.0e9 / (2.0 * CLK_HZ);
    always #(HALF_NS) clk = ~clk;

    wire [CHANNELS-1:0] lo, loe, li;
    twh_wb #(.CLK_HZ(CLK_HZ), .CHANNELS(CHANNELS), .FIFO_DEPTH(FIFO_DEPTH),
             .PROG_TIMING(PROG_TIMING), .POLLING(POLLING)) dut (
        .clk(clk), .rst(rst),
        .wb_adr_i(wb_adr_i), .wb_dat_i(wb_dat_i), .wb_dat_o(wb_dat_o),
        .wb_we_i(wb_we_i), .wb_sel_i(wb_sel_i), .wb_stb_i(wb_stb_i),
        .wb_cyc_i(wb_cyc_i), .wb_ack_o(wb_ack_o), .wb_err_o(wb_err_o),
        .irq(irq), .line_o(lo), .line_oe(loe), .line_i(li)
    );
    genvar n;
    generate
        for (n = 0; n < CHANNELS; n = n + 1) begin : g_ch
            tb_engine_ch #(.N(n)) u_ch (.host_o(lo[n]), .host_oe(loe[n]), .line(li[n]));
        end
    endgenerate
endmodule
`default_nettype wire
