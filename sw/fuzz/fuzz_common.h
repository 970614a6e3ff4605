/* Shared by every libFuzzer harness of the driver (sw/fuzz/fuzz_*.c).
 *
 * A harness reads its input through fz_in_t: past the end every read gives
 * 0, so any byte string is a valid input and short inputs still run the
 * whole harness. A property that does not hold aborts, which libFuzzer
 * reports as a crash and saves as crash-<sha1> for replay. */
#ifndef FUZZ_COMMON_H
#define FUZZ_COMMON_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "twh.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

typedef struct fz_in {
    const uint8_t *p;
    size_t n;
} fz_in_t;

static inline void fz_init(fz_in_t *in, const uint8_t *data, size_t size)
{
    in->p = data;
    in->n = size;
}

static inline uint8_t fz_u8(fz_in_t *in)
{
    if (!in->n)
        return 0;
    in->n--;
    return *in->p++;
}

/* little endian, like the seed files gen_corpus.py writes */
static inline uint16_t fz_u16(fz_in_t *in)
{
    uint16_t lo = fz_u8(in);
    return (uint16_t)(lo | (uint16_t)fz_u8(in) << 8);
}

static inline uint32_t fz_u32(fz_in_t *in)
{
    uint32_t lo = fz_u16(in);
    return lo | (uint32_t)fz_u16(in) << 16;
}

/* the k-th 32-bit value ahead (0 = next), without consuming it: what a
 * raw-mode register read is about to return */
static inline uint32_t fz_peek_u32(const fz_in_t *in, unsigned k)
{
    fz_in_t c = *in;
    uint32_t v = 0;
    unsigned i;

    for (i = 0; i <= k; i++)
        v = fz_u32(&c);
    return v;
}

static inline int fz_empty(const fz_in_t *in)
{
    return in->n == 0;
}

/* Both values are printed, so a crash report alone says what differed. */
#define FZ_EQ(a, b)                                                               \
    do {                                                                          \
        long long fz_a_ = (long long)(a), fz_b_ = (long long)(b);                 \
        if (fz_a_ != fz_b_) {                                                     \
            fprintf(stderr, "PROPERTY FAILED %s:%d: %s == %s (%lld != %lld)\n",   \
                    __FILE__, __LINE__, #a, #b, fz_a_, fz_b_);                    \
            abort();                                                              \
        }                                                                         \
    } while (0)

#define FZ_CHECK(c)                                                               \
    do {                                                                          \
        if (!(c)) {                                                               \
            fprintf(stderr, "PROPERTY FAILED %s:%d: %s\n", __FILE__, __LINE__, #c); \
            abort();                                                              \
        }                                                                         \
    } while (0)

/* "Output parameters are written only on success" (twh.h) is checked by
 * filling outputs with this byte before a call and comparing afterwards. */
#define FZ_POISON 0xA5

static inline int fz_untouched(const void *p, size_t n)
{
    const uint8_t *b = p;
    size_t i;

    for (i = 0; i < n; i++)
        if (b[i] != FZ_POISON)
            return 0;
    return 1;
}

/* twh_read_image on failure: the words read before the failing one are
 * written, the rest untouched (a 14-bit word never equals the poison).
 * Returns how many were written. */
static inline unsigned fz_written_prefix(const uint16_t *w, unsigned n)
{
    unsigned k = 0, i;

    while (k < n && !fz_untouched(&w[k], sizeof(w[k])))
        k++;
    for (i = k; i < n; i++)
        if (!fz_untouched(&w[i], sizeof(w[i])))
            return ~0u;
    return k;
}

/* A fallible driver function returns TWH_OK or one of the TWH_ERR_* codes. */
static inline int fz_is_err_code(int rc)
{
    return rc <= TWH_OK && rc >= TWH_ERR_RANGE;
}

#endif
