"""Generate the shared test vectors in tb/vectors/ (run by hand, not by tests).

    cd tb && ../.venv/bin/python gen_vectors.py

The JSON files are committed; tests (Python here, later the C driver and RTL
tests) read them and check that their own code reproduces every output.
Inputs are chosen by hand below so that each file can be checked on paper;
every non-obvious case says why it is there in its "note".
"""
from __future__ import annotations

import json
import os
from datetime import datetime

import flashmap as fm
import protocol as p

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "vectors")


def hx(bs) -> str:
    return " ".join(f"{b:02X}" for b in bs)


# ---------------------------------------------------------------------------
# frames.json
# ---------------------------------------------------------------------------
COMMANDS = [
    # (cmd, payload16, note)
    (0x41, 0x00AA, "NOTES.md example: 41 AA -> 14"),
    (0x44, 0x00AA, "NOTES.md example: 44 AA -> 11"),
    (0x85, 0x1234, "NOTES.md example: 85 12 34 -> 34 (write word 0x005 = 0x1234)"),
    (0x40, 0x00AA, "config / flash size"),
    (0x42, 0x00F0, "reference voltage, the other recommended unused payload 0xF0"),
    (0x43, 0x00AA, "temperature"),
    (0x46, 0x0020, "find free from 0x020 (start of the calibration area)"),
    (0x47, 0x0000, "find free from 0x100 (odd command = address bit 8)"),
    (0x48, 0x000E, "read word 0x00E (memory map version)"),
    (0x49, 0x00EF, "read word 0x1EF"),
    (0x4A, 0x0020, "erase the page 0x020-0x02F"),
    (0x4B, 0x0000, "erase the page 0x100-0x10F"),
    (0xA0, 0x0BB8, "write word 0x020 = 0x0BB8 (a calibration time stamp)"),
    (0xEF, 0xFFFE, "write word 0x1EF = 0x3FFE: address bits 8:7 in data MSB bits 7:6"),
    (0xFF, 0xFFFF, "write word 0x1FF = 0x3FFF: sum wraps several times, checksum 0x02"),
    (0x80, 0x0000, "write word 0x000 = 0: all-zero body, checksum 0x7F"),
    (0x00, 0x0000, "reserved command, all zero: checksum 0xFF"),
    (0x45, 0x00AA, "reserved"),
    (0x7F, 0x00FF, "reserved, last 3-byte command"),
]

RESPONSES = [
    (0x00, 0xF0, "0x40 answer: config 0, 240 words"),
    (0x02, 0xF0, "0x40 answer: config bits 0x01 (MSB bits 7:1), 240 words"),
    (0x00, 0x80, "0x40 answer: 128 words (firmware v15)"),
    (0x01, 0xFF, "0x40 answer: 511 words, size bit 8 in MSB bit 0"),
    (0x0F, 0x01, "0x41 answer: firmware v15, O2 cell"),
    (0x12, 0x01, "0x41 answer: firmware v18, O2 cell"),
    (0x26, 0x02, "0x41 answer: firmware v26 (BCD), CO2 sensor"),
    (0x05, 0x49, "0x42 answer: 12-bit reading 0x549 = 1353"),
    (0x3F, 0xFF, "0x48 answer: blank word"),
    (0x00, 0x00, "all zero: checksum 0xFF"),
    (0xFF, 0xFF, "all ones: checksum 0x01"),
]


def frames_json() -> dict:
    vectors = []
    for cmd, payload, note in COMMANDS:
        frame = p.build_frame(cmd, payload)
        v = {"kind": "command", "name": p.command_name(cmd), "cmd": cmd,
             "payload": payload, "bytes_in": list(frame[:-1]),
             "frame": list(frame), "checksum": frame[-1], "hex": hx(frame),
             "frame_len": p.frame_len(cmd),
             "expects_response": p.expects_response(cmd), "note": note}
        if cmd >= 0x80:
            addr, data = p.decode_write(cmd, payload)
            v["addr"], v["data"] = addr, data
        elif p.command_name(cmd) in ("FIND_FREE", "READ", "ERASE"):
            v["addr"] = p.decode_addr(cmd, payload)
        vectors.append(v)
    for msb, lsb, note in RESPONSES:
        frame = p.response_frame(msb, lsb)
        vectors.append({"kind": "response", "bytes_in": [msb, lsb],
                        "frame": list(frame), "checksum": frame[-1],
                        "hex": hx(frame), "note": note})
    return {
        "about": (
            "2-wire frames. checksum = ~(sum of bytes_in) & 0xFF, i.e. all bytes "
            "of a frame incl. the checksum sum to 0xFF mod 256. Commands < 0x80 "
            "are [cmd, payload LSB, chk]; >= 0x80 are [cmd, payload MSB, payload "
            "LSB, chk]. Responses are [MSB, LSB, chk]. 'payload' is the 16-bit "
            "value given to the host core (only its LSB is sent for 3-byte "
            "frames). Write commands: addr = (payload bits 15:14) << 7 | cmd bits "
            "6:0, data = payload & 0x3FFF. 0x46-0x4B: addr = (cmd bit 0) << 8 | "
            "payload LSB. expects_response is false for erase, write, reserved."),
        "vectors": vectors,
    }


# ---------------------------------------------------------------------------
# conversions.json
# ---------------------------------------------------------------------------
def conversions_json() -> dict:
    supply = []
    for adc, note in [(2048, "exactly 2048 mV"), (1353, "3100 mV nominal"),
                      (1271, "3300 mV"), (1422, "2949.6 -> 2949 (truncated)"),
                      (1, "smallest valid reading"), (4094, "largest valid reading"),
                      (4095, "saturated: invalid"), (0, "zero: invalid"),
                      (3000, "1398.1 -> 1398")]:
        supply.append({"adc": adc, "supply_mv": p.supply_mv(adc), "note": note})

    temp = []
    for adc, rt, aref, smv, scale, note in [
        (2000, 2500, 2000, 3000, 7800, "at the reference point"),
        (2100, 2500, 2000, 3000, 7800, "+100 counts: 100*300000/7800 = 3846.15 -> 3846"),
        (1900, 2500, 2000, 3000, 7800, "-100 counts: -3846.15 truncates toward zero to -3846"),
        (1994, 25, 2000, 3300, 7800, "Ref_Temp 25 < 100 is whole degrees -> 2500; -253.8 -> -253"),
        (1999, 2500, 2000, 3000, 7800, "-1 count: -38.46 -> -38 (floor would give -39)"),
        (4095, 2500, 0, 4194304, 7800, "64-bit: 4095 * 419430400 exceeds 32 bits"),
        (2076, 2500, 2100, 3199, 7800, "CO2 temperature stick profile"),
        (2005, 2437, 1987, 2949, 7750, "O2 v26 profile"),
        (2000, 2500, 2000, None, 7800, "supply unknown -> null"),
        (2000, 2500, 2000, 3000, 0, "Temp_Scale 0 -> null"),
    ]:
        temp.append({"adc": adc, "ref_temp": rt, "adc_ref": aref, "supply_mv": smv,
                     "temp_scale": scale,
                     "temperature_c100": p.temperature_c100(adc, rt, aref, smv, scale),
                     "note": note})

    o2 = []
    for adc, off, note in [(0, 0, "zero"), (22, 0, "exactly 100 = 1.00 mV"),
                           (239, 35, "23900/22 = 1086.36 -> 1086, +35"),
                           (234, -42, "negative offset"),
                           (4095, -1200, "full scale, large negative offset"),
                           (1, -10, "result below zero: 4 - 10 = -6")]:
        o2.append({"adc": adc, "opamp_offset": off, "o2_mv100": p.o2_mv100(adc, off),
                   "note": note})

    ppo2 = []
    for adc, gain, note in [(4096, 1024, "full scale with gain 1024 = 1.000 bar"),
                            (239, 3672, "air-ish reading, 0.2092 bar -> 209"),
                            (1100, 3810, "about 1 bar -> 999"),
                            (4095, 16383, "largest inputs: adc*gain*1000 exceeds 32 bits, needs 64"),
                            (0, 3650, "zero")]:
        ppo2.append({"adc": adc, "gain": gain, "ppo2_mbar": p.ppo2_mbar(adc, gain),
                     "note": note})

    fw = []
    for b in (0x00, 0x0F, 0x10, 0x12, 0x19, 0x1A, 0x20, 0x25, 0x26, 0x29,
              0x2A, 0x30, 0x99, 0x9A, 0xA0, 0xFF):
        v = p.decode_fw_version(b)
        fw.append({"byte": b, "version": v.version, "encoding": v.encoding})

    return {
        "about": (
            "Integer conversions, every division truncating toward zero like C, "
            "64-bit intermediates. supply_mv = 1024*4096/adc for 0 < adc < 4095 "
            "else null. temperature_c100 = R + (adc - adc_ref) * (supply_mv*100) "
            "/ temp_scale with R = ref_temp*100 if ref_temp < 100 else ref_temp "
            "(null if supply_mv is null or temp_scale is 0). o2_mv100 = 100*adc/22 "
            "+ opamp_offset. ppo2_mbar = adc*gain*1000 / (4096*1024). fw_version: "
            "byte <= 0x19 binary; >= 0x26 with both nibbles <= 9 BCD; else "
            "unknown (version null)."),
        "supply": supply, "temperature": temp, "o2": o2, "ppo2": ppo2,
        "fw_version": fw,
    }


# ---------------------------------------------------------------------------
# flash_o2.json / flash_co2.json
# ---------------------------------------------------------------------------
def cal_json(r):
    return None if r is None else {"addr": r.addr, "stamp": r.stamp, "value": r.value}


def decoded_json(d, words, unit) -> dict:
    cur = fm.current_calibration(words)
    out = {
        "model": d.model, "mfg_id": d.mfg_id, "serial": d.serial,
        "manufactured": fm.datetime_to_json(d.manufactured),
        "expires": fm.datetime_to_json(d.expires),
        "temp_scale": d.temp_scale, "ref_temp": d.ref_temp, "adc_ref": d.adc_ref,
        "calibration_count": fm.calibration_count(words),
        "current_calibration": cal_json(cur),
        "current_calibration_hours": None if cur is None else cur.stamp * unit,
        "flash_size": len(words),
    }
    if isinstance(d, fm.O2Map):
        out.update(map_version=d.map_version, map_type=d.map_type,
                   opamp_offset=d.opamp_offset,
                   opamp_offset_word=words[fm.OPAMP_OFFSET_ADDR],
                   mfg_cal=[list(x) for x in d.mfg_cal])
    else:
        out.update(rgb_offset=None if d.rgb_offset is None else list(d.rgb_offset),
                   rgb_gain=None if d.rgb_gain is None else list(d.rgb_gain))
    return out


def map_entry(d, note) -> dict:
    if isinstance(d, fm.O2Map):
        words, dec, unit = fm.build_o2_map(d), fm.decode_o2_map, fm.O2_CAL_UNIT_HOURS
    else:
        words, dec, unit = fm.build_co2_map(d), fm.decode_co2_map, fm.CO2_CAL_UNIT_HOURS
    back = dec(words)
    assert back == d, (back, d)
    return {"note": note, "description": fm.desc_to_json(d), "words": words,
            "layout": layout(d, words), "decoded": decoded_json(d, words, unit)}


def layout(d, words) -> list:
    """The programmed fields with their addresses, to check 'words' by hand."""
    rows = [("model", fm.MODEL_ADDR, fm.MODEL_WORDS),
            ("mfg_id", fm.MFG_ID_ADDR, fm.MFG_ID_WORDS),
            ("manufactured", fm.MFG_DATE_ADDR, 2), ("expires", fm.EXPIRY_ADDR, 2)]
    if isinstance(d, fm.O2Map):
        rows.append(("map_version<<8|map_type", fm.MAP_VERSION_ADDR, 1))
    rows += [("serial", fm.SERIAL_ADDR, fm.SERIAL_WORDS),
             ("temp_scale", fm.TEMP_SCALE_ADDR, 1), ("ref_temp", fm.REF_TEMP_ADDR, 1),
             ("adc_ref", fm.ADC_REF_ADDR, 1)]
    if isinstance(d, fm.O2Map):
        rows += [("opamp_offset (s14)", fm.OPAMP_OFFSET_ADDR, 1),
                 ("mfg_cal (3 pairs)", fm.MFG_CAL_ADDR, 6)]
    else:
        rows += [("rgb_offset", fm.RGB_OFFSET_ADDR, 3), ("rgb_gain", fm.RGB_GAIN_ADDR, 3)]
    for r in fm.cal_records(words):
        rows.append((f"field cal (word0 = stamp, word1 = value)", r.addr, 2))
    return [{"field": n, "addr": a, "addr_hex": f"0x{a:02X}",
             "words": words[a:a + k], "words_hex": [f"0x{w:04X}" for w in words[a:a + k]]}
            for n, a, k in rows]


def encoding_cases() -> dict:
    text = []
    for s, n, pad in [("AB", 1, " "), ("A", 1, " "), ("A", 1, "\0"), ("", 1, "\0"),
                      ("DIGITAL O2", 7, " "), ("SRI001", 3, "\0")]:
        text.append({"text": s, "n_words": n, "pad": pad,
                     "words": fm.encode_text(s, n, pad)})
    dates = []
    for dt, note in [(datetime(2000, 1, 1, 0, 0), "epoch of the field"),
                     (datetime(2017, 11, 17, 9, 30), "spec rev E date"),
                     (datetime(2127, 12, 31, 23, 59), "largest"),
                     (datetime(2024, 2, 29, 23, 59), "leap day")]:
        w0, w1 = fm.encode_datetime(dt)
        dates.append({"datetime": fm.datetime_to_json(dt), "words": [w0, w1],
                      "note": note})
    dates.append({"datetime": None, "words": [0x3FFF, 0x3FFF],
                  "note": "blank words: minutes 63, month 15 -> not a date (null)"})
    s14 = [{"value": v, "word": fm.to_s14(v)} for v in (0, 1, 35, -42, -1200, 8191, -8192)]
    s14.append({"value": -1, "word": fm.to_s14(-1),
                "note": "-1 encodes as 0x3FFF, the same as a blank word"})
    return {"text": text, "datetime": dates, "s14": s14}


def cal_cases() -> list:
    """Small calibration areas for current_calibration / calibration_count.
    'pairs' lists [addr, word0, word1]; every other word is blank."""
    cases = [
        ("empty area", []),
        ("one record", [[0x20, 8, 3650]]),
        ("largest stamp wins, not the highest address",
         [[0x20, 400, 3700], [0x22, 401, 3701], [0x30, 300, 3600], [0x32, 350, 3650]]),
        ("tie on the stamp: the higher address is the later write",
         [[0x20, 500, 3700], [0x2A, 500, 3710], [0x24, 499, 3720]]),
        ("half-written record (word 1 blank) is ignored",
         [[0x20, 10, 3650], [0x22, 20, 0x3FFF]]),
        ("half-written record (word 0 blank) is ignored",
         [[0x20, 10, 3650], [0x22, 0x3FFF, 3700]]),
        ("stamp 0 is a valid record", [[0x20, 0, 4000]]),
        ("last pair of the area (0xDE)", [[0x20, 5, 3000], [0xDE, 6, 3001]]),
    ]
    out = []
    for note, pairs in cases:
        words = [fm.BLANK] * 240
        for a, w0, w1 in pairs:
            words[a], words[a + 1] = w0, w1
        out.append({"note": note, "size": 240, "pairs": pairs,
                    "calibration_count": fm.calibration_count(words),
                    "current_calibration": cal_json(fm.current_calibration(words))})
    return out


def flash_o2_json() -> dict:
    v18 = fm.O2Map(
        model="DIGITAL O2", mfg_id="SRI001",
        manufactured=datetime(2017, 11, 17, 9, 30),
        expires=datetime(2019, 5, 17, 9, 30), map_version=2, serial="A1B2C3D4E5F6",
        temp_scale=7800, ref_temp=2500, adc_ref=2012, opamp_offset=-42,
        mfg_cal=((210, 232), (1000, 1105), (1600, 1768)),
        field_cals=(fm.FieldCal(2403, 3702, 0x20), fm.FieldCal(2406, 3705, 0x22),
                    fm.FieldCal(2130, 3690, 0x30), fm.FieldCal(2160, 3695, 0x32),
                    fm.FieldCal(2190, 3698, 0x34)),
        size=240)
    v15 = fm.O2Map(
        model="DIGITAL O2", mfg_id="SRI15A",
        manufactured=datetime(2015, 8, 3, 14, 5), expires=datetime(2017, 2, 3, 14, 5),
        map_version=1, serial="O2V15-000123", temp_scale=7800, ref_temp=25,
        adc_ref=2000, opamp_offset=35,
        mfg_cal=((210, 239), (1000, 1138), (1600, 1820)),
        field_cals=(fm.FieldCal(24, 3672, 0x20), fm.FieldCal(744, 3690, 0x22),
                    fm.FieldCal(2160, 3705, 0x24), fm.FieldCal(2163, 3706, 0x7E)),
        size=128)
    return {
        "about": (
            "Digital O2 flash maps (spec 7.1 + NOTES.md). 14-bit words, blank = "
            "0x3FFF (16383). Text: 2 chars/word, first char bits 13:7. Date/time: "
            "2 words, word0 = bits 27:14 of (minute<<21 | (year-2000)<<14 | "
            "month<<10 | day<<5 | hour). 0x0E = map_version<<8 | map_type. "
            "OpAmp_Offset is 14-bit two's complement. Field calibration records at "
            "0x20.. (pairs up to 0xDF, or the flash end): word0 = hours since "
            "manufacture / 3, word1 = gain. A record counts only if both words are "
            "programmed; current = largest word0, ties -> higher address. "
            "'words' is the whole image (len = flash size); 'description' is its "
            "readable form (hours, not word0, in field_cals)."),
        "maps": [
            map_entry(v18, "240-word map (fw v16+): calibrations after a wrap: the "
                           "newest records are at 0x20/0x22, older ones at 0x30-0x34"),
            map_entry(v15, "128-word map (fw v15): Ref_Temp in whole degrees, last "
                           "record in the last pair 0x7E"),
        ],
        "encodings": encoding_cases(),
        "calibration_cases": cal_cases(),
    }


def flash_co2_json() -> dict:
    co2 = fm.CO2Map(
        model="CO2 SENSOR", mfg_id="SRICO2", manufactured=datetime(2021, 6, 1, 8, 0),
        expires=datetime(2026, 6, 1, 8, 0), serial="CO2-00000042", temp_scale=7800,
        ref_temp=2500, adc_ref=2048, rgb_offset=(101, 202, 303),
        rgb_gain=(4096, 4100, 3990),
        field_cals=(fm.FieldCal(6, 1234, 0x20), fm.FieldCal(1440, 1240, 0x22),
                    fm.FieldCal(8754, 1251, 0x24)),
        size=240, text_pad="\0")
    stick = fm.CO2Map(
        model="TEMP STICK", mfg_id="SRITMP", manufactured=datetime(2022, 1, 10, 12, 0),
        expires=datetime(2032, 1, 10, 12, 0), serial="TS0000000007", temp_scale=7800,
        ref_temp=2500, adc_ref=2100, size=240)
    return {
        "about": (
            "CO2 sensor flash maps (spec 7.2, preliminary, + NOTES.md). Same "
            "manufacturer area as O2 without the map version word (0x0E-0x0F "
            "reserved, left blank). 0x19-0x1B RGB offset, 0x1C-0x1E RGB gain "
            "(blank when absent), 0x1F reserved. Field calibration word0 = hours "
            "since manufacture / 6, word1 = reading at 400 ppm. Text here is NUL "
            "padded (the O2 file uses spaces); decoders strip both. The CO2 "
            "temperature stick has no map in the spec: this project gives it the "
            "CO2 layout with blank RGB words and no calibrations."),
        "maps": [map_entry(co2, "CO2 sensor, NUL-padded text, 3 calibrations"),
                 map_entry(stick, "CO2 temperature stick: no RGB data, no calibrations")],
    }


def dumps(obj, ind: str = "") -> str:
    """JSON with one key per line but lists of plain values on one line."""
    nxt = ind + "  "
    if isinstance(obj, dict):
        if not obj:
            return "{}"
        items = [f"{nxt}{json.dumps(k)}: {dumps(v, nxt)}" for k, v in obj.items()]
        return "{\n" + ",\n".join(items) + "\n" + ind + "}"
    if isinstance(obj, list) and any(isinstance(x, (dict, list)) for x in obj):
        if all(isinstance(x, list) and not any(isinstance(y, (dict, list)) for y in x)
               for x in obj):
            return json.dumps(obj)
        return "[\n" + ",\n".join(nxt + dumps(x, nxt) for x in obj) + "\n" + ind + "]"
    return json.dumps(obj)


def write(name: str, obj) -> None:
    path = os.path.join(OUT, name)
    with open(path, "w") as f:
        f.write(dumps(obj) + "\n")
    print("wrote", path)


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    write("frames.json", frames_json())
    write("conversions.json", conversions_json())
    write("flash_o2.json", flash_o2_json())
    write("flash_co2.json", flash_co2_json())
