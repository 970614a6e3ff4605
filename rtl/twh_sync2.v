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

`ifdef FORMAL
    // The pin reaches q exactly two clocks later, through no other path;
    // a reset shows as a low (released line reads as no carrier) until the
    // pin has passed both flops again.
    reg [1:0] f_rst_d = 2'b00;
    reg       f_past_valid = 1'b0;
    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_rst_d <= {f_rst_d[0], rst};
    end
    always @(posedge clk) begin
        if (f_past_valid && $past(f_past_valid)) begin
            if (f_rst_d == 2'b00) assert(q == $past(d, 2));
            else                  assert(q == 1'b0);
        end
    end
`endif
endmodule
`default_nettype wire
