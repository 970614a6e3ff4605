/* twowire-host driver: conversions and flash-map decoding (no bus access).
 * The same rules as tb/protocol.py and tb/flashmap.py; the shared vectors in
 * tb/vectors/ check that they agree. Integers only; every division truncates
 * toward zero (C semantics). */
#include <stddef.h>
#include <stdint.h>

#include "twh.h"

/* ------------------------------------------------------------ conversions */
int twh_supply_mv(uint16_t adc, int32_t *mv)
{
    if (adc == 0 || adc >= 4095u)
        return TWH_ERR_RANGE;
    *mv = (int32_t)((1024uL * 4096uL) / adc);
    return TWH_OK;
}

int twh_temperature_c100(uint16_t adc, uint16_t ref_temp, uint16_t adc_ref,
                         int32_t supply_mv, uint16_t temp_scale, int32_t *c100)
{
    int64_t t;

    if (supply_mv <= 0 || temp_scale == 0)
        return TWH_ERR_RANGE;
    /* C division truncates toward zero, as the Python reference does */
    t = (int64_t)((int32_t)adc - (int32_t)adc_ref) * ((int64_t)supply_mv * 100) /
        (int64_t)temp_scale;
    t += ref_temp < 100u ? (int32_t)ref_temp * 100 : (int32_t)ref_temp;
    if (t > INT32_MAX || t < INT32_MIN)
        return TWH_ERR_RANGE;
    *c100 = (int32_t)t;
    return TWH_OK;
}

int32_t twh_o2_mv100(uint16_t adc, int16_t opamp_offset)
{
    return (int32_t)((100uL * adc) / 22u) + opamp_offset;
}

/* PPO2 (bar) = ADC * gain / (4096 * 1024): NOTES.md's reading of
 * PPO2_Full_Scale, kept in this one helper. Non-negative, so the shift is
 * the truncating division by 2^22. */
int32_t twh_ppo2_mbar(uint16_t adc, uint16_t gain)
{
    return (int32_t)(((uint64_t)adc * gain * 1000u) >> 22);
}

/* ------------------------------------------------------------ field encodings */
int16_t twh_s14(uint16_t word)
{
    word &= TWH_WORD_MASK;
    return (int16_t)((word & 0x2000u) ? (int32_t)word - 0x4000 : (int32_t)word);
}

static const uint8_t days_in_month[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};

int twh_decode_datetime(uint16_t w0, uint16_t w1, twh_datetime_t *dt)
{
    uint32_t v = ((uint32_t)(w0 & TWH_WORD_MASK) << 14) | (w1 & TWH_WORD_MASK);
    uint8_t minute = (uint8_t)((v >> 21) & 0x3Fu), y = (uint8_t)((v >> 14) & 0x7Fu);
    uint8_t month = (uint8_t)((v >> 10) & 0xFu), day = (uint8_t)((v >> 5) & 0x1Fu);
    uint8_t hour = (uint8_t)(v & 0x1Fu), dim;

    dt->year = 0;
    dt->month = dt->day = dt->hour = dt->minute = 0;
    if (month < 1u || month > 12u || hour > 23u || minute > 59u)
        return TWH_ERR_RANGE;
    dim = days_in_month[month - 1u];
    /* years 2000-2127: leap every 4 years except 2100 */
    if (month == 2u && (y & 3u) == 0 && y != 100u)
        dim = 29;
    if (day < 1u || day > dim)
        return TWH_ERR_RANGE;
    dt->year = (uint16_t)(2000u + y);
    dt->month = month;
    dt->day = day;
    dt->hour = hour;
    dt->minute = minute;
    return TWH_OK;
}

void twh_decode_text(const uint16_t *words, uint8_t n_words, char *out)
{
    char *p = out;
    uint8_t i;

    /* a blank word (two DEL characters) ends the text */
    for (i = 0; i < n_words && (words[i] & TWH_WORD_MASK) != TWH_BLANK; i++) {
        *p++ = (char)((words[i] >> 7) & 0x7Fu);
        *p++ = (char)(words[i] & 0x7Fu);
    }
    while (p > out && (p[-1] == ' ' || p[-1] == '\0'))
        p--;
    *p = '\0';
}

/* ------------------------------------------------------------ calibrations */
uint16_t twh_cal_scan(const uint16_t *words, uint16_t n, twh_cal_t *current,
                      twh_cal_t *list, uint16_t max)
{
    uint16_t end = n < TWH_CAL_END ? n : TWH_CAL_END, a, s, v, count = 0;

    current->addr = current->stamp = current->value = 0;
    for (a = TWH_CAL_START; a + 1u < end; a += 2u) {
        s = words[a] & TWH_WORD_MASK;
        v = words[a + 1u] & TWH_WORD_MASK;
        /* a record counts only when both words are programmed */
        if (s == TWH_BLANK || v == TWH_BLANK)
            continue;
        if (list && count < max) {
            list[count].addr = a;
            list[count].stamp = s;
            list[count].value = v;
        }
        count++;
        if (!current->addr || s >= current->stamp) {  /* ties -> higher address */
            current->addr = a;
            current->stamp = s;
            current->value = v;
        }
    }
    return count;
}

/* ------------------------------------------------------------ maps */
static uint8_t triple(const uint16_t *w, uint16_t *out)
{
    uint8_t i, any = 0;

    for (i = 0; i < 3u; i++) {
        out[i] = w[i] & TWH_WORD_MASK;
        any |= out[i] != TWH_BLANK;
    }
    if (!any)
        out[0] = out[1] = out[2] = 0;
    return any;
}

int twh_decode_map(const uint16_t *words, uint16_t n, uint8_t kind, twh_map_t *m)
{
    uint8_t i, o2 = kind == TWH_MAP_O2;

    if (n < TWH_CAL_START || n > TWH_ADDR_MAX + 1u || (!o2 && kind != TWH_MAP_CO2))
        return TWH_ERR_BAD_ARG;
    m->kind = kind;
    m->size = n;
    twh_decode_text(words + 0x00, 7, m->model);
    twh_decode_text(words + 0x07, 3, m->mfg_id);
    twh_decode_text(words + 0x10, 6, m->serial);
    (void)twh_decode_datetime(words[0x0A], words[0x0B], &m->manufactured);
    (void)twh_decode_datetime(words[0x0C], words[0x0D], &m->expires);
    m->temp_scale = words[0x16] & TWH_WORD_MASK;
    m->ref_temp = words[0x17] & TWH_WORD_MASK;
    m->adc_ref = words[0x18] & TWH_WORD_MASK;
    /* O2: 0x0E version/type, 0x19 OpAmp_Offset, 0x1A-0x1F 3 cal pairs;
     * CO2: 0x19-0x1B RGB offset, 0x1C-0x1E RGB gain */
    m->map_version = (uint8_t)(o2 ? (words[0x0E] & TWH_WORD_MASK) >> 8 : 0);
    m->map_type = (uint8_t)(o2 ? words[0x0E] : 0);
    m->opamp_offset = o2 ? twh_s14(words[0x19]) : 0;
    for (i = 0; i < 6u; i++)
        m->mfg_cal[i >> 1][i & 1u] = o2 ? words[0x1A + i] & TWH_WORD_MASK : 0;
    m->has_rgb_offset = m->has_rgb_gain = 0;
    m->rgb_offset[0] = m->rgb_offset[1] = m->rgb_offset[2] = 0;
    m->rgb_gain[0] = m->rgb_gain[1] = m->rgb_gain[2] = 0;
    if (!o2) {
        m->has_rgb_offset = triple(words + 0x19, m->rgb_offset);
        m->has_rgb_gain = triple(words + 0x1C, m->rgb_gain);
    }
    m->cal_unit_hours = o2 ? 3u : 6u;
    m->cal_count = twh_cal_scan(words, n, &m->current, NULL, 0);
    return TWH_OK;
}
