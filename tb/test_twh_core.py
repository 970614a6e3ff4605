"""The bus-attached core (twh_wb / twh_axil around twh_core) in tb/tb_core.v.

Every test runs a spec monitor on every channel's host pins for its whole
length (CoreTB) and closes them with finish(): any breach of the spec's
timing table, carrier, bit rate, framing or checksum fails the test. The
register map is read from rdl/twh_regs.rdl (tb/regmap.py): nothing about
addresses, reset values or access types is restated here.

Most functional tests use Wishbone; the register tests and the FIFO test
run on both buses. Tests that only need the command/result machinery run
lab-short phases (LAB_KEY, ~3 ms per transaction, no peripheral); tests
that need answers run real spec timing against the peripheral models.
"""
import os
import random

import cocotb
import pytest
from cocotb.simtime import get_sim_time
from cocotb.triggers import RisingEdge, Timer

import protocol as p
import regmap
from coretb import (BLOCKED, CANCELLED, DEFAULT_TIMING, FACTORY_KEY, LAB_KEY,
                    NO_RESPONSE, OK, TIMING_FIELDS, TXN_US, CoreTB)
from periph_model import Faults

BLANK = 0x3FFF
BAD_CHECKSUM = int(p.Status.BAD_CHECKSUM)
LINE_STUCK_HIGH = int(p.Status.LINE_STUCK_HIGH)


def frame(cmd, payload=0xAA):
    return p.build_frame(cmd, payload)


def check_order(results, pushed):
    """Every pushed (ch, tag, cmd) has exactly one result, and per channel
    the results come in push order."""
    key = sorted((r.channel, r.tag) for r in results)
    assert key == sorted((c, t) for c, t, _ in pushed), (results, pushed)
    for ch in {c for c, _, _ in pushed}:
        want = [(t, cmd) for c, t, cmd in pushed if c == ch]
        got = [(r.tag, r.cmd) for r in results if r.channel == ch]
        assert got == want, f"channel {ch}: results {got}, pushed {want}"


def txn_end_ps(tx):
    """End of the listen window of a spec-monitor transaction."""
    us = sum(x or 0 for x in (tx.charge_us, tx.sync_us, tx.preamble_us,
                              tx.command_us, tx.execute_us, tx.listen_us))
    return tx.start_ps + us * 1e6


# ============================================================== 1. regmap
TIMING_PATTERNS = {   # in-window values, (low field, high field)
    "TIMING0": [(7000, 900), (65535, 1100), (12345, 1050), (0xA5A5, 0x3FF)],
    "TIMING1": [(1800, 3500), (2200, 10000), (2047, 0x1555), (1900, 9999)],
    "TIMING2": [(2000, 2000), (65535, 65535), (0x5A5A, 0xA5A5), (3001, 2001)],
}


@cocotb.test()
async def regmap_access(dut):
    """Every register of the RDL: reset value (build parameters substituted),
    rw fields hold patterns, ro fields ignore writes, write-only registers
    read 0, woclr bits clear on 1 only, unmapped addresses and absent channel
    blocks answer with a bus error, partial byte enables answer with an
    error and change nothing."""
    tb = await CoreTB(dut, cells=(None, None, None)).start()
    rm = tb.rm
    last = tb.channels - 1

    # ---- IDLE_CHARGE waits for the post-reset hold-off: a reset may have
    # cut a listen short, and the line rests the minimum turnaround (2 ms)
    # however soon software sets IDLE_CHARGE again
    ones = (1 << tb.channels) - 1
    await tb.write("IDLE_CHARGE", ones)
    assert get_sim_time("us") - tb.t_reset_us < 100
    while get_sim_time("us") - tb.t_reset_us < 1995:
        assert all(getattr(dut, f"line_oe_{ch}").value == 0 for ch in range(tb.channels)), \
            f"idle charge {get_sim_time('us') - tb.t_reset_us:.1f} us after reset"
        await Timer(5, "us")
    await Timer(10, "us")
    assert all(getattr(dut, f"line_oe_{ch}").value == 1 for ch in range(tb.channels)), \
        "idle charge not driven after the hold-off"
    await Timer(100, "us")                 # a carrier burst, for the monitor
    await tb.write("IDLE_CHARGE", 0)       # back to the reset state

    present = {r.address: r for r in rm.registers}

    async def snapshot():
        out = {}
        for reg in rm.registers:
            if reg.name != "RES_POP":
                out[reg.name] = await tb.read(reg.name)
        return out

    # ---- reset values
    for reg in rm.registers:
        v, err = await tb.read32(reg.address)
        assert not err, f"{reg.name}: bus error on read"
        want = reg.reset & reg.read_mask
        assert v == want, f"{reg.name} after reset: {v:#010x}, RDL says {want:#010x}"
    assert dut.irq.value == 0

    # ---- read-only registers: writes acknowledged and ignored
    for reg in rm.registers:
        if reg.write_mask:
            continue
        before = await tb.read(reg.name)
        await tb.write(reg.name, ~before & 0xFFFFFFFF)
        assert await tb.read(reg.name) == before, f"{reg.name}: a write changed a read-only register"
        await tb.write(reg.name, 0xFFFFFFFF)
        await tb.write(reg.name, 0)
        assert await tb.read(reg.name) == before, reg.name

    # ---- write-only registers read 0 (CMD_PUSH, keys), also after a write
    for name in ("LAB_KEY", "FACTORY_KEY"):
        assert await tb.read(name) == 0
        await tb.write(name, 0x12345678)
        assert await tb.read(name) == 0, name
    # the keys: the right value unlocks, anything else locks again
    for name, key, fld in (("LAB_KEY", LAB_KEY, "LAB_UNLOCKED"),
                           ("FACTORY_KEY", FACTORY_KEY, "FACTORY_UNLOCKED")):
        await tb.write(name, key)
        assert await tb.field("VERSION", fld) == 1, name
        assert await tb.read(name) == 0, f"{name} reads back its key"
        await tb.write(name, key ^ 1)
        assert await tb.field("VERSION", fld) == 0, name

    # ---- CTRL: ENABLE holds values, FLUSH reads 0; IDLE_CHARGE holds a bit
    # for each channel of the build (the others read 0)
    ctrl = tb.reg("CTRL")
    for en, ic in ((0, 0x00), (1, 0xA5A5A5A5), (0, 0x5A5A5A5A), (1, 0xFFFFFFFF), (1, 0x00)):
        v = tb.pack("CTRL", ENABLE=en)
        await tb.write("CTRL", v | ctrl.reserved_mask)
        got = await tb.read("CTRL")
        assert got == v, f"CTRL wrote {v:#x}, read {got:#x}"
        await tb.write("IDLE_CHARGE", ic)
        got = await tb.read("IDLE_CHARGE")
        assert got == ic & ones, f"IDLE_CHARGE wrote {ic:#x}, read {got:#x}"
        # the carrier runs on channels with IDLE_CHARGE set: keep every
        # burst long enough to be a carrier (the monitor judges it)
        for ch in range(tb.channels):
            if (ic >> ch) & 1:
                await Timer(100, "us")
                assert getattr(dut, f"line_oe_{ch}").value == 1, f"idle charge ch{ch} not driven"
                break
        else:
            await Timer(20, "us")
    await tb.write("CTRL", tb.pack("CTRL", ENABLE=1, FLUSH=1))
    assert await tb.read("CTRL") == tb.pack("CTRL", ENABLE=1), "FLUSH does not read 0"
    assert await tb.read("IDLE_CHARGE") == 0
    await Timer(20, "us")
    for ch in range(tb.channels):
        assert getattr(dut, f"line_oe_{ch}").value == 0, f"ch{ch} still driven after IDLE_CHARGE=0"

    # ---- IRQ_EN
    for res, er, po, thr in ((1, 0, 1, 0xFF), (0, 1, 0, 0x55), (1, 1, 1, 0xAA), (0, 0, 0, 7)):
        v = tb.pack("IRQ_EN", RESULT=res, ERROR=er, POLL=po, RES_THRESHOLD=thr)
        await tb.write("IRQ_EN", v | tb.reg("IRQ_EN").reserved_mask)
        assert await tb.read("IRQ_EN") == v
        assert dut.irq.value == 0, "irq without a source"
    await tb.write("IRQ_EN", tb.reg("IRQ_EN").reset)

    # ---- per-channel timing: in-window patterns hold, nothing refused
    for ch in range(tb.channels):
        for rname, pats in TIMING_PATTERNS.items():
            reg = tb.reg(rname, ch)
            lo_f, hi_f = reg.fields[0].name, reg.fields[1].name
            for lo, hi in pats:
                v = tb.pack(rname, ch, **{lo_f: lo, hi_f: hi})
                await tb.write(rname, v, ch)
                assert await tb.read(rname, ch) == v, (rname, ch, hex(v))
            await tb.write(rname, reg.reset, ch)
            assert await tb.read(rname, ch) == reg.reset
    assert await tb.errors() == 0, "an in-window timing write was refused"

    # ---- POLL_CTRL: patterns with read-only commands (ENABLE = 0 while EN
    # is set, so no poll starts)
    await tb.write("CTRL", tb.pack("CTRL", ENABLE=0))
    for ch in range(tb.channels):
        reg = tb.reg("POLL_CTRL", ch)
        for cmd, pl, iv, en in ((0x40, 0x55, 0x5555, 0), (0x49, 0xAA, 0x2AAA, 1),
                                (0x46, 0xFF, 0x7FFF, 0), (0x43, 0x00, 1, 1)):
            v = tb.pack("POLL_CTRL", ch, CMD=cmd, PAYLOAD=pl, INTERVAL_MS=iv, EN=en)
            await tb.write("POLL_CTRL", v, ch)
            assert await tb.read("POLL_CTRL", ch) == v, (ch, hex(v))
        await tb.write("POLL_CTRL", reg.reset, ch)
        assert await tb.read("POLL_CTRL", ch) == reg.reset
    assert await tb.errors() == 0
    await tb.write("CTRL", tb.reg("CTRL").reset)

    # ---- ERRORS (woclr): provoke three sources, then clear bit by bit
    errs = tb.reg("ERRORS")
    await tb.write("ERRORS", errs.woclr_mask)          # 1s on clear bits set nothing
    assert await tb.errors() == 0
    await tb.write_fields("TIMING0", 0, CHARGE_US=100, SYNC_US=1000)       # refused
    await tb.push(0x41, ch=tb.channels, expect_err=True)                    # absent channel
    await tb.write("CTRL", tb.pack("CTRL", ENABLE=0))
    for i in range(tb.fifo_depth):
        await tb.push(0x41, ch=i % tb.channels, tag=i)
    await tb.push(0x41, expect_err=True)                                    # full
    want = tb.pack("ERRORS", CMD_OVERFLOW=1, VALUE_REFUSED=1, BAD_CHANNEL=1)
    assert await tb.errors() == want, hex(await tb.errors())
    assert await tb.field("IRQ_STATUS", "ERROR") == 1
    await tb.write("ERRORS", 0)
    assert await tb.errors() == want, "writing 0 cleared an error bit"
    for name in ("VALUE_REFUSED", "CMD_OVERFLOW", "BAD_CHANNEL"):
        await tb.write_fields("ERRORS", **{name: 1})
        want &= ~errs.field(name).mask
        assert await tb.errors() == want, (name, hex(await tb.errors()))
    assert await tb.field("IRQ_STATUS", "ERROR") == 0
    # the queued commands go as CANCELLED: no line activity
    await tb.write("CTRL", tb.pack("CTRL", ENABLE=0, FLUSH=1))
    res = await tb.wait_results(tb.fifo_depth, timeout_ms=20)
    assert all(r.status == CANCELLED for r in res), res
    await tb.write("CTRL", tb.reg("CTRL").reset)

    # ---- POLL_READY (woclr): 1s on clear bits set nothing
    await tb.write("POLL_READY", 0xFFFFFFFF)
    assert await tb.read("POLL_READY") == 0

    # ---- CMD_PUSH reads 0
    for ch in range(tb.channels):
        assert await tb.read("CMD_PUSH", ch) == 0

    # ---- unmapped addresses and absent channel blocks: bus error, no
    # effect but ERRORS.BAD_CHANNEL for a push to an absent channel (its
    # command is refused: nothing queued)
    before = await snapshot()
    n_unmapped = n_bad = 0
    bad_ch = tb.reg("ERRORS").field("BAD_CHANNEL").mask
    absent_push = {r.address for r in rm.absent if r.name.endswith(".CMD_PUSH")}
    for a in range(0, 0x800, 4):
        if a in present:
            continue
        n_unmapped += 1
        v, err = await tb.read32(a)
        assert err, f"read of unmapped {a:#05x} acknowledged"
        assert await tb.write32(a, 0xFFFFFFFF), f"write of unmapped {a:#05x} acknowledged"
        assert await tb.write32(a, 0x00000000), f"write of unmapped {a:#05x} acknowledged"
        if a in absent_push:
            n_bad += 1
            assert await tb.errors() == bad_ch, f"push to absent {a:#05x}: ERRORS {await tb.errors():#x}"
            await tb.write("ERRORS", bad_ch)
        assert await tb.errors() == 0, f"access to unmapped {a:#05x}: ERRORS {await tb.errors():#x}"
    assert n_unmapped == 512 - len(rm.registers)
    assert n_bad == 32 - tb.channels
    for reg in rm.absent:
        assert reg.address not in present
    after = await snapshot()
    assert after == before, "writes to unmapped addresses changed registers"

    # ---- partial byte enables: error, nothing written
    sels = (0x1, 0x3, 0x7, 0xE, 0xC, 0x8, 0x6) + ((0x0,) if tb.bus_kind == 0 else ())
    targets = [("CTRL", None, 0x00000000), ("IDLE_CHARGE", None, 0xFFFFFFFF),
               ("IRQ_EN", None, 0x0000FF07),
               ("TIMING0", 0, tb.pack("TIMING0", 0, CHARGE_US=9000, SYNC_US=1100)),
               ("POLL_CTRL", last, tb.pack("POLL_CTRL", last, CMD=0x41, INTERVAL_MS=5)),
               ("ERRORS", None, 0xFFFFFFFF), ("LAB_KEY", None, LAB_KEY),
               ("FACTORY_KEY", None, FACTORY_KEY),
               ("CMD_PUSH", last, tb.pack("CMD_PUSH", last, CMD=0x41, TAG=3))]
    await tb.write_fields("TIMING0", last, CHARGE_US=100, SYNC_US=1000)    # refused: sets an error
    before = await snapshot()
    assert before["ERRORS"] != 0
    for name, ch, value in targets:
        for sel in sels:
            err = await tb.write32(tb.addr(name, ch), value, sel=sel)
            assert err, f"{name}: write with byte enables {sel:#x} acknowledged"
    after = await snapshot()
    assert after == before, {k: (hex(before[k]), hex(after[k])) for k in before if before[k] != after[k]}
    await tb.clear_errors()
    assert await tb.pop() is None

    if tb.bus_kind == 0:
        # one Wishbone cycle of back-to-back strobes: each answered once,
        # in order, with its own data or error
        thr = tb.pack("IRQ_EN", RES_THRESHOLD=9)
        hole = next(a for a in range(0, 0x200, 4) if a not in present)
        ops = [(tb.addr("ID"), None, 0xF), (tb.addr("IRQ_EN"), thr, 0xF),
               (tb.addr("IRQ_EN"), None, 0xF), (hole, None, 0xF), (tb.addr("PARAMS"), None, 0xF),
               (tb.addr("IRQ_EN"), 0, 0x1), (tb.addr("IRQ_EN"), None, 0xF), (hole, 0, 0xF),
               (tb.addr("ID"), None, 0xF)]
        got = await tb.bus.cycle(ops)
        want = [(tb.reg("ID").reset, False), (0, False), (thr, False), (0, True),
                (tb.reg("PARAMS").reset, False), (0, True), (thr, False), (0, True),
                (tb.reg("ID").reset, False)]
        for (a, d, sel), g, w in zip(ops, got, want):
            if d is None:
                assert g == w, (hex(a), g, w)
            else:
                assert g[1] == w[1], (hex(a), g, w)
        await tb.write("IRQ_EN", tb.reg("IRQ_EN").reset)
    if tb.bus_kind == 1:
        # reads and writes issued at once (AR beside AW/W): each is answered
        # once, with its own data and response
        bus = tb.bus
        id_addr, thr_addr = tb.addr("ID"), tb.addr("IRQ_EN")
        hole = next(a for a in range(0, 0x200, 4) if a not in present)
        ops = []
        for k in range(12):
            ops.append(("r", id_addr, cocotb.start_soon(bus.read(id_addr))))
            ops.append(("w", thr_addr, cocotb.start_soon(
                bus.write(thr_addr, tb.pack("IRQ_EN", RES_THRESHOLD=k + 1)))))
            ops.append(("r", hole, cocotb.start_soon(bus.read(hole))))
        for kind, a, task in ops:
            r = await task
            data, resp = r if kind == "r" else (None, r)
            if a == hole:
                assert resp == 2, (kind, hex(a), r)
            else:
                assert resp == 0, (kind, hex(a), r)
                if kind == "r":
                    assert data == tb.reg("ID").reset
        tb.bus.n_access += len(ops)      # issued around the driver's count
        assert await tb.field("IRQ_EN", "RES_THRESHOLD") == 12
        await tb.write("IRQ_EN", tb.reg("IRQ_EN").reset)
    await tb.finish()


# ============================================================== 2. three cells
def plan_for(prof, ch):
    """Four commands with the answers the profile must give."""
    msb, lsb = prof.config_response()
    fw = prof.fw_byte << 8 | prof.type_byte
    free = next(a for a in range(0x20, prof.flash_size) if prof.flash[a] == BLANK)
    return [
        [(0x41, 0xAA, fw), (0x44, 0xAA, prof.adc_o2),
         (*p.addr_cmd(0x48, 0x19), prof.flash[0x19]), (0x40, 0xAA, msb << 8 | lsb)],
        [(0x41, 0xAA, fw), (0x43, 0xAA, prof.adc_temperature),
         (*p.addr_cmd(0x48, 0x0A), prof.flash[0x0A]), (0x42, 0xAA, prof.adc_ref_voltage)],
        [(0x41, 0xAA, fw), (0x42, 0xAA, prof.adc_ref_voltage),
         (*p.addr_cmd(0x48, 0x10), prof.flash[0x10]), (*p.addr_cmd(0x46, 0x20), free)],
    ][ch]


@cocotb.test()
async def three_channels(dut):
    """Three modelled cells busy at once: per-channel timing, results right,
    per-channel order and tags, the lines' transactions overlap."""
    tb = await CoreTB(dut, cells=("o2_v18", "o2_v15", "co2")).start()
    execute = {0: 6000, 1: 4500, 2: 3500}     # v18 recommended; v15 <= 4.5 ms
    for ch, ex in execute.items():
        await tb.set_timing(ch, execute=ex)
    plans = {ch: plan_for(tb.profiles[ch], ch) for ch in range(3)}
    # channel 2 keeps its carrier on while idle (IDLE_CHARGE), the others
    # release the line
    await tb.write_fields("CTRL", ENABLE=1)
    await tb.write("IDLE_CHARGE", 0b100)
    pushed = []
    for i in range(4):
        for ch in range(3):
            cmd, pl, _ = plans[ch][i]
            tag = ch * 8 + i
            await tb.push(cmd, pl, ch, tag)
            pushed.append((ch, tag, cmd))

    # all three engines busy together
    await tb.wait_until(lambda: _running(tb, (0, 1, 2)), timeout_ms=10)
    assert await tb.read("BUSY") == 0b111
    for ch in range(3):
        assert (await tb.fields("STATE", ch)).BUSY == 1

    results = await tb.wait_results(12, timeout_ms=4 * TXN_US // 1000 + 40)
    check_order(results, pushed)
    for ch in range(3):
        mine = [r for r in results if r.channel == ch]
        answered = [t for t in tb.models[ch].log if t.response is not None]
        assert len(answered) == 4, (ch, tb.models[ch].log)
        for (cmd, pl, want), r, t in zip(plans[ch], mine, answered):
            assert r.status == OK, r
            assert r.data == want, (ch, hex(cmd), hex(r.data), hex(want))
            assert r.data == t.response[0] << 8 | t.response[1], (r, t.response)
        txs = tb.txns(ch)
        assert [bytes(t.frame) for t in txs] == [frame(c, pl) for c, pl, _ in plans[ch]]
        for t in txs:
            assert round(t.execute_us) == execute[ch], (ch, t.execute_us)
    # the first transaction of each line overlaps those of the other two
    firsts = [tb.txns(ch)[0] for ch in range(3)]
    assert max(t.start_ps for t in firsts) < min(txn_end_ps(t) for t in firsts), \
        [(t.start_ps, txn_end_ps(t)) for t in firsts]
    # every line ran its four back to back: the next charge right after the
    # turnaround (the queue kept all three fed)
    for ch in range(3):
        for t in tb.txns(ch)[:-1]:
            assert 2000 <= t.turnaround_us < 2010, (ch, t.turnaround_us)
    assert await tb.errors() == 0
    # after the last turnaround: ch2 charging, ch0 and ch1 released
    await tb.wait_idle()
    await Timer(100, "us")
    assert [int(getattr(dut, f"line_oe_{ch}").value) for ch in range(3)] == [0, 0, 1]
    await tb.finish()


# ============================================================== 3. FIFO edges
@cocotb.test()
async def fifo_edges(dut):
    """Command FIFO filled with ENABLE = 0 (nothing drains): the next push
    errs and sets CMD_OVERFLOW, levels and flags read right. Result FIFO
    full: the engines hold their results (no transaction beyond FIFO_DEPTH +
    one held per channel) and nothing is lost. Popping an empty FIFO gives
    VALID = 0 and removes nothing."""
    tb = await CoreTB(dut, cells=(None, None, None)).start()
    depth, nch = tb.fifo_depth, tb.channels
    await tb.lab_timing()
    st = await tb.fields("STATUS")
    assert (st.CMD_EMPTY, st.CMD_FULL, st.RES_EMPTY, st.RES_FULL) == (1, 0, 1, 0), st
    assert await tb.pop() is None

    await tb.write_fields("CTRL", ENABLE=0)
    pushed = []
    for i in range(depth):
        ch = i % nch
        await tb.push(0x41 + (i % 3), ch=ch, tag=i % 32)
        pushed.append((ch, i % 32, 0x41 + (i % 3)))
        lv = await tb.fields("LEVELS")
        assert (lv.CMD_LEVEL, lv.RES_LEVEL) == (i + 1, 0), (i, lv)
        st = await tb.fields("STATUS")
        assert st.CMD_FULL == (i + 1 == depth) and st.CMD_EMPTY == 0, (i, st)
    assert await tb.errors() == 0
    await tb.push(0x41, ch=0, tag=31, expect_err=True)
    assert await tb.errors() == tb.pack("ERRORS", CMD_OVERFLOW=1)
    await tb.push(0x41, ch=7, tag=31, expect_err=True)          # absent channel, FIFO full
    assert await tb.field("ERRORS", "BAD_CHANNEL") == 1
    assert (await tb.fields("LEVELS")).CMD_LEVEL == depth
    await tb.clear_errors()
    # nothing starts while disabled
    await Timer(4, "ms")
    assert all(len(tb.txns(ch)) == 0 for ch in range(nch))
    assert await tb.read("BUSY") == 0
    for ch in range(nch):
        assert (await tb.fields("STATE", ch)).SLOT_FULL == 0

    # ---- result FIFO full: push more than depth + channels in all
    total = depth + nch + 3
    await tb.write_fields("CTRL", ENABLE=1)
    i = depth
    while i < total:
        ch = i % nch
        if await tb.push(0x40, ch=ch, tag=i % 32, expect_err=None):
            pushed.append((ch, i % 32, 0x40))
            i += 1
        else:
            assert await tb.field("ERRORS", "CMD_OVERFLOW") == 1
            await tb.clear_errors()
            await Timer(500, "us")

    async def res_full():
        return (await tb.fields("STATUS")).RES_FULL == 1
    await tb.wait_until(res_full, timeout_ms=total * 4)
    await Timer(12, "ms")                      # ~4 lab transactions
    n_line = sum(len(tb.txns(ch)) for ch in range(nch))
    assert n_line == depth + tb.held_results, \
        f"{n_line} transactions ran with a full result FIFO (depth {depth})"
    lv = await tb.fields("LEVELS")
    assert lv.RES_LEVEL == depth, lv
    st = await tb.fields("STATUS")
    assert st.RES_FULL == 1 and st.RES_EMPTY == 0, st
    # BUSY: "a transaction is queued in the channel or running, or
    # its result has yet to enter the result FIFO": each engine ran one
    # transaction more than the FIFO holds, and its result waits in the
    # channel with the engine idle (STATE.BUSY 0)
    busy = await tb.read("BUSY")
    assert busy == (1 << nch) - 1, f"results wait in every channel, BUSY = {busy:#x}"
    for ch in range(nch):
        s = await tb.fields("STATE", ch)
        assert s.BUSY == 0 and s.PHASE == 0, (ch, s)

    # ---- pop everything: every command exactly once, in order per channel
    results = await tb.wait_results(total, timeout_ms=total * 4)
    check_order(results, pushed)
    assert all(r.status == NO_RESPONSE and r.data == 0 for r in results), results
    assert sum(len(tb.txns(ch)) for ch in range(nch)) == total
    # the line carried exactly the pushed commands, in order per channel
    for ch in range(nch):
        assert tb.frames(ch) == [frame(c) for cc, _, c in pushed if cc == ch]

    # ---- empty FIFO: VALID = 0, nothing removed, nothing invented
    await tb.wait_idle()
    for _ in range(3):
        info = await tb.fields("RES_INFO")
        pop = await tb.fields("RES_POP")
        assert info.VALID == 0 and pop.VALID == 0, (info, pop)
    lv = await tb.fields("LEVELS")
    assert (lv.CMD_LEVEL, lv.RES_LEVEL) == (0, 0), lv
    st = await tb.fields("STATUS")
    assert (st.CMD_EMPTY, st.CMD_FULL, st.RES_EMPTY, st.RES_FULL) == (1, 0, 1, 0), st
    r = await tb.command(0x43, ch=1, tag=17, timeout_ms=20)
    assert r.status == NO_RESPONSE and r.channel == 1, r
    assert await tb.errors() == 0, "NO_RESPONSE results set an error"
    await tb.finish()


# ============================================================== 4. protection
@cocotb.test()
async def factory_protection(dut):
    """Erase/write of words 0x00-0x1F: BLOCKED, nothing on the line,
    ERRORS.BLOCKED. FACTORY_KEY lets the next pushed command through (and
    only that one). Addresses 0x20 and up are never blocked."""
    tb = await CoreTB(dut, cells=("o2_v18", "o2_v18", "co2")).start()
    m0 = tb.models[0]
    blocked = [p.addr_cmd(0x4A, 0x05), p.write_cmd(0x10, 0x1234), p.addr_cmd(0x4A, 0x1F),
               p.write_cmd(0x1F, 0x0000), p.write_cmd(0x00, 0x3FFF), p.addr_cmd(0x4A, 0x00)]
    # payload bits outside the address must not matter: 0x4A with payload
    # 0xFF05 is still address 0x05
    blocked.append((0x4A, 0xFF05))
    for tag, (cmd, pl) in enumerate(blocked):
        await tb.push(cmd, pl, ch=0, tag=tag)
    res = await tb.wait_results(len(blocked), timeout_ms=5)
    for (cmd, pl), r, tag in zip(blocked, res, range(len(blocked))):
        assert (r.cmd, r.status, r.data, r.tag, r.channel) == (cmd, BLOCKED, 0, tag, 0), r
    assert await tb.errors() == tb.pack("ERRORS", BLOCKED=1)
    await tb.clear_errors()
    # an armed key that is overwritten is disarmed
    await tb.write("FACTORY_KEY", FACTORY_KEY)
    assert await tb.field("VERSION", "FACTORY_UNLOCKED") == 1
    await tb.write("FACTORY_KEY", 0)
    assert await tb.field("VERSION", "FACTORY_UNLOCKED") == 0
    r = await tb.command(*p.addr_cmd(0x4A, 0x10), ch=0, tag=20, timeout_ms=5)
    assert r.status == BLOCKED, r
    await tb.clear_errors()
    await Timer(3, "ms")              # past the post-reset hold-off
    assert m0.log == [] and tb.txns(0) == [], "a blocked command reached the line"

    # ---- the key lets exactly the next command through (ch0); unblocked
    # addresses on ch1/ch2 run at the same time
    await tb.write("FACTORY_KEY", FACTORY_KEY)
    assert await tb.field("VERSION", "FACTORY_UNLOCKED") == 1
    await tb.push(*p.addr_cmd(0x4A, 0x10), ch=0, tag=1)
    assert await tb.field("VERSION", "FACTORY_UNLOCKED") == 0, "unlock still armed after a push"
    await tb.push(*p.write_cmd(0x10, 0x0ABC), ch=0, tag=2)      # blocked again
    await tb.push(*p.addr_cmd(0x48, 0x10), ch=0, tag=3)
    free1 = 0x85 if tb.profiles[1].flash[0x85] == BLANK else None
    ch1 = [p.addr_cmd(0x4A, 0x20), p.write_cmd(0x85, 0x0155)]   # 0x85: cmd bits 6:0 = 0x05
    ch2 = [p.addr_cmd(0x4A, 0x105), p.write_cmd(0x20, 0x0AAA)]  # 0x4B 0x05, 0x20
    for i, (cmd, pl) in enumerate(ch1):
        await tb.push(cmd, pl, ch=1, tag=i)
    for i, (cmd, pl) in enumerate(ch2):
        await tb.push(cmd, pl, ch=2, tag=i)
    res = await tb.wait_results(7, timeout_ms=3 * TXN_US // 1000 + 30)
    r0 = [r for r in res if r.channel == 0]
    assert [(r.tag, r.status) for r in r0] == [(1, NO_RESPONSE), (2, BLOCKED), (3, OK)], r0
    assert r0[2].data == BLANK, "the unlocked erase did not reach the cell"
    assert [t.name for t in m0.log] == ["ERASE", "READ"], m0.log
    assert m0.log[0].frame == frame(*p.addr_cmd(0x4A, 0x10))
    assert m0.flash[0x10:0x20] == [BLANK] * 16
    assert await tb.field("ERRORS", "BLOCKED") == 1
    for ch, cmds in ((1, ch1), (2, ch2)):
        rs = [r for r in res if r.channel == ch]
        assert [(r.tag, r.cmd, r.status) for r in rs] == \
            [(i, c, NO_RESPONSE) for i, (c, _) in enumerate(cmds)], rs
        assert [t.frame for t in tb.models[ch].log] == [frame(c, pl) for c, pl in cmds]
        assert tb.frames(ch) == [frame(c, pl) for c, pl in cmds]
    if free1 is not None:
        assert tb.models[1].flash[0x85] == 0x0155
    assert tb.models[2].flash[0x20] == 0x0AAA or tb.profiles[2].flash[0x20] != BLANK
    await tb.finish()


# ============================================================== 5. timing
OUT_OF_WINDOW = {   # phase: values just outside its window
    "charge": [6999, 0], "sync": [899, 1101, 0, 65535], "preamble": [1799, 2201],
    "execute": [3499, 10001, 65535], "listen": [1999, 0], "turnaround": [1999, 1],
}
EDGES = {"charge": [7000, 65535], "sync": [900, 1100], "preamble": [1800, 2200],
         "execute": [3500, 10000], "listen": [2000, 65535], "turnaround": [2000, 65535]}


@cocotb.test()
async def timing_registers(dut):
    """Out-of-window timing writes are refused as a whole (register keeps its
    value, VALUE_REFUSED); the window edges are taken. With LAB_KEY the
    values are taken and run unclamped; locked again, the engine clamps."""
    tb = await CoreTB(dut, cells=("o2_v18", None, None)).start()
    for ch in range(tb.channels):
        for ph, values in OUT_OF_WINDOW.items():
            for v in values:
                await tb.set_timing(ch, expect_refused=True, **{ph: v})
                assert await tb.errors() == tb.pack("ERRORS", VALUE_REFUSED=1), (ch, ph, v)
                await tb.clear_errors()
        for ph, values in EDGES.items():
            for v in values:
                await tb.set_timing(ch, **{ph: v})
            await tb.set_timing(ch, **{ph: DEFAULT_TIMING[ph]})
        assert await tb.errors() == 0
    # one good field and one bad: the whole write is refused
    await tb.set_timing(1, expect_refused=True, charge=9000, sync=850)
    await tb.set_timing(1, expect_refused=True, preamble=2100, execute=3000)
    await tb.set_timing(1, expect_refused=True, listen=5000, turnaround=100)
    await tb.clear_errors()

    # ---- lab unlock: values taken as written (zero too), run unclamped
    await tb.lab_unlock(True)
    await tb.set_timing(2, listen=0, turnaround=0)
    await tb.set_timing(2, **DEFAULT_TIMING)
    tb.monitors[0].allow_out_of_spec(True)
    await tb.set_timing(0, sync=600, preamble=2500, execute=3200, listen=2500)
    assert await tb.errors() == 0
    r = await tb.command(0x41, ch=0, tag=1)
    tx = tb.txns(0)[-1]
    assert (round(tx.sync_us), round(tx.preamble_us), round(tx.execute_us)) == (600, 2500, 3200), tx
    assert r.status == OK, r         # the model answers a 3 ms execute
    tb.monitors[0].allow_out_of_spec(False)
    # ---- locked again: the registers keep the values, the engine clamps
    await tb.lab_unlock(False)
    assert await tb.field("TIMING0", "SYNC_US", 0) == 600
    r = await tb.command(0x41, ch=0, tag=2)
    tx = tb.txns(0)[-1]
    assert (round(tx.sync_us), round(tx.preamble_us), round(tx.execute_us)) == (900, 2200, 3500), tx
    assert r.status == OK, r
    # and an out-of-window write is refused again
    await tb.set_timing(0, expect_refused=True, sync=600)
    await tb.clear_errors()
    await tb.finish()


# ============================================================== 6. polling
@cocotb.test()
async def polling(dut):
    """Autonomous polling beside queued commands on the same channel: they
    alternate; POLL_RESULT carries the cell's reading, COUNT counts, and
    POLL_READY and the poll IRQ follow. Polls never enter the result FIFO.
    Refused poll commands; the interval between poll starts."""
    tb = await CoreTB(dut, cells=("o2_v18", "o2_v15", None)).start()
    prof = tb.profiles[0]
    # ---- only read-only commands are accepted
    before = await tb.read("POLL_CTRL", 0)
    for cmd in (0x00, 0x3F, 0x45, 0x4A, 0x4B, 0x4C, 0x7F, 0x80, 0xFF):
        await tb.write_fields("POLL_CTRL", 0, CMD=cmd, PAYLOAD=0xAA, INTERVAL_MS=1, EN=1)
        assert await tb.read("POLL_CTRL", 0) == before, hex(cmd)
        assert await tb.errors() == tb.pack("ERRORS", VALUE_REFUSED=1), hex(cmd)
        await tb.clear_errors()
    assert len(tb.txns(0)) == 0

    # ---- poll 0x44 with INTERVAL_MS = 0 (acts as 1 ms: always due) beside
    # three queued commands
    await tb.write_fields("IRQ_EN", POLL=1, RES_THRESHOLD=1)
    await tb.write_fields("POLL_CTRL", 0, CMD=0x44, PAYLOAD=0xAA, INTERVAL_MS=0, EN=1)
    assert await tb.field("POLL_CTRL", "INTERVAL_MS", 0) == 0   # rw: reads as written
    pushed = []
    for tag in (1, 2, 3):
        await tb.push(0x41, ch=0, tag=tag)
        pushed.append((0, tag, 0x41))
    res = await tb.wait_results(3, timeout_ms=8 * TXN_US // 1000 + 20)
    check_order(res, pushed)
    assert all(r.status == OK and r.data == prof.fw_byte << 8 | prof.type_byte for r in res), res
    await tb.write_fields("POLL_CTRL", 0, CMD=0x44, PAYLOAD=0xAA, INTERVAL_MS=1, EN=0)
    await tb.wait_idle()
    cmds = [f[0] for f in tb.frames(0)]
    last_cmd = max(i for i, c in enumerate(cmds) if c == 0x41)
    window = cmds[:last_cmd + 1]
    assert window.count(0x41) == 3
    # both wait all along: strictly alternating
    for a, b in zip(window, window[1:]):
        assert a != b, f"not alternating: {[hex(c) for c in cmds]}"
    n_polls = cmds.count(0x44)
    assert n_polls >= 2, cmds
    pr = await tb.fields("POLL_RESULT", 0)
    assert (pr.DATA, pr.STATUS, pr.COUNT) == (prof.adc_o2, OK, n_polls), (pr, n_polls)
    assert await tb.read("POLL_READY") == 0b001
    ist = await tb.fields("IRQ_STATUS")
    assert (ist.POLL, ist.RESULT, ist.ERROR) == (1, 0, 0), ist
    assert dut.irq.value == 1
    assert (await tb.fields("LEVELS")).RES_LEVEL == 0, "a poll result entered the result FIFO"
    await tb.write("POLL_READY", 0b001)
    assert await tb.read("POLL_READY") == 0
    assert dut.irq.value == 0

    # ---- interval: 30 ms between poll starts; ch1 polls a flash word at
    # the same time; one poll answered with a bad checksum -> LINK_ERROR
    await tb.write_fields("POLL_CTRL", 1, CMD=0x48, PAYLOAD=0x10, INTERVAL_MS=30, EN=1)
    await tb.write_fields("POLL_CTRL", 0, CMD=0x44, PAYLOAD=0xAA, INTERVAL_MS=30, EN=1)
    n0 = len(tb.txns(0))

    async def polls_done(k):
        async def f():
            return (await tb.fields("POLL_RESULT", 0)).COUNT >= n_polls + k
        return f
    await tb.wait_until(await polls_done(2), timeout_ms=80)
    tb.models[0].inject(Faults(bad_checksum=True))
    await tb.wait_until(await polls_done(3), timeout_ms=40)
    await tb.write_fields("POLL_CTRL", 0, CMD=0x44, PAYLOAD=0xAA, INTERVAL_MS=30, EN=0)
    await tb.write_fields("POLL_CTRL", 1, CMD=0x48, PAYLOAD=0x10, INTERVAL_MS=30, EN=0)
    pr = await tb.fields("POLL_RESULT", 0)
    assert pr.STATUS == BAD_CHECKSUM and pr.COUNT == n_polls + 3, pr
    assert await tb.field("ERRORS", "LINK_ERROR") == 1
    await tb.wait_idle()
    starts = [t.start_ps for t in tb.txns(0)[n0:]]
    assert len(starts) == 3, starts
    for a, b in zip(starts, starts[1:]):
        assert abs((b - a) / 1e9 - 30) <= 1.0, f"poll starts {(b - a) / 1e9:.3f} ms apart"
    pr1 = await tb.fields("POLL_RESULT", 1)
    assert pr1.DATA == tb.profiles[1].flash[0x10] and pr1.STATUS == OK and pr1.COUNT >= 2, pr1
    assert await tb.read("POLL_READY") == 0b011
    assert all(bytes(f) == frame(0x48, 0x10) for f in tb.frames(1))
    assert await tb.pop() is None, "a poll result entered the result FIFO"
    await tb.write("POLL_READY", 0xFFFFFFFF)
    await tb.clear_errors()
    await tb.finish()


# ============================================================== 7. random traffic
@cocotb.test()
async def random_traffic(dut):
    """Seeded random reads and writes (mapped and unmapped addresses, some
    partial byte enables): every access is answered in time, unmapped ones
    and partial writes with an error, the core does not lock up, and a
    normal command works afterwards."""
    # A fixed default keeps CI deterministic; TWH_TRAFFIC_SEED=N (or
    # =random) picks another, and the log line replays it.
    env_seed = os.environ.get("TWH_TRAFFIC_SEED", "20251123")
    seed = random.getrandbits(32) if env_seed == "random" else int(env_seed)
    n = int(os.environ.get("TWH_RANDOM_ACCESSES", "3000"))
    dut._log.info("random_traffic: seed TWH_TRAFFIC_SEED=%d, %d accesses", seed, n)
    rng = random.Random(seed)
    tb = await CoreTB(dut, cells=("o2_v18", "o2_v15", "co2")).start()
    rm = tb.rm
    present = {r.address: r for r in rm.registers}
    n_err = n_pushed = 0
    for i in range(n):
        if rng.random() < 0.75:
            addr = rng.choice(list(present))
        else:
            addr = rng.randrange(0, 0x800, 4)
        reg = present.get(addr)
        if rng.random() < 0.5:
            v, err = await tb.read32(addr)
            assert err == (reg is None), f"#{i} read {addr:#05x}: err={err}"
            if reg is not None:
                assert v & ~reg.read_mask == 0, f"#{i} {reg.name}: {v:#x} has bits outside fields"
                if reg.name == "ID":
                    assert v == reg.reset
            continue
        value = rng.getrandbits(32)
        if reg is not None and reg.name.endswith("TIMING2") and rng.random() < 0.8:
            value &= ~0xF800            # mostly a refused listen (< 2000 us): keeps the lines' times short
        if reg is not None and reg.name == "IDLE_CHARGE":
            value = 0                   # no idle-charge toggling: bursts of a few us are runts
        absent_push = reg is None and any(r.address == addr and r.name.endswith(".CMD_PUSH")
                                          for r in rm.absent)
        sel = 0xF if rng.random() < 0.9 else rng.choice([0x1, 0x3, 0x7, 0xE, 0xC, 0x8])
        err = await tb.write32(addr, value, sel=sel)
        if reg is None or sel != 0xF:
            assert err, f"#{i} write {addr:#05x} sel {sel:#x} acknowledged"
            if absent_push and sel == 0xF:
                assert await tb.field("ERRORS", "BAD_CHANNEL") == 1, f"#{i} push to absent {addr:#05x}"
        elif reg.name.endswith(".CMD_PUSH"):
            n_pushed += not err
        else:
            assert not err, f"#{i} write {reg.name} = {value:#x}: bus error"
        n_err += err
    dut._log.info("random_traffic: %d errors answered, %d commands accepted", n_err, n_pushed)

    # ---- back to a known state: stop polls, flush, let the lines finish
    await tb.lab_unlock(False)
    for ch in range(tb.channels):
        await tb.write_fields("POLL_CTRL", ch, CMD=0x44, PAYLOAD=0xAA, INTERVAL_MS=1000, EN=0)
        tb.timing[ch] = {k: -1 for k in DEFAULT_TIMING}    # unknown: write them all
        await tb.set_timing(ch, **DEFAULT_TIMING)
    await tb.write("IRQ_EN", 0)
    await tb.write_fields("CTRL", ENABLE=1, FLUSH=1)
    await tb.wait_idle(timeout_ms=400, drain=True)
    await tb.drain()
    tb.results.clear()
    await tb.write("POLL_READY", 0xFFFFFFFF)
    await tb.clear_errors()
    # a random LAB_KEY write may have unlocked a random timing write: any
    # transaction that ran was judged in lab mode only if the lab key was on
    # ---- a normal command on every channel
    for ch in range(tb.channels):
        await tb.push(0x41, ch=ch, tag=30)
    res = await tb.wait_results(3, timeout_ms=TXN_US // 1000 + 20)
    for r in res:
        prof = tb.profiles[r.channel]
        assert (r.status, r.data, r.tag) == (OK, prof.fw_byte << 8 | prof.type_byte, 30), r
    await tb.finish()


# ============================================================== 8. IRQ, flush
@cocotb.test()
async def irq_and_flush(dut):
    """IRQ: result-level threshold (0 acts as 1), error, enables gate the
    raw sources. FLUSH: queued commands come back CANCELLED in order, the
    running ones finish; nothing is lost."""
    tb = await CoreTB(dut, cells=(None, None, None)).start()
    await tb.lab_timing()
    assert dut.irq.value == 0

    # ---- result threshold
    await tb.write_fields("IRQ_EN", RESULT=1, RES_THRESHOLD=3)
    for k in range(3):
        await tb.push(0x41, ch=k, tag=k)
        await tb.wait_until(lambda: _level_is(tb, k + 1), timeout_ms=10)
        ist = await tb.fields("IRQ_STATUS")
        assert ist.RESULT == (k + 1 >= 3) and int(dut.irq.value) == (k + 1 >= 3), (k, ist)
    r = await tb.pop()
    assert r.tag in (0, 1, 2)
    assert dut.irq.value == 0 and (await tb.fields("IRQ_STATUS")).RESULT == 0
    await tb.write_fields("IRQ_EN", RESULT=1, RES_THRESHOLD=0)     # 0 behaves as 1
    assert dut.irq.value == 1
    assert await tb.field("IRQ_EN", "RES_THRESHOLD") == 0      # rw: reads as written
    await tb.write_fields("IRQ_EN", RESULT=0, RES_THRESHOLD=1)
    assert dut.irq.value == 0 and (await tb.fields("IRQ_STATUS")).RESULT == 1
    await tb.drain()
    tb.results.clear()
    assert (await tb.fields("IRQ_STATUS")).RESULT == 0

    # ---- error: bad channel, then a link error (line stuck high)
    await tb.write_fields("IRQ_EN", ERROR=1)
    assert dut.irq.value == 0
    await tb.push(0x41, ch=5, expect_err=True)
    assert dut.irq.value == 1 and (await tb.fields("IRQ_STATUS")).ERROR == 1
    await tb.write("ERRORS", 0)
    assert dut.irq.value == 1
    await tb.clear_errors()
    assert dut.irq.value == 0
    dut.stuck_val_0.value = 1
    dut.stuck_en_0.value = 1
    r = await tb.command(0x41, ch=0, tag=9, timeout_ms=20)
    dut.stuck_en_0.value = 0
    assert r.status == LINE_STUCK_HIGH and r.data == 0, r
    assert await tb.errors() == tb.pack("ERRORS", LINK_ERROR=1)
    assert dut.irq.value == 1
    await tb.write_fields("IRQ_EN", ERROR=0)
    assert dut.irq.value == 0 and (await tb.fields("IRQ_STATUS")).ERROR == 1
    await tb.clear_errors()

    # ---- flush while disabled: every queued command CANCELLED, in order,
    # nothing on the line
    n_line = [len(tb.txns(ch)) for ch in range(tb.channels)]
    await tb.write_fields("CTRL", ENABLE=0)
    pushed = []
    for i, ch in enumerate((0, 1, 0, 2, 0)):
        await tb.push(0x40 + i, ch=ch, tag=10 + i)
        pushed.append((ch, 10 + i, 0x40 + i))
    await tb.write_fields("CTRL", ENABLE=0, FLUSH=1)
    res = await tb.wait_results(5, timeout_ms=5)
    check_order(res, pushed)
    assert all(r.status == CANCELLED and r.data == 0 for r in res), res
    st = await tb.fields("STATUS")
    assert st.FLUSHING == 0 and st.CMD_EMPTY == 1, st
    assert [len(tb.txns(ch)) for ch in range(tb.channels)] == n_line
    assert await tb.errors() == 0

    # ---- flush while running: A (ch0) and E (ch1) run, the others wait in
    # their channels' queues
    await tb.write_fields("CTRL", ENABLE=1)
    order = [(0, 20, 0x41), (1, 21, 0x42), (0, 22, 0x43), (1, 23, 0x44), (0, 24, 0x40), (0, 25, 0x41)]
    for ch, tag, cmd in order:
        await tb.push(cmd, ch=ch, tag=tag)

    await tb.wait_until(lambda: _running(tb, (0, 1)), timeout_ms=5, poll_us=20)
    # every command reaches its channel's queue (each waits at most a
    # carrier period for its channel's visit): none is held behind another
    await tb.wait_until(lambda: _cmd_level_is(tb, 0), timeout_ms=1, poll_us=2)
    assert await _running(tb, (0, 1))
    await tb.write_fields("CTRL", ENABLE=1, FLUSH=1)
    assert (await tb.fields("STATUS")).FLUSHING == 1
    res = await tb.wait_results(6, timeout_ms=20)
    check_order(res, order)
    status = {r.tag: r.status for r in res}
    assert status == {20: NO_RESPONSE, 21: NO_RESPONSE, 22: CANCELLED, 23: CANCELLED,
                      24: CANCELLED, 25: CANCELLED}, status
    assert [len(tb.txns(ch)) for ch in range(tb.channels)] == [n_line[0] + 1, n_line[1] + 1, n_line[2]]
    assert (await tb.fields("STATUS")).FLUSHING == 0
    # after the flush commands run normally
    r = await tb.command(0x42, ch=0, tag=26, timeout_ms=20)
    assert r.status == NO_RESPONSE, r

    # ---- ENABLE = 0 mid-transaction: the running one finishes, the next
    # waits in its queue (queued: BUSY), nothing starts, no poll runs
    await tb.push(0x40, ch=2, tag=27)
    await tb.push(0x43, ch=2, tag=28)
    await tb.wait_until(lambda: _running(tb, (2,)), timeout_ms=10, poll_us=20)
    await tb.write_fields("CTRL", ENABLE=0)
    await tb.write_fields("POLL_CTRL", 2, CMD=0x41, PAYLOAD=0xAA, INTERVAL_MS=1, EN=1)
    r = await tb.wait_result(2, 27, timeout_ms=10)
    assert r.status == NO_RESPONSE, r
    n2 = len(tb.txns(2))
    await Timer(5, "ms")
    assert len(tb.txns(2)) == n2, "a transaction or poll started with ENABLE = 0"
    assert (await tb.fields("POLL_RESULT", 2)).COUNT == 0
    s = await tb.fields("STATE", 2)
    assert s.SLOT_FULL == 1 and s.PHASE == 0, s
    busy = await tb.read("BUSY")
    # enabled again: the queued command and the polls run
    await tb.write_fields("CTRL", ENABLE=1)
    r = await tb.wait_result(2, 28, timeout_ms=20)
    assert r.status == NO_RESPONSE and r.cmd == 0x43, r
    await tb.wait_until(lambda: _polls(tb, 2, 2), timeout_ms=20)
    await tb.write_fields("POLL_CTRL", 2, CMD=0x41, PAYLOAD=0xAA, INTERVAL_MS=1, EN=0)
    await tb.wait_idle()
    pr = await tb.fields("POLL_RESULT", 2)
    assert pr.STATUS == NO_RESPONSE and pr.DATA == 0, pr
    assert pr.COUNT == sum(1 for f in tb.frames(2)[n2:] if f[0] == 0x41), (pr, tb.frames(2))
    assert await tb.read("POLL_READY") == 0b100
    await tb.write("POLL_READY", 0b100)
    assert await tb.errors() == 0, "NO_RESPONSE polls set an error"

    # ---- a push while FLUSHING is still draining (the head waits for a busy
    # channel): is it cancelled too? (RDL: the flush cancels the commands
    # "still in the command FIFO" when it is written)
    for ch, tag in ((0, 1), (0, 2), (0, 3)):
        await tb.push(0x41, ch=ch, tag=tag)
    await tb.wait_until(lambda: _running(tb, (0,)), timeout_ms=10, poll_us=20)
    await tb.write_fields("CTRL", ENABLE=1, FLUSH=1)
    assert (await tb.fields("STATUS")).FLUSHING == 1
    await tb.push(0x42, ch=1, tag=4)
    res = await tb.wait_results(4, timeout_ms=20)
    late = [r for r in res if r.tag == 4][0]
    dut._log.warning("push during FLUSHING: result status %d (%s)", late.status,
                     "cancelled" if late.status == CANCELLED else "ran")
    assert late.status != CANCELLED, "a command pushed after the flush was cancelled by it"
    assert await tb.errors() == 0, "CANCELLED results set an error bit"
    # checked last so that the rest of the test runs first
    assert busy & 0b100, f"command queued in ch2's queue (ENABLE = 0), BUSY = {busy:#x}"
    await tb.finish()


async def _running(tb, channels):
    for ch in channels:
        if (await tb.fields("STATE", ch)).PHASE == 0:
            return False
    return True


async def _polls(tb, ch, n):
    return (await tb.fields("POLL_RESULT", ch)).COUNT >= n


async def _level_is(tb, n):
    return (await tb.fields("LEVELS")).RES_LEVEL == n


async def _cmd_level_is(tb, n):
    return (await tb.fields("LEVELS")).CMD_LEVEL == n


@cocotb.test()
async def reset_mid_traffic(dut):
    """Reset while every channel works: queued commands, one transaction on
    each line, results waiting, a poll running. What software sees after
    it: every line released on the first reset clock, every register at
    its reset value, no result from before the reset, ever, and nothing on
    the lines until something is pushed; then a command runs as usual, its
    charge at least the minimum turnaround (2 ms) after the reset."""
    tb = await CoreTB(dut, cells=("o2_v18", "o2_v15", "co2")).start()
    d = tb.dut
    await tb.write_fields("POLL_CTRL", 2, CMD=0x44, PAYLOAD=0xAA, INTERVAL_MS=1, EN=1)
    # every timing register away from its reset value (the reset sweep
    # must write each back)
    for ch in range(3):
        await tb.write_fields("TIMING0", ch, CHARGE_US=7100 + ch, SYNC_US=1050)
        await tb.write_fields("TIMING1", ch, PREAMBLE_US=2100, EXECUTE_US=4400 + ch)
        await tb.write_fields("TIMING2", ch, LISTEN_US=3100 + ch, TURNAROUND_US=2100)
        assert (await tb.fields("TIMING1", ch)).EXECUTE_US == 4400 + ch
    for i in range(12):
        await tb.push(0x42 + i % 3, ch=i % 2, tag=i)

    async def all_lines_busy():
        phases = [(await tb.fields("STATE", ch)).PHASE for ch in range(3)]
        return all(ph != 0 for ph in phases)
    await tb.wait_until(all_lines_busy, timeout_ms=60)
    lv = await tb.fields("LEVELS")
    assert lv.CMD_LEVEL > 0, lv          # commands still queued

    # the reset: two clocks, between bus accesses
    for m in tb.monitors:
        m.reset_seen()
    await RisingEdge(d.clk)
    d.rst.value = 1
    await RisingEdge(d.clk)              # the first reset edge
    await RisingEdge(d.clk)
    assert all(getattr(d, f"line_oe_{ch}").value == 0 for ch in range(3)), \
        "a line still driven a clock into reset"
    d.rst.value = 0
    await RisingEdge(d.clk)
    t_reset = get_sim_time("us")
    first_oe = []

    async def watch_oe():
        await RisingEdge(d.line_oe_0)
        first_oe.append(get_sim_time("us") - t_reset)
    cocotb.start_soon(watch_oe())

    st = await tb.fields("STATUS")
    assert (st.CMD_EMPTY, st.RES_EMPTY, st.CMD_FULL, st.RES_FULL, st.FLUSHING) == \
        (1, 1, 0, 0, 0), st
    assert await tb.read("BUSY") == 0
    assert await tb.read("LEVELS") == 0
    assert await tb.errors() == 0
    assert await tb.read("POLL_READY") == 0
    for name in ("CTRL", "IRQ_EN"):
        assert await tb.read(name) == regmap.fields_reset(tb.reg(name)), name
    for ch in range(3):
        for name in ("POLL_CTRL", "POLL_RESULT", "TIMING0", "TIMING1", "TIMING2"):
            assert await tb.read(name, ch) == regmap.fields_reset(tb.reg(name, ch)), (name, ch)
        s = await tb.fields("STATE", ch)
        assert s.SLOT_FULL == 0 and s.BUSY == 0 and s.PHASE == 0, (ch, s)
    assert (await tb.fields("RES_INFO")).VALID == 0
    assert not first_oe
    n_txns = [len(tb.txns(ch)) for ch in range(3)]

    # a command pushed at once runs as usual (the execute phase is back at
    # its reset value, 4 ms, which every modelled cell takes), its charge
    # no sooner than 2 ms after the reset
    await tb.push(0x41, ch=0, tag=7)
    assert get_sim_time("us") - t_reset < 1000
    r = await tb.wait_result(0, 7, timeout_ms=40)
    prof = tb.profiles[0]
    assert r.status == OK and r.data == (prof.fw_byte << 8 | prof.type_byte), r
    assert first_oe and first_oe[0] >= 2000.0, f"charge {first_oe} us after reset"
    # and nothing else, ever: no result from before the reset, no
    # transaction on the other lines
    await Timer(30, "ms")                # longer than any transaction
    assert (await tb.fields("RES_INFO")).VALID == 0, "a result from before the reset"
    assert await tb.read("LEVELS") == 0
    assert [len(tb.txns(ch)) for ch in (1, 2)] == n_txns[1:], "a transaction started after reset"
    assert len(tb.txns(0)) == n_txns[0] + 1
    # ... on the reset's lengths, not the ones written before it
    t = tb.txns(0)[-1]
    for got, want in ((t.charge_us, 8000), (t.sync_us, 1000), (t.preamble_us, 2000),
                      (t.execute_us, 4000), (t.listen_us, 3000)):
        assert got is not None and abs(got - want) <= 2, (t, want)
    await tb.finish()


# ============================================================== 10. lean build
@cocotb.test()
async def lean_build(dut):
    """PROG_TIMING = 0 and POLLING = 0 (docs/integration.md, "Lean builds"):
    VERSION says so; TIMING0-2 read the defaults and refuse every write
    (in or out of the window, lab key or not); POLL_CTRL and POLL_RESULT
    read 0, a write switching polling on is refused, one switching it off is
    taken; no poll ever runs; commands run with the default phase lengths."""
    tb = await CoreTB(dut, cells=("o2_v18", "o2_v15", "co2")).start()
    ver = await tb.fields("VERSION")
    assert (ver.FIXED_TIMING, ver.NO_POLLING, ver.LAB_UNLOCKED) == (1, 1, 0), ver
    for ch in range(tb.channels):
        for rname in ("TIMING0", "TIMING1", "TIMING2"):
            assert await tb.read(rname, ch) == regmap.fields_reset(tb.reg(rname, ch)), (rname, ch)
    # in the window, at its edges and outside it: refused alike
    for ch in range(tb.channels):
        for us in ({"charge": 9000}, {"sync": 1100}, {"preamble": 1800, "execute": 4500},
                   {"listen": 2500}, {"turnaround": 100}):
            await tb.set_timing(ch, expect_refused=True, **us)
            assert await tb.errors() == tb.pack("ERRORS", VALUE_REFUSED=1), (ch, us)
            await tb.clear_errors()
    # the lab key has nothing to unlock
    await tb.write("LAB_KEY", LAB_KEY)
    assert await tb.field("VERSION", "LAB_UNLOCKED") == 0
    await tb.set_timing(0, expect_refused=True, sync=600)
    await tb.write("LAB_KEY", 0)
    await tb.clear_errors()

    # ---- no poller: reads 0, switching on is refused, off is taken
    for ch in range(tb.channels):
        assert await tb.read("POLL_CTRL", ch) == 0
        assert await tb.read("POLL_RESULT", ch) == 0
    await tb.write_fields("POLL_CTRL", 0, CMD=0x44, PAYLOAD=0xAA, INTERVAL_MS=1, EN=1)
    assert await tb.read("POLL_CTRL", 0) == 0
    assert await tb.errors() == tb.pack("ERRORS", VALUE_REFUSED=1)
    await tb.clear_errors()
    await tb.write_fields("POLL_CTRL", 0, CMD=0x44, PAYLOAD=0xAA, INTERVAL_MS=1, EN=0)
    assert await tb.errors() == 0
    assert await tb.read("POLL_CTRL", 0) == 0
    await Timer(3, "ms")                      # three poll intervals, had it been on
    assert all(len(tb.txns(ch)) == 0 for ch in range(tb.channels))
    assert await tb.read("POLL_READY") == 0

    # ---- commands run, with the fixed (default) phase lengths: one a
    # channel, all at once (the channels run concurrently)
    for ch in range(tb.channels):
        await tb.push(0x41, ch=ch, tag=ch + 1)
    got_res = {(r.channel, r.tag): r for r in await tb.wait_results(tb.channels)}
    for ch in range(tb.channels):
        tb.monitors[ch].check()
        prof = tb.profiles[ch]
        assert (ch, ch + 1) in got_res, (ch, got_res)
        r = got_res[(ch, ch + 1)]
        assert r.cmd == 0x41 and r.status == OK and r.data == prof.fw_byte << 8 | prof.type_byte, r
        tx = tb.txns(ch)[-1]
        got = (round(tx.charge_us), round(tx.sync_us), round(tx.preamble_us),
               round(tx.execute_us), round(tx.listen_us))
        want = tuple(DEFAULT_TIMING[k] for k in ("charge", "sync", "preamble", "execute", "listen"))
        assert got == want, (ch, got, want)
    assert all(len(tb.txns(ch)) == 1 for ch in range(tb.channels))
    await tb.finish()


# ============================================================== 11. more than four channels
@cocotb.test()
async def six_channels(dut):
    """Six channels, two beyond the four whose timing words fit 16 deep
    (twh_timing's memories are 32 words above four channels): every
    channel's TIMING0-2 keep their own values (channel 4's words are not
    channel 0's), six engines run at once with their own phase lengths,
    three modelled cells answer and three empty lines give NO_RESPONSE."""
    cells = ("o2_v18", None, None, None, "co2", "o2_v15")
    tb = await CoreTB(dut, cells=cells).start()
    assert tb.channels == 6
    timing = {0: dict(execute=6000), 1: dict(execute=4100, listen=2500),
              2: dict(execute=4200, charge=9000), 3: dict(execute=4300),
              4: dict(execute=3500, charge=9000, listen=2500), 5: dict(execute=4500)}
    for ch, us in timing.items():
        await tb.set_timing(ch, **us)
    # read back after every write: no channel's write reached another's word
    for ch in range(tb.channels):
        want = dict(DEFAULT_TIMING, **timing[ch])
        got = {ph: await tb.field(reg, f, ch) for ph, (reg, f) in TIMING_FIELDS.items()}
        assert got == want, (ch, got, want)
    pushed = []
    for ch in range(tb.channels):
        await tb.push(0x41, ch=ch, tag=ch + 1)
        pushed.append((ch, ch + 1, 0x41))
    await tb.wait_until(lambda: _running(tb, range(tb.channels)), timeout_ms=10)
    assert await tb.read("BUSY") == 0b111111

    results = await tb.wait_results(6, timeout_ms=TXN_US // 1000 + 20)
    check_order(results, pushed)
    for r in results:
        prof = tb.profiles[r.channel]
        if prof is None:
            assert r.status == NO_RESPONSE, r
        else:
            assert r.status == OK and r.data == prof.fw_byte << 8 | prof.type_byte, r
    for ch in range(tb.channels):
        txs = tb.txns(ch)
        assert [bytes(t.frame) for t in txs] == [frame(0x41)], (ch, txs)
        want = dict(DEFAULT_TIMING, **timing[ch])
        t = txs[0]
        got = {ph: round(getattr(t, f"{ph}_us")) for ph in ("charge", "execute", "listen")}
        assert got == {ph: want[ph] for ph in got}, (ch, got)
    # all six ran at once
    firsts = [tb.txns(ch)[0] for ch in range(tb.channels)]
    assert max(t.start_ps for t in firsts) < min(txn_end_ps(t) for t in firsts)
    assert await tb.errors() == 0          # NO_RESPONSE is no link error
    await tb.finish()


# ============================================================== 12. a rig's worth of cells
MANY_CELLS = ("o2_v18", "o2_v15", "co2", None)      # every fourth line empty


@cocotb.test()
async def many_channels(dut):
    """16 or 32 channels (register map version 2; tb_core_many.v): every
    cell is asked its identity (0x41) at once through its own channel's
    CMD_PUSH, with the tag of its channel; every line runs concurrently, each
    result comes back with its channel (5 bits) and tag and its own cell's
    answer, an empty line gives NO_RESPONSE; the last channel polls (0x44)
    beside its command and sets its POLL_READY bit; BUSY shows every channel
    at once; IDLE_CHARGE of the last channel drives that line alone; a push
    beyond the build's channels is refused with BAD_CHANNEL."""
    n = int(os.environ["TWH_CHANNELS"])
    cells = tuple(MANY_CELLS[c % len(MANY_CELLS)] for c in range(n))
    tb = await CoreTB(dut, cells=cells).start()
    assert tb.channels == n and tb.many
    last = n - 1
    assert await tb.field("VERSION", "CHANNELS") == n
    assert await tb.field("VERSION", "MAJOR") == 2
    await tb.write_fields("POLL_CTRL", last, CMD=0x44, PAYLOAD=0xAA, INTERVAL_MS=1, EN=1)
    pushed = []
    for ch in range(n):
        await tb.push(0x41, ch=ch, tag=ch % 32)
        pushed.append((ch, ch % 32, 0x41))
    await tb.wait_until(lambda: _running(tb, range(n)), timeout_ms=10)
    assert await tb.read("BUSY") == (1 << n) - 1
    if n < 32:
        assert not await tb.push(0x41, ch=n, expect_err=True)
        assert await tb.errors() == tb.pack("ERRORS", BAD_CHANNEL=1)
        await tb.clear_errors()

    results = await tb.wait_results(n, timeout_ms=TXN_US // 1000 + 30)
    check_order(results, pushed)
    for r in results:
        prof = tb.profiles[r.channel]
        assert r.tag == r.channel % 32, r
        if prof is None:
            assert r.status == NO_RESPONSE, r
        else:
            assert r.status == OK and r.data == prof.fw_byte << 8 | prof.type_byte, r
    # every line ran at once
    firsts = [tb.txns(ch)[0] for ch in range(n)]
    assert max(t.start_ps for t in firsts) < min(txn_end_ps(t) for t in firsts)
    # the last channel's poll ran beside its command, and only there
    await tb.wait_until(lambda: _polls(tb, last, 1), timeout_ms=TXN_US // 1000 + 10)
    assert await tb.read("POLL_READY") == 1 << last
    await tb.write_fields("POLL_CTRL", last, CMD=0x44, PAYLOAD=0xAA, INTERVAL_MS=1, EN=0)
    await tb.write("POLL_READY", 0xFFFFFFFF)
    await tb.wait_idle(timeout_ms=TXN_US // 1000 + 10)
    assert all(len(tb.txns(ch)) == 1 for ch in range(last))
    # idle charge on the last line alone
    await tb.write("IDLE_CHARGE", 1 << last)
    assert await tb.read("IDLE_CHARGE") == 1 << last
    await Timer(100, "us")
    assert [int(p.line_oe.value) for p in tb.pins] == [0] * last + [1]
    await tb.write("IDLE_CHARGE", 0)
    await Timer(20, "us")
    assert await tb.errors() == 0          # NO_RESPONSE is no link error
    await tb.finish()


# ============================================================== pytest
import simrun  # noqa: E402

CORE_SOURCES = ["tb_core.v"]


def run_core(testcase, bus, clk_hz=12_000_000, channels=3, fifo_depth=16, env=None,
             features=None, sim="icarus", name=None, seed_name=None, design=None, defines=None):
    """design, defines: simrun.run's (tb/test_netlist.py)"""
    name = name or core_name(testcase, bus, channels)
    extra = {"TWH_BUS": str(bus), "TWH_CHANNELS": str(channels),
             "TWH_FIFO_DEPTH": str(fifo_depth), "TWH_CLK_HZ": str(clk_hz),
             "TWH_PROG_TIMING": str((features or {}).get("PROG_TIMING", 1)),
             "TWH_POLLING": str((features or {}).get("POLLING", 1))}
    extra.update(env or {})
    simrun.run("tb_core", "test_twh_core", name,
               parameters={"CLK_HZ": clk_hz, "CHANNELS": channels,
                           "FIFO_DEPTH": fifo_depth, "BUS": bus, **(features or {})},
               testcase=testcase, tb_sources=CORE_SOURCES, extra_env=extra, sim=sim,
               seed_name=seed_name, design=design, defines=defines)


def core_name(testcase, bus, channels):
    return f"core_{testcase}_{'wb' if bus == 0 else 'axil'}_{channels}ch"


# (testcase, bus, clk_hz, channels, fifo_depth)
CASES = [
    ("regmap_access", 0, 12_000_000, 3, 16),
    ("regmap_access", 1, 4_000_000, 3, 16),
    ("regmap_access", 0, 4_000_000, 1, 4),
    ("three_channels", 0, 4_000_000, 3, 16),
    ("fifo_edges", 0, 4_000_000, 3, 16),
    ("fifo_edges", 1, 4_000_000, 3, 4),
    ("factory_protection", 0, 4_000_000, 3, 16),
    ("timing_registers", 0, 4_000_000, 3, 16),
    ("polling", 0, 4_000_000, 3, 16),
    ("random_traffic", 0, 12_000_000, 3, 16),
    ("random_traffic", 1, 4_000_000, 3, 8),
    ("irq_and_flush", 1, 4_000_000, 3, 16),
    ("reset_mid_traffic", 0, 4_000_000, 3, 16),
    ("reset_mid_traffic", 1, 4_000_000, 3, 16),
    ("lean_build", 1, 4_000_000, 3, 16),      # with LEAN's parameters
    ("lean_build", 0, 4_000_000, 1, 16),      # ... one channel (the engine's HOLD_Q)
    ("six_channels", 0, 6_000_000, 6, 16),   # the engine's floor for six channels
]
# the feature parameters of a fixed-timing board without polling
LEAN = {"PROG_TIMING": 0, "POLLING": 0}
# The configuration most cases (and test_random's quick run) share runs on
# Verilator in make test, one build for all (tb/simrun.py), each case four
# to six times faster than on Icarus; make test-slow runs each of them on
# Icarus too, with the same seed, and requires the same transcript
# (CoreTB.write_transcript). The other configurations serve one to three
# cases each, which on Icarus cost no more than a Verilator build.
VERILATOR_CONFIG = (0, 4_000_000, 3, 16)     # bus, clk_hz, channels, fifo_depth


def _on_verilator(c):
    return (c[1], c[2], c[3], c[4]) == VERILATOR_CONFIG


def _id(c):
    return f"{c[0]}-{'wb' if c[1] == 0 else 'axil'}-{c[3]}ch-{c[2] // 1_000_000}MHz-d{c[4]}"


def _case(testcase, bus, clk_hz, channels, fifo_depth, sim="icarus", name=None, seed_name=None):
    env = {"TWH_RANDOM_ACCESSES": "1000"} if (testcase == "random_traffic" and bus == 1) else None
    run_core(testcase, bus, clk_hz=clk_hz, channels=channels, fifo_depth=fifo_depth, env=env,
             features=LEAN if testcase == "lean_build" else None, sim=sim, name=name,
             seed_name=seed_name)


@pytest.mark.parametrize("testcase,bus,clk_hz,channels,fifo_depth", CASES, ids=[_id(c) for c in CASES])
def test_core(testcase, bus, clk_hz, channels, fifo_depth):
    c = (testcase, bus, clk_hz, channels, fifo_depth)
    if _on_verilator(c):    # with the seed its Icarus twin will take
        _case(*c, sim="verilator", seed_name=core_name(testcase, bus, channels))
    else:
        _case(*c)


BOTH = [c for c in CASES if _on_verilator(c)]


@pytest.mark.slow
@pytest.mark.parametrize("testcase,bus,clk_hz,channels,fifo_depth", BOTH, ids=[_id(c) for c in BOTH])
def test_core_both(testcase, bus, clk_hz, channels, fifo_depth):
    c = (testcase, bus, clk_hz, channels, fifo_depth)
    simrun.same_on_both(lambda sim, name, seed_name: _case(*c, sim=sim, name=name,
                                                           seed_name=seed_name),
                        core_name(testcase, bus, channels))


# A rig's worth of cells on the register map's 32 channels (tb_core_many.v):
# 16 channels at 16 MHz and 32 at 32 MHz, each on Verilator at its channel
# count's clock floor, in make test-slow (CI): the 16-channel build and run,
# about 40 s of one core, had held make test at its 300 s limit.
def _many(channels, clk_hz):
    simrun.run("tb_core_many", "test_twh_core", f"core_many_channels_wb_{channels}ch",
               parameters={"CLK_HZ": clk_hz, "CHANNELS": channels, "FIFO_DEPTH": 64},
               testcase="many_channels", tb_sources=["tb_engine.v", "tb_core_many.v"],
               extra_env={"TWH_BUS": "0", "TWH_CHANNELS": str(channels),
                          "TWH_FIFO_DEPTH": "64", "TWH_CLK_HZ": str(clk_hz)},
               sim="verilator")


@pytest.mark.slow
def test_core_16ch():
    _many(16, 16_000_000)


@pytest.mark.slow
def test_core_32ch():
    _many(32, 32_000_000)
