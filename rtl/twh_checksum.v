// The 2-wire checksum: one's complement of the 8-bit sum of the bytes it
// covers (NOTES.md reads the spec's "MOD 8" as modulo 2^8). Unused inputs are
// tied to zero by the caller, so one module serves 2- and 3-byte sums.
`default_nettype none
module twh_checksum (
    input  wire [7:0] a,
    input  wire [7:0] b,
    input  wire [7:0] c,
    output wire [7:0] chk
);
    wire [7:0] sum = a + b + c;
    assign chk = ~sum;
endmodule
`default_nettype wire
