"""Co-simulation: the C driver (sw/, built as libtwh.so) drives the Wishbone
core with three modelled cells, through ctypes and cocotb's bridge/resume
(tb/cosim.py). Every transaction is watched by the spec monitors.

driver_session is also run, step for step, by the soak harness's C++
cells on its own Verilated core (`make cosim-session`, part of make test:
a second, not a minute); here, in make test-slow, both runs must leave the
same transcript of frames handled by the same cells (soc/cells.py): the
Python cell models and the C++ ones, cocotb's bridge and the harness's
direct calls. Both cases run on cocotb's Verilator: on Icarus, with the
time-shared engine stepping a channel in most clocks, they took about 290
and 250 s (Icarus against Verilator is held by tb/test_twh_core.py's
test_core_both)."""
import ctypes as C
import dataclasses
import subprocess
import sys
from pathlib import Path

import cocotb
import pytest
from cocotb.triggers import Timer

import profiles
import simrun
import twh_ctypes as T
from coretb import CoreTB
from cosim import Cosim

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "soc"))
import cells  # noqa: E402

# the cells of the session: the demo's and the LiteX SoC's (O2 v18, O2 v15,
# CO2, with the shared vectors' flash images), as the Verilated run has them
SESSION_CELLS = tuple(name for name, _, _ in cells.cells())
TRANSCRIPT = "session_cocotb.txt"


def transcript_lines(models, marks):
    """One line per frame a cell handled, before marks[ch]; the format of
    the soak harness's --transcript (sim/soak/soak_main.cpp)."""
    out = []
    for ch, (model, mark) in enumerate(zip(models, marks)):
        for rec in model.logic.log[:mark]:
            answer = "none" if rec.response is None else f"{rec.response[0]:02X} {rec.response[1]:02X}"
            out.append(f"ch{ch} " + " ".join(f"{b:02X}" for b in rec.frame) + f" -> {answer}")
    return out

E = T.ERR


async def start(dut, cells):
    tb = await CoreTB(dut, cells=cells).start()
    cs = Cosim(tb)
    assert await cs.init() == 0
    assert cs.t.channels == 3
    return tb, cs


@cocotb.test()
async def driver_session(dut):
    """Negotiation per firmware, every read helper, write with verify, the
    driver's own refusal to touch the factory area, an image read, and
    submit / cancel / collect; then the transcript of frames for the
    comparison with the Verilated run."""
    cells.register()                # in the simulator: the bench takes cells by name
    tb, cs = await start(dut, SESSION_CELLS)
    expect_exec = {0: 6000, 1: 4000, 2: 6000}          # v18, v15, CO2 fw 0x12
    for ch in range(3):
        prof = tb.profiles[ch]
        rc, fw = await cs.negotiate(ch)
        assert rc == 0 and fw.raw == prof.fw_byte and fw.type == prof.type_byte, (ch, rc)
        assert await tb.field("TIMING1", "EXECUTE_US", ch) == expect_exec[ch], ch
        bits, words = C.c_uint8(), C.c_uint16()
        assert await cs.call("twh_config", C.byref(cs.t), ch, C.byref(bits), C.byref(words)) == 0
        assert words.value == prof.flash_size, (ch, words.value)
    assert await cs.get16("twh_o2_voltage", 0) == (0, tb.profiles[0].adc_o2)
    assert await cs.get16("twh_temperature", 1) == (0, tb.profiles[1].adc_temperature)
    assert await cs.get16("twh_ref_voltage", 2) == (0, tb.profiles[2].adc_ref_voltage)
    assert await cs.get16("twh_read_word", 0, 0x10) == (0, tb.profiles[0].flash[0x10])
    # write with verify on a blank word of the v18 cell
    model = tb.models[0]
    free = next(a for a in range(0x20, 0xE0) if model.flash[a] == 0x3FFF)
    assert await cs.call("twh_write_word", C.byref(cs.t), 0, free, 0x0ACE) == 0
    assert model.flash[free] == 0x0ACE
    # a second write to the same (now programmed) word fails its verify
    assert await cs.call("twh_write_word", C.byref(cs.t), 0, free, 0x0123) == E["VERIFY"]
    # the factory area is refused before anything reaches the bus
    before = (cs.accesses, len(model.log))
    assert await cs.call("twh_write_word", C.byref(cs.t), 0, 0x05, 0x0001) == E["BAD_ARG"]
    assert await cs.call("twh_erase_page", C.byref(cs.t), 0, 0x10) == E["BAD_ARG"]
    assert (cs.accesses, len(model.log)) == before
    # a whole-image read
    img = (C.c_uint16 * 4)()
    assert await cs.call("twh_read_image", C.byref(cs.t), 1, img, 4) == 0
    assert list(img) == list(tb.profiles[1].flash[:4])
    # which frames a cancel catches depends on the bus's timing: the
    # transcript ends here
    marks = [len(m.logic.log) for m in tb.models]
    # non-blocking: queue three, cancel what has not started, collect all
    tags = [await cs.call("twh_submit", C.byref(cs.t), 2, 0x41, 0xAA) for _ in range(3)]
    assert all(tag >= 0 for tag in tags), tags
    assert await cs.call("twh_cancel_all", C.byref(cs.t)) == 0
    got, res = {}, T.Result()
    while len(got) < 3:
        rc = await cs.call("twh_result", C.byref(cs.t), C.byref(res))
        if rc == E["AGAIN"]:
            await Timer(1, "ms")
            continue
        assert rc == 0 and res.channel == 2
        got[res.tag] = res.status
    cancelled = [tag for tag in tags if got[tag] == 8]
    assert len(cancelled) >= 2 and all(got[tag] in (0, 8) for tag in tags), got
    assert cs.irq_waits > 0, "the driver never waited on the interrupt"
    await tb.finish()
    Path(TRANSCRIPT).write_text("\n".join(transcript_lines(tb.models, marks)) + "\n")


@cocotb.test()
async def driver_errors(dut):
    """No response, a timeout whose late result is still delivered, and a
    calibration append into a full area (oldest page erased first)."""
    # channel 0: an O2 cell with a 64-word flash, so a full calibration area
    # is 16 records (the driver reads every record's stamp to find the oldest)
    small = dataclasses.replace(profiles.O2_V18, name="o2_v18_64w",
                                flash=profiles.O2_V18.flash[:64])
    profiles.PROFILES[small.name] = small
    tb, cs = await start(dut, (small.name, "o2_v15", None))
    # channel 2 has no sensor: a read gets no response
    assert (await cs.get16("twh_read_word", 2, 0x00))[0] == E["NO_RESPONSE"]
    # a timeout shorter than a transaction; the result arrives later, intact
    cs.t.timeout_us = 5000
    assert (await cs.get16("twh_o2_voltage", 1))[0] == E["TIMEOUT"]
    cs.t.timeout_us = 200_000
    await Timer(30, "ms")
    res = T.Result()
    assert await cs.call("twh_result", C.byref(cs.t), C.byref(res)) == 0
    assert (res.cmd, res.channel, res.status, res.data) == \
        (0x44, 1, 0, tb.profiles[1].adc_o2)
    # fill the calibration area (0x20-0x3F): page 0x30 holds the oldest
    # records, page 0x20 the newest
    flash = tb.models[0].flash
    for a in range(0x20, 0x40, 2):
        flash[a] = 100 + a if a < 0x30 else a - 0x30 + 1
        flash[a + 1] = 3600
    addr = C.c_uint16()
    rc = await cs.call("twh_cal_append", C.byref(cs.t), 0, 500, 3700, C.byref(addr))
    assert rc == 0, T.ERRORS.get(rc, rc)
    assert addr.value == 0x30, hex(addr.value)
    assert flash[0x30:0x32] == [500, 3700]
    assert all(w == 0x3FFF for w in flash[0x32:0x40])          # rest of the erased page
    assert flash[0x20:0x22] == [100 + 0x20, 3600]              # the other page untouched
    await tb.finish()


@pytest.fixture(scope="session")
def libtwh():
    subprocess.run(["make", "-s", "-C", str(simrun.ROOT / "sw"), "shared"], check=True)
    return T.LIB_PATH


# Both carry the marker slow (make test-slow, in CI): driver_session (make
# test runs it in the soak harness, and here the two must agree) and
# driver_errors, every error path through the driver.
@pytest.mark.slow
@pytest.mark.parametrize("testcase", ["driver_session", "driver_errors"])
def test_cosim(libtwh, testcase):
    simrun.run("tb_core", "test_cosim", f"cosim_{testcase}",
               parameters={"CLK_HZ": 4_000_000, "CHANNELS": 3, "FIFO_DEPTH": 16, "BUS": 0},
               testcase=testcase, tb_sources=["tb_core.v"],
               extra_env={"TWH_CLK_HZ": "4000000", "TWH_CHANNELS": "3",
                          "TWH_FIFO_DEPTH": "16", "TWH_BUS": "0"},
               sim="verilator")
    if testcase == "driver_session":
        # the same session on the Verilated core, the same cells: the same
        # frames, in the same order, with the same answers
        subprocess.run(["make", "-s", "-C", str(simrun.ROOT), "cosim-session"], check=True,
                       stdout=subprocess.DEVNULL)
        cocotb_run = (simrun.ROOT / "build" / "sim" / "cosim_driver_session" / TRANSCRIPT).read_text()
        harness = (simrun.ROOT / "build" / "demo" / "session_verilator.txt").read_text()
        assert cocotb_run.splitlines() and cocotb_run == harness, \
            f"transcripts differ:\n--- cocotb\n{cocotb_run}--- soak harness\n{harness}"
