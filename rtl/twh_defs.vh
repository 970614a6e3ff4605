// Shared constants of the twowire-host core: phase and status codes and the
// host-generated timing windows of the spec's section 4 table (microseconds).
// These codes are part of the programming model: never renumber them.
`ifndef TWH_DEFS_VH
`define TWH_DEFS_VH

// Phase codes (twh_engine's `phase`, STATE.PHASE)
`define TWH_PH_IDLE        3'd0
`define TWH_PH_CHARGE      3'd1
`define TWH_PH_SYNC        3'd2
`define TWH_PH_PREAMBLE    3'd3
`define TWH_PH_COMMAND     3'd4
`define TWH_PH_EXECUTE     3'd5
`define TWH_PH_LISTEN      3'd6
`define TWH_PH_TURNAROUND  3'd7

// Result status codes
`define TWH_ST_OK              4'd0
`define TWH_ST_NO_RESPONSE     4'd1
`define TWH_ST_BAD_CHECKSUM    4'd2
`define TWH_ST_FRAMING         4'd3
`define TWH_ST_SHORT_RESPONSE  4'd4
`define TWH_ST_LINE_STUCK_LOW  4'd5
`define TWH_ST_LINE_STUCK_HIGH 4'd6
`define TWH_ST_BLOCKED         4'd7
`define TWH_ST_CANCELLED       4'd8
// a status whose result carries the answer's data bytes (else they read 0)
`define TWH_ST_HAS_DATA(s) (((s) == `TWH_ST_OK) || ((s) == `TWH_ST_BAD_CHECKSUM))
// a status that counts as a link error (ERRORS.LINK_ERROR)
`define TWH_ST_LINK_ERR(s) (((s) >= `TWH_ST_BAD_CHECKSUM) && ((s) <= `TWH_ST_LINE_STUCK_HIGH))

// Spec windows, microseconds (the charge, listen and turnaround phases have
// no spec maximum; the 16-bit duration inputs cap them at 65535 us).
`define TWH_CHARGE_MIN      16'd7000
`define TWH_SYNC_MIN        16'd900
`define TWH_SYNC_MAX        16'd1100
`define TWH_PREAMBLE_MIN    16'd1800
`define TWH_PREAMBLE_MAX    16'd2200
`define TWH_EXECUTE_MIN     16'd3500
`define TWH_EXECUTE_MAX     16'd10000
`define TWH_LISTEN_MIN      16'd2000
`define TWH_TURNAROUND_MIN  16'd2000
`define TWH_US_MAX          16'd65535

// Defaults of NOTES.md, microseconds
`define TWH_CHARGE_DEF      16'd8000
`define TWH_SYNC_DEF        16'd1000
`define TWH_PREAMBLE_DEF    16'd2000
`define TWH_EXECUTE_DEF     16'd4000
`define TWH_LISTEN_DEF      16'd3000
`define TWH_TURNAROUND_DEF  16'd2000
// ... as TIMING0-2 hold them (each register's low field in bits 15:0)
`define TWH_TIMING0_DEF     {`TWH_SYNC_DEF, `TWH_CHARGE_DEF}
`define TWH_TIMING1_DEF     {`TWH_EXECUTE_DEF, `TWH_PREAMBLE_DEF}
`define TWH_TIMING2_DEF     {`TWH_TURNAROUND_DEF, `TWH_LISTEN_DEF}
// POLL_CTRL's reset value where a poller is built: off, 1000 ms, the O2
// reading (0x44, payload 0x00AA)
`define TWH_POLL_CTRL_DEF   {1'b0, 15'd1000, 8'hAA, 8'h44}
// ... by timing field (twh_timing's codes: 1 charge .. 6 turnaround), what a
// build with fixed timing runs (twh_timing's fetch, twh_engine's FIXED_TIMING)
`define TWH_FLD_DEF(f) \
    (((f) == 3'd1) ? `TWH_CHARGE_DEF : ((f) == 3'd2) ? `TWH_SYNC_DEF : \
     ((f) == 3'd3) ? `TWH_PREAMBLE_DEF : ((f) == 3'd4) ? `TWH_EXECUTE_DEF : \
     ((f) == 3'd5) ? `TWH_LISTEN_DEF : `TWH_TURNAROUND_DEF)

// Register interface (rdl/twh_regs.rdl is the description)
// The time-shared engine's clock floor (docs/engine.md): P = CLK_HZ / 1 MHz
// clocks a period, FRAC the Hz left over. twh_engine checks it, and
// twh_carrier for the core (so that a bad clock names one error).
`define TWH_ENGINE_FLOOR_OK(p, frac, ch) \
    ((p) >= 4 && (p) >= (ch) && (ch) + 4 < 2 * (p) && ((frac) == 0 || (p) >= (ch) + 5))

// The timing field (twh_timing's codes: 1 charge .. 6 turnaround) that the
// phase after phase `p` loads, for the time-shared engine, which keeps a
// channel's phase and not its field (twh_engine reads its timing RAM with
// it; twh_timing decodes it after its channel multiplexer). The command
// phase's length is fixed, so preamble names execute; the idle after a
// turnaround is one tick, so turnaround names charge.
`define TWH_FLD_OF(p) \
    (((p) == `TWH_PH_CHARGE) ? 3'd2 : ((p) == `TWH_PH_SYNC) ? 3'd3 : \
     ((p) == `TWH_PH_PREAMBLE || (p) == `TWH_PH_COMMAND) ? 3'd4 : \
     ((p) == `TWH_PH_EXECUTE) ? 3'd5 : ((p) == `TWH_PH_LISTEN) ? 3'd6 : 3'd1)

// The timing register (0-2: TIMING0-2) that holds field `f` (1-6, two a
// register, the low half first): twh_timing's word address, which the
// time-shared engine registers at its write-back (sc_tr) so that the
// fetch's address is flip-flops alone
`define TWH_TREG_OF(f) (((f) <= 3'd2) ? 2'd0 : ((f) <= 3'd4) ? 2'd1 : 2'd2)

// The receiver's fields in its 45-bit word (twh_rx_dec, twh_rx_step; the
// engine keeps it in its state word's union during listen): bit offsets
`define TWH_RX_SH  0      // 24: the data bits received, the first in [0]
`define TWH_RX_SB  24     // 5: ticks into the bit
`define TWH_RX_MK  29     // 5: consecutive mark ticks (saturates at 16)
`define TWH_RX_BN  34     // 4: the bit of the character (0 the start bit)
`define TWH_RX_VT  38     // 2: ones among the bit's samples so far
`define TWH_RX_NB  40     // 2: characters received
`define TWH_RX_AC  42     // inside a character
`define TWH_RX_FE  43     // a framing error ended the answer
`define TWH_RX_EN  44     // a break ended the answer
`define TWH_RX_W   45

`define TWH_MAGIC         32'h54574831    // "TWH1"
`define TWH_VERSION_MAJOR 8'd2
`define TWH_VERSION_MINOR 8'd0
`define TWH_LAB_KEY       32'h4C414221    // "LAB!"
`define TWH_FACTORY_KEY   32'h46414354    // "FACT"
// words 0x00-0x1F: manufacturer and factory calibration, never erased or
// written unless the factory unlock is armed
`define TWH_FACTORY_END   9'h020

// Whether the pollers' timers live beside POLL_CTRL in twh_timing's memory
// (1) or in a memory of twh_polls' own (0): with pollers, above one
// channel, in block RAM. twh_timing and twh_polls must agree, so both take
// it from here.
`define TWH_POLL_TIMERS_IN_TIMING(poll, channels, ram_block) \
    (((poll) != 0 && (channels) > 1 && (ram_block) != 0) ? 1 : 0)

`endif
