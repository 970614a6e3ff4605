"""Constrained-random regression on the bus-attached core (tb/tb_core.v).

Three channel agents run at once, one per 2-wire line, each with its own
peripheral model and spec monitor (as tb/coretb.py attaches them). Every
command an agent pushes carries an expectation written down *before* the
push: status from the command, the device profile, the timing and the fault
the model was told to inject; the answer's data from the model's own log.
One collector, woken by the core's `irq`, pops every result and checks it
against the channel's oldest expectation, so per-channel order is checked as
a side effect.

Stimulus is random but steered by the functional coverage (cocotb-coverage):
while a bin is unhit, the generators prefer choices that hit it. Everything
comes from random.Random instances seeded from one number (TWH_SEED), and the
simulation has no wall-clock input, so a seed replays exactly.

Global operations (FLUSH, CTRL.ENABLE) would cancel the other agents'
queued commands unpredictably, so a flush event first pauses every agent at
a command boundary (Coordinator), then runs with all channels idle.
"""
from __future__ import annotations

import math
import os
import random
import types
from collections import deque
from dataclasses import dataclass, field
from pathlib import Path
from typing import List, Optional

import cocotb
from cocotb.simtime import get_sim_time
from cocotb.triggers import Event, FallingEdge, Lock, RisingEdge, SimTimeoutError, with_timeout
from cocotb_coverage.coverage import CoverCross, CoverPoint, coverage_db

import periph_model as pm
import profiles
import protocol as p
from coretb import FACTORY_KEY, CoreTB
from periph_model import Faults, PeripheralModel
from spec_monitor import SpecMonitor

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_SEED = 20240611
# agent commands, both bus variants together (a flush event adds a few):
# enough to hit every bin with the default seed and most others, ~75 s of CPU
DEFAULT_N = 30

# ============================================================ the vocabulary
STATUS_NAMES = ["OK", "NO_RESPONSE", "BAD_CHECKSUM", "FRAMING", "SHORT_RESPONSE",
                "LINE_STUCK_LOW", "LINE_STUCK_HIGH", "BLOCKED", "CANCELLED"]
ST = {n: i for i, n in enumerate(STATUS_NAMES)}
assert all(int(p.Status[n]) == i for n, i in ST.items()), "status codes moved"
LINK_ERRORS = {ST[n] for n in ("BAD_CHECKSUM", "FRAMING", "SHORT_RESPONSE",
                               "LINE_STUCK_LOW", "LINE_STUCK_HIGH")}
# statuses an agent can aim at; CANCELLED only comes from a flush event
AGENT_STATUSES = STATUS_NAMES[:8]

CMD_CLASSES = ["CONFIG", "FIRMWARE", "REF_VOLTAGE", "TEMPERATURE", "O2_VOLTAGE",
               "FIND_FREE", "READ", "ERASE", "WRITE", "RESERVED"]
CONST_CMDS = {"CONFIG": 0x40, "FIRMWARE": 0x41, "REF_VOLTAGE": 0x42,
              "TEMPERATURE": 0x43, "O2_VOLTAGE": 0x44}
RESERVED_CODES = [c for c in range(0x80) if p.command_name(c) == "RESERVED"]
# Command variants worth a bin of their own (see docs/random.md).
SPECIALS = ["erase_factory_blocked", "write_factory_blocked", "factory_unlocked",
            "out_of_range", "addr_bit8", "write_addr_bits_8_7", "payload_msb_ignored"]

PROFILE_NAMES = list(profiles.PROFILES)

# Phase windows in us: (lowest legal, highest legal). Charge, listen and
# turnaround have no spec maximum; 65535 is the register's largest value.
WINDOWS = {"charge": (7000, 65535), "sync": (900, 1100), "preamble": (1800, 2200),
           "execute": (3500, 10000), "listen": (2000, 65535), "turnaround": (2000, 65535)}
PHASES = list(WINDOWS)
OPEN_ENDED = ("charge", "listen", "turnaround")
# "inside" draws for the open-ended phases stay short: each ms costs ~50 ms
# of wall time per channel, more while the carrier runs
INSIDE_OPEN_SPAN = {"charge": 1500, "listen": 1000, "turnaround": 1000}
CORNERS = [f"{ph}:{k}" for ph in PHASES for k in ("min", "inside", "max")]
REFUSALS = [f"{ph}:{side}" for ph in PHASES for side in ("below", "above")
            if not (side == "above" and ph in OPEN_ENDED)]


@dataclass(frozen=True)
class FaultKind:
    """One way the line or the peripheral misbehaves.

    status: what the core must report when the command is one the device
    answers (for a silent command every model fault reads NO_RESPONSE);
    make(timing) builds the model's Faults; stuck is the level of a stuck
    line (None: the line works)."""
    name: str
    status: str
    kwargs: dict = field(default_factory=dict)
    stuck: Optional[int] = None

    def make(self, timing) -> Faults:
        if self.name == "late_in_window":
            # ends 20 us before the host's listen window closes: a later
            # answer would overlap the turnaround the host drives
            f = Faults()
            return Faults(response_delay_us=timing["listen"] - f.response_duration_us(3) - 20)
        return Faults(**self.kwargs)


FAULT_KINDS = [
    FaultKind("none", "OK"),
    FaultKind("no_response", "NO_RESPONSE", dict(no_response=True)),
    FaultKind("bad_checksum", "BAD_CHECKSUM", dict(bad_checksum=True)),
    FaultKind("bad_stop_bit_0", "FRAMING", dict(bad_stop_bit=0)),
    FaultKind("bad_stop_bit_1", "FRAMING", dict(bad_stop_bit=1)),
    FaultKind("bad_stop_bit_2", "FRAMING", dict(bad_stop_bit=2)),
    FaultKind("truncate_1", "SHORT_RESPONSE", dict(truncate=1)),
    FaultKind("truncate_2", "SHORT_RESPONSE", dict(truncate=2)),
    # Edges of what NOTES.md says the receiver must accept, several per
    # answer (test_twh_link.py::response_tolerance takes them one by one):
    # slow = 30.75 kbps on a 0.9 MHz carrier at 30 % duty; fast = 31.75 kbps,
    # 1.1 MHz, 70 %, one stop bit and a mark of just over half a bit.
    FaultKind("slow_edge", "OK", dict(baud=30750, carrier_hz=0.90e6, duty=0.3)),
    FaultKind("fast_edge", "OK", dict(baud=31750, carrier_hz=1.10e6, duty=0.7,
                                      stop_bits=1, mark_us=20)),
    FaultKind("baseband", "OK", dict(baseband=True)),
    FaultKind("late_in_window", "OK"),
    FaultKind("stuck_low", "LINE_STUCK_LOW", stuck=0),
    FaultKind("stuck_high", "LINE_STUCK_HIGH", stuck=1),
]
FAULTS = {f.name: f for f in FAULT_KINDS}
FAULT_NAMES = [f.name for f in FAULT_KINDS]


# ============================================================ coverage model
# cocotb-coverage samples through decorated functions; the bodies are empty.
COV = "twh"


@CoverPoint(f"{COV}.result.channel", xf=lambda ch, st: ch, bins=[0, 1, 2])
@CoverPoint(f"{COV}.result.status", xf=lambda ch, st: st, bins=STATUS_NAMES)
@CoverCross(f"{COV}.result.channel_x_status",
            items=[f"{COV}.result.channel", f"{COV}.result.status"])
def sample_result(ch, st):
    pass


@CoverPoint(f"{COV}.command.class", bins=CMD_CLASSES)
def sample_class(cls):
    pass


@CoverPoint(f"{COV}.command.special", bins=SPECIALS)
def sample_special(name):
    pass


# a fault counts only where it could show: on an answered command or a
# stuck line
@CoverPoint(f"{COV}.fault", bins=FAULT_NAMES)
def sample_fault(name):
    pass


@CoverPoint(f"{COV}.profile", bins=PROFILE_NAMES)
def sample_profile(name):
    pass


@CoverPoint(f"{COV}.timing.corner", xf=lambda ph, kind: f"{ph}:{kind}", bins=CORNERS)
def sample_corner(ph, kind):
    pass


@CoverPoint(f"{COV}.timing.refused", xf=lambda ph, side: f"{ph}:{side}", bins=REFUSALS)
def sample_refused(ph, side):
    pass


@CoverPoint(f"{COV}.bus.event", bins=["flush_running", "flush_disabled", "bad_channel"])
def sample_event(name):
    pass


COVER_ITEMS = ["result.channel", "result.status", "result.channel_x_status",
               "command.class", "command.special", "fault", "profile",
               "timing.corner", "timing.refused", "bus.event"]


def unhit(item) -> list:
    """Bins of one cover item (name without the 'twh.' prefix) not hit yet."""
    return [b for b, n in coverage_db[f"{COV}.{item}"].detailed_coverage.items() if n == 0]


def corner_kind(ph, value) -> str:
    lo, hi = WINDOWS[ph]
    return "min" if value == lo else "max" if value == hi else "inside"


# ============================================================ commands
@dataclass
class Command:
    cls: str
    cmd: int
    payload: int
    specials: tuple = ()
    unlock: bool = False        # FACTORY_KEY written just before the push

    @property
    def factory(self) -> bool:
        """Erase or write of words 0x00-0x1F (the core's protection rule)."""
        if self.cls == "ERASE":
            return p.decode_addr(self.cmd, self.payload) < 0x20
        if self.cls == "WRITE":
            return p.decode_write(self.cmd, self.payload)[0] < 0x20
        return False

    @property
    def blocked(self) -> bool:
        return self.factory and not self.unlock

    def answered_by(self, prof) -> bool:
        """Does a working device of this profile answer it at all?"""
        if self.cls in CONST_CMDS:
            return True
        if self.cls in ("READ", "FIND_FREE"):
            return p.decode_addr(self.cmd, self.payload) < prof.flash_size
        return False

    def model_reasons(self, prof) -> set:
        """What PeripheralModel may log for a silent command."""
        if self.cls == "RESERVED":
            return {pm.R_RESERVED}
        if self.cls == "WRITE":
            addr = p.decode_write(self.cmd, self.payload)[0]
            return {pm.R_OUT_OF_RANGE} if addr >= prof.flash_size else {pm.R_WRITTEN, pm.R_NOT_BLANK}
        addr = p.decode_addr(self.cmd, self.payload)
        if addr >= prof.flash_size:
            return {pm.R_OUT_OF_RANGE}
        return {pm.R_ERASED} if self.cls == "ERASE" else {pm.R_ANSWERED}

    def __repr__(self):
        return f"{self.cls}({self.cmd:#04x}, {self.payload:#06x}{', unlock' if self.unlock else ''})"



def pick_addr(rng, cls, prof, kind) -> int:
    """A word address of one kind: in range (above the factory area for
    erase and write), factory area 0x00-0x1F, beyond the flash, with bit 8
    set (beyond every modelled flash), or 0x80 and up (a write then carries
    address bits 8:7 in its payload)."""
    size = prof.flash_size
    lo, hi = {"in": (0x20 if cls in ("ERASE", "WRITE") else 0, size - 1),
              "factory": (0, 0x1F), "out": (size, 0x1FF), "bit8": (0x100, 0x1FF),
              "high": (0x80, 0x1FF)}[kind]
    return rng.randint(lo, hi)


def default_addr_kind(rng, cls) -> str:
    if cls in ("READ", "FIND_FREE"):
        return "in" if rng.random() < 0.85 else "out"
    return rng.choices(["in", "factory", "out"], [0.7, 0.15, 0.15])[0]


def make_command(rng, cls, prof, *, addr_kind=None, unlock=False) -> Command:
    """A random command of class `cls` for a device of profile `prof`."""
    junk = rng.getrandbits(8)
    if cls in CONST_CMDS:
        # the payload MSB is not part of a 3-byte frame: random junk there
        # must not reach the line
        payload = junk << 8 | rng.choice([p.UNUSED_PAYLOAD, 0xF0, rng.getrandbits(8)])
        return Command(cls, CONST_CMDS[cls], payload, ("payload_msb_ignored",) if junk else ())
    if cls == "RESERVED":
        return Command(cls, rng.choice(RESERVED_CODES), rng.getrandbits(16))
    kind = addr_kind or default_addr_kind(rng, cls)
    if kind == "factory" and cls not in ("ERASE", "WRITE"):
        kind = "in"
    addr = pick_addr(rng, cls, prof, kind)
    sp = []
    if addr >= prof.flash_size:
        sp.append("out_of_range")
    if cls == "WRITE":
        cmd, payload = p.write_cmd(addr, rng.getrandbits(14))
        if addr > 0x7F:
            sp.append("write_addr_bits_8_7")
    else:
        cmd, pl = p.addr_cmd({"READ": p.CMD_READ, "FIND_FREE": p.CMD_FIND_FREE,
                              "ERASE": p.CMD_ERASE}[cls], addr)
        payload = junk << 8 | pl
        if addr > 0xFF:
            sp.append("addr_bit8")
    if addr < 0x20 and cls in ("ERASE", "WRITE"):
        sp.append("factory_unlocked" if unlock else f"{cls.lower()}_factory_blocked")
    else:
        unlock = False
    return Command(cls, cmd, payload, tuple(sp), unlock)


# ============================================================ expectations
@dataclass
class Expect:
    """One pushed command and everything needed to judge its result."""
    n: int                      # running number (failure messages)
    ch: int
    tag: int
    command: Command
    status: int
    fault: str
    faults: Optional[Faults]
    profile: object
    timing: dict
    pushed_ps: int
    line: bool                  # reaches the line (not blocked or cancelled)
    model: Optional[PeripheralModel] = None
    model_index: Optional[int] = None
    monitor: Optional[SpecMonitor] = None
    mon_index: Optional[int] = None
    done: Event = field(default_factory=Event)

    def __repr__(self):
        return (f"#{self.n} ch{self.ch} tag={self.tag} {self.command!r} fault={self.fault} "
                f"profile={self.profile.name} expect {STATUS_NAMES[self.status]}")


def expected_status(command: Command, prof, fault: FaultKind, cancelled=False) -> int:
    if cancelled:
        return ST["CANCELLED"]
    if command.blocked:
        return ST["BLOCKED"]
    if fault.stuck is not None:
        return ST[fault.status]
    if not command.answered_by(prof):
        return ST["NO_RESPONSE"]
    return ST[fault.status]


def const_answer(cls, prof) -> Optional[int]:
    """What the profile says a working device answers, where that is fixed
    (an independent check of the model's answer)."""
    if cls == "CONFIG":
        msb, lsb = prof.config_response()
        return msb << 8 | lsb
    if cls == "FIRMWARE":
        return prof.fw_byte << 8 | prof.type_byte
    adc = {"REF_VOLTAGE": prof.adc_ref_voltage, "TEMPERATURE": prof.adc_temperature,
           "O2_VOLTAGE": prof.adc_o2}.get(cls)
    return None if adc is None else adc & 0xFFF


# ============================================================ pause for flush
class Coordinator:
    """Lets one agent stop the others at their next command boundary."""

    def __init__(self, n_agents):
        self.n = n_agents
        self.owner = None
        self.parked = 0
        self.finished = 0
        self.changed = Event()
        self.resume = Event()

    async def checkpoint(self, me):
        while self.owner is not None and self.owner != me:
            self.parked += 1
            self.changed.set()
            await self.resume.wait()
            self.parked -= 1

    async def stop_others(self, me):
        await self.checkpoint(me)          # someone else may hold it now
        self.owner = me
        self.resume.clear()
        while self.parked + self.finished < self.n - 1:
            self.changed.clear()
            await self.changed.wait()

    def release(self):
        self.owner = None
        self.resume.set()

    def agent_finished(self):
        self.finished += 1
        self.changed.set()


# ============================================================ the harness
@dataclass
class ChannelState:
    profile: object
    model: PeripheralModel
    monitor: SpecMonitor
    timing: dict
    tag: int = 0
    model_count: int = 0        # model.log entries expected so far
    mon_exps: list = field(default_factory=list)   # parallel to monitor.transactions
    pending: deque = field(default_factory=deque)  # pushed, result not seen yet


class RandomTB(CoreTB):
    """CoreTB with serialised bus access (several coroutines use the bus),
    agents, a collector and the checks described in the module doc."""

    def __init__(self, dut, seed, n_commands, cells=("o2_v18", "o2_v15", "co2")):
        super().__init__(dut, cells=cells)
        self.seed = seed
        self.n_commands = n_commands
        # the two bus variants of one seed draw different streams
        self.master_rng = random.Random(f"{seed}:{self.bus_kind}")
        # one stream per agent: an agent's choices do not shift when another
        # agent draws more or fewer numbers
        self.rngs = [random.Random(self.master_rng.getrandbits(64)) for _ in range(3)]
        self.flush_rng = random.Random(self.master_rng.getrandbits(64))
        self.bus_lock = Lock()    # one bus access at a time
        self.push_lock = Lock()   # pushes, FACTORY_KEY, ERRORS.BLOCKED/LINK_ERROR bookkeeping
        self.err_lock = Lock()    # ERRORS.VALUE_REFUSED/BAD_CHANNEL sequences
        self.chan: List[ChannelState] = []
        self.retired = []         # (model, monitor) pairs swapped out
        self.coord = Coordinator(3)
        self.issued = 0
        self.n_exp = 0
        self.outstanding = {"BLOCKED": 0, "LINK_ERROR": 0}
        self.claims = {}          # expensive timing corner -> agent going for it
        self.long_phases = [0, 0, 0]   # 65535 us phases per agent
        self.flush_done = False
        self.stats = types.SimpleNamespace(results=[], line=0, refused=0, bad_channel=0,
                                           swaps=0, flushes=[], corners_checked=0,
                                           breaks=0)
        self._collector = None
        self.verbose = bool(os.environ.get("TWH_RANDOM_VERBOSE"))
        self.failure: Optional[BaseException] = None

    def log_debug(self, *args):
        if self.verbose:
            self.dut._log.info(*args)

    # ------------------------------------------------------------ bus
    async def access(self, addr, data=None, sel=0xF, **kw):
        async with self.bus_lock:
            return await super().access(addr, data, sel, **kw)

    # ------------------------------------------------------------ start
    async def start(self):
        await super().start()
        assert self.channels == 3, "the random regression needs tb_core with 3 channels"
        for ch in range(3):
            self.chan.append(ChannelState(self.profiles[ch], self.models[ch],
                                          self.monitors[ch], dict(self.timing[ch])))
        # the collector sleeps until the core raises irq for a result
        await self.write_fields("IRQ_EN", RESULT=1, RES_THRESHOLD=1)
        self._collector = cocotb.start_soon(self._collect())
        return self

    # ------------------------------------------------------------ results
    async def _collect(self):
        d = self.dut
        while True:
            if not int(d.irq.value):
                await RisingEdge(d.irq)
                # irq rises a delta after the clock's edge: which of the two
                # the simulator reports first differs (Icarus, Verilator), and
                # with it which waiting agent reaches the bus first; at the
                # falling edge both agree (tb/coretb.py)
                await FallingEdge(d.clk)
            r = await self.pop()
            if r is None:
                continue        # irq falls a clock after the last pop
            try:
                await self._judge(r)
            except BaseException as e:   # noqa: BLE001 - handed to the waiting agent
                self.failure = e
                for st in self.chan:
                    for x in st.pending:
                        x.done.set()
                raise

    async def _judge(self, r):
        assert 0 <= r.channel < 3, f"result for channel {r.channel}: {r}"
        st = self.chan[r.channel]
        assert st.pending, f"result nobody waits for: {r}"
        x = st.pending.popleft()
        where = f"{x!r}, got {r!r} (TWH_SEED={self.seed})"
        assert (r.tag, r.cmd) == (x.tag, x.command.cmd), f"out of order or wrong command: {where}"
        if x.faults is not None and x.faults.bad_stop_bit is not None and x.model is not None \
                and x.status == ST["FRAMING"]:
            # docs/protocol.md: a 0x00 byte whose stop bit reads 0 is a whole
            # character of 0s, a break: the answer ended, SHORT_RESPONSE
            sent = x.model.log[x.model_index].response
            if sent is not None and sent[x.faults.bad_stop_bit] == 0:
                x.status = ST["SHORT_RESPONSE"]
                self.stats.breaks += 1
        assert r.status == x.status, f"status {STATUS_NAMES[r.status] if r.status < 9 else r.status}: {where}"
        frame = p.build_frame(x.command.cmd, x.command.payload)
        want_data = 0
        if x.line:
            tx = x.monitor.transactions[x.mon_index]
            assert bytes(tx.frame) == frame, f"line carried {bytes(tx.frame).hex()}, not {frame.hex()}: {where}"
            assert tx.complete, f"transaction not complete on the line: {where}"
            self._check_phases(x, tx, where)
        if x.model is not None:
            rec = x.model.log[x.model_index]
            assert rec.frame == frame, f"model received {rec.frame.hex()}: {where}"
            assert rec.faults == x.faults, f"model used faults {rec.faults}: {where}"
            if x.command.answered_by(x.profile):
                want_reason = pm.R_FAULT_SILENT if x.faults.no_response else pm.R_ANSWERED
                assert rec.reason == want_reason, f"model: {rec.reason}: {where}"
            else:
                assert rec.reason in x.command.model_reasons(x.profile), f"model: {rec.reason}: {where}"
            if r.status in (ST["OK"], ST["BAD_CHECKSUM"]):
                want_data = rec.response[0] << 8 | rec.response[1]
                const = const_answer(x.command.cls, x.profile)
                if const is not None:
                    assert want_data == const, f"model answered {want_data:#06x}, profile says {const:#06x}: {where}"
        assert r.data == want_data, f"data {r.data:#06x}, expected {want_data:#06x}: {where}"
        await self._check_errors(x)
        self._sample(x)
        self.stats.results.append((x, r))
        self.log_debug("%r: ok at %.3f ms, timing %s", x, get_sim_time("us") / 1000,
                       "/".join(str(x.timing[ph]) for ph in PHASES))
        x.done.set()

    def _check_phases(self, x, tx, where):
        """The line showed the programmed durations (measured by the spec
        monitor); a turnaround is exact when the next command was waiting."""
        cmd_us = (44 if x.command.cmd >= 0x80 else 33) * 32
        got = dict(charge=tx.charge_us, sync=tx.sync_us, preamble=tx.preamble_us,
                   execute=tx.execute_us, listen=tx.listen_us)
        for ph, v in got.items():
            assert v is not None and abs(v - x.timing[ph]) <= 2, \
                f"{ph} {v} us on the line, programmed {x.timing[ph]}: {where}"
        assert abs(tx.command_us - cmd_us) <= 2, f"command {tx.command_us} us: {where}"
        if x.mon_index > 0:
            prev_tx = x.monitor.transactions[x.mon_index - 1]
            prev = self.chan[x.ch].mon_exps[x.mon_index - 1]
            ta, want = prev_tx.turnaround_us, prev.timing["turnaround"]
            assert ta is not None and ta >= want - 2, f"turnaround {ta} us before it, programmed {want}: {where}"
            listen_end = prev_tx.start_ps + 1e6 * sum(
                getattr(prev_tx, f"{ph}_us") for ph in ("charge", "sync", "preamble", "command",
                                                          "execute", "listen"))
            self.log_debug("ch%d #%d turnaround %.1f us (programmed %d), pushed %.1f us after the listen ended",
                           x.ch, x.n, ta, want, (x.pushed_ps - listen_end) / 1e6)
            if x.pushed_ps + 50e6 < listen_end + want * 1e6:
                # pushed while the turnaround ran: it waited in the slot
                assert ta <= want + 10, f"turnaround {ta} us with the next command waiting, programmed {want}: {where}"
                sample_corner("turnaround", corner_kind("turnaround", want))
                self.stats.corners_checked += 1
        for ph in ("charge", "sync", "preamble", "execute", "listen"):
            sample_corner(ph, corner_kind(ph, x.timing[ph]))
        self.stats.corners_checked += 5

    async def _check_errors(self, x):
        """ERRORS.BLOCKED and LINK_ERROR: set while a result of that kind is
        outstanding or unread, never otherwise (cleared once none is left)."""
        kinds = {"BLOCKED": x.status == ST["BLOCKED"], "LINK_ERROR": x.status in LINK_ERRORS}
        async with self.push_lock:
            errs = self.unpack("ERRORS", await self.read("ERRORS"))
            assert errs["CMD_OVERFLOW"] == 0, f"command FIFO overflowed: {x!r}"
            clear = {}
            for k, mine in kinds.items():
                if mine:
                    assert errs[k] == 1, f"ERRORS.{k} not set after {x!r}"
                    self.outstanding[k] -= 1
                if self.outstanding[k] == 0:
                    if errs[k]:
                        assert mine, f"ERRORS.{k} set with no such result: {x!r} (TWH_SEED={self.seed})"
                        clear[k] = 1
            if clear:
                await self.write_fields("ERRORS", **clear)
                errs = self.unpack("ERRORS", await self.read("ERRORS"))
                for k in clear:
                    assert errs[k] == 0, f"ERRORS.{k} did not clear"

    def _sample(self, x):
        sample_result(x.ch, STATUS_NAMES[x.status])
        sample_class(x.command.cls)
        for s in x.command.specials:
            sample_special(s)
        if x.model is not None:
            sample_profile(x.profile.name)
        fk = FAULTS[x.fault]
        if x.line and (fk.stuck is not None or
                       (x.model is not None and x.command.answered_by(x.profile))):
            sample_fault(x.fault)

    # ------------------------------------------------------------ expectations
    def _expect(self, ch, command, fault_name, faults, cancelled=False) -> Expect:
        st = self.chan[ch]
        fk = FAULTS[fault_name]
        status = expected_status(command, st.profile, fk, cancelled)
        line = status not in (ST["BLOCKED"], ST["CANCELLED"])
        x = Expect(self.n_exp, ch, st.tag, command, status, fault_name, faults, st.profile,
                   dict(st.timing), int(get_sim_time("ps")), line)
        self.n_exp += 1
        st.tag = (st.tag + 1) % 32
        if line:
            x.monitor, x.mon_index = st.monitor, len(st.mon_exps)
            st.mon_exps.append(x)
            if fk.stuck is None:
                x.model, x.model_index = st.model, st.model_count
                st.model_count += 1
        if status == ST["BLOCKED"]:
            self.outstanding["BLOCKED"] += 1
        if status in LINK_ERRORS:
            self.outstanding["LINK_ERROR"] += 1
        st.pending.append(x)
        return x

    async def push_expect(self, ch, command, fault_name="none", faults=None, cancelled=False):
        """Push one command with its expectation (caller holds push_lock)."""
        x = self._expect(ch, command, fault_name, faults, cancelled)
        if command.unlock:
            await self.write("FACTORY_KEY", FACTORY_KEY)
            assert await self.field("VERSION", "FACTORY_UNLOCKED") == 1
        await self.push(command.cmd, command.payload, ch, x.tag)
        if command.unlock:
            assert await self.field("VERSION", "FACTORY_UNLOCKED") == 0, "unlock outlived its push"
        return x

    async def wait_done(self, exps, timeout_ms):
        timeout_ms = math.ceil(timeout_ms)     # a Timer takes whole time steps
        for x in exps:
            try:
                await with_timeout(x.done.wait(), timeout_ms, "ms")
            except SimTimeoutError:
                raise AssertionError(f"no result within {timeout_ms} ms for {x!r} "
                                     f"(TWH_SEED={self.seed}): {await self.describe()}") from None
            if self.failure is not None:
                raise self.failure

    @staticmethod
    def txn_ms(timing, n=1) -> float:
        return n * (sum(timing.values()) + 44 * 32) / 1000

    # ------------------------------------------------------------ channel set-up
    async def swap_profile(self, ch, name):
        """Another device on the line: a new model and a new spec monitor
        (its execute limit follows the profile), as CoreTB builds them. The
        old pair is closed and checked."""
        st = self.chan[ch]
        old_model, old_mon = st.model, st.monitor
        old_model.stop()
        old_mon.finish()
        coll = [t for t in old_model.log if t.collision]
        assert not coll, f"channel {ch}: host drove the line during {len(coll)} answer(s)"
        self.retired.append((old_model, old_mon))
        prof = profiles.PROFILES[name]
        pins = self.pins[ch]
        st.model = PeripheralModel(pins, prof, Faults(), line_log=f"line_{ch}.log", carrier=pins.carrier)
        st.monitor = SpecMonitor(pins, execute_max_us=prof.exec_max_us, name=f"spec_ch{ch}_{len(self.retired)}",
                                 pin_log=f"pins_{ch}.log")
        st.profile = prof
        st.model_count = 0
        st.mon_exps = []
        self.models[ch], self.monitors[ch], self.profiles[ch] = st.model, st.monitor, prof
        st.monitor.start()
        st.model.start()
        self.stats.swaps += 1

    async def program_timing(self, ch, timing):
        async with self.err_lock:
            await self.set_timing(ch, **timing)
            assert await self.field("ERRORS", "VALUE_REFUSED") == 0, \
                f"legal timing refused on ch{ch}: {timing}"
        self.chan[ch].timing = dict(self.timing[ch])
        assert self.chan[ch].timing == timing

    async def refused_write(self, ch, ph, value, other=None):
        """An out-of-window value (with `other`, the register's other field
        gets a new legal value in the same write): refused as a whole."""
        kw = {ph: value}
        if other:
            kw.update(other)
        async with self.err_lock:
            assert await self.field("ERRORS", "VALUE_REFUSED") == 0
            await self.set_timing(ch, expect_refused=True, **kw)   # reads back: unchanged
            assert await self.field("ERRORS", "VALUE_REFUSED") == 1, f"not flagged: ch{ch} {kw}"
            await self.write_fields("ERRORS", VALUE_REFUSED=1)
            assert await self.field("ERRORS", "VALUE_REFUSED") == 0
        lo, hi = WINDOWS[ph]
        sample_refused(ph, "below" if value < lo else "above")
        self.stats.refused += 1

    async def bad_channel_push(self, rng):
        ch = rng.randint(self.channels, 31)      # an absent channel of the 32-channel map
        async with self.err_lock:
            assert await self.field("ERRORS", "BAD_CHANNEL") == 0
            async with self.push_lock:
                await self.push(0x41, ch=ch, tag=rng.getrandbits(5), expect_err=True)
            assert await self.field("ERRORS", "BAD_CHANNEL") == 1
            await self.write_fields("ERRORS", BAD_CHANNEL=1)
            assert await self.field("ERRORS", "BAD_CHANNEL") == 0
        sample_event("bad_channel")
        self.stats.bad_channel += 1

    # ------------------------------------------------------------ agents
    async def agent(self, ch):
        """Each agent pushes its own share of the commands: every channel
        has statuses only its agent can show."""
        gen = Generator(self, ch)
        quota = self.n_commands // 3 + (ch < self.n_commands % 3)
        try:
            for k in range(quota):
                await self.coord.checkpoint(ch)
                if ch == 0 and k == self.flush_at:
                    await self.flush_event(ch)
                self.issued += 1
                plan = gen.plan(last=k == quota - 1)
                await self.run_plan(ch, plan, gen.rng)
        finally:
            self.coord.agent_finished()

    async def run_plan(self, ch, plan, rng):
        st = self.chan[ch]
        if plan.swap:
            await self.swap_profile(ch, plan.swap)
        for ph, value, other in plan.refused:
            await self.refused_write(ch, ph, value, other)
        if plan.timing != st.timing:
            await self.program_timing(ch, plan.timing)
        if plan.bad_channel:
            await self.bad_channel_push(rng)
        fk = FAULTS[plan.fault]
        faults = fk.make(st.timing)
        st.model.faults = faults
        if fk.stuck is not None:
            getattr(self.dut, f"stuck_val_{ch}").value = fk.stuck
            getattr(self.dut, f"stuck_en_{ch}").value = 1
        async with self.push_lock:
            x = await self.push_expect(ch, plan.command, plan.fault, faults)
        # the previous turnaround (<= 65.5 ms) may still run
        await self.wait_done([x], self.txn_ms(st.timing) + 70 + 20)
        if fk.stuck is not None:
            # released during the turnaround, before the next charge
            getattr(self.dut, f"stuck_en_{ch}").value = 0
        st.model.faults = Faults()
        assert len(st.model.log) == st.model_count, \
            f"ch{ch}: model saw {len(st.model.log)} transactions, expected {st.model_count}: {st.model.log[-2:]}"
        assert len(st.monitor.transactions) == len(st.mon_exps), \
            f"ch{ch}: {len(st.monitor.transactions)} transactions on the line, expected {len(st.mon_exps)}"
        st.monitor.check()
        if x.line:
            self.stats.line += 1

    # ------------------------------------------------------------ flush events
    async def flush_event(self, me):
        """Every agent parked (one pause: the others idle meanwhile), then
        both kinds of flush, in random order."""
        await self.coord.stop_others(me)
        try:
            modes = ["flush_running", "flush_disabled"]
            self.flush_rng.shuffle(modes)
            for mode in modes:
                await self._flush(mode)
        finally:
            self.flush_done = True
            self.coord.release()

    async def _flush(self, mode):
        """flush_disabled: disable, queue, flush: all CANCELLED, nothing on
        the line. flush_running: one command per channel starts, more queue
        behind it, flush while they run: the running ones finish normally,
        the queued ones come back CANCELLED."""
        rng = self.flush_rng
        await self.wait_idle(timeout_ms=200)
        line_before = [len(st.monitor.transactions) for st in self.chan]
        for st in self.chan:
            st.model.faults = Faults()
        exps, runners = [], []
        if mode == "flush_disabled":
            await self.write_fields("CTRL", ENABLE=0)
        async with self.push_lock:
            if mode == "flush_running":
                for ch, st in enumerate(self.chan):
                    want = unhit("command.class")
                    cls = rng.choice([c for c in CMD_CLASSES if c in want] or CMD_CLASSES)
                    c = make_command(rng, cls, st.profile, addr_kind="in")
                    runners.append(await self.push_expect(ch, c, "none", st.model.faults))
            # queued after every runner: none of them waits behind
            # another channel's command at the FIFO head
            for _ in range(rng.randint(1, 2)):
                for ch, st in enumerate(self.chan):
                    c = make_command(rng, rng.choice(CMD_CLASSES), st.profile, addr_kind="in")
                    exps.append(await self.push_expect(ch, c, "none", None, cancelled=True))
        if mode == "flush_running":
            async def all_running():
                for ch in range(3):
                    if not 1 <= (await self.fields("STATE", ch)).PHASE <= 5:
                        return False
                return True
            # (after reset an engine holds its first charge back 2 ms)
            await self.wait_until(all_running, timeout_ms=3, poll_us=20)
            # a charge lasts >= 7 ms: none of them can finish before the flush
            await self.write_fields("CTRL", ENABLE=1, FLUSH=1)
        else:
            await self.write_fields("CTRL", ENABLE=0, FLUSH=1)
        wait_ms = max(self.txn_ms(st.timing) for st in self.chan) + 20
        await self.wait_done(runners + exps, wait_ms)
        s = await self.fields("STATUS")
        assert s.FLUSHING == 0 and s.CMD_EMPTY == 1, s
        await self.write_fields("CTRL", ENABLE=1)
        added = [len(st.monitor.transactions) - b for st, b in zip(self.chan, line_before)]
        assert added == ([1, 1, 1] if mode == "flush_running" else [0, 0, 0]), \
            f"{mode}: line transactions {added} (TWH_SEED={self.seed})"
        sample_event(mode)
        self.stats.flushes.append((mode, len(exps)))

    # ------------------------------------------------------------ the run
    async def run(self):
        # One flush event per coverage goal (not again in the second half),
        # early: it waits until every channel is idle, and until it has run
        # no agent goes for a 65 ms phase.
        self.flush_at = None
        if {"flush_running", "flush_disabled"} & set(unhit("bus.event")) and self.n_commands >= 3:
            self.flush_at = self.flush_rng.randint(0, 2)
        else:
            self.flush_done = True
        agents = [cocotb.start_soon(self.agent(ch)) for ch in range(3)]
        for a in agents:
            await a
        await self.wait_idle(timeout_ms=100)
        for st in self.chan:
            assert not st.pending, f"results missing: {list(st.pending)}"
        self._collector.cancel()
        assert await self.read("ERRORS") == 0, f"ERRORS left set: {await self.fields('ERRORS')}"
        for model, mon in self.retired:
            assert not [t for t in model.log if t.collision]
        await self.finish()


# ============================================================ stimulus
@dataclass
class Plan:
    command: Command
    fault: str
    timing: dict
    swap: Optional[str] = None
    refused: list = field(default_factory=list)
    bad_channel: bool = False


class Generator:
    """One agent's stimulus. Each draw prefers what the coverage still
    lacks; with everything hit it is plain constrained random."""

    ANSWERED = ["CONFIG", "FIRMWARE", "REF_VOLTAGE", "TEMPERATURE", "O2_VOLTAGE",
                "FIND_FREE", "READ"]
    SILENT = ["ERASE", "WRITE", "RESERVED", "READ", "FIND_FREE"]   # the last two out of range

    def __init__(self, tb: RandomTB, ch):
        self.tb = tb
        self.ch = ch
        self.rng = tb.rngs[ch]
        self.claims = []     # expensive corners this agent went for last time
        self.long_turnaround = False   # the last plan had a 65535 us turnaround

    def release_claims(self):
        """Called before each plan. A charge or listen corner is judged with
        its own command, a turnaround only with the next one: a claim lasts
        until its corner is hit or two plans have passed."""
        want = unhit("timing.corner")
        keep = []
        for corner, age in self.claims:
            if corner in want and age < 1:
                keep.append((corner, age + 1))
            else:
                self.tb.claims.pop(corner, None)
        self.claims = keep

    def _may_go_long(self, ph) -> bool:
        """A 65535 us phase holds a channel for tens of ms, while every agent
        has the same number of commands to push: one agent per corner at a
        time, each agent one such phase before any takes a second, and none
        before the flush event (it waits for all channels to go idle)."""
        tb = self.tb
        return (f"{ph}:max" not in tb.claims and tb.flush_done
                and tb.long_phases[self.ch] == min(tb.long_phases))

    def _pick(self, options, wanted, p_want=0.8):
        want = [o for o in options if o in wanted]
        if want and self.rng.random() < p_want:
            return self.rng.choice(want)
        return self.rng.choice(options)

    def plan(self, last=False) -> Plan:
        """last: this agent's last command (no command after it to show that
        a turnaround was exact)."""
        rng, tb, ch = self.rng, self.tb, self.ch
        st = tb.chan[ch]
        self.release_claims()
        # ---- device on the line; not right after a 65535 us turnaround: a
        # new monitor would not measure it
        swap = None
        keep_device, self.long_turnaround = self.long_turnaround, False
        others = {tb.chan[c].profile.name for c in range(3) if c != ch}
        want_prof = [n for n in unhit("profile") if n != st.profile.name and n not in others]
        if keep_device:
            pass
        elif want_prof and rng.random() < 0.5:
            swap = rng.choice(want_prof)
        elif rng.random() < 0.05:
            swap = rng.choice([n for n in PROFILE_NAMES if n != st.profile.name])
        prof = profiles.PROFILES[swap] if swap else st.profile

        # ---- aim: a status this channel has not shown (only this agent can
        # get it), else a fault or command variant not seen yet, else random
        want_st = [s for (c, s) in unhit("result.channel_x_status") if c == ch and s != "CANCELLED"]
        want_fault = unhit("fault")
        goals = [("fault", f) for f in want_fault] + \
            [("special", x) for x in unhit("command.special")]
        target = special = None
        if want_st and rng.random() < 0.9:
            target = rng.choice(want_st)
        elif goals and rng.random() < 0.85:
            kind, goal = rng.choice(goals)
            if kind == "fault":
                want_fault = [goal]
                target = FAULTS[goal].status
            else:
                special = goal
        elif rng.random() < 0.5:
            target = rng.choice(AGENT_STATUSES)
        if special:
            fault, command = self._for_special(special, prof, want_fault)
        else:
            fault, command = self._fault_and_command(target, prof, want_fault)

        # ---- timing, refusals, bad channel
        # no 65535 us phase where it would not be measured: a blocked
        # command never reaches the line, and a turnaround shows only with
        # the command after it
        timing = self._timing(st.timing, prof, last or command.blocked)
        refused = []
        want_ref = unhit("timing.refused")
        if (want_ref and rng.random() < 0.5) or rng.random() < 0.1:
            for _ in range(rng.randint(1, 2)):
                refused.append(self._refusal(want_ref, st.timing))
        bad = ("bad_channel" in unhit("bus.event") and rng.random() < 0.5) or rng.random() < 0.03
        return Plan(command, fault, timing, swap, refused, bad)

    def _fault_and_command(self, target, prof, want_fault):
        rng = self.rng
        want_cls = unhit("command.class")
        model_faults = [f.name for f in FAULT_KINDS if f.stuck is None]
        if target == "BLOCKED":
            want_sp = unhit("command.special")
            cls = self._pick(["ERASE", "WRITE"], [c for c in ("ERASE", "WRITE")
                                                   if f"{c.lower()}_factory_blocked" in want_sp])
            return rng.choice(model_faults), make_command(rng, cls, prof, addr_kind="factory")
        if target in ("LINE_STUCK_LOW", "LINE_STUCK_HIGH"):
            fault = "stuck_low" if target == "LINE_STUCK_LOW" else "stuck_high"
            return fault, self._command(self._pick(CMD_CLASSES, want_cls), prof, may_block=False)
        cls_goals = [c for c in want_cls if c in ("ERASE", "WRITE", "RESERVED")]
        sp_goals = [x for x in unhit("command.special")
                    if x in ("factory_unlocked", "out_of_range", "addr_bit8", "write_addr_bits_8_7")]
        silent_goal = cls_goals or sp_goals
        if target == "NO_RESPONSE":
            # either a command the device never answers (any model fault) or
            # an answered one under the no_response fault: whichever an
            # open bin needs
            if "no_response" in want_fault:
                silent = bool(silent_goal) and rng.random() < 0.5
            else:
                silent = bool(silent_goal) or rng.random() < 0.6
        else:
            silent = False
        if silent:
            if sp_goals and (not cls_goals or rng.random() < 0.5):
                return self._for_special(rng.choice(sp_goals), prof, want_fault)
            cls = self._pick(self.SILENT, want_cls)
            fault = self._pick(model_faults, want_fault, 0.3)
            return fault, self._command(cls, prof, may_block=False, silent=True)
        if target is None:
            fault = self._pick([f.name for f in FAULT_KINDS], want_fault, 0.5) \
                if rng.random() < 0.6 else "none"
            cls = self._pick(CMD_CLASSES, want_cls, 0.5)
            return fault, self._command(cls, prof, may_block=True)
        # an answered command, with a fault that gives the target status
        fault = self._pick([f.name for f in FAULT_KINDS
                            if f.status == target and f.stuck is None], want_fault)
        classes = self.ANSWERED
        k = FAULTS[fault].kwargs.get("bad_stop_bit")
        if k is not None:
            # a 0x00 byte with a bad stop bit is a break (SHORT_RESPONSE):
            # aim at answers known to have byte k non-zero
            classes = [c for c in CONST_CMDS
                       if p.response_frame(const_answer(c, prof) >> 8, const_answer(c, prof))[k]] \
                or self.ANSWERED
        cls = self._pick(classes, want_cls)
        return fault, self._command(cls, prof, may_block=False, answered=True)

    def _for_special(self, special, prof, want_fault):
        """A command that shows one command variant, under a model fault (it
        may or may not show, depending on whether the command is answered)."""
        rng = self.rng
        fault = self._pick([f.name for f in FAULT_KINDS if f.stuck is None], want_fault, 0.5)
        if special == "payload_msb_ignored":
            cls, kind, unlock = rng.choice(list(CONST_CMDS)), None, False
        elif special in ("erase_factory_blocked", "write_factory_blocked"):
            cls, kind, unlock = special.split("_")[0].upper(), "factory", False
        elif special == "factory_unlocked":
            cls, kind, unlock = rng.choice(["ERASE", "WRITE"]), "factory", True
        elif special == "write_addr_bits_8_7":
            cls, kind, unlock = "WRITE", "high", False
        elif special == "addr_bit8":
            cls, kind, unlock = rng.choice(["READ", "FIND_FREE", "ERASE"]), "bit8", False
        else:
            assert special == "out_of_range", special
            cls, kind, unlock = rng.choice(["READ", "FIND_FREE", "ERASE", "WRITE"]), "out", False
        return fault, make_command(rng, cls, prof, addr_kind=kind, unlock=unlock)

    def _command(self, cls, prof, may_block, silent=False, answered=False) -> Command:
        """A command of class cls; the address kind goes for an unhit
        special where the class can give one. silent / answered: for READ
        and FIND_FREE, out of / in range."""
        rng = self.rng
        want = unhit("command.special")
        if cls in CONST_CMDS or cls == "RESERVED":
            return make_command(rng, cls, prof)
        if cls in ("READ", "FIND_FREE"):
            if answered:
                kind = "in"
            elif silent or ("addr_bit8" in want and rng.random() < 0.5):
                kind = "bit8" if "addr_bit8" in want or rng.random() < 0.5 else "out"
            else:
                kind = None
            return make_command(rng, cls, prof, addr_kind=kind)
        kinds = []
        if "factory_unlocked" in want:
            kinds.append(("factory", True))
        if may_block and f"{cls.lower()}_factory_blocked" in want:
            kinds.append(("factory", False))
        if cls == "WRITE" and "write_addr_bits_8_7" in want:
            kinds.append(("high", False))
        if cls == "ERASE" and "addr_bit8" in want:
            kinds.append(("bit8", False))
        if "out_of_range" in want:
            kinds.append(("out", False))
        if kinds and rng.random() < 0.7:
            kind, unlock = rng.choice(kinds)
        else:
            kind = default_addr_kind(rng, cls)
            unlock = kind == "factory" and (not may_block or rng.random() < 0.5)
        return make_command(rng, cls, prof, addr_kind=kind, unlock=unlock)

    def _timing(self, cur, prof, no_long=False) -> dict:
        """Each phase at its minimum, its maximum or inside (an unhit corner
        first). Short values are favoured once the corners are hit: a run's
        cost is its simulated time."""
        rng = self.rng
        if rng.random() < 0.2 and not any(cur[ph] == WINDOWS[ph][1] for ph in OPEN_ENDED):
            # keep the timing (no write), unless it holds a 65535 us phase
            t = dict(cur)
            if prof.exec_max_us < t["execute"]:
                t["execute"] = rng.randint(WINDOWS["execute"][0], prof.exec_max_us)
            return t
        want = unhit("timing.corner")
        t = {}
        expensive = False
        for ph in PHASES:
            lo, hi = WINDOWS[ph]
            hi_ok = min(hi, prof.exec_max_us) if ph == "execute" else hi
            kinds = [k for k in ("min", "inside") if f"{ph}:{k}" in want]
            if f"{ph}:max" in want and hi_ok == hi and not expensive and \
                    (ph not in OPEN_ENDED or (self._may_go_long(ph) and not no_long)):
                kinds.append("max")
            if kinds and rng.random() < 0.5:
                kind = rng.choice(kinds)
            elif ph in OPEN_ENDED:
                kind = rng.choices(["min", "inside"], [0.6, 0.4])[0]
            else:
                kind = rng.choices(["min", "inside", "max"], [0.5, 0.4, 0.1])[0]
            if kind == "max" and hi_ok != hi:
                kind = "inside"
            if kind == "min":
                v = lo
            elif kind == "max":
                v = hi
                if ph in OPEN_ENDED:
                    expensive = True
                    self.tb.claims[f"{ph}:max"] = self.ch
                    self.claims.append((f"{ph}:max", 0))
                    self.tb.long_phases[self.ch] += 1
                    self.long_turnaround = ph == "turnaround"
            elif ph in OPEN_ENDED:
                v = rng.randint(lo + 1, lo + INSIDE_OPEN_SPAN[ph])
            else:
                v = rng.randint(lo + 1, hi_ok - 1)
            t[ph] = v
        return t

    def _refusal(self, want, cur):
        rng = self.rng
        pick = self._pick(REFUSALS, want, 0.8)
        ph, side = pick.split(":")
        lo, hi = WINDOWS[ph]
        # the first refusal of each kind is right at the window's edge
        edge = pick in want or rng.random() < 0.5
        if side == "below":
            v = lo - 1 if edge else rng.randint(0, lo - 1)
        else:
            v = hi + 1 if edge else rng.randint(hi + 1, 65535)
        other = None
        if rng.random() < 0.5:
            # the register's other field moves to a new legal value: still
            # refused as a whole
            partner = {"charge": "sync", "sync": "charge", "preamble": "execute",
                       "execute": "preamble", "listen": "turnaround", "turnaround": "listen"}[ph]
            plo, phi = WINDOWS[partner]
            choices = [x for x in (plo, min(phi, plo + 300)) if x != cur[partner]]
            if choices:
                other = {partner: rng.choice(choices)}
        return ph, v, other


# ============================================================ report
def coverage_report(log) -> list:
    """Log a summary table; return the unhit bins as 'item: bin' strings."""
    missing = []
    rows = []
    for item in COVER_ITEMS:
        cp = coverage_db[f"{COV}.{item}"]
        miss = unhit(item)
        missing += [f"{item}: {b}" for b in miss]
        rows.append((item, cp.coverage, cp.size, cp.cover_percentage, miss))
    w = max(len(r[0]) for r in rows)
    log(f"{'coverage item'.ljust(w)}  hit/bins      %   unhit")
    for item, c, s, pct, miss in rows:
        log(f"{item.ljust(w)}  {c:4d}/{s:<4d}  {pct:5.1f}   {', '.join(map(str, miss)) or '-'}")
    top = coverage_db[COV]
    log(f"{'total'.ljust(w)}  {top.coverage:4d}/{top.size:<4d}  {top.cover_percentage:5.1f}")
    return missing


def bins_table(log):
    """Hit counts of every bin, one item per block (for docs/random.md)."""
    for item in COVER_ITEMS:
        cp = coverage_db[f"{COV}.{item}"]
        if item == "result.channel_x_status":
            cells = cp.detailed_coverage
            log("channel x status: " + "  ".join(f"{s[:6]}" for s in STATUS_NAMES))
            for c in range(3):
                log(f"  ch{c}            " + "  ".join(f"{cells[(c, s)]:6d}" for s in STATUS_NAMES))
            continue
        log(f"{item}: " + ", ".join(f"{b}={n}" for b, n in cp.detailed_coverage.items()))


def export_coverage(name) -> Path:
    out = ROOT / "build" / "coverage"
    out.mkdir(parents=True, exist_ok=True)
    yml = out / f"{name}.yml"
    coverage_db.export_to_yaml(str(yml))
    coverage_db.export_to_xml(str(out / f"{name}.xml"))
    return yml


def load_coverage(path):
    """Replay the hits of an earlier run's YAML export into this process's
    coverage (the two bus variants share one coverage goal)."""
    import ast

    import yaml
    with open(path) as fh:
        data = yaml.safe_load(fh)
    samplers = {
        "command.class": sample_class, "command.special": sample_special,
        "fault": sample_fault, "profile": sample_profile, "bus.event": sample_event,
        "timing.corner": lambda b: sample_corner(*b.split(":")),
        "timing.refused": lambda b: sample_refused(*b.split(":")),
        # channel and status are sampled with their cross
        "result.channel_x_status": lambda b: sample_result(*ast.literal_eval(b)),
    }
    for item, sample in samplers.items():
        for b, n in data[f"{COV}.{item}"]["bins:_hits"].items():
            for _ in range(n):
                sample(b)


def seed_from_env() -> int:
    """TWH_SEED: a number replays that run; 'random' draws a fresh one."""
    s = os.environ.get("TWH_SEED", "").strip()
    if not s:
        return DEFAULT_SEED
    if s.lower() == "random":
        return random.SystemRandom().getrandbits(32)
    return int(s, 0)
