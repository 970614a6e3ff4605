"""Harness for the simulated iCEBreaker board (tb/tb_board.v around
boards/icebreaker/twh_icebreaker.v).

- The PC side is cocotbext-uart: a UartSource on the board's receive pin and
  a UartSink on its transmit pin, at the build's BAUD.
- One PeripheralModel and one SpecMonitor per channel, attached to the
  channel's simulated line exactly as tb/coretb.py does for tb_core.
- `Bridge` speaks the bridge protocol (boards/common/twh_uart_bridge.v,
  docs/boards.md) byte by byte and decodes the answers; every wait for an
  answer is bounded in simulated time.
- `PtyLink` connects a pseudo terminal to the UART: what a process writes to
  the pty's slave side goes out on the board's receive pin, what the board
  sends comes back on it. The C command-line tool runs against it exactly as
  against a USB serial port.
- `finish()` closes and checks every spec monitor, checks that no model saw
  the host drive during its answer and that the board's pads never
  disagreed with their buffer enables.
"""
from __future__ import annotations

import logging
import os
import subprocess
import tty
import types
from dataclasses import dataclass
from typing import List, Optional

import cocotb
from cocotb.triggers import SimTimeoutError, Timer, with_timeout
from cocotbext.uart import UartSink, UartSource

import profiles
import regmap
from periph_model import Faults, PeripheralModel
from spec_monitor import SpecMonitor

CLK_HZ = 12_000_000
TB_CHANNELS = 3

OP_READ, OP_WRITE, OP_STATUS = 0x52, 0x57, 0x53
ST_MARK, ST_DROPPED, ST_IRQ, ST_FRAME, ST_BUS = 0xA0, 0x08, 0x04, 0x02, 0x01
TIMEOUT_BITS = 1024        # twh_uart_bridge's default


def check_byte(data) -> int:
    """One's complement of the 8-bit sum: the bridge's request check byte."""
    return ~sum(data) & 0xFF


def read_frame(word: int) -> bytes:
    b = bytes([OP_READ, word])
    return b + bytes([check_byte(b)])


def write_frame(word: int, value: int) -> bytes:
    b = bytes([OP_WRITE, word]) + value.to_bytes(4, "little")
    return b + bytes([check_byte(b)])


@dataclass(frozen=True)
class Answer:
    status: int
    data: Optional[int] = None

    @property
    def mark_ok(self) -> bool:
        return self.status & 0xF0 == ST_MARK

    @property
    def bus_err(self) -> bool:
        return bool(self.status & ST_BUS)

    @property
    def frame_err(self) -> bool:
        return bool(self.status & ST_FRAME)

    @property
    def irq(self) -> bool:
        return bool(self.status & ST_IRQ)

    @property
    def dropped(self) -> bool:
        return bool(self.status & ST_DROPPED)


def _param(dut, name, env, default):
    try:
        return int(getattr(dut, name).value)
    except Exception:  # noqa: BLE001 - not every simulator exposes parameters
        return int(os.environ.get(env, default))


class BoardTB:
    def __init__(self, dut, cells=("o2_v18", "o2_v15", "co2")):
        self.dut = dut
        self.channels = _param(dut, "CHANNELS", "TWH_CHANNELS", 3)
        self.baud = _param(dut, "BAUD", "TWH_BAUD", 115200)
        self.bit_ns = 1e9 / self.baud
        self.rm = regmap.load(channels=self.channels, fifo_depth=16, clk_hz=CLK_HZ)
        self.cells = tuple(cells)
        self.profiles = [profiles.PROFILES[self.cells[ch]] if ch < len(self.cells)
                         and self.cells[ch] else None for ch in range(self.channels)]
        self.models: List[Optional[PeripheralModel]] = []
        self.monitors: List[SpecMonitor] = []
        self.source = None
        self.sink = None

    async def start(self):
        d = self.dut
        await Timer(1, "ns")     # Icarus ignores values deposited before time 0
        d.btn_n.value = 1
        for ch in range(TB_CHANNELS):
            for sig in ("periph_o", "periph_oe", "stuck_en", "stuck_val", "glitch"):
                getattr(d, f"{sig}_{ch}").value = 0
        self.source = UartSource(d.uart_rx, baud=self.baud, bits=8, stop_bits=1)
        self.sink = UartSink(d.uart_tx, baud=self.baud, bits=8, stop_bits=1)
        for sig in (d.uart_rx, d.uart_tx):   # one log line per byte otherwise
            logging.getLogger(f"cocotb.{sig._path}").setLevel(logging.WARNING)
        for ch in range(self.channels):
            pins = types.SimpleNamespace(
                line=getattr(d, f"line_{ch}"), periph_o=getattr(d, f"periph_o_{ch}"),
                periph_oe=getattr(d, f"periph_oe_{ch}"), line_o=getattr(d, f"line_o_{ch}"),
                line_oe=getattr(d, f"line_oe_{ch}"), carrier=getattr(d, f"u_line{ch}").carrier)
            prof = self.profiles[ch]
            self.models.append(PeripheralModel(pins, prof, Faults(), line_log=f"line_{ch}.log",
                                               carrier=pins.carrier).start() if prof else None)
            mon = SpecMonitor(pins, execute_max_us=prof.exec_max_us if prof else 10000,
                              name=f"spec_ch{ch}", pin_log=f"pins_{ch}.log")
            mon.start()
            self.monitors.append(mon)
        await self.wait_running()
        return self

    async def wait_running(self, timeout_us=50):
        """Until the power-on / button reset is over (the green LED)."""
        async def running():
            while int(self.dut.led_green_n.value) != 0:
                await Timer(1, "us")
        await with_timeout(running(), timeout_us, "us")

    # ------------------------------------------------------------ raw bytes
    def char_us(self, n=1) -> float:
        return n * 10 * self.bit_ns / 1000

    async def send(self, data: bytes):
        await self.source.write(data)

    async def recv(self, n: int, timeout_us: Optional[float] = None) -> bytes:
        """n answer bytes; fails when they are not all there in time."""
        if timeout_us is None:
            timeout_us = self.char_us(n + 8) + 50
        out = bytearray()

        async def collect():
            while len(out) < n:
                await self.sink.wait()
                out.extend(self.sink.read_nowait())
        try:
            await with_timeout(collect(), round(timeout_us * 1000), "ns")
        except SimTimeoutError:
            raise AssertionError(f"{len(out)} of {n} answer bytes within {timeout_us:.0f} us: "
                                 f"{bytes(out).hex()}") from None
        return bytes(out)

    async def quiet(self, us: float) -> bytes:
        """Whatever the board sends during the next `us` microseconds."""
        await Timer(round(us * 1000), "ns")
        return bytes(self.sink.read_nowait())

    # ------------------------------------------------------------ protocol
    async def request(self, frame: bytes, n_answer: int) -> Answer:
        await self.source.wait()
        await self.send(frame)
        # the answer starts once the last request byte is in
        await self.source.wait()
        raw = await self.recv(n_answer)
        ans = Answer(raw[0], int.from_bytes(raw[1:5], "little") if n_answer == 5 else None)
        assert ans.mark_ok, f"answer {raw.hex()} to {frame.hex()}: not a status byte"
        return ans

    async def read_word(self, word: int) -> Answer:
        return await self.request(read_frame(word), 5)

    async def write_word(self, word: int, value: int) -> Answer:
        return await self.request(write_frame(word, value), 1)

    async def status(self) -> Answer:
        return await self.request(bytes([OP_STATUS]), 1)

    def addr(self, name, ch=None) -> int:
        return self.rm[name if ch is None else f"CH[{ch}].{name}"].address

    async def read(self, name, ch=None) -> int:
        a = await self.read_word(self.addr(name, ch) >> 2)
        assert not a.bus_err and not a.frame_err, f"read {name}: status {a.status:#04x}"
        return a.data

    async def write(self, name, value, ch=None) -> Answer:
        a = await self.write_word(self.addr(name, ch) >> 2, value)
        assert not a.frame_err, f"write {name}: status {a.status:#04x}"
        return a

    def field(self, name, value, field, ch=None) -> int:
        return self.rm[name if ch is None else f"CH[{ch}].{name}"].field(field).get(value)

    # ------------------------------------------------------------ end
    async def finish(self):
        errors = []
        for ch, m in enumerate(self.monitors):
            try:
                m.finish()
            except AssertionError as e:
                errors.append(f"channel {ch}: {e}")
        for ch, m in enumerate(self.models):
            if m is not None:
                m.stop()
                coll = [t for t in m.log if t.collision]
                if coll:
                    errors.append(f"channel {ch}: host drove the line during {len(coll)} answer(s)")
        pad = int(self.dut.pad_errors.value)
        if pad:
            errors.append(f"{pad} clock edges with a drive pad disagreeing with its enable")
        if errors:
            raise AssertionError("\n".join(errors))


class PtyLink:
    """A pseudo terminal bridged to the board's UART. The process under test
    opens `path`; the test side keeps the master and shuttles bytes every
    `poll_us` of simulated time (a few character times: it only adds that
    much latency, the UART itself is simulated bit by bit)."""

    def __init__(self, tb: BoardTB, poll_us: float = 20):
        self.tb = tb
        self.poll_us = poll_us
        self.master, self.slave = os.openpty()
        tty.setraw(self.slave)
        self.path = os.ttyname(self.slave)
        os.set_blocking(self.master, False)
        self.to_board = 0
        self.from_board = 0
        self._task = None

    def start(self):
        self._task = cocotb.start_soon(self._run())
        return self

    async def _run(self):
        while True:
            await Timer(self.poll_us, "us")
            try:
                data = os.read(self.master, 4096)
            except (BlockingIOError, OSError):
                data = b""
            if data:
                self.to_board += len(data)
                self.tb.source.write_nowait(data)
            out = bytes(self.tb.sink.read_nowait())
            if out:
                self.from_board += len(out)
                os.write(self.master, out)

    async def run_process(self, argv, out_path, max_sim_ms: float) -> subprocess.CompletedProcess:
        """Runs argv (stdout and stderr to out_path) until it exits, bounded
        by max_sim_ms of simulated time."""
        with open(out_path, "w") as out:
            proc = subprocess.Popen(argv, stdout=out, stderr=subprocess.STDOUT,
                                    stdin=subprocess.DEVNULL)
        waited_us = 0.0
        try:
            while proc.poll() is None:
                if waited_us > max_sim_ms * 1000:
                    raise AssertionError(f"{argv[0]} still running after {max_sim_ms} ms "
                                         f"of simulated time")
                await Timer(200, "us")
                waited_us += 200
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
        with open(out_path) as f:
            text = f.read()
        return subprocess.CompletedProcess(argv, proc.returncode, text, "")

    def close(self):
        if self._task is not None:
            self._task.cancel()
        os.close(self.master)
        os.close(self.slave)
