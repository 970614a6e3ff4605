"""Flash-map encodings of the 2-wire peripherals (spec section 7, NOTES.md).

Flash words are 14 bits; an erased word reads BLANK (0x3FFF). A map is a
list of `size` words, blank wherever the description puts nothing.

Field encodings:
- text: two 7-bit characters per word, first character in bits 13:7,
  second in bits 6:0, padded with NUL or space;
- date/time: 28 bits over two words, first word = bits 27:14
  (bit 27 unused, minutes 26:21, year-2000 20:14, month 13:10, day 9:5,
  hour 4:0);
- signed values (OpAmp_Offset): 14-bit two's complement;
- field calibration records: 2 words, word 0 = time since manufacture in
  units of 3 h (O2) or 6 h (CO2), word 1 = gain (O2) or 400 ppm reading (CO2).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from datetime import datetime
from typing import NamedTuple, Optional

WORD_MASK = 0x3FFF
BLANK = 0x3FFF

# ---- addresses shared by both maps -------------------------------------
MODEL_ADDR, MODEL_WORDS = 0x00, 7        # 14 characters
MFG_ID_ADDR, MFG_ID_WORDS = 0x07, 3      # 6 characters
MFG_DATE_ADDR = 0x0A                     # 2 words
EXPIRY_ADDR = 0x0C                       # 2 words
SERIAL_ADDR, SERIAL_WORDS = 0x10, 6      # 12 characters
TEMP_SCALE_ADDR = 0x16
REF_TEMP_ADDR = 0x17
ADC_REF_ADDR = 0x18
# ---- O2 only -----------------------------------------------------------
MAP_VERSION_ADDR = 0x0E                  # version << 8 | type
OPAMP_OFFSET_ADDR = 0x19                 # signed
MFG_CAL_ADDR = 0x1A                      # 3 pairs
# ---- CO2 only ----------------------------------------------------------
RGB_OFFSET_ADDR = 0x19                   # 3 words
RGB_GAIN_ADDR = 0x1C                     # 3 words
# ---- field calibrations ------------------------------------------------
CAL_START = 0x20
CAL_END = 0xE0                           # exclusive; 0xE0-0xEF reserved
O2_CAL_UNIT_HOURS = 3
CO2_CAL_UNIT_HOURS = 6
PROTECTED_END = 0x20                     # words 0x00-0x1F: never erase/write
PAGE_WORDS = 16


# ---------------------------------------------------------------------------
# Field encodings
# ---------------------------------------------------------------------------
def encode_text(text: str, n_words: int, pad: str = " ") -> list:
    """Words for a text field of n_words (2 * n_words characters)."""
    if pad not in (" ", "\0"):
        raise ValueError("pad must be space or NUL")
    if len(text) > 2 * n_words:
        raise ValueError(f"text {text!r} longer than {2 * n_words} characters")
    codes = [ord(c) for c in text.ljust(2 * n_words, pad)]
    if any(c > 0x7F for c in codes):
        raise ValueError(f"text {text!r} is not 7-bit ASCII")
    return [codes[2 * i] << 7 | codes[2 * i + 1] for i in range(n_words)]


def decode_text(words) -> str:
    """Text of a text field; trailing NUL and space padding is removed.

    Decision: a blank word (0x3FFF, i.e. two DEL characters) ends the text,
    so an unprogrammed field decodes to "".
    """
    chars = []
    for w in words:
        if w & WORD_MASK == BLANK:
            break
        chars += [chr((w >> 7) & 0x7F), chr(w & 0x7F)]
    return "".join(chars).rstrip("\0 ")


def encode_datetime(dt: datetime) -> tuple:
    """(word0, word1) of a 28-bit date/time; seconds are dropped."""
    if not 2000 <= dt.year <= 2127:
        raise ValueError(f"year {dt.year} outside 2000-2127")
    v = (dt.minute << 21 | (dt.year - 2000) << 14 | dt.month << 10
         | dt.day << 5 | dt.hour)
    return (v >> 14) & WORD_MASK, v & WORD_MASK


def decode_datetime(w0: int, w1: int) -> Optional[datetime]:
    """datetime of a 28-bit date/time, or None if the fields are not a valid
    date (e.g. a blank pair: minutes 63, month 15)."""
    v = (w0 & WORD_MASK) << 14 | (w1 & WORD_MASK)
    minute = (v >> 21) & 0x3F
    year = 2000 + ((v >> 14) & 0x7F)
    month = (v >> 10) & 0xF
    day = (v >> 5) & 0x1F
    hour = v & 0x1F
    try:
        return datetime(year, month, day, hour, minute)
    except ValueError:
        return None


def to_s14(value: int) -> int:
    """14-bit two's complement word of a signed value (-8192..8191)."""
    if not -0x2000 <= value <= 0x1FFF:
        raise ValueError(f"{value} does not fit 14-bit signed")
    return value & WORD_MASK


def from_s14(word: int) -> int:
    """Signed value of a 14-bit two's complement word."""
    word &= WORD_MASK
    return word - 0x4000 if word & 0x2000 else word


def _u14(value: int, what: str) -> int:
    if not 0 <= value <= WORD_MASK:
        raise ValueError(f"{what}={value!r} does not fit 14 bits")
    return value


# ---------------------------------------------------------------------------
# Field calibration records
# ---------------------------------------------------------------------------
@dataclass(frozen=True)
class FieldCal:
    """One field calibration.

    hours: time since manufacture; must be a multiple of the map's unit
        (3 h O2, 6 h CO2) so that the description survives a round trip.
    value: word 1 (O2: gain = 1024 * PPO2 full scale; CO2: 400 ppm reading).
    addr: word address of the record; None = next pair after the previous
        record (the first at 0x20). Decoders always fill it in.
    """
    hours: int
    value: int
    addr: Optional[int] = None


class CalRecord(NamedTuple):
    addr: int    # word address of word 0
    stamp: int   # word 0, in units of 3 h (O2) or 6 h (CO2)
    value: int   # word 1


def cal_timestamp(now: datetime, manufactured: datetime, unit_hours: int) -> int:
    """Record word 0 for a calibration made at `now` (spec 7.1): seconds since
    manufacture / (unit * 3600), truncated. Negative means a clock error."""
    secs = int((now - manufactured).total_seconds())
    if secs < 0:
        raise ValueError("calibration time before manufacture (clock error)")
    return secs // (unit_hours * 3600)


def cal_area_end(words) -> int:
    """End (exclusive) of the calibration area: 0xE0 or the flash size."""
    return min(CAL_END, len(words))


def cal_records(words) -> list:
    """Programmed calibration records in address order.

    Decision: a record counts only when both of its words are programmed. A
    half-written pair (power lost between the two writes) carries no usable
    gain and is ignored; fully blank pairs are free slots.
    """
    out = []
    for a in range(CAL_START, cal_area_end(words) - 1, 2):
        w0, w1 = words[a] & WORD_MASK, words[a + 1] & WORD_MASK
        if w0 != BLANK and w1 != BLANK:
            out.append(CalRecord(a, w0, w1))
    return out


def current_calibration(words) -> Optional[CalRecord]:
    """The record with the largest time stamp; ties go to the higher address
    (it was written later). None when there is no record."""
    best = None
    for r in cal_records(words):
        if best is None or r.stamp >= best.stamp:  # >= : ties -> later (higher)
            best = r
    return best


def calibration_count(words) -> int:
    """Number of programmed calibration records."""
    return len(cal_records(words))


def _place_cals(img: list, cals, unit_hours: int) -> None:
    addr = CAL_START
    end = cal_area_end(img)
    for c in cals:
        if c.addr is not None:
            addr = c.addr
        if addr < CAL_START or addr % 2 or addr + 1 >= end:
            raise ValueError(f"calibration record address {addr:#x} outside area")
        if c.hours < 0 or c.hours % unit_hours:
            raise ValueError(f"calibration hours {c.hours} not a multiple of {unit_hours}")
        stamp = c.hours // unit_hours
        if stamp >= BLANK:  # 0x3FFF would read as a blank word
            raise ValueError(f"calibration hours {c.hours} beyond the 14-bit limit")
        if img[addr] != BLANK or img[addr + 1] != BLANK:
            raise ValueError(f"two calibration records at {addr:#x}")
        img[addr] = stamp
        img[addr + 1] = _u14(c.value, "calibration value")
        addr += 2


def _decode_cals(words, unit_hours: int) -> tuple:
    return tuple(FieldCal(r.stamp * unit_hours, r.value, r.addr)
                 for r in cal_records(words))


# ---------------------------------------------------------------------------
# O2 map (spec 7.1)
# ---------------------------------------------------------------------------
@dataclass(frozen=True)
class O2Map:
    """Readable description of a digital O2 cell's flash.

    ref_temp is stored as is (C * 100, or whole degrees if below 100).
    opamp_offset is signed (mV * 100).
    mfg_cal: the 3 manufacturing PPO2 calibration pairs. The spec only says
        "3 cal x 2 x 14 bit uint"; this project reads each pair as
        (PPO2 in mbar, O2 ADC counts) but the encoder just stores the numbers.
    size: flash size in words (128 for firmware v15, 240 later).
    """
    model: str
    mfg_id: str
    manufactured: datetime
    expires: datetime
    map_version: int
    serial: str
    temp_scale: int
    ref_temp: int
    adc_ref: int
    opamp_offset: int
    mfg_cal: tuple
    field_cals: tuple = ()
    map_type: int = 0x01
    size: int = 240
    text_pad: str = field(default=" ", compare=False)


def _common_image(d) -> list:
    """Blank image with the fields both maps share at the same addresses:
    model, MFG ID, manufacture and expiry dates, serial, Temp_Scale,
    Ref_Temp, ADC_Ref."""
    img = [BLANK] * d.size
    img[MODEL_ADDR:MODEL_ADDR + MODEL_WORDS] = encode_text(d.model, MODEL_WORDS, d.text_pad)
    img[MFG_ID_ADDR:MFG_ID_ADDR + MFG_ID_WORDS] = encode_text(d.mfg_id, MFG_ID_WORDS, d.text_pad)
    img[MFG_DATE_ADDR:MFG_DATE_ADDR + 2] = encode_datetime(d.manufactured)
    img[EXPIRY_ADDR:EXPIRY_ADDR + 2] = encode_datetime(d.expires)
    img[SERIAL_ADDR:SERIAL_ADDR + SERIAL_WORDS] = encode_text(d.serial, SERIAL_WORDS, d.text_pad)
    img[TEMP_SCALE_ADDR] = _u14(d.temp_scale, "temp_scale")
    img[REF_TEMP_ADDR] = _u14(d.ref_temp, "ref_temp")
    img[ADC_REF_ADDR] = _u14(d.adc_ref, "adc_ref")
    return img


def build_o2_map(d: O2Map) -> list:
    """Word image (len d.size) of an O2 description."""
    img = _common_image(d)
    if not (0 <= d.map_version <= 0x3F and 0 <= d.map_type <= 0xFF):
        raise ValueError("map version is 6 bits, type 8 bits")
    img[MAP_VERSION_ADDR] = d.map_version << 8 | d.map_type
    img[OPAMP_OFFSET_ADDR] = to_s14(d.opamp_offset)
    if len(d.mfg_cal) != 3:
        raise ValueError("mfg_cal needs 3 pairs")
    for i, (a, b) in enumerate(d.mfg_cal):
        img[MFG_CAL_ADDR + 2 * i] = _u14(a, "mfg_cal")
        img[MFG_CAL_ADDR + 2 * i + 1] = _u14(b, "mfg_cal")
    _place_cals(img, d.field_cals, O2_CAL_UNIT_HOURS)
    return img


def _common_fields(w) -> dict:
    """The fields both maps share (inverse of _common_image)."""
    return dict(
        model=decode_text(w[MODEL_ADDR:MODEL_ADDR + MODEL_WORDS]),
        mfg_id=decode_text(w[MFG_ID_ADDR:MFG_ID_ADDR + MFG_ID_WORDS]),
        manufactured=decode_datetime(*w[MFG_DATE_ADDR:MFG_DATE_ADDR + 2]),
        expires=decode_datetime(*w[EXPIRY_ADDR:EXPIRY_ADDR + 2]),
        serial=decode_text(w[SERIAL_ADDR:SERIAL_ADDR + SERIAL_WORDS]),
        temp_scale=w[TEMP_SCALE_ADDR],
        ref_temp=w[REF_TEMP_ADDR],
        adc_ref=w[ADC_REF_ADDR],
        size=len(w),
    )


def decode_o2_map(words) -> O2Map:
    """Description of an O2 word image (inverse of build_o2_map)."""
    w = [x & WORD_MASK for x in words]
    return O2Map(
        **_common_fields(w),
        map_version=w[MAP_VERSION_ADDR] >> 8,
        map_type=w[MAP_VERSION_ADDR] & 0xFF,
        opamp_offset=from_s14(w[OPAMP_OFFSET_ADDR]),
        mfg_cal=tuple((w[MFG_CAL_ADDR + 2 * i], w[MFG_CAL_ADDR + 2 * i + 1])
                      for i in range(3)),
        field_cals=_decode_cals(w, O2_CAL_UNIT_HOURS),
    )


# ---------------------------------------------------------------------------
# CO2 map (spec 7.2, preliminary)
# ---------------------------------------------------------------------------
@dataclass(frozen=True)
class CO2Map:
    """Readable description of a CO2 sensor's flash (also used for the CO2
    temperature stick, for which the spec defines no map).

    rgb_offset / rgb_gain: 3 words each, or None to leave them blank.
    Words 0x0E-0x0F and 0x1F are reserved and left blank.
    """
    model: str
    mfg_id: str
    manufactured: datetime
    expires: datetime
    serial: str
    temp_scale: int
    ref_temp: int
    adc_ref: int
    rgb_offset: Optional[tuple] = None
    rgb_gain: Optional[tuple] = None
    field_cals: tuple = ()
    size: int = 240
    text_pad: str = field(default=" ", compare=False)


def build_co2_map(d: CO2Map) -> list:
    """Word image (len d.size) of a CO2 description."""
    img = _common_image(d)
    for base, vals in ((RGB_OFFSET_ADDR, d.rgb_offset), (RGB_GAIN_ADDR, d.rgb_gain)):
        if vals is not None:
            if len(vals) != 3:
                raise ValueError("RGB fields need 3 values")
            img[base:base + 3] = [_u14(v, "rgb") for v in vals]
    _place_cals(img, d.field_cals, CO2_CAL_UNIT_HOURS)
    return img


def _rgb(w, base) -> Optional[tuple]:
    vals = tuple(w[base:base + 3])
    return None if all(v == BLANK for v in vals) else vals


def decode_co2_map(words) -> CO2Map:
    """Description of a CO2 word image (inverse of build_co2_map)."""
    w = [x & WORD_MASK for x in words]
    return CO2Map(
        **_common_fields(w),
        rgb_offset=_rgb(w, RGB_OFFSET_ADDR),
        rgb_gain=_rgb(w, RGB_GAIN_ADDR),
        field_cals=_decode_cals(w, CO2_CAL_UNIT_HOURS),
    )


# ---------------------------------------------------------------------------
# JSON form of a description (used by tb/vectors/flash_*.json)
# ---------------------------------------------------------------------------
def datetime_to_json(dt: Optional[datetime]) -> Optional[dict]:
    if dt is None:
        return None
    return {"year": dt.year, "month": dt.month, "day": dt.day,
            "hour": dt.hour, "minute": dt.minute}


def datetime_from_json(obj: Optional[dict]) -> Optional[datetime]:
    if obj is None:
        return None
    return datetime(obj["year"], obj["month"], obj["day"], obj["hour"], obj["minute"])


def desc_to_json(d) -> dict:
    """Plain-JSON form of an O2Map or CO2Map ("kind": "o2" or "co2")."""
    out = {"kind": "o2" if isinstance(d, O2Map) else "co2"}
    for f in d.__dataclass_fields__:
        v = getattr(d, f)
        if isinstance(v, datetime):
            v = datetime_to_json(v)
        elif f == "field_cals":
            v = [{"hours": c.hours, "value": c.value, "addr": c.addr} for c in v]
        elif isinstance(v, tuple):
            v = [list(x) if isinstance(x, tuple) else x for x in v]
        out[f] = v
    return out


def desc_from_json(obj: dict):
    """Inverse of desc_to_json."""
    kw = dict(obj)
    kind = kw.pop("kind")
    for k in ("manufactured", "expires"):
        kw[k] = datetime_from_json(kw[k])
    kw["field_cals"] = tuple(FieldCal(c["hours"], c["value"], c.get("addr"))
                             for c in kw.get("field_cals", []))
    for k in ("mfg_cal", "rgb_offset", "rgb_gain"):
        if kw.get(k) is not None:
            kw[k] = tuple(tuple(x) if isinstance(x, list) else x for x in kw[k])
    return O2Map(**kw) if kind == "o2" else CO2Map(**kw)
