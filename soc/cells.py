"""The three modelled cells of the LiteX drop-in proof (docs/soc.md): the
flash images of the shared vectors (tb/vectors/flash_o2.json,
flash_co2.json) in devices whose firmware byte, type and raw readings come
from tb/profiles.py. The rig (make rig, docs/rig.md) takes N cells from
them: the three in turn, each with a serial of its own, and every fifth,
from channel 4, injecting one of the soak's faults.

    cells.py OUT.h            the C++ header the soak's peripheral model
                              (sim/soak/periph.cpp) takes its devices from,
                              written by sim/soak/gen_profiles.py itself
    cells.py --rig N OUT.h    the same for the rig's N cells, with their
                              faults (RIG_FAULT, RIG_FAULT_RATE)
"""
import dataclasses
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
VECTORS = ROOT / "tb" / "vectors"
sys.path.insert(0, str(ROOT / "tb"))
sys.path.insert(0, str(ROOT / "sim" / "soak"))
import flashmap as fm  # noqa: E402
import profiles  # noqa: E402

# channel -> (profile for firmware/type/readings, vector file, map index)
CELLS = [("o2_v18", "flash_o2", 0),    # 240 words, records after a wrap
         ("o2_v15", "flash_o2", 1),    # 128 words, v15 (execute 4 ms)
         ("co2", "flash_co2", 0)]      # CO2 sensor, 3 calibrations


def vector_map(vfile, index):
    return json.loads((VECTORS / f"{vfile}.json").read_text())["maps"][index]


def cells():
    """[(name, Profile with the vector's image, the vector's map)]"""
    out = []
    for prof, vfile, index in CELLS:
        m = vector_map(vfile, index)
        name = f"{prof}+{vfile}[{index}]"
        pr = dataclasses.replace(profiles.PROFILES[prof], name=name, flash=tuple(m["words"]))
        out.append((name, pr, m))
    return out


def register():
    """Adds the cells to profiles.PROFILES under their names (the cocotb
    benches take cells by name); returns the names, channel by channel."""
    table = {name: pr for name, pr, _ in cells()}
    profiles.PROFILES.update(table)
    return list(table)


# ------------------------------------------------------------------ the rig
# Faults, by the names the rig's harness knows (sim/soak/soak_main.cpp):
# the soak's four answer faults (sim/soak/periph.h) and a line held low
# (tb/tb_line.v's stuck-line fault). A faulty cell injects its fault on
# RIG_FAULT_RATE of its answers (a stuck line: on every transaction).
RIG_FAULTS = ("checksum", "silent", "stuck_low", "stopbit", "short")
FAULT_TEXT = {"checksum": "bad checksum", "silent": "no response",
              "stuck_low": "line stuck low", "stopbit": "stop bit 0",
              "short": "short answer"}
RIG_FAULT_FIRST, RIG_FAULT_EVERY = 4, 5
RIG_FAULT_RATE = 0.1


def rig_fault(ch):
    """the fault of the rig's cell on channel ch, or None"""
    if ch < RIG_FAULT_FIRST or (ch - RIG_FAULT_FIRST) % RIG_FAULT_EVERY:
        return None
    return RIG_FAULTS[(ch - RIG_FAULT_FIRST) // RIG_FAULT_EVERY % len(RIG_FAULTS)]


def rig_serial(vmap, ch):
    """the vector's serial with its last two characters the channel number"""
    return vmap["description"]["serial"][:-2] + f"{ch:02d}"


def rig_cells(n):
    """[(name, Profile, the vector's map, fault or None)] for channels 0..n-1:
    the three cells above in turn, each image the vector's with its own
    serial (words 0x10-0x15, the vector's text padding)"""
    out = []
    base = cells()
    for ch in range(n):
        name, pr, m = base[ch % len(base)]
        serial = rig_serial(m, ch)
        flash = list(pr.flash)
        flash[fm.SERIAL_ADDR:fm.SERIAL_ADDR + fm.SERIAL_WORDS] = fm.encode_text(
            serial, fm.SERIAL_WORDS, m["description"]["text_pad"])
        rp = dataclasses.replace(pr, name=f"{name}#{ch:02d}", flash=tuple(flash))
        out.append((rp.name, rp, m, rig_fault(ch)))
    return out


def main(argv):
    import gen_profiles
    if len(argv) == 1:
        gen_profiles.main(argv[0], register())
        return
    if len(argv) != 3 or argv[0] != "--rig" or not 1 <= int(argv[1]) <= 32:
        sys.exit(__doc__)
    n, out_h = int(argv[1]), argv[2]
    rig = rig_cells(n)
    profiles.PROFILES.update({name: pr for name, pr, _, _ in rig})
    gen_profiles.main(out_h, [name for name, _, _, _ in rig])
    faults = ", ".join(f'"{f or ""}"' for _, _, _, f in rig)
    with open(out_h, "a") as f:
        f.write(f"\n// the rig's faults, channel by channel (soc/cells.py)\n"
                f"#define SOAK_RIG_CELLS {n}\n"
                f"#define RIG_FAULT_RATE {RIG_FAULT_RATE}\n"
                f"static const char *const RIG_FAULT[{n}] = {{{faults}}};\n")


if __name__ == "__main__":
    main(sys.argv[1:])
