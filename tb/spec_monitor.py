"""Independent checker of the host's line behaviour against SRI-2WIRE-IRD rev E.

This module deliberately shares nothing with the RTL or with the peripheral model:
it carries its own copy of the host timing table (spec section 4) and re-derives
every phase from the two host pins alone (``line_oe``, ``line_o``). The only
import from the project is ``checksum`` (the one agreed checksum helper).

Two layers:

* ``SpecChecker`` - pure Python, fed with pin changes ``feed(t_ps, oe, o)``. It
  is unit-tested without a simulator (``tb/test_spec_monitor.py``).
* ``SpecMonitor`` - a thin cocotb 2.x wrapper that feeds the checker from the
  pin-change log the test bench's ``tb_line`` writes (read in bulk, nothing
  per edge or per clock), or from the pins' value-change callbacks.

Measurement definitions (times are kept in picoseconds, reported in us):

* Host drive state: Z when ``oe`` = 0, else the level of ``o``. Changes in the
  same time step are coalesced: only the state left when simulation time
  advances counts, so a zero-width intermediate state (``o`` and ``oe``
  falling in the same step but seen by two callbacks) is never a runt or a
  phase.
* Carrier burst: high halves separated by driven-low halves shorter than
  ``LOW_SPLIT_PS``. Its length is ``last rise - first rise + mean period``
  (mean period = (last rise - first rise) / (rises - 1)): the burst ends where
  its next rising edge would have been. Its last low half cannot be told from
  the "no signal" after it, so this is exact both for a burst that ends after
  a full period and for one released right after its last high half.
* charge = length of the burst before the sync (with idle charge it includes
  the idle carrier); sync = preamble's first rise - charge end; preamble =
  preamble burst length, i.e. up to ``t0`` where the first start bit begins;
  command = nbits x bit time; execute = end of the burst carrying the last
  stop bits - (t0 + nbits x bit time); listen = Z time (oe fall to the next
  oe rise); turnaround = first rising edge after the end of listen - end of
  listen (the carrier must stay off throughout). The end of listen is the
  host's drive coming back (driven 0, as this core does); a host that stayed
  released from listen into the turnaround would merge the two and read as
  a turnaround of 0, a false alarm, never a missed breach.
* Bit time: least-squares slope, through ``t0``, of every frame edge against
  its bit index; indices are assigned progressively (byte 0 first) so that
  rates well off nominal still decode. Every frame edge must lie within
  ``EDGE_TOL_PS`` of ``t0 + n x bit time``. Bits are sampled mid-bit.
* Carrier: every period (rise to rise) must be 0.90-1.10 MHz and every high
  half 45-60 % of its period (a burst's last high half is judged against its
  mean period, so a high half cut short by a release is caught). A lone pulse
  or a burst of fewer than ``MIN_BURST_PERIODS`` periods is a runt.

Tolerance: the bench clock is rounded to 1 ps (12 MHz -> 83.334 ns, 8 ppm
slow), so every window limit is widened by ``REL_TOL`` = 100 ppm relative (e.g.
sync 899.91-1100.11 us, duty 44.9955-60.006 %) and by nothing else.

Listing: a transaction enters ``transactions`` as soon as its execute phase is
over; ``complete`` turns True when its listen ends (the next oe rise). Given a
time source (the cocotb wrapper passes one), reading ``transactions`` or
``errors`` commits a pin change that is already in the past, and a running
listen shows the time listened so far - so a test that looks at the very
clock edge where the host ends the listen (before the pins move) finds it.
``turnaround_us`` is filled in at the next rising edge (None if it never
comes: not a breach).

Reset: ``reset(t)`` (``SpecMonitor.reset_seen()``) discards the transaction in
progress with every breach raised since the last commit point, so the line
release at the reset edge is no breach whether the test reports the reset just
before or just after pulsing it. Commit points: the end of a listen and the
first rising edge of every burst outside a transaction. Turnaround breaches are
committed at once. Without ``reset_seen()`` a cut transaction is a breach.

Lab mode: ``allow_out_of_spec(True)`` stops enforcing the phase-duration
windows (charge, sync, preamble, command, execute, listen, turnaround).
Structure, framing, checksum, bit rate and carrier are still enforced. A
transaction started in lab mode stays exempt up to its turnaround.

Parser limits (structural, not spec): a low or carrier run longer than
``FRAME_SCALE_PS`` (400 us, > 12 bit times) cannot be part of a command frame,
so lab-mode syncs or preambles under 400 us cannot be parsed. A transaction is
recognised by its first start bit; a charge-sync-preamble that is not followed
by a command is a breach, so an idle carrier switched off and on again within
one sync time (<= 1.1 ms off) would be reported as such. A burst that is still
running at ``finish()`` may be an idle carrier and is not a breach.
"""

from __future__ import annotations

import logging
from bisect import bisect_right
from dataclasses import dataclass, field

import cocotb
from cocotb.utils import get_sim_time

from protocol import checksum

# ---------------------------------------------------------------------------
# Our own copy of the spec's host timing table (SRI-2WIRE-IRD rev E, section 4).
# Units: microseconds, MHz, fraction, kbps.
# ---------------------------------------------------------------------------
CHARGE_MIN_US = 7000.0
SYNC_US = (900.0, 1100.0)
PREAMBLE_US = (1800.0, 2200.0)
COMMAND_US = (1000.0, 1500.0)
EXECUTE_MIN_US = 3500.0
EXECUTE_MAX_US_V16 = 10000.0  # 4500 for firmware v15: constructor argument
LISTEN_MIN_US = 2000.0
TURNAROUND_MIN_US = 2000.0
CARRIER_MHZ = (0.90, 1.10)
DUTY = (0.45, 0.60)
BIT_RATE_KBPS = (30.75, 31.75)

# Relative widening of every window limit: the bench clock is rounded to 1 ps,
# which shifts every RTL-generated duration by a few ppm. Nothing more lenient.
REL_TOL = 100e-6

# Nominal values, used only as a starting point for estimates.
NOMINAL_CARRIER_PS = 1_000_000  # 1 MHz
NOMINAL_BIT_PS = 32_000_000  # 31.25 kbps = 32 carrier periods

# Structural constants of the parser (not spec limits).
# A driven low shorter than this between two high halves is a carrier low half
# (and is judged by the period/duty checks); a longer one is a gap. Legal low
# halves are <= 0.62 us, the shortest legal gap is one bit (>= 31 us).
LOW_SPLIT_PS = 4_000_000
# A driven low of at most this long between the end of a burst and Z is the
# tail of the last carrier period, not a phase of its own.
GAP_TOL_PS = 2_000_000
# Every frame edge must be within this of an integer number of bit times.
EDGE_TOL_PS = 2_000_000
# Longest run inside a command frame is 10 bit times (<= 326 us at 30.75 kbps);
# anything longer than this is a phase (sync, preamble, execute, off).
FRAME_SCALE_PS = 400_000_000
# In lab mode a driven low between two bursts this long or shorter still counts
# as "a sync" for the missing-command check.
LAB_SYNC_MAX_PS = 10_000_000_000
# A burst shorter than this many periods cannot be a host bit (>= ~27 periods).
MIN_BURST_PERIODS = 16

Z = 2  # drive state: 0, 1 or Z

# Carrier limits in the units used on the hot path (period in ps, duty fraction).
_P_MIN = 1e6 / (CARRIER_MHZ[1] * (1 + REL_TOL))
_P_MAX = 1e6 / (CARRIER_MHZ[0] * (1 - REL_TOL))
_D_MIN = DUTY[0] * (1 - REL_TOL)
_D_MAX = DUTY[1] * (1 + REL_TOL)


def _us(ps: float) -> float:
    return ps / 1e6


def _in_window(value: float, lo: float | None, hi: float | None) -> bool:
    if lo is not None and value < lo * (1 - REL_TOL):
        return False
    if hi is not None and value > hi * (1 + REL_TOL):
        return False
    return True


@dataclass
class Transaction:
    """One host transaction as seen on the pins. Durations in microseconds."""

    start_ps: int | None  # first rising edge of the charge burst
    charge_us: float | None = None
    sync_us: float | None = None
    preamble_us: float | None = None
    command_us: float | None = None
    bit_time_us: float | None = None
    frame: list[int] = field(default_factory=list)
    execute_us: float | None = None
    listen_us: float | None = None
    turnaround_us: float | None = None  # filled when the next carrier starts
    # Carrier seen in this transaction's bursts (charge .. execute), per period.
    carrier_min_hz: float | None = None
    carrier_max_hz: float | None = None
    carrier_mean_hz: float | None = None  # over all periods of all its bursts
    duty_min: float | None = None  # fraction of the period, 0..1
    duty_max: float | None = None
    out_of_spec_allowed: bool = False  # lab mode was on
    complete: bool = False  # False: cut off (a breach is recorded) or still listening
    errors: list[str] = field(default_factory=list)

    def transcript(self) -> str:
        """Its start to the picosecond and each phase to the nanosecond, as
        the cross-simulator transcripts write them (tb/simrun.py)."""
        return f"txn {self.start_ps} {bytes(self.frame).hex()} " + " ".join(
            f"{v:.3f}" if isinstance(v, float) else str(v)
            for v in (self.charge_us, self.sync_us, self.preamble_us, self.command_us,
                      self.execute_us, self.listen_us, self.turnaround_us, self.complete))


class _Burst:
    """Running statistics of one carrier burst (no per-edge storage)."""

    __slots__ = (
        "first", "last", "fall", "n", "pmin", "pmax", "dmin", "dmax",
        "nbad_f", "nbad_d", "bad_f_t", "bad_d_t", "partial", "open", "end", "errs",
    )

    def __init__(self, t: int, partial: bool = False):
        self.first = t  # first rising edge
        self.last = t  # latest rising edge
        self.fall = None  # falling edge after `last` (None while high)
        self.n = 1  # rising edges
        self.pmin = self.pmax = None
        self.dmin = self.dmax = None
        self.nbad_f = self.nbad_d = 0
        self.bad_f_t = self.bad_d_t = None
        # partial: the burst was already running when the checker (re)started,
        # so its start and first period are unknown and it is not judged.
        self.partial = partial
        self.open = False  # still running at finish()
        self.end = None
        self.errs: list[str] = []

    def mean_period(self) -> float:
        if self.n > 1:
            return (self.last - self.first) / (self.n - 1)
        return float(NOMINAL_CARRIER_PS)


class _Seg:
    """A closed stretch of line activity: 'B' burst, 'L' driven low, 'Z' released."""

    __slots__ = ("kind", "start", "end", "burst", "nxt")

    def __init__(self, kind, start, end, burst=None, nxt=None):
        self.kind = kind
        self.start = start
        self.end = end
        self.burst = burst
        self.nxt = nxt  # what ended it: 'B' (a rise), 'L', 'Z', None (finish)

    def dur(self) -> float:
        return self.end - self.start

    def __repr__(self):
        return f"_Seg({self.kind}, {_us(self.start):.3f}, {_us(self.end):.3f} us, nxt={self.nxt})"


_PRE, _FRAME, _LISTEN = "pre", "frame", "listen"


class SpecChecker:
    """Parses host pin changes into transactions and records every breach."""

    def __init__(self, execute_max_us: float = EXECUTE_MAX_US_V16, log: logging.Logger | None = None,
                 now=None):
        """`now`: optional callable returning the current time in ps. Pin changes
        are committed only once time has moved past them (coalescing), so
        without it the last change before a quiet stretch (e.g. the end of a
        listen) would stay pending until the next change; with it, reading
        `transactions` or `errors` commits whatever is already final."""
        self.execute_max_us = float(execute_max_us)
        self.log = log or logging.getLogger(__name__)
        self._now = now
        self._transactions: list[Transaction] = []
        self._committed: list[str] = []
        self._prov: list[str] = []  # breaches that a reset may still discard
        self._lab = False
        self._finished = False
        # pin-change coalescing
        self._pend_t = None
        self._pend_s = None
        # level 1: drive state -> segments
        self._state = None
        self._burst: _Burst | None = None
        self._low_start = None
        self._z_start = None
        # level 2: segments -> transactions
        self._mode = _PRE
        self._pre: list[_Seg] = []
        self._txn: Transaction | None = None
        self._region: list[_Seg] = []
        self._txn_bursts: list[_Burst] = []
        self._listen_start = None
        self._last_txn: Transaction | None = None
        self._await_ta = None  # end of the last listen, until the next rise
        self._ta_suppressed = False

    # ------------------------------------------------------------------ API
    @property
    def transactions(self) -> list[Transaction]:
        """Every transaction seen, oldest first. One is listed as soon as its
        execute phase is over; while its listen runs, `complete` is False and
        (given `now`) `listen_us` is the time listened so far."""
        self._flush()
        if self._mode == _LISTEN and self._now is not None:
            self._txn.listen_us = _us(int(self._now()) - self._listen_start)
        return self._transactions

    @property
    def errors(self) -> list[str]:
        """Every breach so far (including those a reset may still discard)."""
        self._flush()
        return self._committed + self._prov

    def _flush(self) -> None:
        if self._now is not None and self._pend_t is not None and not self._finished:
            t = int(self._now())
            if t > self._pend_t:
                self._commit(self._pend_t, self._pend_s)
                self._pend_t = None

    def allow_out_of_spec(self, flag: bool) -> None:
        self._lab = bool(flag)

    def feed(self, t_ps: int, oe, o) -> None:
        """One pin change. Only the last call of a time step counts."""
        if self._finished:
            return
        t = int(t_ps)
        s = (1 if o else 0) if oe else Z
        if self._pend_t is not None:
            if t == self._pend_t:
                self._pend_s = s
                return
            if t < self._pend_t:
                raise ValueError(f"time went backwards: {t} < {self._pend_t}")
            self._commit(self._pend_t, self._pend_s)
        self._pend_t, self._pend_s = t, s

    def reset(self, t_ps: int) -> None:
        """The host was reset: drop the transaction in progress, restart parsing."""
        t = int(t_ps)
        if self._pend_t is not None and self._pend_t < t:
            self._commit(self._pend_t, self._pend_s)
            self._pend_t = None
        if self._prov:
            self.log.info("spec monitor: reset at %.3f us discards %d breach(es) of the "
                          "interrupted transaction", _us(t), len(self._prov))
        self._prov = []
        if self._mode == _LISTEN:  # already listed: the transaction is discarded
            self._transactions.remove(self._txn)
        self._mode = _PRE
        self._pre = []
        self._txn = None
        self._region = []
        self._txn_bursts = []
        self._listen_start = None
        self._await_ta = None  # an interrupted turnaround is neither measured nor checked
        self._ta_suppressed = False
        self._restart_level1(t, self._state)

    def finish(self, t_ps: int) -> None:
        """End of observation: close the last transaction."""
        if self._finished:
            return
        t = int(t_ps)
        if self._pend_t is not None:
            self._commit(self._pend_t, self._pend_s)
            self._pend_t = None
        self._finished = True
        b = self._burst
        if b is not None and self._state == 0 and t - b.fall >= LOW_SPLIT_PS:
            # the burst is over (closed lazily until now); a gap is running
            self._close_burst(t, "L")
            self._emit(_Seg("L", b.end, max(t, b.end), nxt=None))
        elif b is not None:
            b.open = True
            self._close_burst(max(t, b.last), None)
        elif self._state == 0:
            self._emit(_Seg("L", self._low_start, t, nxt=None))
        elif self._state == Z:
            self._emit(_Seg("Z", self._z_start, t, nxt=None))
        self._l2_finish(t)

    # ------------------------------------------------------------ errors
    def _error(self, t: float, msg: str, txn: Transaction | None = None, burst: _Burst | None = None) -> None:
        s = f"t={_us(t):.3f} us: {msg}"
        self._prov.append(s)
        if txn is not None:
            txn.errors.append(s)
        if burst is not None:
            burst.errs.append(s)
        self.log.error("spec breach: %s", s)

    def _commit_errors(self) -> None:
        if self._prov:
            self._committed.extend(self._prov)
            self._prov = []

    def _enforce(self, txn: Transaction | None = None) -> bool:
        return not (self._lab or (txn is not None and txn.out_of_spec_allowed))

    def _window(self, t, txn, name, value_us, lo, hi) -> None:
        if value_us is None or not self._enforce(txn):
            return
        if not _in_window(value_us, lo, None):
            self._error(t, f"{name} {value_us:.3f} us < {lo:g} us min", txn)
        elif not _in_window(value_us, None, hi):
            self._error(t, f"{name} {value_us:.3f} us > {hi:g} us max", txn)

    # ------------------------------------------------------- level 1
    def _commit(self, t: int, s: int) -> None:
        prev = self._state
        if s == prev:
            return
        if prev is None:  # first observation
            self._state = s
            self._restart_level1(t, s)
            return
        self._state = s
        if s == 1:
            self._on_rise(t, prev)
        elif s == 0:
            if prev == 1:
                self._burst.fall = t
            else:  # Z -> driven low
                self._emit(_Seg("Z", self._z_start, t, nxt="L"))
                self._low_start = t
        else:
            self._on_release(t, prev)

    def _restart_level1(self, t: int, s) -> None:
        """Start segmenting afresh at t with the line in state s."""
        self._burst = None
        self._low_start = self._z_start = None
        if s == Z:
            self._z_start = t
        elif s == 1:
            self._burst = _Burst(t, partial=True)
        elif s == 0:
            # We may be in a carrier low half or a gap: a partial burst covers
            # both (a long low closes it as a gap, a short one continues it).
            b = _Burst(t, partial=True)
            b.fall = t
            self._burst = b

    def _on_rise(self, t: int, prev: int) -> None:
        b = self._burst
        if b is not None and prev == 0 and t - b.fall < LOW_SPLIT_PS:
            # Next carrier period of the running burst: check it.
            p = t - b.last
            judge = not (b.partial and b.n == 1)  # first period of a partial burst is unknown
            if judge:
                if b.pmin is None or p < b.pmin:
                    b.pmin = p
                if b.pmax is None or p > b.pmax:
                    b.pmax = p
                if p < _P_MIN or p > _P_MAX:
                    b.nbad_f += 1
                    if b.bad_f_t is None:
                        b.bad_f_t = b.last
                d = (b.fall - b.last) / p
                if b.dmin is None or d < b.dmin:
                    b.dmin = d
                if b.dmax is None or d > b.dmax:
                    b.dmax = d
                if d < _D_MIN or d > _D_MAX:
                    b.nbad_d += 1
                    if b.bad_d_t is None:
                        b.bad_d_t = b.last
            b.last = t
            b.fall = None
            b.n += 1
            return
        if b is not None:  # the low since the last fall was a gap
            self._close_burst(t, "L")
            self._emit(_Seg("L", b.end, t, nxt="B"))
        elif prev == Z:
            self._emit(_Seg("Z", self._z_start, t, nxt="B"))
        elif prev == 0:
            self._emit(_Seg("L", self._low_start, t, nxt="B"))
        self._burst = _Burst(t)
        self._l2_burst_start(t)

    def _on_release(self, t: int, prev: int) -> None:
        b = self._burst
        if b is not None:
            if prev == 1:
                b.fall = t  # the last high half ends at the release
                self._close_burst(t, "Z")
            else:
                trailing = t - (b.last + b.mean_period()) > GAP_TOL_PS
                self._close_burst(t, "L" if trailing else "Z")
                if trailing:
                    self._emit(_Seg("L", b.end, t, nxt="Z"))
        elif prev == 0:
            self._emit(_Seg("L", self._low_start, t, nxt="Z"))
        self._z_start = t
        self._l2_z_start(t)

    def _close_burst(self, t: int, nxt) -> None:
        """Finish a burst's statistics, report its carrier breaches, emit it."""
        b = self._burst
        self._burst = None
        mean = b.mean_period()
        b.end = b.last + mean
        if not b.partial or b.n > 1:
            if b.fall is not None and b.n > 1 and not b.partial:
                # last high half, judged against the burst's mean period
                d = (b.fall - b.last) / mean
                b.dmin = d if b.dmin is None else min(b.dmin, d)
                b.dmax = d if b.dmax is None else max(b.dmax, d)
                if d < _D_MIN or d > _D_MAX:
                    b.nbad_d += 1
                    if b.bad_d_t is None:
                        b.bad_d_t = b.last
            where = f"carrier burst starting at {_us(b.first):.3f} us"
            if b.nbad_f:
                self._error(b.bad_f_t, (
                    f"{where}: {b.nbad_f} period(s) outside {CARRIER_MHZ[0]:.2f}-{CARRIER_MHZ[1]:.2f} MHz "
                    f"(seen {1e6 / b.pmax:.4f}-{1e6 / b.pmin:.4f} MHz)"), burst=b)
            if b.nbad_d:
                self._error(b.bad_d_t, (
                    f"{where}: {b.nbad_d} high half/halves outside duty {DUTY[0] * 100:.0f}-{DUTY[1] * 100:.0f} % "
                    f"(seen {b.dmin * 100:.2f}-{b.dmax * 100:.2f} %) - runt or bad duty"), burst=b)
        if not b.partial and not b.open:
            if b.n == 1:
                high = (b.fall if b.fall is not None else t) - b.first
                self._error(b.first, f"isolated pulse of {high / 1e3:.1f} ns (runt, not a carrier burst)", burst=b)
            elif b.n < MIN_BURST_PERIODS:
                self._error(b.first, f"runt carrier burst of {b.n} periods ({_us(b.end - b.first):.3f} us), "
                            "shorter than half a bit", burst=b)
        self._emit(_Seg("B", b.first, b.end, burst=b, nxt=nxt))

    # ------------------------------------------------------- level 2
    def _emit(self, seg: _Seg) -> None:
        if self._mode == _PRE:
            self._pre_seg(seg)
        elif self._mode == _FRAME:
            if seg.kind == "L" and seg.dur() > FRAME_SCALE_PS:
                self._end_frame("low", seg.start)
                self._pre_seg(seg)
            else:
                self._region.append(seg)
        else:  # _LISTEN: the only thing that can close is the listen's Z
            self._end_listen(seg)

    def _l2_burst_start(self, t: int) -> None:
        if self._mode != _PRE:
            return
        self._commit_errors()
        if self._await_ta is not None:
            txn = self._last_txn
            ta = _us(t - self._await_ta)
            txn.turnaround_us = ta
            self._await_ta = None
            if not self._ta_suppressed and self._enforce(txn):
                if not _in_window(ta, TURNAROUND_MIN_US, None):
                    self._error(t, f"turnaround (carrier off after listen) {ta:.3f} us < "
                                f"{TURNAROUND_MIN_US:g} us", txn)
            self._ta_suppressed = False
            self._commit_errors()

    def _l2_z_start(self, t: int) -> None:
        if self._mode == _FRAME:
            self._end_frame("Z", t)

    def _sync_like(self, seg: _Seg) -> bool:
        if seg.kind != "L" or seg.nxt != "B" or seg.dur() <= FRAME_SCALE_PS:
            return False
        if self._lab:
            return seg.dur() <= LAB_SYNC_MAX_PS
        return _us(seg.dur()) <= SYNC_US[1] * (1 + REL_TOL)

    def _preamble_pattern(self, segs: list[_Seg]) -> bool:
        """segs ends in burst, sync-like low, burst: a transaction has begun."""
        if len(segs) < 3:
            return False
        b1, low, b2 = segs[-3], segs[-2], segs[-1]

        def real(seg):  # a burst that can be a phase (not partial, not a runt)
            return seg.kind == "B" and not seg.burst.partial and seg.burst.n >= MIN_BURST_PERIODS

        return real(b1) and self._sync_like(low) and real(b2)

    def _pre_seg(self, seg: _Seg) -> None:
        pre = self._pre
        pre.append(seg)
        if len(pre) > 16:
            del pre[0]
        if seg.kind == "L" and len(pre) >= 2 and pre[-2].kind == "B":
            if seg.dur() <= FRAME_SCALE_PS and (seg.nxt == "B" or self._preamble_pattern(pre[:-1])):
                self._begin_frame()
                return
            if seg.dur() > FRAME_SCALE_PS and self._preamble_pattern(pre[:-1]):
                self._error(seg.start, "charge, sync and preamble were sent but no command followed "
                            "(line went low)")
        elif seg.kind == "B" and seg.nxt == "Z" and self._preamble_pattern(pre):
            self._error(seg.end, "charge, sync and preamble were sent but no command followed "
                        "(line released)")

    def _begin_frame(self) -> None:
        pre = self._pre
        l0, bp = pre[-1], pre[-2]
        t0 = l0.start
        # Walk back over the gap before the preamble to the charge burst.
        gaps = []
        i = len(pre) - 3
        while i >= 0 and pre[i].kind != "B":
            gaps.append(pre[i])
            i -= 1
        bc = pre[i].burst if i >= 0 else None
        txn = Transaction(start_ps=bc.first if bc is not None else bp.first, out_of_spec_allowed=self._lab)
        self._txn = txn
        self._txn_bursts = [b for b in (bc, bp.burst) if b is not None]
        for b in self._txn_bursts:
            txn.errors.extend(b.errs)
        if bp.burst.partial:
            self._error(bp.start, "preamble already running at reset/monitor start: "
                        "host did not release the line", txn)
        else:
            txn.preamble_us = _us(t0 - bp.start)
        if bc is None:
            self._error(bp.start, "no charge burst before the sync/preamble", txn)
        else:
            txn.sync_us = _us(bp.start - bc.end)
            if bc.partial:
                self._error(bc.first, "charge already running at reset/monitor start: "
                            "host did not release the line", txn)
            else:
                txn.charge_us = _us(bc.end - bc.first)
        for g in gaps:
            if g.kind == "Z":
                self._error(g.start, "host released the line (Z) during the sync", txn)
                break
        self._window(bc.first if bc else bp.start, txn, "charge", txn.charge_us, CHARGE_MIN_US, None)
        self._window(bp.start, txn, "sync", txn.sync_us, *SYNC_US)
        self._window(t0, txn, "preamble", txn.preamble_us, *PREAMBLE_US)
        self._region = [l0]
        self._mode = _FRAME
        self._pre = []

    def _end_frame(self, reason: str, t: float) -> None:
        """The line left the command/execute stretch: decode and judge it.

        The transaction is listed from here on (its listen is still to come)
        so that a test reading `transactions` at the very clock edge the
        listen ends - before the pins have moved - already finds it.
        """
        txn = self._txn
        ok = self._decode(txn, self._region, reason)
        self._region = []
        bs = [b for b in self._txn_bursts if not b.partial and b.pmin is not None]
        if bs:
            txn.carrier_min_hz = 1e12 / max(b.pmax for b in bs)
            txn.carrier_max_hz = 1e12 / min(b.pmin for b in bs)
            txn.carrier_mean_hz = 1e12 * sum(b.n - 1 for b in bs) / sum(b.last - b.first for b in bs)
            txn.duty_min = min(b.dmin for b in bs)
            txn.duty_max = max(b.dmax for b in bs)
        self._transactions.append(txn)
        if reason == "Z":
            self._mode = _LISTEN
            self._listen_start = t
        elif reason == "low":
            if ok:
                self._error(t, "no listen phase: host drove the line low instead of releasing it", txn)
            self._complete(txn, False, t)
        else:  # finish
            if ok:
                self._error(t, "transaction cut off during execute (no listen phase)", txn)
            self._complete(txn, False, None)

    @staticmethod
    def _fit_bit_time(t0: int, times: list[int], t_init: float, max_index: int) -> float:
        """Progressive least-squares bit time through t0 (see module doc)."""
        tb = t_init
        num = 0.0
        den = 0
        for t in times:
            n = max(1, round((t - t0) / tb))
            if n > max_index:
                break
            num += n * (t - t0)
            den += n * n
            tb = num / den
        return tb

    def _decode(self, txn: Transaction, region: list[_Seg], reason: str) -> bool:
        """Decode the command frame; returns True if it was complete."""
        t0 = region[0].start
        times = [s.start for s in region[1:]]
        levels = [1 if s.kind == "B" else 0 for s in region[1:]]
        last = region[-1]
        covered = last.end
        for s in region:
            if s.kind == "B":
                self._txn_bursts.append(s.burst)
                txn.errors.extend(s.burst.errs)

        def level_at(x: float):
            if x >= covered:
                return None
            i = bisect_right(times, x)
            return 0 if i == 0 else levels[i - 1]

        # Byte 0 decides the frame length: fit on its edges first.
        tb = self._fit_bit_time(t0, times, NOMINAL_BIT_PS, 11)
        b0 = [level_at(t0 + (i + 0.5) * tb) for i in range(1, 9)]
        nbytes = 3
        if None not in b0 and b0[7] == 1:
            nbytes = 4
        nbits = 11 * nbytes
        tb = self._fit_bit_time(t0, times, tb, nbits - 1)
        txn.bit_time_us = _us(tb)
        kbps = 1e9 / tb
        if not _in_window(kbps, *BIT_RATE_KBPS):
            self._error(t0, f"bit rate {kbps:.3f} kbps (bit {_us(tb):.3f} us) outside "
                        f"{BIT_RATE_KBPS[0]}-{BIT_RATE_KBPS[1]} kbps", txn)
        frame_end = t0 + nbits * tb

        # Every edge inside the frame must sit on the bit grid.
        for t in times:
            n = round((t - t0) / tb)
            if n >= nbits:
                break  # after the frame: judged below
            off = t - (t0 + n * tb)
            if abs(off) > EDGE_TOL_PS:
                self._error(t, f"command edge {_us(off):+.3f} us off the bit grid (bit {n})", txn)

        bits = []
        for i in range(nbits):
            lv = level_at(t0 + (i + 0.5) * tb)
            if lv is None:
                break
            bits.append(lv)
        frame = []
        for k in range(len(bits) // 11):
            bb = bits[11 * k: 11 * k + 11]
            if bb[0] != 0:
                self._error(t0 + 11 * k * tb, f"byte {k}: start bit is 1", txn)
            if bb[9] != 1 or bb[10] != 1:
                self._error(t0 + (11 * k + 9) * tb, f"byte {k}: stop bits {bb[9]}{bb[10]}, expected 11", txn)
            frame.append(sum(bit << j for j, bit in enumerate(bb[1:9])))
        txn.frame = frame
        if len(bits) < nbits:
            self._error(covered, f"transaction cut off during the command after {len(bits)} of {nbits} bits",
                        txn)
            return False
        txn.command_us = _us(nbits * tb)
        self._window(t0, txn, "command", txn.command_us, *COMMAND_US)
        if checksum(frame[:-1]) != frame[-1]:
            self._error(frame_end, "bad checksum: frame " + " ".join(f"{b:02X}" for b in frame)
                        + f" (expected {checksum(frame[:-1]):02X})", txn)

        # The burst carrying the stop bits runs on as the execute phase.
        i = bisect_right([s.start for s in region], frame_end - tb / 2) - 1
        bf = region[i] if region[i].kind == "B" else None
        if bf is None:
            self._error(frame_end, "no execute carrier after the command", txn)
            return True
        if bf.nxt is None:  # still running at finish
            txn.execute_us = None
            self._error(frame_end, "transaction cut off during execute", txn)
            return False
        txn.execute_us = _us(bf.end - frame_end)
        self._window(frame_end, txn, "execute", txn.execute_us, EXECUTE_MIN_US, self.execute_max_us)
        rest = region[i + 1:]
        if reason == "Z" and len(rest) == 1 and rest[0].kind == "L":
            self._error(rest[0].start, f"host drove the line low for {_us(rest[0].dur()):.3f} us between "
                        "execute and listen", txn)
        elif rest:
            self._error(rest[0].start, f"carrier interrupted {_us(rest[0].start - frame_end):.3f} us after "
                        "the command (during execute)", txn)
        return True

    def _end_listen(self, seg: _Seg) -> None:
        txn = self._txn
        listen = _us(seg.dur())
        txn.listen_us = listen
        if seg.nxt is None:  # still listening at finish
            if self._enforce(txn) and not _in_window(listen, LISTEN_MIN_US, None):
                self._error(seg.end, f"transaction cut off during listen after {listen:.3f} us", txn)
                self._complete(txn, False, None)
            else:
                self._complete(txn, True, None)
            return
        if self._enforce(txn) and not _in_window(listen, LISTEN_MIN_US, None):
            if seg.nxt == "B":
                self._error(seg.end, f"carrier during listen: host started the carrier {listen:.3f} us "
                            f"into the listen phase (min {LISTEN_MIN_US:g} us)", txn)
                self._ta_suppressed = True  # the same breach, reported once
            else:
                self._error(seg.end, f"listen {listen:.3f} us < {LISTEN_MIN_US:g} us "
                            "(host drove the line)", txn)
        self._complete(txn, True, seg.end)

    def _complete(self, txn: Transaction, complete: bool, listen_end) -> None:
        txn.complete = complete
        self._last_txn = txn
        self._txn = None
        self._txn_bursts = []
        self._mode = _PRE
        self._pre = []
        self._listen_start = None
        self._await_ta = listen_end
        self._commit_errors()

    def _l2_finish(self, t: int) -> None:
        if self._mode == _FRAME:
            self._end_frame("finish", t)
        elif self._mode == _PRE:
            pre = self._pre
            if pre and pre[-1].kind == "B" and pre[-1].nxt is None and self._preamble_pattern(pre):
                self._error(t, "transaction cut off during the preamble")
        # _LISTEN was closed by the open Z segment emitted by finish()


# ---------------------------------------------------------------------------
# cocotb wrapper
# ---------------------------------------------------------------------------
class SpecMonitor:
    """Feeds a SpecChecker from the host pins of the test-bench top.

    With ``pin_log`` (the file a ``tb_line`` with that PIN_LOG writes: one
    line "<ps> <oe> <o>" per change of the host's drive), the pin changes are
    read from the file in bulk whenever the checker is looked at (``checker``,
    ``transactions``, ``errors``, ``check``, ``reset_seen``,
    ``allow_out_of_spec``, ``finish``), so nothing wakes Python on a carrier
    edge. The file is written by the simulator in the same time step as each
    change and flushed, so a read sees every change up to now. Without it,
    two coroutines wait on the value-change trigger of ``line_o`` and
    ``line_oe`` and sample both pins (one Python wake-up per pin edge). Either
    way the checker coalesces changes that happen in the same time step.
    """

    def __init__(self, dut, execute_max_us: float = EXECUTE_MAX_US_V16, name: str = "spec_monitor",
                 pin_log: str | None = None):
        self._dut = dut
        self._o = dut.line_o
        self._oe = dut.line_oe
        self.log = logging.getLogger(f"cocotb.{name}")
        self._checker = SpecChecker(execute_max_us=execute_max_us, log=self.log, now=self._now)
        self._tasks = []
        self._pin_log = pin_log
        self._file = None        # open while the monitor follows the file
        self._partial = ""       # a line the simulator has not finished writing

    @property
    def checker(self) -> SpecChecker:
        self._drain()
        return self._checker

    @property
    def transactions(self) -> list[Transaction]:
        return self.checker.transactions

    @property
    def errors(self) -> list[str]:
        return self.checker.errors

    def _now(self) -> int:
        return round(get_sim_time("ps"))

    def _sample(self) -> None:
        # Anything but a clean 1 (X/Z before reset) counts as 0.
        self._checker.feed(self._now(), str(self._oe.value) == "1", str(self._o.value) == "1")

    def _read_lines(self) -> list[str]:
        text = self._partial + self._file.read()
        lines = text.split("\n")
        self._partial = lines.pop()
        return lines

    def _drain(self) -> None:
        """Feed the checker every pin change logged since the last drain."""
        if self._file is None:
            return
        feed = self._checker.feed
        for line in self._read_lines():
            t, oe, o = line.split()
            feed(int(t), oe == "1", o == "1")

    async def _watch(self, sig) -> None:
        trigger = sig.value_change
        sample = self._sample
        while True:
            await trigger
            sample()

    def start(self) -> None:
        if self._tasks or self._file is not None:
            return
        if self._pin_log is not None:
            self._file = open(self._pin_log)
            self._read_lines()  # changes before the start are not observed
        self._sample()  # the state the line starts in
        if self._file is None:
            self._tasks = [cocotb.start_soon(self._watch(self._o)), cocotb.start_soon(self._watch(self._oe))]

    def stop(self) -> None:
        self._drain()
        if self._file is not None:
            self._file.close()
            self._file = None
        for task in self._tasks:
            task.cancel()
        self._tasks = []

    def reset_seen(self) -> None:
        """The test pulses reset: discard the transaction in progress."""
        self.checker.reset(self._now())

    def allow_out_of_spec(self, flag: bool) -> None:
        """Lab mode: phase-duration windows are not enforced (see module doc)."""
        self.checker.allow_out_of_spec(flag)

    def check(self) -> None:
        """Raise AssertionError listing every breach so far."""
        errs = self.checker.errors
        if errs:
            raise AssertionError(f"{len(errs)} 2-wire spec breach(es):\n  " + "\n  ".join(errs))

    def finish(self) -> None:
        """Stop observing, close the last transaction and check."""
        self.stop()
        self._checker.finish(self._now())
        self.check()
