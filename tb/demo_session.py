"""`make demo`: the C driver (libtwh.so) runs a sensor session on the
Wishbone core, co-simulated: three channels with a digital O2 cell (firmware
v18), an older O2 cell (v15) and a CO2 sensor. The spec monitors check every
transaction on every line. For each channel it prints the page a diver's
computer would show.

The three channels run at once: after the timing negotiation (blocking
helpers), every further command is queued with the driver's non-blocking
twh_submit and collected with twh_result, so all three engines stay busy.
"""
import ctypes as C
from datetime import datetime, timedelta

import cocotb
from cocotb.triggers import RisingEdge

import protocol as p
import twh_ctypes as T
from coretb import CoreTB
from cosim import Cosim

CELLS = ("o2_v18", "o2_v15", "co2")
TYPES = {1: "Digital O2 sensor", 2: "CO2 sensor", 3: "CO2 temperature stick"}
# flash words the page needs: model, MFG ID, dates; serial and factory cal
WORDS = {1: list(range(0x00, 0x0E)) + list(range(0x10, 0x1A)),
         2: list(range(0x00, 0x0E)) + list(range(0x10, 0x19))}
STATUS = ["OK", "NO_RESPONSE", "BAD_CHECKSUM", "FRAMING", "SHORT_RESPONSE",
          "LINE_STUCK_LOW", "LINE_STUCK_HIGH", "BLOCKED", "CANCELLED"]


def out(text=""):
    print(text, flush=True)


def fmt_dt(dt):
    return f"{dt.year:04d}-{dt.month:02d}-{dt.day:02d} {dt.hour:02d}:{dt.minute:02d}"


def cal_date(m):
    """Date of the current calibration: manufacture + stamp x unit hours."""
    made = datetime(m.manufactured.year, m.manufactured.month, m.manufactured.day,
                    m.manufactured.hour, m.manufactured.minute)
    return f"{made + timedelta(hours=m.current.stamp * m.cal_unit_hours):%Y-%m-%d %H:%M}"


class Channel:
    def __init__(self, ch, fw):
        self.ch, self.fw = ch, fw
        self.kind = T.MAP_O2 if fw.type == 1 else T.MAP_CO2
        self.queue = [(c, 0xAA) for c in (0x40, 0x42, 0x43, 0x44)] + [(0x46, 0x20)]
        self.queue += [(0x48, a) for a in WORDS[self.kind]]
        self.answers = {}
        self.words = {}


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

    chans = []
    for ch in range(3):
        rc, fw = await cs.negotiate(ch)
        assert rc == 0, (ch, T.ERRORS.get(rc))
        execute = await tb.field("TIMING1", "EXECUTE_US", ch)
        out(f"ch{ch}: firmware byte 0x{fw.raw:02X} -> v{fw.version}, "
            f"{TYPES.get(fw.type, 'reserved')}: execute {execute} us")
        chans.append(Channel(ch, fw))

    # all three channels at once, two commands in flight per channel
    out("commands as their results arrive (channel, frame on the line, result):")
    inflight = {}
    res = T.Result()
    while any(c.queue for c in chans) or inflight:
        for c in chans:
            while c.queue and sum(1 for k in inflight if k[0] == c.ch) < 2:
                cmd, arg = c.queue.pop(0)
                code, payload = (cmd | (arg >> 8), arg & 0xFF) if cmd in (0x46, 0x48) else (cmd, arg)
                tag = await cs.call("twh_submit", t, c.ch, code, payload)
                assert tag >= 0, T.ERRORS.get(tag)
                inflight[(c.ch, tag)] = (cmd, arg)
        rc = await cs.call("twh_result", t, C.byref(res))
        if rc == T.ERR["AGAIN"]:
            if not dut.irq.value:           # IRQ_EN.RESULT, set by twh_init
                await RisingEdge(dut.irq)
            continue
        assert rc == 0, T.ERRORS.get(rc)
        cmd, arg = inflight.pop((res.channel, res.tag))
        c = chans[res.channel]
        frame = " ".join(f"{b:02X}" for b in p.build_frame(res.cmd, arg & 0xFF))
        data = f"{res.data:04X}" if res.status in (0, 2) else "----"
        out(f"  ch{res.channel}  {frame:<9} {p.command_name(res.cmd):<12} -> "
            f"{STATUS[res.status]:<12} {data}")
        err = await cs.call("twh_status_err", res.status, res.cmd)
        assert err == 0, (res.channel, hex(res.cmd), STATUS[res.status])
        if cmd == 0x48:
            c.words[arg] = res.data & 0x3FFF
        else:
            c.answers[cmd] = res.data
        if cmd == 0x46:   # field calibrations: every word below the first free one
            c.queue += [(0x48, a) for a in range(0x20, res.data)]

    for c in chans:
        size = ((c.answers[0x40] >> 8) & 1) << 8 | (c.answers[0x40] & 0xFF)
        img = (C.c_uint16 * size)(*([0x3FFF] * size))
        for a, w in c.words.items():
            img[a] = w
        m = T.Map()
        assert await cs.call("twh_decode_map", img, size, c.kind, C.byref(m)) == 0
        supply, temp = C.c_int32(), C.c_int32()
        rc_s = await cs.call("twh_supply_mv", c.answers[0x42] & 0xFFF, C.byref(supply))
        rc_t = await cs.call("twh_temperature_c100", c.answers[0x43] & 0xFFF, m.ref_temp,
                             m.adc_ref, supply.value, m.temp_scale, C.byref(temp))
        out()
        out(f"== channel {c.ch}: {TYPES.get(c.fw.type)}, firmware v{c.fw.version}")
        out(f"  model            {m.model.decode()}   (MFG ID {m.mfg_id.decode()})")
        out(f"  serial           {m.serial.decode()}")
        out(f"  manufactured     {fmt_dt(m.manufactured)}   expires {fmt_dt(m.expires)}")
        out(f"  flash            {size} words")
        out(f"  supply           {supply.value if rc_s == 0 else '?'} mV")
        out(f"  temperature      {temp.value / 100:.2f} C" if rc_t == 0 else "  temperature      ?")
        if c.kind == T.MAP_O2:
            adc = c.answers[0x44] & 0xFFF
            o2 = await cs.call("twh_o2_mv100", adc, m.opamp_offset)
            out(f"  O2 cell          {o2 / 100:.2f} mV")
            if m.current.addr:
                ppo2 = await cs.call("twh_ppo2_mbar", adc, m.current.value)
                out(f"  PPO2             {ppo2 / 1000:.3f} bar (calibrated {cal_date(m)}, "
                    f"gain {m.current.value}, record at 0x{m.current.addr:02X})")
        elif m.current.addr:
            out(f"  CO2 400 ppm cal  reading {m.current.value} (calibrated {cal_date(m)})")
        out(f"  calibrations     {m.cal_count} stored")
    n = sum(len(mon.transactions) for mon in tb.monitors)
    out()
    out(f"{n} transactions on 3 lines, every one inside the spec's timing table (spec monitors); "
        f"{cs.accesses} bus accesses by the driver, {cs.irq_waits} interrupt waits")
    await tb.finish()
