/* twh_decode_datetime: any two words, and fields -> words -> fields.
 *
 * Input: w0, w1 (u16 LE each, all 16 bits used), then year offset, month,
 * day, hour, minute (1 byte each) for the round trip.
 *
 * Properties: TWH_OK exactly when the reference (fuzz_ref.h: fields cut
 * per word, Gregorian leap rule on the full year) says the date exists,
 * with equal fields and year 2000-2127; otherwise TWH_ERR_RANGE and *dt
 * all zero (documented). Bits the format does not use (bit 27 = word 0 bit
 * 13, and bits 15:14 of both words) change nothing. A valid decode encodes
 * back to the same used bits. Any fields encoded, then decoded, come back
 * unchanged exactly when they name a real date and time. */
#include "fuzz_common.h"
#include "fuzz_ref.h"

static int decode_checked(uint16_t w0, uint16_t w1, twh_datetime_t *dt)
{
    ref_dt_t d = ref_datetime(w0 & TWH_WORD_MASK, w1 & TWH_WORD_MASK);
    int rc;

    memset(dt, FZ_POISON, sizeof(*dt));
    rc = twh_decode_datetime(w0, w1, dt);
    if (!d.valid) {
        FZ_EQ(rc, TWH_ERR_RANGE);
        FZ_EQ(dt->year, 0);
        FZ_EQ(dt->month | dt->day | dt->hour | dt->minute, 0);
        return rc;
    }
    FZ_EQ(rc, TWH_OK);
    FZ_EQ(dt->year, d.year);
    FZ_EQ(dt->month, d.month);
    FZ_EQ(dt->day, d.day);
    FZ_EQ(dt->hour, d.hour);
    FZ_EQ(dt->minute, d.minute);
    FZ_CHECK(dt->year >= 2000u && dt->year <= 2127u);
    FZ_CHECK(dt->month >= 1u && dt->month <= 12u && dt->day >= 1u && dt->day <= 31u);
    FZ_CHECK(dt->hour <= 23u && dt->minute <= 59u);
    return rc;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_in_t in;
    uint16_t w0, w1, e0, e1;
    unsigned year, month, day, hour, minute;
    twh_datetime_t a, b;
    int rc, rc2;

    fz_init(&in, data, size);
    w0 = fz_u16(&in);
    w1 = fz_u16(&in);
    rc = decode_checked(w0, w1, &a);
    /* unused bits flipped: same answer */
    rc2 = decode_checked((uint16_t)(w0 ^ 0xE000u), (uint16_t)(w1 ^ 0xC000u), &b);
    FZ_EQ(rc2, rc);
    FZ_CHECK(memcmp(&a, &b, sizeof(a)) == 0);
    if (rc == TWH_OK) {
        ref_encode_datetime(a.year, a.month, a.day, a.hour, a.minute, &e0, &e1);
        FZ_EQ(e0, w0 & 0x1FFFu);
        FZ_EQ(e1, w1 & 0x3FFFu);
    }

    year = 2000u + fz_u8(&in) % 128u;
    month = fz_u8(&in) % 16u;
    day = fz_u8(&in) % 32u;
    hour = fz_u8(&in) % 32u;
    minute = fz_u8(&in) % 64u;
    ref_encode_datetime(year, month, day, hour, minute, &e0, &e1);
    rc = decode_checked(e0, e1, &a);
    if (month >= 1 && month <= 12 && hour < 24 && minute < 60 && day >= 1 &&
        day <= ref_days_in_month(year, month)) {
        FZ_EQ(rc, TWH_OK);
        FZ_EQ(a.year, year);
        FZ_EQ(a.month, month);
        FZ_EQ(a.day, day);
        FZ_EQ(a.hour, hour);
        FZ_EQ(a.minute, minute);
    } else {
        FZ_EQ(rc, TWH_ERR_RANGE);
    }
    return 0;
}
