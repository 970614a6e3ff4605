"""The programming model of twowire-host, read from rdl/twh_regs.rdl.

The SystemRDL file is the single description of the register map; this
module compiles it with systemrdl-compiler and hands the tests a flat,
plain-Python view of it: every register of one RTL build with its byte
address and, per field, position, reset value and software access. Nothing
here restates the map: names, addresses, resets and access types all come
from the RDL.

Build parameters. Three reset values depend on the RTL parameters of the
build under test; the RDL holds the values of the default build (see
`default_params()`), and `load()` substitutes others:

    RTL parameter   field                 reset value
    CHANNELS        VERSION.CHANNELS      CHANNELS
    FIFO_DEPTH      PARAMS.FIFO_DEPTH     FIFO_DEPTH
    CLK_HZ          PARAMS.CLK_KHZ        CLK_HZ // 1000 (Verilog integer division)

CHANNELS also decides which channel blocks exist: CH[n] for n < CHANNELS are
in `RegMap.registers`; the blocks of absent channels (n >= CHANNELS) are in
`RegMap.absent`, and every access to them must answer with a bus error.

Read/write model used by the mask helpers and `read_after_write()`: the
SystemRDL meaning of the properties, plus an assumption the RDL does not
state (rtl/twh_core.v does it): write-only fields and bits outside every
field read as 0.

    sw    onwrite  reads as                    a write ...
    r     -        the hardware value          has no effect
    w     -        0                           has an effect (singlepulse: a
                                               one-cycle pulse per 1 written)
    rw    -        the last value written      stores the value
    rw    woclr    the hardware-set value      clears the bits written as 1
    (no field)     0                           has no effect

Example (a doctest: tb/test_regmap_py.py runs it):

    >>> import regmap
    >>> rm = regmap.load(channels=2, fifo_depth=32, clk_hz=100_000_000)
    >>> [(hex(r.address), r.name) for r in rm.registers][:3]
    [('0x0', 'ID'), ('0x4', 'VERSION'), ('0x8', 'PARAMS')]
    >>> t0 = rm["CH[1].TIMING0"]
    >>> hex(t0.address), t0.channel, hex(t0.reset), t0.field("SYNC_US").reset
    ('0xa0', 1, '0x3e81f40', 1000)
    >>> ctrl = rm["CTRL"]
    >>> f = ctrl.field("FLUSH")
    >>> f.lsb, f.msb, f.sw, f.onwrite, f.singlepulse
    (1, 1, 'w', None, True)
    >>> hex(regmap.rw_mask(ctrl)), hex(regmap.wo_mask(ctrl)), hex(ctrl.read_mask)
    ('0x1', '0x2', '0x1')
    >>> [r.name for r in rm.absent][:2]        # CH[2]..CH[31]: bus error
    ['CH[2].TIMING0', 'CH[2].TIMING1']
    >>> rm["VERSION"].field("CHANNELS").reset
    2
    >>> hex(regmap.fields_reset(rm["PARAMS"]))  # CLK_KHZ 100000, FIFO_DEPTH 32
    '0x186a0020'
    >>> errors = rm["ERRORS"]
    >>> errors.field("BLOCKED").onwrite, hex(errors.woclr_mask)
    ('woclr', '0x1f')
    >>> hex(regmap.read_after_write(errors, before=0x1F, written=0x05))
    '0x1a'
    >>> [hex(a) for a in rm.holes()][:3]      # reserved words inside the map
    ['0x28', '0x44', '0x48']
    >>> f = rm["IDLE_CHARGE"].field("IDLE_CHARGE")   # one bit a channel of the build
    >>> f.per_channel, f.msb, hex(rm["IDLE_CHARGE"].reserved_mask)
    (True, 1, '0xfffffffc')
"""
from __future__ import annotations

import functools
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Dict, Iterator, List, Optional, Tuple

REPO = Path(__file__).resolve().parent.parent
RDL_PATH = REPO / "rdl" / "twh_regs.rdl"

# The array of per-channel blocks in the RDL (CH[n]).
CHANNEL_ARRAY = "CH"

# RTL parameter -> (register, field, value of the field for a parameter value)
BUILD_PARAMS = {
    "CHANNELS": ("VERSION", "CHANNELS", lambda v: v),
    "FIFO_DEPTH": ("PARAMS", "FIFO_DEPTH", lambda v: v),
    "CLK_HZ": ("PARAMS", "CLK_KHZ", lambda hz: hz // 1000),
}

_SW = {"r": "r", "w": "w", "rw": "rw"}


@dataclass(frozen=True)
class Field:
    """One field. `sw` is "r", "w" or "rw"; `onwrite` is the SystemRDL
    onwrite type by name ("woclr" here) or None; `onread` likewise ("rclr",
    ...) or None; `hw` is the hardware access ("r", "w", "rw", "na")."""
    name: str
    lsb: int
    msb: int
    reset: Optional[int]
    sw: str
    onwrite: Optional[str] = None
    onread: Optional[str] = None
    singlepulse: bool = False
    hw: str = "na"
    desc: str = ""
    per_channel: bool = False     # bit n is channel n (narrowed by load())

    @property
    def width(self) -> int:
        return self.msb - self.lsb + 1

    @property
    def mask(self) -> int:
        """The field's bits, in register position."""
        return ((1 << self.width) - 1) << self.lsb

    @property
    def readable(self) -> bool:
        return "r" in self.sw

    @property
    def writable(self) -> bool:
        return "w" in self.sw

    def get(self, value: int) -> int:
        """The field's value within a register value."""
        return (value & self.mask) >> self.lsb

    def put(self, value: int, field_value: int) -> int:
        """`value` with this field replaced by `field_value`."""
        if not 0 <= field_value < (1 << self.width):
            raise ValueError(f"{self.name}: {field_value:#x} does not fit "
                             f"in {self.width} bits")
        return (value & ~self.mask) | (field_value << self.lsb)


@dataclass(frozen=True)
class Register:
    """One register of one build. `name` is the path below the top, e.g.
    "CTRL" or "CH[1].TIMING0"; `address` is the byte address; `channel` is
    n for a register of CH[n], None for a global one; `title` and `desc` are
    the RDL's name and desc; `fields` are in bit order."""
    name: str
    address: int
    width: int
    fields: Tuple[Field, ...]
    channel: Optional[int] = None
    title: str = ""
    desc: str = ""

    def field(self, name: str) -> Field:
        for f in self.fields:
            if f.name == name:
                return f
        raise KeyError(f"{self.name} has no field {name}")

    @property
    def full_mask(self) -> int:
        return (1 << self.width) - 1

    def _mask(self, pred) -> int:
        m = 0
        for f in self.fields:
            if pred(f):
                m |= f.mask
        return m

    # the mask helpers, also available as module functions of the same name
    @property
    def reset(self) -> int:
        """The register value after reset (fields_reset)."""
        return fields_reset(self)

    @property
    def field_mask(self) -> int:
        """Bits covered by some field; the rest are reserved."""
        return self._mask(lambda f: True)

    @property
    def read_mask(self) -> int:
        """Bits software can read (sw r or rw); all others read as 0."""
        return self._mask(lambda f: f.readable)

    @property
    def write_mask(self) -> int:
        """Bits a software write acts on (sw w or rw, any onwrite)."""
        return self._mask(lambda f: f.writable)

    @property
    def rw_mask(self) -> int:
        """Plain read/write storage: a read returns what was last written
        (sw rw, no onwrite, no singlepulse)."""
        return self._mask(lambda f: f.sw == "rw" and f.onwrite is None
                          and not f.singlepulse)

    @property
    def ro_mask(self) -> int:
        """Read-only bits (sw r): writes leave them alone."""
        return self._mask(lambda f: f.sw == "r")

    @property
    def wo_mask(self) -> int:
        """Write-only bits (sw w): they read as 0."""
        return self._mask(lambda f: f.sw == "w")

    @property
    def woclr_mask(self) -> int:
        """Write-one-to-clear bits."""
        return self._mask(lambda f: f.onwrite == "woclr")

    @property
    def singlepulse_mask(self) -> int:
        """Singlepulse bits: writing 1 pulses them for one cycle."""
        return self._mask(lambda f: f.singlepulse)

    @property
    def reserved_mask(self) -> int:
        """Bits of no field: they read as 0 and ignore writes."""
        return self.full_mask & ~self.field_mask


def fields_reset(reg: Register) -> int:
    """The register's reset value: every field's reset at its position."""
    value = 0
    for f in reg.fields:
        if f.reset is None:
            raise ValueError(f"{reg.name}.{f.name} has no reset value")
        value |= f.reset << f.lsb
    return value


def field_mask(reg: Register) -> int:
    return reg.field_mask


def read_mask(reg: Register) -> int:
    return reg.read_mask


def write_mask(reg: Register) -> int:
    return reg.write_mask


def rw_mask(reg: Register) -> int:
    return reg.rw_mask


def ro_mask(reg: Register) -> int:
    return reg.ro_mask


def wo_mask(reg: Register) -> int:
    return reg.wo_mask


def woclr_mask(reg: Register) -> int:
    return reg.woclr_mask


def singlepulse_mask(reg: Register) -> int:
    return reg.singlepulse_mask


def reserved_mask(reg: Register) -> int:
    return reg.reserved_mask


def read_after_write(reg: Register, before: int, written: int) -> int:
    """What a read should return after software wrote `written`, when a read
    just before the write returned `before`, assuming the hardware changes
    nothing in between. Only the access types are modelled: a register that
    refuses values (timing windows, POLL_CTRL commands: see the field
    descriptions) or whose write has side effects (CMD_PUSH, the keys, FLUSH)
    needs more care than this."""
    value = 0
    for f in reg.fields:
        if f.sw == "r":
            value |= before & f.mask
        elif f.sw == "w":
            pass                                    # reads as 0
        elif f.onwrite is None and not f.singlepulse:
            value |= written & f.mask
        elif f.onwrite == "woclr":
            value |= before & ~written & f.mask
        else:
            raise NotImplementedError(
                f"{reg.name}.{f.name}: onwrite={f.onwrite} "
                f"singlepulse={f.singlepulse} is not modelled")
    return value


class RegMap:
    """The registers of one build: `registers` (present, address order),
    `absent` (channel blocks n >= CHANNELS: bus error), `params` (the build
    parameters used). Index by name: rm["CH[0].STATE"]; iterate: the
    present registers."""

    def __init__(self, registers: List[Register], absent: List[Register],
                 params: Dict[str, int], size: int, channel_base: int,
                 channel_stride: int, max_channels: int,
                 channel_regs: int) -> None:
        self.registers: Tuple[Register, ...] = tuple(registers)
        self.absent: Tuple[Register, ...] = tuple(absent)
        self.params = dict(params)
        self.size = size                    # bytes spanned by the whole map
        self.channel_base = channel_base    # address of CH[0]
        self.channel_stride = channel_stride
        self.max_channels = max_channels    # CH[] array size in the RDL
        self.channel_regs = channel_regs    # registers per channel block
        self._by_name = {r.name: r for r in self.all}

    @property
    def all(self) -> Tuple[Register, ...]:
        """Present and absent registers, in address order."""
        return tuple(sorted(self.registers + self.absent,
                            key=lambda r: r.address))

    @property
    def channels(self) -> int:
        return self.params["CHANNELS"]

    def __getitem__(self, name: str) -> Register:
        return self._by_name[name]

    def __contains__(self, name: str) -> bool:
        return name in self._by_name

    def __iter__(self) -> Iterator[Register]:
        return iter(self.registers)

    def __len__(self) -> int:
        return len(self.registers)

    def at(self, address: int) -> Optional[Register]:
        """The register (present or absent) at a byte address, or None."""
        for r in self.all:
            if r.address == address:
                return r
        return None

    def channel(self, n: int) -> Tuple[Register, ...]:
        """The registers of CH[n] (present or absent), address order."""
        return tuple(r for r in self.all if r.channel == n)

    def channel_span(self, n: int) -> range:
        """Byte addresses of the whole CH[n] block, holes included."""
        start = self.channel_base + n * self.channel_stride
        return range(start, start + self.channel_stride)

    def holes(self) -> List[int]:
        """Word addresses below `size` that hold no register, absent
        channels not counted (reserved space inside the map; the RDL does
        not say what an access there answers)."""
        used = {r.address for r in self.all}
        return [a for a in range(0, self.size, 4) if a not in used]


def default_params(rdl: Path = RDL_PATH) -> Dict[str, int]:
    """The build the RDL's reset values describe, e.g.
    {"CHANNELS": 1, "FIFO_DEPTH": 16, "CLK_HZ": 48000000}."""
    regs = {r.name: r for r in _compile(str(rdl))[0]}
    out = {}
    for param, (reg, fld, _conv) in BUILD_PARAMS.items():
        value = regs[reg].field(fld).reset
        out[param] = value * 1000 if param == "CLK_HZ" else value
    return out


def load(channels: Optional[int] = None, fifo_depth: Optional[int] = None,
         clk_hz: Optional[int] = None, rdl: Path = RDL_PATH) -> RegMap:
    """The register map of the build with these RTL parameters; a parameter
    left None takes the RDL's default (`default_params()`). Raises
    ValueError for a value the register map cannot express."""
    regs, size, base, stride, count = _compile(str(rdl))
    params = default_params(rdl)
    given = {"CHANNELS": channels, "FIFO_DEPTH": fifo_depth, "CLK_HZ": clk_hz}
    for k, v in given.items():
        if v is None:
            continue
        if isinstance(v, float):
            if not v.is_integer():
                raise ValueError(f"{k} = {v} is not a whole number")
            v = int(v)
        params[k] = v
    if not 1 <= params["CHANNELS"] <= count:
        raise ValueError(f"CHANNELS = {params['CHANNELS']}: the map has "
                         f"channel blocks for 1-{count}")

    by_name = {r.name: r for r in regs}
    for param, (rname, fname, conv) in BUILD_PARAMS.items():
        reg = by_name[rname]
        f = reg.field(fname)
        value = conv(params[param])
        if not 1 <= value < (1 << f.width):
            raise ValueError(f"{param} = {params[param]}: {rname}.{fname} "
                             f"({f.width} bits) cannot hold {value}")
        fields = tuple(replace(x, reset=value) if x is f else x
                       for x in reg.fields)
        by_name[rname] = replace(reg, fields=fields)

    # a per-channel field has one bit for each channel of the build: the
    # bits of absent channels are reserved (read 0, ignore writes)
    for name, reg in list(by_name.items()):
        if any(f.per_channel for f in reg.fields):
            fields = tuple(replace(f, msb=f.lsb + params["CHANNELS"] - 1,
                                   reset=f.reset & ((1 << params["CHANNELS"]) - 1))
                           if f.per_channel else f for f in reg.fields)
            by_name[name] = replace(reg, fields=fields)

    present, absent = [], []
    for r in regs:
        r = by_name[r.name]
        (absent if r.channel is not None and r.channel >= params["CHANNELS"]
         else present).append(r)
    per_channel = sum(1 for r in regs if r.channel == 0)
    return RegMap(present, absent, params, size, base, stride, count,
                  per_channel)


def _udp(node, name):
    """A user-defined property of the RDL, or None where it is not set."""
    try:
        return node.get_property(name)
    except LookupError:
        return None


@functools.lru_cache(maxsize=None)
def _compile(rdl: str):
    """Compile and flatten the RDL once per process: (registers, size,
    channel base, channel stride, channel count)."""
    from systemrdl import RDLCompiler
    from systemrdl.node import RegNode, RegfileNode, AddrmapNode

    comp = RDLCompiler()
    comp.compile_file(rdl)
    top = comp.elaborate().top
    prefix = top.inst_name + "."

    arr = top.get_child_by_name(CHANNEL_ARRAY)
    if not (isinstance(arr, (RegfileNode, AddrmapNode)) and arr.is_array
            and len(arr.array_dimensions) == 1):
        raise ValueError(f"{rdl}: expected a 1-D array {CHANNEL_ARRAY}[]")
    count = arr.array_dimensions[0]
    stride = arr.array_stride
    base = arr.raw_absolute_address

    regs = []
    for node in top.descendants(unroll=True):
        if not isinstance(node, RegNode):
            continue
        if node.is_array:
            raise ValueError(f"{node.get_path()}: register arrays are not "
                             "supported")
        path = node.get_path(hier_separator=".", array_suffix="[{index:d}]")
        name = path[len(prefix):] if path.startswith(prefix) else path
        channel = None
        p = node.parent
        while p is not None and p is not top:
            if p.inst_name == CHANNEL_ARRAY and p.is_array:
                channel = p.current_idx[0]
            p = p.parent
        fields = []
        for f in node.fields():
            sw = f.get_property("sw").name
            if sw not in _SW:
                raise ValueError(f"{name}.{f.inst_name}: sw = {sw} is not "
                                 "modelled")
            onwrite = f.get_property("onwrite")
            onread = f.get_property("onread")
            fields.append(Field(
                name=f.inst_name, lsb=f.lsb, msb=f.msb,
                reset=f.get_property("reset"), sw=_SW[sw],
                onwrite=onwrite.name if onwrite is not None else None,
                onread=onread.name if onread is not None else None,
                singlepulse=bool(f.get_property("singlepulse")),
                hw=f.get_property("hw").name,
                desc=f.get_property("desc") or "",
                per_channel=bool(_udp(f, "per_channel"))))
        regs.append(Register(
            name=name, address=node.absolute_address,
            width=node.get_property("regwidth"),
            fields=tuple(sorted(fields, key=lambda x: x.lsb)),
            channel=channel, title=node.get_property("name") or "",
            desc=node.get_property("desc") or ""))
    regs.sort(key=lambda r: r.address)
    return tuple(regs), top.size, base, stride, count
