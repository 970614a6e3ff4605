/* The sensor page of every channel (what twh_cli prints), over any platform
 * hooks of the C driver. */
#ifndef TWH_PAGE_H
#define TWH_PAGE_H

#include <stdint.h>
#include <stdio.h>

#include "twh.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct twh_page_opts {
    int         quick;        /* firmware and raw readings only, no flash reads */
    long        only;         /* this channel only; -1: every channel */
    uint32_t    timeout_ms;   /* an answer or a result later than this: give up
                               * (at most 4000000) */
    const char *where;        /* the banner's "(...)": port and baud rate */
    FILE       *out, *err;    /* the pages; failures */
    /* the transport: nonzero once it has failed (the hook says why on its
     * own), NULL if it cannot; a monotonic clock in microseconds */
    int       (*failed)(void *ctx);
    uint64_t  (*now_us)(void *ctx);
    void       *ctx;
} twh_page_opts_t;

/* Probes the core, negotiates each channel's execute phase, reads every
 * selected channel's page and prints it. Returns the exit status: 0 done
 * (a channel's own failure is part of its page), 1 the transport, the core
 * or a result failed, 2 no such channel. */
int twh_page_run(const twh_platform_t *plat, const twh_page_opts_t *o);

#ifdef __cplusplus
}
#endif

#endif /* TWH_PAGE_H */
