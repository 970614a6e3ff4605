// Top of formal/twh_link.sby: twh_link with the carrier generator that
// twh_core shares among its channels (the engine takes tick and fall as
// inputs). Every other input of the engine stays free here; its properties
// are in rtl/twh_link.v.
`default_nettype none
module twh_link_top #(
    parameter integer CLK_HZ = 48_000_000,
    parameter integer TAG_W  = 8
) (
    input  wire             clk,
    input  wire             rst,
    output wire [2:0]       nx_fld,
    input  wire             dur_we,
    input  wire [15:0]      dur_in,
    input  wire [2:0]       dur_fld_in,
    input  wire             cfg_idle_charge,
    input  wire             s_cmd_valid,
    output wire             s_cmd_ready,
    input  wire [7:0]       s_cmd_code,
    input  wire [15:0]      s_cmd_payload,
    input  wire [TAG_W-1:0] s_cmd_tag,
    input  wire [3:0]       s_cmd_skip,
    output wire             m_res_valid,
    input  wire             m_res_ready,
    output wire [7:0]       m_res_code,
    output wire [15:0]      m_res_data,
    output wire [3:0]       m_res_status,
    output wire [TAG_W-1:0] m_res_tag,
    output wire             line_o,
    output wire             line_oe,
    input  wire             line_i,
    output wire [2:0]       phase,
    output wire             busy
);
    wire tick, fall;
    twh_carrier #(.CLK_HZ(CLK_HZ)) u_carrier (.clk(clk), .rst(rst), .tick(tick), .fall(fall));

    twh_link #(.CLK_HZ(CLK_HZ), .TAG_W(TAG_W)) u_link (
        .clk(clk), .rst(rst), .tick(tick), .fall(fall),
        .nx_fld(nx_fld), .dur_we(dur_we), .dur_in(dur_in), .dur_fld_in(dur_fld_in),
        .cfg_idle_charge(cfg_idle_charge),
        .s_cmd_valid(s_cmd_valid), .s_cmd_ready(s_cmd_ready),
        .s_cmd_code(s_cmd_code), .s_cmd_payload(s_cmd_payload), .s_cmd_tag(s_cmd_tag),
        .s_cmd_skip(s_cmd_skip),
        .m_res_valid(m_res_valid), .m_res_ready(m_res_ready),
        .m_res_code(m_res_code), .m_res_data(m_res_data),
        .m_res_status(m_res_status), .m_res_tag(m_res_tag),
        .line_o(line_o), .line_oe(line_oe), .line_i(line_i),
        .phase(phase), .busy(busy)
    );
endmodule
`default_nettype wire
