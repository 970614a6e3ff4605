"""`make demo`: two halves, run side by side on the two cores.

- The sensor pages: the C driver's page tool (sw/tools/twh_page.c, what
  twh_cli and the LiteX SoC run) on the Verilated Wishbone core, three cells
  on the lines (build/demo/soak_cells: the soak harness in --page mode, with
  the SoC's cells). soc/check_page.py holds every page to the shared vectors
  and the interrupt waits to the interrupt; the harness holds every phase on
  the lines to the spec's table.
- The waveform: a shorter session of the same driver co-simulated with the
  core on Icarus (tb/demo_session.py), every transaction checked by the
  cocotb spec monitors, written to build/demo/demo.vcd beside a GTKWave save
  file (make waves).

Exits non-zero if either half fails.
"""
import shutil
import subprocess
import sys
from pathlib import Path

TB = Path(__file__).resolve().parent
sys.path.insert(0, str(TB))
import conftest  # noqa: E402,F401  (sets PYTHONPATH for the simulator)
import simrun  # noqa: E402

ROOT = simrun.ROOT
out_dir = ROOT / "build" / "demo"
out_dir.mkdir(parents=True, exist_ok=True)
vcd = out_dir / "demo.vcd"
page_txt = out_dir / "page.txt"
subprocess.run(["make", "-s", "-C", str(ROOT), "build/demo/soak_cells"], check=True)
subprocess.run(["make", "-s", "-C", str(ROOT / "sw"), "shared"], check=True)

with open(page_txt, "w") as f:
    page = subprocess.Popen([str(out_dir / "soak_cells"), "--page"], stdout=f,
                            stderr=subprocess.STDOUT, cwd=ROOT)
wave_err = None
print("== the waveform session (Icarus, cocotb spec monitors): build/demo/demo.vcd", flush=True)
try:
    simrun.run("tb_core", "demo_session", "demo",
               parameters={"CLK_HZ": 4_000_000, "CHANNELS": 3, "FIFO_DEPTH": 16, "BUS": 0},
               tb_sources=["tb_core.v"], plusargs=[f"+vcd={vcd}"], vcd=True,
               extra_env={"COCOTB_LOG_LEVEL": "WARNING", "GPI_LOG_LEVEL": "WARNING",
                          "TWH_CLK_HZ": "4000000", "TWH_CHANNELS": "3",
                          "TWH_FIFO_DEPTH": "16", "TWH_BUS": "0"})
except RuntimeError as exc:
    wave_err = exc
page_rc = page.wait()

print("\n== the sensor pages (C driver on the Verilated core): build/demo/page.txt", flush=True)
print(page_txt.read_text(), end="", flush=True)
check = subprocess.run([sys.executable, str(ROOT / "soc" / "check_page.py"), str(page_txt)])
shutil.copy(TB / "demo.gtkw", out_dir / "demo.gtkw")
print(f"\nwaveform: {vcd} (make waves opens it in GTKWave)")
fails = [what for what, bad in (("the waveform session", wave_err is not None),
                                ("the page run", page_rc != 0),
                                ("the page check", check.returncode != 0)) if bad]
if fails:
    sys.exit("demo: FAIL: " + ", ".join(fails) + (f" ({wave_err})" if wave_err else ""))
print("demo: PASS")
