#!/usr/bin/env python3
"""Runs make targets as timed stages and ends with each stage's wall time.

    scripts/stages.py [--jobs N] [--title T] GROUP [GROUP ...]

A GROUP is one target, or several joined by '+': the targets of a group run
side by side (at most N at once), each into its own log under
build/stages/, and each log is printed whole when its target ends, so two
outputs never interleave; a group of one target streams its output as it
runs. The groups run one after the other; the first failing group stops the
run (after its other targets finish), and the table is printed either way,
so a slow-down or a failure shows with its stage on the day it happens.
"""
import argparse
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LOGS = ROOT / "build" / "stages"


def make_cmd(target):
    return [os.environ.get("MAKE", "make"), "--no-print-directory", "-C", str(ROOT), target]


def run_streamed(target):
    t0 = time.monotonic()
    rc = subprocess.call(make_cmd(target))
    return target, rc, time.monotonic() - t0


def run_logged(target):
    LOGS.mkdir(parents=True, exist_ok=True)
    log = LOGS / f"{target}.log"
    t0 = time.monotonic()
    with open(log, "wb") as f:
        rc = subprocess.call(make_cmd(target), stdout=f, stderr=subprocess.STDOUT)
    dt = time.monotonic() - t0
    # one write per log: the other lane's output never lands inside it
    text = f"==== {target} ({dt:.1f} s, exit {rc}) ====\n" + log.read_text(errors="replace")
    sys.stdout.write(text if text.endswith("\n") else text + "\n")
    sys.stdout.flush()
    return target, rc, dt


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--title", default="stages")
    ap.add_argument("groups", nargs="+")
    args = ap.parse_args()

    rows = []
    t_all = time.monotonic()
    failed = None
    for group in args.groups:
        targets = [t for t in group.split("+") if t]
        if len(targets) == 1:
            rows.append(run_streamed(targets[0]))
        else:
            with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
                rows += list(pool.map(run_logged, targets))
        bad = [t for t, rc, _ in rows if rc != 0]
        if bad:
            failed = bad
            break
    total = time.monotonic() - t_all

    print(f"\n{args.title}: wall time per stage")
    for target, rc, dt in rows:
        print(f"  {target:<16} {dt:8.1f} s  {'ok' if rc == 0 else f'FAILED (exit {rc})'}")
    print(f"  {'total':<16} {total:8.1f} s")
    if failed:
        print(f"{args.title}: failed: {' '.join(failed)}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
