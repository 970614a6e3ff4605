// On-off-keying demodulator for the peripheral's answer.
//
// Turns the synchronised line into an envelope: high while a carrier
// (0.90-1.10 MHz, 30-70 % duty) or a plain baseband high is present.
// - A high must last GLITCH_NS (rounded down to whole clocks, at least one
//   clock) before it counts, so shorter spikes are ignored outright.
// - Each accepted high re-arms a hold of HOLD_NS, which bridges the carrier's
//   low halves (at most 0.78 us at 0.90 MHz and 30 % duty) but is short
//   against a 32 us bit. The envelope rises a synchroniser and GLITCH_NS
//   after the line (about 0.1 us) and falls HOLD_NS after its last high
//   (1-1.5 us), so a 0 bit reads about 1 us short and the receiver's
//   samples sit about 1 us after the bit's centre, well inside it. Longer
//   glitches that get through become envelope pulses of about HOLD_NS; the
//   receiver's majority vote rejects those.
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

`ifdef FORMAL
    // No assumption on rst: checked from the first reset on (f_ok).
    reg f_ok = 1'b0;
    always @(posedge clk) if (rst) f_ok <= 1'b1;

    // Reference, in the terms of docs/protocol.md: a sample is accepted
    // when it and the F_GL-1 before it (since reset) are high, F_GL =
    // max(1, floor(CLK_HZ x GLITCH_NS)); the envelope is high for the
    // F_HOLD+1 clocks after an accepted sample, F_HOLD = HOLD_NS in clocks
    // rounded up. (Written anew here, so a slip in the RTL's constants shows.)
    // (x * ns / 1e9 in 32 bits: whole kHz first, the rest of the clock
    // rounded the same way; floor and ceiling nest exactly)
    localparam integer F_GL_RAW = (CLK_HZ / 1_000 * GLITCH_NS
                                   + CLK_HZ % 1_000 * GLITCH_NS / 1_000) / 1_000_000;
    localparam integer F_GL     = (F_GL_RAW < 1) ? 1 : F_GL_RAW;
    localparam integer F_HOLD_I = (CLK_HZ / 1_000 * HOLD_NS
                                   + (CLK_HZ % 1_000 * HOLD_NS + 999) / 1_000
                                   + 999_999) / 1_000_000;
    localparam integer F_AW = $clog2(F_HOLD_I + 3);
    localparam [F_AW-1:0] F_HOLD = F_HOLD_I;
    reg  [F_GL-1:0] f_hist;     // samples before this clock, newest in [0]
    reg  [F_AW-1:0] f_age;      // clocks since the last accepted sample
    wire [F_GL:0]   f_win = {f_hist, line_s};
    wire            f_acc = &f_win[F_GL-1:0];
    always @(posedge clk) begin
        if (rst) begin
            f_hist <= {F_GL{1'b0}};
            f_age  <= F_HOLD + 1'b1;
        end else begin
            f_hist <= f_win[F_GL-1:0];
            if (f_acc)              f_age <= {F_AW{1'b0}};
            else if (f_age <= F_HOLD) f_age <= f_age + 1'b1;
        end
    end

    always @(*) begin
        if (f_ok) begin
            assert(hi_ok == f_acc);
            assert(env == (f_age <= F_HOLD));
            assert(hold == ((f_age < F_HOLD) ? F_HOLD - f_age : {F_AW{1'b0}}));
            assert(f_age <= F_HOLD + 1'b1);
        end
    end

    // the filter's count is the run of high samples it has seen
    localparam integer F_GW = $clog2(F_GL + 1);
    integer f_i;
    reg [F_GW-1:0] f_run;
    always @(*) begin
        f_run = {F_GW{1'b0}};
        for (f_i = 0; f_i < F_GL; f_i = f_i + 1)
            if (f_run == f_i[F_GW-1:0] && f_hist[f_i]) f_run = f_run + 1'b1;
    end
    generate
        if (GL > 1) begin : g_f_filter
            always @(*) begin
                if (f_ok) assert(g_filter.hc == f_run);
            end
        end
    endgenerate

`ifdef TWH_F_DEMOD_CARRIER
    // A peripheral carrier anywhere in the window of NOTES.md (0.90-1.10
    // MHz, duty 30-70 %), as the synchronised line samples it (one clock
    // of margin each way for the synchroniser): a high lasts at least
    // F_HMIN clocks, a low at most F_LMAX once the first high came. The
    // first high after reset may be cut short by the reset.
    localparam integer F_HMIN_R = CLK_HZ / 1_000 * 3 / 11_000 - 1;    // 0.3 / 1.1 MHz
    localparam integer F_HMIN   = (F_HMIN_R < 1) ? 1 : F_HMIN_R;
    localparam integer F_LMAX   = (CLK_HZ / 1_000 * 7 + 8_999) / 9_000 + 1;  // 0.7 / 0.9 MHz
    localparam integer F_HSAT   = (F_HMIN > F_GL) ? F_HMIN : F_GL;
    localparam integer F_RW     = $clog2(F_LMAX + F_HSAT + 2);
    localparam [F_RW-1:0] F_HMIN_V = F_HMIN;
    localparam [F_RW-1:0] F_LMAX_V = F_LMAX;
    localparam [F_RW-1:0] F_HSAT_V = F_HSAT;
    localparam [F_RW-1:0] F_GL_V   = F_GL;

    reg [F_RW-1:0] f_hi, f_lo;  // length of the run of highs / lows just before
    reg            f_on;        // a high came since reset
    reg            f_full;      // the current high run began after reset
    reg            f_env_seen;  // the envelope came up since reset
    always @(posedge clk) begin
        if (rst) begin
            f_hi <= {F_RW{1'b0}};
            f_lo <= {F_RW{1'b0}};
            f_on <= 1'b0;
            f_full <= 1'b0;
            f_env_seen <= 1'b0;
        end else begin
            f_on <= f_on || line_s;
            f_env_seen <= f_env_seen || env;
            if (line_s) begin
                f_lo <= {F_RW{1'b0}};
                if (f_hi != F_HSAT_V) f_hi <= f_hi + 1'b1;
                if (f_lo != {F_RW{1'b0}}) f_full <= 1'b1;
            end else begin
                f_hi <= {F_RW{1'b0}};
                f_full <= 1'b0;
                if (f_lo != F_LMAX_V + 1'b1) f_lo <= f_lo + 1'b1;
            end
        end
    end

    always @(*) begin
        if (f_ok && !line_s) begin
            if (f_on) assume(f_lo < F_LMAX_V);
            if (f_full && f_hi != {F_RW{1'b0}}) assume(f_hi >= F_HMIN_V);
        end
    end

    always @(*) begin
        if (f_ok) begin
            // once up, the envelope stays up for as long as the carrier runs
            if (f_env_seen) assert(env);
            // the time since the last accepted sample is bounded by the
            // run lengths: the state the above rests on
            if (f_env_seen && f_lo != {F_RW{1'b0}}) assert(f_age == f_lo);
            if (f_env_seen && f_hi >= F_GL_V) assert(f_age == {F_AW{1'b0}});
            if (f_env_seen && f_hi != {F_RW{1'b0}} && f_hi < F_GL_V)
                assert(f_full && f_age <= f_hi + F_LMAX_V);
            if (f_on) assert(f_lo <= F_LMAX_V);
            assert(f_hi <= F_HSAT_V && f_lo <= F_LMAX_V + 1'b1);
            // the filter window agrees with the run of highs
            assert(f_run == ((f_hi < F_GL_V) ? f_hi[F_GW-1:0] : F_GL_V[F_GW-1:0]));
            assert(!(f_hi != {F_RW{1'b0}} && f_lo != {F_RW{1'b0}}));
            assert(!f_full || f_hi != {F_RW{1'b0}});
            assert(f_on || f_hi == {F_RW{1'b0}});
            if (f_env_seen) assert(f_on && (f_hi != {F_RW{1'b0}} || f_lo != {F_RW{1'b0}}));
        end
    end
`endif
`endif
endmodule
`default_nettype wire
