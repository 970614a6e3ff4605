"""Plain pytest (no simulator): device profiles, PeripheralLogic and the
answer waveform of periph_model."""
import dataclasses

import pytest

import flashmap as fm
import periph_model as pm
import profiles as prof
import protocol as p
from periph_model import Faults, PeripheralLogic

PROFILES = list(prof.PROFILES.values())
BLANK = 0x3FFF


def cmd_frame(cmd, payload=p.UNUSED_PAYLOAD):
    return p.build_frame(cmd, payload)


def answer(logic, cmd, payload=p.UNUSED_PAYLOAD):
    r = logic.handle(cmd_frame(cmd, payload))
    if r is not None:
        assert len(r) == 3 and p.frame_ok(r)
    return r


def word(r):
    return r[0] << 8 | r[1]


def read(logic, addr):
    return answer(logic, *p.addr_cmd(p.CMD_READ, addr))


def write(logic, addr, data):
    return logic.handle(p.build_frame(*p.write_cmd(addr, data)))


# ---------------------------------------------------------------- profiles
def test_profile_table():
    assert [(x.name, x.fw_byte, x.type_byte, x.flash_size, x.exec_max_us)
            for x in PROFILES] == [
        ("o2_v15", 0x0F, 1, 128, 4500), ("o2_v18", 0x12, 1, 240, 10000),
        ("o2_v26", 0x26, 1, 240, 10000), ("co2", 0x12, 2, 240, 10000),
        ("co2_stick", 0x12, 3, 240, 10000)]
    assert all(x.exec_min_us == 3000 for x in PROFILES)
    assert prof.O2_V26.fw_version.version == 26
    assert prof.O2_V15.fw_version.version == 15


@pytest.mark.parametrize("pr", PROFILES, ids=lambda x: x.name)
def test_profile_readings_match_physical_values(pr):
    d = pr.flash_desc
    assert all(0 <= a <= 0xFFF for a in (pr.adc_ref_voltage, pr.adc_temperature, pr.adc_o2))
    s = p.supply_mv(pr.adc_ref_voltage)
    assert abs(s - pr.supply_mv) <= 2
    t = p.temperature_c100(pr.adc_temperature, d.ref_temp, d.adc_ref, s, d.temp_scale)
    assert abs(t - pr.temperature_c100) <= 40          # within one ADC count
    if pr.o2_mv100 is not None:
        assert abs(p.o2_mv100(pr.adc_o2, d.opamp_offset) - pr.o2_mv100) <= 5


@pytest.mark.parametrize("pr", PROFILES, ids=lambda x: x.name)
def test_profile_flash_decodes(pr):
    words = list(pr.flash)
    if pr.type_byte == 1:
        d = fm.decode_o2_map(words)
        assert d.map_type == 1
        assert fm.calibration_count(words) >= 3         # a few field calibrations
    else:
        d = fm.decode_co2_map(words)
    assert d.model and d.serial and d.manufactured < d.expires
    assert d.size == pr.flash_size


def test_stick_has_no_rgb_and_no_cals():
    d = fm.decode_co2_map(list(prof.CO2_STICK.flash))
    assert d.rgb_offset is None and d.rgb_gain is None and d.field_cals == ()


# ---------------------------------------------------------------- answering commands
@pytest.mark.parametrize("pr", PROFILES, ids=lambda x: x.name)
def test_config_and_firmware(pr):
    lg = PeripheralLogic(pr)
    r = answer(lg, 0x40)
    assert r[0] >> 1 == pr.config_bits
    assert (r[0] & 1) << 8 | r[1] == pr.flash_size
    assert answer(lg, 0x41)[:2] == bytes([pr.fw_byte, pr.type_byte])
    # unused payload may be anything
    assert answer(lg, 0x41, 0xF0) == answer(lg, 0x41, 0x00)


def test_config_bits_nonzero_v26():
    r = answer(PeripheralLogic(prof.O2_V26), 0x40)
    assert r[:2] == bytes([0x02, 0xF0])


@pytest.mark.parametrize("pr", PROFILES, ids=lambda x: x.name)
def test_readings(pr):
    lg = PeripheralLogic(pr)
    assert word(answer(lg, 0x42)) == pr.adc_ref_voltage
    assert word(answer(lg, 0x43)) == pr.adc_temperature
    assert word(answer(lg, 0x44)) == pr.adc_o2
    assert all(answer(lg, c)[0] <= 0x0F for c in (0x42, 0x43, 0x44))   # 12 bits


@pytest.mark.parametrize("pr", PROFILES, ids=lambda x: x.name)
def test_read_every_word(pr):
    lg = PeripheralLogic(pr)
    for a in range(pr.flash_size):
        r = read(lg, a)
        assert word(r) == pr.flash[a] and r[0] <= 0x3F
    for a in (pr.flash_size, pr.flash_size + 1, 0x1FF):
        assert read(lg, a) is None
        assert lg.log[-1].reason == pm.R_OUT_OF_RANGE


@pytest.mark.parametrize("pr", PROFILES, ids=lambda x: x.name)
def test_find_free(pr):
    lg = PeripheralLogic(pr)
    ff = lambda a: word(answer(lg, *p.addr_cmd(p.CMD_FIND_FREE, a)))
    first_blank = next(a for a in range(0x20, pr.flash_size) if pr.flash[a] == BLANK)
    assert ff(0x20) == first_blank
    assert ff(pr.flash_size - 1) == pr.flash_size - 1    # last word is blank
    assert answer(lg, *p.addr_cmd(p.CMD_FIND_FREE, pr.flash_size)) is None
    assert answer(lg, *p.addr_cmd(p.CMD_FIND_FREE, 0x1FF)) is None


def test_find_free_skips_programmed_and_reports_size_when_full():
    lg = PeripheralLogic(prof.O2_V18)
    lg.flash[0x40] = 0x1234
    lg.flash[0x41] = 0x0000
    assert word(answer(lg, 0x46, 0x40)) == 0x42
    for a in range(0x80, 240):
        lg.flash[a] = 0
    assert word(answer(lg, 0x46, 0x80)) == 240                  # none left: size
    lg.flash = [0] * 240
    assert word(answer(lg, 0x46, 0x00)) == 240


def test_find_free_and_read_above_0x100():
    """The largest flash the 9-bit size of 0x40 can announce: 511 words."""
    pr = dataclasses.replace(prof.O2_V18, flash=tuple([BLANK] * 511))
    lg = PeripheralLogic(pr)
    assert answer(lg, 0x40)[:2] == bytes([0x01, 0xFF])
    lg.flash[0x100] = 0
    assert word(answer(lg, 0x47, 0x00)) == 0x101
    assert word(answer(lg, 0x49, 0x00)) == 0
    assert word(answer(lg, 0x49, 0xFE)) == BLANK
    assert answer(lg, 0x47, 0xFF) is None                       # 0x1FF >= 511
    assert answer(lg, 0x49, 0xFF) is None


def test_profile_rejects_flash_size_beyond_9_bits():
    with pytest.raises(ValueError):
        dataclasses.replace(prof.O2_V18, flash=tuple([BLANK] * 512))
    with pytest.raises(ValueError):
        dataclasses.replace(prof.O2_V18, config_bits=0x80)


@pytest.mark.parametrize("pr", PROFILES, ids=lambda x: x.name)
def test_write_once(pr):
    lg = PeripheralLogic(pr)
    a = next(a for a in range(0x20, pr.flash_size) if pr.flash[a] == BLANK)
    assert write(lg, a, 0x1555) is None and lg.log[-1].reason == pm.R_WRITTEN
    assert word(read(lg, a)) == 0x1555
    assert write(lg, a, 0x0000) is None and lg.log[-1].reason == pm.R_NOT_BLANK
    assert word(read(lg, a)) == 0x1555                          # unchanged
    # a programmed manufacturer word is not blank either
    assert write(lg, 0x00, 0) is None and lg.flash[0] == pr.flash[0]
    # out of range, incl. the address bits carried in the data MSB
    assert write(lg, pr.flash_size, 0) is None
    assert lg.log[-1].reason == pm.R_OUT_OF_RANGE and lg.log[-1].addr == pr.flash_size
    assert lg.flash == [0x1555 if i == a else w for i, w in enumerate(pr.flash)]


def test_write_high_address_bits():
    pr = dataclasses.replace(prof.O2_V18, flash=tuple([BLANK] * 511))
    lg = PeripheralLogic(pr)
    write(lg, 0x1EF, 0x2AAA)
    write(lg, 0x0EF, 0x1111)
    write(lg, 0x06F, 0x0222)
    assert (lg.flash[0x1EF], lg.flash[0x0EF], lg.flash[0x06F]) == (0x2AAA, 0x1111, 0x0222)
    assert sum(w != BLANK for w in lg.flash) == 3


def test_model_does_not_protect_manufacturer_area():
    """Blocking 0x00-0x1F is the host core's job; the device obeys."""
    lg = PeripheralLogic(prof.O2_V18)
    assert lg.handle(cmd_frame(0x4A, 0x05)) is None and lg.log[-1].reason == pm.R_ERASED
    assert lg.flash[0x00:0x10] == [BLANK] * 16
    assert lg.flash[0x10:0x20] == list(prof.O2_V18.flash[0x10:0x20])
    write(lg, 0x03, 0x0123)
    assert lg.flash[0x03] == 0x0123


@pytest.mark.parametrize("pr", PROFILES, ids=lambda x: x.name)
def test_erase_page(pr):
    lg = PeripheralLogic(pr)
    for a in range(0x20, 0x50):
        lg.flash[a] = a
    assert lg.handle(cmd_frame(*p.addr_cmd(p.CMD_ERASE, 0x37))) is None
    assert lg.log[-1].reason == pm.R_ERASED
    assert lg.flash[0x30:0x40] == [BLANK] * 16
    assert lg.flash[0x20:0x30] == list(range(0x20, 0x30))
    assert lg.flash[0x40:0x50] == list(range(0x40, 0x50))
    last_page = (pr.flash_size - 1) & ~15
    lg.flash[pr.flash_size - 1] = 0
    lg.handle(cmd_frame(0x4A, pr.flash_size - 1))
    assert lg.flash[last_page:] == [BLANK] * (pr.flash_size - last_page)
    before = list(lg.flash)
    assert lg.handle(cmd_frame(*p.addr_cmd(p.CMD_ERASE, pr.flash_size))) is None
    assert lg.log[-1].reason == pm.R_OUT_OF_RANGE and lg.flash == before


def test_erased_word_can_be_written_again():
    lg = PeripheralLogic(prof.O2_V18)
    write(lg, 0x40, 1)
    lg.handle(cmd_frame(0x4A, 0x40))
    write(lg, 0x40, 2)
    assert lg.flash[0x40] == 2


@pytest.mark.parametrize("cmd", list(range(0x00, 0x40)) + [0x45] + list(range(0x4C, 0x80)))
def test_reserved_commands_silent(cmd):
    lg = PeripheralLogic(prof.O2_V18)
    assert lg.handle(cmd_frame(cmd)) is None
    assert lg.log[-1].reason == pm.R_RESERVED
    assert lg.flash == list(prof.O2_V18.flash)


@pytest.mark.parametrize("pr", PROFILES, ids=lambda x: x.name)
def test_bad_checksum_and_length(pr):
    lg = PeripheralLogic(pr)
    for cmd in (0x40, 0x41, 0x48, 0x46):
        f = bytearray(cmd_frame(cmd, 0x00))
        f[-1] ^= 0x01
        assert lg.handle(bytes(f)) is None and lg.log[-1].reason == pm.R_BAD_CHECKSUM
    # a write with a bad checksum must not write
    f = bytearray(p.build_frame(*p.write_cmd(0x7F, 0)))
    f[-1] ^= 0x80
    assert lg.handle(bytes(f)) is None and lg.flash[0x7F] == pr.flash[0x7F] == BLANK
    # wrong length for the command byte
    for f in (b"", b"\x41", b"\x41\xaa", p.build_frame(0x41, 0xAA) + b"\x00",
              bytes([0x85, 0x12, p.checksum([0x85, 0x12])])):
        assert lg.handle(f) is None and lg.log[-1].reason == pm.R_BAD_LENGTH


def test_log_records():
    lg = PeripheralLogic(prof.O2_V15)
    lg.handle(cmd_frame(0x41))
    lg.handle(cmd_frame(0x48, 0x7F))
    lg.handle(cmd_frame(0x48, 0x80))
    assert [(r.name, r.reason, r.addr) for r in lg.log] == [
        ("FIRMWARE", pm.R_ANSWERED, None), ("READ", pm.R_ANSWERED, 0x7F),
        ("READ", pm.R_OUT_OF_RANGE, 0x80)]
    assert lg.log[0].response == p.response_frame(0x0F, 0x01)


def test_logic_copies_flash():
    lg = PeripheralLogic(prof.O2_V18)
    lg.handle(cmd_frame(0x4A, 0x20))
    assert PeripheralLogic(prof.O2_V18).flash == list(prof.O2_V18.flash)


def test_cal_record_written_by_the_driver_way():
    """A new calibration goes into the first blank pair (command 0x46)."""
    lg = PeripheralLogic(prof.O2_V18)
    a = word(answer(lg, 0x46, 0x20))
    write(lg, a, 800)
    write(lg, a + 1, 3700)
    cur = fm.current_calibration(lg.flash)
    assert cur == fm.CalRecord(a, 800, 3700)


# ---------------------------------------------------------------- faults and waveform
def test_faults_validation():
    for kw in ({"truncate": 3}, {"bad_stop_bit": 3}, {"stop_bits": 3}, {"duty": 1.0},
               {"baud": 0}, {"response_delay_us": -1}):
        with pytest.raises(ValueError):
            Faults(**kw)


def test_wire_bytes():
    r = p.response_frame(0x12, 0x34)
    assert Faults().wire_bytes(r) == r
    assert Faults(bad_checksum=True).wire_bytes(r) == r[:2] + bytes([r[2] ^ 1])
    assert Faults(truncate=1).wire_bytes(r) == r[:1]
    assert Faults(truncate=2, bad_checksum=True).wire_bytes(r) == r[:2]


RESP = p.response_frame(0x0F, 0x01)
FAULT_CASES = [
    Faults(), Faults(baud=30750), Faults(baud=31750), Faults(carrier_hz=0.9e6),
    Faults(carrier_hz=1.1e6), Faults(duty=0.3), Faults(duty=0.7), Faults(baseband=True),
    Faults(stop_bits=1), Faults(mark_us=100), Faults(baud=30750, carrier_hz=1.1e6, duty=0.3),
    Faults(baud=31750, carrier_hz=0.9e6, duty=0.7, stop_bits=1),
]


@pytest.mark.parametrize("f", FAULT_CASES, ids=repr)
def test_response_waveform_decodes(f):
    t0 = 123_456_789
    ev = pm.response_events(RESP, f, t0)
    assert ev[0] == (t0, 1, 1)                                   # mark: carrier on
    assert ev[-1][1:] == (0, 0)
    assert all(a[0] < b[0] for a, b in zip(ev, ev[1:]))          # strictly increasing
    assert all(oe == 1 for _, _, oe in ev[:-1])
    dur = (ev[-1][0] - t0) / 1e6
    assert dur == pytest.approx(f.response_duration_us(3), abs=0.001)
    assert pm.decode_events(ev, f.baud) == (RESP, False)


@pytest.mark.parametrize("f", [Faults(), Faults(carrier_hz=0.9e6, duty=0.3),
                               Faults(carrier_hz=1.1e6, duty=0.7)], ids=repr)
def test_carrier_shape(f):
    ev = pm.response_events(RESP, f, 0)
    per = 1e12 / f.carrier_hz
    mark_end = f.mark_time_us() * 1e6
    rises = [t for t, o, _ in ev if o == 1 and t < mark_end - per]
    falls = [t for t, o, _ in ev if o == 0 and t < mark_end - per]
    assert len(rises) >= 25
    for a, b in zip(rises, rises[1:]):
        assert abs((b - a) - per) <= 1                           # ps rounding
    for r, fl in zip(rises, falls):
        assert abs((fl - r) - f.duty * per) <= 1
    # phase continuity: a rise is on the t0 + k*P grid, or is the start of a
    # 1-bit that begins inside a carrier high half
    bit = 1e12 / f.baud
    boundaries = [mark_end + i * bit for i in range(40)]
    for t, o, _ in ev[:-1]:
        if o == 1:
            on_grid = abs(t - round(t / per) * per) <= 1
            at_bit = any(abs(t - b) <= 1 for b in boundaries)
            assert on_grid or at_bit, t


def test_baseband_is_dc():
    ev = pm.response_events(RESP, Faults(baseband=True), 0)
    # mark + bits: a handful of level changes, not a carrier
    assert len(ev) < 40


def test_fault_bad_stop_bit_and_truncate_waveform():
    for i in range(3):
        ev = pm.response_events(RESP, Faults(bad_stop_bit=i), 0)
        data, framing = pm.decode_events(ev)
        assert framing and data == RESP[:i + 1]
    ev = pm.response_events(Faults(truncate=2).wire_bytes(RESP), Faults(truncate=2), 0)
    assert pm.decode_events(ev) == (RESP[:2], False)
    assert (ev[-1][0]) / 1e6 == pytest.approx(Faults().response_duration_us(2), abs=0.001)


def test_no_mark():
    ev = pm.response_events(RESP, Faults(mark_us=0), 0)
    assert ev[0] == (0, 0, 1)                 # starts straight with the start bit
    assert pm.decode_events(ev)[0] == RESP


def test_uart_parser():
    bits = [1, 1] + p.uart_bits(0x41) + p.uart_bits(0xAA, 1) + p.uart_bits(0x14)
    out, starts, pending, err = pm._parse_uart(bits)
    assert out == [0x41, 0xAA, 0x14] and not err and pending is None
    assert starts == [2, 13, 23]
    out, _, pending, err = pm._parse_uart(bits[:20])
    assert out == [0x41] and pending == 13 and not err
    bad = p.uart_bits(0x41)
    bad[9] = 0
    assert pm._parse_uart(bad)[3] is True
