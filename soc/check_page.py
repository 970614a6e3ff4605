#!/usr/bin/env python3
"""Checks the UART output of the simulated LiteX SoC (docs/soc.md) against
the shared vectors: every channel's page must be, line for line, the page
derived from the vector map its cell carries (tb/vectors/flash_o2.json,
flash_co2.json: the readable 'description' of the image) and the cell's raw
readings, converted by tb/protocol.py (the Python conversions the project
checks against tb/vectors/conversions.json). The run must also have used
the interrupt: wait_irq called, every wait ended by the core's interrupt,
none by its timeout, and at least one that had to wait for it.

    check_page.py UART_LOG [--clk-khz 4000] [--channels 3] [--fifo-depth 16]
"""
import argparse
import re
import sys
from datetime import datetime, timedelta
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from cells import ROOT, cells  # noqa: E402

sys.path.insert(0, str(ROOT / "tb"))
import protocol as p  # noqa: E402

TYPES = {1: "Digital O2 sensor", 2: "CO2 sensor", 3: "CO2 temperature stick"}
CAL_UNIT_HOURS = {"o2": 3, "co2": 6}


def fixed(v, decimals):
    s = "-" if v < 0 else ""
    v = abs(v)
    return f"{s}{v // 10 ** decimals}.{v % 10 ** decimals:0{decimals}d}"


def when(d):
    return datetime(d["year"], d["month"], d["day"], d["hour"], d["minute"])


def expected_page(ch, prof, vmap):
    """The page of a cell, from its vector map's description."""
    d = vmap["description"]
    v = p.decode_fw_version(prof.fw_byte).version
    execute = 6000 if v is not None and v >= 18 else 4000
    ver = f"v{v}" if v is not None else "unknown"
    adc_ref, adc_t, adc_o2 = (prof.adc_ref_voltage & 0xFFF, prof.adc_temperature & 0xFFF,
                              prof.adc_o2 & 0xFFF)
    supply = p.supply_mv(adc_ref)
    t = p.temperature_c100(adc_t, d["ref_temp"], d["adc_ref"], supply, d["temp_scale"])
    made = when(d["manufactured"])
    size = len(vmap["words"])
    assert d.get("size", size) == size, "vector: size and image disagree"
    page = [f"== channel {ch}: {TYPES[prof.type_byte]}, firmware {ver} "
            f"(byte 0x{prof.fw_byte:02X}), execute {execute} us",
            f"  model            {d['model']}   (MFG ID {d['mfg_id']})",
            f"  serial           {d['serial']}",
            f"  manufactured     {made:%Y-%m-%d %H:%M}   expires "
            f"{when(d['expires']):%Y-%m-%d %H:%M}",
            f"  flash            {size} words",
            f"  supply           {supply} mV",
            f"  temperature      {fixed(t, 2)} C"]
    # the current record: the largest time stamp, ties -> the higher address
    unit = CAL_UNIT_HOURS[d["kind"]]
    cals = d["field_cals"]
    cur = max(cals, key=lambda c: (c["hours"] // unit, c["addr"])) if cals else None
    cal_date = f"{made + timedelta(hours=cur['hours']):%Y-%m-%d %H:%M}" if cur else ""
    if d["kind"] == "o2":
        page.append(f"  O2 cell          {fixed(p.o2_mv100(adc_o2, d['opamp_offset']), 2)} mV")
        if cur:
            page.append(f"  PPO2             {fixed(p.ppo2_mbar(adc_o2, cur['value']), 3)} bar "
                        f"(calibrated {cal_date}, gain {cur['value']}, "
                        f"record at 0x{cur['addr']:02X})")
    elif cur:
        page.append(f"  CO2 400 ppm cal  reading {cur['value']} (calibrated {cal_date})")
    page.append(f"  calibrations     {len(cals)} stored")
    return page


def pages(text):
    out, cur = {}, None
    for line in text.splitlines():
        m = re.match(r"== channel (\d+):", line)
        if m:
            cur = int(m.group(1))
            out[cur] = [line]
        elif cur is not None and line.startswith("  "):
            out[cur].append(line)
        else:
            cur = None
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("log")
    ap.add_argument("--clk-khz", type=int, default=4000)
    ap.add_argument("--channels", type=int, default=3)
    ap.add_argument("--fifo-depth", type=int, default=16)
    a = ap.parse_args()
    text = Path(a.log).read_text()
    fails = []

    head = f"core: {a.channels} channels, FIFO depth {a.fifo_depth}, {a.clk_khz} kHz, version "
    if not any(line.startswith(head) for line in text.splitlines()):
        fails.append(f"no line starting '{head}'")
    got = pages(text)
    for ch, (name, prof, vmap) in enumerate(cells()):
        want = expected_page(ch, prof, vmap)
        have = got.get(ch)
        if have != want:
            fails.append(f"channel {ch} ({name}, vector note: {vmap['note']}):\n"
                         + "\n".join(f"  want: {w}" for w in want) + "\n"
                         + "\n".join(f"  got:  {h}" for h in (have or ["(no page)"])))
        else:
            print(f"check_page: channel {ch} ({name}): {len(want)} lines match the vector")
    if sorted(got) != list(range(len(cells()))):
        fails.append(f"pages for channels {sorted(got)}")

    m = re.search(r"twh_page_run returned (-?\d+)", text)
    if not m or m.group(1) != "0":
        fails.append("twh_page_run did not return 0")
    m = re.search(r"wait_irq calls (\d+), woken by the interrupt (\d+) "
                  r"\(pending on entry (\d+)\), timed out (\d+)", text)
    if not m:
        fails.append("no wait_irq statistics")
    else:
        calls, woke, already, timed_out = map(int, m.groups())
        if calls == 0 or woke != calls or timed_out != 0 or woke - already <= 0:
            fails.append(f"interrupt path: {calls} waits, {woke} ended by the interrupt "
                         f"({already} pending on entry), {timed_out} timed out")
        else:
            print(f"check_page: interrupt path: {calls} waits, all ended by the core's "
                  f"interrupt ({woke - already} waited for it, {already} found it pending)")
    if "twh_cli:" in text:
        fails.append("the page tool reported an error: " +
                     next(line for line in text.splitlines() if "twh_cli:" in line))
    if fails:
        print("check_page: FAIL\n" + "\n".join(fails))
        return 1
    print("check_page: PASS: every page matches tb/vectors/, the interrupt path was used")
    return 0


if __name__ == "__main__":
    sys.exit(main())
