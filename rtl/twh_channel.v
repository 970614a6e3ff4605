// One channel of the bus core: its polling registers, a one-entry command
// slot fed by the core's dispatcher, the autonomous poller, and the twh_link
// engine. The channel's timing registers live in the core's twh_timing,
// shared by all channels, which hands the engine its clamped phase lengths.
//
// - A poll write that switches polling on is refused (`wdata_ok`, the
//   core's verdict) unless the command is read-only (0x40-0x44,
//   0x46-0x49): a poller must never erase or write a sensor's flash.
//   Switching it off is always accepted.
// - When a queued command and a due poll both wait for the engine they take
//   turns, so neither can starve the other.
// - Poll results update POLL_RESULT here and never reach the result FIFO;
//   they are told apart by the engine tag's top bit.
`default_nettype none
`include "twh_defs.vh"
module twh_channel #(
    parameter integer CLK_HZ      = 48_000_000,
    parameter integer POLLING     = 1      // 0: no poller (POLL_CTRL reads 0)
) (
    input  wire        clk,
    input  wire        rst,
    input  wire        ms_tick,
    input  wire        tick,           // the carrier's timebase (twh_link)
    input  wire        tick_nx,
    input  wire        fall,
    input  wire        enable,
    input  wire        idle_charge,
    // register writes, decoded by the core (one-clock strobes)
    input  wire [31:0] wdata,
    input  wire        wdata_ok,       // POLL_CTRL: wdata switches polling off or names
                                       // a read-only command (the core's verdict)
    input  wire        wr_poll_ctrl,
    // phase lengths from twh_timing
    output wire [2:0]  nx_fld,
    input  wire        dur_we,
    input  wire [15:0] dur,
    input  wire [2:0]  dur_fld,
    output wire [31:0] poll_ctrl,
    output wire [31:0] poll_result,
    output wire [31:0] state,
    output reg         poll_sample,    // a poll result arrived
    output reg         poll_error,     // ... and it was a link error
    // command slot
    input  wire        slot_load,
    input  wire [7:0]  slot_cmd_i,
    input  wire [15:0] slot_payload_i,
    input  wire [4:0]  slot_tag_i,
    input  wire [3:0]  slot_skip_i,
    input  wire        cancel,         // flush: a command still in the slot is cancelled
    output reg         slot_full,
    // results for the result FIFO
    output wire        res_valid,
    input  wire        res_ready,
    output wire [7:0]  res_cmd,
    output wire [15:0] res_data,
    output wire [3:0]  res_status,
    output wire [4:0]  res_tag,
    // the 2-wire pin
    output wire        line_o,
    output wire        line_oe,
    input  wire        line_i,
    output wire        busy,           // the engine's (the core's proofs)
    output reg         status_busy     // STATUS.BUSY (see below)
);
    // ------------------------------------------------------------ registers
    reg [7:0]  poll_cmd, poll_payload;
    reg [14:0] poll_interval;
    reg        poll_en;
    reg [15:0] poll_data;
    reg [3:0]  poll_status;
    reg [11:0] poll_count;

    // The core checks each written value once for every channel (from the
    // bus data, a clock before the write reaches the channel), so the
    // register's enable starts from its flip-flops.
    wire ok_poll = wdata_ok;
    // without the poller POLL_CTRL reads 0 (polling off)
    localparam [7:0]  POLL_CMD_DEF      = (POLLING != 0) ? 8'h44 : 8'h00;
    localparam [7:0]  POLL_PAYLOAD_DEF  = (POLLING != 0) ? 8'hAA : 8'h00;
    localparam [14:0] POLL_INTERVAL_DEF = (POLLING != 0) ? 15'd1000 : 15'd0;

    always @(posedge clk) begin
        if (rst) begin
            poll_cmd      <= POLL_CMD_DEF;
            poll_payload  <= POLL_PAYLOAD_DEF;
            poll_interval <= POLL_INTERVAL_DEF;
            poll_en       <= 1'b0;
        end else begin
            // without the poller the registers keep their reset values:
            // constants that synthesis folds away
            if (POLLING != 0 && wr_poll_ctrl && ok_poll) begin
                poll_cmd      <= wdata[7:0];
                poll_payload  <= wdata[15:8];
                poll_interval <= wdata[30:16];
                poll_en       <= wdata[31];
            end
        end
    end

    // ------------------------------------------------------------ poll timer
    // Milliseconds to the next poll, this one included. It reloads at 1 or
    // below, so a reload of 0 (an interval of 0) polls at the next
    // millisecond, as an interval of 1 does, with no fix-up in front of the
    // reload. Whether it is at 1 or below is a flag that moves with it: the
    // compare is off the path into the counter (ECP5's critical path).
    reg [14:0] poll_timer;
    reg        poll_last;     // poll_timer <= 1
    reg        poll_due;

    // ------------------------------------------------------------ slot and arbitration
    reg [7:0]  slot_cmd;
    reg [15:0] slot_payload;
    reg [4:0]  slot_tag;
    reg [3:0]  slot_skip;
    reg        prefer_poll;

    wire eng_ready;
    wire slot_go  = slot_full && (enable || slot_skip != 4'd0);
    wire poll_go  = poll_en && poll_due && enable;
    wire use_poll = poll_go && (prefer_poll || !slot_go);
    wire issue    = use_poll || slot_go;
    // The choice is registered, so the engine's inputs start from flip-flops;
    // it lags the slot and poll state by one clock, which only delays a start.
    reg  issue_q, use_poll_q;
    wire taken    = issue_q && eng_ready;

    always @(posedge clk) begin
        if (rst) begin
            slot_full    <= 1'b0;
            slot_cmd     <= 8'd0;
            slot_payload <= 16'd0;
            slot_tag     <= 5'd0;
            slot_skip    <= 4'd0;
            prefer_poll  <= 1'b0;
            poll_timer   <= 15'd1;
            poll_last    <= 1'b1;
            poll_due     <= 1'b0;
            issue_q      <= 1'b0;
            use_poll_q   <= 1'b0;
        end else begin
            // a poll-control write withdraws the registered choice for a
            // clock: the engine must never see a command byte that was not
            // checked (switching polling off accepts any byte)
            issue_q    <= issue && !taken && !wr_poll_ctrl;
            use_poll_q <= use_poll;
            if (slot_load) begin
                slot_full    <= 1'b1;
                slot_cmd     <= slot_cmd_i;
                slot_payload <= slot_payload_i;
                slot_tag     <= slot_tag_i;
                slot_skip    <= slot_skip_i;
            end else if (taken && !use_poll_q) begin
                slot_full    <= 1'b0;
            end
            // (a slot is loaded only while empty; one taken in this clock
            // is marked too: it is empty next clock, and a load writes its
            // skip afresh)
            if (cancel && slot_full) slot_skip <= `TWH_ST_CANCELLED;
            if (taken) prefer_poll <= !use_poll_q;

            if (!poll_en) begin
                poll_timer <= 15'd1;          // first poll at the next millisecond
                poll_last  <= 1'b1;
                poll_due   <= 1'b0;
            end else begin
                if (ms_tick) begin
                    if (poll_last) begin
                        poll_timer <= poll_interval;
                        poll_last  <= (poll_interval <= 15'd1);
                        poll_due   <= 1'b1;
                    end else begin
                        poll_timer <= poll_timer - 1'b1;
                        poll_last  <= (poll_timer == 15'd2);
                    end
                end
                if (taken && use_poll_q) poll_due <= 1'b0;
            end
        end
    end

    // ------------------------------------------------------------ engine
    wire        e_valid;
    wire        e_ready;
    wire [7:0]  e_code;
    wire [15:0] e_data;
    wire [3:0]  e_status;
    wire [5:0]  e_tag;
    wire [2:0]  phase;
    wire        link_busy;
    wire        e_is_poll = (POLLING != 0) && e_tag[5];

    twh_link #(.CLK_HZ(CLK_HZ), .TAG_W(6)) u_link (
        .clk(clk), .rst(rst), .tick(tick), .tick_nx(tick_nx), .fall(fall),
        .nx_fld(nx_fld), .dur_we(dur_we), .dur_in(dur), .dur_fld_in(dur_fld),
        .cfg_idle_charge(idle_charge),
        .s_cmd_valid(issue_q), .s_cmd_ready(eng_ready),
        .s_cmd_code(use_poll_q ? poll_cmd : slot_cmd),
        .s_cmd_payload(use_poll_q ? {8'h00, poll_payload} : slot_payload),
        .s_cmd_tag(use_poll_q ? 6'b100000 : {1'b0, slot_tag}),
        .s_cmd_skip(use_poll_q ? 4'd0 : slot_skip),
        .m_res_valid(e_valid), .m_res_ready(e_ready),
        .m_res_code(e_code), .m_res_data(e_data), .m_res_status(e_status),
        .m_res_tag(e_tag),
        .line_o(line_o), .line_oe(line_oe), .line_i(line_i),
        .phase(phase), .busy(link_busy)
    );

    wire link_err = (e_status >= `TWH_ST_BAD_CHECKSUM) && (e_status <= `TWH_ST_LINE_STUCK_HIGH);

    assign e_ready    = e_is_poll || res_ready;
    assign res_valid  = e_valid && !e_is_poll;
    assign res_cmd    = e_code;
    assign res_data   = e_data;
    assign res_status = e_status;
    assign res_tag    = e_tag[4:0];

    always @(posedge clk) begin
        if (rst) begin
            poll_data   <= 16'd0;
            poll_status <= 4'd0;
            poll_count  <= 12'd0;
            poll_sample <= 1'b0;
            poll_error  <= 1'b0;
        end else if (e_valid || poll_sample) begin   // else both are 0 already
            poll_sample <= e_valid && e_is_poll;
            poll_error  <= e_valid && e_is_poll && link_err;
            if (e_valid && e_is_poll) begin
                poll_data   <= e_data;
                poll_status <= e_status;
                poll_count  <= poll_count + 1'b1;
            end
        end
    end

    assign poll_ctrl   = {poll_en, poll_interval, poll_payload, poll_cmd};
    assign poll_result = {poll_count, poll_status, poll_data};
    // STATUS.BUSY (a command in the slot, in the engine or its result
    // waiting) and STATE.BUSY (the engine's) are flip-flops, so the core's
    // answer registers take them with no engine decode in front (ECP5's
    // three-channel paths ran from the engine's phase through them). Each
    // loads what it reports now or an event that makes it true in the next
    // clock (a slot load, an accept; for STATE, of a command that is sent):
    // it is never 0 while what it reports is 1, and reads 1 at most one
    // clock after that has ended (proven below), so STATUS saying
    // everything was answered still means it.
    assign busy = link_busy;
    reg state_busy;
    always @(posedge clk) begin
        // (a skipped command is answered at once and never makes the engine busy)
        state_busy  <= !rst && (link_busy || (taken && (use_poll_q || slot_skip == 4'd0)));
        status_busy <= !rst && (link_busy || slot_full || res_valid || slot_load || taken);
    end
    assign state       = {27'd0, slot_full, state_busy, phase};

`ifdef FORMAL
    // ================================================================ formal
    // formal/twh_channel.sby proves the channel with TWH_F_CHANNEL defined
    // and a stand-in engine (formal/twh_channel_link.v) that keeps only
    // twh_link's proven interface contract. The one rule the core must keep
    // (a slot is loaded only while free) is then assumed; read without
    // TWH_F_CHANNEL the same rule is checked instead. Everything else: any
    // input, rst included, from the first reset on (f_ok).
    reg f_ok = 1'b0;
    always @(posedge clk) if (rst) f_ok <= 1'b1;
    reg f_run = 1'b0;      // the previous clock ran and was no reset
    always @(posedge clk) f_run <= f_ok && !rst;

    always @(*) begin
        if (f_ok && !rst && slot_load) begin
`ifdef TWH_F_CHANNEL
            assume(!slot_full);
`else
            assert(!slot_full);
`endif
        end
    end

    // ------------------------------------------------ register rules
    function f_ro;        // the read-only commands a poller may send
        input [7:0] c;
        f_ro = (c >= 8'h40 && c <= 8'h44) || (c >= 8'h46 && c <= 8'h49);
    endfunction
    // Whether a POLL_CTRL write of wdata must be taken (the timing
    // registers' rules are twh_timing's and the core's). A wire, not a
    // function call under $past: Yosys 0.70 evaluates a function call inside
    // $past on the current arguments.
    wire f_takep = !wdata[31] || f_ro(wdata[7:0]);
    // the core's verdict is right for the register written (proven on the
    // core: twh_core's f_cw_ok)
    wire f_ok_right = !wr_poll_ctrl || wdata_ok == f_takep;
    always @(*) begin
        if (f_ok && !rst) begin
`ifdef TWH_F_CHANNEL
            assume(f_ok_right);
`else
            assert(f_ok_right);
`endif
        end
    end

    wire [7:0] f_code = use_poll_q ? poll_cmd : slot_cmd;     // what the engine is offered
    wire [3:0] f_skip = use_poll_q ? 4'd0 : slot_skip;

    // STATUS.BUSY and STATE.BUSY: never 0 while what they report is 1, and
    // 1 only while it is or a clock after it was
    wire f_sbusy_now = link_busy || slot_full || res_valid;
    always @(posedge clk) begin
        if (f_run && !rst) begin
            if (f_sbusy_now) assert(status_busy);
            if (link_busy)   assert(state_busy);
            if (status_busy) assert(f_sbusy_now || $past(f_sbusy_now));
            if (state_busy)  assert(link_busy || $past(link_busy));
        end
    end

    always @(*) begin
        if (f_ok) begin
            // the timer's flag is its compare
            assert(poll_last == (poll_timer <= 15'd1));
            // the poller is only ever armed with, and only ever hands the
            // engine, a read-only command
            if (poll_en) assert(f_ro(poll_cmd));
            if (taken && use_poll_q) assert(f_ro(f_code));
            // a slot command is offered only while it is in the slot
            if (issue_q && !use_poll_q) assert(slot_full);
            // poll results stay in the channel, all others leave it
            assert(res_valid == (e_valid && !e_tag[5]));
        end
    end

    always @(posedge clk) begin
        if (f_run) begin
            if ($past(wr_poll_ctrl && f_takep))
                assert(poll_ctrl == $past(wdata));
            // a result to the core stays offered, unchanged, until taken
            if ($past(res_valid && !res_ready))
                assert(res_valid && $stable({res_cmd, res_data, res_status, res_tag}));
        end
    end

`ifdef TWH_F_CHANNEL
    // ------------------------------------------------ commands through the channel
    // Needs the stand-in engine: its busy is exactly "a sent command waits
    // for its result" and its m_res_tag the tag of the last accepted command.
    //
    // f_n: commands loaded into the slot minus results handed to the core.
    // f_s*: the command in the slot as loaded, its skip as it must be
    // (loaded with one, or cancelled while waiting); f_l*: the slot command
    // the engine has.
    reg [1:0] f_n;
    reg [4:0] f_stag, f_ltag;
    reg [7:0] f_scmd, f_lcmd;
    reg [3:0] f_sskip, f_lskip;
    wire f_take = taken && !use_poll_q;
    always @(posedge clk) begin
        if (rst) begin
            f_n <= 2'd0;
        end else begin
            f_n <= f_n + {1'b0, slot_load} - {1'b0, res_valid && res_ready};
            if (slot_load) begin
                f_stag  <= slot_tag_i;
                f_scmd  <= slot_cmd_i;
                f_sskip <= slot_skip_i;
            end else if (cancel && slot_full && !f_take) begin
                f_sskip <= `TWH_ST_CANCELLED;
            end
            if (f_take) begin
                f_ltag  <= f_stag;
                f_lcmd  <= f_scmd;
                f_lskip <= f_sskip;
            end
        end
    end
    wire f_eng_slot = (busy || e_valid) && !e_tag[5];    // the engine holds a slot command

    always @(*) begin
        if (f_ok) begin
            // the stand-in engine's own state: a sent command or a result
            assert(!(busy && e_valid));
            // every command loaded is in the slot, in the engine, or has
            // left as exactly one result: none lost, none doubled
            assert(f_n == {1'b0, slot_full} + {1'b0, f_eng_slot});
            if (slot_full)
                assert(slot_cmd == f_scmd && slot_tag == f_stag && slot_skip == f_sskip);
            // a blocked or cancelled command never reaches the line: the
            // engine gets it with its skip status
            if (f_take) assert(f_skip == f_sskip);
            if (f_eng_slot) begin
                assert(e_tag == {1'b0, f_ltag} && e_code == f_lcmd);
                if (busy) assert(f_lskip == 4'd0);      // only unskipped ones are sent
                if (e_valid) begin
                    if (f_lskip != 4'd0) assert(e_status == f_lskip);
                    else                 assert(e_status <= `TWH_ST_LINE_STUCK_HIGH);
                end
            end
            // polls are told apart by the tag's top bit alone
            if (busy || e_valid) assert(e_tag[5] ? e_tag[4:0] == 5'd0 && f_ro(e_code) : 1'b1);
        end
    end

    // ------------------------------------------------ taking turns
    // Neither a queued command nor a due poll can starve the other. f_pw:
    // polls the engine took while the same command waited in the slot;
    // f_sw: slot commands it took while the same poll was due and polling
    // could go (enable on: with it off only skipped slot commands go, and
    // they never reach the line). Each is at most one, so with the engine's
    // proven bound per transaction neither waits, beyond the transaction
    // already running, longer than one transaction of the other kind.
    reg [1:0] f_pw, f_sw;
    always @(posedge clk) begin
        if (rst || !slot_full || f_take)                      f_pw <= 2'd0;
        else if (taken && use_poll_q && f_pw != 2'd3)         f_pw <= f_pw + 1'b1;
        if (rst || !(poll_en && poll_due && enable) || (taken && use_poll_q)) f_sw <= 2'd0;
        else if (f_take && f_sw != 2'd3)                      f_sw <= f_sw + 1'b1;
    end
    always @(*) begin
        if (f_ok) begin
            assert(f_pw <= 2'd1);
            assert(f_sw <= 2'd1);
            // the turn is the other kind's once one kind was taken
            if (f_pw == 2'd1) assert(!prefer_poll);
            if (f_sw == 2'd1) assert(prefer_poll);
        end
    end

    always @(posedge clk) begin
        if (f_ok && !rst) begin
            cover(f_pw == 2'd1 && f_take);
            cover(f_sw == 2'd1 && taken && use_poll_q);
            cover(res_valid && res_ready && f_lskip == `TWH_ST_CANCELLED && f_sskip == 4'd0);
            cover(taken && use_poll_q && slot_full);
            cover(poll_sample && slot_full && f_n == 2'd1);
            cover(f_n == 2'd2 && res_valid);
        end
    end
`endif
`endif
endmodule
`default_nettype wire
