// UART receiver for the peripheral's 3-byte answer, on the demodulated
// envelope, timed by the 1 us carrier tick.
// The reference model of the engine's receiver: it is no part of the core
// (rtl/). Its proof (formal/twh_rx.sby, tasks prove and uart) states the
// receiver's rules here, and task equiv proves the time-shared engine's
// receiver word (rtl/twh_rx_step.v, rtl/twh_rx_dec.v, rtl/twh_rx_sum.v) equal to it. (It was
// the receiver of twh_link, the per-channel engine of ENGINE = 0, retired.)
//
// - The first start bit counts only after at least half a bit (16 us) of
//   mark, so a line that merely wakes up or a lone glitch is not a start.
// - Each bit is the majority of three samples 11, 15 and 19 us after the
//   start edge was seen (the envelope edge lags the real edge by ~1 us, and
//   the spread keeps a glitch-stretched envelope pulse to one vote). The
//   start bit is re-checked this way, so a false start is dropped.
// - One stop bit is checked; the next start is hunted right after it, so a
//   sender with one or two stop bits is accepted. A 0 stop bit ends
//   reception with `frame_err`, except after eight 0 data bits: in on-off
//   keying a sender that stops keying leaves the line at 0, and a whole
//   character of 0s (a break) means the answer ended: reception stops and
//   the answer counts as short, not as a framing error.
// - 30.75-31.75 kbps: after 9.5 bits the sampling drift is at most ~5 us.
// Clearing `en` (outside the listen phase) clears everything.
// Input contract (its proof assumes it; twh_carrier's tick keeps it): `tick_nx`
// says a clock ahead that `tick` comes (twh_carrier's), a tick never comes
// in two clocks running, and at a tick `en` is what it was a clock before,
// or 0 if reset was on then. So whether a tick steps the receiver (`step`:
// a tick, en and not done) is this receiver's own flip-flop, taken a clock
// ahead: the core's one tick, routed to every channel, is off every path
// in here (it was the HX8K's three-channel critical path).
`default_nettype none
module twh_rx (
    input  wire        clk,
    input  wire        rst,
    input  wire        en,
    // verilator lint_off UNUSEDSIGNAL
    input  wire        tick,        // the proofs' (the logic takes step from tick_nx)
    // verilator lint_on UNUSEDSIGNAL
    input  wire        tick_nx,
    input  wire        env,
    output reg  [1:0]  nbytes,      // complete bytes received (0-3)
    output reg  [23:0] bytes,       // received bytes, first in [23:16]
    output reg         started,     // a start bit passed its re-check
    output reg         frame_err
);
    // verilator lint_off UNUSEDSIGNAL
    reg       ended;      // the line went silent (a break) mid-answer (read by the proofs;
                          // the logic needs only `done`)
    // verilator lint_on UNUSEDSIGNAL
    reg       active;     // inside a character
    reg       more;       // a good stop bit was seen: next start needs no mark
    reg [4:0] mark;       // consecutive mark ticks, saturating at 16
    reg       mark_full;  // mark == 16 (a flag that moves with it, off the start's path)
    reg [4:0] sub;        // ticks since the start edge, within the bit
    reg [3:0] bitn;       // 0 start, 1-8 data, 9 stop
    reg [1:0] votes;      // ones among the samples of this bit
    reg [7:0] sh;

    // the answer is complete (three bytes), broken or over: a flag set with
    // its cause, so the enables of everything above start from a flip-flop
    reg  done;
    // Where in the character the receiver stands, kept as flags that move
    // with `sub` and `bitn` (each proven equal to its decode), so that the
    // sample points are flip-flops and not decodes behind the tick: the
    // first two samples of a bit, its last one (the start bit's re-check,
    // a data bit, the stop bit), and the bit's end. All are 0 outside a
    // character.
    reg  at_vote;      // active && sub is 11 or 15
    reg  chk_start;    // active && sub == 19 && bitn == 0
    reg  chk_data;     // active && sub == 19 && bitn is 1-8
    reg  chk_stop;     // active && sub == 19 && bitn == 9
    reg  at_end;       // active && sub == 31
    // the third sample completes the vote
    wire bit_val = (votes + {1'b0, env}) >= 2'd2;

    // Cleared in reset and in the first clock without en (both flip-flops,
    // so the clear is one LUT from them): the state then stays clear, and
    // an idle receiver does no work in simulation.
    reg  en_q;
    wire clr = rst || (en_q && !en);
    // tick && en && !done, taken a clock ahead: done moves only at a tick,
    // en not in the clock before one (the contract)
    reg  step;
    always @(posedge clk) begin
        en_q <= !rst && en;
        step <= !rst && tick_nx && en && !done;
        if (clr) begin
            nbytes    <= 2'd0;
            bytes     <= 24'd0;
            started   <= 1'b0;
            frame_err <= 1'b0;
            ended     <= 1'b0;
            active    <= 1'b0;
            more      <= 1'b0;
            mark      <= 5'd0;
            mark_full <= 1'b0;
            sub       <= 5'd0;
            bitn      <= 4'd0;
            votes     <= 2'd0;
            sh        <= 8'd0;
            done      <= 1'b0;
            at_vote   <= 1'b0;
            chk_start <= 1'b0;
            chk_data  <= 1'b0;
            chk_stop  <= 1'b0;
            at_end    <= 1'b0;
        end else if (step) begin
            if (!env)                mark <= 5'd0;
            else if (!mark_full)     mark <= mark + 1'b1;
            mark_full <= env && (mark_full || mark == 5'd15);

            if (!active) begin
                if (!env && (more || mark_full)) begin
                    active <= 1'b1;
                    sub    <= 5'd1;
                    bitn   <= 4'd0;
                end
            end else begin
                // (a character starts at sub 1 and leaves at sub 19, so
                // the flags are 0 there without a term of their own)
                sub       <= sub + 1'b1;
                at_vote   <= (sub == 5'd10) || (sub == 5'd14);
                chk_start <= (sub == 5'd18) && (bitn == 4'd0);
                chk_data  <= (sub == 5'd18) && (bitn != 4'd0) && (bitn != 4'd9);
                chk_stop  <= (sub == 5'd18) && (bitn == 4'd9);
                at_end    <= (sub == 5'd30);
                if (at_end) bitn <= bitn + 1'b1;
                // cleared once the bit is decided, so they are 0 at the
                // next bit's first sample and outside a character, and
                // the start needs no term of its own here
                if (chk_start || chk_data || chk_stop) votes <= 2'd0;
                if (at_vote) votes <= votes + {1'b0, env};
                if (chk_start) begin
                    if (bit_val) active <= 1'b0;    // false start
                    else         started <= 1'b1;
                end
                if (chk_data) sh <= {bit_val, sh[7:1]};
                if (chk_stop) begin
                    active <= 1'b0;
                    if (bit_val) begin
                        more   <= 1'b1;
                        nbytes <= nbytes + 1'b1;
                        bytes  <= {bytes[15:0], sh};
                        if (nbytes == 2'd2) done <= 1'b1;
                    end else if (sh == 8'd0) begin
                        ended     <= 1'b1;
                        done      <= 1'b1;
                    end else begin
                        frame_err <= 1'b1;
                        done      <= 1'b1;
                    end
                end
            end
        end
    end

`ifdef FORMAL
    // No assumption on rst: checked from the first reset on (f_ok).
    reg f_ok = 1'b0;
    always @(posedge clk) if (rst) f_ok <= 1'b1;
    reg f_past_valid = 1'b0;
    reg f_past_ok = 1'b0;  // the last clock was defined, out of reset, en on
    always @(posedge clk) begin
        f_past_valid <= 1'b1;
        f_past_ok       <= f_ok && !rst && en;
    end
    // the input contract (assumed here: twh_carrier's tick and an en that
    // changes only between ticks)
    always @(posedge clk)
        if (f_ok && f_past_valid && tick)
            assume(!$past(tick) && en == ($past(en) && !$past(rst)));
    always @(posedge clk)
        if (f_ok && f_past_valid) assume(tick == $past(tick_nx && !rst));
    // ... under which the flip-flop is the enable it stands for
    always @(posedge clk)
        if (f_ok && f_past_valid) assert(step == (tick && en && !done));

    // Consecutive mark ticks since en (saturating at 16), and whether 16
    // of them were seen before some tick: what a first start needs.
    reg [4:0] f_mk;
    reg       f_mk16;
    always @(posedge clk) begin
        if (rst || !en) begin
            f_mk   <= 5'd0;
            f_mk16 <= 1'b0;
        end else if (tick) begin
            if (!env)               f_mk <= 5'd0;
            else if (f_mk != 5'd16) f_mk <= f_mk + 1'b1;
            if (f_mk == 5'd16) f_mk16 <= 1'b1;
        end
    end

    always @(posedge clk) begin
        if (f_ok && f_past_valid && $past(rst || !en)) begin
            // clearing en (or reset) clears everything
            assert(nbytes == 2'd0 && bytes == 24'd0 && !started && !frame_err);
        end
        if (f_past_ok) begin
            // nothing moves between ticks, nothing once the answer is done
            if (!$past(tick) || $past(done))
                assert($stable(nbytes) && $stable(bytes) && $stable(started)
                       && $stable(frame_err) && $stable(ended));
            // bytes only add up, one at a time
            assert(nbytes == $past(nbytes) || nbytes == $past(nbytes) + 1'b1);
        end
    end

    always @(*) begin
        if (f_ok) begin
            // a first start only after half a bit of mark
            if (started) assert(f_mk16);
            if (active && !more) assert(f_mk16);
            // every result rests on a start bit that passed its re-check
            if (nbytes != 2'd0 || frame_err || ended || more) assert(started);
            assert(!(frame_err && ended));
            assert(!(more && nbytes == 2'd0));
            // bytes holds exactly the completed characters
            case (nbytes)
                2'd0: assert(bytes == 24'd0);
                2'd1: assert(bytes[23:8] == 16'd0);
                2'd2: assert(bytes[23:16] == 8'd0);
                default: ;
            endcase
            // the counters stay in range
            assert(bitn <= 4'd9);
            // the position flags are the decodes they stand for
            assert(at_vote   == (active && (sub == 5'd11 || sub == 5'd15)));
            assert(chk_start == (active && sub == 5'd19 && bitn == 4'd0));
            assert(chk_data  == (active && sub == 5'd19 && bitn != 4'd0 && bitn != 4'd9));
            assert(chk_stop  == (active && sub == 5'd19 && bitn == 4'd9));
            assert(at_end    == (active && sub == 5'd31));
            if (active) assert(!done);
            assert(done == ((nbytes == 2'd3) || frame_err || ended));
            assert(mark <= 5'd16);
            assert(mark_full == (mark == 5'd16));
            if (!done) assert(mark == f_mk);
            if (active && bitn == 4'd9) assert(sub <= 5'd19);
            if (active && bitn == 4'd0) assert(sub != 5'd0);
            if (active && (bitn != 4'd0 || sub > 5'd19)) assert(started);
            assert(votes <= 2'd2);
            if (!active || sub > 5'd19) assert(votes == 2'd0);
            if (active && sub <= 5'd11) assert(votes == 2'd0);
            if (active && sub <= 5'd15) assert(votes <= 2'd1);
        end
    end

`ifdef TWH_F_RX_UART
    // An ideal sender, on the envelope at exactly 32 ticks a bit (rate
    // error is left to simulation): silence, possibly marks cut short
    // before half a bit (a line waking up), at least 16 ticks of mark, then
    // characters of any value with any idle time (one stop bit or more)
    // between them; it may stop keying instead of starting a character (a
    // break: all zeros). Once the receiver is done the envelope is free.
    // Ticks and en are free but for the input contract; the sender starts
    // over whenever en is low. Its assumptions touch only the env input.
    localparam [2:0] M_SILENT = 3'd0, M_MARK = 3'd1, M_CHAR = 3'd2,
                     M_GAP = 3'd3, M_FREE = 3'd4;
    reg [2:0]  m_st;
    reg [3:0]  m_b;         // bit of the character: 0 start, 1-8 data, 9 stop
    reg [4:0]  m_c;         // ticks into that bit
    reg        m_brk;       // this character is the break
    reg [7:0]  m_byte;
    reg [4:0]  m_mk;        // consecutive mark ticks, saturating at 16
    reg [1:0]  m_n;         // characters whose stop bit has been sampled
    reg        m_started;   // a start bit's re-check point has passed
    reg [23:0] m_exp;       // those characters, as `bytes` must show them
    (* anyseq *) reg       f_go, f_brk;
    (* anyseq *) reg [7:0] f_data;

    reg m_env;
    always @(*) begin
        case (m_st)
            M_MARK, M_GAP: m_env = 1'b1;
            M_CHAR:        m_env = (m_b == 4'd0) ? 1'b0 :
                                   (m_b == 4'd9) ? !m_brk : m_byte[m_b - 4'd1];
            default:       m_env = 1'b0;
        endcase
    end
    always @(*) if (f_ok && m_st != M_FREE) assume(env == m_env);

    wire [4:0] m_mk_next = !m_env ? 5'd0 : (m_mk == 5'd16) ? 5'd16 : m_mk + 1'b1;
    always @(posedge clk) begin
        if (rst || !en) begin
            m_st      <= M_SILENT;
            m_b       <= 4'd0;
            m_c       <= 5'd0;
            m_brk     <= 1'b0;
            m_byte    <= 8'd0;
            m_mk      <= 5'd0;
            m_n       <= 2'd0;
            m_started <= 1'b0;
            m_exp     <= 24'd0;
        end else if (tick) begin
            m_mk <= m_mk_next;
            case (m_st)
                M_SILENT: if (f_go) m_st <= M_MARK;
                M_MARK: begin
                    if (f_go) begin
                        if (m_mk_next == 5'd16) begin
                            m_st   <= M_CHAR;
                            m_b    <= 4'd0;
                            m_c    <= 5'd0;
                            m_brk  <= f_brk;
                            m_byte <= f_brk ? 8'd0 : f_data;
                        end else begin
                            m_st <= M_SILENT;
                        end
                    end
                end
                M_CHAR: begin
                    m_c <= m_c + 1'b1;
                    if (m_c == 5'd31) m_b <= m_b + 1'b1;
                    if (m_b == 4'd0 && m_c == 5'd19) m_started <= 1'b1;
                    if (m_b == 4'd9 && m_c == 5'd19) begin
                        if (m_brk) begin
                            m_st <= M_FREE;
                        end else begin
                            m_n   <= m_n + 1'b1;
                            m_exp <= {m_exp[15:0], m_byte};
                            if (m_n == 2'd2) m_st <= M_FREE;
                        end
                    end
                    if (m_b == 4'd9 && m_c == 5'd31) begin
                        m_b <= 4'd0;
                        if (f_go) begin
                            m_brk  <= f_brk;
                            m_byte <= f_brk ? 8'd0 : f_data;
                        end else begin
                            m_st <= M_GAP;
                        end
                    end
                end
                M_GAP: begin
                    if (f_go) begin
                        m_st   <= M_CHAR;
                        m_b    <= 4'd0;
                        m_c    <= 5'd0;
                        m_brk  <= f_brk;
                        m_byte <= f_brk ? 8'd0 : f_data;
                    end
                end
                default: ;
            endcase
        end
    end

    // data bits of the current character already shifted into sh
    reg [3:0] m_k;
    always @(*) begin
        if (m_b == 4'd0)      m_k = 4'd0;
        else if (m_b == 4'd9) m_k = 4'd8;
        else                  m_k = m_b - 4'd1 + {3'd0, m_c > 5'd19};
    end

    always @(*) begin
        if (f_ok) begin
            // every character arrives, unchanged and in order, on the tick
            // its stop bit is sampled; no framing error, no false start
            assert(nbytes == m_n);
            assert(bytes == m_exp);
            assert(!frame_err);
            assert(started == m_started);
            // the break ends reception as a short answer, and only it does
            assert(ended == (m_st == M_FREE && m_brk));
            if (m_st == M_FREE) assert(done);
            else                assert(!done);

            // the receiver's state follows the sender's position
            assert(m_st <= M_FREE && m_b <= 4'd9);
            assert(more == (m_n != 2'd0));
            if (!done) assert(mark == m_mk);
            if (m_st == M_SILENT || m_st == M_MARK)
                assert(!active && m_n == 2'd0 && !m_started && m_b == 4'd0 && m_c == 5'd0);
            if (m_st == M_SILENT) assert(m_mk != 5'd16);
            if (m_st != M_FREE) assert(m_n != 2'd3);
            if (m_st == M_GAP) assert(!active && m_n != 2'd0 && m_b == 4'd0 && m_c == 5'd0);
            if (m_st == M_CHAR) begin
                if (m_b == 4'd0 && m_c == 5'd0) begin
                    assert(!active);
                    if (m_n == 2'd0) assert(m_mk == 5'd16);
                end else if (m_b != 4'd9 || m_c <= 5'd19) begin
                    assert(active && bitn == m_b && sub == m_c);
                    assert(votes == ((m_env && m_c <= 5'd19) ? {1'b0, m_c > 5'd11} + {1'b0, m_c > 5'd15}
                                                       : 2'd0));
                end else begin
                    assert(!active && !m_brk && m_n != 2'd0);
                end
                assert((sh >> (4'd8 - m_k)) == (m_byte & ~(8'hFF << m_k)));
                if (m_brk) assert(m_byte == 8'd0);
                if (m_b != 4'd0 || m_c > 5'd19) assert(m_started);
            end
        end
    end

    // the sender model gets going: a start bit accepted after the mark
    always @(*) if (f_ok) cover(started && !done);
`endif

`ifdef TWH_F_RX_EQUIV
`include "twh_defs.vh"
    // The time-shared engine's receiver against this one (task equiv): its
    // word (twh_defs.vh, TWH_RX_*) stepped by twh_rx_step, with
    // twh_rx_dec's decodes of it, on every tick with en (the engine steps
    // it at each of its channel's visits in listen; twh_engine's proof
    // shows the decodes it takes a clock ahead are the word's), cleared
    // where this receiver clears, on the same envelope. Its word is
    // proven to hold this receiver's state field for field, and its
    // verdict (status, data) to be the one below from this receiver's
    // outputs, so every property above, and task uart's, holds of it.
    reg  [`TWH_RX_W-1:0] e_w;
    wire [`TWH_RX_W-1:0] e_n;
    wire [8:0] e_dec;
    wire [3:0] e_status;
    wire       e_sum;
    twh_rx_sum  e_c (.rx(e_w), .ok(e_sum));
    twh_rx_dec  e_d (.rx(e_w), .sync_low(1'b1), .pre_high(1'b1), .sum_ok(e_sum),
                     .dec(e_dec), .status(e_status));
    wire       e_ok = (e_status == `TWH_ST_OK) || (e_status == `TWH_ST_BAD_CHECKSUM);
    twh_rx_step e_s (.rx(e_w), .dec(e_dec), .env(env), .rx_n(e_n));
    // data bits shifted in since the clear (the engine keeps all 24 in one
    // shift register, the first at the bottom once three have come)
    reg  [4:0] f_n;
    always @(posedge clk) begin
        if (clr) begin
            e_w <= {`TWH_RX_W{1'b0}};
            f_n <= 5'd0;
        end else if (tick && en) begin
            e_w <= e_n;
            if (step && chk_data) f_n <= f_n + 5'd1;
        end
    end
    wire [23:0] e_sh = e_w[`TWH_RX_SH +: 24];
    // the data bits of the character under way
    wire [3:0] f_j = active ? ((bitn == 4'd0) ? 4'd0 : (bitn == 4'd9) ? 4'd8 :
                               bitn - 4'd1 + {3'd0, sub > 5'd19})
                            : ((frame_err || ended) ? 4'd8 : 4'd0);
    // the answer's verdict from this receiver's outputs (line not stuck), as
    // the retired twh_link gave it
    reg [3:0] f_status;
    always @(*) begin
        if (frame_err)            f_status = `TWH_ST_FRAMING;
        else if (nbytes == 2'd3)  f_status = (~(bytes[23:16] + bytes[15:8]) == bytes[7:0])
                                             ? `TWH_ST_OK : `TWH_ST_BAD_CHECKSUM;
        else if (started)         f_status = `TWH_ST_SHORT_RESPONSE;
        else                      f_status = `TWH_ST_NO_RESPONSE;
    end
    integer k;
    always @(*) begin
        if (f_ok) begin
            // the verdict and the data the engine hands over
            assert(e_status == f_status);
            if (e_ok) assert({e_sh[7:0], e_sh[15:8]} == bytes[23:8]);
            assert(e_dec[0] == done);
            // field for field
            assert(e_w[`TWH_RX_NB +: 2] == nbytes);
            assert(e_w[`TWH_RX_FE] == frame_err);
            assert(e_w[`TWH_RX_EN] == ended);
            assert(e_w[`TWH_RX_AC] == active);
            assert(e_w[`TWH_RX_SB +: 5] == sub);
            assert(e_w[`TWH_RX_BN +: 4] == bitn);
            assert(e_w[`TWH_RX_VT +: 2] == votes);
            assert(e_w[`TWH_RX_MK +: 5] == mark);
            assert(more == (nbytes != 2'd0));
            // the shift register: the last eight data bits are this
            // receiver's sh, each completed character k sits at
            // 24 - f_n + 8k, and nothing lies below the first bit
            assert(f_n == {nbytes, 3'd0} + {1'b0, f_j});
            assert(f_n <= 5'd24);
            assert(e_sh[23:16] == sh);
            if (f_n < 5'd24) assert((e_sh & ((24'd1 << (5'd24 - f_n)) - 24'd1)) == 24'd0);
            for (k = 0; k < 3; k = k + 1)
                if (k < nbytes)
                    assert(((e_sh >> (5'd24 - f_n + 5'd8 * k[4:0])) & 24'hFF) ==
                           ((bytes >> (5'd8 * (nbytes - 2'd1 - k[1:0]))) & 24'hFF));
        end
    end
`endif
`endif
endmodule
`default_nettype wire
