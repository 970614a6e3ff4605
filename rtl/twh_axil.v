// AXI4-Lite slave around twh_core. A write takes its address and data
// together; one access is in flight at a time (writes first when both
// arrive together). SLVERR answers wherever the core reports an error.
`default_nettype none
module twh_axil #(
    parameter integer CLK_HZ     = 48_000_000,
    parameter integer CHANNELS   = 1,
    parameter integer FIFO_DEPTH = 16,
    parameter integer PROG_TIMING = 1,   // twh_core: features a fixed board may leave out
    parameter integer POLLING     = 1,
    parameter integer RAM_BLOCK   = 1    // twh_core: the engine's memories in block RAM
) (
    input  wire                clk,
    input  wire                rst,
    input  wire [10:0]         s_axil_awaddr,
    input  wire [2:0]          s_axil_awprot,
    input  wire                s_axil_awvalid,
    output wire                s_axil_awready,
    input  wire [31:0]         s_axil_wdata,
    input  wire [3:0]          s_axil_wstrb,
    input  wire                s_axil_wvalid,
    output wire                s_axil_wready,
    output reg  [1:0]          s_axil_bresp,
    output reg                 s_axil_bvalid,
    input  wire                s_axil_bready,
    input  wire [10:0]         s_axil_araddr,
    input  wire [2:0]          s_axil_arprot,
    input  wire                s_axil_arvalid,
    output wire                s_axil_arready,
    output reg  [31:0]         s_axil_rdata,
    output reg  [1:0]          s_axil_rresp,
    output reg                 s_axil_rvalid,
    input  wire                s_axil_rready,
    output wire                irq,
    output wire [CHANNELS-1:0] line_o,
    output wire [CHANNELS-1:0] line_oe,
    input  wire [CHANNELS-1:0] line_i
);
    reg  busy;                        // an access is in the core
    wire ready;                       // the core takes requests (not during its reset sweep)
    wire idle = !busy && !s_axil_bvalid && !s_axil_rvalid && ready;
    wire do_write = idle && s_axil_awvalid && s_axil_wvalid;
    wire do_read  = idle && s_axil_arvalid && !do_write;

    assign s_axil_awready = do_write;
    assign s_axil_wready  = do_write;
    assign s_axil_arready = do_read;

    wire        ack, err;
    wire [31:0] rdata;
    reg         was_write;

    twh_core #(.CLK_HZ(CLK_HZ), .CHANNELS(CHANNELS), .FIFO_DEPTH(FIFO_DEPTH),
               .PROG_TIMING(PROG_TIMING), .POLLING(POLLING),
               .RAM_BLOCK(RAM_BLOCK)) u_core (
        .clk(clk), .rst(rst),
        .reg_ready(ready), .reg_req(do_write || do_read), .reg_we(do_write),
        .reg_addr(do_write ? s_axil_awaddr : s_axil_araddr),
        .reg_wdata(s_axil_wdata), .reg_wstrb(s_axil_wstrb),
        .reg_ack(ack), .reg_err(err), .reg_rdata(rdata),
        .irq(irq), .line_o(line_o), .line_oe(line_oe), .line_i(line_i)
    );

    always @(posedge clk) begin
        if (rst) begin
            busy          <= 1'b0;
            was_write     <= 1'b0;
            s_axil_bvalid <= 1'b0;
            s_axil_bresp  <= 2'b00;
            s_axil_rvalid <= 1'b0;
            s_axil_rresp  <= 2'b00;
            s_axil_rdata  <= 32'd0;
        end else begin
            if (do_write || do_read) begin
                busy      <= 1'b1;
                was_write <= do_write;
            end
            if (ack) begin
                busy <= 1'b0;
                if (was_write) begin
                    s_axil_bvalid <= 1'b1;
                    s_axil_bresp  <= err ? 2'b10 : 2'b00;
                end else begin
                    s_axil_rvalid <= 1'b1;
                    s_axil_rresp  <= err ? 2'b10 : 2'b00;
                    s_axil_rdata  <= rdata;
                end
            end
            if (s_axil_bvalid && s_axil_bready) s_axil_bvalid <= 1'b0;
            if (s_axil_rvalid && s_axil_rready) s_axil_rvalid <= 1'b0;
        end
    end

`ifdef FORMAL
    // Proven against formal/stub/twh_core.v, which keeps only the register
    // port's contract (answer two clocks after the request, error and read
    // data free),
    // so these are the wrapper's own properties. Assumptions bind the
    // master's side only (AMBA AXI A3.1.2, A3.2.1): no VALID during reset,
    // and a VALID stays up with its payload unchanged until its READY.
    reg f_ok = 1'b0;       // a reset has been seen: the state is defined
    always @(posedge clk) if (rst) f_ok <= 1'b1;
    reg f_past_valid = 1'b0;
    always @(posedge clk) f_past_valid <= 1'b1;

    wire f_aw = s_axil_awvalid && s_axil_awready;
    wire f_w  = s_axil_wvalid  && s_axil_wready;
    wire f_ar = s_axil_arvalid && s_axil_arready;
    wire f_b  = s_axil_bvalid  && s_axil_bready;
    wire f_r  = s_axil_rvalid  && s_axil_rready;

    always @(*) begin
        if (rst) assume(!s_axil_awvalid && !s_axil_wvalid && !s_axil_arvalid);
    end
    always @(posedge clk) begin
        if (f_past_valid && !$past(rst)) begin
            if ($past(s_axil_awvalid && !s_axil_awready))
                assume(s_axil_awvalid && $stable(s_axil_awaddr) && $stable(s_axil_awprot));
            if ($past(s_axil_wvalid && !s_axil_wready))
                assume(s_axil_wvalid && $stable(s_axil_wdata) && $stable(s_axil_wstrb));
            if ($past(s_axil_arvalid && !s_axil_arready))
                assume(s_axil_arvalid && $stable(s_axil_araddr) && $stable(s_axil_arprot));
        end
    end

    // Accesses accepted and not yet answered by a B or R handshake, and the
    // core's answer to the access in flight; f_q, f_q2: the access in the
    // core's request stage, and the one being answered.
    reg        f_q = 1'b0, f_q2 = 1'b0;
    always @(posedge clk) begin
        f_q  <= !rst && (do_write || do_read);
        f_q2 <= !rst && f_q;
    end
    reg        f_wr_open, f_rd_open;
    reg        f_err;
    reg [31:0] f_rdata;
    always @(posedge clk) begin
        if (rst) begin
            f_wr_open <= 1'b0;
            f_rd_open <= 1'b0;
        end else begin
            if (f_aw) f_wr_open <= 1'b1;
            else if (f_b) f_wr_open <= 1'b0;
            if (f_ar) f_rd_open <= 1'b1;
            else if (f_r) f_rd_open <= 1'b0;
        end
        if (ack) begin
            f_err   <= err;
            f_rdata <= rdata;
        end
    end

    always @(*) begin
        if (f_ok) begin
            // address and data are taken together, reads and writes never
            // both: one access in flight
            assert(f_aw == f_w);
            assert(!(f_aw && f_ar));
            assert(!(f_wr_open && f_rd_open));
            assert(!f_wr_open || !(f_aw || f_ar));
            assert(!f_rd_open || !(f_aw || f_ar));
            // a response only for an access that was accepted, on its own
            // channel, and never a second one (the handshake closes it)
            assert(!s_axil_bvalid || f_wr_open);
            assert(!s_axil_rvalid || f_rd_open);
            // the response carries the core's answer: OKAY or SLVERR only
            if (s_axil_bvalid) assert(s_axil_bresp == {f_err, 1'b0});
            if (s_axil_rvalid) assert(s_axil_rresp == {f_err, 1'b0} && s_axil_rdata == f_rdata);
            // an open access with no response up yet is in the core
            assert(busy == ((f_wr_open && !s_axil_bvalid) || (f_rd_open && !s_axil_rvalid)));
            assert(!busy || was_write == f_wr_open);
            // the core answers two clocks after the request (stage, access)
            assert(ack == f_q2);
            assert(busy == (f_q || f_q2));
        end
    end

    always @(posedge clk) begin
        if (f_ok && f_past_valid && !$past(rst)) begin
            // VALID is held until READY, the payload unchanged meanwhile
            if ($past(s_axil_bvalid && !s_axil_bready))
                assert(s_axil_bvalid && $stable(s_axil_bresp));
            if ($past(s_axil_rvalid && !s_axil_rready))
                assert(s_axil_rvalid && $stable(s_axil_rresp) && $stable(s_axil_rdata));
            // the response comes up three clocks after the request: two to
            // the core's answer, one to the response register
            if ($past(f_past_valid && !rst && f_aw, 3) && !$past(rst, 2)) assert(s_axil_bvalid);
            if ($past(f_past_valid && !rst && f_ar, 3) && !$past(rst, 2)) assert(s_axil_rvalid);
        end
        if (f_ok && f_past_valid && $past(rst))
            assert(!s_axil_bvalid && !s_axil_rvalid);
    end

    // every clock the covers look back on lies after a reset
    reg [2:0] f_run = 3'd0;    // clocks since reset, saturating
    always @(posedge clk) begin
        if (rst) f_run <= 3'd0;
        else if (f_ok && f_run != 3'd5) f_run <= f_run + 1'b1;
    end
    always @(posedge clk) begin
        if (f_run == 3'd5) begin
            cover(f_b && s_axil_bresp == 2'b10);
            cover(f_r && $past(f_b, 4));     // back to back: one access per 4 clocks
            // a read and a write arrive together: the write goes first
            cover(f_ar && $past(s_axil_arvalid && s_axil_awvalid && s_axil_wvalid, 4));
        end
    end
`endif

    // protection attributes carry no meaning for this core
    // verilator lint_off UNUSEDSIGNAL
    wire unused_prot = |{s_axil_awprot, s_axil_arprot};
    // verilator lint_on UNUSEDSIGNAL
endmodule
`default_nettype wire
