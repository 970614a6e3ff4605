/* cmocka unit tests of the twowire-host C driver.
 *
 * 1. The shared vectors (the JSON files in tb/vectors/, via build/gen/twh_vectors.h,
 *    made by scripts/gen_c_vectors.py): the same data tb/test_protocol.py
 *    checks the Python reference against.
 * 2. The driver against a fake core (fake_core.c): FIFOs, RES_INFO/RES_POP,
 *    scripted results, a simulated peripheral behind each channel.
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
#include "twh_regs.h"
#include "twh_vectors.h"

/* ------------------------------------------------------------ fixture */
typedef struct env {
    fake_core_t f;
    twh_t t;
    twh_platform_t p;
} env_t;

static env_t *env_new(uint8_t channels, uint16_t depth, int with_irq)
{
    env_t *e = calloc(1, sizeof(*e));

    assert_non_null(e);
    fake_init(&e->f, channels, depth);
    /* ch0: O2 cell v18 with the 240-word vector map; ch1: CO2 v26 */
    fake_dev_setup(&e->f.dev[0], 0x12, TWH_TYPE_O2, vec_maps[0].words, vec_maps[0].n_words);
    fake_dev_setup(&e->f.dev[1], 0x26, TWH_TYPE_CO2, vec_maps[2].words, vec_maps[2].n_words);
    fake_platform(&e->f, &e->p, with_irq);
    assert_int_equal(twh_init(&e->t, &e->p), TWH_OK);
    return e;
}

static int setup(void **state)
{
    *state = env_new(2, 8, 0);
    return 0;
}

static int setup_irq(void **state)
{
    *state = env_new(2, 8, 1);
    return 0;
}

static int teardown(void **state)
{
    env_t *e = *state;

    /* the driver never makes the core answer with a bus error, and always
     * reads RES_INFO before RES_POP */
    assert_int_equal(e->f.bus_errors, 0);
    assert_int_equal(e->f.order_errors, 0);
    free(e);
    return 0;
}

#define E ((env_t *)*state)

static void blank_image(uint16_t *w, unsigned n)
{
    unsigned i;

    for (i = 0; i < n; i++)
        w[i] = TWH_BLANK;
}

/* ================================================================ vectors */
static void test_vec_frames_encoding(void **state)
{
    size_t i;
    unsigned n = 0;

    (void)state;
    for (i = 0; i < VEC_COUNT(vec_frames); i++) {
        const vec_frame_t *v = &vec_frames[i];
        uint8_t cmd = 0;
        uint16_t payload = 0;

        if (!v->is_command)
            continue;
        n++;
        /* the frame the core builds from (cmd, payload) */
        assert_int_equal(v->frame[0], v->cmd);
        assert_int_equal(v->frame_len, v->cmd < 0x80 ? 3 : 4);
        if (v->frame_len == 3) {
            assert_int_equal(v->frame[1], v->payload & 0xFF);
        } else {
            assert_int_equal(v->frame[1], v->payload >> 8);
            assert_int_equal(v->frame[2], v->payload & 0xFF);
        }
        assert_int_equal(twh_expects_response(v->cmd), v->expects_response);
        if (v->name && strcmp(v->name, "WRITE") == 0) {
            assert_int_equal(twh_encode_write((uint16_t)v->addr, (uint16_t)v->data, &cmd, &payload),
                             TWH_OK);
            assert_int_equal(cmd, v->cmd);
            assert_int_equal(payload, v->payload);
        } else if (v->addr >= 0) {
            assert_int_equal(twh_encode_addr(v->cmd & 0xFE, (uint16_t)v->addr, &cmd, &payload),
                             TWH_OK);
            assert_int_equal(cmd, v->cmd);
            assert_int_equal(payload, v->payload & 0xFF);
        }
    }
    assert_true(n >= 19);
}

/* every command vector through the driver: the core sees exactly the
 * vector's (cmd, payload); factory-area writes never reach the core */
static void test_vec_frames_on_bus(void **state)
{
    size_t i;

    for (i = 0; i < VEC_COUNT(vec_frames); i++) {
        const vec_frame_t *v = &vec_frames[i];
        unsigned before = E->f.n_pushed;
        uint16_t data;
        int rc;

        if (!v->is_command)
            continue;
        rc = twh_xfer(&E->t, 0, v->cmd, v->payload, &data);
        if (v->addr >= 0 && v->addr < 0x20 && v->name &&
            (!strcmp(v->name, "WRITE") || !strcmp(v->name, "ERASE"))) {
            assert_int_equal(rc, TWH_ERR_BAD_ARG);
            assert_int_equal(E->f.n_pushed, before);
            continue;
        }
        assert_int_equal(E->f.n_pushed, before + 1);
        assert_int_equal(E->f.pushed[before].cmd, v->cmd);
        assert_int_equal(E->f.pushed[before].payload, v->payload);
        assert_int_equal(E->f.pushed[before].ch, 0);
        if (!v->expects_response) {
            assert_int_equal(rc, TWH_OK);  /* no answer is the expected outcome */
        } else if (v->addr >= 0x100) {
            assert_int_equal(rc, TWH_ERR_NO_RESPONSE);  /* beyond the 240 words */
        } else {
            assert_int_equal(rc, TWH_OK);
        }
    }
}

static void test_vec_responses(void **state)
{
    size_t i;

    for (i = 0; i < VEC_COUNT(vec_frames); i++) {
        const vec_frame_t *v = &vec_frames[i];
        uint8_t bits = 0xEE;
        uint16_t words = 0, val = 0, data = 0;
        twh_fw_t fw;

        if (v->is_command)
            continue;
        assert_int_equal(v->resp_data, v->frame[0] << 8 | v->frame[1]);
        fake_script(&E->f, 0, -1, TWH_ST_OK, v->resp_data);
        switch (v->resp_cmd) {
        case 0x40:
            assert_int_equal(twh_config(&E->t, 0, &bits, &words), TWH_OK);
            if (v->resp_a >= 0)
                assert_int_equal(bits, v->resp_a);
            assert_int_equal(bits, v->frame[0] >> 1);
            assert_int_equal(words, v->resp_b);
            break;
        case 0x41:
            assert_int_equal(twh_firmware(&E->t, 0, &fw), TWH_OK);
            assert_int_equal(fw.version, v->resp_a);
            assert_int_equal(fw.type, v->resp_b);
            assert_int_equal(fw.raw, v->frame[0]);
            break;
        case 0x42:
            assert_int_equal(twh_ref_voltage(&E->t, 0, &val), TWH_OK);
            assert_int_equal(val, v->resp_a);
            break;
        case 0x48:
            assert_int_equal(twh_read_word(&E->t, 0, 0x30, &val), TWH_OK);
            assert_int_equal(val, v->resp_a);
            break;
        case -1:  /* generic answer: passed through unchanged */
            assert_int_equal(twh_xfer(&E->t, 0, TWH_CMD_READ, 0x30, &data), TWH_OK);
            assert_int_equal(data, v->resp_data);
            break;
        default:
            fail_msg("response vector %s for command 0x%02X: not handled", v->hex, v->resp_cmd);
        }
    }
}

static void test_vec_supply(void **state)
{
    size_t i;

    (void)state;
    for (i = 0; i < VEC_COUNT(vec_supply); i++) {
        int32_t mv = -12345;
        int rc = twh_supply_mv(vec_supply[i].adc, &mv);

        if (vec_supply[i].valid) {
            assert_int_equal(rc, TWH_OK);
            assert_int_equal(mv, vec_supply[i].supply_mv);
        } else {
            assert_int_equal(rc, TWH_ERR_RANGE);
            assert_int_equal(mv, -12345);  /* untouched */
        }
    }
}

static void test_vec_temperature(void **state)
{
    size_t i;

    (void)state;
    for (i = 0; i < VEC_COUNT(vec_temperature); i++) {
        const vec_temp_t *v = &vec_temperature[i];
        int32_t t = 0;
        /* Python's None supply is "unknown": the C API takes <= 0 for it */
        int rc = twh_temperature_c100(v->adc, v->ref_temp, v->adc_ref,
                                      v->supply_valid ? v->supply_mv : 0, v->temp_scale, &t);

        if (v->valid) {
            assert_int_equal(rc, TWH_OK);
            if (t != v->c100)
                fail_msg("%s: got %ld, want %ld", v->note, (long)t, (long)v->c100);
        } else {
            assert_int_equal(rc, TWH_ERR_RANGE);
        }
    }
}

static void test_vec_o2_ppo2(void **state)
{
    size_t i;

    (void)state;
    for (i = 0; i < VEC_COUNT(vec_o2); i++)
        assert_int_equal(twh_o2_mv100(vec_o2[i].adc, vec_o2[i].opamp_offset), vec_o2[i].o2_mv100);
    for (i = 0; i < VEC_COUNT(vec_ppo2); i++)
        assert_int_equal(twh_ppo2_mbar(vec_ppo2[i].adc, vec_ppo2[i].gain), vec_ppo2[i].ppo2_mbar);
}

static void test_vec_fw_version(void **state)
{
    size_t i;

    (void)state;
    for (i = 0; i < VEC_COUNT(vec_fw); i++) {
        twh_fw_t fw;

        twh_fw_decode((uint16_t)(vec_fw[i].byte << 8 | 0x01), &fw);
        assert_int_equal(fw.raw, vec_fw[i].byte);
        assert_int_equal(fw.type, 0x01);
        assert_int_equal(fw.version, vec_fw[i].version);
        assert_int_equal(fw.encoding, vec_fw[i].encoding);
    }
}

static void check_dt(const twh_datetime_t *dt, const vec_dt_t *want)
{
    assert_int_equal(dt->year, want->year);
    assert_int_equal(dt->month, want->month);
    assert_int_equal(dt->day, want->day);
    assert_int_equal(dt->hour, want->hour);
    assert_int_equal(dt->minute, want->minute);
}

static void check_map(const twh_map_t *m, const vec_map_t *v)
{
    unsigned i;

    assert_int_equal(m->kind, v->kind);
    assert_string_equal(m->model, v->model);
    assert_string_equal(m->mfg_id, v->mfg_id);
    assert_string_equal(m->serial, v->serial);
    check_dt(&m->manufactured, &v->manufactured);
    check_dt(&m->expires, &v->expires);
    assert_int_equal(m->temp_scale, v->temp_scale);
    assert_int_equal(m->ref_temp, v->ref_temp);
    assert_int_equal(m->adc_ref, v->adc_ref);
    assert_int_equal(m->size, v->flash_size);
    assert_int_equal(m->cal_count, v->calibration_count);
    assert_int_equal(m->cal_count, v->n_field_cals);
    if (v->has_current) {
        assert_int_equal(m->current.addr, v->cur_addr);
        assert_int_equal(m->current.stamp, v->cur_stamp);
        assert_int_equal(m->current.value, v->cur_value);
        assert_int_equal(m->current.stamp * m->cal_unit_hours, v->cur_hours);
    } else {
        assert_int_equal(m->current.addr, 0);
    }
    /* every record of the description is a programmed pair of the image */
    for (i = 0; i < v->n_field_cals; i++) {
        const uint16_t *fc = v->field_cals[i];
        assert_int_equal(v->words[fc[0]] * m->cal_unit_hours, fc[1]);
        assert_int_equal(v->words[fc[0] + 1], fc[2]);
    }
    if (v->kind == TWH_MAP_O2) {
        assert_int_equal(m->cal_unit_hours, 3);
        assert_int_equal(m->map_version, v->map_version);
        assert_int_equal(m->map_type, v->map_type);
        assert_int_equal(m->opamp_offset, v->opamp_offset);
        assert_int_equal(twh_s14((uint16_t)v->opamp_offset_word), v->opamp_offset);
        for (i = 0; i < 3; i++) {
            assert_int_equal(m->mfg_cal[i][0], v->mfg_cal[i][0]);
            assert_int_equal(m->mfg_cal[i][1], v->mfg_cal[i][1]);
        }
        assert_int_equal(m->has_rgb_offset, 0);
        assert_int_equal(m->has_rgb_gain, 0);
    } else {
        assert_int_equal(m->cal_unit_hours, 6);
        assert_int_equal(m->has_rgb_offset, v->has_rgb_offset);
        assert_int_equal(m->has_rgb_gain, v->has_rgb_gain);
        for (i = 0; i < 3; i++) {
            assert_int_equal(m->rgb_offset[i], v->rgb_offset[i]);
            assert_int_equal(m->rgb_gain[i], v->rgb_gain[i]);
        }
        assert_int_equal(m->opamp_offset, 0);
        assert_int_equal(m->map_version, 0);
    }
}

/* the records, listed: the description's field_cals (hours, value, addr) */
static void check_cal_list(const vec_map_t *v, unsigned unit)
{
    twh_cal_t cur, list[16];
    unsigned i, j, prev = 0;
    uint16_t n;

    memset(list, 0xA5, sizeof(list));
    n = twh_cal_scan(v->words, v->n_words, &cur, list, 16);
    assert_int_equal(n, v->n_field_cals);
    for (i = 0; i < n; i++) {
        assert_true(list[i].addr > prev);            /* address order */
        prev = list[i].addr;
        for (j = 0; j < v->n_field_cals && v->field_cals[j][0] != list[i].addr; j++)
            ;
        assert_true(j < v->n_field_cals);
        assert_int_equal(list[i].stamp * unit, v->field_cals[j][1]);
        assert_int_equal(list[i].value, v->field_cals[j][2]);
    }
    /* max limits what is written, not the count */
    memset(list, 0xA5, sizeof(list));
    assert_int_equal(twh_cal_scan(v->words, v->n_words, &cur, list, 1), n);
    if (n > 1)
        assert_int_equal(list[1].addr, 0xA5A5);
}

static void test_vec_maps(void **state)
{
    size_t i;

    (void)state;
    assert_int_equal(VEC_COUNT(vec_maps), 4);
    for (i = 0; i < VEC_COUNT(vec_maps); i++) {
        twh_map_t m;
        twh_cal_t cur;

        memset(&m, 0xA5, sizeof(m));
        assert_int_equal(twh_decode_map(vec_maps[i].words, vec_maps[i].n_words,
                                        (uint8_t)vec_maps[i].kind, &m), TWH_OK);
        check_map(&m, &vec_maps[i]);
        assert_int_equal(twh_cal_scan(vec_maps[i].words, vec_maps[i].n_words, &cur, NULL, 0),
                         vec_maps[i].calibration_count);
        assert_int_equal(cur.addr, vec_maps[i].cur_addr);
        check_cal_list(&vec_maps[i], m.cal_unit_hours);
    }
}

/* the same images, read from the (fake) device word by word */
static void test_vec_maps_from_device(void **state)
{
    size_t i;
    static uint16_t img[512];

    for (i = 0; i < VEC_COUNT(vec_maps); i++) {
        twh_map_t m;

        fake_dev_setup(&E->f.dev[1], 0x26, 2, vec_maps[i].words, vec_maps[i].n_words);
        assert_int_equal(twh_read_image(&E->t, 1, img, vec_maps[i].n_words), TWH_OK);
        assert_memory_equal(img, vec_maps[i].words, vec_maps[i].n_words * 2u);
        assert_int_equal(twh_decode_map(img, vec_maps[i].n_words, (uint8_t)vec_maps[i].kind, &m),
                         TWH_OK);
        check_map(&m, &vec_maps[i]);
    }
}

static void test_vec_text(void **state)
{
    size_t i;

    (void)state;
    for (i = 0; i < VEC_COUNT(vec_text); i++) {
        char out[17];

        memset(out, 'x', sizeof(out));
        twh_decode_text(vec_text[i].words, vec_text[i].n_words, out);
        assert_string_equal(out, vec_text[i].text);
    }
}

static void test_vec_datetime(void **state)
{
    size_t i;

    (void)state;
    for (i = 0; i < VEC_COUNT(vec_datetime); i++) {
        twh_datetime_t dt;
        int rc = twh_decode_datetime(vec_datetime[i].w0, vec_datetime[i].w1, &dt);

        assert_int_equal(rc, vec_datetime[i].valid ? TWH_OK : TWH_ERR_RANGE);
        check_dt(&dt, &vec_datetime[i].dt);  /* null: all zero */
    }
}

static void test_vec_s14(void **state)
{
    size_t i;

    (void)state;
    for (i = 0; i < VEC_COUNT(vec_s14); i++)
        assert_int_equal(twh_s14(vec_s14[i].word), vec_s14[i].value);
}

static void test_vec_calcases(void **state)
{
    size_t i;
    unsigned j;

    (void)state;
    for (i = 0; i < VEC_COUNT(vec_calcases); i++) {
        const vec_calcase_t *v = &vec_calcases[i];
        uint16_t w[512];
        twh_cal_t cur;

        blank_image(w, v->size);
        for (j = 0; j < v->n_pairs; j++) {
            w[v->pairs[j][0]] = v->pairs[j][1];
            w[v->pairs[j][0] + 1] = v->pairs[j][2];
        }
        assert_int_equal(twh_cal_scan(w, v->size, &cur, NULL, 0), v->count);
        if (v->has_current) {
            assert_int_equal(cur.addr, v->cur_addr);
            assert_int_equal(cur.stamp, v->cur_stamp);
            assert_int_equal(cur.value, v->cur_value);
        } else {
            assert_int_equal(cur.addr, 0);
        }
    }
}

/* ================================================================ decoding */
static void test_datetime_rules(void **state)
{
    static const struct { unsigned y, mo, d, h, mi; int ok; } c[] = {
        {2024, 2, 29, 0, 0, 1}, {2023, 2, 29, 0, 0, 0}, {2100, 2, 29, 0, 0, 0},
        {2000, 2, 29, 0, 0, 1}, {2100, 2, 28, 23, 59, 1}, {2017, 4, 31, 0, 0, 0},
        {2017, 4, 30, 0, 0, 1}, {2017, 12, 31, 24, 0, 0}, {2017, 12, 31, 0, 60, 0},
        {2017, 0, 1, 0, 0, 0}, {2017, 13, 1, 0, 0, 0}, {2017, 1, 0, 0, 0, 0},
        {2127, 1, 31, 0, 0, 1},
    };
    size_t i;

    (void)state;
    for (i = 0; i < sizeof(c) / sizeof(c[0]); i++) {
        uint32_t v = c[i].mi << 21 | (c[i].y - 2000) << 14 | c[i].mo << 10 | c[i].d << 5 | c[i].h;
        twh_datetime_t dt;
        int rc = twh_decode_datetime((uint16_t)(v >> 14), (uint16_t)(v & 0x3FFF), &dt);

        assert_int_equal(rc, c[i].ok ? TWH_OK : TWH_ERR_RANGE);
        assert_int_equal(dt.year, c[i].ok ? c[i].y : 0);
    }
}

static void test_text_rules(void **state)
{
    uint16_t w[3] = {('A' << 7) | 'B', TWH_BLANK, ('C' << 7) | 'D'};
    uint16_t pad[2] = {(' ' << 7) | ' ', 0};
    char out[8];

    (void)state;
    twh_decode_text(w, 3, out);       /* a blank word ends the text */
    assert_string_equal(out, "AB");
    twh_decode_text(pad, 2, out);     /* padding only */
    assert_string_equal(out, "");
    w[0] = TWH_BLANK;
    twh_decode_text(w, 3, out);       /* unprogrammed field */
    assert_string_equal(out, "");
    twh_decode_text(w, 0, out);
    assert_string_equal(out, "");
}

static void test_conversion_edges(void **state)
{
    int32_t t = 0;

    (void)state;
    /* a result that does not fit int32 is refused, not wrapped */
    assert_int_equal(twh_temperature_c100(4095, 2500, 0, INT32_MAX, 1, &t), TWH_ERR_RANGE);
    assert_int_equal(twh_temperature_c100(0, 0, 4095, INT32_MAX, 1, &t), TWH_ERR_RANGE);
    assert_int_equal(twh_temperature_c100(2000, 2500, 2000, -5, 7800, &t), TWH_ERR_RANGE);
    assert_int_equal(twh_temperature_c100(2000, 99, 2000, 3000, 7800, &t), TWH_OK);
    assert_int_equal(t, 9900);
    assert_int_equal(twh_temperature_c100(2000, 100, 2000, 3000, 7800, &t), TWH_OK);
    assert_int_equal(t, 100);
    assert_int_equal(twh_ppo2_mbar(65535, 65535), (int32_t)((65535ull * 65535 * 1000) >> 22));
    assert_int_equal(twh_o2_mv100(65535, -32768), 297886 - 32768);
}

static void test_decode_map_args(void **state)
{
    uint16_t w[0x20];
    twh_map_t m;

    (void)state;
    blank_image(w, 0x20);
    assert_int_equal(twh_decode_map(w, 0x1F, TWH_MAP_O2, &m), TWH_ERR_BAD_ARG);
    assert_int_equal(twh_decode_map(w, 0x201, TWH_MAP_O2, &m), TWH_ERR_BAD_ARG);
    assert_int_equal(twh_decode_map(w, 0x20, 0, &m), TWH_ERR_BAD_ARG);
    assert_int_equal(twh_decode_map(w, 0x20, 3, &m), TWH_ERR_BAD_ARG);
    /* a blank factory area: empty texts, no dates, no records */
    assert_int_equal(twh_decode_map(w, 0x20, TWH_MAP_CO2, &m), TWH_OK);
    assert_string_equal(m.model, "");
    assert_int_equal(m.manufactured.year, 0);
    assert_int_equal(m.cal_count, 0);
    assert_int_equal(m.has_rgb_gain, 0);
}

/* ================================================================ core access */
static void test_init_probe(void **state)
{
    twh_t t;
    twh_platform_t p = E->p;

    assert_int_equal(E->t.channels, 2);
    assert_int_equal(E->t.fifo_depth, 8);
    assert_int_equal(E->t.clk_khz, 48000);
    assert_int_equal(E->t.version_major, 2);
    assert_int_equal(E->t.timeout_us, TWH_TIMEOUT_US_DEFAULT);
    assert_int_equal(twh_sizeof(), sizeof(twh_t));
    /* without wait_irq the driver leaves IRQ_EN alone */
    assert_int_equal(E->f.irq_en & TWH_REGS__IRQ_EN__RESULT_bm, 0);

    E->f.id = 0x54574832;
    assert_int_equal(twh_init(&t, &p), TWH_ERR_BAD_ID);
    assert_int_equal(t.channels, 0);
    assert_int_equal(twh_submit(&t, 0, 0x41, 0xAA), TWH_ERR_BAD_ARG);
    E->f.id = TWH_MAGIC;
    /* map version 2 only: a version 1 core (8 channels at most, one
     * CMD_PUSH at 0x28) or a later one is refused */
    E->f.major = 1;
    assert_int_equal(twh_init(&t, &p), TWH_ERR_BAD_ID);
    assert_int_equal(t.channels, 0);
    E->f.major = 3;
    assert_int_equal(twh_init(&t, &p), TWH_ERR_BAD_ID);
    E->f.major = 2;
    /* VERSION.CHANNELS is 6 bits: 1-32 are accepted, 0 and 33-63 refused */
    E->f.channels = 0;
    assert_int_equal(twh_init(&t, &p), TWH_ERR_BAD_ID);
    E->f.channels = 33;
    assert_int_equal(twh_init(&t, &p), TWH_ERR_BAD_ID);
    assert_int_equal(t.channels, 0);
    assert_int_equal(twh_submit(&t, 0, 0x41, 0xAA), TWH_ERR_BAD_ARG);
    assert_int_equal(twh_set_idle_charge(&t, 0), TWH_ERR_BAD_ARG);
    E->f.channels = 63;
    assert_int_equal(twh_init(&t, &p), TWH_ERR_BAD_ID);
    E->f.channels = 9;                    /* more than version 1 had */
    assert_int_equal(twh_init(&t, &p), TWH_OK);
    assert_int_equal(t.channels, 9);
    E->f.channels = 32;
    assert_int_equal(twh_init(&t, &p), TWH_OK);
    assert_int_equal(t.channels, 32);
    E->f.channels = 1;
    assert_int_equal(twh_init(&t, &p), TWH_OK);
    assert_int_equal(t.channels, 1);
    E->f.channels = 2;
    E->f.depth = 0;
    assert_int_equal(twh_init(&t, &p), TWH_ERR_BAD_ID);
    E->f.depth = 8;
    assert_int_equal(twh_init(&t, &p), TWH_OK);
    assert_int_equal(twh_init(NULL, &p), TWH_ERR_BAD_ARG);
    assert_int_equal(twh_init(&t, NULL), TWH_ERR_BAD_ARG);
    p.read32 = NULL;
    assert_int_equal(twh_init(&t, &p), TWH_ERR_BAD_ARG);
    p = E->p;
    p.write32 = NULL;
    assert_int_equal(twh_init(&t, &p), TWH_ERR_BAD_ARG);
    p = E->p;
    p.delay_us = NULL;
    assert_int_equal(twh_init(&t, &p), TWH_ERR_BAD_ARG);
    assert_int_equal(E->f.n_pushed, 0);
}

static void test_submit_result(void **state)
{
    twh_result_t r;
    int tag, i;

    assert_int_equal(twh_result(&E->t, &r), TWH_ERR_AGAIN);
    assert_int_equal(twh_poll(&E->t), 0);
    tag = twh_submit(&E->t, 0, TWH_CMD_FIRMWARE, 0xAA);
    assert_int_equal(tag, 0);
    assert_int_equal(twh_poll(&E->t), 0);
    assert_int_equal(twh_result(&E->t, &r), TWH_ERR_AGAIN);
    fake_step(&E->f);
    assert_int_equal(twh_poll(&E->t), 1);
    assert_int_equal(twh_result(&E->t, &r), TWH_OK);
    assert_int_equal(r.cmd, TWH_CMD_FIRMWARE);
    assert_int_equal(r.status, TWH_ST_OK);
    assert_int_equal(r.channel, 0);
    assert_int_equal(r.tag, 0);
    assert_int_equal(r.data, 0x1201);
    assert_int_equal(twh_status_err(r.status, r.cmd), TWH_OK);
    assert_int_equal(twh_result(&E->t, &r), TWH_ERR_AGAIN);
    /* tags count up and wrap at 32 */
    for (i = 1; i < 40; i++) {
        tag = twh_submit(&E->t, 1, TWH_CMD_CONFIG, 0xAA);
        assert_int_equal(tag, i & 31);
        fake_step(&E->f);
        assert_int_equal(twh_result(&E->t, &r), TWH_OK);
        assert_int_equal(r.tag, i & 31);
        assert_int_equal(r.channel, 1);
        assert_int_equal(r.data, 240);
    }
}

static void test_submit_bad_channel(void **state)
{
    assert_int_equal(twh_submit(&E->t, 2, TWH_CMD_FIRMWARE, 0xAA), TWH_ERR_BAD_ARG);
    assert_int_equal(twh_submit(&E->t, 7, TWH_CMD_FIRMWARE, 0xAA), TWH_ERR_BAD_ARG);
    assert_int_equal(twh_firmware(&E->t, 2, NULL), TWH_ERR_BAD_ARG);
    assert_int_equal(twh_set_execute_us(&E->t, 2, 4000), TWH_ERR_BAD_ARG);
    assert_int_equal(E->f.n_pushed, 0);
    assert_int_equal(E->f.writes, 0);
}

static void test_submit_refuses_factory_area(void **state)
{
    unsigned a;

    for (a = 0; a < 0x20; a++) {
        uint8_t cmd;
        uint16_t payload;

        assert_int_equal(twh_submit(&E->t, 0, TWH_CMD_ERASE, (uint16_t)a), TWH_ERR_BAD_ARG);
        assert_int_equal(twh_submit(&E->t, 0, TWH_CMD_ERASE, (uint16_t)(0xFF00 | a)),
                         TWH_ERR_BAD_ARG);   /* payload MSB is not sent */
        assert_int_equal(twh_encode_write((uint16_t)a, 0x1234, &cmd, &payload), TWH_OK);
        assert_int_equal(twh_submit(&E->t, 0, cmd, payload), TWH_ERR_BAD_ARG);
        assert_int_equal(twh_write_word(&E->t, 0, (uint16_t)a, 0x1234), TWH_ERR_BAD_ARG);
        assert_int_equal(twh_erase_page(&E->t, 0, (uint16_t)a), TWH_ERR_BAD_ARG);
    }
    assert_int_equal(E->f.n_pushed, 0);
    assert_int_equal(E->f.writes, 0);
    /* 0x20, 0x100 (erase 0x4B 0x00) and 0x80 (write 0x80 with bits 15:14 = 1) are not */
    assert_int_equal(twh_submit(&E->t, 0, TWH_CMD_ERASE, 0x20), 0);
    assert_int_equal(twh_submit(&E->t, 0, TWH_CMD_ERASE | 1, 0x00), 1);
    assert_int_equal(twh_submit(&E->t, 0, 0x80, 0x4000 | 0x1234), 2);
    assert_int_equal(E->f.n_pushed, 3);
}

static void test_fifo_full(void **state)
{
    int i;

    E->f.stall = 1;
    for (i = 0; i < 8; i++)
        assert_int_equal(twh_submit(&E->t, i & 1, TWH_CMD_CONFIG, 0xAA), i);
    assert_int_equal(twh_submit(&E->t, 0, TWH_CMD_CONFIG, 0xAA), TWH_ERR_FIFO_FULL);
    assert_int_equal(twh_read_word(&E->t, 0, 0x20, NULL), TWH_ERR_FIFO_FULL);
    assert_int_equal(E->f.n_pushed, 8);
    /* the tag was not used up by the refused pushes */
    E->f.stall = 0;
    fake_step(&E->f);
    assert_int_equal(twh_submit(&E->t, 0, TWH_CMD_CONFIG, 0xAA), 8);
}

static void test_timeout_polling(void **state)
{
    uint16_t w = 0x1111;

    E->f.stall = 1;
    E->t.timeout_us = 50000;
    E->t.poll_us = 2000;
    assert_int_equal(twh_read_word(&E->t, 0, 0x20, &w), TWH_ERR_TIMEOUT);
    assert_int_equal(w, 0x1111);
    assert_int_equal(E->f.delays, 25);
    assert_true(E->f.now_us >= 50000);
    /* poll_us 0 still ends */
    E->t.poll_us = 0;
    E->t.timeout_us = 10;
    assert_int_equal(twh_read_word(&E->t, 0, 0x20, &w), TWH_ERR_TIMEOUT);
    /* the late result is not lost: it comes out of twh_result */
    E->f.stall = 0;
    fake_run(&E->f);
    assert_int_equal(twh_poll(&E->t), 2);
}

static void test_wait_irq(void **state)
{
    uint16_t w = 0;

    assert_int_equal(E->f.irq_en & TWH_REGS__IRQ_EN__RESULT_bm, TWH_REGS__IRQ_EN__RESULT_bm);
    assert_int_equal(E->f.irq_en & TWH_REGS__IRQ_EN__RES_THRESHOLD_bm,
                     1u << TWH_REGS__IRQ_EN__RES_THRESHOLD_bp);
    assert_int_equal(twh_read_word(&E->t, 0, 0x16, &w), TWH_OK);
    assert_int_equal(w, 7800);
    assert_int_equal(E->f.delays, 0);
    assert_int_equal(E->f.irq_waits, 1);
    E->f.stall = 1;
    E->t.timeout_us = 300000;
    assert_int_equal(twh_read_word(&E->t, 0, 0x16, &w), TWH_ERR_TIMEOUT);
    assert_int_equal(E->f.irq_waits, 2);   /* one wait for the whole remaining time */
    assert_int_equal(E->f.delays, 0);
}

static void test_status_mapping(void **state)
{
    static const int want[16] = {
        TWH_OK, TWH_ERR_NO_RESPONSE, TWH_ERR_CHECKSUM, TWH_ERR_FRAMING, TWH_ERR_SHORT,
        TWH_ERR_STUCK_LOW, TWH_ERR_STUCK_HIGH, TWH_ERR_BLOCKED, TWH_ERR_CANCELLED,
        TWH_ERR_HW_STATUS, TWH_ERR_HW_STATUS, TWH_ERR_HW_STATUS, TWH_ERR_HW_STATUS,
        TWH_ERR_HW_STATUS, TWH_ERR_HW_STATUS, TWH_ERR_HW_STATUS,
    };
    unsigned s;

    for (s = 0; s < 16; s++) {
        uint16_t w = 0x5555;
        int rc;

        /* a command that expects an answer */
        fake_script(&E->f, 0, -1, (uint8_t)s, 0x0123);
        rc = twh_read_word(&E->t, 0, 0x20, &w);
        assert_int_equal(rc, want[s]);
        assert_int_equal(w, s == 0 ? 0x0123 : 0x5555);   /* output only on success */
        assert_int_equal(twh_status_err((uint8_t)s, TWH_CMD_READ), want[s]);
        /* erase, write and reserved commands: no response is success */
        fake_script(&E->f, 0, -1, (uint8_t)s, 0);
        rc = twh_erase_page(&E->t, 0, 0x20);
        assert_int_equal(rc, s == 1 ? TWH_OK : want[s]);
        assert_int_equal(twh_status_err((uint8_t)s, 0xA0), s == 1 ? TWH_OK : want[s]);
        assert_int_equal(twh_status_err((uint8_t)s, 0x45), s == 1 ? TWH_OK : want[s]);
        assert_int_equal(twh_status_err((uint8_t)s, 0x4B), s == 1 ? TWH_OK : want[s]);
    }
    /* a write whose write fails on the link is not verified as good */
    fake_script(&E->f, 0, -1, TWH_ST_LINE_STUCK_LOW, 0);
    assert_int_equal(twh_write_word(&E->t, 0, 0x40, 0x0100), TWH_ERR_STUCK_LOW);
    /* a write answered "no response" is read back */
    fake_script(&E->f, 0, -1, TWH_ST_NO_RESPONSE, 0);
    fake_script(&E->f, 0, -1, TWH_ST_FRAMING, 0);
    assert_int_equal(twh_write_word(&E->t, 0, 0x40, 0x0100), TWH_ERR_FRAMING);
}

static void test_blocked_by_core(void **state)
{
    uint8_t cmd;
    uint16_t payload;

    /* the driver refuses factory commands itself, but a BLOCKED result from
     * the core (e.g. pushed by other software) still maps */
    assert_int_equal(twh_encode_write(0x05, 0x1234, &cmd, &payload), TWH_OK);
    fake_script(&E->f, 0, -1, TWH_ST_BLOCKED, 0);
    assert_int_equal(twh_xfer(&E->t, 0, TWH_CMD_CONFIG, 0xAA, NULL), TWH_ERR_BLOCKED);
}

static void test_stash_keeps_other_results(void **state)
{
    twh_result_t r;
    uint16_t w = 0;
    int t1, t2;

    /* two non-blocking commands queued before the blocking read */
    t1 = twh_submit(&E->t, 1, TWH_CMD_FIRMWARE, 0xAA);
    t2 = twh_submit(&E->t, 0, TWH_CMD_O2_VOLTAGE, 0xAA);
    assert_int_equal(twh_read_word(&E->t, 0, 0x17, &w), TWH_OK);
    assert_int_equal(w, 2500);
    assert_int_equal(E->t.stash_count, 2);
    assert_int_equal(twh_poll(&E->t), 2);
    assert_int_equal(twh_result(&E->t, &r), TWH_OK);
    assert_int_equal(r.tag, t1);
    assert_int_equal(r.channel, 1);
    assert_int_equal(r.data, 0x2602);
    assert_int_equal(twh_result(&E->t, &r), TWH_OK);
    assert_int_equal(r.tag, t2);
    assert_int_equal(r.cmd, TWH_CMD_O2_VOLTAGE);
    assert_int_equal(r.data, 239);
    assert_int_equal(twh_result(&E->t, &r), TWH_ERR_AGAIN);
}

static void test_stash_full_loses_nothing(void **state)
{
    twh_result_t r;
    uint16_t w = 0;
    int tags[TWH_STASH_SIZE + 1], i, n;

    for (i = 0; i < TWH_STASH_SIZE + 1; i++)
        tags[i] = twh_submit(&E->t, 1, TWH_CMD_CONFIG, 0xAA);
    assert_int_equal(twh_read_word(&E->t, 0, 0x17, NULL), TWH_ERR_STASH_FULL);
    assert_int_equal(E->t.stash_count, TWH_STASH_SIZE);
    /* drain: every result comes out in order, the read's own last */
    fake_run(&E->f);
    for (i = 0; i < TWH_STASH_SIZE + 1; i++) {
        assert_int_equal(twh_result(&E->t, &r), TWH_OK);
        assert_int_equal(r.tag, tags[i]);
        assert_int_equal(r.data, 240);
    }
    assert_int_equal(twh_result(&E->t, &r), TWH_OK);
    assert_int_equal(r.cmd, TWH_CMD_READ);
    assert_int_equal(r.data, 2500);
    assert_int_equal(twh_result(&E->t, &r), TWH_ERR_AGAIN);
    /* and a blocking call works again */
    n = twh_read_word(&E->t, 0, 0x17, &w);
    assert_int_equal(n, TWH_OK);
    assert_int_equal(w, 2500);
}

/* the stash is a ring: fill, drain part, refill across the wrap */
static void test_stash_ring_wraps(void **state)
{
    twh_result_t r;
    uint16_t w = 0;
    int tags[6], i;

    tags[0] = twh_submit(&E->t, 1, TWH_CMD_CONFIG, 0xAA);
    tags[1] = twh_submit(&E->t, 1, TWH_CMD_FIRMWARE, 0xAA);
    assert_int_equal(twh_read_word(&E->t, 0, 0x16, &w), TWH_OK);
    assert_int_equal(twh_result(&E->t, &r), TWH_OK);
    assert_int_equal(r.tag, tags[0]);
    for (i = 2; i < 5; i++)
        tags[i] = twh_submit(&E->t, 1, TWH_CMD_REF_VOLTAGE, 0xAA);
    assert_int_equal(twh_read_word(&E->t, 0, 0x17, &w), TWH_OK);
    assert_int_equal(w, 2500);
    assert_int_equal(E->t.stash_count, 4);
    assert_int_equal(twh_poll(&E->t), 4);
    for (i = 1; i < 5; i++) {
        assert_int_equal(twh_result(&E->t, &r), TWH_OK);
        assert_int_equal(r.tag, tags[i]);
        assert_int_equal(r.data, i == 1 ? 0x2602 : 1353);
    }
    assert_int_equal(twh_result(&E->t, &r), TWH_ERR_AGAIN);
}

static void test_same_tag_other_channel_or_cmd(void **state)
{
    twh_result_t r;
    uint16_t w = 0;

    /* a result with the tag the blocking call will get but another channel:
     * tags are shared, so force it by pushing a foreign result first */
    E->f.resq[0].cmd = TWH_CMD_READ;
    E->f.resq[0].status = TWH_ST_OK;
    E->f.resq[0].ch = 1;
    E->f.resq[0].tag = 0;
    E->f.resq[0].data = 0x0BAD;
    E->f.resq[1] = E->f.resq[0];
    E->f.resq[1].ch = 0;
    E->f.resq[1].cmd = TWH_CMD_CONFIG;   /* same channel and tag, other command */
    E->f.res_n = 2;
    assert_int_equal(twh_read_word(&E->t, 0, 0x16, &w), TWH_OK);
    assert_int_equal(w, 7800);
    assert_int_equal(twh_result(&E->t, &r), TWH_OK);
    assert_int_equal(r.data, 0x0BAD);
    assert_int_equal(twh_result(&E->t, &r), TWH_OK);
    assert_int_equal(r.cmd, TWH_CMD_CONFIG);
}

static void test_res_pop_mismatch(void **state)
{
    twh_result_t r;

    E->f.corrupt_next_pop = 1;
    assert_int_equal(twh_read_word(&E->t, 0, 0x16, NULL), TWH_ERR_BUS);
    assert_int_equal(twh_submit(&E->t, 0, TWH_CMD_CONFIG, 0xAA), 1);
    fake_step(&E->f);
    E->f.corrupt_next_pop = 1;
    memset(&r, 0xA5, sizeof r);
    assert_int_equal(twh_result(&E->t, &r), TWH_ERR_BUS);
    /* found by fuzzing (sw/fuzz/regress/result/result_bus_writes_r.bin):
     * *r was filled before the check */
    assert_int_equal(r.cmd, 0xA5);
    assert_int_equal(r.status, 0xA5);
    assert_int_equal(r.tag, 0xA5);
    assert_int_equal(r.data, 0xA5A5);
}

/* found by fuzzing (xfer_data_on_error.bin in sw/fuzz/regress): twh_xfer
 * handed a bad answer's data to the caller along with the error */
static void test_xfer_no_data_on_error(void **state)
{
    uint16_t d = 0x5555;

    fake_script(&E->f, 0, -1, TWH_ST_BAD_CHECKSUM, 0x1234);
    assert_int_equal(twh_xfer(&E->t, 0, TWH_CMD_CONFIG, 0xAA, &d), TWH_ERR_CHECKSUM);
    assert_int_equal(d, 0x5555);
    fake_script(&E->f, 0, -1, TWH_ST_OK, 0x1234);
    assert_int_equal(twh_xfer(&E->t, 0, TWH_CMD_CONFIG, 0xAA, &d), TWH_OK);
    assert_int_equal(d, 0x1234);
}

static void test_cancel_all(void **state)
{
    twh_result_t r;
    int i;

    E->f.stall = 1;
    for (i = 0; i < 3; i++)
        assert_int_equal(twh_submit(&E->t, 0, TWH_CMD_O2_VOLTAGE, 0xAA), i);
    assert_int_equal(twh_cancel_all(&E->t), TWH_OK);
    assert_int_equal(E->f.ctrl & TWH_REGS__CTRL__ENABLE_bm, TWH_REGS__CTRL__ENABLE_bm);
    for (i = 0; i < 3; i++) {
        assert_int_equal(twh_result(&E->t, &r), TWH_OK);
        assert_int_equal(r.tag, i);
        assert_int_equal(r.status, TWH_ST_CANCELLED);
        assert_int_equal(twh_status_err(r.status, r.cmd), TWH_ERR_CANCELLED);
    }
}

/* ============================================= map version 2: 1-32 channels */
#define CMD_PUSH_OFF(ch)                                                         \
    ((uint32_t)(offsetof(twh_regs_t, CH) + (ch) * sizeof(twh_regs__channel_t__stride20_t) + \
                offsetof(twh_regs__channel_t__stride20_t, CMD_PUSH)))

static int setup32(void **state)
{
    env_t *e = env_new(32, 16, 0);

    /* ch31: the CO2 v26 cell, ch15 and ch20: O2 v18 (ch0 and ch1 as usual) */
    fake_dev_setup(&e->f.dev[31], 0x26, TWH_TYPE_CO2, vec_maps[2].words, vec_maps[2].n_words);
    fake_dev_setup(&e->f.dev[15], 0x12, TWH_TYPE_O2, vec_maps[0].words, vec_maps[0].n_words);
    fake_dev_setup(&e->f.dev[20], 0x12, TWH_TYPE_O2, vec_maps[0].words, vec_maps[0].n_words);
    *state = e;
    return 0;
}

static int setup16(void **state)
{
    *state = env_new(16, 8, 1);
    return 0;
}

static int setup21(void **state)
{
    *state = env_new(21, 8, 0);
    return 0;
}

/* the register map's layout the driver relies on */
static void test_v2_layout(void **state)
{
    (void)state;
    assert_int_equal(TWH_REGS__VERSION__MAJOR_reset, 2);
    assert_int_equal(offsetof(twh_regs_t, IDLE_CHARGE), 0x3C);
    assert_int_equal(offsetof(twh_regs_t, BUSY), 0x40);
    assert_int_equal(offsetof(twh_regs_t, CH), 0x80);
    assert_int_equal(sizeof(twh_regs__channel_t__stride20_t), 0x20);
    assert_int_equal(sizeof(((twh_regs_t *)0)->CH) / sizeof(twh_regs__channel_t__stride20_t),
                     TWH_MAX_CHANNELS);
    assert_int_equal(CMD_PUSH_OFF(0), 0x98);
    assert_int_equal(CMD_PUSH_OFF(31), 0x478);
}

/* A 32-channel core: a command on channel 31 goes to CH[31].CMD_PUSH and
 * its result comes back carrying channel 31 (5-bit channel fields). */
static void test_ch32_submit_result(void **state)
{
    twh_result_t r;
    twh_fw_t fw;
    uint16_t w = 0;
    int tag;

    assert_int_equal(E->t.channels, 32);
    tag = twh_submit(&E->t, 31, TWH_CMD_FIRMWARE, 0xAA);
    assert_int_equal(tag, 0);
    assert_int_equal(E->f.n_pushed, 1);
    assert_int_equal(E->f.pushed[0].ch, 31);
    assert_int_equal(E->f.pushed[0].cmd, TWH_CMD_FIRMWARE);
    assert_int_equal(E->f.pushed[0].payload, 0xAA);
    assert_int_equal(E->f.pushed[0].tag, 0);
    fake_step(&E->f);
    assert_int_equal(twh_result(&E->t, &r), TWH_OK);
    assert_int_equal(r.channel, 31);
    assert_int_equal(r.tag, 0);
    assert_int_equal(r.cmd, TWH_CMD_FIRMWARE);
    assert_int_equal(r.data, 0x2602);
    /* the blocking helpers on channel 31, and its timing block */
    assert_int_equal(twh_firmware(&E->t, 31, &fw), TWH_OK);
    assert_int_equal(fw.version, 26);
    assert_int_equal(fw.type, TWH_TYPE_CO2);
    assert_int_equal(twh_read_word(&E->t, 31, 0x16, &w), TWH_OK);
    assert_int_equal(w, vec_maps[2].words[0x16]);
    assert_int_equal(twh_negotiate(&E->t, 31, &fw), TWH_OK);
    assert_int_equal((E->f.timing[31][1] & TWH_REGS__CHANNEL_T__TIMING1__EXECUTE_US_bm) >>
                         TWH_REGS__CHANNEL_T__TIMING1__EXECUTE_US_bp, TWH_EXECUTE_RECOMMENDED_US);
    assert_int_equal(E->f.timing[30][1], E->f.timing[0][1]);     /* no other block */
    /* every pushed command went to the block of the channel asked for */
    assert_int_equal(E->f.pushed[E->f.n_pushed - 1].ch, 31);
    assert_int_equal(twh_submit(&E->t, 32, TWH_CMD_FIRMWARE, 0xAA), TWH_ERR_BAD_ARG);
    assert_int_equal(twh_set_execute_us(&E->t, 32, 4000), TWH_ERR_BAD_ARG);
}

/* Results of channels that a 3-bit channel field would alias (31, 15, 7)
 * are told apart: a blocking call on channel 31 takes only its own. */
static void test_ch32_results_apart(void **state)
{
    twh_result_t r;
    uint16_t w = 0;
    int i;

    /* results with the tag and command the blocking call will use, on
     * channels 15 and 7, queued before its own */
    for (i = 0; i < 2; i++) {
        E->f.resq[i].cmd = TWH_CMD_READ;
        E->f.resq[i].status = TWH_ST_OK;
        E->f.resq[i].ch = i ? 7 : 15;
        E->f.resq[i].tag = 0;
        E->f.resq[i].data = (uint16_t)(0x0BA0 + i);
    }
    E->f.res_n = 2;
    assert_int_equal(twh_read_word(&E->t, 31, 0x16, &w), TWH_OK);
    assert_int_equal(w, vec_maps[2].words[0x16]);
    assert_int_equal(E->t.stash_count, 2);
    assert_int_equal(twh_result(&E->t, &r), TWH_OK);
    assert_int_equal(r.channel, 15);
    assert_int_equal(r.data, 0x0BA0);
    assert_int_equal(twh_result(&E->t, &r), TWH_OK);
    assert_int_equal(r.channel, 7);
    assert_int_equal(r.data, 0x0BA1);
    /* non-blocking traffic on every channel: each result names its own */
    E->f.stall = 1;
    for (i = 0; i < 16; i++)
        assert_int_equal(twh_submit(&E->t, (uint8_t)(31 - i), TWH_CMD_CONFIG, 0xAA), (i + 1) & 31);
    E->f.stall = 0;
    fake_run(&E->f);
    for (i = 0; i < 16; i++) {
        assert_int_equal(twh_result(&E->t, &r), TWH_OK);
        assert_int_equal(r.channel, 31 - i);
        assert_int_equal(r.tag, (i + 1) & 31);
    }
}

/* BUSY (0x40): bit n for channel n, up to bit 31 */
static void test_ch32_busy(void **state)
{
    assert_int_equal(twh_busy(&E->t), 0);
    E->f.stall = 1;
    assert_true(twh_submit(&E->t, 31, TWH_CMD_CONFIG, 0xAA) >= 0);
    assert_true(twh_submit(&E->t, 20, TWH_CMD_CONFIG, 0xAA) >= 0);
    assert_true(twh_submit(&E->t, 3, TWH_CMD_CONFIG, 0xAA) >= 0);
    assert_int_equal(twh_busy(&E->t), 0x80100008u);
    /* not STATUS: its bits 7:0 are no longer the channels' */
    assert_int_equal(fake_read32(&E->f, offsetof(twh_regs_t, STATUS)) & 0xFFu, 0);
    E->f.stall = 0;
    fake_step(&E->f);
    assert_int_equal(twh_busy(&E->t), 0x00100008u);
    fake_run(&E->f);
    assert_int_equal(twh_busy(&E->t), 0);
}

/* IDLE_CHARGE (0x3C), not CTRL[15:8]: channel 20's bit on a 32-channel core */
static void test_idle_charge_ch20(void **state)
{
    uint32_t ctrl = E->f.ctrl;

    assert_int_equal(twh_set_idle_charge(&E->t, 1u << 20), TWH_OK);
    assert_int_equal(E->f.idle_charge, 1u << 20);
    assert_int_equal(fake_read32(&E->f, offsetof(twh_regs_t, IDLE_CHARGE)), 1u << 20);
    assert_int_equal(E->f.ctrl, ctrl);
    assert_int_equal(twh_set_idle_charge(&E->t, 0x80000001u), TWH_OK);
    assert_int_equal(E->f.idle_charge, 0x80000001u);
    assert_int_equal(twh_set_idle_charge(&E->t, 0), TWH_OK);
    assert_int_equal(E->f.idle_charge, 0);
    /* a command on channel 20 runs as before */
    assert_int_equal(twh_set_idle_charge(&E->t, 1u << 20), TWH_OK);
    assert_int_equal(twh_config(&E->t, 20, NULL, NULL), TWH_OK);
    assert_int_equal(E->f.line[E->f.n_line - 1].ch, 20);
    assert_int_equal(E->f.idle_charge, 1u << 20);
}

/* 21 channels: channel 20 is the last one; bit 21 and up are refused by
 * the driver (nothing written) and ignored by the core */
static void test_idle_charge_ch20_last(void **state)
{
    unsigned writes;

    assert_int_equal(twh_set_idle_charge(&E->t, 1u << 20), TWH_OK);
    assert_int_equal(E->f.idle_charge, 1u << 20);
    writes = E->f.writes;
    assert_int_equal(twh_set_idle_charge(&E->t, 1u << 21), TWH_ERR_BAD_ARG);
    assert_int_equal(twh_set_idle_charge(&E->t, 0x80000000u | 1u << 20), TWH_ERR_BAD_ARG);
    assert_int_equal(E->f.writes, writes);
    assert_int_equal(E->f.idle_charge, 1u << 20);
    fake_write32(&E->f, offsetof(twh_regs_t, IDLE_CHARGE), 0xFFFFFFFFu);
    assert_int_equal(fake_read32(&E->f, offsetof(twh_regs_t, IDLE_CHARGE)), 0x001FFFFFu);
    assert_int_equal(twh_submit(&E->t, 20, TWH_CMD_FIRMWARE, 0xAA), 0);
    assert_int_equal(twh_submit(&E->t, 21, TWH_CMD_FIRMWARE, 0xAA), TWH_ERR_BAD_ARG);
    assert_int_equal(E->f.pushed[0].ch, 20);
}

/* A 16-channel core: channels 0-15, the blocks of 16-31 absent */
static void test_ch16(void **state)
{
    twh_fw_t fw;
    unsigned writes;

    assert_int_equal(E->t.channels, 16);
    fake_dev_setup(&E->f.dev[15], 0x12, TWH_TYPE_O2, vec_maps[0].words, vec_maps[0].n_words);
    assert_int_equal(twh_firmware(&E->t, 15, &fw), TWH_OK);
    assert_int_equal(fw.version, 18);
    assert_int_equal(E->f.pushed[0].ch, 15);
    assert_int_equal(twh_negotiate(&E->t, 15, &fw), TWH_OK);
    assert_int_equal(twh_set_idle_charge(&E->t, 0xFFFFu), TWH_OK);
    writes = E->f.writes;
    assert_int_equal(twh_submit(&E->t, 16, TWH_CMD_FIRMWARE, 0xAA), TWH_ERR_BAD_ARG);
    assert_int_equal(twh_firmware(&E->t, 31, &fw), TWH_ERR_BAD_ARG);
    assert_int_equal(twh_set_execute_us(&E->t, 16, 4000), TWH_ERR_BAD_ARG);
    assert_int_equal(twh_set_idle_charge(&E->t, 0x10000u), TWH_ERR_BAD_ARG);
    assert_int_equal(E->f.writes, writes);
    /* POLL_READY is 32 bits; absent channels' bits read 0 */
    E->f.poll_ready = 0xFFFFFFFFu;
    assert_int_equal(fake_read32(&E->f, offsetof(twh_regs_t, POLL_READY)), 0xFFFFu);
    assert_int_equal(twh_busy(&E->t), 0);
}

/* A push into an absent channel's block: bus error and ERRORS.BAD_CHANNEL,
 * nothing queued. The driver never does it (it refuses the channel); a
 * driver whose channel count is wrong would hit exactly that block. */
static void test_bad_channel_push(void **state)
{
    uint32_t word = TWH_CMD_FIRMWARE | 0xAAu << 8;

    assert_int_equal(twh_submit(&E->t, 16, TWH_CMD_FIRMWARE, 0xAA), TWH_ERR_BAD_ARG);
    assert_int_equal(E->f.errors, 0);
    E->t.channels = 17;                   /* the driver believes in channel 16 */
    assert_int_equal(twh_submit(&E->t, 16, TWH_CMD_FIRMWARE, 0xAA), 0);
    E->t.channels = 16;
    assert_int_equal(E->f.bus_errors, 1);
    assert_int_equal(E->f.last_bus_error, CMD_PUSH_OFF(16));
    assert_int_equal(E->f.errors, TWH_REGS__ERRORS__BAD_CHANNEL_bm);
    assert_int_equal(E->f.n_pushed, 0);
    assert_int_equal(E->f.cmd_n, 0);
    /* the last block and past it, too */
    fake_write32(&E->f, CMD_PUSH_OFF(31), word);
    assert_int_equal(E->f.bus_errors, 2);
    assert_int_equal(E->f.n_pushed, 0);
    /* the version 1 CMD_PUSH (0x28) is unmapped: a bus error, not a push,
     * and not BAD_CHANNEL */
    E->f.errors = 0;
    fake_write32(&E->f, 0x28, word);
    assert_int_equal(E->f.bus_errors, 3);
    assert_int_equal(E->f.last_bus_error, 0x28);
    (void)fake_read32(&E->f, 0x28);
    assert_int_equal(E->f.bus_errors, 4);
    assert_int_equal(E->f.errors, 0);
    assert_int_equal(E->f.n_pushed, 0);
    /* CMD_OVERFLOW as before: a present channel's push into a full FIFO */
    fake_write32(&E->f, CMD_PUSH_OFF(15), word);
    assert_int_equal(E->f.n_pushed, 1);
    assert_int_equal(E->f.pushed[0].ch, 15);
    E->f.bus_errors = 0;                  /* the teardown's check: the driver's own */
}

/* ================================================================ helpers */
static void test_helpers(void **state)
{
    uint8_t bits = 0;
    uint16_t v = 0, a = 0;
    twh_fw_t fw;

    E->f.dev[0].config_bits = 0x55;
    assert_int_equal(twh_config(&E->t, 0, &bits, &v), TWH_OK);
    assert_int_equal(bits, 0x55);
    assert_int_equal(v, 240);
    assert_int_equal(twh_config(&E->t, 0, NULL, NULL), TWH_OK);
    assert_int_equal(twh_firmware(&E->t, 1, &fw), TWH_OK);
    assert_int_equal(fw.version, 26);
    assert_int_equal(fw.encoding, TWH_FW_BCD);
    assert_int_equal(fw.type, TWH_TYPE_CO2);
    /* 12-bit readings: bits 15:12 are not part of them */
    E->f.dev[0].adc_ref = 0xF549;
    E->f.dev[0].adc_temp = 0x07D0;
    E->f.dev[0].adc_o2 = 0x10EF;
    assert_int_equal(twh_ref_voltage(&E->t, 0, &v), TWH_OK);
    assert_int_equal(v, 0x549);
    assert_int_equal(twh_temperature(&E->t, 0, &v), TWH_OK);
    assert_int_equal(v, 2000);
    assert_int_equal(twh_o2_voltage(&E->t, 0, &v), TWH_OK);
    assert_int_equal(v, 0xEF);
    /* flash words: 14 bits */
    fake_script(&E->f, 0, -1, TWH_ST_OK, 0xFFFF);
    assert_int_equal(twh_read_word(&E->t, 0, 0x30, &v), TWH_OK);
    assert_int_equal(v, 0x3FFF);
    /* find free: map 0 holds records at 0x20-0x23 and 0x30-0x35 */
    assert_int_equal(twh_find_free(&E->t, 0, 0x20, &a), TWH_OK);
    assert_int_equal(a, 0x24);
    assert_int_equal(twh_find_free(&E->t, 0, 0x30, &a), TWH_OK);
    assert_int_equal(a, 0x36);
    assert_int_equal(twh_find_free(&E->t, 0, 0x1EF, &a), TWH_ERR_NO_RESPONSE);
    assert_int_equal(twh_find_free(&E->t, 0, 0x200, &a), TWH_ERR_BAD_ARG);
    /* an answer below the start address or past 0x200 is impossible */
    fake_script(&E->f, 0, -1, TWH_ST_OK, 0x1F);
    assert_int_equal(twh_find_free(&E->t, 0, 0x20, &a), TWH_ERR_BAD_RESPONSE);
    fake_script(&E->f, 0, -1, TWH_ST_OK, 0x201);
    assert_int_equal(twh_find_free(&E->t, 0, 0x20, &a), TWH_ERR_BAD_RESPONSE);
    assert_int_equal(a, 0x36);
    /* addresses and data out of range */
    assert_int_equal(twh_read_word(&E->t, 0, 0x200, &v), TWH_ERR_BAD_ARG);
    assert_int_equal(twh_erase_page(&E->t, 0, 0x200), TWH_ERR_BAD_ARG);
    assert_int_equal(twh_write_word(&E->t, 0, 0x200, 1), TWH_ERR_BAD_ARG);
    assert_int_equal(twh_write_word(&E->t, 0, 0x40, 0x4000), TWH_ERR_BAD_ARG);
    assert_int_equal(twh_read_image(&E->t, 0, NULL, 0x201), TWH_ERR_BAD_ARG);
}

static void test_write_verify(void **state)
{
    uint16_t w = 0;

    assert_int_equal(twh_write_word(&E->t, 0, 0x40, 0x1234), TWH_OK);
    assert_int_equal(E->f.dev[0].flash[0x40], 0x1234);
    /* write-once: the same word again with other data */
    assert_int_equal(twh_write_word(&E->t, 0, 0x40, 0x0001), TWH_ERR_VERIFY);
    assert_int_equal(E->f.dev[0].flash[0x40], 0x1234);
    /* a device that ignores the write */
    E->f.dev[0].write_broken = 1;
    assert_int_equal(twh_write_word(&E->t, 0, 0x41, 0x0042), TWH_ERR_VERIFY);
    /* the read-back fails: that error, not OK */
    E->f.dev[0].write_broken = 0;
    fake_script(&E->f, 0, 0xC2, TWH_ST_NO_RESPONSE, 0);
    fake_script(&E->f, 0, TWH_CMD_READ, TWH_ST_BAD_CHECKSUM, 0x0042);
    assert_int_equal(twh_write_word(&E->t, 0, 0x42, 0x0042), TWH_ERR_CHECKSUM);
    (void)w;
}

/* ================================================================ timing */
static uint16_t execute_us(env_t *e, unsigned ch)
{
    return (uint16_t)((e->f.timing[ch][1] & TWH_REGS__CHANNEL_T__TIMING1__EXECUTE_US_bm) >>
                      TWH_REGS__CHANNEL_T__TIMING1__EXECUTE_US_bp);
}

static void negotiate_case(env_t *e, uint8_t fw_byte, uint16_t want_us, int want_version)
{
    twh_fw_t fw;
    unsigned n;

    e->f.dev[0].fw_byte = fw_byte;
    /* a previous device on the channel left 6 ms */
    assert_int_equal(twh_set_execute_us(&e->t, 0, 6000), TWH_OK);
    assert_int_equal(execute_us(e, 0), 6000);
    n = e->f.n_line;
    assert_int_equal(twh_negotiate(&e->t, 0, &fw), TWH_OK);
    assert_int_equal(fw.version, want_version);
    assert_int_equal(execute_us(e, 0), want_us);
    /* the version was asked at the safe 4 ms */
    assert_int_equal(e->f.n_line, n + 1);
    assert_int_equal(e->f.line[n].cmd, TWH_CMD_FIRMWARE);
    assert_int_equal(e->f.line[n].execute_us, TWH_EXECUTE_SAFE_US);
    /* preamble untouched */
    assert_int_equal(e->f.timing[0][1] & 0xFFFF, 2000);
}

/* A lean build (PROG_TIMING = 0): the driver sees VERSION.FIXED_TIMING,
 * asks the firmware at the fixed default execute phase and never writes a
 * timing register, so no VALUE_REFUSED is left behind. */
static void test_negotiate_fixed_timing(void **state)
{
    twh_fw_t fw;
    unsigned n;

    E->f.fixed_timing = 1;
    assert_int_equal(twh_init(&E->t, &E->p), TWH_OK);
    assert_int_equal(E->t.fixed_timing, 1);
    E->f.dev[0].fw_byte = 0x12;                 /* v18 would want 6 ms */
    n = E->f.n_line;
    assert_int_equal(twh_negotiate(&E->t, 0, &fw), TWH_OK);
    assert_int_equal(fw.version, 18);
    assert_int_equal(E->f.n_line, n + 1);
    assert_int_equal(E->f.line[n].execute_us, TWH_EXECUTE_SAFE_US);
    assert_int_equal(execute_us(E, 0), TWH_EXECUTE_SAFE_US);
    /* the fixed value is reported as set, any other as refused */
    assert_int_equal(twh_set_execute_us(&E->t, 0, TWH_EXECUTE_SAFE_US), TWH_OK);
    assert_int_equal(twh_set_execute_us(&E->t, 0, 6000), TWH_ERR_REFUSED);
    assert_int_equal(execute_us(E, 0), TWH_EXECUTE_SAFE_US);
    assert_int_equal(E->f.errors, 0);
}

static void test_negotiate(void **state)
{
    negotiate_case(E, 0x0F, 4000, 15);  /* v15: <= 4.5 ms */
    negotiate_case(E, 0x10, 4000, 16);
    negotiate_case(E, 0x11, 4000, 17);
    negotiate_case(E, 0x12, 6000, 18);  /* v18+: recommended 6 ms */
    negotiate_case(E, 0x19, 6000, 25);
    negotiate_case(E, 0x26, 6000, 26);  /* BCD */
    negotiate_case(E, 0x99, 6000, 99);
    negotiate_case(E, 0x1A, 4000, -1);  /* unknown: safe */
    negotiate_case(E, 0xFF, 4000, -1);
    negotiate_case(E, 0x00, 4000, 0);
}

static void test_negotiate_v15_device(void **state)
{
    twh_fw_t fw;
    uint16_t img[128];

    /* a v15 cell browns out with execute > 4.5 ms: asking it at 6 ms fails */
    blank_image(img, 128);
    fake_dev_setup(&E->f.dev[0], 0x0F, TWH_TYPE_O2, vec_maps[1].words, 128);
    E->f.dev[0].max_execute_us = 4500;
    assert_int_equal(twh_set_execute_us(&E->t, 0, 6000), TWH_OK);
    assert_int_equal(twh_firmware(&E->t, 0, &fw), TWH_ERR_NO_RESPONSE);
    assert_int_equal(twh_negotiate(&E->t, 0, &fw), TWH_OK);
    assert_int_equal(fw.version, 15);
    assert_int_equal(execute_us(E, 0), 4000);
    assert_int_equal(twh_read_word(&E->t, 0, 0x17, &img[0]), TWH_OK);
    assert_int_equal(img[0], 25);
    assert_int_equal(twh_negotiate(&E->t, 0, NULL), TWH_OK);
}

static void test_negotiate_errors(void **state)
{
    twh_fw_t fw = {0, 0, 0, 0};

    /* a timing write the core refuses: reported, the old value stays */
    E->f.refuse_timing = 1;
    assert_int_equal(twh_set_execute_us(&E->t, 0, 5000), TWH_ERR_REFUSED);
    assert_int_equal(execute_us(E, 0), 4000);
    /* negotiation with a v18 device: 4 ms is already set, 6 ms is refused */
    assert_int_equal(twh_negotiate(&E->t, 0, &fw), TWH_ERR_REFUSED);
    assert_int_equal(fw.version, 18);
    assert_int_equal(execute_us(E, 0), 4000);
    /* a channel left at 6 ms whose safe 4 ms is refused: nothing is sent */
    E->f.refuse_timing = 0;
    assert_int_equal(twh_set_execute_us(&E->t, 0, 6000), TWH_OK);
    E->f.refuse_timing = 1;
    E->f.n_pushed = 0;
    assert_int_equal(twh_negotiate(&E->t, 0, &fw), TWH_ERR_REFUSED);
    assert_int_equal(E->f.n_pushed, 0);
    E->f.refuse_timing = 0;
    /* out of the spec window: the core refuses, the driver reports it */
    assert_int_equal(twh_set_execute_us(&E->t, 0, 4000), TWH_OK);
    assert_int_equal(twh_set_execute_us(&E->t, 0, 12000), TWH_ERR_REFUSED);
    assert_int_equal(execute_us(E, 0), 4000);
    assert_true(E->f.errors & TWH_REGS__ERRORS__VALUE_REFUSED_bm);
    /* no device: the version query fails, timing stays safe, fw untouched */
    assert_int_equal(twh_set_execute_us(&E->t, 0, 6000), TWH_OK);
    E->f.dev[0].present = 0;
    memset(&fw, 0, sizeof(fw));
    assert_int_equal(twh_negotiate(&E->t, 0, &fw), TWH_ERR_NO_RESPONSE);
    assert_int_equal(execute_us(E, 0), 4000);
    assert_int_equal(fw.raw, 0);
}

/* ================================================================ calibration */
static unsigned erases_below(const fake_core_t *f, unsigned addr)
{
    unsigned i, n = 0;

    for (i = 0; i < f->n_line; i++) {
        const fake_line_t *l = &f->line[i];
        unsigned a;
        if ((l->cmd & 0xFE) == TWH_CMD_ERASE) {
            a = (l->cmd & 1u) << 8 | (l->payload & 0xFF);
            n += a < addr;
        } else if (l->cmd & 0x80) {
            a = ((l->payload >> 14) & 3u) << 7 | (l->cmd & 0x7F);
            n += a < addr;
        }
    }
    return n;
}

static void test_cal_append_simple(void **state)
{
    uint16_t a = 0;
    twh_map_t m;

    /* map 0: records at 0x20-0x23 and 0x30-0x35 -> first blank pair 0x24 */
    assert_int_equal(twh_cal_append(&E->t, 0, 803, 3710, &a), TWH_OK);
    assert_int_equal(a, 0x24);
    assert_int_equal(E->f.dev[0].flash[0x24], 803);
    assert_int_equal(E->f.dev[0].flash[0x25], 3710);
    assert_int_equal(twh_decode_map(E->f.dev[0].flash, 240, TWH_MAP_O2, &m), TWH_OK);
    assert_int_equal(m.cal_count, 6);
    assert_int_equal(m.current.addr, 0x24);
    assert_int_equal(fake_line_count(&E->f, 0x4A, 0x4B), 0);
    assert_int_equal(erases_below(&E->f, 0x20), 0);
    /* an empty area: 0x20 */
    fake_dev_setup(&E->f.dev[1], 0x26, 2, NULL, 240);
    assert_int_equal(twh_cal_append(&E->t, 1, 1, 1234, NULL), TWH_OK);
    assert_int_equal(E->f.dev[1].flash[0x20], 1);
    assert_int_equal(E->f.dev[1].flash[0x21], 1234);
}

static void test_cal_append_skips_half_pairs(void **state)
{
    uint16_t img[240], a = 0;

    blank_image(img, 240);
    img[0x20] = 5;             /* 0x21 blank: find free answers 0x21 (odd) */
    img[0x23] = 7;             /* 0x22 blank but its neighbour is programmed */
    img[0x26] = 9;
    img[0x27] = 3000;
    fake_dev_setup(&E->f.dev[0], 0x12, 1, img, 240);
    assert_int_equal(twh_cal_append(&E->t, 0, 10, 3001, &a), TWH_OK);
    assert_int_equal(a, 0x24);
    assert_int_equal(twh_cal_append(&E->t, 0, 11, 3002, &a), TWH_OK);
    assert_int_equal(a, 0x28);
    assert_int_equal(E->f.dev[0].flash[0x21], TWH_BLANK);   /* left alone */
    assert_int_equal(E->f.dev[0].flash[0x22], TWH_BLANK);
}

static void fill_area(uint16_t *img, unsigned size, unsigned first_page, uint16_t v)
{
    unsigned end = size < 0xE0 ? size : 0xE0, a, stamp = 100, n = (end - 0x20) / 2, i;

    blank_image(img, size);
    /* records in time order starting at first_page, wrapping to 0x20 */
    for (i = 0, a = first_page; i < n; i++) {
        img[a] = (uint16_t)stamp++;
        img[a + 1] = v;
        a += 2;
        if (a + 1 >= end)
            a = 0x20;
    }
}

static void test_cal_append_full_erases_oldest_page(void **state)
{
    static uint16_t img[240];
    uint16_t a = 0;
    unsigned w;
    twh_map_t m;

    fill_area(img, 240, 0x50, 3700);
    fake_dev_setup(&E->f.dev[0], 0x12, 1, img, 240);
    assert_int_equal(twh_cal_append(&E->t, 0, 1000, 3800, &a), TWH_OK);
    assert_int_equal(a, 0x50);
    assert_int_equal(fake_line_count(&E->f, 0x4A, 0x4B), 1);
    assert_int_equal(erases_below(&E->f, 0x20), 0);
    for (w = 0; w < 240; w++) {
        uint16_t want = img[w];
        if (w == 0x50) want = 1000;
        else if (w == 0x51) want = 3800;
        else if (w > 0x51 && w < 0x60) want = TWH_BLANK;
        assert_int_equal(E->f.dev[0].flash[w], want);
    }
    assert_int_equal(twh_decode_map(E->f.dev[0].flash, 240, TWH_MAP_O2, &m), TWH_OK);
    assert_int_equal(m.current.addr, 0x50);
    assert_int_equal(m.cal_count, 96 - 8 + 1);
    /* the next appends fill the erased page */
    assert_int_equal(twh_cal_append(&E->t, 0, 1001, 3801, &a), TWH_OK);
    assert_int_equal(a, 0x52);
}

static void test_cal_append_full_oldest_rules(void **state)
{
    static uint16_t img[240];
    uint16_t a = 0;

    /* tie on the smallest stamp: the lower address is the older */
    fill_area(img, 240, 0x20, 3700);
    img[0x20] = 500;
    img[0x90] = 50;
    img[0xB0] = 50;
    fake_dev_setup(&E->f.dev[0], 0x12, 1, img, 240);
    assert_int_equal(twh_cal_append(&E->t, 0, 2000, 3800, &a), TWH_OK);
    assert_int_equal(a, 0x90);
    /* a half-written pair with the smallest stamp does not count */
    fill_area(img, 240, 0x20, 3700);
    img[0x40] = 1;
    img[0x41] = TWH_BLANK;
    img[0x60] = 2;
    fake_dev_setup(&E->f.dev[0], 0x12, 1, img, 240);
    assert_int_equal(twh_cal_append(&E->t, 0, 2000, 3800, &a), TWH_OK);
    assert_int_equal(a, 0x60);
    assert_int_equal(E->f.dev[0].flash[0x40], 1);   /* page 0x40 untouched */
    /* nothing valid at all: the first page */
    fill_area(img, 240, 0x20, TWH_BLANK);
    fake_dev_setup(&E->f.dev[0], 0x12, 1, img, 240);
    /* ... which is only "full" if every word 1 is programmed: make the
     * word-0s blank instead so every pair is half-written */
    for (a = 0x20; a < 0xE0; a += 2) {
        E->f.dev[0].flash[a] = TWH_BLANK;
        E->f.dev[0].flash[a + 1] = 77;
    }
    assert_int_equal(twh_cal_append(&E->t, 0, 2000, 3800, &a), TWH_OK);
    assert_int_equal(a, 0x20);
    assert_int_equal(erases_below(&E->f, 0x20), 0);
}

static void test_cal_append_v15_map(void **state)
{
    static uint16_t img[128];
    uint16_t a = 0;

    /* the v15 vector map: records at 0x20-0x25 and 0x7E -> next 0x26 */
    fake_dev_setup(&E->f.dev[0], 0x0F, 1, vec_maps[1].words, 128);
    assert_int_equal(twh_cal_append(&E->t, 0, 722, 3707, &a), TWH_OK);
    assert_int_equal(a, 0x26);
    /* full 128-word map, oldest at 0x70 */
    fill_area(img, 128, 0x70, 3700);
    fake_dev_setup(&E->f.dev[0], 0x0F, 1, img, 128);
    assert_int_equal(twh_cal_append(&E->t, 0, 900, 3800, &a), TWH_OK);
    assert_int_equal(a, 0x70);
    assert_int_equal(E->f.dev[0].flash[0x7E], TWH_BLANK);
    assert_int_equal(E->f.dev[0].flash[0x6E], img[0x6E]);
}

static void test_cal_append_errors(void **state)
{
    static uint16_t img[240];
    uint16_t a = 0x1234;

    /* a stamp or value of 0x3FFF would read as blank */
    assert_int_equal(twh_cal_append(&E->t, 0, TWH_BLANK, 1, &a), TWH_ERR_BAD_ARG);
    assert_int_equal(twh_cal_append(&E->t, 0, 1, TWH_BLANK, &a), TWH_ERR_BAD_ARG);
    assert_int_equal(twh_cal_append(&E->t, 0, 0x4000, 1, &a), TWH_ERR_BAD_ARG);
    assert_int_equal(E->f.n_pushed, 0);
    /* the erase does not take: full after the erase */
    fill_area(img, 240, 0x20, 3700);
    fake_dev_setup(&E->f.dev[0], 0x12, 1, img, 240);
    E->f.dev[0].erase_broken = 1;
    assert_int_equal(twh_cal_append(&E->t, 0, 2000, 3800, &a), TWH_ERR_FLASH_FULL);
    assert_int_equal(fake_line_count(&E->f, 0x4A, 0x4B), 1);
    assert_int_equal(erases_below(&E->f, 0x20), 0);
    assert_int_equal(a, 0x1234);
    /* writes that do not take */
    fake_dev_setup(&E->f.dev[0], 0x12, 1, NULL, 240);
    E->f.dev[0].write_broken = 1;
    assert_int_equal(twh_cal_append(&E->t, 0, 2000, 3800, &a), TWH_ERR_VERIFY);
    /* a device too small for a calibration area */
    fake_dev_setup(&E->f.dev[0], 0x12, 1, NULL, 0x21);
    assert_int_equal(twh_cal_append(&E->t, 0, 2000, 3800, &a), TWH_ERR_FLASH_FULL);
    /* link errors propagate */
    fake_dev_setup(&E->f.dev[0], 0x12, 1, NULL, 240);
    fake_script(&E->f, 0, TWH_CMD_FIND_FREE, TWH_ST_SHORT_RESPONSE, 0);
    assert_int_equal(twh_cal_append(&E->t, 0, 2000, 3800, &a), TWH_ERR_SHORT);
    fake_script(&E->f, 0, TWH_CMD_CONFIG, TWH_ST_NO_RESPONSE, 0);
    assert_int_equal(twh_cal_append(&E->t, 0, 2000, 3800, &a), TWH_ERR_NO_RESPONSE);
    assert_int_equal(a, 0x1234);
    assert_int_equal(erases_below(&E->f, 0x20), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vec_frames_encoding),
        cmocka_unit_test_setup_teardown(test_vec_frames_on_bus, setup, teardown),
        cmocka_unit_test_setup_teardown(test_vec_responses, setup, teardown),
        cmocka_unit_test(test_vec_supply),
        cmocka_unit_test(test_vec_temperature),
        cmocka_unit_test(test_vec_o2_ppo2),
        cmocka_unit_test(test_vec_fw_version),
        cmocka_unit_test(test_vec_maps),
        cmocka_unit_test_setup_teardown(test_vec_maps_from_device, setup, teardown),
        cmocka_unit_test(test_vec_text),
        cmocka_unit_test(test_vec_datetime),
        cmocka_unit_test(test_vec_s14),
        cmocka_unit_test(test_vec_calcases),
        cmocka_unit_test(test_datetime_rules),
        cmocka_unit_test(test_text_rules),
        cmocka_unit_test(test_conversion_edges),
        cmocka_unit_test(test_decode_map_args),
        cmocka_unit_test_setup_teardown(test_init_probe, setup, teardown),
        cmocka_unit_test_setup_teardown(test_submit_result, setup, teardown),
        cmocka_unit_test_setup_teardown(test_submit_bad_channel, setup, teardown),
        cmocka_unit_test_setup_teardown(test_submit_refuses_factory_area, setup, teardown),
        cmocka_unit_test_setup_teardown(test_fifo_full, setup, teardown),
        cmocka_unit_test_setup_teardown(test_timeout_polling, setup, teardown),
        cmocka_unit_test_setup_teardown(test_wait_irq, setup_irq, teardown),
        cmocka_unit_test_setup_teardown(test_status_mapping, setup, teardown),
        cmocka_unit_test_setup_teardown(test_blocked_by_core, setup, teardown),
        cmocka_unit_test_setup_teardown(test_stash_keeps_other_results, setup, teardown),
        cmocka_unit_test_setup_teardown(test_stash_full_loses_nothing, setup, teardown),
        cmocka_unit_test_setup_teardown(test_stash_ring_wraps, setup, teardown),
        cmocka_unit_test_setup_teardown(test_same_tag_other_channel_or_cmd, setup, teardown),
        cmocka_unit_test_setup_teardown(test_res_pop_mismatch, setup, teardown),
        cmocka_unit_test_setup_teardown(test_xfer_no_data_on_error, setup, teardown),
        cmocka_unit_test_setup_teardown(test_cancel_all, setup, teardown),
        cmocka_unit_test(test_v2_layout),
        cmocka_unit_test_setup_teardown(test_ch32_submit_result, setup32, teardown),
        cmocka_unit_test_setup_teardown(test_ch32_results_apart, setup32, teardown),
        cmocka_unit_test_setup_teardown(test_ch32_busy, setup32, teardown),
        cmocka_unit_test_setup_teardown(test_idle_charge_ch20, setup32, teardown),
        cmocka_unit_test_setup_teardown(test_idle_charge_ch20_last, setup21, teardown),
        cmocka_unit_test_setup_teardown(test_ch16, setup16, teardown),
        cmocka_unit_test_setup_teardown(test_bad_channel_push, setup16, teardown),
        cmocka_unit_test_setup_teardown(test_helpers, setup, teardown),
        cmocka_unit_test_setup_teardown(test_write_verify, setup, teardown),
        cmocka_unit_test_setup_teardown(test_negotiate, setup, teardown),
        cmocka_unit_test_setup_teardown(test_negotiate_fixed_timing, setup, teardown),
        cmocka_unit_test_setup_teardown(test_negotiate_v15_device, setup, teardown),
        cmocka_unit_test_setup_teardown(test_negotiate_errors, setup, teardown),
        cmocka_unit_test_setup_teardown(test_cal_append_simple, setup, teardown),
        cmocka_unit_test_setup_teardown(test_cal_append_skips_half_pairs, setup, teardown),
        cmocka_unit_test_setup_teardown(test_cal_append_full_erases_oldest_page, setup, teardown),
        cmocka_unit_test_setup_teardown(test_cal_append_full_oldest_rules, setup, teardown),
        cmocka_unit_test_setup_teardown(test_cal_append_v15_map, setup, teardown),
        cmocka_unit_test_setup_teardown(test_cal_append_errors, setup, teardown),
    };

    return cmocka_run_group_tests(tests, NULL, NULL);
}
