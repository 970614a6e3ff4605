/* twh_decode_text on any words, and the encode -> decode round trip.
 *
 * Input: n_words (1 byte), then n_words little-endian words (missing ones
 * blank); whatever input is left is a text for the round trip.
 *
 * Properties: the output buffer of exactly 2*n_words+1 bytes is never
 * overrun (ASan); the bytes up to the NUL equal the reference decoding
 * (characters up to the first blank word, trailing NUL/space stripped);
 * every character is 7-bit. Round trip: printable 7-bit text of up to
 * 2*n_words characters, encoded two characters per word (first in bits
 * 13:7) with space or NUL padding, decodes to itself minus trailing
 * spaces. */
#include "fuzz_common.h"
#include "fuzz_ref.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_in_t in;
    uint8_t n_words, pad;
    uint16_t *w;
    char *out, *want, text[2 * 255];
    unsigned i, len, cap, tlen, keep;

    fz_init(&in, data, size);
    n_words = fz_u8(&in);
    cap = 2u * n_words + 1u;
    w = malloc((n_words ? n_words : 1u) * sizeof(*w));
    out = malloc(cap);
    want = malloc(cap);
    for (i = 0; i < n_words; i++)
        w[i] = fz_empty(&in) ? TWH_BLANK : fz_u16(&in);

    memset(out, FZ_POISON, cap);
    twh_decode_text(w, n_words, out);
    len = ref_text(w, n_words, want);
    FZ_CHECK(memcmp(out, want, len) == 0);
    FZ_EQ(out[len], 0);
    for (i = 0; i < len; i++)
        FZ_CHECK((unsigned char)out[i] <= 0x7Fu);

    /* round trip */
    tlen = 0;
    while (!fz_empty(&in) && tlen < 2u * n_words)
        text[tlen++] = (char)(0x20u + fz_u8(&in) % 0x5Fu);   /* ' ' .. '~' */
    pad = (tlen & 1u) ? ' ' : 0;     /* both paddings get their turn */
    for (i = 0; i < n_words; i++) {
        unsigned c0 = 2u * i < tlen ? (unsigned char)text[2u * i] : pad;
        unsigned c1 = 2u * i + 1u < tlen ? (unsigned char)text[2u * i + 1u] : pad;
        w[i] = (uint16_t)(c0 << 7 | c1);
    }
    memset(out, FZ_POISON, cap);
    twh_decode_text(w, n_words, out);
    keep = tlen;
    while (keep && text[keep - 1] == ' ')
        keep--;
    FZ_CHECK(memcmp(out, text, keep) == 0);
    FZ_EQ(out[keep], 0);

    free(want);
    free(out);
    free(w);
    return 0;
}
