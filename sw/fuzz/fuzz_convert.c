/* The integer conversions, twh_s14, twh_fw_decode and twh_execute_us_for.
 *
 * Input (LE): adc u16, ref_temp u16, adc_ref u16, supply_mv i32,
 * temp_scale u16, opamp_offset i16, gain u16, word u16, fw data u16,
 * flags u8 (bit 0: take supply_mv from twh_supply_mv(adc_ref) as a real
 * caller does, instead of the raw value).
 *
 * Each conversion is checked by the defining inequality of a truncating
 * division rather than by repeating the formula:
 * - supply: OK exactly for 0 < adc < 4095; q*adc <= 2^22 < (q+1)*adc;
 *   1024 <= q <= 4194304; output untouched on error;
 * - temperature: TWH_ERR_RANGE exactly for supply <= 0, scale 0 or a
 *   result outside int32 (computed here in 128 bits), output untouched
 *   then; else with num = (adc - adc_ref) * supply * 100 and
 *   d = result - Ref: |num - d*scale| < scale with the sign of num
 *   (truncation toward zero); Ref = ref_temp*100 below 100; monotonic in
 *   adc;
 * - O2 mV*100: (r - off)*22 <= 100*adc < (r - off + 1)*22; monotonic;
 * - PPO2: r*2^22 <= adc*gain*1000 < (r+1)*2^22, r >= 0; monotonic in both;
 * - s14: -8192..8191, same low 14 bits as the word;
 * - firmware byte: binary 0x00-0x19, BCD from 0x26 with decimal nibbles
 *   (version re-encodes to the byte), else unknown with version -1; raw
 *   and type bytes as sent; execute 6000 us exactly for version >= 18. */
#include "fuzz_common.h"
#include "fuzz_ref.h"

static void check_supply(uint16_t adc)
{
    int32_t mv;
    int rc;

    memset(&mv, FZ_POISON, sizeof(mv));
    rc = twh_supply_mv(adc, &mv);
    if (adc == 0 || adc >= 4095u) {
        FZ_EQ(rc, TWH_ERR_RANGE);
        FZ_CHECK(fz_untouched(&mv, sizeof(mv)));
        return;
    }
    FZ_EQ(rc, TWH_OK);
    FZ_CHECK((int64_t)mv * adc <= 4194304 && ((int64_t)mv + 1) * adc > 4194304);
    FZ_CHECK(mv >= 1024 && mv <= 4194304);
}

static int temp(uint16_t adc, uint16_t rt, uint16_t aref, int32_t s, uint16_t scale, int32_t *out)
{
    __int128 num, d, rem, r, ref;
    int32_t c;
    int rc;

    memset(&c, FZ_POISON, sizeof(c));
    rc = twh_temperature_c100(adc, rt, aref, s, scale, &c);
    if (s <= 0 || scale == 0) {
        FZ_EQ(rc, TWH_ERR_RANGE);
        FZ_CHECK(fz_untouched(&c, sizeof(c)));
        return rc;
    }
    ref = rt < 100u ? (__int128)rt * 100 : (__int128)rt;
    num = ((__int128)adc - aref) * s * 100;
    /* the truncated quotient in 128 bits, divided as magnitudes (where
     * truncation and floor agree), then the remainder checks it */
    d = (num < 0 ? -num : num) / scale;
    if (num < 0)
        d = -d;
    r = ref + d;
    if (r > INT32_MAX || r < INT32_MIN) {
        FZ_EQ(rc, TWH_ERR_RANGE);
        FZ_CHECK(fz_untouched(&c, sizeof(c)));
        return rc;
    }
    FZ_EQ(rc, TWH_OK);
    FZ_CHECK((__int128)c == r);
    d = (__int128)c - ref;
    rem = num - d * scale;
    FZ_CHECK(rem > -(__int128)scale && rem < (__int128)scale);
    FZ_CHECK(rem == 0 || (rem > 0) == (num > 0));
    *out = c;
    return rc;
}

static void check_fw(uint16_t data)
{
    twh_fw_t fw;
    uint8_t b = (uint8_t)(data >> 8);
    uint16_t ex;

    memset(&fw, FZ_POISON, sizeof(fw));
    twh_fw_decode(data, &fw);
    FZ_EQ(fw.raw, b);
    FZ_EQ(fw.type, data & 0xFFu);
    if (b <= 0x19u) {
        FZ_EQ(fw.encoding, TWH_FW_BINARY);
        FZ_EQ(fw.version, b);
    } else if (b >= 0x26u && (b >> 4) <= 9u && (b & 15u) <= 9u) {
        FZ_EQ(fw.encoding, TWH_FW_BCD);
        FZ_CHECK(fw.version >= 26 && fw.version <= 99);
        FZ_EQ(((fw.version / 10) << 4) | (fw.version % 10), b);
    } else {
        FZ_EQ(fw.encoding, TWH_FW_UNKNOWN);
        FZ_EQ(fw.version, -1);
    }
    ex = twh_execute_us_for(&fw);
    FZ_EQ(ex, fw.version >= 18 ? TWH_EXECUTE_RECOMMENDED_US : TWH_EXECUTE_SAFE_US);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_in_t in;
    uint16_t adc, rt, aref, scale, gain, word, fwd;
    int16_t off;
    int32_t s, t0, t1, o, o1, p, p1;
    uint8_t flags;
    int64_t x;
    int16_t v;

    fz_init(&in, data, size);
    adc = fz_u16(&in);
    rt = fz_u16(&in);
    aref = fz_u16(&in);
    s = (int32_t)fz_u32(&in);
    scale = fz_u16(&in);
    off = (int16_t)fz_u16(&in);
    gain = fz_u16(&in);
    word = fz_u16(&in);
    fwd = fz_u16(&in);
    flags = fz_u8(&in);

    check_supply(adc);
    check_supply(aref);
    if ((flags & 1u) && twh_supply_mv(aref, &t0) == TWH_OK)
        s = t0;
    if (temp(adc, rt, aref, s, scale, &t0) == TWH_OK && adc < 0xFFFFu &&
        temp((uint16_t)(adc + 1u), rt, aref, s, scale, &t1) == TWH_OK)
        FZ_CHECK(t1 >= t0);

    o = twh_o2_mv100(adc, off);
    x = (int64_t)o - off;
    FZ_CHECK(x * 22 <= 100 * (int64_t)adc && (x + 1) * 22 > 100 * (int64_t)adc);
    if (adc < 0xFFFFu) {
        o1 = twh_o2_mv100((uint16_t)(adc + 1u), off);
        FZ_CHECK(o1 >= o);
    }

    p = twh_ppo2_mbar(adc, gain);
    FZ_CHECK(p >= 0);
    x = (int64_t)adc * gain * 1000;
    FZ_CHECK(((int64_t)p << 22) <= x && ((int64_t)(p + 1) << 22) > x);
    if (adc < 0xFFFFu) {
        p1 = twh_ppo2_mbar((uint16_t)(adc + 1u), gain);
        FZ_CHECK(p1 >= p);
    }
    if (gain < 0xFFFFu) {
        p1 = twh_ppo2_mbar(adc, (uint16_t)(gain + 1u));
        FZ_CHECK(p1 >= p);
    }

    v = twh_s14(word);
    FZ_CHECK(v >= -8192 && v <= 8191);
    FZ_EQ((uint16_t)v & 0x3FFFu, word & 0x3FFFu);
    FZ_EQ(v, ref_s14(word));

    check_fw(fwd);
    return 0;
}
