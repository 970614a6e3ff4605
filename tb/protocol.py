"""The one Python implementation of the 2-wire protocol rules.

Everything here follows SRI-2WIRE-IRD rev E as read by shared/spec/NOTES.md.
The C driver and the RTL implement the same rules; tb/vectors/*.json pins
them down so that the three can be checked against each other.

Integer arithmetic only: every conversion below is written the way a C
implementation with 64-bit intermediates would compute it, and every
division truncates toward zero (C semantics), never Python's floor.
"""
from __future__ import annotations

from enum import IntEnum
from typing import NamedTuple, Optional

# --------------------------------------------------------------------------
# Timing constants of the link (NOTES.md "Serial format", "Timing")
# --------------------------------------------------------------------------
BAUD = 31250                  # bits per second, both directions
CARRIER_HZ = 1_000_000        # host carrier
CARRIER_PERIODS_PER_BIT = 32  # one bit = 32 host carrier periods = 32 us
BIT_US = 32
STOP_BITS = 2


class Status(IntEnum):
    """Result status codes of the host core (m_res_status)."""
    OK = 0
    NO_RESPONSE = 1
    BAD_CHECKSUM = 2
    FRAMING = 3
    SHORT_RESPONSE = 4
    LINE_STUCK_LOW = 5
    LINE_STUCK_HIGH = 6
    BLOCKED = 7
    CANCELLED = 8


class Phase(IntEnum):
    """Phase codes of the host core (the `phase` output)."""
    IDLE = 0
    CHARGE = 1
    SYNC = 2
    PREAMBLE = 3
    COMMAND = 4
    EXECUTE = 5
    LISTEN = 6
    TURNAROUND = 7


# --------------------------------------------------------------------------
# Framing
# --------------------------------------------------------------------------
def checksum(bytes_) -> int:
    """One's complement of the 8-bit sum ("MOD 8" read as modulo 2^8).

    Property: the sum of all bytes of a frame including its checksum is
    0xFF modulo 256.
    """
    return ~sum(bytes_) & 0xFF


def frame_len(cmd: int) -> int:
    """Length of a host frame in bytes, from its command byte."""
    return 3 if (cmd & 0xFF) < 0x80 else 4


def build_frame(cmd: int, payload16: int) -> bytes:
    """Host command frame.

    cmd < 0x80: [cmd, payload LSB, chk] (the payload MSB is not sent);
    cmd >= 0x80: [cmd, payload MSB, payload LSB, chk].
    """
    if not 0 <= cmd <= 0xFF:
        raise ValueError(f"command byte out of range: {cmd!r}")
    if not 0 <= payload16 <= 0xFFFF:
        raise ValueError(f"payload out of range: {payload16!r}")
    if cmd < 0x80:
        body = [cmd, payload16 & 0xFF]
    else:
        body = [cmd, payload16 >> 8, payload16 & 0xFF]
    return bytes(body + [checksum(body)])


def response_frame(msb: int, lsb: int) -> bytes:
    """Peripheral response: [MSB, LSB, chk]."""
    body = [msb & 0xFF, lsb & 0xFF]
    return bytes(body + [checksum(body)])


def frame_ok(frame: bytes) -> bool:
    """True when the last byte is the checksum of the others."""
    return len(frame) >= 2 and checksum(frame[:-1]) == frame[-1]


def uart_bits(byte: int, stop_bits: int = STOP_BITS) -> list:
    """Line bits of one UART character: start 0, 8 data bits LSB first, stop 1s."""
    return [0] + [(byte >> i) & 1 for i in range(8)] + [1] * stop_bits


# --------------------------------------------------------------------------
# Command table
# --------------------------------------------------------------------------
CMD_CONFIG = 0x40
CMD_FIRMWARE = 0x41
CMD_REF_VOLTAGE = 0x42
CMD_TEMPERATURE = 0x43
CMD_O2_VOLTAGE = 0x44
CMD_FIND_FREE = 0x46      # and 0x47 (address bit 8)
CMD_READ = 0x48           # and 0x49
CMD_ERASE = 0x4A          # and 0x4B
CMD_WRITE = 0x80          # 0x80-0xFF

# Payload for commands whose payload is unused (spec: 0xAA or 0xF0 recommended).
UNUSED_PAYLOAD = 0xAA


def command_name(cmd: int) -> str:
    """Symbolic name of a command byte."""
    cmd &= 0xFF
    if cmd >= 0x80:
        return "WRITE"
    return {
        0x40: "CONFIG", 0x41: "FIRMWARE", 0x42: "REF_VOLTAGE",
        0x43: "TEMPERATURE", 0x44: "O2_VOLTAGE",
        0x46: "FIND_FREE", 0x47: "FIND_FREE",
        0x48: "READ", 0x49: "READ",
        0x4A: "ERASE", 0x4B: "ERASE",
    }.get(cmd, "RESERVED")


def expects_response(cmd: int) -> bool:
    """True for commands a working peripheral answers.

    Erase, write and reserved commands never answer, so "no response" is the
    expected outcome for them (NOTES.md "The response").
    """
    return command_name(cmd) not in ("ERASE", "WRITE", "RESERVED")


# --------------------------------------------------------------------------
# Addresses (NOTES.md "Flash words and the memory map")
# --------------------------------------------------------------------------
ADDR_MAX = 0x1FF  # 9-bit word address
WORD_MASK = 0x3FFF
BLANK = 0x3FFF


def write_cmd(addr: int, data14: int) -> tuple:
    """(cmd, payload16) of the write command for a word address and 14-bit data.

    Address bits 6:0 go to command bits 6:0, address bits 8:7 to bits 7:6 of
    the data MSB; data = (MSB & 0x3F) << 8 | LSB.
    """
    if not 0 <= addr <= ADDR_MAX:
        raise ValueError(f"address out of range: {addr!r}")
    if not 0 <= data14 <= WORD_MASK:
        raise ValueError(f"data out of 14-bit range: {data14!r}")
    cmd = 0x80 | (addr & 0x7F)
    payload = ((addr >> 7) & 0x3) << 14 | data14
    return cmd, payload


def decode_write(cmd: int, payload: int) -> tuple:
    """(addr, data14) of a write command; inverse of write_cmd."""
    if not 0x80 <= cmd <= 0xFF:
        raise ValueError(f"not a write command: {cmd!r}")
    addr = ((payload >> 14) & 0x3) << 7 | (cmd & 0x7F)
    return addr, payload & WORD_MASK


def addr_cmd(base_cmd: int, addr: int) -> tuple:
    """(cmd, payload) for the 0x46 / 0x48 / 0x4A families: bit 8 of the
    address selects the odd command, the payload byte is bits 7:0."""
    if base_cmd not in (CMD_FIND_FREE, CMD_READ, CMD_ERASE):
        raise ValueError(f"not an addressed command family: {base_cmd!r}")
    if not 0 <= addr <= ADDR_MAX:
        raise ValueError(f"address out of range: {addr!r}")
    return base_cmd | (addr >> 8), addr & 0xFF


def decode_addr(cmd: int, payload: int) -> int:
    """Word address of a 0x46-0x4B command: (cmd bit 0) << 8 | payload byte."""
    return (cmd & 1) << 8 | (payload & 0xFF)


# --------------------------------------------------------------------------
# Firmware version byte (command 0x41 MSB)
# --------------------------------------------------------------------------
class FwVersion(NamedTuple):
    raw: int
    version: Optional[int]  # None when the byte cannot be decoded
    encoding: str           # "binary", "bcd" or "unknown"


def decode_fw_version(byte: int) -> FwVersion:
    """Decode the firmware-version byte.

    <= 0x19: binary (v15 = 0x0F, v25 = 0x19). From v26 on the byte is two
    decimal digits read as hex (v26 = 0x26), so >= 0x26 with both nibbles
    <= 9 is BCD. Anything else (0x1A-0x25, a nibble > 9) is reported raw.
    """
    byte &= 0xFF
    if byte <= 0x19:
        return FwVersion(byte, byte, "binary")
    hi, lo = byte >> 4, byte & 0xF
    if byte >= 0x26 and hi <= 9 and lo <= 9:
        return FwVersion(byte, hi * 10 + lo, "bcd")
    return FwVersion(byte, None, "unknown")


def encode_fw_version(version: int) -> int:
    """Inverse of decode_fw_version for versions 0-25 and 26-99."""
    if 0 <= version <= 25:
        return version
    if 26 <= version <= 99:
        return (version // 10) << 4 | (version % 10)
    raise ValueError(f"version not encodable: {version!r}")


# --------------------------------------------------------------------------
# Conversions (spec section 6, NOTES.md "Conversions"). Integers only.
# --------------------------------------------------------------------------
def cdiv(a: int, b: int) -> int:
    """Integer division truncating toward zero, like C's `/`."""
    if b == 0:
        raise ZeroDivisionError("cdiv by zero")
    q = abs(a) // abs(b)
    return q if (a >= 0) == (b >= 0) else -q


def supply_mv(adc: int) -> Optional[int]:
    """Supply voltage in mV from the 0x42 reading: 1024 * 4096 / ADC.

    Truncated toward zero. Valid only for 0 < ADC < 4095 (the spec: accurate
    only below 4095; 0 would divide by zero); returns None otherwise.
    """
    if not 0 < adc < 4095:
        return None
    return cdiv(1024 * 4096, adc)


def temperature_c100(adc: int, ref_temp: int, adc_ref: int,
                     supply_mv: Optional[int], temp_scale: int) -> Optional[int]:
    """Temperature in degrees C * 100 from the 0x43 reading.

        T = Ref_Temp + (ADC - ADC_Ref) * Supply / Temp_Scale

    - ref_temp: as stored in flash; a value below 100 is whole degrees and is
      multiplied by 100 first.
    - supply_mv: the supply in mV as returned by supply_mv() (an integer);
      the formula takes it in mV * 100, so it is multiplied by 100 here
      (i.e. the mV value is truncated first, then scaled).
    - The product is formed in (at most) 64 bits and the division truncates
      toward zero like C, also for negative (ADC - ADC_Ref).
    Returns None when the supply is unknown (None) or Temp_Scale is 0.
    """
    if supply_mv is None or temp_scale == 0:
        return None
    ref_c100 = ref_temp * 100 if ref_temp < 100 else ref_temp
    return ref_c100 + cdiv((adc - adc_ref) * (supply_mv * 100), temp_scale)


def o2_mv100(adc: int, opamp_offset: int) -> int:
    """O2 cell voltage in mV * 100 from the 0x44 reading.

        O2 = 100 * ADC / 22 + OpAmp_Offset

    opamp_offset is the already sign-decoded value (mV * 100); the division
    truncates toward zero before the offset is added.
    """
    return cdiv(100 * adc, 22) + opamp_offset


def ppo2_mbar(adc: int, gain: int) -> int:
    """PPO2 in millibar: PPO2 (bar) = ADC * gain / (4096 * 1024).

    gain is a field-calibration word (1024 * PPO2 full scale, full scale
    meaning a 4096-count reading). Computed as ADC * gain * 1000 / 4194304,
    truncated toward zero (NOTES.md: an interpretation kept in one helper).
    """
    return cdiv(adc * gain * 1000, 4096 * 1024)


# Inverses used by the device profiles to turn physical values into the raw
# readings a peripheral returns. Rounded to nearest, clamped to 12 bits.
def _clamp12(v: int) -> int:
    return max(0, min(0xFFF, v))


def adc_for_supply(mv: int) -> int:
    """0x42 reading for a supply voltage in mV (rounded to nearest)."""
    return _clamp12((2 * 1024 * 4096 + mv) // (2 * mv))


def adc_for_temperature(t_c100: int, ref_temp: int, adc_ref: int,
                        supply_mv_: int, temp_scale: int) -> int:
    """0x43 reading for a temperature in C * 100 (rounded to nearest)."""
    ref_c100 = ref_temp * 100 if ref_temp < 100 else ref_temp
    num = (t_c100 - ref_c100) * temp_scale
    den = supply_mv_ * 100
    return _clamp12(adc_ref + round(num / den))


def adc_for_o2(mv100: int, opamp_offset: int) -> int:
    """0x44 reading for an O2 cell voltage in mV * 100 (rounded to nearest)."""
    return _clamp12(round((mv100 - opamp_offset) * 22 / 100))
