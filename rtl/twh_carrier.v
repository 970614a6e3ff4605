// 1 MHz carrier timebase.
//
// Emits `tick` once per carrier period (the period that starts on the next
// clock edge) and `fall` where that period's high half ends. Everything in
// the core counts these ticks, so "one microsecond" is one carrier period and
// one UART bit is exactly 32 of them.
//
// The period is P = floor(CLK_HZ / 1 MHz) clocks. When CLK_HZ is not a whole
// number of MHz, a Bresenham accumulator stretches some periods to P+1 so the
// long-term average is exactly 1 MHz; each single period then stays within
// the spec's 0.90-1.10 MHz and 45-60 % duty, which elaboration checks. Below
// 10 MHz that is only possible for whole-MHz clocks.
//
// Only a narrow down-counter runs every cycle; the accumulator advances once
// per period and vanishes when CLK_HZ is a whole number of MHz.
`default_nettype none
module twh_carrier #(
    parameter integer CLK_HZ = 48_000_000
) (
    input  wire clk,
    input  wire rst,
    output reg  tick,
    output reg  fall
);
    localparam integer P    = CLK_HZ / 1_000_000;     // clocks per period
    localparam integer FRAC = CLK_HZ % 1_000_000;     // Hz left over
    localparam integer H    = (P + 1) / 2;            // clocks high
    localparam integer CW   = $clog2(P);              // counter width
    localparam integer LOAD_I    = P - 1;
    localparam integer FALL_AT_I = P - H;
    localparam [CW-1:0] LOAD    = LOAD_I[CW-1:0];
    localparam [CW-1:0] FALL_AT = FALL_AT_I[CW-1:0];
    localparam [20:0]   FRAC21  = FRAC[20:0];

    // Elaboration checks: an unknown module names the problem.
    generate
        if (CLK_HZ < 4_000_000 || CLK_HZ > 200_000_000) begin : g_bad_clk
            twh_error_CLK_HZ_must_be_4MHz_to_200MHz u_err ();
        end
        // per-period frequency of a stretched (P+1) and an unstretched (P)
        // period, and the duty of both, must stay inside the spec window
        if (FRAC != 0 && (CLK_HZ / 10 > 1_100_000 / 10 * P ||
                          CLK_HZ / 10 < 900_000 / 10 * (P + 1))) begin : g_bad_frac
            twh_error_CLK_HZ_below_10MHz_must_be_whole_MHz u_err ();
        end
        if (100 * H > 60 * P || 100 * H < 45 * (P + (FRAC != 0 ? 1 : 0))) begin : g_bad_duty
            twh_error_CLK_HZ_gives_carrier_duty_out_of_spec u_err ();
        end
    endgenerate

    reg [CW-1:0] cnt;
    reg          stretch;   // this period gets one extra (low) clock
    reg [19:0]   acc;       // fractional MHz, in Hz

    // The next accumulator value and whether it overflows one whole MHz.
    wire [20:0] acc_sum  = {1'b0, acc} + FRAC21;
    wire        acc_wrap = (acc_sum >= 21'd1_000_000);

    always @(posedge clk) begin
        if (rst) begin
            cnt     <= {CW{1'b0}};
            stretch <= 1'b0;
            acc     <= 20'd0;
            tick    <= 1'b0;
            fall    <= 1'b0;
        end else begin
            tick <= 1'b0;
            fall <= (cnt == FALL_AT);
            if (cnt == {CW{1'b0}}) begin
                if (stretch) begin
                    stretch <= 1'b0;          // hold zero one more clock
                end else begin
                    tick <= 1'b1;
                    cnt  <= LOAD;
                    if (FRAC != 0) begin
                        stretch <= acc_wrap;
                        acc     <= acc_wrap ? acc_sum[19:0] - 20'd1_000_000
                                            : acc_sum[19:0];
                    end
                end
            end else begin
                cnt <= cnt - 1'b1;
            end
        end
    end
endmodule
`default_nettype wire
