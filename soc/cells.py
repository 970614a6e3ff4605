"""The three modelled cells of the LiteX drop-in proof (docs/soc.md): the
flash images of the shared vectors (tb/vectors/flash_o2.json,
flash_co2.json) in devices whose firmware byte, type and raw readings come
from tb/profiles.py.

    cells.py OUT.h     the C++ header the soak's peripheral model
                       (sim/soak/periph.cpp) takes its devices from, written
                       by sim/soak/gen_profiles.py itself
"""
import dataclasses
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
VECTORS = ROOT / "tb" / "vectors"
sys.path.insert(0, str(ROOT / "tb"))
sys.path.insert(0, str(ROOT / "sim" / "soak"))
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


def main(out_h):
    import gen_profiles
    gen_profiles.main(out_h, register())


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
