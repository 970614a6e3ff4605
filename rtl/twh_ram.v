// Simple dual-port memory: one write port, one read port whose data is
// registered (block RAM on the iCE40s and the ECP5). Nothing is reset: a
// user that needs defaults keeps a flag of its own per word (the engine's
// `init` per channel).
`default_nettype none
module twh_ram #(
    parameter integer W  = 16,
    parameter integer AW = 8
) (
    input  wire          clk,
    input  wire          we,
    input  wire [AW-1:0] waddr,
    input  wire [W-1:0]  wdata,
    input  wire [AW-1:0] raddr,
    output reg  [W-1:0]  rdata
);
    // a read of the word written in the same clock is never used: the
    // engine reads a channel's word at least four clocks after its write
    (* no_rw_check *) reg [W-1:0] mem [0:(1 << AW) - 1];
    always @(posedge clk) begin
        if (we) mem[waddr] <= wdata;
        rdata <= mem[raddr];
    end
endmodule
`default_nettype wire
