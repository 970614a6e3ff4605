/* twh_cli: the sensor page of every channel of a twowire-host board, from a
 * PC, over the board's USB serial port (docs/boards.md).
 *
 * The C driver (sw/src, unmodified) runs here on the PC; its platform hooks
 * go through the board's UART bridge (serial_port.c). The page itself is
 * twh_page.c, which the driver's tests also run against their fake core.
 *
 *   twh_cli -p /dev/ttyUSB1 [-b 115200] [-t ms] [-c ch] [-q]
 */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "serial_port.h"
#include "twh_page.h"

static void usage(const char *argv0)
{
    fprintf(stderr,
            "usage: %s -p PORT [-b BAUD] [-t MS] [-c CH] [-q]\n"
            "  -p PORT  serial port of the board (e.g. /dev/ttyUSB1)\n"
            "  -b BAUD  bridge baud rate (default 115200)\n"
            "  -t MS    give up on an answer or a result after MS ms (default 1000)\n"
            "  -c CH    only channel CH (default: every channel)\n"
            "  -q       quick: firmware and raw readings, no flash reads\n", argv0);
}

static int link_failed(void *ctx)
{
    twb_link_t *l = ctx;

    if (!l->failed)
        return 0;
    fprintf(stderr, "twh_cli: serial link: %s\n", l->err);
    return 1;
}

static uint64_t now_us(void *ctx)
{
    (void)ctx;
    return twb_now_us();
}

int main(int argc, char **argv)
{
    static twb_link_t link;
    const char *port = NULL;
    unsigned long baud = 115200, timeout_ms = 1000;
    char where[200];
    twh_page_opts_t o = { 0 };
    twh_platform_t plat;
    int opt, rc;

    o.only = -1;
    while ((opt = getopt(argc, argv, "p:b:t:c:qh")) != -1) {
        switch (opt) {
        case 'p': port = optarg; break;
        case 'b': baud = strtoul(optarg, NULL, 0); break;
        case 't': timeout_ms = strtoul(optarg, NULL, 0); break;
        case 'c': o.only = strtol(optarg, NULL, 0); break;
        case 'q': o.quick = 1; break;
        default: usage(argv[0]); return 2;
        }
    }
    if (!port || baud == 0 || timeout_ms == 0 || timeout_ms > 4000000ul) {
        usage(argv[0]);
        return 2;
    }
    if (twb_open(&link, port, (uint32_t)baud, (uint32_t)timeout_ms) != TWB_OK) {
        fprintf(stderr, "twh_cli: %s\n", link.err);
        return 1;
    }
    snprintf(where, sizeof where, "%s, %lu baud", port, baud);
    twb_platform(&link, &plat);
    o.timeout_ms = (uint32_t)timeout_ms;
    o.where = where;
    o.out = stdout;
    o.err = stderr;
    o.failed = link_failed;
    o.now_us = now_us;
    o.ctx = &link;
    rc = twh_page_run(&plat, &o);
    if (rc == 0)
        printf("\n%lu bridge requests (%lu sent again), %lu answers reported dropped bytes\n",
               link.exchanges, link.resent, link.dropped);
    twb_close(&link);
    return rc;
}
