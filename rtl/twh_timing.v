// Every channel's timing registers (TIMING0-2) in one memory, and the one
// clamp that turns them into phase lengths for all engines.
//
// Why a memory: six 16-bit lengths with their window flags, a read
// multiplexer and a clamp per channel were about 285 iCE40 logic cells a
// channel; here they are block RAM (iCE40) or LUT RAM (ECP5) and one
// pipeline for all channels.
//
// - Two copies of the words, written together: one read by the bus, one by
//   the engines' fetch, so neither ever waits for the other.
// - A word never written since reset reads its default (a flag per word
//   cleared by rst), so a reset needs no walk through the memory.
// - The core writes with the request, not a clock later: its verdict (in
//   the window, or lab) is taken from the bus data on the way in. A read
//   presents its address with its own request and gets the word a clock
//   later (rd_data), so it sees every earlier write and no forwarding is
//   needed. A reset in the clock after the write clears the word's flag.
// - Fetch: one channel per clock, in turn, reads the field its engine names
//   on nx_fld (the length its next programmable phase will load), clamps
//   it to the field's spec window unless `lab` is set (the window flags were
//   taken when the word was written, by the core's twh_window), and hands
//   it to that engine (dur_we, dur, dur_fld) two clocks later. An engine
//   loads a length only when dur_fld names the field it needs, so a length
//   is never taken from a stale fetch; a channel's field is fetched again
//   within CHANNELS + 2 clocks of a change of its value or of nx_fld.
`default_nettype none
`include "twh_defs.vh"
module twh_timing #(
    parameter integer CHANNELS = 1
) (
    input  wire                  clk,
    input  wire                  rst,
    input  wire                  lab,        // lengths run unclamped
    // bus write (the core's verdict taken: the value is to be stored)
    input  wire                  wr,
    input  wire [2:0]            wr_ch,
    input  wire [1:0]            wr_reg,     // 0-2: TIMING0-2
    input  wire [31:0]           wr_data,
    input  wire [3:0]            wr_cmp,     // twh_window's flags of wr_data
    // bus read
    input  wire [2:0]            rd_ch,
    input  wire [1:0]            rd_reg,
    output wire [31:0]           rd_data,    // one clock after rd_*
    // engines
    input  wire [CHANNELS*3-1:0] nx_fld,     // per channel: field 1-6 it needs next
    output reg  [CHANNELS-1:0]   dur_we,
    output reg  [15:0]           dur,
    output reg  [2:0]            dur_fld
);
    localparam [31:0] DEF0 = {`TWH_SYNC_DEF, `TWH_CHARGE_DEF};
    localparam [31:0] DEF1 = {`TWH_EXECUTE_DEF, `TWH_PREAMBLE_DEF};
    localparam [31:0] DEF2 = {`TWH_TURNAROUND_DEF, `TWH_LISTEN_DEF};
    function [31:0] def_word;
        input [1:0] r;
        def_word = (r == 2'd0) ? DEF0 : (r == 2'd1) ? DEF1 : DEF2;
    endfunction

    // ------------------------------------------------------------ storage
    // 32 words whatever CHANNELS is ({channel, register}), so the memory
    // maps to block RAM rather than flip-flops; each copy is read old-first
    // in the clock it is written (the core never reads and writes one word
    // in the same clock).
    reg [31:0] mem_bus [0:31];
    reg [35:0] mem_eng [0:31];
    reg [31:0] written;                   // word {ch, reg} holds a value
    wire [4:0] wa = {wr_ch, wr_reg};
    wire [4:0] ra = {rd_ch, rd_reg};
    reg  [31:0] rb_word;
    always @(posedge clk) begin
        if (wr) mem_bus[wa] <= wr_data;
        rb_word <= mem_bus[ra];
    end
    integer n;
    always @(posedge clk) begin
        for (n = 0; n < 32; n = n + 1)
            if (rst || n >= CHANNELS * 4 || n % 4 == 3) written[n] <= 1'b0;
            else if (wr && wa == n[4:0])              written[n] <= 1'b1;
    end

    // ------------------------------------------------------------ bus read
    reg         rb_written;
    reg  [1:0]  rb_reg;
    always @(posedge clk) begin
        rb_written <= written[ra];
        rb_reg     <= rd_reg;
    end
    assign rd_data = rb_written ? rb_word : def_word(rb_reg);

    // ------------------------------------------------------------ fetch
    // stage 0: the channel in turn names its field and the word is read;
    // stage 1: the field's half and flags picked; then the clamp, into the
    // engine's register
    localparam integer LAST_I = CHANNELS - 1;
    localparam [2:0]   LAST_CH = LAST_I[2:0];
    reg  [2:0] f_ch;
    wire [2:0] f_fld = nx_fld[f_ch*3 +: 3];
    // fields 1-2 are TIMING0's, 3-4 TIMING1's, 5-6 TIMING2's
    wire [1:0] f_reg = (f_fld <= 3'd2) ? 2'd0 : (f_fld <= 3'd4) ? 2'd1 : 2'd2;
    reg  [35:0] e_word;
    reg         e_written, e_ok;
    reg  [2:0]  e_ch, e_fld;
    always @(posedge clk) begin
        if (wr) mem_eng[wa] <= {wr_cmp, wr_data};
        e_word <= mem_eng[{f_ch, f_reg}];
    end
    always @(posedge clk) begin
        if (rst || f_ch == LAST_CH)      f_ch <= 3'd0;
        else                             f_ch <= f_ch + 3'd1;
        e_written <= written[{f_ch, f_reg}];
        e_ok      <= !rst && f_fld != 3'd0 && f_fld <= 3'd6;
        e_ch      <= f_ch;
        e_fld     <= f_fld;
    end
    wire [2:0]  e_fm1  = e_fld - 3'd1;             // {register, half}
    wire [35:0] e_val  = e_written ? e_word : {4'd0, def_word(e_fm1[2:1])};
    reg  [15:0] p_v;
    reg         p_b, p_a, p_ok;
    reg  [2:0]  p_ch, p_fld;
    always @(posedge clk) begin
        p_v   <= e_fm1[0] ? e_val[31:16] : e_val[15:0];
        p_b   <= !lab && (e_fm1[0] ? e_val[34] : e_val[32]);
        p_a   <= !lab && (e_fm1[0] ? e_val[35] : e_val[33]);
        p_ok  <= !rst && e_ok;
        p_ch  <= e_ch;
        p_fld <= e_fld;
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
    integer c;
    always @(*) begin
        for (c = 0; c < CHANNELS; c = c + 1)
            dur_we[c] = p_ok && p_ch == c[2:0];
        dur     = p_b ? w_lo : p_a ? w_hi : p_v;
        dur_fld = p_fld;
    end
endmodule
`default_nettype wire
