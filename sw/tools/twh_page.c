/* The sensor page of every channel of a twowire-host core (docs/boards.md),
 * over any platform hooks: twh_cli runs it over the board's UART bridge,
 * sw/test/test_page.c over the driver tests' fake core.
 *
 * All channels (up to TWH_MAX_CHANNELS, 32) are worked at once: commands
 * are queued with twh_submit (two in flight per channel, so each engine has
 * the next one ready, and never more than the 32 tags) and collected with
 * twh_result, waiting on the core's interrupt line between results.
 *
 * The state of every channel is kept (the pages are printed at the end),
 * compactly: a firmware on a small SoC keeps it in its RAM for 32 channels
 * (soc/fw/main.c). Only words below TWH_CAL_END are ever read: the page's
 * factory words and the calibration area.
 */
#include <stdio.h>
#include <string.h>

#include "twh_page.h"

#define MAX_CH      TWH_MAX_CHANNELS
/* per channel: at most 4 single commands, 24 factory words, the first word
 * of each of the 96 calibration pairs and, as their answers come, the second
 * ones: 220 */
#define QUEUE_MAX   256
#define IN_FLIGHT   2            /* commands queued per engine */
#define TAGS        32           /* RES_INFO.TAG: 5 bits */
#define WORDS       TWH_CAL_END  /* flash words the page reads: 0x00-0xDF */

static const char *status_name[] = {
    "OK", "NO_RESPONSE", "BAD_CHECKSUM", "FRAMING", "SHORT_RESPONSE",
    "LINE_STUCK_LOW", "LINE_STUCK_HIGH", "BLOCKED", "CANCELLED"
};

/* what a queued command is for */
enum what { W_FIRMWARE, W_CONFIG, W_REF, W_TEMP, W_O2, W_WORD };

typedef struct item {
    uint8_t  what;
    uint16_t addr;               /* W_WORD: flash word address */
} item_t;

/* a queued item in 16 bits: what in 15:12, addr in 11:0 */
typedef uint16_t qitem_t;

typedef struct chan {
    int      selected;
    int      present;            /* firmware answered */
    int      err;                /* first failure of this channel (TWH_ERR_*) */
    uint8_t  err_status;         /* hardware status of it, if any */
    uint8_t  err_what;
    twh_fw_t fw;
    uint16_t execute_us;
    qitem_t  queue[QUEUE_MAX];
    int      qhead, qlen;
    int      in_flight;
    uint8_t  have[W_WORD];       /* answers of the single commands */
    uint16_t ans[W_WORD];
    uint16_t words[WORDS];       /* as read; TWH_BLANK until read */
} chan_t;

typedef struct flight {
    int      used;
    uint8_t  ch;
    uint8_t  cmd;
    item_t   item;
} flight_t;

typedef struct session {
    twh_t       t;
    const twh_page_opts_t *o;
    uint32_t    timeout_ms;
    int         quick;
    chan_t      ch[MAX_CH];
    flight_t    flight[TAGS];    /* by tag */
    int         next_ch;         /* where the next round of submits starts */
} session_t;

static session_t S;              /* large: kept off the stack */

/* ------------------------------------------------------------ formatting */
static void fixed(char *buf, size_t n, long v, int decimals)
{
    long scale = decimals == 3 ? 1000 : decimals == 2 ? 100 : 10;
    unsigned long a = (unsigned long)(v < 0 ? -v : v);

    snprintf(buf, n, "%s%lu.%0*lu", v < 0 ? "-" : "", a / (unsigned long)scale, decimals,
             a % (unsigned long)scale);
}

static const char *type_name(uint8_t type)
{
    switch (type) {
    case TWH_TYPE_O2:        return "Digital O2 sensor";
    case TWH_TYPE_CO2:       return "CO2 sensor";
    case TWH_TYPE_CO2_STICK: return "CO2 temperature stick";
    default:                 return "unknown device type";
    }
}

/* the device types whose flash map the driver decodes: the O2 cell's, and
 * the CO2 map (the temperature stick uses it too, docs/protocol.md) */
static int known_map(uint8_t type)
{
    return type == TWH_TYPE_O2 || type == TWH_TYPE_CO2 || type == TWH_TYPE_CO2_STICK;
}

/* days since 1970-01-01 of a civil date, and back (proleptic Gregorian) */
static long days_from_civil(long y, unsigned m, unsigned d)
{
    long era;
    unsigned yoe, doy, doe;

    y -= m <= 2;
    era = (y >= 0 ? y : y - 399) / 400;
    yoe = (unsigned)(y - era * 400);
    doy = (153u * (m > 2 ? m - 3 : m + 9) + 2u) / 5u + d - 1u;
    doe = yoe * 365u + yoe / 4u - yoe / 100u + doy;
    return era * 146097L + (long)doe - 719468L;
}

static void civil_from_days(long z, long *y, unsigned *m, unsigned *d)
{
    long era;
    unsigned doe, yoe, doy, mp;

    z += 719468L;
    era = (z >= 0 ? z : z - 146096L) / 146097L;
    doe = (unsigned)(z - era * 146097L);
    yoe = (doe - doe / 1460u + doe / 36524u - doe / 146096u) / 365u;
    doy = doe - (365u * yoe + yoe / 4u - yoe / 100u);
    mp = (5u * doy + 2u) / 153u;
    *d = doy - (153u * mp + 2u) / 5u + 1u;
    *m = mp < 10 ? mp + 3 : mp - 9;
    *y = (long)yoe + era * 400 + (*m <= 2);
}

static void fmt_date(char *buf, size_t n, const twh_datetime_t *dt, unsigned long add_hours)
{
    long y, mins;
    unsigned mo, d;

    if (dt->year == 0) {
        snprintf(buf, n, "(not a date)");
        return;
    }
    mins = (days_from_civil(dt->year, dt->month, dt->day) * 24L + dt->hour +
            (long)add_hours) * 60L + dt->minute;
    civil_from_days(mins / 1440L, &y, &mo, &d);
    snprintf(buf, n, "%04ld-%02u-%02u %02ld:%02ld", y, mo, d, (mins % 1440L) / 60L,
             mins % 60L);
}

/* ------------------------------------------------------------ session */
/* the transport failed: the hook has said why */
static int link_failed(void)
{
    return S.o->failed != NULL && S.o->failed(S.o->ctx);
}

static uint64_t now_us(void)
{
    return S.o->now_us(S.o->ctx);
}

static void enqueue(chan_t *c, uint8_t what, uint16_t addr)
{
    int i;

    if (c->qlen >= QUEUE_MAX)
        return;
    i = (c->qhead + c->qlen) % QUEUE_MAX;
    c->queue[i] = (qitem_t)((unsigned)what << 12 | (addr & 0xFFFu));
    c->qlen++;
}

static void encode(const item_t *it, uint8_t *cmd, uint16_t *payload)
{
    static const uint8_t single[] = {
        TWH_CMD_FIRMWARE, TWH_CMD_CONFIG, TWH_CMD_REF_VOLTAGE,
        TWH_CMD_TEMPERATURE, TWH_CMD_O2_VOLTAGE
    };

    if (it->what == W_WORD)
        twh_encode_addr(TWH_CMD_READ, it->addr, cmd, payload);
    else {
        *cmd = single[it->what];
        *payload = TWH_UNUSED_PAYLOAD;
    }
}

static void channel_error(chan_t *c, int err, uint8_t status, uint8_t what)
{
    if (c->err)
        return;
    c->err = err;
    c->err_status = status;
    c->err_what = what;
    c->qlen = 0;                 /* nothing more for this channel */
}

/* Runs every queued command of every channel to its result. */
static int run_queues(void (*on_result)(int ch, const item_t *it, const twh_result_t *r))
{
    uint64_t last = now_us();
    twh_result_t r;
    int k, rc;

    for (;;) {
        int busy = 0, pass, j, full = 0;

        /* Fill the engines fairly: every channel with work gets its first
         * command in flight before any gets its second, starting after the
         * channel served last. The 32 tags are fewer than two commands on
         * each of 32 channels: handed out in channel order, the low
         * channels would take them all, round after round. */
        for (pass = 0; pass < IN_FLIGHT && !full; pass++) {
            for (j = 0; j < S.t.channels && !full; j++) {
                chan_t *c;
                item_t item, *it = &item;
                uint8_t cmd;
                uint16_t payload;
                int tag;

                k = (S.next_ch + j) % S.t.channels;
                c = &S.ch[k];
                /* the tag the driver gives next must not be one still in
                 * flight: with 32 channels more than 32 could be */
                if (c->qlen == 0 || c->in_flight > pass || S.flight[S.t.next_tag % TAGS].used)
                    continue;
                item.what = (uint8_t)(c->queue[c->qhead] >> 12);
                item.addr = (uint16_t)(c->queue[c->qhead] & 0xFFFu);
                encode(it, &cmd, &payload);
                tag = twh_submit(&S.t, (uint8_t)k, cmd, payload);
                if (link_failed())
                    return -1;
                if (tag == TWH_ERR_FIFO_FULL) {
                    full = 1;
                    break;
                }
                if (tag < 0) {
                    fprintf(S.o->err, "twh_cli: channel %d: submit 0x%02X: error %d\n",
                            k, cmd, tag);
                    return -1;
                }
                S.flight[tag].used = 1;
                S.flight[tag].ch = (uint8_t)k;
                S.flight[tag].cmd = cmd;
                S.flight[tag].item = *it;
                c->qhead = (c->qhead + 1) % QUEUE_MAX;
                c->qlen--;
                c->in_flight++;
                S.next_ch = (k + 1) % S.t.channels;
            }
        }
        for (k = 0; k < S.t.channels; k++)
            busy |= S.ch[k].qlen > 0 || S.ch[k].in_flight > 0;
        if (!busy)
            return 0;

        rc = twh_result(&S.t, &r);
        if (link_failed())
            return -1;
        if (rc == TWH_ERR_AGAIN) {
            uint64_t waited = now_us() - last;
            uint32_t left;

            if (waited >= (uint64_t)S.timeout_ms * 1000u) {
                fprintf(S.o->err, "twh_cli: no result for %lu ms\n", (unsigned long)S.timeout_ms);
                return -1;
            }
            left = (uint32_t)((uint64_t)S.timeout_ms * 1000u - waited);
            /* wait_irq may be NULL (a CPU without interrupts): then look
             * again after the driver's polling step, as twh_xfer does */
            if (S.t.plat.wait_irq)
                S.t.plat.wait_irq(S.t.plat.ctx, left);
            else
                S.t.plat.delay_us(S.t.plat.ctx, left < S.t.poll_us ? left : S.t.poll_us);
            if (link_failed())
                return -1;
            continue;
        }
        if (rc != TWH_OK) {
            fprintf(S.o->err, "twh_cli: reading a result: error %d\n", rc);
            return -1;
        }
        last = now_us();
        if (r.tag >= TAGS || !S.flight[r.tag].used || S.flight[r.tag].ch != r.channel ||
            S.flight[r.tag].cmd != r.cmd) {
            fprintf(S.o->err,
                    "twh_cli: a result nobody asked for: channel %u tag %u command 0x%02X\n",
                    r.channel, r.tag, r.cmd);
            continue;            /* e.g. left over from an earlier session */
        }
        S.flight[r.tag].used = 0;
        S.ch[r.channel].in_flight--;
        on_result(r.channel, &S.flight[r.tag].item, &r);
    }
}

static void firmware_result(int k, const item_t *it, const twh_result_t *r)
{
    chan_t *c = &S.ch[k];
    int rc = twh_status_err(r->status, r->cmd);

    if (rc != TWH_OK) {
        channel_error(c, rc, r->status, it->what);
        return;
    }
    twh_fw_decode(r->data, &c->fw);
    c->present = 1;
}

/* the flash size in words of a 0x40 answer, as twh_config() takes it */
static uint16_t config_size(uint16_t data)
{
    return data & TWH_ADDR_MAX;
}

static void page_result(int k, const item_t *it, const twh_result_t *r)
{
    chan_t *c = &S.ch[k];
    int rc = twh_status_err(r->status, r->cmd);

    if (rc != TWH_OK) {
        channel_error(c, rc, r->status, it->what);
        return;
    }
    if (it->what == W_WORD) {
        uint16_t a = it->addr;

        if (a >= WORDS)
            return;              /* never asked for */
        c->words[a] = r->data & TWH_WORD_MASK;
        /* a calibration record counts only with both words programmed: its
         * second word matters only when its first is programmed */
        if (!c->err && a >= TWH_CAL_START && a < TWH_CAL_END && !((a - TWH_CAL_START) & 1u) &&
            c->words[a] != TWH_BLANK)
            enqueue(c, W_WORD, (uint16_t)(a + 1u));
        return;
    }
    c->have[it->what] = 1;
    c->ans[it->what] = r->data;
    if (it->what == W_CONFIG && !c->err) {
        /* The field calibrations: the first word of every pair in the area.
         * The current record is the one with the largest stamp wherever it
         * lies: records sit beyond blank pairs once the area has wrapped
         * (the oldest page erased) or a record was left half-written, so
         * reading up to the first blank word would miss them. */
        uint16_t size = config_size(r->data), end = size < TWH_CAL_END ? size : TWH_CAL_END, a;

        for (a = TWH_CAL_START; (uint16_t)(a + 1u) < end; a += 2u)
            enqueue(c, W_WORD, a);
    }
}

/* execute phase per firmware, for every channel at once: 4 ms (safe for
 * all) first, then the firmware answer, then 6 ms for v18 and later - what
 * twh_negotiate() does one channel at a time */
static int negotiate_all(void)
{
    int k, rc;

    for (k = 0; k < S.t.channels; k++) {
        if (!S.ch[k].selected)
            continue;
        rc = twh_set_execute_us(&S.t, (uint8_t)k, TWH_EXECUTE_SAFE_US);
        if (link_failed())
            return -1;
        if (rc != TWH_OK) {
            fprintf(S.o->err, "twh_cli: channel %d: execute %u us refused (%d)\n", k,
                    TWH_EXECUTE_SAFE_US, rc);
            return -1;
        }
        enqueue(&S.ch[k], W_FIRMWARE, 0);
    }
    if (run_queues(firmware_result) != 0)
        return -1;
    for (k = 0; k < S.t.channels; k++) {
        chan_t *c = &S.ch[k];

        if (!c->present)
            continue;
        c->execute_us = twh_execute_us_for(&c->fw);
        rc = twh_set_execute_us(&S.t, (uint8_t)k, c->execute_us);
        if (link_failed())
            return -1;
        if (rc != TWH_OK) {
            fprintf(S.o->err, "twh_cli: channel %d: execute %u us refused (%d)\n", k,
                    c->execute_us, rc);
            return -1;
        }
    }
    return 0;
}

/* flash words the page shows: model, MFG ID, dates, serial, temperature
 * constants, and for O2 cells the op-amp offset */
static void queue_page(chan_t *c)
{
    uint16_t a, last_factory = c->fw.type == TWH_TYPE_O2 ? 0x19 : 0x18;

    enqueue(c, W_REF, 0);
    enqueue(c, W_TEMP, 0);
    enqueue(c, W_O2, 0);
    if (S.quick)
        return;
    if (!known_map(c->fw.type))
        return;                  /* no flash map to read it by */
    enqueue(c, W_CONFIG, 0);
    for (a = 0x00; a <= 0x0D; a++)
        enqueue(c, W_WORD, a);
    for (a = 0x10; a <= last_factory; a++)
        enqueue(c, W_WORD, a);
}

static const char *what_name(uint8_t what)
{
    static const char *n[] = { "firmware (0x41)", "config (0x40)", "supply (0x42)",
                               "temperature (0x43)", "O2 (0x44)", "flash read (0x48)" };
    return what <= W_WORD ? n[what] : "?";
}

static void print_page(int k)
{
    chan_t *c = &S.ch[k];
    char b1[32], b2[32];
    int32_t supply = 0;
    int rc_s;

    if (!c->present) {
        if (c->err == TWH_ERR_NO_RESPONSE)
            fprintf(S.o->out, "== channel %d: no sensor (no answer to the firmware command)\n", k);
        else
            fprintf(S.o->out, "== channel %d: error %d (%s) on %s\n", k, c->err,
                    c->err_status < 9 ? status_name[c->err_status] : "?", what_name(c->err_what));
        return;
    }
    if (c->fw.version >= 0)
        fprintf(S.o->out, "== channel %d: %s, firmware v%d (byte 0x%02X), execute %u us\n", k,
                type_name(c->fw.type), c->fw.version, c->fw.raw, c->execute_us);
    else
        fprintf(S.o->out, "== channel %d: %s, firmware unknown (byte 0x%02X), execute %u us\n", k,
                type_name(c->fw.type), c->fw.raw, c->execute_us);
    if (c->err)
        fprintf(S.o->out, "  error            %d (%s) on %s; the page is incomplete\n", c->err,
                c->err_status < 9 ? status_name[c->err_status] : "?", what_name(c->err_what));

    rc_s = c->have[W_REF] ? twh_supply_mv(c->ans[W_REF] & 0xFFFu, &supply) : TWH_ERR_RANGE;
    /* Values worked out from flash words need every word they use: a page
     * cut short by an error shows only what was answered, raw, and so does
     * a device whose flash map is not known. */
    if (S.quick || c->err || !known_map(c->fw.type)) {
        if (rc_s == TWH_OK)
            fprintf(S.o->out, "  supply           %ld mV (ADC %u)\n",
                    (long)supply, c->ans[W_REF] & 0xFFFu);
        if (c->have[W_TEMP])
            fprintf(S.o->out, "  temperature ADC  %u\n", c->ans[W_TEMP] & 0xFFFu);
        if (c->have[W_O2])
            fprintf(S.o->out, "  O2 ADC           %u\n", c->ans[W_O2] & 0xFFFu);
        if (!S.quick && !c->err)
            fprintf(S.o->out, "  flash            not read: no map known for device type 0x%02X\n",
                    c->fw.type);
        return;
    }

    {
        uint16_t size = c->have[W_CONFIG] ? config_size(c->ans[W_CONFIG]) : 0;
        uint16_t img[512], a;
        uint8_t kind = c->fw.type == TWH_TYPE_O2 ? TWH_MAP_O2 : TWH_MAP_CO2;
        twh_map_t m;
        int32_t c100;

        if (size < 0x20 || size > 512) {
            fprintf(S.o->out, "  flash            size %u not usable\n", size);
            return;
        }
        for (a = 0; a < size; a++)
            img[a] = a < WORDS ? c->words[a] : TWH_BLANK;   /* not read: blank */
        if (twh_decode_map(img, size, kind, &m) != TWH_OK) {
            fprintf(S.o->out, "  flash            map not decodable\n");
            return;
        }
        fprintf(S.o->out, "  model            %s   (MFG ID %s)\n", m.model, m.mfg_id);
        fprintf(S.o->out, "  serial           %s\n", m.serial);
        fmt_date(b1, sizeof b1, &m.manufactured, 0);
        fmt_date(b2, sizeof b2, &m.expires, 0);
        fprintf(S.o->out, "  manufactured     %s   expires %s\n", b1, b2);
        fprintf(S.o->out, "  flash            %u words\n", size);
        if (rc_s == TWH_OK)
            fprintf(S.o->out, "  supply           %ld mV\n", (long)supply);
        else
            fprintf(S.o->out, "  supply           ?\n");
        if (c->have[W_TEMP] && rc_s == TWH_OK &&
            twh_temperature_c100(c->ans[W_TEMP] & 0xFFFu, m.ref_temp, m.adc_ref, supply,
                                 m.temp_scale, &c100) == TWH_OK) {
            fixed(b1, sizeof b1, c100, 2);
            fprintf(S.o->out, "  temperature      %s C\n", b1);
        } else {
            fprintf(S.o->out, "  temperature      ?\n");
        }
        if (kind == TWH_MAP_O2) {
            uint16_t adc = c->ans[W_O2] & 0xFFFu;

            if (c->have[W_O2]) {
                fixed(b1, sizeof b1, twh_o2_mv100(adc, m.opamp_offset), 2);
                fprintf(S.o->out, "  O2 cell          %s mV\n", b1);
            }
            if (c->have[W_O2] && m.current.addr) {
                fixed(b1, sizeof b1, twh_ppo2_mbar(adc, m.current.value), 3);
                fmt_date(b2, sizeof b2, &m.manufactured,
                         (unsigned long)m.current.stamp * m.cal_unit_hours);
                fprintf(S.o->out,
                        "  PPO2             %s bar (calibrated %s, gain %u, record at 0x%02X)\n",
                        b1, b2, m.current.value, m.current.addr);
            }
        } else if (m.current.addr) {
            fmt_date(b2, sizeof b2, &m.manufactured,
                     (unsigned long)m.current.stamp * m.cal_unit_hours);
            fprintf(S.o->out, "  CO2 400 ppm cal  reading %u (calibrated %s)\n",
                    m.current.value, b2);
        }
        fprintf(S.o->out, "  calibrations     %u stored\n", m.cal_count);
    }
}

int twh_page_run(const twh_platform_t *plat, const twh_page_opts_t *o)
{
    twh_result_t stale;
    int k, rc, n_stale = 0;

    memset(&S, 0, sizeof S);
    S.o = o;
    S.quick = o->quick;
    S.timeout_ms = o->timeout_ms;
    rc = twh_init(&S.t, plat);
    if (link_failed())
        return 1;
    if (rc != TWH_OK) {
        fprintf(o->err, "twh_cli: %s answers, but no twowire-host core is behind it "
                "(twh_init: %d)\n", o->where, rc);
        return 1;
    }
    S.t.timeout_us = o->timeout_ms * 1000u;
    fprintf(o->out, "core: %u channels, FIFO depth %u, %lu kHz, version %u.%u (%s)\n",
            S.t.channels, S.t.fifo_depth, (unsigned long)S.t.clk_khz, S.t.version_major,
            S.t.version_minor, o->where);
    if (o->only >= S.t.channels) {
        fprintf(o->err, "twh_cli: the core has no channel %ld\n", o->only);
        return 2;
    }
    /* results left from an earlier session are not ours */
    while (twh_result(&S.t, &stale) == TWH_OK)
        n_stale++;
    if (link_failed())
        return 1;
    if (n_stale)
        fprintf(o->out, "(%d results of an earlier session discarded)\n", n_stale);

    for (k = 0; k < S.t.channels; k++) {
        unsigned a;

        S.ch[k].selected = o->only < 0 || o->only == k;
        for (a = 0; a < WORDS; a++)
            S.ch[k].words[a] = TWH_BLANK;
    }
    if (negotiate_all() != 0)
        return 1;
    for (k = 0; k < S.t.channels; k++)
        if (S.ch[k].present)
            queue_page(&S.ch[k]);
    if (run_queues(page_result) != 0)
        return 1;

    for (k = 0; k < S.t.channels; k++) {
        if (!S.ch[k].selected)
            continue;
        fprintf(o->out, "\n");
        print_page(k);
    }
    return 0;
}
