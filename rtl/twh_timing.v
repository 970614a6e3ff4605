// Every channel's timing registers (TIMING0-2) in one memory, and the one
// clamp that turns them into phase lengths for all engines.
//
// Why a memory: six 16-bit lengths with their window flags, a read
// multiplexer and a clamp per channel were about 285 iCE40 logic cells a
// channel; here they are block RAM (iCE40) or LUT RAM (ECP5) and one
// pipeline for all channels.
//
// - One copy of the words, each with its window flags, and one read port:
//   the fetch reads it every clock but the one of a bus read (`rd`), which
//   takes the port; the fetch of that clock is dropped and comes round
//   again (three iCE40 blocks of 16 bits rather than a copy for each side's
//   two and three).
// - POLL (the core's POLLING): each channel's fourth word, which no timing
//   register uses, is its POLL_CTRL. The bus writes and reads it as
//   register 3, and the pollers' walker (twh_polls) reads it once a
//   millisecond (pc_rd, pc_ch; the word on pc_word a clock later), taking
//   the port as a bus read does (the walker waits for a bus read, the fetch
//   of that clock is dropped). Kept here rather than in a memory of the
//   pollers, POLL_CTRL costs no block RAM of its own (two iCE40 blocks) and
//   no term of its own in the register read's AND-OR (a LUT a bit).
// - TMR (POLL above one channel, in block RAM): each channel's pollers'
//   timer lives in its POLL_CTRL word too, in bits 47:32, which the third
//   iCE40 block of a 36-bit word leaves spare (POLL_CTRL's window flags,
//   bits 35:32, are never read). The walker reads it with POLL_CTRL
//   (pc_tm beside pc_word) and writes it at its commit (tm_we, never in
//   the clock of a bus write or the sweep: the walker yields) by bit
//   lanes, so neither a bus write nor the timer's touches the other's
//   bits. That is twh_polls' timer memory gone, a block at every channel
//   count above one, for a few cells (18 at one channel, where the block
//   stays; docs/architecture.md). With LUT RAM (RAM_BLOCK = 0) the
//   blocks are not what costs, and the wider word would widen the read
//   that is the ECP5-25F's longest path: the timer stays the pollers'.
// - Reset: a sweep writes every word's default, one word a clock (`SW`
//   clocks: four words a channel, rounded up to a power of two), then waits
//   as long again (with one channel the fetch has handed over its lengths
//   from the swept words by then; above one, the visits fetch them during
//   the 2001 periods of idle a channel starts with after a reset, before it
//   can start a transaction); `ready` is low until then, and the core's
//   register port takes no request while it is (so no bus write is swept
//   over), and the pollers' walker does not start until its writes are
//   over (`sw_we`). A memory written back to its defaults
//   costs no cells a channel, where a "written since reset" flag a word
//   and its multiplexers cost about six (docs/engine.md). The word the
//   sweep writes is the core's: its request stage's data register holds
//   the default of the register `sw_reg` names (POLL_CTRL's reset value
//   at `sw_reg` = 3), so no multiplexer
//   stands between that register and the memory's write port (a LUT a
//   bit on the iCE40s).
// - The core's request stage writes (its verdict taken: in the window, or
//   lab) and reads (the address in that clock, the word a clock later on
//   rd_data, from the block RAM's own register). One request is in the
//   stage at a time, so a read never meets a write and sees every earlier
//   one.
// - Fetch: a channel's engine names the field it needs (the length its
//   next programmable phase will load); the fetch reads it, clamps it to
//   the field's spec window unless `lab` is set (the window flags were
//   taken when the word was written, by the core's twh_window), and hands
//   it to that engine (dur_we, dur, dur_fld) two clocks later. With one
//   channel the naming is nx_fld, read every clock. Above one channel it
//   is the time-shared engine's visit (sc_v, sc_ch, sc_ph, and sc_tr, the
//   TIMING register of the field named: every visit's write-back names
//   its channel and the phase it leaves, once a carrier period a channel,
//   from the engine's flip-flops): no multiplexer over
//   the channels and no register of the naming, where a round over every
//   channel's nx_fld cost about five logic cells a channel. An engine
//   loads a length only when dur_fld names the field it needs, so a
//   length is never taken from a stale fetch. A channel's field is fetched
//   again within a clock (one channel) or at its next visit (above) of a
//   change of its value or of its naming; a read of the port in that clock
//   (a bus read, the walker's) drops the fetch, which comes at the next
//   clock or visit.
`default_nettype none
`include "twh_defs.vh"
module twh_timing #(
    parameter integer CHANNELS = 1,
    // 0: the core's PROG_TIMING = 0 (never written): every length is its
    // default, handed over straight from the field named, with no memory
    // and no pipeline
    parameter integer PROG     = 1,
    // 1: nx_fld and sc_ph carry a phase (the time-shared engine's), and
    // the field its successor loads is decoded here (one decode rather
    // than one a channel)
    parameter integer NX_PHASE = 0,
    // 1: each channel's fourth word is its POLL_CTRL (the core's POLLING),
    // and the reset sweep runs with fixed timing too (PROG = 0)
    parameter integer POLL     = 0,
    // 1: the memory in block RAM (the iCE40s: they have no LUT RAM); 0:
    // LUT RAM at every depth (the ECP5: its read is faster than a DP16KD
    // block RAM's 5.8 ns from clock to output, which at 16 and 32
    // channels stood in front of the pollers' step; the core's RAM_BLOCK)
    parameter integer RAM_BLOCK = 1
) (
    input  wire                  clk,
    input  wire                  rst,
    // the reset sweep: the register port may take requests (ready); a
    // word is written with its register's reset value (sw_we), the
    // core's data register holding the default of sw_reg's
    output wire                  ready,
    output wire                  sw_we,
    output wire [1:0]            sw_reg,     // (3: POLL_CTRL's)
    input  wire                  lab,        // lengths run unclamped
    // bus write (the core's verdict taken: the value is to be stored)
    input  wire                  wr,
    input  wire [4:0]            wr_ch,      // 0 .. CHANNELS-1 (up to 32)
    input  wire [1:0]            wr_reg,     // 0-2: TIMING0-2, 3: POLL_CTRL (POLL)
    input  wire [31:0]           wr_data,    // ... or with sw_we the default sw_reg names
    input  wire [3:0]            wr_cmp,     // twh_window's flags of wr_data (0 with sw_we)
    // bus read (rd: a read of TIMING0-2, or POLL_CTRL with POLL, now: the
    // port is the bus's; the word of rd_ch, rd_reg a clock later)
    input  wire                  rd,
    input  wire [4:0]            rd_ch,
    input  wire [1:0]            rd_reg,
    output wire [31:0]           rd_data,    // one clock after rd
    // the pollers' walker (POLL): it asks to read POLL_CTRL of pc_ch now
    // (never while the sweep writes) and reads it unless the bus reads in
    // that clock (rd has the port first: the walker asks again), its word
    // on pc_word a clock later
    input  wire                  pc_rd,
    input  wire [4:0]            pc_ch,
    output wire [31:0]           pc_word,
    // TMR: pc_ch's timer, read with pc_word; and its write (tm_we: never
    // with wr or sw_we, nor with pc_rd)
    output wire [15:0]           pc_tm,
    input  wire                  tm_we,
    input  wire [15:0]           tm_wd,
    // engines: above one channel a visit names its channel's field
    // (NX_PHASE: its phase) now; with one channel nx_fld names it
    input  wire                  sc_v,
    input  wire [4:0]            sc_ch,
    input  wire [2:0]            sc_ph,
    input  wire [1:0]            sc_tr,      // the register of sc_ph's successor's field
    input  wire [CHANNELS*3-1:0] nx_fld,     // per channel: field 1-6 it needs next
                                             // (NX_PHASE: its phase; the fetch reads
                                             // it with one channel, PROG = 0 with any)
    output reg  [CHANNELS-1:0]   dur_we,
    output reg                   dur_v,      // a length is handed over (|dur_we, kept
                                             // apart: the time-shared engine reads only
                                             // this and dur_ch, so dur_we's flip-flops go)
    output reg  [4:0]            dur_ch,     // dur_we's channel, by number
    output reg  [15:0]           dur,
    output reg  [2:0]            dur_fld
);
    localparam [31:0] DEF0 = `TWH_TIMING0_DEF;
    localparam [31:0] DEF1 = `TWH_TIMING1_DEF;
    localparam [31:0] DEF2 = `TWH_TIMING2_DEF;
    function [31:0] def_word;
        input [1:0] r;
        def_word = (r == 2'd0) ? DEF0 : (r == 2'd1) ? DEF1 : DEF2;
    endfunction

    // ------------------------------------------------------------ storage
    // Four words a channel ({channel, register}: the address needs no
    // arithmetic), 16 up to four channels, then 32, 64 or 128 words (up to
    // 8, 16, 32 channels): one block RAM deep on the iCE40s up to 64
    // channels' words, and on ECP5 LUT RAM. A read in the clock its word
    // is written may see the old or the new value (no_rw_check: no
    // collision logic in front of the RAM): the bus never reads a word in
    // its write's clock (a request is a read or a write), and a fetch that
    // meets a write is repeated within CHANNELS clocks anyway.
    localparam integer AW = (CHANNELS <= 4) ? 4 : (CHANNELS <= 8) ? 5 :
                            (CHANNELS <= 16) ? 6 : 7;
    localparam integer NW = 1 << AW;
    // the word of channel c's register r is {c[AW-3:0], r}; the channel's
    // bits above AW-3 are unused (0 for every channel that exists)
    // verilator lint_off UNUSEDSIGNAL
    wire unused_ch = ^wr_ch ^ ^rd_ch ^ ^pc_ch;
    // verilator lint_on UNUSEDSIGNAL
    // {window flags, value}: the flags twh_window took of the value
    // verilator lint_off UNUSEDPARAM
    localparam STYLE = (RAM_BLOCK != 0) ? "block" : "distributed";
    // verilator lint_on UNUSEDPARAM
    localparam integer TMR = `TWH_POLL_TIMERS_IN_TIMING(POLL, CHANNELS, RAM_BLOCK);
    localparam integer MW  = (TMR != 0) ? 48 : 36;
    (* no_rw_check *) (* ram_style = STYLE *) reg [MW-1:0] mem [0:NW-1];
    wire [AW-1:0] wa = {wr_ch[AW-3:0], wr_reg};
    wire [AW-1:0] ra = {rd_ch[AW-3:0], rd_reg};
    reg  [MW-1:0] m_rd;                   // the port's word: the bus's after rd, else the fetch's

    // ------------------------------------------------------------ reset sweep
    // sw_n: the word written (first half, sw_n[AW] = 0), then the wait
    // for the fetch's round (second half); a narrow up-counter of its own
    // with the end a carry, not a compare against CHANNELS
    localparam integer SW_ON = (PROG != 0 || POLL != 0) ? 1 : 0;
    reg  [AW:0] sw_n;
    reg         sw_run;
    always @(posedge clk) begin
        if (rst) begin
            sw_n   <= {(AW+1){1'b0}};
            sw_run <= (SW_ON != 0);
        end else if (sw_run) begin
            sw_n   <= sw_n + 1'b1;
            sw_run <= (sw_n != {(AW+1){1'b1}});
        end
    end
    // Without a sweep (SW_ON = 0) the flag is a constant 0 here, not just
    // from reset: a flip-flop could hold a 1 from power-up until the first
    // reset, so synthesis would keep the counter (fourteen cells of the
    // lean build) for it.
    wire        sw_on = (SW_ON != 0) && sw_run;
    assign ready = !sw_on;
    assign sw_we = sw_on && !sw_n[AW];
    wire [AW-1:0] sw_a = sw_n[AW-1:0];
    assign sw_reg = sw_a[1:0];
    wire [31:0] rb_word = m_rd[31:0];
    assign pc_word = m_rd[31:0];
    // (the walker's read takes the port after a bus read's: its address;
    // its request is its own flip-flops', so no bus compare stands in
    // front of the memory's address: ECP5's LUT RAM reads asynchronously)
    wire          p_rd = pc_rd && POLL != 0;
    wire [AW-1:0] pa   = {pc_ch[AW-3:0], 2'b11};
    // (the port waits for ready, so a bus write never meets the sweep)
    generate
        if (TMR != 0) begin : g_wr_tm
            // one write port by lanes: the value (bus, sweep), the flags
            // (bus and sweep of TIMING0-2; the sweep's zero in POLL_CTRL's
            // is before any timer), the timer's (tm_we, at pa)
            wire [AW-1:0] w_a  = sw_we ? sw_a : tm_we ? pa : wa;
            wire          we_f = sw_we || (wr && wr_reg != 2'd3) || tm_we;
            wire [3:0]    fl_d = tm_we ? tm_wd[3:0] : wr_cmp;
            always @(posedge clk) begin
                if (wr || sw_we) mem[w_a][31:0]  <= wr_data;
                if (we_f)        mem[w_a][35:32] <= fl_d;
                if (tm_we)       mem[w_a][47:36] <= tm_wd[15:4];
            end
            assign pc_tm = m_rd[MW-1:32];
        end else begin : g_wr
            always @(posedge clk)
                if (wr || sw_we) mem[sw_we ? sw_a : wa] <= {wr_cmp, wr_data};
            assign pc_tm = 16'd0;
            // verilator lint_off UNUSEDSIGNAL
            wire unused_tm = tm_we ^ (^tm_wd);
            // verilator lint_on UNUSEDSIGNAL
        end
    endgenerate
    // (words past TIMING2 and past the last channel are swept too, and
    // never read)

    // ------------------------------------------------------------ bus read
    reg  [1:0]  rb_reg;
    always @(posedge clk) rb_reg <= rd_reg;
    assign rd_data = (PROG != 0 || (POLL != 0 && rb_reg == 2'd3)) ? rb_word : def_word(rb_reg);

    // ------------------------------------------------------------ fetch
    // stage 0: a channel names its field (one channel: nx_fld every clock;
    // above: a visit) and the word is read (unless the bus or the walker
    // reads: that fetch is dropped); stage 1: the field's half and flags
    // picked; then the clamp, into the engine's register. (f_ch, a round
    // over the channels, names them for the one-channel fetch and for the
    // build without programmable timing, which hands over defaults.)
    localparam integer LAST_I = CHANNELS - 1;
    localparam [4:0]   LAST_CH = LAST_I[4:0];
    reg  [4:0] f_ch;
    wire [2:0] f_nx  = nx_fld[f_ch*3 +: 3];
    wire [2:0] f_fld = (NX_PHASE != 0) ? `TWH_FLD_OF(f_nx) : f_nx;
    // fields 1-2 are TIMING0's, 3-4 TIMING1's, 5-6 TIMING2's (the memory's
    // read of a programmable build; with PROG = 0 only the proof reads it)
    // verilator lint_off UNUSEDSIGNAL
    wire [1:0] f_reg = `TWH_TREG_OF(f_fld);
    // verilator lint_on UNUSEDSIGNAL
    // The read address: above one channel the visit's naming, which comes
    // from the engine's flip-flops. In LUT RAM (RAM_BLOCK = 0), which reads
    // in the clock, the word's register comes decoded from there too
    // (sc_tr), as the bus's and the walker's selects are flip-flops of
    // their own (rd, pc_rd): the address is one LUT of flip-flops (the
    // decode in front of it was the ECP5-25F's longest path at three and 32
    // channels). A block RAM registers its address itself, so there the
    // register is decoded from sc_ph here (the engine's two flip-flops of
    // it placed about twenty cells more on the HX8K). One channel reads its
    // naming every clock, which is what lets a lab-short phase of one tick
    // at 4 MHz go without waiting. Either hands its length over two clocks
    // after the naming. The read stage is written out in both branches:
    // with the address as a wire chosen by CHANNELS the one-channel netlist
    // came out a dozen LUTs larger (Yosys 0.70), where this keeps it the
    // direct fetch's own.
    wire [35:0] e_word = m_rd[35:0];
    reg         e_ok;
    reg  [4:0]  e_ch;
    reg  [2:0]  e_fld;
    // (one channel: 0 as a constant, not just from reset, as the sweep's
    // flag above; with a round of one the counter could only hold a value
    // from power-up, and synthesis kept it)
    always @(posedge clk) begin
        if (rst || f_ch == LAST_CH || CHANNELS == 1) f_ch <= 5'd0;
        else                                         f_ch <= f_ch + 5'd1;
    end
    generate
        if (CHANNELS > 1) begin : g_stage
            // the visit's channel and phase (or field), registers of the
            // engine's write-back stage
            wire [4:0] a_ch = sc_ch;
            wire [2:0] a_nx = sc_ph;
            wire       a_ok = sc_v;
            wire [2:0] a_fld = (NX_PHASE != 0) ? `TWH_FLD_OF(a_nx) : a_nx;
            wire [1:0] a_reg = (RAM_BLOCK == 0) ? sc_tr : `TWH_TREG_OF(a_fld);
            always @(posedge clk)
                m_rd <= mem[rd ? ra : p_rd ? pa : {a_ch[AW-3:0], a_reg}];
            // (a word read while the sweep writes may not be swept yet:
            // nothing is handed over then)
            always @(posedge clk) begin
                e_ok      <= !rst && !rd && !p_rd && !sw_we && a_ok && a_fld != 3'd0 && a_fld <= 3'd6;
                e_ch      <= a_ch;
                e_fld     <= a_fld;
            end
        end else begin : g_direct
            // (one channel: the visits' naming is not needed)
            // verilator lint_off UNUSEDSIGNAL
            wire unused_sc = sc_v ^ (^sc_ch) ^ (^sc_ph) ^ (^sc_tr);
            // verilator lint_on UNUSEDSIGNAL
            always @(posedge clk)
                m_rd <= mem[rd ? ra : p_rd ? pa : {f_ch[AW-3:0], f_reg}];
            always @(posedge clk) begin
                e_ok      <= !rst && !rd && !p_rd && !sw_we && f_fld != 3'd0 && f_fld <= 3'd6;
                e_ch      <= f_ch;
                e_fld     <= f_fld;
            end
        end
    endgenerate
    wire        e_hi   = !e_fld[0];                // fields 2, 4, 6: a word's high half
    wire [35:0] e_val  = e_word;
    reg  [15:0] p_v;
    reg         p_b, p_a;
    reg  [2:0]  p_fld;
    reg  [4:0]  p_ch;
    // which engine the length is for, one-hot (the channel decoded on the
    // way in): each engine compares the field it is handed with the one it
    // needs in the clock it comes (ECP5's path from here into its next move)
    localparam integer ONE_I = 1;
    localparam [CHANNELS-1:0] ONE = ONE_I[CHANNELS-1:0];
    reg  [CHANNELS-1:0] p_we;
    reg                 p_ok;
    always @(posedge clk) begin
        p_ok  <= !rst && e_ok;
        p_v   <= e_hi ? e_val[31:16] : e_val[15:0];
        p_b   <= !lab && (e_hi ? e_val[34] : e_val[32]);
        p_a   <= !lab && (e_hi ? e_val[35] : e_val[33]);
        p_we  <= (!rst && e_ok) ? ONE << e_ch : {CHANNELS{1'b0}};
        p_fld <= e_fld;
        p_ch  <= e_ch;
    end
    reg [15:0] w_lo, w_hi;
    always @(*) begin
        case (p_fld)
            3'd1:    begin w_lo = `TWH_CHARGE_MIN;     w_hi = `TWH_US_MAX;       end
            3'd2:    begin w_lo = `TWH_SYNC_MIN;       w_hi = `TWH_SYNC_MAX;     end
            3'd3:    begin w_lo = `TWH_PREAMBLE_MIN;   w_hi = `TWH_PREAMBLE_MAX; end
            3'd4:    begin w_lo = `TWH_EXECUTE_MIN;    w_hi = `TWH_EXECUTE_MAX;  end
            3'd5:    begin w_lo = `TWH_LISTEN_MIN;     w_hi = `TWH_US_MAX;       end
            default: begin w_lo = `TWH_TURNAROUND_MIN; w_hi = `TWH_US_MAX;       end
        endcase
    end
    always @(*) begin
        if (PROG != 0) begin
            dur_we  = p_we;
            dur_v   = p_ok;
            dur_ch  = p_ch;
            dur     = p_b ? w_lo : p_a ? w_hi : p_v;
            dur_fld = p_fld;
        end else begin
            // the defaults lie in their windows: nothing to clamp
            dur_we  = ONE << f_ch;
            dur_v   = 1'b1;
            dur_ch  = f_ch;
            dur     = `TWH_FLD_DEF(f_fld);
            dur_fld = f_fld;
        end
    end

`ifdef FORMAL
    // ================================================================ formal
    // formal/twh_timing.sby, at one and three channels. The core's side is
    // assumed as the core's proof shows it (a write names an existing
    // channel's TIMING0-2 and carries twh_window's flags of its data); the
    // engines name fields 1-6 with NX_PHASE = 0, any phase with 1. One word, f_a, is
    // followed symbolically: what holds for it holds for every word.
    reg f_ok = 1'b0;
    always @(posedge clk) if (rst) f_ok <= 1'b1;

    // the spec windows (section 4 table), written out here
    function [15:0] f_lo;
        input [2:0] f;
        case (f)
            3'd1: f_lo = 16'd7000;  3'd2: f_lo = 16'd900;   3'd3: f_lo = 16'd1800;
            3'd4: f_lo = 16'd3500;  3'd5: f_lo = 16'd2000;  default: f_lo = 16'd2000;
        endcase
    endfunction
    function [15:0] f_hi;
        input [2:0] f;
        case (f)
            3'd2: f_hi = 16'd1100;  3'd3: f_hi = 16'd2200;  3'd4: f_hi = 16'd10000;
            default: f_hi = 16'hFFFF;
        endcase
    endfunction
    // {hi above, hi below, lo above, lo below} of a word of register r
    function [3:0] f_flags;
        input [1:0]  r;
        input [31:0] v;
        reg   [2:0]  fl, fh;
        begin
            fl = {r, 1'b0} + 3'd1;
            fh = {r, 1'b0} + 3'd2;
            f_flags = {v[31:16] > f_hi(fh), v[31:16] < f_lo(fh),
                       v[15:0] > f_hi(fl), v[15:0] < f_lo(fl)};
        end
    endfunction
    function [31:0] f_def;
        input [1:0] r;
        case (r)
            2'd0:    f_def = {16'd1000, 16'd8000};
            2'd1:    f_def = {16'd4000, 16'd2000};
            2'd2:    f_def = {16'd2000, 16'd3000};
            default: f_def = {1'b0, 15'd1000, 8'hAA, 8'h44};     // POLL_CTRL's
        endcase
    endfunction
    function [15:0] f_clamp;
        input [15:0] v;
        input [2:0]  f;
        input        unl;
        if (unl)              f_clamp = v;
        else if (v < f_lo(f)) f_clamp = f_lo(f);
        else if (v > f_hi(f)) f_clamp = f_hi(f);
        else                  f_clamp = v;
    endfunction

    integer f_c;
    always @(*) begin
        // (with PROG = 0 the core never writes TIMING0-2: its PROG_TIMING
        // is 0; POLL_CTRL, register 3, only with POLL, with any flags)
        if (wr) assume(wr_ch < CHANNELS &&
                       (wr_reg <= 2'd2 ? PROG != 0 && wr_cmp == f_flags(wr_reg, wr_data)
                                       : POLL != 0));
        // a bus read names an existing channel's TIMING0-2 (or POLL_CTRL,
        // POLL), and a request is a read or a write
        if (rd) assume(!wr && (rd_reg <= 2'd2 || POLL != 0) && rd_ch < CHANNELS);
        // the walker asks only with POLL, for an existing channel, while
        // the sweep does not write (a bus read in that clock goes first)
        if (pc_rd) assume(POLL != 0 && !sw_we && pc_ch < CHANNELS);
        // the walker writes a timer (TMR) only at its commit: never with a
        // bus write (it yields), the sweep or its own read
        if (tm_we) assume(TMR != 0 && !wr && !sw_we && !pc_rd && pc_ch < CHANNELS);
        // the core's register port takes no request during the sweep,
        // and its data register holds the default of the word swept (no
        // window flags: the defaults lie in their windows)
        if (!ready) assume(!wr && !rd);
        if (sw_we) assume(wr_data == f_def(sw_reg) && wr_cmp == 4'd0);
        // (a phase, NX_PHASE, is any of the eight)
        for (f_c = 0; f_c < CHANNELS; f_c = f_c + 1)
            if (NX_PHASE == 0) assume(nx_fld[f_c*3 +: 3] >= 3'd1 && nx_fld[f_c*3 +: 3] <= 3'd6);
        // a visit names an existing channel (any clock, any order)
        // (and the register of the field it names: the engine's proof
        // shows it for its write-back)
        if (CHANNELS > 1 && sc_v)
            assume(sc_ch < CHANNELS && (NX_PHASE != 0 || (sc_ph >= 3'd1 && sc_ph <= 3'd6)) &&
                   sc_tr == `TWH_TREG_OF((NX_PHASE != 0) ? `TWH_FLD_OF(sc_ph) : sc_ph));
    end

    // the word followed, and what it must hold: f_w, written since the
    // reset; f_val, the last value written
    (* anyconst *) reg [4:0] f_ach;
    (* anyconst *) reg [1:0] f_areg;
    wire [AW-1:0] f_a = {f_ach[AW-3:0], f_areg};        // where it is stored
    // a write, read or fetch of that register, by channel and register (not
    // by the address formula: a formula that put two registers in one word
    // would then break the word's value)
    wire f_wr_a = wr && wr_ch == f_ach && wr_reg == f_areg;
    always @(*) assume(f_ach < CHANNELS && (f_areg <= 2'd2 || POLL != 0));
    reg        f_w;
    reg [31:0] f_val;
    always @(posedge clk) begin
        if (rst) begin
            f_w <= 1'b0;
        end else if (f_wr_a) begin
            f_w   <= 1'b1;
            f_val <= wr_data;
        end
    end
    wire [31:0] f_now = f_w ? f_val : f_def(f_areg);      // the register's value
    wire [31:0] f_dw  = f_def(f_reg);                     // the default of the field fetched

    always @(*) begin
        if (f_ok) begin
            // the sweep has written the word's default (and the defaults
            // lie in their windows: no flags) or a write its value, which
            // only comes once the sweep is over
            if (PROG != 0 && f_areg != 2'd3 && (!sw_on || sw_n[AW] || sw_n[AW-1:0] > f_a))
                assert(mem[f_a][35:0] == (f_w ? {f_flags(f_areg, f_val), f_val}
                                              : {4'd0, f_def(f_areg)}));
            // (POLL_CTRL's flags are never read)
            if (POLL != 0 && f_areg == 2'd3 && (!sw_on || sw_n[AW] || sw_n[AW-1:0] > f_a))
                assert(mem[f_a][31:0] == f_now);
            if (f_w) assert(!sw_on);
            // (the core's stand-in jobs take this as given)
            if (sw_we) assert(!ready);
            if (PROG == 0 && POLL == 0) assert(!sw_on);
            // the fetch takes every channel in turn
            assert(f_ch < CHANNELS);
            // fixed timing: no timing register is ever written
            if (PROG == 0 && f_areg != 2'd3) assert(!f_w);
        end
    end

    // ---- TMR: the followed channel's timer, in its POLL_CTRL word's
    // lanes 47:32, is the last the walker wrote (no bus write or sweep
    // touches it), and the walker reads it so
    reg        f_tw;
    reg [15:0] f_tv;
    always @(posedge clk) begin
        if (rst) begin
            f_tw <= 1'b0;
        end else if (tm_we && pc_ch == f_ach && f_areg == 2'd3) begin
            f_tw <= 1'b1;
            f_tv <= tm_wd;
        end
    end
    reg        f_pt = 1'b0;
    reg [15:0] f_pt_want;
    always @(posedge clk) begin
        f_pt      <= f_ok && !rst && pc_rd && !rd && pc_ch == f_ach && f_areg == 2'd3 && f_tw;
        f_pt_want <= f_tv;
    end
    generate
        if (TMR != 0) begin : g_f_tm
            always @(*) begin
                // (a timer is written only after the sweep's writes,
                // whose zero in POLL_CTRL's flag lanes would clear its
                // low bits: the walker starts in the sweep's wait)
                if (f_ok && f_tw) assert(f_areg == 2'd3 && (!sw_on || sw_n[AW]) &&
                                         mem[f_a][47:32] == f_tv);
                if (f_pt) assert(pc_tm == f_pt_want);
            end
        end
    endgenerate

    // ---- the bus reads the register's value as of its request's clock
    // (a read in the clock its word is written may see either value: the
    // core never makes one, a request being a read or a write)
    reg        f_rd = 1'b0;
    reg [31:0] f_rd_want;
    always @(posedge clk) begin
        f_rd      <= f_ok && !rst && rd && rd_ch == f_ach && rd_reg == f_areg;
        f_rd_want <= f_now;
    end
    always @(*) if (f_rd) assert(rd_data == f_rd_want);

    // ---- the walker reads POLL_CTRL's value as of its read's clock, or
    // as a bus write in that clock leaves it (the pollers read again then)
    reg        f_pr = 1'b0;
    reg [31:0] f_pr_want, f_pr_wn;
    always @(posedge clk) begin
        f_pr      <= f_ok && !rst && pc_rd && !rd && pc_ch == f_ach && f_areg == 2'd3;
        f_pr_want <= f_now;
        f_pr_wn   <= f_wr_a ? wr_data : f_now;
    end
    always @(*) if (f_pr) assert(pc_word == f_pr_want || pc_word == f_pr_wn);

    // ---- every fetch hands its channel the field it named, clamped into
    // the field's window unless lab was set in the clock after the read
    // (one channel: nx_fld every clock; above: each visit's naming), but
    // the one a bus read or the walker's displaced, which hands nothing over
    localparam [0:0] STAGE = (CHANNELS > 1);
    reg        f1_ok = 1'b0, f2_ok = 1'b0;
    reg        f1_hit, f2_hit, f2_lab;
    reg [4:0]  f1_ch, f2_ch;
    reg [2:0]  f1_fld, f2_fld;
    // the value as of the read, and as a write in that clock leaves it
    // (a fetch that meets a write may take either)
    reg [31:0] f1_v, f2_v, f1_vn, f2_vn;
    wire [2:0] sc_fld = (NX_PHASE != 0) ? `TWH_FLD_OF(sc_ph) : sc_ph;
    wire       r_ok  = f_ok && !rst && (!STAGE || sc_v);  // a fetch reads now ...
    wire [4:0] r_ch  = STAGE ? sc_ch  : f_ch;             // ... this channel's
    wire [2:0] r_fld = STAGE ? sc_fld : f_fld;            // ... named field
    wire [1:0] r_reg = (r_fld <= 3'd2) ? 2'd0 : (r_fld <= 3'd4) ? 2'd1 : 2'd2;
    always @(posedge clk) begin
        f1_ok  <= r_ok && !rst && !rd && !pc_rd && !sw_we;
        f1_hit <= r_ch == f_ach && r_reg == f_areg;
        f1_ch  <= r_ch;
        f1_fld <= r_fld;
        f1_v   <= f_now;
        f1_vn  <= f_wr_a ? wr_data : f_now;
        f2_ok  <= f1_ok && !rst;
        f2_hit <= f1_hit;
        f2_ch  <= f1_ch;
        f2_fld <= f1_fld;
        f2_v   <= f1_v;
        f2_vn  <= f1_vn;
        f2_lab <= lab;
    end
    wire        f2_hi   = f2_fld == 3'd2 || f2_fld == 3'd4 || f2_fld == 3'd6;
    wire [15:0] f2_half = f2_hi ? f2_v[31:16] : f2_v[15:0];
    wire [15:0] f2_halfn = f2_hi ? f2_vn[31:16] : f2_vn[15:0];
    always @(*) begin
        if (PROG == 0 && f_ok) begin
            // fixed timing: each channel in turn gets its field's default
            assert(dur_we == ({{(CHANNELS-1){1'b0}}, 1'b1} << f_ch));
            assert(dur_fld == f_fld);
            assert(dur == f_clamp(f_fld[0] ? f_dw[15:0] : f_dw[31:16], f_fld, 1'b0));
        end
        if (PROG != 0 && f2_ok) begin
            assert(dur_we == ({{(CHANNELS-1){1'b0}}, 1'b1} << f2_ch));
            assert(dur_fld == f2_fld);
            if (f2_hit) assert(dur == f_clamp(f2_half, f2_fld, f2_lab) ||
                               dur == f_clamp(f2_halfn, f2_fld, f2_lab));
        end
        if (PROG != 0 && f_ok && !f2_ok) assert(dur_we == {CHANNELS{1'b0}});
        // dur_v is "a length is handed over": dur_we's OR
        if (f_ok) assert(dur_v == (dur_we != {CHANNELS{1'b0}}));
    end
    always @(posedge clk) begin
        if (f_ok && !rst)
            assert(f_ch == (($past(f_ch) == LAST_CH || $past(rst)) ? 5'd0 : $past(f_ch) + 5'd1));
    end
`endif
endmodule
`default_nettype wire
