"""Test-bench harness for one channel of the link (tb/tb_link.v: the
time-shared engine with one channel).

Drives the command stream, collects every result, and runs the independent
spec monitor on the host pins for the whole test. A peripheral model is
attached when the test names a profile.

The handshakes read a ready or valid at the falling edge, where it holds
the value the next rising edge samples: right after a rising edge Icarus
shows the values before it and Verilator those after it, and the benches
run on both (tb/simrun.py). At the end a test writes its transcript (every
result, every frame the cell handled, every transaction the monitor
measured) for the comparison of the two simulators.
"""
from dataclasses import dataclass

import cocotb
from cocotb.queue import Queue
from cocotb.triggers import FallingEdge, RisingEdge, Timer

from protocol import Status
from spec_monitor import SpecMonitor

# NOTES.md defaults, microseconds
DEFAULT_TIMING = dict(charge=8000, sync=1000, preamble=2000, execute=4000,
                      listen=3000, turnaround=2000)


@dataclass(frozen=True)
class Result:
    code: int
    data: int
    status: Status
    tag: int


class LinkTB:
    def __init__(self, dut, model=None, execute_max_us=10000):
        self.dut = dut
        self.model = model
        self.monitor = SpecMonitor(dut, execute_max_us=execute_max_us, pin_log="pins_0.log")
        self.results = Queue()
        self.taken = []             # every result, in order (the transcript)
        self.timing = dict(DEFAULT_TIMING)

    async def start(self):
        d = self.dut
        self.set_timing()
        d.cfg_idle_charge.value = 0
        d.cfg_unlock.value = 0
        d.s_cmd_valid.value = 0
        d.s_cmd_code.value = 0
        d.s_cmd_payload.value = 0
        d.s_cmd_tag.value = 0
        d.s_cmd_skip.value = 0
        d.m_res_ready.value = 1
        d.periph_o.value = 0
        d.periph_oe.value = 0
        d.stuck_en.value = 0
        d.stuck_val.value = 0
        d.glitch.value = 0
        d.dropout.value = 0
        d.rst.value = 1
        await Timer(1, "us")
        await RisingEdge(d.clk)
        d.rst.value = 0
        self.monitor.start()
        if self.model is not None:
            self.model.start()
        cocotb.start_soon(self._collect())

    def set_timing(self, **us):
        """Program phase durations (microseconds); unnamed ones keep their value."""
        self.timing.update(us)
        for name, value in self.timing.items():
            getattr(self.dut, f"cfg_{name}_us").value = value

    async def reset_pulse(self, cycles=2):
        """Synchronous reset for `cycles` (>= 2) clocks, aligned to the clock.
        Returns line_oe as it stood one clock after the first reset edge."""
        self.monitor.reset_seen()
        await RisingEdge(self.dut.clk)
        self.dut.rst.value = 1
        await RisingEdge(self.dut.clk)          # the first reset edge
        await RisingEdge(self.dut.clk)          # reads what that edge left
        oe_after_first_edge = int(self.dut.line_oe.value)
        for _ in range(cycles - 2):
            await RisingEdge(self.dut.clk)
        self.dut.rst.value = 0
        return oe_after_first_edge

    async def submit(self, code, payload=0x00AA, tag=0, skip=0):
        d = self.dut
        # Drive on a falling edge: a write made in the same time step as a
        # rising edge would land after the DUT sampled its inputs.
        await FallingEdge(d.clk)
        d.s_cmd_code.value = code
        d.s_cmd_payload.value = payload
        d.s_cmd_tag.value = tag
        d.s_cmd_skip.value = skip
        d.s_cmd_valid.value = 1
        while True:
            ready = int(d.s_cmd_ready.value)    # what the next rising edge samples
            if not ready:
                await RisingEdge(d.s_cmd_ready)
                await FallingEdge(d.clk)
                continue
            await FallingEdge(d.clk)            # past the edge that accepted it
            break
        d.s_cmd_valid.value = 0
        d.s_cmd_skip.value = 0

    async def _collect(self):
        d = self.dut
        while True:
            if not d.m_res_valid.value:
                await RisingEdge(d.m_res_valid)
            if not d.m_res_ready.value:
                await RisingEdge(d.m_res_ready)
            await FallingEdge(d.clk)
            if d.m_res_valid.value and d.m_res_ready.value:
                res = Result(code=int(d.m_res_code.value), data=int(d.m_res_data.value),
                             status=Status(int(d.m_res_status.value)),
                             tag=int(d.m_res_tag.value))
                self.taken.append(res)
                self.results.put_nowait(res)
                await RisingEdge(d.clk)     # the edge that takes it

    async def result(self):
        return await self.results.get()

    async def command(self, code, payload=0x00AA, tag=0):
        await self.submit(code, payload, tag)
        res = await self.result()
        assert res.code == code and res.tag == tag, res
        self.monitor.check()
        return res

    async def finish(self):
        """End of test: every breach the monitor saw fails the test."""
        # A result goes out at the visit after the listen's last, up to a
        # carrier period before the turnaround's drive reaches the line
        # (the drive lands one or two ticks after its visit): let the line
        # leave the listen before the monitor closes its last transaction.
        await Timer(2, "us")
        self.monitor.finish()
        assert self.results.empty(), "unclaimed results"
        self.write_transcript()

    def write_transcript(self, path="transcript.txt"):
        lines = [f"result {r.code:02X} {r.data:04X} {r.status.name} {r.tag}" for r in self.taken]
        if self.model is not None:
            lines += [x.transcript() for x in self.model.logic.log]
        lines += [t.transcript() for t in self.monitor.checker.transactions]
        with open(path, "w") as f:
            f.write("\n".join(lines) + "\n")
