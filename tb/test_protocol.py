"""Plain pytest (no simulator): protocol.py and flashmap.py against the shared
vectors in tb/vectors/, plus round trips and the firmware-version rules."""
import json
import os
import re
from datetime import datetime, timedelta

import pytest

import flashmap as fm
import protocol as p

VEC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "vectors")


def load(name):
    with open(os.path.join(VEC, name)) as f:
        return json.load(f)


FRAMES = load("frames.json")["vectors"]
CONV = load("conversions.json")
FLASH_O2 = load("flash_o2.json")
FLASH_CO2 = load("flash_co2.json")


# ---------------------------------------------------------------- frames
@pytest.mark.parametrize("v", FRAMES, ids=lambda v: v["hex"])
def test_frame_vector(v):
    assert p.checksum(v["bytes_in"]) == v["checksum"]
    assert v["frame"] == v["bytes_in"] + [v["checksum"]]
    assert sum(v["frame"]) % 256 == 0xFF
    assert v["hex"] == " ".join(f"{b:02X}" for b in v["frame"])
    if v["kind"] == "response":
        assert list(p.response_frame(*v["bytes_in"])) == v["frame"]
        return
    cmd, payload = v["cmd"], v["payload"]
    assert list(p.build_frame(cmd, payload)) == v["frame"]
    assert p.frame_len(cmd) == v["frame_len"] == len(v["frame"])
    assert p.command_name(cmd) == v["name"]
    assert p.expects_response(cmd) == v["expects_response"]
    if v["name"] == "WRITE":
        assert p.decode_write(cmd, payload) == (v["addr"], v["data"])
        assert p.write_cmd(v["addr"], v["data"]) == (cmd, payload)
    elif "addr" in v:
        assert p.decode_addr(cmd, payload) == v["addr"]
        assert p.addr_cmd(cmd & ~1, v["addr"]) == (cmd, payload & 0xFF)


def test_notes_examples_present():
    hexes = {v["hex"] for v in FRAMES}
    assert {"41 AA 14", "44 AA 11", "85 12 34 34"} <= hexes


def test_checksum_examples():
    assert p.checksum([0x41, 0xAA]) == 0x14
    assert p.checksum([0x44, 0xAA]) == 0x11
    assert p.checksum([0x85, 0x12, 0x34]) == 0x34
    assert p.checksum([]) == 0xFF


def test_build_frame_3_byte_drops_payload_msb():
    assert p.build_frame(0x48, 0x1234) == bytes([0x48, 0x34, p.checksum([0x48, 0x34])])


def test_build_frame_range():
    with pytest.raises(ValueError):
        p.build_frame(0x100, 0)
    with pytest.raises(ValueError):
        p.build_frame(0x40, 0x10000)


def test_frame_ok():
    assert p.frame_ok(p.build_frame(0x41, 0xAA))
    assert not p.frame_ok(bytes([0x41, 0xAA, 0x15]))


def test_uart_bits():
    assert p.uart_bits(0x41) == [0, 1, 0, 0, 0, 0, 0, 1, 0, 1, 1]
    assert p.uart_bits(0xFF, stop_bits=1) == [0] + [1] * 9
    assert len(p.uart_bits(0)) == 11


def test_command_table():
    names = {c: p.command_name(c) for c in range(256)}
    assert [c for c, n in names.items() if n == "RESERVED"] == \
        list(range(0x00, 0x40)) + [0x45] + list(range(0x4C, 0x80))
    assert all(names[c] == "WRITE" for c in range(0x80, 0x100))
    assert (names[0x40], names[0x41], names[0x42], names[0x43], names[0x44]) == \
        ("CONFIG", "FIRMWARE", "REF_VOLTAGE", "TEMPERATURE", "O2_VOLTAGE")
    assert names[0x46] == names[0x47] == "FIND_FREE"
    assert names[0x48] == names[0x49] == "READ"
    assert names[0x4A] == names[0x4B] == "ERASE"
    answering = [c for c in range(256) if p.expects_response(c)]
    assert answering == [0x40, 0x41, 0x42, 0x43, 0x44, 0x46, 0x47, 0x48, 0x49]


def test_frame_len_all():
    assert all(p.frame_len(c) == 3 for c in range(0x80))
    assert all(p.frame_len(c) == 4 for c in range(0x80, 0x100))


def test_write_addressing_round_trip():
    for addr in range(0x200):
        for data in (0, 1, 0x1555, 0x2AAA, 0x3FFE, 0x3FFF):
            cmd, payload = p.write_cmd(addr, data)
            assert 0x80 <= cmd <= 0xFF and 0 <= payload <= 0xFFFF
            assert p.decode_write(cmd, payload) == (addr, data)
            frame = p.build_frame(cmd, payload)
            assert len(frame) == 4 and frame[0] & 0x7F == addr & 0x7F
            assert frame[1] >> 6 == addr >> 7
    with pytest.raises(ValueError):
        p.write_cmd(0x200, 0)
    with pytest.raises(ValueError):
        p.write_cmd(0, 0x4000)


def test_addr_cmd_round_trip():
    for base in (p.CMD_FIND_FREE, p.CMD_READ, p.CMD_ERASE):
        for addr in range(0x200):
            cmd, payload = p.addr_cmd(base, addr)
            assert cmd == base | (addr >> 8) and payload == addr & 0xFF
            assert p.decode_addr(cmd, payload) == addr
    with pytest.raises(ValueError):
        p.addr_cmd(0x40, 0)
    with pytest.raises(ValueError):
        p.addr_cmd(p.CMD_READ, 0x200)


def test_enums_match_rtl_defines():
    """Status and phase codes are part of the programming model."""
    path = os.path.join(os.path.dirname(VEC), "..", "rtl", "twh_defs.vh")
    text = open(path).read()
    ph = {m[0]: int(m[1]) for m in re.findall(r"`define TWH_PH_(\w+)\s+3'd(\d+)", text)}
    st = {m[0]: int(m[1]) for m in re.findall(r"`define TWH_ST_(\w+)\s+4'd(\d+)", text)}
    assert ph == {e.name: e.value for e in p.Phase}
    assert st == {e.name: e.value for e in p.Status}


# ---------------------------------------------------------------- firmware version
@pytest.mark.parametrize("byte,version", [
    (0x0F, 15), (0x12, 18), (0x19, 25), (0x26, 26), (0x1A, None), (0x2A, None),
    (0x00, 0), (0x25, None), (0x20, None), (0x30, 30), (0x99, 99), (0x9A, None),
    (0xA0, None), (0xFF, None)])
def test_fw_version(byte, version):
    v = p.decode_fw_version(byte)
    assert v.raw == byte and v.version == version
    if version is None:
        assert v.encoding == "unknown"
    else:
        assert v.encoding == ("binary" if byte <= 0x19 else "bcd")


def test_fw_version_vectors_and_inverse():
    for v in CONV["fw_version"]:
        d = p.decode_fw_version(v["byte"])
        assert (d.version, d.encoding) == (v["version"], v["encoding"])
    for ver in list(range(0, 26)) + list(range(26, 100)):
        assert p.decode_fw_version(p.encode_fw_version(ver)).version == ver


# ---------------------------------------------------------------- conversions
def test_cdiv_truncates_toward_zero():
    assert p.cdiv(7, 2) == 3 and p.cdiv(-7, 2) == -3
    assert p.cdiv(7, -2) == -3 and p.cdiv(-7, -2) == 3
    with pytest.raises(ZeroDivisionError):
        p.cdiv(1, 0)


def test_conversion_vectors():
    for v in CONV["supply"]:
        assert p.supply_mv(v["adc"]) == v["supply_mv"], v
    for v in CONV["temperature"]:
        got = p.temperature_c100(v["adc"], v["ref_temp"], v["adc_ref"],
                                 v["supply_mv"], v["temp_scale"])
        assert got == v["temperature_c100"], v
    for v in CONV["o2"]:
        assert p.o2_mv100(v["adc"], v["opamp_offset"]) == v["o2_mv100"], v
    for v in CONV["ppo2"]:
        assert p.ppo2_mbar(v["adc"], v["gain"]) == v["ppo2_mbar"], v


def test_conversion_hand_values():
    assert p.supply_mv(2048) == 2048
    assert p.supply_mv(4095) is None and p.supply_mv(0) is None
    # negative step truncates toward zero (floor would give 2461)
    assert p.temperature_c100(1999, 2500, 2000, 3000, 7800) == 2462
    assert p.temperature_c100(1994, 25, 2000, 3300, 7800) == 2247
    assert p.o2_mv100(22, 0) == 100
    assert p.ppo2_mbar(4096, 1024) == 1000


def test_inverse_conversions():
    for mv in range(1100, 4000, 37):
        adc = p.adc_for_supply(mv)
        assert abs(p.supply_mv(adc) - mv) <= mv * mv // 4194304 + 1
    for t in range(-1000, 5000, 77):
        adc = p.adc_for_temperature(t, 2500, 2000, 3100, 7800)
        assert abs(p.temperature_c100(adc, 2500, 2000, 3100, 7800) - t) <= 40
    for mv100 in range(0, 15000, 111):
        adc = p.adc_for_o2(mv100, -42)
        assert abs(p.o2_mv100(adc, -42) - mv100) <= 5


# ---------------------------------------------------------------- flash encodings
def test_text_encoding_vectors():
    for c in FLASH_O2["encodings"]["text"]:
        assert fm.encode_text(c["text"], c["n_words"], c["pad"]) == c["words"]
        assert fm.decode_text(c["words"]) == c["text"]


def test_text_rules():
    assert fm.encode_text("AB", 1) == [ord("A") << 7 | ord("B")]
    assert fm.decode_text([ord("A") << 7 | 0, 0]) == "A"
    assert fm.decode_text([ord("A") << 7 | ord(" ")]) == "A"
    assert fm.decode_text([fm.BLANK] * 3) == ""
    assert fm.decode_text([ord("A") << 7 | ord("B"), fm.BLANK]) == "AB"
    with pytest.raises(ValueError):
        fm.encode_text("ABC", 1)
    with pytest.raises(ValueError):
        fm.encode_text("\u00e9", 1)


def test_datetime_vectors():
    for c in FLASH_O2["encodings"]["datetime"]:
        dt = fm.datetime_from_json(c["datetime"])
        assert fm.decode_datetime(*c["words"]) == dt
        if dt is not None:
            assert list(fm.encode_datetime(dt)) == c["words"]


def test_datetime_round_trip_and_bits():
    dt = datetime(2000, 1, 1, 0, 0)
    while dt.year < 2128:
        w0, w1 = fm.encode_datetime(dt)
        assert 0 <= w0 <= 0x1FFF and 0 <= w1 <= 0x3FFF  # bit 27 unused
        assert fm.decode_datetime(w0, w1) == dt
        dt += timedelta(days=37, hours=5, minutes=13)
    w0, w1 = fm.encode_datetime(datetime(2017, 11, 17, 9, 30))
    v = w0 << 14 | w1
    assert (v >> 21 & 63, v >> 14 & 127, v >> 10 & 15, v >> 5 & 31, v & 31) == \
        (30, 17, 11, 17, 9)
    assert fm.decode_datetime(0x3FFF, 0x3FFF) is None
    with pytest.raises(ValueError):
        fm.encode_datetime(datetime(1999, 12, 31))


def test_s14():
    for c in FLASH_O2["encodings"]["s14"]:
        assert fm.to_s14(c["value"]) == c["word"]
        assert fm.from_s14(c["word"]) == c["value"]
    for v in range(-8192, 8192):
        assert fm.from_s14(fm.to_s14(v)) == v
    with pytest.raises(ValueError):
        fm.to_s14(8192)


# ---------------------------------------------------------------- flash maps
MAPS = [(m, "o2") for m in FLASH_O2["maps"]] + [(m, "co2") for m in FLASH_CO2["maps"]]


@pytest.mark.parametrize("entry,kind", MAPS, ids=lambda x: x if isinstance(x, str) else "")
def test_flash_map_vector(entry, kind):
    d = fm.desc_from_json(entry["description"])
    build, decode = ((fm.build_o2_map, fm.decode_o2_map) if kind == "o2"
                     else (fm.build_co2_map, fm.decode_co2_map))
    words = entry["words"]
    assert build(d) == words
    assert decode(words) == d
    assert fm.desc_to_json(d) == entry["description"]
    for row in entry["layout"]:
        a = row["addr"]
        assert words[a:a + len(row["words"])] == row["words"]
    dec = entry["decoded"]
    assert len(words) == dec["flash_size"]
    assert fm.decode_text(words[0:7]) == dec["model"]
    assert fm.decode_text(words[7:10]) == dec["mfg_id"]
    assert fm.decode_text(words[0x10:0x16]) == dec["serial"]
    assert fm.decode_datetime(*words[0x0A:0x0C]) == fm.datetime_from_json(dec["manufactured"])
    assert fm.decode_datetime(*words[0x0C:0x0E]) == fm.datetime_from_json(dec["expires"])
    assert (words[0x16], words[0x17], words[0x18]) == \
        (dec["temp_scale"], dec["ref_temp"], dec["adc_ref"])
    if kind == "o2":
        assert fm.from_s14(words[0x19]) == dec["opamp_offset"]
        assert words[0x19] == dec["opamp_offset_word"]
        assert words[0x0E] == dec["map_version"] << 8 | dec["map_type"]
    cur = fm.current_calibration(words)
    exp = dec["current_calibration"]
    assert (None if cur is None else [cur.addr, cur.stamp, cur.value]) == \
        (None if exp is None else [exp["addr"], exp["stamp"], exp["value"]])
    assert fm.calibration_count(words) == dec["calibration_count"]
    # everything the description does not place is blank
    placed = set()
    for row in entry["layout"]:
        placed |= set(range(row["addr"], row["addr"] + len(row["words"])))
    assert all(w == fm.BLANK for a, w in enumerate(words) if a not in placed)


@pytest.mark.parametrize("case", FLASH_O2["calibration_cases"], ids=lambda c: c["note"])
def test_calibration_cases(case):
    words = [fm.BLANK] * case["size"]
    for a, w0, w1 in case["pairs"]:
        words[a], words[a + 1] = w0, w1
    cur = fm.current_calibration(words)
    exp = case["current_calibration"]
    assert (None if cur is None else cur._asdict()) == exp
    assert fm.calibration_count(words) == case["calibration_count"]


def test_cal_area_ends():
    words = [fm.BLANK] * 240
    words[0xE0], words[0xE1] = 5, 5      # reserved area: not a record
    assert fm.calibration_count(words) == 0
    words = [fm.BLANK] * 128
    words[0x7E], words[0x7F] = 5, 5      # v15: the area ends with the flash
    assert fm.current_calibration(words).addr == 0x7E


def test_cal_timestamp():
    m = datetime(2017, 11, 17, 9, 30)
    assert fm.cal_timestamp(m + timedelta(hours=8, minutes=59), m, 3) == 2
    assert fm.cal_timestamp(m + timedelta(hours=9), m, 3) == 3
    assert fm.cal_timestamp(m + timedelta(hours=12), m, 6) == 2
    with pytest.raises(ValueError):
        fm.cal_timestamp(m - timedelta(seconds=1), m, 3)


def test_builder_rejects_bad_descriptions():
    base = fm.desc_from_json(FLASH_O2["maps"][0]["description"])
    import dataclasses
    with pytest.raises(ValueError):   # hours not a multiple of 3
        fm.build_o2_map(dataclasses.replace(base, field_cals=(fm.FieldCal(4, 1),)))
    with pytest.raises(ValueError):   # two records in one pair
        fm.build_o2_map(dataclasses.replace(
            base, field_cals=(fm.FieldCal(3, 1, 0x20), fm.FieldCal(6, 1, 0x20))))
    with pytest.raises(ValueError):   # beyond a 128-word flash
        fm.build_o2_map(dataclasses.replace(
            base, size=128, field_cals=(fm.FieldCal(3, 1, 0x80),)))
    with pytest.raises(ValueError):   # opamp offset out of 14-bit signed range
        fm.build_o2_map(dataclasses.replace(base, opamp_offset=9000))


def test_sequential_cal_placement():
    base = fm.desc_from_json(FLASH_O2["maps"][0]["description"])
    import dataclasses
    d = dataclasses.replace(base, field_cals=tuple(fm.FieldCal(3 * i, 3000 + i)
                                                   for i in range(96)))
    words = fm.build_o2_map(d)
    assert fm.calibration_count(words) == 96
    assert fm.current_calibration(words) == fm.CalRecord(0xDE, 95, 3095)
    assert words[0xE0:0xF0] == [fm.BLANK] * 16
    with pytest.raises(ValueError):   # 97 records do not fit
        fm.build_o2_map(dataclasses.replace(
            base, field_cals=tuple(fm.FieldCal(3 * i, 1) for i in range(97))))
