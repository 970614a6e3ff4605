// The core's channels on the time-shared engine (twh_core): the engine
// (twh_engine), every channel's poller with its registers in RAM
// (twh_polls), and what the core's registers read of them. Its command side
// is a stream into per-channel queues.
//
// - Commands: the core's dispatcher offers the command FIFO's head
//   (cmd_valid, held until cmd_ready), and the engine takes it at its
//   channel's visit when that channel's queue has room, so a command waits
//   behind another channel's only while four are queued there, or for at
//   most a carrier period while the one before it waits for its channel's
//   visit.
// - Phase lengths: twh_timing fetches, for every channel, the field its next
//   phase loads (decoded from the engine's `phase`: NX_PHASE) and clamps
//   it; this module writes each length into the engine's timing RAM. A
//   phase lasts at least 900 us (outside the lab unlock), and its
//   successor's field is fetched at the visit that starts it and at every
//   visit after (one channel: every clock; the engine's write-back names
//   the channel and its phase: sc_v, sc_ch, sc_ph, and the register of
//   the field named: sc_tr),
//   long before its last period reads it.
// - STATE: PHASE the engine's phase, BUSY a transaction under way (phases
//   charge to turnaround), SLOT_FULL a queued command not started; read
//   with POLL_RESULT on rd_data, a clock after the request. POLL_CTRL is
//   twh_timing's (each channel's fourth word), which the pollers' walker
//   reads through that memory's port (pc_rd, pc_ch, pc_word).
// - BUSY (the register): a command queued or running, a transaction on the
//   line (the engine's `busy`, a poll's too), or a result waiting in its
//   channel for room in the result FIFO.
`default_nettype none
`include "twh_defs.vh"
module twh_core_engine #(
    parameter integer CLK_HZ   = 48_000_000,
    parameter integer CHANNELS = 1,
    parameter integer POLLING  = 1,
    parameter integer PROG_TIMING = 1,   // 0: the engine runs the default lengths (no timing RAM)
    parameter integer RAM_BLOCK = 1      // the engine's and pollers' memories in block RAM (twh_core)
) (
    input  wire                   clk,
    input  wire                   rst,
    input  wire                   ms_tick,
    // twh_timing's reset sweep writes (the pollers wait for it)
    input  wire                   sw_we,
    input  wire                   tick,
    input  wire                   fall,
    input  wire                   enable,
    input  wire [CHANNELS-1:0]    idle_charge,
    // an accepted POLL_CTRL write, a read (the request stage's), the
    // read's word a clock later
    input  wire [31:0]            wdata,
    input  wire                   pc_wr,
    input  wire                   port_rd,      // the bus reads twh_timing's memory now
    input  wire                   rd_res,
    input  wire                   rd_state,     // STATE of reg_ch
    input  wire [4:0]             reg_ch,
    output wire [31:0]            rd_data,
    // POLL_CTRL in twh_timing's memory: the walker's read of pc_ch, its
    // word a clock later
    output wire                   pc_rd,
    output wire [4:0]             pc_ch,
    input  wire [31:0]            pc_word,
    // the pollers' timers in twh_timing's memory (twh_polls' TMR)
    input  wire [15:0]            pc_tm,
    input  wire                   port_wr,      // the bus writes twh_timing's memory now
    output wire                   pt_we,
    output wire [15:0]            pt_wd,
    // phase lengths from twh_timing
    output wire [CHANNELS*3-1:0]  nx_ph,        // each channel's phase (twh_timing's NX_PHASE;
                                                // its fetch reads it with one channel)
    // each visit's write-back: its channel and the phase it leaves (the
    // fetch's naming above one channel)
    output wire                   sc_v,
    output wire [4:0]             sc_ch,
    output wire [2:0]             sc_ph,
    output wire [1:0]             sc_tr,
    input  wire                   dur_v,
    input  wire [4:0]             dur_ch,
    input  wire [15:0]            dur,
    input  wire [2:0]             dur_fld,
    // channel registers
    output wire [CHANNELS-1:0]    poll_sample,
    output wire                   poll_error,
    // commands from the dispatcher
    input  wire                   cmd_valid,
    input  wire [4:0]             cmd_ch,
    input  wire [7:0]             cmd_code,
    input  wire [15:0]            cmd_payload,
    input  wire [4:0]             cmd_tag,
    input  wire [3:0]             cmd_skip,
    output wire                   cmd_ready,    // the offered command is taken now
    input  wire                   cancel,
    output wire                   cancelling,   // queued commands a flush cancels are left
    // results for the result FIFO: {tag, channel, status, code, data};
    // res_valid only in a clock with res_ready (the FIFO takes it then)
    output wire                   res_valid,
    input  wire                   res_ready,
    output wire [37:0]            res,
    // pins
    output wire [CHANNELS-1:0]    line_o,
    output wire [CHANNELS-1:0]    line_oe,
    input  wire [CHANNELS-1:0]    line_i,
    output wire [CHANNELS-1:0]    status_busy
);
    localparam integer CW = (CHANNELS > 1) ? $clog2(CHANNELS) : 1;

    // twh_timing's write to the engine's timing RAM: its channel by number
    wire [CW-1:0] t_ch = dur_ch[CW-1:0];

    wire [CHANNELS-1:0]    p_due;
    wire [15:0]            p_cmd;
    wire [CW-1:0]          scan_ch;
    wire [CW-1:0]          pc_cw;         // the walker's channel
    wire [CW-1:0]          sc_cw;
    wire                   p_take, p_res;
    wire [CW-1:0]          p_ch;
    wire [15:0]            p_data;
    wire [3:0]             p_status;
    wire [11:0]            p_count;
    wire [CHANNELS-1:0]    e_busy;
    wire [CHANNELS*3-1:0]  e_phase;
    wire                   st_pend;       // SLOT_FULL of reg_ch
    // verilator lint_off UNUSEDSIGNAL
    wire [CHANNELS*3-1:0]  e_fld;         // (twh_timing decodes it from the phase)
    wire [CHANNELS-1:0]    e_pending;     // (STATE reads it through st_pend)
    // verilator lint_on UNUSEDSIGNAL
    wire [CW-1:0]          r_ch;
    wire [7:0]             r_code;
    wire [15:0]            r_data;
    wire [3:0]             r_status;
    wire [4:0]             r_tag;
    // (its clock floor is the core's twh_carrier's to check)
    twh_engine #(.CLK_HZ(CLK_HZ), .CHANNELS(CHANNELS), .TAG_W(5), .QDEPTH(4),
                 .CHECK_FLOOR(0), .RAM_BLOCK(RAM_BLOCK),
                 .FIXED_TIMING(PROG_TIMING != 0 ? 0 : 1), .POLLING(POLLING)) u_engine (
        .clk(clk), .rst(rst), .tick(tick), .fall(fall), .cfg_idle_charge(idle_charge),
        .enable(enable), .cancel(cancel), .poll_req(p_due), .poll_cmd(p_cmd), .scan_ch(scan_ch),
        .t_we(dur_v), .t_ch(t_ch), .t_fld(dur_fld), .t_len(dur),
        .s_cmd_valid(cmd_valid), .s_cmd_ready(cmd_ready), .s_cmd_ch(cmd_ch[CW-1:0]),
        .s_cmd_code(cmd_code), .s_cmd_payload(cmd_payload), .s_cmd_tag(cmd_tag),
        .s_cmd_skip(cmd_skip),
        .m_res_valid(res_valid), .m_res_ready(res_ready), .m_res_ch(r_ch),
        .m_res_code(r_code), .m_res_data(r_data), .m_res_status(r_status), .m_res_tag(r_tag),
        .line_o(line_o), .line_oe(line_oe), .line_i(line_i),
        .busy(e_busy), .pending(e_pending), .st_ch(reg_ch[CW-1:0]), .st_pend(st_pend),
        .cancelling(cancelling),
        .phase(e_phase), .fld(e_fld), .sc_v(sc_v), .sc_ch(sc_cw), .sc_ph(sc_ph), .sc_tr(sc_tr),
        .p_take(p_take), .p_res(p_res), .p_ch(p_ch), .p_data(p_data), .p_status(p_status),
        .p_count(p_count)
    );
    twh_polls #(.CHANNELS(CHANNELS), .POLLING(POLLING), .RAM_BLOCK(RAM_BLOCK)) u_polls (
        .clk(clk), .rst(rst), .ms_tick(ms_tick), .sw_we(sw_we),
        .wr(pc_wr), .wr_ch(reg_ch[CW-1:0]), .wr_data(wdata),
        .port_rd(port_rd), .rd_res(rd_res), .rd_ch(reg_ch[CW-1:0]), .rd_data(p_rdata),
        .pc_rd(pc_rd), .pc_ch(pc_cw), .pc_word(pc_word),
        .pc_tm(pc_tm), .port_wr(port_wr), .pt_we(pt_we), .pt_wd(pt_wd),
        .scan_ch(scan_ch), .poll_cmd(p_cmd), .poll_req(p_due),
        .p_take(p_take), .p_res(p_res), .p_ch(p_ch), .p_data(p_data), .p_status(p_status),
        .p_count(p_count), .sample(poll_sample), .error(poll_error)
    );
    // verilator lint_off UNUSEDSIGNAL
    wire [5:0] r_ch6 = {{(6-CW){1'b0}}, r_ch};    // (CW is 1-5)
    wire [5:0] pc_ch6 = {{(6-CW){1'b0}}, pc_cw};
    wire [5:0] sc_ch6 = {{(6-CW){1'b0}}, sc_cw};
    // verilator lint_on UNUSEDSIGNAL
    assign res = {r_tag, r_ch6[4:0], r_status, r_code, r_data};
    assign pc_ch = pc_ch6[4:0];
    assign sc_ch = sc_ch6[4:0];

    // (the dispatcher names an existing channel: the push checked it; the
    // engine checks its queue's room itself, at the visit: `full` unused)
    // verilator lint_off UNUSEDSIGNAL
    wire [4:0] unused_ch = cmd_ch ^ reg_ch ^ dur_ch;
    // verilator lint_on UNUSEDSIGNAL

    // STATE of the channel read, a clock after the request stage (as
    // twh_polls answers POLL_CTRL and POLL_RESULT): one multiplexer over
    // the channels' phases rather than a select flip-flop and an AND-OR
    // term each; the pending flag is the engine's st_pend, which keeps the
    // command going in off that multiplexer
    localparam integer CN = 1 << CW;
    assign nx_ph = e_phase;
    wire [CN*3-1:0] st_w;       // each channel's phase
    reg  [3:0]      st_q;
    wire [31:0]     p_rdata;
    always @(posedge clk)
        st_q <= (rst || !rd_state) ? 4'd0 : {st_pend, st_w[reg_ch[CW-1:0]*3 +: 3]};
    // STATE: SLOT_FULL, BUSY (a transaction: not idle), PHASE
    assign rd_data = p_rdata | {27'd0, st_q[3], st_q[2:0] != `TWH_PH_IDLE, st_q[2:0]};

    genvar n;
    generate
        if (CHANNELS < CN) begin : g_pad
            assign st_w[CN*3-1:CHANNELS*3] = {((CN-CHANNELS)*3){1'b0}};
        end
        for (n = 0; n < CHANNELS; n = n + 1) begin : g_ch
            assign st_w[n*3 +: 3] = e_phase[n*3 +: 3];
            // (the engine's busy counts a transaction on the line, a poll's
            // too, and a result still waiting in the channel: it clears
            // at the visit's write, a clock after the result went into the
            // result FIFO)
            assign status_busy[n] = e_busy[n];
        end
    endgenerate
endmodule
`default_nettype wire
