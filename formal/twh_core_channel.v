// Formal-only stand-in for twh_channel in formal/twh_core.sby. It keeps the
// command path of the channel as formal/twh_channel.sby proves it (the core
// loads the slot only while it is free; the core job checks that) and
// nothing else:
//   - slot_load fills the one-entry slot; the slot empties when the engine
//     takes the command, at a free moment, but only while the engine holds
//     no other command from the slot (nor its result);
//   - cancel makes a command still waiting in the slot CANCELLED, unless
//     the engine takes it in that same clock;
//   - each slot command gives exactly one result, in order: its own tag and
//     code, its skip status when it had one (never sent), a link status
//     (0-6) otherwise; the result stays offered, unchanged, until res_ready.
// Polls, the registers, the pins and the interrupt sources are left free:
// the core proof reads none of them.
//
// Liberties, invisible to the core's logic, that let the core's proof see
// the stand-in's state: `busy` is exactly "the engine holds a command from
// the slot, or its result" (the real one also counts polls and the engine's
// turnaround; the core only shows it in STATUS), and the read-back ports
// POLL_CTRL and POLL_RESULT carry the slot's and the engine's command (the
// core only copies them to reg_rdata, which no property of that job reads).
`default_nettype none
`include "twh_defs.vh"
module twh_channel #(
    parameter integer CLK_HZ      = 48_000_000,
    // the proofs run the full feature set: the stand-in keeps its contract
    // only there (twh_core's lean builds are tested, not proven)
    parameter integer POLLING     = 1
) (
    input  wire        clk,
    input  wire        rst,
    input  wire        ms_tick,
    input  wire        tick,
    input  wire        tick_nx,
    input  wire        fall,
    input  wire        enable,
    input  wire        idle_charge,
    input  wire [31:0] wdata,
    input  wire        wdata_ok,
    input  wire        wr_poll_ctrl,
    output wire [2:0]  nx_fld,
    input  wire        dur_we,
    input  wire [15:0] dur,
    input  wire [2:0]  dur_fld,
    output wire [31:0] poll_ctrl,
    output wire [31:0] poll_result,
    output wire [31:0] state,
    output reg         poll_sample,
    output reg         poll_error,
    input  wire        slot_load,
    input  wire [7:0]  slot_cmd_i,
    input  wire [15:0] slot_payload_i,
    input  wire [4:0]  slot_tag_i,
    input  wire [3:0]  slot_skip_i,
    input  wire        cancel,
    output reg         slot_full,
    output reg         res_valid,
    input  wire        res_ready,
    output reg  [7:0]  res_cmd,
    output reg  [15:0] res_data,
    output reg  [3:0]  res_status,
    output reg  [4:0]  res_tag,
    output wire        line_o,
    output wire        line_oe,
    input  wire        line_i,
    output wire        busy,
    output reg         status_busy
);
    (* anyseq *) reg        f_take, f_done;
    (* anyseq *) reg [3:0]  f_status;
    (* anyseq *) reg [15:0] f_data;
    (* anyseq *) reg [2:0]  f_nx;
    (* anyseq *) reg [2:0]  f_phase;
    (* anyseq *) reg        f_sample, f_perr, f_line_o, f_line_oe;

    reg [7:0] s_cmd;
    reg [4:0] s_tag;
    reg [3:0] s_skip;
    reg       eng;          // the engine holds a slot command or its result
    reg [7:0] e_cmd;
    reg [4:0] e_tag;
    reg [3:0] e_skip;

    wire take = slot_full && !eng && f_take;
    wire [3:0] link_status = (f_status > `TWH_ST_LINE_STUCK_HIGH) ? `TWH_ST_NO_RESPONSE : f_status;

    always @(posedge clk) begin
        if (rst) begin
            slot_full <= 1'b0;
            eng       <= 1'b0;
            res_valid <= 1'b0;
        end else begin
            if (slot_load) begin
                slot_full <= 1'b1;
                s_cmd     <= slot_cmd_i;
                s_tag     <= slot_tag_i;
                s_skip    <= slot_skip_i;
            end else if (take) begin
                slot_full <= 1'b0;
            end
            if (cancel && slot_full && !take) s_skip <= `TWH_ST_CANCELLED;

            if (take) begin
                eng    <= 1'b1;
                e_cmd  <= s_cmd;
                e_tag  <= s_tag;
                e_skip <= s_skip;
            end else if (res_valid && res_ready) begin
                eng       <= 1'b0;
                res_valid <= 1'b0;
            end else if (eng && !res_valid && f_done) begin
                res_valid  <= 1'b1;
                res_cmd    <= e_cmd;
                res_tag    <= e_tag;
                res_status <= (e_skip != 4'd0) ? e_skip : link_status;
                res_data   <= (e_skip == 4'd0 && (link_status == `TWH_ST_OK ||
                                                  link_status == `TWH_ST_BAD_CHECKSUM)) ? f_data : 16'd0;
            end
        end
        poll_sample   <= f_sample;
        poll_error    <= f_perr;
    end

    // STATUS.BUSY as twh_channel builds it: what it reports now, or a slot
    // load (the stand-in's take needs a full slot); never 0 while that is 1
    always @(posedge clk)
        status_busy <= !rst && (eng || slot_full || res_valid || slot_load);
    reg f_run = 1'b0;
    always @(posedge clk) f_run <= !rst;
    always @(*) if (f_run && !rst && (eng || slot_full || res_valid)) assert(status_busy);

    assign busy        = eng;
    assign poll_ctrl   = {15'd0, s_skip, s_tag, s_cmd};
    assign poll_result = {15'd0, e_skip, e_tag, e_cmd};
    assign nx_fld      = f_nx;
    assign state       = {27'd0, slot_full, eng, f_phase};
    assign line_o      = f_line_o;
    assign line_oe     = f_line_oe;

    // verilator lint_off UNUSEDSIGNAL
    wire unused = &{1'b0, ms_tick, tick, tick_nx, fall, enable, idle_charge, wdata, wdata_ok, wr_poll_ctrl,
                    dur_we, dur, dur_fld, slot_payload_i, line_i};
    // verilator lint_on UNUSEDSIGNAL
endmodule
`default_nettype wire
