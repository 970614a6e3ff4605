#!/usr/bin/env python3
"""GTKWave translate process filter: the bytes on a 2-wire line, named.

GTKWave starts this once and then writes one value per line on its stdin,
as the trace shows it (hexadecimal, with a leading "$" when View > Show
Base Symbols is on); each value gets exactly one line of text back, flushed
at once, or GTKWave would wait for it forever.

What a value means depends on its width:
- 6 hex digits: the `mon_word_N` of tb/tb_core.v's byte monitor (the byte,
  its direction, its place in the frame, the frame's command byte and the
  checksum verdict; the layout is documented at tb_bytemon). Shown like the
  sigrok decoder's byte row: "H: 41 FIRMWARE", "H: AA arg", "H: 14 chk OK"
  from the host, "P: 12 FIRMWARE MSB", "P: 01 LSB", "P: EC chk OK" from the
  peripheral.
- 1 or 2 hex digits: a command byte, e.g. tb_link's s_cmd_code or m_res_code:
  "41 FIRMWARE".
Anything else (X, Z, other widths) is passed back unchanged.

A "?colour?" prefix colours the value in GTKWave's wave window.
The command names come from tb/protocol.py, the one Python copy of the
protocol rules; this script finds it relative to its own location.
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tb"))
from protocol import command_name  # noqa: E402

COLOUR_HOST = "?RoyalBlue?"
COLOUR_PERIPH = "?SeaGreen?"
COLOUR_BAD = "?red3?"
ADDRESSED = ("READ", "FIND_FREE", "ERASE")     # the payload byte is an address


def describe_word(w: int) -> str:
    """Text for one 24-bit byte-monitor word (tb_bytemon in tb/tb_core.v)."""
    if not w & (1 << 20):
        return "-"                                # no byte decoded yet
    byte, cmd, idx = w & 0xFF, (w >> 8) & 0xFF, (w >> 16) & 0x3
    stop_err = bool(w & (1 << 18))
    periph, last, chk_ok = bool(w & (1 << 21)), bool(w & (1 << 22)), bool(w & (1 << 23))
    name = command_name(cmd)
    if last:
        role = "chk " + ("OK" if chk_ok else "BAD")
    elif periph:
        role = f"{name} MSB" if idx == 0 else "LSB"
    elif idx == 0:
        role = name
    elif cmd >= 0x80:
        role = "data MSB" if idx == 1 else "data LSB"
    elif name in ADDRESSED:
        role = f"addr {(cmd & 1) << 8 | byte:03X}"
    else:
        role = "arg"
    text = f"{'P' if periph else 'H'}: {byte:02X} {role}"
    if stop_err:
        text += " FRAMING"
    bad = stop_err or (last and not chk_ok)
    return (COLOUR_BAD if bad else COLOUR_PERIPH if periph else COLOUR_HOST) + text


def translate(value: str) -> str:
    """One GTKWave value (a line of stdin) to its text."""
    digits = value.strip()
    if digits.startswith("$"):
        digits = digits[1:]
    try:
        v = int(digits, 16)
    except ValueError:
        return value.strip()                      # X, Z or mixed: leave it
    if len(digits) == 6:
        return describe_word(v)
    if len(digits) <= 2:
        return f"{v:02X} {command_name(v)}"
    return value.strip()


def main() -> None:
    while True:
        line = sys.stdin.readline()
        if not line:
            return
        sys.stdout.write(translate(line) + "\n")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
