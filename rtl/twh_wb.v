// Wishbone B4 classic slave around twh_core: 32-bit data, byte addresses.
// Each strobe is answered by exactly one ack or err, two clocks after it is
// taken (the core's request stage, then the access; see twh_core for what
// answers err). One access is in the core at a time. A cycle abandoned
// (CYC dropped) before its answer still completes inside the core, but its
// answer is swallowed, so it can never be taken for a later strobe's. Side
// effects stay: an abandoned RES_POP read has removed its result (lost to
// software), an abandoned CMD_PUSH has queued its command (a retry queues
// it twice). Masters that abandon cycles must not do so on those two.
`default_nettype none
module twh_wb #(
    parameter integer CLK_HZ     = 48_000_000,
    parameter integer CHANNELS   = 1,
    parameter integer FIFO_DEPTH = 16,
    parameter integer PROG_TIMING = 1,   // twh_core: features a fixed board may leave out
    parameter integer POLLING     = 1,
    parameter integer RAM_BLOCK   = 1    // twh_core: the engine's memories in block RAM
) (
    input  wire                clk,
    input  wire                rst,
    input  wire [10:0]         wb_adr_i,
    input  wire [31:0]         wb_dat_i,
    output wire [31:0]         wb_dat_o,
    input  wire                wb_we_i,
    input  wire [3:0]          wb_sel_i,
    input  wire                wb_stb_i,
    input  wire                wb_cyc_i,
    output wire                wb_ack_o,
    output wire                wb_err_o,
    output wire                irq,
    output wire [CHANNELS-1:0] line_o,
    output wire [CHANNELS-1:0] line_oe,
    input  wire [CHANNELS-1:0] line_i
);
    wire ack, err;
    wire ready;  // the core takes requests (not during its reset sweep)
    reg  busy;   // a taken strobe waits for its answer
    reg  drop;   // ... and its cycle was abandoned: the answer is swallowed
    wire req = wb_cyc_i && wb_stb_i && !busy && ready;
    always @(posedge clk) begin
        if (rst) begin
            busy <= 1'b0;
            drop <= 1'b0;
        end else begin
            if (req)      busy <= 1'b1;
            else if (ack) busy <= 1'b0;
            if (ack)                    drop <= 1'b0;
            else if (busy && !wb_cyc_i) drop <= 1'b1;
        end
    end
    wire answer = ack && wb_cyc_i && !drop;

    twh_core #(.CLK_HZ(CLK_HZ), .CHANNELS(CHANNELS), .FIFO_DEPTH(FIFO_DEPTH),
               .PROG_TIMING(PROG_TIMING), .POLLING(POLLING),
               .RAM_BLOCK(RAM_BLOCK)) u_core (
        .clk(clk), .rst(rst),
        .reg_ready(ready), .reg_req(req), .reg_we(wb_we_i), .reg_addr(wb_adr_i),
        .reg_wdata(wb_dat_i), .reg_wstrb(wb_sel_i),
        .reg_ack(ack), .reg_err(err), .reg_rdata(wb_dat_o),
        .irq(irq), .line_o(line_o), .line_oe(line_oe), .line_i(line_i)
    );

    assign wb_ack_o = answer && !err;
    assign wb_err_o = answer && err;

`ifdef FORMAL
    // Proven against formal/stub/twh_core.v, which keeps only the register
    // port's contract (answer two clocks after the request), so these are
    // the wrapper's own properties. The master is bound by one rule only: a
    // classic-cycle strobe stays up until it is answered (Wishbone B4
    // handshaking protocol; a reset releases it). With TWH_F_WB_ABORT it
    // may instead drop CYC at any time (abort).
    reg f_ok = 1'b0;       // a reset has been seen: the state is defined
    always @(posedge clk) if (rst) f_ok <= 1'b1;

    wire f_answer = wb_ack_o || wb_err_o;
    wire f_strobe = wb_cyc_i && wb_stb_i && !f_answer;   // asks, unanswered
    reg  f_past_valid = 1'b0;
    // clocks the strobe now up has waited unanswered since the core could
    // take it (0: none waiting; the core's reset sweep, ready low, does not
    // count)
    reg  [2:0] f_age = 3'd0;
    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        if (rst || !f_strobe)                    f_age <= 3'd0;
        else if (f_age != 3'd7 && (busy || ready)) f_age <= f_age + 1'b1;
    end

    always @(posedge clk) begin
        if (f_past_valid && !$past(rst) && $past(f_strobe)) begin
`ifdef TWH_F_WB_ABORT
            if (wb_cyc_i) assume(wb_stb_i);
`else
            assume(wb_cyc_i && wb_stb_i);
`endif
        end
    end

    // the request in the core's stage, and the one being answered
    reg f_q = 1'b0, f_q2 = 1'b0;
    always @(posedge clk) begin
        f_q  <= !rst && req;
        f_q2 <= !rst && f_q;
    end

    always @(*) begin
        if (f_ok) begin
            // one access in the core at a time, answered as the contract says
            assert(ack == f_q2);
            assert(busy == (f_q || f_q2));
            assert(!(f_q && f_q2));
            assert(!(wb_ack_o && wb_err_o));
`ifdef TWH_F_WB_ABORT
            // answers only to a strobe that is up and has waited its two
            // clocks, and none waits more than three (an abandoned access
            // ahead of it)
            if (f_answer) assert(wb_cyc_i && wb_stb_i && f_age >= 3'd2);
            assert(f_age <= 3'd3);
            // how long the strobe up has waited, by where its access is
            if (!busy) assert(f_age <= 3'd1 && !drop);
            if (f_q)   assert((f_age == 3'd1 || f_age == 3'd2) && !drop);
            if (f_q2)  assert(drop ? f_age == 3'd0 : (f_age == 3'd2 || f_age == 3'd3));
`else
            // one answer per strobe, exactly two clocks after it is taken;
            // none unasked, none twice, none left over from a strobe cut
            // short by a reset
            assert(f_answer == (f_age == 3'd2));
            assert(f_age <= 3'd2);
            assert(busy == (f_age != 3'd0));
            assert(!drop);
`endif
        end
    end

    // every clock the covers look back on lies after a reset
    reg [2:0] f_run = 3'd0;    // clocks since reset, saturating
    always @(posedge clk) begin
        if (rst) f_run <= 3'd0;
        else if (f_ok && f_run != 3'd4) f_run <= f_run + 1'b1;
    end
    always @(posedge clk) begin
        if (f_run == 3'd4) begin
            // a block cycle: a strobe held on after its answer is the next
            // access (answered every third clock)
            cover(f_answer && $past(wb_cyc_i && wb_stb_i) && $past(f_answer, 3));
            cover(wb_err_o && $past(wb_ack_o, 3));
`ifdef TWH_F_WB_ABORT
            // an abandoned access's answer is swallowed; the next strobe
            // gets its own
            cover(f_answer && f_age == 3'd3);
`endif
        end
    end
`endif
endmodule
`default_nettype wire
