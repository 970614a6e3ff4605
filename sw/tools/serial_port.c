/* POSIX serial transport for the board's UART bridge (see serial_port.h). */
#define _POSIX_C_SOURCE 200809L
#define _DEFAULT_SOURCE            /* glibc: baud rates above 38400 */

#include "serial_port.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#define FRAME_RETRIES 3

uint64_t twb_now_us(void)
{
    struct timespec ts;

    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u;
}

static void sleep_us(uint64_t us)
{
    struct timespec ts;

    ts.tv_sec = (time_t)(us / 1000000u);
    ts.tv_nsec = (long)(us % 1000000u) * 1000L;
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR)
        ;
}

static int fail(twb_link_t *l, int rc, const char *fmt, ...)
{
    va_list ap;

    if (!l->failed) {              /* keep the first reason */
        va_start(ap, fmt);
        vsnprintf(l->err, sizeof l->err, fmt, ap);
        va_end(ap);
        l->failed = 1;
    }
    return rc;
}

static int baud_code(uint32_t baud, speed_t *code)
{
    static const struct { uint32_t baud; speed_t code; } rates[] = {
        { 9600, B9600 }, { 19200, B19200 }, { 38400, B38400 },
#ifdef B57600
        { 57600, B57600 },
#endif
#ifdef B115200
        { 115200, B115200 },
#endif
#ifdef B230400
        { 230400, B230400 },
#endif
#ifdef B460800
        { 460800, B460800 },
#endif
#ifdef B921600
        { 921600, B921600 },
#endif
#ifdef B1000000
        { 1000000, B1000000 },
#endif
    };
    size_t i;

    for (i = 0; i < sizeof rates / sizeof rates[0]; i++) {
        if (rates[i].baud == baud) {
            *code = rates[i].code;
            return 0;
        }
    }
    return -1;
}

int twb_open(twb_link_t *l, const char *path, uint32_t baud, uint32_t timeout_ms)
{
    struct termios tio;
    speed_t code;

    memset(l, 0, sizeof *l);
    l->fd = -1;
    l->baud = baud;
    l->timeout_ms = timeout_ms;
    if (baud_code(baud, &code) != 0)
        return fail(l, TWB_ERR_IO, "baud rate %lu not supported here", (unsigned long)baud);
    l->fd = open(path, O_RDWR | O_NOCTTY);
    if (l->fd < 0)
        return fail(l, TWB_ERR_IO, "%s: %s", path, strerror(errno));
    if (tcgetattr(l->fd, &tio) != 0) {
        fail(l, TWB_ERR_IO, "%s: not a serial port (%s)", path, strerror(errno));
        twb_close(l);
        return TWB_ERR_IO;
    }
    /* raw 8N1: no echo, no line editing, no CR/LF or flow-control bytes
     * taken out of a binary stream */
    tio.c_iflag &= ~(tcflag_t)(IGNBRK | BRKINT | PARMRK | ISTRIP | INLCR | IGNCR |
                               ICRNL | IXON | IXOFF | IXANY | INPCK);
    tio.c_oflag &= ~(tcflag_t)OPOST;
    tio.c_lflag &= ~(tcflag_t)(ECHO | ECHONL | ICANON | ISIG | IEXTEN);
    tio.c_cflag &= ~(tcflag_t)(CSIZE | PARENB | CSTOPB);
    tio.c_cflag |= (tcflag_t)(CS8 | CREAD | CLOCAL);
#ifdef CRTSCTS
    tio.c_cflag &= ~(tcflag_t)CRTSCTS;
#endif
    tio.c_cc[VMIN] = 0;        /* reads are paced by poll() */
    tio.c_cc[VTIME] = 0;
    if (cfsetispeed(&tio, code) != 0 || cfsetospeed(&tio, code) != 0 ||
        tcsetattr(l->fd, TCSANOW, &tio) != 0) {
        fail(l, TWB_ERR_IO, "%s: cannot set %lu baud 8N1 (%s)", path,
             (unsigned long)baud, strerror(errno));
        twb_close(l);
        return TWB_ERR_IO;
    }
    tcflush(l->fd, TCIOFLUSH);
    return TWB_OK;
}

void twb_close(twb_link_t *l)
{
    if (l->fd >= 0)
        close(l->fd);
    l->fd = -1;
}

static int send_all(twb_link_t *l, const uint8_t *buf, size_t n)
{
    while (n > 0) {
        ssize_t w = write(l->fd, buf, n);

        if (w < 0) {
            if (errno == EINTR)
                continue;
            return fail(l, TWB_ERR_IO, "write: %s", strerror(errno));
        }
        buf += w;
        n -= (size_t)w;
    }
    return TWB_OK;
}

/* n bytes before the deadline (absolute, microseconds); returns the number
 * received (< n on timeout) or TWB_ERR_IO */
static int recv_until(twb_link_t *l, uint8_t *buf, size_t n, uint64_t deadline)
{
    size_t got = 0;

    while (got < n) {
        struct pollfd pfd;
        uint64_t now = twb_now_us();
        int ms, pr;
        ssize_t r;

        if (now >= deadline)
            break;
        ms = (int)((deadline - now + 999u) / 1000u);
        pfd.fd = l->fd;
        pfd.events = POLLIN;
        pfd.revents = 0;
        pr = poll(&pfd, 1, ms);
        if (pr < 0) {
            if (errno == EINTR)
                continue;
            return fail(l, TWB_ERR_IO, "poll: %s", strerror(errno));
        }
        if (pr == 0)
            continue;
        r = read(l->fd, buf + got, n - got);
        if (r < 0) {
            if (errno == EINTR || errno == EAGAIN)
                continue;
            return fail(l, TWB_ERR_IO, "read: %s", strerror(errno));
        }
        if (r == 0 && (pfd.revents & POLLHUP))
            return fail(l, TWB_ERR_IO, "the port hung up");
        got += (size_t)r;
    }
    return (int)got;
}

/* bytes already waiting in the input before a request: the link is out of
 * step (an old answer, line noise) */
static int pending_input(twb_link_t *l)
{
    struct pollfd pfd;

    pfd.fd = l->fd;
    pfd.events = POLLIN;
    pfd.revents = 0;
    return poll(&pfd, 1, 0) > 0 && (pfd.revents & POLLIN);
}

static uint8_t check_byte(const uint8_t *b, size_t n)
{
    uint8_t sum = 0;
    size_t i;

    for (i = 0; i < n; i++)
        sum = (uint8_t)(sum + b[i]);
    return (uint8_t)~sum;
}

/* one request, its answer of nans bytes (status first) */
static int exchange(twb_link_t *l, const uint8_t *req, size_t nreq, uint8_t *ans, size_t nans)
{
    int attempt, got, rc;

    if (l->fd < 0)
        return fail(l, TWB_ERR_IO, "port not open");
    if (l->failed)                 /* no access after a failure: fail fast */
        return TWB_ERR_IO;
    for (attempt = 0; attempt <= FRAME_RETRIES; attempt++) {
        if (pending_input(l)) {
            rc = twb_resync(l);
            if (rc != TWB_OK)
                return rc;
        }
        rc = send_all(l, req, nreq);
        if (rc != TWB_OK)
            return rc;
        got = recv_until(l, ans, nans, twb_now_us() + (uint64_t)l->timeout_ms * 1000u);
        if (got < 0)
            return got;
        if ((size_t)got < nans) {
            rc = fail(l, TWB_ERR_TIMEOUT, "request 0x%02X: %d of %u answer bytes in %lu ms",
                      req[0], got, (unsigned)nans, (unsigned long)l->timeout_ms);
            twb_resync(l);         /* leave the line usable for a next run */
            return rc;
        }
        if ((ans[0] & TWB_ST_MARK_MASK) != TWB_ST_MARK) {
            rc = fail(l, TWB_ERR_GARBLED, "request 0x%02X: answer starts 0x%02X, not a status byte",
                      req[0], ans[0]);
            twb_resync(l);
            return rc;
        }
        l->status = ans[0];
        l->exchanges++;
        if (ans[0] & TWB_ST_DROPPED)
            l->dropped++;
        if (!(ans[0] & TWB_ST_FRAME_ERR))
            return TWB_OK;
        l->resent++;               /* not carried out: safe to send again */
    }
    return fail(l, TWB_ERR_FRAME, "request 0x%02X: the bridge received it damaged %d times",
                req[0], FRAME_RETRIES + 1);
}

static int word_addr(twb_link_t *l, uint32_t offset, uint8_t *a)
{
    if ((offset & 3u) != 0)
        return fail(l, TWB_ERR_ADDR, "offset 0x%03lX is not a register", (unsigned long)offset);
    if (offset >= TWB_WINDOW)
        return fail(l, TWB_ERR_ADDR, "offset 0x%03lX is beyond the bridge's %u-byte window "
                    "(register map version 2: channels 28-31 are out of its reach)",
                    (unsigned long)offset, TWB_WINDOW);
    *a = (uint8_t)(offset >> 2);
    return TWB_OK;
}

int twb_read(twb_link_t *l, uint32_t offset, uint32_t *value)
{
    uint8_t req[3], ans[5];
    int rc;

    rc = word_addr(l, offset, &req[1]);
    if (rc != TWB_OK)
        return rc;
    req[0] = TWB_OP_READ;
    req[2] = check_byte(req, 2);
    rc = exchange(l, req, sizeof req, ans, sizeof ans);
    if (rc != TWB_OK)
        return rc;
    if (ans[0] & TWB_ST_BUS_ERR)
        return TWB_ERR_BUS;
    *value = (uint32_t)ans[1] | (uint32_t)ans[2] << 8 | (uint32_t)ans[3] << 16 |
             (uint32_t)ans[4] << 24;
    return TWB_OK;
}

int twb_write(twb_link_t *l, uint32_t offset, uint32_t value)
{
    uint8_t req[7], ans[1];
    int rc;

    rc = word_addr(l, offset, &req[1]);
    if (rc != TWB_OK)
        return rc;
    req[0] = TWB_OP_WRITE;
    req[2] = (uint8_t)value;
    req[3] = (uint8_t)(value >> 8);
    req[4] = (uint8_t)(value >> 16);
    req[5] = (uint8_t)(value >> 24);
    req[6] = check_byte(req, 6);
    rc = exchange(l, req, sizeof req, ans, sizeof ans);
    if (rc != TWB_OK)
        return rc;
    return (ans[0] & TWB_ST_BUS_ERR) ? TWB_ERR_BUS : TWB_OK;
}

int twb_status(twb_link_t *l, uint8_t *status)
{
    uint8_t req = TWB_OP_STATUS, ans;
    int rc = exchange(l, &req, 1, &ans, 1);

    if (rc == TWB_OK)
        *status = ans;
    return rc;
}

int twb_resync(twb_link_t *l)
{
    /* twice the bridge's silence timeout, and at least 20 ms for the
     * USB-serial adapter's own buffering */
    uint64_t quiet_us = 2u * TWB_TIMEOUT_BITS * 1000000u / l->baud + 20000u;
    uint64_t byte_us = 10u * 1000000u / l->baud + 1u;
    int probe;

    for (probe = 0; probe < 8; probe++) {
        uint8_t req = TWB_OP_STATUS, ans[2];
        int got;

        sleep_us(quiet_us);
        tcflush(l->fd, TCIOFLUSH);
        if (send_all(l, &req, 1) != TWB_OK)
            return TWB_ERR_IO;
        got = recv_until(l, ans, 1, twb_now_us() + (uint64_t)l->timeout_ms * 1000u);
        if (got < 0)
            return got;
        if (got == 0 || (ans[0] & TWB_ST_MARK_MASK) != TWB_ST_MARK)
            continue;
        /* a lone status byte: nothing else may follow it. Otherwise the
         * probe completed an old half request whose answer is arriving. */
        got = recv_until(l, ans + 1, 1, twb_now_us() + 8u * byte_us + 5000u);
        if (got == 0)
            return TWB_OK;
    }
    return fail(l, TWB_ERR_GARBLED, "cannot resynchronise with the bridge");
}

/* ------------------------------------------------------------ driver hooks */
static uint32_t hook_read32(void *ctx, uint32_t offset)
{
    twb_link_t *l = ctx;
    uint32_t v = 0;
    int rc = twb_read(l, offset, &v);

    if (rc == TWB_ERR_BUS)
        fail(l, rc, "bus error reading 0x%03lX", (unsigned long)offset);
    return rc == TWB_OK ? v : 0;
}

static void hook_write32(void *ctx, uint32_t offset, uint32_t value)
{
    twb_link_t *l = ctx;
    int rc = twb_write(l, offset, value);

    if (rc == TWB_ERR_BUS)
        fail(l, rc, "bus error writing 0x%08lX to 0x%03lX", (unsigned long)value,
             (unsigned long)offset);
}

static void hook_delay_us(void *ctx, uint32_t us)
{
    (void)ctx;
    sleep_us(us);
}

/* The bridge reports the irq line in every status byte: poll it. Each poll
 * is a round trip on the serial line, which paces the loop by itself. */
static uint32_t hook_wait_irq(void *ctx, uint32_t max_us)
{
    twb_link_t *l = ctx;
    uint64_t t0 = twb_now_us(), dt;
    uint8_t st = 0;

    for (;;) {
        if (l->failed)
            return max_us ? max_us : 1u;   /* let the driver's timeout end it */
        if (twb_status(l, &st) != TWB_OK || (st & TWB_ST_IRQ))
            break;
        if (twb_now_us() - t0 >= max_us)
            break;
    }
    dt = twb_now_us() - t0;
    if (dt > 0xFFFFFFFFu)
        dt = 0xFFFFFFFFu;
    return dt ? (uint32_t)dt : 1u;
}

void twb_platform(twb_link_t *l, twh_platform_t *p)
{
    p->read32 = hook_read32;
    p->write32 = hook_write32;
    p->delay_us = hook_delay_us;
    p->wait_irq = hook_wait_irq;
    p->ctx = l;
}
