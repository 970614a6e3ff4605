// Synthesis harness for measuring twh_engine alone (scripts/bench_engine.py):
// the engine and the carrier, with the command, timing and result ports
// behind a shift register on a few pins, so a placement of up to 32
// channels needs only its lines and five more pins. Every engine input is
// a flip-flop and every output reaches a pin, so synthesis keeps all of the
// engine; the harness's own cells (about 70 flip-flops and the fold of the
// result) are the same at every channel count and drop out of the slope
// (but for the register of the outputs, 4 flip-flops a channel).
`default_nettype none
module twh_engine_bench #(
    parameter integer CLK_HZ   = 48_000_000,
    parameter integer CHANNELS = 32,
    parameter integer RAM_BLOCK = 1,
    parameter integer CW       = (CHANNELS > 1) ? $clog2(CHANNELS) : 1
) (
    input  wire                clk,
    input  wire                rst,
    input  wire                sin,        // shifted into the port register
    input  wire                go,         // 1: present a command, 2nd pin: a timing write
    input  wire                go_t,
    output reg                 sout,       // the result, folded
    output wire [CHANNELS-1:0] line_o,
    output wire [CHANNELS-1:0] line_oe,
    input  wire [CHANNELS-1:0] line_i
);
    localparam integer SW = CW + 8 + 16 + 8 + 4 + 1;
    reg [SW-1:0] sr;
    always @(posedge clk) sr <= {sr[SW-2:0], sin};
    wire tick, tick_nx, fall;
    twh_carrier #(.CLK_HZ(CLK_HZ)) u_carrier (.clk(clk), .rst(rst), .tick(tick),
                                              .tick_nx(tick_nx), .fall(fall));
    wire          ready, rv;
    wire [CW-1:0] rch;
    wire [7:0]    rcode, rtag;
    wire [15:0]   rdata;
    wire [3:0]    rst_s;
    wire [CHANNELS-1:0] busy;
    wire [CHANNELS*3-1:0] phase;
    wire [CHANNELS-1:0] pending;
    wire          st_pend;
    wire          p_take, p_res;
    wire [CW-1:0] p_ch;
    wire [15:0]   p_data;
    wire [3:0]    p_status;
    wire [11:0]   p_count;
    twh_engine #(.CLK_HZ(CLK_HZ), .CHANNELS(CHANNELS), .RAM_BLOCK(RAM_BLOCK)) u_engine (
        .clk(clk), .rst(rst), .tick(tick), .fall(fall), .cfg_idle_charge(sr[CHANNELS-1:0]),
        // (the poll command is a RAM's read in the core: twh_polls)
        .enable(sr[SW-2]), .cancel(sr[SW-3]), .poll_req(sr[SW-1 -: CHANNELS]),
        .poll_cmd(sr[CW +: 16]), .scan_ch(),
        .t_we(go_t), .t_ch(sr[CW-1:0]), .t_fld(sr[CW +: 3]), .t_len(sr[CW+3 +: 16]),
        .s_cmd_valid(go), .s_cmd_ready(ready), .s_cmd_ch(sr[CW-1:0]),
        .s_cmd_code(sr[CW +: 8]), .s_cmd_payload(sr[CW+8 +: 16]), .s_cmd_tag(sr[CW+24 +: 8]),
        .s_cmd_skip(sr[CW+32 +: 4]),
        .m_res_valid(rv), .m_res_ready(sr[SW-1]), .m_res_ch(rch), .m_res_code(rcode),
        .m_res_data(rdata), .m_res_status(rst_s), .m_res_tag(rtag),
        .line_o(line_o), .line_oe(line_oe), .line_i(line_i), .busy(busy),
        .phase(phase), .pending(pending), .st_ch(sr[CW-1:0]), .st_pend(st_pend),
        .cancelling(), .fld(), .sc_v(), .sc_ch(), .sc_ph(), .sc_tr(),
        .p_take(p_take), .p_res(p_res), .p_ch(p_ch), .p_data(p_data), .p_status(p_status), .p_count(p_count)
    );
    // every output registered before the fold, so the fold's XOR tree is
    // no path of the engine's
    localparam integer OW = 1 + 1 + CW + 8 + 8 + 16 + 4 + CHANNELS + CHANNELS * 3 +
                            CHANNELS + 1 + 2 + CW + 16 + 4 + 12;
    reg [OW-1:0] outs;
    always @(posedge clk) begin
        outs <= {ready, rv, rch, rcode, rtag, rdata, rst_s, busy, phase,
                 pending, st_pend, p_take, p_res, p_ch, p_data, p_status, p_count};
        sout <= ^outs;
    end
endmodule
`default_nettype wire
