/* twh_cal_scan on any calibration area, with and without a record list.
 *
 * Input: n (u16 LE), max (1 byte), flags (1 byte: bit 0 = pass a list),
 * then words at 0x20.. (the area; words 0x00-0x1F are blank, missing words
 * blank). The buffer holds exactly min(n, 0xE0) words and the list exactly
 * `max` entries, so ASan catches a read past the area or a write past max.
 *
 * Properties: the count and the current record equal the reference
 * (fuzz_ref.h; largest stamp, ties to the higher address, both words
 * programmed); current.addr is 0 or an even address inside the area; the
 * list holds the first min(count, max) records in increasing address
 * order, each with both words as stored; entries past them are untouched. */
#include "fuzz_common.h"
#include "fuzz_ref.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_in_t in;
    uint16_t n, *w, count;
    uint8_t max, flags;
    unsigned alloc, i, a, k, end;
    twh_cal_t cur, *list;
    ref_cal_t ref;

    fz_init(&in, data, size);
    n = fz_u16(&in);
    max = fz_u8(&in);
    flags = fz_u8(&in);
    alloc = n < TWH_CAL_END ? n : TWH_CAL_END;
    w = malloc((alloc ? alloc : 1u) * sizeof(*w));
    for (i = 0; i < alloc; i++)
        w[i] = (i < TWH_CAL_START || fz_empty(&in)) ? TWH_BLANK : fz_u16(&in);
    list = (flags & 1u) ? malloc((max ? max : 1u) * sizeof(*list)) : NULL;
    if (list)
        memset(list, FZ_POISON, (max ? max : 1u) * sizeof(*list));
    memset(&cur, FZ_POISON, sizeof(cur));

    count = twh_cal_scan(w, n, &cur, list, max);

    ref = ref_cal(w, n);
    end = alloc;
    FZ_EQ(count, ref.count);
    FZ_CHECK(count <= (TWH_CAL_END - TWH_CAL_START) / 2u);
    FZ_EQ(cur.addr, ref.cur_addr);
    FZ_EQ(cur.stamp, ref.cur_stamp);
    FZ_EQ(cur.value, ref.cur_value);
    if (cur.addr) {
        FZ_CHECK(cur.addr >= TWH_CAL_START && cur.addr + 1u < end && !(cur.addr & 1u));
        FZ_CHECK(cur.stamp != TWH_BLANK && cur.value != TWH_BLANK);
    } else {
        FZ_EQ(count, 0);
    }
    if (list) {
        k = 0;
        for (a = TWH_CAL_START; a + 1u < end && k < max; a += 2u) {
            if ((w[a] & TWH_WORD_MASK) == TWH_BLANK || (w[a + 1] & TWH_WORD_MASK) == TWH_BLANK)
                continue;
            FZ_EQ(list[k].addr, a);
            FZ_EQ(list[k].stamp, w[a] & TWH_WORD_MASK);
            FZ_EQ(list[k].value, w[a + 1] & TWH_WORD_MASK);
            k++;
        }
        FZ_EQ(k, count < max ? count : max);
        for (; k < max; k++)
            FZ_CHECK(fz_untouched(&list[k], sizeof(list[k])));
    }
    free(list);
    free(w);
    return 0;
}
