"""The iCEBreaker board top (boards/icebreaker/twh_icebreaker.v, 3 channels,
12 MHz) simulated end to end: a PC (cocotbext-uart) on its serial port, the
peripheral model and the spec monitor on each 2-wire line (tb/boardtb.py).

- bridge_protocol (115200 baud, the board's build): register reads and
  writes, the ID magic, bus errors (from the core, at the top of the bridge's 1 KiB
  window, which must not alias), the irq bit, damaged requests, garbage,
  the silence timeout and the break that resynchronise the parser, a glitch
  on the idle line, a one-sample glitch inside each bit (majority vote),
  bytes arriving during an answer, the reset button and the LEDs.
- cli_quick (1 Mbaud, a simulation-only build so that the serial traffic
  does not add to the ~90 ms of 2-wire time): the C tool sw/tools/twh_cli
  as a subprocess on a pty bridged to the UART, -q page of every channel
  (firmware, negotiated execute phase, raw readings, supply voltage),
  compared with the modelled cells and with what the models saw on the line.
  On Verilator (a build of its own, 34 s with it against 101 s on Icarus);
  bridge_protocol keeps the board top on Icarus.
- cli_full_page (opt-in, `make board-sim-full`, long: the tool reads the
  first word of every calibration pair): the whole sensor page (identity,
  dates, calibration, converted readings) at 115200 baud with three cells,
  one of them with records behind blank pairs, compared with values derived
  from the device profiles by the Python flash-map and conversion helpers.
  The page logic itself is unit-tested fast in sw/test/test_page.c.
"""
import dataclasses
import os
import re
import subprocess

import cocotb
import pytest
from cocotb.triggers import Timer

import profiles
from sensor_page import expected_page, fw_line, pages
import protocol as p
import simrun
from boardtb import (OP_STATUS, ST_MARK, TIMEOUT_BITS, BoardTB, PtyLink, read_frame,
                     write_frame)

ID_MAGIC = 0x54574831
CLI = simrun.ROOT / "sw" / "build" / "tools" / "twh_cli"


# ============================================================== bridge
async def bitbang(tb, data: bytes, glitch_bit=None, glitch_ns=600):
    """Drives the board's receive pin bit by bit (the UartSource idle). With
    glitch_bit, that data bit of every byte gets an inverted pulse of
    glitch_ns centred on the receiver's middle sample."""
    pin = tb.dut.uart_rx
    bit = tb.bit_ns
    for byte in data:
        bits = [0] + [(byte >> k) & 1 for k in range(8)] + [1]
        for i, level in enumerate(bits):
            pin.value = level
            if glitch_bit is not None and i == 1 + glitch_bit:
                # the middle sample is taken DIV/2 clocks after the start
                # edge is seen, about three clocks (synchroniser, edge
                # detect) after the edge itself; the other two samples are
                # DIV/8 = 13 clocks (1.08 us) either side, out of reach
                centre = bit / 2 + 3 * 1e9 / 12e6
                await Timer(round(centre - glitch_ns / 2), "ns")
                pin.value = 1 - level
                await Timer(glitch_ns, "ns")
                pin.value = level
                await Timer(round(bit - centre - glitch_ns / 2), "ns")
            else:
                await Timer(round(bit), "ns")
    pin.value = 1


@cocotb.test()
async def bridge_protocol(dut):
    tb = await BoardTB(dut).start()
    d = dut
    assert int(d.led_red_n.value) == 1, "fault LED lit before any fault"

    # -- reads: ID magic, build parameters; a clean status byte
    a = await tb.read_word(0)
    assert (a.status, a.data) == (ST_MARK, ID_MAGIC), (hex(a.status), hex(a.data))
    ver = await tb.read("VERSION")
    assert tb.field("VERSION", ver, "CHANNELS") == 3
    params = await tb.read("PARAMS")
    assert tb.field("PARAMS", params, "CLK_KHZ") == 12000
    assert tb.field("PARAMS", params, "FIFO_DEPTH") == 16
    assert int(d.led_green_n.value) == 0 and int(d.led_brk.value) & 0b01000, \
        "running LED off, or UART LED not lit after requests"

    # -- writes read back; every byte of the data lands in its place
    t0_reg = tb.rm["CH[1].TIMING0"]
    t0 = t0_reg.field("CHARGE_US").put(0, 9000) | t0_reg.field("SYNC_US").put(0, 1100)
    assert not (await tb.write("TIMING0", t0, ch=1)).bus_err
    assert await tb.read("TIMING0", ch=1) == t0
    irq_en = tb.rm["IRQ_EN"].field("ERROR").put(0, 1) | \
        tb.rm["IRQ_EN"].field("RES_THRESHOLD").put(0, 5)
    await tb.write("IRQ_EN", irq_en)
    assert await tb.read("IRQ_EN") == irq_en

    # -- a damaged request is not carried out: FRAME_ERR, the answer keeps
    # its length, the register keeps its value
    bad = bytearray(write_frame(tb.addr("TIMING0", 1) >> 2, 0x12345678))
    bad[-1] ^= 0x01
    a = await tb.request(bytes(bad), 1)
    assert a.frame_err and not a.bus_err, hex(a.status)
    assert await tb.read("TIMING0", ch=1) == t0
    bad = bytearray(read_frame(0))
    bad[-1] ^= 0x80
    a = await tb.request(bytes(bad), 5)
    assert a.frame_err and a.data == 0, (hex(a.status), hex(a.data))
    assert int(d.led_red_n.value) == 0, "fault LED not lit after a damaged request"

    # -- bus errors: an unmapped register; the top of the bridge's 1 KiB
    # window (A = 0xFF, an absent channel's unused word), which must not
    # alias onto the core (ID); version 1's CMD_PUSH address (0x28), which
    # must not push a command
    a = await tb.read_word(0x44 >> 2)
    assert a.bus_err and a.data == 0, (hex(a.status), hex(a.data))
    a = await tb.read_word(0xFF)
    assert a.bus_err and a.data == 0, (hex(a.status), hex(a.data))
    ctrl = tb.rm["CTRL"]
    await tb.write("CTRL", ctrl.field("ENABLE").put(ctrl.reset, 0))   # a push would stay queued
    push = tb.rm["CH[0].CMD_PUSH"].field("CMD").put(0, 0x41) | \
        tb.rm["CH[0].CMD_PUSH"].field("PAYLOAD").put(0, 0xAA)
    a = await tb.write_word(0x28 >> 2, push)
    assert a.bus_err, hex(a.status)
    assert tb.field("LEVELS", await tb.read("LEVELS"), "CMD_LEVEL") == 0
    assert await tb.read("ERRORS") == 0
    await tb.write("CTRL", ctrl.reset)

    # -- a bus error from the core, and the irq line in the status byte
    a = await tb.write_word(tb.rm["CH[5].CMD_PUSH"].address >> 2, push)
    assert a.bus_err, hex(a.status)
    assert tb.field("ERRORS", await tb.read("ERRORS"), "BAD_CHANNEL") == 1
    a = await tb.status()
    assert a.irq and not a.bus_err, hex(a.status)
    assert int(d.led_brk.value) & 0b10000, "IRQ LED off while irq is high"
    await tb.write("ERRORS", tb.rm["ERRORS"].woclr_mask)
    a = await tb.status()
    assert a.status == ST_MARK, hex(a.status)
    assert not int(d.led_brk.value) & 0b10000

    # -- garbage outside a request: no answer, reported once by DROPPED
    await tb.send(bytes([0x00, 0xFF, 0x41, 0x99, 0xA5]))
    await tb.source.wait()
    assert await tb.quiet(tb.char_us(4)) == b"", "the bridge answered garbage"
    assert (await tb.status()).dropped
    assert not (await tb.status()).dropped, "DROPPED not cleared by the answer that reported it"

    # -- a request may pause for less than the timeout
    await tb.send(bytes([0x52]))
    await tb.source.wait()
    await Timer(round(TIMEOUT_BITS // 2 * tb.bit_ns), "ns")
    await tb.send(read_frame(0)[1:])
    await tb.source.wait()
    raw = await tb.recv(5)
    assert raw[0] == ST_MARK and int.from_bytes(raw[1:], "little") == ID_MAGIC, raw.hex()

    # -- a half request is dropped after TIMEOUT_BITS bit times of silence
    await tb.send(write_frame(tb.addr("TIMING0", 1) >> 2, 0x0BB80FA0)[:4])
    await tb.source.wait()
    assert await tb.quiet((TIMEOUT_BITS + 64) * tb.bit_ns / 1000) == b""
    a = await tb.read_word(tb.addr("TIMING0", 1) >> 2)
    assert a.dropped and a.data == t0, (hex(a.status), hex(a.data))

    # -- a break drops a half request at once
    await tb.send(write_frame(tb.addr("TIMING0", 1) >> 2, 0x0BB80FA0)[:3])
    await tb.source.wait()
    d.uart_rx.value = 0
    await Timer(round(30 * tb.bit_ns), "ns")
    d.uart_rx.value = 1
    await Timer(round(2 * tb.bit_ns), "ns")
    a = await tb.read_word(tb.addr("TIMING0", 1) >> 2)
    assert a.dropped and a.data == t0, (hex(a.status), hex(a.data))

    # -- a glitch on the idle line is not a start bit
    d.uart_rx.value = 0
    await Timer(round(tb.bit_ns / 4), "ns")
    d.uart_rx.value = 1
    assert await tb.quiet(tb.char_us(2)) == b""
    assert (await tb.status()).status == ST_MARK

    # -- majority vote: one disturbed sample in a bit of every byte
    for glitch_bit in (0, 4, 7):
        await bitbang(tb, read_frame(0), glitch_bit=glitch_bit)
        raw = await tb.recv(5)
        assert raw[0] == ST_MARK and int.from_bytes(raw[1:], "little") == ID_MAGIC, \
            (glitch_bit, raw.hex())

    # -- bytes sent while the bridge answers are dropped, and reported
    await tb.send(read_frame(0) + bytes([OP_STATUS]))
    raw = await tb.recv(5)
    assert int.from_bytes(raw[1:], "little") == ID_MAGIC, raw.hex()
    assert await tb.quiet(tb.char_us(4)) == b""
    assert (await tb.status()).dropped

    # -- the reset button: the core's registers and the bridge start over
    await tb.send(write_frame(tb.addr("IRQ_EN") >> 2, 0)[:2])    # a half request
    await tb.source.wait()
    d.btn_n.value = 0
    await Timer(2, "us")
    assert int(d.led_green_n.value) == 1, "running LED lit during reset"
    d.btn_n.value = 1
    await tb.wait_running()
    assert await tb.read("IRQ_EN") == tb.rm["IRQ_EN"].reset
    assert await tb.read("TIMING0", ch=1) == tb.rm["CH[1].TIMING0"].reset
    assert (await tb.status()).status == ST_MARK
    await tb.finish()


# ============================================================== the C tool
async def run_cli(dut, cells, quick, max_sim_ms):
    tb = await BoardTB(dut, cells=cells).start()
    link = PtyLink(tb).start()
    lit = set()

    async def watch_leds():
        trigger = dut.led_brk.value_change
        while True:
            await trigger
            v = int(dut.led_brk.value)
            lit.update(k for k in range(5) if v >> k & 1)
    watcher = cocotb.start_soon(watch_leds())
    argv = [str(CLI), "-p", link.path, "-b", str(tb.baud), "-t", "600000"] + (["-q"] if quick else [])
    out_path = simrun.ROOT / "build" / "sim" / f"board_cli_{'quick' if quick else 'full'}.txt"
    res = await link.run_process(argv, out_path, max_sim_ms)
    watcher.cancel()
    link.close()
    dut._log.info("twh_cli output:\n%s", res.stdout)
    assert res.returncode == 0, f"twh_cli exit {res.returncode}:\n{res.stdout}"
    return tb, res.stdout, lit, link


async def check_cli(tb, text, quick, lit):
    ver = await tb.read("VERSION")      # the bridge is still in step afterwards
    head = (f"core: 3 channels, FIFO depth 16, 12000 kHz, version "
            f"{tb.field('VERSION', ver, 'MAJOR')}.{tb.field('VERSION', ver, 'MINOR')}")
    assert text.splitlines()[0].startswith(head), text
    got = pages(text)
    assert sorted(got) == [0, 1, 2], text
    for ch, prof in enumerate(tb.profiles):
        if prof is None:
            assert got[ch] == [f"== channel {ch}: no sensor (no answer to the firmware command)"], got[ch]
            continue
        assert got[ch] == expected_page(ch, prof, quick), \
            "\n".join(["got:"] + got[ch] + ["expected:"] + expected_page(ch, prof, quick))
        _, execute = fw_line(ch, prof)
        assert tb.field("TIMING1", await tb.read("TIMING1", ch=ch), "EXECUTE_US", ch=ch) == execute
    # what the cells received on their lines: the firmware command first,
    # then the page's commands, each answered
    for ch, m in enumerate(tb.models):
        if m is None:
            continue
        cmds = [r.frame[0] for r in m.log]
        assert cmds[0] == 0x41 and all(r.reason == "answered" for r in m.log), \
            [(hex(r.frame[0]), r.reason) for r in m.log]
        if quick:
            assert cmds == [0x41, 0x42, 0x43, 0x44], [hex(c) for c in cmds]
    assert lit >= {0, 1, 2, 3, 4}, f"LEDs seen lit: {sorted(lit)}"
    await tb.finish()


@cocotb.test()
async def cli_quick(dut):
    tb, text, lit, link = await run_cli(dut, ("o2_v18", "co2", None), quick=True, max_sim_ms=400)
    assert link.to_board > 0 and link.from_board > 0
    await check_cli(tb, text, True, lit)


def o2_v15_gaps():
    """The v15 cell with its calibration area as use leaves it: a record
    half-written (power lost between its words), blank pairs, and the newest
    record beyond them in the area's last pair. A tool that reads up to the
    first blank word shows a stale gain."""
    img = list(profiles.O2_V15.flash)
    img[0x23] = fm.BLANK                        # 0x22 lost its second word
    img[0x24] = img[0x25] = fm.BLANK            # 0x24 erased with its page
    img[0x30], img[0x31] = 2160 // fm.O2_CAL_UNIT_HOURS, 3705
    img[0x7E], img[0x7F] = 2163 // fm.O2_CAL_UNIT_HOURS, 3711
    prof = dataclasses.replace(profiles.O2_V15, name="o2_v15_gaps", flash=tuple(img))
    cur = fm.current_calibration(prof.flash)
    assert (cur.addr, cur.value, fm.calibration_count(prof.flash)) == (0x7E, 3711, 3)
    return prof


@cocotb.test()
async def cli_full_page(dut):
    gaps = o2_v15_gaps()
    profiles.PROFILES[gaps.name] = gaps
    tb, text, lit, _ = await run_cli(dut, ("o2_v18", gaps.name, "co2"), quick=False,
                                     max_sim_ms=8000)
    await check_cli(tb, text, False, lit)


# ============================================================== pytest
@pytest.fixture(scope="session")
def twh_cli():
    subprocess.run(["make", "-s", "-C", str(simrun.ROOT / "sw" / "tools")], check=True)
    return CLI


def _run(testcase, baud, sim="icarus"):
    simrun.run("tb_board", "test_board_top", f"board_{testcase}",
               parameters={"CHANNELS": 3, "BAUD": baud}, testcase=testcase,
               tb_sources=["tb_board.v", *simrun.board_sources("icebreaker")],
               extra_env={"TWH_CHANNELS": "3", "TWH_BAUD": str(baud)}, sim=sim)


def test_bridge_protocol():
    _run("bridge_protocol", 115200)


@pytest.mark.slow
def test_cli_quick(twh_cli):
    _run("cli_quick", 1_000_000, sim="verilator")


@pytest.mark.skipif(not os.environ.get("TWH_BOARD_FULL"),
                    reason="several minutes of simulation: make board-sim-full")
def test_cli_full_page(twh_cli):
    _run("cli_full_page", 115200)
