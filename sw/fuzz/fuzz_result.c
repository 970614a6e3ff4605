/* The driver's result path against a hostile core: every register read
 * returns the next 4 input bytes (fuzz_core raw mode).
 *
 * Input: flags (bit 0: give a wait_irq hook), the reads of twh_init (ID,
 * VERSION, PARAMS[, IRQ_EN]), timeout and poll step, then operations, each
 * an op byte and its arguments, with the register values the driver reads
 * interleaved in the order it reads them.
 *
 * The harness keeps its own copy of what the stash must hold: every result
 * popped with RES_POP agreeing with RES_INFO (status, channel, tag, VALID)
 * that is neither handed out by twh_result nor the own result of the
 * command the current call pushed last (same channel, tag and command).
 * Properties after every call:
 * - the driver's stash equals that copy, in order (nothing lost, nothing
 *   duplicated, nothing reordered), never more than TWH_STASH_SIZE;
 * - RES_POP is read only right after a RES_INFO that showed VALID;
 * - twh_init succeeds exactly for the right ID, major version (2), 1-32
 *   channels and a FIFO depth > 0, and otherwise leaves channels 0;
 * - twh_poll = stash + RES_LEVEL; twh_result serves the stash first without
 *   a bus access, else RES_INFO then RES_POP: TWH_ERR_AGAIN without VALID,
 *   the popped result when RES_POP agrees, TWH_ERR_BUS when it does not;
 * - twh_submit refuses absent channels and factory-area erase/write with no
 *   bus access, a full FIFO with no push, else pushes once with the next
 *   tag, into the channel's own CMD_PUSH; twh_cancel_all writes CTRL as
 *   read plus FLUSH; twh_set_idle_charge refuses a mask with a bit of an
 *   absent channel with no bus access, else writes it to IDLE_CHARGE and
 *   nothing else; twh_busy returns BUSY as read, one read;
 * - blocking calls return a documented code; the status code of a result
 *   comes back only when the own result was popped, and is
 *   twh_status_err() of it; TWH_ERR_BUS exactly when a RES_POP disagreed;
 *   TWH_ERR_STASH_FULL only with a full stash; waits are bounded by the
 *   timeout;
 * - helpers write outputs only on success, with the documented ranges
 *   (7 config bits, 9-bit size, 12-bit ADC, 14-bit word, find-free
 *   answer in [from, 0x200]); twh_cal_append erases and writes only inside
 *   [0x20, min(0xE0, size)) of the size it was answered; no erase or write
 *   of words 0x00-0x1F is ever pushed; twh_read_image keeps the words read
 *   before a failing one and leaves the rest untouched; twh_negotiate
 *   fills *fw once the version was read (also when the last timing write
 *   is refused), not before; twh_set_execute_us succeeds exactly when the
 *   read-back equals the value read with EXECUTE_US replaced;
 * - on a fixed-timing build (VERSION.FIXED_TIMING at twh_init) no timing
 *   register is written: twh_set_execute_us only reads TIMING1 twice, and
 *   twh_negotiate only asks the version (TWH_OK once it was read). */
#include "fuzz_core.h"
#include "twh_regs.h"

#define POP_DEFINED                                                         \
    ((uint32_t)(TWH_REGS__RES_POP__DATA_bm | TWH_REGS__RES_POP__STATUS_bm |  \
                TWH_REGS__RES_POP__CHANNEL_bm | TWH_REGS__RES_POP__VALID_bm | \
                TWH_REGS__RES_POP__TAG_bm))
#define GETF(v, r, f) (((uint32_t)(v) & (uint32_t)TWH_REGS__##r##__##f##_bm) >> TWH_REGS__##r##__##f##_bp)

typedef struct harness {
    fz_core_t f;
    twh_t t;
    twh_result_t shadow[TWH_STASH_SIZE + 1];
    unsigned n_shadow;
    int fixed_timing;           /* VERSION.FIXED_TIMING as twh_init read it */
    /* the current call */
    int in_result;              /* twh_result: a popped result is handed out */
    int have_own;
    fz_cmd_t own_cmd;           /* the call's last push */
    int own_seen;
    fz_res_t own;
    unsigned rejected;          /* RES_POP reads that disagreed with RES_INFO */
    fz_res_t delivered;
    int delivered_n;
    /* twh_cal_append: size answered to its config command */
    int in_cal;
    unsigned cal_end;
    int cal_end_known;
    /* twh_negotiate: the firmware answer */
    int fw_read;
    uint16_t fw_data;
    /* twh_read_image: the words the own results carried */
    uint16_t img[512];
    unsigned n_img;
} harness_t;

static harness_t H;

static int same_res(const twh_result_t *a, const fz_res_t *b)
{
    return a->cmd == b->cmd && a->status == b->status && a->channel == b->ch &&
           a->tag == b->tag && a->data == b->data;
}

static void on_push(void *ctx, const fz_cmd_t *c)
{
    harness_t *h = ctx;
    uint16_t ta = fz_target_addr(c->cmd, c->payload);

    h->have_own = 1;
    h->own_cmd = *c;
    h->own_seen = 0;
    if (h->in_cal && ta != 0xFFFFu) {
        FZ_CHECK(h->cal_end_known);
        FZ_CHECK(ta >= TWH_CAL_START && ta < h->cal_end);
    }
}

static void on_pop(void *ctx, const fz_res_t *r)
{
    harness_t *h = ctx;
    uint32_t info = h->f.last_info, pop = h->f.last_pop_raw;
    twh_result_t *s;

    /* RES_POP agrees with RES_INFO: VALID, the same status, channel and
     * tag, and nothing in the bits the register map leaves undefined */
    if (!(pop & TWH_REGS__RES_POP__VALID_bm) || (pop & ~POP_DEFINED) ||
        GETF(info, RES_INFO, STATUS) != r->status || GETF(info, RES_INFO, CHANNEL) != r->ch ||
        GETF(info, RES_INFO, TAG) != r->tag) {
        h->rejected++;
        return;
    }
    if (h->in_result) {
        h->delivered = *r;
        h->delivered_n++;
        return;
    }
    if (h->have_own && r->ch == h->own_cmd.ch && r->tag == h->own_cmd.tag &&
        r->cmd == h->own_cmd.cmd) {
        h->own_seen = 1;
        h->own = *r;
        if (h->in_cal && r->cmd == TWH_CMD_CONFIG && !h->cal_end_known) {
            unsigned size = r->data & TWH_ADDR_MAX;
            h->cal_end = size < TWH_CAL_END ? size : TWH_CAL_END;
            h->cal_end_known = 1;
        }
        if (r->cmd == TWH_CMD_FIRMWARE && twh_status_err(r->status, r->cmd) == TWH_OK) {
            h->fw_read = 1;
            h->fw_data = r->data;
        }
        if ((r->cmd & 0xFEu) == TWH_CMD_READ && h->n_img < 512u)
            h->img[h->n_img++] = r->data & TWH_WORD_MASK;
        return;
    }
    FZ_CHECK(h->n_shadow < TWH_STASH_SIZE);
    s = &h->shadow[h->n_shadow++];
    s->cmd = r->cmd;
    s->status = r->status;
    s->channel = r->ch;
    s->tag = r->tag;
    s->data = r->data;
}

static void begin(harness_t *h, int in_result)
{
    fz_obs_reset(&h->f);
    h->in_result = in_result;
    h->have_own = 0;
    h->own_seen = 0;
    h->rejected = 0;
    h->delivered_n = 0;
    h->in_cal = 0;
    h->cal_end_known = 0;
    h->n_img = 0;
    h->fw_read = 0;
}

static void check_stash(const harness_t *h)
{
    unsigned i, k;

    FZ_EQ(h->t.stash_count, h->n_shadow);
    for (i = 0; i < h->n_shadow; i++) {
        const twh_result_t *a = &h->t.stash[(h->t.stash_head + i) % TWH_STASH_SIZE];
        const twh_result_t *b = &h->shadow[i];

        k = a->cmd == b->cmd && a->status == b->status && a->channel == b->channel &&
            a->tag == b->tag && a->data == b->data;
        FZ_CHECK(k);
    }
}

/* what every blocking call must satisfy */
static void end_blocking(harness_t *h, int rc)
{
    unsigned per;

    FZ_CHECK(fz_is_err_code(rc));
    FZ_EQ(h->f.order_errors, 0);
    FZ_EQ(h->f.factory_pushes, 0);
    FZ_EQ(h->rejected, rc == TWH_ERR_BUS ? 1u : 0u);
    if (rc == TWH_ERR_STASH_FULL)
        FZ_EQ(h->n_shadow, TWH_STASH_SIZE);
    /* each command waits for at most its own timeout; a wait_irq return
     * of 0 still counts as 1 us */
    per = h->t.plat.wait_irq ? h->t.timeout_us : h->t.timeout_us / h->t.poll_us + 1u;
    FZ_CHECK(h->f.obs.waits <= (h->f.obs.pushes ? h->f.obs.pushes : 1u) * per);
    check_stash(h);
}

/* The error a single-command call must return, judged from its own
 * result: 1 and *e when it was popped. */
static int own_err(const harness_t *h, int *e)
{
    if (!h->own_seen)
        return 0;
    *e = twh_status_err(h->own.status, h->own.cmd);
    return 1;
}

/* rc of a single-command call: the own result's status code, or a driver
 * error (never a status code) when it did not arrive */
static void check_single(const harness_t *h, int rc, int *e)
{
    if (own_err(h, e)) {
        if (*e)
            FZ_EQ(rc, *e);
    } else {
        *e = 1;
        FZ_CHECK(rc < TWH_ERR_HW_STATUS);
    }
}

static void op_submit(harness_t *h, uint8_t ch, uint8_t cmd, uint16_t payload)
{
    uint32_t st = fz_peek_u32(h->f.in, 0);
    uint8_t tag = h->t.next_tag;
    int rc;

    begin(h, 0);
    rc = twh_submit(&h->t, ch, cmd, payload);
    if (ch >= h->t.channels || fz_target_addr(cmd, payload) < TWH_FACTORY_END) {
        FZ_EQ(rc, TWH_ERR_BAD_ARG);
        FZ_EQ(h->f.obs.reads + h->f.obs.pushes, 0);
    } else if (st & TWH_REGS__STATUS__CMD_FULL_bm) {
        FZ_EQ(rc, TWH_ERR_FIFO_FULL);
        FZ_EQ(h->f.obs.pushes, 0);
    } else {
        FZ_EQ(rc, tag);
        FZ_EQ(h->f.obs.pushes, 1);
        FZ_EQ(h->f.obs.last_push.cmd, cmd);
        FZ_EQ(h->f.obs.last_push.payload, payload);
        FZ_EQ(h->f.obs.last_push.ch, ch);
        FZ_EQ(h->f.obs.last_push.tag, tag);
        FZ_EQ(h->t.next_tag, (tag + 1u) & 31u);
    }
    FZ_EQ(h->f.tag_errors, 0);
    check_stash(h);
}

static void op_result(harness_t *h)
{
    twh_result_t r;
    uint32_t info = fz_peek_u32(h->f.in, 0);
    unsigned had = h->t.stash_count, i;
    int rc;

    begin(h, 1);
    memset(&r, FZ_POISON, sizeof(r));
    rc = twh_result(&h->t, &r);
    FZ_EQ(h->f.order_errors, 0);
    if (had) {
        FZ_EQ(rc, TWH_OK);
        FZ_EQ(h->f.obs.reads, 0);
        FZ_CHECK(r.cmd == h->shadow[0].cmd && r.status == h->shadow[0].status &&
                 r.channel == h->shadow[0].channel && r.tag == h->shadow[0].tag &&
                 r.data == h->shadow[0].data);
        for (i = 1; i < h->n_shadow; i++)
            h->shadow[i - 1] = h->shadow[i];
        h->n_shadow--;
    } else if (!(info & TWH_REGS__RES_INFO__VALID_bm)) {
        FZ_EQ(rc, TWH_ERR_AGAIN);
        FZ_EQ(h->f.obs.reads, 1);
        FZ_CHECK(fz_untouched(&r, sizeof(r)));
    } else if (h->delivered_n) {
        FZ_EQ(rc, TWH_OK);
        FZ_EQ(h->f.obs.reads, 2);
        FZ_CHECK(same_res(&r, &h->delivered));
    } else {
        FZ_EQ(rc, TWH_ERR_BUS);
        FZ_EQ(h->f.obs.reads, 2);
        FZ_CHECK(fz_untouched(&r, sizeof(r)));    /* outputs only on success */
    }
    check_stash(h);
}

static void op_xfer(harness_t *h, uint8_t ch, uint8_t cmd, uint16_t payload, int with_data)
{
    uint16_t d;
    int rc, e;

    begin(h, 0);
    memset(&d, FZ_POISON, sizeof(d));
    rc = twh_xfer(&h->t, ch, cmd, payload, with_data ? &d : NULL);
    end_blocking(h, rc);
    if (rc == TWH_ERR_BAD_ARG || rc == TWH_ERR_FIFO_FULL)
        FZ_EQ(h->f.obs.pushes, 0);
    else
        FZ_EQ(h->f.obs.pushes, 1);
    check_single(h, rc, &e);
    if (h->own_seen)
        FZ_EQ(rc, e);
    if (rc == TWH_OK)
        FZ_CHECK(!with_data || d == h->own.data);
    else
        FZ_CHECK(fz_untouched(&d, sizeof(d)));    /* outputs only on success */
}

static void op_helper(harness_t *h, uint8_t which, uint8_t ch, uint16_t a, uint16_t b)
{
    union {
        struct { uint8_t bits; uint16_t words; } cfg;
        twh_fw_t fw;
        uint16_t v;
    } o;
    twh_fw_t fw;
    uint16_t *img = NULL;
    unsigned n = 0, i, k;
    int rc = 0, e = 0;

    begin(h, 0);
    memset(&o, FZ_POISON, sizeof(o));
    switch (which % 15u) {
    case 0:
        rc = twh_config(&h->t, ch, &o.cfg.bits, &o.cfg.words);
        end_blocking(h, rc);
        check_single(h, rc, &e);
        if (rc == TWH_OK) {
            FZ_EQ(o.cfg.bits, h->own.data >> 9);
            FZ_EQ(o.cfg.words, h->own.data & 0x1FFu);
        } else {
            FZ_CHECK(fz_untouched(&o, sizeof(o)));
        }
        break;
    case 1:
        rc = twh_firmware(&h->t, ch, &o.fw);
        end_blocking(h, rc);
        check_single(h, rc, &e);
        if (rc == TWH_OK) {
            FZ_EQ(o.fw.raw, h->own.data >> 8);
            FZ_EQ(o.fw.type, h->own.data & 0xFFu);
        } else {
            FZ_CHECK(fz_untouched(&o, sizeof(o)));
        }
        break;
    case 2: case 3: case 4:
        rc = (which % 15u) == 2 ? twh_ref_voltage(&h->t, ch, &o.v)
           : (which % 15u) == 3 ? twh_temperature(&h->t, ch, &o.v)
                                : twh_o2_voltage(&h->t, ch, &o.v);
        end_blocking(h, rc);
        check_single(h, rc, &e);
        if (rc == TWH_OK)
            FZ_EQ(o.v, h->own.data & 0x0FFFu);
        else
            FZ_CHECK(fz_untouched(&o, sizeof(o)));
        break;
    case 5:
        rc = twh_find_free(&h->t, ch, a, &o.v);
        end_blocking(h, rc);
        if (a > TWH_ADDR_MAX) {
            FZ_EQ(rc, TWH_ERR_BAD_ARG);
            FZ_EQ(h->f.obs.pushes, 0);
        }
        check_single(h, rc, &e);
        if (h->own_seen && e == 0 && (h->own.data < a || h->own.data > TWH_ADDR_MAX + 1u))
            FZ_EQ(rc, TWH_ERR_BAD_RESPONSE);
        if (rc == TWH_OK) {
            FZ_EQ(o.v, h->own.data);
            FZ_CHECK(o.v >= a && o.v <= TWH_ADDR_MAX + 1u);
        } else {
            FZ_CHECK(fz_untouched(&o, sizeof(o)));
        }
        break;
    case 6:
        rc = twh_read_word(&h->t, ch, a, &o.v);
        end_blocking(h, rc);
        if (a > TWH_ADDR_MAX) {
            FZ_EQ(rc, TWH_ERR_BAD_ARG);
            FZ_EQ(h->f.obs.pushes, 0);
        }
        check_single(h, rc, &e);
        if (rc == TWH_OK)
            FZ_EQ(o.v, h->own.data & TWH_WORD_MASK);
        else
            FZ_CHECK(fz_untouched(&o, sizeof(o)));
        break;
    case 7:
        rc = twh_erase_page(&h->t, ch, a);
        end_blocking(h, rc);
        if (a > TWH_ADDR_MAX || a < TWH_FACTORY_END) {
            FZ_EQ(rc, TWH_ERR_BAD_ARG);
            FZ_EQ(h->f.obs.pushes, 0);
        }
        check_single(h, rc, &e);
        break;
    case 8:
        rc = twh_write_word(&h->t, ch, a, b);
        end_blocking(h, rc);
        if (a > TWH_ADDR_MAX || b > TWH_WORD_MASK || a < TWH_FACTORY_END) {
            FZ_EQ(rc, TWH_ERR_BAD_ARG);
            FZ_EQ(h->f.obs.pushes, 0);
        }
        /* success needs the read-back of the same word */
        if (rc == TWH_OK) {
            FZ_CHECK(h->own_seen && (h->own.cmd & 0xFEu) == TWH_CMD_READ);
            FZ_EQ(h->own.data & TWH_WORD_MASK, b);
        }
        break;
    case 9:
        n = a % 600u;               /* past 512 must be refused */
        img = malloc((n ? n : 1u) * sizeof(*img));
        memset(img, FZ_POISON, (n ? n : 1u) * sizeof(*img));
        rc = twh_read_image(&h->t, ch, img, (uint16_t)n);
        end_blocking(h, rc);
        if (n > 512u) {
            FZ_EQ(rc, TWH_ERR_BAD_ARG);
            FZ_EQ(h->f.obs.pushes, 0);
        }
        if (rc == TWH_OK) {
            FZ_EQ(h->n_img, n);
            for (i = 0; i < n; i++)
                FZ_EQ(img[i], h->img[i]);
        } else if (n <= 512u) {
            /* words read before the failing one are kept (not "outputs only
             * on success": docs/fuzzing.md) */
            i = fz_written_prefix(img, n);
            FZ_CHECK(i != ~0u && i < n);
            FZ_CHECK(i <= h->n_img);
            for (k = 0; k < i; k++)
                FZ_EQ(img[k], h->img[k]);
        } else {
            FZ_CHECK(fz_untouched(img, sizeof(*img)));
        }
        free(img);
        break;
    case 10:
        rc = twh_negotiate(&h->t, ch, &o.fw);
        end_blocking(h, rc);
        /* Once the version was read, *fw holds it even when the last timing
         * write is refused (twh.h: the one documented exception to "outputs
         * only on success"). Before that, untouched. */
        if (h->fixed_timing) {
            /* nothing to set before or after the question (twh.c) */
            FZ_EQ(h->f.obs.timing_writes, 0);
            if (h->fw_read)
                FZ_EQ(rc, TWH_OK);
        }
        if (h->fw_read) {
            FZ_CHECK(rc == TWH_OK || rc == TWH_ERR_REFUSED);
            twh_fw_decode(h->fw_data, &fw);
            FZ_CHECK(fw.raw == o.fw.raw && fw.type == o.fw.type &&
                     fw.version == o.fw.version && fw.encoding == o.fw.encoding);
        } else {
            FZ_CHECK(rc != TWH_OK);
            FZ_CHECK(fz_untouched(&o, sizeof(o)));
        }
        break;
    case 12: {
        uint32_t r1 = fz_peek_u32(h->f.in, 0), r2 = fz_peek_u32(h->f.in, 1);

        rc = twh_set_execute_us(&h->t, ch, a);
        FZ_EQ(h->f.obs.pushes, 0);
        if (ch >= h->t.channels) {
            FZ_EQ(rc, TWH_ERR_BAD_ARG);
            FZ_EQ(h->f.obs.reads + h->f.obs.timing_writes, 0);
        } else {
            /* a fixed-timing build refuses every timing write: the driver
             * writes nothing and only compares the read-back */
            FZ_EQ(h->f.obs.reads, 2);
            FZ_EQ(h->f.obs.timing_writes, h->fixed_timing ? 0u : 1u);
            FZ_EQ(rc, r2 == ((r1 & 0xFFFFu) | (uint32_t)a << 16) ? TWH_OK : TWH_ERR_REFUSED);
        }
        break;
    }
    case 13: {
        uint32_t mask = (uint32_t)a | (uint32_t)b << 16;

        rc = twh_set_idle_charge(&h->t, mask);
        FZ_EQ(h->f.obs.pushes + h->f.obs.reads + h->f.obs.timing_writes + h->f.obs.ctrl_writes, 0);
        if (!h->t.channels || (h->t.channels < 32u && (mask >> h->t.channels) != 0)) {
            FZ_EQ(rc, TWH_ERR_BAD_ARG);
            FZ_EQ(h->f.obs.other_writes, 0);
        } else {
            FZ_EQ(rc, TWH_OK);
            FZ_EQ(h->f.obs.other_writes, 1);
            FZ_EQ(h->f.obs.last_write_off, offsetof(twh_regs_t, IDLE_CHARGE));
            FZ_EQ(h->f.obs.last_write_val, mask);
        }
        break;
    }
    case 14: {
        uint32_t busy = fz_peek_u32(h->f.in, 0);

        FZ_EQ(twh_busy(&h->t), busy);
        FZ_EQ(h->f.obs.reads, 1);
        FZ_EQ(h->f.obs.pushes + h->f.obs.other_writes + h->f.obs.timing_writes +
              h->f.obs.ctrl_writes, 0);
        break;
    }
    case 11:
        h->in_cal = 1;
        rc = twh_cal_append(&h->t, ch, a, b, &o.v);
        end_blocking(h, rc);
        if (a >= TWH_BLANK || b >= TWH_BLANK) {
            FZ_EQ(rc, TWH_ERR_BAD_ARG);
            FZ_EQ(h->f.obs.pushes, 0);
        }
        if (rc == TWH_OK) {
            FZ_CHECK(h->cal_end_known);
            FZ_CHECK(!(o.v & 1u) && o.v >= TWH_CAL_START && o.v + 1u < h->cal_end);
        } else {
            FZ_CHECK(fz_untouched(&o, sizeof(o)));
        }
        break;
    }
    if (ch >= h->t.channels)
        FZ_EQ(h->f.obs.pushes, 0);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    harness_t *h = &H;
    fz_in_t in;
    twh_platform_t plat;
    uint32_t id, ver, par, v;
    uint8_t flags, op, ch, cmd;
    uint16_t a, b;
    unsigned ops = 0, chans, depth;
    int rc, ok;

    fz_init(&in, data, size);
    memset(h, 0, sizeof(*h));
    flags = fz_u8(&in);
    fz_core_init(&h->f, &in, 1, 0, 0);
    h->f.on_push = on_push;
    h->f.on_pop = on_pop;
    h->f.hctx = h;
    fz_platform(&h->f, &plat, flags & 1u);

    id = fz_peek_u32(&in, 0);
    ver = fz_peek_u32(&in, 1);
    par = fz_peek_u32(&in, 2);
    chans = GETF(ver, VERSION, CHANNELS);
    depth = GETF(par, PARAMS, FIFO_DEPTH);
    ok = id == TWH_REGS__ID__MAGIC_reset &&
         GETF(ver, VERSION, MAJOR) == TWH_REGS__VERSION__MAJOR_reset &&
         chans >= 1 && chans <= TWH_MAX_CHANNELS && depth > 0;
    rc = twh_init(&h->t, &plat);
    FZ_EQ(rc, ok ? TWH_OK : TWH_ERR_BAD_ID);
    FZ_EQ(h->t.channels, ok ? chans : 0u);
    h->fixed_timing = ok && GETF(ver, VERSION, FIXED_TIMING);
    FZ_EQ(h->f.obs.pushes, 0);
    if (ok && (flags & 1u)) {
        FZ_EQ(h->f.obs.other_writes, 1);         /* IRQ_EN.RESULT */
    }
    /* small limits keep each input quick; the loop bounds are the same */
    h->t.timeout_us = 1u + fz_u8(&in) * 16u;
    h->t.poll_us = 1u + fz_u8(&in) % 64u;

    while (!fz_empty(&in) && ops++ < 200u) {
        op = fz_u8(&in);
        ch = fz_u8(&in) % (TWH_MAX_CHANNELS + 1u);   /* 32: never a channel */
        switch (op % 6u) {
        case 0:
            v = fz_peek_u32(&in, 0);
            begin(h, 0);
            rc = twh_poll(&h->t);
            FZ_EQ(h->f.obs.reads, 1);
            FZ_EQ(rc, h->n_shadow + GETF(v, LEVELS, RES_LEVEL));
            break;
        case 1:
            op_result(h);
            break;
        case 2:
            cmd = fz_u8(&in);
            a = fz_u16(&in);
            op_submit(h, ch, cmd, a);
            break;
        case 3:
            cmd = fz_u8(&in);
            a = fz_u16(&in);
            op_xfer(h, ch, cmd, a, op & 0x80u);
            break;
        case 4:
            v = fz_peek_u32(&in, 0);
            begin(h, 0);
            FZ_EQ(twh_cancel_all(&h->t), TWH_OK);
            FZ_EQ(h->f.obs.ctrl_writes, 1);
            FZ_EQ(h->f.obs.last_ctrl, v | TWH_REGS__CTRL__FLUSH_bm);
            break;
        default:
            cmd = fz_u8(&in);
            a = fz_u16(&in);
            b = fz_u16(&in);
            op_helper(h, cmd, ch, a, b);
            break;
        }
    }
    return 0;
}
