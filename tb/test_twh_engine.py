"""twh_engine: every channel of the time-shared engine against its own
behavioural peripheral, all at once.

Each channel's line has its own independent spec monitor (the timing table,
carrier, bit rate, framing, checksum) over the whole test, and its own
peripheral model; each result is checked against what that channel's model
put on its line. The pytest functions at the bottom build and run these
cocotb tests in make test-slow, which CI runs: 3, 16 and 32 channels on
Verilator, two cases at 3 channels on Icarus.
"""
import types
from collections import defaultdict

import cocotb
import pytest
from cocotb.queue import Queue
from cocotb.triggers import FallingEdge, RisingEdge, Timer
from cocotb.utils import get_sim_time

import profiles
import protocol as p
from periph_model import Faults, PeripheralModel
from protocol import Status
from spec_monitor import SpecMonitor

# NOTES.md defaults, microseconds; field codes 1 charge .. 6 turnaround
TIMING = dict(charge=8000, sync=1000, preamble=2000, execute=4000, listen=3000, turnaround=2000)
FIELDS = ("charge", "sync", "preamble", "execute", "listen", "turnaround")
PROFILE_CYCLE = ("o2_v18", "o2_v15", "co2", "o2_v26", "co2_stick")
TXN_US = sum(TIMING.values()) + 1408    # the longest default transaction


class EngineTB:
    def __init__(self, dut, profiles_by_ch=None, faults=None):
        self.dut = dut
        self.n = int(dut.CHANNELS.value)
        names = profiles_by_ch or [PROFILE_CYCLE[c % len(PROFILE_CYCLE)] for c in range(self.n)]
        self.profiles = [profiles.PROFILES[x] for x in names]
        self.pins, self.models, self.monitors = [], [], []
        for c in range(self.n):
            ch = dut.g_ch[c].u_ch
            pins = types.SimpleNamespace(line=ch.line, periph_o=ch.periph_o, periph_oe=ch.periph_oe,
                                         line_o=ch.line_o, line_oe=ch.line_oe,
                                         stuck_en=ch.stuck_en, stuck_val=ch.stuck_val,
                                         carrier=ch.u_line.carrier)
            self.pins.append(pins)
            prof = self.profiles[c]
            self.models.append(PeripheralModel(pins, prof, (faults or {}).get(c, Faults()),
                                               line_log=f"line_{c:02d}.log", carrier=pins.carrier))
            self.monitors.append(SpecMonitor(pins, execute_max_us=prof.exec_max_us,
                                             name=f"spec_ch{c}", pin_log=f"pins_{c:02d}.log"))
        self.results = defaultdict(Queue)   # per channel
        # None: every result is taken at once; else the room left in a
        # modelled result FIFO (m_res_ready while there is room)
        self.room = None
        self.taken = []                     # (time_us, channel, code, data, status, tag)
        self.submitted = defaultdict(list)  # per channel: (code, payload, tag, skip)

    async def start(self, idle_charge=0):
        d = self.dut
        d.cfg_idle_charge.value = idle_charge
        d.t_we.value = 0
        d.s_cmd_valid.value = 0
        d.s_cmd_skip.value = 0
        d.s_cmd_ch.value = 0
        d.s_cmd_code.value = 0
        d.s_cmd_payload.value = 0
        d.s_cmd_tag.value = 0
        d.m_res_ready.value = 1
        d.rst.value = 1
        await Timer(1, "us")
        await FallingEdge(d.clk)
        for c in range(self.n):
            for f, name in enumerate(FIELDS, start=1):
                await self.set_length(c, f, TIMING[name])
        d.rst.value = 0
        for m in self.monitors:
            m.start()
        for m in self.models:
            m.start()
        cocotb.start_soon(self._collect())

    async def set_length(self, ch, fld, us):
        d = self.dut
        await FallingEdge(d.clk)
        d.t_ch.value = ch
        d.t_fld.value = fld
        d.t_len.value = us
        d.t_we.value = 1
        await FallingEdge(d.clk)
        d.t_we.value = 0

    async def submit(self, ch, code, payload=0x00AA, tag=0, skip=0):
        d = self.dut
        await FallingEdge(d.clk)
        d.s_cmd_ch.value = ch
        d.s_cmd_code.value = code
        d.s_cmd_payload.value = payload
        d.s_cmd_tag.value = tag
        d.s_cmd_skip.value = skip
        d.s_cmd_valid.value = 1
        while True:
            await Timer(1, "ns")            # the inputs settled, well before the edge
            ready = int(d.s_cmd_ready.value)
            await FallingEdge(d.clk)        # past the edge that sampled them
            if ready:
                break
        d.s_cmd_valid.value = 0
        self.submitted[ch].append((code, payload, tag, skip))

    async def _collect(self):
        d = self.dut
        fall, valid_rise = FallingEdge(d.clk), RisingEdge(d.m_res_valid)
        while True:
            # a falling edge only while a result may be offered: waking at
            # every one was a third of a run at 16 MHz
            if not int(d.m_res_valid.value):
                await valid_rise
            await fall
            if int(d.m_res_valid.value) and int(d.m_res_ready.value):
                r = types.SimpleNamespace(
                    t_us=get_sim_time("us"), ch=int(d.m_res_ch.value), code=int(d.m_res_code.value),
                    data=int(d.m_res_data.value), status=Status(int(d.m_res_status.value)),
                    tag=int(d.m_res_tag.value))
                self.taken.append(r)
                self.results[r.ch].put_nowait(r)
                if self.room is not None:
                    # (ready drops only after the edge that takes it: the
                    # engine's valid follows ready within the clock)
                    self.room -= 1
                    await RisingEdge(d.clk)
                    d.m_res_ready.value = int(self.room is None or self.room > 0)

    def set_room(self, room):
        """Model a result FIFO with `room` places left (None: unlimited);
        call between a falling edge and the next rising one."""
        self.room = room
        self.dut.m_res_ready.value = int(room is None or room > 0)

    async def result(self, ch):
        return await self.results[ch].get()

    def check_channel(self, ch, results):
        """Every submitted command has its one result, in order, and each
        result that reached the line is what the model put there."""
        subs = self.submitted[ch]
        assert len(results) == len(subs), (ch, len(results), len(subs))
        on_line = [r for r, s in zip(results, subs) if s[3] == 0]
        log = self.models[ch].log
        assert len(log) == len(on_line), (ch, len(log), len(on_line))
        for r, s in zip(results, subs):
            assert (r.code, r.tag) == (s[0], s[2]), (ch, r, s)
            if s[3]:
                assert r.status == Status(s[3]) and r.data == 0, (ch, r)
        for r, txn in zip(on_line, log):
            assert bytes(txn.frame) == p.build_frame(r.code, self._payload(ch, r)), (ch, txn.frame)
            if r.status in (Status.OK, Status.BAD_CHECKSUM):
                assert txn.response is not None and r.data == (txn.response[0] << 8 | txn.response[1]), \
                    (ch, r, txn.response)
            else:
                assert r.data == 0, (ch, r)

    def _payload(self, ch, r):
        for code, payload, tag, skip in self.submitted[ch]:
            if (code, tag) == (r.code, r.tag) and not skip:
                return payload
        raise AssertionError(r)

    async def finish(self):
        # A result goes out at the visit after the listen's last, up to a
        # carrier period before the turnaround's drive reaches the line
        # (the drive lands one or two ticks after its visit): let the line
        # leave the listen before the monitor closes its last transaction.
        await Timer(2, "us")
        for m in self.monitors:
            m.finish()
        for ch in range(self.n):
            assert self.results[ch].empty(), f"channel {ch}: unclaimed results"


async def drain(tb, ch, count):
    return [await tb.result(ch) for _ in range(count)]


@cocotb.test()
async def concurrent_pages(dut):
    """Every channel reads its identity and a page of words at once: each
    answer is its own cell's, every line keeps the spec, and the channels
    run side by side (the whole set takes as long as one channel's)."""
    tb = EngineTB(dut)
    await tb.start()
    cmds = [(p.CMD_FIRMWARE, 0x00AA), (p.CMD_CONFIG, 0x00AA), p.addr_cmd(p.CMD_READ, 0x10)]
    if tb.n > 16:
        cmds = cmds[:1]         # a 32-cell rig: each cell's identity (make test's time)
    elif tb.n > 8:
        cmds = cmds[::2]        # each cell's identity and first serial word
    t0 = get_sim_time("us")
    for i, (code, payload) in enumerate(cmds):
        for ch in range(tb.n):
            await tb.submit(ch, code, payload, tag=(ch * 8 + i) & 0xFF)
    got = {ch: await drain(tb, ch, len(cmds)) for ch in range(tb.n)}
    elapsed = get_sim_time("us") - t0
    for ch in range(tb.n):
        assert all(r.status == Status.OK for r in got[ch]), (ch, got[ch])
        tb.check_channel(ch, got[ch])
        fw = got[ch][0].data
        assert fw >> 8 == tb.profiles[ch].fw_byte and fw & 0xFF == tb.profiles[ch].type_byte
    # concurrency: a few transactions each, not a few per channel in turn
    assert elapsed < (len(cmds) + 1) * TXN_US, elapsed
    starts = [tb.monitors[ch].transactions[0].start_ps / 1e6 for ch in range(tb.n)]
    assert max(starts) - min(starts) < 100, starts
    await tb.finish()


@cocotb.test()
async def faults_per_channel(dut):
    """Each channel's cell misbehaves its own way at the same time; every
    channel reports its own fault and no other."""
    n = int(dut.CHANNELS.value)
    plan = [
        (Faults(), Status.OK),
        (Faults(bad_checksum=True), Status.BAD_CHECKSUM),
        (Faults(no_response=True), Status.NO_RESPONSE),
        (Faults(truncate=2), Status.SHORT_RESPONSE),
        (Faults(bad_stop_bit=1), Status.FRAMING),
        (Faults(baud=30750, carrier_hz=0.9e6, duty=0.3), Status.OK),
        (Faults(baud=31750, carrier_hz=1.1e6, duty=0.7), Status.OK),
        (Faults(baseband=True, stop_bits=1), Status.OK),
    ]
    tb = EngineTB(dut, faults={c: plan[c % len(plan)][0] for c in range(n)})
    await tb.start()
    for ch in range(n):
        await tb.submit(ch, p.CMD_FIRMWARE, tag=ch)
    for ch in range(n):
        r = await tb.result(ch)
        assert r.status == plan[ch % len(plan)][1], (ch, r)
        tb.check_channel(ch, [r])
    await tb.finish()


@cocotb.test()
async def stuck_lines(dut):
    """A line held high reads as stuck high, one held low as stuck low,
    and the channels beside them answer normally."""
    tb = EngineTB(dut)
    n = tb.n
    await tb.start()
    tb.models[0].stop()
    tb.pins[0].stuck_val.value = 1
    tb.pins[0].stuck_en.value = 1
    if n > 1:
        tb.models[1].stop()
        tb.pins[1].stuck_val.value = 0
        tb.pins[1].stuck_en.value = 1
    for ch in range(n):
        await tb.submit(ch, p.CMD_FIRMWARE, tag=ch)
    want = {0: Status.LINE_STUCK_HIGH, 1: Status.LINE_STUCK_LOW}
    for ch in range(n):
        r = await tb.result(ch)
        assert r.status == want.get(ch, Status.OK), (ch, r)
    # the monitors watch the host's drive, which kept the spec throughout
    for m in tb.monitors:
        m.check()


@cocotb.test()
async def no_head_of_line_blocking(dut):
    """Four reads queued for channel 0, then one for the last channel: the
    last channel is answered after one transaction, channel 0's keep their
    order, and skipped commands are answered in their place at once."""
    tb = EngineTB(dut)
    await tb.start()
    last = tb.n - 1
    assert last > 0, "needs two channels"
    t0 = get_sim_time("us")
    for a in range(3):
        await tb.submit(0, *p.addr_cmd(p.CMD_READ, a), tag=a)
    await tb.submit(0, p.CMD_FIRMWARE, tag=3, skip=int(Status.BLOCKED))
    await tb.submit(last, p.CMD_FIRMWARE, tag=9)
    r = await tb.result(last)
    assert r.status == Status.OK and r.tag == 9, r
    assert get_sim_time("us") - t0 < 1.2 * TXN_US
    got0 = await drain(tb, 0, 4)
    assert [x.tag for x in got0] == [0, 1, 2, 3], got0
    assert all(x.status == Status.OK for x in got0[:3]), got0
    assert got0[3].status == Status.BLOCKED and got0[3].data == 0
    tb.check_channel(0, got0)
    await tb.finish()


@cocotb.test()
async def results_held_back(dut):
    """With no room for results (m_res_ready 0: the result FIFO full), no
    result goes out; every channel finishes its transaction, keeps its
    result and starts no other. Once results flow, all arrive, none lost
    and none twice."""
    tb = EngineTB(dut)
    await tb.start()
    tb.set_room(0)
    for ch in range(tb.n):
        await tb.submit(ch, p.CMD_FIRMWARE, tag=1)
        await tb.submit(ch, p.CMD_CONFIG, tag=2)
    await Timer(int(2.5 * TXN_US), "us")
    runs = [len(tb.models[ch].log) for ch in range(tb.n)]
    assert runs == [1] * tb.n, runs
    await Timer(TXN_US, "us")
    assert [len(tb.models[ch].log) for ch in range(tb.n)] == runs
    assert not tb.taken and int(dut.m_res_valid.value) == 0
    assert all(int(dut.busy.value) >> ch & 1 for ch in range(tb.n))
    await FallingEdge(dut.clk)
    tb.set_room(None)
    for ch in range(tb.n):
        got = await drain(tb, ch, 2)
        assert [r.tag for r in got] == [1, 2] and all(r.status == Status.OK for r in got), got
        tb.check_channel(ch, got)
    await tb.finish()


@cocotb.test()
async def result_register_fairness(dut):
    """A channel's result gets room in the result FIFO while results flow,
    however busy its neighbours are. The FIFO is modelled full, one place
    freed every 20 us, always in the clock after channel 2's visit, so
    channel 0, visited next, would take every place: channels 0 and 1
    answer a stream of skipped (BLOCKED) commands, each with a result
    waiting at every visit, from 15 to 45 ms after the reset. Channel 2's
    result must come out about when its transaction ends, not when the
    stream stops (the claim: the first channel refused takes the next
    place)."""
    tb = EngineTB(dut)
    await tb.start()
    await tb.submit(2, p.CMD_FIRMWARE, tag=7)
    t_sub = get_sim_time("us")
    # channel 2's listen ends about 21 ms after the reset (the turnaround's
    # hold-off, then the default phases); the stream runs from 15 to 45 ms
    await Timer(15_000, "us")
    stop_at = t_sub + 45_000
    await FallingEdge(dut.clk)
    tb.set_room(0)
    eng = dut.dut
    freed = 0

    async def slow_reader():
        nonlocal freed
        while get_sim_time("us") < stop_at:
            await Timer(20, "us")
            while True:
                await FallingEdge(dut.clk)
                if int(eng.s2_v.value) and int(eng.s2_ch.value) == 2:
                    break
            # the clock after channel 2's S2 has no visit's S2 (3 channels,
            # four clocks a period): channel 0's comes next
            await FallingEdge(dut.clk)
            tb.set_room(tb.room + 1)
            freed += 1
        await FallingEdge(dut.clk)
        tb.set_room(None)

    cocotb.start_soon(slow_reader())
    fed = 0
    while get_sim_time("us") < stop_at:
        for ch in (0, 1):
            await tb.submit(ch, p.CMD_FIRMWARE, tag=fed & 0xFF, skip=int(Status.BLOCKED))
        fed += 1
    t_stop = get_sim_time("us")
    r = await tb.result(2)
    dut._log.info("channel 2's result %.0f us after its submission, the stream (%d pairs, "
                  "%d places freed) stopped at %.0f us", r.t_us - t_sub, fed, freed, t_stop - t_sub)
    assert freed > 1000, freed
    assert r.status == Status.OK and r.tag == 7, r
    assert r.t_us - t_sub < TXN_US + 2_000, \
        f"channel 2's result waited for the stream: {r.t_us - t_sub:.0f} us after its submission"
    tb.check_channel(2, [r])
    for ch in (0, 1):
        tb.check_channel(ch, await drain(tb, ch, fed))
    await tb.finish()


@cocotb.test()
async def reset_mid_transaction(dut):
    """A reset in the middle of the command phase releases every line at
    once, drops what was queued (no result), and the engine then waits the
    minimum turnaround before its next charge and works again."""
    tb = EngineTB(dut)
    await tb.start()
    for ch in range(tb.n):
        await tb.submit(ch, p.CMD_FIRMWARE)
    await Timer(TIMING["charge"] + TIMING["sync"] + TIMING["preamble"] + 500, "us")
    for m in tb.monitors:
        m.reset_seen()
    d = tb.dut
    await FallingEdge(d.clk)
    d.rst.value = 1
    await FallingEdge(d.clk)
    await FallingEdge(d.clk)
    for ch in range(tb.n):
        assert int(tb.pins[ch].line_oe.value) == 0
    d.rst.value = 0
    assert int(d.busy.value) == 0
    for ch in range(tb.n):
        tb.submitted[ch].clear()
        tb.models[ch].log.clear()
    await Timer(3 * TXN_US, "us")        # the cells give up on the cut frame
    for ch in range(tb.n):
        tb.models[ch].log.clear()
        await tb.submit(ch, p.CMD_FIRMWARE, tag=5)
    for ch in range(tb.n):
        r = await tb.result(ch)
        assert r.status == Status.OK and r.tag == 5, (ch, r)
    await tb.finish()


@cocotb.test()
async def idle_charge_and_phase(dut):
    """Idle charge is per channel: once the post-reset turnaround is out,
    channel 0 keeps its carrier on while idle and the others stay released;
    every channel's phase output follows its transaction and each line
    keeps the spec (channel 0's charge includes its idle carrier)."""
    tb = EngineTB(dut)
    await tb.start(idle_charge=1)           # channel 0 only
    await Timer(2500, "us")
    assert int(tb.pins[0].line_oe.value) == 1
    for ch in range(1, tb.n):
        assert int(tb.pins[ch].line_oe.value) == 0, ch
    assert all(int(dut.phase.value) >> (3 * ch) & 7 == p.Phase.IDLE for ch in range(tb.n))
    for ch in range(tb.n):
        await tb.submit(ch, p.CMD_FIRMWARE, tag=ch)
    seen = [set() for _ in range(tb.n)]
    for _ in range(2 * TXN_US // 250):
        await Timer(250, "us")
        ph = int(dut.phase.value)
        for ch in range(tb.n):
            seen[ch].add(p.Phase(ph >> (3 * ch) & 7))
        if all(tb.results[ch].qsize() for ch in range(tb.n)):
            break
    for ch in range(tb.n):
        r = await tb.result(ch)
        assert r.status == Status.OK, (ch, r)
        tb.check_channel(ch, [r])
        assert seen[ch] >= {p.Phase.CHARGE, p.Phase.SYNC, p.Phase.PREAMBLE, p.Phase.COMMAND,
                            p.Phase.EXECUTE, p.Phase.LISTEN}, (ch, seen[ch])
    await tb.finish()


TESTS = ["concurrent_pages", "faults_per_channel", "stuck_lines", "no_head_of_line_blocking",
         "results_held_back", "reset_mid_transaction", "idle_charge_and_phase"]


def _run(channels, clk_hz, testcase, sim):
    from simrun import run
    run("tb_engine", "test_twh_engine", f"engine_{sim}_{channels}ch_{testcase}",
        parameters={"CHANNELS": channels, "CLK_HZ": clk_hz}, testcase=testcase,
        tb_sources=["tb_engine.v"], sim=sim)


# All in make test-slow, which CI runs (make test is at its 5 minutes, and
# runs the engine through the bus core's cases, tb/test_twh_core.py): the seven cases at 3 channels at the
# 4 MHz floor and a 32-cell rig at its 32 MHz floor (each cell's identity,
# and its faults) and 16 channels at their 16 MHz floor, on Verilator; two
# of the cases on Icarus (the same bench on the other simulator).
@pytest.mark.slow
@pytest.mark.parametrize("testcase", TESTS)
def test_engine_3ch(testcase):
    _run(3, 4_000_000, testcase, "verilator")


# the hand-over's claim: a channel is not kept from the result FIFO's room
# by two busy neighbours
@pytest.mark.slow
def test_engine_3ch_fairness():
    _run(3, 4_000_000, "result_register_fairness", "verilator")


@pytest.mark.slow
def test_engine_32ch():
    _run(32, 32_000_000, "concurrent_pages", "verilator")


@pytest.mark.slow
def test_engine_32ch_faults():
    _run(32, 32_000_000, "faults_per_channel", "verilator")


@pytest.mark.slow
def test_engine_16ch():
    _run(16, 16_000_000, "concurrent_pages", "verilator")


@pytest.mark.slow
@pytest.mark.parametrize("testcase", ["faults_per_channel", "idle_charge_and_phase"])
def test_engine_3ch_icarus(testcase):
    _run(3, 4_000_000, testcase, "icarus")
