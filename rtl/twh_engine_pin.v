// One channel's pin logic beside the time-shared engine (twh_engine): what
// must run at the clock rather than at the engine's once-a-microsecond visit.
//
// Receive: line_i passes twh_sync2 and a glitch filter (a high counts once
// it has lasted GLITCH_NS); `seen` says whether a filtered high came in the
// window since the engine's last visit or in the window before it. A
// peripheral carrier of 0.9-1.1 MHz, 30-70 % duty, gives a filtered high
// at least every 1.5 us (at 4 MHz, sampling and the filter included; less
// at faster clocks: twh_engine_pin:carrier_*), so two windows of a
// carrier period always hold one while it keys the carrier, and a
// baseband high holds `seen` high throughout.
//
// Drive: the engine hands the drive for the next carrier period (nx_oe,
// nx_on) at its visit; every channel takes it at the carrier tick, so a
// channel's line changes only at a period's start and never shows a runt.
// line_o is the shared carrier gated by the channel's own `on`: high from
// the tick, low from the carrier's fall.
`default_nettype none
module twh_engine_pin #(
    parameter integer CLK_HZ    = 48_000_000,
    parameter integer GLITCH_NS = 100
) (
    input  wire clk,
    input  wire rst,
    input  wire tick,       // the carrier's: a period starts
    input  wire fall,       // ... its high half ends
    // the engine's visit
    input  wire visit,      // the engine samples `seen` now; a new window starts
    output wire seen,
    input  wire nx_we,
    input  wire nx_oe,
    input  wire nx_on,
    // the pin
    input  wire line_i,
    output reg  line_o,
    output reg  line_oe
);
    localparam integer CLK_KHZ = CLK_HZ / 1000;
    localparam integer GL_RAW  = CLK_KHZ * GLITCH_NS / 1_000_000;
    localparam integer GL      = (GL_RAW < 1) ? 1 : GL_RAW;
    localparam integer GW      = $clog2(GL + 1);
    localparam integer GL_LAST_I = GL - 1;
    localparam [GW-1:0] GL_LAST = GL_LAST_I[GW-1:0];
    localparam [GW-1:0] GL_SAT  = GL[GW-1:0];

    wire line_s;
    twh_sync2 u_sync (.clk(clk), .rst(rst), .d(line_i), .q(line_s));

    // A high counts once it has lasted GL samples: line_s now and the GL-1
    // before it. Up to five samples (GLITCH_NS at up to 50-60 MHz) they are
    // a shift register ANDed, one LUT; above, a saturating count is the
    // fewer flip-flops.
    wire hi_ok;
    generate
        if (GL == 1) begin : g_nofilter
            assign hi_ok = line_s;
        end else if (GL <= 5) begin : g_shift
            reg  [GL-2:0] hs;   // the GL-1 samples before this one, newest in [0]
            // verilator lint_off UNUSEDSIGNAL
            wire [GL-1:0] hs_n = {hs, line_s};      // (its top bit falls out)
            // verilator lint_on UNUSEDSIGNAL
            always @(posedge clk) begin
                if (rst) hs <= {(GL-1){1'b0}};
                else     hs <= hs_n[GL-2:0];
            end
            assign hi_ok = line_s && (&hs);
        end else begin : g_filter
            reg [GW-1:0] hc;    // consecutive high samples, saturating at GL
            always @(posedge clk) begin
                if (rst || !line_s)    hc <= {GW{1'b0}};
                else if (hc != GL_SAT) hc <= hc + 1'b1;
            end
            assign hi_ok = line_s && (hc >= GL_LAST);
        end
    endgenerate

    reg now_w, prev_w;      // a filtered high in this window, in the one before
    always @(posedge clk) begin
        if (rst) begin
            now_w  <= 1'b0;
            prev_w <= 1'b0;
        end else begin
            now_w <= hi_ok || (now_w && !visit);
            if (visit) prev_w <= now_w;
        end
    end
    assign seen = now_w || prev_w;

    reg oe_n, on_n;         // the drive for the next period
    always @(posedge clk) begin
        if (rst) begin
            oe_n    <= 1'b0;
            on_n    <= 1'b0;
            line_oe <= 1'b0;
            line_o  <= 1'b0;
        end else begin
            if (nx_we) begin
                oe_n <= nx_oe;
                on_n <= nx_on;
            end
            if (tick) begin
                line_oe <= oe_n;
                line_o  <= oe_n && on_n;
            end else if (fall) begin
                line_o  <= 1'b0;
            end
        end
    end

`ifdef FORMAL
    // No assumption on rst: checked from the first reset on (f_ok).
    reg f_ok = 1'b0;
    always @(posedge clk) if (rst) f_ok <= 1'b1;
    reg f_pv = 1'b0;            // a clock has passed: $past is defined
    always @(posedge clk) f_pv <= 1'b1;

    // The filter's reference, as the retired twh_demod's (docs/protocol.md): a sample
    // is accepted when it and the F_GL-1 before it (since reset) are high,
    // F_GL = max(1, floor(CLK_HZ x GLITCH_NS)), with its own constants. The
    // samples are the pin's, two clocks late (the synchroniser), so the
    // reference starts at line_i.
    localparam integer F_GL_RAW = (CLK_HZ / 1_000 * GLITCH_NS
                                   + CLK_HZ % 1_000 * GLITCH_NS / 1_000) / 1_000_000;
    localparam integer F_GL     = (F_GL_RAW < 1) ? 1 : F_GL_RAW;
    reg  [F_GL+1:0] f_d;        // line_i k+1 clocks ago in [k]; 0 before the reset
    wire [F_GL+2:0] f_dw  = {f_d, line_i};
    wire            f_acc = &f_d[F_GL:1];      // line_s and the F_GL-1 before it
    always @(posedge clk) f_d <= rst ? {(F_GL+2){1'b0}} : f_dw[F_GL+1:0];

    // the run of high samples before line_s, at most F_GL (the count's
    // reference)
    localparam integer F_GW = $clog2(F_GL + 1);
    integer f_i;
    reg [F_GW-1:0] f_run;
    always @(*) begin
        f_run = {F_GW{1'b0}};
        for (f_i = 0; f_i < F_GL; f_i = f_i + 1)
            if (f_run == f_i[F_GW-1:0] && f_d[f_i + 2]) f_run = f_run + 1'b1;
    end

    // The window flags' reference: f_x, a filtered high since the last
    // visit, the visit's own clock included (a high in the clock of a
    // visit opens the new window, the `seen` that visit samples does not
    // have it); f_y, one since the visit before it (since the reset while
    // there are fewer visits). A visit or high in a reset clock does not count.
    reg f_x, f_y;
    // f_g1 / f_g2: the pin was high in some clock from two clocks before
    // the last visit / the one before it (the synchroniser's two clocks)
    reg f_g1, f_g2;
    always @(posedge clk) begin
        if (rst) begin
            f_x  <= 1'b0;
            f_y  <= 1'b0;
            f_g1 <= 1'b0;
            f_g2 <= 1'b0;
        end else if (visit) begin
            f_x  <= f_acc;
            f_y  <= f_x || f_acc;
            f_g1 <= f_d[1] || f_d[0] || line_i;
            f_g2 <= f_g1 || line_i;
        end else begin
            f_x  <= f_x || f_acc;
            f_y  <= f_y || f_acc;
            f_g1 <= f_g1 || line_i;
            f_g2 <= f_g2 || line_i;
        end
    end

    // The drive last written (nx_we) before this clock, 0 since reset;
    // a fall since the last tick.
    reg f_dr_oe, f_dr_on, f_fell;
    always @(posedge clk) begin
        if (rst) begin
            f_dr_oe <= 1'b0;
            f_dr_on <= 1'b0;
        end else if (nx_we) begin
            f_dr_oe <= nx_oe;
            f_dr_on <= nx_on;
        end
        f_fell <= !rst && !tick && (fall || f_fell);
    end

    always @(*) begin
        if (f_ok) begin
            // the synchroniser and the filter
            assert(line_s == f_d[1]);
            assert(hi_ok == f_acc);
            // the window flags
            assert(now_w == f_x);
            assert(seen == f_y);
            // so seen is 0 unless the pin was high since two clocks before
            // the older window opened
            assert(!seen || f_g2);
            assert(!f_x || f_g1);
            assert(!(f_d[1] || f_d[0]) || f_g1);
            assert(!f_g1 || f_g2);
            // the drive: the next period's, the line
            assert(oe_n == f_dr_oe && on_n == f_dr_on);
            assert(!line_o || line_oe);
            if (f_fell) assert(!line_o);
        end
    end
    // (Yosys puts the branches after the first `else` in a block of their
    // own, genblk1)
    generate
        if (GL > 1 && GL <= 5) begin : g_f_shift
            always @(*) if (f_ok) assert(genblk1.g_shift.hs == f_d[F_GL:2]);
        end else if (GL > 5) begin : g_f_filter
            always @(*) if (f_ok) assert(genblk1.g_filter.hc == f_run);
        end
    endgenerate

    // The line changes only at a tick, to the drive written before it,
    // or (line_o, to 0) at a fall; a reset drives nothing.
    always @(posedge clk) begin
        if (f_pv) begin
            if ($past(rst)) begin
                assert(!line_oe && !line_o);
            end else if ($past(f_ok)) begin
                if ($past(tick)) begin
                    assert(line_oe == $past(f_dr_oe));
                    assert(line_o == $past(f_dr_oe && f_dr_on));
                end else begin
                    assert(line_oe == $past(line_oe));
                    assert(line_o == ($past(fall) ? 1'b0 : $past(line_o)));
                end
            end
        end
    end

    always @(posedge clk) begin
        if (f_pv && f_ok && $past(f_ok) && !$past(rst)) begin
            cover(seen && !$past(seen));
            cover(line_oe && !$past(line_oe));
            cover(!line_o && $past(line_o) && $past(fall));
        end
    end

`ifdef TWH_F_PIN_CARRIER
    // A peripheral carrier anywhere in the window of NOTES.md (0.90-1.10
    // MHz, duty 30-70 %), as the pin's first flop samples it (one clock of
    // margin each way), the retired twh_demod's model on line_i: a high lasts at least
    // F_HMIN clocks, a low at most F_LMAX once the first high came; the
    // first high after reset may be cut short by the reset.
    localparam integer F_HMIN_R = CLK_HZ / 1_000 * 3 / 11_000 - 1;    // 0.3 / 1.1 MHz
    localparam integer F_HMIN   = (F_HMIN_R < 1) ? 1 : F_HMIN_R;
    localparam integer F_LMAX   = (CLK_HZ / 1_000 * 7 + 8_999) / 9_000 + 1;  // 0.7 / 0.9 MHz
    localparam integer F_HSAT   = (F_HMIN > F_GL) ? F_HMIN : F_GL;
    localparam integer F_RW     = $clog2(F_LMAX + F_HSAT + 2);
    localparam [F_RW-1:0] F_HMIN_V = F_HMIN;
    localparam [F_RW-1:0] F_LMAX_V = F_LMAX;
    localparam [F_RW-1:0] F_HSAT_V = F_HSAT;
    localparam [F_RW-1:0] F_GL_R   = F_GL;
    // And the engine's visits (docs/engine.md, "Pipeline"): channel c is
    // visited c+1 clocks after every tick, so one carrier period apart:
    // P clocks, or P+1 after a stretched period when CLK_HZ is not a
    // whole number of MHz (twh_carrier's P). Assumed: at least P clocks
    // apart (what the property needs of them); the first visit is free.
    localparam integer F_P  = CLK_HZ / 1_000_000;
    // the longest time from a filtered high to the next while the carrier
    // runs: a low of F_LMAX, then F_GL samples of the next high
    localparam integer F_AMAX = F_LMAX + F_GL - 1;
    localparam integer F_CW   = $clog2(2 * F_P + F_AMAX + 4);
    localparam [F_CW-1:0] F_P_V    = F_P;
    localparam [F_CW-1:0] F_AMAX_V = F_AMAX;
    localparam [F_CW-1:0] F_ACAP   = F_AMAX + 1;
    localparam [F_CW-1:0] F_VCAP   = 2 * F_P + F_AMAX + 1;  // past 2P and F_AMAX

    reg [F_RW-1:0] f_hi, f_lo;  // length of the pin's run of highs / lows just before
    reg            f_on;        // a high came since reset
    reg            f_full;      // the current high run began after reset
    always @(posedge clk) begin
        if (rst) begin
            f_hi <= {F_RW{1'b0}};
            f_lo <= {F_RW{1'b0}};
            f_on <= 1'b0;
            f_full <= 1'b0;
        end else begin
            f_on <= f_on || line_i;
            if (line_i) begin
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
        if (f_ok && !rst && !line_i) begin
            if (f_on) assume(f_lo < F_LMAX_V);
            if (f_full && f_hi != {F_RW{1'b0}}) assume(f_hi >= F_HMIN_V);
        end
    end

    // visits: clocks since the last (f_va) and the one before (f_vb),
    // saturating at F_VCAP
    reg [F_CW-1:0] f_va, f_vb;
    reg            f_v1, f_v2;  // one visit, two visits since reset
    always @(posedge clk) begin
        if (rst) begin
            f_v1 <= 1'b0;
            f_v2 <= 1'b0;
            f_va <= {F_CW{1'b0}};
            f_vb <= {F_CW{1'b0}};
        end else if (visit) begin
            f_v1 <= 1'b1;
            f_v2 <= f_v1;
            f_va <= {{(F_CW-1){1'b0}}, 1'b1};
            f_vb <= f_va + (f_va != F_VCAP);
        end else begin
            if (f_va != F_VCAP) f_va <= f_va + 1'b1;
            if (f_vb != F_VCAP) f_vb <= f_vb + 1'b1;
        end
    end
    always @(*) begin
        if (f_ok && !rst && f_v1 && visit) assume(f_va >= F_P_V);
    end

    // Clocks since the last filtered high (0: in the clock before), and
    // the same for the acceptance in the pin's own time (line_i and the
    // F_GL-1 samples before it), which the filter sees two clocks later:
    // f_ag1, f_ag2 are f_ag delayed.
    wire           f_acc_i = &f_dw[F_GL-1:0];
    reg [F_CW-1:0] f_hage, f_ag, f_ag1, f_ag2;
    reg            f_hon, f_aon, f_aon1, f_aon2;  // ... one came since reset
    always @(posedge clk) begin
        if (rst) begin
            f_hon  <= 1'b0;
            f_aon  <= 1'b0;
            f_aon1 <= 1'b0;
            f_aon2 <= 1'b0;
        end else begin
            f_hon  <= f_hon || hi_ok;
            f_aon  <= f_aon || f_acc_i;
            f_aon1 <= f_aon;
            f_aon2 <= f_aon1;
        end
        f_hage <= hi_ok   ? {F_CW{1'b0}} : f_hage + (f_hage != F_ACAP);
        f_ag   <= f_acc_i ? {F_CW{1'b0}} : f_ag + (f_ag != F_ACAP);
        f_ag1  <= f_ag;
        f_ag2  <= f_ag1;
    end
    wire [F_CW-1:0] f_ag2_n = f_ag2 + (f_ag2 != F_ACAP);
    wire [F_CW-1:0] f_ag1_n = f_ag1 + (f_ag1 != F_ACAP);

    // the pin's run of highs as f_d holds it, at most F_GL
    reg [F_GW-1:0] f_run_i;
    always @(*) begin
        f_run_i = {F_GW{1'b0}};
        for (f_i = 0; f_i < F_GL; f_i = f_i + 1)
            if (f_run_i == f_i[F_GW-1:0] && f_d[f_i]) f_run_i = f_run_i + 1'b1;
    end

    always @(*) begin
        if (f_ok) begin
            // Once a filtered high has come, `seen` is 1 at every visit:
            // two windows (at least 2P clocks) always hold one.
            if (visit && !rst && f_hon) assert(seen);
            // the window flags in clocks (f_hage is 0 for a high in the
            // clock before, f_va 1 for a visit then)
            assert(f_x == (f_hon && (!f_v1 || f_hage < f_va)));
            assert(f_y == (f_hon && (!f_v2 || f_hage < f_vb)));
            if (f_hon) assert(f_hage <= F_AMAX_V);
            // the visits' spacing
            assert(f_va <= F_VCAP && f_vb <= F_VCAP);
            if (f_v1) assert(f_va != {F_CW{1'b0}});
            else      assert(!f_v2);
            if (f_v2) assert({1'b0, f_vb} >= (({1'b0, f_va} + F_P_V > {1'b0, F_VCAP})
                                              ? {1'b0, F_VCAP} : {1'b0, f_va} + F_P_V));
            // the filter's acceptance is the pin's, two clocks late
            assert(f_hon == f_aon2);
            if (f_hon) assert(f_hage == f_ag2);
            assert(f_aon1 == (f_aon2 || hi_ok));
            if (f_aon1) assert(f_ag1 == (hi_ok ? {F_CW{1'b0}} : f_ag2_n));
            assert(f_aon == (f_aon1 || (&f_d[F_GL-1:0])));
            if (f_aon) assert(f_ag == ((&f_d[F_GL-1:0]) ? {F_CW{1'b0}} : f_ag1_n));
            // the time since the pin's last acceptance is bounded by the
            // run lengths (the retired twh_demod's invariants, on the pin)
            if (f_aon && f_lo != {F_RW{1'b0}}) assert(f_ag == f_lo);
            if (f_aon && f_hi >= F_GL_R) assert(f_ag == {F_CW{1'b0}});
            if (f_aon && f_hi != {F_RW{1'b0}} && f_hi < F_GL_R)
                assert(f_full && f_ag <= f_hi + F_LMAX_V);
            if (f_on) assert(f_lo <= F_LMAX_V);
            assert(f_hi <= F_HSAT_V && f_lo <= F_LMAX_V + 1'b1);
            assert(f_run_i == ((f_hi < F_GL_R) ? f_hi[F_GW-1:0] : F_GL_R[F_GW-1:0]));
            assert(!(f_hi != {F_RW{1'b0}} && f_lo != {F_RW{1'b0}}));
            assert(!f_full || f_hi != {F_RW{1'b0}});
            assert(f_on || f_hi == {F_RW{1'b0}});
            if (f_aon) assert(f_on && (f_hi != {F_RW{1'b0}} || f_lo != {F_RW{1'b0}}));
        end
    end

    always @(posedge clk) begin
        if (f_ok && !rst) begin
            cover(visit && f_v2 && f_hon && seen);   // two windows behind it
            cover(f_hon && f_hage == F_AMAX_V);     // the longest gap
        end
    end
`endif
`endif
endmodule
`default_nettype wire
