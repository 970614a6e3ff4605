"""Device profiles for the peripheral model: what each kind of device answers.

Each profile is written as physical values (supply voltage, temperature, O2
cell voltage) and a readable flash description; the raw 12-bit readings a
device returns for 0x42/0x43/0x44 are derived by inverting the conversions of
protocol.py, and the flash image is built with flashmap.py.

Profiles are immutable. PeripheralLogic copies the flash image, so writes
and erases made during a test never leak into another test.
"""
from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime
from typing import Optional, Union

import flashmap as fm
import protocol as p


@dataclass(frozen=True)
class Profile:
    name: str
    fw_byte: int            # 0x41 MSB
    type_byte: int          # 0x41 LSB: 1 O2, 2 CO2, 3 CO2 temperature stick
    config_bits: int        # 7 bits, 0x40 MSB bits 7:1 (meaning not specified)
    flash_desc: Union[fm.O2Map, fm.CO2Map]
    flash: tuple            # word image, len == flash size
    supply_mv: int          # physical values the readings were derived from
    temperature_c100: int
    o2_mv100: Optional[int]
    adc_ref_voltage: int    # 0x42 reading
    adc_temperature: int    # 0x43 reading
    adc_o2: int             # 0x44 reading
    exec_min_us: int = 3000    # execute carrier the firmware needs
    exec_max_us: int = 10000   # longest execute phase it tolerates

    def __post_init__(self):
        # the 0x40 answer carries the size in 9 bits and the config in 7
        if not 0 < len(self.flash) <= 0x1FF:
            raise ValueError("flash size must be 1-511 words")
        if not 0 <= self.config_bits <= 0x7F:
            raise ValueError("config_bits is 7 bits")

    @property
    def flash_size(self) -> int:
        return len(self.flash)

    @property
    def fw_version(self) -> p.FwVersion:
        return p.decode_fw_version(self.fw_byte)

    def config_response(self) -> tuple:
        """(MSB, LSB) of the 0x40 answer: config bits + 9-bit flash size."""
        return ((self.config_bits << 1) | (self.flash_size >> 8)) & 0xFF, self.flash_size & 0xFF


def _make(name, fw_byte, type_byte, desc, *, supply_mv, temperature_c100,
          o2_mv100=None, adc_o2=None, config_bits=0, exec_min_us=3000,
          exec_max_us=10000) -> Profile:
    if isinstance(desc, fm.O2Map):
        flash = fm.build_o2_map(desc)
    else:
        flash = fm.build_co2_map(desc)
    adc_ref_v = p.adc_for_supply(supply_mv)
    # The temperature reading is derived with the supply as the host will
    # compute it from the (quantised) 0x42 reading, so the round trip holds.
    supply_q = p.supply_mv(adc_ref_v)
    adc_t = p.adc_for_temperature(temperature_c100, desc.ref_temp, desc.adc_ref,
                                  supply_q, desc.temp_scale)
    if adc_o2 is None:
        adc_o2 = p.adc_for_o2(o2_mv100, desc.opamp_offset)
    return Profile(name, fw_byte, type_byte, config_bits, desc, tuple(flash),
                   supply_mv, temperature_c100, o2_mv100, adc_ref_v, adc_t,
                   adc_o2, exec_min_us, exec_max_us)


MFG_DATE = datetime(2017, 11, 17, 9, 30)
EXPIRY = datetime(2019, 5, 17, 9, 30)

# --- Digital O2 cell, firmware v15: 128-word flash, execute <= 4.5 ms -------
# Ref_Temp is stored in whole degrees (25), the legacy form the spec still
# allows ("degree C if < 100"), so the *100 rule gets exercised.
O2_V15 = _make(
    "o2_v15", 0x0F, 0x01,
    fm.O2Map(model="DIGITAL O2", mfg_id="SRI15A",
             manufactured=datetime(2015, 8, 3, 14, 5),
             expires=datetime(2017, 2, 3, 14, 5), map_version=1,
             serial="O2V15-000123", temp_scale=7800, ref_temp=25,
             adc_ref=2000, opamp_offset=35,
             mfg_cal=((210, 239), (1000, 1138), (1600, 1820)),
             field_cals=(fm.FieldCal(24, 3672), fm.FieldCal(744, 3690),
                         fm.FieldCal(2160, 3705)),
             size=128),
    supply_mv=3300, temperature_c100=2250, o2_mv100=1050,
    exec_max_us=4500)

# --- Digital O2 cell, firmware v18 (0x12): 240 words -------------------------
O2_V18 = _make(
    "o2_v18", 0x12, 0x01,
    fm.O2Map(model="DIGITAL O2 V18", mfg_id="SRI18B",
             manufactured=MFG_DATE, expires=EXPIRY, map_version=2,
             serial="A1B2C3D4E5F6", temp_scale=7800, ref_temp=2500,
             adc_ref=2012, opamp_offset=-42,
             mfg_cal=((210, 232), (1000, 1105), (1600, 1768)),
             field_cals=(fm.FieldCal(3, 3650), fm.FieldCal(720, 3662),
                         fm.FieldCal(1464, 3671), fm.FieldCal(2205, 3688))),
    supply_mv=3100, temperature_c100=1875, o2_mv100=1023)

# --- Digital O2 cell, firmware v26 (byte 0x26, BCD): 240 words ---------------
# Config bits are non-zero here (their meaning is unspecified) so tests see
# that the 0x40 answer carries them next to the 9-bit flash size.
O2_V26 = _make(
    "o2_v26", 0x26, 0x01,
    fm.O2Map(model="DIGITAL O2 V26", mfg_id="SRI26C",
             manufactured=datetime(2024, 2, 29, 23, 59),
             expires=datetime(2025, 8, 31, 0, 0), map_version=3,
             serial="Z9Y8X7W6V5U4", temp_scale=7750, ref_temp=2437,
             adc_ref=1987, opamp_offset=-1200,
             mfg_cal=((210, 503), (1000, 497), (1600, 1002)),
             field_cals=tuple(fm.FieldCal(3 * 8 * (i + 1), 3600 + i) for i in range(6))),
    supply_mv=2950, temperature_c100=3112, o2_mv100=987, config_bits=0x01)

# --- CO2 sensor (type 2, fw 0x12) -------------------------------------------
# 0x44 has no O2 meaning on CO2 devices; the model still answers it (the
# command table is common to all types) with a fixed raw value.
CO2 = _make(
    "co2", 0x12, 0x02,
    fm.CO2Map(model="CO2 SENSOR", mfg_id="SRICO2",
              manufactured=datetime(2021, 6, 1, 8, 0),
              expires=datetime(2026, 6, 1, 8, 0),
              serial="CO2-00000042", temp_scale=7800, ref_temp=2500,
              adc_ref=2048, rgb_offset=(101, 202, 303),
              rgb_gain=(4096, 4100, 3990),
              field_cals=(fm.FieldCal(6, 1234), fm.FieldCal(1440, 1240)),
              text_pad="\0"),
    supply_mv=3000, temperature_c100=2000, adc_o2=0x123)

# --- CO2 scrubber temperature stick (type 3, fw 0x12) ------------------------
# The spec gives no flash map for this device. Choice: the CO2-style
# manufacturer and factory areas (model, MFG ID, dates, serial, Temp_Scale,
# Ref_Temp, ADC_Ref), RGB words left blank (it has no colour sensor), and no
# field calibrations (nothing to calibrate in the field).
CO2_STICK = _make(
    "co2_stick", 0x12, 0x03,
    fm.CO2Map(model="TEMP STICK", mfg_id="SRITMP",
              manufactured=datetime(2022, 1, 10, 12, 0),
              expires=datetime(2032, 1, 10, 12, 0),
              serial="TS0000000007", temp_scale=7800, ref_temp=2500,
              adc_ref=2100),
    supply_mv=3200, temperature_c100=1500, adc_o2=0)

PROFILES = {pr.name: pr for pr in (O2_V15, O2_V18, O2_V26, CO2, CO2_STICK)}
