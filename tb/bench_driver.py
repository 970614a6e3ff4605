"""`make bench`: bus accesses and interrupt waits the C driver spends per
2-wire transaction (co-simulated, Wishbone core, one O2 cell). Figures are
printed, never asserted."""
import ctypes as C

import cocotb

from coretb import CoreTB
from cosim import Cosim

N = 5


@cocotb.test()
async def bench(dut):
    tb = await CoreTB(dut, cells=("o2_v18", None, None)).start()
    rows = []
    for use_irq in (True, False):
        cs = Cosim(tb)
        assert await cs.init(use_irq=use_irq) == 0
        if not use_irq:
            cs.t.poll_us = 1000
        a0, w0 = cs.accesses, cs.irq_waits
        for _ in range(N):
            rc, _ = await cs.get16("twh_o2_voltage", 0)
            assert rc == 0
        rows.append((("irq (wait_irq hook)" if use_irq else f"polling every {cs.t.poll_us} us"),
                     (cs.accesses - a0) / N, (cs.irq_waits - w0) / N))
    print("\nC driver, blocking twh_o2_voltage(), per 2-wire transaction:", flush=True)
    for mode, acc, waits in rows:
        print(f"  {mode:<26} {acc:6.1f} bus accesses, {waits:5.1f} interrupt waits", flush=True)
    await tb.finish()
