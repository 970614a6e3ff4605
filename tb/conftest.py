# pytest configuration: the test-bench modules live in tb/ and are imported
# by name, both here and inside the simulator (cocotb imports the test module
# in the simulator process, which inherits PYTHONPATH).
import os
import signal
import sys
from pathlib import Path

import pytest

TB_DIR = Path(__file__).resolve().parent
if str(TB_DIR) not in sys.path:
    sys.path.insert(0, str(TB_DIR))
os.environ["PYTHONPATH"] = os.pathsep.join(
    p for p in (str(TB_DIR), os.environ.get("PYTHONPATH", "")) if p)


# Time budgets (wall seconds, on the project's machine with both cores busy,
# as make test runs them): a test that passes over its budget is failed, so
# a slow-down breaks the build the day it happens instead of creeping into
# CI's limit; one still running at HANG_FACTOR times its budget is stopped.
# Each budget is about three times what the test takes on a normal day
# (docs/verification.md has the figures), so a machine running slow for a
# day does not fail the build but a test that grew does; the longest tests
# of make test (about 55 s) use BUDGET_S, a longer one states its own with
# @pytest.mark.budget(seconds).
BUDGET_S = 180
SLOW_BUDGET_S = 900
HANG_FACTOR = 2

# Scheduled first, longest first, so that pytest-xdist does not start a long
# run on one core while the other has nothing left to do. The first two
# start the two Verilator builds most tests share (tb/simrun.py: the bus
# core's, with the Verilator runtime, then the engine's, which waits for
# that runtime on its lock while the first build compiles it on both
# cores). test_netlist.py's first case goes before them all and its others
# last (below): all four first, both cores started on its one netlist.
LONG_MODULES = ("test_random.py", "test_twh_link.py", "test_twh_core.py", "test_twh_engine.py",
                "test_cosim.py", "test_board_top.py")


def pytest_configure(config):
    # `slow`: long end-to-end runs kept out of `make test` (its budget is
    # 5 minutes on two cores); `make test-slow` runs them, and .ci/run
    # runs it after `make test`.
    config.addinivalue_line("markers", "slow: long end-to-end run, make test-slow (in CI)")
    config.addinivalue_line("markers", "budget(seconds): this test's own wall-time budget")


def pytest_collection_modifyitems(config, items):
    # test_netlist.py (make test-slow): its first case goes first of all,
    # its others last. The first builds the netlist (Yosys, then Verilator)
    # while the other worker runs test_random; the others find it built.
    # Last together, one case built it while the other waited on its lock,
    # its core idle through Yosys and the verilating.
    netlist = [i for i in items if Path(str(i.fspath)).name == "test_netlist.py"]

    def rank(item):
        name = Path(str(item.fspath)).name
        if name == "test_netlist.py":
            return -1 if item is netlist[0] else len(LONG_MODULES) + 1
        return LONG_MODULES.index(name) if name in LONG_MODULES else len(LONG_MODULES)
    items.sort(key=rank)    # stable: the order inside a module stays


def budget_of(item):
    mark = item.get_closest_marker("budget")
    if mark is not None:
        return float(mark.args[0])
    return SLOW_BUDGET_S if item.get_closest_marker("slow") else BUDGET_S


class _Hang(Exception):
    pass


def _on_alarm(signum, frame):
    raise _Hang("stopped: still running at its hang limit")


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_call(item):
    limit = max(1, int(budget_of(item) * HANG_FACTOR))
    old = signal.signal(signal.SIGALRM, _on_alarm)
    signal.alarm(limit)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    report = outcome.get_result()
    if call.when == "call" and report.passed:
        budget = budget_of(item)
        if report.duration > budget:
            report.outcome = "failed"
            report.longrepr = (f"{item.nodeid} passed but took {report.duration:.1f} s, over its "
                               f"budget of {budget:.0f} s (tb/conftest.py)")
