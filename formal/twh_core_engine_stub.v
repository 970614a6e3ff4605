// Formal-only stand-in for twh_core_engine (the time-shared engine and its
// pollers) in formal/twh_core.sby's eng tasks. It keeps the command path of
// the engine as formal/twh_engine.sby proves it and tb/test_twh_engine.py
// tests it, and nothing else:
//   - each channel has a queue of four entries; the core offers a command
//     (cmd_valid, held until taken) and it is taken (cmd_ready) at any
//     moment its channel's queue is not full, as the real engine takes it
//     at its channel's visit (within a carrier period once there is room);
//   - the head starts at a free moment, when `enable` is 1 or it has a skip
//     code; started, it gives a link status (0-6) and data, or, with a skip
//     code (BLOCKED, CANCELLED), that status and data 0 without reaching
//     the line;
//   - `cancel` makes every entry not started CANCELLED (a head starting in
//     that very clock counts as started), but not a command pushed in that
//     clock (the core pushes that one CANCELLED itself);
//   - a started head's result goes out (res_valid, one channel at a time)
//     only in a clock with res_ready, and the head leaves its queue then.
// Polls, the timing fetch, the registers' read-back and the pins are left
// free: the core's command-path proof reads none of them (STATUS.BUSY
// takes a free "poll running" term too).
//
// Its queues and start flags are probed by the core's
// proof (formal/twh_core.sby, connect -set), as the command FIFO's words
// are: f_q (entry i of channel c, counted from the head, at
// (c*4 + i)*17: {skip, tag, code}), f_n (3 bits a channel), f_st (the head
// started), f_strt (it starts now), f_pop (its result goes in now).
`default_nettype none
`include "twh_defs.vh"
module twh_core_engine #(
    parameter integer CLK_HZ    = 48_000_000,
    parameter integer CHANNELS  = 1,
    parameter integer POLLING   = 1,
    parameter integer PROG_TIMING = 1,   // (the real one's: its engine's lengths; none here)
    parameter integer RAM_BLOCK = 1
) (
    input  wire                   clk,
    input  wire                   rst,
    input  wire                   ms_tick,
    input  wire                   sw_we,        // (the pollers' reset sweep: no pollers here)
    input  wire                   tick,
    input  wire                   fall,
    input  wire                   enable,
    input  wire [CHANNELS-1:0]    idle_charge,
    input  wire [31:0]            wdata,
    input  wire                   pc_wr,
    input  wire                   port_rd,
    input  wire                   rd_res,
    input  wire                   rd_state,
    input  wire [4:0]             reg_ch,
    output wire [31:0]            rd_data,
    output wire                   pc_rd,
    output wire [4:0]             pc_ch,
    input  wire [31:0]            pc_word,
    input  wire [15:0]            pc_tm,
    input  wire                   port_wr,
    output wire                   pt_we,
    output wire [15:0]            pt_wd,
    output wire [CHANNELS*3-1:0]  nx_ph,
    output wire                   sc_v,
    output wire [4:0]             sc_ch,
    output wire [2:0]             sc_ph,
    output wire [1:0]             sc_tr,
    input  wire                   dur_v,
    input  wire [4:0]             dur_ch,
    input  wire [15:0]            dur,
    input  wire [2:0]             dur_fld,
    output wire [CHANNELS-1:0]    poll_sample,
    output wire                   poll_error,
    input  wire                   cmd_valid,
    input  wire [4:0]             cmd_ch,
    input  wire [7:0]             cmd_code,
    input  wire [15:0]            cmd_payload,
    input  wire [4:0]             cmd_tag,
    input  wire [3:0]             cmd_skip,
    output wire                   cmd_ready,
    input  wire                   cancel,
    output wire                   cancelling,
    output wire                   res_valid,
    input  wire                   res_ready,
    output wire [37:0]            res,
    output wire [CHANNELS-1:0]    line_o,
    output wire [CHANNELS-1:0]    line_oe,
    input  wire [CHANNELS-1:0]    line_i,
    output wire [CHANNELS-1:0]    status_busy
);
    (* anyseq *) reg [CHANNELS-1:0]    f_start;    // a head may start now
    (* anyseq *) reg                   f_done;     // a result may be handed over now ...
    (* anyseq *) reg [4:0]             f_dch;      // ... by this channel
    (* anyseq *) reg [3:0]             f_status;
    (* anyseq *) reg [15:0]            f_data;
    (* anyseq *) reg [CHANNELS-1:0]    f_poll;     // a poll on the line (STATUS.BUSY)
    (* anyseq *) reg [31:0]            f_rd;
    (* anyseq *) reg [CHANNELS*3-1:0]  f_nx;
    (* anyseq *) reg [CHANNELS-1:0]    f_sample, f_line_o, f_line_oe;
    (* anyseq *) reg                   f_perr, f_canc;
    (* anyseq *) reg                   f_take;     // the offered command's visit is now

    localparam integer E = 17;                       // {skip, tag, code}
    wire [CHANNELS*4*E-1:0] f_q;
    wire [CHANNELS*3-1:0]   f_n;
    wire [CHANNELS-1:0]     f_st;
    reg  [4:0]              r_ch, r_tag;
    reg  [3:0]              r_status;
    reg  [7:0]              r_code;
    reg  [15:0]             r_data;

    wire [3:0] link_status = (f_status > `TWH_ST_LINE_STUCK_HIGH) ? `TWH_ST_NO_RESPONSE : f_status;

    wire [CHANNELS-1:0] f_pop, f_strt;
    wire [CHANNELS-1:0] f_full;
    wire [CHANNELS+31:0] f_full_x = {32'd0, f_full};
    // (the core offers only existing channels: its proof checks that)
    assign cmd_ready = !rst && f_take && !f_full_x[cmd_ch];
    // (one channel pops at a time: f_dch names it)
    integer c;
    always @(*) begin
        r_ch = 5'd0; r_tag = 5'd0; r_code = 8'd0; r_status = 4'd0; r_data = 16'd0;
        for (c = 0; c < CHANNELS; c = c + 1)
            if (f_pop[c]) begin
                r_ch     = c[4:0];
                r_tag    = f_q[(c*4)*E + 8 +: 5];
                r_code   = f_q[(c*4)*E +: 8];
                r_status = (f_q[(c*4)*E + 13 +: 4] != 4'd0) ? f_q[(c*4)*E + 13 +: 4] : link_status;
                r_data   = (f_q[(c*4)*E + 13 +: 4] == 4'd0 &&
                            (link_status == `TWH_ST_OK || link_status == `TWH_ST_BAD_CHECKSUM))
                           ? f_data : 16'd0;
            end
    end

    genvar n;
    integer i;
    generate
        for (n = 0; n < CHANNELS; n = n + 1) begin : g_ch
            reg  [4*E-1:0] q;          // entry i at i*E, the head at 0
            reg  [2:0]     cnt = 3'd0;
            reg            st = 1'b0;
            wire [E-1:0]   hd = q[E-1:0];
            // the head starts (a skip code is decided as a start is); a
            // started head hands its result over into an empty register
            assign f_strt[n] = f_start[n] && !st && cnt != 3'd0 &&
                               (enable || hd[16:13] != 4'd0);
            assign f_pop[n]  = res_ready && !rst && f_done && f_dch == n && st;
            wire [2:0]     kept = cnt - {2'd0, f_pop[n]};
            always @(posedge clk) begin
                if (rst) begin
                    cnt <= 3'd0;
                    st  <= 1'b0;
                end else begin
                    if (f_pop[n]) begin
                        st <= 1'b0;
                        q  <= {{E{1'b0}}, q[4*E-1:E]};
                    end else if (f_strt[n]) begin
                        st <= 1'b1;
                    end
                    // a flush: every entry not started, of those queued
                    // before it (the head that leaves now is answered as
                    // it stands)
                    if (cancel)
                        for (i = 0; i < 4; i = i + 1)
                            if (i < cnt && (i != 0 || !(st || f_strt[n])))
                                q[(i - (f_pop[n] ? 1 : 0))*E + 13 +: 4] <= `TWH_ST_CANCELLED;
                    if (cmd_valid && cmd_ready && cmd_ch == n)
                        q[kept*E +: E] <= {cmd_skip, cmd_tag, cmd_code};
                    cnt <= kept + {2'd0, cmd_valid && cmd_ready && cmd_ch == n};
                end
            end
            assign f_q[n*4*E +: 4*E] = q;
            assign f_n[n*3 +: 3]     = cnt;
            assign f_st[n]           = st;
            assign f_full[n]      = (cnt == 3'd4);
            assign status_busy[n] = (cnt != 3'd0) || f_poll[n];
        end
    endgenerate

    assign res_valid   = |f_pop;
    assign res         = {r_tag, r_ch, r_status, r_code, r_data};
    assign cancelling  = f_canc;
    // a POLL_RESULT / STATE read is answered in the clock after its
    // select, with 0 otherwise (twh_polls' timing: the core ORs it in;
    // POLL_CTRL is twh_timing's, and no walker reads it here)
    reg rd_q;
    always @(posedge clk) rd_q <= !rst && (rd_res || rd_state);
    assign pc_rd       = 1'b0;
    assign pt_we       = 1'b0;
    assign pt_wd       = 16'd0;
    // (the stand-in jobs cut twh_timing: no visit names a fetch here)
    assign sc_v        = 1'b0;
    assign sc_ch       = 5'd0;
    assign sc_ph       = 3'd0;
    assign sc_tr       = 2'd0;
    assign pc_ch       = 5'd0;
    assign rd_data     = rd_q ? f_rd : 32'd0;
    assign nx_ph       = f_nx;
    assign poll_sample = f_sample;
    assign poll_error  = f_perr;
    assign line_o      = f_line_o;
    assign line_oe     = f_line_oe;

    // the stand-in's own bookkeeping (from its initial state on): counts
    // within the queue's depth, a started head exists
    always @(*) begin
        for (c = 0; c < CHANNELS; c = c + 1) begin
            assert(f_n[c*3 +: 3] <= 3'd4);
            if (f_st[c]) assert(f_n[c*3 +: 3] != 3'd0);
        end
        if (res_valid) assert({1'b0, r_ch} < CHANNELS);
    end

    // verilator lint_off UNUSEDSIGNAL
    wire unused = &{1'b0, ms_tick, sw_we, port_rd, pc_word, pc_tm, port_wr, tick, fall, idle_charge, wdata, pc_wr, reg_ch,
                    dur_v, dur_ch, dur, dur_fld, cmd_payload, line_i, CLK_HZ[0], POLLING[0],
                    RAM_BLOCK[0]};
    // verilator lint_on UNUSEDSIGNAL
endmodule
`default_nettype wire
