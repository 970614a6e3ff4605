"""The sigrok protocol decoder (tools/sigrok/twowire) on simulated captures.

Each test runs a short tb_link simulation (the time-shared engine with one
channel) at 4 MHz against the behavioural
peripheral (tb/sigrok_capture.py), dumps the pins to a VCD and decodes it
with Debian's sigrok-cli (installed by scripts/bootstrap.sh; the test fails
when it is missing). Icarus writes the VCD with a 1 ps timescale: the vcd
input's downsample option brings it to 10 MHz, what a logic analyser on a
real line would use.
"""
import os
import shutil
import subprocess

import profiles
import protocol as p
import simrun

DECODER_DIR = simrun.ROOT / "tools" / "sigrok"
SAMPLERATE_HZ = 10_000_000
DOWNSAMPLE = 10**12 // SAMPLERATE_HZ      # 1 ps VCD timescale -> 10 MHz
QUIET = {"COCOTB_LOG_LEVEL": "WARNING", "GPI_LOG_LEVEL": "WARNING"}


def capture(testcase):
    """Runs one capture test; returns a VCD sigrok can read."""
    out = simrun.ROOT / "build" / "sigrok"
    out.mkdir(parents=True, exist_ok=True)
    raw = out / f"{testcase}.raw.vcd"
    simrun.run("tb_link", "sigrok_capture", f"sigrok_{testcase}",
               parameters={"CLK_HZ": 4_000_000}, testcase=testcase,
               tb_sources=["tb_engine1.v", "tb_link.v"], plusargs=[f"+vcd={raw}"], vcd=True,
               extra_env=QUIET)
    # libsigrok 0.5.2's VCD input stops reading at the first multi-digit
    # vector value ("b10 $", the 3-bit phase); keep the 1-bit signals only.
    vcd = out / f"{testcase}.vcd"
    with raw.open() as src, vcd.open("w") as dst:
        dst.writelines(line for line in src if not line.startswith("b"))
    return vcd


def sigrok_cmd(vcd, oe=True, rows=None):
    chans = "line=line_i" + (":oe=line_oe" if oe else "")
    cmd = ["sigrok-cli", "-i", str(vcd), "-I", f"vcd:downsample={DOWNSAMPLE}",
           "-P", f"twowire:{chans}"]
    return cmd + (["-A", f"twowire={rows}"] if rows else [])


def decode(vcd, oe=True, rows=None):
    """Annotations as (row class, text) pairs, in output order."""
    assert shutil.which("sigrok-cli"), \
        "sigrok-cli is missing: run scripts/bootstrap.sh (Debian package sigrok-cli)"
    env = dict(os.environ, SIGROKDECODE_DIR=str(DECODER_DIR))
    cmd = sigrok_cmd(vcd, oe, rows)
    res = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=60)
    assert res.returncode == 0 and not res.stderr.strip(), (cmd, res.stderr)
    lines = [line.split(": ", 1)[1] for line in res.stdout.splitlines()
             if line.startswith("twowire-1: ")]
    assert lines or rows, (cmd, res.stdout)
    return lines


def warnings(vcd, oe=True):
    """The decoder's warnings row alone."""
    return decode(vcd, oe, rows="warnings")


def expected():
    prof = profiles.PROFILES["o2_v18"]
    fw = p.build_frame(0x41, 0x00AA)
    wr = p.build_frame(*p.write_cmd(0x31, 0x1234))
    resp = p.response_frame(prof.fw_byte, prof.type_byte)
    hx = lambda b: " ".join(f"{x:02X}" for x in b)  # noqa: E731
    return fw, wr, resp, hx


def test_decode_in_spec():
    fw, wr, resp, hx = expected()
    assert hx(fw) == "41 AA 14"
    vcd = capture("capture_in_spec")
    for oe in (True, False):
        lines = decode(vcd, oe)
        frames = [line for line in lines if line.startswith(("Command ", "Response ", "No response"))
                  and not line.endswith(" us")]
        assert frames == [
            "Command 41 AA 14: FIRMWARE, checksum OK",
            f"Response {hx(resp)}: 0x{resp[0] << 8 | resp[1]:04X}, checksum OK",
            f"Command {hx(wr)}: WRITE 0x031 <- 0x1234, checksum OK",
            "No response",
        ][:len(frames)], (oe, lines)
        # without OE the end of the last listen window is not visible
        assert len(frames) == (4 if oe else 3), (oe, lines)
        host = [line[3:] for line in lines if line.startswith("H: ")]
        periph = [line[3:] for line in lines if line.startswith("P: ")]
        assert host == hx(fw).split() + hx(wr).split(), lines
        assert periph == hx(resp).split(), lines
        assert warnings(vcd, oe) == [], lines
        phases = [line.rsplit(" ", 2)[0] for line in lines if line.endswith(" us")]
        one = ["Charge", "Sync", "Preamble", "Command", "Execute"]
        if oe:
            assert phases == (one + ["Listen", "Turnaround"]) * 2, lines
            assert "Listen 3000 us" in lines and "Turnaround 2000 us" in lines
        else:
            assert phases == one + ["Listen/turnaround"] + one, lines
        for text in ("Charge 8000 us", "Sync 1000 us", "Preamble 2000 us",
                     "Command 1056 us", "Command 1408 us", "Execute 4000 us"):
            assert text in lines, (text, lines)


def test_decode_short_sync_warns():
    vcd = capture("capture_short_sync")
    lines = decode(vcd)
    assert warnings(vcd) == ["Sync 500 us outside 900-1100 us"], lines
    assert warnings(vcd, oe=False) == ["Sync 500 us outside 900-1100 us"]
    assert "Command 41 AA 14: FIRMWARE, checksum OK" in lines, lines
