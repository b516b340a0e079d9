// rgvc_sweep: run time against error (issue 12, section 3). Every named scene of scenes/ is run under a
// base setting and one-factor-at-a-time variations (SweepSettings.hpp: grid resolution, occluder
// extension, the 3D core (brick tree or shell caps) and its image rows, the occlusion buffer, TBVs, the
// GL stage's method and n_vp) and a few combinations; each is measured for median cull time, frame time
// with drawing (OSMesa, llvmpipe), misses and |answer| / |visible| against the exact reference
// (SweepRunner.hpp). The results: a CSV (the settings in `#` header lines), the Pareto front of time
// against overestimation per scene, the best setting per scene (the fastest on the front, and the tightest
// within 1.5x of its time) and, with --plot, a PNG drawn by scripts/plot_sweep.gp (gnuplot).
//
//   rgvc_sweep [--scenes NAME,NAME,...] [--frames N] [--warmup W] [--ref-frames K] [--no-gl] [--gl-size WxH]
//              [--csv FILE] [--plot FILE.png] [--quick]
//
// NAME: a scene file, or the stem of one in the source tree's scenes/ (default: city-2d, city-3d,
// clusters-3d, maze-2d, maze-3d, open-2d, open-3d, paper-walk-3d). --quick: 3 measured frames after 1
// warm-up, 1 checked, a few settings, small images, four scenes: the ctest smoke run.
// Exit status: 0; 1 when a conservative setting missed a visible object (or on an error); 2 on bad flags.
#include "SweepReport.hpp"
#include "SweepRunner.hpp"

#include "BenchSupport.hpp"
#include "BenchReference.hpp"

#include "SceneFile.hpp"
#include "rgvc/render/gl/GlError.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

using namespace rgvc;
using namespace rgvc::bench;
namespace fs = std::filesystem;

namespace {

struct Args {
    SweepConfig cfg;
    std::vector<std::string> scenes;
    std::string csv = "rgvc_sweep.csv", plot;
};

[[noreturn]] void usage(const std::string& why) {
    std::fprintf(stderr,
                 "rgvc_sweep: %s\nusage: rgvc_sweep [--scenes NAME,...] [--frames N] [--warmup W] [--ref-frames K] "
                 "[--no-gl] [--gl-size WxH] [--csv FILE] [--plot FILE.png] [--quick]\n",
                 why.c_str());
    std::exit(2);
}

int intArg(const std::string& flag, const std::string& v, int lo, int hi) {
    char* end = nullptr;
    const long n = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || *end != '\0' || n < lo || n > hi)
        usage(flag + " needs an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '" + v + "'");
    return int(n);
}

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::size_t start = 0;
    for (std::size_t comma; (comma = s.find(',', start)) != std::string::npos; start = comma + 1)
        if (comma > start) out.push_back(s.substr(start, comma - start));
    if (start < s.size()) out.push_back(s.substr(start));
    return out;
}

Args parse(int argc, char** argv) {
    Args a;
    bool framesGiven = false, warmupGiven = false, refGiven = false, sizeGiven = false;
    std::string scenes;
    for (int i = 1; i < argc; ++i) {
        const std::string f = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) usage(f + " needs a value");
            return argv[++i];
        };
        if (f == "--scenes") scenes = next();
        else if (f == "--frames") a.cfg.frames = intArg(f, next(), 1, 100000), framesGiven = true;
        else if (f == "--warmup") a.cfg.warmup = intArg(f, next(), 0, 100000), warmupGiven = true;
        else if (f == "--ref-frames") a.cfg.refFrames = intArg(f, next(), 1, 100000), refGiven = true;
        else if (f == "--no-gl") a.cfg.draw = false;
        else if (f == "--gl-size") {
            const std::string v = next();
            int w = 0, h = 0;
            char extra = 0;
            if (std::sscanf(v.c_str(), "%dx%d%c", &w, &h, &extra) != 2 || w < 1 || h < 1 || w > 4096 || h > 4096)
                usage("--gl-size needs WxH with 1 <= W, H <= 4096, got '" + v + "'");
            a.cfg.glWidth = w;
            a.cfg.glHeight = h;
            sizeGiven = true;
        } else if (f == "--csv") a.csv = next();
        else if (f == "--plot") a.plot = next();
        else if (f == "--quick") a.cfg.quick = true;
        else if (f == "--help" || f == "-h") {
            std::printf("usage: rgvc_sweep [--scenes NAME,...] [--frames N] [--warmup W] [--ref-frames K] [--no-gl] "
                        "[--gl-size WxH] [--csv FILE] [--plot FILE.png] [--quick]\n");
            std::exit(0);
        } else usage("unknown flag '" + f + "'");
    }
    if (a.cfg.quick) {
        if (!framesGiven) a.cfg.frames = 3;
        if (!warmupGiven) a.cfg.warmup = 1;
        if (!refGiven) a.cfg.refFrames = 1;
        if (!sizeGiven) a.cfg.glWidth = 160, a.cfg.glHeight = 90;
    }
    if (scenes.empty())
        scenes = a.cfg.quick ? "city-2d,maze-2d,open-3d,city-3d"
                             : "city-2d,city-3d,clusters-3d,maze-2d,maze-3d,open-2d,open-3d,paper-walk-3d";
    for (const std::string& s : split(scenes)) {
        fs::path p(s);
        if (!fs::exists(p)) p = fs::path(RGVC_SCENES_DIR) / (s + ".json");
        if (!fs::exists(p)) usage("--scenes: no scene file '" + s + "' (nor " + p.string() + ")");
        a.scenes.push_back(p.string());
    }
    return a;
}

} // namespace

int main(int argc, char** argv) {
    const Args args = parse(argc, argv);
    const SweepConfig& cfg = args.cfg;
    const bool tty = isatty(2) != 0;
    std::unique_ptr<SweepGl> gl;
    try {
        if (cfg.draw) gl = std::make_unique<SweepGl>(cfg.glWidth, cfg.glHeight);
    } catch (const GlError& e) {
        std::fprintf(stderr, "rgvc_sweep: no GL context (%s); --no-gl runs without drawing\n", e.what());
        return 1;
    }
    std::vector<std::string> header;
    header.push_back("rgvc_sweep on " + machine() + ", one thread" + (cfg.quick ? ", --quick" : ""));
    header.push_back("frames: " + std::to_string(cfg.warmup) + " warm-up + up to " + std::to_string(cfg.frames) +
                     " measured per setting; reference on " + std::to_string(cfg.refFrames) +
                     " of them per scene (exact: tests/reference, 2D exactVisible2D, 3D visible3D at " +
                     std::to_string(kReferenceGridDivisions) + " grid / " + std::to_string(kReferenceTargetDivisions) +
                     " target divisions; GL query methods: the item buffer of all objects)");
    header.push_back(gl ? "drawing: " + gl->description() + ", " + std::to_string(cfg.glWidth) + "x" +
                              std::to_string(cfg.glHeight) + " pixels; 3D balls as 1,280-triangle icospheres; 2D shapes "
                              "as prisms seen level from the 2D camera"
                        : std::string("drawing: off (--no-gl): time_ms is the cull time"));
    header.push_back("time_ms: median frame ms with drawing (cull + GL method + glFinish), else median cull ms; "
                     "overestimation: mean |answer|/|exact visible| over checked frames with the camera outside objects");
    std::printf("%s\n", header[0].c_str());
    std::vector<SweepRow> rows;
    std::vector<std::string> notes, names;
    try {
        for (std::size_t k = 0; k < args.scenes.size(); ++k) {
            const std::string name = fs::path(args.scenes[k]).stem().string();
            names.push_back(name);
            const SweepProgress progress = [&](int si, int sn, int f, int fn, const std::string& what) {
                if (!tty) return;
                if (si == 0)
                    std::fprintf(stderr, "\r[%zu/%zu %s] reference %d/%d\033[K", k + 1, args.scenes.size(), name.c_str(),
                                 f, fn);
                else
                    std::fprintf(stderr, "\r[%zu/%zu %s] setting %d/%d %s: frame %d/%d\033[K", k + 1,
                                 args.scenes.size(), name.c_str(), si, sn, what.c_str(), f, fn);
                std::fflush(stderr);
            };
            std::vector<SweepRow> r = runSweepScene(args.scenes[k], cfg, gl.get(), progress, notes);
            rows.insert(rows.end(), r.begin(), r.end());
        }
    } catch (const SceneError& e) {
        if (tty) std::fprintf(stderr, "\n");
        std::fprintf(stderr, "rgvc_sweep: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        if (tty) std::fprintf(stderr, "\n");
        std::fprintf(stderr, "rgvc_sweep: %s\n", e.what());
        return 1;
    }
    if (tty) std::fprintf(stderr, "\r\033[K");
    markPareto(rows);
    for (const std::string& n : notes) header.push_back("scene " + n);
    for (const std::string& n : names) printSceneTable(rows, n);
    std::printf("\nbest setting per scene (front: conservative settings with 0 misses that no other beats on both "
                "time and |answer|/|visible|; time: %s):\n",
                gl ? "median frame ms with drawing" : "median cull ms");
    printBestTable(rows, names);
    std::printf("\nnotes:\n");
    for (const std::string& n : notes) std::printf("- %s\n", n.c_str());
    if (!args.csv.empty()) {
        std::ofstream out(args.csv);
        writeCsv(out, header, rows);
        if (!out) {
            std::fprintf(stderr, "rgvc_sweep: cannot write %s\n", args.csv.c_str());
            return 1;
        }
        std::printf("CSV: %s\n", args.csv.c_str());
    }
    if (!args.plot.empty()) {
        if (args.csv.empty()) usage("--plot needs --csv");
        const PlotStatus ps = runGnuplot(RGVC_SOURCE_DIR "/scripts/plot_sweep.gp", {{"csv", args.csv}, {"out", args.plot}});
        if (ps != PlotStatus::Drawn) {
            std::fprintf(stderr, "rgvc_sweep: no plot: %s\n", plotStatusText(ps));
            return 1;
        }
        std::printf("plot: %s\n", args.plot.c_str());
    }
    std::uint64_t misses = 0, approximateMisses = 0;
    for (const SweepRow& r : rows) (r.setting.approximate() ? approximateMisses : misses) += r.misses;
    std::printf("misses: %llu in conservative settings (must be 0); %llu in approximate ones (n_vp > 0, counted)\n",
                (unsigned long long)misses, (unsigned long long)approximateMisses);
    return misses == 0 ? 0 : 1;
}
