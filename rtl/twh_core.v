// Bus-agnostic core: CHANNELS twh_channel engines running concurrently, a
// shared command FIFO and result FIFO, and the registers of
// rdl/twh_regs.rdl behind a simple one-request-per-clock register port that
// the Wishbone (twh_wb) and AXI4-Lite (twh_axil) wrappers drive.
//
// Register port: a request (reg_req) is answered on the next clock with
// reg_ack, reg_err and reg_rdata. Errors: unmapped address, a write with
// byte enables other than all four, a push into the full command FIFO, a
// push for an absent channel.
//
// Dispatch: the command FIFO's head moves into its channel's one-entry slot
// when that slot is free. A head waiting for a busy channel therefore holds
// back the commands behind it (head-of-line blocking): queue commands for
// several channels in round-robin order to keep them all busy.
// Results: one channel at a time is offered the result FIFO in turn (a scan,
// not a priority), so every channel gets its turn; a full FIFO holds the
// engines back and no result is ever dropped.
`default_nettype none
`include "twh_defs.vh"
module twh_core #(
    parameter integer CLK_HZ     = 48_000_000,
    parameter integer CHANNELS   = 1,
    parameter integer FIFO_DEPTH = 16
) (
    input  wire                clk,
    input  wire                rst,
    // register port
    input  wire                reg_req,
    input  wire                reg_we,
    input  wire [8:0]          reg_addr,
    input  wire [31:0]         reg_wdata,
    input  wire [3:0]          reg_wstrb,
    output reg                 reg_ack,
    output reg                 reg_err,
    output reg  [31:0]         reg_rdata,
    output wire                irq,
    // 2-wire pins
    output wire [CHANNELS-1:0] line_o,
    output wire [CHANNELS-1:0] line_oe,
    input  wire [CHANNELS-1:0] line_i
);
    generate
        if (CHANNELS < 1 || CHANNELS > 8) begin : g_bad_channels
            twh_error_CHANNELS_must_be_1_to_8 u_err ();
        end
        if (FIFO_DEPTH > 2048) begin : g_bad_depth
            twh_error_FIFO_DEPTH_at_most_2048 u_err ();
        end
    endgenerate

    localparam integer LW = $clog2(FIFO_DEPTH + 1);
    localparam [3:0]  CH_COUNT = CHANNELS[3:0];
    localparam [11:0] DEPTH12  = FIFO_DEPTH[11:0];
    localparam integer CLK_KHZ_I = CLK_HZ / 1000;
    localparam [19:0] CLK_KHZ  = CLK_KHZ_I[19:0];

    // ------------------------------------------------------------ millisecond tick
    wire us_tick, us_fall_unused;
    twh_carrier #(.CLK_HZ(CLK_HZ)) u_tick (
        .clk(clk), .rst(rst), .tick(us_tick), .fall(us_fall_unused)
    );
    reg [9:0] us_count;
    reg       ms_tick;
    always @(posedge clk) begin
        if (rst) begin
            us_count <= 10'd0;
            ms_tick  <= 1'b0;
        end else begin
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

    // ------------------------------------------------------------ decode
    wire       is_ch     = (reg_addr[8:6] != 3'd0);           // 0x40 and up
    wire [3:0] ch_blk    = reg_addr[8:5] - 4'd2;              // channel block
    wire [2:0] ch_sel    = ch_blk[2:0];
    wire [2:0] ch_reg    = reg_addr[4:2];
    wire       ch_exists = is_ch && (ch_blk < CH_COUNT) && (ch_reg <= 3'd5);
    wire [3:0] g_reg     = reg_addr[5:2];
    wire       full_word = (reg_wstrb == 4'hF);
    wire       wr        = reg_req && reg_we && full_word;
    wire       rd        = reg_req && !reg_we;

    localparam [3:0] R_ID = 4'd0, R_VERSION = 4'd1, R_PARAMS = 4'd2, R_CTRL = 4'd3,
                     R_STATUS = 4'd4, R_LEVELS = 4'd5, R_ERRORS = 4'd6, R_IRQ_EN = 4'd7,
                     R_IRQ_STATUS = 4'd8, R_POLL_READY = 4'd9, R_CMD_PUSH = 4'd10,
                     R_RES_INFO = 4'd11, R_RES_POP = 4'd12, R_LAB_KEY = 4'd13,
                     R_FACTORY_KEY = 4'd14;
    wire g_mapped = !is_ch && (g_reg != 4'd15);
    wire mapped   = g_mapped || ch_exists;

    // ------------------------------------------------------------ control registers
    reg        enable, lab, factory_armed;
    reg [LW-1:0] flush_left;    // queued commands a flush still has to cancel
    wire       flushing = (flush_left != {LW{1'b0}});
    reg [7:0]  idle_charge;
    reg        ie_result, ie_error, ie_poll;
    reg [7:0]  res_threshold;
    reg        err_overflow, err_refused, err_blocked, err_bad_channel, err_link;
    reg [7:0]  poll_ready;

    // ------------------------------------------------------------ command FIFO
    // entry: {blocked, tag[4:0], channel[2:0], payload[15:0], cmd[7:0]}
    // The factory-area verdict is taken on the way in, from the bus data, so
    // the FIFO's RAM output drives no comparator on its way to the slot.
    wire [2:0]  push_ch   = reg_wdata[26:24];
    wire        push_req  = wr && !is_ch && g_reg == R_CMD_PUSH;
    wire        cmd_full, cmd_empty;
    wire [LW-1:0] cmd_level;
    wire [32:0] cmd_head;
    wire        push_bad_ch = {1'b0, push_ch} >= CH_COUNT;
    wire        push_ok   = push_req && !push_bad_ch && !cmd_full;

    // erase (0x4A/4B) or write (0x80-0xFF) addressed to words 0x00-0x1F
    wire [7:0]  p_cmd     = reg_wdata[7:0];
    wire [8:0]  p_erase_addr = {p_cmd[0], reg_wdata[15:8]};     // payload low byte
    wire [8:0]  p_write_addr = {reg_wdata[23:22], p_cmd[6:0]};  // payload bits 15:14
    wire        p_factory = ((p_cmd[7:1] == 7'b0100101) && (p_erase_addr < `TWH_FACTORY_END)) ||
                            (p_cmd[7] && (p_write_addr < `TWH_FACTORY_END));
    wire        p_blocked = p_factory && !factory_armed;

    wire [7:0]  h_cmd     = cmd_head[7:0];
    wire [15:0] h_payload = cmd_head[23:8];
    wire [2:0]  h_ch      = cmd_head[26:24];
    wire [4:0]  h_tag     = cmd_head[31:27];
    wire        h_blocked = cmd_head[32];

    wire [CHANNELS-1:0] slot_full;
    wire [7:0] slot_full8;
    wire h_slot_free = !slot_full8[h_ch];
    // Dispatch is decided one clock and done the next: the decision reads the
    // FIFO's RAM output (slow on iCE40), the pop and slot load then start
    // from a flip-flop. The head and its slot cannot change in between.
    reg  dispatch;
    reg  [2:0] disp_ch;
    always @(posedge clk) begin
        if (rst) dispatch <= 1'b0;
        else     dispatch <= !dispatch && !cmd_empty && (enable || flushing) && h_slot_free;
        disp_ch <= h_ch;
    end
    wire [3:0] h_skip = flushing  ? `TWH_ST_CANCELLED :
                        h_blocked ? `TWH_ST_BLOCKED : 4'd0;

    twh_fifo #(.W(33), .DEPTH(FIFO_DEPTH)) u_cmd_fifo (
        .clk(clk), .rst(rst),
        .push(push_ok), .din({p_blocked, reg_wdata}), .full(cmd_full),
        .pop(dispatch), .dout(cmd_head), .empty(cmd_empty), .level(cmd_level)
    );

    // ------------------------------------------------------------ result FIFO
    // entry: {tag[4:0], channel[2:0], status[3:0], cmd[7:0], data[15:0]}
    wire [CHANNELS-1:0] c_res_valid;
    wire [CHANNELS*8-1:0]  c_res_cmd;
    wire [CHANNELS*16-1:0] c_res_data;
    wire [CHANNELS*4-1:0]  c_res_status;
    wire [CHANNELS*5-1:0]  c_res_tag;
    reg  [2:0] scan;
    wire res_full, res_empty;
    wire [LW-1:0] res_level;
    wire [35:0] res_head;
    wire [7:0] c_res_valid8;
    wire res_push = c_res_valid8[scan] && !res_full;
    wire [3:0] push_status = c_res_status[scan*4 +: 4];
    wire pop_req = rd && !is_ch && g_reg == R_RES_POP;

    twh_fifo #(.W(36), .DEPTH(FIFO_DEPTH)) u_res_fifo (
        .clk(clk), .rst(rst),
        .push(res_push),
        .din({c_res_tag[scan*5 +: 5], scan, push_status,
              c_res_cmd[scan*8 +: 8], c_res_data[scan*16 +: 16]}),
        .full(res_full),
        .pop(pop_req), .dout(res_head), .empty(res_empty), .level(res_level)
    );

    always @(posedge clk) begin
        if (rst || scan == CH_COUNT[2:0] - 3'd1 || CHANNELS == 1) scan <= 3'd0;
        else                                                     scan <= scan + 1'b1;
    end

    // ------------------------------------------------------------ channels
    wire [CHANNELS*32-1:0] c_t0, c_t1, c_t2, c_pc, c_pr, c_st;
    wire [CHANNELS-1:0] c_refused, c_sample, c_poll_err, c_busy;

    genvar n;
    generate
        for (n = 0; n < CHANNELS; n = n + 1) begin : g_ch
            wire sel = ch_exists && (ch_sel == n);
            twh_channel #(.CLK_HZ(CLK_HZ)) u_ch (
                .clk(clk), .rst(rst), .ms_tick(ms_tick),
                .enable(enable), .idle_charge(idle_charge[n]), .lab(lab),
                .wdata(reg_wdata),
                .wr_timing0(wr && sel && ch_reg == 3'd0),
                .wr_timing1(wr && sel && ch_reg == 3'd1),
                .wr_timing2(wr && sel && ch_reg == 3'd2),
                .wr_poll_ctrl(wr && sel && ch_reg == 3'd3),
                .timing0(c_t0[n*32 +: 32]), .timing1(c_t1[n*32 +: 32]),
                .timing2(c_t2[n*32 +: 32]), .poll_ctrl(c_pc[n*32 +: 32]),
                .poll_result(c_pr[n*32 +: 32]), .state(c_st[n*32 +: 32]),
                .value_refused(c_refused[n]), .poll_sample(c_sample[n]),
                .poll_error(c_poll_err[n]),
                .slot_load(dispatch && disp_ch == n),
                .slot_cmd_i(h_cmd), .slot_payload_i(h_payload), .slot_tag_i(h_tag),
                .slot_skip_i(h_skip),
                .cancel(wr && !is_ch && g_reg == R_CTRL && reg_wdata[1]),
                .slot_full(slot_full[n]),
                .res_valid(c_res_valid[n]), .res_ready(scan == n && !res_full),
                .res_cmd(c_res_cmd[n*8 +: 8]), .res_data(c_res_data[n*16 +: 16]),
                .res_status(c_res_status[n*4 +: 4]), .res_tag(c_res_tag[n*5 +: 5]),
                .line_o(line_o[n]), .line_oe(line_oe[n]), .line_i(line_i[n]),
                .busy(c_busy[n])
            );
        end
    endgenerate

    // per-channel bits widened to the 8 channels of the register map
    generate
        for (n = 0; n < 8; n = n + 1) begin : g_pad
            if (n < CHANNELS) begin : g_on
                assign slot_full8[n]   = slot_full[n];
                assign c_res_valid8[n] = c_res_valid[n];
                assign sample8[n]      = c_sample[n];
                assign busy8[n]        = c_busy[n] || slot_full[n];
            end else begin : g_off
                assign slot_full8[n]   = 1'b0;
                assign c_res_valid8[n] = 1'b0;
                assign sample8[n]      = 1'b0;
                assign busy8[n]        = 1'b0;
            end
        end
    endgenerate

    // reg_addr[1:0]: accesses are whole 32-bit words
    // verilator lint_off UNUSEDSIGNAL
    wire unused_addr = |reg_addr[1:0];
    // verilator lint_on UNUSEDSIGNAL

    // ------------------------------------------------------------ register writes
    wire push_link_err = res_push && (push_status >= `TWH_ST_BAD_CHECKSUM) &&
                         (push_status <= `TWH_ST_LINE_STUCK_HIGH);
    wire [7:0] sample8, busy8;

    always @(posedge clk) begin
        if (rst) begin
            enable          <= 1'b1;
            flush_left      <= {LW{1'b0}};
            lab             <= 1'b0;
            factory_armed   <= 1'b0;
            idle_charge     <= 8'd0;
            ie_result       <= 1'b0;
            ie_error        <= 1'b0;
            ie_poll         <= 1'b0;
            res_threshold   <= 8'd1;
            err_overflow    <= 1'b0;
            err_refused     <= 1'b0;
            err_blocked     <= 1'b0;
            err_bad_channel <= 1'b0;
            err_link        <= 1'b0;
            poll_ready      <= 8'd0;
        end else begin
            // A flush cancels exactly the commands queued when it is written;
            // commands pushed after it run normally.
            if (dispatch && flushing) flush_left <= flush_left - 1'b1;
            if (wr && !is_ch) begin
                case (g_reg)
                    R_CTRL: begin
                        enable      <= reg_wdata[0];
                        if (reg_wdata[1]) flush_left <= cmd_level - {{(LW-1){1'b0}}, dispatch};
                        idle_charge <= reg_wdata[15:8];
                    end
                    R_ERRORS: begin
                        if (reg_wdata[0]) err_overflow    <= 1'b0;
                        if (reg_wdata[1]) err_refused     <= 1'b0;
                        if (reg_wdata[2]) err_blocked     <= 1'b0;
                        if (reg_wdata[3]) err_bad_channel <= 1'b0;
                        if (reg_wdata[4]) err_link        <= 1'b0;
                    end
                    R_IRQ_EN: begin
                        ie_result     <= reg_wdata[0];
                        ie_error      <= reg_wdata[1];
                        ie_poll       <= reg_wdata[2];
                        res_threshold <= reg_wdata[15:8];
                    end
                    R_LAB_KEY:     lab           <= (reg_wdata == `TWH_LAB_KEY);
                    R_FACTORY_KEY: factory_armed <= (reg_wdata == `TWH_FACTORY_KEY);
                    default: ;
                endcase
            end
            if (push_ok) factory_armed <= 1'b0;        // the next command only
            // hardware sets win over a clear in the same clock
            if (push_req && cmd_full && !push_bad_ch) err_overflow <= 1'b1;
            if (push_req && push_bad_ch)              err_bad_channel <= 1'b1;
            if (|c_refused)                           err_refused <= 1'b1;
            if (dispatch && h_skip == `TWH_ST_BLOCKED) err_blocked <= 1'b1;
            if (push_link_err || |c_poll_err)         err_link <= 1'b1;
            poll_ready <= ((wr && !is_ch && g_reg == R_POLL_READY) ? (poll_ready & ~reg_wdata[7:0])
                                                                  : poll_ready) | sample8;
        end
    end

    // ------------------------------------------------------------ reads
    wire [15:0] cmd_level16 = {{(16-LW){1'b0}}, cmd_level};
    wire [15:0] res_level16 = {{(16-LW){1'b0}}, res_level};
    wire [4:0]  errors = {err_link, err_bad_channel, err_blocked, err_refused, err_overflow};
    wire [7:0]  thr = (res_threshold == 8'd0) ? 8'd1 : res_threshold;
    wire        src_result = (res_level16 >= {8'd0, thr});
    wire        src_error  = (errors != 5'd0);
    wire        src_poll   = (poll_ready != 8'd0);
    assign irq = (ie_result && src_result) || (ie_error && src_error) || (ie_poll && src_poll);

    reg [31:0] g_rdata;
    always @(*) begin
        case (g_reg)
            R_ID:         g_rdata = `TWH_MAGIC;
            R_VERSION:    g_rdata = {factory_armed, lab, 10'd0, CH_COUNT,
                                     `TWH_VERSION_MAJOR, `TWH_VERSION_MINOR};
            R_PARAMS:     g_rdata = {CLK_KHZ, DEPTH12};
            R_CTRL:       g_rdata = {16'd0, idle_charge, 7'd0, enable};
            R_STATUS:     g_rdata = {19'd0, flushing, res_empty, res_full, cmd_empty,
                                     cmd_full, busy8};
            R_LEVELS:     g_rdata = {res_level16, cmd_level16};
            R_ERRORS:     g_rdata = {27'd0, errors};
            R_IRQ_EN:     g_rdata = {16'd0, res_threshold, 5'd0, ie_poll, ie_error, ie_result};
            R_IRQ_STATUS: g_rdata = {29'd0, src_poll, src_error, src_result};
            R_POLL_READY: g_rdata = {24'd0, poll_ready};
            R_RES_INFO:   g_rdata = {11'd0, res_head[35:31], !res_empty, res_head[30:28],
                                     res_head[27:24], res_head[23:16]};
            R_RES_POP:    g_rdata = {3'd0, res_head[35:31], !res_empty, res_head[30:28],
                                     res_head[27:24], res_head[15:0]};
            default:      g_rdata = 32'd0;     // write-only and unmapped
        endcase
        // an empty FIFO's output register holds stale data: show zeros
        if ((g_reg == R_RES_INFO || g_reg == R_RES_POP) && res_empty) g_rdata = 32'd0;
    end

    reg [31:0] c_rdata;
    always @(*) begin
        case (ch_reg)
            3'd0:    c_rdata = c_t0[ch_sel*32 +: 32];
            3'd1:    c_rdata = c_t1[ch_sel*32 +: 32];
            3'd2:    c_rdata = c_t2[ch_sel*32 +: 32];
            3'd3:    c_rdata = c_pc[ch_sel*32 +: 32];
            3'd4:    c_rdata = c_pr[ch_sel*32 +: 32];
            default: c_rdata = c_st[ch_sel*32 +: 32];
        endcase
    end

    always @(posedge clk) begin
        if (rst) begin
            reg_ack   <= 1'b0;
            reg_err   <= 1'b0;
            reg_rdata <= 32'd0;
        end else begin
            reg_ack   <= reg_req;
            reg_err   <= reg_req && (!mapped || (reg_we && !full_word) ||
                                     (push_req && (push_bad_ch || cmd_full)));
            reg_rdata <= (rd && mapped) ? (is_ch ? c_rdata : g_rdata) : 32'd0;
        end
    end
endmodule
`default_nettype wire
