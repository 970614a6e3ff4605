// Synchronous FIFO with a registered read port (so it maps onto block RAM)
// and a show-ahead output register: `dout` is valid whenever `empty` is low.
// `level` counts every entry, including the one on the output. DEPTH must be
// a power of two.
`default_nettype none
module twh_fifo #(
    parameter integer W     = 8,
    parameter integer DEPTH = 16
) (
    input  wire                         clk,
    input  wire                         rst,
    input  wire                         push,
    input  wire [W-1:0]                 din,
    output wire                         full,
    input  wire                         pop,
    output reg  [W-1:0]                 dout,
    output wire                         empty,
    output wire [$clog2(DEPTH+1)-1:0]   level
);
    localparam integer AW = $clog2(DEPTH);
    localparam integer LW = $clog2(DEPTH + 1);
    localparam [LW-1:0] DEPTH_L = DEPTH[LW-1:0];

    generate
        if ((1 << AW) != DEPTH || DEPTH < 2) begin : g_bad_depth
            twh_error_FIFO_DEPTH_must_be_a_power_of_two u_err ();
        end
    endgenerate

    reg [W-1:0] mem [0:DEPTH-1];
    reg [AW:0]  wr_ptr, rd_ptr;
    reg         out_valid;

    wire [AW:0] mem_count = wr_ptr - rd_ptr;
    wire        mem_empty = (wr_ptr == rd_ptr);
    assign level = mem_count + {{AW{1'b0}}, out_valid};
    assign full  = (level == DEPTH_L);
    assign empty = !out_valid;

    wire do_push = push && !full;
    wire do_pop  = pop && out_valid;
    wire load    = !mem_empty && (!out_valid || do_pop);

    always @(posedge clk) begin
        if (do_push) mem[wr_ptr[AW-1:0]] <= din;
        if (load)    dout <= mem[rd_ptr[AW-1:0]];
    end

    always @(posedge clk) begin
        if (rst) begin
            wr_ptr    <= {(AW+1){1'b0}};
            rd_ptr    <= {(AW+1){1'b0}};
            out_valid <= 1'b0;
        end else begin
            if (do_push) wr_ptr <= wr_ptr + 1'b1;
            if (load)    rd_ptr <= rd_ptr + 1'b1;
            if (load)         out_valid <= 1'b1;
            else if (do_pop)  out_valid <= 1'b0;
        end
    end
endmodule
`default_nettype wire
