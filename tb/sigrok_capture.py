"""Short link captures for the sigrok decoder test (tb/test_sigrok.py).

Each test drives tb_link with the behavioural peripheral; the pytest side
asks tb_link for a VCD of the pins (+vcd=<file>) and runs sigrok-cli on it.
"""
import cocotb
from cocotb.triggers import Timer

import profiles
import protocol as p
from linktb import LinkTB
from periph_model import Faults, PeripheralModel
from protocol import Status

# The result arrives at the end of the listen window; run on through the
# turnaround so the capture holds the whole transaction (sigrok's VCD input
# also drops the value change at the very last timestamp).
TAIL_US = 2500


async def _tb(dut):
    prof = profiles.PROFILES["o2_v18"]
    model = PeripheralModel(dut, prof, Faults())
    tb = LinkTB(dut, model, execute_max_us=prof.exec_max_us)
    await tb.start()
    return tb, prof


@cocotb.test()
async def capture_in_spec(dut):
    """FIRMWARE (answered) and a 4-byte WRITE (silent), default timing."""
    tb, prof = await _tb(dut)
    res = await tb.command(0x41, 0x00AA)
    assert res.status == Status.OK and res.data == prof.fw_byte << 8 | prof.type_byte, res
    res = await tb.command(*p.write_cmd(0x31, 0x1234))
    assert res.status == Status.NO_RESPONSE, res
    await tb.finish()
    await Timer(TAIL_US, "us")


@cocotb.test()
async def capture_short_sync(dut):
    """Lab unlock: a 500 us sync, out of spec on purpose."""
    tb, prof = await _tb(dut)
    tb.monitor.allow_out_of_spec(True)
    dut.cfg_unlock.value = 1
    tb.set_timing(sync=500)
    res = await tb.command(0x41, 0x00AA)
    assert res.status == Status.OK, res
    await tb.finish()
    await Timer(TAIL_US, "us")
