/* A fake twowire-host core for the driver's unit tests: the register file of
 * rdl/twh_regs.rdl, map version 2 (offsets and fields from the generated
 * twh_regs.h), the command and result FIFOs with RES_INFO/RES_POP
 * semantics, timing registers with the spec-window refusal, flush, the
 * factory-area block, and behind each channel a simulated peripheral (the
 * rules of tb/periph_model.py PeripheralLogic) or scripted results.
 *
 * Map version 2, up to FAKE_MAX_CH channels: channel n's block at
 * 0x80 + 0x20 * n holds its CMD_PUSH (the channel is the block's); a push
 * into an absent channel's block (n >= channels) answers a bus error and
 * sets ERRORS.BAD_CHANNEL, every other access to an absent block, to an
 * unused word (0x28, the old CMD_PUSH, included) or past the last block is
 * a bus error. IDLE_CHARGE, BUSY and POLL_READY have bit n for channel n;
 * bits of absent channels read 0 and IDLE_CHARGE ignores writes to them.
 * BUSY: channel n has a command in the command FIFO (the fake has no
 * channel queues: a command waits in the FIFO until it completes).
 *
 * Time: nothing happens on its own. Each delay_us / wait_irq call of the
 * driver completes at most one queued command (the head of the command
 * FIFO), like a core whose transactions take one poll step. */
#ifndef FAKE_CORE_H
#define FAKE_CORE_H

#include <stdint.h>

#include "twh.h"

#define FAKE_FIFO_MAX 64
#define FAKE_LOG_MAX 4096
#define FAKE_SCRIPT_MAX 64
#define FAKE_MAX_CH 32         /* channel blocks of the map (CH[32]) */

typedef struct fake_dev {
    int present;               /* 0: nothing on the line (NO_RESPONSE) */
    uint16_t flash[512];
    uint16_t size;             /* flash words */
    uint8_t fw_byte, type_byte, config_bits;
    uint16_t adc_ref, adc_temp, adc_o2;   /* raw 16-bit answers */
    uint16_t max_execute_us;   /* longer execute: browns out, no answer */
    int write_broken;          /* writes do nothing */
    int erase_broken;          /* erases do nothing */
} fake_dev_t;

typedef struct fake_cmd {
    uint8_t cmd, ch, tag, unlock;
    uint16_t payload;
} fake_cmd_t;

typedef struct fake_res {
    uint8_t cmd, status, ch, tag;
    uint16_t data;
} fake_res_t;

typedef struct fake_line {     /* a command that reached the line */
    uint8_t cmd, ch;
    uint16_t payload;
    uint16_t execute_us;       /* TIMING1.EXECUTE_US when it ran */
} fake_line_t;

typedef struct fake_script {
    int ch, cmd;               /* -1: any */
    uint8_t status;
    uint16_t data;
} fake_script_t;

typedef struct fake_core {
    /* build parameters and identity (tests may corrupt them; channels is
     * what VERSION.CHANNELS says, 0-63, the channels that exist are the
     * first min(channels, FAKE_MAX_CH)) */
    uint32_t id;
    uint8_t major, minor, channels;
    uint16_t depth;
    uint32_t clk_khz;
    /* registers */
    uint32_t ctrl, errors, irq_en;
    uint32_t idle_charge;      /* IDLE_CHARGE as written (present channels' bits) */
    uint32_t poll_ready;       /* POLL_READY as set by a test (no poller here) */
    uint32_t timing[FAKE_MAX_CH][3];
    int lab, factory_armed;
    int refuse_timing;         /* refuse every timing write (test knob) */
    int fixed_timing;          /* a PROG_TIMING = 0 build: VERSION says so, writes refused */
    /* FIFOs */
    fake_cmd_t cmdq[FAKE_FIFO_MAX];
    unsigned cmd_n;
    fake_res_t resq[FAKE_FIFO_MAX];
    unsigned res_n;
    /* peripherals */
    fake_dev_t dev[FAKE_MAX_CH];
    /* scripted results, used in order for matching commands instead of the
     * device (the command then does not reach the device) */
    fake_script_t script[FAKE_SCRIPT_MAX];
    unsigned n_script;
    int stall;                 /* 1: no command completes */
    int corrupt_next_pop;      /* RES_POP answers a different tag once */
    /* observation */
    unsigned bus_errors;       /* accesses a real core answers with an error */
    uint32_t last_bus_error;   /* the offset of the last one */
    unsigned order_errors;     /* RES_POP without a RES_INFO read before it */
    int info_seen;
    unsigned reads, writes, delays, irq_waits;
    uint64_t now_us;
    fake_cmd_t pushed[FAKE_LOG_MAX];
    unsigned n_pushed;
    fake_line_t line[FAKE_LOG_MAX];
    unsigned n_line;
} fake_core_t;

void fake_init(fake_core_t *f, uint8_t channels, uint16_t depth);
/* a device with a flash image (size words; a NULL image is all blank) */
void fake_dev_setup(fake_dev_t *d, uint8_t fw_byte, uint8_t type_byte,
                    const uint16_t *image, uint16_t size);
void fake_platform(fake_core_t *f, twh_platform_t *p, int with_irq);
void fake_script(fake_core_t *f, int ch, int cmd, uint8_t status, uint16_t data);
void fake_step(fake_core_t *f);          /* complete one queued command */
void fake_run(fake_core_t *f);           /* complete every queued command */
/* line commands with cmd_lo <= cmd <= cmd_hi */
unsigned fake_line_count(const fake_core_t *f, uint8_t cmd_lo, uint8_t cmd_hi);

uint32_t fake_read32(void *ctx, uint32_t off);
void fake_write32(void *ctx, uint32_t off, uint32_t v);
void fake_delay_us(void *ctx, uint32_t us);
uint32_t fake_wait_irq(void *ctx, uint32_t max_us);

#endif
