#!/usr/bin/env python3
"""Resources and Fmax of the time-shared engine (rtl/twh_engine.v) alone, at
1 to 32 channels, with the project's flow (scripts/synth.py): the figures
behind docs/engine.md's prototype table.

    bench_engine.py [--parts hx8k up5k ecp5-25f] [--channels 1 3 8 16 32] [--seeds 1]

The engine is placed inside scripts/bench/twh_engine_bench.v (its ports
behind a shift register, so 32 lines fit the pins); the harness is the same
at every channel count, so the slope between two counts is the engine's
own. Prints one row per part and count (logic cells, LUT4s, flip-flops,
block RAMs, Fmax: the median of the seeds) and the slope from 8 to 32
channels. Figures, not a test: nothing here passes or fails.
"""
import argparse
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from synth import synth  # noqa: E402

FILES = ["rtl/twh_engine.v", "rtl/twh_engine_pin.v", "rtl/twh_ram.v", "rtl/twh_sync2.v",
         "rtl/twh_checksum.v", "rtl/twh_rx_dec.v", "rtl/twh_rx_sum.v", "rtl/twh_rx_step.v", "rtl/twh_carrier.v", "scripts/bench/twh_engine_bench.v"]
TARGET = {"hx8k": 100.0, "up5k": 48.0, "ecp5-25f": 160.0, "ecp5-85f": 160.0}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--parts", nargs="+", default=["hx8k"])
    ap.add_argument("--channels", nargs="+", type=int, default=[1, 3, 8, 16, 32])
    ap.add_argument("--seeds", type=int, default=1)
    ap.add_argument("--clk-hz", type=int, default=48_000_000)
    a = ap.parse_args()
    print(f"{'part':9} {'ch':>3} {'LC':>6} {'LUT4':>6} {'FF':>6} {'RAM':>4} {'Fmax MHz':>9}  seeds")
    for part in a.parts:
        rows = {}
        for n in a.channels:
            # block RAM at every depth on the iCE40s (no LUT RAM there);
            # LUT RAM at every depth on the ECP5 (RAM_BLOCK = 0)
            params = {"CHANNELS": n, "CLK_HZ": a.clk_hz,
                      "RAM_BLOCK": 0 if part.startswith("ecp5") else 1}
            runs = [synth(part, "twh_engine_bench", params, FILES,
                          TARGET[part], f"build/bench-engine/{part}-{n}-s{s}", seed=s)
                    for s in range(1, a.seeds + 1)]
            r = runs[0]
            fmax = statistics.median(x["fmax"] for x in runs)
            rows[n] = r
            print(f"{part:9} {n:>3} {r['logic']:>6} {r['lut']:>6} {r['ff']:>6} {r['ram']:>4} "
                  f"{fmax:>9.1f}  {' '.join(str(x['fmax']) for x in runs)}"
                  + ("" if r["yosys_warnings"] == 0 else f"  ({r['yosys_warnings']} Yosys warnings)"),
                  flush=True)
        if 8 in rows and 32 in rows:
            slope = (rows[32]["logic"] - rows[8]["logic"]) / 24
            print(f"{part:9} slope 8 -> 32 channels: {slope:.1f} logic cells a channel, "
                  f"{rows[32]['ram'] - rows[8]['ram']} block RAMs more")


if __name__ == "__main__":
    main()
