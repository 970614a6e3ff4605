"""Runs the demo session (tb/demo_session.py) and writes build/demo/demo.vcd
with the host's line_o, line_oe and line_i, plus a GTKWave save file."""
import shutil
import sys
from pathlib import Path

TB = Path(__file__).resolve().parent
sys.path.insert(0, str(TB))
import conftest  # noqa: E402,F401  (sets PYTHONPATH for the simulator)
import simrun  # noqa: E402

out_dir = simrun.ROOT / "build" / "demo"
out_dir.mkdir(parents=True, exist_ok=True)
vcd = out_dir / "demo.vcd"
simrun.run("tb_link", "demo_session", "demo", parameters={"CLK_HZ": 12_000_000},
           tb_sources=["tb_link.v"], plusargs=[f"+vcd={vcd}"], vcd=True,
           extra_env={"COCOTB_LOG_LEVEL": "WARNING", "GPI_LOG_LEVEL": "WARNING"})
shutil.copy(TB / "demo.gtkw", out_dir / "demo.gtkw")
print(f"\nwaveform: {vcd} (make waves opens it in GTKWave)")
