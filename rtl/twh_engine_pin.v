// One channel's pin logic beside the time-shared engine (twh_engine): what
// must run at the clock rather than at the engine's once-a-microsecond visit.
//
// Receive: line_i passes twh_sync2 and a glitch filter (a high counts once
// it has lasted GLITCH_NS); `seen` says whether a filtered high came in the
// window since the engine's last visit or in the window before it. A
// peripheral carrier of 0.9-1.1 MHz gives a filtered high at least every
// 1.11 us, so two 1 us windows always hold one while it keys the carrier,
// and a baseband high holds `seen` high throughout.
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
endmodule
`default_nettype wire
