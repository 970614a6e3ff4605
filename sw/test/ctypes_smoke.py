#!/usr/bin/env python3
"""Smoke test of build/shared/libtwh.so through Python ctypes (stdlib only).

It shows, and checks, that the API is usable from ctypes the way the
co-simulation will use it:
- the platform hooks are plain CFUNCTYPE callbacks plus a void *ctx;
- twh_t mirrored as a ctypes Structure has sizeof == twh_sizeof();
- twh_init / twh_submit / twh_result run against a register file written in
  Python, whose offsets and field positions are read from the generated
  include/twh_regs.h (nothing hand-copied): register map version 2, each
  channel's CMD_PUSH in its block, one core with 1 channel and one with 32;
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
def struct_layout(text, name):
    """Members of a packed struct of the generated header: {member: (offset,
    type, count)} and its size. uint32_t registers, uint8_t RESERVED_ gaps,
    and an array of an earlier struct (the channel blocks)."""
    body = re.search(r"typedef struct __attribute__ \(\(__packed__\)\) \{([^}]*)\} %s;" % name,
                     text, re.S).group(1)
    sizes = {"uint32_t": 4, "uint8_t": 1}
    members, off = {}, 0
    for typ, member, arr in re.findall(r"(\w+) (\w+)(?:\[(0x[0-9a-f]+|\d+)\])?;", body):
        n = int(arr, 0) if arr else 1
        if typ not in sizes:
            sizes[typ] = struct_layout(text, typ)[1]
        members[member] = (off, typ, n)
        off += sizes[typ] * n
    return members, off


def load_regs_h(path):
    """Register offsets of the generated header: the global registers by
    name, the channel blocks (base, stride, count, register offsets in a
    block), and the field macros (_bp, _bm)."""
    text = open(path).read()
    top, _ = struct_layout(text, "twh_regs_t")
    offsets = {m: o for m, (o, typ, n) in top.items() if typ == "uint32_t"}
    base, ch_typ, count = top["CH"]
    block, stride = struct_layout(text, ch_typ)
    ch_regs = {m: o for m, (o, typ, n) in block.items() if typ == "uint32_t"}
    fields = {m[0]: int(m[1], 0) for m in re.findall(r"#define TWH_REGS__(\w+) (0x[0-9a-f]+|\d+)", text)}
    return offsets, (base, stride, count, ch_regs), fields


OFF, (CH_BASE, CH_STRIDE, CH_COUNT, CH_REGS), FLD = load_regs_h(
    os.path.join(SW, "include", "twh_regs.h"))
assert "CMD_PUSH" not in OFF and "CMD_PUSH" in CH_REGS, "register map version 2 expected"


def decode_off(off):
    """a global register's name, or ("CH", n, register) for a channel block"""
    by_off = {v: k for k, v in OFF.items()}
    if off in by_off:
        return by_off[off]
    n, r = divmod(off - CH_BASE, CH_STRIDE)
    by_reg = {v: k for k, v in CH_REGS.items()}
    assert 0 <= n < CH_COUNT and r in by_reg, f"offset 0x{off:03X} is no register"
    return ("CH", n, by_reg[r])


def put(reg, field, value):
    return (value << FLD[f"{reg}__{field}_bp"]) & FLD[f"{reg}__{field}_bm"]


def get(reg, field, word):
    return (word & FLD[f"{reg}__{field}_bm"]) >> FLD[f"{reg}__{field}_bp"]


# ---------------------------------------------------------------- ctypes API
# the project's one ctypes binding of the driver lives in tb/
sys.path.insert(0, os.path.join(REPO, "tb"))
from twh_ctypes import (DELAY, READ32, WAIT_IRQ, WRITE32, Map, Platform,  # noqa: E402
                        Result, Twh)


class Core:
    """A register file in Python with `channels` channels; a push yields its
    result at once (0x1201 for the firmware command)."""

    def __init__(self, channels, major=None):
        self.channels = channels
        self.regs = {"ID": FLD["ID__MAGIC_reset"],
                     "VERSION": put("VERSION", "MAJOR", FLD["VERSION__MAJOR_reset"]
                                    if major is None else major) |
                                put("VERSION", "CHANNELS", channels),
                     "PARAMS": put("PARAMS", "FIFO_DEPTH", 16) | put("PARAMS", "CLK_KHZ", 48000),
                     "IRQ_EN": 0, "IDLE_CHARGE": 0, "BUSY": 0}
        self.results, self.log, self.pushes = [], [], []
        self.errors = []       # a failed check in a callback cannot raise through C
        # keep references to the callbacks alive
        self.cbs = (READ32(self.checked(self.read32)), WRITE32(self.checked(self.write32)),
                    DELAY(lambda ctx, us: None))
        self.plat = Platform(self.cbs[0], self.cbs[1], self.cbs[2], WAIT_IRQ(), None)

    def checked(self, fn):
        def call(*args):
            try:
                return fn(*args)
            except Exception as e:  # noqa: BLE001 - reported after the call
                self.errors.append(repr(e))
                return 0
        return call

    def read32(self, ctx, off):
        name = decode_off(off)
        assert isinstance(name, str), f"read of {name}"
        log, results, regs = self.log, self.results, self.regs
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

    def write32(self, ctx, off, value):
        name = decode_off(off)
        self.log.append(("w", name, value))
        if isinstance(name, tuple):
            _, ch, reg = name
            assert reg == "CMD_PUSH" and ch < self.channels, f"write of {name}"
            cmd = get("CHANNEL_T__CMD_PUSH", "CMD", value)
            self.pushes.append(ch)
            self.results.append((cmd, 0, ch, get("CHANNEL_T__CMD_PUSH", "TAG", value),
                                 0x1201 if cmd == 0x41 else 0))
        else:
            self.regs[name] = value


def main(libpath):
    lib = C.CDLL(libpath)
    lib.twh_sizeof.restype = C.c_uint32
    assert lib.twh_sizeof() == C.sizeof(Twh), (lib.twh_sizeof(), C.sizeof(Twh))
    lib.twh_submit.argtypes = [C.POINTER(Twh), C.c_uint8, C.c_uint8, C.c_uint16]
    lib.twh_set_idle_charge.argtypes = [C.POINTER(Twh), C.c_uint32]
    lib.twh_busy.argtypes = [C.POINTER(Twh)]
    lib.twh_busy.restype = C.c_uint32

    # ---- one channel, results made on push
    core = Core(1)
    log = core.log
    t = Twh()
    assert lib.twh_init(C.byref(t), C.byref(core.plat)) == 0
    assert (t.channels, t.fifo_depth, t.clk_khz) == (1, 16, 48000)
    assert log[0] == ("r", "ID")

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
    assert core.pushes == [0, 0] and not core.errors, core.errors

    # ---- 32 channels: channel 31's CMD_PUSH, its result, IDLE_CHARGE, BUSY
    core = Core(32)
    t = Twh()
    assert lib.twh_init(C.byref(t), C.byref(core.plat)) == 0
    assert t.channels == 32
    assert lib.twh_xfer(C.byref(t), 31, 0x41, 0xAA, C.byref(data)) == 0
    assert data.value == 0x1201 and core.pushes == [31], core.errors
    assert lib.twh_submit(C.byref(t), 31, 0x41, 0xAA) == 1
    assert lib.twh_result(C.byref(t), C.byref(r)) == 0 and (r.channel, r.tag) == (31, 1)
    assert lib.twh_submit(C.byref(t), 32, 0x41, 0xAA) == -13       # TWH_ERR_BAD_ARG
    assert lib.twh_set_idle_charge(C.byref(t), 1 << 20) == 0
    assert core.regs["IDLE_CHARGE"] == 1 << 20
    core.regs["BUSY"] = 0x80000001
    assert lib.twh_busy(C.byref(t)) == 0x80000001
    # a version 1 core and 33 channels are refused
    for bad in (Core(1, major=1), Core(33)):
        assert lib.twh_init(C.byref(t), C.byref(bad.plat)) == -14   # TWH_ERR_BAD_ID
        assert not bad.errors, bad.errors
    assert not core.errors, core.errors

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
    print("ctypes smoke: libtwh.so OK (sizeof(twh_t) = %d, init/submit/result/xfer on 1 and "
          "32 channels, %d O2 maps decoded)" % (C.sizeof(Twh), len(vec["maps"])))
    return 0


if __name__ == "__main__":
    sys.exit(main(os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                                  os.path.join(SW, "build", "shared", "libtwh.so"))))
