// One channel's autonomous poller for the time-shared engine (twh_engine):
// its POLL_CTRL and POLL_RESULT registers and its millisecond timer. The
// engine reads `due` and `cmd` at the channel's idle visits, starts the poll
// on its turn (`take`) and hands its result back (`res`); the poll never
// reaches the result FIFO.
//
// - A POLL_CTRL write that switches polling on is refused (`wdata_ok`, the
//   core's verdict) unless the command is read-only (0x40-0x44, 0x46-0x49):
//   a poller must never erase or write a sensor's flash. The command and the
//   enable load in the same clock, so the engine never sees a command that
//   was not checked as due (switching polling off accepts any byte).
// - The timer keeps a fixed rate: a poll falls due every interval; one that
//   waits (queued commands go first on their turn) runs late and the next
//   falls due on the same grid (docs/registers.md, POLL_CTRL).
`default_nettype none
`include "twh_defs.vh"
module twh_poller #(
    parameter integer POLLING = 1      // 0: no poller (POLL_CTRL reads 0, never due)
) (
    input  wire        clk,
    input  wire        rst,
    input  wire        ms_tick,
    input  wire [31:0] wdata,
    input  wire        wdata_ok,       // the core's verdict on wdata as POLL_CTRL
    input  wire        wr_poll_ctrl,
    input  wire        take,           // the engine started this channel's poll
    input  wire        res,            // ... and here is its result
    input  wire [15:0] res_data,
    input  wire [3:0]  res_status,
    output wire        due,            // armed and due
    output wire [15:0] cmd,            // {payload, code}
    output wire [31:0] poll_ctrl,
    output wire [31:0] poll_result,
    output reg         sample,         // a poll result arrived
    output reg         error           // ... and it was a link error
);
    reg [7:0]  poll_cmd, poll_payload;
    reg [14:0] poll_interval;
    reg        poll_en;
    reg [15:0] poll_data;
    reg [3:0]  poll_status;
    reg [11:0] poll_count;
    localparam [7:0]  POLL_CMD_DEF      = (POLLING != 0) ? 8'h44 : 8'h00;
    localparam [7:0]  POLL_PAYLOAD_DEF  = (POLLING != 0) ? 8'hAA : 8'h00;
    localparam [14:0] POLL_INTERVAL_DEF = (POLLING != 0) ? 15'd1000 : 15'd0;

    // Milliseconds to the next poll, this one included. It reloads at 1 or
    // below, so an interval of 0 polls at every millisecond as 1 does; the
    // "at 1 or below" flag moves with it, off the counter's path.
    reg [14:0] poll_timer;
    reg        poll_last;
    reg        poll_due;
    always @(posedge clk) begin
        if (rst) begin
            poll_cmd      <= POLL_CMD_DEF;
            poll_payload  <= POLL_PAYLOAD_DEF;
            poll_interval <= POLL_INTERVAL_DEF;
            poll_en       <= 1'b0;
            poll_timer    <= 15'd1;
            poll_last     <= 1'b1;
            poll_due      <= 1'b0;
        end else begin
            // without the poller the registers keep their reset values:
            // constants that synthesis folds away
            if (POLLING != 0 && wr_poll_ctrl && wdata_ok) begin
                poll_cmd      <= wdata[7:0];
                poll_payload  <= wdata[15:8];
                poll_interval <= wdata[30:16];
                poll_en       <= wdata[31];
            end
            if (!poll_en) begin
                poll_timer <= 15'd1;          // first poll at the next millisecond
                poll_last  <= 1'b1;
                poll_due   <= 1'b0;
            end else begin
                if (ms_tick) begin
                    if (poll_last) begin
                        poll_timer <= poll_interval;
                        poll_last  <= (poll_interval <= 15'd1);
                        poll_due   <= 1'b1;
                    end else begin
                        poll_timer <= poll_timer - 1'b1;
                        poll_last  <= (poll_timer == 15'd2);
                    end
                end
                if (take) poll_due <= 1'b0;
            end
        end
    end
    assign due = (POLLING != 0) && poll_en && poll_due;
    assign cmd = {poll_payload, poll_cmd};

    wire link_err = (res_status >= `TWH_ST_BAD_CHECKSUM) && (res_status <= `TWH_ST_LINE_STUCK_HIGH);
    always @(posedge clk) begin
        if (rst) begin
            poll_data   <= 16'd0;
            poll_status <= 4'd0;
            poll_count  <= 12'd0;
            sample      <= 1'b0;
            error       <= 1'b0;
        end else begin
            sample <= res;
            error  <= res && link_err;
            if (res) begin
                poll_data   <= res_data;
                poll_status <= res_status;
                poll_count  <= poll_count + 1'b1;
            end
        end
    end
    assign poll_ctrl   = {poll_en, poll_interval, poll_payload, poll_cmd};
    assign poll_result = {poll_count, poll_status, poll_data};

`ifdef FORMAL
    reg f_ok = 1'b0;
    always @(posedge clk) if (rst) f_ok <= 1'b1;
    function f_ro;        // the read-only commands a poller may send
        input [7:0] c;
        f_ro = (c >= 8'h40 && c <= 8'h44) || (c >= 8'h46 && c <= 8'h49);
    endfunction
    // the core's verdict (proven on the core) is assumed here
    always @(*) if (f_ok && !rst && wr_poll_ctrl) assume(wdata_ok == (!wdata[31] || f_ro(wdata[7:0])));
    always @(*) if (f_ok) begin
        assert(poll_last == (poll_timer <= 15'd1));
        // the poller is only ever armed with, and only ever offers, a
        // read-only command
        if (poll_en) assert(f_ro(poll_cmd));
        if (due) assert(f_ro(cmd[7:0]));
    end
`endif
endmodule
`default_nettype wire
