/* twowire-host driver: register access, command/result flow, blocking
 * helpers, timing negotiation, calibration append. See docs/driver.md. */
#include <stddef.h>
#include <stdint.h>

#include "twh.h"
#include "twh_regs.h"

/* ---- register offsets and fields, all from the generated header ---- */
#define REG(r) ((uint32_t)offsetof(twh_regs_t, r))
#define CHREG(ch, r)                                                        \
    ((uint32_t)(offsetof(twh_regs_t, CH) +                                  \
                (uint32_t)(ch) * sizeof(twh_regs__channel_t__stride20_t) +  \
                offsetof(twh_regs__channel_t__stride20_t, r)))
#define GET(v, r, f) \
    (((uint32_t)(v) & (uint32_t)TWH_REGS__##r##__##f##_bm) >> TWH_REGS__##r##__##f##_bp)
#define PUT(x, r, f) \
    (((uint32_t)(x) << TWH_REGS__##r##__##f##_bp) & (uint32_t)TWH_REGS__##r##__##f##_bm)
#define BIT(r, f) ((uint32_t)TWH_REGS__##r##__##f##_bm)

#define TAG_MASK ((1u << TWH_REGS__CHANNEL_T__CMD_PUSH__TAG_bw) - 1u)

/* register map version 2: CH[TWH_MAX_CHANNELS], each with its CMD_PUSH; the
 * channel fields of VERSION, RES_INFO and RES_POP hold every channel */
typedef char twh_check_channels[
    sizeof(((twh_regs_t *)0)->CH) / sizeof(twh_regs__channel_t__stride20_t) == TWH_MAX_CHANNELS &&
    TWH_REGS__VERSION__CHANNELS_bm >> TWH_REGS__VERSION__CHANNELS_bp >= TWH_MAX_CHANNELS &&
    TWH_REGS__RES_INFO__CHANNEL_bm >> TWH_REGS__RES_INFO__CHANNEL_bp == TWH_MAX_CHANNELS - 1u &&
    TWH_REGS__RES_POP__CHANNEL_bm >> TWH_REGS__RES_POP__CHANNEL_bp == TWH_MAX_CHANNELS - 1u
    ? 1 : -1];

static uint32_t rd(const twh_t *t, uint32_t off)
{
    return t->plat.read32(t->plat.ctx, off);
}

static void wr(const twh_t *t, uint32_t off, uint32_t v)
{
    t->plat.write32(t->plat.ctx, off, v);
}

/* ------------------------------------------------------------ encoding */
int twh_encode_addr(uint8_t base_cmd, uint16_t addr, uint8_t *cmd, uint16_t *payload)
{
    if (addr > TWH_ADDR_MAX)
        return TWH_ERR_BAD_ARG;
    *cmd = (uint8_t)(base_cmd | (addr >> 8));
    *payload = (uint16_t)(addr & 0xFFu);
    return TWH_OK;
}

int twh_encode_write(uint16_t addr, uint16_t word, uint8_t *cmd, uint16_t *payload)
{
    if (addr > TWH_ADDR_MAX || word > TWH_WORD_MASK)
        return TWH_ERR_BAD_ARG;
    *cmd = (uint8_t)(TWH_CMD_WRITE | (addr & 0x7Fu));
    *payload = (uint16_t)(((addr >> 7) << 14) | word);
    return TWH_OK;
}

int twh_expects_response(uint8_t cmd)
{
    return cmd >= TWH_CMD_CONFIG && cmd <= (TWH_CMD_READ | 1u) && cmd != 0x45u;
}

/* Word address an erase or write command touches (0xFFFF: neither). The
 * same rule as the core's factory-area protection. */
static uint16_t target_addr(uint8_t cmd, uint16_t payload)
{
    if (cmd & 0x80u)
        return (uint16_t)(((payload >> 14) << 7) | (cmd & 0x7Fu));
    if ((cmd & 0xFEu) == TWH_CMD_ERASE)
        return (uint16_t)(((cmd & 1u) << 8) | (payload & 0xFFu));
    return 0xFFFFu;
}

int twh_status_err(uint8_t status, uint8_t cmd)
{
    if (status == TWH_ST_NO_RESPONSE && !twh_expects_response(cmd))
        return TWH_OK;
    if (status > TWH_ST_CANCELLED)
        return TWH_ERR_HW_STATUS;
    return -(int)status;
}

/* ------------------------------------------------------------ core access */
uint32_t twh_sizeof(void)
{
    return (uint32_t)sizeof(twh_t);
}

int twh_init(twh_t *t, const twh_platform_t *plat)
{
    uint32_t v;
    uint8_t ch;

    if (!t || !plat || !plat->read32 || !plat->write32 || !plat->delay_us)
        return TWH_ERR_BAD_ARG;
    t->plat = *plat;
    t->timeout_us = TWH_TIMEOUT_US_DEFAULT;
    t->poll_us = TWH_POLL_US_DEFAULT;
    t->next_tag = 0;
    t->stash_head = 0;
    t->stash_count = 0;
    t->channels = 0;            /* refuses every submit until the probe passes */
    if (rd(t, REG(ID)) != TWH_REGS__ID__MAGIC_reset)
        return TWH_ERR_BAD_ID;
    v = rd(t, REG(VERSION));
    t->version_major = (uint8_t)GET(v, VERSION, MAJOR);
    t->version_minor = (uint8_t)GET(v, VERSION, MINOR);
    t->fixed_timing = (uint8_t)GET(v, VERSION, FIXED_TIMING);
    ch = (uint8_t)GET(v, VERSION, CHANNELS);
    v = rd(t, REG(PARAMS));
    t->fifo_depth = (uint16_t)GET(v, PARAMS, FIFO_DEPTH);
    t->clk_khz = GET(v, PARAMS, CLK_KHZ);
    if (t->version_major != TWH_REGS__VERSION__MAJOR_reset || ch == 0 ||
        ch > TWH_MAX_CHANNELS || t->fifo_depth == 0)
        return TWH_ERR_BAD_ID;
    if (plat->wait_irq)
        wr(t, REG(IRQ_EN), rd(t, REG(IRQ_EN)) | BIT(IRQ_EN, RESULT));
    t->channels = ch;
    return TWH_OK;
}

int twh_submit(twh_t *t, uint8_t ch, uint8_t cmd, uint16_t payload)
{
    uint8_t tag;

    if (ch >= t->channels || target_addr(cmd, payload) < TWH_FACTORY_END)
        return TWH_ERR_BAD_ARG;
    /* a push into a full FIFO answers with a bus error: never rely on it */
    if (rd(t, REG(STATUS)) & BIT(STATUS, CMD_FULL))
        return TWH_ERR_FIFO_FULL;
    tag = t->next_tag;
    t->next_tag = (uint8_t)((tag + 1u) & TAG_MASK);
    /* the channel is the block's: CH[ch].CMD_PUSH */
    wr(t, CHREG(ch, CMD_PUSH),
       PUT(cmd, CHANNEL_T__CMD_PUSH, CMD) | PUT(payload, CHANNEL_T__CMD_PUSH, PAYLOAD) |
           PUT(tag, CHANNEL_T__CMD_PUSH, TAG));
    return tag;
}

int twh_poll(twh_t *t)
{
    return (int)(t->stash_count + GET(rd(t, REG(LEVELS)), LEVELS, RES_LEVEL));
}

/* Pop the head whose RES_INFO was read as `info` (VALID set). RES_POP must
 * describe the same result: status, channel and tag, VALID. */
static int pop(twh_t *t, uint32_t info, twh_result_t *r)
{
    uint32_t p = rd(t, REG(RES_POP));

    /* checked before *r is touched: outputs are written only on success */
    if ((p & ~BIT(RES_POP, DATA)) !=
        (PUT(GET(info, RES_INFO, STATUS), RES_POP, STATUS) |
         PUT(GET(info, RES_INFO, CHANNEL), RES_POP, CHANNEL) | BIT(RES_POP, VALID) |
         PUT(GET(info, RES_INFO, TAG), RES_POP, TAG)))
        return TWH_ERR_BUS;
    r->cmd = (uint8_t)GET(info, RES_INFO, CMD);
    r->status = (uint8_t)GET(info, RES_INFO, STATUS);
    r->channel = (uint8_t)GET(info, RES_INFO, CHANNEL);
    r->tag = (uint8_t)GET(info, RES_INFO, TAG);
    r->data = (uint16_t)GET(p, RES_POP, DATA);
    return TWH_OK;
}

/* field by field: a struct assignment may become a memcpy call, and the
 * driver links without libc */
static void copy_res(twh_result_t *d, const twh_result_t *s)
{
    d->data = s->data;
    d->cmd = s->cmd;
    d->status = s->status;
    d->channel = s->channel;
    d->tag = s->tag;
}

int twh_result(twh_t *t, twh_result_t *r)
{
    uint32_t info;

    if (t->stash_count) {                    /* ring: oldest at stash_head */
        copy_res(r, &t->stash[t->stash_head]);
        if (++t->stash_head >= TWH_STASH_SIZE)
            t->stash_head = 0;
        t->stash_count--;
        return TWH_OK;
    }
    info = rd(t, REG(RES_INFO));
    if (!(info & BIT(RES_INFO, VALID)))
        return TWH_ERR_AGAIN;
    return pop(t, info, r);
}

int twh_cancel_all(twh_t *t)
{
    wr(t, REG(CTRL), rd(t, REG(CTRL)) | BIT(CTRL, FLUSH));
    return TWH_OK;
}

int twh_set_idle_charge(twh_t *t, uint32_t mask)
{
    /* a bit of an absent channel, or no core (twh_init failed): refused */
    if (!t->channels || (t->channels < TWH_MAX_CHANNELS && mask >> t->channels))
        return TWH_ERR_BAD_ARG;
    wr(t, REG(IDLE_CHARGE), PUT(mask, IDLE_CHARGE, IDLE_CHARGE));
    return TWH_OK;
}

uint32_t twh_busy(twh_t *t)
{
    return GET(rd(t, REG(BUSY)), BUSY, BUSY);
}

/* Wait for the result of (ch, tag, cmd). Results of other commands are
 * moved to the stash; when the stash is full they stay in the core and
 * TWH_ERR_STASH_FULL is returned (nothing is lost). */
static int wait_own(twh_t *t, uint8_t ch, uint8_t cmd, uint8_t tag, uint16_t *data)
{
    uint32_t waited = 0, info, w;
    twh_result_t r;
    int mine, rc;

    for (;;) {
        info = rd(t, REG(RES_INFO));
        if (info & BIT(RES_INFO, VALID)) {
            mine = GET(info, RES_INFO, CHANNEL) == ch && GET(info, RES_INFO, TAG) == tag &&
                   GET(info, RES_INFO, CMD) == cmd;
            if (!mine && t->stash_count >= TWH_STASH_SIZE)
                return TWH_ERR_STASH_FULL;
            rc = pop(t, info, &r);
            if (rc)
                return rc;
            if (mine) {
                rc = twh_status_err(r.status, cmd);
                if (!rc)
                    *data = r.data;     /* outputs only on success */
                return rc;
            }
            w = (uint32_t)t->stash_head + t->stash_count++;
            copy_res(&t->stash[w < TWH_STASH_SIZE ? w : w - TWH_STASH_SIZE], &r);
            continue;
        }
        if (waited >= t->timeout_us)
            return TWH_ERR_TIMEOUT;
        if (t->plat.wait_irq) {
            w = t->plat.wait_irq(t->plat.ctx, t->timeout_us - waited);
        } else {
            w = t->poll_us;
            t->plat.delay_us(t->plat.ctx, w);
        }
        waited += w ? w : 1u;
    }
}

int twh_xfer(twh_t *t, uint8_t ch, uint8_t cmd, uint16_t payload, uint16_t *data)
{
    uint16_t d;
    int tag = twh_submit(t, ch, cmd, payload);

    if (tag < 0)
        return tag;
    return wait_own(t, ch, cmd, (uint8_t)tag, data ? data : &d);
}

/* ------------------------------------------------------------ helpers */
static int simple(twh_t *t, uint8_t ch, uint8_t cmd, uint16_t *data)
{
    return twh_xfer(t, ch, cmd, TWH_UNUSED_PAYLOAD, data);
}

int twh_config(twh_t *t, uint8_t ch, uint8_t *config_bits, uint16_t *flash_words)
{
    uint16_t d;
    int rc = simple(t, ch, TWH_CMD_CONFIG, &d);

    if (rc)
        return rc;
    if (config_bits)
        *config_bits = (uint8_t)(d >> 9);
    if (flash_words)
        *flash_words = d & TWH_ADDR_MAX;
    return TWH_OK;
}

void twh_fw_decode(uint16_t data, twh_fw_t *fw)
{
    uint8_t b = (uint8_t)(data >> 8), hi = (uint8_t)(b >> 4), lo = (uint8_t)(b & 15u);

    fw->raw = b;
    fw->type = (uint8_t)data;
    fw->version = -1;
    fw->encoding = TWH_FW_UNKNOWN;
    if (b <= 0x19u) {
        fw->version = (int8_t)b;
        fw->encoding = TWH_FW_BINARY;
    } else if (b >= 0x26u && hi <= 9u && lo <= 9u) {
        fw->version = (int8_t)(hi * 10u + lo);
        fw->encoding = TWH_FW_BCD;
    }
}

int twh_firmware(twh_t *t, uint8_t ch, twh_fw_t *fw)
{
    uint16_t d;
    int rc = simple(t, ch, TWH_CMD_FIRMWARE, &d);

    if (!rc)
        twh_fw_decode(d, fw);
    return rc;
}

/* 12-bit ADC answers: bits 15:12 are not part of the reading */
static int adc(twh_t *t, uint8_t ch, uint8_t cmd, uint16_t *v)
{
    uint16_t d;
    int rc = simple(t, ch, cmd, &d);

    if (!rc)
        *v = d & 0x0FFFu;
    return rc;
}

int twh_ref_voltage(twh_t *t, uint8_t ch, uint16_t *v)
{
    return adc(t, ch, TWH_CMD_REF_VOLTAGE, v);
}

int twh_temperature(twh_t *t, uint8_t ch, uint16_t *v)
{
    return adc(t, ch, TWH_CMD_TEMPERATURE, v);
}

int twh_o2_voltage(twh_t *t, uint8_t ch, uint16_t *v)
{
    return adc(t, ch, TWH_CMD_O2_VOLTAGE, v);
}

static int addressed(twh_t *t, uint8_t ch, uint8_t base, uint16_t addr, uint16_t *d)
{
    uint8_t cmd;
    uint16_t payload;
    int rc = twh_encode_addr(base, addr, &cmd, &payload);

    if (rc)
        return rc;
    return twh_xfer(t, ch, cmd, payload, d);
}

int twh_find_free(twh_t *t, uint8_t ch, uint16_t from, uint16_t *addr)
{
    uint16_t d;
    int rc = addressed(t, ch, TWH_CMD_FIND_FREE, from, &d);

    if (rc)
        return rc;
    if (d < from || d > TWH_ADDR_MAX + 1u)
        return TWH_ERR_BAD_RESPONSE;
    *addr = d;
    return TWH_OK;
}

int twh_read_word(twh_t *t, uint8_t ch, uint16_t addr, uint16_t *word)
{
    uint16_t d;
    int rc = addressed(t, ch, TWH_CMD_READ, addr, &d);

    if (!rc)
        *word = d & TWH_WORD_MASK;
    return rc;
}

int twh_erase_page(twh_t *t, uint8_t ch, uint16_t addr)
{
    return addressed(t, ch, TWH_CMD_ERASE, addr, NULL);
}

int twh_write_word(twh_t *t, uint8_t ch, uint16_t addr, uint16_t word)
{
    uint8_t cmd;
    uint16_t payload, back;
    int rc = twh_encode_write(addr, word, &cmd, &payload);

    if (!rc)
        rc = twh_xfer(t, ch, cmd, payload, NULL);
    if (!rc)
        rc = twh_read_word(t, ch, addr, &back);
    if (!rc && back != word)
        rc = TWH_ERR_VERIFY;
    return rc;
}

int twh_read_image(twh_t *t, uint8_t ch, uint16_t *words, uint16_t n)
{
    uint16_t a;
    int rc;

    if (n > TWH_ADDR_MAX + 1u)
        return TWH_ERR_BAD_ARG;
    for (a = 0; a < n; a++) {
        rc = twh_read_word(t, ch, a, &words[a]);
        if (rc)
            return rc;
    }
    return TWH_OK;
}

/* ------------------------------------------------------------ timing */
int twh_set_execute_us(twh_t *t, uint8_t ch, uint16_t us)
{
    uint32_t off = CHREG(ch, TIMING1), v;

    if (ch >= t->channels)
        return TWH_ERR_BAD_ARG;
    v = (rd(t, off) & ~BIT(CHANNEL_T__TIMING1, EXECUTE_US)) |
        PUT(us, CHANNEL_T__TIMING1, EXECUTE_US);
    /* a fixed-timing build refuses every timing write: ask nothing of it
     * (no VALUE_REFUSED left behind), only say whether it already runs us */
    if (t->fixed_timing)
        return rd(t, off) == v ? TWH_OK : TWH_ERR_REFUSED;
    wr(t, off, v);
    return rd(t, off) == v ? TWH_OK : TWH_ERR_REFUSED;
}

uint16_t twh_execute_us_for(const twh_fw_t *fw)
{
    return fw->version >= 18 ? TWH_EXECUTE_RECOMMENDED_US : TWH_EXECUTE_SAFE_US;
}

int twh_negotiate(twh_t *t, uint8_t ch, twh_fw_t *fw)
{
    twh_fw_t f;
    int rc;

    if (!fw)
        fw = &f;
    /* a fixed-timing build runs the default execute phase, which is
     * TWH_EXECUTE_SAFE_US: right for every firmware, so there is nothing
     * to set before or after the question */
    if (t->fixed_timing)
        return twh_firmware(t, ch, fw);
    rc = twh_set_execute_us(t, ch, TWH_EXECUTE_SAFE_US);
    if (!rc)
        rc = twh_firmware(t, ch, fw);
    if (rc)
        return rc;
    return twh_set_execute_us(t, ch, twh_execute_us_for(fw));
}

/* ------------------------------------------------------------ calibration */
/* Page holding the oldest record (smallest stamp, ties -> lower address);
 * only records with both words programmed count. None: the first page. */
static int oldest_page(twh_t *t, uint8_t ch, uint16_t end, uint16_t *page)
{
    uint16_t a, s, v, best = TWH_BLANK;
    int rc;

    *page = TWH_CAL_START;
    for (a = TWH_CAL_START; a + 1u < end; a += 2u) {
        rc = twh_read_word(t, ch, a, &s);
        if (rc)
            return rc;
        if (s >= best)
            continue;
        rc = twh_read_word(t, ch, (uint16_t)(a + 1u), &v);
        if (rc)
            return rc;
        if (v != TWH_BLANK) {
            best = s;
            *page = (uint16_t)(a & ~(TWH_PAGE_WORDS - 1u));
        }
    }
    return TWH_OK;
}

int twh_cal_append(twh_t *t, uint8_t ch, uint16_t stamp, uint16_t value, uint16_t *addr)
{
    uint16_t size, end, from, a, w;
    int rc, erased = 0;

    if (stamp >= TWH_BLANK || value >= TWH_BLANK)
        return TWH_ERR_BAD_ARG;
    rc = twh_config(t, ch, NULL, &size);
    if (rc)
        return rc;
    end = size < TWH_CAL_END ? size : TWH_CAL_END;
    for (;;) {
        for (from = TWH_CAL_START; from + 1u < end; from = (uint16_t)((a | 1u) + 1u)) {
            rc = twh_find_free(t, ch, from, &a);
            if (rc)
                return rc;
            if (a + 1u >= end)
                break;                       /* no blank pair left */
            if (a & 1u)
                continue;                    /* a-1 programmed: pair taken */
            rc = twh_read_word(t, ch, (uint16_t)(a + 1u), &w);
            if (rc)
                return rc;
            if (w != TWH_BLANK)
                continue;                    /* neighbour programmed */
            rc = twh_write_word(t, ch, a, stamp);
            if (!rc)
                rc = twh_write_word(t, ch, (uint16_t)(a + 1u), value);
            if (!rc && addr)
                *addr = a;
            return rc;
        }
        if (erased || end < TWH_CAL_START + 2u)
            return TWH_ERR_FLASH_FULL;
        rc = oldest_page(t, ch, end, &w);
        if (!rc)
            rc = twh_erase_page(t, ch, w);   /* refuses pages below 0x20 */
        if (rc)
            return rc;
        erased = 1;
    }
}
