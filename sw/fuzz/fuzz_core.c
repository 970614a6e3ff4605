/* The fuzz platform (see fuzz_core.h). */
#include "fuzz_core.h"

#include <stddef.h>
#include <string.h>

#include "twh_regs.h"

#define OFF(r) ((uint32_t)offsetof(twh_regs_t, r))
#define CH_BASE ((uint32_t)offsetof(twh_regs_t, CH))
#define CH_STRIDE ((uint32_t)sizeof(twh_regs__channel_t__stride20_t))
#define CH_OFF(r) ((uint32_t)offsetof(twh_regs__channel_t__stride20_t, r))
#define F(v, r, f) (((uint32_t)(v) & (uint32_t)TWH_REGS__##r##__##f##_bm) >> TWH_REGS__##r##__##f##_bp)
#define P(x, r, f) (((uint32_t)(x) << TWH_REGS__##r##__##f##_bp) & (uint32_t)TWH_REGS__##r##__##f##_bm)
#define M(r, f) ((uint32_t)TWH_REGS__##r##__##f##_bm)

uint16_t fz_target_addr(uint8_t cmd, uint16_t payload)
{
    if (cmd >= 0x80u)
        return (uint16_t)(((payload >> 14) & 3u) << 7 | (cmd & 0x7Fu));
    if (cmd == 0x4Au || cmd == 0x4Bu)
        return (uint16_t)((cmd & 1u) << 8 | (payload & 0xFFu));
    return 0xFFFFu;
}

void fz_core_init(fz_core_t *f, fz_in_t *in, int raw, uint8_t channels, uint16_t depth)
{
    unsigned ch;

    memset(f, 0, sizeof(*f));
    f->in = in;
    f->raw = raw;
    f->channels = channels;
    f->depth = depth;
    f->ctrl = M(CTRL, ENABLE);
    f->irq_en = P(1, IRQ_EN, RES_THRESHOLD);
    for (ch = 0; ch < FZ_MAX_CH; ch++) {
        f->timing[ch][0] = P(8000, CHANNEL_T__TIMING0, CHARGE_US) | P(1000, CHANNEL_T__TIMING0, SYNC_US);
        f->timing[ch][1] = P(2000, CHANNEL_T__TIMING1, PREAMBLE_US) | P(4000, CHANNEL_T__TIMING1, EXECUTE_US);
        f->timing[ch][2] = P(3000, CHANNEL_T__TIMING2, LISTEN_US) | P(2000, CHANNEL_T__TIMING2, TURNAROUND_US);
    }
}

void fz_obs_reset(fz_core_t *f)
{
    memset(&f->obs, 0, sizeof(f->obs));
}

/* ------------------------------------------------------------- device */
/* The spec's command set (SRI-2WIRE-IRD 6, NOTES.md) on a NOR-like flash:
 * a write only programs a blank word, an erase blanks a 16-word page.
 * Returns 1 and *data when the device answers. */
static int device(fz_dev_t *d, uint8_t cmd, uint16_t payload, uint16_t *data)
{
    unsigned addr, a;

    if (!d->present)
        return 0;
    if (cmd >= 0x80u) {
        addr = fz_target_addr(cmd, payload);
        if (addr < d->size && d->flash[addr] == TWH_BLANK)
            d->flash[addr] = payload & TWH_WORD_MASK;
        return 0;
    }
    switch (cmd) {
    case 0x40:
        *data = (uint16_t)((unsigned)(d->config & 0x7Fu) << 9 | (d->size & 0x1FFu));
        return 1;
    case 0x41:
        *data = (uint16_t)(d->fw << 8 | d->type);
        return 1;
    case 0x42: case 0x43: case 0x44:
        *data = d->adc[cmd - 0x42u];
        return 1;
    case 0x46: case 0x47: case 0x48: case 0x49: case 0x4A: case 0x4B:
        addr = (cmd & 1u) << 8 | (payload & 0xFFu);
        if (addr >= d->size)
            return 0;
        if (cmd <= 0x47u) {
            for (a = addr; a < d->size && d->flash[a] != TWH_BLANK; a++)
                ;
            *data = (uint16_t)a;
            return 1;
        }
        if (cmd <= 0x49u) {
            *data = d->flash[addr];
            return 1;
        }
        for (a = addr & ~15u; a < (addr & ~15u) + 16u && a < d->size; a++)
            d->flash[a] = TWH_BLANK;
        return 0;
    default:
        return 0;
    }
}

/* ------------------------------------------------------------- model core */
static void push_result(fz_core_t *f, const fz_cmd_t *c, uint8_t status, uint16_t data)
{
    fz_res_t *r = &f->resq[f->res_n++];

    r->cmd = c->cmd;
    r->status = status;
    r->ch = c->ch;
    r->tag = c->tag;
    /* the core passes data only with OK and BAD_CHECKSUM */
    r->data = (status == TWH_ST_OK || status == TWH_ST_BAD_CHECKSUM) ? data : 0;
    r->seq = c->seq;
}

static fz_cmd_t take_head(fz_core_t *f)
{
    fz_cmd_t c = f->cmdq[0];

    memmove(&f->cmdq[0], &f->cmdq[1], (f->cmd_n - 1) * sizeof(c));
    f->cmd_n--;
    return c;
}

/* One completion. ev_status >= 0: that status instead of the device's
 * (the device still runs the command when `runs`); lie: data instead of
 * the device's answer. */
static int complete(fz_core_t *f, int ev_status, int runs, int lie, uint16_t lie_data)
{
    fz_cmd_t c;
    uint16_t data = 0;
    uint8_t status;
    int answered = 0;

    if (!(f->ctrl & M(CTRL, ENABLE)) || f->cmd_n == 0 || f->res_n >= f->depth)
        return 0;
    c = take_head(f);
    if (c.cancelled) {
        push_result(f, &c, TWH_ST_CANCELLED, 0);
        return 1;
    }
    if (fz_target_addr(c.cmd, c.payload) < TWH_FACTORY_END) {
        push_result(f, &c, TWH_ST_BLOCKED, 0);
        return 1;
    }
    if (ev_status < 0 || runs)
        answered = device(&f->dev[c.ch], c.cmd, c.payload, &data);
    status = answered ? TWH_ST_OK : TWH_ST_NO_RESPONSE;
    if (ev_status >= 0)
        status = (uint8_t)ev_status;
    if (lie)
        data = lie_data;
    push_result(f, &c, status, data);
    return 1;
}

int fz_complete_clean(fz_core_t *f)
{
    return complete(f, -1, 1, 0, 0);
}

/* A time step of the driver (delay_us or wait_irq): the input decides.
 * An all-zero (or exhausted) input completes one command cleanly, so short
 * inputs make progress instead of timing out. Returns the event byte. */
uint8_t fz_step(fz_core_t *f)
{
    uint8_t e = fz_u8(f->in), st;
    unsigned k = ((e & 3u) + 1u) & 3u, i;
    uint16_t lie_data;
    int done;

    f->obs.waits++;
    for (i = 0; i < k; i++) {
        if (e & 0x04u) {            /* a made-up status */
            st = fz_u8(f->in) & 15u;
            lie_data = (e & 0x08u) ? fz_u16(f->in) : 0;
            done = complete(f, st, (e & 0x10u) != 0, (e & 0x08u) != 0, lie_data);
            f->obs.injected += (unsigned)done;
        } else if (e & 0x08u) {     /* the device's status, made-up data */
            lie_data = fz_u16(f->in);
            done = complete(f, -1, 1, 1, lie_data);
            f->obs.injected += (unsigned)done;
        } else {
            complete(f, -1, 1, 0, 0);
        }
    }
    if (k == 0 && f->cmd_n)
        f->obs.injected++;          /* a stall: queued commands wait */
    return e;
}

/* ------------------------------------------------------------- registers */
uint32_t fz_present_mask(const fz_core_t *f)
{
    return f->channels >= 32u ? 0xFFFFFFFFu : (1u << f->channels) - 1u;
}

uint32_t fz_busy(const fz_core_t *f)
{
    uint32_t v = 0;
    unsigned i;

    for (i = 0; i < f->cmd_n; i++)
        v |= 1u << f->cmdq[i].ch;
    return v & fz_present_mask(f);
}

/* channel block of off: 1 and *ch, *reg (offset in the block) when off is
 * inside CH[0..FZ_MAX_CH-1] and word aligned */
static int ch_block(uint32_t off, unsigned *ch, unsigned *reg)
{
    if (off < CH_BASE || off >= CH_BASE + FZ_MAX_CH * CH_STRIDE || (off & 3u) != 0)
        return 0;
    *ch = (off - CH_BASE) / CH_STRIDE;
    *reg = off - CH_BASE - *ch * CH_STRIDE;
    return 1;
}

static uint32_t model_read(fz_core_t *f, uint32_t off)
{
    const fz_res_t *h = &f->resq[0];
    unsigned ch, reg;
    uint32_t v;

    if (off == OFF(ID)) return TWH_REGS__ID__MAGIC_reset;
    if (off == OFF(VERSION))
        return P(TWH_REGS__VERSION__MAJOR_reset, VERSION, MAJOR) | P(f->channels, VERSION, CHANNELS);
    if (off == OFF(PARAMS)) return P(f->depth, PARAMS, FIFO_DEPTH) | P(48000, PARAMS, CLK_KHZ);
    if (off == OFF(CTRL)) return f->ctrl;
    if (off == OFF(STATUS))
        return (f->cmd_n >= f->depth ? M(STATUS, CMD_FULL) : 0) |
               (f->cmd_n == 0 ? M(STATUS, CMD_EMPTY) : 0) |
               (f->res_n >= f->depth ? M(STATUS, RES_FULL) : 0) |
               (f->res_n == 0 ? M(STATUS, RES_EMPTY) : 0);
    if (off == OFF(LEVELS)) return P(f->cmd_n, LEVELS, CMD_LEVEL) | P(f->res_n, LEVELS, RES_LEVEL);
    if (off == OFF(ERRORS) || off == OFF(POLL_READY) || off == OFF(LAB_KEY) ||
        off == OFF(FACTORY_KEY))
        return 0;
    if (off == OFF(IDLE_CHARGE)) return f->idle_charge;
    if (off == OFF(BUSY)) return fz_busy(f);
    if (off == OFF(IRQ_EN)) return f->irq_en;
    if (off == OFF(IRQ_STATUS)) return f->res_n ? M(IRQ_STATUS, RESULT) : 0;
    if (off == OFF(RES_INFO)) {
        if (!f->res_n)
            return 0;
        f->info_valid = 1;
        return P(h->cmd, RES_INFO, CMD) | P(h->status, RES_INFO, STATUS) |
               P(h->ch, RES_INFO, CHANNEL) | M(RES_INFO, VALID) | P(h->tag, RES_INFO, TAG);
    }
    if (off == OFF(RES_POP)) {
        fz_res_t r;

        if (!f->res_n)
            return 0;
        if (!f->info_valid)
            f->order_errors++;
        f->info_valid = 0;
        r = *h;
        v = P(r.data, RES_POP, DATA) | P(r.status, RES_POP, STATUS) |
            P(r.ch, RES_POP, CHANNEL) | M(RES_POP, VALID) | P(r.tag, RES_POP, TAG);
        memmove(&f->resq[0], &f->resq[1], (f->res_n - 1) * sizeof(*h));
        f->res_n--;
        f->obs.pops++;
        f->obs.last_pop = r;
        if (f->on_pop)
            f->on_pop(f->hctx, &r);
        return v;
    }
    if (ch_block(off, &ch, &reg) && ch < f->channels) {
        if (reg == CH_OFF(TIMING0)) return f->timing[ch][0];
        if (reg == CH_OFF(TIMING1)) return f->timing[ch][1];
        if (reg == CH_OFF(TIMING2)) return f->timing[ch][2];
        if (reg == CH_OFF(POLL_CTRL) || reg == CH_OFF(POLL_RESULT) || reg == CH_OFF(STATE) ||
            reg == CH_OFF(CMD_PUSH))
            return 0;
    }
    f->bus_errors++;
    return 0;
}

static uint32_t fz_read32(void *ctx, uint32_t off)
{
    fz_core_t *f = ctx;
    uint32_t v;

    f->obs.reads++;
    if (!f->raw)
        return model_read(f, off);
    v = fz_u32(f->in);
    if (off == OFF(RES_INFO)) {
        f->last_info = v;
        f->info_valid = (v & M(RES_INFO, VALID)) != 0;
    } else if (off == OFF(RES_POP)) {
        if (!f->info_valid)
            f->order_errors++;
        f->info_valid = 0;
        f->last_pop_raw = v;
        {
            fz_res_t r;

            r.cmd = (uint8_t)F(f->last_info, RES_INFO, CMD);
            r.status = (uint8_t)F(v, RES_POP, STATUS);
            r.ch = (uint8_t)F(v, RES_POP, CHANNEL);
            r.tag = (uint8_t)F(v, RES_POP, TAG);
            r.data = (uint16_t)F(v, RES_POP, DATA);
            r.seq = 0;
            f->obs.pops++;
            f->obs.last_pop = r;
            /* the harness judges from last_info and last_pop_raw whether
             * this pop agrees with its RES_INFO */
            if (f->on_pop)
                f->on_pop(f->hctx, &r);
        }
    }
    return v;
}

/* a write of CH[ch].CMD_PUSH: the channel is the block's */
static void do_push(fz_core_t *f, unsigned ch, uint32_t v)
{
    fz_cmd_t c;

    c.cmd = (uint8_t)F(v, CHANNEL_T__CMD_PUSH, CMD);
    c.payload = (uint16_t)F(v, CHANNEL_T__CMD_PUSH, PAYLOAD);
    c.ch = (uint8_t)ch;
    c.tag = (uint8_t)F(v, CHANNEL_T__CMD_PUSH, TAG);
    c.cancelled = 0;
    c.seq = f->next_seq++;
    if (f->any_push && c.tag != ((f->last_tag + 1u) & 31u))
        f->tag_errors++;
    f->any_push = 1;
    f->last_tag = c.tag;
    if (fz_target_addr(c.cmd, c.payload) < TWH_FACTORY_END)
        f->factory_pushes++;
    if (!f->obs.pushes)
        f->obs.first_push = c;
    f->obs.pushes++;
    f->obs.last_push = c;
    if (!f->raw) {
        /* a push into an absent channel's block (ERRORS.BAD_CHANNEL) or
         * into a full FIFO (CMD_OVERFLOW) is a bus error */
        if (c.ch >= f->channels) {
            f->bad_channel++;
            f->bus_errors++;
            return;
        }
        if (f->cmd_n >= f->depth) {
            f->bus_errors++;
            return;
        }
        f->cmdq[f->cmd_n++] = c;
    }
    if (f->on_push)
        f->on_push(f->hctx, &c);
}

static void write_timing(fz_core_t *f, unsigned ch, unsigned reg, uint32_t v)
{
    uint32_t lo = v & 0xFFFFu, hi = v >> 16;
    int ok;

    if (reg == 0)
        ok = lo >= 7000u && hi >= 900u && hi <= 1100u;
    else if (reg == 1)
        ok = lo >= 1800u && lo <= 2200u && hi >= FZ_EXECUTE_MIN && hi <= FZ_EXECUTE_MAX;
    else
        ok = lo >= 2000u && hi >= 2000u;
    if (ok)
        f->timing[ch][reg] = v;
}

static void fz_write32(void *ctx, uint32_t off, uint32_t v)
{
    fz_core_t *f = ctx;
    unsigned ch, reg, i;

    f->obs.last_write_off = off;
    f->obs.last_write_val = v;
    if (ch_block(off, &ch, &reg) && reg == CH_OFF(CMD_PUSH)) {
        do_push(f, ch, v);
        return;
    }
    if (off == OFF(CTRL)) {
        f->obs.ctrl_writes++;
        f->obs.last_ctrl = v;
        if (f->raw)
            return;
        f->ctrl = v & M(CTRL, ENABLE);
        if (v & M(CTRL, FLUSH))
            for (i = 0; i < f->cmd_n; i++)
                f->cmdq[i].cancelled = 1;
        return;
    }
    if (ch_block(off, &ch, &reg)) {
        f->obs.timing_writes++;
        if (f->raw)
            return;
        if (ch < f->channels && reg <= CH_OFF(TIMING2)) {
            write_timing(f, ch, reg / 4u, v);
            return;
        }
        f->bus_errors++;
        return;
    }
    f->obs.other_writes++;
    if (f->raw)
        return;
    if (off == OFF(IRQ_EN)) {
        f->irq_en = v & (M(IRQ_EN, RESULT) | M(IRQ_EN, ERROR) | M(IRQ_EN, POLL) |
                         M(IRQ_EN, RES_THRESHOLD));
        return;
    }
    if (off == OFF(ERRORS))
        return;
    if (off == OFF(IDLE_CHARGE)) {
        /* bits of absent channels ignore writes */
        f->idle_charge = v & fz_present_mask(f);
        return;
    }
    /* read-only registers, keys: the driver has no business writing them */
    f->bus_errors++;
}

static void fz_delay_us(void *ctx, uint32_t us)
{
    fz_core_t *f = ctx;

    (void)us;
    if (f->raw) {
        f->obs.waits++;
        return;
    }
    (void)fz_step(f);
}

/* Returns what the input says was waited: 0 (which the driver must count
 * as 1), a little, or everything it was allowed. */
static uint32_t fz_wait_irq(void *ctx, uint32_t max_us)
{
    fz_core_t *f = ctx;
    uint8_t e;

    if (f->raw) {
        f->obs.waits++;
        e = fz_u8(f->in);
    } else {
        e = fz_step(f);
    }
    switch (e >> 6) {
    case 0: return max_us < 1000u ? max_us : 1000u;
    case 1: return 0;
    case 2: return max_us;
    default: return (uint32_t)(e & 0x3Fu);
    }
}

void fz_platform(fz_core_t *f, twh_platform_t *p, int with_irq)
{
    p->read32 = fz_read32;
    p->write32 = fz_write32;
    p->delay_us = fz_delay_us;
    p->wait_irq = with_irq ? fz_wait_irq : NULL;
    p->ctx = f;
}
