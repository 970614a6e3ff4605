"""Runs the demo session (tb/demo_session.py: the C driver, co-simulated with
the Wishbone core) and writes build/demo/demo.vcd with every channel's
line_o, line_oe and line, plus a GTKWave save file."""
import shutil
import subprocess
import sys
from pathlib import Path

TB = Path(__file__).resolve().parent
sys.path.insert(0, str(TB))
import conftest  # noqa: E402,F401  (sets PYTHONPATH for the simulator)
import simrun  # noqa: E402

out_dir = simrun.ROOT / "build" / "demo"
out_dir.mkdir(parents=True, exist_ok=True)
vcd = out_dir / "demo.vcd"
subprocess.run(["make", "-s", "-C", str(simrun.ROOT / "sw"), "shared"], check=True)
simrun.run("tb_core", "demo_session", "demo",
           parameters={"CLK_HZ": 4_000_000, "CHANNELS": 3, "FIFO_DEPTH": 16, "BUS": 0},
           tb_sources=["tb_core.v"], plusargs=[f"+vcd={vcd}"], vcd=True,
           extra_env={"COCOTB_LOG_LEVEL": "WARNING", "GPI_LOG_LEVEL": "WARNING",
                      "TWH_CLK_HZ": "4000000", "TWH_CHANNELS": "3",
                      "TWH_FIFO_DEPTH": "16", "TWH_BUS": "0"})
shutil.copy(TB / "demo.gtkw", out_dir / "demo.gtkw")
print(f"\nwaveform: {vcd} (make waves opens it in GTKWave)")
