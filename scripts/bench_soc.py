#!/usr/bin/env python3
"""Resources and Fmax of the LiteX SoC of the drop-in proof (docs/soc.md):
VexRiscv "minimal" + twowire-host with three channels + LiteX's UART (a
real 115200-baud PHY here, the stream model in the simulation), timer,
ROM and SRAM, synthesized with the project's YoWASP flow
(scripts/synth.py) for the iCE40 UP5K and the ECP5-25F. Printed, never
asserted (part of make bench).

Memory configurations of the same SoC (soc/twh_soc.py --variant hw):
  as simulated   ROM 32 KiB (the firmware of make soc, 18 KiB) and SRAM
                 64 KiB (the page tool keeps 34 KiB of state)
  small memories ROM 8 KiB (the firmware's first 8 KiB, so the ROM stays
                 non-constant) and SRAM 4 KiB: the logic of the SoC, with
                 memories an FPGA of this size could hold in block RAM;
                 this firmware would not run from it
  small, 1 channel  the same with CHANNELS=1 (UP5K only): what fits there
  PicoRV32, SPRAM / SERV, SPRAM  (UP5K only) the two smaller RV32I CPUs of
                 issue 19's question (a PicoRV32/SERV-class CPU beside
                 three channels on a UP5K) in place of the VexRiscv, ROM
                 8 KiB, SRAM 64 KiB in the UP5K's SPRAM (LiteX's
                 Up5kSPRAM), block RAM left to the ROM and the core; SERV
                 takes no interrupts, so the core's irq is not wired there.
                 These rows are a fit check of the logic and memories: the
                 firmware (18 KiB) does not fit their ROM; make soc runs it
                 on SERV with the simulation's memories
  SERV, flash    (UP5K only) SERV with no ROM: the firmware executes in
                 place from the board's SPI flash (litespi, one bit wide,
                 as LiteX's iCEBreaker target), the SRAM in SPRAM: what a
                 UP5K board with the firmware of make soc would build
  VexRiscv, flash  (UP5K only) the SERV, flash row with LiteX's default
                 CPU: issue 34's three channels and the VexRiscv on the UP5K
                 with no block RAM spent on a ROM
  PicoRV32, SPRAM, lean core  (UP5K only) the PicoRV32 row with the
                 core's lean build (PROG_TIMING = 0, POLLING = 0: fixed
                 spec timing, no poller), what a fixed-timing board with
                 three cells would pick; a fit check like the PicoRV32 row
The core's memories are block RAM on the UP5K and LUT RAM on the ECP5
(RAM_BLOCK = 0, as docs/integration.md has ECP5 builds set it; twh_soc.py
--lut-ram). The SoC clock is 24 MHz (CLK_HZ of the core); nextpnr targets 24 MHz on the
UP5K, 50 MHz on the ECP5. Yosys runs with the flow's options (iCE40:
-dffe_min_ce_use 4, without which the flash build does not place); ECP5
runs use nextpnr's default options (not the project's --tmg-ripup: it
takes several times as long on a design this size). A configuration
whose memories exceed the part is reported from Yosys's statistics with
nextpnr's reason.

    bench_soc.py [--fw build/soc/fw/fw.bin] [--only up5k|ecp5-25f] [--config NAME]
                 [--write docs/soc.md]

With --write (make bench-soc), a run of every configuration writes its
table into the file between the lines WRITE_BEGIN and WRITE_END, so the
table in docs/soc.md is always the last run's.
"""
import argparse
import contextlib
import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
import synth  # noqa: E402

OUT = ROOT / "build" / "soc" / "bench"
CLK_HZ = 24_000_000
# name, ROM (0: the firmware runs from SPI flash), SRAM, ROM image truncated
# to, channels, parts (None: all), CPU, SRAM in the UP5K's SPRAM, the core's
# lean build
CONFIGS = [("as simulated", 0x8000, 0x10000, None, 3, None, "vexriscv", False, False),
           ("small memories", 0x2000, 0x1000, 0x2000, 3, None, "vexriscv", False, False),
           ("small, 1 channel", 0x2000, 0x1000, 0x2000, 1, ["up5k"], "vexriscv", False, False),
           ("PicoRV32, SPRAM", 0x2000, 0x10000, 0x2000, 3, ["up5k"], "picorv32", True, False),
           ("PicoRV32, SPRAM, lean core", 0x2000, 0x10000, 0x2000, 3, ["up5k"], "picorv32",
            True, True),
           ("SERV, SPRAM", 0x2000, 0x10000, 0x2000, 3, ["up5k"], "serv", True, False),
           ("SERV, flash", 0, 0x10000, None, 3, ["up5k"], "serv", True, False),
           ("VexRiscv, flash", 0, 0x10000, None, 3, ["up5k"], "vexriscv", True, False)]
PARTS = [("up5k", 24.0, "30 EBR (4 kbit), 4 SPRAM (256 kbit, not inferred)"),
         ("ecp5-25f", 50.0, "56 DP16KD (18 kbit)")]


def gen_verilog(name, rom_size, sram_size, fw, truncate, channels, cpu, spram, lean, lut_ram):
    d = OUT / (re.sub(r"\W+", "_", name) + ("_lutram" if lut_ram else ""))
    d.mkdir(parents=True, exist_ok=True)
    if rom_size == 0:
        mem = ["--flash"]               # no ROM: nothing to write its image for
    else:
        rom = d / "fw.bin"
        data = fw.read_bytes()
        rom.write_bytes(data[:truncate] if truncate else data)
        mem = ["--rom-size", hex(rom_size), "--rom", str(rom)]
    subprocess.run([sys.executable, str(ROOT / "soc" / "twh_soc.py"), "--variant", "hw",
                    "--out", str(d), "--clk-hz", str(CLK_HZ), "--sram-size", hex(sram_size)]
                   + mem + ["--channels", str(channels), "--cpu", cpu]
                   + (["--spram"] if spram else []) + (["--lean"] if lean else [])
                   + (["--lut-ram"] if lut_ram else []), check=True,
                   stdout=subprocess.DEVNULL)
    gw = d / "gateware"
    files = [l for l in (gw / "sources.f").read_text().split() if not l.startswith("+incdir")]
    # the ROM/RAM .init files are read by bare name: give Yosys the paths
    # relative to the repository, where the YoWASP tools run
    v = gw / "twh_soc.v"
    text = v.read_text()
    fixed = re.sub(r'\$readmemh\("([^"/]+)"',
                   lambda m: f'$readmemh("{synth.rel(gw / m.group(1))}"', text)
    vs = gw / "twh_soc_synth.v"
    vs.write_text(fixed)
    return [f if f != str(v) else str(vs) for f in files], d


def yosys_only(out):
    stat = json.loads((ROOT / synth.rel(out) / "stat.json").read_text())
    cells = stat["design"]["num_cells_by_type"]
    ram = sum(n for c, n in cells.items() if c.startswith(("SB_RAM", "DP16KD")))
    lut = cells.get("SB_LUT4", 0) + cells.get("LUT4", 0)
    ff = sum(n for c, n in cells.items() if re.match(r"^(SB_DFF|TRELLIS_FF)", c))
    log = (ROOT / synth.rel(out) / "nextpnr.log").read_text()
    why = next((l.strip() for l in log.splitlines() if "ERROR" in l), "nextpnr failed")
    # nextpnr's utilisation lines, e.g. "ICESTORM_LC:  6673/  5280   126%"
    util = ", ".join(f"{m.group(1)} {m.group(2)}/{m.group(3)}" for m in re.finditer(
        r"(ICESTORM_LC|ICESTORM_RAM|TRELLIS_COMB|DP16KD):\s+(\d+)/\s*(\d+)", log))
    return ram, lut, ff, why, util


WRITE_BEGIN = "<!-- bench-soc: the table below is written by scripts/bench_soc.py --write -->"
WRITE_END = "<!-- bench-soc: end of the written table -->"
PART_NAME = {"up5k": "UP5K", "ecp5-25f": "ECP5-25F"}
PART_MEM = {"up5k": ("EBR", 30), "ecp5-25f": ("DP16KD", 56)}
PART_LOGIC = {"up5k": 5280, "ecp5-25f": 24288}


CPU_NAME = {"vexriscv": "VexRiscv", "picorv32": "PicoRV32 (minimal)", "serv": "SERV"}


def describe(name, rom_size, sram_size, channels, cpu, spram, lean):
    what = name if cpu == "vexriscv" else f"{CPU_NAME[cpu]} for the VexRiscv"
    rom = f"ROM {rom_size // 1024} KiB" if rom_size else "firmware in SPI flash, no ROM"
    core = ", the core's lean build" if lean else ""
    return (f"{what}: {channels} ch{core}, {rom}, SRAM "
            f"{sram_size // 1024} KiB{' in SPRAM' if spram else ''}")


def spram_blocks(out):
    stat = json.loads((ROOT / synth.rel(out) / "stat.json").read_text())
    return stat["design"]["num_cells_by_type"].get("SB_SPRAM256KA", 0)


def table_row(part, config, out, r=None, failed=None):
    """One markdown row: r from synth.synth, or failed = (ram, lut, ff, util)."""
    unit, total = PART_MEM[part]
    spram = spram_blocks(out)
    spram_txt = f", {spram} of 4 SPRAM" if spram else ""
    if r is not None:
        pct = 100.0 * r["logic"] / PART_LOGIC[part]
        logic = (f"{r['logic']} LC of {PART_LOGIC[part]} ({pct:.1f} %)" if part == "up5k"
                 else f"{r['logic']} LUT4+ (TRELLIS_COMB)")
        ram = (f"{r['ram']} of {total} {unit}" + spram_txt
               + (f" (+{r['lutram']} LUTRAM)" if r["lutram"] else ""))
        fmax = f"{r['fmax']} MHz ({r['freq']:g})" + ("" if r["timing_met"] else ", missed")
        return f"| {PART_NAME[part]} | {config} | {logic} | {r['lut']} | {r['ff']} | {ram} | {fmax} | yes |"
    ram, lut, ff, util = failed
    m = re.search(r"(?:ICESTORM_LC|TRELLIS_COMB) (\d+)/(\d+)", util)
    lc = "LC" if part == "up5k" else "LUT4+"
    logic = (f"{m.group(1)} {lc} of {m.group(2)} "
             f"({100.0 * int(m.group(1)) / int(m.group(2)):.0f} %)" if m else "-")
    r_m = re.search(r"(?:ICESTORM_RAM|DP16KD) (\d+)/(\d+)", util)
    if not m or int(m.group(1)) > int(m.group(2)):
        fits = "no"
    elif r_m and int(r_m.group(1)) > int(r_m.group(2)):
        fits = "no (RAM)"
    else:
        fits = "no (placement)"     # every count fits, nextpnr found no legal placement
    return (f"| {PART_NAME[part]} | {config} | {logic} | {lut} | {ff} | "
            f"{ram} of {total} {unit}{spram_txt} | - | {fits} |")


def write_table(path, rows, seconds):
    text = Path(path).read_text()
    if WRITE_BEGIN not in text or WRITE_END not in text:
        sys.exit(f"{path}: no bench-soc markers")
    head, rest = text.split(WRITE_BEGIN, 1)
    _, tail = rest.split(WRITE_END, 1)
    table = "\n".join(
        ["| part | configuration | logic | LUT4 | FF | block RAM | Fmax (target) | fits |",
         "|---|---|---|---|---|---|---|---|"] + rows)
    note = (f"\n\n(Written by `make bench-soc` on {time.strftime('%Y-%m-%d')}, {seconds:.0f} s. "
            "Rows that do not fit: the figures are nextpnr's utilisation before it gave up "
            "placing, and Yosys's cell counts; no Fmax.)\n")
    Path(path).write_text(head + WRITE_BEGIN + "\n" + table + note + WRITE_END + tail)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fw", default=str(ROOT / "build" / "soc" / "fw" / "fw.bin"))
    ap.add_argument("--only", choices=[p for p, *_ in PARTS])
    ap.add_argument("--config", action="append", choices=[c[0] for c in CONFIGS],
                    help="only this configuration (repeatable)")
    ap.add_argument("--write", help="markdown file whose bench-soc table to rewrite "
                    "(only with every configuration and part)")
    a = ap.parse_args()
    if a.write and (a.config or a.only):
        sys.exit("--write needs the whole run (no --config, no --only)")
    rows = []
    fw = Path(a.fw)
    if not fw.exists():
        sys.exit(f"{fw}: build the firmware first (make soc)")
    print("== LiteX SoC: a RV32I CPU (VexRiscv minimal unless named) + twowire-host + UART + timer, "
          f"{CLK_HZ / 1e6:g} MHz (docs/soc.md)")
    t0 = time.time()
    for name, rom_size, sram_size, truncate, channels, only, cpu, spram, lean in CONFIGS:
        if a.config and name not in a.config:
            continue
        desc = describe(name, rom_size, sram_size, channels, cpu, spram, lean)
        for part, freq, mem in PARTS:
            if (a.only and part != a.only) or (only and part not in only):
                continue
            # the core's memories as the part's builds set them: block RAM
            # on the iCE40s, LUT RAM on the ECP5 (RAM_BLOCK = 0)
            files, d = gen_verilog(name, rom_size, sram_size, fw, truncate, channels, cpu, spram,
                                   lean, lut_ram=part.startswith("ecp5"))
            out = d / part
            rom_txt = f"ROM {rom_size // 1024:2} KiB" if rom_size else "SPI flash "
            label = (f"{part:9} {name:16} {channels} ch{' lean' if lean else ''}, {rom_txt} "
                     f"SRAM {sram_size // 1024:2} KiB{' (SPRAM)' if spram else ''}")
            try:
                # synth.py prints the tail of a failed tool's log: the
                # reason is taken from the log below instead
                with open(os.devnull, "w") as null, contextlib.redirect_stderr(null):
                    r = synth.synth(part, "twh_soc", {}, files, freq, out, default_pnr=True)
            except SystemExit:
                ram, lut, ff, why, util = yosys_only(out)
                print(f"{label}  DOES NOT FIT: nextpnr utilisation {util} "
                      f"(Yosys: LUT {lut}, FF {ff}, {ram} block RAMs; part: {mem}); {why}")
                rows.append(table_row(part, desc, out, failed=(ram, lut, ff, util)))
                continue
            rows.append(table_row(part, desc, out, r=r))
            unit = "LC" if part == "up5k" else "LUT4+"
            print(f"{label}  logic {r['logic']:5} {unit}  LUT {r['lut']:5}  FF {r['ff']:5}  "
                  f"BRAM {r['ram']:2}  LUTRAM {r['lutram']:2}  Fmax {r['fmax']:6.1f} MHz "
                  f"(target {freq:g}){'' if r['timing_met'] else ' MISSED'}  fits  "
                  f"[{r['seconds']} s]")
            sys.stdout.flush()
    print(f"bench_soc: {time.time() - t0:.0f} s")
    if a.write:
        write_table(a.write, rows, time.time() - t0)
        print(f"bench_soc: table written into {a.write}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
