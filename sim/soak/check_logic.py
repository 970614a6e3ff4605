"""Replays the frames the soak's C++ device model handled (soak
--trace-logic FILE) through tb/periph_model.py's PeripheralLogic, one device
per channel, and fails on the first answer that differs. The soak checks the
core and the driver against the C++ model; this checks the C++ model against
the Python one every cocotb test uses.

usage: check_logic.py TRACE
"""
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tb"))
import profiles  # noqa: E402
from periph_model import PeripheralLogic  # noqa: E402


def main(path):
    devices = {}
    n = answered = 0
    for lineno, line in enumerate(Path(path).read_text().splitlines(), 1):
        if not line or line.startswith("#"):
            continue
        head, answer = line.split(" -> ")
        ch, name, *frame = head.split()
        frame = bytes(int(b, 16) for b in frame)
        dev = devices.setdefault(ch, PeripheralLogic(profiles.PROFILES[name]))
        want = dev.handle(frame)
        got = None if answer.strip() == "-" else bytes(int(b, 16) for b in answer.split())
        if (want[:2] if want else None) != got:
            sys.exit(f"{path}:{lineno}: ch{ch} {name} frame {frame.hex(' ')}: C++ answered "
                     f"{got.hex(' ') if got else 'nothing'}, Python {want.hex(' ') if want else 'nothing'} "
                     f"({dev.log[-1].reason})")
        n += 1
        answered += want is not None
    if n == 0:
        sys.exit(f"{path}: no frames")
    print(f"device logic: {n} frames on {len(devices)} devices, {answered} answers, "
          "C++ and Python agree on every one")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
