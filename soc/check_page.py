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

With --rig N (make rig, docs/rig.md) the cells are the rig's N
(soc/cells.py rig_cells): every healthy cell's page must be the vector page
of its image, and every faulty cell's page what the page tool prints for
the answers its model recorded (the "rig: page pass" lines the rig writes:
each transaction on the line with the status its answer must read as): the
page stops at the first answer that is not OK and shows what was answered
raw; the statuses that are not OK must be ones its fault gives.

    check_page.py UART_LOG [--clk-khz 4000] [--channels 3] [--fifo-depth 16] [--no-irq]
    check_page.py PAGES --rig N [--clk-khz 32000] [--fifo-depth 32]
"""
import argparse
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from cells import FAULT_TEXT, ROOT, cells, rig_cells, rig_fault  # noqa: E402

sys.path.insert(0, str(ROOT / "tb"))
from sensor_page import expected_page, pages  # noqa: E402


def major_version():
    """VERSION.MAJOR's reset value in the generated header the driver was
    built with (twh_init refuses any other major)"""
    text = (ROOT / "sw" / "include" / "twh_regs.h").read_text()
    return int(re.search(r"#define TWH_REGS__VERSION__MAJOR_reset (0x[0-9a-fA-F]+|\d+)", text)
               .group(1), 0)


STATUS = ("OK", "NO_RESPONSE", "BAD_CHECKSUM", "FRAMING", "SHORT_RESPONSE",
          "LINE_STUCK_LOW", "LINE_STUCK_HIGH", "BLOCKED", "CANCELLED")
# what a command was for, in the page tool's words (sw/tools/twh_page.c)
WHAT = {0x41: "firmware (0x41)", 0x40: "config (0x40)", 0x42: "supply (0x42)",
        0x43: "temperature (0x43)", 0x44: "O2 (0x44)", 0x48: "flash read (0x48)",
        0x49: "flash read (0x48)"}
# the statuses each of the rig's faults can give (docs/soak.md's table: a 0
# stop bit after a 0x00 byte is a break, so SHORT_RESPONSE)
FAULT_STATUS = {"checksum": {"BAD_CHECKSUM"}, "silent": {"NO_RESPONSE"},
                "stopbit": {"FRAMING", "SHORT_RESPONSE"}, "short": {"SHORT_RESPONSE"},
                "stuck_low": {"LINE_STUCK_LOW"}}


def rig_records(text):
    """{channel: (fault key or None, record)} from the rig's "page pass"
    lines; record: "ok" (every answer OK), "stuck" (nothing reached the
    cell) or [(command, status)] in line order"""
    out = {}
    for m in re.finditer(r"^rig: page pass, channel (\d+) \((?:no fault|fault (\w+))\): (.*)$",
                         text, re.M):
        ch, fault, body = int(m.group(1)), m.group(2), m.group(3)
        if re.fullmatch(r"\d+ transactions, all OK", body):
            rec = "ok"
        elif re.fullmatch(r"\d+ transactions? by the host, none reached the cell", body):
            rec = "stuck"
        else:
            rec = [(int(c, 16), st) for c, st in
                   (item.split(" ") for item in body.split(", "))]
        out[ch] = (fault, rec)
    return out


def faulty_page(ch, prof, rec):
    """the page the page tool prints for a cell whose page pass met rec: the
    channel stops at its first answer that is not OK (a failed firmware
    answer: no page at all); what was answered before it, and by the one
    still in flight, shows raw, as in the quick page"""
    if rec == "stuck":
        rec = [(0x41, "LINE_STUCK_LOW")]
    if rec == "ok":
        return expected_page(ch, prof)
    bad = next((i for i, (_, st) in enumerate(rec) if st != "OK"), None)
    if bad is None:
        return expected_page(ch, prof)
    cmd, st = rec[bad]
    code = -STATUS.index(st)
    if cmd == 0x41:
        return [f"== channel {ch}: no sensor (no answer to the firmware command)"
                if st == "NO_RESPONSE" else f"== channel {ch}: error {code} ({st}) on {WHAT[cmd]}"]
    quick = expected_page(ch, prof, quick=True)   # head, supply, temperature ADC, O2 ADC
    answered = {c for c, s in rec if s == "OK"}
    return [quick[0], f"  error            {code} ({st}) on {WHAT[cmd]}; the page is incomplete"] + \
        [line for c, line in zip((0x42, 0x43, 0x44), quick[1:]) if c in answered]


def check_rig(n, text, got, fails):
    """every page of the rig's n cells: healthy ones against the vectors,
    faulty ones against their records"""
    recs = rig_records(text)
    healthy = []
    for ch, (name, prof, vmap, fault) in enumerate(rig_cells(n)):
        rfault, rec = recs.get(ch, (None, None))
        if rec is None:
            fails.append(f"channel {ch}: no 'rig: page pass' record")
            continue
        if rfault != fault:
            fails.append(f"channel {ch}: the record names fault {rfault}, soc/cells.py {fault}")
            continue
        if fault is None and rec != "ok":
            fails.append(f"channel {ch} ({name}): a healthy cell's answers were not all OK: {rec}")
            continue
        if fault is not None and rec not in ("ok", "stuck"):
            odd = {st for _, st in rec} - {"OK"} - FAULT_STATUS[fault]
            if odd:
                fails.append(f"channel {ch} ({name}): {', '.join(sorted(odd))} from a cell "
                             f"injecting {FAULT_TEXT[fault]}")
        if (rec == "stuck") != (fault == "stuck_low"):
            fails.append(f"channel {ch} ({name}): record {rec!r} for fault {fault}")
            continue
        want = expected_page(ch, prof) if fault is None else faulty_page(ch, prof, rec)
        have = got.get(ch)
        if have != want:
            fails.append(f"channel {ch} ({name}, {FAULT_TEXT.get(fault, 'no fault')}, "
                         f"vector note: {vmap['note']}):\n"
                         + "\n".join(f"  want: {w}" for w in want) + "\n"
                         + "\n".join(f"  got:  {h}" for h in (have or ["(no page)"])))
        elif fault is None:
            healthy.append(ch)
        else:
            print(f"check_page: channel {ch} ({name}, {FAULT_TEXT[fault]}): "
                  f"{len(want)} line{'s' if len(want) > 1 else ''}, as the page tool prints "
                  f"the answers its model recorded"
                  + ("" if len(want) > 1 or rec == "ok" else f": {want[0].split(': ', 1)[1]}"))
    if healthy:
        print(f"check_page: {len(healthy)} healthy cells' pages match the vectors line for line "
              f"(channels {', '.join(map(str, healthy))})")
    if sorted(got) != list(range(n)):
        fails.append(f"pages for channels {sorted(got)}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("log")
    ap.add_argument("--clk-khz", type=int, default=4000)
    ap.add_argument("--channels", type=int, default=3)
    ap.add_argument("--fifo-depth", type=int, default=16)
    ap.add_argument("--no-irq", action="store_true",
                    help="the CPU takes no interrupts (SERV): the driver polled")
    ap.add_argument("--rig", type=int, metavar="N",
                    help="the rig's N cells (make rig), faulty ones held to their records")
    a = ap.parse_args()
    if a.rig:
        a.channels = a.rig
    no_irq = a.no_irq
    text = Path(a.log).read_text()
    fails = []

    head = (f"core: {a.channels} channels, FIFO depth {a.fifo_depth}, {a.clk_khz} kHz, "
            f"version {major_version()}.")
    if not any(line.startswith(head) for line in text.splitlines()):
        fails.append(f"no line starting '{head}'")
    got = pages(text)
    for ch, (name, prof, vmap) in enumerate([] if a.rig else cells()):
        want = expected_page(ch, prof)
        have = got.get(ch)
        if have != want:
            fails.append(f"channel {ch} ({name}, vector note: {vmap['note']}):\n"
                         + "\n".join(f"  want: {w}" for w in want) + "\n"
                         + "\n".join(f"  got:  {h}" for h in (have or ["(no page)"])))
        else:
            print(f"check_page: channel {ch} ({name}): {len(want)} lines match the vector")
    if a.rig:
        check_rig(a.rig, text, got, fails)
    elif sorted(got) != list(range(len(cells()))):
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
    if a.rig:
        print("check_page: PASS: every healthy page matches tb/vectors/, every faulty one "
              "what its cell injected; the interrupt path was used")
        return 0
    print("check_page: PASS: every page matches tb/vectors/, " +
          ("polled, no interrupt" if no_irq else "the interrupt path was used"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
