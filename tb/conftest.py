# pytest configuration: the test-bench modules live in tb/ and are imported
# by name, both here and inside the simulator (cocotb imports the test module
# in the simulator process, which inherits PYTHONPATH).
import os
import sys
from pathlib import Path

TB_DIR = Path(__file__).resolve().parent
if str(TB_DIR) not in sys.path:
    sys.path.insert(0, str(TB_DIR))
os.environ["PYTHONPATH"] = os.pathsep.join(
    p for p in (str(TB_DIR), os.environ.get("PYTHONPATH", "")) if p)


def pytest_configure(config):
    # `slow`: long end-to-end runs kept out of `make test` (its budget is
    # 10 minutes on two cores); `make test-slow` runs them, and .ci/run
    # runs it after `make test`.
    config.addinivalue_line("markers", "slow: long end-to-end run, make test-slow (in CI)")
