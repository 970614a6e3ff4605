"""Behavioural model of a 2-wire peripheral (digital O2 cell, CO2 sensor...).

Three layers:

- PeripheralLogic: pure Python. Takes a received host frame, returns the
  3-byte answer or None, and keeps the device's flash. No simulator needed.
- Faults + response_events(): what the peripheral puts on the line for an
  answer (bit rate, carrier, duty, mark, injected errors) as a list of
  timed events. Also pure Python, so the waveform itself is unit-tested.
- PeripheralModel: the cocotb coroutine that follows the host's carrier on
  tb_link's `line`, decodes the command, checks the execute phase and plays
  the answer on `periph_o` / `periph_oe`.
"""
from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass
from typing import Optional

import cocotb
from cocotb.simtime import get_sim_time
from cocotb.triggers import First, RisingEdge, Timer

import protocol as p

BLANK = 0x3FFF
PAGE_WORDS = 16

# Reasons recorded in the logs. A test can compare against these names.
R_ANSWERED = "answered"
R_BAD_LENGTH = "bad length"
R_BAD_CHECKSUM = "bad checksum"
R_RESERVED = "reserved command"
R_OUT_OF_RANGE = "address out of range"
R_WRITTEN = "written"
R_NOT_BLANK = "write ignored: word not blank"
R_ERASED = "erased"


# ===========================================================================
# 1. Command handling
# ===========================================================================
@dataclass
class LogicRecord:
    """One frame handled by PeripheralLogic."""
    frame: bytes
    response: Optional[bytes]
    reason: str
    addr: Optional[int] = None

    @property
    def cmd(self) -> Optional[int]:
        return self.frame[0] if self.frame else None

    @property
    def name(self) -> str:
        return p.command_name(self.frame[0]) if self.frame else "EMPTY"

    def transcript(self) -> str:
        """This frame and its answer as the cross-simulator transcripts
        write them (tb/simrun.py)."""
        return (f"frame {bytes(self.frame).hex()} -> "
                f"{'none' if self.response is None else bytes(self.response).hex()}")


class PeripheralLogic:
    """Command handler of one device, on a private copy of its flash.

    It does NOT protect words 0x00-0x1F: a real device erases and writes
    them when told to; blocking such commands is the host core's job, and
    tests need to see that the core really blocks them.
    """

    def __init__(self, profile):
        self.profile = profile
        self.flash = list(profile.flash)
        self.log: list[LogicRecord] = []

    @property
    def size(self) -> int:
        return len(self.flash)

    def handle(self, frame) -> Optional[bytes]:
        frame = bytes(frame)
        rec = self._dispatch(frame)
        self.log.append(rec)
        return rec.response

    # -- internals -----------------------------------------------------------
    def _answer(self, frame, msb, lsb, addr=None) -> LogicRecord:
        return LogicRecord(frame, p.response_frame(msb, lsb), R_ANSWERED, addr)

    def _dispatch(self, frame: bytes) -> LogicRecord:
        if len(frame) < 3 or len(frame) != p.frame_len(frame[0]):
            return LogicRecord(frame, None, R_BAD_LENGTH)
        if not p.frame_ok(frame):
            return LogicRecord(frame, None, R_BAD_CHECKSUM)
        cmd = frame[0]
        name = p.command_name(cmd)
        pr = self.profile
        if name == "WRITE":
            addr, data = p.decode_write(cmd, frame[1] << 8 | frame[2])
            if addr >= self.size:
                return LogicRecord(frame, None, R_OUT_OF_RANGE, addr)
            if self.flash[addr] != BLANK:          # write-once
                return LogicRecord(frame, None, R_NOT_BLANK, addr)
            self.flash[addr] = data
            return LogicRecord(frame, None, R_WRITTEN, addr)
        if name == "CONFIG":
            return self._answer(frame, *pr.config_response())
        if name == "FIRMWARE":
            return self._answer(frame, pr.fw_byte, pr.type_byte)
        if name in ("REF_VOLTAGE", "TEMPERATURE", "O2_VOLTAGE"):
            adc = {"REF_VOLTAGE": pr.adc_ref_voltage,
                   "TEMPERATURE": pr.adc_temperature,
                   "O2_VOLTAGE": pr.adc_o2}[name] & 0xFFF
            return self._answer(frame, adc >> 8, adc & 0xFF)
        if name in ("FIND_FREE", "READ", "ERASE"):
            addr = p.decode_addr(cmd, frame[1])
            if addr >= self.size:
                return LogicRecord(frame, None, R_OUT_OF_RANGE, addr)
            if name == "READ":
                w = self.flash[addr] & 0x3FFF
                return self._answer(frame, w >> 8, w & 0xFF, addr)
            if name == "FIND_FREE":
                # Decision: when no blank word is left at or above the start
                # address, answer the flash size (one past the last word), a
                # value no real free address can take. The spec is silent.
                found = next((a for a in range(addr, self.size)
                              if self.flash[a] == BLANK), self.size)
                return self._answer(frame, found >> 8, found & 0xFF, addr)
            page = addr & ~(PAGE_WORDS - 1)
            for a in range(page, min(page + PAGE_WORDS, self.size)):
                self.flash[a] = BLANK
            return LogicRecord(frame, None, R_ERASED, addr)
        return LogicRecord(frame, None, R_RESERVED)


# ===========================================================================
# 2. Faults and the answer's waveform
# ===========================================================================
@dataclass
class Faults:
    """How the peripheral answers. Defaults: a well-behaved device.

    no_response       handle the command (writes do happen) but stay silent
    bad_checksum      corrupt the checksum byte (xor 0x01)
    bad_stop_bit      index (0-2) of the byte whose first stop bit is sent as 0
    truncate          send only the first 1 or 2 bytes
    baud              answer bit rate (spec 30750-31750)
    carrier_hz        the peripheral's own carrier (spec 0.9-1.1 MHz)
    duty              carrier high fraction (NOTES: 0.3-0.7 must work)
    baseband          key a DC high level instead of a carrier
    response_delay_us host carrier stop -> start of the mark
    mark_us           carrier before the first start bit; None = one bit time
    stop_bits         1 or 2
    once              used for one transaction, then the model reverts to
                      Faults() (see also PeripheralModel.inject())
    """
    no_response: bool = False
    bad_checksum: bool = False
    bad_stop_bit: Optional[int] = None
    truncate: Optional[int] = None
    baud: float = 31250.0
    carrier_hz: float = 1.0e6
    duty: float = 0.5
    baseband: bool = False
    response_delay_us: float = 150.0
    mark_us: Optional[float] = None
    stop_bits: int = 2
    once: bool = False

    def __post_init__(self):
        if self.truncate not in (None, 1, 2):
            raise ValueError("truncate must be None, 1 or 2")
        if self.bad_stop_bit not in (None, 0, 1, 2):
            raise ValueError("bad_stop_bit must be None or a byte index 0-2")
        if self.stop_bits not in (1, 2):
            raise ValueError("stop_bits must be 1 or 2")
        if not 0.0 < self.duty < 1.0:
            raise ValueError("duty must be between 0 and 1")
        if self.baud <= 0 or self.carrier_hz <= 0:
            raise ValueError("baud and carrier_hz must be positive")
        if self.response_delay_us < 0 or (self.mark_us is not None and self.mark_us < 0):
            raise ValueError("delays must not be negative")

    @property
    def bit_us(self) -> float:
        return 1e6 / self.baud

    def mark_time_us(self) -> float:
        return self.bit_us if self.mark_us is None else self.mark_us

    def wire_bytes(self, response: bytes) -> bytes:
        """The bytes actually sent for a response (checksum/truncate faults)."""
        data = bytearray(response)
        if self.bad_checksum:
            data[2] ^= 0x01
        if self.truncate is not None:
            data = data[:self.truncate]
        return bytes(data)

    def response_duration_us(self, n_bytes: int = 3) -> float:
        """Mark start to release, for n_bytes sent (helps place a late answer
        exactly at the edge of the host's listen window)."""
        return self.mark_time_us() + n_bytes * (1 + 8 + self.stop_bits) * self.bit_us


def response_events(data: bytes, faults: Faults, t0_ps: int) -> list:
    """Line events of an answer: sorted (time_ps, periph_o, periph_oe).

    Starts at t0_ps with the mark, ends with the release (oe = 0) right after
    the last stop bit. Bit edges are computed from t0 (no accumulated drift);
    the carrier runs continuously from t0 (phase-continuous across bits), is
    high for `duty` of each period and is cut (driven 0) at 0-bit boundaries.
    """
    f = faults
    bit = 1e12 / f.baud
    mark = f.mark_time_us() * 1e6
    line_bits = []
    for i, b in enumerate(data):
        ub = p.uart_bits(b, f.stop_bits)
        if f.bad_stop_bit == i:
            ub[9] = 0                     # first stop bit sent as 0
        line_bits += ub
    end_all = mark + len(line_bits) * bit
    # stretches of 1s (carrier on), in ps relative to t0: the mark, then the
    # 1-bits, adjacent ones merged so the carrier phase runs on across them
    ones = [(0.0, mark)] if mark > 0 else []
    for k, lvl in enumerate(line_bits):
        a, b_ = mark + k * bit, mark + (k + 1) * bit
        if not lvl:
            continue
        if ones and ones[-1][1] == a:
            ones[-1] = (ones[-1][0], b_)
        else:
            ones.append((a, b_))
    ev = {}  # time -> level; later writes at the same time win

    def put(t_rel: float, level: int):
        ev[int(round(t0_ps + t_rel))] = level

    put(0.0, 0)
    for a, b_ in ones:
        if f.baseband:
            put(a, 1)
            put(b_, 0)
            continue
        per = 1e12 / f.carrier_hz
        high = f.duty * per
        k = math.floor(a / per)
        while k * per < b_:
            hs, he = k * per, k * per + high
            rise, fall = max(hs, a), min(he, b_)
            if fall > rise:
                put(rise, 1)
                put(fall, 0)
            k += 1
    t_rel = int(round(t0_ps + end_all))
    out = [(t, lvl, 1) for t, lvl in sorted(ev.items()) if t < t_rel]
    out.append((t_rel, 0, 0))
    # drop repeated levels (a fall and the next rise can round together)
    clean = []
    for e in out:
        if clean and clean[-1][1:] == e[1:]:
            continue
        clean.append(e)
    return clean


def decode_events(events, baud: float = 31250.0):
    """Reference decoder of response_events() output, for unit tests.

    Turns the keyed carrier back into an envelope (high stretches closer
    than 1.5 us merge) and samples each UART bit in its middle, the way a
    host receiver would. Returns (bytes, framing_error).
    """
    highs = []  # (rise, fall) of every driven-high stretch
    for (t, lvl, oe), nxt in zip(events, events[1:]):
        if lvl and oe:
            highs.append((t, nxt[0]))
    env = []
    for a, b in highs:
        if env and a - env[-1][1] < 1_500_000:
            env[-1] = (env[-1][0], b)
        else:
            env.append((a, b))
    bit = 1e12 / baud
    if not env:
        return b"", False
    release = events[-1][0]

    def level(ts: float) -> int:
        return int(any(a <= ts < b for a, b in env))

    out = bytearray()
    t = env[0][0]
    # an answer without a mark starts with the line driven low: a start bit
    first_low = events[0][0] if events[0][1] == 0 else None
    while True:
        falls = [b for a, b in env if b >= t and b < release - bit / 2]
        if first_low is not None:
            falls, first_low = [first_low], None
        if not falls:
            return bytes(out), False
        s = min(falls)
        out.append(sum(level(s + (1.5 + i) * bit) << i for i in range(8)))
        if not level(s + 9.5 * bit):
            return bytes(out), True
        t = s + 9.5 * bit


# ===========================================================================
# 3. The cocotb model
# ===========================================================================
US = 1_000_000          # ps per microsecond
GAP_PS = 4 * US         # no rising edge for this long = the carrier is off
EXEC_GAP_US = 2         # during execute: timeout that sees the carrier stop
                        # (tb_line's QUIET_PS, which drops `carrier`, is the same)
CHARGE_MIN_US = 7000    # continuous carrier needed to power up
SYNC_MIN_US = 500       # a gap in this window after the charge arms the receiver
SYNC_MAX_US = 1500
QUIET_US = 1500         # after an error: wait for a gap this long (listen)
MAX_ZERO_BITS = 10      # a longer 0-run inside a frame is not UART data
TOL_US = 1.5            # edge-quantisation tolerance on phase lengths
SHORT_CHARGE_LOG_US = 1000  # shorter bursts before a sync gap are not logged

R_CHARGE_SHORT = "charge too short"
R_SYNC_SHORT = "sync too short"
R_SYNC_LONG = "sync too long"
R_FRAMING = "framing error in command"
R_FRAME_TIMEOUT = "command incomplete"
R_EXEC_SHORT = "execute carrier too short"
R_EXEC_LONG = "execute phase too long"
R_EXEC_BROKEN = "execute carrier interrupted"
R_FAULT_SILENT = "fault: no_response"


@dataclass
class Transaction:
    """What the model saw of one host transaction (PeripheralModel.log).

    Phase lengths are measured from the rising edges on the line, in us:
    a carrier burst lasts from its first rising edge to one host period after
    its last; a gap is the rest. command_us ends after the last byte's second
    stop bit; execute_us runs from there to where the carrier stopped.
    """
    start_ps: int
    host_period_ns: float
    charge_us: float
    sync_us: float
    preamble_us: Optional[float] = None
    command_us: Optional[float] = None
    execute_us: Optional[float] = None
    frame: bytes = b""
    response: Optional[bytes] = None   # bytes put on the line (after faults)
    reason: str = ""
    faults: Optional[Faults] = None
    response_start_ps: Optional[int] = None   # start of the mark
    response_end_ps: Optional[int] = None     # release
    collision: bool = False   # the host drove the line while we answered

    @property
    def cmd(self) -> Optional[int]:
        return self.frame[0] if self.frame else None

    @property
    def name(self) -> str:
        return p.command_name(self.frame[0]) if self.frame else "NONE"


class _Abort(Exception):
    """Ends a transaction early.

    pushback: an edge already taken from the line that starts the next
        transaction (its charge).
    quiet_from: the peripheral lost track of the host; it follows the line
        from this edge until a gap longer than QUIET_US (the host's listen and
        turnaround) before it looks for a charge again.
    """

    def __init__(self, reason: str, pushback: Optional[int] = None,
                 quiet_from: Optional[int] = None):
        super().__init__(reason)
        self.reason = reason
        self.pushback = pushback
        self.quiet_from = quiet_from


def _parse_uart(bits):
    """Parse a 0/1 list into UART characters (1 stop bit required).

    Returns (bytes, start_indices, pending_start, error): pending_start is the
    index of a start bit whose character is not complete yet.
    """
    out, starts, i = [], [], 0
    while True:
        while i < len(bits) and bits[i] == 1:
            i += 1
        if i >= len(bits):
            return out, starts, None, False
        s = i
        if len(bits) < s + 10:
            return out, starts, s, False
        if bits[s + 9] != 1:
            return out, starts, s, True
        out.append(sum(bits[s + 1 + k] << k for k in range(8)))
        starts.append(s)
        i = s + 10


class PeripheralModel:
    """cocotb model of one peripheral on tb_link's line.

    It watches `dut.line` (rising edges only, plus a 2 us timeout while the
    execute carrier runs) and drives `dut.periph_o` / `dut.periph_oe`.
    With `line_log` and `carrier` (the LINE_LOG file and the `carrier` flag
    of the line's tb_line) it reads the rising edges in bulk from the file
    and wakes only when `carrier` changes, twice a carrier burst; without
    them it waits on every rising edge of `dut.line`. The edges, and so every
    decision, are the same either way.

    1. charge: a carrier burst of >= 7 ms powers the device (shorter bursts
       are counted in short_bursts; one followed by a sync-like gap is logged
       as "charge too short");
    2. sync: the gap after it must be 0.5-1.5 ms, else no answer;
    3. preamble: carrier, measured and logged;
    4. command: run lengths of the keyed carrier, rounded to host bit times
       (32 host carrier periods, the period being measured during the charge),
       parsed as 8N1/8N2 UART; the first byte gives the frame length;
    5. execute: the carrier must last exec_min_us after the last byte's second
       stop bit (then PeripheralLogic executes the frame) and stop before
       exec_max_us (else no answer);
    6. answer: response_delay_us after the carrier stopped (one host period
       after its last rising edge), the precomputed response_events() are
       played at absolute times, then the line is released.
    After a reception error the model waits for a quiet line (> 1.5 ms, the
    host's listen + turnaround) before it looks for the next charge. Lone
    spikes (no second edge within 4 us) are ignored.

    Usage:
        model = PeripheralModel(dut, profiles.O2_V18).start()
        model.inject(Faults(baud=30750))   # next transaction only
        ...
        assert model.log[-1].response == ...
    """

    def __init__(self, dut, profile, faults: Optional[Faults] = None,
                 line_log: Optional[str] = None, carrier=None):
        self.dut = dut
        self.profile = profile
        self.logic = PeripheralLogic(profile)
        self.faults = faults if faults is not None else Faults()
        self.log: list[Transaction] = []
        self.short_bursts = 0       # carrier bursts too short to power up
        self.spikes = 0             # lone rising edges ignored (glitches)
        self._last_edge = -(1 << 62)
        self._next: Optional[Faults] = None
        self._pending = deque()     # edges read ahead, to be taken again
        self._fresh = deque()       # edges read from line_log, not yet taken
        self._line_log = line_log
        self._carrier = carrier
        self._file = None
        self._partial = ""
        self._task = None
        self._line = dut.line
        self._rise = RisingEdge(dut.line)
        self._o = dut.periph_o
        self._oe = dut.periph_oe
        self._host_oe = getattr(dut, "line_oe", None)
        self._o.value = 0
        self._oe.value = 0

    # -- public --------------------------------------------------------------
    @property
    def flash(self) -> list:
        return self.logic.flash

    def start(self):
        if self._line_log is not None and self._file is None:
            self._file = open(self._line_log)
            self._skip_log()            # edges before the start are not seen
        self._task = cocotb.start_soon(self._run())
        return self

    def stop(self):
        if self._task is not None:
            self._task.cancel()
            self._task = None
        if self._file is not None:
            self._file.close()
            self._file = None
        self._o.value = 0
        self._oe.value = 0

    def inject(self, faults: Faults):
        """Use these faults for the next transaction only."""
        self._next = faults

    # -- helpers -------------------------------------------------------------
    @staticmethod
    def _now() -> int:
        return int(round(get_sim_time("ps")))

    def _push(self, t: int):
        """Give an edge back: the next _raw_edge() returns it first."""
        self._pending.appendleft(t)

    def _read_log(self) -> None:
        """Queue the rising edges logged since the last read."""
        text = self._partial + self._file.read()
        lines = text.split("\n")
        self._partial = lines.pop()
        self._fresh.extend(int(x) for x in lines)

    def _skip_log(self) -> None:
        """Drop every edge logged so far: the model was not listening (the
        per-edge form misses the edges while it plays its answer, too)."""
        self._read_log()
        self._fresh.clear()

    def _take(self) -> Optional[int]:
        """The next edge already known (pushed back or logged), else None."""
        if self._pending:
            return self._pending.popleft()
        if not self._fresh:
            self._read_log()
        return self._fresh.popleft() if self._fresh else None

    async def _raw_edge(self) -> int:
        """Time of the next rising edge of the line (or the pushed-back one)."""
        if self._file is None:
            if self._pending:
                return self._pending.popleft()
            await self._rise
            return self._now()
        while True:
            t = self._take()
            if t is not None:
                return t
            # a burst starts (the edge is logged) or ends (all of it is)
            await self._carrier.value_change

    async def _execute_edge(self) -> Optional[int]:
        """The next rising edge of the execute carrier, or None once the line
        has had none for EXEC_GAP_US (the carrier stopped)."""
        if self._file is None:
            tmr = Timer(EXEC_GAP_US, unit="us")
            res = await First(self._rise, tmr)
            return None if res is tmr else self._now()
        while True:
            t = self._take()
            if t is not None:
                return t
            if str(self._carrier.value) != "1":
                return None
            await self._carrier.value_change

    async def _edge(self) -> int:
        """Time of the next rising edge that belongs to a carrier.

        An edge after a gap counts only when another edge follows within
        GAP_PS: a lone spike (tb_link's `glitch`) is no carrier, and a real
        demodulator would not see it either. The check looks one edge ahead,
        so a burst is confirmed one carrier period after its first edge; the
        time returned is still that of the first edge.
        """
        t = await self._raw_edge()
        if t - self._last_edge > GAP_PS:
            while True:
                t2 = await self._raw_edge()
                if t2 - t <= GAP_PS:
                    self._push(t2)
                    break
                self.spikes += 1
                t = t2
        self._last_edge = t
        return t

    def _take_faults(self) -> Faults:
        if self._next is not None:
            f, self._next = self._next, None
        elif self.faults.once:
            f, self.faults = self.faults, Faults()
        else:
            f = self.faults
        return f

    async def _skip_until_quiet(self, last: int):
        """Follow the line until a gap longer than QUIET_US (the host's listen
        and turnaround); the edge after it starts the next transaction."""
        while True:
            t = await self._edge()
            if t - last > QUIET_US * US:
                self._push(t)
                return
            last = t

    # -- main loop -----------------------------------------------------------
    async def _run(self):
        while True:
            rec = Transaction(0, 0.0, 0.0, 0.0)
            try:
                await self._transaction(rec)
            except _Abort as e:
                rec.reason = e.reason
                self.log.append(rec)
                if e.quiet_from is not None:
                    await self._skip_until_quiet(e.quiet_from)
                elif e.pushback is not None:
                    self._push(e.pushback)
                continue

    async def _transaction(self, rec: Transaction):
        # ---- 1. charge: a burst of >= 7 ms powers the device ---------------
        t = await self._edge()
        start = last = t
        n = 1
        while True:
            t = await self._edge()
            if t - last <= GAP_PS:
                last, n = t, n + 1
                continue
            per = (last - start) / (n - 1) if n > 1 else float(US)
            burst = last - start + per
            if burst >= (CHARGE_MIN_US - TOL_US) * US:
                break
            self.short_bursts += 1
            gap = t - last - per
            if (burst >= SHORT_CHARGE_LOG_US * US
                    and SYNC_MIN_US * US <= gap <= SYNC_MAX_US * US):
                # looks like a charge + sync that was too short to power up:
                # worth a record; sit out the rest of this transaction
                rec.start_ps, rec.host_period_ns = start, per / 1000
                rec.charge_us, rec.sync_us = burst / US, gap / US
                raise _Abort(R_CHARGE_SHORT, quiet_from=t)
            start = last = t
            n = 1
        rec.start_ps = start
        rec.host_period_ns = per / 1000
        rec.charge_us = burst / US
        gap = t - last - per
        rec.sync_us = gap / US

        # ---- 2. sync: a gap of 0.5-1.5 ms arms the receiver ----------------
        if gap < SYNC_MIN_US * US:
            raise _Abort(R_SYNC_SHORT, quiet_from=t)
        if gap > SYNC_MAX_US * US:
            raise _Abort(R_SYNC_LONG, pushback=t)

        # ---- 3./4. preamble, then the command frame -------------------------
        bit = 32 * per                 # host bit = 32 of its carrier periods
        run_start = last = t
        preamble_end = None
        bits: list = []
        marks: list = []               # (bit index, time) where each run began
        expected = None
        frame_end = None
        out: list = []
        while True:
            t = await self._edge()
            if t - last <= GAP_PS:
                last = t
                if frame_end is not None and t >= frame_end - bit / 2:
                    break              # mid second stop bit, carrier on: done
                continue
            gap_start = last + per
            if preamble_end is None:
                preamble_end = gap_start
                rec.preamble_us = (gap_start - run_start) / US
            else:
                marks.append((len(bits), run_start))
                bits += [1] * round((gap_start - run_start) / bit)
            zeros = round((t - gap_start) / bit)
            if zeros > MAX_ZERO_BITS:
                raise _Abort(R_FRAME_TIMEOUT, pushback=t)
            marks.append((len(bits), gap_start))
            bits += [0] * zeros
            run_start = last = t
            out, starts, pending, err = _parse_uart(bits)
            rec.frame = bytes(out)
            if err:
                raise _Abort(R_FRAMING, quiet_from=t)
            if out and expected is None:
                expected = p.frame_len(out[0])
            if expected is not None and len(out) >= expected:
                # a gap inside the last byte's second stop bit or after it
                raise _Abort(R_EXEC_BROKEN, quiet_from=t)
            if expected is not None and len(out) == expected - 1 and pending is not None:
                idx, tm = max(m for m in marks if m[0] <= pending)
                frame_end = tm + (pending - idx) * bit + 11 * bit
        # close the frame with the open carrier run (data 1s and stop bits)
        bits += [1] * round((frame_end - run_start) / bit)
        out, _, _, err = _parse_uart(bits)
        rec.frame = bytes(out[:expected])
        if err or len(out) < expected:
            raise _Abort(R_FRAMING, quiet_from=last)
        rec.command_us = (frame_end - preamble_end) / US
        faults = self._take_faults()
        rec.faults = faults

        # ---- 5. execute: the carrier must hold exec_min, end before exec_max
        pr = self.profile
        t_min = frame_end + (pr.exec_min_us - TOL_US) * US
        t_max = frame_end + (pr.exec_max_us + TOL_US) * US
        response = None
        handled = False
        while self._pending:                   # never expected; stay exact
            last = self._pending.popleft()
        while True:
            t = await self._execute_edge()
            if t is None:
                break
            last = t
            if not handled and last >= t_min:
                # enough energy banked: the firmware executes the command
                response = self.logic.handle(rec.frame)
                handled = True
        self._last_edge = last
        stop = last + per
        rec.execute_us = (stop - frame_end) / US
        if not handled:
            raise _Abort(R_EXEC_SHORT, quiet_from=last)
        if last > t_max:
            # The command did execute, but such firmware (v15 past 4.5 ms)
            # starts its answer while the host still drives: modelled as no
            # answer at all.
            rec.reason = R_EXEC_LONG
        elif response is None:
            rec.reason = self.logic.log[-1].reason
        elif faults.no_response:
            rec.reason = R_FAULT_SILENT
        if rec.reason:
            self.log.append(rec)
            return

        # ---- 6. answer in the host's listen window --------------------------
        data = faults.wire_bytes(response)
        t0 = max(int(round(stop + faults.response_delay_us * US)), self._now() + 1)
        events = response_events(data, faults, t0)
        rec.response = data
        rec.reason = R_ANSWERED
        rec.response_start_ps = t0
        rec.response_end_ps = events[-1][0]
        # logged before it is played, so a test that sees the host's result
        # finds the record even when the answer overruns the listen window
        self.log.append(rec)
        await self._play(events, rec)

    async def _play(self, events, rec: Transaction):
        """Drive the precomputed events at their absolute times."""
        now = self._now()
        for t, o, oe in events:
            if t > now:
                await Timer(t - now, unit="ps")
                now = t
            self._o.value = o
            self._oe.value = oe
            if self._host_oe is not None and oe and not rec.collision:
                if str(self._host_oe.value) == "1":
                    rec.collision = True
        if self._file is not None:
            self._skip_log()
