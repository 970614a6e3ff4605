"""The sensor page sw/tools/twh_page.c prints for a cell, as the tests
expect it: derived from the cell's profile (readings, firmware byte) and
flash image through the project's Python rules (tb/flashmap.py,
tb/protocol.py, held to tb/vectors/ by tb/test_protocol.py). Used by the PC
tool's test against the simulated board (tb/test_board_top.py) and by the
LiteX SoC's check (soc/check_page.py)."""
import re
from datetime import timedelta

import flashmap as fm
import protocol as p

TYPES = {1: "Digital O2 sensor", 2: "CO2 sensor", 3: "CO2 temperature stick"}


def fw_line(ch, prof):
    v = p.decode_fw_version(prof.fw_byte).version
    execute = 6000 if v is not None and v >= 18 else 4000
    ver = f"v{v}" if v is not None else "unknown"
    return (f"== channel {ch}: {TYPES[prof.type_byte]}, firmware {ver} "
            f"(byte 0x{prof.fw_byte:02X}), execute {execute} us"), execute


def fixed(v, decimals):
    s = "-" if v < 0 else ""
    v = abs(v)
    return f"{s}{v // 10 ** decimals}.{v % 10 ** decimals:0{decimals}d}"


def expected_page(ch, prof, quick=False):
    """The page the tool must print for a modelled cell, from its profile."""
    head, _ = fw_line(ch, prof)
    adc_ref, adc_t, adc_o2 = (prof.adc_ref_voltage & 0xFFF, prof.adc_temperature & 0xFFF,
                              prof.adc_o2 & 0xFFF)
    supply = p.supply_mv(adc_ref)
    if quick:
        return [head, f"  supply           {supply} mV (ADC {adc_ref})",
                f"  temperature ADC  {adc_t}", f"  O2 ADC           {adc_o2}"]
    flash = list(prof.flash)
    o2 = prof.type_byte == 1
    m = fm.decode_o2_map(flash) if o2 else fm.decode_co2_map(flash)
    unit = fm.O2_CAL_UNIT_HOURS if o2 else fm.CO2_CAL_UNIT_HOURS
    cur = fm.current_calibration(flash)
    t = p.temperature_c100(adc_t, m.ref_temp, m.adc_ref, supply, m.temp_scale)
    page = [head,
            f"  model            {m.model}   (MFG ID {m.mfg_id})",
            f"  serial           {m.serial}",
            f"  manufactured     {m.manufactured:%Y-%m-%d %H:%M}   expires {m.expires:%Y-%m-%d %H:%M}",
            f"  flash            {len(flash)} words",
            f"  supply           {supply} mV",
            f"  temperature      {fixed(t, 2)} C"]
    cal_date = f"{m.manufactured + timedelta(hours=cur.stamp * unit):%Y-%m-%d %H:%M}" if cur else ""
    if o2:
        page.append(f"  O2 cell          {fixed(p.o2_mv100(adc_o2, m.opamp_offset), 2)} mV")
        if cur:
            page.append(f"  PPO2             {fixed(p.ppo2_mbar(adc_o2, cur.value), 3)} bar "
                        f"(calibrated {cal_date}, gain {cur.value}, record at 0x{cur.addr:02X})")
    elif cur:
        page.append(f"  CO2 400 ppm cal  reading {cur.value} (calibrated {cal_date})")
    page.append(f"  calibrations     {fm.calibration_count(flash)} stored")
    return page


def pages(text):
    """The tool's output split into its channel pages (lists of lines)."""
    out, cur = {}, None
    for line in text.splitlines():
        mt = re.match(r"== channel (\d+):", line)
        if mt:
            cur = int(mt.group(1))
            out[cur] = [line]
        elif cur is not None and line.startswith("  "):
            out[cur].append(line)
        else:
            cur = None
    return out
