"""Builds and runs a cocotb test module on Icarus Verilog (cocotb runner).

Each pytest case gets its own build directory so that pytest-xdist workers
never share one. The random seed of every run is printed by cocotb
("Seeding Python random module with N") and can be replayed with
COCOTB_RANDOM_SEED=N.
"""
import os
from pathlib import Path

from cocotb_tools.runner import get_results, get_runner

ROOT = Path(__file__).resolve().parents[1]
RTL_DIR = ROOT / "rtl"
TB_DIR = ROOT / "tb"


def rtl_sources():
    return sorted(RTL_DIR.glob("*.v"))


def run(toplevel, test_module, name, *, parameters=None, testcase=None,
        tb_sources=(), plusargs=(), extra_env=None):
    build_dir = ROOT / "build" / "sim" / name
    runner = get_runner("icarus")
    runner.build(
        sources=[*rtl_sources(), *(TB_DIR / s for s in tb_sources)],
        includes=[RTL_DIR],
        hdl_toplevel=toplevel,
        parameters=parameters or {},
        build_dir=build_dir,
        timescale=("1ns", "1ps"),
        always=True,
    )
    env = {"PYTHONPATH": os.environ.get("PYTHONPATH", str(TB_DIR))}
    env.update(extra_env or {})
    seed = os.environ.get("COCOTB_RANDOM_SEED")
    results = runner.test(
        hdl_toplevel=toplevel,
        test_module=test_module,
        testcase=testcase,
        build_dir=build_dir,
        test_dir=build_dir,
        plusargs=list(plusargs),
        extra_env=env,
        seed=seed,
    )
    # Under pytest the runner raises on failures itself; outside (make demo)
    # it only returns the results file, so check it here in both cases.
    n_tests, n_failed = get_results(results)
    if n_tests == 0 or n_failed:
        raise RuntimeError(f"{name}: {n_failed} of {n_tests} cocotb tests failed")
    return results
