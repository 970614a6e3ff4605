#!/usr/bin/env python3
"""Checks the output of the sensor-page tool, as the simulated LiteX SoC
prints it on its UART (docs/soc.md) and `make demo` prints it from the
Verilated core (build/demo/page.txt), against the shared vectors: every
channel's page must be, line for line, the page tb/sensor_page.py derives
from the vector image its cell carries (tb/vectors/flash_o2.json,
flash_co2.json) and the cell's raw readings, through the project's Python
map and conversion rules (tb/flashmap.py, tb/protocol.py, held to the same
vectors by tb/test_protocol.py) - the page the PC tool's test expects too.
The banner must name the core's channels, FIFO depth, clock and the
register map's major version (VERSION.MAJOR of sw/include/twh_regs.h: 2,
the map for up to 32 channels). The run must also have used the interrupt:
wait_irq called, every wait ended by the core's interrupt, none by its
timeout, and at least one that had to wait for it; with --no-irq (a CPU
without interrupts: SERV), the firmware must say it polled and no wait_irq
may have run.

    check_page.py UART_LOG [--clk-khz 4000] [--channels 3] [--fifo-depth 16] [--no-irq]
"""
import argparse
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from cells import ROOT, cells  # noqa: E402

sys.path.insert(0, str(ROOT / "tb"))
from sensor_page import expected_page, pages  # noqa: E402


def major_version():
    """VERSION.MAJOR's reset value in the generated header the driver was
    built with (twh_init refuses any other major)"""
    text = (ROOT / "sw" / "include" / "twh_regs.h").read_text()
    return int(re.search(r"#define TWH_REGS__VERSION__MAJOR_reset (0x[0-9a-fA-F]+|\d+)", text)
               .group(1), 0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("log")
    ap.add_argument("--clk-khz", type=int, default=4000)
    ap.add_argument("--channels", type=int, default=3)
    ap.add_argument("--fifo-depth", type=int, default=16)
    ap.add_argument("--no-irq", action="store_true",
                    help="the CPU takes no interrupts (SERV): the driver polled")
    a = ap.parse_args()
    no_irq = a.no_irq
    text = Path(a.log).read_text()
    fails = []

    head = (f"core: {a.channels} channels, FIFO depth {a.fifo_depth}, {a.clk_khz} kHz, "
            f"version {major_version()}.")
    if not any(line.startswith(head) for line in text.splitlines()):
        fails.append(f"no line starting '{head}'")
    got = pages(text)
    for ch, (name, prof, vmap) in enumerate(cells()):
        want = expected_page(ch, prof)
        have = got.get(ch)
        if have != want:
            fails.append(f"channel {ch} ({name}, vector note: {vmap['note']}):\n"
                         + "\n".join(f"  want: {w}" for w in want) + "\n"
                         + "\n".join(f"  got:  {h}" for h in (have or ["(no page)"])))
        else:
            print(f"check_page: channel {ch} ({name}): {len(want)} lines match the vector")
    if sorted(got) != list(range(len(cells()))):
        fails.append(f"pages for channels {sorted(got)}")

    m = re.search(r"twh_page_run returned (-?\d+)", text)
    if not m or m.group(1) != "0":
        fails.append("twh_page_run did not return 0")
    m = re.search(r"wait_irq calls (\d+), woken by the interrupt (\d+) "
                  r"\(pending on entry (\d+)\), timed out (\d+)", text)
    if no_irq:
        # a CPU without interrupts: the banner says so and no wait_irq ran
        if "no irq (the driver polls)" not in text or m:
            fails.append("expected a run without the interrupt (--no-irq)")
        else:
            print("check_page: no interrupt: the driver polled RES_INFO")
    elif not m:
        fails.append("no wait_irq statistics")
    else:
        calls, woke, already, timed_out = map(int, m.groups())
        if calls == 0 or woke != calls or timed_out != 0 or woke - already <= 0:
            fails.append(f"interrupt path: {calls} waits, {woke} ended by the interrupt "
                         f"({already} pending on entry), {timed_out} timed out")
        else:
            print(f"check_page: interrupt path: {calls} waits, all ended by the core's "
                  f"interrupt ({woke - already} waited for it, {already} found it pending)")
    if "twh_cli:" in text:
        fails.append("the page tool reported an error: " +
                     next(line for line in text.splitlines() if "twh_cli:" in line))
    if fails:
        print("check_page: FAIL\n" + "\n".join(fails))
        return 1
    print("check_page: PASS: every page matches tb/vectors/, " +
          ("polled, no interrupt" if no_irq else "the interrupt path was used"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
