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
endmodule
`default_nettype wire
