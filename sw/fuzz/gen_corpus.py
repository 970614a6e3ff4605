#!/usr/bin/env python3
"""Seed corpora for the driver's fuzz harnesses, from the shared vectors.

    python3 sw/fuzz/gen_corpus.py -o build/fuzz/corpus tb/vectors/*.json

Writes build/fuzz/corpus/<harness>/<name>.bin (not committed). Each seed is
laid out the way its harness reads its input (see the comment at the top of
sw/fuzz/fuzz_<harness>.c): the flash images, texts, dates, conversions and
frames of tb/vectors/ become the starting points the fuzzer mutates.
The register words of the driver harnesses' seeds are packed with the
field positions of the generated sw/include/twh_regs.h (register map
version 2: up to 32 channels, 5-bit channel fields).
Standard library only. Fails when a vector file misses a section it needs.
"""
from __future__ import annotations

import argparse
import json
import os
import re
import struct
import sys

BLANK = 0x3FFF
MAGIC = 0x54574831
HARNESSES = ("map", "cal_scan", "text", "datetime", "convert", "encode", "result", "driver")
REGS_H = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "include", "twh_regs.h")


def load_fields(path=REGS_H):
    """TWH_REGS__<REG>__<FIELD>_bp/_bm/_reset of the generated header"""
    with open(path) as f:
        text = f.read()
    return {m[0]: int(m[1], 0) for m in re.findall(r"#define TWH_REGS__(\w+) (0x[0-9a-fA-F]+|\d+)", text)}


FLD = load_fields()


def pack(reg: str, **fields) -> int:
    """a register word from field values, e.g. pack("RES_INFO", CMD=0x41, VALID=1)"""
    v = 0
    for name, x in fields.items():
        bp, bm = FLD[f"{reg}__{name}_bp"], FLD[f"{reg}__{name}_bm"]
        assert (x << bp) & bm == x << bp, f"{reg}.{name} = {x} does not fit"
        v |= x << bp
    return v


def u16(v: int) -> bytes:
    return struct.pack("<H", v & 0xFFFF)


def u32(v: int) -> bytes:
    return struct.pack("<I", v & 0xFFFFFFFF)


def words_bytes(words) -> bytes:
    return b"".join(u16(w) for w in words)


class Out:
    def __init__(self, root: str):
        self.root = root
        self.count = {h: 0 for h in HARNESSES}

    def __call__(self, harness: str, name: str, data: bytes) -> None:
        d = os.path.join(self.root, harness)
        os.makedirs(d, exist_ok=True)
        with open(os.path.join(d, name + ".bin"), "wb") as f:
            f.write(data)
        self.count[harness] += 1


def load(paths):
    vec = {}
    for p in paths:
        with open(p) as f:
            vec[os.path.splitext(os.path.basename(p))[0]] = json.load(f)
    for need in ("frames", "conversions", "flash_o2", "flash_co2"):
        if need not in vec:
            sys.exit(f"gen_corpus: {need}.json not given")
    return vec


def images(vec):
    """(name, kind 1=O2/2=CO2, words, decoded or None) of every flash image
    in the vectors."""
    out = []
    for i, m in enumerate(vec["flash_o2"]["maps"]):
        out.append((f"o2_map{i}", 1, m["words"], m["decoded"]))
    for i, m in enumerate(vec["flash_co2"]["maps"]):
        out.append((f"co2_map{i}", 2, m["words"], m["decoded"]))
    for i, c in enumerate(vec["flash_o2"]["calibration_cases"]):
        words = [BLANK] * c["size"]
        for a, w0, w1 in c["pairs"]:
            words[a], words[a + 1] = w0, w1
        out.append((f"calcase{i}", 1, words, None))
    return out


def gen_map(out, imgs):
    for name, kind, words, _ in imgs:
        out("map", name, bytes([kind]) + u16(len(words)) + words_bytes(words))
    # the smallest accepted image and one past the largest
    out("map", "min_size", bytes([1]) + u16(0x20) + words_bytes([BLANK] * 0x20))
    out("map", "too_big", bytes([2]) + u16(0x201))


def gen_cal_scan(out, imgs):
    for name, _, words, _ in imgs:
        area = words[0x20:min(len(words), 0xE0)]
        out("cal_scan", name, u16(len(words)) + bytes([255, 1]) + words_bytes(area))
        out("cal_scan", name + "_max2", u16(len(words)) + bytes([2, 1]) + words_bytes(area))


def text_seed(words, text: str) -> bytes:
    rt = bytes((ord(c) - 0x20) % 0x5F for c in text)
    return bytes([len(words)]) + words_bytes(words) + rt


def gen_text(out, vec, imgs):
    for i, t in enumerate(vec["flash_o2"]["encodings"]["text"]):
        out("text", f"enc{i}", text_seed(t["words"], t["text"]))
    for name, _, words, dec in imgs[:4]:
        out("text", name + "_model", text_seed(words[0:7], dec["model"]))
        out("text", name + "_mfg_id", text_seed(words[7:10], dec["mfg_id"]))
        out("text", name + "_serial", text_seed(words[0x10:0x16], dec["serial"]))


def dt_seed(w0: int, w1: int, d) -> bytes:
    if d is None:
        fields = bytes([0, 0, 0, 0, 0])
    else:
        fields = bytes([d["year"] - 2000, d["month"], d["day"], d["hour"], d["minute"]])
    return u16(w0) + u16(w1) + fields


def gen_datetime(out, vec, imgs):
    for i, d in enumerate(vec["flash_o2"]["encodings"]["datetime"]):
        out("datetime", f"enc{i}", dt_seed(d["words"][0], d["words"][1], d["datetime"]))
    for name, _, words, dec in imgs[:4]:
        out("datetime", name + "_mfg", dt_seed(words[0x0A], words[0x0B], dec["manufactured"]))
        out("datetime", name + "_exp", dt_seed(words[0x0C], words[0x0D], dec["expires"]))


def conv_seed(adc=0, rt=0, aref=0, smv=0, scale=0, off=0, gain=0, word=0, fw=0, flags=0):
    return (u16(adc) + u16(rt) + u16(aref) + u32(smv) + u16(scale) + u16(off) + u16(gain)
            + u16(word) + u16(fw) + bytes([flags]))


def gen_convert(out, vec):
    c = vec["conversions"]
    s14 = [e["word"] for e in vec["flash_o2"]["encodings"]["s14"]]
    for i, e in enumerate(c["supply"]):
        out("convert", f"supply{i}", conv_seed(adc=e["adc"], aref=e["adc"], flags=1))
    for i, e in enumerate(c["temperature"]):
        out("convert", f"temp{i}", conv_seed(adc=e["adc"], rt=e["ref_temp"], aref=e["adc_ref"],
                                             smv=e["supply_mv"] or 0, scale=e["temp_scale"]))
    for i, e in enumerate(c["o2"]):
        out("convert", f"o2_{i}", conv_seed(adc=e["adc"], off=e["opamp_offset"],
                                            word=s14[i % len(s14)]))
    for i, e in enumerate(c["ppo2"]):
        out("convert", f"ppo2_{i}", conv_seed(adc=e["adc"], gain=e["gain"]))
    for i, e in enumerate(c["fw_version"]):
        out("convert", f"fw{i}", conv_seed(fw=e["byte"] << 8 | 1))


def gen_encode(out, vec):
    for i, v in enumerate(v for v in vec["frames"]["vectors"] if v["kind"] == "command"):
        cmd = v["cmd"]
        base = cmd & 0xFE if 0x46 <= cmd <= 0x4B else cmd
        out("encode", f"cmd{i}", bytes([base]) + u16(v.get("addr", 0)) + u16(v.get("data", 0))
            + bytes([cmd, i % 16]))


def responses(vec):
    """(cmd, data) of the response vectors, the command taken from the note
    ("0x40 answer: ...") and 0x48 for the ones without one."""
    out = []
    for v in vec["frames"]["vectors"]:
        if v["kind"] != "response":
            continue
        note = v.get("note", "")
        cmd = int(note[2:4], 16) if note.startswith("0x") else 0x48
        out.append((cmd, v["bytes_in"][0] << 8 | v["bytes_in"][1]))
    return out


def result_init(channels: int) -> bytes:
    """the result harness's first bytes: flags, then what twh_init reads
    (ID, VERSION, PARAMS), the timeout and poll step"""
    version = pack("VERSION", MAJOR=FLD["VERSION__MAJOR_reset"], CHANNELS=channels)
    params = pack("PARAMS", FIFO_DEPTH=16, CLK_KHZ=48000)
    return bytes([0]) + u32(MAGIC) + u32(version) + u32(params) + bytes([64, 0])


def result_xfer(ch: int, cmd: int, data: int, tag: int) -> bytes:
    """op 0x81 % 6 = 3: twh_xfer, bit 7: with a data pointer; then the
    register values it reads: STATUS (room), RES_INFO, RES_POP"""
    info = pack("RES_INFO", CMD=cmd, STATUS=0, CHANNEL=ch, VALID=1, TAG=tag)
    pop = pack("RES_POP", DATA=data, STATUS=0, CHANNEL=ch, VALID=1, TAG=tag)
    return bytes([0x81, ch, cmd]) + u16(0xAA) + u32(0) + u32(info) + u32(pop)


def gen_result(out, vec):
    """raw mode: init reads, then one blocking transfer per response vector
    answered by the register values a real core would give."""
    init = result_init(2)
    body = b""
    for tag, (cmd, data) in enumerate(responses(vec)):
        step = result_xfer(0, cmd, data, tag)
        out("result", f"xfer{tag}", init + step)
        body += step
    # then poll, result (empty), cancel
    body += bytes([0, 0]) + u32(0) + bytes([1, 0]) + u32(0) + bytes([4, 0]) + u32(1)
    out("result", "all", init + body)
    # a 32-channel core: transfers on channels 31 and 16 (a 3-bit channel
    # field would alias them with 7 and 0), idle charge on channel 20 and
    # BUSY (helpers 13 and 14)
    cmd, data = responses(vec)[0]
    body = result_xfer(31, cmd, data, 0) + result_xfer(16, cmd, data, 1)
    body += bytes([5, 0, 13]) + u16(0) + u16(1 << 4) + bytes([5, 0, 14]) + u16(0) + u16(0) \
        + u32(1 << 31 | 1 << 20)
    out("result", "ch32", result_init(32) + body)


def dev_seed(words, fw: int, typ: int, fill=None) -> bytes:
    """a device description for fuzz_driver.c setup_dev; fill = (base, step)
    programs the whole calibration area with base + i*step first"""
    prog = [(a, w) for a, w in enumerate(words) if 0x20 <= a < 0xE0 and w != BLANK][:255]
    d = bytes([0x40 if fill else 0]) + u16(len(words) ^ 240) + bytes([fw ^ 0x12, typ ^ 0x01, 0])
    d += u16(0) + u16(0) + u16(0)
    if fill:
        d += u16(fill[0]) + bytes([fill[1]])
    d += bytes([len(prog)])
    for a, w in prog:
        d += bytes([a - 0x20]) + u16(w)
    return d


def helper(op: int, sub: int = 0, a: int = 0, b: int = 0, ch: int = 0) -> bytes:
    return bytes([op, ch, sub]) + u16(a) + u16(b)


def gen_driver(out, imgs):
    fws = {"o2_map0": (0x12, 1), "o2_map1": (0x0F, 1), "co2_map0": (0x26, 2), "co2_map1": (0x26, 3)}
    for name, _, words, _ in imgs:
        fw, typ = fws.get(name, (0x12, 1))
        head = bytes([0]) + u16(0xFFFF) + bytes([0, 0, 7]) + dev_seed(words, fw, typ)
        ops = (helper(6) + helper(7) + helper(8, 0) + helper(8, 2) + helper(14, 0)
               + helper(13, a=len(words)) + helper(15, a=3000, b=3650)
               + helper(9, a=0x20) + helper(10, a=0x16))
        out("driver", name, head + ops)
    # a full calibration area: the append must erase the oldest page (with
    # step 0 every stamp ties, and the lowest page is the oldest)
    name, _, words, _ = imgs[0]
    for base, step in ((2000, 0), (100, 3)):
        head = bytes([0]) + u16(0xFFFF) + bytes([0, 0, 7]) + dev_seed(words, 0x12, 1, (base, step))
        out("driver", f"full_area_{base}_{step}",
            head + helper(15, a=4000, b=3650) + helper(13, a=len(words)))
    # two channels with the O2 v18 map, non-blocking traffic mixed in
    name, _, words, _ = imgs[0]
    head = bytes([1]) + u16(0xFFFF) + bytes([1, 2, 3]) + dev_seed(words, 0x12, 1) + dev_seed(words, 0x0F, 1)
    ops = b""
    for i in range(6):
        ops += bytes([0, i % 2, 0x44]) + u16(0xAA)       # submit
        ops += helper(15, a=4000 + i, b=3600 + i, ch=i % 2)
    ops += bytes([4, 0]) + bytes([1, 0]) + bytes([2, 0]) * 8
    out("driver", "two_channels", head + ops)
    # 32 channels (1 + 31 % 32), the O2 v18 map on channel 31 and a CO2 cell
    # on 20, none on the others; traffic on 31 and 20, idle charge (helper
    # 14, sub 2 | 4: present channels only), BUSY with commands queued
    absent = bytes([0x80]) + bytes(12)
    co2_name, _, co2_words, _ = imgs[2]
    devs = [absent] * 32
    devs[20] = dev_seed(co2_words, 0x26, 2)
    devs[31] = dev_seed(words, 0x12, 1)
    head = bytes([1]) + u16(0xFFFF) + bytes([31, 0, 3]) + b"".join(devs)
    ops = helper(7, ch=31) + helper(14, ch=31) + helper(6, ch=20) + helper(10, a=0x16, ch=31)
    ops += bytes([0, 31, 0x44]) + u16(0xAA) + bytes([0, 20, 0x44]) + u16(0xAA) + bytes([1, 0])
    ops += helper(14, sub=6, a=0, b=(1 << 15) | (1 << 4)) + bytes([2, 0]) * 2
    ops += helper(15, a=4000, b=3600, ch=31)
    out("driver", "ch32", head + ops)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--out", required=True)
    ap.add_argument("vectors", nargs="+")
    args = ap.parse_args()
    vec = load(args.vectors)
    out = Out(args.out)
    imgs = images(vec)
    gen_map(out, imgs)
    gen_cal_scan(out, imgs)
    gen_text(out, vec, imgs)
    gen_datetime(out, vec, imgs)
    gen_convert(out, vec)
    gen_encode(out, vec)
    gen_result(out, vec)
    gen_driver(out, imgs)
    print("gen_corpus: " + ", ".join(f"{h} {n}" for h, n in out.count.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
