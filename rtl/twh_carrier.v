// 1 MHz carrier timebase.
//
// Emits `tick` once per carrier period (the period that starts on the next
// clock edge) and `fall` where that period's high half ends; `tick_nx` says
// a clock ahead that `tick` comes next (unless reset is on), so a channel
// can take its own registered copy, with its own enable in it, off the one
// tick's routing. Everything in
// the core counts these ticks, so "one microsecond" is one carrier period and
// one UART bit is exactly 32 of them.
//
// The period is P = floor(CLK_HZ / 1 MHz) clocks. When CLK_HZ is not a whole
// number of MHz, a Bresenham accumulator stretches some periods to P+1 so the
// long-term average is exactly 1 MHz; each single period then stays within
// the spec's 0.90-1.10 MHz and 45-60 % duty, which elaboration checks. Below
// 10 MHz few fractional clocks pass (5.5, 7.5 and 9.5 MHz do; 6.5 and 8.5 MHz
// fail on the duty): whole-MHz clocks are the safe choice there.
//
// Only a narrow down-counter runs every cycle; the accumulator advances once
// per period and vanishes when CLK_HZ is a whole number of MHz.
`default_nettype none
`include "twh_defs.vh"
module twh_carrier #(
    parameter integer CLK_HZ = 48_000_000,
    // the core's time-shared engine's channels (0: none): the engine's
    // clock floor is checked here, after this module's own checks
    parameter integer FLOOR_CHANNELS = 0
) (
    input  wire clk,
    input  wire rst,
    output reg  tick,
    output reg  fall,
    output reg  tick_nx     // tick is 1 in the next clock (with rst low now)
);
    localparam integer CLK_HZ_MIN = 4_000_000;
    localparam integer CLK_HZ_MAX = 200_000_000;
    localparam CLK_OK = CLK_HZ >= CLK_HZ_MIN && CLK_HZ <= CLK_HZ_MAX;
    // out of the range, a legal stand-in: nothing below breaks on the bad
    // value before the tool reports the check's missing module
    localparam integer CLK_N = CLK_OK ? CLK_HZ : 48_000_000;
    localparam integer P    = CLK_N / 1_000_000;      // clocks per period
    localparam integer FRAC = CLK_N % 1_000_000;      // Hz left over
    localparam integer H    = (P + 1) / 2;            // clocks high
    localparam integer CW   = $clog2(P);              // counter width
    localparam integer LOAD_I    = P - 1;
    localparam integer FALL_AT_I = P - H;
    localparam [CW-1:0] LOAD    = LOAD_I[CW-1:0];
    localparam [CW-1:0] FALL_AT = FALL_AT_I[CW-1:0];
    localparam integer  ONE_I   = 1;
    localparam [CW-1:0] ONE     = ONE_I[CW-1:0];
    localparam [20:0]   FRAC21  = FRAC[20:0];

    // Elaboration checks: an unknown module names the problem, the first
    // that applies (outside the range the carrier checks below mean
    // nothing). The range is CLK_HZ_MIN-CLK_HZ_MAX and its module's name:
    // change both together (tb/test_params.py checks that they agree).
    generate
        if (!CLK_OK) begin : g_bad_clk
            twh_error_CLK_HZ_must_be_4MHz_to_200MHz u_err ();
        end
        // per-period frequency of a stretched (P+1) and an unstretched (P)
        // period, and the duty of both, must stay inside the spec window
        else if (FRAC != 0 && (CLK_HZ / 10 > 1_100_000 / 10 * P ||
                               CLK_HZ / 10 < 900_000 / 10 * (P + 1))) begin : g_bad_frac
            twh_error_CLK_HZ_fraction_puts_a_carrier_period_out_of_spec u_err ();
        end
        else if (100 * H > 60 * P || 100 * H < 45 * (P + (FRAC != 0 ? 1 : 0))) begin : g_bad_duty
            twh_error_CLK_HZ_gives_carrier_duty_out_of_spec u_err ();
        end
        else if (FLOOR_CHANNELS != 0 && !`TWH_ENGINE_FLOOR_OK(P, FRAC, FLOOR_CHANNELS)) begin : g_bad_floor
            twh_error_CLK_HZ_below_the_engine_floor_for_CHANNELS u_err ();
        end
    endgenerate

    reg [CW-1:0] cnt;
    reg          stretch;   // this period gets one extra (low) clock
    reg [19:0]   acc;       // fractional MHz, in Hz
    // tick_nx is "cnt is 0 and no stretch", a register taken a clock ahead:
    // cnt reaches 0 from 1 (stretch as it is), or stays at 0 for the
    // stretch's extra clock, or starts there after reset. Every channel's
    // early-tick registers then start from it, not from the compare (ECP5's
    // three-channel path ran through it).
    always @(posedge clk)
        tick_nx <= rst || (cnt == ONE && !stretch) || (cnt == {CW{1'b0}} && stretch);

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
            tick <= tick_nx;
            fall <= (cnt == FALL_AT);
            if (cnt == {CW{1'b0}}) begin
                if (stretch) begin
                    stretch <= 1'b0;          // hold zero one more clock
                end else begin
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

`ifdef FORMAL
    // No assumption on rst: checked from the first reset on (f_ok).
    reg f_ok = 1'b0;
    always @(posedge clk) if (rst) f_ok <= 1'b1;

    localparam [8:0] F_P  = P;
    localparam [8:0] F_H  = H;
    localparam [8:0] F_PM = P + ((FRAC != 0) ? 1 : 0);     // longest period
    // the spec window (0.90-1.10 MHz, duty 45-60 %) for a period of P and
    // of P+1 clocks, high for H
    localparam F_P_IN  = (P * 1_100 >= CLK_HZ / 1_000) && (P * 900 <= CLK_HZ / 1_000)
                         && (100 * H >= 45 * P) && (100 * H <= 60 * P);
    localparam F_P1_IN = ((P + 1) * 1_100 >= CLK_HZ / 1_000) && ((P + 1) * 900 <= CLK_HZ / 1_000)
                         && (100 * H >= 45 * (P + 1)) && (100 * H <= 60 * (P + 1));

    // clocks since the last tick, a tick seen since reset, a fall seen in
    // the current period
    reg  [8:0] f_since;
    reg        f_ticked, f_fell;
    wire [8:0] f_j = tick ? 9'd0 : f_since;
    // Time error of the last tick against an exact 1 MHz grid anchored at
    // the first tick after reset, in units of 1/(CLK_HZ * 1 MHz) seconds (a
    // clock is 1_000_000 of them): each period of n clocks adds
    // n * 1 MHz - CLK_HZ.
    localparam signed [23:0] F_US     = 24'sd1_000_000;
    localparam signed [23:0] F_FRAC_S = FRAC;
    reg  signed [23:0] f_drift_r;
    wire signed [23:0] f_drift = (tick && f_ticked)
        ? f_drift_r - F_FRAC_S + ((f_since == F_P) ? 24'sd0 : F_US) : f_drift_r;
    always @(posedge clk) begin
        if (rst) begin
            f_since  <= 9'd0;
            f_ticked <= 1'b0;
            f_fell   <= 1'b0;
            f_drift_r <= 24'sd0;
        end else begin
            f_since  <= f_j + 1'b1;
            f_ticked <= f_ticked || tick;
            f_fell   <= fall || (f_fell && !tick);
            f_drift_r <= f_drift;
        end
    end

    // the accumulator as it was when this period's stretch was decided
    wire        f_stretched = stretch || (f_j == F_P);
    wire [20:0] f_acc_prev  = {1'b0, acc} - FRAC21
                              + (f_stretched ? 21'd1_000_000 : 21'd0);

    reg f_pv = 1'b0;
    always @(posedge clk) f_pv <= 1'b1;
    always @(posedge clk) if (f_pv) assert(tick == $past(tick_nx && !rst));
    // (from any state a clock back, reset or not) ...
    always @(*) if (f_pv) assert(tick_nx == ((cnt == {CW{1'b0}}) && !stretch));
    // ... so a tick comes with the count just loaded: ticks are a whole
    // period apart (tick is tick_nx's register, and the proofs of the
    // engines that count ticks need this as an invariant of every state;
    // tick_nx starts at 0 here so that it holds from the first clock)
    initial tick_nx = 1'b0;
    always @(*) if (f_pv) assert(!tick || cnt == LOAD);

    always @(*) begin
        if (f_ok) begin
            assert(!(tick && fall));
            // first tick two clocks after reset, then one per period
            if (!f_ticked) assert(f_since == (tick ? 9'd1 : 9'd0) && !fall);
            if (f_ticked) begin
                assert(f_j < F_PM);
                // the high half ends exactly H clocks into the period, once
                if (fall) assert(f_j == F_H && !f_fell);
                if (tick) begin
                    assert(f_fell);
                    // every period is P clocks, or P+1 when stretched, and
                    // inside the spec window
                    assert((f_since == F_P && F_P_IN) ||
                           (FRAC != 0 && f_since == F_P + 9'd1 && F_P1_IN));
                end
                // every tick lies less than one clock ahead of the exact
                // 1 MHz grid, never behind it: the average is exact
                assert(f_drift <= 24'sd0 && f_drift > -F_US);
                // the state follows from the time in the period; the drift
                // is the Bresenham error left in the accumulator
                assert(cnt == ((f_j < F_P) ? F_P - 9'd1 - f_j : 9'd0));
                assert(f_fell == (tick || f_j > F_H));
                assert(!(stretch && f_j == F_P));
                assert(acc < 20'd1_000_000);
                if (FRAC == 0) assert(acc == 20'd0 && !stretch);
                // a period is stretched exactly when the accumulator wrapped
                else assert(f_stretched == (acc < FRAC21[19:0]));
                assert(f_drift == -$signed({3'd0, f_acc_prev}));
            end else begin
                assert(f_drift == 24'sd0);
                if (tick) assert(cnt == LOAD && !stretch && acc == FRAC21[19:0]);
                else      assert(cnt == {CW{1'b0}} && !stretch && acc == 20'd0);
            end
        end
    end

    always @(posedge clk) begin
        if (f_ok && f_ticked) begin
            cover(tick && f_since == F_PM);    // a stretched period, if any
        end
    end
`endif
endmodule
`default_nettype wire
