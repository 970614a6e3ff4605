// C++ peripheral model and host-side monitor of the Verilator soak (periph.h).
#include "periph.h"

#include <algorithm>
#include <cmath>

namespace soak {

namespace {
// the spec's and NOTES.md's numbers the model works with, microseconds
constexpr double CHARGE_MIN_US = 7000;   // carrier needed to power up
constexpr double SYNC_MIN_US = 500;      // a gap in this window arms the receiver
constexpr double SYNC_MAX_US = 1500;
constexpr double QUIET_US = 1500;        // after an error: the host's listen + turnaround
constexpr double GAP_US = 2;             // no rising edge this long: carrier off
constexpr double TOL_US = 1.5;           // edge quantisation on phase lengths
// the answer's physical windows (NOTES.md "The response")
constexpr double BAUD_MIN = 30750, BAUD_MAX = 31750;
constexpr double CARRIER_MIN = 0.90e6, CARRIER_MAX = 1.10e6;
constexpr double DUTY_MIN = 0.30, DUTY_MAX = 0.70;
// the host needs half a bit of mark; one bit is what a peripheral sends
constexpr double MARK_MIN_BITS = 1.0, MARK_MAX_BITS = 2.0;
// carrier stop -> mark; short enough that the longest answer (2 bits of
// mark, 33 bits at 30.75 kbps: ~1.14 ms) ends inside a 2 ms listen window
constexpr double DELAY_MIN_US = 20, DELAY_MAX_US = 400;

uint64_t cycles_ceil(double us, double cyc_us) {
    return static_cast<uint64_t>(std::ceil(us / cyc_us));
}
}  // namespace

const char *fault_name(Fault f) {
    switch (f) {
    case Fault::None: return "none";
    case Fault::Silent: return "no response";
    case Fault::Checksum: return "bad checksum";
    case Fault::StopBit: return "stop bit 0";
    case Fault::Short: return "short answer";
    }
    return "?";
}

// ---------------------------------------------------------------- Device
Device::Device(const SoakProfile &pr) : pr_(pr), flash_(pr.flash, pr.flash + pr.size) {}

DeviceAnswer Device::handle(const uint8_t *f, int n) {
    DeviceAnswer a;
    if (n < 3 || n != (f[0] < 0x80 ? 3 : 4)) {
        a.reason = "bad length";
        return a;
    }
    uint8_t sum = 0;
    for (int i = 0; i < n - 1; ++i)
        sum = static_cast<uint8_t>(sum + f[i]);
    if (static_cast<uint8_t>(~sum) != f[n - 1]) {
        a.reason = "bad checksum";
        return a;
    }
    const uint8_t cmd = f[0];
    const unsigned size = pr_.size;
    auto answer = [&a](unsigned msb, unsigned lsb) {
        a.answer = true;
        a.msb = static_cast<uint8_t>(msb);
        a.lsb = static_cast<uint8_t>(lsb);
        a.reason = "answered";
    };
    if (cmd >= 0x80) {
        const unsigned payload = static_cast<unsigned>(f[1]) << 8 | f[2];
        const unsigned addr = ((payload >> 14) & 3u) << 7 | (cmd & 0x7Fu);
        if (addr >= size) {
            a.reason = "address out of range";
        } else if (flash_[addr] != BLANK) {
            a.reason = "write ignored: word not blank";   // write-once
        } else {
            flash_[addr] = static_cast<uint16_t>(payload & 0x3FFFu);
            a.reason = "written";
        }
        return a;
    }
    switch (cmd) {
    case 0x40: answer(pr_.config_msb, pr_.config_lsb); return a;
    case 0x41: answer(pr_.fw_byte, pr_.type_byte); return a;
    case 0x42: answer((pr_.adc_ref_voltage & 0xFFFu) >> 8, pr_.adc_ref_voltage & 0xFFu); return a;
    case 0x43: answer((pr_.adc_temperature & 0xFFFu) >> 8, pr_.adc_temperature & 0xFFu); return a;
    case 0x44: answer((pr_.adc_o2 & 0xFFFu) >> 8, pr_.adc_o2 & 0xFFu); return a;
    default: break;
    }
    if (cmd < 0x46 || cmd > 0x4B) {
        a.reason = "reserved command";
        return a;
    }
    const unsigned addr = (cmd & 1u) << 8 | f[1];
    if (addr >= size) {
        a.reason = "address out of range";
        return a;
    }
    if (cmd >= 0x48 && cmd <= 0x49) {
        const unsigned w = flash_[addr] & 0x3FFFu;
        answer(w >> 8, w & 0xFFu);
    } else if (cmd <= 0x47) {
        // none left: the flash size, as tb/periph_model.py decides
        unsigned found = size;
        for (unsigned x = addr; x < size; ++x)
            if (flash_[x] == BLANK) {
                found = x;
                break;
            }
        answer(found >> 8, found & 0xFFu);
    } else {
        const unsigned page = addr & ~15u;
        for (unsigned x = page; x < std::min(page + 16u, size); ++x)
            flash_[x] = BLANK;
        a.reason = "erased";
    }
    return a;
}

// ---------------------------------------------------------------- Periph
Periph::Periph(const SoakProfile &pr, uint64_t seed, double fault_rate, double clk_hz)
    : dev_(pr), rng_(seed), fault_rate_(fault_rate), cyc_us_(1e6 / clk_hz),
      gap_cyc_(cycles_ceil(GAP_US, 1e6 / clk_hz)),
      quiet_cyc_(cycles_ceil(QUIET_US, 1e6 / clk_hz)), cyc_ns_(1e9 / clk_hz) {}

void Periph::on_rise(uint64_t cyc) {
    const bool start = !burst_on_;
    last_rise_ = cyc;
    if (!start) {
        ++burst_rises_;
        return;
    }
    burst_on_ = true;
    burst_first_ = cyc;
    burst_rises_ = 1;
    switch (st_) {
    case St::Idle:
        cur_ = PeriphTxn();
        st_ = St::Charge;
        break;
    case St::Sync: {
        const double gap = us(static_cast<double>(cyc) - sync_start_);
        cur_.sync_us = gap;
        if (gap >= SYNC_MIN_US && gap <= SYNC_MAX_US) {
            pre_start_ = static_cast<double>(cyc);
            st_ = St::Preamble;
        } else if (gap > SYNC_MAX_US) {
            // the host ran a charge and never went on: log it, then this
            // burst may be the next charge
            cur_.error = "sync too long";
            log.push_back(cur_);
            cur_ = PeriphTxn();
            st_ = St::Charge;
        } else {
            fail(cyc, "sync too short");
        }
        break;
    }
    default:
        break;   // carrier of 1 bits in a command, or ignored while quiet
    }
}

void Periph::on_burst_end() {
    burst_on_ = false;
    double per = period_cyc_ > 0 ? period_cyc_ : 1.0 / cyc_us_;
    if (burst_rises_ > 1)
        per = static_cast<double>(last_rise_ - burst_first_) / static_cast<double>(burst_rises_ - 1);
    const double end = static_cast<double>(last_rise_) + per;
    switch (st_) {
    case St::Charge: {
        const double len = us(end - static_cast<double>(burst_first_));
        if (len >= CHARGE_MIN_US - TOL_US) {
            period_cyc_ = per;
            bit_cyc_ = 32 * per;     // the host's bit is 32 of its periods
            cur_.charge_us = len;
            sync_start_ = end;
            st_ = St::Sync;
        } else {
            ++short_bursts;
            st_ = St::Idle;
        }
        break;
    }
    case St::Preamble:
        cur_.preamble_us = us(end - pre_start_);
        pre_end_ = end;
        st_ = St::Command;
        hunting_ = true;
        [[fallthrough]];
    case St::Command:
        // the carrier stopping while hunting is the next start bit; inside
        // a character it is only a 0 data bit, which sampling reads
        if (hunting_) {
            hunting_ = false;
            char_start_ = end;
            bitn_ = 0;
            sh_ = 0;
            next_sample_ = end + 0.5 * bit_cyc_;
        }
        break;
    case St::Execute: {
        cur_.execute_us = us(end - frame_end_);
        const SoakProfile &pr = dev_.profile();
        if (cur_.execute_us < pr.exec_min_us - TOL_US) {
            fail(last_rise_, "execute carrier too short");
        } else if (cur_.execute_us > pr.exec_max_us + TOL_US) {
            // the command runs, but such firmware answers over the host's
            // carrier: modelled as no answer, as tb/periph_model.py does
            DeviceAnswer a = dev_.handle(cur_.frame, cur_.flen);
            cur_.device_reason = a.reason;
            cur_.error = "execute phase too long";
            log.push_back(cur_);
            st_ = St::Idle;
        } else {
            handle_frame(end);
        }
        break;
    }
    default:
        break;
    }
}

void Periph::sample(uint64_t cyc) {
    const bool env = burst_on_;
    if (bitn_ == 0) {
        if (env) {
            fail(cyc, "command: start bit reads 1");
            return;
        }
    } else if (bitn_ <= 8) {
        sh_ = static_cast<uint8_t>(sh_ | (env ? 1u : 0u) << (bitn_ - 1));
    } else {
        if (!env) {
            fail(cyc, "command: stop bit reads 0");
            return;
        }
        cur_.frame[cur_.flen++] = sh_;
        if (cur_.flen == 1)
            expected_ = sh_ < 0x80 ? 3 : 4;
        if (cur_.flen == expected_) {
            // the host keeps its carrier on from the stop bits into execute
            frame_end_ = char_start_ + 11 * bit_cyc_;
            cur_.command_us = us(frame_end_ - pre_end_);
            st_ = St::Execute;
        } else {
            hunting_ = true;
            hunt_deadline_ = char_start_ + 12 * bit_cyc_;
        }
        return;
    }
    ++bitn_;
    next_sample_ = char_start_ + (bitn_ + 0.5) * bit_cyc_;
}

void Periph::fail(uint64_t cyc, const char *why) {
    cur_.error = why;
    log.push_back(cur_);
    last_rise_ = std::max(last_rise_, cyc);
    hunting_ = false;
    st_ = St::Quiet;
}

void Periph::handle_frame(double exec_end) {
    const DeviceAnswer a = dev_.handle(cur_.frame, cur_.flen);
    cur_.device_reason = a.reason;
    cur_.answers = a.answer;
    cur_.dev_msb = a.msb;
    cur_.dev_lsb = a.lsb;
    if (!a.answer) {
        log.push_back(cur_);
        st_ = St::Idle;
        return;
    }
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    auto uni = [&](double lo, double hi) { return lo + (hi - lo) * u01(rng_); };
    uint8_t resp[3] = {a.msb, a.lsb, static_cast<uint8_t>(~(a.msb + a.lsb))};
    cur_.wire[0] = resp[0];
    cur_.wire[1] = resp[1];
    cur_.wire[2] = resp[2];
    cur_.nwire = 3;
    if (u01(rng_) < fault_rate_)
        cur_.fault = only_ != Fault::None ? only_ : static_cast<Fault>(1 + rng_() % 4);
    cur_.baud = uni(BAUD_MIN, BAUD_MAX);
    cur_.carrier_hz = uni(CARRIER_MIN, CARRIER_MAX);
    cur_.duty = uni(DUTY_MIN, DUTY_MAX);
    cur_.stop_bits = 1 + static_cast<int>(rng_() % 2);
    cur_.mark_us = uni(MARK_MIN_BITS, MARK_MAX_BITS) * 1e6 / cur_.baud;
    cur_.delay_us = uni(DELAY_MIN_US, DELAY_MAX_US);
    carrier_phase_ = u01(rng_);
    switch (cur_.fault) {
    case Fault::Silent:
        log.push_back(cur_);          // handled, but nothing on the line
        st_ = St::Idle;
        return;
    case Fault::Checksum:
        cur_.wire[2] = static_cast<uint8_t>(cur_.wire[2] ^ (1 + rng_() % 255));
        break;
    case Fault::StopBit:
        cur_.fault_byte = static_cast<int>(rng_() % 3);
        break;
    case Fault::Short:
        cur_.nwire = 1 + static_cast<int>(rng_() % 2);
        break;
    case Fault::None:
        break;
    }
    bits_.clear();
    for (int i = 0; i < cur_.nwire; ++i) {
        bits_.push_back(0);
        for (int k = 0; k < 8; ++k)
            bits_.push_back(static_cast<uint8_t>(cur_.wire[i] >> k & 1u));
        for (int s = 0; s < cur_.stop_bits; ++s)
            bits_.push_back(s == 0 && cur_.fault == Fault::StopBit && i == cur_.fault_byte ? 0 : 1);
    }
    cur_.answered = true;
    bit_ns_ = 1e9 / cur_.baud;
    mark_ns_ = cur_.mark_us * 1e3;
    end_ns_ = mark_ns_ + static_cast<double>(bits_.size()) * bit_ns_;
    t0_cyc_ = exec_end + cur_.delay_us / cyc_us_;
    // recorded before it is played: the host's result comes after it anyway
    log.push_back(cur_);
    st_ = St::Answer;
}

void Periph::answer_step(uint64_t cyc, bool host_oe) {
    const double tc = static_cast<double>(cyc) - t0_cyc_;
    if (tc < 0) {
        o = oe = false;
        return;
    }
    const double t = tc * cyc_ns_;
    if (t >= end_ns_) {
        o = oe = false;
        st_ = St::Idle;
        prev_line_ = false;
        burst_on_ = false;
        return;
    }
    const bool level = t < mark_ns_ || bits_[static_cast<size_t>((t - mark_ns_) / bit_ns_)];
    if (level) {
        // the carrier runs on from the start of the mark (phase-continuous)
        double ph = t * cur_.carrier_hz * 1e-9 + carrier_phase_;
        ph -= std::floor(ph);
        o = ph < cur_.duty;
    } else {
        o = false;
    }
    oe = true;
    if (host_oe)
        ++collisions;
}

// ---------------------------------------------------------------- HostMonitor
HostMonitor::HostMonitor(double clk_hz)
    : cyc_us_(1e6 / clk_hz), gap_cyc_(cycles_ceil(GAP_US, 1e6 / clk_hz)) {}

void HostMonitor::edge(uint64_t cyc, bool o, bool oe) {
    const bool oe_rise = oe && !prev_oe_, oe_fall = !oe && prev_oe_;
    const bool o_rise = o && !prev_o_, o_fall = !o && prev_o_;
    prev_o_ = o;
    prev_oe_ = oe;
    if (oe_fall && have_rise_ && cyc - last_rise_ <= gap_cyc_) {
        // released straight out of a carrier: the listen window (a release
        // after the driven-low turnaround is idle)
        in_listen_ = true;
        listen_start_ = cyc;
    }
    if (oe_rise && in_listen_) {
        in_listen_ = false;
        listen_us.push_back(static_cast<double>(cyc - listen_start_) * cyc_us_);
        listen_end_cyc = cyc;
        in_turn_ = true;
        turn_start_ = cyc;
    }
    if (o_fall) {
        last_fall_ = cyc;
        have_fall_ = true;
    }
    if (o_rise && oe) {
        if (in_turn_) {
            in_turn_ = false;
            turnaround_us.push_back(static_cast<double>(cyc - turn_start_) * cyc_us_);
        }
        if (have_rise_ && cyc - last_rise_ <= gap_cyc_) {
            const double per = static_cast<double>(cyc - last_rise_) * cyc_us_;
            const double duty = have_fall_ && last_fall_ > last_rise_
                                    ? static_cast<double>(last_fall_ - last_rise_) * cyc_us_ / per
                                    : 0.0;
            ++periods;
            period_min_us = std::min(period_min_us, per);
            period_max_us = std::max(period_max_us, per);
            duty_min = std::min(duty_min, duty);
            duty_max = std::max(duty_max, duty);
            if ((per < 1 / 1.10 || per > 1 / 0.90 || duty < 0.45 || duty > 0.60) &&
                violations.size() < 20)
                violations.push_back("carrier period " + std::to_string(per) + " us, duty " +
                                     std::to_string(duty) + " at cycle " + std::to_string(cyc));
        }
        last_rise_ = cyc;
        have_rise_ = true;
    }
}

// ---------------------------------------------------------------- LineVcd
bool LineVcd::open(const std::string &path, int nch, unsigned cyc_per_us,
                   const std::vector<std::string> &labels) {
    f_ = std::fopen(path.c_str(), "w");
    if (!f_)
        return false;
    buf_.resize(1u << 20);
    std::setvbuf(f_, buf_.data(), _IOFBF, buf_.size());
    nch_ = nch;
    cyc_per_us_ = left_ = cyc_per_us;
    labels_ = labels;
    std::fprintf(f_,
                 "$version twowire-host rig (sim/soak/soak_main.cpp, docs/rig.md) $end\n"
                 "$comment per line: chNN_oe, the host's drive enable (line_oe); chNN_env, "
                 "the carrier envelope of the resolved line (1: carrier present); chNN_uart, "
                 "the envelope, 1 where neither host nor cell drives (UART, 31250 baud); "
                 "one sample a microsecond $end\n"
                 "$timescale 1us $end\n$scope module rig $end\n");
    for (int ch = 0; ch < nch; ++ch)
        std::fprintf(f_,
                     "$scope module ch%02d $end\n$var wire 1 o%d ch%02d_oe $end\n"
                     "$var wire 1 e%d ch%02d_env $end\n$var wire 1 u%d ch%02d_uart $end\n"
                     "$upscope $end\n",
                     ch, ch, ch, ch, ch, ch, ch);
    std::fprintf(f_, "$upscope $end\n$enddefinitions $end\n#0\n$dumpvars\n");
    for (int ch = 0; ch < nch; ++ch)
        std::fprintf(f_, "0o%d\n0e%d\n1u%d\n", ch, ch, ch);
    std::fprintf(f_, "$end\n");
    return true;
}

// Window us_ has just ended: window us_ - 1 is written, its envelope
// bridged over a window without an edge when both neighbours have one.
void LineVcd::window(unsigned oe, unsigned driven) {
    left_ = cyc_per_us_;
    const unsigned r_next = rise_;
    rise_ = 0;
    if (us_ >= 1) {
        const unsigned env = r_cur_ | (r_prev_ & r_next);
        emit(us_ - 1, env, oe_cur_, env | ~drv_cur_);
    }
    r_prev_ = r_cur_;
    r_cur_ = r_next;
    oe_cur_ = oe;
    drv_cur_ = driven;
    ++us_;
}

void LineVcd::emit(uint64_t t, unsigned env, unsigned oe, unsigned uart) {
    const unsigned mask = nch_ >= 32 ? ~0u : (1u << nch_) - 1u;
    uart &= mask;
    const unsigned d_env = env ^ env_last_, d_oe = oe ^ oe_last_, d_uart = uart ^ (uart_last_ & mask);
    if (!(d_env | d_oe | d_uart) || !f_)
        return;
    std::fprintf(f_, "#%llu\n", static_cast<unsigned long long>(t));
    for (int ch = 0; ch < nch_; ++ch) {
        if (d_oe >> ch & 1u)
            std::fprintf(f_, "%uo%d\n", oe >> ch & 1u, ch);
        if (d_env >> ch & 1u)
            std::fprintf(f_, "%ue%d\n", env >> ch & 1u, ch);
        if (d_uart >> ch & 1u)
            std::fprintf(f_, "%uu%d\n", uart >> ch & 1u, ch);
    }
    env_last_ = env;
    oe_last_ = oe;
    uart_last_ = uart;
}

uint64_t LineVcd::close() {
    if (!f_)
        return 0;
    std::fprintf(f_, "#%llu\n", static_cast<unsigned long long>(us_));
    const long size = std::ftell(f_);
    std::fclose(f_);
    f_ = nullptr;
    return size < 0 ? 0 : static_cast<uint64_t>(size);
}

bool LineVcd::write_gtkw(const std::string &path, const std::string &vcd_path) const {
    FILE *f = std::fopen(path.c_str(), "w");
    if (!f)
        return false;
    std::fprintf(f,
                 "[*] GTKWave save file of make rig (docs/rig.md), written by the rig\n"
                 "[*] per line: the host's drive enable, the carrier envelope, the envelope for UART\n"
                 "[dumpfile] \"%s\"\n[timestart] 0\n[size] 1600 1000\n[pos] -1 -1\n"
                 "[sst_width] 220\n[signals_width] 260\n[sst_expanded] 1\n",
                 vcd_path.c_str());
    for (int ch = 0; ch < nch_; ++ch) {
        const std::string g = labels_.size() > static_cast<size_t>(ch) ? labels_[ch] : "";
        std::fprintf(f, "@800200\n-ch%02d %s\n@28\nrig.ch%02d.ch%02d_oe\nrig.ch%02d.ch%02d_env\n"
                        "rig.ch%02d.ch%02d_uart\n@1000200\n-ch%02d %s\n",
                     ch, g.c_str(), ch, ch, ch, ch, ch, ch, ch, g.c_str());
    }
    return std::fclose(f) == 0;
}

LineDrive step_channels(std::vector<std::unique_ptr<Periph>> &periph,
                        std::vector<HostMonitor> &mon, uint64_t cyc, unsigned line,
                        unsigned line_o, unsigned line_oe) {
    LineDrive d;
    for (size_t ch = 0; ch < periph.size(); ++ch) {
        Periph &p = *periph[ch];
        p.step(cyc, line >> ch & 1u, line_oe >> ch & 1u);
        mon[ch].step(cyc, line_o >> ch & 1u, line_oe >> ch & 1u);
        d.o |= static_cast<unsigned>(p.o) << ch;
        d.oe |= static_cast<unsigned>(p.oe) << ch;
    }
    return d;
}

}  // namespace soak
