"""Unit tests of the independent spec monitor (tb/spec_monitor.py), no simulator.

A small synthetic "host" (LineGen) produces the pin events of transactions the
way a clocked RTL would: every edge on a clock tick, whole carrier periods,
bits on an exact bit grid. It is test code only and knows nothing of the RTL.
"""
import pytest

from protocol import checksum
from spec_monitor import Z, SpecChecker

CLK_12M_UP = 83_334  # 12 MHz with the half period rounded up to 41.667 ns
CLK_12M_DOWN = 83_332  # the same clock rounded the other way (-16 ppm)
CLK_100M = 10_000  # fine grid for off-nominal carriers and bit rates


def frame_of(*data):
    return (*data, checksum(data))


def frame_bits(frame):
    bits = []
    for byte in frame:
        bits += [0] + [(byte >> i) & 1 for i in range(8)] + [1, 1]
    return bits


class LineGen:
    """Host pin events on a clock grid. Durations are given in microseconds."""

    def __init__(self, clk_ps=CLK_12M_UP, carrier_clks=12, high_clks=None, bit_clks=None, start_clk=1000):
        self.clk = clk_ps
        # carrier_clks may be a tuple: periods cycle through it (a clock that
        # does not divide into 1 MHz).
        self.periods = carrier_clks if isinstance(carrier_clks, tuple) else (carrier_clks,)
        self.high = high_clks if high_clks is not None else min(self.periods) // 2
        self.bit = bit_clks if bit_clks is not None else 32 * sum(self.periods) // len(self.periods)
        self.n = start_clk
        self.events = []
        self.state = None
        self.z(100)  # the line is released when observation starts

    def ps(self, ticks):
        return ticks * self.clk

    def us(self, ticks):
        return ticks * self.clk / 1e6

    def ticks(self, us):
        return round(us * 1e6 / self.clk)

    def _set(self, s):
        if s != self.state:
            oe, o = (0, 0) if s == Z else (1, s)
            self.events.append((self.n * self.clk, oe, o))
            self.state = s

    def z(self, us):
        self._set(Z)
        self.n += self.ticks(us)

    def low(self, us):
        self._set(0)
        self.n += self.ticks(us)

    def pulse(self, high_ticks, low_ticks=0):
        self._set(1)
        self.n += high_ticks
        self._set(0)
        self.n += low_ticks

    def carrier_ticks(self, length):
        """Whole periods whose high half fits in `length` ticks; returns the
        burst's length as the monitor defines it (n periods)."""
        start = self.n
        k = 0
        while self.n + self.high <= start + length:
            p = self.periods[k % len(self.periods)]
            self._set(1)
            self.n += self.high
            self._set(0)
            self.n += p - self.high
            k += 1
        return self.n - start

    def carrier(self, us):
        return self.us(self.carrier_ticks(self.ticks(us)))

    def transaction(self, frame=(0x41, 0xAA, 0x14), charge=8000, sync=1000, preamble=2000,
                    execute=4000, listen=3000, turnaround=2000, bits_hook=None,
                    release_after_high=False):
        """One host transaction; returns the durations the monitor must measure."""
        exp = {"start_ps": self.ps(self.n), "frame": list(frame)}
        exp["charge_us"] = self.carrier(charge)
        self.low(sync)
        exp["sync_us"] = self.us(self.ticks(sync))
        exp["preamble_us"] = self.carrier(preamble)
        bits = frame_bits(frame)
        if bits_hook:
            bits = bits_hook(bits)
        runs = []
        for b in bits:
            if runs and runs[-1][0] == b:
                runs[-1][1] += 1
            else:
                runs.append([b, 1])
        assert runs[-1][0] == 1, "a frame ends in stop bits"
        t0 = self.n
        self.t0_ps = self.ps(t0)  # where the first start bit begins
        for i, (level, nb) in enumerate(runs):
            length = nb * self.bit
            if i == len(runs) - 1:
                start = self.n
                self.carrier_ticks(length + self.ticks(execute))
                exec_end = self.n  # virtual end: after the last full period
                if release_after_high:
                    self.n -= self.periods[0] - self.high
            elif level == 0:
                self._set(0)
                self.n += length
            else:
                start = self.n
                self.carrier_ticks(length)
                self.n = start + length
        nbits = len(bits)
        frame_end = t0 + nbits * self.bit
        exp["bit_time_us"] = self.us(self.bit)
        exp["command_us"] = self.us(nbits * self.bit)
        exp["execute_us"] = self.us(exec_end - frame_end)
        listen_start = self.n
        self.z(listen)
        exp["listen_us"] = self.us(self.n - listen_start)
        self.low(turnaround)
        exp["turnaround_us"] = self.us(self.ticks(turnaround))
        return exp

    def run(self, checker=None, finish=True, **kw):
        c = checker or SpecChecker(**kw)
        for ev in self.events:
            c.feed(*ev)
        if finish:
            c.finish(self.ps(self.n))
        return c


def assert_measured(tx, exp, keys=None):
    for k, v in exp.items():
        if keys is not None and k not in keys:
            continue
        got = getattr(tx, k)
        if isinstance(v, float):
            assert got is not None and abs(got - v) < 1e-3, (k, got, v)  # 1 ns
        else:
            assert got == v, (k, got, v)


def assert_only(c, *words):
    """At least one breach, and every breach mentions one of `words`."""
    assert c.errors, "breach not detected"
    for e in c.errors:
        assert any(w in e for w in words), (words, c.errors)


# ---------------------------------------------------------------- conforming
@pytest.mark.parametrize("clk", [CLK_12M_UP, CLK_12M_DOWN])
def test_conforming_transactions_measured_exactly(clk):
    g = LineGen(clk_ps=clk)
    g.low(500)
    exps = [g.transaction(), g.transaction(frame=(0x85, 0x12, 0x34, 0x34), execute=6000),
            g.transaction(frame=frame_of(0x00, 0x00))]
    c = g.run()
    assert c.errors == []
    assert len(c.transactions) == 3
    for tx, exp in zip(c.transactions, exps):
        assert tx.complete
        assert_measured(tx, {k: v for k, v in exp.items() if k != "turnaround_us"})
        assert 0.9999e6 < tx.carrier_min_hz <= tx.carrier_mean_hz <= tx.carrier_max_hz < 1.0001e6
        assert tx.duty_min == pytest.approx(0.5) and tx.duty_max == pytest.approx(0.5)
    assert c.transactions[0].turnaround_us == pytest.approx(exps[0]["turnaround_us"], abs=1e-3)
    assert c.transactions[1].turnaround_us == pytest.approx(exps[1]["turnaround_us"], abs=1e-3)
    assert c.transactions[-1].turnaround_us is None  # never completed: not a breach
    assert c.transactions[1].command_us == pytest.approx(44 * 32, rel=1e-4)
    assert c.transactions[0].command_us == pytest.approx(33 * 32, rel=1e-4)


def test_release_right_after_last_high_half():
    g = LineGen()
    exp = g.transaction(release_after_high=True)
    c = g.run()
    assert c.errors == []
    tx = c.transactions[0]
    assert tx.execute_us == pytest.approx(exp["execute_us"], abs=1e-3)
    assert tx.listen_us == pytest.approx(exp["listen_us"], abs=1e-3)


def test_clock_not_dividing_into_1mhz():
    # 10.5 MHz: carrier periods alternate 10 and 11 clocks (45-55 % duty)
    g = LineGen(clk_ps=95_238, carrier_clks=(10, 11), high_clks=5, bit_clks=336)
    g.transaction()
    g.transaction(frame=(0x85, 0x12, 0x34, 0x34))
    c = g.run()
    assert c.errors == []
    assert [tx.frame for tx in c.transactions] == [[0x41, 0xAA, 0x14], [0x85, 0x12, 0x34, 0x34]]


def test_idle_charge_and_idle_states():
    g = LineGen()
    idle = g.carrier(3000)  # idle carrier running straight into the charge
    e1 = g.transaction()
    g.z(5000)  # idle Z after the turnaround low
    g.low(10)
    e2 = g.transaction()
    g.carrier(4000)  # idle carrier switched off again, no transaction
    g.low(100)
    g.z(1000)
    c = g.run()
    assert c.errors == []
    assert len(c.transactions) == 2
    assert c.transactions[0].charge_us == pytest.approx(idle + e1["charge_us"], abs=1e-3)
    # carrier off from the end of listen to the next rising edge (low, Z, low)
    assert c.transactions[0].turnaround_us == pytest.approx(2000 + 5000 + 10, abs=0.1)
    assert c.transactions[1].turnaround_us == pytest.approx(e2["turnaround_us"], abs=1e-3)


def test_same_time_events_are_coalesced():
    g = LineGen()
    g.transaction()
    ev = []
    for t, oe, o in g.events:
        if oe == 0:  # release: o falls first, seen as a separate callback
            ev += [(t, 1, 0), (t, 0, 0)]
        elif o == 0:  # every fall preceded by a zero-width glitch through Z
            ev += [(t, 0, 0), (t, 1, 0)]
        else:
            ev.append((t, oe, o))
    c = SpecChecker()
    for e in ev:
        c.feed(*e)
    c.finish(g.ps(g.n))
    assert c.errors == []
    assert len(c.transactions) == 1


# ---------------------------------------------------------------- window edges
@pytest.mark.parametrize("clk", [CLK_12M_UP, CLK_12M_DOWN])
@pytest.mark.parametrize("edge", [
    dict(charge=7000), dict(sync=900), dict(sync=1100), dict(preamble=1800), dict(preamble=2200),
    dict(execute=3500), dict(execute=10000), dict(listen=2000), dict(turnaround=2000),
])
def test_window_edges_pass(clk, edge):
    g = LineGen(clk_ps=clk)
    exp = g.transaction(**edge)
    g.transaction()
    c = g.run()
    assert c.errors == []
    name, us = next(iter(edge.items()))
    got = getattr(c.transactions[0], f"{name}_us")
    assert got == pytest.approx(exp[f"{name}_us"], abs=1e-3)
    assert abs(got - us) / us < 20e-6  # the clock rounding, nothing else


def test_execute_edge_v15():
    g = LineGen()
    g.transaction(execute=4500)
    assert g.run(execute_max_us=4500).errors == []


@pytest.mark.parametrize("sync,ok", [(899.91, True), (899.89, False), (1100.10, True), (1100.12, False)])
def test_tolerance_is_100ppm(sync, ok):
    g = LineGen(clk_ps=CLK_100M, carrier_clks=100, high_clks=50)
    g.transaction(sync=sync)
    c = g.run()
    assert (c.errors == []) == ok, c.errors
    if not ok:
        assert_only(c, "sync")


# ---------------------------------------------------------------- breaches
@pytest.mark.parametrize("kw,words", [
    (dict(charge=6900), ["charge"]),
    (dict(sync=850), ["sync"]),
    (dict(sync=1150), ["sync"]),
    (dict(preamble=1700), ["preamble"]),
    (dict(preamble=2300), ["preamble"]),
    (dict(execute=3400), ["execute"]),
    (dict(execute=10100), ["execute"]),
    (dict(listen=1900), ["listen"]),
    (dict(turnaround=1900), ["turnaround"]),
    (dict(frame=(0x41, 0xAA, 0x15)), ["checksum"]),
    (dict(frame=(0x85, 0x12, 0x34, 0x35)), ["checksum"]),
])
def test_timing_and_checksum_breaches(kw, words):
    g = LineGen()
    g.transaction(**kw)
    g.transaction()
    assert_only(g.run(), *words)


def test_execute_too_long_for_v15():
    g = LineGen()
    g.transaction(execute=4600)
    assert g.run().errors == []
    assert_only(g.run(execute_max_us=4500), "execute")


@pytest.mark.parametrize("carrier,high,words", [
    (87, 43, ["MHz"]),  # 1.149 MHz
    (118, 59, ["MHz"]),  # 0.847 MHz
    (100, 40, ["duty"]),  # 40 %
    (100, 65, ["duty"]),  # 65 %
])
def test_carrier_breaches(carrier, high, words):
    g = LineGen(clk_ps=CLK_100M, carrier_clks=carrier, high_clks=high, bit_clks=3200)
    g.transaction()
    c = g.run()
    assert_only(c, *words)
    assert c.transactions[0].frame == [0x41, 0xAA, 0x14]  # still decoded


@pytest.mark.parametrize("bit_us", [1000 / 30.0, 1000 / 32.5])
def test_bit_rate_breaches(bit_us):
    g = LineGen(clk_ps=CLK_100M, carrier_clks=100, high_clks=50, bit_clks=round(bit_us * 100))
    g.transaction()
    g.transaction(frame=(0x85, 0x12, 0x34, 0x34))
    c = g.run()
    assert_only(c, "bit rate")
    assert [tx.frame for tx in c.transactions] == [[0x41, 0xAA, 0x14], [0x85, 0x12, 0x34, 0x34]]
    assert c.transactions[0].bit_time_us == pytest.approx(bit_us, abs=0.01)


@pytest.mark.parametrize("bit_us", [1000 / 30.76, 1000 / 31.74])
def test_bit_rate_inside_window(bit_us):
    g = LineGen(clk_ps=CLK_100M, carrier_clks=100, high_clks=50, bit_clks=round(bit_us * 100))
    g.transaction(frame=(0x85, 0x12, 0x34, 0x34))
    assert g.run().errors == []


@pytest.mark.parametrize("bit", [9, 10])
def test_stop_bit_zero(bit):
    def hook(bits):
        bits[11 + bit] = 0  # byte 1
        return bits
    g = LineGen()
    g.transaction(bits_hook=hook)
    assert_only(g.run(), "stop bit")


def test_edge_off_the_bit_grid():
    g = LineGen(clk_ps=CLK_100M, carrier_clks=100, high_clks=50)
    g.transaction()  # 0x41: bit 0 is 1, so a rise ends the first start bit
    rise = g.t0_ps + 32_000_000
    # move that whole one-bit burst 3 us early
    ev = [(t - 3_000_000 if rise <= t < rise + 32_000_000 else t, oe, o) for t, oe, o in g.events]
    assert ev != g.events
    c = SpecChecker()
    for e in ev:
        c.feed(*e)
    c.finish(g.ps(g.n))
    assert_only(c, "bit grid")


def test_runt_pulse_in_sync():
    g = LineGen()
    g.carrier(8000)
    g.low(500)
    g.pulse(1)  # one 83 ns spike
    g.low(500)
    g.carrier(2000)
    c = g.run(finish=False)
    assert any("runt" in e for e in c.errors), c.errors


def test_runt_high_half_inside_carrier():
    g = LineGen()
    g.carrier(4000)
    g.pulse(1, 11)  # a short high half in the middle of the charge
    g.carrier(4000)
    g.low(1000)
    c = g.run()
    assert_only(c, "runt", "duty")


def test_runt_at_release():
    # the host releases the line in the middle of a high half
    g = LineGen()
    g.transaction(execute=4000)
    ev = list(g.events)
    i = max(k for k, e in enumerate(ev) if e[1] == 0 and e[0] < g.ps(g.n) - 2_500_000_000)
    t_rel = ev[i][0]
    ev[i - 1] = (t_rel - 2 * CLK_12M_UP, 1, 1)  # last rise 2 clocks before the release
    c = SpecChecker()
    for e in ev:
        c.feed(*e)
    c.finish(g.ps(g.n))
    assert any("duty" in e for e in c.errors), c.errors


def test_carrier_during_listen():
    g = LineGen()
    g.transaction(listen=1000, turnaround=0)
    g.carrier(200)
    g.z(2000)
    g.low(2000)
    g.transaction()
    c = g.run()
    assert_only(c, "carrier during listen")
    assert len(c.errors) == 1


def test_turnaround_zero_is_a_breach():
    g = LineGen()
    g.transaction(turnaround=0)
    g.transaction()
    assert_only(g.run(), "turnaround")


def test_z_during_sync():
    g = LineGen()
    g.carrier(8000)
    g.low(300)
    g.z(400)
    g.low(300)
    g.carrier(2000)
    g.transaction(charge=0, sync=0, preamble=0)  # frame etc. right after
    c = g.run()
    assert any("(Z) during the sync" in e for e in c.errors), c.errors


def test_missing_listen():
    g = LineGen()
    g.transaction(listen=0)
    c = g.run()
    assert_only(c, "no listen")


@pytest.mark.parametrize("cut", ["z", "low"])
def test_missing_command(cut):
    g = LineGen()
    g.carrier(8000)
    g.low(1000)
    g.carrier(2000)
    getattr(g, cut)(3000)
    g.low(3000)
    assert_only(g.run(), "no command")


@pytest.mark.parametrize("phase,offset_us", [
    ("preamble", -1000), ("command", 500), ("execute", 1056 + 2000), ("listen", 1056 + 4000 + 1000),
])
def test_cut_off_at_finish(phase, offset_us):
    """finish() in the middle of a transaction is a breach."""
    g = LineGen()
    g.transaction()
    t_end = g.t0_ps + offset_us * 1_000_000  # relative to the first start bit
    c = SpecChecker()
    for e in g.events:
        if e[0] <= t_end:
            c.feed(*e)
    c.finish(t_end)
    assert_only(c, "cut off")


def test_finish_after_two_ms_of_listen_is_fine():
    g = LineGen()
    g.transaction()
    t_end = g.t0_ps + (1056 + 4000 + 2500) * 1_000_000
    c = SpecChecker()
    for e in g.events:
        if e[0] <= t_end:
            c.feed(*e)
    c.finish(t_end)
    assert c.errors == []
    assert c.transactions[0].complete and c.transactions[0].listen_us == pytest.approx(2500, abs=0.1)


def test_listed_while_listening_with_a_clock():
    """With a time source, a transaction is listed once its execute is over and
    its listen time is read live (a test may look at the clock edge where the
    listen ends, before the pins move)."""
    g = LineGen()
    exp = g.transaction()
    now = [0]
    c = SpecChecker(now=lambda: now[0])
    listen_start = g.t0_ps + round((exp["command_us"] + exp["execute_us"]) * 1e6)
    for e in g.events:
        if e[0] > listen_start + 3_000_000_000:
            break
        now[0] = e[0]
        c.feed(*e)
    now[0] = listen_start + 1_500_000_000
    tx = c.transactions[-1]
    assert not tx.complete and tx.listen_us == pytest.approx(1500, abs=0.01)
    assert tx.execute_us == pytest.approx(exp["execute_us"], abs=1e-3)
    now[0] = listen_start + round(exp["listen_us"] * 1e6)  # the end of listen, pins not moved yet
    assert c.transactions[-1].listen_us == pytest.approx(exp["listen_us"], abs=0.01)
    assert c.errors == []


def test_finish_during_charge_or_turnaround_is_fine():
    g = LineGen()
    g.transaction()
    g.carrier(3000)  # could be an idle carrier or a charge: not judged
    assert g.run().errors == []


def test_z_in_command_is_cut_off():
    g = LineGen()
    g.transaction()
    t_cut = g.t0_ps + 500 * 1_000_000  # inside the command
    ev = [e for e in g.events if e[0] < t_cut] + [(t_cut, 0, 0)]
    c = SpecChecker()
    for e in ev:
        c.feed(*e)
    c.finish(t_cut + 5_000_000_000)
    assert_only(c, "cut off")


# ---------------------------------------------------------------- reset
@pytest.mark.parametrize("cut_us", [4000, 8500, 9000 + 1000, 11000 + 500, 12500, 14000, 18000])
@pytest.mark.parametrize("report", ["before", "after"])
def test_reset_discards_partial_transaction(cut_us, report):
    """The line is released mid-transaction by a reset; the test reports it
    just before or just after the release. Nothing is a breach, and the next
    transaction is parsed cleanly."""
    g = LineGen()
    t_start = g.ps(g.n)
    g.transaction()
    t_cut = t_start + cut_us * 1_000_000 + 41_667  # between clock ticks: not a period boundary
    t_cut = (t_cut // CLK_12M_UP) * CLK_12M_UP
    g2 = LineGen(start_clk=t_cut // CLK_12M_UP + 3000)
    g2.low(50)
    second = g2.transaction()
    c = SpecChecker()
    for e in g.events:
        if e[0] < t_cut:
            c.feed(*e)
    if report == "before":
        c.reset(t_cut - 2 * CLK_12M_UP)
    c.feed(t_cut, 0, 0)  # the release at the reset edge
    if report == "after":
        c.reset(t_cut + 3 * CLK_12M_UP)
    c.feed(t_cut + 1_000_000, 0, 1)  # o changing while released: no state change
    for e in g2.events[1:]:
        c.feed(*e)
    c.finish(g2.ps(g2.n))
    assert c.errors == []
    assert len(c.transactions) == 1
    tx = c.transactions[0]
    assert_measured(tx, {k: v for k, v in second.items() if k != "turnaround_us"})


def test_reset_keeps_earlier_committed_breaches():
    g = LineGen()
    g.transaction(sync=1200)  # a genuine breach, committed at the end of listen
    t_reset = g.ps(g.n) + 500_000_000 + 41_667  # in the middle of the next carrier
    g.carrier(1000)
    c = SpecChecker()
    for e in g.events:
        if e[0] < t_reset:
            c.feed(*e)
    c.reset(t_reset)
    c.feed(t_reset + 1000, 0, 0)
    c.finish(t_reset + 1_000_000_000)
    assert_only(c, "sync")


def test_reset_without_reset_seen_is_a_breach():
    g = LineGen()
    g.transaction()
    ev = [e for e in g.events if e[0] < g.events[0][0] + 12_000_000_000]
    c = SpecChecker()
    for e in ev:
        c.feed(*e)
    c.feed(ev[-1][0] + 100_000, 0, 0)
    c.finish(ev[-1][0] + 10_000_000_000)
    assert c.errors


# ---------------------------------------------------------------- lab mode
def test_lab_mode_skips_windows_only():
    g = LineGen()
    exp = g.transaction(charge=5000, sync=500, preamble=2500, execute=3000, listen=1, turnaround=1000)
    g.transaction(frame=(0x41, 0xAA, 0x00))  # bad checksum: still a breach
    c = SpecChecker()
    c.allow_out_of_spec(True)
    for e in g.events:
        c.feed(*e)
    c.finish(g.ps(g.n))
    assert_only(c, "checksum")
    assert_measured(c.transactions[0], exp)
    assert c.transactions[0].out_of_spec_allowed


def test_lab_mode_carrier_still_checked():
    g = LineGen(clk_ps=CLK_100M, carrier_clks=100, high_clks=40)
    g.transaction(sync=500)
    c = SpecChecker()
    c.allow_out_of_spec(True)
    for e in g.events:
        c.feed(*e)
    c.finish(g.ps(g.n))
    assert_only(c, "duty")


def test_same_stream_strict_fails():
    g = LineGen()
    g.transaction(charge=5000, sync=500, preamble=2500, execute=3000, listen=1, turnaround=1000)
    g.transaction()
    assert_only(g.run(), "charge", "sync", "preamble", "execute", "listen", "turnaround")
    words = {w for e in g.run().errors for w in ("charge", "sync", "preamble", "execute", "listen",
                                                 "turnaround") if w in e}
    assert words == {"charge", "sync", "preamble", "execute", "listen", "turnaround"}
