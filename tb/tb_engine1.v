// The time-shared engine (twh_engine) with one channel, its poller side and
// the ports a one-channel bench does not use tied off: what tb_link.v (the
// cocotb benches) and tb_link_smoke.v (the FuseSoC smoke test) drive, with
// the pin's filtered-high flag (`pin_hi`, the window flag the receiver
// samples) brought out for test_twh_link.py's clock_conformance.
`default_nettype none
module tb_engine1 #(
    parameter integer CLK_HZ = 4_000_000,
    parameter integer TAG_W  = 8
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             tick,
    input  wire             fall,
    input  wire             cfg_idle_charge,
    input  wire             t_we,        // a phase length (twh_timing's dur_v, dur_fld, dur)
    input  wire [2:0]       t_fld,
    input  wire [15:0]      t_len,
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
    output wire             busy,
    output wire [2:0]       phase,
    output wire [2:0]       fld,         // the timing field its next phase loads
    output wire             pin_hi
);
    wire        scan_unused, res_ch_unused, p_take_unused, p_res_unused, p_ch_unused;
    wire        pending_unused, st_pend_unused, cancelling_unused, sc_v_unused, sc_ch_unused;
    wire [2:0]  sc_ph_unused;
    wire [1:0]  sc_tr_unused;
    wire [15:0] p_data_unused;
    wire [3:0]  p_status_unused;
    wire [11:0] p_count_unused;
    twh_engine #(.CLK_HZ(CLK_HZ), .CHANNELS(1), .TAG_W(TAG_W)) dut (
        .clk(clk), .rst(rst), .tick(tick), .fall(fall),
        .cfg_idle_charge(cfg_idle_charge), .enable(1'b1), .cancel(1'b0),
        .poll_req(1'b0), .poll_cmd(16'd0), .scan_ch(scan_unused),
        .t_we(t_we), .t_ch(1'b0), .t_fld(t_fld), .t_len(t_len),
        .s_cmd_valid(s_cmd_valid), .s_cmd_ready(s_cmd_ready), .s_cmd_ch(1'b0),
        .s_cmd_code(s_cmd_code), .s_cmd_payload(s_cmd_payload), .s_cmd_tag(s_cmd_tag),
        .s_cmd_skip(s_cmd_skip),
        .m_res_valid(m_res_valid), .m_res_ready(m_res_ready), .m_res_ch(res_ch_unused),
        .m_res_code(m_res_code), .m_res_data(m_res_data),
        .m_res_status(m_res_status), .m_res_tag(m_res_tag),
        .line_o(line_o), .line_oe(line_oe), .line_i(line_i),
        .busy(busy), .pending(pending_unused), .st_ch(1'b0), .st_pend(st_pend_unused),
        .cancelling(cancelling_unused), .phase(phase), .fld(fld),
        .sc_v(sc_v_unused), .sc_ch(sc_ch_unused), .sc_ph(sc_ph_unused), .sc_tr(sc_tr_unused),
        .p_take(p_take_unused), .p_res(p_res_unused), .p_ch(p_ch_unused),
        .p_data(p_data_unused), .p_status(p_status_unused), .p_count(p_count_unused)
    );
    assign pin_hi = dut.g_ch[0].g_on.u_pin.now_w;
    // verilator lint_off UNUSEDSIGNAL
    wire unused = &{1'b0, scan_unused, res_ch_unused, pending_unused, st_pend_unused,
                    cancelling_unused, p_take_unused, p_res_unused, p_ch_unused,
                    p_data_unused, p_status_unused, p_count_unused, sc_v_unused, sc_ch_unused,
                    sc_ph_unused, sc_tr_unused};
    // verilator lint_on UNUSEDSIGNAL
endmodule
`default_nettype wire
