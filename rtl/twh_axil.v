// AXI4-Lite slave around twh_core. A write takes its address and data
// together; one access is in flight at a time (writes first when both
// arrive together). SLVERR answers wherever the core reports an error.
`default_nettype none
module twh_axil #(
    parameter integer CLK_HZ     = 48_000_000,
    parameter integer CHANNELS   = 1,
    parameter integer FIFO_DEPTH = 16
) (
    input  wire                clk,
    input  wire                rst,
    input  wire [8:0]          s_axil_awaddr,
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
    input  wire [8:0]          s_axil_araddr,
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
    wire idle = !busy && !s_axil_bvalid && !s_axil_rvalid;
    wire do_write = idle && s_axil_awvalid && s_axil_wvalid;
    wire do_read  = idle && s_axil_arvalid && !do_write;

    assign s_axil_awready = do_write;
    assign s_axil_wready  = do_write;
    assign s_axil_arready = do_read;

    wire        ack, err;
    wire [31:0] rdata;
    reg         was_write;

    twh_core #(.CLK_HZ(CLK_HZ), .CHANNELS(CHANNELS), .FIFO_DEPTH(FIFO_DEPTH)) u_core (
        .clk(clk), .rst(rst),
        .reg_req(do_write || do_read), .reg_we(do_write),
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

    // protection attributes carry no meaning for this core
    // verilator lint_off UNUSEDSIGNAL
    wire unused_prot = |{s_axil_awprot, s_axil_arprot};
    // verilator lint_on UNUSEDSIGNAL
endmodule
`default_nettype wire
