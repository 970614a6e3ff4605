"""twowire-host as a LiteX peripheral (docs/integration.md, "Adding the core
to a LiteX SoC"; docs/soc.md).

    from twh_litex import add_twh
    add_twh(soc, "twh", pads=platform.request("twh"), channels=3)

`TwoWireHost` wraps rtl/twh_wb.v (Wishbone B4 classic, 32-bit data) in a
Migen module: a LiteX Wishbone slave (word addressed, as LiteX's bus is)
with the core's level `irq` behind an `ev.irq` (what LiteX's IRQ handler
wires to the CPU), CLK_HZ set from the SoC's clock, CHANNELS, FIFO_DEPTH
and the lean build's PROG_TIMING / POLLING passed through, and the 2-wire
pins from a pad record. The window size and the register offsets come from
rdl/twh_regs.rdl through systemrdl-compiler (`read_regmap`), the same
single source as the C header sw/include/twh_regs.h; nothing of the map is
written down here.

Pads: either `line_o`, `line_oe`, `line_i` ([CHANNELS-1:0] each: the
tri-state buffer and front end stay outside, as for the bare core), or one
tri-state `line` [CHANNELS-1:0] (an FPGA pin with a pull-down: a TSTriple
per channel is built here).
"""
import functools
import os
from dataclasses import dataclass, field
from pathlib import Path

from migen import Cat, ClockSignal, Constant, Instance, Module, ResetSignal, Signal, TSTriple

from litex.soc.interconnect import wishbone
from litex.soc.integration.soc import SoCRegion

ROOT = Path(__file__).resolve().parent.parent
RTL_DIR = ROOT / "rtl"
RDL_PATH = ROOT / "rdl" / "twh_regs.rdl"
# the core's sources (no board or UART bridge files)
RTL_FILES = ("twh_wb.v", "twh_core.v", "twh_carrier.v", "twh_checksum.v", "twh_fifo.v",
             "twh_sync2.v", "twh_timing.v", "twh_window.v", "twh_ram.v", "twh_engine_pin.v",
             "twh_engine.v", "twh_polls.v", "twh_core_engine.v", "twh_rx_dec.v", "twh_rx_sum.v",
             "twh_rx_step.v")


@dataclass(frozen=True)
class RegMap:
    """The register map of rdl/twh_regs.rdl, flattened."""
    size: int                  # bytes the whole map spans (every channel)
    ch_base: int               # offset of CH[0]
    ch_stride: int             # bytes per channel
    ch_count: int              # channels the map has room for
    regs: dict = field(default_factory=dict)     # top-level NAME -> offset
    ch_regs: dict = field(default_factory=dict)  # per-channel NAME -> offset in CH[k]
    id_reset: int = 0          # ID's reset value (the magic)

    def span(self, channels):
        """Bytes used with `channels` channels."""
        return self.ch_base + channels * self.ch_stride

    def window(self, channels):
        """The bus window: span rounded up to a power of two (LiteX regions
        must be)."""
        n = 1
        while n < self.span(channels):
            n <<= 1
        return n


@functools.lru_cache(maxsize=None)
def read_regmap(rdl=str(RDL_PATH)):
    """Compiles the SystemRDL source with systemrdl-compiler."""
    from systemrdl import RDLCompiler
    from systemrdl.node import FieldNode, RegNode

    comp = RDLCompiler()
    comp.compile_file(rdl)
    top = comp.elaborate().top
    arr = top.get_child_by_name("CH")
    regs, ch_regs, id_reset = {}, {}, 0
    for node in top.children():
        if isinstance(node, RegNode):
            regs[node.inst_name] = node.raw_address_offset
            if node.inst_name == "ID":
                id_reset = sum((f.get_property("reset") or 0) << f.lsb
                               for f in node.children() if isinstance(f, FieldNode))
    for node in arr.children():
        if isinstance(node, RegNode):
            ch_regs[node.inst_name] = node.raw_address_offset
    return RegMap(size=top.size, ch_base=arr.raw_address_offset, ch_stride=arr.array_stride,
                  ch_count=arr.array_dimensions[0], regs=regs, ch_regs=ch_regs,
                  id_reset=id_reset)


class _IRQ:
    """What LiteX's SoC IRQ handler takes from a peripheral: `ev.irq`."""
    def __init__(self, irq):
        self.irq = irq


class TwoWireHost(Module):
    """rtl/twh_wb.v as a LiteX Wishbone slave with its irq and pins."""

    def __init__(self, platform, pads, clk_freq, channels=1, fifo_depth=16, rdl=str(RDL_PATH),
                 prog_timing=True, polling=True, ram_block=True):
        self.regmap = regmap = read_regmap(rdl)
        if not 1 <= channels <= regmap.ch_count:
            raise ValueError(f"channels must be 1-{regmap.ch_count}")
        self.channels = channels
        self.clk_hz = int(clk_freq)
        self.size = regmap.window(channels)
        adr_w = (regmap.size - 1).bit_length()        # byte address bits of twh_wb
        word_bits = adr_w - 2

        self.bus = bus = wishbone.Interface(data_width=32, address_width=30, addressing="word")
        self.irq = Signal()
        self.ev = _IRQ(self.irq)

        line_o = Signal(channels)
        line_oe = Signal(channels)
        line_i = Signal(channels)
        if hasattr(pads, "line"):
            for k in range(channels):
                t = TSTriple()
                self.specials += t.get_tristate(pads.line[k])
                self.comb += [t.o.eq(line_o[k]), t.oe.eq(line_oe[k]), line_i[k].eq(t.i)]
        else:
            self.comb += [pads.line_o.eq(line_o), pads.line_oe.eq(line_oe),
                          line_i.eq(pads.line_i)]

        # LiteX addresses words; twh_wb takes byte addresses. Accesses
        # beyond the map are answered with err by the core itself. The
        # parameters as 32-bit constants: `integer` parameters (a bare int
        # would be written with the fewest bits it needs).
        self.specials += Instance("twh_wb",
            p_CLK_HZ=Constant(self.clk_hz, 32), p_CHANNELS=Constant(channels, 32),
            p_FIFO_DEPTH=Constant(fifo_depth, 32),
            p_PROG_TIMING=Constant(int(prog_timing), 32), p_POLLING=Constant(int(polling), 32),
            p_RAM_BLOCK=Constant(int(ram_block), 32),
            i_clk=ClockSignal(), i_rst=ResetSignal(),
            i_wb_adr_i=Cat(Constant(0, 2), bus.adr[:word_bits]),
            i_wb_dat_i=bus.dat_w, o_wb_dat_o=bus.dat_r,
            i_wb_we_i=bus.we, i_wb_sel_i=bus.sel,
            i_wb_stb_i=bus.stb, i_wb_cyc_i=bus.cyc,
            o_wb_ack_o=bus.ack, o_wb_err_o=bus.err,
            o_irq=self.irq,
            o_line_o=line_o, o_line_oe=line_oe, i_line_i=line_i)

        platform.add_verilog_include_path(str(RTL_DIR))
        for f in RTL_FILES:
            platform.add_source(str(RTL_DIR / f))


def add_twh(soc, name="twh", pads=None, channels=1, fifo_depth=16, origin=None,
            prog_timing=True, polling=True, ram_block=True):
    """Adds a TwoWireHost to a LiteX SoC: its Wishbone window (uncached:
    put `origin` in an IO region, or let LiteX place it), its interrupt
    (when the CPU takes interrupts; without, the irq pin is left unused
    and software polls the core: the C driver with no wait_irq hook), and
    constants for software (<NAME>_CHANNELS, <NAME>_REG_<REG> offsets,
    <NAME>_CH_BASE/_CH_STRIDE, from the RDL). prog_timing=False,
    polling=False: the lean build (docs/integration.md, "Lean builds").
    ram_block=False: the core's RAM_BLOCK = 0, its engine's and pollers'
    memories in LUT RAM at every depth (the ECP5's; the iCE40s need 1)."""
    twh = TwoWireHost(soc.platform, pads, soc.sys_clk_freq, channels, fifo_depth,
                      prog_timing=prog_timing, polling=polling, ram_block=ram_block)
    setattr(soc.submodules, name, twh)
    soc.bus.add_slave(name, twh.bus, SoCRegion(origin=origin, size=twh.size, cached=False))
    if soc.irq.enabled:
        soc.irq.add(name, use_loc_if_exists=True)
    up = name.upper()
    soc.add_constant(f"{up}_CHANNELS", channels)
    soc.add_constant(f"{up}_ID_MAGIC", twh.regmap.id_reset)
    for reg, off in twh.regmap.regs.items():
        soc.add_constant(f"{up}_REG_{reg}", off)
    soc.add_constant(f"{up}_CH_BASE", twh.regmap.ch_base)
    soc.add_constant(f"{up}_CH_STRIDE", twh.regmap.ch_stride)
    return twh


if __name__ == "__main__":
    m = read_regmap()
    print(f"{RDL_PATH.relative_to(ROOT)}: {m.size:#x} bytes, CH[{m.ch_count}] at {m.ch_base:#x} "
          f"+= {m.ch_stride:#x}, ID reset {m.id_reset:#010x}")
    print("registers:", ", ".join(f"{k}@{v:#x}" for k, v in m.regs.items()))
    print("per channel:", ", ".join(f"{k}@{v:#x}" for k, v in m.ch_regs.items()))
    print("window for 3 channels:", hex(m.window(3)))
