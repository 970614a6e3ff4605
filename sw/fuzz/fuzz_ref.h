/* Reference decoders the harnesses compare the driver against. They are
 * written from the spec text (SRI-2WIRE-IRD rev E 7.1, NOTES.md) in a
 * different shape from sw/src/twh_decode.c on purpose: fields are cut
 * from each word separately instead of from one 28-bit value, leap years
 * use the full Gregorian rule, "current" is found scanning downwards. A
 * shared mistake would need the same slip made twice in different code. */
#ifndef FUZZ_REF_H
#define FUZZ_REF_H

#include <stdint.h>

#include "twh.h"

typedef struct ref_dt {
    int valid;
    unsigned year, month, day, hour, minute;
} ref_dt_t;

static inline unsigned ref_days_in_month(unsigned year, unsigned month)
{
    int leap = (year % 4u == 0 && year % 100u != 0) || year % 400u == 0;

    switch (month) {
    case 2: return leap ? 29u : 28u;
    case 4: case 6: case 9: case 11: return 30u;
    default: return 31u;
    }
}

/* word 0 = v bits 27:14: bit 13 unused, 12:7 minute, 6:0 year;
 * word 1 = v bits 13:0: 13:10 month, 9:5 day, 4:0 hour */
static inline ref_dt_t ref_datetime(uint16_t w0, uint16_t w1)
{
    ref_dt_t d;

    d.minute = (w0 >> 7) & 0x3Fu;
    d.year = 2000u + (w0 & 0x7Fu);
    d.month = (w1 >> 10) & 0xFu;
    d.day = (w1 >> 5) & 0x1Fu;
    d.hour = w1 & 0x1Fu;
    d.valid = d.month >= 1 && d.month <= 12 && d.hour < 24 && d.minute < 60 &&
              d.day >= 1 && d.day <= ref_days_in_month(d.year, d.month);
    return d;
}

static inline void ref_encode_datetime(unsigned year, unsigned month, unsigned day,
                                       unsigned hour, unsigned minute,
                                       uint16_t *w0, uint16_t *w1)
{
    *w0 = (uint16_t)((minute & 0x3Fu) << 7 | ((year - 2000u) & 0x7Fu));
    *w1 = (uint16_t)((month & 0xFu) << 10 | (day & 0x1Fu) << 5 | (hour & 0x1Fu));
}

/* Text: the characters up to the first blank word, trailing NUL/space
 * removed; returns the length kept (the driver writes a NUL after it). */
static inline unsigned ref_text(const uint16_t *words, unsigned n_words, char *out)
{
    unsigned i, len = 0;

    for (i = 0; i < n_words; i++) {
        if ((words[i] & 0x3FFFu) == 0x3FFFu)
            break;
        out[len++] = (char)((words[i] >> 7) & 0x7Fu);
        out[len++] = (char)(words[i] & 0x7Fu);
    }
    while (len > 0 && (out[len - 1] == ' ' || out[len - 1] == 0))
        len--;
    return len;
}

/* Calibration records in [0x20, min(0xE0, n)): both words programmed. */
typedef struct ref_cal {
    unsigned count;
    unsigned cur_addr, cur_stamp, cur_value;   /* cur_addr 0: none */
} ref_cal_t;

static inline ref_cal_t ref_cal(const uint16_t *words, unsigned n)
{
    ref_cal_t r = {0, 0, 0, 0};
    unsigned end = n < 0xE0u ? n : 0xE0u, a;
    int have = 0;

    if (end < 0x22u)
        return r;
    /* highest pair first: a strictly larger stamp must appear to replace */
    for (a = 0x20u + ((end - 0x20u) / 2u - 1u) * 2u;; a -= 2u) {
        unsigned s = words[a] & 0x3FFFu, v = words[a + 1] & 0x3FFFu;

        if (s != 0x3FFFu && v != 0x3FFFu) {
            r.count++;
            if (!have || s > r.cur_stamp) {
                have = 1;
                r.cur_addr = a;
                r.cur_stamp = s;
                r.cur_value = v;
            }
        }
        if (a == 0x20u)
            break;
    }
    return r;
}

static inline int ref_s14(uint16_t w)
{
    w &= 0x3FFFu;
    return w >= 0x2000u ? (int)w - 0x4000 : (int)w;
}

#endif
