"""Python ctypes binding of the C driver (sw/include/twh.h, libtwh.so).

The one place Python mirrors the driver's structs and prototypes; used by the
co-simulation (tb/cosim.py) and by sw/test/ctypes_smoke.py. Sizes are checked
against the library (twh_sizeof) when it is loaded.
"""
import ctypes as C
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LIB_PATH = ROOT / "sw" / "build" / "shared" / "libtwh.so"

READ32 = C.CFUNCTYPE(C.c_uint32, C.c_void_p, C.c_uint32)
WRITE32 = C.CFUNCTYPE(None, C.c_void_p, C.c_uint32, C.c_uint32)
DELAY = C.CFUNCTYPE(None, C.c_void_p, C.c_uint32)
WAIT_IRQ = C.CFUNCTYPE(C.c_uint32, C.c_void_p, C.c_uint32)

# enum twh_err
ERRORS = {0: "OK", -1: "NO_RESPONSE", -2: "CHECKSUM", -3: "FRAMING", -4: "SHORT",
          -5: "STUCK_LOW", -6: "STUCK_HIGH", -7: "BLOCKED", -8: "CANCELLED",
          -9: "HW_STATUS", -10: "TIMEOUT", -11: "FIFO_FULL", -12: "AGAIN",
          -13: "BAD_ARG", -14: "BAD_ID", -15: "VERIFY", -16: "FLASH_FULL",
          -17: "REFUSED", -18: "STASH_FULL", -19: "BAD_RESPONSE", -20: "BUS",
          -21: "RANGE"}
ERR = {name: code for code, name in ERRORS.items()}
STASH_SIZE = 4          # TWH_STASH_SIZE default
MAP_O2, MAP_CO2 = 1, 2


class Platform(C.Structure):
    _fields_ = [("read32", READ32), ("write32", WRITE32), ("delay_us", DELAY),
                ("wait_irq", WAIT_IRQ), ("ctx", C.c_void_p)]


class Result(C.Structure):
    _fields_ = [("data", C.c_uint16), ("cmd", C.c_uint8), ("status", C.c_uint8),
                ("channel", C.c_uint8), ("tag", C.c_uint8)]


class Twh(C.Structure):
    _fields_ = [("plat", Platform), ("timeout_us", C.c_uint32), ("poll_us", C.c_uint32),
                ("clk_khz", C.c_uint32), ("fifo_depth", C.c_uint16), ("channels", C.c_uint8),
                ("version_major", C.c_uint8), ("version_minor", C.c_uint8),
                ("fixed_timing", C.c_uint8),
                ("next_tag", C.c_uint8), ("stash_head", C.c_uint8), ("stash_count", C.c_uint8),
                ("stash", Result * STASH_SIZE)]


class Fw(C.Structure):
    _fields_ = [("raw", C.c_uint8), ("type", C.c_uint8), ("version", C.c_int8),
                ("encoding", C.c_uint8)]


class Datetime(C.Structure):
    _fields_ = [("year", C.c_uint16), ("month", C.c_uint8), ("day", C.c_uint8),
                ("hour", C.c_uint8), ("minute", C.c_uint8)]


class Cal(C.Structure):
    _fields_ = [("addr", C.c_uint16), ("stamp", C.c_uint16), ("value", C.c_uint16)]


class Map(C.Structure):
    _fields_ = [("model", C.c_char * 15), ("mfg_id", C.c_char * 7), ("serial", C.c_char * 13),
                ("kind", C.c_uint8), ("manufactured", Datetime), ("expires", Datetime),
                ("size", C.c_uint16), ("temp_scale", C.c_uint16), ("ref_temp", C.c_uint16),
                ("adc_ref", C.c_uint16), ("map_version", C.c_uint8), ("map_type", C.c_uint8),
                ("opamp_offset", C.c_int16), ("mfg_cal", (C.c_uint16 * 2) * 3),
                ("rgb_offset", C.c_uint16 * 3), ("rgb_gain", C.c_uint16 * 3),
                ("has_rgb_offset", C.c_uint8), ("has_rgb_gain", C.c_uint8),
                ("cal_unit_hours", C.c_uint16), ("cal_count", C.c_uint16), ("current", Cal)]


P = C.POINTER
u8, u16, u32, i32 = C.c_uint8, C.c_uint16, C.c_uint32, C.c_int32
PROTOTYPES = {
    "twh_init": (C.c_int, [P(Twh), P(Platform)]),
    "twh_sizeof": (u32, []),
    "twh_submit": (C.c_int, [P(Twh), u8, u8, u16]),
    "twh_poll": (C.c_int, [P(Twh)]),
    "twh_result": (C.c_int, [P(Twh), P(Result)]),
    "twh_status_err": (C.c_int, [u8, u8]),
    "twh_cancel_all": (C.c_int, [P(Twh)]),
    "twh_xfer": (C.c_int, [P(Twh), u8, u8, u16, P(u16)]),
    "twh_config": (C.c_int, [P(Twh), u8, P(u8), P(u16)]),
    "twh_firmware": (C.c_int, [P(Twh), u8, P(Fw)]),
    "twh_ref_voltage": (C.c_int, [P(Twh), u8, P(u16)]),
    "twh_temperature": (C.c_int, [P(Twh), u8, P(u16)]),
    "twh_o2_voltage": (C.c_int, [P(Twh), u8, P(u16)]),
    "twh_find_free": (C.c_int, [P(Twh), u8, u16, P(u16)]),
    "twh_read_word": (C.c_int, [P(Twh), u8, u16, P(u16)]),
    "twh_erase_page": (C.c_int, [P(Twh), u8, u16]),
    "twh_write_word": (C.c_int, [P(Twh), u8, u16, u16]),
    "twh_read_image": (C.c_int, [P(Twh), u8, P(u16), u16]),
    "twh_set_execute_us": (C.c_int, [P(Twh), u8, u16]),
    "twh_negotiate": (C.c_int, [P(Twh), u8, P(Fw)]),
    "twh_cal_append": (C.c_int, [P(Twh), u8, u16, u16, P(u16)]),
    "twh_supply_mv": (C.c_int, [u16, P(i32)]),
    "twh_temperature_c100": (C.c_int, [u16, u16, u16, i32, u16, P(i32)]),
    "twh_o2_mv100": (i32, [u16, C.c_int16]),
    "twh_ppo2_mbar": (i32, [u16, u16]),
    "twh_decode_map": (C.c_int, [P(u16), u16, u8, P(Map)]),
}


def load(path=LIB_PATH):
    lib = C.CDLL(str(path))
    for name, (restype, argtypes) in PROTOTYPES.items():
        fn = getattr(lib, name)
        fn.restype, fn.argtypes = restype, argtypes
    if lib.twh_sizeof() != C.sizeof(Twh):
        raise RuntimeError(f"twh_t is {lib.twh_sizeof()} bytes in C, {C.sizeof(Twh)} here")
    return lib
