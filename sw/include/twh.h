/* twowire-host C driver: host controller for Shearwater's 2-wire sensor link.
 *
 * Portable C99, no malloc, no floating point, no libc calls. Register
 * offsets and fields come from the generated twh_regs.h (rdl/twh_regs.rdl).
 * See docs/driver.md for the overview, the platform hooks and the decisions.
 *
 * Conventions
 * - Every function that can fail returns int: TWH_OK (0) or a negative
 *   TWH_ERR_* code. Output parameters are written only on success.
 * - One twh_t per core. The driver is not reentrant: one execution context
 *   at a time may call it (no internal locking, no globals).
 * - Word addresses are flash word addresses (0x000-0x1FF), flash words are
 *   14 bits, an erased word reads TWH_BLANK.
 */
#ifndef TWH_H
#define TWH_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ errors */
/* -1 .. -8 are the hardware result status codes 1 .. 8, negated. */
enum twh_err {
    TWH_OK               =   0,
    TWH_ERR_NO_RESPONSE  =  -1, /* no answer (an error unless erase/write) */
    TWH_ERR_CHECKSUM     =  -2, /* three bytes, checksum wrong */
    TWH_ERR_FRAMING      =  -3, /* a stop bit read 0 */
    TWH_ERR_SHORT        =  -4, /* answer started, fewer than 3 bytes */
    TWH_ERR_STUCK_LOW    =  -5, /* line never read high during preamble */
    TWH_ERR_STUCK_HIGH   =  -6, /* line never read low during sync */
    TWH_ERR_BLOCKED      =  -7, /* core's factory-area protection */
    TWH_ERR_CANCELLED    =  -8, /* flushed before it started */
    TWH_ERR_HW_STATUS    =  -9, /* status code 9-15: not defined */
    TWH_ERR_TIMEOUT      = -10, /* own result did not arrive in timeout_us */
    TWH_ERR_FIFO_FULL    = -11, /* command FIFO full: nothing pushed */
    TWH_ERR_AGAIN        = -12, /* no result available (non-blocking) */
    TWH_ERR_BAD_ARG      = -13, /* argument out of range, factory area, ... */
    TWH_ERR_BAD_ID       = -14, /* core not found: ID/VERSION/PARAMS wrong */
    TWH_ERR_VERIFY       = -15, /* written word read back different */
    TWH_ERR_FLASH_FULL   = -16, /* no calibration slot, even after erase */
    TWH_ERR_REFUSED      = -17, /* core refused a timing value */
    TWH_ERR_STASH_FULL   = -18, /* other results pending: drain twh_result() */
    TWH_ERR_BAD_RESPONSE = -19, /* answer with a checksum but impossible */
    TWH_ERR_BUS          = -20, /* RES_INFO and RES_POP disagree */
    TWH_ERR_RANGE        = -21  /* conversion input invalid / not a date */
};

/* ------------------------------------------------------------- constants */
#define TWH_MAGIC             0x54574831u  /* "TWH1" (= ID reset value) */
#define TWH_BLANK             0x3FFFu      /* erased flash word */
#define TWH_WORD_MASK         0x3FFFu
#define TWH_ADDR_MAX          0x1FFu
#define TWH_FACTORY_END       0x20u        /* words 0x00-0x1F: never touched */
#define TWH_CAL_START         0x20u
#define TWH_CAL_END           0xE0u        /* exclusive */
#define TWH_PAGE_WORDS        16u

#define TWH_CMD_CONFIG        0x40u
#define TWH_CMD_FIRMWARE      0x41u
#define TWH_CMD_REF_VOLTAGE   0x42u
#define TWH_CMD_TEMPERATURE   0x43u
#define TWH_CMD_O2_VOLTAGE    0x44u
#define TWH_CMD_FIND_FREE     0x46u        /* | address bit 8 */
#define TWH_CMD_READ          0x48u        /* | address bit 8 */
#define TWH_CMD_ERASE         0x4Au        /* | address bit 8 */
#define TWH_CMD_WRITE         0x80u        /* | address bits 6:0 */
#define TWH_UNUSED_PAYLOAD    0xAAu

/* channels a core can have (VERSION.CHANNELS 1-32, register map version 2:
 * channel n has its register block, CMD_PUSH included, at 0x80 + 0x20 * n;
 * IDLE_CHARGE, BUSY and POLL_READY have bit n for channel n) */
#define TWH_MAX_CHANNELS      32u

/* hardware result status codes (RES_INFO.STATUS, docs/protocol.md) */
#define TWH_ST_OK             0u
#define TWH_ST_NO_RESPONSE    1u
#define TWH_ST_BAD_CHECKSUM   2u
#define TWH_ST_FRAMING        3u
#define TWH_ST_SHORT_RESPONSE 4u
#define TWH_ST_LINE_STUCK_LOW 5u
#define TWH_ST_LINE_STUCK_HIGH 6u
#define TWH_ST_BLOCKED        7u
#define TWH_ST_CANCELLED      8u

/* execute phase (TIMING1.EXECUTE_US) chosen by twh_negotiate() */
#define TWH_EXECUTE_SAFE_US        4000u  /* every firmware, v15 needs <= 4500 */
#define TWH_EXECUTE_RECOMMENDED_US 6000u  /* firmware v18 and later */

#define TWH_TIMEOUT_US_DEFAULT 1000000u   /* blocking helpers: 1 s */
#define TWH_POLL_US_DEFAULT    1000u      /* step when there is no wait_irq */

/* Results of other commands kept while a blocking helper waits. */
#ifndef TWH_STASH_SIZE
#define TWH_STASH_SIZE 4
#endif

/* --------------------------------------------------------- platform hooks */
/* Plain function pointers and a context pointer (ctypes-friendly).
 * offset: byte offset of a 32-bit register from the core's base address.
 * read32/write32/delay_us are required; wait_irq may be NULL. */
typedef struct twh_platform {
    uint32_t (*read32)(void *ctx, uint32_t offset);
    void     (*write32)(void *ctx, uint32_t offset, uint32_t value);
    /* busy-wait or yield for about `us` microseconds */
    void     (*delay_us)(void *ctx, uint32_t us);
    /* optional: sleep until the core's irq line is high or max_us passed;
     * return the microseconds actually waited (0 counts as 1) */
    uint32_t (*wait_irq)(void *ctx, uint32_t max_us);
    void     *ctx;
} twh_platform_t;

/* One result, as popped from the core. */
typedef struct twh_result {
    uint16_t data;     /* MSB:LSB of the answer (0 unless OK/BAD_CHECKSUM) */
    uint8_t  cmd;      /* command byte */
    uint8_t  status;   /* TWH_ST_* */
    uint8_t  channel;
    uint8_t  tag;
} twh_result_t;

/* Driver state; allocate it anywhere (static, stack, Python ctypes). */
typedef struct twh {
    twh_platform_t plat;
    uint32_t timeout_us;     /* blocking helpers give up after this */
    uint32_t poll_us;        /* delay between looks without wait_irq */
    uint32_t clk_khz;        /* PARAMS.CLK_KHZ */
    uint16_t fifo_depth;     /* PARAMS.FIFO_DEPTH */
    uint8_t  channels;       /* VERSION.CHANNELS, 1-32 (0 until init succeeded) */
    uint8_t  version_major;
    uint8_t  version_minor;
    uint8_t  fixed_timing;   /* VERSION.FIXED_TIMING: a lean build, timing read-only */
    uint8_t  next_tag;
    uint8_t  stash_head;     /* stash: ring of results popped while a  */
    uint8_t  stash_count;    /* blocking helper waited; oldest at head */
    twh_result_t stash[TWH_STASH_SIZE];
} twh_t;

/* Firmware version and device type (command 0x41). */
#define TWH_FW_BINARY  0u   /* byte <= 0x19 */
#define TWH_FW_BCD     1u   /* byte >= 0x26, both nibbles <= 9 */
#define TWH_FW_UNKNOWN 2u   /* anything else: version = -1 */
#define TWH_TYPE_O2        1u
#define TWH_TYPE_CO2       2u
#define TWH_TYPE_CO2_STICK 3u
typedef struct twh_fw {
    uint8_t raw;       /* version byte as received */
    uint8_t type;      /* peripheral type byte */
    int8_t  version;   /* decoded version, -1 when unknown */
    uint8_t encoding;  /* TWH_FW_* */
} twh_fw_t;

/* Date/time of the flash maps; year 0 = not a valid date. */
typedef struct twh_datetime {
    uint16_t year;     /* 2000-2127 */
    uint8_t  month, day, hour, minute;
} twh_datetime_t;

/* One field calibration record; addr 0 = no record. */
typedef struct twh_cal {
    uint16_t addr;     /* word address of word 0 */
    uint16_t stamp;    /* word 0: time since manufacture / unit */
    uint16_t value;    /* word 1: gain (O2) or 400 ppm reading (CO2) */
} twh_cal_t;

#define TWH_MAP_O2  1u
#define TWH_MAP_CO2 2u     /* also the CO2 temperature stick */
typedef struct twh_map {
    char     model[15];      /* NUL-terminated, padding stripped */
    char     mfg_id[7];
    char     serial[13];
    uint8_t  kind;           /* TWH_MAP_* */
    twh_datetime_t manufactured;
    twh_datetime_t expires;
    uint16_t size;           /* words in the image */
    uint16_t temp_scale;
    uint16_t ref_temp;       /* as stored: C*100, or whole degrees if < 100 */
    uint16_t adc_ref;
    /* O2 only (0 for CO2) */
    uint8_t  map_version;
    uint8_t  map_type;
    int16_t  opamp_offset;   /* mV*100, sign-decoded */
    uint16_t mfg_cal[3][2];
    /* CO2 only (0 / has_ 0 for O2) */
    uint16_t rgb_offset[3];
    uint16_t rgb_gain[3];
    uint8_t  has_rgb_offset; /* 0: all three words blank */
    uint8_t  has_rgb_gain;
    /* field calibrations */
    uint16_t cal_unit_hours; /* 3 (O2) or 6 (CO2) */
    uint16_t cal_count;      /* records with both words programmed */
    twh_cal_t current;       /* largest stamp, ties -> higher address */
} twh_map_t;

/* ------------------------------------------------------------ core access */
/* Probe the core: ID magic, VERSION (major must be the one this driver was
 * generated for, 2, and 1-32 channels), PARAMS. Copies *plat. With
 * plat->wait_irq it also sets IRQ_EN.RESULT. Queued results are left alone. */
int      twh_init(twh_t *t, const twh_platform_t *plat);
uint32_t twh_sizeof(void);   /* sizeof(twh_t), for foreign-language callers */

/* Non-blocking. twh_submit returns the tag (0-31) it gave the command, or an
 * error; it checks STATUS.CMD_FULL first and refuses absent channels and
 * erase/write of words 0x00-0x1F (TWH_ERR_BAD_ARG) before any bus write.
 * The command goes to the channel's own CMD_PUSH (CH[ch].CMD_PUSH). */
int twh_submit(twh_t *t, uint8_t ch, uint8_t cmd, uint16_t payload);
/* number of results ready (stash + core result FIFO), >= 0 */
int twh_poll(twh_t *t);
/* oldest result: the stash first, then the core (RES_INFO, then RES_POP);
 * TWH_ERR_AGAIN when there is none */
int twh_result(twh_t *t, twh_result_t *r);
/* error code of a result: NO_RESPONSE is TWH_OK for commands that expect no
 * answer (erase, write, reserved) */
int twh_status_err(uint8_t status, uint8_t cmd);
/* CTRL.FLUSH: every command not yet started ends with status CANCELLED */
int twh_cancel_all(twh_t *t);
/* IDLE_CHARGE = mask: bit n = 1 keeps channel n's carrier on while the
 * channel is idle (charging), 0 releases the line. A bit of an absent
 * channel (or a core twh_init refused): TWH_ERR_BAD_ARG, nothing written. */
int twh_set_idle_charge(twh_t *t, uint32_t mask);
/* The BUSY register: bit n set while channel n has a command queued or
 * running, a poll running, or a result waiting to enter the result FIFO.
 * Bits of absent channels read 0. */
uint32_t twh_busy(twh_t *t);

/* Blocking: submit, then wait for this command's own result (channel + tag +
 * command); other results arriving meanwhile go to the stash. *data may be
 * NULL. Returns twh_status_err() of the result, or a driver error. */
int twh_xfer(twh_t *t, uint8_t ch, uint8_t cmd, uint16_t payload, uint16_t *data);

/* ------------------------------------------------- blocking command helpers */
int twh_config(twh_t *t, uint8_t ch, uint8_t *config_bits, uint16_t *flash_words); /* 0x40 */
int twh_firmware(twh_t *t, uint8_t ch, twh_fw_t *fw);                              /* 0x41 */
int twh_ref_voltage(twh_t *t, uint8_t ch, uint16_t *adc);                          /* 0x42 */
int twh_temperature(twh_t *t, uint8_t ch, uint16_t *adc);                          /* 0x43 */
int twh_o2_voltage(twh_t *t, uint8_t ch, uint16_t *adc);                           /* 0x44 */
int twh_find_free(twh_t *t, uint8_t ch, uint16_t from, uint16_t *addr);            /* 0x46/47 */
int twh_read_word(twh_t *t, uint8_t ch, uint16_t addr, uint16_t *word);            /* 0x48/49 */
int twh_erase_page(twh_t *t, uint8_t ch, uint16_t addr);                           /* 0x4A/4B */
/* 0x80-0xFF, then reads the word back: TWH_ERR_VERIFY if it differs */
int twh_write_word(twh_t *t, uint8_t ch, uint16_t addr, uint16_t word);
/* words 0..n-1 into words[] (n <= 512). On failure words[] holds the words
 * read before the failing one; the rest is untouched. */
int twh_read_image(twh_t *t, uint8_t ch, uint16_t *words, uint16_t n);

/* TIMING1.EXECUTE_US of a channel (read-modify-write, read back:
 * TWH_ERR_REFUSED when the core kept the old value) */
int twh_set_execute_us(twh_t *t, uint8_t ch, uint16_t us);
/* Timing negotiation: execute = 4 ms (safe), ask 0x41, then 6 ms for v18+,
 * else stay at 4 ms (v15 needs <= 4.5 ms). fw may be NULL. Once the version
 * was read, *fw holds it, also when the final timing write is refused
 * (TWH_ERR_REFUSED): the one documented exception to "outputs only on
 * success", so a caller can tell which firmware refused. */
int twh_negotiate(twh_t *t, uint8_t ch, twh_fw_t *fw);
uint16_t twh_execute_us_for(const twh_fw_t *fw);

/* Append a field calibration record (stamp, value), both < 0x3FFF: first
 * blank even pair from 0x20 (0x46, neighbour checked with 0x48); when the
 * area is full, the page holding the oldest record is erased first (never
 * below 0x20). Both words are written and verified. *addr may be NULL. */
int twh_cal_append(twh_t *t, uint8_t ch, uint16_t stamp, uint16_t value, uint16_t *addr);

/* ------------------------------------------------- encoding (no bus access) */
int twh_encode_addr(uint8_t base_cmd, uint16_t addr, uint8_t *cmd, uint16_t *payload);
int twh_encode_write(uint16_t addr, uint16_t word, uint8_t *cmd, uint16_t *payload);
int twh_expects_response(uint8_t cmd);     /* 1 for 0x40-0x44, 0x46-0x49 */
void twh_fw_decode(uint16_t data, twh_fw_t *fw);

/* ------------------------------------------- conversions (integers only) */
/* 1024*4096/adc, only for 0 < adc < 4095, else TWH_ERR_RANGE */
int twh_supply_mv(uint16_t adc, int32_t *mv);
/* Ref + (adc - adc_ref) * supply_mv*100 / temp_scale (C*100); ref_temp < 100
 * is whole degrees. TWH_ERR_RANGE for supply_mv <= 0 (unknown), temp_scale 0
 * or a result outside int32 */
int twh_temperature_c100(uint16_t adc, uint16_t ref_temp, uint16_t adc_ref,
                         int32_t supply_mv, uint16_t temp_scale, int32_t *c100);
int32_t twh_o2_mv100(uint16_t adc, int16_t opamp_offset);  /* 100*adc/22 + off */
int32_t twh_ppo2_mbar(uint16_t adc, uint16_t gain);        /* adc*gain*1000/2^22 */

/* --------------------------------------------------- flash-map decoding */
int16_t twh_s14(uint16_t word);            /* 14-bit two's complement */
/* TWH_ERR_RANGE (and *dt zeroed) when the fields are not a valid date */
int  twh_decode_datetime(uint16_t w0, uint16_t w1, twh_datetime_t *dt);
/* n_words words -> out[2*n_words+1]; stops at a blank word, strips trailing
 * NUL/space */
void twh_decode_text(const uint16_t *words, uint8_t n_words, char *out);
/* Field calibration records (both words programmed) in [0x20, min(0xE0, n)):
 * returns their number; the current one (largest stamp, ties -> higher
 * address) goes to *current (addr 0: none); with list != NULL the first
 * `max` records, in address order, go to list[]. */
uint16_t twh_cal_scan(const uint16_t *words, uint16_t n, twh_cal_t *current,
                      twh_cal_t *list, uint16_t max);
/* whole image (n = flash size, 0x20..0x200 words) of kind TWH_MAP_* */
int  twh_decode_map(const uint16_t *words, uint16_t n, uint8_t kind, twh_map_t *m);

#ifdef __cplusplus
}
#endif

#endif /* TWH_H */
