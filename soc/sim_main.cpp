// Verilator harness of the LiteX drop-in proof (docs/soc.md): clocks the
// SoC (soc/sim_top.v around LiteX's twh_soc), answers its three 2-wire lines
// with the soak's C++ peripheral model (sim/soak/periph.cpp, no faults) and
// the host monitor of the same file, and copies what the CPU writes to the
// UART to stdout. Everything the firmware does is its own: the harness
// never touches the bus.
//
// Ends when the firmware prints "soc: end", or fails (exit 1) after
// --max-ms of SoC time. Exit 1 as well on a reception error of a model, a
// collision on a line or a timing breach the host monitor saw.
//
//   sim_soc --mem-dir DIR [--max-ms N] [--seed S]
//   (DIR: where LiteX's $readmemh .init files are)
#include <unistd.h>

#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <verilated.h>

#include "Vsim_top.h"
#include "periph.h"

#ifndef SOC_CLK_HZ
#error "SOC_CLK_HZ must match the SoC's clock"
#endif

namespace {
constexpr int NCH = 3;
constexpr double CLK_HZ = SOC_CLK_HZ;
}  // namespace

int main(int argc, char **argv) {
    std::string mem_dir;
    double max_ms = 20000;
    uint64_t seed = 1;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--mem-dir" && i + 1 < argc) mem_dir = argv[++i];
        else if (a == "--max-ms" && i + 1 < argc) max_ms = std::atof(argv[++i]);
        else if (a == "--seed" && i + 1 < argc) seed = std::strtoull(argv[++i], nullptr, 0);
        else {
            std::fprintf(stderr, "usage: sim_soc --mem-dir DIR [--max-ms N] [--seed S]\n");
            return 2;
        }
    }
    // LiteX's memories read their .init files by bare name
    if (!mem_dir.empty() && chdir(mem_dir.c_str()) != 0) {
        std::perror(mem_dir.c_str());
        return 2;
    }

    const auto wall0 = std::chrono::steady_clock::now();
    auto ctx = std::make_unique<VerilatedContext>();
    auto top = std::make_unique<Vsim_top>(ctx.get());
    std::vector<std::unique_ptr<soak::Periph>> periph;
    std::vector<soak::HostMonitor> mon;
    for (int ch = 0; ch < NCH; ++ch) {
        periph.emplace_back(new soak::Periph(SOAK_PROFILES[ch], seed + static_cast<uint64_t>(ch),
                                             0.0, CLK_HZ));
        mon.emplace_back(CLK_HZ);
    }

    Vsim_top &d = *top;
    const uint64_t max_cyc = static_cast<uint64_t>(max_ms * 1e-3 * CLK_HZ);
    std::string out, line_buf;
    bool ended = false;
    uint64_t cyc = 0;
    d.uart_ready = 1;
    d.rst = 1;
    d.clk = 0;
    d.eval();
    for (; cyc < max_cyc && !ended; ) {
        if (cyc == 16)
            d.rst = 0;
        // the byte the stream hands over at this edge
        const bool take = d.uart_valid && d.uart_ready;
        const char c = static_cast<char>(d.uart_data);
        d.clk = 1;
        d.eval();
        ++cyc;
        if (take && c != '\r') {
            std::fputc(c, stdout);
            out += c;
            if (c == '\n') {
                std::fflush(stdout);
                ended = line_buf == "soc: end";
                line_buf.clear();
            } else {
                line_buf += c;
            }
        }
        const soak::LineDrive drv = soak::step_channels(periph, mon, cyc, d.line, d.line_o, d.line_oe);
        d.periph_o = static_cast<uint8_t>(drv.o);
        d.periph_oe = static_cast<uint8_t>(drv.oe);
        d.clk = 0;
        d.eval();
    }
    top->final();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();

    int bad = 0;
    uint64_t txns = 0;
    for (int ch = 0; ch < NCH; ++ch) {
        const soak::Periph &p = *periph[static_cast<size_t>(ch)];
        uint64_t errors = 0;
        for (const auto &x : p.log)
            if (!x.error.empty()) {
                if (errors++ < 3)
                    std::printf("sim: channel %d: the model could not follow the host: %s\n", ch,
                                x.error.c_str());
            }
        txns += p.log.size();
        const auto &m = mon[static_cast<size_t>(ch)];
        for (size_t i = 0; i < m.violations.size() && i < 3; ++i)
            std::printf("sim: channel %d: host timing: %s\n", ch, m.violations[i].c_str());
        std::printf("sim: channel %d (%s): %zu transactions, %" PRIu64
                    " reception errors, %" PRIu64 " collisions, %zu timing violations\n",
                    ch, p.device().profile().name, p.log.size(), errors, p.collisions,
                    m.violations.size());
        bad |= errors != 0 || p.collisions != 0 || !m.violations.empty();
    }
    std::printf("sim: %" PRIu64 " clocks (%.1f ms of SoC time at %.0f MHz), %" PRIu64
                " line transactions, %.1f s wall, %.2f M clocks/s\n",
                cyc, static_cast<double>(cyc) / CLK_HZ * 1e3, CLK_HZ / 1e6, txns, wall,
                static_cast<double>(cyc) / wall / 1e6);
    if (!ended) {
        std::printf("sim: FAIL: no \"soc: end\" within %.0f ms of SoC time\n", max_ms);
        return 1;
    }
    if (bad) {
        std::printf("sim: FAIL: line errors above\n");
        return 1;
    }
    return 0;
}
