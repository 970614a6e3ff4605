/* cmocka tests of the sensor page twh_cli prints (sw/tools/twh_page.c), run
 * against the fake core (fake_core.c) with the shared vector flash images
 * (tb/vectors/flash_*.json) behind its channels.
 *
 * The oracle is the driver's map decoder applied to the whole image: the page
 * must show what the flash holds, although the tool reads only the words it
 * needs. The vector images put calibration records behind blank pairs (after
 * a wrap, in the last pair), which a tool that stops at the first blank word
 * gets wrong.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "fake_core.h"
#include "twh.h"
#include "twh_page.h"
#include "twh_vectors.h"

static fake_core_t F;
static char OUT[65536], ERR[4096];

static uint64_t fake_now(void *ctx)
{
    return ((fake_core_t *)ctx)->now_us;
}

static void slurp(FILE *fp, char *buf, size_t n)
{
    size_t got;

    rewind(fp);
    got = fread(buf, 1, n - 1, fp);
    buf[got] = '\0';
    fclose(fp);
}

/* runs the page over F (with the interrupt hook or without: the driver
 * polls); the output goes to OUT and ERR */
static int run_page_irq(int quick, int with_irq)
{
    twh_platform_t p;
    twh_page_opts_t o;
    FILE *out = tmpfile(), *err = tmpfile();
    int rc;

    assert_non_null(out);
    assert_non_null(err);
    memset(&o, 0, sizeof o);
    o.quick = quick;
    o.only = -1;
    o.timeout_ms = 1000;
    o.where = "fake core";
    o.out = out;
    o.err = err;
    o.now_us = fake_now;
    o.ctx = &F;
    fake_platform(&F, &p, with_irq);
    rc = twh_page_run(&p, &o);
    slurp(out, OUT, sizeof OUT);
    slurp(err, ERR, sizeof ERR);
    return rc;
}

static int run_page(int quick)
{
    return run_page_irq(quick, 1);
}

/* channel ch's page (up to the next one) as a NUL-terminated copy */
static const char *page(int ch)
{
    static char buf[8192];
    char head[32];
    const char *a, *b;

    snprintf(head, sizeof head, "== channel %d:", ch);
    a = strstr(OUT, head);
    assert_non_null(a);
    b = strstr(a + 1, "\n== channel ");
    if (!b)
        b = a + strlen(a);
    assert_true((size_t)(b - a) < sizeof buf);
    memcpy(buf, a, (size_t)(b - a));
    buf[b - a] = '\0';
    return buf;
}

static void has(const char *text, const char *line)
{
    if (!strstr(text, line))
        fail_msg("missing \"%s\" in:\n%s", line, text);
}

static void lacks(const char *text, const char *what)
{
    if (strstr(text, what))
        fail_msg("unexpected \"%s\" in:\n%s", what, text);
}

static uint8_t type_of(const vec_map_t *v)
{
    if (v->kind == TWH_MAP_O2)
        return TWH_TYPE_O2;
    return strstr(v->note, "stick") ? TWH_TYPE_CO2_STICK : TWH_TYPE_CO2;
}

/* the lines of a page that come from the flash, from the decode of the
 * whole image */
static void check_flash_lines(const char *pg, const uint16_t *img, uint16_t n, uint8_t kind)
{
    twh_map_t m;
    char line[128];

    assert_int_equal(twh_decode_map(img, n, kind, &m), TWH_OK);
    snprintf(line, sizeof line, "  model            %s   (MFG ID %s)\n", m.model, m.mfg_id);
    has(pg, line);
    snprintf(line, sizeof line, "  serial           %s\n", m.serial);
    has(pg, line);
    snprintf(line, sizeof line, "  flash            %u words\n", n);
    has(pg, line);
    snprintf(line, sizeof line, "  calibrations     %u stored\n", m.cal_count);
    has(pg, line);
    if (kind == TWH_MAP_O2 && m.current.addr) {
        snprintf(line, sizeof line, "gain %u, record at 0x%02X)\n", m.current.value,
                 m.current.addr);
        has(pg, line);
    } else if (m.current.addr) {
        snprintf(line, sizeof line, "  CO2 400 ppm cal  reading %u (calibrated ", m.current.value);
        has(pg, line);
    } else {
        lacks(pg, "PPO2");
        lacks(pg, "400 ppm");
    }
}

/* every vector map behind its own channel: the page shows the current
 * calibration and the record count of the whole image */
static void test_page_vector_maps(void **state)
{
    unsigned k, n = (unsigned)VEC_COUNT(vec_maps);

    (void)state;
    assert_true(n <= TWH_MAX_CHANNELS);
    fake_init(&F, (uint8_t)n, 16);
    for (k = 0; k < n; k++)
        fake_dev_setup(&F.dev[k], 0x12, type_of(&vec_maps[k]), vec_maps[k].words,
                       vec_maps[k].n_words);
    assert_int_equal(run_page(0), 0);
    for (k = 0; k < n; k++) {
        const vec_map_t *v = &vec_maps[k];
        const char *pg = page((int)k);

        check_flash_lines(pg, v->words, v->n_words, (uint8_t)v->kind);
        /* and the vector's own expectation, made by the Python decoder */
        if (v->has_current) {
            char want[64];

            snprintf(want, sizeof want, v->kind == TWH_MAP_O2 ? "record at 0x%02X)" :
                     "reading %u (", v->kind == TWH_MAP_O2 ? v->cur_addr : v->cur_value);
            has(pg, want);
        }
        lacks(pg, "incomplete");
    }
    assert_string_equal(ERR, "");
    assert_int_equal(F.bus_errors, 0);
}

/* A 32-channel core (register map version 2): a cell on every channel but
 * 5 and 6, the vector maps in turn. With a 64-deep FIFO the tool would have
 * 64 commands in flight, two a channel, but there are 32 tags: it must never
 * reuse a tag still in flight. */
static void test_page_32_channels(void **state)
{
    unsigned k, n = (unsigned)VEC_COUNT(vec_maps);
    char line[64];

    (void)state;
    fake_init(&F, 32, 64);
    for (k = 0; k < 32; k++)
        if (k != 5 && k != 6)
            fake_dev_setup(&F.dev[k], k == 31 ? 0x26 : 0x12, type_of(&vec_maps[k % n]),
                           vec_maps[k % n].words, vec_maps[k % n].n_words);
    assert_int_equal(run_page(0), 0);
    assert_string_equal(ERR, "");
    assert_int_equal(F.bus_errors, 0);
    has(OUT, "core: 32 channels, FIFO depth 64, 48000 kHz, version 2.0 (fake core)\n");
    /* The 32 tags are shared fairly: in the first half of the session every
     * channel with a sensor has had about as many commands as any other
     * (handed out in channel order, channels 0-15 took two each, round
     * after round, and 16-31 waited for what was left). */
    {
        unsigned cnt[32] = {0}, lo = ~0u, hi = 0;

        assert_true(F.n_pushed < FAKE_LOG_MAX);
        for (k = 0; k < F.n_pushed / 2; k++)
            cnt[F.pushed[k].ch]++;
        for (k = 0; k < 32; k++) {
            if (k == 5 || k == 6)
                continue;
            lo = cnt[k] < lo ? cnt[k] : lo;
            hi = cnt[k] > hi ? cnt[k] : hi;
        }
        assert_true(hi - lo <= 2);
    }
    for (k = 0; k < 32; k++) {
        const vec_map_t *v = &vec_maps[k % n];

        if (k == 5 || k == 6) {
            snprintf(line, sizeof line, "== channel %u: no sensor", k);
            has(OUT, line);
            continue;
        }
        check_flash_lines(page((int)k), v->words, v->n_words, (uint8_t)v->kind);
        lacks(page((int)k), "incomplete");
    }
    has(page(31), "firmware v26 (byte 0x26)");

    /* -c 31 on a 16-channel core: no such channel */
    fake_init(&F, 16, 16);
    {
        twh_platform_t p;
        twh_page_opts_t o;
        FILE *out = tmpfile(), *err = tmpfile();

        memset(&o, 0, sizeof o);
        o.only = 31;
        o.timeout_ms = 1000;
        o.where = "fake core";
        o.out = out;
        o.err = err;
        o.now_us = fake_now;
        o.ctx = &F;
        fake_platform(&F, &p, 1);
        assert_int_equal(twh_page_run(&p, &o), 2);
        slurp(out, OUT, sizeof OUT);
        slurp(err, ERR, sizeof ERR);
        has(ERR, "no channel 31");
    }
}

/* A record left half-written (power lost between its two words) and the
 * newest record in the area's last pair, with blank pairs between: the
 * current one lies beyond the first blank word. */
static void test_page_half_written_record(void **state)
{
    uint16_t img[512];
    const vec_map_t *v = &vec_maps[1];    /* 128 words, records 0x20-0x24, 0x7E */
    twh_map_t m;

    (void)state;
    assert_int_equal(v->n_words, 128);
    memcpy(img, v->words, sizeof img[0] * v->n_words);
    img[0x23] = TWH_BLANK;                /* 0x22 loses its second word */
    img[0x7F] = 3711;                     /* a newer gain in the last pair */
    assert_int_equal(twh_decode_map(img, v->n_words, TWH_MAP_O2, &m), TWH_OK);
    assert_int_equal(m.current.addr, 0x7E);
    assert_int_equal(m.cal_count, 3);
    fake_init(&F, 1, 16);
    fake_dev_setup(&F.dev[0], 0x0F, TWH_TYPE_O2, img, v->n_words);
    assert_int_equal(run_page(0), 0);
    check_flash_lines(page(0), img, v->n_words, TWH_MAP_O2);
    has(page(0), "gain 3711, record at 0x7E)");
}

/* A read that fails part way: the page says so and shows the answers it got,
 * raw, and nothing worked out from flash words it does not have. */
static void test_page_incomplete(void **state)
{
    const char *pg;

    (void)state;
    fake_init(&F, 2, 16);
    fake_dev_setup(&F.dev[0], 0x12, TWH_TYPE_O2, vec_maps[0].words, vec_maps[0].n_words);
    fake_dev_setup(&F.dev[1], 0x12, TWH_TYPE_O2, vec_maps[0].words, vec_maps[0].n_words);
    fake_script(&F, 0, 0x48, TWH_ST_NO_RESPONSE, 0);    /* ch0's first flash read */
    assert_int_equal(run_page(0), 0);
    pg = page(0);
    has(pg, "(NO_RESPONSE) on flash read (0x48); the page is incomplete\n");
    has(pg, "  supply           3100 mV (ADC 1353)\n");
    has(pg, "  temperature ADC  2000\n");
    has(pg, "  O2 ADC           239\n");
    lacks(pg, "  temperature      ");
    lacks(pg, "O2 cell");
    lacks(pg, "PPO2");
    lacks(pg, "model");
    lacks(pg, "calibrations");
    /* the other channel is unaffected */
    check_flash_lines(page(1), vec_maps[0].words, vec_maps[0].n_words, TWH_MAP_O2);
    lacks(page(1), "incomplete");
}

/* A device type with no known flash map: its readings, raw, and no flash
 * read on its line. */
static void test_page_unknown_type(void **state)
{
    const char *pg;
    unsigned i;

    (void)state;
    fake_init(&F, 1, 16);
    fake_dev_setup(&F.dev[0], 0x12, 0x07, vec_maps[0].words, vec_maps[0].n_words);
    assert_int_equal(run_page(0), 0);
    pg = page(0);
    has(pg, "unknown device type");
    has(pg, "  supply           3100 mV (ADC 1353)\n");
    has(pg, "  flash            not read: no map known for device type 0x07\n");
    lacks(pg, "model");
    lacks(pg, "PPO2");
    for (i = 0; i < F.n_line; i++)
        assert_true(F.line[i].cmd != 0x40 && F.line[i].cmd != 0x48 && F.line[i].cmd != 0x49);
}

/* -q: the readings only, no flash read */
static void test_page_quick(void **state)
{
    (void)state;
    fake_init(&F, 1, 16);
    fake_dev_setup(&F.dev[0], 0x12, TWH_TYPE_O2, vec_maps[0].words, vec_maps[0].n_words);
    assert_int_equal(run_page(1), 0);
    has(page(0), "  O2 ADC           239\n");
    lacks(page(0), "flash");
    assert_int_equal(fake_line_count(&F, 0x40, 0x40), 0);
    assert_int_equal(fake_line_count(&F, 0x46, 0x49), 0);
}

/* a platform without wait_irq (a CPU that takes no interrupts): the tool
 * waits with delay_us and prints the same page as with the interrupt */
static void test_page_polled(void **state)
{
    static char with_irq[sizeof OUT];

    (void)state;
    fake_init(&F, 2, 16);
    fake_dev_setup(&F.dev[0], 0x12, TWH_TYPE_O2, vec_maps[0].words, vec_maps[0].n_words);
    fake_dev_setup(&F.dev[1], 0x12, type_of(&vec_maps[1]), vec_maps[1].words,
                   vec_maps[1].n_words);
    assert_int_equal(run_page_irq(0, 1), 0);
    assert_true(F.irq_waits > 0);
    memcpy(with_irq, OUT, sizeof OUT);

    fake_init(&F, 2, 16);
    fake_dev_setup(&F.dev[0], 0x12, TWH_TYPE_O2, vec_maps[0].words, vec_maps[0].n_words);
    fake_dev_setup(&F.dev[1], 0x12, type_of(&vec_maps[1]), vec_maps[1].words,
                   vec_maps[1].n_words);
    assert_int_equal(run_page_irq(0, 0), 0);
    assert_string_equal(ERR, "");
    assert_int_equal(F.irq_waits, 0);
    assert_true(F.delays > 0);
    assert_string_equal(OUT, with_irq);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_page_vector_maps),
        cmocka_unit_test(test_page_32_channels),
        cmocka_unit_test(test_page_half_written_record),
        cmocka_unit_test(test_page_incomplete),
        cmocka_unit_test(test_page_unknown_type),
        cmocka_unit_test(test_page_quick),
        cmocka_unit_test(test_page_polled),
    };

    return cmocka_run_group_tests(tests, NULL, NULL);
}
