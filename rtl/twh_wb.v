// Wishbone B4 classic slave around twh_core: 32-bit data, byte addresses.
// Each strobe is answered by exactly one ack or err, one clock after it is
// taken (see twh_core for what answers err).
`default_nettype none
module twh_wb #(
    parameter integer CLK_HZ     = 48_000_000,
    parameter integer CHANNELS   = 1,
    parameter integer FIFO_DEPTH = 16
) (
    input  wire                clk,
    input  wire                rst,
    input  wire [8:0]          wb_adr_i,
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
    // a strobe still high in the clock its answer goes out is the same
    // access, not a new one
    wire req = wb_cyc_i && wb_stb_i && !ack;

    twh_core #(.CLK_HZ(CLK_HZ), .CHANNELS(CHANNELS), .FIFO_DEPTH(FIFO_DEPTH)) u_core (
        .clk(clk), .rst(rst),
        .reg_req(req), .reg_we(wb_we_i), .reg_addr(wb_adr_i),
        .reg_wdata(wb_dat_i), .reg_wstrb(wb_sel_i),
        .reg_ack(ack), .reg_err(err), .reg_rdata(wb_dat_o),
        .irq(irq), .line_o(line_o), .line_oe(line_oe), .line_i(line_i)
    );

    assign wb_ack_o = ack && !err;
    assign wb_err_o = ack && err;

`ifdef FORMAL
    // Proven against formal/stub/twh_core.v, which keeps only the register
    // port's contract (answer on the next clock), so these are the
    // wrapper's own properties. The master is bound by one rule only: a
    // classic-cycle strobe stays up until it is answered (Wishbone B4
    // handshaking protocol; a reset releases it). With TWH_F_WB_ABORT it
    // may instead drop CYC at any time (abort).
    reg f_ok = 1'b0;       // a reset has been seen: the state is defined
    always @(posedge clk) if (rst) f_ok <= 1'b1;

    wire f_answer = wb_ack_o || wb_err_o;
    wire f_strobe = wb_cyc_i && wb_stb_i && !f_answer;   // asks, unanswered
    reg  f_past_valid = 1'b0;
    reg  f_asked = 1'b0;   // a strobe went unanswered on the last clock
    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_asked      <= !rst && f_strobe;
    end

    always @(posedge clk) begin
        if (f_past_valid && $past(f_strobe && !rst)) begin
`ifdef TWH_F_WB_ABORT
            if (wb_cyc_i) assume(wb_stb_i);
`else
            assume(wb_cyc_i && wb_stb_i);
`endif
        end
    end

    always @(*) begin
        if (f_ok) begin
            assert(!(wb_ack_o && wb_err_o));
            // one answer per strobe, on the next clock; none unasked, none
            // twice, none left over from a strobe cut short by a reset
            assert(f_answer == f_asked);
        end
    end
    always @(posedge clk) begin
        if (f_ok && f_answer) begin
`ifdef TWH_F_WB_ABORT
            // only in the very clock the master gives up the cycle
            assert((wb_cyc_i && wb_stb_i) || (!wb_cyc_i && $past(wb_cyc_i)));
`else
            assert(wb_cyc_i && wb_stb_i);
`endif
        end
    end

    // every clock the covers look back on lies after a reset
    reg [1:0] f_run = 2'd0;    // clocks since reset, saturating
    always @(posedge clk) begin
        if (rst) f_run <= 2'd0;
        else if (f_ok && f_run != 2'd3) f_run <= f_run + 1'b1;
    end
    always @(posedge clk) begin
        if (f_run == 2'd3) begin
            // a block cycle: a strobe held on after its answer is the next
            // access (answered every second clock, not every clock)
            cover(f_answer && $past(wb_cyc_i && wb_stb_i) && $past(f_answer, 2));
            cover(wb_err_o && $past(wb_ack_o, 2));
        end
    end
`endif
endmodule
`default_nettype wire
