"""Test-bench harness for the bus-attached core (tb/tb_core.v: twh_wb or
twh_axil around twh_core, up to eight channels on simulated 2-wire lines).

- One PeripheralModel and one SpecMonitor per channel, each pointed at its
  channel through a small adapter whose attributes are that channel's
  handles (`line`, `periph_o`, `periph_oe`, `line_o`, `line_oe`).
- A bus master: classic Wishbone (BUS=0) or AXI-Lite (BUS=1), both behind
  `access()`, which returns (data, error) and fails the test if the access
  is not answered within ACCESS_TIMEOUT_US of simulated time. A protocol
  check runs around every access: Wishbone answers exactly one ack or err,
  two clocks after the strobe is taken (the core's request stage, then the
  access), never both; AXI-Lite takes AW and W in the same clock and
  answers each access exactly once.
- Register helpers by name (tb/regmap.py reads rdl/twh_regs.rdl), command
  push / result pop helpers, and `finish()`, which closes and checks every
  spec monitor.

The build parameters come from the simulator (the tb_core parameters), with
the TWH_* environment variables of the pytest runner as a fallback.
"""
from __future__ import annotations

import os
import types
from dataclasses import dataclass
from typing import Dict, List, Optional

import cocotb
from cocotb.simtime import get_sim_time
from cocotb.triggers import FallingEdge, First, Lock, RisingEdge, Timer, with_timeout

import profiles
import regmap
from periph_model import Faults, PeripheralModel
from protocol import Status
from spec_monitor import SpecMonitor

# status codes of the bus core (protocol.Status may not carry CANCELLED yet)
CANCELLED = int(getattr(Status, "CANCELLED", 8))
BLOCKED = int(Status.BLOCKED)
OK = int(Status.OK)
NO_RESPONSE = int(Status.NO_RESPONSE)

LAB_KEY = 0x4C414221       # "LAB!"
FACTORY_KEY = 0x46414354   # "FACT"

TB_CHANNELS = 8            # channels wired in tb_core.v
ACCESS_TIMEOUT_US = 50     # every bus access must be answered within this

# NOTES.md defaults, microseconds
DEFAULT_TIMING = dict(charge=8000, sync=1000, preamble=2000, execute=4000,
                      listen=3000, turnaround=2000)
# Lab-short phases (LAB_KEY needed): a transaction takes ~3 ms instead of 21.
# Short enough to be quick, long enough for the spec monitor to parse (a
# lab sync or preamble must be longer than 400 us).
LAB_TIMING = dict(charge=600, sync=500, preamble=500, execute=100, listen=100,
                  turnaround=100)
TIMING_FIELDS = {   # register, field for each phase
    "charge": ("TIMING0", "CHARGE_US"), "sync": ("TIMING0", "SYNC_US"),
    "preamble": ("TIMING1", "PREAMBLE_US"), "execute": ("TIMING1", "EXECUTE_US"),
    "listen": ("TIMING2", "LISTEN_US"), "turnaround": ("TIMING2", "TURNAROUND_US"),
}
# one default transaction (3-byte command), microseconds
TXN_US = sum(DEFAULT_TIMING.values()) + 33 * 32


class BusError(AssertionError):
    pass


@dataclass(frozen=True)
class Result:
    """One entry of the result FIFO (RES_INFO and RES_POP together)."""
    cmd: int
    data: int
    status: int
    channel: int
    tag: int

    def __repr__(self):
        return (f"Result(ch{self.channel} tag={self.tag} cmd={self.cmd:#04x} "
                f"status={self.status} data={self.data:#06x})")


# ---------------------------------------------------------------- bus drivers
# Both masters drive right after a rising edge and read the core's outputs
# at the falling edge, where they hold the value the next rising edge takes.
# Right after a rising edge Icarus shows the values before it and Verilator
# those after it, so a master (or a check) reading there would see a
# different bus on each simulator; at the falling edge both agree, and the
# same bench runs on both (tb/simrun.py).
def sweep_clocks(channels, prog_timing=1, polling=1):
    """The clocks after a reset in which the register port takes no
    request (docs/registers.md, "After a reset"): the reset sweep writes four
    words a channel, rounded up to a power of two and at least 16, then waits
    as long again; none with fixed timing and no poller."""
    if not prog_timing and not polling:
        return 0
    words = 16
    while words < 4 * channels:
        words *= 2
    return 2 * words


class PortReady:
    """Tells, at a falling edge, whether the core takes a strobe at the next
    rising edge, from the reset pin alone and the documented sweep: after
    the last reset edge, `sweep` more rising edges."""

    def __init__(self, dut, sweep):
        self.dut = dut
        self.sweep = sweep
        self.edges = 0          # rising edges since the last reset edge

    def start(self):
        cocotb.start_soon(self._count())

    async def _count(self):
        d = self.dut
        clk, rst_rise = RisingEdge(d.clk), RisingEdge(d.rst)
        while True:
            await clk
            # (rst as the edge takes it: a write in this step comes after)
            if int(d.rst.value):
                self.edges = 0
            elif self.edges < self.sweep:
                self.edges += 1
            else:
                # ready until an edge takes rst high: nothing to count till
                # rst rises (a Python wake-up every clock was a quarter of
                # an Icarus run's time)
                await rst_rise

    def ready(self) -> bool:
        return self.edges >= self.sweep


class WishboneDriver:
    """Classic-cycle Wishbone master on tb_core's wb_* port, with a check
    of the handshake around every cycle: a strobe is answered exactly two
    clocks after the core takes it, which is at once except in the reset
    sweep's clocks (PortReady)."""

    def __init__(self, dut, port=None):
        self.dut = dut
        self.port = port
        self.violations: List[str] = []

    def idle_inputs(self):
        d = self.dut
        for s in (d.wb_cyc_i, d.wb_stb_i, d.wb_we_i, d.wb_adr_i, d.wb_dat_i):
            s.value = 0
        d.wb_sel_i.value = 0xF

    async def _watch(self, box):
        """Samples the handshake before every rising edge of one cycle: a
        strobe taken at edge k must be answered (ack or err, not both) at
        edge k+2, and nothing else may be answered."""
        d = self.dut
        fall = FallingEdge(d.clk)
        waited = 0          # edges the strobe now up has been seen unanswered
        answers = 0
        seen_cyc = False
        while True:
            await fall
            cyc, stb = int(d.wb_cyc_i.value), int(d.wb_stb_i.value)
            ack, err = int(d.wb_ack_o.value), int(d.wb_err_o.value)
            if ack and err:
                self.violations.append(f"{get_sim_time('ns')} ns: ack and err together")
            resp = ack or err
            if resp:
                answers += 1
                if waited != 2:
                    self.violations.append(f"{get_sim_time('ns')} ns: answer to a strobe taken "
                                           f"{waited} clocks before (expected 2)")
                waited = 0
            elif cyc and stb and waited == 0 and self.port is not None and not self.port.ready():
                pass            # the reset sweep: not taken yet
            elif cyc and stb:
                if waited == 2:
                    self.violations.append(f"{get_sim_time('ns')} ns: strobe taken two clocks "
                                           "before got no answer")
                waited += 1
            else:
                waited = 0
            seen_cyc = seen_cyc or bool(cyc)
            if seen_cyc and not cyc and waited == 0:
                break
        box.append(answers)

    async def cycle(self, ops):
        """One bus cycle (cyc held) of several accesses, strobes back to
        back: ops are (addr, data or None, sel); returns [(data, err)]."""
        d = self.dut
        box: list = []
        watcher = cocotb.start_soon(self._watch(box))
        res = []
        await RisingEdge(d.clk)
        d.wb_cyc_i.value = 1
        for addr, data, sel in ops:
            d.wb_stb_i.value = 1
            d.wb_adr_i.value = addr
            d.wb_we_i.value = int(data is not None)
            d.wb_dat_i.value = data or 0
            d.wb_sel_i.value = sel
            while True:
                await FallingEdge(d.clk)
                ack, err = int(d.wb_ack_o.value), int(d.wb_err_o.value)
                if ack or err:
                    dat = d.wb_dat_o.value
                    res.append((int(dat) if dat.is_resolvable else 0, bool(err)))
                    break
            await RisingEdge(d.clk)     # the edge that takes the answer
        self.idle_inputs()
        await watcher
        if not box or box[0] != len(ops) or len(res) != len(ops):
            self.violations.append(f"cycle at {ops[0][0]:#x}: {box} answers, {len(res)} results "
                                   f"for {len(ops)} strobes")
        if self.violations:
            raise AssertionError("Wishbone handshake: " + "; ".join(self.violations))
        return res

    async def access(self, addr, data=None, sel=0xF):
        return (await self.cycle([(addr, data, sel)]))[0]


class AxiLiteDriver:
    """AXI-Lite master on tb_core's s_axil_* port: one write and one read
    may be in flight at once (each channel pair in order), as a CPU's load
    and store units would issue them; bready and rready are always high.
    A watcher checks that AW and W are always taken in the same clock and
    counts the responses (one per access)."""

    def __init__(self, dut):
        self.dut = dut
        self.violations: List[str] = []
        self.n_access = 0
        self.n_resp = 0
        self._watch_task = None
        self._write_lock = Lock()
        self._read_lock = Lock()

    def idle_inputs(self):
        d = self.dut
        for s in (d.wb_cyc_i, d.wb_stb_i, d.wb_we_i, d.wb_adr_i, d.wb_dat_i, d.wb_sel_i):
            s.value = 0
        for s in (d.s_axil_awvalid, d.s_axil_awaddr, d.s_axil_awprot, d.s_axil_wvalid,
                  d.s_axil_wdata, d.s_axil_wstrb, d.s_axil_arvalid, d.s_axil_araddr,
                  d.s_axil_arprot):
            s.value = 0
        d.s_axil_bready.value = 1
        d.s_axil_rready.value = 1

    def start(self):
        self._watch_task = cocotb.start_soon(self._watch())

    async def _watch(self):
        d = self.dut
        fall = FallingEdge(d.clk)
        while True:
            # sleep while the bus is quiet
            if not any(int(s.value) for s in (d.s_axil_awvalid, d.s_axil_wvalid,
                                                d.s_axil_arvalid, d.s_axil_bvalid,
                                                d.s_axil_rvalid)):
                await _axil_activity(d)
            await fall
            aw = int(d.s_axil_awvalid.value) and int(d.s_axil_awready.value)
            w = int(d.s_axil_wvalid.value) and int(d.s_axil_wready.value)
            if aw != w:
                self.violations.append(f"{get_sim_time('ns')} ns: AW and W taken in different clocks")
            if int(d.s_axil_bvalid.value) and int(d.s_axil_bready.value):
                self.n_resp += 1
            if int(d.s_axil_rvalid.value) and int(d.s_axil_rready.value):
                self.n_resp += 1

    async def _until(self, cond, sample=lambda: None):
        """Waits for the falling edge where cond() holds, then for the
        rising edge that takes it; returns sample() as read at that falling
        edge."""
        clk = self.dut.clk
        while True:
            await FallingEdge(clk)
            if cond():
                value = sample()
                break
        await RisingEdge(clk)
        return value

    async def write(self, addr, data, strb=0xF):
        """One write; returns its BRESP."""
        d = self.dut
        async with self._write_lock:
            await RisingEdge(d.clk)
            d.s_axil_awaddr.value = addr
            d.s_axil_wdata.value = data
            d.s_axil_wstrb.value = strb
            d.s_axil_awvalid.value = 1
            d.s_axil_wvalid.value = 1
            pending = {"aw": True, "w": True}
            while any(pending.values()):
                await FallingEdge(d.clk)
                taken = {"aw": pending["aw"] and int(d.s_axil_awready.value),
                         "w": pending["w"] and int(d.s_axil_wready.value)}
                await RisingEdge(d.clk)
                if taken["aw"]:
                    d.s_axil_awvalid.value = 0
                    pending["aw"] = False
                if taken["w"]:
                    d.s_axil_wvalid.value = 0
                    pending["w"] = False
            return await self._until(lambda: int(d.s_axil_bvalid.value),
                                     lambda: int(d.s_axil_bresp.value))

    async def read(self, addr):
        """One read; returns (RDATA, RRESP)."""
        d = self.dut
        async with self._read_lock:
            await RisingEdge(d.clk)
            d.s_axil_araddr.value = addr
            d.s_axil_arvalid.value = 1
            await self._until(lambda: int(d.s_axil_arready.value))
            d.s_axil_arvalid.value = 0
            return await self._until(lambda: int(d.s_axil_rvalid.value),
                                     lambda: (int(d.s_axil_rdata.value),
                                              int(d.s_axil_rresp.value)))

    async def access(self, addr, data=None, sel=0xF):
        self.n_access += 1
        if data is None:
            value, resp = await self.read(addr)
        else:
            value, resp = 0, await self.write(addr, data, sel)
        if resp not in (0, 2):
            self.violations.append(f"access {addr:#x}: resp {resp} (expected OKAY or SLVERR)")
        # the watcher counted the response at the falling edge before the
        # rising edge that took it, which write()/read() waited for
        if self.n_resp != self.n_access:
            self.violations.append(f"{self.n_resp} responses for {self.n_access} accesses")
        if self.violations:
            raise AssertionError("AXI-Lite handshake: " + "; ".join(self.violations))
        return value, resp == 2


async def _axil_activity(d):
    await First(RisingEdge(d.s_axil_awvalid), RisingEdge(d.s_axil_wvalid),
                RisingEdge(d.s_axil_arvalid), RisingEdge(d.s_axil_bvalid),
                RisingEdge(d.s_axil_rvalid))


# ---------------------------------------------------------------- the harness
def _param(dut, name, env, default):
    try:
        return int(getattr(dut, name).value)
    except Exception:  # noqa: BLE001 - not every simulator exposes parameters
        return int(os.environ.get(env, default))


class CoreTB:
    """Harness for tb_core.

    cells: one profile name (or None: no peripheral, the line is pulled
    down) per channel; only the first CHANNELS are used.
    """

    def __init__(self, dut, cells=("o2_v18", "o2_v15", "co2"), faults=None):
        self.dut = dut
        self.bus_kind = _param(dut, "BUS", "TWH_BUS", 0)
        self.channels = _param(dut, "CHANNELS", "TWH_CHANNELS", 3)
        self.fifo_depth = _param(dut, "FIFO_DEPTH", "TWH_FIFO_DEPTH", 16)
        self.clk_hz = _param(dut, "CLK_HZ", "TWH_CLK_HZ", 12_000_000)
        self.prog_timing = _param(dut, "PROG_TIMING", "TWH_PROG_TIMING", 1)
        self.polling = _param(dut, "POLLING", "TWH_POLLING", 1)
        # the time-shared engine queues four commands a channel behind the
        # command FIFO and hands each result straight into the result FIFO
        self.queue_depth = 4
        # results held back while the result FIFO is full: one a channel
        # (it waits in its channel)
        self.held_results = self.channels
        self.rm = regmap.load(channels=self.channels, fifo_depth=self.fifo_depth,
                              clk_hz=self.clk_hz)
        self.cells = tuple(cells)
        self.faults = faults
        self.pins = []
        self.models: List[Optional[PeripheralModel]] = []
        self.monitors: List[SpecMonitor] = []
        self.profiles = []
        for ch in range(self.channels):
            name = self.cells[ch] if ch < len(self.cells) else None
            self.profiles.append(profiles.PROFILES[name] if name else None)
        self.bus = None
        self.timing = [dict(DEFAULT_TIMING) for _ in range(self.channels)]
        self.results: List[Result] = []    # popped, not yet claimed by a wait
        self.popped: List[Result] = []     # every result popped, in order
        self.lab = False

    # ------------------------------------------------------------ start
    async def start(self):
        d = self.dut
        d.rst.value = 1
        # Icarus does not propagate values deposited on the top-level nets
        # before time starts (the WB handshake stayed X): drive them later.
        await Timer(1, "ns")
        d.rst.value = 1
        # tb_core: flat per-channel scalars (up to eight); tb_core_many: a
        # tb_engine_ch a channel (its regs start at 0)
        many = self.many = hasattr(d, "g_ch")
        for ch in range(0 if many else TB_CHANNELS):
            for sig in ("periph_o", "periph_oe", "stuck_en", "stuck_val", "glitch"):
                getattr(d, f"{sig}_{ch}").value = 0
        for ch in range(self.channels):
            if many:
                c = d.g_ch[ch].u_ch
                pins = types.SimpleNamespace(
                    line=c.line, periph_o=c.periph_o, periph_oe=c.periph_oe,
                    line_o=c.line_o, line_oe=c.line_oe, carrier=c.u_line.carrier)
            else:
                pins = types.SimpleNamespace(
                    line=getattr(d, f"line_{ch}"), periph_o=getattr(d, f"periph_o_{ch}"),
                    periph_oe=getattr(d, f"periph_oe_{ch}"), line_o=getattr(d, f"line_o_{ch}"),
                    line_oe=getattr(d, f"line_oe_{ch}"), carrier=getattr(d, f"u_line{ch}").carrier)
            self.pins.append(pins)
            prof = self.profiles[ch]
            self.models.append(PeripheralModel(pins, prof, self.faults or Faults(),
                                               line_log=f"line_{ch:02d}.log" if many else f"line_{ch}.log",
                                               carrier=pins.carrier)
                               if prof else None)
            self.monitors.append(SpecMonitor(pins, execute_max_us=prof.exec_max_us if prof else 10000,
                                             name=f"spec_ch{ch}",
                                             pin_log=f"pins_{ch:02d}.log" if many else f"pins_{ch}.log"))
        self.port = PortReady(d, sweep_clocks(self.channels, self.prog_timing,
                                              self.polling))
        self.port.start()
        self.bus = WishboneDriver(d, self.port) if self.bus_kind == 0 else AxiLiteDriver(d)
        self.bus.idle_inputs()
        for _ in range(4):
            await RisingEdge(d.clk)
        d.rst.value = 0
        await RisingEdge(d.clk)
        self.t_reset_us = get_sim_time("us")     # the first clock out of reset
        for m in self.monitors:
            m.start()
        for m in self.models:
            if m is not None:
                m.start()
        if self.bus_kind == 1:
            self.bus.start()
        return self

    # ------------------------------------------------------------ raw access
    async def access(self, addr, data=None, sel=0xF, timeout_us=ACCESS_TIMEOUT_US):
        """One 32-bit access: (read data or 0, True if it got a bus error)."""
        return await with_timeout(self.bus.access(addr, data, sel), timeout_us, "us")

    async def read32(self, addr):
        return await self.access(addr)

    async def write32(self, addr, value, sel=0xF):
        _, err = await self.access(addr, value, sel)
        return err

    # ------------------------------------------------------------ by name
    def reg(self, name, ch=None) -> regmap.Register:
        return self.rm[name if ch is None else f"CH[{ch}].{name}"]

    def addr(self, name, ch=None) -> int:
        return self.reg(name, ch).address

    async def read(self, name, ch=None) -> int:
        value, err = await self.read32(self.addr(name, ch))
        if err:
            raise BusError(f"read {name} ch={ch}: bus error")
        return value

    async def write(self, name, value, ch=None, expect_err=False):
        err = await self.write32(self.addr(name, ch), value)
        if err != expect_err:
            raise BusError(f"write {name} ch={ch} = {value:#010x}: "
                           f"{'bus error' if err else 'acknowledged'}, expected "
                           f"{'an error' if expect_err else 'an ack'}")
        return err

    def pack(self, name, ch=None, **fields) -> int:
        reg = self.reg(name, ch)
        v = 0
        for k, x in fields.items():
            v = reg.field(k).put(v, x)
        return v

    def unpack(self, name, value, ch=None) -> Dict[str, int]:
        return {f.name: f.get(value) for f in self.reg(name, ch).fields}

    async def fields(self, name, ch=None) -> types.SimpleNamespace:
        return types.SimpleNamespace(**self.unpack(name, await self.read(name, ch), ch))

    async def field(self, name, fname, ch=None) -> int:
        return self.reg(name, ch).field(fname).get(await self.read(name, ch))

    async def write_fields(self, name, ch=None, expect_err=False, **fields):
        return await self.write(name, self.pack(name, ch, **fields), ch, expect_err)

    async def errors(self) -> int:
        return await self.read("ERRORS")

    async def clear_errors(self):
        await self.write("ERRORS", self.reg("ERRORS").woclr_mask)
        assert await self.read("ERRORS") == 0

    # ------------------------------------------------------------ timing
    async def set_timing(self, ch, expect_refused=False, **us):
        """Program phase durations (microseconds) of channel `ch`; unnamed
        ones keep their value. With expect_refused the write must be refused
        (ERRORS.VALUE_REFUSED, register unchanged)."""
        new = dict(self.timing[ch])
        new.update(us)
        for rname in ("TIMING0", "TIMING1", "TIMING2"):
            fl = {f: new[ph] for ph, (r, f) in TIMING_FIELDS.items() if r == rname}
            cur = {f: self.timing[ch][ph] for ph, (r, f) in TIMING_FIELDS.items() if r == rname}
            if fl == cur:
                continue
            await self.write_fields(rname, ch, **fl)
            got = self.unpack(rname, await self.read(rname, ch), ch)
            if expect_refused:
                assert got == cur, (rname, ch, fl, got)
            else:
                assert got == fl, (rname, ch, fl, got)
        if not expect_refused:
            self.timing[ch] = new

    async def lab_unlock(self, flag=True):
        await self.write("LAB_KEY", LAB_KEY if flag else 0)
        assert await self.field("VERSION", "LAB_UNLOCKED") == int(flag)
        self.lab = flag

    async def lab_timing(self, channels=None):
        """Lab-short phases on the given channels (default all): unlock, put
        those monitors in lab mode, program LAB_TIMING."""
        await self.lab_unlock(True)
        for ch in (range(self.channels) if channels is None else channels):
            self.monitors[ch].allow_out_of_spec(True)
            await self.set_timing(ch, **LAB_TIMING)

    # ------------------------------------------------------------ commands
    async def push(self, cmd, payload=0x00AA, ch=0, tag=0, expect_err=False):
        """CMD_PUSH one command into channel ch's block (an absent channel's
        too: the map has 32); returns True when it was accepted."""
        v = self.pack("CMD_PUSH", 0, CMD=cmd, PAYLOAD=payload, TAG=tag)
        err = await self.write32(self.addr("CMD_PUSH", ch), v)
        if expect_err is not None and err != expect_err:
            raise BusError(f"push cmd={cmd:#04x} ch={ch} tag={tag}: "
                           f"{'refused' if err else 'accepted'}")
        return not err

    async def pop(self) -> Optional[Result]:
        """RES_INFO, then (if it shows a result) RES_POP; None when empty.
        The head cannot change between the two reads (only a pop removes
        it), so both must describe the same result."""
        info = self.unpack("RES_INFO", await self.read("RES_INFO"))
        if not info["VALID"]:
            return None
        pop = self.unpack("RES_POP", await self.read("RES_POP"))
        assert pop["VALID"], f"RES_INFO showed a result, RES_POP popped none: {info} {pop}"
        for k in ("STATUS", "CHANNEL", "TAG"):
            assert info[k] == pop[k], f"RES_INFO {info} and RES_POP {pop} disagree on {k}"
        r = Result(cmd=info["CMD"], data=pop["DATA"], status=pop["STATUS"],
                   channel=pop["CHANNEL"], tag=pop["TAG"])
        self.popped.append(r)
        return r

    async def drain(self) -> List[Result]:
        """Pop whatever is in the result FIFO now."""
        out = []
        while True:
            r = await self.pop()
            if r is None:
                return out
            self.results.append(r)
            out.append(r)

    async def wait_results(self, n, timeout_ms=200, poll_us=250, pred=None) -> List[Result]:
        """Wait until n results (matching pred) have been popped; they are
        claimed (removed from self.results) and returned in pop order."""
        pred = pred or (lambda r: True)
        t_end = get_sim_time("us") + timeout_ms * 1000
        while True:
            got = [r for r in self.results if pred(r)]
            if len(got) >= n:
                got = got[:n]
                for r in got:
                    self.results.remove(r)
                return got
            if get_sim_time("us") > t_end:
                raise AssertionError(f"only {len(got)} of {n} results after {timeout_ms} ms: {got}")
            if not await self.drain():
                await Timer(poll_us, "us")

    async def wait_result(self, ch, tag, timeout_ms=100) -> Result:
        return (await self.wait_results(1, timeout_ms,
                                        pred=lambda r: r.channel == ch and r.tag == tag))[0]

    async def command(self, cmd, payload=0x00AA, ch=0, tag=0, timeout_ms=100) -> Result:
        await self.push(cmd, payload, ch, tag)
        r = await self.wait_result(ch, tag, timeout_ms)
        assert r.cmd == cmd, r
        self.monitors[ch].check()
        return r

    async def wait_until(self, coro_fn, timeout_ms=100, poll_us=200):
        """Poll an async predicate until it is true."""
        t_end = get_sim_time("us") + timeout_ms * 1000
        while not await coro_fn():
            if get_sim_time("us") > t_end:
                raise AssertionError(f"condition not met within {timeout_ms} ms")
            await Timer(poll_us, "us")

    async def wait_idle(self, timeout_ms=200, drain=False):
        """Every channel idle (BUSY = 0, no slot full) and the command
        FIFO empty. With drain, results are popped meanwhile (into
        self.results), so a full result FIFO cannot hold the engines."""
        async def idle():
            if drain:
                await self.drain()
            st = await self.fields("STATUS")
            if await self.read("BUSY") or not st.CMD_EMPTY:
                return False
            for ch in range(self.channels):
                s = await self.fields("STATE", ch)
                if s.BUSY or s.SLOT_FULL:
                    return False
            return True
        try:
            await self.wait_until(idle, timeout_ms)
        except AssertionError:
            raise AssertionError(f"not idle after {timeout_ms} ms: {await self.describe()}") from None

    async def describe(self) -> str:
        """The core's state in one line (for failure messages)."""
        out = [f"STATUS {await self.fields('STATUS')}", f"LEVELS {await self.fields('LEVELS')}",
               f"CTRL {await self.read('CTRL'):#x}", f"BUSY {await self.read('BUSY'):#x}",
               f"IDLE_CHARGE {await self.read('IDLE_CHARGE'):#x}"]
        for ch in range(self.channels):
            out.append(f"ch{ch}: STATE {await self.fields('STATE', ch)} "
                       f"POLL_CTRL {await self.read('POLL_CTRL', ch):#010x} "
                       f"T0 {await self.read('TIMING0', ch):#010x} T1 {await self.read('TIMING1', ch):#010x} "
                       f"T2 {await self.read('TIMING2', ch):#010x} txns {len(self.txns(ch))}")
        return "; ".join(out)

    # ------------------------------------------------------------ line views
    def txns(self, ch):
        """Transactions the spec monitor of channel ch saw (complete ones
        and the one listening now)."""
        return self.monitors[ch].transactions

    def frames(self, ch):
        return [bytes(t.frame) for t in self.txns(ch)]

    # ------------------------------------------------------------ end
    async def finish(self, expect_empty=True):
        """End of test: every spec monitor is closed and checked, no model
        saw the host drive the line while it answered, no result is left
        unclaimed."""
        errors = []
        for ch, m in enumerate(self.monitors):
            try:
                m.finish()
            except AssertionError as e:
                errors.append(f"channel {ch}: {e}")
        for ch, m in enumerate(self.models):
            if m is not None:
                m.stop()
                coll = [t for t in m.log if t.collision]
                if coll:
                    errors.append(f"channel {ch}: host drove the line during {len(coll)} answer(s)")
        if errors:
            raise AssertionError("\n".join(errors))
        if expect_empty:
            assert not self.results, f"unclaimed results: {self.results}"
            assert await self.pop() is None, "results left in the result FIFO"
        self.write_transcript()

    def write_transcript(self, path="transcript.txt"):
        """Every result popped, then per channel every frame its cell
        handled (with the answer) and every transaction its spec monitor
        measured: what make test-slow requires to be the same on Icarus
        and Verilator (tb/simrun.py)."""
        lines = [f"result ch{r.channel} {r.cmd:02X} {r.data:04X} {r.status} {r.tag}"
                 for r in self.popped]
        for ch in range(self.channels):
            lines.append(f"channel {ch}")
            if self.models[ch] is not None:
                lines += [x.transcript() for x in self.models[ch].logic.log]
            lines += [t.transcript() for t in self.monitors[ch].transactions]
        with open(path, "w") as f:
            f.write("\n".join(lines) + "\n")
