"""Builds and runs a cocotb test module on Icarus Verilog (cocotb runner).

Each pytest case gets its own build directory so that pytest-xdist workers
never share one. The random seed of every run is printed by cocotb
("Seeding Python random module with N") and can be replayed with
COCOTB_RANDOM_SEED=N.
"""
import os
from pathlib import Path

from cocotb_tools.runner import Icarus, get_results, get_runner

ROOT = Path(__file__).resolve().parents[1]
RTL_DIR = ROOT / "rtl"
TB_DIR = ROOT / "tb"


class _IcarusVcd(Icarus):
    """The cocotb runner passes vvp `-none` (no waveform) unless it dumps an
    FST of everything itself; this one lets the test bench's own $dumpfile
    write a small VCD of chosen signals instead."""

    def _test_command(self):
        return [["-vcd" if arg == "-none" else arg for arg in cmd]
                for cmd in super()._test_command()]


def rtl_sources():
    return sorted(RTL_DIR.glob("*.v"))


def run(toplevel, test_module, name, *, parameters=None, testcase=None,
        tb_sources=(), plusargs=(), extra_env=None, vcd=False):
    build_dir = ROOT / "build" / "sim" / name
    runner = _IcarusVcd() if vcd else get_runner("icarus")
    runner.build(
        # tb_line.v (the simulated line) serves every test-bench top
        sources=[*rtl_sources(), TB_DIR / "tb_line.v", *(TB_DIR / s for s in tb_sources)],
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
    # The runner lets the parent environment override extra_env, so a
    # variable exported in the shell would silently replace what the test
    # asked for: put the test's values into the environment for the run.
    saved = {k: os.environ.get(k) for k in env}
    os.environ.update(env)
    try:
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
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
    # Under pytest the runner raises on failures itself; outside (make demo)
    # it only returns the results file, so check it here in both cases.
    n_tests, n_failed = get_results(results)
    if n_tests == 0 or n_failed:
        raise RuntimeError(f"{name}: {n_failed} of {n_tests} cocotb tests failed")
    return results
