/* twh_decode_map on any image.
 *
 * Input: kind (1 byte, raw: 1 = O2, 2 = CO2, anything else invalid),
 * n (u16 LE, raw), then little-endian words; words missing from the input
 * are blank. The image buffer is exactly n words (1 word when n is out of
 * range, since the decoder must refuse it before reading), so ASan sees
 * any read past the end.
 *
 * Properties: refuses exactly the bad kinds/sizes, with *m untouched; on
 * success every field equals the reference decoding (fuzz_ref.h): texts,
 * both dates (or all zero), masked 14-bit fields, the O2 or CO2 specific
 * fields and zeros for the other kind, RGB presence flags, calibration
 * count and current record; ranges: map_version 0-63, OpAmp offset
 * -8192..8191, unit hours 3/6. */
#include "fuzz_common.h"
#include "fuzz_ref.h"

static void check_text(const char *got, size_t cap, const uint16_t *words, unsigned n_words)
{
    char want[2 * 16];
    unsigned len = ref_text(words, n_words, want);

    FZ_CHECK(len < cap);
    FZ_CHECK(memcmp(got, want, len) == 0);
    FZ_EQ(got[len], 0);
}

static void check_date(const twh_datetime_t *got, uint16_t w0, uint16_t w1)
{
    ref_dt_t d = ref_datetime(w0 & TWH_WORD_MASK, w1 & TWH_WORD_MASK);

    if (!d.valid) {
        FZ_EQ(got->year, 0);
        FZ_EQ(got->month | got->day | got->hour | got->minute, 0);
        return;
    }
    FZ_EQ(got->year, d.year);
    FZ_EQ(got->month, d.month);
    FZ_EQ(got->day, d.day);
    FZ_EQ(got->hour, d.hour);
    FZ_EQ(got->minute, d.minute);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_in_t in;
    uint8_t kind;
    uint16_t n, *w;
    unsigned alloc, i;
    twh_map_t m;
    ref_cal_t rc;
    int rc_map, valid, o2;

    fz_init(&in, data, size);
    kind = fz_u8(&in);
    n = fz_u16(&in);
    valid = n >= TWH_CAL_START && n <= TWH_ADDR_MAX + 1u &&
            (kind == TWH_MAP_O2 || kind == TWH_MAP_CO2);
    alloc = valid || n < TWH_CAL_START ? n : 1u;
    w = malloc((alloc ? alloc : 1u) * sizeof(*w));
    for (i = 0; i < alloc; i++)
        w[i] = fz_empty(&in) ? TWH_BLANK : fz_u16(&in);

    memset(&m, FZ_POISON, sizeof(m));
    rc_map = twh_decode_map(w, n, kind, &m);
    if (!valid) {
        FZ_EQ(rc_map, TWH_ERR_BAD_ARG);
        FZ_CHECK(fz_untouched(&m, sizeof(m)));
        free(w);
        return 0;
    }
    FZ_EQ(rc_map, TWH_OK);
    o2 = kind == TWH_MAP_O2;
    FZ_EQ(m.kind, kind);
    FZ_EQ(m.size, n);
    check_text(m.model, sizeof(m.model), w + 0x00, 7);
    check_text(m.mfg_id, sizeof(m.mfg_id), w + 0x07, 3);
    check_text(m.serial, sizeof(m.serial), w + 0x10, 6);
    check_date(&m.manufactured, w[0x0A], w[0x0B]);
    check_date(&m.expires, w[0x0C], w[0x0D]);
    FZ_EQ(m.temp_scale, w[0x16] & 0x3FFFu);
    FZ_EQ(m.ref_temp, w[0x17] & 0x3FFFu);
    FZ_EQ(m.adc_ref, w[0x18] & 0x3FFFu);
    if (o2) {
        FZ_EQ(m.map_version, (w[0x0E] & 0x3FFFu) >> 8);
        FZ_CHECK(m.map_version <= 63u);
        FZ_EQ(m.map_type, w[0x0E] & 0xFFu);
        FZ_EQ(m.opamp_offset, ref_s14(w[0x19]));
        FZ_CHECK(m.opamp_offset >= -8192 && m.opamp_offset <= 8191);
        for (i = 0; i < 6; i++)
            FZ_EQ(m.mfg_cal[i / 2][i % 2], w[0x1A + i] & 0x3FFFu);
        FZ_EQ(m.has_rgb_offset | m.has_rgb_gain, 0);
        for (i = 0; i < 3; i++)
            FZ_EQ(m.rgb_offset[i] | m.rgb_gain[i], 0);
        FZ_EQ(m.cal_unit_hours, 3);
    } else {
        unsigned any_off = 0, any_gain = 0;

        FZ_EQ(m.map_version | m.map_type | m.opamp_offset, 0);
        for (i = 0; i < 6; i++)
            FZ_EQ(m.mfg_cal[i / 2][i % 2], 0);
        for (i = 0; i < 3; i++) {
            any_off |= (w[0x19 + i] & 0x3FFFu) != 0x3FFFu;
            any_gain |= (w[0x1C + i] & 0x3FFFu) != 0x3FFFu;
        }
        FZ_EQ(m.has_rgb_offset, any_off);
        FZ_EQ(m.has_rgb_gain, any_gain);
        for (i = 0; i < 3; i++) {
            FZ_EQ(m.rgb_offset[i], any_off ? w[0x19 + i] & 0x3FFFu : 0);
            FZ_EQ(m.rgb_gain[i], any_gain ? w[0x1C + i] & 0x3FFFu : 0);
        }
        FZ_EQ(m.cal_unit_hours, 6);
    }
    rc = ref_cal(w, n);
    FZ_EQ(m.cal_count, rc.count);
    FZ_EQ(m.current.addr, rc.cur_addr);
    FZ_EQ(m.current.stamp, rc.cur_stamp);
    FZ_EQ(m.current.value, rc.cur_value);
    free(w);
    return 0;
}
