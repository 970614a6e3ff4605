// Every channel's autonomous poller for the time-shared engine, its
// registers in RAM: POLL_RESULT (bus read), each channel's millisecond
// timer, and the command the engine sends. POLL_CTRL is each channel's
// fourth word in twh_timing's memory (the bus writes and reads it there,
// the walker reads it through that memory's port: pc_rd, pc_ch, pc_word);
// this module takes its writes (wr) for what they withdraw. Per
// channel only three flags stay in flip-flops (due, restart, pr_ok), so a channel
// costs a few cells here rather than a poller's eighty flip-flops.
//
// - A walker steps every channel's timer once a millisecond (three clocks a
//   channel: read, step, commit; a bus read of twh_timing's memory,
//   TIMING0-2 or POLL_CTRL, takes its port first and the walker waits).
//   Polls fall due on a fixed grid: every INTERVAL_MS
//   from the first millisecond tick after EN was set. A channel's command
//   is copied for the engine when its poll falls due and only then (never
//   while one is due), so the engine reads a command that was checked as
//   read-only when it was written (the core refuses a write with EN = 1 of
//   any other command) and that no write changes under it.
// - `due` is raised a clock after the command is written: a scan that read
//   the command memory in the clock it was written sees no request.
// - A POLL_CTRL write with EN = 0 withdraws the channel's due poll at once,
//   and its timer restarts at the walker's next step (so polling switched
//   off and on again polls at the next millisecond, as switched on does).
//   A write the walker read a moment before is read again (`w_dirty`); a
//   write in the commit's own clock counts as after the commit (the step
//   keeps the word it read; the write's EN = 0 withdraws what the commit
//   raises a clock later), so no bus compare reaches the commit's RAM
//   write enables. (With the timers in twh_timing's memory, TMR below, a
//   commit never meets a write there: it waits for a clock without one;
//   the single bit port_wr, not a compare, is what reaches the timer's
//   write enable.)
// - POLL_RESULT is written when a poll's result arrives, with the count
//   the engine keeps in the channel's state word; a read in the clock of
//   that write answers the word before it (the read comes first, and the
//   sample's POLL_READY bit a clock later announces the new one: no
//   32-bit bypass, about 54 logic cells at every channel count). Until a
//   channel's first result since the reset its word reads 0, its reset
//   value: a flag a channel (`pr_ok`) masks the read. The reset sweep
//   does not write it: its zero in front of the memory's write data was
//   32 logic cells at every channel count, the flag is one a channel.
//   The memory holds the answer's bytes whatever its status; the read
//   shows them only with OK or BAD_CHECKSUM (16 cells fewer than a zero
//   in front of the write).
// - The timers: above one channel in block RAM (TMR), each channel's
//   timer is in its POLL_CTRL word of twh_timing's memory (pc_tm, read
//   with pc_word; written at the commit, pt_we), a block fewer; the commit
//   then waits for a clock in which the bus does not write that memory
//   (port_wr), its step held (a write to the channel meanwhile makes the
//   walker read it again). With one channel, or LUT RAM, they are a
//   memory of their own here.
// - Reset: twh_timing's reset sweep writes every channel's POLL_CTRL with
//   its reset value; the register port takes no request and the walker
//   does not start until its writes are over (sw_we; the timers need
//   none: `restart`).
`default_nettype none
`include "twh_defs.vh"
module twh_polls #(
    parameter integer CHANNELS = 1,
    parameter integer POLLING  = 1,      // 0: no poller (POLL_CTRL reads 0, nothing due)
    // 1: the memories in block RAM (the iCE40s have no LUT RAM); 0: in
    // LUT RAM at every depth (the ECP5's reads faster: twh_core's RAM_BLOCK)
    parameter integer RAM_BLOCK = 1,
    parameter integer CW       = (CHANNELS > 1) ? $clog2(CHANNELS) : 1
) (
    input  wire                clk,
    input  wire                rst,
    input  wire                ms_tick,
    // the reset sweep (twh_timing) writes: no bus access, poll or result
    // comes while it runs
    input  wire                sw_we,
    // the core's request stage: an accepted POLL_CTRL write, a read
    input  wire                wr,
    input  wire [CW-1:0]       wr_ch,
    // (its EN bit: what a write withdraws; the proof follows the word)
    // verilator lint_off UNUSEDSIGNAL
    input  wire [31:0]         wr_data,
    // verilator lint_on UNUSEDSIGNAL
    input  wire                port_rd,      // the bus reads twh_timing's memory now
    input  wire                rd_res,       // POLL_RESULT of rd_ch
    input  wire [CW-1:0]       rd_ch,
    output wire [31:0]         rd_data,      // a clock later; 0 after no read
    // POLL_CTRL in twh_timing's memory: the walker asks to read pc_ch's
    // now and reads it unless port_rd (the bus goes first), its word a
    // clock later
    output wire                pc_rd,
    output wire [CW-1:0]       pc_ch,
    input  wire [31:0]         pc_word,
    // TMR: pc_ch's timer, read with pc_word; and its write at the commit
    // (never while port_wr: the bus writes twh_timing's memory now)
    input  wire [15:0]         pc_tm,
    input  wire                port_wr,
    output wire                pt_we,
    output wire [15:0]         pt_wd,
    // the engine
    input  wire [CW-1:0]       scan_ch,      // its read address (the engine's S1)
    output wire [15:0]         poll_cmd,     // that channel's {payload, code}, a clock later
    output wire [CHANNELS-1:0] poll_req,     // its poll is due
    input  wire                p_take,       // a poll started (p_ch)
    input  wire                p_res,        // a poll's result (p_ch)
    input  wire [CW-1:0]       p_ch,
    input  wire [15:0]         p_data,
    input  wire [3:0]          p_status,
    input  wire [11:0]         p_count,
    output reg  [CHANNELS-1:0] sample,       // a poll result arrived (one clock)
    output reg                 error         // ... and it was a link error
);
    reg  [CHANNELS-1:0] due, restart;
    reg  [CHANNELS-1:0] pr_ok;       // a poll result arrived since the reset

    // ------------------------------------------------------------ POLL_CTRL
    reg          w_on, w_pend, w_dirty;
    reg [1:0]    w_s;           // 0 read, 1 step (from the words read), 2 commit
    reg          w_r;           // w_on && w_s == 0: the walker asks for the port
    reg [CW-1:0] w_ch;
    // (it asks for the port whatever the bus does, which goes first: its
    // request is flip-flops' alone, off the bus's path into the memory's
    // address. In LUT RAM (RAM_BLOCK = 0, the ECP5's), which reads the
    // address in the clock, it is a flip-flop of its own, so that
    // twh_timing's read address is one LUT of flip-flops; a block RAM
    // registers its address itself, and there the flip-flop (with the
    // core's q_r_tm) placed the UP5K's top at three channels at a median
    // of 47.2 MHz against 51.2: w_r is then unused)
    assign pc_rd = (RAM_BLOCK == 0) ? w_r : (w_on && w_s == 2'd0);
    wire         w_read = pc_rd && !port_rd;   // the walker reads this clock
    assign pc_ch = w_ch;
    // the engine's copy of the command (below) is a memory of this module,
    // as twh_ram's, so that its proof can name its words (g_mem.cm_mem:
    // one label for either style)
    reg  [15:0]  cm_rd;
    wire         cm_we;
    generate
        if (RAM_BLOCK != 0) begin : g_mem
            (* ram_style = "block" *) (* no_rw_check *) reg [15:0] cm_mem [0:(1 << CW) - 1];
            always @(posedge clk) begin
                if (cm_we) cm_mem[w_ch] <= pc_w[15:0];
                cm_rd <= cm_mem[scan_ch];
            end
        end else begin : g_mem
            (* ram_style = "distributed" *) (* no_rw_check *) reg [15:0] cm_mem [0:(1 << CW) - 1];
            always @(posedge clk) begin
                if (cm_we) cm_mem[w_ch] <= pc_w[15:0];
                cm_rd <= cm_mem[scan_ch];
            end
        end
    endgenerate
    // (twh_timing's condition, from twh_defs.vh)
    localparam integer TMR = `TWH_POLL_TIMERS_IN_TIMING(POLLING, CHANNELS, RAM_BLOCK);
    wire [15:0] tm_rd;
    wire        tm_we;
    reg  [15:0] tm_wd;
    reg  [15:0] q_tm;           // the step's timer word, for the commit
    generate
        if (TMR != 0) begin : g_tm_pc
            assign tm_rd = pc_tm;
            assign pt_we = tm_we;
        end else begin : g_tm
            twh_ram #(.W(16), .AW(CW), .BLOCK(RAM_BLOCK)) u_timer (
                .clk(clk), .we(tm_we), .waddr(w_ch), .wdata(q_tm), .re(1'b1), .raddr(w_ch), .rdata(tm_rd)
            );
            assign pt_we = 1'b0;
            // verilator lint_off UNUSEDSIGNAL
            wire unused_tm = port_wr ^ (^pc_tm);
            // verilator lint_on UNUSEDSIGNAL
        end
    endgenerate
    assign pt_wd = q_tm;
    wire [31:0] pc_w;
    assign poll_cmd = cm_rd;

    // the walker's step for w_ch, from the words read a clock ago and the
    // channel's flags taken with them (a write to the channel in between
    // makes the walker read again: w_dirty), registered for the commit a
    // clock later (off the RAM outputs' path; the flags' multiplexer over
    // the channels is off it too)
    reg         rs_q;
    always @(posedge clk) if (w_read) rs_q <= restart[w_ch];
    assign      pc_w   = pc_word;
    wire        p_en   = pc_w[31];
    wire [14:0] p_iv   = pc_w[30:16];
    wire        rs     = rs_q;
    // (the timer's last millisecond, or a restart: reload. A count steps
    // down only when neither, so its decrement takes the memory's word
    // with no restart's multiplexer in front of the carry chain)
    wire        l_now  = rs || tm_rd[15];
    wire        reload = p_en && l_now;
    always @(*) begin
        if (!p_en)       tm_wd = {1'b1, 15'd1};
        else if (l_now)  tm_wd = {p_iv <= 15'd1, p_iv};
        else             tm_wd = {tm_rd[14:0] == 15'd2, tm_rd[14:0] - 15'd1};
    end
    // TMR: a commit that meets a bus write of twh_timing's memory waits
    // for the next clock without one, its step's timer and copy flag held
    // (a retry from the read, three clocks on, could meet a write stream
    // in step with it every time)
    wire c_wait = TMR != 0 && w_on && w_s == 2'd2 && !w_dirty && port_wr;
    // (q_tm and cm_did written out for each build: with the wait's terms
    // left for synthesis to fold, the one-channel netlist, the same logic,
    // placed 12 logic cells larger: ABC's mapping, Yosys 0.70, HX8K)
    generate
        if (TMR != 0) begin : g_qtm_w
            always @(posedge clk) if (!c_wait) q_tm <= tm_wd;
        end else begin : g_qtm
            always @(posedge clk) q_tm <= tm_wd;
        end
    endgenerate
    wire commit = w_on && w_s == 2'd2 && !w_dirty && !(TMR != 0 && port_wr);
    localparam [CW-1:0] LAST = CHANNELS[CW-1:0] - 1'b1;
    reg          set_due;       // raise due a clock after the command is written
    reg [CW-1:0] set_ch;
    always @(posedge clk) begin
        if (rst || POLLING == 0) begin
            w_on <= 1'b0; w_s <= 2'd0; w_pend <= 1'b0; w_dirty <= 1'b0;
            w_r  <= 1'b0;
            w_ch <= {CW{1'b0}};
        end else begin
            if (ms_tick) w_pend <= 1'b1;
            if (!w_on) begin
                if ((w_pend || ms_tick) && !sw_we) begin
                    w_on   <= 1'b1;
                    w_r    <= 1'b1;
                    w_pend <= 1'b0;
                    w_s    <= 2'd0;
                    w_ch   <= {CW{1'b0}};
                end
            end else if (w_s == 2'd0) begin
                if (w_read) begin
                    w_s     <= 2'd1;
                    w_r     <= 1'b0;
                    w_dirty <= wr && wr_ch == w_ch;
                end
            end else if (w_s == 2'd1) begin
                // a write to the channel between its read and its commit:
                // read it again
                w_s     <= 2'd2;
                if (wr && wr_ch == w_ch) w_dirty <= 1'b1;
            end else if (TMR != 0 && c_wait) begin
                // (the port is the bus's this clock; a write to this
                // channel makes the walker read it again)
                if (wr && wr_ch == w_ch) w_dirty <= 1'b1;
            end else begin
                w_s <= 2'd0;
                w_r <= !(commit && w_ch == LAST);
                if (commit) begin
                    if (CHANNELS > 1) w_ch <= w_ch + 1'b1;   // (one: stays 0)
                    if (w_ch == LAST) w_on <= 1'b0;
                end
            end
        end
    end
    // the commit's writes: the timer and, a clock later, due at a poll
    // falling due (none pending)
    assign tm_we = commit && !rst && POLLING != 0;
    // (due of the walker's channel as it stands, taken a clock ahead: only
    // a poll taken since clears it, and nothing sets it; its multiplexer
    // over the channels was HX8K's 32-channel path into the command copy's
    // write enable)
    reg          due_q;
    always @(posedge clk) due_q <= due[w_ch] && !(p_take && p_ch == w_ch);
    // The command is copied at the step, from the word read, while the
    // memory's register still holds it (a bus read may take the read port
    // in the step's clock; not in the read's), when the poll
    // falls due and none is (a poll taken in this clock has had its
    // command: the engine read it a clock ago). The commit raises due only
    // after a copy (`cm_did`); a write to the channel in between stops
    // the commit, and the copy, of a word that was stored, is read by no
    // one while no poll is due. (Copied at the commit, the command needed
    // a 16-bit register from the step: 16 logic cells.)
    assign cm_we = w_on && w_s == 2'd1 && reload && !(due_q && !(p_take && p_ch == w_ch)) &&
                   !rst && POLLING != 0;
    reg          cm_did;
    generate
        if (TMR != 0) begin : g_cmd_w
            always @(posedge clk) cm_did <= cm_we || (!rst && cm_did && c_wait);
        end else begin : g_cmd
            always @(posedge clk) cm_did <= cm_we;
        end
    endgenerate
    // A commit clears its channel's restart flag a clock later (the walker
    // reads that flag again no sooner than two clocks after). A POLL_CTRL write with EN = 0 to the channel in the commit's own
    // clock withdraws its due poll and restarts its timer a clock later, so
    // the commit's own raising of due and clearing of restart give way (the
    // write's compare reaches these two flip-flops, not the RAMs' write
    // enables: HX8K's 32-channel and the UP5K's critical path).
    reg          clr_rs;
    wire         wr_off = wr && wr_ch == w_ch && !wr_data[31];
    always @(posedge clk) begin
        set_due <= tm_we && cm_did && !wr_off;
        set_ch  <= w_ch;
        clr_rs  <= tm_we && !wr_off;
    end

    genvar n;
    generate
        for (n = 0; n < CHANNELS; n = n + 1) begin : g_ch
            wire wr_n = wr && wr_ch == n;
            always @(posedge clk) begin
                if (rst || POLLING == 0) begin
                    due[n]     <= 1'b0;
                    restart[n] <= 1'b1;
                    pr_ok[n]   <= 1'b0;
                end else begin
                    if (p_res && p_ch == n) pr_ok[n] <= 1'b1;
                    if (wr_n && !wr_data[31])            restart[n] <= 1'b1;
                    else if (clr_rs && set_ch == n)      restart[n] <= 1'b0;
                    if ((wr_n && !wr_data[31]) || (p_take && p_ch == n)) due[n] <= 1'b0;
                    else if (set_due && set_ch == n)                      due[n] <= 1'b1;
                end
            end
        end
    endgenerate
    assign poll_req = due;

    // ------------------------------------------------------------ POLL_RESULT
    wire [31:0] pr_wd = {p_count, p_status, p_data};
    wire [31:0] pr_rd;
`ifdef FORMAL
    wire [31:0] f_pr_n;         // the memory's word of the followed channel
`endif
    twh_ram #(.W(32), .AW(CW), .BLOCK(RAM_BLOCK)) u_res (
        .clk(clk), .we(p_res && POLLING != 0), .waddr(p_ch), .wdata(pr_wd),
        .re(1'b1), .raddr(rd_ch), .rdata(pr_rd)
`ifdef FORMAL
        , .f_addr(f_n), .f_data(f_pr_n)
`endif
    );
    wire link_err = `TWH_ST_LINK_ERR(p_status);
    always @(posedge clk) begin
        sample <= (!rst && p_res && POLLING != 0) ? {{(CHANNELS-1){1'b0}}, 1'b1} << p_ch
                                                  : {CHANNELS{1'b0}};
        error  <= !rst && p_res && POLLING != 0 && link_err;
    end

    // ------------------------------------------------------------ bus reads
    // (POLL_RESULT before the channel's first result reads 0: the mask
    // is taken with the read, so a result written in the read's clock
    // comes after it, as the memory's word does)
    reg        q_res;
    always @(posedge clk) q_res <= !rst && rd_res && pr_ok[rd_ch];
    // (the answer's data only with OK or BAD_CHECKSUM: the engine hands
    // over the bytes whatever the status, and the mask is here, in the
    // select of the read's AND-OR, not in front of the memory)
    wire        pr_dok = `TWH_ST_HAS_DATA(pr_rd[19:16]);
    assign rd_data = {32{q_res && POLLING != 0}} & {pr_rd[31:16], pr_rd[15:0] & {16{pr_dok}}};

`ifdef FORMAL
    // ================================================================ formal
    // formal/twh_polls.sby. The property that matters: whenever the engine
    // takes a channel's request in the clock it names that channel for the
    // command memory's read (scan_ch), the command read is read-only (0x40-0x44,
    // 0x46-0x49), whatever the bus writes and whenever. The core's verdict
    // on a POLL_CTRL write with EN = 1 (proven on the core, twh_core:port)
    // is assumed, and the core names only existing channels.
    reg f_ok = 1'b0;
    always @(posedge clk) if (rst) f_ok <= 1'b1;
    function f_ro;
        input [7:0] c;
        f_ro = (c >= 8'h40 && c <= 8'h44) || (c >= 8'h46 && c <= 8'h49);
    endfunction
    always @(*) begin
        // a POLL_CTRL write is a write of twh_timing's memory
        if (wr) assume(port_wr);
        // the timer's write (TMR) waits for a clock without one, and is
        // never in the sweep or in the walker's own read
        if (f_ok && !rst && pt_we) assert(TMR != 0 && !port_wr && !sw_we && !pc_rd);
        if (wr && wr_data[31]) assume(f_ro(wr_data[7:0]));
        assume(wr_ch < CHANNELS && rd_ch < CHANNELS && scan_ch < CHANNELS && p_ch < CHANNELS);
    end
    (* anyconst *) reg [CW-1:0] f_n;
    always @(*) assume(f_n < CHANNELS);
    // the reset sweep's writes, as twh_timing runs them and the core waits
    // for them: on from reset until they end, then never again before a
    // reset; no bus access, poll or result while they run (any length)
    reg                f_swo;
    always @(posedge clk) begin
        if (rst)         f_swo <= 1'b1;
        else if (!sw_we) f_swo <= 1'b0;
    end
    always @(*) begin
        if (f_ok && !rst) begin
            if (!f_swo) assume(!sw_we);
            if (f_swo) assume(!wr && !port_rd && !port_wr && !rd_res && !p_take && !p_res);
        end
    end
    // POLL_CTRL of the followed channel as twh_timing's memory holds it
    // (its proof: the sweep writes the reset value before the walker
    // starts, then each write is stored), and the walker's read of it:
    // the word as of the read's clock, or as a write in that clock leaves
    // it (twh_timing's proof asserts that of its port)
    localparam [31:0] F_PC_DEF = {1'b0, 15'd1000, 8'hAA, 8'h44};   // (written out)
    reg [31:0] f_pc, f_pa, f_pb;
    reg        f_pr = 1'b0;
    always @(posedge clk) begin
        if (rst)                    f_pc <= F_PC_DEF;
        else if (wr && wr_ch == f_n) f_pc <= wr_data;
        f_pr <= pc_rd && !port_rd && pc_ch == f_n;
        f_pa <= f_pc;
        f_pb <= (wr && wr_ch == f_n) ? wr_data : f_pc;
    end
    always @(*) if (f_ok && f_pr) assume(pc_word == f_pa || pc_word == f_pb);
    // (twh_timing's proof assumes it: the walker asks only for an
    // existing channel's, and only once the sweep's writes are over)
    always @(*) if (f_ok && pc_rd) assert(pc_ch < CHANNELS && !f_swo);
    reg [CW-1:0] f_sc;            // the channel the engine's read named a clock ago
    reg          f_sd;            // ... and that channel's request then
    reg          f_past = 1'b0;
    // POLL_RESULT of the followed channel as software is to see it: 0
    // from the reset, then the last result written
    reg [31:0] f_prs, f_prq;
    reg        f_rq;
    always @(posedge clk) begin
        f_sc   <= scan_ch;
        f_sd   <= due[scan_ch];
        f_past <= f_ok && !rst;
        if (rst)                                 f_prs <= 32'd0;
        else if (p_res && p_ch == f_n && POLLING != 0)
            f_prs <= {pr_wd[31:16], (p_status == `TWH_ST_OK || p_status == `TWH_ST_BAD_CHECKSUM) ?
                                    pr_wd[15:0] : 16'd0};
        f_prq  <= f_prs;
        f_rq   <= !rst && rd_res && rd_ch == f_n;
    end
    // the step's timer word and whether it copied the command
    reg [15:0] f_tmw;
    reg        f_cp;
    always @(posedge clk) begin
        if (w_on && w_s == 2'd1) begin
            f_tmw <= tm_wd;
            f_cp  <= cm_we;
        end
    end
    reg f_cw = 1'b0;
    always @(posedge clk) f_cw <= c_wait;
    always @(*) begin
        if (f_ok && POLLING != 0) begin
            // every POLL_CTRL word that polls names a read-only command
            if (f_pc[31]) assert(f_ro(f_pc[7:0]));
            // EN = 0 stored: no poll due or about to fall due (a write with
            // EN = 0 withdraws it at once, one in the commit's clock too)
            if (!f_pc[31])
                assert(!due[f_n] && !(set_due && set_ch == f_n));
            // nothing walks or falls due before the sweep is over
            if (f_swo) assert(!w_on && due == {CHANNELS{1'b0}} && !set_due);
            // the walker's word is the memory's, unless a write met its read;
            // the command its step took is read-only when it falls due
            if (w_on && w_s == 2'd1) assert(f_pr == (w_ch == f_n));
            if (w_on && w_s == 2'd1 && !w_dirty) assert(rs_q == restart[w_ch]);
            if (w_on && w_s == 2'd1 && !w_dirty && w_ch == f_n) assert(pc_word == f_pc);
            // (the step's word, if it polls, was stored, so its command is
            // read-only; a copy leaves no poll due until the commit)
            if (w_on && w_s == 2'd1 && w_ch == f_n && pc_word[31]) assert(f_ro(pc_word[7:0]));
            if (cm_did) assert(w_on && w_s == 2'd2);
            if (cm_did && w_ch == f_n) assert(f_ro(g_mem.cm_mem[f_n][7:0]) && !due[f_n]);
            // (while the commit waits, TMR: the copied word still polls,
            // unless a write to the channel has made the walker read again)
            if (cm_did && !w_dirty && w_ch == f_n) assert(f_pc[31]);
            // the commit writes the step's timer and raises due after the
            // step's copy, however long it waited (TMR)
            if (w_on && w_s == 2'd2) assert(q_tm == f_tmw && cm_did == f_cp);
            if (w_on && w_s == 2'd2 && !w_dirty) assert(due_q == due[w_ch]);
            // (set_due follows a commit by a clock, the walker then reading)
            if (set_due) assert(!w_on || w_s == 2'd0);
            if (w_on) assert(w_s != 2'd3);
            assert(w_r == (w_on && w_s == 2'd0));
            if (w_on) assert(w_ch < CHANNELS);
            // a due poll's command, and one about to fall due, is read-only
            if (due[f_n]) assert(f_ro(g_mem.cm_mem[f_n][7:0]));
            if (set_due && set_ch == f_n) assert(f_ro(g_mem.cm_mem[f_n][7:0]) && !due[f_n]);
        end
        // the engine's contract: a request with the command read for it
        if (f_past && f_sc == f_n && f_sd) assert(f_ro(poll_cmd[7:0]));
        // a POLL_RESULT read answers the channel's word as it stood in the
        // read's clock (0 before its first result since the reset): a
        // result written in that clock comes after it
        if (f_past && f_rq && POLLING != 0) assert(rd_data == f_prq);
        // (the memory holds the word once the channel has had a result)
        if (f_ok && POLLING != 0)
            assert(pr_ok[f_n] ? f_pr_n[31:16] == f_prs[31:16] &&
                                (f_prs[19:16] == `TWH_ST_OK || f_prs[19:16] == `TWH_ST_BAD_CHECKSUM ?
                                 f_pr_n[15:0] == f_prs[15:0] : f_prs[15:0] == 16'd0)
                              : f_prs == 32'd0);
        if (POLLING == 0) assert(due == {CHANNELS{1'b0}});
    end
    always @(posedge clk) begin
        if (f_ok && !rst) begin
            cover(p_take && p_ch == f_n);
            cover(set_due && set_ch == f_n);
            // (a commit that waited for a clock without a bus write, TMR)
            if (TMR != 0) cover(f_cw && tm_we && cm_did);
        end
    end
`endif
endmodule
`default_nettype wire
