// Verilator soak: the C driver (sw/, unmodified) runs random traffic on three
// channels of the Verilated twh_wb (sim/soak/soak_top.v), each line answered
// by a C++ O2-cell model that injects faults on a chosen fraction of its
// answers and records what it put on the line (periph.h). Every result the
// driver returns, status and data, is checked against that record; any
// mismatch, reception error of the model, spec-timing breach, collision on
// the line or bus error makes the exit code non-zero. Built against the
// LiteX SoC's cells it also runs the sensor-page tool (--page, make demo)
// and the co-simulated driver session (--session, make test); built with
// the rig's 16 or 32 cells, the rig (--rig, make rig, docs/rig.md).
//
// Time belongs to the driver: a register access steps the clock until the
// core answers, the wait/interrupt hook steps it until irq rises. Everything
// is derived from one seed, so a run replays exactly; wall-clock time is only
// measured for the rates printed at the end.
#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <memory>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include <verilated.h>

#include "Vsoak_top.h"
#include "periph.h"
#include "twh.h"
#include "twh_page.h"
#include "twh_regs.h"

#ifndef SOAK_CLK_HZ
#error "SOAK_CLK_HZ must match the Verilated CLK_HZ"
#endif
#ifndef SOAK_CHANNELS
#error "SOAK_CHANNELS must match the Verilated CHANNELS"
#endif

namespace {

using soak::Fault;
using soak::PeriphTxn;

constexpr int NCH = SOAK_CHANNELS;
constexpr double CLK_HZ = SOAK_CLK_HZ;
constexpr uint64_t CYC_PER_US = SOAK_CLK_HZ / 1000000;
static_assert(SOAK_CLK_HZ % 1000000 == 0, "the soak steps whole microseconds");
constexpr int TAGS = 1 << TWH_REGS__CHANNEL_T__CMD_PUSH__TAG_bw;
static_assert(NCH >= 1 && NCH <= static_cast<int>(TWH_MAX_CHANNELS),
              "CHANNELS is 1-32 (register map version 2)");

// the shortest legal transaction (spec table, NOTES.md)
constexpr uint16_t CHARGE_US = 7000, SYNC_US = 900, PREAMBLE_US = 1800,
                   EXECUTE_US = 3500, LISTEN_US = 2000, TURNAROUND_US = 2000;

constexpr uint32_t reg_off(size_t field) { return static_cast<uint32_t>(field); }
uint32_t ch_off(int ch, size_t reg) {
    return static_cast<uint32_t>(offsetof(twh_regs_t, CH) +
                                 static_cast<size_t>(ch) * sizeof(twh_regs__channel_t__stride20_t) + reg);
}

const char *status_name(unsigned s) {
    static const char *n[] = {"OK", "NO_RESPONSE", "BAD_CHECKSUM", "FRAMING", "SHORT_RESPONSE",
                              "LINE_STUCK_LOW", "LINE_STUCK_HIGH", "BLOCKED", "CANCELLED"};
    return s < 9 ? n[s] : "UNDEFINED";
}

struct Options {
    uint64_t transactions = 10000;
    uint64_t seed = 0;
    bool seed_given = false;
    double fault_rate = 0.2;
    int depth = 2;                // commands in flight per channel
    double blocking_rate = 0.05;  // share of issues made by a blocking helper
    uint64_t progress = 1000;
    std::string trace_logic;      // file: every frame and the device's answer
    std::string rate_file;        // file: the rate lines, for make soak's comparison
    bool page = false;            // make demo: the sensor-page tool instead of traffic
    bool session = false;         // make test: the co-simulated driver session
    std::string transcript;       // --session: every frame the cells handled, to this file
    bool rig = false;             // make rig: every cell's page at once, then live readings
    uint32_t live_ms = 500;       // --rig: the live readings' window
    double rig_fault_rate = -1;   // --rig: answers a faulty cell spoils (<0: RIG_FAULT_RATE)
    std::string pages;            // --rig: the page tool's output and the cells' records
    std::string vcd;              // --rig: the lines' waveform (LineVcd)
};

void usage() {
    std::fprintf(stderr,
                 "usage: soak [--transactions N] [--seed S] [--fault-rate F] [--depth D]\n"
                 "            [--blocking-rate B] [--progress N] [--trace-logic FILE]\n"
                 "            [--rate-file FILE]\n"
                 "       soak --page   (make demo: every channel's sensor page, no faults)\n"
                 "       soak --session [--transcript FILE]   (make test: the driver session)\n"
                 "       soak --rig [--live-ms N] [--rig-fault-rate F] [--pages FILE] [--vcd FILE]\n"
                 "            [--seed S]   (make rig: the rig build's cells, docs/rig.md)\n");
    std::exit(2);
}

Options parse(int argc, char **argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto val = [&]() -> const char * {
            if (i + 1 >= argc)
                usage();
            return argv[++i];
        };
        if (a == "--transactions") o.transactions = std::strtoull(val(), nullptr, 0);
        else if (a == "--seed") { o.seed = std::strtoull(val(), nullptr, 0); o.seed_given = true; }
        else if (a == "--fault-rate") o.fault_rate = std::atof(val());
        else if (a == "--depth") o.depth = std::atoi(val());
        else if (a == "--blocking-rate") o.blocking_rate = std::atof(val());
        else if (a == "--progress") o.progress = std::strtoull(val(), nullptr, 0);
        else if (a == "--trace-logic") o.trace_logic = val();
        else if (a == "--rate-file") o.rate_file = val();
        else if (a == "--page") o.page = true;
        else if (a == "--session") o.session = true;
        else if (a == "--transcript") o.transcript = val();
        else if (a == "--rig") o.rig = true;
        else if (a == "--live-ms") o.live_ms = static_cast<uint32_t>(std::strtoul(val(), nullptr, 0));
        else if (a == "--rig-fault-rate") o.rig_fault_rate = std::atof(val());
        else if (a == "--pages") o.pages = val();
        else if (a == "--vcd") o.vcd = val();
        else if (a.rfind("+verilator", 0) == 0) continue;
        else usage();
    }
    if (o.page || o.session || o.rig)
        o.fault_rate = 0;         // healthy cells: a page shows no injected fault
    if (o.rig && o.rig_fault_rate > 1)
        usage();
    if (o.transactions == 0 || o.depth < 1 || o.depth > 4 || o.fault_rate < 0 ||
        o.fault_rate > 1 || o.blocking_rate < 0 || o.blocking_rate > 1)
        usage();
    return o;
}

// ------------------------------------------------------------ expectations
// What the driver must report for one transaction, from the model's record
// and docs/protocol.md ("Receiving the answer", "Results and status codes").
struct Expect {
    uint8_t status = 0;
    uint16_t data = 0;
};

Expect predict(const PeriphTxn &x) {
    Expect e;
    if (!x.answered) {
        e.status = TWH_ST_NO_RESPONSE;
        return e;
    }
    if (x.fault == Fault::StopBit) {
        // a 0 stop bit after eight 0 data bits is a break: the answer ended
        e.status = x.wire[x.fault_byte] == 0 ? TWH_ST_SHORT_RESPONSE : TWH_ST_FRAMING;
        return e;
    }
    if (x.nwire < 3) {
        e.status = TWH_ST_SHORT_RESPONSE;
        return e;
    }
    const uint8_t chk = static_cast<uint8_t>(~(x.wire[0] + x.wire[1]));
    e.status = chk == x.wire[2] ? TWH_ST_OK : TWH_ST_BAD_CHECKSUM;
    e.data = static_cast<uint16_t>(x.wire[0] << 8 | x.wire[1]);
    return e;
}

bool expects_answer(uint8_t cmd) { return cmd >= 0x40 && cmd <= 0x49 && cmd != 0x45; }

// driver error code for a status (the contract in twh.h)
int rc_of(uint8_t status, uint8_t cmd) {
    if (status == TWH_ST_NO_RESPONSE && !expects_answer(cmd))
        return TWH_OK;
    if (status > TWH_ST_CANCELLED)
        return TWH_ERR_HW_STATUS;
    return -static_cast<int>(status);
}

// the frame the host must put on the line for (cmd, payload)
int frame_of(uint8_t cmd, uint16_t payload, uint8_t *f) {
    int n = 0;
    f[n++] = cmd;
    if (cmd >= 0x80)
        f[n++] = static_cast<uint8_t>(payload >> 8);
    f[n++] = static_cast<uint8_t>(payload);
    uint8_t sum = 0;
    for (int i = 0; i < n; ++i)
        sum = static_cast<uint8_t>(sum + f[i]);
    f[n++] = static_cast<uint8_t>(~sum);
    return n;
}

std::string hex(const uint8_t *b, int n) {
    std::string s;
    char buf[4];
    for (int i = 0; i < n; ++i) {
        std::snprintf(buf, sizeof buf, i ? " %02X" : "%02X", b[i]);
        s += buf;
    }
    return s;
}

struct Range {
    double lo = 1e300, hi = -1e300;
    uint64_t n = 0;
    void add(double v) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
        ++n;
    }
};

// ------------------------------------------------------------ the harness
class Soak {
public:
    explicit Soak(const Options &o);
    int run();
    int run_page();
    twh_page_opts_t page_opts(const char *where, FILE *out);
    int run_session();
    int run_rig();

private:
    // simulation
    void tick();
    void run_cycles(uint64_t n) {
        while (n--)
            tick();
    }
    uint32_t access(uint32_t off, bool we, uint32_t v);
    static uint32_t h_read(void *ctx, uint32_t off) {
        return static_cast<Soak *>(ctx)->access(off, false, 0);
    }
    static void h_write(void *ctx, uint32_t off, uint32_t v) {
        static_cast<Soak *>(ctx)->access(off, true, v);
    }
    static void h_delay(void *ctx, uint32_t us) {
        static_cast<Soak *>(ctx)->run_cycles(static_cast<uint64_t>(us) * CYC_PER_US);
    }
    static uint32_t h_wait_irq(void *ctx, uint32_t max_us) {
        return static_cast<Soak *>(ctx)->wait_irq(max_us);
    }
    uint32_t wait_irq(uint32_t max_us);
    void progress();
    static uint64_t h_now_us(void *ctx) { return static_cast<Soak *>(ctx)->cyc_ / CYC_PER_US; }

    // traffic
    void reset_init();
    void setup();
    void pick(int ch, uint8_t &cmd, uint16_t &payload);
    void submit_one(int ch);
    void try_factory(int ch);
    void blocking_one(int ch);
    bool collect();
    void check_result(const twh_result_t &r);
    const PeriphTxn *received(int ch, uint64_t seq, uint8_t cmd, uint16_t payload,
                              const std::string &via);
    int total_inflight() const {
        int n = 0;
        for (int c = 0; c < NCH; ++c)
            n += inflight_[c];
        return n;
    }
    void mismatch(const std::string &s);
    void count_status(uint8_t s) { ++status_count_[s < 9 ? s : 9]; }
    void digest(uint64_t v) {
        for (int i = 0; i < 8; ++i) {
            digest_ ^= (v >> (8 * i)) & 0xFF;
            digest_ *= 0x100000001B3ull;
        }
    }
    void report(double wall_s, double cpu_s);
    bool spec_check();
    uint64_t check_lines();
    int fail_report(const std::string &head, bool spec_ok);
    void write_trace();
    // the rig (docs/rig.md)
    struct LiveCh;
    void live(uint64_t window_cyc, std::vector<LiveCh> &lc, uint64_t &in_window);

    Options opt_;
    std::unique_ptr<VerilatedContext> ctx_;
    std::unique_ptr<Vsoak_top> top_;
    uint64_t cyc_ = 0;
    uint64_t reset_cyc_ = 0;        // the clock the last reset ended
    std::vector<std::unique_ptr<soak::Periph>> periph_;
    std::vector<soak::HostMonitor> mon_;
    std::mt19937_64 rng_;
    twh_t t_{};
    twh_platform_t plat_{};

    struct Pending {
        bool used = false;
        uint64_t seq = 0;
        uint8_t cmd = 0;
        uint16_t payload = 0;
    };
    Pending pending_[NCH][TAGS];
    int inflight_[NCH] = {};
    uint64_t issued_on_[NCH] = {};     // line transactions issued per channel
    uint64_t last_seq_[NCH] = {};      // in-order check of submitted results
    bool have_last_[NCH] = {};
    uint64_t issued_ = 0, checked_ = 0;

    uint64_t accesses_ = 0, bus_errors_ = 0, irq_waits_ = 0;
    uint64_t irq_pending_ = 0, irq_woke_ = 0, irq_timed_out_ = 0;   // how waits ended
    uint64_t mismatches_ = 0, blocking_calls_ = 0, factory_refused_ = 0;
    uint64_t status_count_[10] = {};
    uint64_t helper_count_[9] = {};
    uint64_t digest_ = 0xCBF29CE484222325ull;
    std::vector<std::string> messages_;
    bool stalled_ = false;
    // the rig
    unsigned stuck_ = 0;                   // lines held low (bit a channel)
    std::vector<std::string> rig_fault_;   // each cell's fault (soc/cells.py), "" none
    soak::LineVcd vcd_;
    uint64_t next_progress_cyc_ = 0;
    std::chrono::steady_clock::time_point w0_;
};

#ifdef SOAK_RIG_CELLS
soak::Fault fault_of(const std::string &key) {
    if (key == "checksum") return Fault::Checksum;
    if (key == "silent") return Fault::Silent;
    if (key == "stopbit") return Fault::StopBit;
    if (key == "short") return Fault::Short;
    std::fprintf(stderr, "rig: unknown fault '%s'\n", key.c_str());
    std::exit(2);
}
#endif

Soak::Soak(const Options &o) : opt_(o), ctx_(new VerilatedContext) {
    top_.reset(new Vsoak_top(ctx_.get()));
    // one seed drives the traffic and, derived from it, each device model
    std::seed_seq seq{static_cast<uint32_t>(o.seed), static_cast<uint32_t>(o.seed >> 32)};
    uint64_t seeds[NCH + 1];
    {
        std::vector<uint32_t> w(2 * (NCH + 1));
        seq.generate(w.begin(), w.end());
        for (int i = 0; i <= NCH; ++i)
            seeds[i] = static_cast<uint64_t>(w[2 * i]) << 32 | w[2 * i + 1];
    }
    rng_.seed(seeds[NCH]);
    const int nprof = static_cast<int>(sizeof SOAK_PROFILES / sizeof SOAK_PROFILES[0]);
    for (int ch = 0; ch < NCH; ++ch) {
        double rate = o.fault_rate;
        Fault only = Fault::None;
        std::string key;
#ifdef SOAK_RIG_CELLS
        // the rig: a cell's fault from soc/cells.py, at RIG_FAULT_RATE of its
        // answers; a stuck line holds the line low for the whole run
        static_assert(SOAK_RIG_CELLS == NCH, "the rig's header has one cell a channel");
        if (o.rig) {
            key = RIG_FAULT[ch];
            rate = 0;
            if (key == "stuck_low")
                stuck_ |= 1u << ch;
            else if (!key.empty()) {
                only = fault_of(key);
                rate = o.rig_fault_rate < 0 ? RIG_FAULT_RATE : o.rig_fault_rate;
            }
        }
#endif
        rig_fault_.push_back(key);
        periph_.emplace_back(new soak::Periph(SOAK_PROFILES[ch % nprof], seeds[ch], rate, CLK_HZ));
        periph_.back()->only_fault(only);
        mon_.emplace_back(CLK_HZ);
    }
    top_->stuck_en = static_cast<std::remove_reference_t<decltype(top_->stuck_en)>>(stuck_);
    top_->stuck_val = 0;
    plat_.read32 = h_read;
    plat_.write32 = h_write;
    plat_.delay_us = h_delay;
    plat_.wait_irq = h_wait_irq;
    plat_.ctx = this;
}

// One clock: rising edge, the models see the new pins and answer, falling
// edge (Verilator only sees an edge across two evaluations).
void Soak::tick() {
    Vsoak_top &d = *top_;
    d.clk = 1;
    d.eval();
    ++cyc_;
    const soak::LineDrive drv = soak::step_channels(periph_, mon_, cyc_, d.line, d.line_o, d.line_oe);
    d.periph_o = static_cast<std::remove_reference_t<decltype(d.periph_o)>>(drv.o);
    d.periph_oe = static_cast<std::remove_reference_t<decltype(d.periph_oe)>>(drv.oe);
    if (vcd_.is_open())
        vcd_.step(d.line, d.line_oe, drv.oe);
    d.clk = 0;
    d.eval();
}

// The clocks after a reset in which the register port takes no request
// (docs/registers.md, "After a reset"): the reset sweep writes four words a
// channel, rounded up to a power of two and at least 16, then waits as long
// again.
static uint64_t sweep_clocks(unsigned channels) {
    uint64_t words = 16;
    while (words < 4ull * channels)
        words *= 2;
    return 2 * words;
}

// One Wishbone classic access: the core takes the strobe at one edge, carries
// it out at the next and answers (ack or err, registered) until the one after,
// where the master sees the answer and ends the access (rtl/twh_wb.v). After a
// reset the core takes the strobe only once its reset sweep is over; an answer
// at any other time, or none, is counted as a bus error.
uint32_t Soak::access(uint32_t off, bool we, uint32_t v) {
    Vsoak_top &d = *top_;
    d.wb_adr_i = static_cast<uint16_t>(off);
    d.wb_dat_i = v;
    d.wb_we_i = we;
    d.wb_sel_i = 0xF;
    d.wb_cyc_i = 1;
    d.wb_stb_i = 1;
    const uint64_t start = cyc_;
    const uint64_t ready = reset_cyc_ + sweep_clocks(NCH) + 1;
    const uint64_t wait = ready > start ? ready - start : 0;    // the sweep's part
    tick();
    const bool early = d.wb_ack_o || d.wb_err_o;
    tick();
    uint64_t n = 2;
    while (!early && !d.wb_ack_o && !d.wb_err_o && n < 2 + wait) {
        tick();
        ++n;
    }
    const bool ack = d.wb_ack_o, err = d.wb_err_o;
    const uint32_t data = d.wb_dat_o;
    tick();
    d.wb_cyc_i = 0;
    d.wb_stb_i = 0;
    d.wb_we_i = 0;
    ++accesses_;
    if (ack == err || early) {
        ++bus_errors_;
        char buf[96];
        std::snprintf(buf, sizeof buf, "bus %s 0x%03X: %s", we ? "write" : "read", off,
                      early ? "answered one clock after the strobe"
                      : ack ? "ack and err" : "no answer two clocks after the strobe is taken");
        mismatch(buf);
    } else if (err) {
        ++bus_errors_;
        char buf[96];
        std::snprintf(buf, sizeof buf, "bus %s 0x%03X = 0x%08X got a bus error", we ? "write" : "read",
                      off, v);
        mismatch(buf);
    }
    return data;
}

uint32_t Soak::wait_irq(uint32_t max_us) {
    ++irq_waits_;
    if (next_progress_cyc_ && cyc_ >= next_progress_cyc_)
        progress();
    if (top_->irq) {
        ++irq_pending_;
        ++irq_woke_;
        return 1;
    }
    const uint64_t c0 = cyc_, lim = c0 + static_cast<uint64_t>(max_us) * CYC_PER_US;
    while (!top_->irq && cyc_ < lim)
        tick();
    ++(top_->irq ? irq_woke_ : irq_timed_out_);
    const uint64_t us = (cyc_ - c0) / CYC_PER_US;
    return us ? static_cast<uint32_t>(us) : 1u;
}

void Soak::mismatch(const std::string &s) {
    ++mismatches_;
    if (messages_.size() < 30)
        messages_.push_back(s);
}

// ------------------------------------------------------------ traffic
void Soak::reset_init() {
    Vsoak_top &d = *top_;
    d.rst = 1;
    d.wb_sel_i = 0xF;
    run_cycles(8);
    d.rst = 0;
    reset_cyc_ = cyc_;
    tick();
    const int rc = twh_init(&t_, &plat_);
    if (rc != TWH_OK || t_.channels != NCH || t_.clk_khz != SOAK_CLK_HZ / 1000) {
        std::fprintf(stderr, "soak: twh_init = %d, %u channels, %u kHz\n", rc, t_.channels,
                     t_.clk_khz);
        std::exit(1);
    }
}

void Soak::setup() {
    reset_init();
    for (int ch = 0; ch < NCH; ++ch) {
        const uint32_t t0 = CHARGE_US | static_cast<uint32_t>(SYNC_US) << 16;
        const uint32_t t1 = PREAMBLE_US | static_cast<uint32_t>(EXECUTE_US) << 16;
        const uint32_t t2 = LISTEN_US | static_cast<uint32_t>(TURNAROUND_US) << 16;
        const uint32_t o0 = ch_off(ch, offsetof(twh_regs__channel_t__stride20_t, TIMING0));
        const uint32_t o1 = ch_off(ch, offsetof(twh_regs__channel_t__stride20_t, TIMING1));
        const uint32_t o2 = ch_off(ch, offsetof(twh_regs__channel_t__stride20_t, TIMING2));
        access(o0, true, t0);
        access(o1, true, t1);
        access(o2, true, t2);
        // the driver's own timing call reads back what the core kept
        if (twh_set_execute_us(&t_, static_cast<uint8_t>(ch), EXECUTE_US) != TWH_OK ||
            access(o0, false, 0) != t0 ||
            access(o1, false, 0) != t1 || access(o2, false, 0) != t2) {
            std::fprintf(stderr, "soak: channel %d refused the minimum spec timing\n", ch);
            std::exit(1);
        }
    }
}

// A random command: the O2 cell's read commands, flash reads and find-free
// (mostly inside the flash, some beyond it: no answer), writes and erases of
// the field area, and a few reserved commands.
void Soak::pick(int ch, uint8_t &cmd, uint16_t &payload) {
    const unsigned size = periph_[static_cast<size_t>(ch)]->device().profile().size;
    auto addr_any = [&]() -> unsigned {
        return rng_() % 100 < 85 ? static_cast<unsigned>(rng_() % size)
                                 : static_cast<unsigned>(rng_() % 0x200);
    };
    auto addr_field = [&]() -> unsigned {
        return rng_() % 100 < 90 ? TWH_CAL_START + static_cast<unsigned>(rng_() % (size - TWH_CAL_START))
                                 : TWH_CAL_START + static_cast<unsigned>(rng_() % (0x200 - TWH_CAL_START));
    };
    const unsigned r = static_cast<unsigned>(rng_() % 100);
    payload = TWH_UNUSED_PAYLOAD;
    if (r < 30) {
        cmd = static_cast<uint8_t>(0x40 + rng_() % 5);
    } else if (r < 78) {
        const unsigned a = addr_any();
        cmd = static_cast<uint8_t>((r < 70 ? TWH_CMD_READ : TWH_CMD_FIND_FREE) | a >> 8);
        payload = static_cast<uint16_t>(a & 0xFFu);
    } else if (r < 92) {
        const unsigned a = addr_field();
        uint16_t w = static_cast<uint16_t>(rng_() % TWH_BLANK);
        twh_encode_write(static_cast<uint16_t>(a), w, &cmd, &payload);
    } else if (r < 96) {
        const unsigned a = addr_field();
        cmd = static_cast<uint8_t>(TWH_CMD_ERASE | a >> 8);
        payload = static_cast<uint16_t>(a & 0xFFu);
    } else {
        static const uint8_t reserved[] = {0x00, 0x21, 0x3F, 0x45, 0x4C, 0x60, 0x7F};
        cmd = reserved[rng_() % sizeof reserved];
        payload = static_cast<uint16_t>(rng_() & 0xFFu);
    }
}

void Soak::submit_one(int ch) {
    uint8_t cmd;
    uint16_t payload;
    pick(ch, cmd, payload);
    const int tag = twh_submit(&t_, static_cast<uint8_t>(ch), cmd, payload);
    if (tag < 0 || tag >= TAGS) {
        mismatch("twh_submit(ch" + std::to_string(ch) + ") = " + std::to_string(tag));
        return;
    }
    Pending &p = pending_[ch][tag];
    if (p.used)
        mismatch("tag " + std::to_string(tag) + " handed out again while in flight");
    p.used = true;
    p.seq = issued_on_[ch]++;
    p.cmd = cmd;
    p.payload = payload;
    ++inflight_[ch];
    ++issued_;
}

// The driver refuses erase/write of words 0x00-0x1F before any bus access.
void Soak::try_factory(int ch) {
    uint8_t cmd;
    uint16_t payload;
    const uint16_t a = static_cast<uint16_t>(rng_() % TWH_FACTORY_END);
    if (rng_() & 1u) {
        cmd = static_cast<uint8_t>(TWH_CMD_ERASE);
        payload = a;
    } else {
        twh_encode_write(a, static_cast<uint16_t>(rng_() % TWH_BLANK), &cmd, &payload);
    }
    const uint64_t before = accesses_;
    const int rc = twh_submit(&t_, static_cast<uint8_t>(ch), cmd, payload);
    if (rc != TWH_ERR_BAD_ARG || accesses_ != before)
        mismatch("factory-area command 0x" + std::to_string(cmd) + " not refused by the driver (rc " +
                 std::to_string(rc) + ")");
    ++factory_refused_;
}

// The record of line transaction `seq` of a channel, when the peripheral
// followed the host through it and received exactly the frame (cmd,
// payload) must produce; otherwise a mismatch and nullptr.
const PeriphTxn *Soak::received(int ch, uint64_t seq, uint8_t cmd, uint16_t payload,
                                const std::string &via) {
    ++checked_;
    const auto &log = periph_[static_cast<size_t>(ch)]->log;
    char head[96];
    std::snprintf(head, sizeof head, ": ch%d #%" PRIu64 " cmd 0x%02X: ", ch, seq, cmd);
    if (seq >= log.size()) {
        mismatch(via + head + "never reached the peripheral");
        return nullptr;
    }
    const PeriphTxn &x = log[seq];
    if (!x.error.empty()) {
        mismatch(via + head + "the peripheral could not follow the host: " + x.error +
                 " (frame so far [" + hex(x.frame, x.flen) + "])");
        return nullptr;
    }
    uint8_t f[4];
    const int n = frame_of(cmd, payload, f);
    if (x.flen != n || std::memcmp(x.frame, f, static_cast<size_t>(n)) != 0) {
        mismatch(via + head + "the line carried [" + hex(x.frame, x.flen) + "], expected [" +
                 hex(f, n) + "]");
        return nullptr;
    }
    return &x;
}

void Soak::check_result(const twh_result_t &r) {
    count_status(r.status);
    if (r.channel >= NCH || r.tag >= TAGS || !pending_[r.channel][r.tag].used) {
        mismatch("result for nothing in flight: ch" + std::to_string(r.channel) + " tag " +
                 std::to_string(r.tag));
        return;
    }
    Pending &p = pending_[r.channel][r.tag];
    p.used = false;
    --inflight_[r.channel];
    if (r.cmd != p.cmd)
        mismatch("ch" + std::to_string(r.channel) + " tag " + std::to_string(r.tag) +
                 ": result carries command " + std::to_string(r.cmd) + ", submitted " +
                 std::to_string(p.cmd));
    if (have_last_[r.channel] && p.seq <= last_seq_[r.channel])
        mismatch("ch" + std::to_string(r.channel) + ": results out of order");
    have_last_[r.channel] = true;
    last_seq_[r.channel] = p.seq;
    digest(static_cast<uint64_t>(r.channel) << 56 | static_cast<uint64_t>(r.cmd) << 48 |
           static_cast<uint64_t>(r.status) << 40 | static_cast<uint64_t>(r.data) << 24 |
           (p.seq & 0xFFFFFF));
    const PeriphTxn *x = received(r.channel, p.seq, p.cmd, p.payload, "twh_result");
    if (!x)
        return;
    const Expect e = predict(*x);
    if (r.status != e.status || r.data != e.data) {
        char buf[320];
        std::snprintf(buf, sizeof buf,
                      "twh_result: ch%u #%" PRIu64 " cmd 0x%02X: got %s 0x%04X; the peripheral sent "
                      "[%s] (fault %s%s, %.0f baud, %.3f MHz, duty %.2f, %d stop bits): expected %s 0x%04X",
                      r.channel, p.seq, p.cmd, status_name(r.status), r.data,
                      hex(x->wire, x->answered ? x->nwire : 0).c_str(), soak::fault_name(x->fault),
                      x->fault == Fault::StopBit ? (" in byte " + std::to_string(x->fault_byte)).c_str() : "",
                      x->baud, x->carrier_hz / 1e6, x->duty, x->stop_bits, status_name(e.status), e.data);
        mismatch(buf);
    }
}

// Pops every result ready; when none is, sleeps on irq (the result
// threshold, IRQ_EN.RESULT set by twh_init). False when nothing came for a
// simulated second.
bool Soak::collect() {
    if (twh_poll(&t_) == 0 && wait_irq(1000000) >= 1000000 && !top_->irq) {
        mismatch("no result for a simulated second with " +
                 std::to_string(total_inflight()) + " in flight");
        stalled_ = true;
        return false;
    }
    twh_result_t r;
    int rc;
    while ((rc = twh_result(&t_, &r)) == TWH_OK)
        check_result(r);
    if (rc != TWH_ERR_AGAIN)
        mismatch("twh_result = " + std::to_string(rc));
    return true;
}

// A blocking helper on one channel. Results of other commands that arrive
// while it waits go to the driver's stash (TWH_STASH_SIZE entries): first
// let the number in flight drop to what the stash can hold.
void Soak::blocking_one(int ch) {
    while (total_inflight() > TWH_STASH_SIZE && !stalled_)
        collect();
    if (stalled_)
        return;
    const uint8_t c8 = static_cast<uint8_t>(ch);
    const uint64_t s0 = issued_on_[ch];
    const unsigned size = periph_[static_cast<size_t>(ch)]->device().profile().size;
    const unsigned kind = static_cast<unsigned>(rng_() % 9);
    const uint16_t addr = static_cast<uint16_t>(rng_() % 100 < 90 ? rng_() % size : rng_() % 0x200);
    const uint16_t field = static_cast<uint16_t>(TWH_CAL_START + rng_() % (size - TWH_CAL_START));
    const uint16_t word = static_cast<uint16_t>(rng_() % TWH_BLANK);
    ++blocking_calls_;
    ++helper_count_[kind];
    int rc = 0, want = 0;
    uint64_t n = 1;
    std::string what;
    // the k-th transaction of this call: what the driver must have seen
    auto st = [&](uint64_t k, uint8_t cmd, uint16_t payload, Expect &e) -> bool {
        const PeriphTxn *x = received(ch, s0 + k, cmd, payload, what);
        if (!x)
            return false;
        e = predict(*x);
        digest(static_cast<uint64_t>(ch) << 56 | static_cast<uint64_t>(cmd) << 48 |
               static_cast<uint64_t>(e.status) << 40 | static_cast<uint64_t>(e.data) << 24 |
               ((s0 + k) & 0xFFFFFF));
        return true;
    };
    auto out16 = [&](unsigned got, unsigned expect) {
        if (rc == TWH_OK && got != expect) {
            char buf[96];
            std::snprintf(buf, sizeof buf, " on ch%d: value 0x%04X, expected 0x%04X", ch, got, expect);
            mismatch(what + buf);
        }
    };
    Expect e;
    uint8_t cmd = 0;
    uint16_t payload = TWH_UNUSED_PAYLOAD;
    switch (kind) {
    case 0: case 1: case 2: {        // ADC readings: 12 bits
        static const char *names[] = {"twh_ref_voltage", "twh_temperature", "twh_o2_voltage"};
        what = names[kind];
        cmd = static_cast<uint8_t>(TWH_CMD_REF_VOLTAGE + kind);
        uint16_t v = 0;
        rc = kind == 0 ? twh_ref_voltage(&t_, c8, &v)
           : kind == 1 ? twh_temperature(&t_, c8, &v) : twh_o2_voltage(&t_, c8, &v);
        if (st(0, cmd, payload, e)) {
            want = rc_of(e.status, cmd);
            out16(v, e.data & 0xFFFu);
        }
        break;
    }
    case 3: {
        what = "twh_firmware";
        cmd = TWH_CMD_FIRMWARE;
        twh_fw_t fw{};
        rc = twh_firmware(&t_, c8, &fw);
        if (st(0, cmd, payload, e)) {
            want = rc_of(e.status, cmd);
            out16(static_cast<unsigned>(fw.raw << 8 | fw.type), e.data);
        }
        break;
    }
    case 4: {
        what = "twh_config";
        cmd = TWH_CMD_CONFIG;
        uint8_t bits = 0;
        uint16_t words = 0;
        rc = twh_config(&t_, c8, &bits, &words);
        if (st(0, cmd, payload, e)) {
            want = rc_of(e.status, cmd);
            out16(static_cast<unsigned>(bits) << 9 | words, e.data);
        }
        break;
    }
    case 5: {
        what = "twh_read_word";
        twh_encode_addr(TWH_CMD_READ, addr, &cmd, &payload);
        uint16_t w = 0;
        rc = twh_read_word(&t_, c8, addr, &w);
        if (st(0, cmd, payload, e)) {
            want = rc_of(e.status, cmd);
            out16(w, e.data & TWH_WORD_MASK);
        }
        break;
    }
    case 6: {
        what = "twh_find_free";
        twh_encode_addr(TWH_CMD_FIND_FREE, addr, &cmd, &payload);
        uint16_t a = 0;
        rc = twh_find_free(&t_, c8, addr, &a);
        if (st(0, cmd, payload, e)) {
            want = rc_of(e.status, cmd);
            if (want == TWH_OK && (e.data < addr || e.data > TWH_ADDR_MAX + 1u))
                want = TWH_ERR_BAD_RESPONSE;
            out16(a, e.data);
        }
        break;
    }
    case 7: {
        what = "twh_erase_page";
        twh_encode_addr(TWH_CMD_ERASE, field, &cmd, &payload);
        rc = twh_erase_page(&t_, c8, field);
        if (st(0, cmd, payload, e))
            want = rc_of(e.status, cmd);
        break;
    }
    default: {                      // write, then the driver reads it back
        what = "twh_write_word";
        twh_encode_write(field, word, &cmd, &payload);
        rc = twh_write_word(&t_, c8, field, word);
        if (!st(0, cmd, payload, e))
            break;
        want = rc_of(e.status, cmd);
        if (want != TWH_OK)
            break;
        n = 2;
        twh_encode_addr(TWH_CMD_READ, field, &cmd, &payload);
        if (!st(1, cmd, payload, e))
            break;
        want = rc_of(e.status, cmd);
        if (want == TWH_OK && (e.data & TWH_WORD_MASK) != word)
            want = TWH_ERR_VERIFY;
        break;
    }
    }
    if (rc != want)
        mismatch(what + " on ch" + std::to_string(ch) + " returned " + std::to_string(rc) +
                 ", expected " + std::to_string(want));
    // nothing else may have reached this line meanwhile
    const uint64_t seen = periph_[static_cast<size_t>(ch)]->log.size();
    if (seen != s0 + n)
        mismatch(what + " on ch" + std::to_string(ch) + ": " + std::to_string(seen - s0) +
                 " transactions on the line, expected " + std::to_string(n));
    issued_on_[ch] = s0 + n;
    issued_ += n;
}

// Every phase the model and the monitor measured, against the spec's table.
bool Soak::spec_check() {
    constexpr double TOL = 1.5;
    Range charge, sync, pre, cmd3, cmd4, exec, listen, turn;
    uint64_t bad = 0;
    auto need = [&](bool ok, int ch, uint64_t i, const char *what, double v) {
        if (ok)
            return;
        ++bad;
        char buf[128];
        std::snprintf(buf, sizeof buf, "spec: ch%d transaction #%" PRIu64 ": %s %.2f us", ch, i, what, v);
        mismatch(buf);
    };
    for (int ch = 0; ch < NCH; ++ch) {
        const auto &log = periph_[static_cast<size_t>(ch)]->log;
        const double exec_max = periph_[static_cast<size_t>(ch)]->device().profile().exec_max_us;
        for (uint64_t i = 0; i < log.size(); ++i) {
            const PeriphTxn &x = log[i];
            if (!x.error.empty())
                continue;                     // reported by the result checks
            charge.add(x.charge_us);
            sync.add(x.sync_us);
            pre.add(x.preamble_us);
            (x.flen == 4 ? cmd4 : cmd3).add(x.command_us);
            exec.add(x.execute_us);
            need(x.charge_us >= 7000 - TOL, ch, i, "charge", x.charge_us);
            need(x.sync_us >= 900 - TOL && x.sync_us <= 1100 + TOL, ch, i, "sync", x.sync_us);
            need(x.preamble_us >= 1800 - TOL && x.preamble_us <= 2200 + TOL, ch, i, "preamble", x.preamble_us);
            need(x.command_us >= 1000 - TOL && x.command_us <= 1500 + TOL, ch, i, "command", x.command_us);
            need(x.execute_us >= 3500 - TOL && x.execute_us <= exec_max + TOL, ch, i, "execute", x.execute_us);
        }
        const soak::HostMonitor &m = mon_[static_cast<size_t>(ch)];
        for (uint64_t i = 0; i < m.listen_us.size(); ++i) {
            listen.add(m.listen_us[i]);
            need(m.listen_us[i] >= 2000 - TOL, ch, i, "listen", m.listen_us[i]);
        }
        for (uint64_t i = 0; i < m.turnaround_us.size(); ++i) {
            turn.add(m.turnaround_us[i]);
            need(m.turnaround_us[i] >= 2000 - TOL, ch, i, "turnaround", m.turnaround_us[i]);
        }
        for (const std::string &v : m.violations) {
            ++bad;
            mismatch("spec: ch" + std::to_string(ch) + ": " + v);
        }
        // every transaction the peripheral saw had its listen window
        if (m.listen_us.size() + 1 < log.size())
            mismatch("spec: ch" + std::to_string(ch) + ": " + std::to_string(m.listen_us.size()) +
                     " listen windows for " + std::to_string(log.size()) + " transactions");
    }
    auto row = [](const char *name, const Range &r) {
        if (r.n)
            std::printf("  %-18s %9.1f - %9.1f us  (%" PRIu64 ")\n", name, r.lo, r.hi, r.n);
    };
    std::printf("phases on the lines (spec window checked for every one):\n");
    row("charge", charge);
    row("sync", sync);
    row("preamble", pre);
    row("command, 3 bytes", cmd3);
    row("command, 4 bytes", cmd4);
    row("execute", exec);
    row("listen", listen);
    row("turnaround", turn);
    double pmin = 1e9, pmax = 0, dmin = 1, dmax = 0;
    uint64_t periods = 0;
    for (const auto &m : mon_) {
        pmin = std::min(pmin, m.period_min_us);
        pmax = std::max(pmax, m.period_max_us);
        dmin = std::min(dmin, m.duty_min);
        dmax = std::max(dmax, m.duty_max);
        periods += m.periods;
    }
    std::printf("  host carrier: %" PRIu64 " periods, %.3f - %.3f us, duty %.0f - %.0f %%\n", periods,
                pmin, pmax, 100 * dmin, 100 * dmax);
    return bad == 0;
}

void Soak::write_trace() {
    FILE *f = std::fopen(opt_.trace_logic.c_str(), "w");
    if (!f) {
        mismatch("cannot write " + opt_.trace_logic);
        return;
    }
    std::fprintf(f, "# channel profile frame -> device answer (MSB LSB) or -\n");
    for (int ch = 0; ch < NCH; ++ch) {
        const soak::Periph &p = *periph_[static_cast<size_t>(ch)];
        for (const PeriphTxn &x : p.log) {
            if (!x.error.empty() && std::strcmp(x.error.c_str(), "execute phase too long") != 0)
                continue;                   // never handled
            std::fprintf(f, "%d %s %s -> ", ch, p.device().profile().name, hex(x.frame, x.flen).c_str());
            if (x.answers)
                std::fprintf(f, "%02X %02X\n", x.dev_msb, x.dev_lsb);
            else
                std::fprintf(f, "-\n");
        }
    }
    std::fclose(f);
}

void Soak::report(double wall_s, double cpu_s) {
    uint64_t faults[5] = {}, stop_on_zero = 0, answered = 0, total = 0, errors = 0;
    Range baud, carrier, duty;
    for (const auto &p : periph_) {
        for (const PeriphTxn &x : p->log) {
            ++total;
            if (!x.error.empty()) {
                ++errors;
                continue;
            }
            if (!x.answers)
                continue;
            ++faults[static_cast<int>(x.fault)];
            if (x.fault == Fault::StopBit && x.wire[x.fault_byte] == 0)
                ++stop_on_zero;
            if (x.answered) {
                ++answered;
                baud.add(x.baud);
                carrier.add(x.carrier_hz / 1e6);
                duty.add(100 * x.duty);
            }
        }
    }
    std::printf("transactions checked: %" PRIu64 "; statuses popped with twh_result:", checked_);
    for (unsigned s = 0; s < 10; ++s)
        if (status_count_[s])
            std::printf(" %s %" PRIu64, status_name(s), status_count_[s]);
    std::printf("\n");
    static const char *helpers[9] = {"ref_voltage", "temperature", "o2_voltage", "firmware", "config",
                                     "read_word", "find_free", "erase_page", "write_word"};
    std::printf("blocking helpers: %" PRIu64 " calls (", blocking_calls_);
    for (int k = 0; k < 9; ++k)
        std::printf("%s%s %" PRIu64, k ? ", " : "", helpers[k], helper_count_[k]);
    std::printf(")\n");
    std::printf("answers: %" PRIu64 " with an answer from the device; faults injected: no response %" PRIu64
                ", bad checksum %" PRIu64 ", stop bit 0 %" PRIu64 " (%" PRIu64
                " on a 0x00 byte: a break), short %" PRIu64 "\n",
                faults[0] + faults[1] + faults[2] + faults[3] + faults[4], faults[1], faults[2],
                faults[3], stop_on_zero, faults[4]);
    if (answered)
        std::printf("answers on the line: %" PRIu64 ", %.0f-%.0f baud, carrier %.3f-%.3f MHz, duty %.0f-%.0f %%\n",
                    answered, baud.lo, baud.hi, carrier.lo, carrier.hi, duty.lo, duty.hi);
    std::printf("driver: %" PRIu64 " bus accesses, %" PRIu64 " interrupt waits, %" PRIu64
                " factory-area commands refused before the bus\n",
                accesses_, irq_waits_, factory_refused_);
    uint64_t collisions = 0;
    for (const auto &p : periph_)
        collisions += p->collisions;
    std::printf("peripheral reception errors: %" PRIu64 "; collisions: %" PRIu64 "; bus errors: %" PRIu64
                "\n", errors, collisions, bus_errors_);
    const double sim_ms = static_cast<double>(cyc_) / CLK_HZ * 1e3;
    // the machine may be shared: CPU time shows what the soak itself cost
    std::printf("simulated %.1f ms (%" PRIu64 " clocks at %.0f MHz) in %.2f s wall, %.2f s CPU\n",
                sim_ms, cyc_, CLK_HZ / 1e6, wall_s, cpu_s);
    char rate[256];
    std::snprintf(rate, sizeof rate,
                  "rate: %.1f transactions/s, %.1f simulated ms/s per wall second\n"
                  "      %.1f transactions/s, %.1f simulated ms/s per CPU second\n",
                  static_cast<double>(total) / wall_s, sim_ms / wall_s,
                  static_cast<double>(total) / cpu_s, sim_ms / cpu_s);
    std::printf("%s", rate);
    if (!opt_.rate_file.empty()) {
        FILE *f = std::fopen(opt_.rate_file.c_str(), "w");
        if (f) {
            std::fprintf(f, "Verilator, this run (%" PRIu64 " transactions, seed %" PRIu64 "):\n%s",
                         total, opt_.seed, rate);
            std::fclose(f);
        }
    }
    std::printf("digest: %016" PRIx64 " (same seed, same digest)\n", digest_);
}

int Soak::run() {
    std::printf("soak: seed %" PRIu64 "%s, %" PRIu64 " transactions on %d channels (",
                opt_.seed, opt_.seed_given ? "" : " (fresh)", opt_.transactions, NCH);
    for (int ch = 0; ch < NCH; ++ch)
        std::printf("%s%s", ch ? ", " : "", periph_[static_cast<size_t>(ch)]->device().profile().name);
    std::printf("), fault rate %.2f, %d in flight per channel, blocking rate %.2f\n", opt_.fault_rate,
                opt_.depth, opt_.blocking_rate);
    std::printf("replay: --seed %" PRIu64 " --transactions %" PRIu64 " --fault-rate %g --depth %d "
                "--blocking-rate %g\n",
                opt_.seed, opt_.transactions, opt_.fault_rate, opt_.depth, opt_.blocking_rate);
    std::fflush(stdout);
    const auto w0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    setup();
    uint64_t next_progress = opt_.progress;
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    int first = 0;
    while ((issued_ < opt_.transactions || total_inflight() > 0) && !stalled_) {
        // keep every channel busy; start at a different channel each round
        for (int k = 0; k < NCH && issued_ < opt_.transactions && !stalled_; ++k) {
            const int ch = (first + k) % NCH;
            while (inflight_[ch] < opt_.depth && issued_ < opt_.transactions && !stalled_) {
                const double r = u01(rng_);
                if (r < opt_.blocking_rate)
                    blocking_one(ch);
                else {
                    if (r > 0.995)
                        try_factory(ch);
                    submit_one(ch);
                }
            }
        }
        first = (first + 1) % NCH;
        collect();
        if (opt_.progress && issued_ >= next_progress) {
            const double w = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
            std::printf("  %" PRIu64 " transactions, simulated %.1f s, %.1f s wall, %" PRIu64 " mismatches\n",
                        issued_, static_cast<double>(cyc_) / CLK_HZ, w, mismatches_);
            std::fflush(stdout);
            next_progress += opt_.progress;
        }
    }
    // let the last turnarounds finish, so every listen window is closed
    run_cycles(3000 * CYC_PER_US);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    // nothing left over: every line transaction was checked, the core is idle
    for (int ch = 0; ch < NCH; ++ch)
        if (periph_[static_cast<size_t>(ch)]->log.size() != issued_on_[ch])
            mismatch("ch" + std::to_string(ch) + ": " +
                     std::to_string(periph_[static_cast<size_t>(ch)]->log.size()) +
                     " transactions on the line, " + std::to_string(issued_on_[ch]) + " issued");
    const uint32_t status = access(reg_off(offsetof(twh_regs_t, STATUS)), false, 0);
    const uint32_t busy = access(reg_off(offsetof(twh_regs_t, BUSY)), false, 0);
    const uint32_t errors = access(reg_off(offsetof(twh_regs_t, ERRORS)), false, 0);
    if (busy || !(status & TWH_REGS__STATUS__RES_EMPTY_bm) ||
        !(status & TWH_REGS__STATUS__CMD_EMPTY_bm)) {
        char buf[80];
        std::snprintf(buf, sizeof buf, "core not idle and empty at the end: STATUS 0x%08X, BUSY 0x%08X",
                      status, busy);
        mismatch(buf);
    }
    // link errors are expected (injected faults); nothing else may be flagged
    if (errors & ~static_cast<uint32_t>(TWH_REGS__ERRORS__LINK_ERROR_bm))
        mismatch("ERRORS = " + std::to_string(errors));
    for (int ch = 0; ch < NCH; ++ch)
        if (periph_[static_cast<size_t>(ch)]->collisions)
            mismatch("ch" + std::to_string(ch) + ": the host drove the line during an answer for " +
                     std::to_string(periph_[static_cast<size_t>(ch)]->collisions) + " clocks");
    const bool spec_ok = spec_check();
    if (!opt_.trace_logic.empty())
        write_trace();
    report(wall, cpu);
    top_->final();
    if (mismatches_) {
        std::printf("FAIL: %" PRIu64 " mismatches%s; first ones:\n", mismatches_,
                    spec_ok ? "" : " (spec-timing breaches among them)");
        for (const std::string &m : messages_)
            std::printf("  %s\n", m.c_str());
        std::printf("replay with --seed %" PRIu64 "\n", opt_.seed);
        return 1;
    }
    std::printf("PASS: %" PRIu64 " transactions, every result matched the peripheral's record\n", checked_);
    return 0;
}

// The page and session modes, no faults injected: every command read by its
// cell, no collision on any line. Returns the transactions on all lines.
uint64_t Soak::check_lines() {
    uint64_t txns = 0;
    for (int ch = 0; ch < NCH; ++ch) {
        const soak::Periph &pe = *periph_[static_cast<size_t>(ch)];
        txns += pe.log.size();
        for (const PeriphTxn &x : pe.log)
            if (!x.error.empty())
                mismatch("ch" + std::to_string(ch) + ": the cell could not read a command: " + x.error);
        if (pe.collisions)
            mismatch("ch" + std::to_string(ch) + ": the host drove the line during an answer");
    }
    return txns;
}

int Soak::fail_report(const std::string &head, bool spec_ok) {
    std::printf("FAIL: %s%" PRIu64 " mismatches%s\n", head.c_str(), mismatches_,
                spec_ok ? "" : " (spec-timing breaches among them)");
    for (const std::string &m : messages_)
        std::printf("  %s\n", m.c_str());
    return 1;
}

// make demo: the sensor-page tool (sw/tools/twh_page.c, what twh_cli and the
// LiteX SoC run) over this harness's bus, three healthy cells on the lines.
// The pages and the interrupt waits are checked by soc/check_page.py against
// the shared vectors (the same lines the SoC prints, with "demo:" for
// "soc:"); every phase on the lines, the bus and the lines are checked here.
// The page tool's options for a run on every channel of this harness,
// printing to out (make demo's and the rig's page passes).
twh_page_opts_t Soak::page_opts(const char *where, FILE *out) {
    twh_page_opts_t o{};
    o.quick = 0;
    o.only = -1;
    o.timeout_ms = 2000;
    o.where = where;
    o.out = out;
    o.err = out;
    o.failed = nullptr;           // the harness's bus cannot fail; it reports bus errors
    o.now_us = h_now_us;
    o.ctx = this;
    return o;
}

int Soak::run_page() {
    std::printf("demo: the C driver on the Verilated twh_wb, %d channels at %u kHz (", NCH,
                static_cast<unsigned>(SOAK_CLK_HZ / 1000));
    for (int ch = 0; ch < NCH; ++ch)
        std::printf("%s%s", ch ? ", " : "", periph_[static_cast<size_t>(ch)]->device().profile().name);
    std::printf(")\n");
    std::fflush(stdout);
    const auto w0 = std::chrono::steady_clock::now();
    setup();
    const twh_page_opts_t o = page_opts("Verilated twh_wb", stdout);
    const uint64_t c0 = cyc_;
    const int rc = twh_page_run(&plat_, &o);
    const uint64_t ms = (cyc_ - c0) / CYC_PER_US / 1000;
    run_cycles(3000 * CYC_PER_US);    // close the last listen windows
    std::printf("\ndemo: twh_page_run returned %d after %" PRIu64 " ms of simulated time\n", rc, ms);
    std::printf("demo: wait_irq calls %" PRIu64 ", woken by the interrupt %" PRIu64
                " (pending on entry %" PRIu64 "), timed out %" PRIu64 "\n",
                irq_waits_, irq_woke_, irq_pending_, irq_timed_out_);
    const uint64_t txns = check_lines();
    const bool spec_ok = spec_check();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    top_->final();
    std::printf("demo: %" PRIu64 " transactions on %d lines, %" PRIu64 " bus accesses, %.1f s wall\n",
                txns, NCH, accesses_, wall);
    if (mismatches_ || rc != 0)
        return fail_report("twh_page_run " + std::to_string(rc) + ", ", spec_ok);
    std::printf("demo: every transaction inside the spec's timing table, no bus error, "
                "no collision\n");
    return 0;
}

// make test: tb/test_cosim.py's driver_session, step for step, on the
// Verilated core: negotiation per firmware, every read helper, write with
// verify, the driver's refusal to touch the factory area, a whole-image read,
// and submit / cancel / collect. The cells are the demo's (soc/cells.py);
// --transcript writes every frame they handled before the non-blocking part
// (which frames a cancel catches depends on bus timing), one line each, for
// the test that holds this run and the Icarus co-simulation to the same
// transcript (test_cosim.py::test_cosim[driver_session], make test-slow).
int Soak::run_session() {
#if SOAK_CHANNELS != 3
    std::fprintf(stderr, "session: the session's expectations name three cells; "
                         "this build has %d channels\n", NCH);
    return 1;
#else
    // the execute phase twh_negotiate picks: v18 6 ms, v15 4 ms, CO2 fw 0x12 6 ms
    static const char *const cell_of[3] = {"o2_v18+", "o2_v15+", "co2+"};
    static const uint16_t expect_exec[3] = {6000, 4000, 6000};
    auto need = [&](bool ok, const std::string &what) {
        if (!ok)
            mismatch("session: " + what);
        return ok;
    };
    auto prof = [&](int ch) -> const SoakProfile & {
        return periph_[static_cast<size_t>(ch)]->device().profile();
    };
    for (int ch = 0; ch < NCH; ++ch)
        if (std::strncmp(prof(ch).name, cell_of[ch], std::strlen(cell_of[ch])) != 0) {
            std::fprintf(stderr, "session: channel %d holds %s, not the %s cell\n", ch,
                         prof(ch).name, cell_of[ch]);
            return 1;
        }
    const auto w0 = std::chrono::steady_clock::now();
    reset_init();
    t_.timeout_us = 200000;
    for (int ch = 0; ch < NCH; ++ch) {
        const std::string c = "ch" + std::to_string(ch) + ": ";
        const auto c8 = static_cast<uint8_t>(ch);
        twh_fw_t fw{};
        int rc = twh_negotiate(&t_, c8, &fw);
        need(rc == TWH_OK && fw.raw == prof(ch).fw_byte && fw.type == prof(ch).type_byte,
             c + "twh_negotiate " + std::to_string(rc));
        const uint32_t t1 = access(ch_off(ch, offsetof(twh_regs__channel_t__stride20_t, TIMING1)), false, 0);
        need((t1 >> TWH_REGS__CHANNEL_T__TIMING1__EXECUTE_US_bp) == expect_exec[ch],
             c + "TIMING1.EXECUTE_US " + std::to_string(t1 >> 16));
        uint8_t bits = 0;
        uint16_t words = 0;
        rc = twh_config(&t_, c8, &bits, &words);
        need(rc == TWH_OK && words == prof(ch).size, c + "twh_config " + std::to_string(rc) +
                                                         ", " + std::to_string(words) + " words");
    }
    uint16_t v = 0;
    need(twh_o2_voltage(&t_, 0, &v) == TWH_OK && v == prof(0).adc_o2, "twh_o2_voltage");
    need(twh_temperature(&t_, 1, &v) == TWH_OK && v == prof(1).adc_temperature, "twh_temperature");
    need(twh_ref_voltage(&t_, 2, &v) == TWH_OK && v == prof(2).adc_ref_voltage, "twh_ref_voltage");
    need(twh_read_word(&t_, 0, 0x10, &v) == TWH_OK && v == prof(0).flash[0x10], "twh_read_word");
    // write with verify on a blank word of the v18 cell, then again on it
    const std::vector<uint16_t> &fl = periph_[0]->device().flash();
    uint16_t free_w = 0x20;
    while (free_w < 0xE0 && fl[free_w] != soak::BLANK)
        ++free_w;
    if (need(free_w < 0xE0, "no blank word in the v18 cell's 0x20-0xDF")) {
        need(twh_write_word(&t_, 0, free_w, 0x0ACE) == TWH_OK && fl[free_w] == 0x0ACE,
             "twh_write_word on a blank word");
        need(twh_write_word(&t_, 0, free_w, 0x0123) == TWH_ERR_VERIFY,
             "a second write to a programmed word passed its verify");
    }
    // the factory area is refused before anything reaches the bus
    const uint64_t acc0 = accesses_;
    const size_t log0 = periph_[0]->log.size();
    need(twh_write_word(&t_, 0, 0x05, 0x0001) == TWH_ERR_BAD_ARG, "factory write not refused");
    need(twh_erase_page(&t_, 0, 0x10) == TWH_ERR_BAD_ARG, "factory erase not refused");
    need(accesses_ == acc0 && periph_[0]->log.size() == log0,
         "a refused factory write reached the bus or the line");
    uint16_t img[4] = {};
    need(twh_read_image(&t_, 1, img, 4) == TWH_OK &&
         std::equal(img, img + 4, prof(1).flash), "twh_read_image");
    size_t mark[NCH];
    for (int ch = 0; ch < NCH; ++ch)
        mark[ch] = periph_[static_cast<size_t>(ch)]->log.size();
    // non-blocking: queue three, cancel what has not started, collect all
    int tags[3];
    for (int &tg : tags)
        need((tg = twh_submit(&t_, 2, 0x41, 0xAA)) >= 0, "twh_submit");
    need(twh_cancel_all(&t_) == TWH_OK, "twh_cancel_all");
    int got = 0, cancelled = 0;
    for (uint64_t waited_ms = 0; got < 3 && waited_ms < 200;) {
        twh_result_t r{};
        const int rc = twh_result(&t_, &r);
        if (rc == TWH_ERR_AGAIN) {
            run_cycles(1000 * CYC_PER_US);
            ++waited_ms;
            continue;
        }
        ++got;
        need(rc == TWH_OK && r.channel == 2 && r.cmd == 0x41 &&
             (r.status == TWH_ST_OK || r.status == TWH_ST_CANCELLED) &&
             std::count(tags, tags + 3, static_cast<int>(r.tag)) == 1,
             "twh_result " + std::to_string(rc) + ", status " + std::to_string(r.status));
        cancelled += r.status == TWH_ST_CANCELLED;
    }
    need(got == 3 && cancelled >= 2, "of three queued commands " + std::to_string(got) +
                                         " came back, " + std::to_string(cancelled) + " cancelled");
    need(irq_waits_ > 0, "the driver never waited on the interrupt");
    run_cycles(3000 * CYC_PER_US);    // close the last listen window
    const uint64_t txns = check_lines();
    const bool spec_ok = spec_check();
    if (!opt_.transcript.empty()) {
        FILE *f = std::fopen(opt_.transcript.c_str(), "w");
        if (!f) {
            std::perror(opt_.transcript.c_str());
            return 1;
        }
        for (int ch = 0; ch < NCH; ++ch)
            for (size_t i = 0; i < mark[ch]; ++i) {
                const PeriphTxn &x = periph_[static_cast<size_t>(ch)]->log[i];
                std::fprintf(f, "ch%d", ch);
                for (int b = 0; b < x.flen; ++b)
                    std::fprintf(f, " %02X", x.frame[b]);
                if (x.answers)
                    std::fprintf(f, " -> %02X %02X\n", x.dev_msb, x.dev_lsb);
                else
                    std::fprintf(f, " -> none\n");
            }
        std::fclose(f);
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
    top_->final();
    std::printf("session: %" PRIu64 " transactions on %d lines, %" PRIu64 " bus accesses, %" PRIu64
                " interrupt waits, %" PRIu64 " ms simulated, %.1f s wall\n",
                txns, NCH, accesses_, irq_waits_, cyc_ / CYC_PER_US / 1000, wall);
    if (mismatches_)
        return fail_report("", spec_ok);
    std::printf("PASS: the driver session on the Verilated core, every transaction inside the "
                "spec's timing table\n");
    return 0;
#endif
}

// ------------------------------------------------------------ the rig
// make rig (docs/rig.md): one cell a channel (soc/cells.py: O2 v18, O2 v15
// and CO2 in turn, each with its own serial; a few inject one of the soak's
// faults, or hold their line low).
// Pass 1: the sensor-page tool (sw/tools/twh_page.c, what twh_cli and the
//   LiteX SoC run) reads every cell's page, every channel at once; its
//   output goes to --pages with, per channel, what the cell's model
//   recorded, for soc/check_page.py --rig (every healthy page against the
//   shared vectors, every faulty one against what its model injected).
// Pass 2: live readings for --live-ms, one command in flight on every line
//   (0x42, 0x43, 0x44 in turn) at the shortest legal timing, every result
//   checked against the cell's record as the soak checks it.
// One line a cell, the aggregate rate against the physical limit, the
// spec-timing, bus and line checks of the other modes, and the lines'
// waveform (soak::LineVcd).
#ifdef SOAK_RIG_CELLS
namespace rig {

// the shortest legal transaction with a 3-byte command (spec table,
// NOTES.md): a bit is 32 us at 31.25 kbps, a byte 11 bits (start, 8 data,
// 2 stop)
constexpr double BIT_US = 32;
constexpr double CMD3_US = 3 * 11 * BIT_US;
double txn_us(double execute_us) {
    return CHARGE_US + SYNC_US + PREAMBLE_US + CMD3_US + execute_us + LISTEN_US + TURNAROUND_US;
}

// twh_page.c's names of what a command was for
const char *what_name(uint8_t cmd) {
    switch (cmd) {
    case TWH_CMD_FIRMWARE: return "firmware (0x41)";
    case TWH_CMD_CONFIG: return "config (0x40)";
    case TWH_CMD_REF_VOLTAGE: return "supply (0x42)";
    case TWH_CMD_TEMPERATURE: return "temperature (0x43)";
    case TWH_CMD_O2_VOLTAGE: return "O2 (0x44)";
    case TWH_CMD_READ: case TWH_CMD_READ | 1: return "flash read (0x48)";
    default: return "?";
    }
}

std::string trim(const std::string &s) {
    const size_t a = s.find_first_not_of(' '), b = s.find_last_not_of(' ');
    return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// the page tool's output cut into its channel pages, as tb/sensor_page.py
// pages() cuts it
std::vector<std::vector<std::string>> pages_of(const std::string &text, int nch) {
    std::vector<std::vector<std::string>> out(static_cast<size_t>(nch));
    int cur = -1;
    size_t pos = 0;
    while (pos < text.size()) {
        size_t nl = text.find('\n', pos);
        if (nl == std::string::npos)
            nl = text.size();
        const std::string l = text.substr(pos, nl - pos);
        pos = nl + 1;
        int ch = -1;
        if (std::sscanf(l.c_str(), "== channel %d:", &ch) == 1 && ch >= 0 && ch < nch) {
            cur = ch;
            out[static_cast<size_t>(ch)].assign(1, l);
        } else if (cur >= 0 && l.rfind("  ", 0) == 0) {
            out[static_cast<size_t>(cur)].push_back(l);
        } else {
            cur = -1;
        }
    }
    return out;
}

// what a channel's page says, for its line in the table
struct PageView {
    bool found = false, present = false, error = false;
    std::string type = "-", serial = "-", reading = "-";
    std::string err_status, err_what;   // the page's error: status name, what it was for
};

PageView view(const std::vector<std::string> &page) {
    PageView v;
    if (page.empty())
        return v;
    v.found = true;
    char st[32], what[64];
    int err = 0;
    const std::string &h = page[0];
    const std::string rest = h.substr(h.find(": ") + 2);
    if (rest.rfind("no sensor", 0) == 0) {
        v.error = true;
        v.err_status = "NO_RESPONSE";
        v.err_what = what_name(TWH_CMD_FIRMWARE);
    } else if (std::sscanf(rest.c_str(), "error %d (%31[^)]) on %63[^\n]", &err, st, what) == 3) {
        v.error = true;
        v.err_status = st;
        v.err_what = what;
    } else {
        // "Digital O2 sensor, firmware v18 (byte 0x12), execute 6000 us"
        v.present = true;
        std::string kind = rest.substr(0, rest.find(','));
        kind = kind == "Digital O2 sensor" ? "O2" : kind == "CO2 sensor" ? "CO2"
             : kind == "CO2 temperature stick" ? "CO2 stick" : kind;
        const size_t f = rest.find("firmware ");
        v.type = kind + (f == std::string::npos ? "" : " " + rest.substr(f + 9, rest.find(' ', f + 9) - f - 9));
    }
    std::string o2, ppo2, temp, cal, o2_adc, t_adc, supply;
    for (size_t i = 1; i < page.size(); ++i) {
        const std::string &l = page[i];
        if (l.size() < 20)
            continue;
        const std::string key = trim(l.substr(2, 17)), val = l.substr(19);
        if (key == "error" &&
            std::sscanf(val.c_str(), "%d (%31[^)]) on %63[^;]", &err, st, what) == 3) {
            v.error = true;
            v.err_status = st;
            v.err_what = what;
        } else if (key == "serial") {
            v.serial = val;
        } else if (key == "O2 cell") {
            o2 = val;
        } else if (key == "PPO2") {
            ppo2 = val.substr(0, val.find(" ("));
        } else if (key == "temperature") {
            temp = val;
        } else if (key == "CO2 400 ppm cal") {      // "reading 1251 (calibrated ...)"
            cal = val.substr(8, val.find(" (") - 8);
        } else if (key == "O2 ADC") {
            o2_adc = val;
        } else if (key == "temperature ADC") {
            t_adc = val;
        } else if (key == "supply") {
            supply = val.substr(0, val.find(" ("));
        }
    }
    if (!o2.empty())
        v.reading = o2 + (ppo2.empty() ? "" : ", PPO2 " + ppo2);
    else if (!temp.empty() && v.type.rfind("CO2", 0) == 0)
        v.reading = temp + (cal.empty() ? "" : ", 400 ppm cal " + cal);
    else if (!o2_adc.empty() && v.type.rfind("O2", 0) == 0)
        v.reading = "O2 ADC " + o2_adc + " (raw)";
    else if (!t_adc.empty())
        v.reading = "temperature ADC " + t_adc + " (raw)";
    else if (!supply.empty())
        v.reading = "supply " + supply;
    return v;
}

}  // namespace rig

struct Soak::LiveCh {
    bool busy = false;
    uint8_t tag = 0, cmd = 0;
    uint64_t seq = 0;            // its transaction in the cell's record
    size_t mark = 0;             // the record's length before the live pass
    uint64_t issued = 0, in_window = 0;
    uint64_t st[10] = {};        // statuses popped
};

#endif

void Soak::progress() {
    const double w = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0_).count();
    std::printf("  ... %.1f s simulated, %.0f s wall\n", static_cast<double>(cyc_) / CLK_HZ, w);
    std::fflush(stdout);
    next_progress_cyc_ += static_cast<uint64_t>(CLK_HZ);
}

#ifdef SOAK_RIG_CELLS
// Pass 2: one command in flight on every line until the window ends, then
// the last ones collected. Every result against the cell's record.
void Soak::live(uint64_t window_cyc, std::vector<LiveCh> &lc, uint64_t &in_window) {
    static const uint8_t cmds[3] = {TWH_CMD_REF_VOLTAGE, TWH_CMD_TEMPERATURE, TWH_CMD_O2_VOLTAGE};
    const uint64_t end = cyc_ + window_cyc;
    for (;;) {
        int busy = 0;
        for (int ch = 0; ch < NCH; ++ch) {
            LiveCh &c = lc[static_cast<size_t>(ch)];
            if (!c.busy && cyc_ < end) {
                const uint8_t cmd = cmds[c.issued % 3];
                const int tag = twh_submit(&t_, static_cast<uint8_t>(ch), cmd, TWH_UNUSED_PAYLOAD);
                if (tag < 0 || tag >= TAGS) {
                    mismatch("live: twh_submit(ch" + std::to_string(ch) + ") = " + std::to_string(tag));
                    stalled_ = true;
                    return;
                }
                c.busy = true;
                c.tag = static_cast<uint8_t>(tag);
                c.cmd = cmd;
                c.seq = c.mark + c.issued++;
            }
            busy += c.busy;
        }
        if (!busy)
            return;
        if (twh_poll(&t_) == 0 && wait_irq(1000000) >= 1000000 && !top_->irq) {
            mismatch("live: no result for a simulated second");
            stalled_ = true;
            return;
        }
        twh_result_t r;
        int rc;
        while ((rc = twh_result(&t_, &r)) == TWH_OK) {
            if (r.channel >= NCH || !lc[r.channel].busy || r.tag != lc[r.channel].tag ||
                r.cmd != lc[r.channel].cmd) {
                mismatch("live: a result for nothing in flight: ch" + std::to_string(r.channel) +
                         " tag " + std::to_string(r.tag) + " cmd " + std::to_string(r.cmd));
                continue;
            }
            LiveCh &c = lc[r.channel];
            c.busy = false;
            ++c.st[r.status < 9 ? r.status : 9];
            if (cyc_ <= end) {
                ++c.in_window;
                ++in_window;
            }
            Expect e;
            if (stuck_ >> r.channel & 1u) {
                e.status = TWH_ST_LINE_STUCK_LOW;   // nothing reaches the cell
            } else {
                const PeriphTxn *x = received(r.channel, c.seq, c.cmd, TWH_UNUSED_PAYLOAD, "live");
                if (!x)
                    continue;
                e = predict(*x);
            }
            if (r.status != e.status || r.data != e.data) {
                char buf[160];
                std::snprintf(buf, sizeof buf, "live: ch%u #%" PRIu64 " cmd 0x%02X: got %s 0x%04X, "
                              "the cell's record says %s 0x%04X", r.channel, c.seq, r.cmd,
                              status_name(r.status), r.data, status_name(e.status), e.data);
                mismatch(buf);
            }
        }
        if (rc != TWH_ERR_AGAIN)
            mismatch("live: twh_result = " + std::to_string(rc));
    }
}
#endif

int Soak::run_rig() {
#ifndef SOAK_RIG_CELLS
    std::fprintf(stderr, "rig: this build has no rig cells (make rig builds build/rig<N>/soak_rig)\n");
    return 2;
#else
    using rig::txn_us;
    w0_ = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    auto prof = [&](int ch) -> const SoakProfile & {
        return periph_[static_cast<size_t>(ch)]->device().profile();
    };
    auto kind_of = [&](int ch) {
        twh_fw_t fw{};
        twh_fw_decode(static_cast<uint16_t>(prof(ch).fw_byte << 8 | prof(ch).type_byte), &fw);
        return std::string(fw.type == TWH_TYPE_O2 ? "O2" : "CO2") + " v" + std::to_string(fw.version);
    };
    auto fault_text = [&](int ch) -> std::string {
        const std::string &k = rig_fault_[static_cast<size_t>(ch)];
        if (k.empty())
            return "";
        if (k == "stuck_low")
            return "line stuck low";
        return soak::fault_name(fault_of(k));
    };
    // the banner: the cells, by kind, and the faulty ones
    std::printf("rig: the C driver (sw/, unchanged) on the Verilated twh_wb, %d channels at %.0f MHz\n",
                NCH, CLK_HZ / 1e6);
    {
        std::vector<std::pair<std::string, int>> kinds;
        std::string faults;
        for (int ch = 0; ch < NCH; ++ch) {
            const std::string k = kind_of(ch);
            auto it = std::find_if(kinds.begin(), kinds.end(), [&](auto &p) { return p.first == k; });
            if (it == kinds.end())
                kinds.emplace_back(k, 1);
            else
                ++it->second;
            if (!rig_fault_[static_cast<size_t>(ch)].empty())
                faults += (faults.empty() ? "" : ", ") + std::to_string(ch) + " " + fault_text(ch);
        }
        std::printf("rig: %d modelled cells (soc/cells.py), in turn:", NCH);
        for (size_t i = 0; i < kinds.size(); ++i)
            std::printf("%s %d %s", i ? "," : "", kinds[i].second, kinds[i].first.c_str());
        std::printf("\nrig: faulty cells: %s (an answer fault on %.0f %% of the cell's answers)\n",
                    faults.empty() ? "none" : faults.c_str(),
                    100 * (opt_.rig_fault_rate < 0 ? RIG_FAULT_RATE : opt_.rig_fault_rate));
    }
    if (!opt_.vcd.empty()) {
        std::vector<std::string> labels;
        for (int ch = 0; ch < NCH; ++ch) {
            const std::string f = fault_text(ch);
            labels.push_back(kind_of(ch) + " " + prof(ch).name + (f.empty() ? "" : " (" + f + ")"));
        }
        if (!vcd_.open(opt_.vcd, NCH, static_cast<unsigned>(CYC_PER_US), labels)) {
            std::perror(opt_.vcd.c_str());
            return 1;
        }
    }
    std::fflush(stdout);
    setup();                         // reset, twh_init, the shortest legal timing, read back
    next_progress_cyc_ = cyc_ + static_cast<uint64_t>(CLK_HZ);

    // ---- pass 1: every cell's page, every channel at once
    std::printf("rig: pass 1: the sensor-page tool (twh_page_run) on every channel at once ...\n");
    std::fflush(stdout);
    char *pbuf = nullptr;
    size_t plen = 0;
    FILE *pf = open_memstream(&pbuf, &plen);
    if (!pf) {
        std::perror("open_memstream");
        return 1;
    }
    const twh_page_opts_t o = page_opts("Verilated twh_wb, the rig", pf);
    const uint64_t p0 = cyc_;
    const int page_rc = twh_page_run(&plat_, &o);
    const uint64_t p1 = cyc_;
    std::fclose(pf);
    const std::string page_text(pbuf, plen);
    std::free(pbuf);
    const uint64_t w_irq = irq_waits_, w_woke = irq_woke_, w_pend = irq_pending_, w_out = irq_timed_out_;
    std::vector<size_t> page_txns(NCH);
    std::vector<uint64_t> host_txns(NCH), page_end(NCH);
    std::vector<uint16_t> exec_us(NCH);
    uint64_t page_total = 0;
    for (int ch = 0; ch < NCH; ++ch) {
        const size_t c = static_cast<size_t>(ch);
        page_txns[c] = periph_[c]->log.size();
        host_txns[c] = mon_[c].listen_us.size();
        page_end[c] = mon_[c].listen_end_cyc > p0 ? mon_[c].listen_end_cyc - p0 : 0;
        page_total += host_txns[c];
        // the execute phase the page tool negotiated for the cell's firmware
        exec_us[c] = static_cast<uint16_t>(
            access(ch_off(ch, offsetof(twh_regs__channel_t__stride20_t, TIMING1)), false, 0) >>
            TWH_REGS__CHANNEL_T__TIMING1__EXECUTE_US_bp);
    }
    const double page_ms = static_cast<double>(p1 - p0) / CLK_HZ * 1e3;
    std::printf("rig: pass 1: %" PRIu64 " transactions in %.1f ms simulated (twh_page_run returned %d)\n",
                page_total, page_ms, page_rc);

    // ---- pass 2: live readings at the shortest legal timing
    std::printf("rig: pass 2: live readings for %u ms, one command in flight on every line "
                "(0x42, 0x43, 0x44 in turn), execute %u us ...\n", opt_.live_ms, EXECUTE_US);
    std::fflush(stdout);
    for (int ch = 0; ch < NCH; ++ch)
        if (twh_set_execute_us(&t_, static_cast<uint8_t>(ch), EXECUTE_US) != TWH_OK)
            mismatch("ch" + std::to_string(ch) + ": execute " + std::to_string(EXECUTE_US) + " us refused");
    std::vector<LiveCh> lc(NCH);
    for (int ch = 0; ch < NCH; ++ch)
        lc[static_cast<size_t>(ch)].mark = page_txns[static_cast<size_t>(ch)];
    uint64_t live_window = 0;
    const uint64_t l0 = cyc_;
    if (opt_.live_ms)
        live(static_cast<uint64_t>(opt_.live_ms) * 1000 * CYC_PER_US, lc, live_window);
    const uint64_t l1 = cyc_;
    run_cycles(3000 * CYC_PER_US);    // close the last listen windows
    next_progress_cyc_ = 0;

    // ---- checks: every line, the core at the end
    const uint64_t txns = check_lines();
    for (int ch = 0; ch < NCH; ++ch) {
        const size_t c = static_cast<size_t>(ch);
        // pass 1: every transaction the host ran reached the cell
        if (!(stuck_ >> ch & 1u) && host_txns[c] != page_txns[c])
            mismatch("ch" + std::to_string(ch) + ": pass 1: " + std::to_string(host_txns[c]) +
                     " transactions by the host, " + std::to_string(page_txns[c]) + " at the cell");
        const size_t want = (stuck_ >> ch & 1u) ? 0 : page_txns[c] + lc[c].issued;
        if (periph_[c]->log.size() != want)
            mismatch("ch" + std::to_string(ch) + ": " + std::to_string(periph_[c]->log.size()) +
                     " transactions reached the cell, " + std::to_string(want) + " expected");
    }
    {
        const uint32_t status = access(reg_off(offsetof(twh_regs_t, STATUS)), false, 0);
        const uint32_t busy = access(reg_off(offsetof(twh_regs_t, BUSY)), false, 0);
        const uint32_t errors = access(reg_off(offsetof(twh_regs_t, ERRORS)), false, 0);
        if (busy || !(status & TWH_REGS__STATUS__RES_EMPTY_bm) || !(status & TWH_REGS__STATUS__CMD_EMPTY_bm)) {
            char buf[96];
            std::snprintf(buf, sizeof buf, "core not idle and empty at the end: STATUS 0x%08X, BUSY 0x%08X",
                          status, busy);
            mismatch(buf);
        }
        // the faults set LINK_ERROR; nothing else may be flagged
        if (errors & ~static_cast<uint32_t>(TWH_REGS__ERRORS__LINK_ERROR_bm))
            mismatch("ERRORS = " + std::to_string(errors));
    }
    if (page_rc != 0)
        mismatch("twh_page_run returned " + std::to_string(page_rc));

    // ---- pass 1 against the cells' records: the page tool stops a channel at
    // its first answer that is not OK; the record line for check_page.py
    const auto pages = rig::pages_of(page_text, NCH);
    std::string records;
    std::vector<std::string> page_status(NCH);
    for (int ch = 0; ch < NCH; ++ch) {
        const size_t c = static_cast<size_t>(ch);
        const auto &log = periph_[c]->log;
        const rig::PageView v = rig::view(pages[c]);
        const std::string &key = rig_fault_[c];
        std::string rec = "rig: page pass, channel " + std::to_string(ch) + " (" +
                          (key.empty() ? "no fault" : "fault " + key) + "): ";
        int bad = -1;
        uint8_t bad_cmd = 0, bad_status = TWH_ST_OK;
        std::string injected;
        if (stuck_ >> ch & 1u) {
            bad = 0;
            bad_cmd = TWH_CMD_FIRMWARE;
            bad_status = TWH_ST_LINE_STUCK_LOW;
            injected = "line stuck low";
            rec += std::to_string(host_txns[c]) + (host_txns[c] == 1 ? " transaction" : " transactions") +
                   " by the host, none reached the cell";
        } else {
            std::string list;
            for (size_t i = 0; i < page_txns[c] && i < log.size(); ++i) {
                const PeriphTxn &x = log[i];
                if (!x.error.empty())
                    continue;                // check_lines() has reported it
                const Expect e = predict(x);
                if (e.status != TWH_ST_OK && bad < 0) {
                    bad = static_cast<int>(i);
                    bad_cmd = x.frame[0];
                    bad_status = e.status;
                    injected = soak::fault_name(x.fault);
                    if (x.fault == Fault::StopBit)
                        injected += " in byte " + std::to_string(x.fault_byte) +
                                    (x.wire[x.fault_byte] ? "" : ", a 0x00 byte: a break");
                }
                char buf[24];
                std::snprintf(buf, sizeof buf, "%s%02X %s", list.empty() ? "" : ", ", x.frame[0],
                              status_name(e.status));
                list += buf;
            }
            rec += bad < 0 ? std::to_string(page_txns[c]) + " transactions, all OK" : list;
        }
        records += rec + "\n";
        // what the page says against it
        std::string st;
        if (bad < 0) {
            if (!v.present || v.error)
                mismatch("ch" + std::to_string(ch) + ": every answer of its page was OK, but the page "
                         "says " + (pages[c].empty() ? "nothing" : pages[c][0]));
            st = "OK";
        } else {
            const bool fw = bad_cmd == TWH_CMD_FIRMWARE;
            const bool same = v.error && v.present == !fw && v.err_status == status_name(bad_status) &&
                              v.err_what == rig::what_name(bad_cmd);
            if (!same)
                mismatch("ch" + std::to_string(ch) + ": its record says " + status_name(bad_status) +
                         " on " + rig::what_name(bad_cmd) + ", the page says " +
                         (v.error ? v.err_status + " on " + v.err_what : "no error"));
            st = std::string(status_name(bad_status)) + " on " + rig::what_name(bad_cmd) +
                 (stuck_ >> ch & 1u ? "" : ", page answer " + std::to_string(bad + 1)) +
                 (same ? ", as injected (" + injected + ")" : ", NOT as injected (" + injected + ")");
        }
        if (!key.empty() && bad < 0)
            st += " (no fault drawn in its page)";
        page_status[c] = st;
    }

    // ---- the table: one line a cell
    std::printf("\n  ch  serial        type     reading                          page done  status\n");
    for (int ch = 0; ch < NCH; ++ch) {
        const size_t c = static_cast<size_t>(ch);
        const rig::PageView v = rig::view(pages[c]);
        std::string live;
        for (unsigned s = 0; s < 10; ++s)
            if (lc[c].st[s])
                live += (live.empty() ? "" : ", ") + std::to_string(lc[c].st[s]) + " " + status_name(s);
        if (live.empty())
            live = "none";
        if (!rig_fault_[c].empty())
            live += lc[c].st[TWH_ST_OK] == lc[c].issued ? " (no fault drawn)" : ", as injected";
        std::printf("  %2d  %-12s  %-7s  %-32s %7.0f ms  %s; live %s\n", ch, v.serial.c_str(),
                    v.type.c_str(), v.reading.c_str(), static_cast<double>(page_end[c]) / CLK_HZ * 1e3,
                    page_status[c].c_str(), live.c_str());
    }

    // ---- the rates: transactions per simulated second against the limit
    const double t_min = txn_us(EXECUTE_US), per_line = 1e6 / t_min, limit = NCH * per_line;
    double bound = 0;
    for (int ch = 0; ch < NCH; ++ch)
        bound += 1e6 / txn_us(exec_us[static_cast<size_t>(ch)]);
    const double page_rate = static_cast<double>(page_total) / (page_ms / 1e3);
    std::printf("\nrig: physical limit: one transaction a line every %.3f ms (charge %u + sync %u + preamble %u "
                "+ command %.0f (3 bytes) + execute %u + listen %u + turnaround %u us, the spec's minima) "
                "= %.2f/s a line, %.1f/s for %d lines\n",
                t_min / 1e3, CHARGE_US, SYNC_US, PREAMBLE_US, rig::CMD3_US, EXECUTE_US, LISTEN_US,
                TURNAROUND_US, per_line, limit, NCH);
    std::printf("rig: pass 1 (pages): %" PRIu64 " transactions in %.1f ms = %.1f/s, %.3f of the limit "
                "(%.1f lines' worth at once); at the execute phases the page tool negotiated "
                "(6 ms v18, 4 ms v15) the bound is %.1f/s: %.3f of it\n",
                page_total, page_ms, page_rate, page_rate / limit, page_rate / per_line, bound,
                page_rate / bound);
    if (opt_.live_ms) {
        const double live_rate = static_cast<double>(live_window) / (opt_.live_ms / 1e3);
        std::printf("rig: pass 2 (live):  %" PRIu64 " transactions completed in the %u ms window = %.1f/s, "
                    "%.3f of the limit (%.1f lines' worth at once); %.1f ms to collect the last ones\n",
                    live_window, opt_.live_ms, live_rate, live_rate / limit, live_rate / per_line,
                    static_cast<double>(l1 - l0) / CLK_HZ * 1e3 - opt_.live_ms);
    }
    const bool spec_ok = spec_check();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0_).count();
    const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    uint64_t collisions = 0;
    for (const auto &p : periph_)
        collisions += p->collisions;
    std::printf("rig: %" PRIu64 " transactions reached the cells, %" PRIu64 " results checked against "
                "their records; %" PRIu64 " bus accesses, %" PRIu64 " interrupt waits; "
                "%" PRIu64 " bus errors, %" PRIu64 " collisions\n",
                txns, checked_, accesses_, irq_waits_, bus_errors_, collisions);
    std::printf("rig: simulated %.3f s (%.1f M clocks at %.0f MHz) in %.1f s wall, %.1f s CPU: "
                "%.4f simulated s per wall s, %.2f M clocks per CPU s (information, not a check)\n",
                static_cast<double>(cyc_) / CLK_HZ, static_cast<double>(cyc_) / 1e6, CLK_HZ / 1e6, wall, cpu,
                static_cast<double>(cyc_) / CLK_HZ / wall, static_cast<double>(cyc_) / 1e6 / cpu);
    top_->final();
    if (vcd_.is_open()) {
        const uint64_t bytes = vcd_.close();
        const std::string gtkw = opt_.vcd.substr(0, opt_.vcd.rfind('.')) + ".gtkw";
        if (!vcd_.write_gtkw(gtkw, opt_.vcd))
            mismatch("cannot write " + gtkw);
        std::printf("rig: waveform %s, %.1f MB (per line: the host's drive enable, the carrier "
                    "envelope, the envelope for a UART decoder; 1 us steps), GTKWave save file %s\n",
                    opt_.vcd.c_str(), static_cast<double>(bytes) / 1e6, gtkw.c_str());
    }
    if (!opt_.pages.empty()) {
        FILE *f = std::fopen(opt_.pages.c_str(), "w");
        if (!f) {
            std::perror(opt_.pages.c_str());
            return 1;
        }
        std::fprintf(f, "%s\nrig: twh_page_run returned %d after %.0f ms of simulated time\n"
                        "rig: wait_irq calls %" PRIu64 ", woken by the interrupt %" PRIu64
                        " (pending on entry %" PRIu64 "), timed out %" PRIu64 "\n%s",
                     page_text.c_str(), page_rc, page_ms, w_irq, w_woke, w_pend, w_out, records.c_str());
        std::fclose(f);
        std::printf("rig: the pages and the cells' records: %s\n", opt_.pages.c_str());
    }
    if (mismatches_)
        return fail_report("", spec_ok);
    std::printf("rig: every transaction inside the spec's timing table, every live result as its "
                "cell's record says, every faulty cell's page as injected; no bus error, no collision\n");
    return 0;
#endif
}

}  // namespace

int main(int argc, char **argv) {
    Options o = parse(argc, argv);
    if (!o.seed_given && (o.page || o.session || o.rig))
        o.seed = 1;               // the demo, the session and the rig replay the same answers
    else if (!o.seed_given)
        o.seed = (static_cast<uint64_t>(std::random_device{}()) << 32 | std::random_device{}()) & 0xFFFFFFFFFFFFull;
    Verilated::commandArgs(argc, argv);
    Soak s(o);
    return o.rig ? s.run_rig() : o.session ? s.run_session() : o.page ? s.run_page() : s.run();
}
