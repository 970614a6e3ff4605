/* twh_encode_addr, twh_encode_write, twh_expects_response, twh_status_err.
 *
 * Input: base command, address (u16 LE), word (u16 LE), command byte,
 * status byte.
 *
 * Properties:
 * - encode_addr: TWH_ERR_BAD_ARG exactly for addresses past 0x1FF, outputs
 *   untouched; else cmd = base | address bit 8, payload = address bits
 *   7:0; for the three addressed commands (0x46, 0x48, 0x4A) the spec's
 *   decoding (address = cmd bit 0 << 8 | payload LSB) gives the address
 *   back;
 * - encode_write: TWH_ERR_BAD_ARG exactly for address > 0x1FF or word >
 *   0x3FFF, outputs untouched; else a write command (0x80-0xFF) from which
 *   the spec's decoding (address = payload bits 15:14 << 7 | cmd bits 6:0,
 *   data = payload bits 13:0) gives both back;
 * - expects_response: 1 for 0x40-0x44 and 0x46-0x49, else 0;
 * - status_err: OK for status 0 and for NO_RESPONSE to a command that
 *   expects no answer, -status for 1-8, TWH_ERR_HW_STATUS above 8. */
#include "fuzz_common.h"

static int answers(uint8_t cmd)
{
    static const uint8_t yes[] = {0x40, 0x41, 0x42, 0x43, 0x44, 0x46, 0x47, 0x48, 0x49};
    unsigned i;

    for (i = 0; i < sizeof(yes); i++)
        if (cmd == yes[i])
            return 1;
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_in_t in;
    uint8_t base, cmd, st, c, bases[4];
    uint16_t addr, word, pl;
    int rc, want;
    unsigned i;

    fz_init(&in, data, size);
    base = fz_u8(&in);
    addr = fz_u16(&in);
    word = fz_u16(&in);
    cmd = fz_u8(&in);
    st = fz_u8(&in);

    bases[0] = base;
    bases[1] = TWH_CMD_FIND_FREE;
    bases[2] = TWH_CMD_READ;
    bases[3] = TWH_CMD_ERASE;
    for (i = 0; i < 4; i++) {
        memset(&c, FZ_POISON, sizeof(c));
        memset(&pl, FZ_POISON, sizeof(pl));
        rc = twh_encode_addr(bases[i], addr, &c, &pl);
        if (addr > TWH_ADDR_MAX) {
            FZ_EQ(rc, TWH_ERR_BAD_ARG);
            FZ_CHECK(fz_untouched(&c, sizeof(c)) && fz_untouched(&pl, sizeof(pl)));
            continue;
        }
        FZ_EQ(rc, TWH_OK);
        FZ_EQ(c, bases[i] | (addr >> 8));
        FZ_EQ(pl, addr & 0xFFu);
        if (i > 0) {
            FZ_EQ(((c & 1u) << 8) | (pl & 0xFFu), addr);
            FZ_EQ(c & 0xFEu, bases[i]);
        }
    }

    memset(&c, FZ_POISON, sizeof(c));
    memset(&pl, FZ_POISON, sizeof(pl));
    rc = twh_encode_write(addr, word, &c, &pl);
    if (addr > TWH_ADDR_MAX || word > TWH_WORD_MASK) {
        FZ_EQ(rc, TWH_ERR_BAD_ARG);
        FZ_CHECK(fz_untouched(&c, sizeof(c)) && fz_untouched(&pl, sizeof(pl)));
    } else {
        FZ_EQ(rc, TWH_OK);
        FZ_CHECK(c >= 0x80u);
        FZ_EQ(((pl >> 14) << 7) | (c & 0x7Fu), addr);
        FZ_EQ(pl & 0x3FFFu, word);
        FZ_EQ(twh_expects_response(c), 0);
    }

    FZ_EQ(twh_expects_response(cmd), answers(cmd));

    rc = twh_status_err(st, cmd);
    if (st == 0)
        want = TWH_OK;
    else if (st == TWH_ST_NO_RESPONSE)
        want = answers(cmd) ? TWH_ERR_NO_RESPONSE : TWH_OK;
    else if (st <= TWH_ST_CANCELLED)
        want = -(int)st;
    else
        want = TWH_ERR_HW_STATUS;
    FZ_EQ(rc, want);
    FZ_CHECK(rc <= 0 && rc >= TWH_ERR_HW_STATUS);
    return 0;
}
