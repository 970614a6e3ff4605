/* The PC side of the board's UART-to-Wishbone bridge (boards/common/twh_uart_bridge.v,
 * protocol in docs/boards.md) over a POSIX serial port, and the C driver's
 * platform hooks on top of it. The same code talks to a real board (an FTDI
 * /dev/ttyUSB*) and to the simulated one (a pty, tb/test_board_top.py).
 *
 * Only a request the bridge reports as not carried out (FRAME_ERR: its check
 * byte arrived wrong) is sent again. A lost or garbled answer leaves it open
 * whether the access happened - a repeated RES_POP would lose a result - so
 * the link resynchronises and marks itself failed instead; the caller checks
 * `failed` after each driver call.
 */
#ifndef TWH_SERIAL_PORT_H
#define TWH_SERIAL_PORT_H

#include <stdint.h>

#include "twh.h"

/* answer status byte */
#define TWB_ST_MARK_MASK 0xF0u
#define TWB_ST_MARK      0xA0u   /* upper nibble of every status byte */
#define TWB_ST_DROPPED   0x08u   /* bytes were discarded since the last answer */
#define TWB_ST_IRQ       0x04u   /* the core's irq line */
#define TWB_ST_FRAME_ERR 0x02u   /* check byte wrong: nothing was done */
#define TWB_ST_BUS_ERR   0x01u   /* the access was answered with an error */

/* request opcodes */
#define TWB_OP_READ   0x52u      /* 'R' A C            -> S D0 D1 D2 D3 */
#define TWB_OP_WRITE  0x57u      /* 'W' A D0 D1 D2 D3 C -> S */
#define TWB_OP_STATUS 0x53u      /* 'S'                -> S */

/* the bridge's window into the core: A, one byte, is the byte offset / 4,
 * so 0x000-0x3FC, the global registers and channels 0-27 of register map
 * version 2 (channel n at 0x80 + 0x20 * n) */
#define TWB_WINDOW 0x400u

/* silence after which the bridge drops a half-received request */
#define TWB_TIMEOUT_BITS 1024u

enum twb_err {
    TWB_OK          =  0,
    TWB_ERR_IO      = -1,   /* the port failed (read/write/termios) */
    TWB_ERR_TIMEOUT = -2,   /* no (complete) answer in timeout_ms */
    TWB_ERR_GARBLED = -3,   /* an answer that is not one: link out of step */
    TWB_ERR_FRAME   = -4,   /* the bridge kept receiving the request damaged */
    TWB_ERR_BUS     = -5,   /* bus error (the core refused the access) */
    TWB_ERR_ADDR    = -6    /* offset not a multiple of 4 or beyond the window */
};

typedef struct twb_link {
    int      fd;
    uint32_t baud;
    uint32_t timeout_ms;     /* an answer must be complete within this */
    int      failed;         /* sticky: an exchange failed, see err */
    char     err[160];
    uint8_t  status;         /* status byte of the last answer */
    unsigned long exchanges; /* requests answered */
    unsigned long resent;    /* requests sent again after FRAME_ERR */
    unsigned long dropped;   /* answers that reported DROPPED */
} twb_link_t;

int  twb_open(twb_link_t *l, const char *path, uint32_t baud, uint32_t timeout_ms);
void twb_close(twb_link_t *l);

/* one register access; offset = byte offset in the core (multiple of 4) */
int  twb_read(twb_link_t *l, uint32_t offset, uint32_t *value);
int  twb_write(twb_link_t *l, uint32_t offset, uint32_t value);
/* the status byte alone (the irq line, without touching the core) */
int  twb_status(twb_link_t *l, uint8_t *status);
/* silence longer than the bridge's timeout, flush, then a STATUS probe
 * until exactly one status byte comes back */
int  twb_resync(twb_link_t *l);

/* read32/write32/delay_us/wait_irq for twh_init(); ctx = l */
void twb_platform(twb_link_t *l, twh_platform_t *p);

/* monotonic microseconds */
uint64_t twb_now_us(void);

#endif /* TWH_SERIAL_PORT_H */
