// Two-flop synchroniser for an asynchronous pin.
`default_nettype none
module twh_sync2 (
    input  wire clk,
    input  wire rst,
    input  wire d,
    output wire q
);
    reg [1:0] s;
    always @(posedge clk) begin
        if (rst) s <= 2'b00;
        else     s <= {s[0], d};
    end
    assign q = s[1];
endmodule
`default_nettype wire
