/* The whole driver against a well-behaved core whose timing, statuses and
 * answers the input decides (fuzz_core model mode), with a simulated flash
 * device on each channel.
 *
 * Input: flags (bit 0: wait_irq hook), the offset of the event bytes (u16
 * LE), channels (1 + byte % 32), FIFO depth, timeout, one device description per channel
 * (flags: absent, area filled with a sequence; flash size, firmware and
 * type bytes, config bits, ADC answers, the sequence, programmed words),
 * then operations (op byte and arguments) up
 * to the event offset. From there on, one event byte per wait of the
 * driver says how many commands complete, with made-up statuses or data,
 * or none (a stall); without events every wait completes one command as
 * the device answers it.
 *
 * Every command the driver pushes gets a sequence number that travels with
 * it through the core, so its result is known whatever its tag. Properties:
 * - exactly once: every pushed command's result is handed to the caller
 *   exactly once, either by twh_result or as the own result of the
 *   blocking call that pushed it; at the end of each input everything is
 *   completed and drained and no command is left without its result; a
 *   blocking call never takes another command's result for its own;
 * - the stash holds exactly the popped results not yet handed out, in
 *   order; twh_poll = stash + results in the core;
 * - no bus access a real core answers with an error (absent channel's
 *   block, push into a full FIFO, unknown or read-only register), each push
 *   into the CMD_PUSH of the channel asked for, RES_POP only after a VALID
 *   RES_INFO, tags count up by one, no erase or write of words 0x00-0x1F
 *   ever pushed; twh_cal_append erases and writes only inside the
 *   calibration area of the size it was answered;
 * - twh_busy is the BUSY bits of the channels with commands queued;
 *   twh_set_idle_charge sets IDLE_CHARGE to a mask of present channels and
 *   refuses (no bus access) one with a bit of an absent channel;
 * - every call returns a documented code and writes outputs only on
 *   success; refused arguments push nothing; timing writes keep
 *   PREAMBLE_US; twh_set_execute_us succeeds exactly inside the core's
 *   window;
 * - clean runs (core queues empty at the start, no made-up status or data,
 *   no stall during the call): each helper's result is the one the device
 *   model dictates, computed here independently: config, firmware, ADC
 *   readings, read, find-free, erase, write with verify, whole image,
 *   negotiation (4000 us, 6000 us for v18+), and calibration append (the
 *   first blank even pair, else after erasing the page of the oldest
 *   record; the flash afterwards differs from before by exactly that
 *   page and the two new words). */
#include "fuzz_core.h"
#include "fuzz_ref.h"
#include "twh_regs.h"

#define GETF(v, r, f) (((uint32_t)(v) & (uint32_t)TWH_REGS__##r##__##f##_bm) >> TWH_REGS__##r##__##f##_bp)
#define DRAIN_AT 24u    /* the driver needs fewer than 32 commands in flight */

enum { S_NONE, S_FLIGHT, S_STASHED, S_DONE };

typedef struct harness {
    fz_core_t f;
    twh_t t;
    uint8_t state[FZ_SEQ_MAX];
    unsigned outstanding;
    fz_res_t shadow[TWH_STASH_SIZE + 1];
    unsigned n_shadow;
    /* the current call */
    int in_result;
    int have_own;
    uint32_t own_seq;
    int own_seen;
    fz_res_t own, delivered;
    int delivered_n;
    int in_cal, cal_end_known;
    unsigned cal_end, erases, writes;
    uint16_t erase_page;
} harness_t;

static harness_t H;

static void on_push(void *ctx, const fz_cmd_t *c)
{
    harness_t *h = ctx;
    uint16_t ta = fz_target_addr(c->cmd, c->payload);

    FZ_CHECK(c->seq < FZ_SEQ_MAX);
    FZ_EQ(h->state[c->seq], S_NONE);
    h->state[c->seq] = S_FLIGHT;
    h->outstanding++;
    FZ_CHECK(h->outstanding < 32u);
    h->have_own = 1;
    h->own_seq = c->seq;
    h->own_seen = 0;
    if (ta != 0xFFFFu) {
        if (c->cmd >= 0x80u) {
            h->writes++;
        } else {
            h->erases++;
            h->erase_page = ta;
        }
        if (h->in_cal) {
            FZ_CHECK(h->cal_end_known);
            FZ_CHECK(ta >= TWH_CAL_START && ta < h->cal_end);
        }
    }
}

static void on_pop(void *ctx, const fz_res_t *r)
{
    harness_t *h = ctx;

    FZ_EQ(h->state[r->seq], S_FLIGHT);
    if (h->in_result) {
        h->delivered = *r;
        h->delivered_n++;
        h->state[r->seq] = S_DONE;
        h->outstanding--;
        return;
    }
    if (h->have_own && r->seq == h->own_seq) {
        h->own_seen = 1;
        h->own = *r;
        h->state[r->seq] = S_DONE;
        h->outstanding--;
        if (h->in_cal && r->cmd == TWH_CMD_CONFIG && !h->cal_end_known) {
            unsigned size = r->data & TWH_ADDR_MAX;
            h->cal_end = size < TWH_CAL_END ? size : TWH_CAL_END;
            h->cal_end_known = 1;
        }
        return;
    }
    FZ_CHECK(h->n_shadow < TWH_STASH_SIZE);
    h->shadow[h->n_shadow++] = *r;
    h->state[r->seq] = S_STASHED;
}

static void begin(harness_t *h, int in_result)
{
    fz_obs_reset(&h->f);
    h->in_result = in_result;
    h->have_own = 0;
    h->own_seen = 0;
    h->delivered_n = 0;
    h->in_cal = 0;
    h->cal_end_known = 0;
    h->erases = h->writes = 0;
}

static int same(const twh_result_t *a, const fz_res_t *b)
{
    return a->cmd == b->cmd && a->status == b->status && a->channel == b->ch &&
           a->tag == b->tag && a->data == b->data;
}

static void check_invariants(const harness_t *h)
{
    unsigned i, ch;

    FZ_EQ(h->t.stash_count, h->n_shadow);
    for (i = 0; i < h->n_shadow; i++)
        FZ_CHECK(same(&h->t.stash[(h->t.stash_head + i) % TWH_STASH_SIZE], &h->shadow[i]));
    FZ_EQ(h->f.bus_errors, 0);
    FZ_EQ(h->f.bad_channel, 0);
    FZ_EQ(h->f.order_errors, 0);
    FZ_EQ(h->f.factory_pushes, 0);
    FZ_EQ(h->f.tag_errors, 0);
    for (ch = 0; ch < FZ_MAX_CH; ch++)
        FZ_EQ(GETF(h->f.timing[ch][1], CHANNEL_T__TIMING1, PREAMBLE_US), 2000);
}

static void end_blocking(harness_t *h, int rc)
{
    FZ_CHECK(fz_is_err_code(rc));
    FZ_CHECK(rc != TWH_ERR_BUS && rc != TWH_ERR_AGAIN && rc != TWH_ERR_BAD_ID);
    if (rc == TWH_ERR_STASH_FULL)
        FZ_EQ(h->n_shadow, TWH_STASH_SIZE);
    check_invariants(h);
}

static void op_result(harness_t *h)
{
    twh_result_t r;
    unsigned had = h->t.stash_count, in_core = h->f.res_n, i;
    int rc;

    begin(h, 1);
    memset(&r, FZ_POISON, sizeof(r));
    rc = twh_result(&h->t, &r);
    if (had) {
        FZ_EQ(rc, TWH_OK);
        FZ_EQ(h->f.obs.reads, 0);
        FZ_CHECK(same(&r, &h->shadow[0]));
        h->state[h->shadow[0].seq] = S_DONE;
        h->outstanding--;
        for (i = 1; i < h->n_shadow; i++)
            h->shadow[i - 1] = h->shadow[i];
        h->n_shadow--;
    } else if (in_core) {
        FZ_EQ(rc, TWH_OK);
        FZ_EQ(h->delivered_n, 1);
        FZ_CHECK(same(&r, &h->delivered));
    } else {
        FZ_EQ(rc, TWH_ERR_AGAIN);
        FZ_CHECK(fz_untouched(&r, sizeof(r)));
    }
    check_invariants(h);
}

/* complete everything and hand every result out */
static void drain(harness_t *h)
{
    unsigned guard = 0;

    while (h->outstanding) {
        while (fz_complete_clean(&h->f))
            ;
        op_result(h);
        FZ_CHECK(++guard < 100000u);
    }
    FZ_EQ(h->f.cmd_n + h->f.res_n + h->t.stash_count, 0);
}

/* ------------------------------------------------ reference device answers */
static uint16_t first_blank(const fz_dev_t *d, unsigned from)
{
    unsigned a;

    for (a = from; a < d->size && d->flash[a] != TWH_BLANK; a++)
        ;
    return (uint16_t)a;
}

/* lowest even a in [0x20, end) with a and a+1 blank; 0 when none */
static unsigned blank_pair(const uint16_t *fl, unsigned end)
{
    unsigned a;

    for (a = TWH_CAL_START; a + 1u < end; a += 2u)
        if (fl[a] == TWH_BLANK && fl[a + 1u] == TWH_BLANK)
            return a;
    return 0;
}

/* twh_cal_append on a device that answers everything truthfully: the
 * expected code, address and flash afterwards */
static int ref_append(const fz_dev_t *d, uint16_t stamp, uint16_t value, uint16_t *fl,
                      unsigned *addr, int *erased)
{
    unsigned end = d->size < TWH_CAL_END ? d->size : TWH_CAL_END, a, best = TWH_BLANK, page, w;

    memcpy(fl, d->flash, sizeof(d->flash));
    *erased = 0;
    if (!d->present)
        return TWH_ERR_NO_RESPONSE;
    if (end < TWH_CAL_START + 2u)
        return TWH_ERR_FLASH_FULL;
    a = blank_pair(fl, end);
    if (!a) {
        page = TWH_CAL_START;
        for (a = TWH_CAL_START; a + 1u < end; a += 2u)
            if (fl[a] != TWH_BLANK && fl[a + 1u] != TWH_BLANK && fl[a] < best) {
                best = fl[a];
                page = a & ~15u;
            }
        for (w = page; w < page + 16u && w < d->size; w++)
            fl[w] = TWH_BLANK;
        *erased = 1;
        a = blank_pair(fl, end);
        FZ_CHECK(a != 0);
    }
    fl[a] = stamp;
    fl[a + 1u] = value;
    *addr = a;
    return TWH_OK;
}

/* ------------------------------------------------------------ operations */
static void op_submit(harness_t *h, uint8_t ch, uint8_t cmd, uint16_t payload)
{
    int full = h->f.cmd_n >= h->f.depth, rc;
    uint8_t tag = h->t.next_tag;

    begin(h, 0);
    rc = twh_submit(&h->t, ch, cmd, payload);
    if (ch >= h->f.channels || fz_target_addr(cmd, payload) < TWH_FACTORY_END) {
        FZ_EQ(rc, TWH_ERR_BAD_ARG);
        FZ_EQ(h->f.obs.pushes + h->f.obs.reads, 0);
    } else if (full) {
        FZ_EQ(rc, TWH_ERR_FIFO_FULL);
        FZ_EQ(h->f.obs.pushes, 0);
    } else {
        FZ_EQ(rc, tag);
        FZ_EQ(h->f.obs.pushes, 1);
        FZ_EQ(h->f.obs.last_push.ch, ch);
    }
    check_invariants(h);
}

static void op_xfer(harness_t *h, uint8_t ch, uint8_t cmd, uint16_t payload)
{
    uint16_t d;
    int rc;

    begin(h, 0);
    memset(&d, FZ_POISON, sizeof(d));
    rc = twh_xfer(&h->t, ch, cmd, payload, &d);
    end_blocking(h, rc);
    if (ch >= h->f.channels || fz_target_addr(cmd, payload) < TWH_FACTORY_END)
        FZ_EQ(rc, TWH_ERR_BAD_ARG);
    if (rc == TWH_ERR_BAD_ARG || rc == TWH_ERR_FIFO_FULL)
        FZ_EQ(h->f.obs.pushes, 0);
    else
        FZ_EQ(h->f.obs.pushes, 1);
    if (h->own_seen) {
        FZ_EQ(rc, twh_status_err(h->own.status, h->own.cmd));
        FZ_EQ(h->own.cmd, cmd);
        FZ_EQ(h->own.ch, ch);
    } else {
        FZ_CHECK(rc < TWH_ERR_HW_STATUS);
    }
    if (rc == TWH_OK)
        FZ_EQ(d, h->own.data);
    else
        FZ_CHECK(fz_untouched(&d, sizeof(d)));
}

static void op_helper(harness_t *h, uint8_t op, uint8_t sub, uint8_t ch, uint16_t a, uint16_t b)
{
    const fz_dev_t *dv = &h->f.dev[ch < FZ_MAX_CH ? ch : 0];
    fz_dev_t before;
    union {
        struct { uint8_t bits; uint16_t words; } cfg;
        twh_fw_t fw;
        uint16_t v;
    } o;
    twh_fw_t fw;
    uint16_t *img = NULL, ref_fl[512];
    unsigned n = 0, i, k, ref_addr = 0;
    int rc = 0, want, clean, present = ch < h->f.channels && dv->present, ref_erased;

    clean = h->f.cmd_n == 0 && h->f.res_n == 0 && ch < h->f.channels;
    before = *dv;
    begin(h, 0);
    memset(&o, FZ_POISON, sizeof(o));
    switch (op) {
    case 6:
        rc = twh_config(&h->t, ch, &o.cfg.bits, &o.cfg.words);
        end_blocking(h, rc);
        if (rc == TWH_OK)
            FZ_CHECK(o.cfg.bits < 128u && o.cfg.words <= TWH_ADDR_MAX);
        if (clean && !h->f.obs.injected) {
            FZ_EQ(rc, present ? TWH_OK : TWH_ERR_NO_RESPONSE);
            if (present) {
                FZ_EQ(o.cfg.bits, before.config & 0x7Fu);
                FZ_EQ(o.cfg.words, before.size);
            }
        }
        break;
    case 7:
        rc = twh_firmware(&h->t, ch, &o.fw);
        end_blocking(h, rc);
        if (clean && !h->f.obs.injected) {
            FZ_EQ(rc, present ? TWH_OK : TWH_ERR_NO_RESPONSE);
            if (present) {
                twh_fw_decode((uint16_t)(before.fw << 8 | before.type), &fw);
                FZ_CHECK(memcmp(&fw, &o.fw, sizeof(fw)) == 0);
            }
        }
        break;
    case 8:
        rc = sub % 3u == 0 ? twh_ref_voltage(&h->t, ch, &o.v)
           : sub % 3u == 1 ? twh_temperature(&h->t, ch, &o.v)
                           : twh_o2_voltage(&h->t, ch, &o.v);
        end_blocking(h, rc);
        if (rc == TWH_OK)
            FZ_CHECK(o.v <= 0x0FFFu);
        if (clean && !h->f.obs.injected) {
            FZ_EQ(rc, present ? TWH_OK : TWH_ERR_NO_RESPONSE);
            if (present)
                FZ_EQ(o.v, before.adc[sub % 3u] & 0x0FFFu);
        }
        break;
    case 9:
        rc = twh_find_free(&h->t, ch, a, &o.v);
        end_blocking(h, rc);
        if (rc == TWH_OK)
            FZ_CHECK(o.v >= a && o.v <= TWH_ADDR_MAX + 1u);
        if (a > TWH_ADDR_MAX)
            FZ_EQ(rc, TWH_ERR_BAD_ARG);
        if (clean && !h->f.obs.injected && a <= TWH_ADDR_MAX) {
            if (!present || a >= before.size) {
                FZ_EQ(rc, TWH_ERR_NO_RESPONSE);
            } else {
                FZ_EQ(rc, TWH_OK);
                FZ_EQ(o.v, first_blank(&before, a));
            }
        }
        break;
    case 10:
        rc = twh_read_word(&h->t, ch, a, &o.v);
        end_blocking(h, rc);
        if (rc == TWH_OK)
            FZ_CHECK(o.v <= TWH_WORD_MASK);
        if (clean && !h->f.obs.injected && a <= TWH_ADDR_MAX) {
            if (!present || a >= before.size) {
                FZ_EQ(rc, TWH_ERR_NO_RESPONSE);
            } else {
                FZ_EQ(rc, TWH_OK);
                FZ_EQ(o.v, before.flash[a]);
            }
        }
        break;
    case 11:
        rc = twh_erase_page(&h->t, ch, a);
        end_blocking(h, rc);
        if (a < TWH_FACTORY_END || a > TWH_ADDR_MAX) {
            FZ_EQ(rc, TWH_ERR_BAD_ARG);
            FZ_EQ(h->f.obs.pushes, 0);
        } else if (clean && !h->f.obs.injected) {
            FZ_EQ(rc, TWH_OK);
            for (i = 0; i < 512u; i++)
                FZ_EQ(dv->flash[i], (present && a < before.size && i < before.size &&
                                     (i & ~15u) == (a & ~15u))
                                        ? TWH_BLANK : before.flash[i]);
        }
        break;
    case 12:
        rc = twh_write_word(&h->t, ch, a, b);
        end_blocking(h, rc);
        if (a < TWH_FACTORY_END || a > TWH_ADDR_MAX || b > TWH_WORD_MASK) {
            FZ_EQ(rc, TWH_ERR_BAD_ARG);
            FZ_EQ(h->f.obs.pushes, 0);
        } else if (clean && !h->f.obs.injected) {
            if (!present || a >= before.size) {
                FZ_EQ(rc, TWH_ERR_NO_RESPONSE);
            } else {
                want = before.flash[a] == TWH_BLANK || before.flash[a] == b ? TWH_OK : TWH_ERR_VERIFY;
                FZ_EQ(rc, want);
                FZ_EQ(dv->flash[a], before.flash[a] == TWH_BLANK ? b : before.flash[a]);
            }
        }
        break;
    case 13:
        n = a % 600u;
        img = malloc((n ? n : 1u) * sizeof(*img));
        memset(img, FZ_POISON, (n ? n : 1u) * sizeof(*img));
        rc = twh_read_image(&h->t, ch, img, (uint16_t)n);
        end_blocking(h, rc);
        if (n > 512u) {
            FZ_EQ(rc, TWH_ERR_BAD_ARG);
            FZ_EQ(h->f.obs.pushes, 0);
        }
        if (rc != TWH_OK && n <= 512u) {
            /* words read before the failing one are kept (docs/fuzzing.md) */
            i = fz_written_prefix(img, n);
            FZ_CHECK(i != ~0u && i < n);
            for (k = 0; k < i; k++)
                FZ_CHECK(img[k] <= TWH_WORD_MASK);
        } else if (rc != TWH_OK) {
            FZ_CHECK(fz_untouched(img, sizeof(*img)));
        }
        if (clean && !h->f.obs.injected && n <= 512u && n > 0) {
            if (!present || n > before.size) {
                FZ_EQ(rc, TWH_ERR_NO_RESPONSE);
            } else {
                FZ_EQ(rc, TWH_OK);
                for (i = 0; i < n; i++)
                    FZ_EQ(img[i], before.flash[i]);
            }
        }
        free(img);
        break;
    case 14:
        if (sub & 1u) {
            uint32_t old = ch < FZ_MAX_CH ? h->f.timing[ch][1] : 0;

            rc = twh_set_execute_us(&h->t, ch, a);
            check_invariants(h);
            FZ_EQ(h->f.obs.pushes, 0);
            if (ch >= h->f.channels) {
                FZ_EQ(rc, TWH_ERR_BAD_ARG);
                FZ_EQ(h->f.obs.reads + h->f.obs.timing_writes, 0);
            } else {
                want = a >= FZ_EXECUTE_MIN && a <= FZ_EXECUTE_MAX;
                FZ_EQ(rc, want ? TWH_OK : TWH_ERR_REFUSED);
                FZ_EQ(GETF(h->f.timing[ch][1], CHANNEL_T__TIMING1, EXECUTE_US),
                      want ? a : GETF(old, CHANNEL_T__TIMING1, EXECUTE_US));
            }
            break;
        }
        if (sub & 2u) {
            /* IDLE_CHARGE: a mask of channels; with sub bit 2 only present ones */
            uint32_t mask = (uint32_t)a | (uint32_t)b << 16, old = h->f.idle_charge;

            if (sub & 4u)
                mask &= fz_present_mask(&h->f);

            rc = twh_set_idle_charge(&h->t, mask);
            check_invariants(h);
            FZ_EQ(h->f.obs.pushes + h->f.obs.reads, 0);
            if (mask & ~fz_present_mask(&h->f)) {
                FZ_EQ(rc, TWH_ERR_BAD_ARG);
                FZ_EQ(h->f.obs.other_writes, 0);
                FZ_EQ(h->f.idle_charge, old);
            } else {
                FZ_EQ(rc, TWH_OK);
                FZ_EQ(h->f.obs.other_writes, 1);
                FZ_EQ(h->f.idle_charge, mask);
            }
            break;
        }
        rc = twh_negotiate(&h->t, ch, &o.fw);
        end_blocking(h, rc);
        /* this core accepts 4000 and 6000: no failure after the version */
        if (rc == TWH_OK)
            FZ_EQ(GETF(h->f.timing[ch][1], CHANNEL_T__TIMING1, EXECUTE_US), twh_execute_us_for(&o.fw));
        else
            FZ_CHECK(fz_untouched(&o, sizeof(o)));
        if (clean && !h->f.obs.injected) {
            FZ_EQ(rc, present ? TWH_OK : TWH_ERR_NO_RESPONSE);
            twh_fw_decode((uint16_t)(before.fw << 8 | before.type), &fw);
            FZ_EQ(GETF(h->f.timing[ch][1], CHANNEL_T__TIMING1, EXECUTE_US),
                  present ? twh_execute_us_for(&fw) : TWH_EXECUTE_SAFE_US);
        }
        break;
    default:
        h->in_cal = 1;
        rc = twh_cal_append(&h->t, ch, a, b, &o.v);
        end_blocking(h, rc);
        if (a >= TWH_BLANK || b >= TWH_BLANK) {
            FZ_EQ(rc, TWH_ERR_BAD_ARG);
            FZ_EQ(h->f.obs.pushes, 0);
            break;
        }
        FZ_CHECK(h->erases <= 1u);
        if (rc == TWH_OK) {
            FZ_CHECK(h->cal_end_known);
            FZ_CHECK(!(o.v & 1u) && o.v >= TWH_CAL_START && o.v + 1u < h->cal_end);
        } else {
            FZ_CHECK(fz_untouched(&o, sizeof(o)));
        }
        if (clean && !h->f.obs.injected) {
            FZ_EQ(rc, ref_append(&before, a, b, ref_fl, &ref_addr, &ref_erased));
            FZ_EQ(h->erases, (unsigned)ref_erased);
            if (rc == TWH_OK) {
                FZ_EQ(o.v, ref_addr);
                FZ_EQ(h->writes, 2);
            }
            for (i = 0; i < 512u; i++)
                FZ_EQ(dv->flash[i], ref_fl[i]);
        }
        break;
    }
}

static void setup_dev(fz_dev_t *d, fz_in_t *in)
{
    uint8_t flags = fz_u8(in), k, i, step;
    unsigned a, base;

    d->present = !(flags & 0x80u);
    /* XOR with typical values: an all-zero input is an O2 cell v18 with a
     * 240-word map */
    d->size = (uint16_t)((fz_u16(in) ^ 240u) & 0x1FFu);
    d->fw = (uint8_t)(fz_u8(in) ^ 0x12u);
    d->type = (uint8_t)(fz_u8(in) ^ 0x01u);
    d->config = fz_u8(in) & 0x7Fu;
    d->adc[0] = (uint16_t)(fz_u16(in) ^ 1353u);
    d->adc[1] = (uint16_t)(fz_u16(in) ^ 2000u);
    d->adc[2] = (uint16_t)(fz_u16(in) ^ 239u);
    for (a = 0; a < 512u; a++)
        d->flash[a] = TWH_BLANK;
    /* a whole calibration area in one go (an arithmetic sequence; step 0
     * gives every record the same stamp): a full area is what makes
     * twh_cal_append erase, and single words below could hardly fill it */
    if (flags & 0x40u) {
        base = fz_u16(in);
        step = fz_u8(in);
        for (a = TWH_CAL_START; a < TWH_CAL_END; a++)
            d->flash[a] = (uint16_t)((base + (a - TWH_CAL_START) * step) & TWH_WORD_MASK);
    }
    k = fz_u8(in);
    for (i = 0; i < k && !fz_empty(in); i++) {
        a = TWH_CAL_START + fz_u8(in) % 0xC0u;
        d->flash[a] = fz_u16(in) & TWH_WORD_MASK;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    harness_t *h = &H;
    fz_in_t in, ev;
    twh_platform_t plat;
    uint8_t flags, channels, op, ch, cmd, sub;
    uint16_t depth, a, b, ev_off;
    unsigned ops = 0, i;
    int rc;

    fz_init(&in, data, size);
    memset(h, 0, sizeof(*h));
    flags = fz_u8(&in);
    /* the core's events come from the tail of the input, so that they do
     * not shift the operations when the driver waits more or less often */
    ev_off = fz_u16(&in);
    if (ev_off < size) {
        fz_init(&ev, data + ev_off, size - ev_off);
        in.n = ev_off > 3u ? ev_off - 3u : 0;
    } else {
        fz_init(&ev, data, 0);
    }
    channels = (uint8_t)(1u + fz_u8(&in) % FZ_MAX_CH);
    depth = (uint16_t)(FZ_DEPTH_MAX >> (fz_u8(&in) % 5u));
    fz_core_init(&h->f, &ev, 0, channels, depth);
    h->f.on_push = on_push;
    h->f.on_pop = on_pop;
    h->f.hctx = h;
    fz_platform(&h->f, &plat, flags & 1u);
    begin(h, 0);
    rc = twh_init(&h->t, &plat);
    FZ_EQ(rc, TWH_OK);
    FZ_EQ(h->t.channels, channels);
    FZ_EQ(h->t.fifo_depth, depth);
    FZ_EQ((h->f.irq_en & TWH_REGS__IRQ_EN__RESULT_bm) != 0, (flags & 1u) != 0);
    h->t.timeout_us = 1000u * (1u + fz_u8(&in) % 8u);
    for (i = 0; i < channels; i++)
        setup_dev(&h->f.dev[i], &in);

    while (!fz_empty(&in) && ops++ < 300u && h->f.next_seq < FZ_SEQ_MAX - 1024u) {
        if (h->outstanding >= DRAIN_AT)
            drain(h);
        op = fz_u8(&in) % 16u;
        ch = fz_u8(&in) % (FZ_MAX_CH + 1u);   /* FZ_MAX_CH: never a channel */
        switch (op) {
        case 0:
            cmd = fz_u8(&in);
            a = fz_u16(&in);
            op_submit(h, ch, cmd, a);
            break;
        case 1:
            begin(h, 0);
            rc = twh_poll(&h->t);
            FZ_EQ(rc, h->t.stash_count + h->f.res_n);
            /* BUSY: the channels with a command queued, nothing else */
            FZ_EQ(twh_busy(&h->t), fz_busy(&h->f));
            FZ_EQ(fz_busy(&h->f) & ~fz_present_mask(&h->f), 0);
            check_invariants(h);
            break;
        case 2:
            op_result(h);
            break;
        case 3:
            cmd = fz_u8(&in);
            a = fz_u16(&in);
            op_xfer(h, ch, cmd, a);
            break;
        case 4: {
            unsigned queued = h->f.cmd_n;

            begin(h, 0);
            FZ_EQ(twh_cancel_all(&h->t), TWH_OK);
            for (i = 0; i < queued; i++)
                FZ_CHECK(h->f.cmdq[i].cancelled);
            FZ_CHECK(h->f.ctrl & TWH_REGS__CTRL__ENABLE_bm);
            check_invariants(h);
            break;
        }
        case 5:
            (void)fz_step(&h->f);
            break;
        default:
            sub = fz_u8(&in);
            a = fz_u16(&in);
            b = fz_u16(&in);
            op_helper(h, op, sub, ch, a, b);
            break;
        }
    }
    drain(h);
    for (i = 0; i < h->f.next_seq; i++)
        FZ_EQ(h->state[i], S_DONE);
    return 0;
}
