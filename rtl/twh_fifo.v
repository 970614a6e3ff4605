// Synchronous FIFO with a registered read port (so it maps onto block RAM)
// and a show-ahead output register: `dout` is valid whenever `empty` is low.
// `level` counts every entry, including the one on the output; `vacant` is
// "level is 0". A push into an empty FIFO counts at once but reaches the
// output a clock later, so `empty` can be 1 with an entry on its way: a
// user that reports whether anything is queued takes `vacant`. DEPTH must be
// a power of two.
//
// LH > 0 keeps an entry's top LH bits in flip-flops beside the RAM: iCE40
// block RAMs are 16 bits wide, so an entry a few bits over a multiple of
// 16 would otherwise take a whole block for them (the core's command FIFO
// above four channels: 33-35 bits, two blocks and LH flip-flops an entry
// rather than three blocks).
`default_nettype none
module twh_fifo #(
    parameter integer W     = 8,
    parameter integer DEPTH = 16,
    parameter integer LH    = 0      // top bits in flip-flops (0 .. W-1)
) (
    input  wire                         clk,
    input  wire                         rst,
    input  wire                         push,
    input  wire [W-1:0]                 din,
    output wire                         full,
    input  wire                         pop,
    output wire [W-1:0]                 dout,
    output wire                         empty,
    output wire                         valid_next,  // !empty as it will be next clock
    output wire [$clog2(DEPTH+1)-1:0]   level,
    output wire                         vacant       // level == 0
);
    localparam integer AW = $clog2(DEPTH);
    localparam integer LW = $clog2(DEPTH + 1);
    // verilator lint_off UNUSEDPARAM
    localparam [LW-1:0] DEPTH_L = DEPTH[LW-1:0];   // the proofs'
    // verilator lint_on UNUSEDPARAM
    localparam integer  DM2_I    = DEPTH - 2;
    localparam [LW-1:0] DEPTH_M2 = DM2_I[LW-1:0];
    localparam integer  TWO_I    = 2;
    localparam [LW-1:0] TWO_L    = TWO_I[LW-1:0];
    localparam [AW:0]   TWO_P    = TWO_I[AW:0];

    generate
        if ((1 << AW) != DEPTH || DEPTH < 2) begin : g_bad_depth
            twh_error_DEPTH_must_be_a_power_of_two_2_or_more u_err ();
        end
        if (LH < 0 || LH >= W) begin : g_bad_lh
            twh_error_LH_must_be_0_to_W_minus_1 u_err ();
        end
    endgenerate

    // A write and a read never meet at one address (the read address is
    // only written while the RAM is full, and a full FIFO takes no push;
    // proven below), so Yosys need not build its read-during-write bypass:
    // on iCE40 that bypass costs a register and a multiplexer per bit.
    (* no_rw_check *) reg [W-LH-1:0] mem [0:DEPTH-1];
    reg [W-LH-1:0] d_lo;
    reg [AW:0]  wr_ptr;
    // verilator lint_off UNUSEDSIGNAL
    reg [AW:0]  rd_ptr;     // top bit read by the proofs only (occupancy)
    // verilator lint_on UNUSEDSIGNAL
    reg         out_valid;

    // level and full are registers, not sums of the pointers: a push is
    // decided on `full`, and an adder in front of it would be the FIFO
    // user's critical path.
    reg [LW-1:0] level_r;
    reg          full_r, vacant_r;
    // level_r == DEPTH - 1 and level_r == 1, flags that move with it: full
    // and vacant then wait for the push, the pop and one flag, with no
    // compare behind the push (ECP5's path into the full flag); each flag's
    // own compare is of the level as it stands, beside the push decode
    reg          top_r, one_r;
    // "the RAM holds no word" is a flag, not a pointer compare: it gates
    // the RAM's read enable and the output register, and a compare there is
    // the slowest path of the core on an iCE40 UP5K. rd_ptr_p1 = rd_ptr + 1
    // tells a load of the last word apart.
    reg         mem_empty;
    reg [AW:0]  rd_ptr_p1;
    // The RAM holds exactly one word (rd_ptr_p1 == wr_ptr), a flag too: the
    // empty flag's next value is then a choice by push and load among
    // flip-flops (the compare behind the push was ECP5's path into it). Its
    // own next value compares rd_ptr_p2 = rd_ptr + 2 with wr_ptr ("two
    // words"), beside the push decode.
    reg         mem_one;
    reg [AW:0]  rd_ptr_p2;
    assign level = level_r;
    assign full  = full_r;
    assign vacant = vacant_r;
    assign empty = !out_valid;

    wire do_push = push && !full;
    wire do_pop  = pop && out_valid;
    wire load    = !mem_empty && (!out_valid || do_pop);
    // lets a user register a select already masked by "not empty"
    assign valid_next = load || (out_valid && !do_pop);
    // up, down or held: the increment and the decrement run side by side
    // from the register, and push and pop only pick one
    wire [LW-1:0] level_up = level_r + 1'b1;
    wire [LW-1:0] level_dn = level_r - 1'b1;

    always @(posedge clk) begin
        if (do_push) mem[wr_ptr[AW-1:0]] <= din[W-LH-1:0];
        if (load)    d_lo <= mem[rd_ptr[AW-1:0]];
    end
    generate
        if (LH > 0) begin : g_hi
            (* ram_style = "logic" *) reg [LH-1:0] hi [0:DEPTH-1];
            reg [LH-1:0] d_hi;
            always @(posedge clk) begin
                if (do_push) hi[wr_ptr[AW-1:0]] <= din[W-1:W-LH];
                if (load)    d_hi <= hi[rd_ptr[AW-1:0]];
            end
            assign dout = {d_hi, d_lo};
        end else begin : g_lo
            assign dout = d_lo;
        end
    endgenerate

    always @(posedge clk) begin
        if (rst) begin
            wr_ptr    <= {(AW+1){1'b0}};
            rd_ptr    <= {(AW+1){1'b0}};
            rd_ptr_p1 <= {{AW{1'b0}}, 1'b1};
            rd_ptr_p2 <= TWO_P;
            mem_empty <= 1'b1;
            mem_one   <= 1'b0;
            out_valid <= 1'b0;
            level_r   <= {LW{1'b0}};
            full_r    <= 1'b0;
            vacant_r  <= 1'b1;
            top_r     <= 1'b0;             // DEPTH is at least 2
            one_r     <= 1'b0;
        end else begin
            if (do_push && !do_pop)      level_r <= level_up;
            else if (do_pop && !do_push) level_r <= level_dn;
            // from the level as it stands, not through the adder: a full
            // FIFO takes no push, so only a pop ends it
            if (full_r) full_r <= !do_pop;
            else        full_r <= do_push && !do_pop && top_r;
            if (do_push && !do_pop) begin
                vacant_r <= 1'b0;
                top_r    <= (level_r == DEPTH_M2);
                one_r    <= vacant_r;
            end else if (do_pop && !do_push) begin
                vacant_r <= one_r;
                top_r    <= full_r;
                one_r    <= (level_r == TWO_L);
            end
            if (do_push) wr_ptr <= wr_ptr + 1'b1;
            if (load) begin
                rd_ptr    <= rd_ptr_p1;
                rd_ptr_p1 <= rd_ptr_p2;
                rd_ptr_p2 <= rd_ptr_p2 + 1'b1;
            end
            if (do_push)   mem_empty <= 1'b0;
            else if (load) mem_empty <= mem_one;
            if (do_push && !load)      mem_one <= mem_empty;
            else if (load && !do_push) mem_one <= (rd_ptr_p2 == wr_ptr);
            if (load)         out_valid <= 1'b1;
            else if (do_pop)  out_valid <= 1'b0;
        end
    end

`ifdef FORMAL
    // No assumption on rst: the properties hold from the first reset on
    // (f_ok), so they stay true, and get checked again, when a design that
    // contains this FIFO is proven.
    reg f_ok = 1'b0;
    always @(posedge clk) if (rst) f_ok <= 1'b1;

    // Reference occupancy from the interface alone: a push counts unless the
    // FIFO already holds DEPTH words, a pop counts while the output is valid.
    reg  [LW-1:0] f_count;
    wire          f_push = push && (f_count != DEPTH_L);
    wire          f_pop  = pop && !empty;
    always @(posedge clk) begin
        if (rst) f_count <= {LW{1'b0}};
        else     f_count <= f_count + {{(LW-1){1'b0}}, f_push}
                                    - {{(LW-1){1'b0}}, f_pop};
    end

    wire [AW:0] f_mem_count = wr_ptr - rd_ptr;   // words behind the output
    always @(*) begin
        if (f_ok) begin
            assert(f_count <= DEPTH_L);
            assert(level == f_count);
            assert(full == (f_count == DEPTH_L));
            assert(vacant == (f_count == {LW{1'b0}}));
            assert(top_r == (level_r == DEPTH_L - 1'b1));
            assert(one_r == (level_r == {{(LW-1){1'b0}}, 1'b1}));
            // a full FIFO drops the push, an empty one ignores the pop
            assert(do_push == f_push);
            assert(do_pop == f_pop);
            // the output word is loaded one clock after it reaches an
            // empty FIFO: `empty` may trail `level` by that one clock only
            assert(!empty || level <= 1);
            // the registered level and full agree with the pointers
            assert(level == f_mem_count + {{AW{1'b0}}, out_valid});
            assert(out_valid || level == {{(LW-1){1'b0}}, !mem_empty});
            assert(f_mem_count <= DEPTH);
            assert(mem_empty == (wr_ptr == rd_ptr));
            assert(rd_ptr_p1 == rd_ptr + 1'b1);
            assert(rd_ptr_p2 == rd_ptr + 2'd2);
            assert(mem_one == (rd_ptr_p1 == wr_ptr));
            // no_rw_check on mem: never a push and a load at one address
            assert(!(do_push && load && wr_ptr[AW-1:0] == rd_ptr[AW-1:0]));
        end
    end

    reg f_past_ok = 1'b0;
    always @(posedge clk) f_past_ok <= f_ok && !rst;
    always @(posedge clk) begin
        if (f_past_ok) begin
            // a word pushed into an empty FIFO is on the output next clock
            if ($past(empty && level != 0)) assert(!empty);
            // no bubble: popping with more words stored shows the next at once
            if ($past(f_pop && level > 1)) assert(!empty);
            // valid_next told what empty is now
            assert($past(valid_next) == !empty);
        end
    end

    // Follow one arbitrary pushed word: f_pos counts the words ahead of it.
    // It must reach the output unchanged, exactly when those words have
    // been popped; as the word and the moment are arbitrary, every word
    // leaves in push order.
    (* anyseq *) reg f_pick;
    reg          f_track;
    reg [W-1:0]  f_data;
    reg [LW-1:0] f_pos;
    always @(posedge clk) begin
        if (rst) begin
            f_track <= 1'b0;
        end else if (!f_track) begin
            if (f_push && f_pick) begin
                f_track <= 1'b1;
                f_data  <= din;
                f_pos   <= f_count - {{(LW-1){1'b0}}, f_pop};
            end
        end else if (f_pop) begin
            if (f_pos == {LW{1'b0}}) f_track <= 1'b0;
            else                     f_pos   <= f_pos - 1'b1;
        end
    end

    // where the followed word is stored while it waits behind others
    wire [AW:0] f_slot = rd_ptr + f_pos[AW:0] - {{AW{1'b0}}, out_valid};
    wire [W-1:0] f_stored;
    generate
        if (LH > 0) begin : g_f_hi
            assign f_stored = {g_hi.hi[f_slot[AW-1:0]], mem[f_slot[AW-1:0]]};
        end else begin : g_f_lo
            assign f_stored = mem[f_slot[AW-1:0]];
        end
    endgenerate
    always @(*) begin
        if (f_ok && f_track) begin
            assert(f_pos < f_count);
            if (f_pos == {LW{1'b0}} && out_valid) assert(dout == f_data);
            else assert(f_stored == f_data);
        end
    end

    always @(posedge clk) begin
        if (f_past_ok) begin
            cover(full);
            cover($past(f_track && f_pop && f_pos == {LW{1'b0}} && level == DEPTH_L));
        end
    end
`endif
endmodule
`default_nettype wire
