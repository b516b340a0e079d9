// Timing and machine helpers shared by the benchmarks (rgvc_bench2d, rgvc_bench3d, rgvc_bench_dynamic).
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <time.h>

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

/// The CPU's model name, for the benchmark's header line.
inline std::string machine() {
    std::ifstream f("/proc/cpuinfo");
    std::string line;
    while (std::getline(f, line))
        if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
    return "unknown CPU";
}

} // namespace rgvc::bench
