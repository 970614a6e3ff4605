// One engine for every channel: each channel's sequencer and receiver state
// is a word of block RAM, and a five-stage pipeline steps every channel in
// turn once per carrier period (1 us), so all channels run concurrently from
// shared logic. Per channel, only what must run at the clock stays in
// flip-flops: the pin logic (twh_engine_pin: synchroniser, glitch filter,
// the window flags, the drive for the next period), a flush's flag, and
// copies of what the core reads of every channel at once (phase, queue
// not empty / holding an unstarted entry, a flush's count left).
//
// The scan. The carrier's tick starts a scan: channel c is read (S0) in the
// (c+1)th clock after the tick, its words come out of the RAMs (S1) and
// are registered (S2; its state word's late part, its queue head, its
// length and its poll's command are read at S1 into their RAMs' own
// registers), the next word and the queue's moves
// are computed from them and registered (S3; a result handed over goes
// out on m_res_* in the clock it is computed, S2's), and written three
// clocks after the read, while the drive for the next period is computed
// from the new word (S4: the pin takes it a clock later). A channel is read
// again a carrier period (P clocks, P >= 4) after its last read, so it
// always reads what its last visit wrote; a channel's pin takes its drive
// at a fixed number of ticks after its visit (one tick if it lands before
// the next tick, else two; the clock floor below keeps that number the same
// at every visit), so every phase lasts exactly its number of periods on
// the line.
//
// Clock floor (checked at elaboration): with a whole number of MHz, P >= 4,
// P >= CHANNELS (a scan ends before the next begins) and CHANNELS + 4 < 2P
// (a drive lands within two ticks); with a fraction (periods of P and P+1
// clocks), P >= CHANNELS + 5, so every drive lands before the next tick.
//
// Commands. Each channel has a queue of QDEPTH entries in one RAM (its slice
// {channel, index}), its pointers in a control word of its own (a second
// RAM, read with the state word), moved only at its visit: the
// port's command is taken at its channel's visit (within a carrier period
// when its queue has room) and written at the tail then; until it is
// taken, it waits at the port (held there: AXI-Stream). A command for an idle
// channel is never held behind one for a busy channel, and each channel
// keeps its own order. An entry stays at the head of its queue until its
// result is handed over, so the frame's bytes and the result's code and tag
// are read from the queue at every visit and never copied into the state.
// A command with a skip code (BLOCKED or CANCELLED, the core's verdicts) is
// answered with that status without reaching the line; so is every entry a
// flush (cancel) found queued and not yet started (CANCELLED: a count per
// channel).
//
// Polls. A channel's due poll (poll_req, its command from poll_cmd) and its
// queued commands take turns. A poll has no queue entry: its frame goes into
// its state word at its start, and its result leaves on p_res at its
// listen's end, never held back. Nothing starts while `enable` is 0 but
// skipped and cancelled commands, which are still answered.
//
// Results. A channel whose result is ready hands it over (m_res_*, from its
// word and its queue's head at the visit's S2) at a visit in whose clock
// m_res_ready says there is room (the result FIFO not full) and no other
// channel holds the claim (the first channel refused takes it), and keeps
// it (holding its next charge back) until then. So m_res_valid is raised
// only in a clock with m_res_ready: the result is taken in that clock.
//
// Phase lengths (microseconds, already clamped) come from a timing RAM of
// eight words a channel, read at every visit for the field the channel's
// next programmable phase needs (from its phase, kept per channel in
// flip-flops, `ph_q`, which is also the `phase` output).
//
// Phases and line drive follow the spec's table and NOTES.md (codes in
// twh_defs.vh); the receiver's step is proven equal to formal/twh_rx.v,
// the reference model (twh_rx:equiv).
`default_nettype none
`include "twh_defs.vh"
module twh_engine #(
    parameter integer CLK_HZ    = 48_000_000,
    parameter integer CHANNELS  = 3,
    parameter integer TAG_W     = 8,
    parameter integer QDEPTH    = 4,
    parameter integer GLITCH_NS = 100,
    // 1: the engine's RAMs in block RAM at any depth (iCE40: a shallow
    // one would otherwise be flip-flops); 0: in LUT RAM at any depth
    // (ECP5: faster to read than a block RAM, twh_ram)
    parameter integer RAM_BLOCK = 1,
    // 0: the clock floor is checked by the core's twh_carrier instead
    parameter integer CHECK_FLOOR = 1,
    // 1: every channel runs the spec's default lengths (the core's
    // PROG_TIMING = 0): no timing RAM, t_* unused, the length a decode of
    // the field registered where the RAM's output register would be
    parameter integer FIXED_TIMING = 0,
    // 0: no poller (the core's POLLING = 0): poll_req and poll_cmd unused,
    // and the word's poll fields (PL, CT) are 0, so the step has no poll
    // frame, no poll checksum and no poll count
    parameter integer POLLING = 1,
    // derived, not to be set
    parameter integer CW        = (CHANNELS > 1) ? $clog2(CHANNELS) : 1
) (
    input  wire                clk,
    input  wire                rst,
    input  wire                tick,           // twh_carrier's
    input  wire                fall,
    input  wire [CHANNELS-1:0] cfg_idle_charge,  // per channel: carrier while idle
    input  wire                enable,         // 0: only skipped commands are answered
    input  wire                cancel,         // flush: queued commands not yet started
                                               // are answered CANCELLED
    input  wire [CHANNELS-1:0] poll_req,       // per channel: its poll is due (armed, enabled)
    input  wire [15:0]         poll_cmd,       // {payload, code} of the poll of the channel
                                               // at scan_ch a clock before (a RAM's read)
    output wire [CW-1:0]       scan_ch,        // the channel S1 takes (a poll command's
                                               // read, so the RAM's own register is S2's)
    // phase lengths, microseconds, clamped: field 1 charge .. 6 turnaround
    input  wire                t_we,
    input  wire [CW-1:0]       t_ch,
    input  wire [2:0]          t_fld,
    input  wire [15:0]         t_len,
    // commands, to the channel's queue: taken (s_cmd_ready) at the
    // channel's visit; held, with s_cmd_ch, until taken
    input  wire                s_cmd_valid,
    output wire                s_cmd_ready,
    input  wire [CW-1:0]       s_cmd_ch,
    input  wire [7:0]          s_cmd_code,
    input  wire [15:0]         s_cmd_payload,
    input  wire [TAG_W-1:0]    s_cmd_tag,
    input  wire [3:0]          s_cmd_skip,     // 0, or the status to answer the command
                                               // with unstarted: BLOCKED or CANCELLED
    // results
    // (valid only with ready, in the visit's S2 clock; ready must not
    // depend on valid)
    output wire                m_res_valid,
    input  wire                m_res_ready,
    output wire [CW-1:0]       m_res_ch,
    output wire [7:0]          m_res_code,
    output wire [15:0]         m_res_data,
    output wire [3:0]          m_res_status,
    output wire [TAG_W-1:0]    m_res_tag,
    // the pins
    output wire [CHANNELS-1:0] line_o,
    output wire [CHANNELS-1:0] line_oe,
    input  wire [CHANNELS-1:0] line_i,
    output wire [CHANNELS-1:0] busy,           // a command queued or running, or a
                                               // transaction on the line (a poll's too)
    output wire [CHANNELS-1:0] pending,        // a queued command not started yet
    // pending[st_ch] for STATE's read: the same flag, with the command
    // going in compared by channel rather than multiplexed (st_ch below
    // CHANNELS)
    input  wire [CW-1:0]       st_ch,
    output wire                st_pend,
    output wire                cancelling,     // a flush's cancels are still to come
    output wire [CHANNELS*3-1:0] phase,        // each channel's phase as its last visit left it
    output wire [CHANNELS*3-1:0] fld,          // the timing field its next phase loads
    // each visit's write-back: its channel and the phase it leaves
    output wire                  sc_v,
    output wire [CW-1:0]         sc_ch,
    output wire [2:0]            sc_ph,
    output wire [1:0]            sc_tr,        // the TIMING register its successor's field is in
    // polls: a poll taken (its channel's due flag is spent), a poll's result;
    // one-clock strobes with their channel, never held back, straight from
    // the step's S2 (twh_polls registers what it keeps)
    output wire                p_take,
    output wire                p_res,
    output wire [CW-1:0]       p_ch,
    output wire [15:0]         p_data,
    output wire [3:0]          p_status,
    output wire [11:0]         p_count         // the channel's polls completed, this one included
);
    localparam integer P    = CLK_HZ / 1_000_000;
    localparam integer FRAC = CLK_HZ % 1_000_000;
    localparam integer QW   = (QDEPTH > 1) ? $clog2(QDEPTH) : 1;
    localparam integer CN   = 1 << CW;
    // One channel: its visits are P >= 4 clocks apart, so the early part's
    // and the control word's RAM registers hold the visit's words from S1
    // through S2 when read only for the visit, and S2 takes them as they
    // are, with no copy in flip-flops but for the phase and "a result
    // waits" (below): 56 fewer, each a logic cell of its own, as a RAM
    // output into a flip-flop packs with no LUT. The
    // first scan after a reset then reads the reset words from the
    // memories' second word, which the clock after a reset writes
    // (`s3_rw`), rather than taking them by a multiplexer.
    localparam integer HOLD = (CHANNELS == 1) ? 1 : 0;
    // ... and without polls the frame's bytes are the queue head's as it
    // is, so S3 takes them from the queue RAM's register, read only for
    // the visit too, rather than from a copy (below)
    localparam integer HOLD_Q = (HOLD != 0 && POLLING == 0) ? 1 : 0;

    // The ranges (tb/test_params.py reads them and checks that every tool
    // names the error module of a value outside them). The clock floor is
    // docs/engine.md's: with a whole number of MHz P >= 4, P >= CHANNELS and
    // CHANNELS + 4 < 2P; with a fraction P >= CHANNELS + 5.
    localparam integer CHANNELS_MIN = 1;
    localparam integer CHANNELS_MAX = 32;
    generate
        if (CHANNELS < CHANNELS_MIN || CHANNELS > CHANNELS_MAX) begin : g_bad_channels
            twh_error_CHANNELS_must_be_1_to_32 u_err ();
        end else if (CHECK_FLOOR != 0 && !`TWH_ENGINE_FLOOR_OK(P, FRAC, CHANNELS)) begin : g_bad_floor
            twh_error_CLK_HZ_below_the_engine_floor_for_CHANNELS u_err ();
        end
        if ((1 << QW) != QDEPTH || QDEPTH < 2) begin : g_bad_qdepth
            twh_error_QDEPTH_must_be_a_power_of_two_of_at_least_2 u_err ();
        end
    endgenerate

    // ------------------------------------------------------------ state word
    // (as the step sees it; stored in two parts, below, the phase in the
    // control word)
    // [2:0] phase, [18:3] periods left (this one included), [19] a result
    // waits, [20] the line read low during sync, [21] high during preamble,
    // then the union U, by phase: the receiver's fields in listen; the
    // command's bit and byte in the command phase (and a poll's frame, which
    // has no queue entry); the result (data, status) while it waits. Then [PL]:
    // the transaction is a poll (from its charge to its listen's end); [CT]
    // the channel's count of polls completed.
    localparam integer U0 = 22;
    // (the receiver's fields: twh_defs.vh, TWH_RX_*)
    localparam integer SH = U0 + `TWH_RX_SH;   // 24: received data bits, first in [7:0]
    localparam integer BN = U0 + `TWH_RX_BN;   // 4: bit of the character (rx and tx)
    localparam integer NB = U0 + `TWH_RX_NB;   // 2: bytes received; tx: frame byte
    localparam integer PL = U0 + `TWH_RX_W;    // the transaction is a poll (its frame in SH)
    localparam integer CT = U0 + 46;     // 12: polls completed (POLL_RESULT.COUNT)
    localparam integer W  = U0 + 58;     // 80 (77 stored, with a verdict bit: below)
    localparam integer UW = `TWH_RX_W;   // the union's width: the receiver's word
    localparam integer RS = U0 + 16;     // 4: the waiting result's status (data in U[15:0])
    localparam [W-1:0] W_RESET = {{(W-19){1'b0}}, `TWH_TURNAROUND_MIN + 16'd1, `TWH_PH_IDLE};
    // the bits a build without polls keeps 0 (PL, CT): masked as the word
    // is read, so synthesis drops what would step them
    localparam [W-1:0] W_POLL = ({{(W-1){1'b0}}, 1'b1} << PL) | ({{(W-12){1'b0}}, 12'hFFF} << CT);
    localparam [W-1:0] W_KEEP = (POLLING != 0) ? {W{1'b1}} : ~W_POLL;

    // The word is kept in two RAMs, by when the pipeline needs its bits.
    // The early part (EW bits) is read at S0, because S1 decodes it (last
    // period, idle's end, the receiver's decodes and the answer's verdict),
    // and is copied into S2's flip-flops: the count, the flags, the
    // receiver's counters and flags, the poll flag, the poll count's high
    // bits, and (not a field of the word) whether its data bits carry a
    // good checksum, computed at the write (twh_rx_sum) so that S1 needs
    // neither the data bits nor an adder. The late part (LW bits) is what
    // the step reads only as data (the receiver's data bits, which also
    // hold a poll's frame and a waiting result, and the poll count's low
    // bits): read at S1, its RAM's own register is S2's operand, with no
    // copy. The phase is not in either: it is the control word's. Three
    // and two iCE40 blocks of 16 bits, as the 80-bit word took.
    // The parts are the word's bits in their order (twh_defs.vh lays the
    // receiver's data bits below its counters and flags): early [79:76]
    // (the poll count's high bits), [67:46] (the poll flag, the receiver's
    // flags, bytes, votes, bit, marks and bit clock), [21:3] (line flags,
    // result waiting, the count); late [75:68] (the poll count's low bits)
    // and [45:22] (the data bits). Plain slices, so the word is wiring.
    localparam integer EW = 46;
    localparam integer LW = 32;
    // (as macros, not functions: Icarus calls a function at every change
    // of its argument, and the regression ran slower with them)
`define TWH_E_OF(x) {x[W-1 : CT+8], x[PL : SH+24], x[SH-1 : 3]}
`define TWH_L_OF(x) {x[CT+7 : CT], x[SH+23 : SH]}

    // ------------------------------------------------------------ control word
    // Each channel's queue pointers and flags, a word of its own in block
    // RAM (read with its state word, so the queue's and the timing RAM's
    // reads at S1 take their addresses from its output): head, tail,
    // count, the flush's count of entries to cancel, the head started
    // (`act`), a due poll goes next (`pref`), and the phase (the timing
    // field the next phase loads is decoded from it).
    localparam integer C_HD = 0;            // QW: the head entry
    localparam integer C_TL = QW;           // QW: the next free entry
    localparam integer C_CN = 2 * QW;       // QW+1: entries queued (<= QDEPTH)
    localparam integer C_CC = 3 * QW + 1;   // QW+1: entries a flush cancelled, not started
    localparam integer C_AC = 4 * QW + 2;   // the head entry is started (running, or its
                                            // result waits)
    localparam integer C_PF = 4 * QW + 3;   // a due poll goes before a queued command
    localparam integer C_PH = 4 * QW + 4;   // 3: the phase
    localparam integer CTW  = 4 * QW + 7;   // 15 at QDEPTH 4: one iCE40 block
    localparam [CTW-1:0] CTL_RESET = {`TWH_PH_IDLE, {(4 * QW + 4){1'b0}}};

    // ------------------------------------------------------------ per channel
    // (flip-flops; what the core reads of every channel at once, copied
    // from the control word at each visit's write, and a flush's flag)
    reg  [CHANNELS*3-1:0] ph_q;          // each channel's phase, as its last visit wrote it
    reg  [CHANNELS-1:0]  busy_m;         // its queue is not empty, or it is not idle
    reg  [CHANNELS-1:0]  pend_m;         // an entry queued and not started
    reg  [CN-1:0]        cz_m;           // a flush's count left
    reg  [CN-1:0]        fpend;          // a flush came since its last visit's S1: its
                                         // next visit counts what the flush cancels
    wire [CHANNELS-1:0]  seen;

    // ------------------------------------------------------------ scan
    localparam [CW-1:0] LAST_CH = CHANNELS[CW-1:0] - 1'b1;
    reg          s0_v;
    reg [CW-1:0] s0_ch;
    always @(posedge clk) begin
        if (rst) begin
            s0_v  <= 1'b0;
            s0_ch <= {CW{1'b0}};
        end else if (tick) begin
            s0_v  <= 1'b1;
            s0_ch <= {CW{1'b0}};
        end else if (s0_v) begin
            s0_v  <= (s0_ch != LAST_CH);
            // (one channel: s0_ch stays 0, so every stage's channel is a
            // constant and the channel compares and addresses go)
            if (CHANNELS > 1) s0_ch <= s0_ch + 1'b1;
        end
    end

    // Which channel each stage holds, as a shift chain from the tick
    // rather than a compare of the stage's channel a channel: channel n is
    // at S0 n+1 clocks after the tick, so sc[i] (the tick i+1 clocks ago)
    // marks channel n at S0 with sc[n], at S1 with sc[n+1], at S2 with
    // sc[n+2], at S3 with sc[n+3] and at S4 with sc[n+4]. A per-channel
    // flag is read at a stage through it too (an AND-OR of flag and mark:
    // shallower than a multiplexer on the stage's channel number, whose
    // fan-out was the 32-channel critical path).
    reg [CHANNELS+3:0] sc;
    always @(posedge clk) begin
        if (rst) sc <= {(CHANNELS+4){1'b0}};
        else     sc <= {sc[CHANNELS+2:0], tick};
    end
    wire [CHANNELS-1:0] at0 = sc[CHANNELS-1:0];
    wire [CHANNELS-1:0] at1 = sc[CHANNELS:1];
    wire [CHANNELS-1:0] at2 = sc[CHANNELS+1:2];

    // the timing field the phase after `p` loads (twh_defs.vh)
    function [2:0] fld_of;
        input [2:0] p;
        fld_of = `TWH_FLD_OF(p);
    endfunction
    // a field's default length (twh_defs.vh)
    function [15:0] fixed_len;
        input [2:0] f;
        fixed_len = `TWH_FLD_DEF(f);
    endfunction

    // ------------------------------------------------------------ RAMs
    reg           s1_v, s1_init, s1_env;
    reg [CW-1:0]  s1_ch;
    assign scan_ch = s1_ch;
    wire [EW-1:0] e_rd;
    wire [LW-1:0] l_rd;
    reg  [W-1:0]  s3_word;
    // The verdict stored with a word is that of the data bits the visit
    // read (the previous write's), taken at S2 from the late part's RAM
    // register into a flip-flop: at S3, from the new word, its adder stood
    // between S3's register and the state RAM's write data (the ECP5-25F's
    // one-channel path). It is the new word's own whenever it is read: only
    // an answer of three characters (twh_rx_dec's `full`) reads it, and the
    // step that makes the third character and every step after it leave the
    // data bits as they were (twh_rx_step: a stop bit, then done). In the
    // first scan after a reset the late part is not the channel's, and
    // the verdict is 0.
    reg           s3_sum;
    reg           s3_v;
    reg  [CW-1:0] s3_ch;
    wire [EW-1:0] s3_e = {s3_sum, `TWH_E_OF(s3_word)};
    wire [LW-1:0] s3_l = `TWH_L_OF(s3_word);
    // (HOLD: the reset words' write, the clock after a reset, at the
    // second word; the first scan's reads, at S0, take it)
    reg           s3_rw;
    reg           s0_init;
    wire          e_we = s3_v || s3_rw;
    localparam integer RSV_I = 1;
    localparam [CW-1:0] RSV = RSV_I[CW-1:0];
    wire [CW-1:0] e_wa = s3_rw ? RSV : s3_ch;
    wire [CW-1:0] e_ra = (HOLD != 0 && !s0_init) ? RSV : s0_ch;
    wire          e_re = (HOLD != 0) ? s0_v : 1'b1;
`ifdef FORMAL
    wire [EW-1:0] f_e_rsv;      // (HOLD) the memories' second word
    wire [CTW-1:0] f_c_rsv;
`endif
    twh_ram #(.W(EW), .AW(CW), .BLOCK(RAM_BLOCK)) u_state (
        .clk(clk), .we(e_we), .waddr(e_wa), .wdata(s3_e),
        .re(e_re), .raddr(e_ra), .rdata(e_rd)
`ifdef FORMAL
        , .f_addr(RSV), .f_data(f_e_rsv)
`endif
    );
    // (read a clock after the early part: S1's channel; a channel's write
    // and its next read are P - 2 >= 2 clocks apart). Read only for a
    // visit, so that its word changes only then: read every clock, it made
    // the Icarus regression about a tenth slower, as each change goes
    // through the step's word. (The other RAMs read every clock: a read
    // enable shared by all of them cost the HX8K at 32 channels about 9
    // MHz of its median Fmax, by placement.)
    twh_ram #(.W(LW), .AW(CW), .BLOCK(RAM_BLOCK)) u_late (
        .clk(clk), .we(s3_v), .waddr(s3_ch), .wdata(s3_l),
        .re(s1_v), .raddr(s1_ch), .rdata(l_rd)
    );

    // The control word is read with the state word (S0) and written with
    // it at S3; its RAM's own register is S1's (`c_rd`), so the queue's and
    // the timing RAM's reads at S1 take their addresses from it, and no
    // flip-flop copy of it stands between S1 and S2's. (A channel's write
    // and its next read are P - 3 >= 1 clocks apart.)
    wire [CTW-1:0] c_rd;
    reg  [CTW-1:0] s3_ctl;
    twh_ram #(.W(CTW), .AW(CW), .BLOCK(RAM_BLOCK)) u_ctl (
        .clk(clk), .we(e_we), .waddr(e_wa), .wdata(s3_ctl),
        .re(e_re), .raddr(e_ra), .rdata(c_rd)
`ifdef FORMAL
        , .f_addr(RSV), .f_data(f_c_rsv)
`endif
    );
    // Reset needs no flag a channel: every scan visits and writes every
    // channel, so a channel's words are its own from the second scan after
    // reset on, and the first takes the reset words. run1: a tick came
    // since reset (a scan starting now is not the first); run2: two did
    // (the scan under way is not the first).
    reg            run1, run2;
    always @(posedge clk) begin
        if (rst) begin
            run1 <= 1'b0;
            run2 <= 1'b0;
        end else if (tick) begin
            run1 <= 1'b1;
            run2 <= run1;
        end
    end
    // (of the channel S0 takes next: the first channel's S0 is the tick's
    // next clock)
    wire           pre_init = tick ? run1 : run2;
    always @(posedge clk) s0_init <= pre_init;

    // An entry: code, payload (its high byte 0 in a 3-byte command), tag
    // and the skip code in two bits (none, BLOCKED, CANCELLED: the only
    // ones the core gives), 31 bits at the core's TAG_W of 5, so two iCE40
    // blocks of 16 bits. The frame's checksum is taken after the read (S2).
    //
    // The port's command is taken at its channel's visit, when the queue
    // has room, and written at the queue's tail in that clock (S2), with
    // the control word's step; until then it waits at the port (the core's
    // command FIFO holds it at its head; s_cmd_ch holds while s_cmd_valid
    // and not taken, as AXI-Stream has it). So the queue's pointers are
    // only ever moved by a visit, and no register here holds a command:
    // whether the visit takes it is decided at S1 (s2_take: the channel
    // and the queue's count), and the port's ready is that flip-flop.
    localparam integer QE = 8 + 16 + TAG_W + 2;
    localparam [1:0] SK_NONE = 2'd0, SK_BLOCKED = 2'd1, SK_CANCELLED = 2'd2;
    wire [QE-1:0] q_rd;
    wire [1:0]    push_sk = (s_cmd_skip == `TWH_ST_CANCELLED) ? SK_CANCELLED :
                            (s_cmd_skip == `TWH_ST_BLOCKED)   ? SK_BLOCKED : SK_NONE;
    wire [QE-1:0] p_e = {s_cmd_code, s_cmd_code[7] ? s_cmd_payload[15:8] : 8'd0, s_cmd_payload[7:0],
                         s_cmd_tag, push_sk};
    reg           s2_take;      // the visit at S2 takes the port's command ...
    wire          ins;          // ... and it is there: written at the tail
    wire [QW-1:0] ins_tl;       // ... at this entry
    reg           s3_ins;       // (the write a clock on: the copies the core reads)
`ifdef FORMAL
    wire [QW-1:0] f_qi;         // the tracked channel's tracked entry (below)
    wire [QE-1:0] f_qm;         // ... as the queue RAM holds it
    wire [2:0]    f_tf;         // the tracked channel's tracked timing field
    wire [15:0]   f_tm;         // ... as the timing RAM holds it
`endif
    twh_ram #(.W(QE), .AW(CW + QW), .BLOCK(RAM_BLOCK)) u_queue (
        .clk(clk), .we(ins), .waddr({s2_ch, ins_tl}), .wdata(p_e),
        .re((HOLD_Q != 0) ? s1_v : 1'b1), .raddr({s1_ch, c_rd[C_HD +: QW]}), .rdata(q_rd)
`ifdef FORMAL
        , .f_addr({f_ch, f_qi}), .f_data(f_qm)
`endif
    );
    assign s_cmd_ready = s2_take;

    // The timing RAM is read a clock later than the state word (S1, from the
    // registered control word), so its own output register is the length's
    // S2 register: no copy of it in flip-flops. (The length is data into
    // the step's multiplexer, not a select, so the RAM's slower output is
    // off the step's longest paths.)
    wire [15:0] t_rd;
    generate
        if (FIXED_TIMING == 0) begin : g_tram
            twh_ram #(.W(16), .AW(CW + 3), .BLOCK(RAM_BLOCK)) u_timing (
                .clk(clk), .we(t_we), .waddr({t_ch, t_fld}), .wdata(t_len),
                .re(1'b1), .raddr({s1_ch, fld_of(c_rd[C_PH +: 3])}), .rdata(t_rd)
`ifdef FORMAL
                , .f_addr({f_ch, f_tf}), .f_data(f_tm)
`endif
            );
        end else begin : g_tfix
            // the defaults lie in their windows: what twh_timing would hand
            // over with PROG = 0 (a block RAM fewer, and no fetch to feed it)
            reg [15:0] t_fx;
            always @(posedge clk) t_fx <= fixed_len(fld_of(c_rd[C_PH +: 3]));
            assign t_rd = t_fx;
`ifdef FORMAL
            assign f_tm = fixed_len(f_tf);
`endif
            // verilator lint_off UNUSEDSIGNAL
            wire unused_t = t_we ^ (^t_ch) ^ (^t_fld) ^ (^t_len);
            // verilator lint_on UNUSEDSIGNAL
        end
    endgenerate

    // ------------------------------------------------------------ S1, S2
    always @(posedge clk) begin
        s1_v    <= !rst && s0_v;
        s1_ch   <= s0_ch;
        s1_init <= s0_init;
        s1_env  <= |(seen & at0);
    end
    // The channel's control word as its last visit wrote it is the RAM's
    // (c_rd), or the reset word (empty queue, no cancels, idle) in the
    // first scan after a reset: what S1 decides from it takes s1_init in,
    // and S2's copy is reset to it (a flip-flop's reset, not a LUT). The
    // queue's and the timing RAM's read addresses take the RAM's word as
    // it is: in the first scan the step uses neither the head, the queue
    // being empty, nor the length, the reset word's idle having periods
    // left.
    // a flush since the channel's last visit (or in this clock) cancels
    // what its queue holds and has not started; else the count left stands.
    // The channel's flag is taken a clock ahead, at S0, so the AND-OR of
    // every channel's flag and the scan's mark ends in a flip-flop rather
    // than in S1's decisions (at 32 channels on the HX8K and at eight on
    // the ECP5-25F, from the scan's bit through the flags into the start,
    // among the longest paths). A flush in S0's clock sets it even when the
    // channel had nothing to cancel then: a queue takes a command only at
    // its own visit's S2, so it has none by S1 either, and the count is
    // the same, 0 (its count left is 0 too: never more than the entries
    // not started).
    reg           s1_fl;
    always @(posedge clk) s1_fl <= !rst && (|(fpend[CHANNELS-1:0] & at0) || cancel);
    wire [QW:0]   c1_cnt = c_rd[C_CN +: QW+1];
    wire [QW:0]   c1_cc  = (s1_fl || cancel) ? c1_cnt - {{QW{1'b0}}, c_rd[C_AC]}
                                             : c_rd[C_CC +: QW+1];
    reg           s2_v, s2_env, s2_last;
    // a bit of the command's frame ends with this period (cnt[4:0] == 1),
    // taken at S1: from the count's RAM output (one channel) or its copy
    // through the compare into the frame's position, the UP5K's longest
    // path at one channel at three seeds of five
    reg           s2_bl;
    // the word as S1 has it: the early part, the phase from the control
    // word, no data bits
    wire [W-1:0]  st_rd = {e_rd[EW-2 -: 4], 8'd0, e_rd[EW-6 : SH-3], 24'd0, e_rd[SH-4 : 0],
                           c_rd[C_PH +: 3]};
    // ... or the state after reset for a channel not yet visited since:
    // idle, the minimum turnaround (and one) before a charge
    // verilator lint_off UNUSEDSIGNAL
    wire [W-1:0]  w1 = (s1_init ? st_rd : W_RESET) & W_KEEP;   // (the early part's bits)
    // verilator lint_on UNUSEDSIGNAL
    wire [EW-2:0] e1 = `TWH_E_OF(w1);
    // verilator lint_off UNUSEDSIGNAL
    wire [W-1:0]  w1h = st_rd & W_KEEP;
    wire [EW-2:0] e1h = `TWH_E_OF(w1h);
    // verilator lint_on UNUSEDSIGNAL
    // (HOLD: "a result waits" from its copy, as it goes into the result
    // FIFO's push: from the RAM's slower output that was the HX8K's
    // longest path at four seeds of five)
    assign        s2_e = (HOLD != 0) ? {e1h[EW-2:17], s2_eq[16], e1h[15:0]} : s2_eq;
    // the receiver's decodes and the answer's verdict, a clock ahead of
    // the step (off its path); only a word in listen uses them, and that
    // word is always the RAM's (the reset word is idle)
    wire [8:0]    d1_rx;
    wire [3:0]    d1_status;
    twh_rx_dec u_rdec (.rx(st_rd[U0 +: UW]), .sync_low(st_rd[20]), .pre_high(st_rd[21]),
                       .sum_ok(e_rd[EW-1]), .dec(d1_rx), .status(d1_status));
    // (the answer's data is its bytes when OK or BAD_CHECKSUM)
    wire          d1_ok = `TWH_ST_HAS_DATA(d1_status);
    reg           s2_pend;
    reg [8:0]     s2_rdec;
    reg [3:0]     s2_status;
    reg           s2_ok;
    reg [CW-1:0]  s2_ch;
    reg           s2_init;
    reg [EW-2:0]  s2_eq;          // the early part (without the verdict) ...
    wire [EW-2:0] s2_e;           // ... or (HOLD) the RAM's register
    wire [QE-1:0] s2_q = q_rd;    // (the queue RAM's register: read at S1)
    wire [15:0]   s2_len = t_rd;    // (the timing RAM's register: read at S1)
    reg           s2_cc;
    reg [QW:0]    s2_ccnt;
    reg [CTW-1:0] s2_cq;
    // (HOLD: the phase, the step's widest select, from its copy: from the
    // RAM's slower output it was among the HX8K's longest paths)
    wire [CTW-1:0] s2_c = (HOLD != 0) ? {s2_cq[C_PH +: 3], c_rd[C_PH-1:0]} : s2_cq;
    // What an idle channel starts is decided at S1, a clock ahead of the
    // step whose count load and frame it steers (decided at S2, the poll's
    // turn and the queue's count through the start into the count's load
    // were the UP5K's longest paths at three channels). A channel may start
    // in its idle's last period with no result waiting (s2_idle_go, kept
    // apart: folded into the registers below, it made S1's decision, from
    // the poll request's read through it, the ECP5-25F's longest path at
    // eight channels). A due poll may go while `enable` is 1; a queued
    // command goes unless the engine is off and it would reach the line
    // (its skip code, or a flush's cancel, says whether); a poll goes on
    // its turn or when no command is queued (with `enable` 1 a queued
    // command always may go). `enable` is taken here, into the step's own
    // flip-flops, off CTRL's fan-out. Only the head
    // entry's skip code comes with the step (the queue RAM's register), so
    // a command's start is split by it: s2_sq starts it whatever its skip
    // (enabled, or cancelled), s2_sqk only if it has one (the engine off),
    // and s2_sqn sends it to the line unless it has one (s2_sq without a
    // flush's cancel: a flip-flop of its own, so the line start is one
    // LUT of the idle's end and the skip code).
    // The poll's request is taken in the clock twh_polls reads its command
    // (scan_ch), so a poll-control write in between starts at most the
    // poll that was due, with the command it was checked with.
    wire          i1_go = s1_init && (st_rd[2:0] == `TWH_PH_IDLE) && (st_rd[18:4] == 15'd0) &&
                          !st_rd[19];
    wire          i1_en = enable;
    wire          i1_pg = |(poll_req & at1) && (POLLING != 0) && i1_en;
    wire          i1_ne = s1_init && (c1_cnt != {(QW+1){1'b0}});
    // (c1_cc != 0 without its subtractor: cnt - act is 0 exactly when cnt
    // is act; the subtractor's carry in front of the start's decision was
    // the UP5K's longest path at one channel)
    wire          i1_cc = s1_init && ((s1_fl || cancel) ? (c1_cnt != {{QW{1'b0}}, c_rd[C_AC]})
                                                        : (c_rd[C_CC +: QW+1] != {(QW+1){1'b0}}));
    wire          i1_pf = s1_init && c_rd[C_PF];
    wire          i1_cq = i1_ne && !(i1_pg && i1_pf);   // the head's turn
    reg           s2_sp, s2_sq, s2_sqk, s2_sqn, s2_idle_go;
    // The count's next value is chosen at S2 by selects decoded here, a
    // clock ahead, from the phase and the last period as S2 has them (from
    // the phase's copy through its decode and the start into the count's
    // load had been the UP5K's longest path at one channel, four seeds of
    // five): the length (s2_klen, or the head's start onto the line,
    // start_l, which waits for the head's skip code), a
    // constant (s2_kc: the command phase's length after the preamble,
    // s2_kpre, or the one period of idle after the turnaround), or the
    // count down a period unless it is the last
    wire [2:0]    ph1 = s1_init ? c_rd[C_PH +: 3] : `TWH_PH_IDLE;
    wire          last1 = s1_init && (st_rd[18:4] == 15'd0);
    reg           s2_klen, s2_kpre, s2_kc;
    // The word the step takes: the phase from the control word, the early
    // part from its copy, the late part from its RAM's register. In the
    // first scan after a reset the late RAM's word is not the channel's.
    // The step from idle neither reads nor sets it, so its write takes the
    // late part as the reset word has it, 0 (S3's flip-flops' reset: a gate
    // in front of the poll count's adder cost 24 LUTs). (The data bits
    // would do as read, since every use writes them first; cleared, no
    // RAM's unknown power-up word goes round the scan in a simulation.)
    wire [W-1:0]  s2_w = {s2_e[EW-2 -: 4], l_rd[LW-1 -: 8], s2_e[EW-6 : SH-3], l_rd[23:0],
                          s2_e[SH-4 : 0], s2_c[C_PH +: 3]} & W_KEEP;
    always @(posedge clk) begin
        s2_v    <= !rst && s1_v;
        s2_ch   <= s1_ch;
        s2_env  <= s1_env;
        s2_cq   <= s1_init ? c_rd : CTL_RESET;
        s2_init <= s1_init;
        s2_eq   <= e1;
        s2_rdec <= d1_rx;
        s2_status <= d1_status;
        s2_ok   <= d1_ok;
        s2_last <= last1;
        s2_bl   <= (st_rd[7:3] == 5'd1);
        // a poll's listen ends: into twh_polls' result write, off the step
        s2_pend <= s1_init && (st_rd[2:0] == `TWH_PH_LISTEN) && (st_rd[18:4] == 15'd0) &&
                   st_rd[PL] && (POLLING != 0);
        // the port's command is for this channel, whose queue has room
        s2_take <= !rst && s1_v && s_cmd_valid && (s_cmd_ch == s1_ch) &&
                   !(s1_init && c_rd[C_CN + QW]);
        // a flush's count
        s2_ccnt <= s1_init ? c1_cc : {(QW+1){1'b0}};
        s2_cc   <= i1_cc;
        s2_sp   <= !rst && i1_pg && (i1_pf || !i1_ne);
        // the length: at the last period of a phase whose successor has
        // one, or at a poll's start (start_p)
        s2_klen <= (last1 && (ph1 == `TWH_PH_CHARGE || ph1 == `TWH_PH_SYNC ||
                              ph1 == `TWH_PH_COMMAND || ph1 == `TWH_PH_EXECUTE ||
                              ph1 == `TWH_PH_LISTEN)) ||
                   (!rst && i1_go && i1_pg && (i1_pf || !i1_ne));
        s2_kpre <= last1 && (ph1 == `TWH_PH_PREAMBLE);
        s2_kc   <= last1 && (ph1 == `TWH_PH_PREAMBLE || ph1 == `TWH_PH_TURNAROUND);
        s2_idle_go <= i1_go;
        s2_sq   <= i1_cq && (i1_en || i1_cc);
        s2_sqk  <= i1_cq && !i1_en && !i1_cc;
        s2_sqn  <= i1_cq && i1_en && !i1_cc;
    end

    // ------------------------------------------------------------ S2: the step
    wire [W-1:0] w     = s2_w;
    // the fields the logic around the step reads, taken from the part
    // each is kept in rather than through w, so a simulator re-evaluates
    // each only when its own part changes
    wire [2:0]   ph    = s2_c[C_PH +: 3];                     // w[2:0]
    wire [15:0]  cnt   = s2_e[15:0];                          // w[18:3]
    wire         rwait = s2_e[16];                            // w[19]
    wire         w_pl  = s2_e[EW-6];                          // w[PL]
    wire [19:0]  w_sh  = l_rd[19:0];                          // w[SH +: 20]
    wire [UW-1:0] w_rx = {s2_e[EW-7 : SH-3], l_rd[23:0]};    // w[U0 +: UW]
    wire          r_sum;          // its data bits carry a good checksum
    twh_rx_sum u_sum (.rx(w_rx), .ok(r_sum));
    wire         last  = s2_last;       // cnt <= 1: this period is the phase's last
    wire         env   = s2_env;

    wire [7:0]       q_code = s2_q[QE-1 -: 8];
    wire [7:0]       q_pmsb = s2_q[QE-9 -: 8];
    wire [7:0]       q_plsb = s2_q[QE-17 -: 8];
    wire [TAG_W-1:0] q_tag  = s2_q[2 +: TAG_W];
    wire [3:0]       q_skip = (s2_q[1:0] == SK_CANCELLED) ? `TWH_ST_CANCELLED :
                              (s2_q[1:0] == SK_BLOCKED)   ? `TWH_ST_BLOCKED : 4'd0;
    // The frame the command phase sends: the queue's head, or a poll's code
    // and payload from its word (SH), a 3-byte frame; its checksum
    // (NOTES.md: one's complement of the 8-bit sum) is taken here, off the
    // step's path (it goes only into s3_q), by an adder each in front of
    // the choice: one adder behind the choice put the poll flag's fan-out
    // and the carry chain in one path, the ECP5-25F's longest
    wire [7:0]       f_code = w_pl ? w_sh[7:0]  : q_code;
    wire [7:0]       f_pmsb = w_pl ? 8'd0       : q_pmsb;
    wire [7:0]       f_plsb = w_pl ? w_sh[15:8] : q_plsb;
    wire [7:0]       q_chk, p_chk;
    twh_checksum u_qchk (.a(q_code), .b(q_pmsb), .c(q_plsb), .chk(q_chk));
    twh_checksum u_pchk (.a(w_sh[7:0]), .b(8'd0), .c(w_sh[15:8]), .chk(p_chk));
    wire [7:0]       f_chk = w_pl ? p_chk : q_chk;

    // the receiver: its fields (data bits at SH) and the answer's verdict
    wire [15:0] r_sh      = w_sh[15:0];
    wire [3:0]  r_status  = s2_status;
    wire        r_data_ok = s2_ok;
    wire [UW-1:0] rx_n;
    twh_rx_step u_rstep (.rx(w_rx), .dec(s2_rdec), .env(env), .rx_n(rx_n));

    // The hand-over needs room where the result goes (m_res_ready: the
    // result FIFO is not full). The claim: a full FIFO that takes one
    // result at a time lets the channel visited first after each pop have
    // it, so the same neighbours could take every free place ahead of a
    // channel. The first channel refused takes the claim; while it is held
    // no other channel hands over, so it gets the next free place at its
    // next visit, and gives the claim back then. Every waiting result is
    // handed over within about a period a channel while results flow.
    // Whether the claim lets the visit hand over (no claim, or its own) is
    // taken at S1 from the claim as this clock leaves it (below): the
    // compare in front of the hand-over and the result FIFO's push was the
    // UP5K's longest path at three channels.
    wire res_free = m_res_ready;
    reg          rc_v;
    reg [CW-1:0] rc_ch;
    reg          s2_mine;
    wire         res_mine = s2_mine;

    // What an idle channel starts (decided at S1, above). The head's skip
    // is CANCELLED while a flush's count is left.
    wire [3:0]   h_skip  = s2_cc ? `TWH_ST_CANCELLED : q_skip;
    wire [15:0]  p_cmd   = poll_cmd;        // (twh_polls' RAM register: read at S1)
    wire         start_q = s2_idle_go && (s2_sq || (s2_sqk && q_skip != 4'd0));  // the head entry starts ...
    wire         start_l = s2_idle_go && s2_sqn && q_skip == 4'd0;   // ... onto the line (else answered)
    wire         start_p = s2_idle_go && s2_sp;                      // the poll starts
    wire         poll_end = s2_pend;      // (ph == LISTEN) && last && w[PL], at S1

    // the sequencer's step
    reg [W-1:0] wn;
    reg         hand;       // hand the waiting result over (pops the queue)

    always @(*) begin
        wn   = w;
        hand = rwait && res_free && res_mine;
        if (hand) wn[19] = 1'b0;
        case (ph)
            `TWH_PH_IDLE:
                if (start_p) begin
                    wn[2:0]  = `TWH_PH_CHARGE;
                    wn[21:20] = 2'b00;
                    wn[SH +: 16] = p_cmd;
                    wn[PL] = 1'b1;
                end
            `TWH_PH_CHARGE:
                if (last) begin
                    wn[2:0] = `TWH_PH_SYNC;
                end
            `TWH_PH_SYNC: begin
                if (!env) wn[20] = 1'b1;
                if (last) begin
                    wn[2:0] = `TWH_PH_PREAMBLE;
                end
            end
            `TWH_PH_PREAMBLE: begin
                if (env) wn[21] = 1'b1;
                if (last) begin
                    wn[2:0] = `TWH_PH_COMMAND;
                    wn[BN +: 4] = 4'd0;
                    wn[NB +: 2] = 2'd0;
                end
            end
            `TWH_PH_COMMAND:
                if (last) begin
                    wn[2:0] = `TWH_PH_EXECUTE;
                end else if (s2_bl) begin       // a bit's last period (cnt[4:0] == 1)
                    if (w[BN +: 4] == 4'd10) begin
                        wn[BN +: 4] = 4'd0;
                        wn[NB +: 2] = w[NB +: 2] + 2'd1;
                    end else begin
                        wn[BN +: 4] = w[BN +: 4] + 4'd1;
                    end
                end
            `TWH_PH_EXECUTE:
                if (last) begin
                    wn[2:0] = `TWH_PH_LISTEN;
                    wn[U0 +: UW] = {UW{1'b0}};
                end
            `TWH_PH_LISTEN:
                if (last) begin
                    wn[2:0] = `TWH_PH_TURNAROUND;
                    wn[U0 +: UW] = {UW{1'b0}};
                    wn[PL] = 1'b0;
                    if (w[PL]) wn[CT +: 12] = w[CT +: 12] + 12'd1;
                    if (!w[PL]) begin       // a poll's result leaves on p_res
                        wn[19] = 1'b1;
                        wn[RS +: 4]  = r_status;
                        if (r_data_ok) wn[U0 +: 16] = {r_sh[7:0], r_sh[15:8]};
                    end
                end else begin
                    wn[U0 +: UW] = rx_n;
                end
            default:    // turnaround
                if (last) begin
                    wn[2:0] = `TWH_PH_IDLE;
                end
        endcase
        // The head entry's start (an idle channel's, never with a poll's),
        // last: the head's skip code (the queue RAM's register) decides
        // whether it goes to the line or is answered with its skip, so it
        // is the last choice in front of the word
        if (start_l) begin
            wn[2:0]  = `TWH_PH_CHARGE;
            wn[21:20] = 2'b00;
        end else if (start_q) begin     // with a skip: answered with it
            wn[19] = 1'b1;
            wn[U0 +: 16] = 16'd0;
            wn[RS +: 4]  = h_skip;
        end
        // the count (its selects from S1, above): the next phase's length,
        // a constant, or down a period unless this is the last (an idle
        // that starts nothing keeps its 0 or 1). The decrement is the
        // adder's operand, so the choice behind it has three terms
        if (s2_klen || start_l) wn[18:3] = s2_len;
        else if (s2_kc) wn[18:3] = !s2_kpre ? 16'd1 : (q_code[7] && !w[PL]) ? 16'd1408 : 16'd1056;
        else            wn[18:3] = cnt + {16{!last}};
    end

    // the control word's step: the port's command written at the tail
    // (its channel's visit), the head popped with its result handed over,
    // the head started, the poll's turn, the flush's count
    assign        ins = s2_take && s_cmd_valid;
    wire [QW-1:0] c2_hd = s2_c[C_HD +: QW];
    wire [QW-1:0] c2_tl = s2_c[C_TL +: QW];
    assign        ins_tl = c2_tl;
    wire [QW:0]   c2_cn = s2_c[C_CN +: QW+1];
    reg  [CTW-1:0] cn_w;
    always @(*) begin
        cn_w = s2_c;
        cn_w[C_HD +: QW]   = c2_hd + {{(QW-1){1'b0}}, hand};
        cn_w[C_TL +: QW]   = c2_tl + {{(QW-1){1'b0}}, ins};
        cn_w[C_CN +: QW+1] = c2_cn + {{QW{1'b0}}, ins} - {{QW{1'b0}}, hand};
        cn_w[C_CC +: QW+1] = (start_q && s2_cc) ? s2_ccnt - 1'b1 : s2_ccnt;
        // (a hand-over needs a waiting result, a start none: never both)
        if (start_q)   cn_w[C_AC] = 1'b1;
        else if (hand) cn_w[C_AC] = 1'b0;
        if (start_q || start_p) cn_w[C_PF] = start_q;
        cn_w[C_PH +: 3] = wn[2:0];
    end

    // The claim: a hand-over with the claim held is its holder's (res_mine)
    // and gives it back; the first channel refused takes it.
    wire         rc_take = s2_v && !rc_v && rwait && !hand;
    wire         rc_v_n  = rc_v ? !(s2_v && hand) : rc_take;
    wire [CW-1:0] rc_ch_n = rc_take ? s2_ch : rc_ch;
    always @(posedge clk) begin
        rc_v    <= !rst && rc_v_n;
        rc_ch   <= rc_ch_n;
        // (one channel: always its own, said here rather than left to the
        // claim's flip-flops, whose power-up value synthesis cannot rule out)
        s2_mine <= (CHANNELS == 1) || !rc_v_n || (rc_ch_n == s1_ch);
    end

    // ------------------------------------------------------------ S3
    reg          s3_last;
    reg [31:0]   s3_q;
    reg          s3_ich;
    always @(posedge clk) begin
        s3_v      <= !rst && s2_v;
        s3_rw     <= rst && HOLD != 0;
        s3_ch     <= s2_ch;
        s3_word   <= wn;
        s3_sum    <= s2_init && r_sum;
        if (!s2_init) begin
            s3_word[CT +: 8]  <= 8'd0;
            s3_word[SH +: 24] <= 24'd0;
        end
        s3_ctl    <= cn_w;
        // (HOLD: the reset words, which the clock after a reset writes at
        // the memories' second word for the first scan's reads)
        if (rst && HOLD != 0) begin
            s3_word <= W_RESET;
            s3_sum  <= 1'b0;
            s3_ctl  <= CTL_RESET;
        end
        s3_ins    <= ins;
        s3_last   <= last;
        s3_q      <= {f_code, f_pmsb, f_plsb, f_chk};
        s3_ich    <= |(cfg_idle_charge & at2);
    end
    assign p_take   = !rst && s2_v && start_p;
    assign p_res    = !rst && s2_v && poll_end;
    assign p_ch     = s2_ch;
    // (the answer's bytes whatever its status: POLL_RESULT's read shows
    // them only with OK or BAD_CHECKSUM, twh_polls. A zero here, in front
    // of the memory, was 16 logic cells)
    assign p_data   = {r_sh[7:0], r_sh[15:8]};
    assign p_status = r_status;
    assign p_count  = w[CT +: 12] + 12'd1;   // (as the step's count: one adder)

    // S3: the drive for the next period, from the new word (NOTES.md):
    // the idle carrier only once the idle's count is out; the command
    // phase's bit from the queue's bytes
    wire [2:0] n_ph = s3_word[2:0];
    wire [3:0] t_bn = s3_word[BN +: 4];
    reg  [7:0] t_byte;
    // (HOLD_Q: the frame's bytes from the queue RAM's register, which
    // holds the visit's head through S3, and only the checksum from S3's
    // register: 24 flip-flops fewer, each a logic cell of its own, as a
    // copy of a RAM's output. With polls each byte has the poll's frame as
    // its other choice, and from the RAMs' outputs that choice and the
    // bit's made the UP5K's longest path at one channel, 45.8 MHz)
    wire [31:0] t_q = (HOLD_Q != 0) ? {f_code, f_pmsb, f_plsb, s3_q[7:0]} : s3_q;
    always @(*) begin
        case (s3_word[NB +: 2])
            2'd0:    t_byte = t_q[31:24];
            2'd1:    t_byte = t_q[31] ? t_q[23:16] : t_q[15:8];
            2'd2:    t_byte = t_q[31] ? t_q[15:8]  : t_q[7:0];
            default: t_byte = t_q[7:0];
        endcase
    end
    wire [9:0] t_char  = {1'b1, t_byte, 1'b0};
    wire       t_level = (t_bn >= 4'd9) ? 1'b1 : t_char[t_bn];
    reg          s4_oe, s4_on;
    always @(posedge clk) begin
        s4_oe <= (n_ph != `TWH_PH_LISTEN) && (n_ph != `TWH_PH_IDLE || (s3_ich && s3_last));
        s4_on <= (n_ph == `TWH_PH_CHARGE) || (n_ph == `TWH_PH_PREAMBLE) ||
                 (n_ph == `TWH_PH_EXECUTE) || (n_ph == `TWH_PH_IDLE) ||
                 (n_ph == `TWH_PH_COMMAND && t_level);
    end

    // the hand-over: the waiting result from the word, its code and tag
    // from the queue's head
    assign m_res_valid  = !rst && s2_v && hand;
    assign m_res_ch     = s2_ch;
    assign m_res_code   = q_code;
    assign m_res_data   = w_sh[15:0];        // w[U0 +: 16]
    assign m_res_status = w_sh[RS-SH +: 4];  // w[RS +: 4]
    assign m_res_tag    = q_tag;

    // a flush's cancels are left: a channel's flag or count, or one on its
    // way from S1 to the write
    reg s3_cc;
    always @(posedge clk) s3_cc <= cn_w[C_CC +: QW+1] != {(QW+1){1'b0}};
    assign cancelling = (fpend != {CN{1'b0}}) || (cz_m != {CN{1'b0}}) ||
                        (s2_v && s2_cc) || (s3_v && s3_cc);

    // STATE's pending flag of one channel: the offered command's take
    // (ins) reaches the read's register through a compare and an OR, not
    // through i_n and a multiplexer over every channel, which at 32
    // channels was the HX8K's longest path (ins is the visit's at S2,
    // s3_ins the one a clock on: what i_n marks, by channel number)
    wire [CN-1:0] pend_p;
    assign sc_v  = s3_v;
    assign sc_ch = s3_ch;
    assign sc_ph = s3_word[2:0];
    // (decoded on the way into S3, so that twh_timing's read address is
    // flip-flops alone: ECP5's LUT RAM reads it in the clock, and the
    // decode stood in front of it. Not from the new word's phase, whose
    // idle start would put the step's decision in front of it: the phase
    // leaves for its successor at its last period, turnaround's for idle,
    // and idle's start for charge, whose successor's field is in TIMING0
    // as idle's is; the proof checks it against sc_ph)
    reg [1:0] s3_tr;
    always @(posedge clk) s3_tr <= `TWH_TREG_OF(fld_of(last ? ph + 3'd1 : ph));
    assign sc_tr = s3_tr;
    assign st_pend = pend_p[st_ch] || (ins && s2_ch == st_ch) || (s3_v && s3_ins && s3_ch == st_ch);

    // ------------------------------------------------------------ per channel
    wire s3_busy = (s3_ctl[C_CN +: QW+1] != {(QW+1){1'b0}}) || (s3_word[2:0] != `TWH_PH_IDLE);
    wire s3_pend = s3_ctl[C_CN +: QW+1] != {{QW{1'b0}}, s3_ctl[C_AC]};
    // each pin samples its window flag at its channel's S0 and takes the
    // drive its channel's S4 holds
    wire [CHANNELS-1:0] pin_vis, pin_we;
    genvar n;
    generate
        for (n = 0; n < CN; n = n + 1) begin : g_ch
            if (n < CHANNELS) begin : g_on
                wire at_s3 = sc[n+3];
                wire at_s1 = sc[n+1];
                // its visit takes a command now, or took one a clock ago
                // (the copies below take it in at the end of this clock)
                wire i_n   = (sc[n+2] && ins) || (at_s3 && s3_ins);
                always @(posedge clk) begin
                    if (rst) begin
                        ph_q[n*3 +: 3] <= `TWH_PH_IDLE;
                        busy_m[n]      <= 1'b0;
                        pend_m[n]      <= 1'b0;
                        cz_m[n]        <= 1'b0;
                        fpend[n]       <= 1'b0;
                    end else begin
                        if (at_s3) begin
                            ph_q[n*3 +: 3] <= s3_word[2:0];
                            busy_m[n]      <= s3_busy;
                            pend_m[n]      <= s3_pend;
                            cz_m[n]        <= s3_cc;
                        end
                        // (S1 takes the flag, and a flush in its own clock;
                        // a channel with nothing queued and not started, and
                        // no command going in, has nothing to cancel: no
                        // flag, so FLUSHING shows only cancels to come)
                        fpend[n] <= !at_s1 && (fpend[n] || (cancel && (pend_m[n] || i_n)));
                    end
                end
                twh_engine_pin #(.CLK_HZ(CLK_HZ), .GLITCH_NS(GLITCH_NS)) u_pin (
                    .clk(clk), .rst(rst), .tick(tick), .fall(fall),
                    .visit(pin_vis[n]), .seen(seen[n]),
                    .nx_we(pin_we[n]), .nx_oe(s4_oe), .nx_on(s4_on),
                    .line_i(line_i[n]), .line_o(line_o[n]), .line_oe(line_oe[n])
                );
                assign pin_vis[n] = sc[n];
                assign pin_we[n]  = sc[n+4];
                assign busy[n]    = busy_m[n] || i_n;
                assign pending[n] = pend_m[n] || i_n;
                assign pend_p[n]  = pend_m[n];
                assign phase[n*3 +: 3] = ph_q[n*3 +: 3];
                assign fld[n*3 +: 3] = fld_of(ph_q[n*3 +: 3]);
            end else begin : g_off
                // indices past the last channel (CHANNELS not a power of two)
                assign pend_p[n] = 1'b0;
                always @(posedge clk) begin
                    cz_m[n]        <= 1'b0;
                    fpend[n]       <= 1'b0;
                end
            end
        end
    endgenerate
`ifdef FORMAL
    // One tracked channel (any), with a shadow of its state word, its
    // timing field and its queue: the RAM's word for it is always the last
    // one its visit wrote, and its step keeps the spec's rules.
    reg f_ok = 1'b0;
    always @(posedge clk) if (rst) f_ok <= 1'b1;
    wire f_tick, f_tick_nx, f_fall;
    twh_carrier #(.CLK_HZ(CLK_HZ)) f_timebase (.clk(clk), .rst(rst), .tick(f_tick),
                                               .tick_nx(f_tick_nx), .fall(f_fall));
    always @(*) assume(tick == f_tick && fall == f_fall);
    // the channel S4 holds (the pins take it by the scan chain, `sc`)
    reg          s4_v;
    reg [CW-1:0] s4_ch;
    always @(posedge clk) begin
        s4_v  <= !rst && s3_v;
        s4_ch <= s3_ch;
    end
    // a visit's write-back names the TIMING register of the field its
    // phase's successor loads (twh_timing takes it as given)
    always @(*) if (f_ok && s3_v) assert(sc_tr == `TWH_TREG_OF(`TWH_FLD_OF(sc_ph)));
    // the scan chain marks the stages' channels
    integer f_n;
    always @(*) begin
        if (f_ok && !rst)
            for (f_n = 0; f_n < CHANNELS; f_n = f_n + 1) begin
                assert(sc[f_n]     == (s0_v && s0_ch == f_n));
                assert(sc[f_n + 1] == (s1_v && s1_ch == f_n));
                assert(sc[f_n + 2] == (s2_v && s2_ch == f_n));
                assert(sc[f_n + 3] == (s3_v && s3_ch == f_n));
                assert(sc[f_n + 4] == (s4_v && s4_ch == f_n));
                // ... and the pins take their own channel's
                assert(pin_vis[f_n] == (s0_v && s0_ch == f_n) &&
                       pin_we[f_n]  == (s4_v && s4_ch == f_n));
            end
    end
    // a visit's line flag is its own channel's pin's window flag, as S0
    // sampled it
    reg f_seen1, f_sv;
    always @(posedge clk) begin
        f_seen1 <= seen[f_ch];
        f_sv    <= !rst;
    end
    always @(*) if (f_ok && !rst && f_sv && s1_v && s1_ch == f_ch) assert(s1_env == f_seen1);
    // a hand-over at the last clock's S2 (its result went out then)
    reg s3_res;
    always @(posedge clk) s3_res <= !rst && s2_v && hand;
    // the pollers' strobes of the last clock's S2, for the S3-clock checks
    reg          f_ptk, f_prs;
    reg [CW-1:0] f_pch;
    reg [15:0]   f_pdt;
    reg [3:0]    f_pst;
    reg [11:0]   f_pct;
    always @(posedge clk) {f_ptk, f_prs, f_pch, f_pdt, f_pst, f_pct} <=
                          {p_take, p_res, p_ch, p_data, p_status, p_count};

    (* anyconst *) reg [CW-1:0] f_ch;
    (* anyconst *) reg [QW-1:0] f_qi_c;
    assign f_qi = f_qi_c;
    always @(*) assume(f_ch < CHANNELS);
    // a poll's code is one of 0x40-0x44 (the core refuses any other:
    // twh_core:port), so its frame is three bytes
    always @(*) assume(!poll_cmd[7]);
    // the queue keeps a skip code in two bits: the core's are these
    always @(*) if (s_cmd_valid) assume(s_cmd_skip == 4'd0 || s_cmd_skip == `TWH_ST_BLOCKED ||
                                        s_cmd_skip == `TWH_ST_CANCELLED);

    // clocks since the last tick, and whether one came since reset
    reg [7:0] f_since;
    reg       f_ticked;
    always @(posedge clk) begin
        if (rst) begin
            f_since  <= 8'd0;
            f_ticked <= 1'b0;
        end else if (tick) begin
            f_since  <= 8'd1;
            f_ticked <= 1'b1;
        end else if (f_since != 8'hFF) begin
            f_since  <= f_since + 8'd1;
        end
    end
    localparam [7:0] F_ONE = 8'd1;
    // ticks come a carrier period apart (P or P+1 clocks: twh_carrier's own
    // proof); assumed here so that an induction trace cannot start from a
    // carrier state its proof excludes
    always @(*) if (f_ticked) assume(f_since <= P[7:0] + 8'd1);

    // the receiver's decodes and verdict the step takes (registered a
    // clock ahead) are its word's, whenever the word is in listen (the
    // only phase that reads them; twh_rx:equiv proves the step and the
    // decodes against twh_rx)
    // (the verdict of its data bits, which the step reads from the late
    // part's RAM: the one stored with its early part is theirs)
    wire [8:0] f_rdec;
    wire [3:0] f_rstatus;
    wire       f_rsum;
    twh_rx_sum f_rx_sum (.rx(s2_w[U0 +: UW]), .ok(f_rsum));
    twh_rx_dec f_rx_dec (.rx(s2_w[U0 +: UW]), .sync_low(s2_w[20]), .pre_high(s2_w[21]),
                         .sum_ok(f_rsum), .dec(f_rdec), .status(f_rstatus));
    always @(*)
        if (f_ok && s2_v && s2_w[2:0] == `TWH_PH_LISTEN)
            assert(s2_rdec == f_rdec && s2_status == f_rstatus &&
                   s2_ok == (f_rstatus == `TWH_ST_OK || f_rstatus == `TWH_ST_BAD_CHECKSUM));

    // the shadow: the word the tracked channel's last visit wrote
    reg [W-1:0] f_w;
    reg         f_wr;
    reg         f_vs;           // ... and the verdict written with it
    always @(posedge clk) begin
        if (rst) f_wr <= 1'b0;
        else if (s3_v && s3_ch == f_ch) begin
            f_w  <= s3_word;
            f_vs <= s3_sum;
            f_wr <= 1'b1;
        end
    end
    wire [W-1:0] f_cur = f_wr ? f_w : W_RESET;     // the channel's state as it stands
    wire         f_wr_nx = f_wr || (s3_v && s3_ch == f_ch);
    // ... and its control word
    reg  [CTW-1:0] f_c;
    always @(posedge clk) if (s3_v && s3_ch == f_ch) f_c <= s3_ctl;
    wire [CTW-1:0] f_cc = f_wr ? f_c : CTL_RESET;
    wire [2:0]   f_ph  = f_cur[2:0];
    // the early part the RAM holds for the shadow word: with the verdict
    // written with it, which is its data bits' own once the answer has its
    // three characters (the only word that reads it); so is the one on its
    // way to the write
    wire         f_wsum, f_s3sum;
    twh_rx_sum f_w_sum (.rx(f_w[U0 +: UW]), .ok(f_wsum));
    twh_rx_sum f_s3_sum (.rx(s3_word[U0 +: UW]), .ok(f_s3sum));
    // the late part: the first scan after a reset takes the late RAM's
    // word (the step from idle does not read it; its write clears it), so
    // until the tracked channel's first write the step's word is the
    // reset word but there
    localparam [W-1:0] W_LATE = ({{(W-24){1'b0}}, 24'hFFFFFF} << SH) |
                                ({{(W-8){1'b0}}, 8'hFF} << CT);
    wire [W-1:0] f_dc = f_wr ? {W{1'b0}} : W_LATE;

    // the field each phase's successor loads (written out here, not
    // twh_defs.vh's TWH_FLD_OF, which the RTL uses)
    function [2:0] f_fld;
        input [2:0] ph_i;
        case (ph_i)
            `TWH_PH_CHARGE:   f_fld = 3'd2;
            `TWH_PH_SYNC:     f_fld = 3'd3;
            `TWH_PH_PREAMBLE: f_fld = 3'd4;
            `TWH_PH_COMMAND:  f_fld = 3'd4;
            `TWH_PH_EXECUTE:  f_fld = 3'd5;
            `TWH_PH_LISTEN:   f_fld = 3'd6;
            default:          f_fld = 3'd1;
        endcase
    endfunction

    // the field the timing RAM's read at S1 asked for, carried to S2, and
    // whether that read's control word was the RAM's (not the first scan)
    reg [2:0] f_s2_fld;
    reg       f_s2_init;
    always @(posedge clk) begin
        f_s2_fld  <= fld_of(c_rd[C_PH +: 3]);
        f_s2_init <= s1_init;
    end

    wire [QW:0]   f_qcnt = f_cc[C_CN +: QW+1];
    wire [QW-1:0] f_head = f_cc[C_HD +: QW];
    wire [QW-1:0] f_tail = f_cc[C_TL +: QW];
    wire          f_act  = f_cc[C_AC];
    wire [QW:0]   f_ccnt = f_cc[C_CC +: QW+1];

    always @(*) begin
        if (f_ok && !rst) begin
            // the scan: a channel is read once a period, c+1 clocks after
            // the tick, and the scan is over before the next tick
            if (s0_v) assert(f_ticked && s0_ch < CHANNELS && f_since == {{(8-CW){1'b0}}, s0_ch} + F_ONE);
            if (f_ticked && f_since == {{(8-CW){1'b0}}, f_ch} + F_ONE && f_since <= P[7:0])
                assert(s0_v && s0_ch == f_ch);
            if (tick) assert(!s0_v);
            // nothing is visited before the first tick after reset
            if (!f_ticked) assert(!s0_v && !s1_v && !s2_v && !s3_v && !s4_v && !f_wr &&
                                  !run1 && !run2);
            // (HOLD) the memories' second word holds the reset words from
            // the write in the clock after a reset on: nothing is visited
            // before it, and nothing else writes there
            if (s3_rw) assert(!s0_v && !s1_v && !s2_v && !s3_v);
            if (HOLD != 0 && !s3_rw)
                assert(f_e_rsv == {1'b0, `TWH_E_OF(W_RESET)} && f_c_rsv == CTL_RESET);
            if (run2) assert(run1);
            // the stages carry what S0 read, a clock apart
            if (s1_v) assert(s1_ch < CHANNELS);
            if (s2_v) assert(s2_ch < CHANNELS);
            if (s3_v) assert(s3_ch < CHANNELS);
            // one visit of a channel in the pipeline at a time (P >= 4)
            if (s0_v && s0_ch == f_ch)
                assert(!(s1_v && s1_ch == f_ch) && !(s2_v && s2_ch == f_ch) &&
                       !(s3_v && s3_ch == f_ch));
            if (s1_v && s1_ch == f_ch) assert(!(s2_v && s2_ch == f_ch) && !(s3_v && s3_ch == f_ch));
            if (s2_v && s2_ch == f_ch) assert(!(s3_v && s3_ch == f_ch));
            // the RAM's word for the tracked channel is the shadow
            if (s1_v && s1_ch == f_ch) assert(s1_init == f_wr);
            if (s1_v && s1_ch == f_ch && f_wr) assert(e_rd == {f_vs, `TWH_E_OF(f_w)});
            if (f_wr && f_ph == `TWH_PH_LISTEN && f_w[NB +: 2] == 2'd3) assert(f_vs == f_wsum);
            if (s3_v && s3_word[2:0] == `TWH_PH_LISTEN && s3_word[NB +: 2] == 2'd3)
                assert(s3_sum == f_s3sum);
            if (s2_v && s2_ch == f_ch) assert((s2_w | f_dc) == (f_cur | f_dc) &&
                                              s2_last == (f_cur[18:4] == 15'd0));
            // (taken at S1 from the same word)
            if (s2_v) assert(s2_idle_go == (s2_w[2:0] == `TWH_PH_IDLE && s2_last && !s2_w[19]));
            // (in the first scan after a reset s2_bl is the RAM's word's,
            // not the reset word's: only the command phase reads it)
            if (s2_v && s2_init) assert(s2_bl == (s2_w[7:3] == 5'd1));
            // written since reset, or being written: from the first scan's
            // S3 on (f_ch + 4 clocks after the tick: at P = 4 the last
            // channel's falls in the next scan's first clock), so at the
            // clock before its read (S0) the scan flags tell it
            assert(f_wr_nx == (run2 || (run1 && f_since >= {{(8-CW){1'b0}}, f_ch} + 8'd4)));
            if (s0_v && s0_ch == f_ch) assert(s0_init == f_wr);
            // the control word read is the one the last visit wrote, and
            // the flags the core reads are its copies
            if (s1_v && s1_ch == f_ch && s1_init) assert(c_rd == f_cc);
            if (s2_v && s2_ch == f_ch) assert(s2_c == f_cc);
            assert(f_cc[C_PH +: 3] == f_ph);
            assert(busy_m[f_ch] == (f_qcnt != {(QW+1){1'b0}} || f_ph != `TWH_PH_IDLE) &&
                   pend_m[f_ch] == (f_qcnt != {{QW{1'b0}}, f_act}) &&
                   cz_m[f_ch] == (f_ccnt != {(QW+1){1'b0}}));
            // the timing field is the one the phase's successor loads
            assert(ph_q[f_ch*3 +: 3] == f_ph);
            if (s2_v && s2_ch == f_ch && f_s2_init) assert(f_s2_fld == f_fld(f_ph));
            // the queue: its count is tail - head, full at QDEPTH, and a
            // transaction or a waiting result always has its entry (so a
            // pop never finds the queue empty: one result per command)
            assert(f_qcnt <= QDEPTH[QW:0]);
            assert(f_qcnt[QW-1:0] == f_tail - f_head);
            // a command taken at S2 has room in its channel's queue
            if (s2_v && s2_take && s2_ch == f_ch) assert(!f_qcnt[QW]);
            // (a result handed over in the turnaround has popped its entry;
            // a poll has none): the head is started exactly while its
            // transaction runs or its result waits, and a flush's count
            // never exceeds the entries queued and not started
            assert(f_act == (f_cur[19] || (!f_cur[PL] && f_ph != `TWH_PH_IDLE &&
                                            f_ph != `TWH_PH_TURNAROUND)));
            if (f_act) assert(f_qcnt != {(QW+1){1'b0}});
            assert(f_ccnt <= f_qcnt - {{QW{1'b0}}, f_act});
            // a flush's cancels left are shown
            if (fpend[f_ch] || f_ccnt != {(QW+1){1'b0}}) assert(cancelling);
            // a build without polls never starts one, and its word's poll
            // fields stay 0
            if (POLLING == 0) assert(!p_take && !p_res && !f_cur[PL] && f_cur[CT +: 12] == 12'd0);
            // a poll runs from its charge to its listen's end
            if (f_cur[PL]) assert(f_ph != `TWH_PH_IDLE && f_ph != `TWH_PH_TURNAROUND &&
                                  !f_cur[19]);
            if (s3_v && s3_ch == f_ch && s3_res) assert(f_qcnt != {(QW+1){1'b0}});
            // a result waits only between a listen's end (or a skip) and
            // the next charge
            if (f_cur[19]) assert(f_ph == `TWH_PH_TURNAROUND || f_ph == `TWH_PH_IDLE);
            if (f_ph == `TWH_PH_COMMAND) assert(f_cur[BN +: 4] <= 4'd10);
            // a turnaround's idle is one tick; after reset, the minimum
            // turnaround and one
            if (f_ph == `TWH_PH_IDLE) assert(f_cur[18:3] <= `TWH_TURNAROUND_MIN + 16'd1);
            if (f_ph == `TWH_PH_IDLE && f_cur[18:3] > 16'd1) assert(!f_cur[19]);
        end
    end

    // the step, at the tracked channel's write: a count steps down by one a
    // visit, a phase ends only at its last period, phases run in order,
    // each loads the timing word read for its own field (the field is
    // f_fld of the phase before it, above), the command phase its 33 or
    // 44 bits, the idle after a turnaround one tick
    reg [W-1:0] f_pre;        // the word the step started from
    reg         f_pre_init;   // ... not in the first scan after a reset
    reg         f_pre_last;
    reg [15:0]  f_pre_len;
    reg [7:0]   f_pre_code;
    always @(posedge clk) begin
        f_pre      <= s2_w;
        f_pre_init <= s2_init;
        f_pre_last <= s2_last;
        f_pre_len  <= s2_len;
        f_pre_code <= q_code;
    end
    wire [2:0]  f_oph = f_pre[2:0];
    wire [15:0] f_ocnt = f_pre[18:3];
    wire [2:0]  f_nph = s3_word[2:0];
    wire [15:0] f_ncnt = s3_word[18:3];
    always @(*) begin
        if (f_ok && !rst && s3_v && s3_ch == f_ch) begin
            if (!f_pre_last) assert(f_nph == f_oph && f_ncnt == f_ocnt - 16'd1);
            if (f_pre_last && f_oph != `TWH_PH_IDLE) begin
                assert(f_nph == f_oph + 3'd1);
                if (f_nph == `TWH_PH_COMMAND)
                    assert(f_ncnt == ((f_pre_code[7] && !f_pre[PL]) ? 16'd1408 : 16'd1056));
                else if (f_nph == `TWH_PH_IDLE)
                    assert(f_ncnt == 16'd1);
                else
                    assert(f_ncnt == f_pre_len);    // the word of f_fld(f_oph): above
            end
            if (f_pre_last && f_oph == `TWH_PH_IDLE)
                assert(f_nph == `TWH_PH_IDLE || f_nph == `TWH_PH_CHARGE);
            // the receiver starts each listen from its cleared word
            // (twh_rx:equiv's starting point)
            if (f_pre_last && f_oph == `TWH_PH_EXECUTE) assert(s3_word[U0 +: UW] == {UW{1'b0}});
            // a result is handed over exactly when one waits and the
            // register is free, and it pops the queue
            if (s3_res) assert(f_pre[19]);
        end
    end

    // a flush since the tracked channel's last visit took its flag (S1)
    // counts, at the next visit, every entry queued and not started: the
    // count is the queue's less its started head
    reg f_fl, f_fl2;
    always @(posedge clk) begin
        if (rst)                           f_fl <= 1'b0;
        else if (s1_v && s1_ch == f_ch)    f_fl <= 1'b0;
        else if (cancel)                   f_fl <= 1'b1;
        f_fl2 <= f_fl || cancel;
    end
    always @(*) begin
        if (f_ok && !rst) begin
            if (fpend[f_ch]) assert(f_fl);
            // S1's copy of the flag: set with the channel's own, and
            // otherwise only by a flush that found nothing to cancel
            if (s1_v && s1_ch == f_ch && fpend[f_ch]) assert(s1_fl);
            if (s1_v && s1_ch == f_ch && s1_fl && !fpend[f_ch]) assert(!pend_m[f_ch]);
            if (s2_v && s2_ch == f_ch && f_fl2)
                assert(s2_ccnt == f_qcnt - {{QW{1'b0}}, f_act});
        end
    end

    // a result goes out only where there is room for it, in the clock of
    // its channel's hand-over (the one clock its waiting flag is cleared:
    // the step's property above), so it goes out once
    always @(*) if (f_ok && !rst && m_res_valid) assert(m_res_ready && s2_v && w[19]);
    reg f_past = 1'b0;
    always @(posedge clk) f_past <= f_ok && !rst;
    // the port's side (AXI-Stream): a command offered and not taken stays
    // offered, for the same channel (the core's twh_core:eng* prove it)
    always @(posedge clk)
        if (f_past && !rst && $past(s_cmd_valid && !s_cmd_ready && !rst))
            assume(s_cmd_valid && s_cmd_ch == $past(s_cmd_ch));
    always @(*) if (s_cmd_valid) assume(s_cmd_ch < CHANNELS);
    // what S1 decided holds at S2: the command is still offered, for the
    // channel visited
    always @(*) if (f_ok && !rst && s2_take) assert(s2_v && s_cmd_valid && s_cmd_ch == s2_ch);

    // What each command's result carries. The queue entry followed is the
    // tracked channel's entry f_qi (any), as its RAM word holds it (f_qm):
    // - a command taken is the entry written: code, payload (its high
    //   byte 0 in a 3-byte command), tag and skip as the port gave them
    //   in the clock it was taken;
    // - the entry read at the head is the RAM's word, and a result handed
    //   over for it carries its code and tag;
    // - its status: CANCELLED for an entry taken CANCELLED; BLOCKED or
    //   CANCELLED (a flush) for one taken BLOCKED; for one taken to run, a
    //   status of the line (OK .. LINE_STUCK_HIGH) or CANCELLED (a flush
    //   before it started); its data 0 unless OK or BAD_CHECKSUM, and then
    //   the answer's first byte over its second;
    // - an entry taken with a skip never reaches the line.
    wire [7:0]        f_qm_code = f_qm[QE-1 -: 8];
    wire [TAG_W-1:0]  f_qm_tag  = f_qm[2 +: TAG_W];
    wire [1:0]        f_qm_sk   = f_qm[1:0];
    wire              f_at_qi   = (f_head == f_qi);
    // the entry is queued: within the count from the head
    wire [QW-1:0]     f_qoff    = f_qi - f_head;
    wire              f_qin     = {1'b0, f_qoff} < f_qcnt;
    wire [3:0]        f_rs_n    = s3_word[RS +: 4];
    wire [3:0]        f_rs      = f_cur[RS +: 4];
    wire              f_run     = !f_cur[PL] && f_ph != `TWH_PH_IDLE && f_ph != `TWH_PH_TURNAROUND;
    always @(posedge clk) begin
        if (f_past && f_ok && !rst) begin
            // the command taken goes into the tracked entry as the port
            // gave it, in the clock it is taken (ready and valid)
            if ($past(s_cmd_valid && s_cmd_ready && s2_ch == f_ch && c2_tl == f_qi))
                assert(f_qm == {$past(s_cmd_code),
                                $past(s_cmd_code[7]) ? $past(s_cmd_payload[15:8]) : 8'd0,
                                $past(s_cmd_payload[7:0]), $past(s_cmd_tag), $past(push_sk)});
            // it is taken only at its own channel's visit
            if ($past(s_cmd_valid && s_cmd_ready)) assert($past(s2_v && s2_ch == s_cmd_ch));
            // and shows as busy and pending in the clock after, before the
            // copies take it in (from then on they show it: above)
            if ($past(ins && s2_ch == f_ch)) assert(busy[f_ch] && pending[f_ch]);
        end
    end
    // STATE's read of any channel is its pending flag
    always @(*) if (f_ok && !rst && st_ch < CHANNELS) assert(st_pend == pending[st_ch]);
    always @(*) begin
        if (f_ok && !rst) begin
            // the result of the tracked entry: its code and tag (handed
            // over at S2, where the head read is the RAM's word: below)
            if (m_res_valid && s2_ch == f_ch && c2_hd == f_qi) begin
                assert(m_res_valid && m_res_ch == f_ch &&
                       m_res_code == f_qm_code && m_res_tag == f_qm_tag);
                if (f_qm_sk == SK_CANCELLED) assert(m_res_status == `TWH_ST_CANCELLED);
                if (f_qm_sk == SK_BLOCKED)   assert(m_res_status == `TWH_ST_BLOCKED ||
                                                    m_res_status == `TWH_ST_CANCELLED);
                if (f_qm_sk == SK_NONE)      assert(m_res_status <= `TWH_ST_LINE_STUCK_HIGH ||
                                                    m_res_status == `TWH_ST_CANCELLED);
                if (m_res_data != 16'd0) assert(m_res_status == `TWH_ST_OK ||
                                                m_res_status == `TWH_ST_BAD_CHECKSUM);
            end
        end
    end
    always @(*) begin
        if (f_ok && !rst) begin
            // skips are none, BLOCKED or CANCELLED (two bits, never 3)
            if (f_qin) assert(f_qm_sk != 2'd3);
            // the head entry read is the RAM's word
            if (s2_v && s2_ch == f_ch && s2_c[C_HD +: QW] == f_qi && f_qcnt != {(QW+1){1'b0}})
                assert(s2_q == f_qm);
            // a waiting result's status and data (the invariants behind the
            // result's, above)
            if (f_cur[19] && f_cur[U0 +: 16] != 16'd0)
                assert(f_rs == `TWH_ST_OK || f_rs == `TWH_ST_BAD_CHECKSUM);
            if (f_cur[19] && f_at_qi) begin
                if (f_qm_sk == SK_CANCELLED) assert(f_rs == `TWH_ST_CANCELLED);
                if (f_qm_sk == SK_BLOCKED)   assert(f_rs == `TWH_ST_BLOCKED ||
                                                    f_rs == `TWH_ST_CANCELLED);
                if (f_qm_sk == SK_NONE)      assert(f_rs <= `TWH_ST_LINE_STUCK_HIGH ||
                                                    f_rs == `TWH_ST_CANCELLED);
            end
            // an entry with a skip never runs: a command's transaction is
            // always its head's, taken to run
            if (f_run && f_at_qi) assert(f_qm_sk == SK_NONE);
        end
    end
    // The hand-over's claim: while a channel holds it no other channel
    // hands a result over and the holder has a result waiting, so it hands
    // it over at the first of its visits that finds room in the result
    // FIFO (every wait for room is bounded by the FIFO).
    always @(*) begin
        if (f_ok && !rst) begin
            if (rc_v) assert(rc_ch < CHANNELS);
            // (the compare taken at S1 is the claim as S2 finds it)
            if (s2_v) assert(s2_mine == (!rc_v || rc_ch == s2_ch));
            // (a poll's end taken at S1 is the word's at S2)
            if (s2_v) assert(poll_end == ((ph == `TWH_PH_LISTEN) && last && w[PL]));
            // (the count's selects taken at S1 are the phase's and the
            // start's at S2)
            if (s2_v) begin
                assert(s2_klen == ((last && (ph == `TWH_PH_CHARGE || ph == `TWH_PH_SYNC ||
                                             ph == `TWH_PH_COMMAND || ph == `TWH_PH_EXECUTE ||
                                             ph == `TWH_PH_LISTEN)) || start_p));
                assert(s2_kpre == (last && ph == `TWH_PH_PREAMBLE));
                assert(s2_kc == (last && (ph == `TWH_PH_PREAMBLE || ph == `TWH_PH_TURNAROUND)));
            end
            if (s2_v && hand && rc_v) assert(rc_ch == s2_ch);
            if (rc_v && rc_ch == f_ch) assert(f_cur[19]);
            if (s2_v && s2_ch == f_ch && rc_v && rc_ch == f_ch) assert(!(s3_v && s3_res));
        end
    end

    // a result of the line carries the answer's bytes, first over second
    always @(*)
        if (f_ok && !rst && s3_v && s3_ch == f_ch && f_pre_last && f_oph == `TWH_PH_LISTEN &&
            !f_pre[PL] && (f_rs_n == `TWH_ST_OK || f_rs_n == `TWH_ST_BAD_CHECKSUM))
            assert(s3_word[U0 +: 16] == {f_pre[SH +: 8], f_pre[SH + 8 +: 8]});

    // The drive each visit hands the tracked channel's pin for its next
    // period (twh_engine_pin proves the pin takes it at the tick), by the
    // phase the visit wrote (NOTES.md's table): released in
    // listen; the carrier in charge, preamble and execute; driven low in
    // sync and the turnaround; in the command phase the frame's bit (8N2,
    // start 0, data LSB first, two stop bits 1) of the command's frame:
    // its code, the payload's high byte in a 4-byte command, its low byte,
    // and the checksum of the three (NOTES.md); in idle, released, or the
    // carrier with idle charge once the idle's count is out. After a reset
    // a channel is idle for the minimum turnaround and one period.
    reg       f_ich3, f_ich4, f_last4;
    always @(posedge clk) begin
        f_ich3  <= cfg_idle_charge[f_ch];
        f_ich4  <= f_ich3;
        f_last4 <= s3_last;
    end
    wire [7:0] f_e_pm = f_qm[QE-9 -: 8];
    wire [7:0] f_e_pl = f_qm[QE-17 -: 8];
    wire [7:0] f_e_ck = ~(f_qm_code + f_e_pm + f_e_pl);
    wire [1:0] f_nb   = f_cur[NB +: 2];
    wire [3:0] f_bn   = f_cur[BN +: 4];
    reg  [7:0] f_byte;
    always @(*) begin
        if (f_qm_code[7])
            f_byte = (f_nb == 2'd0) ? f_qm_code : (f_nb == 2'd1) ? f_e_pm :
                     (f_nb == 2'd2) ? f_e_pl : f_e_ck;
        else
            f_byte = (f_nb == 2'd0) ? f_qm_code : (f_nb == 2'd1) ? f_e_pl : f_e_ck;
    end
    // the command phase's periods: 32 a bit, 33 or 44 bits; those spent
    wire [15:0] f_b32 = f_qm_code[7] ? 16'd1408 : 16'd1056;
    wire [15:0] f_el  = f_b32 - f_cur[18:3];
    wire f_bit = (f_bn == 4'd0) ? 1'b0 : (f_bn <= 4'd8) ? f_byte[f_bn - 4'd1] : 1'b1;
    always @(*) begin
        if (f_ok && !rst) begin
            if (!f_wr) assert(f_ph == `TWH_PH_IDLE && f_cur[18:3] == `TWH_TURNAROUND_MIN + 16'd1 &&
                              !f_cur[19]);
            if (s4_v && s4_ch == f_ch) begin
                case (f_ph)
                    `TWH_PH_LISTEN:     assert(!s4_oe);
                    `TWH_PH_CHARGE, `TWH_PH_PREAMBLE, `TWH_PH_EXECUTE:
                                        assert(s4_oe && s4_on);
                    `TWH_PH_SYNC, `TWH_PH_TURNAROUND:
                                        assert(s4_oe && !s4_on);
                    `TWH_PH_COMMAND: begin
                        assert(s4_oe);
                        if (!f_cur[PL] && f_at_qi) assert(s4_on == f_bit);
                    end
                    default:            assert(s4_oe == (f_ich4 && f_last4) && (!s4_oe || s4_on));
                endcase
            end
            // the frame's bit is the one the periods spent in the command
            // phase reach: 32 periods a bit, 11 bits a byte
            if (f_ph == `TWH_PH_COMMAND && !f_cur[PL] && f_at_qi) begin
                assert(f_cur[18:3] != 16'd0 && f_cur[18:3] <= f_b32);
                assert({4'd0, f_nb} * 6'd11 + {2'd0, f_bn} == f_el[10:5]);
            end
        end
    end

    // The phase lengths loaded are the ones the port delivered: the timing
    // RAM's word for (tracked channel, tracked field f_tf, any) is the last
    // length written for that channel and field, and a visit whose next
    // phase loads that field reads it (the step loads the word read: above).
    (* anyconst *) reg [2:0] f_tf_c;
    assign f_tf = f_tf_c;
    reg        f_tv;           // a length was delivered for (f_ch, f_tf) since reset
    reg [15:0] f_tl;           // ... the last one
    always @(posedge clk) begin
        if (rst) f_tv <= 1'b0;
        else if (t_we && t_ch == f_ch && t_fld == f_tf) f_tv <= 1'b1;
        if (t_we && t_ch == f_ch && t_fld == f_tf) f_tl <= t_len;
    end
    // the word as the tracked visit's read found it, carried to S2
    // (the RAM is read at S1)
    reg [15:0] f_t2;
    always @(posedge clk) f_t2 <= f_tm;
    always @(*) begin
        if (f_ok && !rst) begin
            if (f_tv && FIXED_TIMING == 0) assert(f_tm == f_tl);
            // fixed timing: the field's default of NOTES.md, written out
            if (FIXED_TIMING != 0)
                assert(f_tm == ((f_tf == 3'd1) ? 16'd8000 : (f_tf == 3'd2) ? 16'd1000 :
                                (f_tf == 3'd3) ? 16'd2000 : (f_tf == 3'd4) ? 16'd4000 :
                                (f_tf == 3'd5) ? 16'd3000 : 16'd2000));
            if (s2_v && s2_ch == f_ch && f_s2_fld == f_tf) assert(s2_len == f_t2);
        end
    end

    // What a visit starts (the turn-taking of polls and commands; with the
    // idle's count and the claim's bound above, a queued command waits at
    // most one poll's transaction once its channel is idle): the poll
    // request and command the core gives in the visit's S1 clock, and the
    // enable in its S1 clock, against what the write holds.
    reg        f_pr2, f_pr3, f_en2, f_en3, f_env3;
    reg [15:0] f_pc3;
    always @(posedge clk) begin
        f_pr2  <= poll_req[f_ch];
        f_pr3  <= f_pr2;
        f_pc3  <= poll_cmd;
        f_en2  <= enable;
        f_en3  <= f_en2;
        f_env3 <= s2_env;
    end
    wire       f_go    = f_oph == `TWH_PH_IDLE && f_pre_last && !f_pre[19];
    wire       f_qsk   = f_at_qi && f_qm_sk != SK_NONE;     // the head is a skipped command
    wire       f_cmdw  = f_qcnt != {(QW+1){1'b0}} && (f_en3 || f_qsk);
    wire       f_pollw = f_pr3 && f_en3 && POLLING != 0;   // (a build without polls ignores poll_req)
    wire       f_pref  = f_cc[C_PF];
    wire       f_s_cmd = s3_ctl[C_AC] && !f_act;              // the head started
    wire       f_s_pol = s3_word[PL] && !f_pre[PL];           // a poll started
    // the frame a poll started now sends: its code, payload and checksum
    wire [7:0] f_pck   = ~(f_pc3[7:0] + f_pc3[15:8]);
    reg [23:0] f_pfr;
    always @(posedge clk)
        if (s3_v && s3_ch == f_ch && f_s_pol) f_pfr <= {f_pck, f_pc3[15:8], f_pc3[7:0]};
    always @(*) begin
        if (f_ok && !rst && s3_v && s3_ch == f_ch) begin
            // a start only at an idle's end with no result waiting
            if (!f_go) assert(!f_s_cmd && !f_s_pol);
            if (f_go) begin
                // a due poll goes on its turn or when no command can; a
                // command that can go goes otherwise
                if (f_pollw && (f_pref || !f_cmdw)) assert(f_s_pol && f_nph == `TWH_PH_CHARGE);
                if (f_cmdw && !(f_pollw && f_pref)) assert(f_s_cmd);
                if (!f_pollw) assert(!f_s_pol);
                // ... and the turn passes: a poll next after a command, a
                // command next after a poll
                if (f_s_cmd) assert(s3_ctl[C_PF]);
                if (f_s_pol) assert(!s3_ctl[C_PF]);
                if (f_s_pol) assert(s3_word[SH +: 16] == f_pc3);
            end
            if (!f_s_cmd && !f_s_pol) assert(s3_ctl[C_PF] == f_pref);
        end
    end

    // A poll's frame stays in its word until the command phase has sent it,
    // and each period of that phase drives its bit (as for a command, a
    // 3-byte frame: code, payload, checksum, 8N2)
    wire [7:0] f_pby = (f_nb == 2'd0) ? f_pfr[7:0] : (f_nb == 2'd1) ? f_pfr[15:8] : f_pfr[23:16];
    wire [15:0] f_pel = 16'd1056 - f_cur[18:3];
    wire f_pbit = (f_bn == 4'd0) ? 1'b0 : (f_bn <= 4'd8) ? f_pby[f_bn - 4'd1] : 1'b1;
    always @(*) begin
        if (f_ok && !rst && f_cur[PL] && f_ph != `TWH_PH_EXECUTE && f_ph != `TWH_PH_LISTEN) begin
            assert(f_cur[SH +: 16] == f_pfr[15:0]);
            assert(!f_pfr[7] && f_pfr[23:16] == ~(f_pfr[7:0] + f_pfr[15:8]));
            if (f_ph == `TWH_PH_COMMAND) begin
                assert(f_cur[18:3] != 16'd0 && f_cur[18:3] <= 16'd1056);
                assert({4'd0, f_nb} * 6'd11 + {2'd0, f_bn} == f_pel[10:5]);
                if (s4_v && s4_ch == f_ch) assert(s4_on == f_pbit);
            end
        end
    end

    // The line's two checks before the answer: the sync's "read low" and the
    // preamble's "read high" are cleared at a transaction's start, each set
    // only by a visit in its own phase that saw the line so, and kept to
    // the listen's end, where they come before the answer's own verdict
    // (stuck high, then stuck low: docs/protocol.md's precedence; the rest is the
    // receiver's, twh_rx:equiv).
    always @(*) begin
        if (f_ok && !rst && s3_v && s3_ch == f_ch) begin
            if (f_nph == `TWH_PH_CHARGE && f_oph == `TWH_PH_IDLE) assert(s3_word[21:20] == 2'b00);
            else if (f_oph == `TWH_PH_SYNC)
                assert(s3_word[20] == (f_pre[20] || !f_env3) && s3_word[21] == f_pre[21]);
            else if (f_oph == `TWH_PH_PREAMBLE)
                assert(s3_word[21] == (f_pre[21] || f_env3) && s3_word[20] == f_pre[20]);
            else
                assert(s3_word[21:20] == f_pre[21:20]);
            if (f_oph == `TWH_PH_LISTEN && f_pre_last) begin
                if (!f_pre[20]) assert(f_pst == `TWH_ST_LINE_STUCK_HIGH);
                else if (!f_pre[21]) assert(f_pst == `TWH_ST_LINE_STUCK_LOW);
                else assert(f_pst != `TWH_ST_LINE_STUCK_HIGH &&
                            f_pst != `TWH_ST_LINE_STUCK_LOW);
                if (!f_pre[PL]) assert(f_rs_n == f_pst && s3_word[19]);
            end
            // a poll's start and end, and only a poll's, go to the pollers
            // (POLL_RESULT): its status as above, the answer's bytes, first
            // over second (twh_polls shows them only with OK or
            // BAD_CHECKSUM), the channel's count of polls one more
            assert(f_ptk == f_s_pol && f_pch == f_ch);
            assert(f_prs == (f_oph == `TWH_PH_LISTEN && f_pre_last && f_pre[PL]));
            if (f_prs) begin
                assert(f_pdt == {f_pre[SH +: 8], f_pre[SH+8 +: 8]});
                assert(f_pct == f_pre[CT +: 12] + 12'd1 && s3_word[CT +: 12] == f_pct);
            end else begin
                // (the first scan's write takes the reset word's count: 0)
                assert(s3_word[CT +: 12] == (f_pre_init ? f_pre[CT +: 12] : 12'd0));
            end
            // ... and its data bits: 0, the reset word's
            if (!f_pre_init) assert(s3_word[SH +: 24] == 24'd0);
        end
        // a charge has both clear, a sync only its own
        if (f_ok && !rst) begin
            if (f_ph == `TWH_PH_CHARGE) assert(f_cur[21:20] == 2'b00);
            if (f_ph == `TWH_PH_SYNC)   assert(!f_cur[21]);
        end
    end
`endif
endmodule
`undef TWH_E_OF
`undef TWH_L_OF
`default_nettype wire
