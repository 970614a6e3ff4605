// C++ peripheral model and host-side timing monitor of the Verilator soak.
//
// Device:  the command handling of tb/periph_model.py's PeripheralLogic for
//          an O2 cell (answers, write-once flash, page erase, ranges).
// Periph:  follows the host's carrier on the resolved line clock by clock,
//          decodes the command frame, handles it after the execute phase and
//          answers in the listen window with an on-off keyed carrier whose
//          bit rate, carrier frequency, duty, stop bits, mark and delay are
//          drawn per answer inside the spec's windows; on a chosen fraction
//          of answers it injects one fault. Every transaction is recorded.
// HostMonitor: the phases the model cannot see from the line alone (listen,
//          turnaround, the carrier's period and duty), from line_o/line_oe.
#pragma once

#include <cstdint>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "soak_profiles.h"

namespace soak {

constexpr uint16_t BLANK = 0x3FFF;

enum class Fault : uint8_t { None, Silent, Checksum, StopBit, Short };
const char *fault_name(Fault f);

// what the device firmware does with one frame
struct DeviceAnswer {
    bool answer = false;
    uint8_t msb = 0, lsb = 0;
    const char *reason = "";
};

class Device {
public:
    explicit Device(const SoakProfile &pr);
    DeviceAnswer handle(const uint8_t *frame, int n);
    const SoakProfile &profile() const { return pr_; }
    const std::vector<uint16_t> &flash() const { return flash_; }

private:
    const SoakProfile &pr_;
    std::vector<uint16_t> flash_;
};

// One host transaction as the peripheral saw it, and what it put on the line.
struct PeriphTxn {
    uint8_t frame[4] = {0, 0, 0, 0};
    int flen = 0;               // bytes decoded
    std::string error;          // reception failed (then nothing was handled)
    bool answers = false;       // the device logic produced an answer
    uint8_t dev_msb = 0, dev_lsb = 0;   // ... this one, before any fault
    bool answered = false;      // ... and bytes went on the line
    uint8_t wire[3] = {0, 0, 0};
    int nwire = 0;              // bytes sent (after truncation)
    Fault fault = Fault::None;
    int fault_byte = -1;        // StopBit: the byte whose first stop bit is 0
    // the answer's physical parameters
    double baud = 0, carrier_hz = 0, duty = 0, delay_us = 0, mark_us = 0;
    int stop_bits = 0;
    // phase lengths measured on the line, microseconds (negative: not seen)
    double charge_us = -1, sync_us = -1, preamble_us = -1, command_us = -1,
           execute_us = -1;
    const char *device_reason = "";
};

class Periph {
public:
    Periph(const SoakProfile &pr, uint64_t seed, double fault_rate, double clk_hz);
    // every fault drawn is this kind (the rig's cells); None: any of the
    // four, drawn at random (the soak)
    void only_fault(Fault f) { only_ = f; }
    // One clock: `line` is the resolved line after the edge, host_oe the
    // host's output enable (only used to detect a collision). Sets o/oe.
    void step(uint64_t cyc, bool line, bool host_oe) {
        if (st_ == St::Answer) {
            answer_step(cyc, host_oe);
            return;
        }
        const bool rise = line && !prev_line_;
        prev_line_ = line;
        if (rise)
            on_rise(cyc);
        else if (burst_on_ && cyc - last_rise_ > gap_cyc_)
            on_burst_end();
        if (st_ == St::Command && !hunting_ && static_cast<double>(cyc) >= next_sample_)
            sample(cyc);
        else if (st_ == St::Command && hunting_ && static_cast<double>(cyc) > hunt_deadline_)
            fail(cyc, "command incomplete: no start bit after a stop bit");
        else if (st_ == St::Quiet && cyc - last_rise_ > quiet_cyc_)
            st_ = St::Idle;
    }

    bool o = false, oe = false;
    std::vector<PeriphTxn> log;
    uint64_t collisions = 0;     // cycles the host drove while we answered
    uint64_t short_bursts = 0;   // carrier bursts too short to be a charge
    const Device &device() const { return dev_; }

private:
    enum class St { Idle, Charge, Sync, Preamble, Command, Execute, Answer, Quiet };

    void on_rise(uint64_t cyc);
    void on_burst_end();
    void sample(uint64_t cyc);
    void fail(uint64_t cyc, const char *why);
    void handle_frame(double exec_end);
    void answer_step(uint64_t cyc, bool host_oe);
    double us(double cycles) const { return cycles * cyc_us_; }

    Device dev_;
    std::mt19937_64 rng_;
    double fault_rate_;
    Fault only_ = Fault::None;
    double cyc_us_;            // microseconds per clock
    uint64_t gap_cyc_;         // no rising edge this long: the carrier stopped
    uint64_t quiet_cyc_;       // after an error: a gap this long ends it

    St st_ = St::Idle;
    bool prev_line_ = false;
    bool burst_on_ = false;
    uint64_t last_rise_ = 0;
    uint64_t burst_first_ = 0;  // first rise of the current burst
    uint64_t burst_rises_ = 0;
    double period_cyc_ = 0;     // the host's carrier period, from the charge
    double bit_cyc_ = 0;        // 32 host periods

    PeriphTxn cur_;
    double sync_start_ = 0, pre_start_ = 0, pre_end_ = 0;
    // command reception
    bool hunting_ = false;
    double char_start_ = 0, next_sample_ = 0, hunt_deadline_ = 0, frame_end_ = 0;
    int bitn_ = 0, expected_ = 0;
    uint8_t sh_ = 0;
    // answer
    std::vector<uint8_t> bits_;   // line bits after the mark
    double t0_cyc_ = 0, carrier_phase_ = 0, bit_ns_ = 0, mark_ns_ = 0,
           end_ns_ = 0, cyc_ns_ = 0;
};

// Listen, turnaround and the carrier of the host, from its own pins.
class HostMonitor {
public:
    explicit HostMonitor(double clk_hz);
    void step(uint64_t cyc, bool o, bool oe) {
        if (o != prev_o_ || oe != prev_oe_)
            edge(cyc, o, oe);
    }
    std::vector<double> listen_us, turnaround_us;
    uint64_t listen_end_cyc = 0;   // the clock the last listen window ended
    double period_min_us = 1e9, period_max_us = 0, duty_min = 1, duty_max = 0;
    uint64_t periods = 0;
    std::vector<std::string> violations;

private:
    void edge(uint64_t cyc, bool o, bool oe);
    double cyc_us_;
    uint64_t gap_cyc_;
    bool prev_o_ = false, prev_oe_ = false;
    bool have_rise_ = false, have_fall_ = false;
    uint64_t last_rise_ = 0, last_fall_ = 0;
    bool in_listen_ = false, in_turn_ = false;
    uint64_t listen_start_ = 0, turn_start_ = 0;
};

// The rig's waveform (docs/rig.md), one sample a microsecond, written as a
// VCD with a 1 us timescale (the raw carrier of every line would be
// hundreds of MB). Per line: the host's drive enable; the envelope of the
// resolved line (1: a carrier edge in this microsecond, or in both
// neighbours: a 0.9 MHz carrier skips one now and then); and the same
// envelope as a UART decoder wants it, 1 wherever neither the host nor the
// cell drives the line (before the cell's answer, between transactions), so
// 31.25 kbps UART decodes the host's commands and the cell's answers.
// Bit 0-31: channel 0-31.
class LineVcd {
public:
    // false when the file cannot be written
    bool open(const std::string &path, int nch, unsigned cyc_per_us,
              const std::vector<std::string> &labels);
    bool is_open() const { return f_ != nullptr; }
    // one clock: the resolved lines, the host's and the cells' drive enables
    void step(unsigned line, unsigned oe, unsigned cell_oe) {
        rise_ |= line & ~prev_;
        prev_ = line;
        if (--left_ == 0)
            window(oe, oe | cell_oe);
    }
    // ends the file; its size in bytes
    uint64_t close();
    // a GTKWave save file for it: one group a line, named by labels
    bool write_gtkw(const std::string &path, const std::string &vcd_path) const;

private:
    void window(unsigned oe, unsigned driven);
    void emit(uint64_t t, unsigned env, unsigned oe, unsigned uart);
    FILE *f_ = nullptr;
    int nch_ = 0;
    unsigned cyc_per_us_ = 1, left_ = 1;
    unsigned rise_ = 0, prev_ = 0;           // rising edges in this window
    unsigned r_prev_ = 0, r_cur_ = 0, oe_cur_ = 0, drv_cur_ = 0;
    unsigned env_last_ = 0, oe_last_ = 0, uart_last_ = ~0u;
    uint64_t us_ = 0;                        // windows ended
    std::vector<std::string> labels_;
    std::vector<char> buf_;
};

// One clock of every channel's model and host monitor, from the pins the
// Verilated top left (bit ch of line, line_o, line_oe); returns the models'
// drive as the same bit vectors. The soak and the LiteX SoC both step so.
struct LineDrive {
    unsigned o = 0, oe = 0;
};
LineDrive step_channels(std::vector<std::unique_ptr<Periph>> &periph,
                        std::vector<HostMonitor> &mon, uint64_t cyc, unsigned line,
                        unsigned line_o, unsigned line_oe);

}  // namespace soak
