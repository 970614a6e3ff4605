/* Firmware of the LiteX drop-in proof (docs/soc.md): the project's C driver
 * (sw/src, unchanged) and the sensor-page tool (sw/tools/twh_page.c, the one
 * twh_cli runs on a PC) on the SoC's VexRiscv, printing every channel's page
 * on the LiteX UART.
 *
 * Platform hooks: register accesses are plain loads and stores in the
 * core's Wishbone window (TWH_BASE from LiteX's mem.h); time is the LiteX
 * timer run free as a 32-bit down-counter, extended to 64 bits here (the
 * SoC leaves out LiteX's 64-bit uptime counter, docs/soc.md); wait_irq
 * waits on the core's interrupt as
 * the CPU sees it: the twh line is unmasked in VexRiscv's interrupt mask
 * CSR (0xBC0) and the hook spins on the pending CSR (0xFC0, LiteX irq.h),
 * never on a core register. Counters of how each wait ended are printed at
 * the end for soc/check_page.py. A CPU that takes no interrupts (SERV: the
 * SoC then has no TWH_INTERRUPT) gets no wait_irq hook, and the driver
 * reads RES_INFO again after each polling step instead.
 */
#include <stdint.h>
#include <stdio.h>

#include <generated/csr.h>
#include <generated/mem.h>
#include <generated/soc.h>
#include <irq.h>

#include "twh.h"
#include "twh_page.h"

#define CYC_PER_US (CONFIG_CLOCK_FREQUENCY / 1000000u)
/* (the SoC carries no identifier string: LiteX's ident costs 62 LC) */
#define SOC_NAME "twowire-host LiteX SoC"

/* ------------------------------------------------------------------ UART */
static int uart_putc(char c, FILE *f)
{
    (void)f;
    if (c == '\n')
        uart_putc('\r', f);
    while (uart_txfull_read())
        ;
    uart_rxtx_write((uint8_t)c);
    return (unsigned char)c;
}

static FILE uart_stdio = FDEV_SETUP_STREAM(uart_putc, NULL, NULL, _FDEV_SETUP_WRITE);
FILE *const stdin = &uart_stdio;
FILE *const stdout = &uart_stdio;
FILE *const stderr = &uart_stdio;

/* picolibc's exit() ends here: the harness has the "end" line by then */
void _exit(int code);
void _exit(int code)
{
    (void)code;
    for (;;)
        ;
}

/* ------------------------------------------------------------------ time */
/* timer0 counts down from 0xFFFFFFFF and reloads; each read adds the
 * cycles since the last one, which is right while reads come less than a
 * wrap apart (2^32 cycles, 179 s at 24 MHz): every wait reads it in a loop */
static uint64_t cyc_total;
static uint32_t cyc_last;

static void time_init(void)
{
    timer0_en_write(0);
    timer0_load_write(0xFFFFFFFFu);
    timer0_reload_write(0xFFFFFFFFu);
    timer0_en_write(1);
    timer0_update_value_write(1);
    cyc_last = timer0_value_read();
}

static uint64_t cycles(void)
{
    uint32_t v;

    timer0_update_value_write(1);
    v = timer0_value_read();
    cyc_total += (uint32_t)(cyc_last - v);
    cyc_last = v;
    return cyc_total;
}

static uint64_t now_us(void *ctx)
{
    (void)ctx;
    return cycles() / CYC_PER_US;
}

/* ------------------------------------------------------------------ hooks */
#ifdef TWH_INTERRUPT
static struct {
    uint32_t waits;      /* wait_irq calls */
    uint32_t woke;       /* ... ended by the core's interrupt */
    uint32_t timed_out;  /* ... ended by max_us */
    uint32_t already;    /* ... found it pending on entry */
} stats;
#endif

static uint32_t twh_read32(void *ctx, uint32_t offset)
{
    (void)ctx;
    return *(volatile uint32_t *)(TWH_BASE + offset);
}

static void twh_write32(void *ctx, uint32_t offset, uint32_t value)
{
    (void)ctx;
    *(volatile uint32_t *)(TWH_BASE + offset) = value;
}

static void twh_delay_us(void *ctx, uint32_t us)
{
    uint64_t end = cycles() + (uint64_t)us * CYC_PER_US;

    (void)ctx;
    while (cycles() < end)
        ;
}

#ifdef TWH_INTERRUPT
static uint32_t twh_wait_irq(void *ctx, uint32_t max_us)
{
    const uint32_t line = 1u << TWH_INTERRUPT;
    uint64_t start = cycles(), end = start + (uint64_t)max_us * CYC_PER_US, now = start;
    uint32_t us;

    (void)ctx;
    stats.waits++;
    if (irq_pending() & line)
        stats.already++;
    for (;;) {
        if (irq_pending() & line) {
            stats.woke++;
            break;
        }
        now = cycles();
        if (now >= end) {
            stats.timed_out++;
            break;
        }
    }
    us = (uint32_t)((now - start) / CYC_PER_US);
    return us ? us : 1u;
}
#define WAIT_IRQ twh_wait_irq
#else
#define WAIT_IRQ NULL
#endif

int main(void)
{
    twh_platform_t plat = {
        twh_read32, twh_write32, twh_delay_us, WAIT_IRQ, NULL
    };
    twh_page_opts_t o = {
        0,                       /* quick: no, the whole page */
        -1,                      /* every channel */
        2000,                    /* timeout_ms */
        "LiteX SoC, " CONFIG_CPU_HUMAN_NAME,
        NULL, NULL,
        NULL,                    /* the bus cannot fail */
        now_us,
        NULL
    };
    uint64_t t0;
    int rc;

    time_init();
    o.out = stdout;
    o.err = stderr;
#ifdef TWH_INTERRUPT
    /* only the core's line: the CPU never takes the interrupt as a trap
     * (mstatus.MIE stays 0), wait_irq reads it from the pending CSR */
    irq_setmask(1u << TWH_INTERRUPT);
    printf("soc: %s, %s, %lu Hz, twh at 0x%08lX, irq %d\n", SOC_NAME,
           CONFIG_CPU_HUMAN_NAME, (unsigned long)CONFIG_CLOCK_FREQUENCY,
           (unsigned long)TWH_BASE, TWH_INTERRUPT);
#else
    printf("soc: %s, %s, %lu Hz, twh at 0x%08lX, no irq (the driver polls)\n",
           SOC_NAME, CONFIG_CPU_HUMAN_NAME, (unsigned long)CONFIG_CLOCK_FREQUENCY,
           (unsigned long)TWH_BASE);
#endif
    t0 = cycles();
    rc = twh_page_run(&plat, &o);
    printf("\nsoc: twh_page_run returned %d after %lu ms of SoC time\n", rc,
           (unsigned long)((cycles() - t0) / CYC_PER_US / 1000u));
#ifdef TWH_INTERRUPT
    printf("soc: wait_irq calls %lu, woken by the interrupt %lu (pending on entry %lu), "
           "timed out %lu\n", (unsigned long)stats.waits, (unsigned long)stats.woke,
           (unsigned long)stats.already, (unsigned long)stats.timed_out);
#endif
    printf("soc: end\n");
    return rc;
}
