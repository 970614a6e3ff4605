"""The bus wrappers driven by third-party masters (issue 34): cocotbext-axi's
AxiLiteMaster on twh_axil, cocotbext-wishbone's WishboneMaster on twh_wb,
each in tb/tb_core.v (BUS = 1 / 0) with one channel and a modelled O2 cell
(firmware v18) on its line.

The third-party master stands in for CoreTB's own bus driver behind
`access()`, so every register access of the harness (push, result pop,
register reads) goes through it, while the spec monitor watches the line for
the whole run and finish() closes it, as in tb/test_twh_core.py. The
project's own handshake checks stay on as an independent watch on the
third-party master: on AXI-Lite the watcher of coretb.AxiLiteDriver (AW and
W taken in the same clock, one response per access), on Wishbone the cycle
check of coretb.WishboneDriver (each strobe answered exactly once, ack or
err, two clocks after it is taken).

Each bench:
- reads ID and PARAMS and checks them against the RDL;
- pushes a real command (0x41, firmware version) at spec timing, reads the
  result back through the master and checks it against the modelled cell
  (its profile and the answer it put on the line) and the frame the spec
  monitor saw;
- gets the documented bus error (AXI SLVERR, Wishbone ERR) for a push to an
  absent channel (ERRORS.BAD_CHANNEL, nothing on the line), a write with
  partial byte enables and an unmapped address (both without effect), and
  an OKAY / ack for the accesses around them;
- AXI-Lite: a read and a write issued together (the master's two channel
  pairs are independent), each answered once with its own data;
  Wishbone: one cycle of back-to-back strobes, answers in order.

They run on Icarus: these masters sample the bus right after the rising
edge, where Icarus shows the values before it (tb/coretb.py), and one
channel at 4 MHz keeps a transaction at spec timing to a few seconds.
"""
import logging

import cocotb
import pytest
from cocotb.triggers import Timer
from cocotbext.axi import AxiLiteBus, AxiLiteMaster
from cocotbext.axi.constants import AxiResp
from cocotbext.wishbone.driver import WBOp, WishboneMaster

import protocol as p
import coretb
from coretb import OK, TXN_US, CoreTB

BAD_CHANNEL_PUSH_TAG = 7
FW_TAG = 5


def _hole(rm):
    """The first word address of the 512-byte window that no register (nor
    an absent channel's block) answers."""
    taken = {r.address for r in rm.registers} | {r.address for r in rm.absent}
    return next(a for a in range(0, 0x200, 4) if a not in taken)


# ---------------------------------------------------------------- the masters
class AxilThirdParty:
    """cocotbext-axi's AxiLiteMaster behind CoreTB's `access()`."""

    def __init__(self, tb):
        self.native = tb.bus            # coretb.AxiLiteDriver: its watcher keeps running
        self.master = AxiLiteMaster(AxiLiteBus.from_prefix(tb.dut, "s_axil"), tb.dut.clk,
                                    tb.dut.rst)
        # it logs every access at INFO: only its warnings in the run's log
        for side in (self.master.write_if, self.master.read_if):
            side.log.setLevel(logging.WARNING)
        self.n_access = 0

    def _resp(self, resp):
        assert resp in (AxiResp.OKAY, AxiResp.SLVERR), f"response {resp!r}"
        return resp == AxiResp.SLVERR

    async def read(self, addr):
        self.n_access += 1
        r = await self.master.read(addr, 4)
        return int.from_bytes(r.data, "little"), self._resp(r.resp)

    async def write(self, addr, data: bytes):
        """A write of len(data) bytes at addr (wstrb follows)."""
        self.n_access += 1
        r = await self.master.write(addr, data)
        return self._resp(r.resp)

    async def access(self, addr, data=None, sel=0xF):
        assert sel == 0xF, "partial writes: write() with fewer bytes"
        if data is None:
            value, err = await self.read(addr)
        else:
            value, err = 0, await self.write(addr, data.to_bytes(4, "little"))
        self.check()
        return value, err

    def check(self):
        """The project's own watcher (coretb.AxiLiteDriver._watch) saw AW
        and W taken together and exactly one response per access."""
        nat = self.native
        assert not nat.violations, "AXI-Lite handshake: " + "; ".join(nat.violations)
        assert nat.n_resp == self.n_access, f"{nat.n_resp} responses for {self.n_access} accesses"


class WbThirdParty:
    """cocotbext-wishbone's WishboneMaster behind CoreTB's `access()`. Its
    signal names are mapped onto tb_core's wb_*_i / wb_*_o; sel and err are
    given as signals of the bus, so the master drives sel and sees err."""

    SIGNALS = {"cyc": "cyc_i", "stb": "stb_i", "we": "we_i", "adr": "adr_i",
               "datwr": "dat_i", "datrd": "dat_o", "ack": "ack_o", "sel": "sel_i",
               "err": "err_o"}
    def __init__(self, tb):
        self.native = tb.bus            # coretb.WishboneDriver: its cycle check
        # clocks: the core answers in two, and after a reset once its reset
        # sweep is over (the project's watcher checks the exact clock)
        self.ACK_TIMEOUT = 2 + coretb.sweep_clocks(tb.channels, tb.prog_timing, tb.polling)
        self.master = WishboneMaster(tb.dut, "wb", tb.dut.clk, timeout=self.ACK_TIMEOUT,
                                     signals_dict=dict(self.SIGNALS))

    async def cycle(self, ops):
        """One cycle of (addr, data or None, sel): [(data, err)]. The
        project's check of the handshake watches it from start to end."""
        box: list = []
        watcher = cocotb.start_soon(self.native._watch(box))
        res = await self.master.send_cycle(
            [WBOp(adr=a, dat=d, sel=s, acktimeout=self.ACK_TIMEOUT) for a, d, s in ops])
        await watcher
        nat = self.native
        assert not nat.violations, "Wishbone handshake: " + "; ".join(nat.violations)
        assert box == [len(ops)] and len(res) == len(ops), (box, len(res), len(ops))
        out = []
        for r in res:
            assert r.ack in (1, 2), f"answer {r.ack} (1 ack, 2 err, 3 rty)"
            out.append((int(r.datrd) if r.datrd.is_resolvable else 0, r.ack == 2))
        return out

    async def access(self, addr, data=None, sel=0xF):
        return (await self.cycle([(addr, data, sel)]))[0]


# ---------------------------------------------------------------- the bench
async def _bench(dut, make_master):
    tb = await CoreTB(dut, cells=("o2_v18",)).start()
    assert tb.channels == 1
    bus = make_master(tb)
    tb.bus = bus
    prof = tb.profiles[0]
    rm = tb.rm
    hole = _hole(rm)

    # ---- identity, through the third-party master
    for name in ("ID", "PARAMS"):
        assert await tb.read(name) == tb.reg(name).reset & tb.reg(name).read_mask, name
    assert await tb.errors() == 0

    # ---- a real command: firmware version from the modelled O2 cell
    r = await tb.command(0x41, 0xAA, ch=0, tag=FW_TAG, timeout_ms=TXN_US // 1000 + 10)
    assert r.status == OK, r
    assert r.data == prof.fw_byte << 8 | prof.type_byte, r
    answered = [t for t in tb.models[0].log if t.response is not None]
    assert len(answered) == 1, tb.models[0].log
    assert r.data == answered[0].response[0] << 8 | answered[0].response[1], answered
    assert tb.frames(0) == [p.build_frame(0x41, 0xAA)], tb.frames(0)
    assert await tb.pop() is None

    # ---- refused accesses: the bus error the docs give, no effect
    n_frames = len(tb.frames(0))
    # a push for an absent channel (docs/registers.md, CMD_PUSH)
    assert not await tb.push(0x41, 0xAA, ch=1, tag=BAD_CHANNEL_PUSH_TAG, expect_err=True)
    assert await tb.errors() == tb.pack("ERRORS", BAD_CHANNEL=1), hex(await tb.errors())
    # a write with partial byte enables (docs/integration.md): error, the
    # register keeps its value
    irq_en = tb.pack("IRQ_EN", RES_THRESHOLD=9)
    await tb.write("IRQ_EN", irq_en)
    assert await tb.read("IRQ_EN") == irq_en
    partial = tb.pack("IRQ_EN", RESULT=1, RES_THRESHOLD=3)
    if isinstance(bus, AxilThirdParty):
        # two bytes at the register: WSTRB 0b0011
        assert await bus.write(tb.addr("IRQ_EN"), partial.to_bytes(4, "little")[:2]), \
            "partial write acknowledged (OKAY)"
        bus.check()
    else:
        assert (await bus.access(tb.addr("IRQ_EN"), partial, sel=0x3))[1], \
            "partial write acknowledged (ack)"
    assert await tb.read("IRQ_EN") == irq_en, "a partial write changed IRQ_EN"
    # an unmapped address: read and write answer with an error
    assert (await tb.read32(hole))[1], f"read of unmapped {hole:#05x} acknowledged"
    assert await tb.write32(hole, 0xFFFFFFFF), f"write of unmapped {hole:#05x} acknowledged"
    assert await tb.read("IRQ_EN") == irq_en
    # only the bad channel is logged; clear it (woclr) through the master
    assert await tb.errors() == tb.pack("ERRORS", BAD_CHANNEL=1)
    await tb.clear_errors()
    # nothing went onto the line, no result came back
    await Timer(2, "ms")
    assert len(tb.frames(0)) == n_frames, tb.frames(0)
    assert await tb.pop() is None

    # ---- concurrency as each master does it
    ident = tb.reg("ID").reset
    if isinstance(bus, AxilThirdParty):
        # a read and a write issued together (AR beside AW/W), twice over,
        # plus a refused read: each answered once with its own data
        thr = [tb.pack("IRQ_EN", RES_THRESHOLD=k) for k in (5, 6)]
        tasks = [cocotb.start_soon(bus.read(tb.addr("ID"))),
                 cocotb.start_soon(bus.write(tb.addr("IRQ_EN"), thr[0].to_bytes(4, "little"))),
                 cocotb.start_soon(bus.read(hole)),
                 cocotb.start_soon(bus.write(tb.addr("IRQ_EN"), thr[1].to_bytes(4, "little"))),
                 cocotb.start_soon(bus.read(tb.addr("ID")))]
        got = [await t for t in tasks]
        assert got == [(ident, False), False, (0, True), False, (ident, False)], got
        bus.check()
        assert await tb.read("IRQ_EN") == thr[1]
    else:
        # one cycle, strobes back to back: ack and err in order
        got = await bus.cycle([(tb.addr("ID"), None, 0xF),
                               (tb.addr("IRQ_EN"), tb.pack("IRQ_EN", RES_THRESHOLD=5), 0xF),
                               (hole, None, 0xF),
                               (tb.addr("IRQ_EN"), None, 0xF),
                               (tb.addr("IRQ_EN"), 0, 0x1),
                               (tb.addr("ID"), None, 0xF)])
        assert [e for _, e in got] == [False, False, True, False, True, False], got
        assert got[0][0] == ident and got[5][0] == ident, got
        assert got[3][0] == tb.pack("IRQ_EN", RES_THRESHOLD=5), got
    await tb.write("IRQ_EN", tb.reg("IRQ_EN").reset)
    assert await tb.errors() == 0

    # the spec monitor closes clean, no result is left
    await tb.finish()


@cocotb.test()
async def axil_cocotbext_axi(dut):
    """cocotbext-axi's AxiLiteMaster drives twh_axil."""
    await _bench(dut, AxilThirdParty)


@cocotb.test()
async def wb_cocotbext_wishbone(dut):
    """cocotbext-wishbone's WishboneMaster drives twh_wb."""
    await _bench(dut, WbThirdParty)


# ======================================================================= pytest
import simrun  # noqa: E402

CLK_HZ = 4_000_000
CHANNELS = 1
FIFO_DEPTH = 4


def _run(testcase, bus):
    simrun.run("tb_core", "test_thirdparty_bus", f"thirdparty_{testcase}",
               parameters={"CLK_HZ": CLK_HZ, "CHANNELS": CHANNELS, "FIFO_DEPTH": FIFO_DEPTH,
                           "BUS": bus},
               testcase=testcase, tb_sources=["tb_core.v"],
               extra_env={"TWH_BUS": str(bus), "TWH_CHANNELS": str(CHANNELS),
                          "TWH_FIFO_DEPTH": str(FIFO_DEPTH), "TWH_CLK_HZ": str(CLK_HZ)})


@pytest.mark.budget(30)
def test_axil_cocotbext_axi():
    _run("axil_cocotbext_axi", 1)


@pytest.mark.budget(30)
def test_wb_cocotbext_wishbone():
    _run("wb_cocotbext_wishbone", 0)
