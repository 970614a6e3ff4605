// Test-bench top for the bus-attached core: twh_wb or twh_axil (BUS = 0 / 1)
// with up to eight channels, each on its own simulated 2-wire line.
//
// The clock is generated here (a Python-driven clock costs ~20x). Each
// channel's line is resolved by tb_line, as in tb_link.v. The per-channel
// signals are flat scalars (line_0, periph_o_0, ...) so the peripheral model
// and the spec monitor can be pointed at one channel each (tb/coretb.py).
`timescale 1ns/1ps
`default_nettype none
module tb_core #(
    parameter integer CLK_HZ     = 12_000_000,
    parameter integer CHANNELS   = 3,        // 1..8
    parameter integer FIFO_DEPTH = 16,
    parameter integer PROG_TIMING = 1,       // the core's feature parameters
    parameter integer POLLING    = 1,
    parameter integer BUS        = 0         // 0 Wishbone, 1 AXI4-Lite
) (
    input  wire        rst,
    // Wishbone B4 classic
    input  wire [10:0] wb_adr_i,
    input  wire [31:0] wb_dat_i,
    output wire [31:0] wb_dat_o,
    input  wire        wb_we_i,
    input  wire [3:0]  wb_sel_i,
    input  wire        wb_stb_i,
    input  wire        wb_cyc_i,
    output wire        wb_ack_o,
    output wire        wb_err_o,
    // AXI4-Lite
    input  wire [10:0] s_axil_awaddr,
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
    input  wire [10:0] s_axil_araddr,
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
    input  wire stuck_en_2, input wire stuck_val_2, input wire glitch_2,
    // channel 3
    output wire line_o_3, output wire line_oe_3, output wire line_3,
    input  wire periph_o_3, input wire periph_oe_3,
    input  wire stuck_en_3, input wire stuck_val_3, input wire glitch_3,
    // channel 4
    output wire line_o_4, output wire line_oe_4, output wire line_4,
    input  wire periph_o_4, input wire periph_oe_4,
    input  wire stuck_en_4, input wire stuck_val_4, input wire glitch_4,
    // channel 5
    output wire line_o_5, output wire line_oe_5, output wire line_5,
    input  wire periph_o_5, input wire periph_oe_5,
    input  wire stuck_en_5, input wire stuck_val_5, input wire glitch_5,
    // channel 6
    output wire line_o_6, output wire line_oe_6, output wire line_6,
    input  wire periph_o_6, input wire periph_oe_6,
    input  wire stuck_en_6, input wire stuck_val_6, input wire glitch_6,
    // channel 7
    output wire line_o_7, output wire line_oe_7, output wire line_7,
    input  wire periph_o_7, input wire periph_oe_7,
    input  wire stuck_en_7, input wire stuck_val_7, input wire glitch_7
);
    reg clk = 1'b0;
    localparam real HALF_NS = 1.0e9 / (2.0 * CLK_HZ);
    always #(HALF_NS) clk = ~clk;

    wire [CHANNELS-1:0] lo, loe, li;
    wire [7:0] lo8  = {{(8-CHANNELS){1'b0}}, lo};
    wire [7:0] loe8 = {{(8-CHANNELS){1'b0}}, loe};
    assign {line_o_7, line_o_6, line_o_5, line_o_4,
            line_o_3, line_o_2, line_o_1, line_o_0}    = lo8;
    assign {line_oe_7, line_oe_6, line_oe_5, line_oe_4,
            line_oe_3, line_oe_2, line_oe_1, line_oe_0} = loe8;
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
    tb_line #(.PIN_LOG("pins_3.log"), .LINE_LOG("line_3.log")) u_line3 (
        .host_o(line_o_3), .host_oe(line_oe_3), .periph_o(periph_o_3), .periph_oe(periph_oe_3),
        .stuck_en(stuck_en_3), .stuck_val(stuck_val_3), .glitch(glitch_3), .line(line_3)
    );
    tb_line #(.PIN_LOG("pins_4.log"), .LINE_LOG("line_4.log")) u_line4 (
        .host_o(line_o_4), .host_oe(line_oe_4), .periph_o(periph_o_4), .periph_oe(periph_oe_4),
        .stuck_en(stuck_en_4), .stuck_val(stuck_val_4), .glitch(glitch_4), .line(line_4)
    );
    tb_line #(.PIN_LOG("pins_5.log"), .LINE_LOG("line_5.log")) u_line5 (
        .host_o(line_o_5), .host_oe(line_oe_5), .periph_o(periph_o_5), .periph_oe(periph_oe_5),
        .stuck_en(stuck_en_5), .stuck_val(stuck_val_5), .glitch(glitch_5), .line(line_5)
    );
    tb_line #(.PIN_LOG("pins_6.log"), .LINE_LOG("line_6.log")) u_line6 (
        .host_o(line_o_6), .host_oe(line_oe_6), .periph_o(periph_o_6), .periph_oe(periph_oe_6),
        .stuck_en(stuck_en_6), .stuck_val(stuck_val_6), .glitch(glitch_6), .line(line_6)
    );
    tb_line #(.PIN_LOG("pins_7.log"), .LINE_LOG("line_7.log")) u_line7 (
        .host_o(line_o_7), .host_oe(line_oe_7), .periph_o(periph_o_7), .periph_oe(periph_oe_7),
        .stuck_en(stuck_en_7), .stuck_val(stuck_val_7), .glitch(glitch_7), .line(line_7)
    );
    wire [7:0] li8 = {line_7, line_6, line_5, line_4, line_3, line_2, line_1, line_0};
    assign li = li8[CHANNELS-1:0];

    // Views for the waveform (tb/demo.gtkw, docs/waves.md) and for tests:
    // each channel's phase and the FIFO levels, read out of the core by
    // hierarchical name (assigned in g_wb / g_axil below), and a byte
    // monitor per line that shows what travelled on it.
    // each channel's phase: the engine's `phase` (the core hands it to
    // twh_timing as c_nx_fld)
    wire [8*3-1:0] ch_phase;
    wire [CHANNELS*3-1:0] ch_ph;
    wire [15:0] cmd_level, res_level;
    wire [2:0]  phase_0 = ch_phase[2:0];
    wire [2:0]  phase_1 = ch_phase[5:3];
    wire [2:0]  phase_2 = ch_phase[8:6];
    genvar pn;
    generate
        if (CHANNELS < 8) begin : g_phase_pad
            assign ch_phase[8*3-1:CHANNELS*3] = {(8-CHANNELS)*3{1'b0}};
        end
        for (pn = 0; pn < CHANNELS; pn = pn + 1) begin : g_phase
            assign ch_phase[pn*3 +: 3] = ch_ph[pn*3 +: 3];
        end
    endgenerate

    wire [7:0]  mon_byte_0, mon_byte_1, mon_byte_2;
    wire [15:0] mon_count_0, mon_count_1, mon_count_2;
    wire [23:0] mon_word_0, mon_word_1, mon_word_2;
    tb_bytemon u_mon0 (.line(line_0), .host_oe(line_oe_0),
                       .data(mon_byte_0), .count(mon_count_0), .word(mon_word_0));
    tb_bytemon u_mon1 (.line(line_1), .host_oe(line_oe_1),
                       .data(mon_byte_1), .count(mon_count_1), .word(mon_word_1));
    tb_bytemon u_mon2 (.line(line_2), .host_oe(line_oe_2),
                       .data(mon_byte_2), .count(mon_count_2), .word(mon_word_2));

    // `make demo` asks for a small VCD of the pins with +vcd=<file>.
    reg [1023:0] vcd_file;
    initial begin
        if ($value$plusargs("vcd=%s", vcd_file)) begin
            $dumpfile(vcd_file);
            $dumpvars(0, line_o_0, line_oe_0, line_0, line_o_1, line_oe_1, line_1,
                      line_o_2, line_oe_2, line_2, irq);
            // what tb/demo.gtkw shows besides the pins (never the clock:
            // it would multiply the file size)
            $dumpvars(0, rst, wb_cyc_i, wb_stb_i, wb_we_i, wb_adr_i, wb_dat_i,
                      wb_dat_o, wb_ack_o, wb_err_o, cmd_level, res_level,
                      phase_0, phase_1, phase_2,
                      mon_byte_0, mon_count_0, mon_word_0,
                      mon_byte_1, mon_count_1, mon_word_1,
                      mon_byte_2, mon_count_2, mon_word_2);
        end
    end

    generate
        if (BUS == 0) begin : g_wb
`ifdef TWH_NETLIST
            // the iCE40 flow's netlist of twh_wb (tb/test_netlist.py): the
            // parameters are those it was synthesized with, and its insides
            // have no names to show
            twh_wb_netlist
`else
            twh_wb #(.CLK_HZ(CLK_HZ), .CHANNELS(CHANNELS), .FIFO_DEPTH(FIFO_DEPTH),
                     .PROG_TIMING(PROG_TIMING), .POLLING(POLLING))
`endif
                dut (
                .clk(clk), .rst(rst),
                .wb_adr_i(wb_adr_i), .wb_dat_i(wb_dat_i), .wb_dat_o(wb_dat_o),
                .wb_we_i(wb_we_i), .wb_sel_i(wb_sel_i), .wb_stb_i(wb_stb_i),
                .wb_cyc_i(wb_cyc_i), .wb_ack_o(wb_ack_o), .wb_err_o(wb_err_o),
                .irq(irq), .line_o(lo), .line_oe(loe), .line_i(li)
            );
`ifdef TWH_NETLIST
            assign ch_ph = {(CHANNELS*3){1'b0}};
            assign cmd_level = 16'd0;
            assign res_level = 16'd0;
`else
            assign ch_ph = dut.u_core.c_nx_fld;
            assign cmd_level = dut.u_core.cmd_level16;
            assign res_level = dut.u_core.res_level16;
`endif
            assign s_axil_awready = 1'b0; assign s_axil_wready = 1'b0;
            assign s_axil_bresp = 2'b00; assign s_axil_bvalid = 1'b0;
            assign s_axil_arready = 1'b0; assign s_axil_rdata = 32'd0;
            assign s_axil_rresp = 2'b00; assign s_axil_rvalid = 1'b0;
        end else begin : g_axil
            twh_axil #(.CLK_HZ(CLK_HZ), .CHANNELS(CHANNELS), .FIFO_DEPTH(FIFO_DEPTH),
                     .PROG_TIMING(PROG_TIMING), .POLLING(POLLING)) dut (
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
            assign ch_ph = dut.u_core.c_nx_fld;
            assign cmd_level = dut.u_core.cmd_level16;
            assign res_level = dut.u_core.res_level16;
            assign wb_dat_o = 32'd0; assign wb_ack_o = 1'b0; assign wb_err_o = 1'b0;
        end
    endgenerate
endmodule

// Byte monitor of one simulated 2-wire line, for the waveform viewer and the
// tests only (behavioural; the core's own receiver is the engine's:
// twh_engine_pin's carrier detection, twh_rx_step / twh_rx_dec).
// It demodulates the on-off-keyed line itself and decodes 8N1/8N2 characters
// in both directions, so it shows what really travelled on the wire, not
// what the core meant to send or believes it received.
//
//   data   last completed byte
//   count  completed bytes so far: a change of count is the byte strobe
//   word   the byte with its context, for tools/gtkwave/twh_bytes.py:
//          [7:0] byte, [15:8] command byte of the frame (a response carries
//          the command it answers), [17:16] index in the frame, [18] stop
//          bit read 0, [20] valid, [21] from the peripheral, [22] last byte
//          of the frame, [23] frame checksum good (with [22])
//
// A character of eight 0 bits with a 0 stop bit is a break (the sync gap,
// the released line after an answer, the turnaround), not a byte.
module tb_bytemon (
    input  wire        line,
    input  wire        host_oe,    // the host drives: the character is a command byte
    output reg  [7:0]  data,
    output reg  [15:0] count,
    output reg  [23:0] word
);
    localparam real BIT_NS   = 32000.0;   // 31.25 kbps
    localparam real HOLD_NS  = 1500.0;    // bridges the carrier's low halves
    localparam real SPIKE_NS = 100.0;     // shorter highs are not carrier
    localparam real GAP_NS   = 1.0e6;     // a longer pause between bytes ends a frame

    // The envelope: rises with a carrier high (inertial delay: spikes are
    // swallowed), falls once the line has stayed low for HOLD_NS.
    wire env;
    assign #(SPIKE_NS, HOLD_NS) env = line;

    // Start of the mark before a start bit. It counts only from when the
    // current driver took the line: at the start of the listen window the
    // host lets go of its execute carrier, and the low released line before
    // the peripheral's own mark is no start bit.
    realtime t_mark;
    always @(posedge env) t_mark = $realtime;
    always @(host_oe) t_mark = $realtime;

    reg        resp, prev_resp, in_frame, stop_ok, last;
    reg [2:0]  idx, len;
    reg [7:0]  rxd, cmd, sum;
    realtime   t_start, t_prev_end;
    integer    i;
    initial begin
        data = 8'd0; count = 16'd0; word = 24'd0;
        in_frame = 1'b0; prev_resp = 1'b0; idx = 3'd0; len = 3'd3;
        cmd = 8'd0; sum = 8'd0; t_mark = 0.0; t_prev_end = 0.0;
    end

    always @(negedge env) begin
        if (env === 1'b0 && $realtime - t_mark >= BIT_NS / 2.0) begin
            t_start = $realtime - HOLD_NS;       // where the line fell
            #(BIT_NS / 2.0 - HOLD_NS);           // middle of the start bit
            if (env === 1'b0) begin
                resp = (host_oe !== 1'b1);
                for (i = 0; i < 8; i = i + 1) begin
                    #(BIT_NS);
                    rxd[i] = (env === 1'b1);
                end
                #(BIT_NS);
                stop_ok = (env === 1'b1);
                if (stop_ok || rxd != 8'h00) begin
                    if (!in_frame || resp != prev_resp || idx == len ||
                        t_start - t_prev_end > GAP_NS) begin
                        idx = 3'd0;
                        sum = 8'd0;
                        if (!resp) cmd = rxd;
                        len = (!resp && rxd[7]) ? 3'd4 : 3'd3;
                    end
                    sum  = sum + rxd;
                    last = (idx == len - 3'd1);
                    word = {last && sum == 8'hFF, last, resp, 1'b1,
                            1'b0, !stop_ok, idx[1:0], cmd, rxd};
                    data = rxd;
                    count = count + 16'd1;
                    idx = idx + 3'd1;
                    in_frame = 1'b1;
                    prev_resp = resp;
                    t_prev_end = $realtime;
                end
            end
        end
    end
endmodule
`default_nettype wire
