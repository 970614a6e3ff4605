/* The fuzz platform: a register file behind the driver's platform hooks,
 * driven by the fuzz input. Two modes:
 *
 * raw   every register read returns the next 4 input bytes: the core and
 *       the bus may answer anything (a hostile or broken core). Writes are
 *       only observed.
 * model a well-behaved core (command and result FIFOs of a fuzzed depth,
 *       RES_INFO/RES_POP, flush, timing registers with the spec-window
 *       refusal, factory block) with a simulated flash device on each
 *       channel. The input decides, at every delay_us/wait_irq, how many
 *       commands complete, with which status, and whether the answer's data
 *       is the device's or made up.
 *
 * Register map version 2 (up to FZ_MAX_CH channels): each channel's
 * CMD_PUSH is in its block (0x80 + 0x20 * n), the channel of a push is the
 * block's; IDLE_CHARGE (0x3C) and BUSY (0x40) have bit n for channel n.
 *
 * Both modes watch the driver: the RES_INFO/RES_POP order, every CMD_PUSH,
 * and every result popped. In model mode each command carries a sequence
 * number through the core, so the harness can tell which command a popped
 * result belongs to whatever its tag. */
#ifndef FUZZ_CORE_H
#define FUZZ_CORE_H

#include <stdint.h>

#include "fuzz_common.h"
#include "twh.h"

#define FZ_DEPTH_MAX 16u
#define FZ_MAX_CH 32u           /* channel blocks of the map (CH[32]) */
#define FZ_SEQ_MAX 65536u

typedef struct fz_cmd {
    uint8_t cmd, ch, tag, cancelled;
    uint16_t payload;
    uint32_t seq;
} fz_cmd_t;

typedef struct fz_res {
    uint8_t cmd, status, ch, tag;
    uint16_t data;
    uint32_t seq;
} fz_res_t;

typedef struct fz_dev {
    int present;
    uint16_t size;              /* flash words, 0-511 */
    uint16_t flash[512];
    uint8_t fw, type, config;
    uint16_t adc[3];            /* answers to 0x42, 0x43, 0x44 */
} fz_dev_t;

/* What one driver call did, for the harness to judge. */
typedef struct fz_obs {
    unsigned pushes;            /* CMD_PUSH writes (any channel's block) */
    fz_cmd_t first_push, last_push;
    unsigned pops;              /* RES_POP reads (model: those that returned VALID) */
    fz_res_t last_pop;
    unsigned ctrl_writes, timing_writes, other_writes;
    uint32_t last_ctrl;         /* the value last written to CTRL */
    uint32_t last_write_off, last_write_val;   /* the last write of any register */
    unsigned reads;
    unsigned waits;             /* delay_us + wait_irq calls */
    unsigned injected;          /* model: statuses made up, data made up, stalls */
} fz_obs_t;

typedef struct fz_core {
    fz_in_t *in;
    int raw;
    /* identity (model) */
    uint8_t channels;
    uint16_t depth;
    /* model registers and FIFOs */
    uint32_t ctrl, irq_en, idle_charge;
    uint32_t timing[FZ_MAX_CH][3];
    fz_cmd_t cmdq[FZ_DEPTH_MAX];
    unsigned cmd_n;
    fz_res_t resq[FZ_DEPTH_MAX];
    unsigned res_n;
    uint32_t next_seq;
    uint8_t last_tag;
    int any_push;
    fz_dev_t dev[FZ_MAX_CH];
    /* order watch: RES_POP must follow a RES_INFO read that showed VALID */
    int info_valid;
    uint32_t last_info;         /* raw mode: the RES_INFO value read last */
    uint32_t last_pop_raw;      /* raw mode: the RES_POP value read last */
    unsigned order_errors;
    unsigned bus_errors;        /* model: accesses a real core answers with an error */
    unsigned bad_channel;       /* model: pushes into an absent channel's block */
    unsigned factory_pushes;    /* erase/write of words 0x00-0x1F pushed */
    unsigned tag_errors;        /* a push whose tag is not the previous + 1 */
    /* accounting hooks: called for every push and every popped result */
    void (*on_push)(void *h, const fz_cmd_t *c);
    void (*on_pop)(void *h, const fz_res_t *r);
    void *hctx;
    fz_obs_t obs;
} fz_core_t;

/* raw: read values come from `in`. model: channels 1-32, depth 1-16. */
void fz_core_init(fz_core_t *f, fz_in_t *in, int raw, uint8_t channels, uint16_t depth);
void fz_platform(fz_core_t *f, twh_platform_t *p, int with_irq);
void fz_obs_reset(fz_core_t *f);
/* model: complete one queued command as the device answers it, with no
 * made-up status or data (0: nothing to complete or result FIFO full) */
int fz_complete_clean(fz_core_t *f);
/* model: one time step as the input decides (what delay_us and wait_irq
 * do); returns the event byte */
uint8_t fz_step(fz_core_t *f);
/* the word address an erase or write touches, 0xFFFF for other commands */
uint16_t fz_target_addr(uint8_t cmd, uint16_t payload);
/* model: bit n for each channel n the core has */
uint32_t fz_present_mask(const fz_core_t *f);
/* model: BUSY, bit n for each channel with a command in the command FIFO
 * (the model has no channel queues: a command waits there until it ends) */
uint32_t fz_busy(const fz_core_t *f);

/* model timing window for TIMING1.EXECUTE_US (docs/registers.md) */
#define FZ_EXECUTE_MIN 3500u
#define FZ_EXECUTE_MAX 10000u

#endif
