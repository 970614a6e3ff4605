"""The soak's traffic on Icarus, for the speed comparison in docs/soak.md:
the C driver (libtwh.so through ctypes, tb/cosim.py) submits random commands
on three channels of the Wishbone core (tb/tb_core.v, 4 MHz, the shortest
legal timing), each line answered by tb/periph_model.py's O2 cells with the
same fault mix and physical spread as the Verilator soak, and every result is
checked against the Python model's record. The spec monitors watch every
line (tb/coretb.py). Prints transactions and simulated milliseconds per wall
second; the figures are printed, never asserted.

usage: icarus_soak.py [N [SEED]]      (make soak-icarus)
"""
import os
import random
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TB = ROOT / "tb"
HERE = Path(__file__).resolve().parent

CELLS = ("o2_v18", "o2_v26", "o2_v15")
CLK_HZ = 4_000_000
MIN_TIMING = dict(charge=7000, sync=900, preamble=1800, execute=3500, listen=2000,
                  turnaround=2000)
DEPTH = 2            # commands in flight per channel, as the Verilator soak


def predict(rec):
    """(status, data) the core must report for what the model sent
    (docs/protocol.md, "Receiving the answer")."""
    from protocol import Status, checksum
    wire = rec.response
    if wire is None:
        return int(Status.NO_RESPONSE), 0
    f = rec.faults
    if f.bad_stop_bit is not None:
        # a 0 stop bit after eight 0 data bits is a break: the answer ended
        return (int(Status.SHORT_RESPONSE) if wire[f.bad_stop_bit] == 0
                else int(Status.FRAMING)), 0
    if len(wire) < 3:
        return int(Status.SHORT_RESPONSE), 0
    ok = checksum(wire[:2]) == wire[2]
    return int(Status.OK if ok else Status.BAD_CHECKSUM), wire[0] << 8 | wire[1]


def random_faults(rng, rate):
    """One answer's faults and physical parameters, the windows of
    sim/soak/periph.cpp."""
    from periph_model import Faults
    baud = rng.uniform(30750, 31750)
    kw = dict(baud=baud, carrier_hz=rng.uniform(0.9e6, 1.1e6), duty=rng.uniform(0.3, 0.7),
              stop_bits=rng.choice((1, 2)), response_delay_us=rng.uniform(20, 400),
              mark_us=rng.uniform(1, 2) * 1e6 / baud)
    if rng.random() < rate:
        kind = rng.randrange(4)
        if kind == 0:
            kw["no_response"] = True
        elif kind == 1:
            kw["bad_checksum"] = True
        elif kind == 2:
            kw["bad_stop_bit"] = rng.randrange(3)
        else:
            kw["truncate"] = rng.choice((1, 2))
    return Faults(**kw)


def pick(rng, size):
    """A random command (cmd, payload), the mix of soak_main.cpp's pick()."""
    r = rng.randrange(100)
    any_addr = rng.randrange(size) if rng.randrange(100) < 85 else rng.randrange(0x200)
    field = 0x20 + (rng.randrange(size - 0x20) if rng.randrange(100) < 90
                    else rng.randrange(0x200 - 0x20))
    if r < 30:
        return 0x40 + rng.randrange(5), 0xAA
    if r < 78:
        return (0x48 if r < 70 else 0x46) | any_addr >> 8, any_addr & 0xFF
    if r < 92:
        word = rng.randrange(0x3FFF)
        return 0x80 | (field & 0x7F), (field >> 7) << 14 | word
    if r < 96:
        return 0x4A | field >> 8, field & 0xFF
    return rng.choice((0x00, 0x21, 0x3F, 0x45, 0x4C, 0x60, 0x7F)), rng.randrange(256)


# ---------------------------------------------------------------- cocotb test
try:
    import cocotb
except ImportError:          # the runner below does not need it
    cocotb = None

if cocotb is not None and os.environ.get("SOAK_ICARUS"):
    import ctypes as C

    from cocotb.simtime import get_sim_time
    from cocotb.triggers import RisingEdge

    @cocotb.test()
    async def soak(dut):
        import protocol as p
        import twh_ctypes as T
        from coretb import CoreTB
        from cosim import Cosim

        n_total = int(os.environ["SOAK_N"])
        rate = float(os.environ.get("SOAK_FAULT_RATE", "0.2"))
        rng = random.Random(random.getrandbits(64))     # cocotb seeded `random`
        tb = await CoreTB(dut, cells=CELLS).start()
        for ch in range(3):
            await tb.set_timing(ch, **MIN_TIMING)
            model = tb.models[ch]
            model._take_faults = lambda r=rng: random_faults(r, rate)
        cs = Cosim(tb)
        assert await cs.init() == 0
        t = C.byref(cs.t)
        res = T.Result()
        inflight, issued = {}, [0, 0, 0]
        done = sent = 0
        mismatches = []
        sim0, wall0, cpu0 = get_sim_time("ms"), time.perf_counter(), time.process_time()
        while sent < n_total or inflight:
            for ch in range(3):
                while sent < n_total and sum(1 for k in inflight if k[0] == ch) < DEPTH:
                    cmd, payload = pick(rng, tb.profiles[ch].flash_size)
                    tag = await cs.call("twh_submit", t, ch, cmd, payload)
                    assert tag >= 0, T.ERRORS.get(tag)
                    inflight[(ch, tag)] = (issued[ch], cmd, payload)
                    issued[ch] += 1
                    sent += 1
            rc = await cs.call("twh_result", t, C.byref(res))
            if rc == T.ERR["AGAIN"]:
                if not dut.irq.value:
                    await RisingEdge(dut.irq)
                continue
            assert rc == 0, T.ERRORS.get(rc)
            seq, cmd, payload = inflight.pop((res.channel, res.tag))
            log = tb.models[res.channel].log
            rec = log[seq] if seq < len(log) else None
            frame = p.build_frame(cmd, payload)
            if rec is None or bytes(rec.frame) != frame:
                mismatches.append(f"ch{res.channel} #{seq}: frame {rec.frame.hex() if rec else None}, "
                                  f"expected {frame.hex()}")
            elif (res.status, res.data) != predict(rec):
                mismatches.append(f"ch{res.channel} #{seq} cmd {cmd:#04x}: got {res.status} "
                                  f"{res.data:#06x}, expected {predict(rec)} ({rec.reason})")
            done += 1
        wall = time.perf_counter() - wall0
        cpu = time.process_time() - cpu0       # this process: Icarus and Python
        sim_ms = get_sim_time("ms") - sim0
        await tb.finish()            # the spec monitors' verdicts, nothing left over
        print(f"\nIcarus + cocotb co-simulation: {done} transactions on 3 channels at "
              f"{CLK_HZ / 1e6:.0f} MHz, {len(mismatches)} mismatches", flush=True)
        print(f"simulated {sim_ms:.1f} ms in {wall:.1f} s wall, {cpu:.1f} s CPU", flush=True)
        print(f"rate: {done / wall:.2f} transactions/s, {sim_ms / wall:.2f} simulated ms/s "
              "per wall second (Icarus)", flush=True)
        print(f"      {done / cpu:.2f} transactions/s, {sim_ms / cpu:.2f} simulated ms/s "
              "per CPU second", flush=True)
        # make soak prints this beside its own figures (a measurement, dated)
        (ROOT / "build" / "soak").mkdir(parents=True, exist_ok=True)
        (ROOT / "build" / "soak" / "icarus_rate.txt").write_text(
            f"Icarus + cocotb, measured {time.strftime('%Y-%m-%d %H:%M')} by make soak-icarus "
            f"({done} transactions, seed {os.environ.get('SOAK_SEED', '?')}):\n"
            f"rate: {done / wall:.2f} transactions/s, {sim_ms / wall:.2f} simulated ms/s per wall second\n"
            f"      {done / cpu:.2f} transactions/s, {sim_ms / cpu:.2f} simulated ms/s per CPU second\n")
        assert not mismatches, "\n".join(mismatches[:20])


# ---------------------------------------------------------------- runner
def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 30
    seed = sys.argv[2] if len(sys.argv) > 2 else str(random.SystemRandom().getrandbits(31))
    # the runner hands its own sys.path to the simulator as PYTHONPATH
    sys.path[:0] = [str(TB), str(HERE)]
    from cocotb_tools.runner import get_results, get_runner
    build = ROOT / "build" / "soak" / "icarus"
    runner = get_runner("icarus")
    runner.build(sources=[*sorted((ROOT / "rtl").glob("*.v")), TB / "tb_line.v", TB / "tb_core.v"],
                 includes=[ROOT / "rtl"], hdl_toplevel="tb_core",
                 parameters={"CLK_HZ": CLK_HZ, "CHANNELS": 3, "FIFO_DEPTH": 16, "BUS": 0},
                 build_dir=build, timescale=("1ns", "1ps"), always=True)
    print(f"icarus soak: {n} transactions, seed {seed} (replay: make soak-icarus "
          f"SOAK_ICARUS_TRANSACTIONS={n} SOAK_SEED={seed})", flush=True)
    results = runner.test(
        hdl_toplevel="tb_core", test_module="icarus_soak", build_dir=build, test_dir=build,
        seed=seed,
        extra_env={"SOAK_ICARUS": "1", "SOAK_SEED": seed,
                   "SOAK_FAULT_RATE": os.environ.get("SOAK_FAULT_RATE", "0.2"),
                   "SOAK_N": str(n), "COCOTB_LOG_LEVEL": "WARNING", "GPI_LOG_LEVEL": "WARNING",
                   "TWH_CLK_HZ": str(CLK_HZ), "TWH_CHANNELS": "3", "TWH_FIFO_DEPTH": "16",
                   "TWH_BUS": "0"})
    n_tests, n_failed = get_results(results)
    if n_tests == 0 or n_failed:
        sys.exit(f"icarus soak failed ({n_failed} of {n_tests})")


if __name__ == "__main__":
    main()
