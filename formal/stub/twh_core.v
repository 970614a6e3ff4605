// Formal-only stand-in for twh_core, used to prove the bus wrappers (twh_wb,
// twh_axil) without the channels behind the register port; the real core is
// too big for k-induction. It keeps nothing of the core but the register-port
// contract stated at the top of rtl/twh_core.v: every request is answered
// two clocks later with reg_ack (a request stage, then the access), and a
// reset cancels the answer; a request is made only while reg_ready, which
// is left free here (the real core's is 0 for its reset sweep, then 1), and
// the wrappers' proofs check that they keep to it. Whether the
// answer is an error, the read data, irq and the pins are left free (anyseq),
// so the wrapper proofs hold whatever the core decides. That the real core
// keeps this contract is a proof obligation of its own (phase 2).
`default_nettype none
module twh_core #(
    parameter integer CLK_HZ     = 48_000_000,
    parameter integer CHANNELS   = 1,
    parameter integer FIFO_DEPTH = 16,
    parameter integer PROG_TIMING = 1,   // the real core's feature parameters: the
    parameter integer POLLING     = 1,   // wrappers pass them on; nothing here uses them
    parameter integer RAM_BLOCK   = 1
) (
    input  wire                clk,
    input  wire                rst,
    output wire                reg_ready,
    input  wire                reg_req,
    input  wire                reg_we,
    input  wire [10:0]         reg_addr,
    input  wire [31:0]         reg_wdata,
    input  wire [3:0]          reg_wstrb,
    output reg                 reg_ack,
    output wire                reg_err,
    output wire [31:0]         reg_rdata,
    output wire                irq,
    output wire [CHANNELS-1:0] line_o,
    output wire [CHANNELS-1:0] line_oe,
    input  wire [CHANNELS-1:0] line_i
);
    (* anyseq *) reg                f_ready;
    (* anyseq *) reg                f_err;
    (* anyseq *) reg [31:0]         f_rdata;
    (* anyseq *) reg                f_irq;
    (* anyseq *) reg [CHANNELS-1:0] f_line_o, f_line_oe;

    reg q_req;
    always @(posedge clk) begin
        q_req   <= !rst && reg_req;
        reg_ack <= !rst && q_req;
    end

    // the wrapper's side of the contract
    always @(*) if (!reg_ready) assert(!reg_req);

    assign reg_ready = f_ready;
    assign reg_err   = f_err;
    assign reg_rdata = f_rdata;
    assign irq       = f_irq;
    assign line_o    = f_line_o;
    assign line_oe   = f_line_oe;
endmodule
`default_nettype wire
