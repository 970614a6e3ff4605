// Formal-only stand-in for twh_link in formal/twh_channel.sby. It keeps the
// engine's interface contract, as formal/twh_link.sby proves it of the real
// engine (any input, no assumption), and nothing else:
//   - s_cmd_ready only while no accepted command is waiting for its result
//     (rtl/twh_link.v: rdy => idle, f_out == 0);
//   - a command with s_cmd_skip != 0 is answered on the next clock with that
//     status, its code and tag and no data;
//   - any other command is answered once, at any later clock, with its code
//     and tag and a link status (0-6), data only for OK / BAD_CHECKSUM;
//   - a result stays offered, unchanged, until m_res_ready; reset clears it.
// Everything the real engine decides on its own (when the answer comes, its
// status and data, the pins, the phase) is left free, so what the channel
// proof shows holds for every engine that keeps the contract.
//
// Two liberties, both invisible to the channel: m_res_code and m_res_tag are
// loaded at the accept rather than with the result (the channel reads them
// only while m_res_valid), and `busy` is exactly "a sent command has no
// result yet" (the real one also covers turnaround and hold-off; the channel
// only passes it on to a status register). They let the channel's proof
// see the engine's state.
`default_nettype none
`include "twh_defs.vh"
module twh_link #(
    parameter integer CLK_HZ    = 48_000_000,
    parameter integer TAG_W     = 8,
    parameter integer GLITCH_NS = 100
) (
    input  wire             clk,
    input  wire             rst,
    input  wire             tick,
    input  wire             tick_nx,
    input  wire             fall,
    output wire [2:0]       nx_fld,
    input  wire             dur_we,
    input  wire [15:0]      dur_in,
    input  wire [2:0]       dur_fld_in,
    input  wire             cfg_idle_charge,
    input  wire             s_cmd_valid,
    output wire             s_cmd_ready,
    input  wire [7:0]       s_cmd_code,
    input  wire [15:0]      s_cmd_payload,
    input  wire [TAG_W-1:0] s_cmd_tag,
    input  wire [3:0]       s_cmd_skip,
    output reg              m_res_valid,
    input  wire             m_res_ready,
    output reg  [7:0]       m_res_code,
    output reg  [15:0]      m_res_data,
    output reg  [3:0]       m_res_status,
    output reg  [TAG_W-1:0] m_res_tag,
    output wire             line_o,
    output wire             line_oe,
    input  wire             line_i,
    output wire [2:0]       phase,
    output wire             busy
);
    (* anyseq *) reg        f_ready, f_done;
    (* anyseq *) reg [3:0]  f_status;
    (* anyseq *) reg [15:0] f_data;
    (* anyseq *) reg        f_line_o, f_line_oe;
    (* anyseq *) reg [2:0]  f_phase, f_nx;

    reg sent;    // a command is on the line, its result not yet raised

    assign s_cmd_ready = f_ready && !sent && !m_res_valid;
    wire accept = s_cmd_valid && s_cmd_ready;
    wire [3:0] link_status = (f_status > `TWH_ST_LINE_STUCK_HIGH) ? `TWH_ST_NO_RESPONSE : f_status;

    always @(posedge clk) begin
        if (rst) begin
            sent        <= 1'b0;
            m_res_valid <= 1'b0;
        end else begin
            if (m_res_valid && m_res_ready) m_res_valid <= 1'b0;
            if (accept) begin
                m_res_code <= s_cmd_code;
                m_res_tag  <= s_cmd_tag;
                if (s_cmd_skip != 4'd0) begin
                    m_res_valid  <= 1'b1;
                    m_res_status <= s_cmd_skip;
                    m_res_data   <= 16'd0;
                end else begin
                    sent <= 1'b1;
                end
            end else if (sent && f_done) begin
                sent         <= 1'b0;
                m_res_valid  <= 1'b1;
                m_res_status <= link_status;
                m_res_data   <= (link_status == `TWH_ST_OK || link_status == `TWH_ST_BAD_CHECKSUM)
                                ? f_data : 16'd0;
            end
        end
    end

    assign busy    = sent;
    assign phase   = f_phase;
    assign nx_fld  = f_nx;
    assign line_o  = f_line_o;
    assign line_oe = f_line_oe;

    // verilator lint_off UNUSEDSIGNAL
    wire unused = &{1'b0, tick, tick_nx, fall, dur_we, dur_in, dur_fld_in, cfg_idle_charge, s_cmd_payload, line_i};
    // verilator lint_on UNUSEDSIGNAL
endmodule
`default_nettype wire
