#!/usr/bin/env python3
"""The LiteX SoC of the drop-in proof (docs/soc.md): a VexRiscv (variant
"minimal", RV32I) with integrated ROM and SRAM, LiteX's UART and timer (no
uptime counter, ctrl module or identifier: the firmware uses none), and twowire-host with three channels added by
soc/twh_litex.py.

    twh_soc.py --variant sim --out build/soc/sim [--rom fw.bin]
    twh_soc.py --variant hw  --out build/soc/hw  [--rom fw.bin] [--cpu serv] [--spram]
               [--flash] [--lean] [--lut-ram]

--cpu picorv32 / serv put one of the smaller RV32I CPUs in place of the
VexRiscv (make soc simulates the VexRiscv and SERV; scripts/bench_soc.py's
UP5K fit check takes PicoRV32 and SERV), --spram the SRAM in the UP5K's
SPRAM blocks (hw only), --lean the core's lean build (PROG_TIMING = 0,
POLLING = 0), --lut-ram the core's RAM_BLOCK = 0 (its engine's and pollers'
memories in LUT RAM: what an ECP5 build sets, docs/integration.md).

Writes OUT/gateware/twh_soc.v (+ the ROM/RAM .init files and sources.f,
every Verilog file the SoC needs), OUT/software/include/generated/ (csr.h,
soc.h, mem.h of LiteX), OUT/regions.ld and OUT/fw_ldflags (the memory
regions, for the firmware's link with picolibc.ld). Without --rom the ROM is left empty: that run is
for the headers the firmware is compiled against; the second run, with the
firmware, gives the Verilog (the map is the same in both).

sim: the UART is LiteX's stream model (RS232PHYModel; the harness
soc/sim_main.cpp takes its bytes), the clock and reset are pins the harness
drives. hw: a real UART PHY (115200 baud) on tx/rx pins; the Verilog
scripts/bench_soc.py synthesizes. Neither build runs LiteX's BIOS build
(no picolibc/compiler-rt pythondata: the firmware is built with Debian's
toolchain by mk/soc.mk) nor any vendor tool.
"""
import argparse
import logging
import os
import sys
from pathlib import Path

from migen import ClockDomain, Module

from litex.build.generic_platform import GenericPlatform, Pins, Subsignal
from litex.soc.integration import export
from litex.soc.integration.builder import Builder
from litex.soc.cores.ram import Up5kSPRAM
from litex.soc.integration.soc import SoCRegion
from litex.soc.integration.soc_core import SoCCore, get_mem_data

sys.path.insert(0, str(Path(__file__).resolve().parent))
from twh_litex import add_twh  # noqa: E402

CHANNELS = 3
# the CPUs the SoC can carry, each in its smallest RV32I variant: the
# VexRiscv, and the two smaller ones of issue 19's question (does a
# PicoRV32/SERV-class CPU fit beside three channels on a UP5K?), whose
# Verilog comes from their pythondata packages
CPU_VARIANT = {"vexriscv": "minimal", "picorv32": "minimal", "serv": "standard"}
TWH_ORIGIN = 0x82000000        # in VexRiscv's uncached IO region (0x80000000+)
FLASH_ORIGIN = 0x20000000      # --flash: the SPI flash's window
FLASH_FW_OFFSET = 0x100000     # ... and the firmware in it, behind the bitstream


def _io(variant, channels):
    io = [("sys_clk", 0, Pins(1)), ("sys_rst", 0, Pins(1)),
          ("twh", 0,
           Subsignal("line_o", Pins(channels)),
           Subsignal("line_oe", Pins(channels)),
           Subsignal("line_i", Pins(channels)))]
    if variant == "sim":
        io.append(("serial", 0,
                   Subsignal("source_valid", Pins(1)), Subsignal("source_ready", Pins(1)),
                   Subsignal("source_data", Pins(8)),
                   Subsignal("sink_valid", Pins(1)), Subsignal("sink_ready", Pins(1)),
                   Subsignal("sink_data", Pins(8))))
    else:
        io.append(("serial", 0, Subsignal("tx", Pins(1)), Subsignal("rx", Pins(1))))
        io.append(("spiflash", 0, Subsignal("cs_n", Pins(1)), Subsignal("clk", Pins(1)),
                   Subsignal("mosi", Pins(1)), Subsignal("miso", Pins(1))))
    return io


class VerilogPlatform(GenericPlatform):
    """Only writes the Verilog (and the list of sources): the simulation
    and the synthesis runs call their tools themselves."""
    default_clk_name = "sys_clk"

    def build(self, fragment, build_dir="build", build_name="top", run=False, **kwargs):
        os.makedirs(build_dir, exist_ok=True)
        cwd = os.getcwd()
        os.chdir(build_dir)
        try:
            if not hasattr(fragment, "statements"):
                fragment = fragment.get_fragment()
            self.finalize(fragment)
            v = self.get_verilog(fragment, name=build_name)
            v.write(build_name + ".v")
            srcs = [os.path.abspath(f) for f, *_ in self.sources] + \
                   [os.path.abspath(build_name + ".v")]
            incs = [os.path.abspath(d) for d in self.verilog_include_paths]
            with open("sources.f", "w") as f:
                f.write("".join(f"+incdir+{d}\n" for d in incs))
                f.write("".join(f"{s}\n" for s in srcs))
        finally:
            os.chdir(cwd)
        return v.ns


class _CRG(Module):
    """One clock domain from the clk pin, reset synchronous from the rst pin
    (the harness or the board holds it)."""
    def __init__(self, platform):
        self.clock_domains.cd_sys = ClockDomain()
        self.comb += [self.cd_sys.clk.eq(platform.request("sys_clk")),
                      self.cd_sys.rst.eq(platform.request("sys_rst"))]


class TwhSoC(SoCCore):
    mem_map = {**SoCCore.mem_map}

    def __init__(self, variant, clk_hz, rom_size, sram_size, rom_init, channels=CHANNELS,
                 cpu="vexriscv", spram=False, flash=False, lean=False, lut_ram=False):
        platform = VerilogPlatform("", _io(variant, channels), name="twh_soc")
        if flash:
            self.mem_map = {**SoCCore.mem_map, "spiflash": FLASH_ORIGIN}
        SoCCore.__init__(self, platform, clk_hz,
                         cpu_type=cpu, cpu_variant=CPU_VARIANT[cpu],
                         cpu_reset_address=FLASH_ORIGIN + FLASH_FW_OFFSET if flash else None,
                         integrated_rom_size=0 if flash else rom_size,
                         integrated_rom_init=[] if flash else rom_init,
                         integrated_sram_size=0 if spram else sram_size,
                         uart_name="sim" if variant == "sim" else "serial",
                         uart_baudrate=115200,
                         with_timer=True, timer_uptime=False,
                         with_ctrl=False, ident="", ident_version=False)
        self.crg = _CRG(platform)
        if flash:
            # the firmware executed in place from the board's SPI flash (one
            # bit wide, as the iCEBreaker's LiteX target), behind the
            # bitstream: no block RAM for a ROM
            from litespi.modules import W25Q128JV
            from litespi.opcodes import SpiNorFlashOpCodes
            self.add_spi_flash(mode="1x", module=W25Q128JV(SpiNorFlashOpCodes.READ_1_1_1),
                               with_master=False)
        if spram:
            # the UP5K's single-port RAM blocks (two side by side: 32 bits,
            # 64 KiB), leaving the block RAM to the ROM and the core
            self.spram = Up5kSPRAM(size=sram_size)
            self.bus.add_slave("sram", self.spram.bus,
                               SoCRegion(origin=self.mem_map["sram"], size=sram_size))
        self.twh = None
        # (the other CPUs' maps have their CSRs there: LiteX places the
        # window in their IO region)
        add_twh(self, "twh", pads=platform.request("twh"), channels=channels,
                origin=TWH_ORIGIN if cpu == "vexriscv" else None,
                prog_timing=not lean, polling=not lean, ram_block=not lut_ram)


class HeaderBuilder(Builder):
    """LiteX's Builder without its BIOS: csr.h, soc.h, mem.h are written,
    the BIOS's make variables (which want the picolibc and compiler-rt
    pythondata packages) are not."""
    def _generate_includes(self, with_bios=True):
        super()._generate_includes(with_bios=False)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--variant", choices=("sim", "hw"), required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--clk-hz", type=int, default=4_000_000)
    ap.add_argument("--rom-size", type=lambda s: int(s, 0), default=0x8000)
    ap.add_argument("--sram-size", type=lambda s: int(s, 0), default=0x10000)
    ap.add_argument("--rom", help="firmware binary for the ROM")
    ap.add_argument("--channels", type=int, default=CHANNELS)
    ap.add_argument("--cpu", choices=sorted(CPU_VARIANT), default="vexriscv")
    ap.add_argument("--spram", action="store_true",
                    help="SRAM in the iCE40 UP5K's SPRAM (hw only; 64 or 128 KiB)")
    ap.add_argument("--flash", action="store_true",
                    help="no ROM: the firmware runs from SPI flash (hw only)")
    ap.add_argument("--lean", action="store_true",
                    help="the core's lean build: PROG_TIMING = 0, POLLING = 0")
    ap.add_argument("--lut-ram", action="store_true",
                    help="the core's RAM_BLOCK = 0: its engine's memories in LUT RAM (ECP5)")
    ap.add_argument("-v", "--verbose", action="store_true", help="LiteX's own log")
    a = ap.parse_args()
    if not a.verbose:
        logging.disable(logging.INFO)

    rom_init = []
    if a.rom:
        rom_init = get_mem_data(a.rom, data_width=32, endianness="little")
        if len(rom_init) * 4 > a.rom_size:
            sys.exit(f"{a.rom}: {len(rom_init) * 4} bytes, the ROM has {a.rom_size}")
    if a.spram and (a.variant != "hw" or a.sram_size not in (0x10000, 0x20000)):
        sys.exit("--spram: hw variant, SRAM of 64 or 128 KiB")
    if a.flash and a.variant != "hw":
        sys.exit("--flash: hw variant")
    soc = TwhSoC(a.variant, a.clk_hz, a.rom_size, a.sram_size, rom_init, a.channels,
                 cpu=a.cpu, spram=a.spram, flash=a.flash, lean=a.lean, lut_ram=a.lut_ram)
    out = Path(a.out).resolve()
    builder = HeaderBuilder(soc, output_dir=str(out), compile_software=False,
                            compile_gateware=False)
    builder.build(build_name="twh_soc", run=False)
    (out / "regions.ld").write_text(export.get_linker_regions(soc.mem_regions))
    # the same regions for picolibc's linker script (picolibc.ld)
    sram = soc.mem_regions["sram"]
    if a.flash:
        flash_origin = FLASH_ORIGIN + FLASH_FW_OFFSET
        flash_size = soc.mem_regions["spiflash"].size - FLASH_FW_OFFSET
    else:
        flash_origin, flash_size = soc.mem_regions["rom"].origin, soc.mem_regions["rom"].size
    (out / "fw_ldflags").write_text(
        f"-Wl,--defsym=__flash={flash_origin:#x} -Wl,--defsym=__flash_size={flash_size:#x} "
        f"-Wl,--defsym=__ram={sram.origin:#x} -Wl,--defsym=__ram_size={sram.size:#x}\n")
    rom_txt = (f"firmware in SPI flash at {flash_origin:#x}" if a.flash else
               f"ROM {len(rom_init) * 4}/{a.rom_size} bytes used")
    print(f"twh_soc ({a.variant}): {out / 'gateware' / 'twh_soc.v'}, {rom_txt}, SRAM {a.sram_size}, "
          f"{soc.sys_clk_freq / 1e6:g} MHz, twh at {soc.bus.regions['twh'].origin:#x}, "
          f"irq {soc.irq.locs.get('twh', 'none (the CPU takes no interrupts)')}")


if __name__ == "__main__":
    main()
