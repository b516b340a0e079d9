// Timing, machine, progress and plotting helpers shared by the benchmarks (rgvc_bench2d, rgvc_bench3d,
// rgvc_bench_dynamic, rgvc_bench_gl, rgvc_bench_classes, rgvc_sweep).
#pragma once

#include <rgvc/config.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <time.h>
#include <unistd.h>

namespace rgvc::bench {

/// [ms] wall time since t0.
inline double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// [ms] CPU time of this thread: on a shared machine it leaves out the time the thread waited for a core,
/// which wall time (CullStats::cullMs) includes.
inline double threadCpuMs() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

/// The q-quantile (0..1) of v by nearest rank; 0 for an empty v.
inline double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, std::size_t(q * double(v.size() - 1) + 0.5))];
}

/// [KiB] resident set size of this process (VmRSS), 0 if unreadable.
inline long rssKiB() {
    std::ifstream f("/proc/self/status");
    std::string line;
    while (std::getline(f, line))
        if (line.rfind("VmRSS:", 0) == 0) return std::atol(line.c_str() + 6);
    return 0;
}

/// The CPU's model name and the instruction set rgvc was compiled for (RGVC_SIMD), for the benchmark's
/// header line: figures of an AVX2 build and of a default one are not comparable.
inline std::string machine() {
    std::ifstream f("/proc/cpuinfo");
    std::string line;
    std::string cpu = "unknown CPU";
    while (std::getline(f, line))
        if (line.rfind("model name", 0) == 0) {
            cpu = line.substr(line.find(':') + 2);
            break;
        }
    return cpu + " (rgvc built for " RGVC_SIMD_LEVEL ")";
}

/// What runGnuplot did.
enum class PlotStatus { Drawn, Failed, NoGnuplot, BadArgument };

/// Runs `gnuplot -e "name='value'; ..." 'script'` (the scripts in scripts/ read their file names from such
/// variables). A missing gnuplot is PlotStatus::NoGnuplot, for the caller to report while keeping its CSVs;
/// a value or script path holding a quote is refused (BadArgument) rather than passed to the shell.
inline PlotStatus runGnuplot(const std::string& script, const std::vector<std::pair<std::string, std::string>>& vars) {
    auto unsafe = [](const std::string& v) { return v.find_first_of("'\"\\$`") != std::string::npos; };
    if (unsafe(script)) return PlotStatus::BadArgument;
    std::string assignments;
    for (const auto& [name, value] : vars) {
        if (unsafe(name) || unsafe(value)) return PlotStatus::BadArgument;
        assignments += name + "='" + value + "'; ";
    }
    if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) return PlotStatus::NoGnuplot;
    const std::string cmd = "gnuplot -e \"" + assignments + "\" '" + script + "'";
    return std::system(cmd.c_str()) == 0 ? PlotStatus::Drawn : PlotStatus::Failed;
}

/// Why a plot was not drawn, for messages ("" when it was).
inline const char* plotStatusText(PlotStatus s) {
    switch (s) {
    case PlotStatus::Drawn: return "";
    case PlotStatus::Failed: return "gnuplot failed";
    case PlotStatus::NoGnuplot: return "gnuplot is not installed (apt-get install gnuplot-nox)";
    case PlotStatus::BadArgument: return "a file name holds a quote, a backslash, $ or `";
    }
    return "";
}

/// A one-line progress bar on stdout, rewritten in place with '\r', for runs of minutes. Silent when
/// stdout is not a terminal (isatty), so that logs and CSV redirections stay clean.
class ProgressBar {
public:
    /// `total` steps ([Limit] >= 1; smaller is taken as 1), `label` printed before the bar.
    ProgressBar(std::string label, long total)
        : m_label(std::move(label)), m_total(std::max(1L, total)), m_enabled(isatty(1) != 0),
          m_start(std::chrono::steady_clock::now()) {}
    ~ProgressBar() { finish(); }
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;

    /// Sets the steps done (clamped to the total) and redraws; `note` goes after the bar (e.g. "N=5000").
    void update(long done, const std::string& note = {}) {
        if (!m_enabled || m_finished) return;
        done = std::clamp(done, 0L, m_total);
        constexpr int kWidth = 30;
        const int filled = int(double(done) / double(m_total) * kWidth);
        std::string bar(std::size_t(filled), '#');
        bar.resize(kWidth, '.');
        const double s = msSince(m_start) / 1000.0;
        // The elapsed time, and the remaining time from the mean step time so far.
        const double eta = done > 0 ? s * double(m_total - done) / double(done) : 0.0;
        std::printf("\r%s [%s] %ld/%ld %.0fs, ~%.0fs left %s\033[K", m_label.c_str(), bar.c_str(), done, m_total, s, eta,
                    note.c_str());
        std::fflush(stdout);
    }
    /// Ends the line (once); later updates are ignored.
    void finish() {
        if (m_enabled && !m_finished) {
            std::printf("\n");
            std::fflush(stdout);
        }
        m_finished = true;
    }

private:
    std::string m_label;
    long m_total;
    bool m_enabled, m_finished = false;
    std::chrono::steady_clock::time_point m_start;
};

} // namespace rgvc::bench
