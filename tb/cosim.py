"""Hardware/software co-simulation: the real C driver (libtwh.so, through
ctypes) drives the Wishbone core of tb/tb_core.v.

The driver is blocking C code, so it runs in a cocotb bridge thread
(cocotb.task.bridge); each platform hook it calls (register read/write,
delay, interrupt wait) hops back into the simulator with cocotb.task.resume
and performs a real bus access or waits simulated time.

ctypes swallows exceptions raised inside callbacks (it prints them and
returns 0), so every hook catches what it raises, records it, and the next
`call()` fails the test with it. A bus error is recorded too: the driver must
never cause one (a CPU could trap on it).
"""
import ctypes as C

import cocotb
from cocotb.simtime import get_sim_time
from cocotb.task import bridge, resume
from cocotb.triggers import First, RisingEdge, Timer

import twh_ctypes as T


class DriverError(AssertionError):
    pass


class Cosim:
    def __init__(self, tb, lib=None):
        self.tb = tb
        self.lib = lib or T.load()
        self.failures = []          # exceptions raised inside hooks
        self.accesses = 0
        self.irq_waits = 0
        self._read = resume(self._a_read)
        self._write = resume(self._a_write)
        self._delay = resume(self._a_delay)
        self._wait_irq = resume(self._a_wait_irq)
        # keep the callback objects alive as long as the platform
        self._cbs = (T.READ32(self._guard(self._read, 0)),
                     T.WRITE32(self._guard(self._write, None)),
                     T.DELAY(self._guard(self._delay, None)),
                     T.WAIT_IRQ(self._guard(self._wait_irq, 1)))
        self.plat = T.Platform(*self._cbs, None)
        self.t = T.Twh()

    def _guard(self, fn, fallback):
        def hook(_ctx, *args):
            try:
                return fn(*args)
            except BaseException as exc:          # noqa: BLE001 - re-raised in call()
                self.failures.append(exc)
                return fallback
        return hook

    async def _a_read(self, off):
        data, err = await self.tb.access(off)
        self.accesses += 1
        if err:
            raise DriverError(f"driver read 0x{off:03X} got a bus error")
        return data

    async def _a_write(self, off, value):
        _, err = await self.tb.access(off, value)
        self.accesses += 1
        if err:
            raise DriverError(f"driver write 0x{off:03X} = 0x{value:08X} got a bus error")

    async def _a_delay(self, us):
        await Timer(max(1, us), "us")

    async def _a_wait_irq(self, max_us):
        self.irq_waits += 1
        if self.tb.dut.irq.value == 1:
            return 1
        t0 = get_sim_time("us")
        await First(RisingEdge(self.tb.dut.irq), Timer(max(1, max_us), "us"))
        return max(1, int(get_sim_time("us") - t0))

    async def call(self, name, *args):
        """Run one driver function in a bridge thread; returns its int result."""
        fn = getattr(self.lib, name)

        def blocking():
            return fn(*args)

        rc = await bridge(blocking)()
        if self.failures:
            raise self.failures[0]
        return rc

    async def init(self, use_irq=True, timeout_us=200_000):
        if not use_irq:
            self.plat.wait_irq = T.WAIT_IRQ()
        rc = await self.call("twh_init", C.byref(self.t), C.byref(self.plat))
        self.t.timeout_us = timeout_us
        return rc

    # convenience wrappers for the blocking helpers: (rc, value)
    async def get16(self, name, ch, *args):
        out = C.c_uint16()
        rc = await self.call(name, C.byref(self.t), ch, *args, C.byref(out))
        return rc, out.value

    async def firmware(self, ch):
        fw = T.Fw()
        rc = await self.call("twh_firmware", C.byref(self.t), ch, C.byref(fw))
        return rc, fw

    async def negotiate(self, ch):
        fw = T.Fw()
        rc = await self.call("twh_negotiate", C.byref(self.t), ch, C.byref(fw))
        return rc, fw
