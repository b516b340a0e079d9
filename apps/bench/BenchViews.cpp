// rgvc_bench_views: several views per frame (Culler::cullViews) on the paper's moving-spheres scene
// (reference::movingSpheres3D, 100 x 60 x 100 unit voxels by default), N cameras walking the same path
// at phases 1/N apart (fov 60, aspect 16:9). Per frame the spheres move and both cullers get
// updateObject for each (not timed); then one culler culls the N views on a SerialExecutor (one thread)
// and the other, holding the same scene, on a TbbExecutor of --threads threads; the order of the two
// alternates per frame. Printed: median and p90 wall time of the call, the process CPU time per call
// (the sum over its threads: on a shared machine wall time includes waiting for a core, CPU time does
// not), the speed-up of the medians, and the scene update's share. Every frame's PVS must be the same in
// both (exit 1 otherwise).
//
//   rgvc_bench_views [--views N] [--threads T] [--frames F] [--spheres S] [--seed S]
//   rgvc_bench_views --ortho [--frames F] [--spheres S] [--seed S] [--ref-every K]
//     (an orthographic cascade over a city: parallel-ray occlusion against view-volume culling, BenchOrtho.cpp)
#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/dynamics/TbbExecutor.hpp"

#include "BenchOrtho.hpp"
#include "BenchSupport.hpp"

#include "RandomScenes3D.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <time.h>

using namespace rgvc;
namespace ref = rgvc::reference;
using namespace rgvc::bench;

namespace {

double processCpuMs() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

[[noreturn]] void usage(const char* what) {
    std::fprintf(stderr, "rgvc_bench_views: %s\nusage: rgvc_bench_views [--views N] [--threads T] [--frames F] [--spheres S] [--seed S]\n"
                         "       rgvc_bench_views --ortho [--frames F] [--spheres S] [--seed S] [--ref-every K]\n", what);
    std::exit(2);
}

int intArg(int& i, int argc, char** argv, int lo, int hi) {
    if (i + 1 >= argc) usage((std::string(argv[i]) + " needs a value").c_str());
    char* end = nullptr;
    const long v = std::strtol(argv[++i], &end, 10);
    if (*end != 0 || v < lo || v > hi)
        usage((std::string(argv[i - 1]) + " must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]").c_str());
    return int(v);
}

} // namespace

int main(int argc, char** argv) {
    int views = 4, threads = 2, frames = 100, spheres = 5000, seed = 1, refEvery = 10;
    bool ortho = false, spheresGiven = false;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--views")) views = intArg(i, argc, argv, 1, int(kMaxViews));
        else if (!std::strcmp(argv[i], "--threads")) threads = intArg(i, argc, argv, 1, 256);
        else if (!std::strcmp(argv[i], "--frames")) frames = intArg(i, argc, argv, 1, 1000000);
        else if (!std::strcmp(argv[i], "--spheres")) spheres = intArg(i, argc, argv, 1, 10000000), spheresGiven = true;
        else if (!std::strcmp(argv[i], "--ortho")) ortho = true;
        else if (!std::strcmp(argv[i], "--ref-every")) refEvery = intArg(i, argc, argv, 0, 1000000);
        else if (!std::strcmp(argv[i], "--seed")) seed = intArg(i, argc, argv, 0, 1 << 30);
        else usage((std::string("unknown option ") + argv[i]).c_str());
    }
    if (ortho) return runOrthoBench(frames, spheresGiven ? spheres : 3000, seed, refEvery);
    ref::MovingSpheres3D b = ref::movingSpheres3D(std::uint64_t(seed), spheres);
    Culler3D serial(b.grid), parallel(b.grid);
    for (const ObjectDesc<3>& o : b.objects) {
        serial.addObject(o);
        parallel.addObject(o);
    }
    SerialExecutor one;
    TbbExecutor tbb(threads);
    std::vector<double> wallS, wallP, cpuS, cpuP, updateS, passesS;
    std::vector<Camera3> cams(static_cast<std::size_t>(views));
    std::size_t pvs = 0;
    for (int f = 0; f < frames; ++f) {
        ref::stepMovingSpheres(b);
        for (const ObjectDesc<3>& o : b.objects) {
            serial.updateObject(o.id, o.shape);
            parallel.updateObject(o.id, o.shape);
        }
        for (int v = 0; v < views; ++v) cams[std::size_t(v)] = ref::movingSpheresCamera(b, f * views + v * frames, frames * views);
        const MultiCullResult* rs = nullptr;
        const MultiCullResult* rp = nullptr;
        for (int k = 0; k < 2; ++k) {
            const bool doSerial = (k == 0) == (f % 2 == 0);
            const double c0 = processCpuMs();
            const auto t0 = std::chrono::steady_clock::now();
            if (doSerial) rs = &serial.cullViews(cams, &one);
            else rp = &parallel.cullViews(cams, &tbb);
            const double wall = msSince(t0), cpu = processCpuMs() - c0;
            (doSerial ? wallS : wallP).push_back(wall);
            (doSerial ? cpuS : cpuP).push_back(cpu);
        }
        updateS.push_back(rs->scene.updateMs);
        double passes = 0;
        for (const CullResult& v : rs->views) passes += v.stats.cullMs;
        passesS.push_back(passes);
        for (int v = 0; v < views; ++v) {
            if (rs->views[std::size_t(v)].pvs != rp->views[std::size_t(v)].pvs) {
                std::fprintf(stderr, "rgvc_bench_views: frame %d view %d: the PVS differs between the executors\n", f, v);
                return 1;
            }
            pvs += rs->views[std::size_t(v)].pvs.size();
        }
    }
    const double mS = percentile(wallS, 0.5), mP = percentile(wallP, 0.5);
    std::printf("rgvc_bench_views: %d spheres, %d views, %d frames, %s, TBB arena of %d threads\n", spheres, views, frames,
                machine().c_str(), tbb.concurrency());
    std::printf("  serial executor: median %.2f ms (p90 %.2f), CPU %.2f ms per frame; scene update median %.2f ms\n", mS,
                percentile(wallS, 0.9), percentile(cpuS, 0.5), percentile(updateS, 0.5));
    std::printf("  TBB executor:    median %.2f ms (p90 %.2f), CPU %.2f ms per frame\n", mP, percentile(wallP, 0.9),
                percentile(cpuP, 0.5));
    // Amdahl: the scene update and the reveals run on one thread, the passes on `threads`.
    const double passes = percentile(passesS, 0.5), serialPart = std::max(0.0, mS - passes);
    std::printf("  view passes (serial run): median %.2f ms of the frame, the rest %.2f ms; bound on %d threads %.2fx\n",
                passes, serialPart, threads, mS / (serialPart + passes / std::min(threads, views)));
    std::printf("  speed-up (median wall) %.2fx; mean |PVS| per view %.1f; same PVS in every frame\n", mS / mP,
                double(pvs) / double(frames * views));
    std::printf("  load average when done: %s", [] {
        static char buf[128] = "?\n";
        if (FILE* f = std::fopen("/proc/loadavg", "r")) {
            if (!std::fgets(buf, sizeof buf, f)) std::snprintf(buf, sizeof buf, "?\n");
            std::fclose(f);
        }
        return buf;
    }());
    return 0;
}
