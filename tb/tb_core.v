// Test-bench top for the bus-attached core: twh_wb or twh_axil (BUS = 0 / 1)
// with up to three channels, each on its own simulated 2-wire line.
//
// The clock is generated here (a Python-driven clock costs ~20x). Each
// channel's line is resolved by tb_line, as in tb_link.v. The per-channel
// signals are flat scalars (line_0, periph_o_0, ...) so the peripheral model
// and the spec monitor can be pointed at one channel each (tb/coretb.py).
`timescale 1ns/1ps
`default_nettype none
module tb_core #(
    parameter integer CLK_HZ     = 12_000_000,
    parameter integer CHANNELS   = 3,        // 1..3 here
    parameter integer FIFO_DEPTH = 16,
    parameter integer BUS        = 0         // 0 Wishbone, 1 AXI4-Lite
) (
    input  wire        rst,
    // Wishbone B4 classic
    input  wire [8:0]  wb_adr_i,
    input  wire [31:0] wb_dat_i,
    output wire [31:0] wb_dat_o,
    input  wire        wb_we_i,
    input  wire [3:0]  wb_sel_i,
    input  wire        wb_stb_i,
    input  wire        wb_cyc_i,
    output wire        wb_ack_o,
    output wire        wb_err_o,
    // AXI4-Lite
    input  wire [8:0]  s_axil_awaddr,
    input  wire [2:0]  s_axil_awprot,
    input  wire        s_axil_awvalid,
    output wire        s_axil_awready,
    input  wire [31:0] s_axil_wdata,
    input  wire [3:0]  s_axil_wstrb,
    input  wire        s_axil_wvalid,
    output wire        s_axil_wready,
    output wire [1:0]  s_axil_bresp,
    output wire        s_axil_bvalid,
    input  wire        s_axil_bready,
    input  wire [8:0]  s_axil_araddr,
    input  wire [2:0]  s_axil_arprot,
    input  wire        s_axil_arvalid,
    output wire        s_axil_arready,
    output wire [31:0] s_axil_rdata,
    output wire [1:0]  s_axil_rresp,
    output wire        s_axil_rvalid,
    input  wire        s_axil_rready,
    output wire        irq,
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
    reg clk = 1'b0;
    localparam real HALF_NS = 1.0e9 / (2.0 * CLK_HZ);
    always #(HALF_NS) clk = ~clk;

    wire [CHANNELS-1:0] lo, loe, li;
    wire [2:0] lo3  = {{(3-CHANNELS){1'b0}}, lo};
    wire [2:0] loe3 = {{(3-CHANNELS){1'b0}}, loe};
    assign {line_o_2, line_o_1, line_o_0}    = lo3;
    assign {line_oe_2, line_oe_1, line_oe_0} = loe3;
    tb_line u_line0 (
        .host_o(line_o_0), .host_oe(line_oe_0), .periph_o(periph_o_0), .periph_oe(periph_oe_0),
        .stuck_en(stuck_en_0), .stuck_val(stuck_val_0), .glitch(glitch_0), .line(line_0)
    );
    tb_line u_line1 (
        .host_o(line_o_1), .host_oe(line_oe_1), .periph_o(periph_o_1), .periph_oe(periph_oe_1),
        .stuck_en(stuck_en_1), .stuck_val(stuck_val_1), .glitch(glitch_1), .line(line_1)
    );
    tb_line u_line2 (
        .host_o(line_o_2), .host_oe(line_oe_2), .periph_o(periph_o_2), .periph_oe(periph_oe_2),
        .stuck_en(stuck_en_2), .stuck_val(stuck_val_2), .glitch(glitch_2), .line(line_2)
    );
    wire [2:0] li3 = {line_2, line_1, line_0};
    assign li = li3[CHANNELS-1:0];

    // `make demo` asks for a small VCD of the pins with +vcd=<file>.
    reg [1023:0] vcd_file;
    initial begin
        if ($value$plusargs("vcd=%s", vcd_file)) begin
            $dumpfile(vcd_file);
            $dumpvars(0, line_o_0, line_oe_0, line_0, line_o_1, line_oe_1, line_1,
                      line_o_2, line_oe_2, line_2, irq);
        end
    end

    generate
        if (BUS == 0) begin : g_wb
            twh_wb #(.CLK_HZ(CLK_HZ), .CHANNELS(CHANNELS), .FIFO_DEPTH(FIFO_DEPTH)) dut (
                .clk(clk), .rst(rst),
                .wb_adr_i(wb_adr_i), .wb_dat_i(wb_dat_i), .wb_dat_o(wb_dat_o),
                .wb_we_i(wb_we_i), .wb_sel_i(wb_sel_i), .wb_stb_i(wb_stb_i),
                .wb_cyc_i(wb_cyc_i), .wb_ack_o(wb_ack_o), .wb_err_o(wb_err_o),
                .irq(irq), .line_o(lo), .line_oe(loe), .line_i(li)
            );
            assign s_axil_awready = 1'b0; assign s_axil_wready = 1'b0;
            assign s_axil_bresp = 2'b00; assign s_axil_bvalid = 1'b0;
            assign s_axil_arready = 1'b0; assign s_axil_rdata = 32'd0;
            assign s_axil_rresp = 2'b00; assign s_axil_rvalid = 1'b0;
        end else begin : g_axil
            twh_axil #(.CLK_HZ(CLK_HZ), .CHANNELS(CHANNELS), .FIFO_DEPTH(FIFO_DEPTH)) dut (
                .clk(clk), .rst(rst),
                .s_axil_awaddr(s_axil_awaddr), .s_axil_awprot(s_axil_awprot),
                .s_axil_awvalid(s_axil_awvalid), .s_axil_awready(s_axil_awready),
                .s_axil_wdata(s_axil_wdata), .s_axil_wstrb(s_axil_wstrb),
                .s_axil_wvalid(s_axil_wvalid), .s_axil_wready(s_axil_wready),
                .s_axil_bresp(s_axil_bresp), .s_axil_bvalid(s_axil_bvalid),
                .s_axil_bready(s_axil_bready),
                .s_axil_araddr(s_axil_araddr), .s_axil_arprot(s_axil_arprot),
                .s_axil_arvalid(s_axil_arvalid), .s_axil_arready(s_axil_arready),
                .s_axil_rdata(s_axil_rdata), .s_axil_rresp(s_axil_rresp),
                .s_axil_rvalid(s_axil_rvalid), .s_axil_rready(s_axil_rready),
                .irq(irq), .line_o(lo), .line_oe(loe), .line_i(li)
            );
            assign wb_dat_o = 32'd0; assign wb_ack_o = 1'b0; assign wb_err_o = 1'b0;
        end
    endgenerate
endmodule
`default_nettype wire
