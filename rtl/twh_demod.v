// On-off-keying demodulator for the peripheral's answer.
//
// Turns the synchronised line into an envelope: high while a carrier
// (0.90-1.10 MHz, 30-70 % duty) or a plain baseband high is present.
// - A high must last GLITCH_NS (rounded down to whole clocks, at least one
//   clock) before it counts, so shorter spikes are ignored outright.
// - Each accepted high re-arms a hold of HOLD_NS, which bridges the carrier's
//   low halves (at most 0.78 us at 0.90 MHz and 30 % duty) but is short
//   against a 32 us bit, so the envelope's edges lag the true bit edges by
//   about one microsecond. Longer glitches that get through become envelope
//   pulses of about HOLD_NS; the receiver's majority vote rejects those.
`default_nettype none
module twh_demod #(
    parameter integer CLK_HZ    = 48_000_000,
    parameter integer GLITCH_NS = 100,
    parameter integer HOLD_NS   = 1500
) (
    input  wire clk,
    input  wire rst,
    input  wire line_s,     // already synchronised
    output reg  env
);
    localparam integer CLK_KHZ = CLK_HZ / 1000;
    localparam integer GL_RAW  = CLK_KHZ * GLITCH_NS / 1_000_000;
    localparam integer GL      = (GL_RAW < 1) ? 1 : GL_RAW;
    localparam integer HOLD    = (CLK_KHZ * HOLD_NS + 999_999) / 1_000_000;
    localparam integer GW      = $clog2(GL + 1);
    localparam integer HW      = $clog2(HOLD + 1);
    localparam integer GL_LAST_I = GL - 1;
    localparam [GW-1:0] GL_LAST = GL_LAST_I[GW-1:0];
    localparam [GW-1:0] GL_SAT  = GL[GW-1:0];
    localparam [HW-1:0] HOLD_V  = HOLD[HW-1:0];

    reg [HW-1:0] hold;
    wire         hi_ok;    // this sample ends GL consecutive high samples

    generate
        if (GL == 1) begin : g_nofilter
            assign hi_ok = line_s;
        end else begin : g_filter
            reg [GW-1:0] hc;    // consecutive high samples, saturating at GL
            always @(posedge clk) begin
                if (rst || !line_s)   hc <= {GW{1'b0}};
                else if (hc != GL_SAT) hc <= hc + 1'b1;
            end
            assign hi_ok = line_s && (hc >= GL_LAST);
        end
    endgenerate

    always @(posedge clk) begin
        if (rst) begin
            hold <= {HW{1'b0}};
            env  <= 1'b0;
        end else begin
            if (hi_ok)                   hold <= HOLD_V;
            else if (hold != {HW{1'b0}}) hold <= hold - 1'b1;
            env <= hi_ok || (hold != {HW{1'b0}});
        end
    end
endmodule
`default_nettype wire
