"""`make demo`, the waveform half (tb/demo.py): the C driver (libtwh.so)
co-simulated with the Wishbone core on Icarus, three channels with a digital
O2 cell (firmware v18), an older O2 cell (v15) and a CO2 sensor, for
build/demo/demo.vcd. The spec monitors check every transaction on every line.

After the timing negotiation (blocking helpers, one channel after the
other), each channel's readings are queued with the driver's non-blocking
twh_submit and collected with twh_result, so all three engines run at once.
The sensor pages themselves (a few hundred transactions) are the other half,
on the Verilated core (sim/soak/soak_main.cpp --page).
"""
import ctypes as C

import cocotb
from cocotb.triggers import RisingEdge

import protocol as p
import twh_ctypes as T
from coretb import CoreTB
from cosim import Cosim
from periph_model import PeripheralLogic

CELLS = ("o2_v18", "o2_v15", "co2")
TYPES = {1: "Digital O2 sensor", 2: "CO2 sensor", 3: "CO2 temperature stick"}
STATUS = ["OK", "NO_RESPONSE", "BAD_CHECKSUM", "FRAMING", "SHORT_RESPONSE",
          "LINE_STUCK_LOW", "LINE_STUCK_HIGH", "BLOCKED", "CANCELLED"]
# the readings queued on every channel: its configuration (0x40), its
# temperature (0x43) and its sensor reading (0x44); the pages' few hundred
# commands are the Verilated half's
READINGS = [(0x40, 0xAA), (0x43, 0xAA), (0x44, 0xAA)]


def out(text=""):
    print(text, flush=True)


@cocotb.test()
async def demo(dut):
    tb = await CoreTB(dut, cells=CELLS).start()
    for ch in range(3):   # the shortest legal transaction keeps the demo quick
        await tb.set_timing(ch, charge=7000, sync=900, preamble=1800, listen=2000,
                            turnaround=2000)
    cs = Cosim(tb)
    t = C.byref(cs.t)
    assert await cs.call("twh_init", t, C.byref(cs.plat)) == 0
    out(f"core: {cs.t.channels} channels, FIFO depth {cs.t.fifo_depth}, "
        f"{cs.t.clk_khz} kHz, version {cs.t.version_major}.{cs.t.version_minor}")

    queue = {}
    for ch in range(3):
        rc, fw = await cs.negotiate(ch)
        assert rc == 0, (ch, T.ERRORS.get(rc))
        assert fw.raw == tb.profiles[ch].fw_byte, (ch, hex(fw.raw))
        execute = await tb.field("TIMING1", "EXECUTE_US", ch)
        out(f"ch{ch}: firmware byte 0x{fw.raw:02X} -> v{fw.version}, "
            f"{TYPES.get(fw.type, 'reserved')}: execute {execute} us")
        queue[ch] = list(READINGS)

    # all three channels at once, two commands in flight per channel
    out("readings as their results arrive (channel, frame on the line, result):")
    inflight = {}
    res = T.Result()
    while any(queue.values()) or inflight:
        for ch, q in queue.items():
            while q and sum(1 for k in inflight if k[0] == ch) < 2:
                cmd, arg = q.pop(0)
                tag = await cs.call("twh_submit", t, ch, cmd, arg)
                assert tag >= 0, T.ERRORS.get(tag)
                inflight[(ch, tag)] = (cmd, arg)
        rc = await cs.call("twh_result", t, C.byref(res))
        if rc == T.ERR["AGAIN"]:
            if not dut.irq.value:           # IRQ_EN.RESULT, set by twh_init
                await RisingEdge(dut.irq)
            continue
        assert rc == 0, T.ERRORS.get(rc)
        cmd, arg = inflight.pop((res.channel, res.tag))
        frame = " ".join(f"{b:02X}" for b in p.build_frame(res.cmd, arg & 0xFF))
        data = f"{res.data:04X}" if res.status in (0, 2) else "----"
        out(f"  ch{res.channel}  {frame:<9} {p.command_name(res.cmd):<12} -> "
            f"{STATUS[res.status]:<12} {data}")
        err = await cs.call("twh_status_err", res.status, res.cmd)
        assert err == 0, (res.channel, hex(res.cmd), STATUS[res.status])
        # every answer is the one the cell's command logic gives (none of
        # these commands changes its flash)
        ans = PeripheralLogic(tb.profiles[res.channel]).handle(p.build_frame(res.cmd, arg & 0xFF))
        assert res.status == 0 and res.data == (ans[0] << 8 | ans[1]), \
            (res.channel, hex(res.cmd), STATUS[res.status], hex(res.data), ans)

    n = sum(len(mon.transactions) for mon in tb.monitors)
    out()
    out(f"{n} transactions on 3 lines, every one inside the spec's timing table (spec monitors); "
        f"{cs.accesses} bus accesses by the driver, {cs.irq_waits} interrupt waits")
    await tb.finish()
