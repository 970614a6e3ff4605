"""The waveform view of `make demo` / `make waves` (docs/waves.md).

- The byte monitor of tb/tb_core.v (tb_bytemon) decodes what travels on a
  line: a short tb_core simulation sends known command frames to a modelled
  O2 cell, and the monitor's words must match the frames (compared with
  protocol.py and with the spec monitor's independent decoding) and the
  answer (with the result the core returned), checksum verdicts included.
- tb/demo.gtkw names only signals that exist in the VCD tb_core writes (the
  same simulation writes one), and its filter paths resolve to the files in
  tools/gtkwave/ from where `make demo` puts the save file.
- tools/gtkwave/twh_phase.txt names every phase code of rtl/twh_defs.vh.
- tools/gtkwave/twh_bytes.py, run as GTKWave runs it (a pipe, one value in,
  one line out), names known words and command bytes, and turns the
  monitor's words from the VCD into the expected texts.
"""
import os
import re
import subprocess
from pathlib import Path, PurePosixPath

import cocotb

import protocol as p

ROOT = Path(__file__).resolve().parents[1]
SAVE_FILE = ROOT / "tb" / "demo.gtkw"
PHASE_FILTER = ROOT / "tools" / "gtkwave" / "twh_phase.txt"
BYTES_FILTER = ROOT / "tools" / "gtkwave" / "twh_bytes.py"
DEFS = ROOT / "rtl" / "twh_defs.vh"
CELL = "o2_v18"
WRITE_ADDR, WRITE_DATA = 0x40, 0x1234
# the shortest in-spec transaction keeps the simulation short
SHORT = dict(charge=7000, sync=900, preamble=1800, execute=3500, listen=2000,
             turnaround=2000)


def word_fields(w):
    """tb_bytemon's word, unpacked (layout: the comment at tb_bytemon)."""
    return dict(byte=w & 0xFF, cmd=(w >> 8) & 0xFF, idx=(w >> 16) & 3,
                stop_err=(w >> 18) & 1, valid=(w >> 20) & 1, periph=(w >> 21) & 1,
                last=(w >> 22) & 1, chk_ok=(w >> 23) & 1)


def pack_word(byte, cmd, idx, periph=0, last=0, chk_ok=0, stop_err=0):
    return (chk_ok << 23 | last << 22 | periph << 21 | 1 << 20 | stop_err << 18
            | idx << 16 | cmd << 8 | byte)


def expected_words(frame, cmd, periph, chk_ok=True):
    """The words a whole frame must give."""
    n = len(frame)
    return [pack_word(b, cmd, i, periph, int(i == n - 1), int(i == n - 1 and chk_ok))
            for i, b in enumerate(frame)]


# ====================================================== in the simulator
@cocotb.test()
async def bytemon_frames(dut):
    """Two transactions on channel 0: FIRMWARE, answered with a corrupted
    checksum (so both verdicts show: the command's good, the answer's bad),
    then a WRITE (4-byte frame, no answer) with lab-short phases: a
    peripheral answers only after real spec timing, which costs simulation
    time (~7 ms of simulated line per second here)."""
    from coretb import CoreTB
    from periph_model import Faults
    from profiles import PROFILES

    tb = await CoreTB(dut, cells=(CELL, None, None)).start()
    seen = []   # (word, phase of the channel when the byte completed)

    async def watch():
        while True:
            await dut.mon_count_0.value_change
            seen.append((int(dut.mon_word_0.value), int(dut.phase_0.value)))

    cocotb.start_soon(watch())
    await tb.set_timing(0, **SHORT)

    tb.models[0].inject(Faults(bad_checksum=True))
    bad = await tb.command(p.CMD_FIRMWARE, tag=1)
    assert bad.status == int(p.Status.BAD_CHECKSUM), bad
    await tb.lab_timing(channels=[0])
    wcmd, wpay = p.write_cmd(WRITE_ADDR, WRITE_DATA)
    wr = await tb.command(wcmd, wpay, tag=2)
    assert wr.status == int(p.Status.NO_RESPONSE), wr
    await tb.finish()

    fw = p.build_frame(p.CMD_FIRMWARE, p.UNUSED_PAYLOAD)
    # the cell's firmware and type bytes, its checksum sent with bit 0
    # flipped (Faults.bad_checksum)
    prof = PROFILES[CELL]
    bad_answer = bytearray(p.response_frame(prof.fw_byte, prof.type_byte))
    bad_answer[2] ^= 0x01
    assert bad.data == prof.fw_byte << 8 | prof.type_byte, bad
    want = (expected_words(fw, 0x41, 0) + expected_words(bad_answer, 0x41, 1, chk_ok=False)
            + expected_words(p.build_frame(wcmd, wpay), wcmd, 0))
    got = [w for w, _ in seen]
    assert got == want, "\n".join(f"{g:06x} {w:06x} {word_fields(g)}" for g, w in zip(got, want))
    # the spec monitor, a decoder of its own, read the same command frames
    assert tb.frames(0) == [fw, p.build_frame(wcmd, wpay)], tb.frames(0)
    # a command byte completes inside the command phase, an answer byte
    # inside the listen window: the phase view and the line agree
    for w, ph in seen:
        want_ph = p.Phase.LISTEN if word_fields(w)["periph"] else p.Phase.COMMAND
        assert ph == want_ph, (hex(w), ph)
    # the idle channels' monitors saw nothing
    assert int(dut.mon_count_1.value) == 0 and int(dut.mon_word_1.value) == 0


# ====================================================== pytest
def run_filter(values):
    """Values through twh_bytes.py the way GTKWave drives it: one process,
    one line written, one line read back before the next is written."""
    proc = subprocess.Popen([str(BYTES_FILTER)], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, text=True, bufsize=1)
    out = []
    try:
        for v in values:
            proc.stdin.write(v + "\n")
            proc.stdin.flush()
            out.append(proc.stdout.readline().rstrip("\n"))
    finally:
        proc.stdin.close()
        assert proc.wait(timeout=10) == 0
    return out


def strip_colour(text):
    m = re.fullmatch(r"\?[^?]*\?(.*)", text)
    return m.group(1) if m else text


def test_bytes_filter_known_values():
    fw = p.build_frame(0x41, 0xAA)
    rd = p.build_frame(0x49, 0x20)              # READ of word 0x120
    wcmd, wpay = p.write_cmd(0x0A5, 0x2345)
    wr = p.build_frame(wcmd, wpay)
    words = (expected_words(fw, 0x41, 0) + expected_words(b"\x12\x01\xec", 0x41, 1)
             + expected_words(rd, 0x49, 0) + expected_words(wr, wcmd, 0)
             + [pack_word(0x13, 0x41, 2, periph=1, last=1, chk_ok=0),
                pack_word(0x00, 0x44, 0, periph=1, stop_err=1)])
    # GTKWave sends what the trace shows: "$" with Show Base Symbols on
    values = [f"${w:06X}" for w in words] + [f"{words[0]:06x}", "$000000", "XXXXXX",
                                             "$41", "4A", "$C5", "3F"]
    out = run_filter(values)
    assert [strip_colour(t) for t in out] == [
        "H: 41 FIRMWARE", "H: AA arg", f"H: {fw[2]:02X} chk OK",
        "P: 12 FIRMWARE MSB", "P: 01 LSB", "P: EC chk OK",
        "H: 49 READ", "H: 20 addr 120", f"H: {rd[2]:02X} chk OK",
        f"H: {wcmd:02X} WRITE", f"H: {wpay >> 8:02X} data MSB",
        f"H: {wpay & 0xFF:02X} data LSB", f"H: {wr[3]:02X} chk OK",
        "P: 13 chk BAD", "P: 00 O2_VOLTAGE MSB FRAMING",
        "H: 41 FIRMWARE", "-", "XXXXXX",
        "41 FIRMWARE", "4A ERASE", "C5 WRITE", "3F RESERVED"]
    # bad frames stand out in colour, the two directions differ
    colours = [t[:t.index("?", 1) + 1] for t in out[:15]]
    assert colours[13] == colours[14] != colours[0]
    assert colours[0] == colours[6] != colours[3]


def phase_defs():
    text = DEFS.read_text()
    return {int(code): name for name, code in
            re.findall(r"`define\s+TWH_PH_(\w+)\s+3'd(\d+)", text)}


def test_phase_filter_names_every_phase():
    defs = phase_defs()
    assert sorted(defs) == list(range(8)), defs
    table = {}
    for line in PHASE_FILTER.read_text().splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        value, text = line.split(None, 1)
        assert value not in table, f"{value} twice in {PHASE_FILTER.name}"
        table[value] = strip_colour(text.strip())
    for code, name in defs.items():
        # decimal (the save file's format) and hex with its base symbol
        for shown in (str(code), f"${code:X}"):
            assert table.get(shown) == name, (shown, table.get(shown), name)
    assert len(table) == 2 * len(defs), table


# ------------------------------------------------------------ save file
def save_file_lines():
    return [ln.rstrip("\n") for ln in SAVE_FILE.read_text().splitlines()]


def save_file_signals():
    """Trace names of the save file (lines that are not comments, options,
    flags, filters or group/comment rows), without an alias."""
    names = []
    for ln in save_file_lines():
        ln = ln.strip()
        if not ln or ln[0] in "[*@-^>!?":
            continue
        ln = re.sub(r"^\+\{[^}]*\}\s*", "", ln)
        assert ln[0] not in "#:", f"bit-blasted vectors are not used: {ln}"
        names.append(ln)
    return names


def save_file_filters():
    """(kind, path) of every filter the save file installs."""
    out = []
    for ln in save_file_lines():
        m = re.match(r"\^(>?)(\d+)\s+(\S+)", ln)
        if m and m.group(2) != "0":
            out.append(("process" if m.group(1) else "file", m.group(3)))
    return out


def quoted(key):
    for ln in save_file_lines():
        m = re.match(rf"\[{key}\]\s+\"(.*)\"", ln)
        if m:
            return m.group(1)
    return None


def gtkwave_relative(orig_save, orig_file, this_save):
    """Where GTKWave looks for a file the save file names when the save file
    has moved: the path relative to the [savefile] it was written as,
    applied to where it is now (savefile.c: find_dumpfile)."""
    rel = os.path.relpath(orig_file, PurePosixPath(orig_save).parent)
    return (this_save.parent / rel).resolve()


def test_save_file_filters_resolve_from_build_demo():
    filters = save_file_filters()
    assert {k for k, _ in filters} == {"file", "process"}, filters
    orig_save = quoted("savefile")
    assert orig_save and orig_save.endswith("/build/demo/demo.gtkw"), orig_save
    # tb/demo.py copies the save file next to the VCD
    placed = ROOT / "build" / "demo" / "demo.gtkw"
    for kind, path in filters:
        found = gtkwave_relative(orig_save, path, placed)
        want = PHASE_FILTER if kind == "file" else BYTES_FILTER
        assert found == want.resolve(), (kind, path, found)
    assert os.access(BYTES_FILTER, os.X_OK), "GTKWave runs the process filter: it must be executable"
    assert gtkwave_relative(orig_save, quoted("dumpfile"), placed) == placed.with_suffix(".vcd")


def vcd_header_and_changes(path, wanted):
    """GTKWave's names of every variable in a VCD, and the value changes of
    the variables named in `wanted`."""
    names, ids, changes = set(), {}, {w: [] for w in wanted}
    scope = []
    with open(path) as f:
        for line in f:
            tok = line.split()
            if not tok:
                continue
            if tok[0] == "$scope":
                scope.append(tok[2])
            elif tok[0] == "$upscope":
                scope.pop()
            elif tok[0] == "$var":
                ref = tok[4] + (tok[5] if tok[5] != "$end" else "")
                name = ".".join(scope + [ref])
                names.add(name)
                if name in wanted:
                    ids[tok[3]] = name
            elif tok[0] == "$enddefinitions":
                break
        for line in f:
            if line[0] == "b":
                value, ident = line[1:].split()
                if ident in ids:
                    changes[ids[ident]].append(value)
    return names, changes


def test_save_file_matches_tb_core_vcd():
    """One short tb_core simulation (bytemon_frames above) writes the VCD
    the way `make demo` does; the save file must not name anything else, and
    the byte filter turns the monitor's words into the expected text."""
    import simrun
    from profiles import PROFILES

    out_dir = simrun.ROOT / "build" / "sim" / "gtkwave_bytemon"
    out_dir.mkdir(parents=True, exist_ok=True)
    vcd = out_dir / "bytemon.vcd"
    if vcd.exists():
        vcd.unlink()
    simrun.run("tb_core", "test_gtkwave", "gtkwave_bytemon",
               parameters={"CLK_HZ": 4_000_000, "CHANNELS": 3, "FIFO_DEPTH": 16, "BUS": 0},
               testcase="bytemon_frames", tb_sources=["tb_core.v"],
               plusargs=[f"+vcd={vcd}"], vcd=True,
               extra_env={"TWH_BUS": "0", "TWH_CHANNELS": "3", "TWH_FIFO_DEPTH": "16",
                          "TWH_CLK_HZ": "4000000"})
    word0 = "tb_core.mon_word_0[23:0]"
    names, changes = vcd_header_and_changes(vcd, {word0})
    missing = [s for s in save_file_signals() if s not in names]
    assert not missing, f"tb/demo.gtkw names signals the VCD does not have: {missing}"
    # every channel's group is there, and the filters are applied to its
    # phase and byte traces
    sigs = save_file_signals()
    for ch in range(3):
        for s in (f"phase_{ch}[2:0]", f"line_{ch}", f"line_oe_{ch}", f"line_o_{ch}",
                  f"mon_word_{ch}[23:0]", f"mon_byte_{ch}[7:0]"):
            assert f"tb_core.{s}" in sigs, s

    fw = p.build_frame(0x41, 0xAA)
    pr = PROFILES[CELL]
    ans = p.response_frame(pr.fw_byte, pr.type_byte)
    wcmd, wpay = p.write_cmd(WRITE_ADDR, WRITE_DATA)
    wr = p.build_frame(wcmd, wpay)
    want = (["H: 41 FIRMWARE", "H: AA arg", f"H: {fw[2]:02X} chk OK",
             f"P: {ans[0]:02X} FIRMWARE MSB", f"P: {ans[1]:02X} LSB",
             f"P: {ans[2] ^ 1:02X} chk BAD"]
            + [f"H: {wcmd:02X} WRITE", f"H: {wpay >> 8:02X} data MSB",
               f"H: {wpay & 0xFF:02X} data LSB", f"H: {wr[3]:02X} chk OK"])
    values = [f"${int(v, 2):06X}" for v in changes[word0] if "x" not in v.lower()]
    got = [strip_colour(t) for t in run_filter(values)]
    assert [t for t in got if t != "-"] == want, got
