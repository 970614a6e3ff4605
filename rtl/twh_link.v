// One 2-wire channel: six-phase sequencer, on-off-keyed UART both
// ways. A command goes in on a valid/ready stream; exactly one result comes
// out for it (unless reset intervenes). A command marked with a non-zero
// s_cmd_skip (blocked or cancelled upstream) is answered at once with that
// status and never reaches the line, so its result keeps its place in order.
//
// Phases: idle, charge, sync, preamble, command, execute, listen, turnaround
// (codes in twh_defs.vh). The programmable lengths (microseconds, already
// clamped into the spec window unless the lab unlock is on) come from
// twh_timing, shared by all channels: the engine names on nx_fld the field
// its next programmable phase will load, and takes a length (dur_we) only
// with that field's name (dur_fld_in). A phase whose length has not come
// yet waits for it a tick at a time; at the fetch's pace that can only
// happen to a lab-short phase of a few clocks. Zero is read as one.
// The command phase is not programmable: it lasts exactly its 33 or 44
// bits; the idle after a turnaround lasts one tick.
//
// Everything steps on the carrier tick (tick and fall come from the core's
// one twh_carrier), so every phase is a whole number of carrier periods,
// bursts always start with a full high half and the line never shows a
// runt pulse. Line drive per phase:
//   charge, preamble, execute  carrier
//   sync, turnaround           driven low
//   command                    carrier for 1 bits, driven low for 0 bits
//   listen                     released (line_oe = 0)
//   idle                       released, or carrier if cfg_idle_charge
// After reset the engine keeps the line released for the minimum turnaround
// before its first charge and before any idle charge, so a reset during a
// listen cannot shorten the turnaround the peripheral sees.
`default_nettype none
`include "twh_defs.vh"
module twh_link #(
    parameter integer CLK_HZ    = 48_000_000,
    parameter integer TAG_W     = 8,
    parameter integer GLITCH_NS = 100
) (
    input  wire             clk,
    input  wire             rst,
    // the carrier's timebase, from the core's one twh_carrier (every
    // channel's carrier and microsecond run in step)
    input  wire             tick,           // a carrier period starts
    input  wire             tick_nx,        // ... in the next clock (unless reset)
    input  wire             fall,           // ... its high half ends
    // phase lengths (microseconds) from twh_timing
    output wire [2:0]       nx_fld,         // 1 charge .. 6 turnaround: needed next
    input  wire             dur_we,
    input  wire [15:0]      dur_in,
    input  wire [2:0]       dur_fld_in,
    input  wire             cfg_idle_charge,
    // command stream
    input  wire             s_cmd_valid,
    output wire             s_cmd_ready,
    input  wire [7:0]       s_cmd_code,
    input  wire [15:0]      s_cmd_payload,
    input  wire [TAG_W-1:0] s_cmd_tag,
    input  wire [3:0]       s_cmd_skip,    // non-zero: do not send, result status = this
    // result stream
    output reg              m_res_valid,
    input  wire             m_res_ready,
    output wire [7:0]       m_res_code,     // the command's own registers: held
    output reg  [15:0]      m_res_data,
    output reg  [3:0]       m_res_status,
    output wire [TAG_W-1:0] m_res_tag,      // until the result is taken
    // the 2-wire pin
    output reg              line_o,
    output reg              line_oe,
    input  wire             line_i,
    // status
    output wire [2:0]       phase,
    output wire             busy
);

    // ------------------------------------------------------------ receive path
    wire line_s, env;
    twh_sync2 u_sync (.clk(clk), .rst(rst), .d(line_i), .q(line_s));
    twh_demod #(.CLK_HZ(CLK_HZ), .GLITCH_NS(GLITCH_NS)) u_demod (
        .clk(clk), .rst(rst), .line_s(line_s), .env(env)
    );

    reg  [2:0]  ph;
    // ph one-hot, a register of its own that moves with ph: the phase tests
    // and the next-length pick read its bits, with none of ph's fanout and
    // no decode in front of them (ECP5's critical path started at ph)
    reg  [7:0]  ph_oh;
    wire [1:0]  rx_n;
    wire [23:0] rx_bytes;
    wire        rx_started, rx_frame_err;
    // The receiver runs while the phase is listen, one clock late: its
    // enable is a flip-flop (it resets the whole receiver), and the first
    // carrier tick of the phase is a whole period away.
    reg rx_en;
    always @(posedge clk) rx_en <= !rst && ph_oh[`TWH_PH_LISTEN];
    twh_rx u_rx (
        .clk(clk), .rst(rst), .en(rx_en), .tick(tick), .tick_nx(tick_nx), .env(env),
        .nbytes(rx_n), .bytes(rx_bytes), .started(rx_started),
        .frame_err(rx_frame_err)
    );

    // The expected checksum is taken from the first two bytes while the
    // third is still on its way (bytes shift in at the bottom, so with two
    // in they are rx_bytes[15:0]), and compared when it is in; the verdict
    // is registered: the last byte is complete at its stop bit's middle, a
    // carrier period or more before the listen phase can end. Neither the
    // adders nor the comparator sit on the path into the verdict.
    wire [7:0] rx_chk;
    twh_checksum u_rx_chk (
        .a(rx_bytes[15:8]), .b(rx_bytes[7:0]), .c(8'd0), .chk(rx_chk)
    );
    reg [7:0] rx_exp;
    always @(posedge clk) if (rx_n == 2'd2) rx_exp <= rx_chk;
    reg rx_chk_ok;
    always @(posedge clk) rx_chk_ok <= (rx_exp == rx_bytes[7:0]);

    // ------------------------------------------------------------ command
    reg              pending;
    reg [7:0]        cmd_r;
    reg [TAG_W-1:0]  tag_r;
    reg [15:0]       pay_r;
    reg [7:0]        chk_r;      // tx_chk a clock later (see below)
    reg [3:0]        bitn;       // 0 start, 1-8 data, 9-10 stop
    reg [1:0]        byten;      // frame byte on the line

    // 0x80-0xFF: 4-byte frame {code, payload hi, payload lo, checksum};
    // otherwise 3 bytes {code, payload lo, checksum}
    wire long_cmd = cmd_r[7];
    // The checksum over two clocks, one adder each (the code and the low
    // payload byte first, then the high one and the complement), so no
    // adder chain sits on one clock's path. The command stays put from its
    // accept to its result, and the charge starts only with a command
    // pending in the clock before its tick (adv), two clocks after the
    // accept at the least, so chk_r is current for the whole transaction.
    reg  [7:0] tx_psum;
    wire [7:0] tx_chk;
    // (the three stages run from an accept to the end of the transaction:
    // the only time the frame is sent or the command can change)
    wire       tx_run = pending || !ph_oh[`TWH_PH_IDLE];
    always @(posedge clk) if (tx_run) tx_psum <= cmd_r + pay_r[7:0];
    twh_checksum u_tx_chk (
        .a(tx_psum), .b(pay_r[15:8]), .c(8'd0), .chk(tx_chk)
    );
    always @(posedge clk) if (tx_run) chk_r <= tx_chk;
    reg [7:0] tx_byte;
    always @(*) begin
        case (byten)
            2'd0:    tx_byte = cmd_r;
            2'd1:    tx_byte = long_cmd ? pay_r[15:8] : pay_r[7:0];
            2'd2:    tx_byte = long_cmd ? pay_r[7:0]  : chk_r;
            default: tx_byte = chk_r;
        endcase
    end
    // The byte on the line, registered: it changes only with byten, at the
    // start of a character, when the line shows the start bit whatever the
    // byte is; a clock later, long before its first data bit, it is current.
    reg [7:0] tx_byte_q;
    always @(posedge clk) if (tx_run) tx_byte_q <= tx_byte;

    // Registered, so the caller's arbitration does not start from the
    // sequencer's state: it lags the true condition by a clock and is never
    // high when that is low (only an accept sets pending or, for a skipped
    // command, m_res_valid while idle, and only pending leaves idle).
    reg rdy;
    assign s_cmd_ready = rdy;
    wire accept = s_cmd_valid && rdy;

    // ------------------------------------------------------------ sequencer
    reg [15:0] cnt;        // periods left in this phase, this one included; a
                           // length of 0 (possible only under the lab unlock)
                           // loads as 0 and counts as 1: `last` is cnt <= 1
    reg [15:0] dur_next;   // length of the phase after this one
    reg        saw_low;    // the line read low during sync
    reg        saw_high;   // the line read high during preamble

    // The next phase's length arrives from twh_timing, fetched and clamped
    // there while the phase before it runs; dur_next holds it.
    // The field the next programmable phase loads (twh_timing's codes:
    // 1 charge, 2 sync, 3 preamble, 4 execute, 5 listen, 6 turnaround). The
    // command phase and the idle after a turnaround have fixed lengths, so
    // preamble already names execute and turnaround names charge.
    // A register that moves with ph_oh, taken from the one-hot value ph_oh
    // is about to hold, so twh_timing's fetch address starts from flip-flops
    // (the UP5K's critical path ran from ph_oh through this decode into the
    // fetch).
    function [2:0] fld_next;
        input [7:0] oh;
        begin
            fld_next[0] = oh[`TWH_PH_IDLE] | oh[`TWH_PH_SYNC] | oh[`TWH_PH_EXECUTE] |
                          oh[`TWH_PH_TURNAROUND];
            fld_next[1] = oh[`TWH_PH_CHARGE] | oh[`TWH_PH_SYNC] | oh[`TWH_PH_LISTEN];
            fld_next[2] = oh[`TWH_PH_PREAMBLE] | oh[`TWH_PH_COMMAND] |
                          oh[`TWH_PH_EXECUTE] | oh[`TWH_PH_LISTEN];
        end
    endfunction
    reg [2:0] nx_fld_r;
    assign nx_fld = nx_fld_r;
    wire [7:0] ph_oh_nx = {ph_oh[6:0], ph_oh[7]};   // the phase after this one
    reg [2:0] dur_fld;      // the field dur_next holds (0: none yet)
    always @(posedge clk) begin
        if (rst) begin
            dur_fld <= 3'd0;
        end else if (dur_we) begin
            dur_next <= dur_in;
            dur_fld  <= dur_fld_in;
        end
    end
    // the fixed lengths: the command's 44 or 33 bits of 32 us, one tick of
    // idle after a turnaround
    wire        fixed_len = ph_oh[`TWH_PH_PREAMBLE] || ph_oh[`TWH_PH_TURNAROUND];
    wire [15:0] fixed_cnt = ph_oh[`TWH_PH_TURNAROUND] ? 16'd1 : cmd_r[7] ? 16'd1408 : 16'd1056;

    // cnt moves only on a carrier tick and ticks are a period (at least 4
    // clocks) apart, so its decodes are registered: at every tick they are
    // those of the count as it stands, and the 16-bit compare is off the
    // path into the phase, bit and frame registers.
    // They are taken over the two clocks after a tick (tick_d, tick_d2),
    // the first after which cnt, the phase or the bit may have changed: the
    // count's halves are compared in the first (c_hz, c_lo1, c_lo01), the
    // flags made of those in the second, so no compare of all 16 bits sits
    // in one clock (ECP5's three-channel path). They are read at the next
    // tick and in the clock before it (adv, dec), at least two clocks on.
    reg tick_d, tick_d2;
    reg c_hz, c_lo1, c_lo01, c_cmd, c_b10;   // cnt[15:5] == 0, cnt[4:0] == 1,
                                             // cnt[4:1] == 0, command, bitn == 10
    reg last;          // cnt <= 1: this period is the phase's last
    reg bit_end;       // a command bit's last period, not the phase's
    reg byte_end;      // bit_end of a character's last (second stop) bit
    always @(posedge clk) begin
        if (rst || tick_d) begin
            c_hz   <= (cnt[15:5] == 11'd0);
            c_lo1  <= (cnt[4:0] == 5'd1);
            c_lo01 <= (cnt[4:1] == 4'd0);
            c_cmd  <= ph_oh[`TWH_PH_COMMAND];
            c_b10  <= (bitn == 4'd10);
        end
        if (rst || tick_d2) begin
            last     <= !rst && c_hz && c_lo01;
            bit_end  <= !rst && c_cmd && c_lo1 && !c_hz;
            byte_end <= !rst && c_b10;
        end
    end

    // result of the listen phase, decided on its last tick
    reg [3:0] rx_status;
    always @(*) begin
        if (!saw_low)                  rx_status = `TWH_ST_LINE_STUCK_HIGH;
        else if (!saw_high)            rx_status = `TWH_ST_LINE_STUCK_LOW;
        else if (rx_frame_err)         rx_status = `TWH_ST_FRAMING;
        else if (rx_n == 2'd3)         rx_status = rx_chk_ok ?                 `TWH_ST_OK
                                                                            : `TWH_ST_BAD_CHECKSUM;
        else if (rx_started)           rx_status = `TWH_ST_SHORT_RESPONSE;
        else                           rx_status = `TWH_ST_NO_RESPONSE;
    end
    wire rx_data_ok = (rx_status == `TWH_ST_OK) || (rx_status == `TWH_ST_BAD_CHECKSUM);
    // registered: the verdict's inputs settle within three clocks of a tick
    // (rx_chk_ok is a register of the receiver's bytes), and a tick is at
    // least four clocks from the next, so at the listen phase's last tick
    // these are the verdict as it stands; the priority chain above is then
    // off the path into the result registers (ECP5's critical path)
    reg [3:0] rx_status_q;
    reg       rx_data_ok_q;
    // (taken through the listen phase only: its last tick is where they
    // are read)
    always @(posedge clk) if (ph_oh[`TWH_PH_LISTEN]) begin
        rx_status_q  <= rx_status;
        rx_data_ok_q <= rx_data_ok;
    end
    // The sequencer's moves at a tick, each a flip-flop taken a clock ahead
    // from tick_nx (the phase, `last` and the length's field do not change
    // in the clock before a tick, and "the length is here" at the tick is
    // the compare taken there, dok_nx), so the phase, count and result
    // registers load on one flip-flop rather than behind the tick's decode
    // (ECP5's three-channel critical path): adv, the phase ends (from idle:
    // a command pending in the clock before, so a clock old at the tick,
    // starts); dec, the count steps down; lis_end, the listen ends and its
    // result loads.
    wire dok_nx = (dur_we ? dur_fld_in : dur_fld) == nx_fld;
    reg lis_end, adv, dec;
    // (loaded in the clock before a tick and cleared in the tick's; held
    // at 0 otherwise: Icarus then has nothing to do in the clocks between)
    always @(posedge clk) if (rst || tick_nx || tick) begin
        lis_end <= !rst && tick_nx && ph_oh[`TWH_PH_LISTEN] && last && dok_nx;
        adv     <= !rst && tick_nx && last &&
                   (ph_oh[`TWH_PH_IDLE] ? pending && dok_nx
                                        : ph_oh[`TWH_PH_PREAMBLE] || ph_oh[`TWH_PH_TURNAROUND] || dok_nx);
        dec     <= !rst && tick_nx && !last;
    end

    always @(posedge clk) begin
        if (rst) begin
            rdy         <= 1'b0;
            ph          <= `TWH_PH_IDLE;
            ph_oh       <= 8'd1 << `TWH_PH_IDLE;
            nx_fld_r    <= fld_next(8'd1 << `TWH_PH_IDLE);
            // one more: the first tick after reset already counts, and the
            // line must rest at least the full minimum turnaround
            cnt         <= `TWH_TURNAROUND_MIN + 16'd1;
            pending     <= 1'b0;
            cmd_r       <= 8'd0;
            tag_r       <= {TAG_W{1'b0}};
            pay_r       <= 16'd0;
            bitn        <= 4'd0;
            byten       <= 2'd0;
            saw_low     <= 1'b0;
            saw_high    <= 1'b0;
            m_res_valid <= 1'b0;
            m_res_data  <= 16'd0;
            m_res_status<= 4'd0;
        end else begin
            if (m_res_valid && m_res_ready) m_res_valid <= 1'b0;
            rdy <= ph_oh[`TWH_PH_IDLE] && !pending && !m_res_valid && !accept;

            // The command is taken whole on every accept (the registers'
            // enables wait for nothing else); a skipped one is answered at
            // once and never touches the line. The result's status and data
            // are loaded on every accept too (they are not valid until a
            // result is, and a sent command's are loaded again when its
            // listen phase ends), so only valid and pending wait for the
            // skip decode.
            if (accept) begin
                cmd_r <= s_cmd_code;
                tag_r <= s_cmd_tag;
                // a 3-byte command's unused payload byte is kept as zero,
                // so the checksum adds both bytes with no choice in front
                pay_r <= {s_cmd_code[7] ? s_cmd_payload[15:8] : 8'd0, s_cmd_payload[7:0]};
                m_res_status <= s_cmd_skip;
                m_res_data   <= 16'd0;
                if (s_cmd_skip != 4'd0) begin
                    m_res_valid  <= 1'b1;
                end else begin
                    pending <= 1'b1;
                end
            end

            if (lis_end) begin
                m_res_valid  <= 1'b1;
                m_res_status <= rx_status_q;
                m_res_data   <= rx_data_ok_q ? rx_bytes[23:8] : 16'd0;
            end

            // a new UART bit starts every 32 periods of the command; bit_end
            // is never set in a phase's last period, nor outside the command
            if (tick && bit_end) begin
                if (byte_end) begin
                    bitn  <= 4'd0;
                    byten <= byten + 1'b1;
                end else begin
                    bitn  <= bitn + 1'b1;
                end
            end

            if (tick) begin
                if (ph_oh[`TWH_PH_SYNC] && !env)     saw_low  <= 1'b1;
                if (ph_oh[`TWH_PH_PREAMBLE] && env)  saw_high <= 1'b1;
            end
            // (in idle the count runs the post-reset hold-off)
            if (dec) cnt <= cnt - 1'b1;
            if (adv) begin
                ph       <= ph + 1'b1;      // phases run in code order, idle's code 0 after turnaround's 7
                ph_oh    <= ph_oh_nx;
                nx_fld_r <= fld_next(ph_oh_nx);
                cnt      <= fixed_len ? fixed_cnt : dur_next;
                if (ph_oh[`TWH_PH_IDLE]) begin
                    pending  <= 1'b0;
                    saw_low  <= 1'b0;
                    saw_high <= 1'b0;
                end
                if (ph_oh[`TWH_PH_PREAMBLE]) begin
                    bitn  <= 4'd0;
                    byten <= 2'd0;
                end
            end
        end
    end

    // ------------------------------------------------------------ line drive
    // The line follows the sequencer one clock later; every burst and gap
    // keeps its exact length.
    wire [9:0] tx_char  = {1'b1, tx_byte_q, 1'b0};     // start, 8 data LSB first, stop
    wire       tx_level = (bitn >= 4'd9) ? 1'b1 : tx_char[bitn];
    // idle: the idle charge or nothing; charge, preamble, execute: the
    // carrier; command: the carrier keyed by the bit; sync, turnaround:
    // driven low; listen: released. An AND-OR of ph_oh's bits, so the
    // phase adds no decode in front of the pin (ECP5's critical path).
    // The idle charge waits for the end of the post-reset hold-off (idle
    // with its count not yet at its last period): a reset may have cut a
    // listen short, and the peripheral gets its full turnaround even when
    // software sets IDLE_CHARGE again at once.
    wire idle_chg   = cfg_idle_charge && last;
    wire drive      = !ph_oh[`TWH_PH_LISTEN] && (!ph_oh[`TWH_PH_IDLE] || idle_chg);
    wire carrier_on = (ph_oh[`TWH_PH_IDLE] && idle_chg)
                    || ph_oh[`TWH_PH_CHARGE] || ph_oh[`TWH_PH_PREAMBLE] || ph_oh[`TWH_PH_EXECUTE]
                    || (ph_oh[`TWH_PH_COMMAND] && tx_level);

    reg fall_d;
    always @(posedge clk) begin
        if (rst) begin
            tick_d  <= 1'b0;
            tick_d2 <= 1'b0;
            fall_d  <= 1'b0;
            line_o  <= 1'b0;
            line_oe <= 1'b0;
        end else begin
            tick_d <= tick;
            if (tick_d || tick_d2) tick_d2 <= tick_d;
            fall_d <= fall;
            if (tick_d) begin
                line_oe <= drive;
                line_o  <= carrier_on;
            end else if (fall_d) begin
                line_o  <= 1'b0;
            end
        end
    end

    // No command is accepted while a result waits (rdy), so the command's
    // registers are the result's.
    assign m_res_code = cmd_r;
    assign m_res_tag  = tag_r;

    assign phase = ph;
    assign busy  = !ph_oh[`TWH_PH_IDLE] || pending;

`ifdef FORMAL
    // ================================================================ formal
    // The engine on its own (formal/twh_link.sby). Every input, rst and the
    // line included, is free but for the carrier's tick and fall, which are
    // those of a twh_carrier on the same clock and reset (the core's one
    // generator, below), and the phase lengths, which arrive as twh_timing
    // hands them to one channel (its proof, formal/twh_timing.sby): every
    // clock, the field named two clocks before, with a length inside that
    // field's spec window unless the lab unlock was on (f_unl_in, free).
    // Everything holds from the first reset on (f_ok). Durations are counted
    // in carrier ticks; that a tick is one microsecond is twh_carrier's own
    // proof. The checks at the
    // pin and at clock level need whole carrier periods inside the induction
    // window, so they are compiled in only with TWH_F_LINK_PINS (4 MHz job).
    reg f_ok = 1'b0;
    always @(posedge clk) if (rst) f_ok <= 1'b1;
    wire f_tick, f_tick_nx, f_fall;
    twh_carrier #(.CLK_HZ(CLK_HZ)) f_timebase (.clk(clk), .rst(rst), .tick(f_tick),
                                               .tick_nx(f_tick_nx), .fall(f_fall));
    always @(*) assume(tick == f_tick && tick_nx == f_tick_nx && fall == f_fall);

    // The conditions the sequencer takes a clock before a tick, as they
    // stand at the tick: pend_q, pending a clock ago too (a command starts
    // only a clock after it was accepted, so the checksum stages are
    // current); dur_ok, dur_next holds the field needed (taken from dur_fld
    // as it will be; nx_fld changes only in a tick's clock, after which this
    // reads 0 for a clock).
    reg pend_q, dur_ok;
    always @(posedge clk) begin
        pend_q <= !rst && pending;
        dur_ok <= !rst && !tick && ((dur_we ? dur_fld_in : dur_fld) == nx_fld);
    end
    // the previous clock ran after a reset and was no reset itself: $past
    // and the stream rules apply
    reg f_run = 1'b0;
    always @(posedge clk) f_run <= f_ok && !rst;
    // two clocks of history: the fetch pipeline's inputs are known
    reg [1:0] f_hist = 2'b00;
    always @(posedge clk) f_hist <= {f_hist[0], 1'b1};

    // the spec windows of the phases (section 4 table), written out here
    // rather than taken from twh_defs.vh, so that a wrong constant there
    // shows
    function f_in_window;
        input [2:0]  p;
        input [15:0] d;
        begin
            case (p)
                `TWH_PH_CHARGE:     f_in_window = d >= 16'd7000;
                `TWH_PH_SYNC:       f_in_window = d >= 16'd900 && d <= 16'd1100;
                `TWH_PH_PREAMBLE:   f_in_window = d >= 16'd1800 && d <= 16'd2200;
                `TWH_PH_EXECUTE:    f_in_window = d >= 16'd3500 && d <= 16'd10000;
                `TWH_PH_LISTEN:     f_in_window = d >= 16'd2000;
                `TWH_PH_TURNAROUND: f_in_window = d >= 16'd2000;
                default:            f_in_window = 1'b1;
            endcase
        end
    endfunction
    // twh_timing's field of a programmable phase (0: a fixed length)
    function [2:0] f_fld_of;
        input [2:0] p;
        case (p)
            `TWH_PH_CHARGE:     f_fld_of = 3'd1;
            `TWH_PH_SYNC:       f_fld_of = 3'd2;
            `TWH_PH_PREAMBLE:   f_fld_of = 3'd3;
            `TWH_PH_EXECUTE:    f_fld_of = 3'd4;
            `TWH_PH_LISTEN:     f_fld_of = 3'd5;
            `TWH_PH_TURNAROUND: f_fld_of = 3'd6;
            default:            f_fld_of = 3'd0;
        endcase
    endfunction
    // and the phase of a field
    function [2:0] f_ph_of;
        input [2:0] f;
        case (f)
            3'd1:    f_ph_of = `TWH_PH_CHARGE;
            3'd2:    f_ph_of = `TWH_PH_SYNC;
            3'd3:    f_ph_of = `TWH_PH_PREAMBLE;
            3'd4:    f_ph_of = `TWH_PH_EXECUTE;
            3'd5:    f_ph_of = `TWH_PH_LISTEN;
            default: f_ph_of = `TWH_PH_TURNAROUND;
        endcase
    endfunction

    // The lengths as twh_timing hands them to a single channel: a delivery
    // every clock but the two after a reset, for the field named two clocks
    // before; f_unl_in: the lab unlock was on when it was clamped (then any
    // length, 0 included).
    (* anyseq *) reg f_unl_in;
    reg [2:0] f_nx1, f_nx2;
    reg [1:0] f_rs2;
    always @(posedge clk) begin
        f_nx1 <= nx_fld;
        f_nx2 <= f_nx1;
        f_rs2 <= {f_rs2[0], rst};
    end
    always @(*) begin
        if (f_hist[1]) assume(dur_we == (f_rs2 == 2'b00));
        if (dur_we) assume(dur_fld_in == f_nx2);
        if (dur_we) assume(dur_fld_in >= 3'd1 && dur_fld_in <= 3'd6);
        if (dur_we && !f_unl_in) assume(f_in_window(f_ph_of(dur_fld_in), dur_in));
    end
    // whether dur_next came with the lab unlock on
    reg f_dn_unl;
    always @(posedge clk) if (dur_we) f_dn_unl <= f_unl_in;

    wire       f_txn   = (ph != `TWH_PH_IDLE) && (ph != `TWH_PH_TURNAROUND); // phases 1-6
    // the answer's checksum as the spec states it (section 5)
    wire [7:0] f_rx_chk = ~(rx_bytes[23:16] + rx_bytes[15:8]);
    wire       f_leave = tick && last && ((ph != `TWH_PH_IDLE) || (pending && pend_q)); // next phase loads
    wire [2:0] f_nph   = (ph == `TWH_PH_IDLE) ? `TWH_PH_CHARGE : ph + 3'd1;

    // ------------------------------------------------ the command and its result
    // f_out: commands accepted minus results taken. The last accepted
    // command is remembered as the caller sent it.
    reg [1:0]       f_out = 2'd0;
    reg [7:0]       f_code;
    reg [15:0]      f_pay;
    reg [TAG_W-1:0] f_tag;
    reg [3:0]       f_skip;
    always @(posedge clk) begin
        if (rst) begin
            f_out <= 2'd0;
        end else begin
            f_out <= f_out + {1'b0, accept} - {1'b0, m_res_valid && m_res_ready};
            if (accept) begin
                f_code <= s_cmd_code;
                f_pay  <= s_cmd_payload;
                f_tag  <= s_cmd_tag;
                f_skip <= s_cmd_skip;
            end
        end
    end

    // The frame as the spec draws it, from the accepted command alone: each
    // character is start (0), 8 data bits LSB first, 2 stop bits (1), sent
    // first character first; bit k is on the line during command ticks
    // 32k to 32k+31.
    wire        f_long = f_code[7];
    wire [7:0]  f_chk  = ~(f_code + (f_long ? f_pay[15:8] : 8'd0) + f_pay[7:0]);
    wire [43:0] f_frame = f_long
        ? {2'b11, f_chk, 1'b0, 2'b11, f_pay[7:0], 1'b0, 2'b11, f_pay[15:8], 1'b0, 2'b11, f_code, 1'b0}
        : {11'h7FF, 2'b11, f_chk, 1'b0, 2'b11, f_pay[7:0], 1'b0, 2'b11, f_code, 1'b0};

    // ------------------------------------------------ phase lengths
    // f_dur: the length loaded for the current phase (2001 for the hold-off
    // after reset); f_ticks: ticks of it already over; f_dur_unl: whether
    // the lab unlock was on when that length was clamped (f_unl_in).
    reg [15:0] f_dur, f_ticks;
    reg        f_dur_unl;
    // the length a loaded value stands for: 0 counts as 1
    function [15:0] f_eff;
        input [15:0] d;
        f_eff = (d == 16'd0) ? 16'd1 : d;
    endfunction
    // the length the next phase must get: the command's 44 or 33 bits, one
    // tick of idle after a turnaround, otherwise the length delivered
    wire [15:0] f_want = (f_nph == `TWH_PH_COMMAND) ? (f_long ? 16'd1408 : 16'd1056) :
                         (f_nph == `TWH_PH_IDLE)    ? 16'd1 : dur_next;
    always @(posedge clk) begin
        if (rst) begin
            f_dur     <= `TWH_TURNAROUND_MIN + 16'd1;
            f_ticks   <= 16'd0;
            f_dur_unl <= 1'b0;
        end else if (f_leave) begin
            f_dur     <= f_eff(f_want);
            f_ticks   <= 16'd0;
            f_dur_unl <= f_fld_of(f_nph) != 3'd0 && f_dn_unl;
        end else if (tick && !last) begin
            f_ticks   <= f_ticks + 1'b1;
        end
    end

    always @(*) begin
        if (f_ok) begin
            // ---- sequencer: the state the counts below rely on
            if (cnt == 16'd0) assert(f_ticks == 16'd0 && f_dur == 16'd1);
            assert(ph_oh == (8'd1 << ph));
            // the registered decodes trail cnt by two clocks only, and never
            // at a tick or in the clock before one; the halves' compares by one
            if (tick_d2) assert(c_hz == (cnt[15:5] == 11'd0) && c_lo1 == (cnt[4:0] == 5'd1) &&
                                c_lo01 == (cnt[4:1] == 4'd0) &&
                                c_cmd == (ph == `TWH_PH_COMMAND) && c_b10 == (bitn == 4'd10));
            if (!tick_d && !tick_d2 && !rst) assert(last == (cnt <= 16'd1) &&
                                        bit_end == (ph == `TWH_PH_COMMAND && cnt[4:0] == 5'd1 &&
                                                    cnt != 16'd1) &&
                                        byte_end == (bitn == 4'd10));
            assert(!(tick && tick_d) && !(tick && tick_d2) && !(tick_nx && tick_d2));
            assert(f_ticks < f_dur);
            assert(f_eff(cnt) + f_ticks == f_dur);
            if (ph == `TWH_PH_IDLE)
                assert(f_dur == 16'd1 || f_dur == `TWH_TURNAROUND_MIN + 16'd1);

            // ---- every phase lasts exactly its loaded length ...
            if (f_leave && ph != `TWH_PH_IDLE) assert(f_ticks + 16'd1 == f_dur);
            // ... and that length lies in the phase's spec window, unless
            // the lab unlock was on when it was picked
            if (!f_dur_unl) assert(f_in_window(ph, f_dur));
            // the command phase is its 33 or 44 bits of 32 ticks, and the
            // bit on the line is the frame's bit for the time elapsed
            if (ph == `TWH_PH_COMMAND) begin
                assert(f_dur == (f_long ? 16'd1408 : 16'd1056));
                assert(bitn <= 4'd10);
                assert({2'd0, byten} * 6'd11 + {2'd0, bitn} == f_ticks[10:5]);
                assert(tx_level == f_frame[f_ticks[10:5]]);
                // the registered byte is the current one past the start bit
                if (bitn != 4'd0) assert(tx_byte_q == tx_byte);
            end

            // ---- one command at a time, one result for each
            assert(f_out <= 2'd1);
            assert(f_out == {1'b0, pending || f_txn || m_res_valid});
            assert(!(pending && (ph != `TWH_PH_IDLE)));
            assert(!(m_res_valid && (pending || f_txn)));
            // ready means: nothing accepted is waiting for its result
            if (rdy) assert(ph == `TWH_PH_IDLE && f_out == 2'd0);
            assert(busy == ((ph != `TWH_PH_IDLE) || pending));
            // only a command that was not skipped ever leaves idle, and the
            // engine sends exactly what was accepted
            if (pending || f_txn) begin
                assert(f_skip == 4'd0);
                assert(cmd_r == f_code && tag_r == f_tag &&
                       pay_r == {f_long ? f_pay[15:8] : 8'd0, f_pay[7:0]});
            end
            // the checksum's two stages are current once pending has
            // lasted a clock, and for the whole transaction
            if ((pending && pend_q) || f_txn) assert(tx_psum == cmd_r + pay_r[7:0]);
            if (f_txn) assert(chk_r == f_chk);
            if (pend_q) assert(pending || f_txn);
            // the result belongs to the last accepted command: a skipped one
            // gets its skip status and no data; a sent one a link status
            if (m_res_valid) begin
                assert(m_res_code == f_code && m_res_tag == f_tag);
                if (f_skip != 4'd0) begin
                    assert(m_res_status == f_skip && m_res_data == 16'd0);
                end else begin
                    assert(m_res_status <= `TWH_ST_LINE_STUCK_HIGH);
                    if (m_res_status != `TWH_ST_OK && m_res_status != `TWH_ST_BAD_CHECKSUM)
                        assert(m_res_data == 16'd0);
                end
            end
            // with three bytes in, the expected checksum is that of the
            // first two, and the registered verdict is never stale when used
            if (rx_n == 2'd3) assert(rx_exp == f_rx_chk);
            if (tick && last && ph == `TWH_PH_LISTEN && rx_n == 2'd3)
                assert(rx_chk_ok == (f_rx_chk == rx_bytes[7:0]));
            // and the registered verdict is the verdict of the answer as it
            // stands at every tick of the listen phase
            if (tick && ph == `TWH_PH_LISTEN)
                assert(rx_status_q == rx_status && rx_data_ok_q == rx_data_ok);
        end
    end

    // the receiver's input contract (twh_rx): tick_nx says a tick a clock
    // ahead, no tick in two clocks running, and at a tick its enable is as
    // a clock before, or 0 after a reset
    always @(posedge clk)
        if (f_ok) assert(tick == $past(tick_nx && !rst) && tick_d2 == $past(tick_d && !rst));
    always @(posedge clk)
        if (f_ok && tick) assert(!$past(tick) && rx_en == ($past(rx_en) && !$past(rst)));

    always @(*) begin
        if (f_ok) begin
            // a programmable phase starts only with a length delivered for
            // its own field (never a stale fetch for the phase before) ...
            if (f_leave && f_fld_of(f_nph) != 3'd0) assert(dur_fld == f_fld_of(f_nph));
            // ... and the flag that lets it start is exact
            if (dur_ok) assert(dur_fld == nx_fld);
            // the listen's end is the tick that leaves it
            assert(lis_end == (tick && ph_oh[`TWH_PH_LISTEN] && last && dur_ok));
            assert(adv == (tick && last &&
                           (ph_oh[`TWH_PH_IDLE] ? pending && pend_q && dur_ok
                                                : ph_oh[`TWH_PH_PREAMBLE] ||
                                                  ph_oh[`TWH_PH_TURNAROUND] || dur_ok)));
            assert(dec == (tick && !last));
            // with lengths delivered as twh_timing does for one channel, a
            // phase never waits for its length (f_leave is taken at the
            // last tick, whatever dur_ok says)
            if (f_hist[1] && tick && last && ph != `TWH_PH_IDLE &&
                ph != `TWH_PH_PREAMBLE && ph != `TWH_PH_TURNAROUND) assert(dur_ok);
            if (f_hist[1] && tick && last && ph == `TWH_PH_IDLE && pending && pend_q)
                assert(dur_ok);
            assert(nx_fld == f_fld_of(ph == `TWH_PH_IDLE ? `TWH_PH_CHARGE :
                                      ph == `TWH_PH_PREAMBLE ? `TWH_PH_EXECUTE :
                                      ph == `TWH_PH_TURNAROUND ? `TWH_PH_CHARGE : ph + 3'd1));
        end
    end

    always @(posedge clk) begin
        if (f_run) begin
            // a result stays offered, unchanged, until it is taken
            if ($past(m_res_valid && !m_res_ready))
                assert(m_res_valid && $stable({m_res_code, m_res_data, m_res_status, m_res_tag}));
            // a skipped command is answered at once, with its own status
            if ($past(accept && s_cmd_skip != 4'd0))
                assert(m_res_valid && m_res_status == $past(s_cmd_skip) &&
                       m_res_code == $past(s_cmd_code) && m_res_tag == $past(s_cmd_tag) &&
                       ph == `TWH_PH_IDLE && !pending);
            // a result appears only for a skip or at the end of a listen
            if (m_res_valid && !$past(m_res_valid))
                assert($past(accept && s_cmd_skip != 4'd0) ||
                       $past(tick && last && ph == `TWH_PH_LISTEN));
            // progress: while a command is outstanding and not answered,
            // every tick moves the sequencer strictly forward (a later phase,
            // or fewer ticks left) but for at most one right after the accept
            // (pend_q follows pending a clock later), so its result comes
            // within at most 2001 + 6 x 65535 ticks
            if ($past(tick && ((pending && pend_q) || f_txn)))
                assert({ph, ~cnt} > $past({ph, ~cnt}));
        end
    end

`ifdef TWH_F_LINK_PINS
    // ------------------------------------------------ the pin
    // The pins follow the sequencer one clock later: f_lp is the phase the
    // pins show now. f_ic and f_txl are the idle-charge input and the
    // command bit as they were when the pins last took them.
    localparam integer F_P = CLK_HZ / 1_000_000;     // clocks per carrier period
    localparam integer F_H = (F_P + 1) / 2;          // clocks high in a period
    localparam [19:0]  F_P20 = F_P;
    localparam [7:0]   F_H8  = F_H;
    generate
        if (CLK_HZ % 1_000_000 != 0 || F_P > 8) begin : g_f_pins_clock
            twh_error_TWH_F_LINK_PINS_needs_a_whole_MHz_clock_of_at_most_8_MHz u_err ();
        end
    endgenerate

    reg [2:0] f_lp;
    reg       f_txl, f_ic, f_tdd;
    // f_ic: the idle charge the pins took, off while the post-reset
    // hold-off runs (idle, not yet in its last period); the clock-level
    // section below bounds the hold-off on its own
    always @(posedge clk) begin
        f_lp  <= ph;
        f_txl <= tx_level;
        f_tdd <= tick_d;
        if (rst)         f_ic <= 1'b0;
        else if (tick_d) f_ic <= cfg_idle_charge && !(ph_oh[`TWH_PH_IDLE] && !last);
    end
    wire f_carrier = (f_lp == `TWH_PH_CHARGE) || (f_lp == `TWH_PH_PREAMBLE) ||
                     (f_lp == `TWH_PH_EXECUTE) || (f_lp == `TWH_PH_COMMAND && f_txl) ||
                     (f_lp == `TWH_PH_IDLE && f_ic);

    // no command other than skipped ones accepted since reset
    reg f_skips_only;
    always @(posedge clk) begin
        if (rst)                             f_skips_only <= 1'b1;
        else if (accept && s_cmd_skip == 4'd0) f_skips_only <= 1'b0;
    end

    // consecutive clocks the pin has been high before this one
    reg [7:0] f_hi = 8'd0;
    always @(posedge clk) f_hi <= line_o ? f_hi + 1'b1 : 8'd0;

    always @(*) begin
        if (f_run) begin
            // released for the whole listen; driven low in sync and
            // turnaround; driven in every other phase; idle as configured
            case (f_lp)
                `TWH_PH_LISTEN:     assert(!line_oe && !line_o);
                `TWH_PH_SYNC,
                `TWH_PH_TURNAROUND: assert(line_oe && !line_o);
                `TWH_PH_IDLE:       assert(line_oe == f_ic);
                default:            assert(line_oe);
            endcase
            // the carrier appears only where it belongs ...
            if (line_o) assert(f_carrier);
            // ... and there, every period starts with its high half
            if (f_tdd) assert(line_o == f_carrier);
            // skipped commands leave the pins exactly as idle has them
            if (f_skips_only) assert(!pending && ph == `TWH_PH_IDLE && f_lp == `TWH_PH_IDLE &&
                                     line_oe == f_ic && (!line_o || f_ic));
            // each high half lasts exactly F_H clocks and starts with a
            // period: no runt pulse, whatever the phases do
            if (line_o) assert(f_hi < F_H8 && (f_hi != 8'd0 || f_tdd));
            if (!line_o && f_hi != 8'd0) assert(f_hi == F_H8);
        end
    end

    // ------------------------------------------------ clock level
    // f_since: clocks since the last tick; f_clk: clocks since the phase
    // began (saturating). After a reset the hold-off counts as a phase that
    // began at a virtual tick F_P - 1 clocks before the first clock out of
    // reset: the carrier ticks one period after it (two clocks after reset).
    reg [7:0]  f_since;
    reg [19:0] f_clk;
    reg        f_fresh;      // no phase has started since the reset
    reg [11:0] f_hot;        // ticks since the reset while fresh (saturating)
    always @(posedge clk) begin
        if (rst) begin
            f_fresh <= 1'b1;
            f_hot   <= 12'd0;
        end else begin
            if (f_leave) f_fresh <= 1'b0;
            if (tick && f_hot != 12'hFFF) f_hot <= f_hot + 1'b1;
        end
    end
    always @(posedge clk) begin
        if (rst) begin
            f_since <= F_P[7:0] - 8'd1;
            f_clk   <= F_P20 - 20'd1;
        end else begin
            f_since <= tick ? 8'd1 : f_since + 1'b1;
            if (f_leave)               f_clk <= 20'd1;
            else if (f_clk != 20'hFFFFF) f_clk <= f_clk + 1'b1;
        end
    end
    always @(*) begin
        if (f_ok) begin
            assert(f_since != 8'd0 && f_since <= F_P[7:0]);
            if (tick) assert(f_since == F_P[7:0]);
            // (waiting in idle for a command only adds clocks)
            if (ph == `TWH_PH_IDLE && last)
                assert(f_clk >= {4'd0, f_ticks} * F_P20 + {12'd0, f_since});
            else
                assert(f_clk == {4'd0, f_ticks} * F_P20 + {12'd0, f_since});
            // a phase lasts f_dur periods of F_P clocks: f_dur microseconds
            if (f_leave && ph != `TWH_PH_IDLE) assert(f_clk == {4'd0, f_dur} * F_P20);
            // after a reset, until the first phase starts, the line stays
            // released for the full minimum turnaround, whatever the idle
            // charge input does (a reset may have cut a listen short):
            // 2000 periods since the reset ended (f_clk began at F_P - 1)
            if (f_fresh && line_oe)
                assert(f_clk >= (`TWH_TURNAROUND_MIN + 20'd1) * F_P20 - 20'd1);
            // (what makes it inductive: the hold-off counts every tick
            // until it reaches its last period, and the idle charge is
            // taken only at a tick after that)
            if (f_fresh) begin
                assert(ph == `TWH_PH_IDLE && f_dur == `TWH_TURNAROUND_MIN + 16'd1);
                if (f_hot < 12'd2100) assert(f_clk == {8'd0, f_hot} * F_P20 + {12'd0, f_since});
                else                  assert(f_clk >= 20'd2100 * F_P20);
                if (!last) assert(f_hot == f_ticks[11:0]);
                else       assert(f_hot >= 12'd2000);
                if (f_ic)  assert(f_hot >= 12'd2001);
            end
            // after a reset no charge before the hold-off's 2001 periods
            // (the first of which began F_P - 1 clocks before the reset
            // ended), so the line rests at least 2000 periods + 3 clocks:
            // the full minimum turnaround
            if (f_leave && ph == `TWH_PH_IDLE && f_dur == `TWH_TURNAROUND_MIN + 16'd1)
                assert(f_clk >= {4'd0, f_dur} * F_P20);
        end
    end
`endif
`endif
endmodule
`default_nettype wire
