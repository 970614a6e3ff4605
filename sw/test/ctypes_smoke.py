#!/usr/bin/env python3
"""Smoke test of build/shared/libtwh.so through Python ctypes (stdlib only).

It shows, and checks, that the API is usable from ctypes the way the
co-simulation will use it:
- the platform hooks are plain CFUNCTYPE callbacks plus a void *ctx;
- twh_t mirrored as a ctypes Structure has sizeof == twh_sizeof();
- twh_init / twh_submit / twh_result run against a register file written in
  Python, whose offsets and field positions are read from the generated
  include/twh_regs.h (nothing hand-copied);
- the decoders agree with the shared vectors (tb/vectors/flash_o2.json).

    python3 test/ctypes_smoke.py build/shared/libtwh.so
"""
import ctypes as C
import json
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SW = os.path.dirname(HERE)
REPO = os.path.dirname(SW)


# ---------------------------------------------------------------- twh_regs.h
def load_regs_h(path):
    """Register offsets (twh_regs_t members, all uint32_t, packed) and
    field macros (_bp, _bm) of the generated header."""
    text = open(path).read()
    body = re.search(r"typedef struct __attribute__ \(\(__packed__\)\) \{([^}]*)\} twh_regs_t;",
                     text, re.S).group(1)
    offsets, off = {}, 0
    for typ, name, arr in re.findall(r"(\w+) (\w+)(?:\[(0x[0-9a-f]+|\d+)\])?;", body):
        if typ != "uint32_t":
            break                      # RESERVED_..., then the channel blocks
        offsets[name] = off
        off += 4
    fields = {m[0]: int(m[1], 0) for m in re.findall(r"#define TWH_REGS__(\w+) (0x[0-9a-f]+|\d+)", text)}
    return offsets, fields


OFF, FLD = load_regs_h(os.path.join(SW, "include", "twh_regs.h"))


def put(reg, field, value):
    return (value << FLD[f"{reg}__{field}_bp"]) & FLD[f"{reg}__{field}_bm"]


def get(reg, field, word):
    return (word & FLD[f"{reg}__{field}_bm"]) >> FLD[f"{reg}__{field}_bp"]


# ---------------------------------------------------------------- ctypes API
# the project's one ctypes binding of the driver lives in tb/
sys.path.insert(0, os.path.join(REPO, "tb"))
from twh_ctypes import (DELAY, READ32, WAIT_IRQ, WRITE32, Map, Platform,  # noqa: E402
                        Result, Twh)


def main(libpath):
    lib = C.CDLL(libpath)
    lib.twh_sizeof.restype = C.c_uint32
    assert lib.twh_sizeof() == C.sizeof(Twh), (lib.twh_sizeof(), C.sizeof(Twh))

    # ---- a register file in Python: one channel, results made on push
    regs = {"ID": FLD["ID__MAGIC_reset"],
            "VERSION": put("VERSION", "MAJOR", FLD["VERSION__MAJOR_reset"]) |
                       put("VERSION", "CHANNELS", 1),
            "PARAMS": put("PARAMS", "FIFO_DEPTH", 16) | put("PARAMS", "CLK_KHZ", 48000),
            "IRQ_EN": 0}
    results, log = [], []
    by_off = {v: k for k, v in OFF.items()}

    def read32(ctx, off):
        name = by_off[off]
        log.append(("r", name))
        if name == "STATUS":
            return 0
        if name == "RES_INFO":
            if not results:
                return 0
            cmd, st, ch, tag, data = results[0]
            return (put("RES_INFO", "CMD", cmd) | put("RES_INFO", "STATUS", st) |
                    put("RES_INFO", "CHANNEL", ch) | put("RES_INFO", "VALID", 1) |
                    put("RES_INFO", "TAG", tag))
        if name == "RES_POP":
            cmd, st, ch, tag, data = results.pop(0)
            return (put("RES_POP", "DATA", data) | put("RES_POP", "STATUS", st) |
                    put("RES_POP", "CHANNEL", ch) | put("RES_POP", "VALID", 1) |
                    put("RES_POP", "TAG", tag))
        return regs[name]

    def write32(ctx, off, value):
        name = by_off[off]
        log.append(("w", name, value))
        if name == "CMD_PUSH":
            cmd = get("CMD_PUSH", "CMD", value)
            results.append((cmd, 0, get("CMD_PUSH", "CHANNEL", value),
                            get("CMD_PUSH", "TAG", value), 0x1201 if cmd == 0x41 else 0))
        else:
            regs[name] = value

    def delay(ctx, us):
        pass

    cbs = (READ32(read32), WRITE32(write32), DELAY(delay))  # keep references alive
    plat = Platform(cbs[0], cbs[1], cbs[2], WAIT_IRQ(), None)
    t = Twh()
    assert lib.twh_init(C.byref(t), C.byref(plat)) == 0
    assert (t.channels, t.fifo_depth, t.clk_khz) == (1, 16, 48000)
    assert log[0] == ("r", "ID")

    lib.twh_submit.argtypes = [C.POINTER(Twh), C.c_uint8, C.c_uint8, C.c_uint16]
    tag = lib.twh_submit(C.byref(t), 0, 0x41, 0xAA)
    assert tag == 0
    r = Result()
    assert lib.twh_result(C.byref(t), C.byref(r)) == 0
    assert (r.cmd, r.status, r.channel, r.tag, r.data) == (0x41, 0, 0, 0, 0x1201)
    assert [e[1] for e in log[-2:]] == ["RES_INFO", "RES_POP"]
    assert lib.twh_result(C.byref(t), C.byref(r)) == -12        # TWH_ERR_AGAIN
    # blocking helper: the result arrives on the push
    data = C.c_uint16()
    assert lib.twh_xfer(C.byref(t), 0, 0x41, 0xAA, C.byref(data)) == 0
    assert data.value == 0x1201

    # ---- decoders on the shared vectors
    vec = json.load(open(os.path.join(REPO, "tb", "vectors", "flash_o2.json")))
    for m in vec["maps"]:
        words = (C.c_uint16 * len(m["words"]))(*m["words"])
        out = Map()
        assert lib.twh_decode_map(words, len(m["words"]), 1, C.byref(out)) == 0
        d = m["decoded"]
        assert out.model.decode() == d["model"] and out.serial.decode() == d["serial"]
        assert out.opamp_offset == d["opamp_offset"]
        assert out.cal_count == d["calibration_count"]
        assert out.current.addr == d["current_calibration"]["addr"]
        assert out.manufactured.year == d["manufactured"]["year"]
    print("ctypes smoke: libtwh.so OK (sizeof(twh_t) = %d, init/submit/result/xfer, "
          "%d O2 maps decoded)" % (C.sizeof(Twh), len(vec["maps"])))
    return 0


if __name__ == "__main__":
    sys.exit(main(os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                                  os.path.join(SW, "build", "shared", "libtwh.so"))))
