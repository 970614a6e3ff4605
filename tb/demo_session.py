"""`make demo`: a scripted session against a modelled digital O2 cell.

The host core (twh_link at 12 MHz, the iCEBreaker's clock) talks to the
behavioural O2 cell over the simulated line while the spec monitor checks
every transaction. Each command, its result and the decoded values are
printed; the host pins are dumped to build/demo/demo.vcd.
"""
from datetime import timedelta

import cocotb

import flashmap as fm
import profiles
import protocol as p
from linktb import LinkTB
from periph_model import PeripheralModel
from protocol import Status

TYPES = {1: "Digital O2 sensor", 2: "CO2 sensor", 3: "CO2 temperature stick"}


def out(text=""):
    print(text, flush=True)


@cocotb.test()
async def demo(dut):
    prof = profiles.O2_V18
    model = PeripheralModel(dut, prof)
    tb = LinkTB(dut, model, execute_max_us=prof.exec_max_us)
    await tb.start()
    # the shortest legal transaction keeps the demo quick
    tb.set_timing(charge=7000, sync=900, preamble=1800, execute=4000,
                  listen=2000, turnaround=2000)

    async def cmd(code, payload=0xAA, note=""):
        res = await tb.command(code, payload)
        frame = " ".join(f"{b:02X}" for b in p.build_frame(code, payload))
        data = f"{res.data:04X}" if res.status in (Status.OK, Status.BAD_CHECKSUM) else "----"
        out(f"  {frame:<12} {p.command_name(code):<12} -> {res.status.name:<12} {data}  {note}")
        return res

    out("== identity and health")
    res = await cmd(0x41)
    fw = p.decode_fw_version(res.data >> 8)
    out(f"     firmware v{fw.version} ({fw.encoding}), type: {TYPES.get(res.data & 0xFF, 'reserved')}")
    res = await cmd(0x40)
    size = ((res.data >> 8) & 1) << 8 | (res.data & 0xFF)
    out(f"     flash {size} words, configuration bits 0x{res.data >> 9:02X}")
    supply = p.supply_mv((await cmd(0x42)).data)
    out(f"     supply {supply} mV")
    adc_t = (await cmd(0x43)).data
    adc_o2 = (await cmd(0x44)).data

    out("== flash: manufacturer and factory areas")
    words = [fm.BLANK] * size
    for addr in range(0x00, 0x20):
        words[addr] = (await cmd(*p.addr_cmd(0x48, addr))).data & 0x3FFF
    free = (await cmd(*p.addr_cmd(0x46, 0x20), note="first free word")).data
    out("== flash: field calibrations")
    for addr in range(0x20, min(free, size)):
        words[addr] = (await cmd(*p.addr_cmd(0x48, addr))).data & 0x3FFF
    m = fm.decode_o2_map(words)
    cur = fm.current_calibration(words)
    temp = p.temperature_c100(adc_t, m.ref_temp, m.adc_ref, supply, m.temp_scale)
    o2 = p.o2_mv100(adc_o2, m.opamp_offset)

    out()
    out("== sensor page")
    out(f"  model            {m.model.strip()}   (MFG ID {m.mfg_id.strip()})")
    out(f"  serial           {m.serial.strip()}")
    out(f"  firmware         v{fw.version}, {TYPES.get(prof.type_byte)}")
    out(f"  manufactured     {m.manufactured:%Y-%m-%d %H:%M}   expires {m.expires:%Y-%m-%d %H:%M}")
    out(f"  supply           {supply} mV")
    out(f"  temperature      {temp / 100:.2f} C")
    out(f"  O2 cell          {o2 / 100:.2f} mV")
    if cur is not None:
        when = m.manufactured + timedelta(hours=fm.O2_CAL_UNIT_HOURS * cur.stamp)
        out(f"  PPO2             {p.ppo2_mbar(adc_o2, cur.value) / 1000:.3f} bar "
            f"(calibrated {when:%Y-%m-%d %H:%M}, gain {cur.value}, record at 0x{cur.addr:02X})")
    out(f"  calibrations     {fm.calibration_count(words)} stored")
    out()
    out(f"{len(tb.monitor.transactions)} transactions, every one inside the spec's timing table (spec monitor)")
    await tb.finish()
