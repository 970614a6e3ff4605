// Bus-agnostic core: CHANNELS channels running concurrently, a shared
// command FIFO and result FIFO, and the registers of rdl/twh_regs.rdl behind
// a simple pipelined register port that the Wishbone (twh_wb) and AXI4-Lite
// (twh_axil) wrappers drive. The channels are the time-shared engine
// (twh_core_engine: every channel's state in RAM, docs/engine.md).
//
// Register port: a request (reg_req, with reg_we, reg_addr, reg_wdata,
// reg_wstrb) is taken into a register stage, carried out on the next clock
// and answered on the clock after that: reg_ack, reg_err and reg_rdata come
// two clocks after the request. Requests may follow on every clock; they
// are carried out in order, so a read sees every earlier write. reg_ack and
// reg_err are registers; reg_rdata is a register ORed with the timing
// registers' block RAM output (twh_timing), itself a register. The stage
// is there for speed: everything the request decides starts from its
// flip-flops, and the checks that need a comparator (the timing windows, the
// unlock keys, the factory-area rule) are taken on the way into it.
// A request is made only while reg_ready is 1. After a reset it is 0 while
// twh_timing's sweep writes every timing register's and POLL_CTRL's reset value
// into the memories and the engines take their lengths from them: 32
// clocks up to 4 channels, 64 up to 8, 128 up to 16, 256 up to 32 (none
// with fixed timing and no poller); then 1 until the next reset. (A
// "written since reset" flag a register in place of the sweep cost about
// six logic cells a channel.)
// Errors: unmapped address, a write with byte enables other than all four,
// a push into the full command FIFO, a push for an absent channel.
//
// Dispatch: the command FIFO's head moves on into its channel when the
// channel can take it: its queue of four is not full. A head waiting for a
// channel that cannot take it holds back the commands behind it; with the
// queues that happens only beyond four commands for one channel.
// Results: the engine hands each over straight into the result FIFO while
// it has room, and its claim gives every channel its turn (docs/engine.md);
// a full FIFO holds the channels back and no result is ever dropped.
`default_nettype none
`include "twh_defs.vh"
module twh_core #(
    parameter integer CLK_HZ     = 48_000_000,
    parameter integer CHANNELS   = 1,
    parameter integer FIFO_DEPTH = 16,
    // Features a fixed board may leave out (docs/integration.md, "Lean
    // builds"); the register map stays the same, the registers of a left-out
    // feature are read-only and say so in VERSION.
    parameter integer PROG_TIMING = 1,   // 0: TIMING0-2 fixed at the defaults, writes refused
    parameter integer POLLING     = 1,   // 0: no poller; POLL_CTRL writes with EN = 1 refused
    // The channels run on the time-shared twh_engine (docs/engine.md), every
    // channel's state in RAM, a queue of four commands a channel behind the
    // command FIFO. 1 keeps the engine's memories (state, queues, phase
    // lengths) in block RAM on every part, as the iCE40s need (no LUT RAM:
    // a shallow memory would become flip-flops); 0 asks for LUT RAM at
    // every depth, for parts that have it (the ECP5: faster to read than
    // its block RAM; docs/integration.md, "Parameters")
    parameter integer RAM_BLOCK   = 1
) (
    input  wire                clk,
    input  wire                rst,
    // register port
    output wire                reg_ready,    // a request may be made (0 after a reset, for a while)
    input  wire                reg_req,
    input  wire                reg_we,
    input  wire [10:0]         reg_addr,
    input  wire [31:0]         reg_wdata,
    input  wire [3:0]          reg_wstrb,
    output reg                 reg_ack,
    output reg                 reg_err,
    output wire [31:0]         reg_rdata,
    output wire                irq,
    // 2-wire pins
    output wire [CHANNELS-1:0] line_o,
    output wire [CHANNELS-1:0] line_oe,
    input  wire [CHANNELS-1:0] line_i
);
    // ------------------------------------------------------------ parameter checks
    // The legal ranges, here and nowhere else (CLK_HZ's: twh_carrier). A
    // value outside its range instantiates a module that does not exist,
    // named for the parameter and its range, and every tool stops on it as
    // missing (docs/integration.md, "Parameters"). A range is its
    // localparams and its module's name: change both together
    // (tb/test_params.py reads them and checks that they agree).
    localparam integer CHANNELS_MIN   = 1;
    localparam integer CHANNELS_MAX   = 32;
    localparam integer FIFO_DEPTH_MIN = 2;      // and a power of two
    localparam integer FIFO_DEPTH_MAX = 2048;
    localparam CHANNELS_OK   = CHANNELS >= CHANNELS_MIN && CHANNELS <= CHANNELS_MAX;
    localparam FIFO_DEPTH_OK = FIFO_DEPTH >= FIFO_DEPTH_MIN && FIFO_DEPTH <= FIFO_DEPTH_MAX &&
                               (FIFO_DEPTH & (FIFO_DEPTH - 1)) == 0;
    generate
        if (!CHANNELS_OK) begin : g_bad_channels
            twh_error_CHANNELS_must_be_1_to_32 u_err ();
        end
        if (!FIFO_DEPTH_OK) begin : g_bad_depth
            twh_error_FIFO_DEPTH_must_be_a_power_of_two_2_to_2048 u_err ();
        end
    endgenerate
    // What the submodules are built with: the parameter, or after a failed
    // check a legal stand-in, so that no tool breaks on the bad value (a
    // memory or index out of range) before it reports the missing module.
    localparam integer CH_N    = CHANNELS_OK ? CHANNELS : 1;
    localparam integer DEPTH_N = FIFO_DEPTH_OK ? FIFO_DEPTH : 16;

    localparam integer LW = $clog2(DEPTH_N + 1);
    localparam [5:0]  CH_COUNT = CHANNELS[5:0];
    localparam integer CH_END_I = CHANNELS + 4;
    localparam [5:0]  CH_END   = CH_END_I[5:0];     // the first block past the channels'
    localparam [11:0] DEPTH12  = FIFO_DEPTH[11:0];
    localparam integer CLK_KHZ_I = CLK_HZ / 1000;
    localparam [19:0] CLK_KHZ  = CLK_KHZ_I[19:0];
    localparam [0:0]  FIXED_TIMING = (PROG_TIMING == 0);
    localparam [0:0]  NO_POLLING   = (POLLING == 0);

    // ------------------------------------------------------------ millisecond tick
    // One carrier generator for the core: its tick starts every channel's
    // carrier period and counts microseconds for the poll timers; every
    // channel's engine steps on it, so all lines' carriers run in step.
    wire us_tick, us_tick_nx, us_fall;
    // (the engine's clock floor is checked here too, after the carrier's own
    // checks, so that a bad clock names one error)
    twh_carrier #(.CLK_HZ(CLK_HZ), .FLOOR_CHANNELS(CH_N)) u_tick (
        .clk(clk), .rst(rst), .tick(us_tick), .tick_nx(us_tick_nx), .fall(us_fall)
    );
    reg [9:0] us_count;
    reg       ms_tick;
    always @(posedge clk) begin
        if (rst) begin
            us_count <= 10'd0;
            ms_tick  <= 1'b0;
        end else if (us_tick || ms_tick) begin   // else nothing moves
            ms_tick <= 1'b0;
            if (us_tick) begin
                if (us_count == 10'd999) begin
                    us_count <= 10'd0;
                    ms_tick  <= 1'b1;
                end else begin
                    us_count <= us_count + 1'b1;
                end
            end
        end
    end

    // ------------------------------------------------------------ request stage
    // Checks taken on the way in, from the bus data (none depends on state
    // that the request ahead could change, except the lab unlock, which is
    // applied after the stage):
    // - i_cmp: where the two fields of a timing value lie against the spec
    //   windows of the channel register addressed (TIMING0-2), one shared
    //   checker whose constants the address picks; twh_timing keeps the
    //   flags with the value and clamps by them;
    // - i_win_p: a POLL_CTRL value switches polling off or names a
    //   read-only command;
    // - the two unlock keys; the factory-area rule of a command word.
    wire [7:0]  i_cmd = reg_wdata[7:0];
    wire [3:0]  i_cmp;           // {hi above, hi below, lo above, lo below}
    twh_window u_window (
        .sel(reg_addr[3:2]), .value(reg_wdata),
        .lo_below(i_cmp[0]), .lo_above(i_cmp[1]), .hi_below(i_cmp[2]), .hi_above(i_cmp[3])
    );
    // Each compare of a bus field with a constant range is a constant map
    // (bit k: k is in the range) indexed by the field: synthesis folds it
    // into a few LUTs, where a `<` against a constant became an iCE40 carry
    // chain, one logic cell a bit whose LUT is left empty, and one more to
    // take the chain's carry out (47 cells at one channel, HX8K).
    // The read-only commands a poll may name: 0x40-0x44, 0x46-0x49.
    localparam [255:0] RO_CMD_MAP = (256'h1F << 8'h40) | (256'h0F << 8'h46);
    // the command is checked only when polling is switched on, so writing 0
    // always stops polling
    wire        i_win_p = !reg_wdata[31] || ((POLLING != 0) && RO_CMD_MAP[i_cmd]);
    // erase (0x4A/4B) or write (0x80-0xFF) addressed to words 0x00-0x1F
    // (bit k of the map: word k is in the factory area)
    localparam [511:0] FACTORY_MAP = (512'd1 << `TWH_FACTORY_END) - 512'd1;
    wire [8:0]  i_erase_addr = {i_cmd[0], reg_wdata[15:8]};     // payload low byte
    wire [8:0]  i_write_addr = {reg_wdata[23:22], i_cmd[6:0]};  // payload bits 15:14
    wire        i_factory = ((i_cmd[7:1] == 7'b0100101) && FACTORY_MAP[i_erase_addr]) ||
                            (i_cmd[7] && FACTORY_MAP[i_write_addr]);

    // The address is decoded on the way in too: one flag per register that
    // a write or a read changes something in, and whether it is mapped.
    // Global registers are words 0-31 (0x000-0x07C), channel n's block is
    // at 0x80 + 0x20 * n (n < 32) and its register k at + 4 * k.
    localparam [4:0] R_ID = 5'd0, R_VERSION = 5'd1, R_PARAMS = 5'd2, R_CTRL = 5'd3,
                     R_STATUS = 5'd4, R_LEVELS = 5'd5, R_ERRORS = 5'd6, R_IRQ_EN = 5'd7,
                     R_IRQ_STATUS = 5'd8, R_POLL_READY = 5'd9,
                     R_RES_INFO = 5'd11, R_RES_POP = 5'd12, R_LAB_KEY = 5'd13,
                     R_FACTORY_KEY = 5'd14, R_IDLE_CHARGE = 5'd15, R_BUSY = 5'd16;
    localparam [2:0] C_CMD_PUSH = 3'd6;         // a channel block's CMD_PUSH
    wire       i_is_ch  = (reg_addr[10:7] != 4'd0);
    wire [4:0] i_blk    = reg_addr[9:5] - 5'd4;    // the channel block (the register stage's)
    // (the checks compare the block's address with constants, not the
    // subtraction's result: a carry chain into a compare was the UP5K's
    // path into the request stage)
    // (bit k of a map: 32-byte block k is a present channel's / any
    // channel's, CH[0] being block 4)
    localparam [63:0] BLK_CH_MAP  = ((64'd1 << CH_END) - 64'd1) & ~64'hF;
    localparam [63:0] BLK_ANY_MAP = ((64'd1 << 36) - 64'd1) & ~64'hF;
    wire       i_ch_ok  = BLK_CH_MAP[reg_addr[10:5]];
    wire [4:0] i_g      = reg_addr[6:2];
    // a full-word write, a read, a read of a global register: of the
    // request on the port, when there is one (the strobes below)
    wire       i_wr     = reg_we && (reg_wstrb == 4'hF);
    wire       i_rd     = !reg_we;
    wire       i_grd    = !reg_we && !i_is_ch;
    // a CMD_PUSH write in the channel array (CH[0] to CH[31]), the channel
    // present or not (an absent one's is BAD_CHANNEL)
    wire       i_push   = i_wr && BLK_ANY_MAP[reg_addr[10:5]] && reg_addr[4:2] == C_CMD_PUSH;
    // The request's data loads only around a request (this one, or the
    // clock after one); between requests its strobes are 0 and the data is
    // unused. Icarus runs every clocked block on every clock, and the idle
    // bus was most of the core's cost there.
    wire       i_load   = rst || reg_req || q_req;
    // The reset sweep (twh_timing, while the port is not ready) writes its
    // words through this stage's data register too: from reset on it holds
    // the default of the register the sweep writes next (TIMING0-2, then
    // POLL_CTRL's reset value, each channel's fourth word), so twh_timing's
    // memory has no multiplexer of its own in front of it (the one here is
    // in the register's own cells).
    // The data's load takes the sweep too, the strobes' does not: the
    // sweep in the strobes' enable was ECP5's path into their reset.
    wire        t_ready, t_sw_we;     // (twh_timing's, below)
    wire [1:0]  t_sw_reg;
    wire       d_load   = i_load || t_sw_we;
    wire       sw_load  = rst || t_sw_we;
    wire [1:0] sw_nx    = rst ? 2'd0 : t_sw_reg + 2'd1;
    wire [31:0] sw_word = (sw_nx == 2'd0) ? `TWH_TIMING0_DEF :
                          (sw_nx == 2'd1) ? `TWH_TIMING1_DEF :
                          (sw_nx == 2'd2) ? `TWH_TIMING2_DEF :
                                            `TWH_POLL_CTRL_DEF;
    reg        q_req, q_we, q_full, q_key_lab, q_key_fact, q_factory;
    reg        q_wr, q_rd, q_mapped, q_bad_ch;
    // Read selects, one per register a read shows (none for write-only or
    // unmapped addresses): the answer is an AND-OR of flip-flops with no
    // address decode in front of it. RES_INFO's and RES_POP's carry "the
    // result FIFO is not empty" too (q_pop is RES_POP's pop).
    reg        q_r_id, q_r_version, q_r_params, q_r_ctrl, q_r_status, q_r_levels,
               q_r_errors, q_r_irq_en, q_r_irq_status, q_r_poll_ready, q_r_res_info,
               q_r_res_pop, q_r_idle, q_r_busy;
    // TIMING0-2 (q_r_t), or POLL_CTRL (q_r_pc, in twh_timing's memory too
    // with POLLING), of an existing channel read: twh_timing's memory. In
    // LUT RAM (RAM_BLOCK = 0, the ECP5's), which reads its address in the
    // clock, that read selects the address, so it is one flip-flop of its
    // own (q_r_tm: an OR of the two stood there); a block RAM registers
    // its address itself, and there the OR is what placed better (the
    // UP5K's top at three channels: a median of 51.2 MHz against 47.2
    // with q_r_tm and the walker's w_r). The unused ones are removed.
    reg        q_r_t, q_r_pc, q_r_tm;
    // POLL_RESULT / STATE of an existing channel read (twh_polls' memory
    // and the engine's copies: twh_core_engine)
    reg        q_r_pr, q_r_st;
    reg        q_cmp_nz;         // ... not all zero: a field lies outside its window
    reg        q_win_p;          // i_win_p of the request
    // The REFUSED verdict's parts, taken on the way in so that the error
    // bit waits only for the lab unlock (the window flags' OR into it was
    // HX8K's critical path): a write to TIMING0-2 of an existing channel,
    // and a POLL_CTRL write there that must be refused (lab does not
    // apply to it).
    reg        q_wr_t, q_ref_p;
    reg [3:0]  q_cmp;            // i_cmp of the request: stored with a timing value
    reg        q_wp;             // POLL_CTRL of an existing channel addressed
    reg        q_ctrl, q_flush, q_errors, q_irq_en, q_poll_ready, q_push, q_pop, q_lab_key, q_fact_key,
               q_idle;
    reg        q_push_ch;        // q_push naming an existing channel: the FIFO's push
                                 // waits for the full flag alone (ECP5's critical path)
    reg [10:0] q_addr;
    reg [4:0]  q_blk;            // q_addr[10:5] - 4: the channel block, taken on the
                                 // way in (the subtraction was in front of the bus
                                 // copy's LUT RAM read address, ECP5's path)
    reg [31:0] q_wdata;
    wire       res_valid_next;   // the result FIFO's !empty of the next clock
    // The data of the request, loaded only around one (see i_load), or the
    // sweep's word (none of the checks on the data holds for it).
    always @(posedge clk) if (d_load) begin
        q_we       <= reg_we;
        q_full     <= (reg_wstrb == 4'hF);
        q_addr     <= reg_addr;
        q_blk      <= i_blk;
        q_wdata    <= sw_load ? sw_word : reg_wdata;
        q_cmp      <= sw_load ? 4'd0 : i_cmp;
        q_cmp_nz   <= !sw_load && (i_cmp != 4'd0);
        q_win_p    <= i_win_p;
        q_key_lab  <= !sw_load && (reg_wdata == `TWH_LAB_KEY);
        q_key_fact <= !sw_load && (reg_wdata == `TWH_FACTORY_KEY);
        q_factory  <= !sw_load && i_factory;
        q_bad_ch   <= !i_ch_ok;
        q_mapped   <= i_is_ch ? (i_ch_ok && reg_addr[4:2] <= 3'd6)
                              : (i_g <= R_BUSY && i_g != 5'd10);
        q_wp       <= i_ch_ok && reg_addr[4:2] == 3'd3;
    end
    // Its strobes and read selects: the address decoded as if a request
    // were on the port, cleared by the flip-flops' synchronous reset when
    // none is (or in reset). The port's strobe then waits for one LUT in
    // front of that reset, not for the decode (the Wishbone strobe, behind
    // twh_wb's busy flag, was ECP5's path into these).
    // (loaded only around a request too: see i_load)
    always @(posedge clk) if (i_load) begin
        if (rst || !reg_req) begin
            q_req <= 1'b0; q_wr <= 1'b0; q_rd <= 1'b0;
            q_wr_t <= 1'b0; q_r_t <= 1'b0; q_r_pc <= 1'b0; q_r_tm <= 1'b0; q_ref_p <= 1'b0; q_r_pr <= 1'b0; q_r_st <= 1'b0;
            q_r_id <= 1'b0; q_r_version <= 1'b0; q_r_params <= 1'b0; q_r_ctrl <= 1'b0;
            q_r_status <= 1'b0; q_r_levels <= 1'b0; q_r_errors <= 1'b0; q_r_irq_en <= 1'b0;
            q_r_irq_status <= 1'b0; q_r_poll_ready <= 1'b0; q_r_res_info <= 1'b0;
            q_r_res_pop <= 1'b0; q_r_idle <= 1'b0; q_r_busy <= 1'b0; q_idle <= 1'b0;
            q_ctrl <= 1'b0; q_flush <= 1'b0; q_errors <= 1'b0; q_irq_en <= 1'b0;
            q_poll_ready <= 1'b0; q_push <= 1'b0; q_push_ch <= 1'b0; q_pop <= 1'b0;
            q_lab_key <= 1'b0; q_fact_key <= 1'b0;
        end else begin
            q_req      <= 1'b1;
            q_wr       <= i_wr;
            q_rd       <= i_rd;
            q_wr_t     <= i_wr && i_ch_ok && reg_addr[4:2] <= 3'd2;
            q_r_t      <= i_rd && i_ch_ok && reg_addr[4:2] <= 3'd2;
            q_r_pc     <= i_rd && i_ch_ok && reg_addr[4:2] == 3'd3;
            q_r_tm     <= i_rd && i_ch_ok && (reg_addr[4:2] <= 3'd2 ||
                                          (POLLING != 0 && reg_addr[4:2] == 3'd3));
            q_r_pr     <= i_rd && i_ch_ok && reg_addr[4:2] == 3'd4;
            q_r_st     <= i_rd && i_ch_ok && reg_addr[4:2] == 3'd5;
            q_ref_p    <= i_wr && i_ch_ok && reg_addr[4:2] == 3'd3 && !i_win_p;
            q_r_id         <= i_grd && i_g == R_ID;
            q_r_version    <= i_grd && i_g == R_VERSION;
            q_r_params     <= i_grd && i_g == R_PARAMS;
            q_r_ctrl       <= i_grd && i_g == R_CTRL;
            q_r_status     <= i_grd && i_g == R_STATUS;
            q_r_levels     <= i_grd && i_g == R_LEVELS;
            q_r_errors     <= i_grd && i_g == R_ERRORS;
            q_r_irq_en     <= i_grd && i_g == R_IRQ_EN;
            q_r_irq_status <= i_grd && i_g == R_IRQ_STATUS;
            q_r_poll_ready <= i_grd && i_g == R_POLL_READY;
            q_r_idle       <= i_grd && i_g == R_IDLE_CHARGE;
            q_r_busy       <= i_grd && i_g == R_BUSY;
            // masked on the way in by "not empty" as the FIFO will be when
            // the read is carried out (an empty FIFO's fields read zero), so
            // neither the empty flag nor its AND is on the read path
            q_r_res_info   <= i_grd && i_g == R_RES_INFO && res_valid_next;
            q_r_res_pop    <= i_grd && i_g == R_RES_POP && res_valid_next;
            // write (or, for RES_POP, read) strobes of the global registers
            q_ctrl       <= i_wr && !i_is_ch && i_g == R_CTRL;
            q_flush      <= i_wr && !i_is_ch && i_g == R_CTRL && reg_wdata[1];
            q_errors     <= i_wr && !i_is_ch && i_g == R_ERRORS;
            q_irq_en     <= i_wr && !i_is_ch && i_g == R_IRQ_EN;
            q_poll_ready <= i_wr && !i_is_ch && i_g == R_POLL_READY;
            q_idle       <= i_wr && !i_is_ch && i_g == R_IDLE_CHARGE;
            q_push       <= i_push;
            q_push_ch    <= i_push && i_ch_ok;
            q_pop        <= i_grd && i_g == R_RES_POP;
            q_lab_key    <= i_wr && !i_is_ch && i_g == R_LAB_KEY;
            q_fact_key   <= i_wr && !i_is_ch && i_g == R_FACTORY_KEY;
        end
    end

    // ------------------------------------------------------------ decode
    // The request's address decoded again, for the proofs only: every flag
    // of the request stage is proven equal to this decode of q_addr.
    // verilator lint_off UNUSEDSIGNAL
    wire       is_ch     = (q_addr[10:7] != 4'd0);            // 0x80 and up
    wire [5:0] ch_blk    = q_addr[10:5] - 6'd4;               // channel block
    wire [4:0] ch_sel    = ch_blk[4:0];
    wire [2:0] ch_reg    = q_addr[4:2];
    wire       ch_exists = is_ch && (ch_blk < CH_COUNT) && (ch_reg <= 3'd6);
    wire [4:0] g_reg     = q_addr[6:2];
    // verilator lint_on UNUSEDSIGNAL
    wire       full_word = q_full;
    // verilator lint_off UNUSEDSIGNAL
    wire       wr        = q_wr;         // q_req && q_we && full_word (formal only: the
    wire       rd        = q_rd;         // q_req && !q_we              strobes include them)
    // verilator lint_on UNUSEDSIGNAL
    wire       mapped    = q_mapped;     // a global register, or one of an existing channel

    // ------------------------------------------------------------ control registers
    reg        enable, lab, factory_armed;
    reg [LW-1:0] flush_left;    // queued commands a flush still has to cancel
    reg        flushing;        // flush_left != 0, kept as a flag: it steers dispatch
    wire [LW-1:0] flush_new = cmd_level - {{(LW-1){1'b0}}, take};   // what a flush now cancels
    // flush_new != 0, with the take as the last choice rather than through
    // the subtraction (it was ECP5's critical path)
    wire       flush_new_nz = take ? (cmd_level != {{(LW-1){1'b0}}, 1'b1})
                                       : (cmd_level != {LW{1'b0}});
    reg [CH_N-1:0] idle_charge;
    reg        ie_result, ie_error, ie_poll;
    reg [7:0]  res_threshold;
    reg        err_overflow, err_refused, err_blocked, err_bad_channel, err_link;
    reg [CH_N-1:0] poll_ready;

    // ------------------------------------------------------------ command FIFO
    // entry: {blocked, tag[4:0], channel[4:0], payload[15:0], cmd[7:0]}
    // (the channel from the CMD_PUSH's address)
    // The factory-area verdict is taken on the way in, from the bus data, so
    // the FIFO's RAM output drives no comparator on its way to the engine.
    wire        push_req  = q_push;
    wire        cmd_full, cmd_empty;
    // verilator lint_off UNUSEDSIGNAL
    wire        cmd_valid_next;       // the command FIFO is read by dispatch alone
    // verilator lint_on UNUSEDSIGNAL
    wire        cmd_vacant;           // no command queued (STATUS.CMD_EMPTY)
    wire [LW-1:0] cmd_level;
    // A command FIFO entry: {blocked, tag, channel, payload, code}, the
    // channel in as many bits as its count needs (CF_CW): with up to four
    // channels an entry is 32 bits, two iCE40 blocks rather than three
    localparam integer CF_CW = (CH_N > 2) ? $clog2(CH_N) : 1;
    localparam integer CF_T  = 24 + CF_CW;       // the tag's low bit
    localparam integer CF_B  = CF_T + 5;         // the blocked flag
    localparam integer CF_W  = CF_B + 1;
    // above four channels the entry's bits above 32 (the channel's top
    // ones) in flip-flops, so that the RAM stays two iCE40 blocks rather
    // than three (twh_fifo's LH: 3 x FIFO_DEPTH flip-flops and their
    // multiplexer at 32 channels); with LUT RAM (RAM_BLOCK = 0: the ECP5,
    // whose block RAM is 36 bits wide anyway) the entry stays whole
    localparam integer CF_LH = (RAM_BLOCK != 0 && CF_W > 32) ? CF_W - 32 : 0;
    wire [CF_W-1:0] cmd_head;
    wire        push_bad_ch = q_bad_ch;      // the push is to an absent channel
    wire        push_ok   = q_push_ch && !cmd_full;

    wire        p_blocked = q_factory && !factory_armed;

    wire [7:0]  h_cmd     = cmd_head[7:0];
    wire [15:0] h_payload = cmd_head[23:8];
    // verilator lint_off UNUSEDSIGNAL
    wire [31:0] h_ch_w    = {{(32-CF_CW){1'b0}}, cmd_head[CF_T-1:24]};
    // verilator lint_on UNUSEDSIGNAL
    // (one channel: channel 0, said as a constant; the FIFO's word says so
    // too, but synthesis cannot see into a RAM, and the compares behind it
    // stayed)
    wire [4:0]  h_ch      = (CH_N == 1) ? 5'd0 : h_ch_w[4:0];
    wire [4:0]  h_tag     = cmd_head[CF_B-1:CF_T];
    wire        h_blocked = cmd_head[CF_B];

    // Dispatch: the FIFO's head is offered to the engine (`dispatch`, a
    // flip-flop, as are its channel and blocked flag: the decision reads
    // the FIFO's RAM output, slow on iCE40) and stays offered, unchanged,
    // until the engine takes it (`take`: its channel's visit, with room in
    // the channel's queue), which pops it. So a command waits at the head
    // of the FIFO for its visit, not in a register of the engine, and a
    // flush meanwhile counts it among the FIFO's. After a take the next
    // head is offered from the clock after next.
    reg  dispatch;
    wire e_ready;            // the engine takes the offered command now
    wire take = dispatch && e_ready;
    reg  [4:0] disp_ch;
    reg        disp_blk;     // h_blocked, taken with the decision like disp_ch
                             // (the RAM output was HX8K's path into BLOCKED)
    always @(posedge clk) begin
        if (rst)           dispatch <= 1'b0;
        else if (dispatch) dispatch <= !e_ready;
        else               dispatch <= !cmd_empty && (enable || flushing);
        if (!dispatch) begin     // (held while offered: the head does not change)
            disp_ch  <= h_ch;
            disp_blk <= h_blocked;
        end
    end
    // a flush written in the clock a command is taken cancels it too: it
    // was queued when the flush came (the engine's cancel misses it)
    wire       flush_wr = q_flush;
    wire [3:0] h_skip = (flushing || flush_wr) ? `TWH_ST_CANCELLED :
                        disp_blk               ? `TWH_ST_BLOCKED : 4'd0;

    twh_fifo #(.W(CF_W), .DEPTH(DEPTH_N), .LH(CF_LH)) u_cmd_fifo (
        .clk(clk), .rst(rst),
        .push(push_ok), .din({p_blocked, q_wdata[28:24], q_blk[CF_CW-1:0], q_wdata[23:0]}), .full(cmd_full),
        .pop(take), .dout(cmd_head), .empty(cmd_empty), .valid_next(cmd_valid_next),
        .level(cmd_level), .vacant(cmd_vacant)
    );

    // ------------------------------------------------------------ result FIFO
    // entry: {tag[4:0], channel[4:0], status[3:0], cmd[7:0], data[15:0]}
    wire res_full;
    // verilator lint_off UNUSEDSIGNAL
    wire res_empty;           // output register empty: the proofs read it (the
                              // read selects take valid_next, STATUS vacant)
    // verilator lint_on UNUSEDSIGNAL
    wire res_vacant;          // no result queued (STATUS.RES_EMPTY)
    wire [LW-1:0] res_level;
    wire [37:0] res_head;
    // what goes into the result FIFO: the engine's hand-over (only while
    // the FIFO is not full)
    wire        e_res_valid;
    wire [37:0] e_res;
    wire        e_cancelling;     // a flush's cancels are left in the queues
    wire [31:0] p_rdata;          // the answer of a POLL_RESULT / STATE read
    wire res_push = e_res_valid && !res_full;
    wire [3:0] push_status = e_res[27:24];
    wire pop_req = q_pop;

    twh_fifo #(.W(38), .DEPTH(DEPTH_N)) u_res_fifo (
        .clk(clk), .rst(rst),
        .push(res_push),
        .din(e_res),
        .full(res_full),
        .pop(pop_req), .dout(res_head), .empty(res_empty), .valid_next(res_valid_next),
        .level(res_level), .vacant(res_vacant)
    );

    // ------------------------------------------------------------ channels
    wire [CHANNELS-1:0] c_sample, c_sbusy;
    wire                c_poll_err;       // a poll's result with an error status (any channel)
    wire [CHANNELS*3-1:0] c_nx_fld;   // per channel: its phase (twh_timing decodes the field)
    wire                  c_sc_v;
    wire [4:0]            c_sc_ch;
    wire [2:0]            c_sc_ph;
    wire [1:0]            c_sc_tr;

    // A channel register write starts from the request stage: its value's
    // window flags were taken on the way in, for the register addressed (the
    // only one whose strobe is raised); the lab unlock applies now, so a
    // LAB_KEY write just ahead counts.
    wire       t_take  = (lab || !q_cmp_nz) && PROG_TIMING != 0;
    // the write twh_timing or the poller does not take, in the clock it would have
    wire       refused = (q_wr_t && !t_take) || q_ref_p;

    // ------------------------------------------------------------ timing registers
    wire [31:0] t_rdata;
    wire [CHANNELS-1:0] t_dur_we;
    wire                t_dur_v;
    wire [15:0] t_dur;
    wire [2:0]  t_dur_fld;
    wire [4:0]  t_dur_ch;
    // twh_timing is written and read by the request stage, like every other
    // register (a read and a write are never in it together); its word
    // comes out of the block RAM's register in the answer's clock
    wire [1:0]  q_treg = q_addr[3:2];            // TIMING0-2 of a channel block
    wire        t_wr  = q_wr_t && t_take;        // a timing write taken
    // POLL_CTRL is each channel's fourth word of twh_timing's memory
    // (POLL): a write the core takes (its read-only verdict) and a read
    // go there, as register 3, and the pollers' walker reads it through
    // the same port
    wire        p_wr  = q_wp && wr && q_win_p && POLLING != 0;
    wire        t_prd = (RAM_BLOCK == 0) ? q_r_tm              // the bus reads twh_timing's memory
                                     : (q_r_t || (q_r_pc && POLLING != 0));
    wire        pc_rd;
    wire        t_pwr = t_wr || p_wr;   // twh_timing's memory is written now
    wire [4:0]  pc_ch;
    wire [31:0] pc_word;
    wire [15:0] pc_tm, pt_wd;     // the pollers' timers in twh_timing's memory
    wire        pt_we;
    // (its reset sweep writes POLL_CTRL's reset value too; the register
    // port waits for it, t_ready)
    twh_timing #(.CHANNELS(CH_N), .PROG(PROG_TIMING), .NX_PHASE(1),
                 .POLL(POLLING != 0 ? 1 : 0), .RAM_BLOCK(RAM_BLOCK)) u_timing (
        .clk(clk), .rst(rst), .ready(t_ready), .sw_we(t_sw_we),
        .sw_reg(t_sw_reg), .lab(lab),
        .wr(t_pwr), .wr_ch(q_blk), .wr_reg(q_treg),
        .wr_data(q_wdata), .wr_cmp(q_cmp),
        .rd(t_prd), .rd_ch(q_blk), .rd_reg(q_treg), .rd_data(t_rdata),
        .pc_rd(pc_rd), .pc_ch(pc_ch), .pc_word(pc_word),
        .pc_tm(pc_tm), .tm_we(pt_we), .tm_wd(pt_wd),
        .sc_v(c_sc_v), .sc_ch(c_sc_ch), .sc_ph(c_sc_ph), .sc_tr(c_sc_tr),
        .nx_fld(c_nx_fld), .dur_we(t_dur_we), .dur_v(t_dur_v), .dur_ch(t_dur_ch), .dur(t_dur),
        .dur_fld(t_dur_fld)
    );

    twh_core_engine #(.CLK_HZ(CLK_HZ), .CHANNELS(CH_N), .POLLING(POLLING),
                      .PROG_TIMING(PROG_TIMING), .RAM_BLOCK(RAM_BLOCK)) u_engine (
        .clk(clk), .rst(rst), .ms_tick(ms_tick), .sw_we(t_sw_we),
        .tick(us_tick), .fall(us_fall), .enable(enable), .idle_charge(idle_charge[CH_N-1:0]),
        .wdata(q_wdata), .pc_wr(p_wr), .port_rd(t_prd),
        .rd_res(q_r_pr), .rd_state(q_r_st), .reg_ch(q_blk), .rd_data(p_rdata),
        .pc_rd(pc_rd), .pc_ch(pc_ch), .pc_word(pc_word),
        .pc_tm(pc_tm), .port_wr(t_pwr), .pt_we(pt_we), .pt_wd(pt_wd),
        .nx_ph(c_nx_fld), .sc_v(c_sc_v), .sc_ch(c_sc_ch), .sc_ph(c_sc_ph), .sc_tr(c_sc_tr), .dur_v(t_dur_v), .dur_ch(t_dur_ch), .dur(t_dur),
        .dur_fld(t_dur_fld), .poll_sample(c_sample), .poll_error(c_poll_err),
        .cmd_valid(dispatch), .cmd_ch(disp_ch), .cmd_code(h_cmd),
        .cmd_payload(h_payload), .cmd_tag(h_tag), .cmd_skip(h_skip),
        .cmd_ready(e_ready), .cancel(flush_wr), .cancelling(e_cancelling),
        .res_valid(e_res_valid), .res_ready(!res_full), .res(e_res),
        .line_o(line_o), .line_oe(line_oe), .line_i(line_i),
        .status_busy(c_sbusy)
    );
    genvar n;
    // (the engine steps on the tick itself; it takes the lengths by number,
    // dur_v and dur_ch, not twh_timing's one-hot dur_we)
    // verilator lint_off UNUSEDSIGNAL
    wire unused_tick_nx = us_tick_nx;
    wire unused_dur_we  = |t_dur_we;
    // verilator lint_on UNUSEDSIGNAL

    // per-channel bits widened to the 32 channels of the register map
    generate
        for (n = 0; n < 32; n = n + 1) begin : g_pad
            if (n < CHANNELS) begin : g_on
                // queued, running, or its result waiting for the result FIFO
                assign busy8[n]        = c_sbusy[n];
            end else begin : g_off
                assign busy8[n]        = 1'b0;
            end
        end
    endgenerate

    // q_addr[1:0]: accesses are whole 32-bit words
    // verilator lint_off UNUSEDSIGNAL
    wire unused_addr = |q_addr[1:0];
    // verilator lint_on UNUSEDSIGNAL

    // ------------------------------------------------------------ register writes
    // A result's link status sets LINK_ERROR a clock after the result goes
    // into the FIFO (registered: the status compare is off the error
    // register's path); the result reaches the FIFO's output in that
    // same clock, so software never sees the one without the other.
    reg  push_link_err;
    always @(posedge clk)
        push_link_err <= !rst && res_push && `TWH_ST_LINK_ERR(push_status);
    wire [31:0] busy8;               // per channel, padded to 32

    // Each register loads on its own strobes, with no shared "anything to
    // do" guard in front of them all (that was a wide OR on every one of
    // their enables, ECP5's three-channel critical path); one block, so
    // Icarus wakes one process a clock for them.
    // A command dispatched as BLOCKED (h_skip) sets BLOCKED a clock later,
    // from a flip-flop (disp_blk_err): the dispatch's terms were ECP5's path
    // into the error register. Its result is several clocks behind it still.
    reg disp_blk_err;
    always @(posedge clk) begin
        disp_blk_err <= !rst && take && disp_blk && !flushing && !flush_wr;
        if (rst) begin
            enable          <= 1'b1;
            idle_charge     <= {CH_N{1'b0}};
            flush_left      <= {LW{1'b0}};
            flushing        <= 1'b0;
            ie_result       <= 1'b0;
            ie_error        <= 1'b0;
            ie_poll         <= 1'b0;
            res_threshold   <= 8'd1;
            lab             <= 1'b0;
            factory_armed   <= 1'b0;
            err_overflow    <= 1'b0;
            err_refused     <= 1'b0;
            err_blocked     <= 1'b0;
            err_bad_channel <= 1'b0;
            err_link        <= 1'b0;
            poll_ready      <= {CH_N{1'b0}};
        end else begin
            if (q_ctrl) enable <= q_wdata[0];
            if (q_idle) idle_charge <= q_wdata[CH_N-1:0];
            // A flush cancels exactly the commands queued when it is
            // written; commands pushed after it run normally.
            if (q_flush) begin
                flush_left <= flush_new;
                flushing   <= flush_new_nz;
            end else if (take && flushing) begin
                flush_left <= flush_left - 1'b1;
                flushing   <= (flush_left != {{(LW-1){1'b0}}, 1'b1});
            end
            if (q_irq_en) begin
                ie_result     <= q_wdata[0];
                ie_error      <= q_wdata[1];
                ie_poll       <= q_wdata[2];
                res_threshold <= q_wdata[15:8];
            end
            // the lab unlock only lets timing out of its windows: a build
            // with fixed timing has none
            if (q_lab_key) lab <= q_key_lab && PROG_TIMING != 0;
            if (push_ok)         factory_armed <= 1'b0;        // the next command only
            else if (q_fact_key) factory_armed <= q_key_fact;
            // hardware sets win over a clear in the same clock
            if ((q_errors && q_wdata[0]) || (push_req && cmd_full && !push_bad_ch))
                err_overflow    <= push_req && cmd_full && !push_bad_ch;
            if ((q_errors && q_wdata[1]) || refused)
                err_refused     <= refused;
            if ((q_errors && q_wdata[2]) || disp_blk_err)
                err_blocked     <= disp_blk_err;
            if ((q_errors && q_wdata[3]) || (push_req && push_bad_ch))
                err_bad_channel <= push_req && push_bad_ch;
            if ((q_errors && q_wdata[4]) || push_link_err || c_poll_err)
                err_link        <= push_link_err || c_poll_err;
            if (q_poll_ready || c_sample != 0)
                poll_ready <= (q_poll_ready ? (poll_ready & ~q_wdata[CH_N-1:0]) : poll_ready) | c_sample;
        end
    end

    // ------------------------------------------------------------ reads
    wire [15:0] cmd_level16 = {{(16-LW){1'b0}}, cmd_level};
    wire [15:0] res_level16 = {{(16-LW){1'b0}}, res_level};
    wire [4:0]  errors = {err_link, err_bad_channel, err_blocked, err_refused, err_overflow};
    // registered: the comparator is off the read and irq paths (the source
    // trails the FIFO level by one clock)
    reg         src_result;
    // (level >= max(1, threshold): a non-empty FIFO at the threshold)
    always @(posedge clk) src_result <= !rst && (res_level != {LW{1'b0}}) &&
                                        (res_level16 >= {8'd0, res_threshold});
    wire        src_error  = (errors != 5'd0);
    // STATUS's FIFO flags: nothing queued, whether or not an entry is still
    // on its way to the FIFO's output (so BUSY 0 with both flags 1 means
    // every result pushed has been read)
    wire        st_cmd_empty = cmd_vacant;
    wire        st_res_empty = res_vacant;
    wire        src_poll   = (poll_ready != {CH_N{1'b0}});
    // (widened through a vector with room to spare: no zero replication
    // at 32 channels)
    // verilator lint_off UNUSEDSIGNAL
    wire [CH_N+31:0] poll_ready_w  = {32'd0, poll_ready};
    wire [CH_N+31:0] idle_charge_w = {32'd0, idle_charge};
    // verilator lint_on UNUSEDSIGNAL
    wire [31:0] poll_ready32  = poll_ready_w[31:0];
    wire [31:0] idle_charge32 = idle_charge_w[31:0];
    assign irq = (ie_result && src_result) || (ie_error && src_error) || (ie_poll && src_poll);

    // An empty FIFO's output register holds stale data: its fields read
    // zero (the select is masked, not the word).
    wire        r_res_info = q_r_res_info;
    wire        r_res_pop  = q_r_res_pop;
    wire [31:0] g_rdata =
          ({32{q_r_id}}         & `TWH_MAGIC)
        | ({32{q_r_version}}    & {factory_armed, lab, CH_COUNT, 2'd0, NO_POLLING, FIXED_TIMING,
                                   4'd0, `TWH_VERSION_MAJOR, `TWH_VERSION_MINOR})
        | ({32{q_r_params}}     & {CLK_KHZ, DEPTH12})
        | ({32{q_r_ctrl}}       & {31'd0, enable})
        | ({32{q_r_status}}     & {19'd0, flushing || e_cancelling, st_res_empty, res_full, st_cmd_empty,
                                   cmd_full, 8'd0})
        | ({32{q_r_levels}}     & {res_level16, cmd_level16})
        | ({32{q_r_errors}}     & {27'd0, errors})
        | ({32{q_r_irq_en}}     & {16'd0, res_threshold, 5'd0, ie_poll, ie_error, ie_result})
        | ({32{q_r_irq_status}} & {29'd0, src_poll, src_error, src_result})
        | ({32{q_r_poll_ready}} & poll_ready32)
        | ({32{q_r_idle}}       & idle_charge32)
        | ({32{q_r_busy}}       & busy8)
        // res_head: {tag 37:33, channel 32:28, status 27:24, cmd 23:16, data 15:0}
        | ({32{r_res_info}}     & {3'd0, res_head[32:28], 3'd0, res_head[37:33], 1'b1, 3'd0,
                                   res_head[27:24], res_head[23:16]})
        | ({32{r_res_pop}}      & {1'b0, res_head[37:33], 1'b1, res_head[32:28],
                                   res_head[27:24], res_head[15:0]});

    // the answer: the global registers' word in a register, ORed with the
    // timing word (twh_timing's RAM register) and the channel word of
    // twh_core_engine (p_rdata, a register there)
    reg [31:0] rdata_q;
    reg        t_rd_q;           // the answer is twh_timing's: TIMING0-2 or POLL_CTRL
    always @(posedge clk) begin
        if (rst) begin
            reg_ack   <= 1'b0;
            reg_err   <= 1'b0;
            rdata_q   <= 32'd0;
            t_rd_q    <= 1'b0;
        end else begin
            reg_ack   <= q_req;
            reg_err   <= q_req && (!mapped || (q_we && !full_word) ||
                                     (push_req && (push_bad_ch || cmd_full)));
            // between answers the read selects are 0, and so are these
            if (q_req || reg_ack) begin
                rdata_q   <= g_rdata;
                t_rd_q  <= t_prd;
            end
        end
    end
    assign reg_rdata = rdata_q | ({32{t_rd_q}} & t_rdata) | p_rdata;
    assign reg_ready = t_ready;

`ifdef FORMAL
    // ================================================================ formal
    // The register-port contract holds on its own: reg_ack is a register of
    // the request. The command path is proven by formal/twh_core.sby with
    // TWH_F_CORE: the engine is a stand-in that keeps its proven contract
    // (formal/twh_core_engine_stub.v, the time-shared engine's queues and
    // hand-over), and the f_cf_* and f_e_* probes below are tied by
    // that job (connect -set) to the command FIFO's pointers, output flag
    // and RAM words, which twh_fifo exposes nowhere else, and to the
    // stand-in's queues.
    reg f_h = 1'b0;           // one clock of history
    always @(posedge clk) f_h <= 1'b1;
    // the wrappers request only while the port is ready (their own proofs)
    always @(*) if (!reg_ready) assume(!reg_req);
`ifdef TWH_F_CORE
    // (the stand-in jobs cut twh_timing: its sweep writes only while the
    // port is not ready, as its own proof asserts)
    always @(*) if (t_sw_we) assume(!t_ready);
`else
    // The reset sweep's contract with twh_timing and twh_polls (their
    // proofs assume it): whenever the sweep writes, the data register
    // holds the default of the register it writes, written out here, and
    // no window flags; POLL_CTRL's reset value with register 3.
    function [31:0] f_sw_def;
        input [1:0] r;
        case (r)
            2'd0:    f_sw_def = {16'd1000, 16'd8000};
            2'd1:    f_sw_def = {16'd4000, 16'd2000};
            2'd2:    f_sw_def = {16'd2000, 16'd3000};
            default: f_sw_def = {1'b0, 15'd1000, 8'hAA, 8'h44};
        endcase
    endfunction
    reg f_swr = 1'b0;         // a reset has been seen (f_rs is declared below)
    always @(posedge clk) if (rst) f_swr <= 1'b1;
    always @(*) begin
        if (f_swr && !rst && t_sw_we) assert(q_wdata == f_sw_def(t_sw_reg) && q_cmp == 4'd0);
    end
`endif
    always @(*) begin
        // an error comes only with its answer
        if (f_h && reg_err) assert(reg_ack);
    end
    always @(posedge clk) begin
        // every request is carried out on the next clock and answered on
        // the one after, and nothing else is; a reset cancels both
        if (f_h) assert(q_req == $past(reg_req && !rst));
        if (f_h) assert(reg_ack == $past(q_req && !rst));
    end

    // A channel register write is taken or refused by the rule for the
    // register written, with the lab unlock as it is when the write is
    // carried out, and the checks staged on the way in are those of the
    // request's own data. The windows and keys are written out here rather
    // than taken from twh_defs.vh.
    reg f_rs = 1'b0;          // a reset has been seen
    always @(posedge clk) if (rst) f_rs <= 1'b1;
    // What the request and answer stages' load guards rest on: with no
    // request in the stage every strobe and select is 0, and with no
    // answer the read word is 0.
    always @(*) if (f_rs && !q_req) begin
        assert({q_wr, q_rd, q_wr_t, q_r_t, q_r_pc, q_r_tm, q_ref_p, q_r_pr, q_r_st} == 0);
        assert({q_r_id, q_r_version, q_r_params, q_r_ctrl, q_r_status, q_r_levels,
                q_r_errors, q_r_irq_en, q_r_irq_status, q_r_poll_ready, q_r_res_info,
                q_r_res_pop, q_r_idle, q_r_busy} == 0);
        assert({q_ctrl, q_flush, q_errors, q_irq_en, q_poll_ready, q_push, q_push_ch,
                q_pop, q_lab_key, q_fact_key, q_idle} == 0);
    end
    always @(*) if (f_rs && !reg_ack) assert(rdata_q == 32'd0 && !t_rd_q);
    wire [15:0] f_lo = q_wdata[15:0], f_hi = q_wdata[31:16];
    wire [7:0]  f_c  = q_wdata[7:0];
    reg         f_cw_ok;
    reg  [3:0]  f_cmp;

    always @(*) begin
        case (ch_reg)
            3'd0: f_cw_ok = lab || (f_lo >= 16'd7000 && f_hi >= 16'd900 && f_hi <= 16'd1100);
            3'd1: f_cw_ok = lab || (f_lo >= 16'd1800 && f_lo <= 16'd2200 &&
                                    f_hi >= 16'd3500 && f_hi <= 16'd10000);
            3'd2: f_cw_ok = lab || (f_lo >= 16'd2000 && f_hi >= 16'd2000);
            3'd3: f_cw_ok = !q_wdata[31] || (f_c >= 8'h40 && f_c <= 8'h44) ||
                                            (f_c >= 8'h46 && f_c <= 8'h49);
            default: f_cw_ok = 1'b0;
        endcase
        // the window flags twh_timing keeps beside the value:
        // {hi above, hi below, lo above, lo below}
        case (ch_reg)
            3'd0:    f_cmp = {f_hi > 16'd1100, f_hi < 16'd900, 1'b0, f_lo < 16'd7000};
            3'd1:    f_cmp = {f_hi > 16'd10000, f_hi < 16'd3500, f_lo > 16'd2200, f_lo < 16'd1800};
            default: f_cmp = {1'b0, f_hi < 16'd2000, 1'b0, f_lo < 16'd2000};
        endcase
        if (f_rs && f_h) begin
`ifndef TWH_F_CORE
            // (the jobs with the engine's stand-in cut the window checker)
            if (wr && ch_exists && ch_reg == 3'd3) assert(q_win_p == f_cw_ok);
            // twh_timing takes the write exactly when the rule takes it, at
            // its address, with the value's window flags
            assert(t_wr == (wr && ch_exists && ch_reg <= 3'd2 && f_cw_ok));
            if (wr && ch_exists && ch_reg <= 3'd2) assert(q_cmp == f_cmp);
            // REFUSED is raised by exactly the channel writes not taken
            assert(refused == (wr && ch_exists && ch_reg <= 3'd3 && !f_cw_ok));
`endif
            // the decode taken on the way in is that of the request's own
            // address and data
            assert(q_wr == (q_req && q_we && q_full) && q_rd == (q_req && !q_we));
            assert(q_mapped == ((!is_ch && g_reg <= 5'd16 && g_reg != 5'd10) || ch_exists));
            assert(q_wp == (ch_exists && ch_reg == 3'd3));
            // the flag is the count's
            assert(flushing == (flush_left != {LW{1'b0}}));
            assert(q_bad_ch == !(is_ch && ch_blk < CH_COUNT));
            assert(q_push_ch == (q_push && !q_bad_ch));
            assert(q_ctrl == (wr && !is_ch && g_reg == R_CTRL) &&
                   q_flush == (wr && !is_ch && g_reg == R_CTRL && q_wdata[1]) &&
                   q_errors == (wr && !is_ch && g_reg == R_ERRORS) &&
                   q_irq_en == (wr && !is_ch && g_reg == R_IRQ_EN) &&
                   q_poll_ready == (wr && !is_ch && g_reg == R_POLL_READY) &&
                   q_push == (wr && is_ch && ch_blk < 6'd32 && ch_reg == 3'd6) &&
                   q_idle == (wr && !is_ch && g_reg == R_IDLE_CHARGE) &&
                   q_pop == (rd && !is_ch && g_reg == R_RES_POP) &&
                   q_lab_key == (wr && !is_ch && g_reg == R_LAB_KEY) &&
                   q_fact_key == (wr && !is_ch && g_reg == R_FACTORY_KEY));
            assert(q_r_res_info == (rd && !is_ch && g_reg == R_RES_INFO && !res_empty));
            assert(q_r_res_pop  == (rd && !is_ch && g_reg == R_RES_POP && !res_empty));
            assert(q_r_idle == (rd && !is_ch && g_reg == R_IDLE_CHARGE) &&
                   q_r_busy == (rd && !is_ch && g_reg == R_BUSY));
            assert(q_key_lab  == (q_wdata == 32'h4C414221));
            assert(q_key_fact == (q_wdata == 32'h46414354));
        end
    end

    // A read answers what the request's own address names, written out here
    // as the plain address multiplexer the one-hot selects stand for; zero
    // for write-only and unmapped addresses and for an empty result FIFO's
    // fields.
    wire [37:0] f_res_shown = res_head & {38{!res_empty}};
    wire [CHANNELS+31:0] f_busy_x = {32'd0, c_sbusy};
    wire [31:0] f_busy32 = f_busy_x[31:0];
    reg  [31:0] f_rdata, f_rdata_q;
    always @(*) begin
        f_rdata = 32'd0;
        if (rd && mapped) begin
            if (is_ch) begin
                case (ch_reg)
                    // TIMING0-2: twh_timing's word, ORed in a clock later
                    // (below)
                    3'd0,
                    3'd1,
                    3'd2:    f_rdata = 32'd0;
                    // POLL_CTRL, POLL_RESULT, STATE: twh_timing's word
                    // or twh_core_engine's (twh_polls' and the engine's),
                    // ORed in a clock later (below); CMD_PUSH: write-only
                    default: f_rdata = 32'd0;
                endcase
            end else begin
                case (g_reg)
                    R_ID:         f_rdata = 32'h54574831;
                    R_VERSION:    f_rdata = {factory_armed, lab, CH_COUNT, 2'd0, NO_POLLING,
                                             FIXED_TIMING, 4'd0, 8'd2, 8'd0};
                    R_PARAMS:     f_rdata = {CLK_KHZ, DEPTH12};
                    R_CTRL:       f_rdata = {31'd0, enable};
                    // FLUSHING: cancels left in the command FIFO or, with the
                    // time-shared engine, in the channels' queues
                    R_STATUS:     f_rdata = {19'd0, flushing || e_cancelling, res_vacant, res_full, cmd_vacant,
                                             cmd_full, 8'd0};
                    R_LEVELS:     f_rdata = {res_level16, cmd_level16};
                    R_ERRORS:     f_rdata = {27'd0, errors};
                    R_IRQ_EN:     f_rdata = {16'd0, res_threshold, 5'd0, ie_poll, ie_error, ie_result};
                    R_IRQ_STATUS: f_rdata = {29'd0, src_poll, src_error, src_result};
                    R_POLL_READY: f_rdata = poll_ready32;
                    R_IDLE_CHARGE: f_rdata = idle_charge32;
                    R_BUSY:       f_rdata = f_busy32;
                    // the FIFO word: {tag, channel, status, cmd, data}
                    R_RES_INFO:   f_rdata = {3'd0, f_res_shown[32:28], 3'd0, f_res_shown[37:33],
                                             !res_empty, 3'd0, f_res_shown[27:24], f_res_shown[23:16]};
                    R_RES_POP:    f_rdata = {1'b0, f_res_shown[37:33], !res_empty, f_res_shown[32:28],
                                             f_res_shown[27:24], f_res_shown[15:0]};
                    default:      f_rdata = 32'd0;
                endcase
            end
        end
    end
    reg f_chk_rd = 1'b0;      // the clock before was decoded as above and no reset
    always @(posedge clk) begin
        f_chk_rd  <= f_rs && f_h && !rst;
        f_rdata_q <= f_rdata;
    end
    // a TIMING0-2 read, and with POLLING a POLL_CTRL read, answers
    // twh_timing's word for its address (its own proof: the register's
    // value as of the read); without POLLING POLL_CTRL reads 0
    reg f_trd_q, f_prd_q;
    always @(posedge clk) begin
        f_trd_q <= rd && mapped && is_ch && (ch_reg <= 3'd2 || (ch_reg == 3'd3 && POLLING != 0));
        f_prd_q <= rd && mapped && is_ch && (ch_reg == 3'd4 || ch_reg == 3'd5);
    end
    always @(*) if (f_chk_rd) assert(reg_rdata == (f_rdata_q | ({32{f_trd_q}} & t_rdata) |
                                                   ({32{f_prd_q}} & p_rdata)));
    // twh_polls is handed the request's channel and register
    always @(*) if (f_rs && f_h)
        assert(q_r_tm == (rd && ch_exists && (ch_reg <= 3'd2 ||
                                              (POLLING != 0 && ch_reg == 3'd3))) &&
               q_r_t == (rd && ch_exists && ch_reg <= 3'd2) &&
               q_r_pc == (rd && ch_exists && ch_reg == 3'd3) &&
               q_r_pr == (rd && ch_exists && ch_reg == 3'd4) &&
               q_r_st == (rd && ch_exists && ch_reg == 3'd5) &&
               (!(q_r_tm || q_r_pr || q_r_st) || q_blk == ch_sel));
    // twh_timing is handed the word the request names, for a read or a write
    always @(*) if (f_rs && f_h && ch_exists && ch_reg <= 3'd3)
        assert(q_blk == ch_sel && q_treg == ch_reg[1:0]);

    // The interrupt as registers.md words it, with the sources written out
    // from the state they stand for: RESULT while the result FIFO held at
    // least max(1, RES_THRESHOLD) entries a clock ago, ERROR while any
    // ERRORS bit is set, POLL while any POLL_READY bit is; irq is the OR of
    // the enabled ones.
    reg [LW-1:0] f_lvl_q;
    reg [7:0]    f_thr_q;
    always @(posedge clk) begin
        f_lvl_q <= res_level;
        f_thr_q <= res_threshold;
    end
    wire [15:0] f_lvl16 = {{(16-LW){1'b0}}, f_lvl_q};
    wire        f_src_res = f_lvl16 >= 16'd1 && f_lvl16 >= {8'd0, f_thr_q};
    wire        f_src_err = err_overflow || err_refused || err_blocked || err_bad_channel || err_link;
    always @(*)
        if (f_chk_rd)
            assert(irq == ((ie_result && f_src_res) || (ie_error && f_src_err) ||
                           (ie_poll && poll_ready != {CHANNELS{1'b0}})));

    // REFUSED rises only with a refused write and always with one (a clear
    // written in the same clock loses)
    always @(posedge clk) begin
        if (f_rs && f_h && !rst && !$past(rst)) begin
            if ($past(refused)) assert(err_refused);
            if (err_refused && !$past(err_refused)) assert($past(refused));
        end
    end

    // BLOCKED rises two clocks after a command is dispatched with the
    // BLOCKED status, always, and at no other time (a clear written in
    // the same clock loses)
    reg f_blk1 = 1'b0, f_blk2 = 1'b0;
    always @(posedge clk) begin
        f_blk1 <= !rst && take && h_skip == `TWH_ST_BLOCKED;
        f_blk2 <= !rst && f_blk1;
    end
    always @(posedge clk) begin
        if (f_rs && f_h && !rst && !$past(rst)) begin
            if (f_blk2) assert(err_blocked);
            if (err_blocked && !$past(err_blocked)) assert($past(f_blk1));
        end
    end

`ifdef TWH_F_CORE
    reg f_ok = 1'b0;
    always @(posedge clk) if (rst) f_ok <= 1'b1;
    always @(*) assert(f_ok == f_rs);        // both mark the first reset

    // ------------------------------------------------ command FIFO probes
    localparam integer F_AW = $clog2(FIFO_DEPTH);
    localparam [LW-1:0] F_DEPTH = FIFO_DEPTH[LW-1:0];
    (* keep *) wire [F_AW:0] f_cf_wr, f_cf_rd;     // u_cmd_fifo.wr_ptr, rd_ptr
    (* keep *) wire          f_cf_ov;              // u_cmd_fifo.out_valid
    (* keep *) wire          f_cf_me;              // u_cmd_fifo.mem_empty
    (* keep *) wire [F_AW:0] f_cf_rp1;             // u_cmd_fifo.rd_ptr_p1
    (* keep *) wire          f_cf_top, f_cf_one;   // u_cmd_fifo.top_r, one_r
    (* keep *) wire          f_cf_mo;              // u_cmd_fifo.mem_one
    (* keep *) wire [F_AW:0] f_cf_rp2;             // u_cmd_fifo.rd_ptr_p2
    wire [CF_W*FIFO_DEPTH-1:0] f_cf_mem;
    genvar f_i;
    generate
        for (f_i = 0; f_i < FIFO_DEPTH; f_i = f_i + 1) begin : g_f_cf_mem
            (* keep *) wire [CF_W-1:0] w;           // u_cmd_fifo.mem[f_i]
            assign f_cf_mem[f_i*CF_W +: CF_W] = w;
        end
    endgenerate
    wire [F_AW:0] f_cf_n = f_cf_wr - f_cf_rd;      // words in the RAM, behind the output
    // result FIFO probes: what its level and flags stand for
    (* keep *) wire [F_AW:0] f_rf_wr, f_rf_rd;     // u_res_fifo.wr_ptr, rd_ptr
    (* keep *) wire          f_rf_ov, f_rf_me;     // u_res_fifo.out_valid, mem_empty
    (* keep *) wire [F_AW:0] f_rf_rp1;             // u_res_fifo.rd_ptr_p1
    (* keep *) wire          f_rf_top, f_rf_one;   // u_res_fifo.top_r, one_r
    (* keep *) wire          f_rf_mo;              // u_res_fifo.mem_one
    (* keep *) wire [F_AW:0] f_rf_rp2;             // u_res_fifo.rd_ptr_p2
    wire [F_AW:0] f_rf_n = f_rf_wr - f_rf_rd;

    integer f_j, f_k;
    // commands the channels hold: in the engine's queues and its result
    // register (the stand-in's probes, f_e_* below)
    wire [4:0] f_inch;

    // f_pend: commands accepted by CMD_PUSH minus results the result FIFO
    // took
    reg [5:0] f_pend;
    always @(posedge clk) begin
        if (rst) f_pend <= 6'd0;
        else     f_pend <= f_pend + {5'd0, push_ok} - {5'd0, res_push && !res_full};
    end
    // STATUS reading "done" (BUSY 0, CMD_EMPTY, RES_EMPTY) means it: every
    // accepted command's result has gone through the result FIFO, and
    // nothing is left in it
    always @(*)
        if (f_ok && !rst && busy8 == 32'd0 && st_cmd_empty && st_res_empty)
            assert(f_pend == 6'd0 && res_level == {LW{1'b0}});

    // ------------------------------------------------ factory rule
    // The factory rule as NOTES.md words it, on the pushed word: erase
    // (0x4A/0x4B, address = code bit 0 : payload low byte) or write
    // (0x80-0xFF, address = payload bits 15:14 : code bits 6:0) of a word
    // below 0x20, unless FACTORY_KEY was armed since the last push.
    wire [8:0] f_erase_at = {q_wdata[0], q_wdata[15:8]};
    wire [8:0] f_write_at = {q_wdata[23:22], q_wdata[6:0]};
    wire       f_factory  = ((q_wdata[7:0] == 8'h4A || q_wdata[7:0] == 8'h4B) && f_erase_at < 9'h020) ||
                            (q_wdata[7] && f_write_at < 9'h020);
    // the factory verdict staged on the way in is that rule's
    always @(*) if (f_ok && f_h) assert(q_factory == f_factory);
    reg        f_armed;
    always @(posedge clk) begin
        if (rst)                                         f_armed <= 1'b0;
        else if (push_ok)                                f_armed <= 1'b0;
        else if (wr && !is_ch && g_reg == R_FACTORY_KEY) f_armed <= (q_wdata == `TWH_FACTORY_KEY);
    end

    // ------------------------------------------------ the engine's stand-in
    // (formal/twh_core_engine_stub.v): its queues, entry i of
    // channel c, counted from the head, at (c*4 + i)*17 ({skip, tag, code}),
    // their counts, whether each head has started, starts now, or hands its
    // result over now; probes tied by formal/twh_core.sby (connect -set)
    (* keep *) wire [CHANNELS*68-1:0] f_e_q;
    (* keep *) wire [CHANNELS*3-1:0]  f_e_n;
    (* keep *) wire [CHANNELS-1:0]    f_e_st, f_e_strt, f_e_pop;
    reg [4:0] f_e_sum;
    always @(*) begin
        f_e_sum = 5'd0;
        for (f_j = 0; f_j < CHANNELS; f_j = f_j + 1)
            f_e_sum = f_e_sum + {2'd0, f_e_n[f_j*3 +: 3]};
    end
    assign f_inch = f_e_sum;

    // ------------------------------------------------ one command, followed
    // An arbitrary accepted push is followed to its result: f_st 1 while in
    // the command FIFO (f_pos words ahead of it); 2 in its channel's queue
    // in the engine (f_qp entries behind the head), until its result goes
    // into the result FIFO (from the head, in one clock). f_can: it must
    // come out CANCELLED (a flush was written while it was queued, or in
    // the engine's queue and not yet started).
    (* anyseq *) reg f_pick;
    reg [1:0]    f_st;
    reg [LW-1:0] f_pos;
    reg [2:0]    f_qp;
    reg [CF_W-1:0] f_word;     // as pushed: {blocked, tag, channel, payload, code}
    reg          f_can;
    reg          f_blk;        // it must come out BLOCKED (unless CANCELLED)
    wire [31:0]  f_ch_w  = {{(32-CF_CW){1'b0}}, f_word[CF_T-1:24]};
    wire [4:0]   f_ch    = f_ch_w[4:0];
    wire         f_flush = wr && !is_ch && g_reg == R_CTRL && q_wdata[1];
    // (the engine takes a flush in its own clock: f_can)
    wire [3:0]   f_skip  = f_can ? `TWH_ST_CANCELLED :
                           f_blk ? `TWH_ST_BLOCKED : 4'd0;
    // its queue's count and head, its entry, whether its head
    // starts or hands over now
    wire [2:0]   f_e_cnt  = f_e_n[f_ch*3 +: 3];
    wire [16:0]  f_e_ent  = f_e_q[(f_ch*4 + f_qp)*17 +: 17];
    wire         f_e_hst  = f_e_st[f_ch];
    wire         f_e_go   = f_e_strt[f_ch];
    wire         f_e_out  = f_e_pop[f_ch];
    // its result goes in
    wire         f_mine  = res_push && f_st == 2'd2 && f_qp == 3'd0 && f_e_out;

    always @(posedge clk) begin
        if (rst) begin
            f_st <= 2'd0;
        end else begin
            case (f_st)
                2'd0: if (push_ok && f_pick) begin
                          f_st   <= 2'd1;
                          f_word <= {p_blocked, q_wdata[28:24], q_blk[CF_CW-1:0], q_wdata[23:0]};
                          f_blk  <= f_factory && !f_armed;
                          f_pos  <= cmd_level - {{(LW-1){1'b0}}, take};
                          f_can  <= 1'b0;
                      end
                2'd1: begin
                          if (f_flush) f_can <= 1'b1;
                          if (take) begin
                              if (f_pos == {LW{1'b0}}) f_st <= 2'd2;
                              else                     f_pos <= f_pos - 1'b1;
                              // behind the entries its queue keeps
                              f_qp <= f_e_cnt - {2'd0, f_e_out};
                          end
                      end
                2'd2: begin
                          // a flush cancels it unless it is the head and
                          // has started (or starts now)
                          if (f_flush && !(f_qp == 3'd0 && (f_e_hst || f_e_go))) f_can <= 1'b1;
                          if (f_e_out) begin
                              if (f_qp == 3'd0) f_st <= 2'd0;
                              else              f_qp <= f_qp - 3'd1;
                          end
                      end
                default: f_st <= 2'd0;
            endcase
        end
    end

    // its FIFO word, where it waits
    wire [F_AW:0] f_at = f_cf_rd + f_pos[F_AW:0] - {{F_AW{1'b0}}, f_cf_ov};
    wire [CF_W-1:0] f_stored = (f_pos == {LW{1'b0}} && f_cf_ov) ? cmd_head
                                                                 : f_cf_mem[f_at[F_AW-1:0]*CF_W +: CF_W];

    always @(*) begin
        f_k = 0;
        if (f_ok) begin
            // ---- the command FIFO as the core relies on it
            assert(f_cf_n <= FIFO_DEPTH && cmd_level <= F_DEPTH);
            assert(cmd_level == f_cf_n + {{F_AW{1'b0}}, f_cf_ov});
            assert(cmd_empty == !f_cf_ov);
            // the result FIFO as the core relies on it, and both FIFOs'
            // "no entry" flags (their proof has them too)
            assert(f_rf_n <= FIFO_DEPTH && res_level <= F_DEPTH);
            assert(res_level == f_rf_n + {{F_AW{1'b0}}, f_rf_ov});
            assert(res_empty == !f_rf_ov && f_rf_me == (f_rf_wr == f_rf_rd) &&
                   f_rf_rp1 == f_rf_rd + 1'b1 && res_full == (res_level == F_DEPTH));
            assert(cmd_vacant == (cmd_level == {LW{1'b0}}));
            assert(res_vacant == (res_level == {LW{1'b0}}));
            // the FIFO's own flags (its proof has them too)
            assert(f_cf_me == (f_cf_wr == f_cf_rd) && f_cf_rp1 == f_cf_rd + 1'b1);
            assert(cmd_full == (cmd_level == F_DEPTH));
            assert(f_cf_top == (cmd_level == F_DEPTH - 1'b1) &&
                   f_cf_one == (cmd_level == {{(LW-1){1'b0}}, 1'b1}));
            assert(f_rf_top == (res_level == F_DEPTH - 1'b1) &&
                   f_rf_one == (res_level == {{(LW-1){1'b0}}, 1'b1}));
            assert(f_cf_mo == (f_cf_rp1 == f_cf_wr) && f_cf_rp2 == f_cf_rd + 2'd2);
            assert(f_rf_mo == (f_rf_rp1 == f_rf_wr) && f_rf_rp2 == f_rf_rd + 2'd2);
            // every queued command names a channel that exists (the push
            // refuses the others), so a dispatch always lands in a queue
            if (f_cf_ov) assert({1'b0, h_ch} < CH_COUNT);
            for (f_k = 0; f_k < FIFO_DEPTH; f_k = f_k + 1)
                if (f_k < f_cf_n)
                    assert(f_cf_mem[((f_cf_rd[F_AW-1:0] + f_k) % FIFO_DEPTH)*CF_W + 24 +: CF_CW] < CH_COUNT);

            // ---- dispatch: the word offered is the FIFO's head, for an
            // existing channel, and it stays offered, unchanged, until taken
            // (below: the engine's proof assumes both)
            if (dispatch)
                assert(f_cf_ov && disp_ch == h_ch && disp_blk == cmd_head[CF_B] &&
                       {1'b0, disp_ch} < CH_COUNT);
            // a result's channel exists
            if (e_res_valid) assert({1'b0, e_res[32:28]} < CH_COUNT);
            // a flush counts down only the commands queued before it
            assert(flush_left <= cmd_level);
            assert(flushing == (flush_left != {LW{1'b0}}));

            // ---- none lost, none doubled: every accepted push is queued,
            // in the engine (its channel's queue), or was put
            // as one result into the result FIFO
            assert(f_pend == {1'b0, cmd_level} + {1'b0, f_inch});

            // ---- the factory verdict stored with each push
            assert(factory_armed == f_armed);
            if (push_ok) assert(p_blocked == (f_factory && !f_armed));

            // ---- the followed command
            if (f_st != 2'd0) assert(f_word[CF_B] == f_blk);
            if (f_st == 2'd1) begin
                assert(f_pos < cmd_level);
                assert(f_stored == f_word);
                // the flush still counts it down exactly when it was queued
                // before the flush was written
                assert(f_can == (f_pos < flush_left));
            end
            if (f_st != 2'd0) assert({1'b0, f_ch} < CH_COUNT);
            // in its channel's queue as pushed, behind f_qp entries;
            // blocked or cancelled as it must be (a started head no
            // longer changes)
            if (f_st == 2'd2)
                assert(f_qp < f_e_cnt && f_e_ent == {f_skip, f_word[CF_B-1:CF_T], f_word[7:0]});
            // its one result, into the result FIFO as its head leaves the
            // queue: its tag, channel and code, and its status
            assert(f_st != 2'd3);
            if (f_st == 2'd2 && f_qp == 3'd0 && f_e_out) begin
                assert(e_res_valid && e_res[32:28] == f_ch && e_res[37:33] == f_word[CF_B-1:CF_T] &&
                       e_res[23:16] == f_word[7:0]);
                if (f_skip != 4'd0) assert(e_res[27:24] == f_skip);
                else                assert(e_res[27:24] <= `TWH_ST_LINE_STUCK_HIGH);
            end
        end
    end

    // the port's side of the engine (AXI-Stream): an offer not taken stays,
    // for the same channel (the head and its data with it: above)
    reg       f_off_q;
    reg [4:0] f_dch_q;
    always @(posedge clk) begin
        f_off_q <= !rst && dispatch && !e_ready;
        f_dch_q <= disp_ch;
    end
    always @(*) if (f_ok && !rst && f_off_q) assert(dispatch && disp_ch == f_dch_q);

    // the followed command does reach each ending, and a flush does catch
    // one waiting in its queue
    always @(posedge clk) begin
        if (f_ok && !rst) begin
            cover(f_mine && f_skip == 4'd0);
            cover(f_mine && f_skip == `TWH_ST_BLOCKED);
            cover(f_mine && f_skip == `TWH_ST_CANCELLED);
            // a flush catches it behind its queue's head, or does not
            // as its head, started
            cover(f_st == 2'd2 && f_flush && f_qp != 3'd0);
            cover(f_st == 2'd2 && f_flush && f_qp == 3'd0 && f_e_hst && f_skip == 4'd0);
            // the command FIFO fills behind a full queue
            cover(cmd_full && f_e_n[2:0] == 3'd4);
        end
    end
`endif
`endif
endmodule
`default_nettype wire
