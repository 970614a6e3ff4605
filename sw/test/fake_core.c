/* Fake twowire-host core for the driver's unit tests (see fake_core.h). */
#include "fake_core.h"

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

#define LAB_KEY_VALUE 0x4C414221u
#define FACTORY_KEY_VALUE 0x46414354u

void fake_dev_setup(fake_dev_t *d, uint8_t fw_byte, uint8_t type_byte,
                    const uint16_t *image, uint16_t size)
{
    unsigned i;

    memset(d, 0, sizeof(*d));
    d->present = 1;
    d->fw_byte = fw_byte;
    d->type_byte = type_byte;
    d->size = size;
    for (i = 0; i < 512; i++)
        d->flash[i] = (image && i < size) ? image[i] : TWH_BLANK;
    d->adc_ref = 1353;      /* 3100 mV */
    d->adc_temp = 2000;
    d->adc_o2 = 239;
    d->max_execute_us = 10000;
}

void fake_init(fake_core_t *f, uint8_t channels, uint16_t depth)
{
    unsigned ch;

    memset(f, 0, sizeof(*f));
    f->id = TWH_REGS__ID__MAGIC_reset;
    f->major = TWH_REGS__VERSION__MAJOR_reset;
    f->minor = 0;
    f->channels = channels;
    f->depth = depth;
    f->clk_khz = 48000;
    f->ctrl = TWH_REGS__CTRL__ENABLE_reset;
    f->irq_en = P(TWH_REGS__IRQ_EN__RES_THRESHOLD_reset, IRQ_EN, RES_THRESHOLD);
    for (ch = 0; ch < FAKE_MAX_CH; ch++) {
        f->timing[ch][0] = P(8000, CHANNEL_T__TIMING0, CHARGE_US) | P(1000, CHANNEL_T__TIMING0, SYNC_US);
        f->timing[ch][1] = P(2000, CHANNEL_T__TIMING1, PREAMBLE_US) | P(4000, CHANNEL_T__TIMING1, EXECUTE_US);
        f->timing[ch][2] = P(3000, CHANNEL_T__TIMING2, LISTEN_US) | P(2000, CHANNEL_T__TIMING2, TURNAROUND_US);
    }
}

void fake_script(fake_core_t *f, int ch, int cmd, uint8_t status, uint16_t data)
{
    fake_script_t *s = &f->script[f->n_script++];

    s->ch = ch;
    s->cmd = cmd;
    s->status = status;
    s->data = data;
}

unsigned fake_line_count(const fake_core_t *f, uint8_t cmd_lo, uint8_t cmd_hi)
{
    unsigned i, n = 0;

    for (i = 0; i < f->n_line; i++)
        n += f->line[i].cmd >= cmd_lo && f->line[i].cmd <= cmd_hi;
    return n;
}

/* ---------------------------------------------------------------- device */
/* PeripheralLogic of tb/periph_model.py: returns 1 and *data when it answers */
static int device(fake_dev_t *d, uint8_t cmd, uint16_t payload, uint16_t *data)
{
    unsigned addr, a, page, w;

    if (cmd & 0x80u) {                                  /* write */
        addr = ((payload >> 14) & 3u) << 7 | (cmd & 0x7Fu);
        if (addr < d->size && d->flash[addr] == TWH_BLANK && !d->write_broken)
            d->flash[addr] = payload & TWH_WORD_MASK;
        return 0;
    }
    switch (cmd) {
    case 0x40:
        *data = (uint16_t)((((unsigned)d->config_bits << 1 | d->size >> 8) & 0xFFu) << 8 |
                           (d->size & 0xFFu));
        return 1;
    case 0x41:
        *data = (uint16_t)(d->fw_byte << 8 | d->type_byte);
        return 1;
    case 0x42: *data = d->adc_ref; return 1;
    case 0x43: *data = d->adc_temp; return 1;
    case 0x44: *data = d->adc_o2; return 1;
    case 0x46: case 0x47: case 0x48: case 0x49: case 0x4A: case 0x4B:
        addr = (cmd & 1u) << 8 | (payload & 0xFFu);
        if (addr >= d->size)
            return 0;
        if (cmd == 0x48 || cmd == 0x49) {
            *data = d->flash[addr] & TWH_WORD_MASK;
            return 1;
        }
        if (cmd == 0x46 || cmd == 0x47) {
            for (a = addr; a < d->size && d->flash[a] != TWH_BLANK; a++)
                ;
            *data = (uint16_t)a;            /* d->size when none is blank */
            return 1;
        }
        page = addr & ~15u;
        if (!d->erase_broken)
            for (w = page; w < page + 16u && w < d->size; w++)
                d->flash[w] = TWH_BLANK;
        return 0;
    default:
        return 0;                           /* reserved */
    }
}

static int is_factory(uint8_t cmd, uint16_t payload)
{
    unsigned addr;

    if ((cmd & 0xFEu) == 0x4Au)
        return ((cmd & 1u) << 8 | (payload & 0xFFu)) < 0x20u;
    if (cmd & 0x80u) {
        addr = ((payload >> 14) & 3u) << 7 | (cmd & 0x7Fu);
        return addr < 0x20u;
    }
    return 0;
}

static void push_result(fake_core_t *f, const fake_cmd_t *c, uint8_t status, uint16_t data)
{
    fake_res_t *r = &f->resq[f->res_n++];

    r->cmd = c->cmd;
    r->status = status;
    r->ch = c->ch;
    r->tag = c->tag;
    r->data = (status == TWH_ST_OK || status == TWH_ST_BAD_CHECKSUM) ? data : 0;
}

void fake_step(fake_core_t *f)
{
    fake_cmd_t c;
    fake_dev_t *d;
    fake_line_t *l;
    uint16_t data = 0;
    uint8_t status;
    unsigned i;

    if (f->stall || !(f->ctrl & M(CTRL, ENABLE)) || f->cmd_n == 0 || f->res_n >= f->depth)
        return;
    c = f->cmdq[0];
    memmove(&f->cmdq[0], &f->cmdq[1], (f->cmd_n - 1) * sizeof(c));
    f->cmd_n--;
    f->now_us += 21000;
    if (is_factory(c.cmd, c.payload) && !c.unlock) {
        f->errors |= M(ERRORS, BLOCKED);
        push_result(f, &c, TWH_ST_BLOCKED, 0);
        return;
    }
    for (i = 0; i < f->n_script; i++) {
        fake_script_t *s = &f->script[i];
        if ((s->ch < 0 || s->ch == c.ch) && (s->cmd < 0 || s->cmd == c.cmd)) {
            status = s->status;
            data = s->data;
            memmove(s, s + 1, (f->n_script - i - 1) * sizeof(*s));
            f->n_script--;
            push_result(f, &c, status, data);
            return;
        }
    }
    d = &f->dev[c.ch];
    l = &f->line[f->n_line < FAKE_LOG_MAX ? f->n_line++ : FAKE_LOG_MAX - 1];
    l->cmd = c.cmd;
    l->ch = c.ch;
    l->payload = c.payload;
    l->execute_us = (uint16_t)F(f->timing[c.ch][1], CHANNEL_T__TIMING1, EXECUTE_US);
    if (!d->present || l->execute_us > d->max_execute_us ||
        !device(d, c.cmd, c.payload, &data))
        status = TWH_ST_NO_RESPONSE;
    else
        status = TWH_ST_OK;
    push_result(f, &c, status, data);
}

void fake_run(fake_core_t *f)
{
    while (f->cmd_n && f->res_n < f->depth && !f->stall)
        fake_step(f);
}

/* ---------------------------------------------------------------- registers */
/* the channels that exist: the first min(channels, FAKE_MAX_CH) */
static unsigned n_present(const fake_core_t *f)
{
    return f->channels < FAKE_MAX_CH ? f->channels : FAKE_MAX_CH;
}

/* bit n for each channel n that exists */
static uint32_t present_mask(const fake_core_t *f)
{
    unsigned n = n_present(f);

    return n >= 32u ? 0xFFFFFFFFu : (1u << n) - 1u;
}

static uint32_t busy_reg(const fake_core_t *f)
{
    uint32_t v = 0;
    unsigned i;

    for (i = 0; i < f->cmd_n; i++)
        v |= 1u << f->cmdq[i].ch;
    return v & present_mask(f);
}

/* channel block of off: 1 and *ch, *reg (offset in the block) when off is
 * inside CH[0..FAKE_MAX_CH-1] and word aligned */
static int ch_block(uint32_t off, unsigned *ch, unsigned *reg)
{
    if (off < CH_BASE || off >= CH_BASE + FAKE_MAX_CH * CH_STRIDE || (off & 3u) != 0)
        return 0;
    *ch = (off - CH_BASE) / CH_STRIDE;
    *reg = off - CH_BASE - *ch * CH_STRIDE;
    return 1;
}

static void bus_error(fake_core_t *f, uint32_t off)
{
    f->bus_errors++;
    f->last_bus_error = off;
}

static uint32_t status_reg(const fake_core_t *f)
{
    return (f->cmd_n >= f->depth ? M(STATUS, CMD_FULL) : 0) |
           (f->cmd_n == 0 ? M(STATUS, CMD_EMPTY) : 0) |
           (f->res_n >= f->depth ? M(STATUS, RES_FULL) : 0) |
           (f->res_n == 0 ? M(STATUS, RES_EMPTY) : 0);
}

uint32_t fake_read32(void *ctx, uint32_t off)
{
    fake_core_t *f = ctx;
    const fake_res_t *h = &f->resq[0];
    uint32_t v;
    unsigned ch, reg;

    f->reads++;
    if (off == OFF(ID)) return f->id;
    if (off == OFF(VERSION))
        return P(f->minor, VERSION, MINOR) | P(f->major, VERSION, MAJOR) |
               P(f->channels, VERSION, CHANNELS) | (f->lab ? M(VERSION, LAB_UNLOCKED) : 0) |
               (f->factory_armed ? M(VERSION, FACTORY_UNLOCKED) : 0) |
               (f->fixed_timing ? M(VERSION, FIXED_TIMING) : 0);
    if (off == OFF(PARAMS)) return P(f->depth, PARAMS, FIFO_DEPTH) | P(f->clk_khz, PARAMS, CLK_KHZ);
    if (off == OFF(CTRL)) return f->ctrl;
    if (off == OFF(STATUS)) return status_reg(f);
    if (off == OFF(LEVELS)) return P(f->cmd_n, LEVELS, CMD_LEVEL) | P(f->res_n, LEVELS, RES_LEVEL);
    if (off == OFF(ERRORS)) return f->errors;
    if (off == OFF(IRQ_EN)) return f->irq_en;
    if (off == OFF(IRQ_STATUS)) return f->res_n ? M(IRQ_STATUS, RESULT) : 0;
    if (off == OFF(POLL_READY)) return f->poll_ready & present_mask(f);
    if (off == OFF(IDLE_CHARGE)) return f->idle_charge & present_mask(f);
    if (off == OFF(BUSY)) return busy_reg(f);
    if (off == OFF(LAB_KEY) || off == OFF(FACTORY_KEY))
        return 0;
    if (off == OFF(RES_INFO)) {
        if (!f->res_n)
            return 0;
        f->info_seen = 1;
        return P(h->cmd, RES_INFO, CMD) | P(h->status, RES_INFO, STATUS) |
               P(h->ch, RES_INFO, CHANNEL) | M(RES_INFO, VALID) | P(h->tag, RES_INFO, TAG);
    }
    if (off == OFF(RES_POP)) {
        if (!f->res_n)
            return 0;
        if (!f->info_seen)
            f->order_errors++;
        f->info_seen = 0;
        v = P(h->data, RES_POP, DATA) | P(h->status, RES_POP, STATUS) |
            P(h->ch, RES_POP, CHANNEL) | M(RES_POP, VALID) |
            P(f->corrupt_next_pop ? h->tag ^ 1u : h->tag, RES_POP, TAG);
        f->corrupt_next_pop = 0;
        memmove(&f->resq[0], &f->resq[1], (f->res_n - 1) * sizeof(*h));
        f->res_n--;
        return v;
    }
    if (ch_block(off, &ch, &reg) && ch < n_present(f)) {
        if (reg == CH_OFF(TIMING0)) return f->timing[ch][0];
        if (reg == CH_OFF(TIMING1)) return f->timing[ch][1];
        if (reg == CH_OFF(TIMING2)) return f->timing[ch][2];
        if (reg == CH_OFF(POLL_CTRL) || reg == CH_OFF(POLL_RESULT) || reg == CH_OFF(STATE) ||
            reg == CH_OFF(CMD_PUSH))
            return 0;
    }
    bus_error(f, off);
    return 0;
}

static int in(uint32_t v, uint32_t lo, uint32_t hi)
{
    return v >= lo && v <= hi;
}

static void write_timing(fake_core_t *f, unsigned ch, unsigned reg, uint32_t v)
{
    uint32_t lo = v & 0xFFFFu, hi = v >> 16;
    int ok;

    if (reg == 0)
        ok = lo >= 7000u && in(hi, 900, 1100);
    else if (reg == 1)
        ok = in(lo, 1800, 2200) && in(hi, 3500, 10000);
    else
        ok = lo >= 2000u && hi >= 2000u;
    if ((ok || f->lab) && !f->refuse_timing && !f->fixed_timing)
        f->timing[ch][reg] = v;
    else
        f->errors |= M(ERRORS, VALUE_REFUSED);
}

void fake_write32(void *ctx, uint32_t off, uint32_t v)
{
    fake_core_t *f = ctx;
    fake_cmd_t *c;
    unsigned ch, reg;

    f->writes++;
    if (ch_block(off, &ch, &reg) && reg == CH_OFF(CMD_PUSH)) {
        /* CH[ch].CMD_PUSH: the channel is the block's */
        if (ch >= n_present(f)) {
            f->errors |= M(ERRORS, BAD_CHANNEL);
            bus_error(f, off);
            return;
        }
        if (f->cmd_n >= f->depth) {
            f->errors |= M(ERRORS, CMD_OVERFLOW);
            bus_error(f, off);
            return;
        }
        c = &f->cmdq[f->cmd_n++];
        c->cmd = (uint8_t)F(v, CHANNEL_T__CMD_PUSH, CMD);
        c->payload = (uint16_t)F(v, CHANNEL_T__CMD_PUSH, PAYLOAD);
        c->ch = (uint8_t)ch;
        c->tag = (uint8_t)F(v, CHANNEL_T__CMD_PUSH, TAG);
        c->unlock = (uint8_t)f->factory_armed;
        f->factory_armed = 0;
        if (f->n_pushed < FAKE_LOG_MAX)
            f->pushed[f->n_pushed++] = *c;
        return;
    }
    if (off == OFF(CTRL)) {
        f->ctrl = v & M(CTRL, ENABLE);
        if (v & M(CTRL, FLUSH)) {
            while (f->cmd_n) {
                push_result(f, &f->cmdq[0], TWH_ST_CANCELLED, 0);
                memmove(&f->cmdq[0], &f->cmdq[1], (f->cmd_n - 1) * sizeof(f->cmdq[0]));
                f->cmd_n--;
            }
        }
        return;
    }
    if (off == OFF(ERRORS)) { f->errors &= ~v; return; }
    if (off == OFF(POLL_READY)) { f->poll_ready &= ~v; return; }
    if (off == OFF(IDLE_CHARGE)) { f->idle_charge = v & present_mask(f); return; }
    if (off == OFF(IRQ_EN)) {
        f->irq_en = v & (M(IRQ_EN, RESULT) | M(IRQ_EN, ERROR) | M(IRQ_EN, POLL) |
                         M(IRQ_EN, RES_THRESHOLD));
        return;
    }
    if (off == OFF(LAB_KEY)) { f->lab = !f->fixed_timing && v == LAB_KEY_VALUE; return; }
    if (off == OFF(FACTORY_KEY)) { f->factory_armed = v == FACTORY_KEY_VALUE; return; }
    if (off == OFF(ID) || off == OFF(VERSION) || off == OFF(PARAMS) || off == OFF(STATUS) ||
        off == OFF(LEVELS) || off == OFF(IRQ_STATUS) || off == OFF(BUSY) ||
        off == OFF(RES_INFO) || off == OFF(RES_POP))
        return;                              /* read-only: no effect */
    if (ch_block(off, &ch, &reg) && ch < n_present(f)) {
        if (reg == CH_OFF(TIMING0)) { write_timing(f, ch, 0, v); return; }
        if (reg == CH_OFF(TIMING1)) { write_timing(f, ch, 1, v); return; }
        if (reg == CH_OFF(TIMING2)) { write_timing(f, ch, 2, v); return; }
        if (reg == CH_OFF(POLL_CTRL) || reg == CH_OFF(POLL_RESULT) || reg == CH_OFF(STATE))
            return;
    }
    bus_error(f, off);
}

void fake_delay_us(void *ctx, uint32_t us)
{
    fake_core_t *f = ctx;

    f->delays++;
    f->now_us += us;
    fake_step(f);
}

uint32_t fake_wait_irq(void *ctx, uint32_t max_us)
{
    fake_core_t *f = ctx;

    f->irq_waits++;
    fake_step(f);
    if (f->res_n && (f->irq_en & M(IRQ_EN, RESULT)))
        return max_us < 21000u ? max_us : 21000u;
    f->now_us += max_us;
    return max_us;
}

void fake_platform(fake_core_t *f, twh_platform_t *p, int with_irq)
{
    p->read32 = fake_read32;
    p->write32 = fake_write32;
    p->delay_us = fake_delay_us;
    p->wait_irq = with_irq ? fake_wait_irq : NULL;
    p->ctx = f;
}
