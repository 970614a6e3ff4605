// Test-bench top for the time-shared engine (twh_engine) with CHANNELS
// lines, each resolved by its own tb_line (logs pins_NN.log, line_NN.log)
// inside a tb_engine_ch, whose regs the peripheral models drive.
`timescale 1ns/1ps
`default_nettype none
module tb_engine_ch #(
    parameter integer N = 0
) (
    input  wire host_o,
    input  wire host_oe,
    output wire line
);
    localparam integer D1 = 48 + N / 10, D0 = 48 + N % 10;
    localparam [15:0] DIG = {D1[7:0], D0[7:0]};
    reg periph_o = 1'b0, periph_oe = 1'b0;
    reg stuck_en = 1'b0, stuck_val = 1'b0, glitch = 1'b0;
    wire line_o = host_o, line_oe = host_oe;
    tb_line #(.PIN_LOG({"pins_", DIG, ".log"}), .LINE_LOG({"line_", DIG, ".log"})) u_line (
        .host_o(host_o), .host_oe(host_oe), .periph_o(periph_o), .periph_oe(periph_oe),
        .stuck_en(stuck_en), .stuck_val(stuck_val), .glitch(glitch), .line(line)
    );
endmodule

module tb_engine #(
    parameter integer CLK_HZ   = 4_000_000,
    parameter integer CHANNELS = 3,
    parameter integer CW       = (CHANNELS > 1) ? $clog2(CHANNELS) : 1
) (
    input  wire                rst,
    input  wire [CHANNELS-1:0] cfg_idle_charge,
    input  wire                t_we,
    input  wire [CW-1:0]       t_ch,
    input  wire [2:0]          t_fld,
    input  wire [15:0]         t_len,
    input  wire                s_cmd_valid,
    output wire                s_cmd_ready,
    input  wire [CW-1:0]       s_cmd_ch,
    input  wire [7:0]          s_cmd_code,
    input  wire [15:0]         s_cmd_payload,
    input  wire [7:0]          s_cmd_tag,
    input  wire [3:0]          s_cmd_skip,
    output wire                m_res_valid,
    input  wire                m_res_ready,
    output wire [CW-1:0]       m_res_ch,
    output wire [7:0]          m_res_code,
    output wire [15:0]         m_res_data,
    output wire [3:0]          m_res_status,
    output wire [7:0]          m_res_tag,
    output wire [CHANNELS-1:0] busy,
    output wire [CHANNELS*3-1:0] phase
);
    reg clk = 1'b0;
    localparam real HALF_NS = 1.0e9 / (2.0 * CLK_HZ);
    always #(HALF_NS) clk = ~clk;

    wire tick, tick_nx, fall;
    twh_carrier #(.CLK_HZ(CLK_HZ)) u_carrier (.clk(clk), .rst(rst), .tick(tick),
                                              .tick_nx(tick_nx), .fall(fall));
    wire [CHANNELS-1:0] line_o, line_oe, line;
    twh_engine #(.CLK_HZ(CLK_HZ), .CHANNELS(CHANNELS), .TAG_W(8)) dut (
        .clk(clk), .rst(rst), .tick(tick), .fall(fall), .cfg_idle_charge(cfg_idle_charge),
        // (polls, flush and the enable are the core's: tb/test_twh_core.py)
        .enable(1'b1), .cancel(1'b0), .poll_req({CHANNELS{1'b0}}), .poll_cmd(16'd0), .scan_ch(),
        .t_we(t_we), .t_ch(t_ch), .t_fld(t_fld), .t_len(t_len),
        .s_cmd_valid(s_cmd_valid), .s_cmd_ready(s_cmd_ready), .s_cmd_ch(s_cmd_ch),
        .s_cmd_code(s_cmd_code), .s_cmd_payload(s_cmd_payload), .s_cmd_tag(s_cmd_tag),
        .s_cmd_skip(s_cmd_skip),
        .m_res_valid(m_res_valid), .m_res_ready(m_res_ready), .m_res_ch(m_res_ch),
        .m_res_code(m_res_code), .m_res_data(m_res_data), .m_res_status(m_res_status),
        .m_res_tag(m_res_tag),
        .line_o(line_o), .line_oe(line_oe), .line_i(line), .busy(busy), .phase(phase),
        .pending(), .st_ch({CW{1'b0}}), .st_pend(), .cancelling(), .fld(), .sc_v(), .sc_ch(), .sc_ph(), .sc_tr(), .p_take(), .p_res(), .p_ch(), .p_data(), .p_status(), .p_count()
    );
    genvar n;
    generate
        for (n = 0; n < CHANNELS; n = n + 1) begin : g_ch
            tb_engine_ch #(.N(n)) u_ch (.host_o(line_o[n]), .host_oe(line_oe[n]), .line(line[n]));
        end
    endgenerate
endmodule
`default_nettype wire
