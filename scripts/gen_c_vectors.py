#!/usr/bin/env python3
"""Turn the shared test vectors tb/vectors/*.json into a C header for the
cmocka tests of the C driver (sw/test/test_twh.c).

    python3 scripts/gen_c_vectors.py -o sw/build/gen/twh_vectors.h tb/vectors/*.json

Run by sw/Makefile at build time; the header is not committed. The C tests
thus read exactly the data the Python tests (tb/test_protocol.py) read.
Standard library only. The script copies values; it computes nothing the
driver is tested for, except picking the expected decodings of a few
response vectors out of their notes ("0x40 answer: ... 240 words"), and it
fails when a note it needs does not parse or a file misses a section.
"""
from __future__ import annotations

import argparse
import json
import os
import re
import sys

BLANK = 0x3FFF


def c_str(s) -> str:
    if s is None:
        return "NULL"
    out = []
    for ch in s:
        o = ord(ch)
        if ch in '\\"':
            out.append("\\" + ch)
        elif 0x20 <= o < 0x7F and ch != "?":
            out.append(ch)
        elif o <= 0xFF:
            out.append(f"\\{o:03o}")
        else:
            raise ValueError(f"non-Latin-1 character in {s!r}")
    return '"' + "".join(out) + '"'


def words_init(words) -> str:
    lines = []
    for i in range(0, len(words), 12):
        lines.append("    " + ", ".join(f"0x{w:04X}" for w in words[i:i + 12]) + ",")
    return "\n".join(lines)


def dt_init(d) -> str:
    """{year, month, day, hour, minute}; a JSON null (no date) is all 0."""
    if d is None:
        return "{0, 0, 0, 0, 0}"
    return f"{{{d['year']}, {d['month']}, {d['day']}, {d['hour']}, {d['minute']}}}"


def opt(v, none=-1) -> str:
    return str(none if v is None else v)


class Out:
    def __init__(self):
        self.lines = []

    def __call__(self, s=""):
        self.lines.append(s)


# --------------------------------------------------------------------- frames
RESP_CMD = re.compile(r"^0x([0-9A-Fa-f]{2}) answer")


def response_expectations(v):
    """(resp_cmd, a, b) of a response vector, from its note.

    0x40: a = config bits (-1 when the note does not say), b = flash words; 0x41: a = version byte,
    b = type byte; 0x42-0x44: a = reading; 0x48: a = word. -1 = none.
    """
    note = v.get("note", "")
    m = RESP_CMD.match(note)
    if not m:
        return -1, -1, -1
    cmd = int(m.group(1), 16)
    msb, lsb = v["bytes_in"]
    if cmd == 0x40:
        words = re.search(r"(\d+) words", note)
        cfg = re.search(r"config(?: bits)? (0x[0-9A-Fa-f]+|\d+)", note)
        if not words:
            raise SystemExit(f"gen_c_vectors: cannot parse 0x40 note {note!r}")
        return cmd, int(cfg.group(1), 0) if cfg else -1, int(words.group(1))
    if cmd == 0x41:
        ver = re.search(r"firmware v(\d+)", note)
        if not ver:
            raise SystemExit(f"gen_c_vectors: cannot parse 0x41 note {note!r}")
        return cmd, int(ver.group(1)), lsb
    if cmd in (0x42, 0x43, 0x44):
        val = re.search(r"= (\d+)", note)
        if not val:
            raise SystemExit(f"gen_c_vectors: cannot parse {cmd:#x} note {note!r}")
        return cmd, int(val.group(1)), -1
    if cmd in (0x48, 0x49):
        if "blank word" in note:
            return cmd, BLANK, -1
        raise SystemExit(f"gen_c_vectors: cannot parse {cmd:#x} note {note!r}")
    raise SystemExit(f"gen_c_vectors: response note for unknown command {note!r}")


def gen_frames(o, data):
    o("/* ---- frames.json ---- */")
    o("typedef struct {")
    o("    const char *hex;       /* frame as hex, for messages */")
    o("    const char *name;      /* command name (NULL for responses) */")
    o("    int is_command;")
    o("    uint8_t cmd;           /* commands: command byte */")
    o("    uint16_t payload;      /* commands: 16-bit payload given to the core */")
    o("    int frame_len;")
    o("    uint8_t frame[4];      /* bytes incl. checksum */")
    o("    uint8_t checksum;")
    o("    int expects_response;  /* commands */")
    o("    int addr;              /* word address or -1 */")
    o("    int data;              /* write data or -1 */")
    o("    uint16_t resp_data;    /* responses: MSB << 8 | LSB */")
    o("    int resp_cmd;          /* responses: command answered, -1 = generic */")
    o("    int resp_a, resp_b;    /* responses: expected decodings, see gen_c_vectors.py */")
    o("} vec_frame_t;")
    o("static const vec_frame_t vec_frames[] = {")
    for v in data["vectors"]:
        fr = v["frame"]
        frame = ", ".join(str(b) for b in fr + [0] * (4 - len(fr)))
        if v["kind"] == "command":
            o(f"    {{{c_str(v['hex'])}, {c_str(v['name'])}, 1, {v['cmd']}, {v['payload']}, "
              f"{len(fr)}, {{{frame}}}, {v['checksum']}, {int(v['expects_response'])}, "
              f"{opt(v.get('addr'))}, {opt(v.get('data'))}, 0, -1, -1, -1}},")
            if v["frame_len"] != len(fr):
                raise SystemExit(f"gen_c_vectors: frame_len mismatch in {v['hex']}")
        elif v["kind"] == "response":
            msb, lsb = v["bytes_in"]
            rc, a, b = response_expectations(v)
            o(f"    {{{c_str(v['hex'])}, NULL, 0, 0, 0, {len(fr)}, {{{frame}}}, "
              f"{v['checksum']}, 0, -1, -1, 0x{msb << 8 | lsb:04X}, {rc}, {a}, {b}}},")
        else:
            raise SystemExit(f"gen_c_vectors: unknown frame kind {v['kind']!r}")
    o("};")
    o()


# ---------------------------------------------------------------- conversions
def gen_conversions(o, data):
    o("/* ---- conversions.json ---- */")
    o("typedef struct { uint16_t adc; int valid; int32_t supply_mv; const char *note; } vec_supply_t;")
    o("static const vec_supply_t vec_supply[] = {")
    for v in data["supply"]:
        mv = v["supply_mv"]
        o(f"    {{{v['adc']}, {int(mv is not None)}, {opt(mv, 0)}, {c_str(v.get('note'))}}},")
    o("};")
    o("typedef struct { uint16_t adc, ref_temp, adc_ref; int supply_valid; int32_t supply_mv;")
    o("                 uint16_t temp_scale; int valid; int32_t c100; const char *note; } vec_temp_t;")
    o("static const vec_temp_t vec_temperature[] = {")
    for v in data["temperature"]:
        s, t = v["supply_mv"], v["temperature_c100"]
        o(f"    {{{v['adc']}, {v['ref_temp']}, {v['adc_ref']}, {int(s is not None)}, {opt(s, 0)}, "
          f"{v['temp_scale']}, {int(t is not None)}, {opt(t, 0)}, {c_str(v.get('note'))}}},")
    o("};")
    o("typedef struct { uint16_t adc; int16_t opamp_offset; int32_t o2_mv100; const char *note; } vec_o2_t;")
    o("static const vec_o2_t vec_o2[] = {")
    for v in data["o2"]:
        o(f"    {{{v['adc']}, {v['opamp_offset']}, {v['o2_mv100']}, {c_str(v.get('note'))}}},")
    o("};")
    o("typedef struct { uint16_t adc, gain; int32_t ppo2_mbar; const char *note; } vec_ppo2_t;")
    o("static const vec_ppo2_t vec_ppo2[] = {")
    for v in data["ppo2"]:
        o(f"    {{{v['adc']}, {v['gain']}, {v['ppo2_mbar']}, {c_str(v.get('note'))}}},")
    o("};")
    enc = {"binary": "TWH_FW_BINARY", "bcd": "TWH_FW_BCD", "unknown": "TWH_FW_UNKNOWN"}
    o("typedef struct { uint8_t byte; int version; unsigned encoding; } vec_fw_t;")
    o("static const vec_fw_t vec_fw[] = {")
    for v in data["fw_version"]:
        o(f"    {{{v['byte']}, {opt(v['version'])}, {enc[v['encoding']]}}},")
    o("};")
    o()


# ---------------------------------------------------------------------- flash
def gen_flash(o, o2, co2):
    o("/* ---- flash_o2.json, flash_co2.json ---- */")
    o("typedef struct { uint16_t year; uint8_t month, day, hour, minute; } vec_dt_t;")
    o("typedef struct {")
    o("    const char *note;")
    o("    unsigned kind;                 /* TWH_MAP_O2 / TWH_MAP_CO2 */")
    o("    const uint16_t *words; uint16_t n_words;")
    o("    const char *model, *mfg_id, *serial;")
    o("    vec_dt_t manufactured, expires; /* all 0: null */")
    o("    uint16_t temp_scale, ref_temp, adc_ref;")
    o("    uint16_t calibration_count;")
    o("    int has_current; uint16_t cur_addr, cur_stamp, cur_value; int32_t cur_hours;")
    o("    uint16_t flash_size;")
    o("    /* O2 */")
    o("    int map_version, map_type, opamp_offset, opamp_offset_word;")
    o("    uint16_t mfg_cal[3][2];")
    o("    /* CO2 */")
    o("    int has_rgb_offset, has_rgb_gain; uint16_t rgb_offset[3], rgb_gain[3];")
    o("    /* field cals of the description: count, then (addr, hours, value) */")
    o("    unsigned n_field_cals; uint16_t field_cals[16][3];")
    o("} vec_map_t;")
    maps = [("o2", i, m) for i, m in enumerate(o2["maps"])] + \
           [("co2", i, m) for i, m in enumerate(co2["maps"])]
    for kind, i, m in maps:
        o(f"static const uint16_t vec_map_{kind}_{i}_words[{len(m['words'])}] = {{")
        o(words_init(m["words"]))
        o("};")
    o("static const vec_map_t vec_maps[] = {")
    for kind, i, m in maps:
        d = m["decoded"]
        desc = m["description"]
        if desc["kind"] != kind:
            raise SystemExit(f"gen_c_vectors: {kind} map {i} has kind {desc['kind']}")
        cur = d["current_calibration"]
        fcs = desc.get("field_cals", [])
        if len(fcs) > 16:
            raise SystemExit("gen_c_vectors: more than 16 field cals in a description")
        fc = ", ".join(f"{{{c['addr']}, {c['hours']}, {c['value']}}}" for c in fcs) or "{0, 0, 0}"
        if kind == "o2":
            o2f = (f"{d['map_version']}, {d['map_type']}, {d['opamp_offset']}, "
                   f"{d['opamp_offset_word']}, "
                   f"{{{', '.join('{%d, %d}' % tuple(p) for p in d['mfg_cal'])}}}, "
                   "0, 0, {0, 0, 0}, {0, 0, 0}")
        else:
            ro, rg = d["rgb_offset"], d["rgb_gain"]
            o2f = ("0, 0, 0, 0, {{0, 0}, {0, 0}, {0, 0}}, "
                   f"{int(ro is not None)}, {int(rg is not None)}, "
                   f"{{{', '.join(str(x) for x in (ro or [0, 0, 0]))}}}, "
                   f"{{{', '.join(str(x) for x in (rg or [0, 0, 0]))}}}")
        o(f"    {{{c_str(m['note'])}, TWH_MAP_{kind.upper()}, vec_map_{kind}_{i}_words, "
          f"{len(m['words'])},")
        o(f"     {c_str(d['model'])}, {c_str(d['mfg_id'])}, {c_str(d['serial'])},")
        o(f"     {dt_init(d['manufactured'])}, {dt_init(d['expires'])},")
        o(f"     {d['temp_scale']}, {d['ref_temp']}, {d['adc_ref']}, {d['calibration_count']},")
        if cur is None:
            o("     0, 0, 0, 0, -1,")
        else:
            o(f"     1, {cur['addr']}, {cur['stamp']}, {cur['value']}, "
              f"{d['current_calibration_hours']},")
        o(f"     {d['flash_size']}, {o2f},")
        o(f"     {len(fcs)}, {{{fc}}}}},")
    o("};")
    o()

    enc = o2["encodings"]
    o("typedef struct { const uint16_t words[8]; uint8_t n_words; const char *text; } vec_text_t;")
    o("static const vec_text_t vec_text[] = {")
    for v in enc["text"]:
        if v["n_words"] > 8:
            raise SystemExit("gen_c_vectors: text vector longer than 8 words")
        # decoders strip NUL and space padding (flash_*.json "about")
        o(f"    {{{{{', '.join(str(w) for w in v['words'])}}}, {v['n_words']}, "
          f"{c_str(v['text'].rstrip(chr(0) + ' '))}}},")
    o("};")
    o("typedef struct { uint16_t w0, w1; int valid; vec_dt_t dt; const char *note; } vec_datetime_t;")
    o("static const vec_datetime_t vec_datetime[] = {")
    for v in enc["datetime"]:
        w0, w1 = v["words"]
        o(f"    {{{w0}, {w1}, {int(v['datetime'] is not None)}, {dt_init(v['datetime'])}, "
          f"{c_str(v.get('note'))}}},")
    o("};")
    o("typedef struct { int value; uint16_t word; } vec_s14_t;")
    o("static const vec_s14_t vec_s14[] = {")
    for v in enc["s14"]:
        o(f"    {{{v['value']}, {v['word']}}},")
    o("};")
    o("typedef struct {")
    o("    const char *note; uint16_t size;")
    o("    unsigned n_pairs; uint16_t pairs[16][3];  /* addr, word0, word1 */")
    o("    uint16_t count; int has_current; uint16_t cur_addr, cur_stamp, cur_value;")
    o("} vec_calcase_t;")
    o("static const vec_calcase_t vec_calcases[] = {")
    for v in o2["calibration_cases"]:
        pairs = v["pairs"]
        if len(pairs) > 16:
            raise SystemExit("gen_c_vectors: more than 16 pairs in a calibration case")
        pr = ", ".join(f"{{{a}, {w0}, {w1}}}" for a, w0, w1 in pairs) or "{0, 0, 0}"
        cur = v["current_calibration"]
        cc = "0, 0, 0, 0" if cur is None else f"1, {cur['addr']}, {cur['stamp']}, {cur['value']}"
        o(f"    {{{c_str(v['note'])}, {v['size']}, {len(pairs)}, {{{pr}}}, "
          f"{v['calibration_count']}, {cc}}},")
    o("};")
    o()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("json", nargs="+", help="tb/vectors/*.json")
    args = ap.parse_args(argv)
    files = {os.path.basename(p): p for p in args.json}
    need = ["frames.json", "conversions.json", "flash_o2.json", "flash_co2.json"]
    missing = [n for n in need if n not in files]
    if missing:
        raise SystemExit(f"gen_c_vectors: missing vector files: {missing}")
    extra = sorted(set(files) - set(need))
    if extra:
        print(f"gen_c_vectors: warning: vector files not used by the C tests: {extra}",
              file=sys.stderr)
    data = {}
    for n in need:
        with open(files[n]) as f:
            data[n] = json.load(f)

    o = Out()
    o("/* Generated by scripts/gen_c_vectors.py from the JSON files in tb/vectors/: do not edit,")
    o(" * do not commit (sw/Makefile makes it at build time). */")
    o("#ifndef TWH_VECTORS_H")
    o("#define TWH_VECTORS_H")
    o("#include <stddef.h>")
    o("#include <stdint.h>")
    o('#include "twh.h"')
    o()
    o("#define VEC_COUNT(a) (sizeof(a) / sizeof((a)[0]))")
    o()
    gen_frames(o, data["frames.json"])
    gen_conversions(o, data["conversions.json"])
    gen_flash(o, data["flash_o2.json"], data["flash_co2.json"])
    o("#endif /* TWH_VECTORS_H */")

    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    tmp = args.output + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(o.lines) + "\n")
    os.replace(tmp, args.output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
