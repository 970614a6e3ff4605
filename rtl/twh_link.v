// One 2-wire channel: carrier, six-phase sequencer, on-off-keyed UART both
// ways. A command goes in on a valid/ready stream; exactly one result comes
// out for it (unless reset intervenes). A command marked with a non-zero
// s_cmd_skip (blocked or cancelled upstream) is answered at once with that
// status and never reaches the line, so its result keeps its place in order.
//
// Phases: idle, charge, sync, preamble, command, execute, listen, turnaround
// (codes in twh_defs.vh). Durations come in as microseconds and are clamped
// into the spec window when each phase is loaded (see docs/protocol.md);
// cfg_unlock (lab work only) takes them as they are, zero read as one.
// The command phase is not programmable: it lasts exactly its 33 or 44 bits.
//
// Everything steps on the carrier tick, so every phase is a whole number of
// carrier periods, bursts always start with a full high half and the line
// never shows a runt pulse. Line drive per phase:
//   charge, preamble, execute  carrier
//   sync, turnaround           driven low
//   command                    carrier for 1 bits, driven low for 0 bits
//   listen                     released (line_oe = 0)
//   idle                       released, or carrier if cfg_idle_charge
// After reset the engine keeps the line released for the minimum turnaround
// before its first charge, so a reset during a listen cannot shorten the
// turnaround the peripheral sees.
`default_nettype none
`include "twh_defs.vh"
module twh_link #(
    parameter integer CLK_HZ    = 48_000_000,
    parameter integer TAG_W     = 8,
    parameter integer GLITCH_NS = 100
) (
    input  wire             clk,
    input  wire             rst,
    // timing, microseconds
    input  wire [15:0]      cfg_charge_us,
    input  wire [15:0]      cfg_sync_us,
    input  wire [15:0]      cfg_preamble_us,
    input  wire [15:0]      cfg_execute_us,
    input  wire [15:0]      cfg_listen_us,
    input  wire [15:0]      cfg_turnaround_us,
    input  wire             cfg_idle_charge,
    input  wire             cfg_unlock,
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
    output reg  [7:0]       m_res_code,
    output reg  [15:0]      m_res_data,
    output reg  [3:0]       m_res_status,
    output reg  [TAG_W-1:0] m_res_tag,
    // the 2-wire pin
    output reg              line_o,
    output reg              line_oe,
    input  wire             line_i,
    // status
    output wire [2:0]       phase,
    output wire             busy
);
    // ------------------------------------------------------------ timebase
    wire tick, fall;
    twh_carrier #(.CLK_HZ(CLK_HZ)) u_carrier (
        .clk(clk), .rst(rst), .tick(tick), .fall(fall)
    );

    // ------------------------------------------------------------ receive path
    wire line_s, env;
    twh_sync2 u_sync (.clk(clk), .rst(rst), .d(line_i), .q(line_s));
    twh_demod #(.CLK_HZ(CLK_HZ), .GLITCH_NS(GLITCH_NS)) u_demod (
        .clk(clk), .rst(rst), .line_s(line_s), .env(env)
    );

    reg  [2:0]  ph;
    wire [1:0]  rx_n;
    wire [23:0] rx_bytes;
    wire        rx_started, rx_frame_err;
    twh_rx u_rx (
        .clk(clk), .rst(rst), .en(ph == `TWH_PH_LISTEN), .tick(tick), .env(env),
        .nbytes(rx_n), .bytes(rx_bytes), .started(rx_started),
        .frame_err(rx_frame_err)
    );

    wire [7:0] rx_chk;
    twh_checksum u_rx_chk (
        .a(rx_bytes[23:16]), .b(rx_bytes[15:8]), .c(8'd0), .chk(rx_chk)
    );

    // ------------------------------------------------------------ command
    reg              pending;
    reg [7:0]        cmd_r;
    reg [TAG_W-1:0]  tag_r;
    reg [31:0]       txd;        // frame bytes, next byte's next bit in [0]
    reg [3:0]        bitn;       // 0 start, 1-8 data, 9-10 stop

    wire long_cmd = s_cmd_code[7];          // 0x80-0xFF: 4-byte frame
    wire [7:0] tx_chk;
    twh_checksum u_tx_chk (
        .a(s_cmd_code),
        .b(long_cmd ? s_cmd_payload[15:8] : s_cmd_payload[7:0]),
        .c(long_cmd ? s_cmd_payload[7:0]  : 8'd0),
        .chk(tx_chk)
    );

    assign s_cmd_ready = (ph == `TWH_PH_IDLE) && !pending && !m_res_valid;
    wire accept = s_cmd_valid && s_cmd_ready;

    // ------------------------------------------------------------ sequencer
    reg [15:0] cnt;        // periods left in this phase, this one included
    reg [15:0] dur_next;   // length of the phase after this one
    reg        saw_low;    // the line read low during sync
    reg        saw_high;   // the line read high during preamble

    function [15:0] clamp;
        input [15:0] v, lo, hi;
        input        unlock;
        begin
            if (unlock)       clamp = (v == 16'd0) ? 16'd1 : v;
            else if (v < lo)  clamp = lo;
            else if (v > hi)  clamp = hi;
            else              clamp = v;
        end
    endfunction

    // The next phase's length, registered a phase ahead: a phase lasts at
    // least 1 us, so the value is settled long before it is loaded, and the
    // one shared clamp stays off the tick path.
    reg [15:0] nx_v, nx_lo, nx_hi;
    reg        nx_fixed;      // not programmable: command length, hold-off
    always @(*) begin
        nx_fixed = 1'b0;
        nx_v  = cfg_charge_us;
        nx_lo = `TWH_CHARGE_MIN;
        nx_hi = `TWH_US_MAX;
        case (ph)
            `TWH_PH_IDLE:     ;
            `TWH_PH_CHARGE:   begin nx_v = cfg_sync_us;     nx_lo = `TWH_SYNC_MIN;     nx_hi = `TWH_SYNC_MAX;     end
            `TWH_PH_SYNC:     begin nx_v = cfg_preamble_us; nx_lo = `TWH_PREAMBLE_MIN; nx_hi = `TWH_PREAMBLE_MAX; end
            `TWH_PH_PREAMBLE: begin nx_v = cmd_r[7] ? 16'd1408 : 16'd1056; nx_fixed = 1'b1; end  // 44 / 33 bits of 32 us
            `TWH_PH_COMMAND:  begin nx_v = cfg_execute_us;  nx_lo = `TWH_EXECUTE_MIN;  nx_hi = `TWH_EXECUTE_MAX;  end
            `TWH_PH_EXECUTE:  begin nx_v = cfg_listen_us;   nx_lo = `TWH_LISTEN_MIN;   end
            `TWH_PH_LISTEN:   begin nx_v = cfg_turnaround_us; nx_lo = `TWH_TURNAROUND_MIN; end
            default:          begin nx_v = 16'd1; nx_fixed = 1'b1; end   // idle: no hold-off after a turnaround
        endcase
    end
    always @(posedge clk) begin
        if (nx_fixed) dur_next <= nx_v;
        else          dur_next <= clamp(nx_v, nx_lo, nx_hi, cfg_unlock);
    end

    wire last = (cnt == 16'd1);

    // result of the listen phase, decided on its last tick
    reg [3:0] rx_status;
    always @(*) begin
        if (!saw_low)                  rx_status = `TWH_ST_LINE_STUCK_HIGH;
        else if (!saw_high)            rx_status = `TWH_ST_LINE_STUCK_LOW;
        else if (rx_frame_err)         rx_status = `TWH_ST_FRAMING;
        else if (rx_n == 2'd3)         rx_status = (rx_chk == rx_bytes[7:0]) ? `TWH_ST_OK
                                                                            : `TWH_ST_BAD_CHECKSUM;
        else if (rx_started)           rx_status = `TWH_ST_SHORT_RESPONSE;
        else                           rx_status = `TWH_ST_NO_RESPONSE;
    end
    wire rx_data_ok = (rx_status == `TWH_ST_OK) || (rx_status == `TWH_ST_BAD_CHECKSUM);

    always @(posedge clk) begin
        if (rst) begin
            ph          <= `TWH_PH_IDLE;
            cnt         <= `TWH_TURNAROUND_MIN;
            pending     <= 1'b0;
            cmd_r       <= 8'd0;
            tag_r       <= {TAG_W{1'b0}};
            txd         <= 32'd0;
            bitn        <= 4'd0;
            saw_low     <= 1'b0;
            saw_high    <= 1'b0;
            m_res_valid <= 1'b0;
            m_res_code  <= 8'd0;
            m_res_data  <= 16'd0;
            m_res_status<= 4'd0;
            m_res_tag   <= {TAG_W{1'b0}};
        end else begin
            if (m_res_valid && m_res_ready) m_res_valid <= 1'b0;

            if (accept && s_cmd_skip != 4'd0) begin
                // blocked or cancelled upstream: the line is never touched
                m_res_valid  <= 1'b1;
                m_res_code   <= s_cmd_code;
                m_res_tag    <= s_cmd_tag;
                m_res_status <= s_cmd_skip;
                m_res_data   <= 16'd0;
            end else if (accept) begin
                pending <= 1'b1;
                cmd_r   <= s_cmd_code;
                tag_r   <= s_cmd_tag;
                txd     <= long_cmd ? {tx_chk, s_cmd_payload[7:0], s_cmd_payload[15:8], s_cmd_code}
                                    : {8'hFF, tx_chk, s_cmd_payload[7:0], s_cmd_code};
            end

            if (tick) begin
                if (ph == `TWH_PH_SYNC && !env)     saw_low  <= 1'b1;
                if (ph == `TWH_PH_PREAMBLE && env)  saw_high <= 1'b1;

                if (ph == `TWH_PH_IDLE) begin
                    if (!last) begin
                        cnt <= cnt - 1'b1;           // post-reset hold-off
                    end else if (pending) begin
                        pending  <= 1'b0;
                        ph       <= `TWH_PH_CHARGE;
                        cnt      <= dur_next;
                        saw_low  <= 1'b0;
                        saw_high <= 1'b0;
                    end
                end else if (!last) begin
                    cnt <= cnt - 1'b1;
                    // a new UART bit starts every 32 periods of the command
                    if (ph == `TWH_PH_COMMAND && cnt[4:0] == 5'd1) begin
                        bitn <= (bitn == 4'd10) ? 4'd0 : bitn + 1'b1;
                        if (bitn >= 4'd1 && bitn <= 4'd8) txd <= {1'b1, txd[31:1]};
                    end
                end else begin
                    ph  <= ph + 1'b1;                // phases run in code order
                    cnt <= dur_next;
                    if (ph == `TWH_PH_PREAMBLE) bitn <= 4'd0;
                    if (ph == `TWH_PH_LISTEN) begin
                        m_res_valid  <= 1'b1;
                        m_res_code   <= cmd_r;
                        m_res_tag    <= tag_r;
                        m_res_status <= rx_status;
                        m_res_data   <= rx_data_ok ? rx_bytes[23:8] : 16'd0;
                    end
                end
            end
        end
    end

    // ------------------------------------------------------------ line drive
    // The line follows the sequencer one clock later; every burst and gap
    // keeps its exact length.
    wire tx_level = (bitn == 4'd0) ? 1'b0 : (bitn <= 4'd8) ? txd[0] : 1'b1;
    reg  carrier_on, drive;
    always @(*) begin
        case (ph)
            `TWH_PH_IDLE:     begin drive = cfg_idle_charge; carrier_on = cfg_idle_charge; end
            `TWH_PH_CHARGE,
            `TWH_PH_PREAMBLE,
            `TWH_PH_EXECUTE:  begin drive = 1'b1; carrier_on = 1'b1; end
            `TWH_PH_COMMAND:  begin drive = 1'b1; carrier_on = tx_level; end
            `TWH_PH_LISTEN:   begin drive = 1'b0; carrier_on = 1'b0; end
            default:          begin drive = 1'b1; carrier_on = 1'b0; end  // sync, turnaround
        endcase
    end

    reg tick_d, fall_d;
    always @(posedge clk) begin
        if (rst) begin
            tick_d  <= 1'b0;
            fall_d  <= 1'b0;
            line_o  <= 1'b0;
            line_oe <= 1'b0;
        end else begin
            tick_d <= tick;
            fall_d <= fall;
            if (tick_d) begin
                line_oe <= drive;
                line_o  <= carrier_on;
            end else if (fall_d) begin
                line_o  <= 1'b0;
            end
        end
    end

    assign phase = ph;
    assign busy  = (ph != `TWH_PH_IDLE) || pending;
endmodule
`default_nettype wire
