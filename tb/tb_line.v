// One simulated 2-wire line: a stuck-line fault overrides everything;
// otherwise the host drives when host_oe is high, else the peripheral model
// when periph_oe is high, else the front end's pull-down reads low. `glitch`
// is OR-ed on top so a test can inject spikes anywhere.
`default_nettype none
module tb_line (
    input  wire host_o,
    input  wire host_oe,
    input  wire periph_o,
    input  wire periph_oe,
    input  wire stuck_en,
    input  wire stuck_val,
    input  wire glitch,
    output wire line
);
    assign line = stuck_en ? stuck_val
                : ((host_oe ? host_o : (periph_oe ? periph_o : 1'b0)) | glitch);
endmodule
`default_nettype wire
