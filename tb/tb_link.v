// Test-bench top for one channel of the link: the time-shared engine
// (twh_engine) with one channel, behind the one-channel ports the link's
// cases (tb/test_twh_link.py) drive: command and result streams, the phase
// lengths from inputs. The engine takes the lengths twh_timing hands over
// by number (dur_v, dur_ch) and names the field its next phase loads
// (fld); it is always enabled, never flushed and never polls here (the
// core's tests cover those).
//
// The clock is generated here (not from Python) because a Python-driven clock
// costs ~20x the simulation time. Everything else (config, command/result
// streams, the peripheral's drive, fault injection) is driven by cocotb.
//
// The 2-wire line itself is resolved by tb_line (faults, host, peripheral
// model, pull-down). `dropout` pulls the host's sense input low on its own
// (a carrier lost on the way in, after the line): the model and the monitor
// still see the line.
`timescale 1ns/1ps
`default_nettype none
module tb_link #(
    parameter integer CLK_HZ = 12_000_000
) (
    input  wire        rst,
    // timing configuration, microseconds
    input  wire [15:0] cfg_charge_us,
    input  wire [15:0] cfg_sync_us,
    input  wire [15:0] cfg_preamble_us,
    input  wire [15:0] cfg_execute_us,
    input  wire [15:0] cfg_listen_us,
    input  wire [15:0] cfg_turnaround_us,
    input  wire        cfg_idle_charge,
    input  wire        cfg_unlock,
    // command stream
    input  wire        s_cmd_valid,
    output wire        s_cmd_ready,
    input  wire [7:0]  s_cmd_code,
    input  wire [15:0] s_cmd_payload,
    input  wire [7:0]  s_cmd_tag,
    input  wire [3:0]  s_cmd_skip,
    // result stream
    output wire        m_res_valid,
    input  wire        m_res_ready,
    output wire [7:0]  m_res_code,
    output wire [15:0] m_res_data,
    output wire [3:0]  m_res_status,
    output wire [7:0]  m_res_tag,
    // host pins and status
    output wire        line_o,
    output wire        line_oe,
    output wire        line_i,
    output wire [2:0]  phase,
    output wire        busy,
    // the peripheral model and fault injection
    input  wire        periph_o,
    input  wire        periph_oe,
    input  wire        stuck_en,
    input  wire        stuck_val,
    input  wire        glitch,
    input  wire        dropout,
    output wire        line
);
    reg clk = 1'b0;
    localparam real HALF_NS = 1.0e9 / (2.0 * CLK_HZ);
    always #(HALF_NS) clk = ~clk;

    tb_line #(.PIN_LOG("pins_0.log"), .LINE_LOG("line_0.log")) u_line (
        .host_o(line_o), .host_oe(line_oe), .periph_o(periph_o), .periph_oe(periph_oe),
        .stuck_en(stuck_en), .stuck_val(stuck_val), .glitch(glitch), .line(line)
    );
    assign line_i = line && !dropout;

    // The phase lengths reach the engine as in the core: through
    // twh_timing, here with one channel, its words written from the cfg_*
    // inputs one register per clock, with their window flags from the
    // core's twh_window, and cfg_unlock as the lab unlock.
    // (written for three clocks after a change of cfg_* or the end of a
    // reset's sweep, which writes what wr_data carries, the cfg_* words
    // here, not the defaults as the core's data register gives them: the
    // three writes come before any command; a memory write every clock
    // costs the simulation dearly, and so does comparing the lengths every
    // clock; a change is seen by t_chg, which toggles only when one of them
    // moves). As the core's register port, the command port waits for the
    // sweep (t_ready), and for those three writes.
    reg  [1:0]  t_reg = 2'd0;
    reg  [1:0]  t_left = 2'd3;
    reg         t_chg = 1'b0, t_chg_q = 1'b0;
    wire [95:0] t_cfg = {cfg_charge_us, cfg_sync_us, cfg_preamble_us,
                         cfg_execute_us, cfg_listen_us, cfg_turnaround_us};
    always @(t_cfg) t_chg = !t_chg;
    wire        t_ready;
    wire        t_wr = !rst && t_ready && t_left != 2'd0;
    always @(posedge clk) if (rst || t_wr || t_chg != t_chg_q) begin
        if (t_wr) t_reg <= (t_reg == 2'd2) ? 2'd0 : t_reg + 2'd1;
        t_chg_q <= t_chg;
        if (rst || t_chg != t_chg_q) t_left <= 2'd3;
        else if (t_wr)               t_left <= t_left - 2'd1;
    end
    wire        s_ready_e;
    wire        s_open = t_ready && t_left == 2'd0;
    assign      s_cmd_ready = s_ready_e && s_open;
    wire [31:0] t_word = (t_reg == 2'd0) ? {cfg_sync_us, cfg_charge_us} :
                         (t_reg == 2'd1) ? {cfg_execute_us, cfg_preamble_us} :
                                           {cfg_turnaround_us, cfg_listen_us};
    // (one checker per register, so each is evaluated only when its
    // inputs change, not every clock)
    wire [3:0]  t_cmp0, t_cmp1, t_cmp2;
    twh_window u_w0 (.sel(2'd0), .value({cfg_sync_us, cfg_charge_us}),
                     .lo_below(t_cmp0[0]), .lo_above(t_cmp0[1]),
                     .hi_below(t_cmp0[2]), .hi_above(t_cmp0[3]));
    twh_window u_w1 (.sel(2'd1), .value({cfg_execute_us, cfg_preamble_us}),
                     .lo_below(t_cmp1[0]), .lo_above(t_cmp1[1]),
                     .hi_below(t_cmp1[2]), .hi_above(t_cmp1[3]));
    twh_window u_w2 (.sel(2'd2), .value({cfg_turnaround_us, cfg_listen_us}),
                     .lo_below(t_cmp2[0]), .lo_above(t_cmp2[1]),
                     .hi_below(t_cmp2[2]), .hi_above(t_cmp2[3]));
    wire [3:0]  t_cmp = (t_reg == 2'd0) ? t_cmp0 : (t_reg == 2'd1) ? t_cmp1 : t_cmp2;
    wire [2:0]  nx_fld, dur_fld;
    wire [15:0] dur;
    wire        dur_we, dur_v;
    wire [4:0]  dur_ch;
    wire [31:0] t_rd_unused;
    twh_timing #(.CHANNELS(1)) u_timing (
        .clk(clk), .rst(rst), .ready(t_ready), .sw_we(), .sw_reg(), .lab(cfg_unlock),
        .wr(t_wr), .wr_ch(5'd0), .wr_reg(t_reg), .wr_data(t_word), .wr_cmp(t_cmp),
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

    // The pin's glitch filter seen from outside (test_twh_link.py's
    // clock_conformance): a filtered high came in the engine's window since
    // its last visit, the flag its receiver samples.
    wire pin_hi;
    tb_engine1 #(.CLK_HZ(CLK_HZ), .TAG_W(8)) dut (
        .clk(clk), .rst(rst), .tick(tick), .fall(fall), .cfg_idle_charge(cfg_idle_charge),
        .t_we(dur_v), .t_fld(dur_fld), .t_len(dur),
        .s_cmd_valid(s_cmd_valid && s_open), .s_cmd_ready(s_ready_e),
        .s_cmd_code(s_cmd_code), .s_cmd_payload(s_cmd_payload), .s_cmd_tag(s_cmd_tag), .s_cmd_skip(s_cmd_skip),
        .m_res_valid(m_res_valid), .m_res_ready(m_res_ready), .m_res_code(m_res_code),
        .m_res_data(m_res_data), .m_res_status(m_res_status), .m_res_tag(m_res_tag),
        .line_o(line_o), .line_oe(line_oe), .line_i(line_i),
        .busy(busy), .phase(phase), .fld(nx_fld), .pin_hi(pin_hi)
    );
    // verilator lint_off UNUSEDSIGNAL
    wire unused = &{1'b0, dur_we, dur_ch, tick_nx};
    // verilator lint_on UNUSEDSIGNAL

    // `make demo` asks for a small VCD of the pins with +vcd=<file>.
    reg [1023:0] vcd_file;
    initial begin
        if ($value$plusargs("vcd=%s", vcd_file)) begin
            $dumpfile(vcd_file);
            $dumpvars(0, line_o, line_oe, line_i, phase, busy);
        end
    end
endmodule
`default_nettype wire
