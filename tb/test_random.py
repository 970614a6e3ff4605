"""Constrained-random regression with functional coverage (issue 6).

Three channels of tb/tb_core.v run random commands at once against modelled
devices (five profiles, swapped in and out), with injected faults and random
legal timing (window edges and inside), plus refused timing writes, factory
protection, pushes to absent channels and flush events. tb/randomtb.py holds
the harness, the generators and the coverage model; docs/random.md describes
both and how to replay a run.

One coverage goal, two buses: the pytest case runs the Wishbone build with
half the commands, then the AXI4-Lite build with the other half, starting
from the Wishbone run's coverage; every bin must be hit by the two together.
(The bins describe the engines and the core; the bus carries every access of
both halves.)

Environment:
  TWH_SEED        seed (default randomtb.DEFAULT_SEED, so CI is
                  deterministic); "random" draws one, printed by both halves
  TWH_RANDOM_N    agent commands of both halves together (default
                  randomtb.DEFAULT_N); flush events add a few
  TWH_RANDOM_BUS  wb or axil: one build only, with all TWH_RANDOM_N commands
  TWH_RANDOM_VERBOSE=1  one log line per checked result

The coverage databases go to build/coverage/ (random-wb.yml after the first
half, random.yml and random.xml for the whole run).
"""
import os
import time

import cocotb
import pytest
from cocotb.simtime import get_sim_time

import randomtb as rt


# The pytest case hands each half its parameters as TWH_RANDOM_RUN_*: the
# cocotb runner lets the parent environment override what it passes, so the
# user-facing names (TWH_SEED, TWH_RANDOM_N) cannot carry per-half values.
def _param(name, user_name=None, default=None):
    return os.environ.get(f"TWH_RANDOM_RUN_{name}") or \
        (os.environ.get(user_name) if user_name else None) or default


@cocotb.test()
async def random_regression(dut):
    run_seed = _param("SEED")
    seed = int(run_seed) if run_seed else rt.seed_from_env()
    n = int(_param("N", "TWH_RANDOM_N", rt.DEFAULT_N))
    cov_in = _param("COV_IN")
    cov_out = _param("COV_OUT", default="random")
    require = _param("REQUIRE", default="1") == "1"
    tb = rt.RandomTB(dut, seed, n)
    bus = "wb" if tb.bus_kind == 0 else "axil"
    log = dut._log.info
    log("random regression on %s: TWH_SEED=%d, %d agent commands%s", bus, seed, n,
        f", continuing the coverage of {cov_in}" if cov_in else "")
    if cov_in:
        rt.load_coverage(cov_in)
        top = rt.coverage_db[rt.COV]
        log("%d of %d bins already hit by the earlier half", top.coverage, top.size)
    wall0, cpu0 = time.perf_counter(), time.process_time()
    await tb.start()
    try:
        await tb.run()
    finally:
        wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
        sim_ms = get_sim_time("ms")
        res = tb.stats.results
        by_status = {}
        for x, r in res:
            name = rt.STATUS_NAMES[r.status] if r.status < len(rt.STATUS_NAMES) else str(r.status)
            by_status[name] = by_status.get(name, 0) + 1
        log("TWH_SEED=%d on %s: %d results checked (%d agent commands, %d agent commands "
            "on the line), %s", seed, bus, len(res), tb.issued, tb.stats.line,
            ", ".join(f"{k} {v}" for k, v in sorted(by_status.items())))
        log("%d profile swaps, %d refused timing writes, %d bad-channel pushes, flushes %s, "
            "%d phase durations checked on the line, %d bad stop bits read as a break",
            tb.stats.swaps, tb.stats.refused, tb.stats.bad_channel, tb.stats.flushes,
            tb.stats.corners_checked, tb.stats.breaks)
        # the simulator process's CPU time (the simulator and Python share it) is
        # what the wall time would be on an idle machine
        log("simulated %.1f ms in %.1f s wall, %.1f s CPU (%.3f CPU s per simulated ms)",
            sim_ms, wall, cpu, cpu / max(sim_ms, 1e-9))
        path = rt.export_coverage(cov_out)
        log("coverage database: %s (and .xml)%s", path,
            " - both halves" if cov_in else "")
        rt.bins_table(log)
        missing = rt.coverage_report(log)
    if require:
        assert not missing, (f"{len(missing)} coverage bin(s) unhit with TWH_SEED={seed} "
                             f"TWH_RANDOM_N={n}: {missing}")


# ============================================================== pytest
import simrun  # noqa: E402

# 4 MHz, the lowest clock the core takes, is the cheapest to simulate; the
# clock range is test_twh_link.py::clock_conformance's business
CLK_HZ = 4_000_000


def _run(bus, n, seed, cov_out, cov_in=None, require=True, build="random", sim="icarus",
         name=None, seed_name=None):
    env = {"TWH_BUS": str(bus), "TWH_CHANNELS": "3", "TWH_FIFO_DEPTH": "16",
           "TWH_CLK_HZ": str(CLK_HZ), "TWH_RANDOM_RUN_SEED": str(seed),
           "TWH_RANDOM_RUN_N": str(n), "TWH_RANDOM_RUN_COV_OUT": cov_out,
           "TWH_RANDOM_RUN_REQUIRE": "1" if require else "0"}
    if cov_in:
        env["TWH_RANDOM_RUN_COV_IN"] = str(cov_in)
    name = name or f"{build}_{'wb' if bus == 0 else 'axil'}"
    simrun.run("tb_core", "test_random", name,
               parameters={"CLK_HZ": CLK_HZ, "CHANNELS": 3, "FIFO_DEPTH": 16, "BUS": bus},
               testcase="random_regression", tb_sources=["tb_core.v"], extra_env=env, sim=sim,
               seed_name=seed_name)


# make test's run: one seed (TWH_SEED, else the default), QUICK_N agent
# commands on the Wishbone build. Every result is checked as in the full
# run; coverage is written and reported but not required (a third of the
# commands cannot hit every bin: test_random, in make test-slow, requires
# them all).
QUICK_N = 10


# It runs on Verilator, on the build test_twh_core's cases share; make
# test-slow runs it on Icarus too and requires the same transcript.
def _one_seed(sim="verilator", name=None, seed_name="random_quick_wb"):
    _run(0, QUICK_N, rt.seed_from_env(), "random-quick", require=False, build="random_quick",
         sim=sim, name=name, seed_name=seed_name)


def test_random_one_seed():
    _one_seed()


@pytest.mark.slow
def test_random_one_seed_both():
    simrun.same_on_both(_one_seed, "random_quick_wb")


# The full run is on Verilator, on the build test_twh_core's Wishbone cases
# share and one AXI4-Lite build: on Icarus the two halves took four times
# as long (277 s against 70 s with the build); test_random_one_seed_both
# holds the two simulators to the same transcript.
@pytest.mark.slow
def test_random():
    # TWH_SEED=random is resolved here, once, so both halves use (and print) it
    seed = rt.seed_from_env()
    n = int(os.environ.get("TWH_RANDOM_N") or rt.DEFAULT_N)
    only = os.environ.get("TWH_RANDOM_BUS", "").strip().lower()
    if only:
        _run({"wb": 0, "axil": 1}[only], n, seed, f"random-{only}", sim="verilator")
        return
    n_wb = n // 2
    _run(0, n_wb, seed, "random-wb", require=False, sim="verilator")
    _run(1, n - n_wb, seed, "random",
         cov_in=rt.ROOT / "build" / "coverage" / "random-wb.yml", sim="verilator")
