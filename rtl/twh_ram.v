// Simple dual-port memory: one write port, one read port whose data is
// registered (block RAM on the iCE40s and the ECP5). Nothing is reset: a
// user that needs defaults writes them (twh_timing's reset sweep) or reads
// a reset word in their place until it has (the engine's first scan after
// a reset). BLOCK = 1 asks for block RAM even where Yosys would
// build a shallow memory of flip-flops (the iCE40s have no LUT RAM, so a
// 2- or 4-word memory of 68 bits would cost 136 or 272 of them); BLOCK = 0
// asks for LUT RAM at every depth (for parts that have it, the ECP5: its
// read is faster than a block RAM's, whose 5.6 ns from clock to output
// would stand in front of the engine's step; on the iCE40s it would be
// flip-flops).
`default_nettype none
module twh_ram #(
    parameter integer W     = 16,
    parameter integer AW    = 8,
    parameter integer BLOCK = 0
) (
    input  wire          clk,
    input  wire          we,
    input  wire [AW-1:0] waddr,
    input  wire [W-1:0]  wdata,
    // 1: read raddr; 0: the read register keeps its word (the engine's
    // late part of the state word is read only for a visit, so that a
    // simulator sees it change only then)
    input  wire          re,
    input  wire [AW-1:0] raddr,
    output reg  [W-1:0]  rdata
`ifdef FORMAL
    ,
    // a proof's view of one word (Yosys takes no hierarchical names): the
    // engine's proof follows its tracked channel's queue entries with it
    input  wire [AW-1:0] f_addr,
    output wire [W-1:0]  f_data
`endif
);
    // No read depends on what a read of the word being written in its
    // clock gives: the engine reads a channel's state and control words
    // P - 3 >= 1 clocks after their write and its queue head while only
    // another channel's queue is written; a timing word rewritten in the
    // clock of its read gives the length before or after, and either is
    // one its field had (docs/engine.md, "In the core").
    // Both branches are g_mem, so f_data (a proof's view of one word) is
    // g_mem.mem[f_addr] whichever is built.
    generate
        if (BLOCK != 0) begin : g_mem
            (* ram_style = "block" *) (* no_rw_check *) reg [W-1:0] mem [0:(1 << AW) - 1];
            always @(posedge clk) begin
                if (we) mem[waddr] <= wdata;
                if (re) rdata <= mem[raddr];
            end
        end else begin : g_mem
            (* ram_style = "distributed" *) (* no_rw_check *) reg [W-1:0] mem [0:(1 << AW) - 1];
            always @(posedge clk) begin
                if (we) mem[waddr] <= wdata;
                if (re) rdata <= mem[raddr];
            end
        end
    endgenerate
`ifdef FORMAL
    assign f_data = g_mem.mem[f_addr];
`endif
endmodule
`default_nettype wire
