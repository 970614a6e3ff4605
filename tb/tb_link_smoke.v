// Self-checking smoke test of the time-shared engine (twh_engine) with one
// channel, plain Verilog (Icarus), no cocotb: the FuseSoC `sim` target
// (twowire-host.core) runs it.
//
// twh_engine at 4 MHz (the slowest clock allowed), default timing, no
// peripheral on the line: the line reads what the host drives, and low (the
// front end's pull-down) while it is released. One 3-byte command (0x41,
// firmware version) is sent. Checks:
//   - the phases run 1, 2, 3, 4, 5, 6, 7 in that order, then back to idle;
//   - line_oe stays low through the listen phase (the engine's `phase`
//     leads its pin by one or two carrier periods, so the check starts
//     three microseconds into the phase) and the listen phase lasts
//     >= 2000 us;
//   - exactly one result: status NO_RESPONSE (1), data 0, code and tag echoed.
// Prints "PASS" and finishes, or "FAIL: ..." and ends with $fatal (vvp exits
// with a non-zero code, which fails the FuseSoC run).
`timescale 1ns/1ps
`default_nettype none
`include "twh_defs.vh"
module tb_link_smoke;
    localparam integer CLK_HZ   = 4_000_000;
    localparam real    HALF_NS  = 1.0e9 / (2.0 * CLK_HZ);
    // post-reset hold-off 2 ms + a whole default transaction (21.06 ms) + margin
    localparam integer TIMEOUT_CLKS = CLK_HZ / 1000 * 40;
    // the engine's phase leads its pin by at most two carrier periods
    localparam integer LEAD_CLKS = 3 * (CLK_HZ / 1_000_000);

    reg clk = 1'b0;
    always #(HALF_NS) clk = ~clk;

    reg         rst = 1'b1;
    reg         s_cmd_valid = 1'b0;
    wire        s_cmd_ready;
    wire        m_res_valid;
    wire [7:0]  m_res_code;
    wire [15:0] m_res_data;
    wire [3:0]  m_res_status;
    wire [7:0]  m_res_tag;
    wire        line_o, line_oe;
    wire [2:0]  phase;
    wire        busy;

    // no peripheral: driven by the host, else pulled low
    wire line_i = line_oe ? line_o : 1'b0;

    // the phase lengths from twh_timing, never written: the defaults (its
    // reset sweep writes them, the word on wr_data the default of the
    // register it names, as the core's data register holds it; the
    // command waits for the sweep, as the core's register port does)
    wire [2:0]  nx_fld, dur_fld;
    wire [15:0] dur;
    wire        dur_we, dur_v;
    wire [4:0]  dur_ch;
    wire [31:0] t_rd_unused;
    wire        t_ready, s_ready_e;
    assign      s_cmd_ready = s_ready_e && t_ready;
    wire [1:0]  t_sw_reg;
    wire [31:0] t_sw_word = (t_sw_reg == 2'd0) ? `TWH_TIMING0_DEF :
                            (t_sw_reg == 2'd1) ? `TWH_TIMING1_DEF : `TWH_TIMING2_DEF;
    twh_timing #(.CHANNELS(1)) u_timing (
        .clk(clk), .rst(rst), .ready(t_ready), .sw_we(), .sw_reg(t_sw_reg),
        .lab(1'b0),
        .wr(1'b0), .wr_ch(5'd0), .wr_reg(2'd0), .wr_data(t_sw_word), .wr_cmp(4'd0),
        .rd(1'b0), .rd_ch(5'd0), .rd_reg(2'd0), .rd_data(t_rd_unused),
        .pc_rd(1'b0), .pc_ch(5'd0), .pc_word(), .pc_tm(), .tm_we(1'b0), .tm_wd(16'd0),
        .sc_v(1'b0), .sc_ch(5'd0), .sc_ph(3'd0), .sc_tr(2'd0),
        .nx_fld(nx_fld), .dur_we(dur_we), .dur_v(dur_v), .dur_ch(dur_ch), .dur(dur),
        .dur_fld(dur_fld)
    );

    // the carrier's timebase, as the core's one twh_carrier gives it
    wire tick, tick_nx, fall;
    twh_carrier #(.CLK_HZ(CLK_HZ)) u_carrier (.clk(clk), .rst(rst), .tick(tick), .tick_nx(tick_nx),
                                              .fall(fall));

    tb_engine1 #(.CLK_HZ(CLK_HZ), .TAG_W(8)) dut (
        .clk(clk), .rst(rst), .tick(tick), .fall(fall), .cfg_idle_charge(1'b0),
        .t_we(dur_v), .t_fld(dur_fld), .t_len(dur),
        .s_cmd_valid(s_cmd_valid && t_ready), .s_cmd_ready(s_ready_e),
        .s_cmd_code(8'h41), .s_cmd_payload(16'h00AA), .s_cmd_tag(8'h5A), .s_cmd_skip(4'd0),
        .m_res_valid(m_res_valid), .m_res_ready(1'b1), .m_res_code(m_res_code),
        .m_res_data(m_res_data), .m_res_status(m_res_status), .m_res_tag(m_res_tag),
        .line_o(line_o), .line_oe(line_oe), .line_i(line_i),
        .busy(busy), .phase(phase), .fld(nx_fld), .pin_hi()
    );

    integer errors = 0;
    integer results = 0;
    integer clks = 0;
    integer seq_len = 0;       // phase changes seen after the command
    integer listen_clks = 0;
    reg [2:0] ph_d = `TWH_PH_IDLE;
    reg [2:0] seq [0:15];
    reg       sent = 1'b0;
    reg       done = 1'b0;

    task fail;
        input [8*64-1:0] msg;
        begin
            $display("FAIL: %0s (t = %0t)", msg, $time);
            errors = errors + 1;
        end
    endtask

    // the command: one valid/ready handshake after reset
    always @(posedge clk) begin
        if (!rst && !sent) begin
            s_cmd_valid <= 1'b1;
            if (s_cmd_valid && s_cmd_ready) begin
                s_cmd_valid <= 1'b0;
                sent        <= 1'b1;
            end
        end
    end

    // monitors
    always @(posedge clk) if (!rst) begin
        clks = clks + 1;
        if (phase != ph_d) begin
            if (seq_len < 16) seq[seq_len] = phase;
            seq_len = seq_len + 1;
        end
        if (ph_d == `TWH_PH_LISTEN) begin
            listen_clks = listen_clks + 1;
            if (listen_clks > LEAD_CLKS && line_oe !== 1'b0 && errors < 5)
                fail("line_oe high during listen");
        end
        ph_d <= phase;
        if (m_res_valid) begin
            results = results + 1;
            if (m_res_status !== `TWH_ST_NO_RESPONSE) fail("status is not NO_RESPONSE (1)");
            if (m_res_data   !== 16'd0)  fail("data not zero");
            if (m_res_code   !== 8'h41)  fail("command code not echoed");
            if (m_res_tag    !== 8'h5A)  fail("tag not echoed");
            $display("result: status %0d code 0x%02h tag 0x%02h data 0x%04h",
                     m_res_status, m_res_code, m_res_tag, m_res_data);
        end
        if (results > 0 && phase == `TWH_PH_IDLE && !busy) done <= 1'b1;
    end

    integer i;
    initial begin
        repeat (4) @(posedge clk);
        rst <= 1'b0;
        while (!done && clks < TIMEOUT_CLKS) @(posedge clk);
        repeat (8) @(posedge clk);
        if (!done) fail("timeout: no result / engine not idle");
        if (results != 1) fail("not exactly one result");
        // expected: 1 2 3 4 5 6 7 0
        if (seq_len != 8) fail("wrong number of phase changes");
        for (i = 0; i < 8 && i < seq_len; i = i + 1)
            if (seq[i] !== ((i + 1) % 8)) fail("phases out of order");
        // 1 us = CLK_HZ / 1e6 clocks; the listen clamp minimum is 2000 us
        if (listen_clks < 2000 * (CLK_HZ / 1_000_000)) fail("listen phase too short");
        $display("phases seen: %0d changes, listen %0d clocks", seq_len, listen_clks);
        if (errors == 0) begin
            $display("PASS");
            $finish;
        end else begin
            $fatal(1, "FAIL: %0d error(s)", errors);
        end
    end
endmodule
`default_nettype wire
