// rgvc_bench_gl: the GL stage on the paper's walkthrough (seed 004 §6, Figure 5 (b); seed 001 §6.2's
// comparison), headless through OSMesa: frame time = cull + draw + glFinish for every method, in one run.
//
// Scene: reference::movingSpheres3D's clustered spheres in 100x60x100 units, the first `static` of them
// made static and the rest (200 by default) moving; balls drawn as icospheres of 1,280 triangles (the
// paper's ~1,200), so 5,000 spheres are 6.4 million triangles. Camera: movingSpheresCamera's walk.
// Methods (interleaved frame by frame, the order rotating, so that none always runs first):
//   zb         draw every object
//   vfc        hierarchical view-frustum culling over the object BVH
//   rgvc       the grid culler's PVS, drawn as is
//   rgvc+chc   the grid culler's PVS refined by CHC++ queries
//   chc        CHC++ over every object
//   sw         hierarchical stop-and-wait over every object
//   ideal      exactly the objects the item buffer shows (found untimed, then drawn and timed)
// Each frame also checks that every object the item buffer shows was drawn by every method (misses,
// must be 0; exit 1 otherwise). The comparison itself is GlWalk.hpp, shared with rgvc_bench3d --figure.
//
//   rgvc_bench_gl [--frames N] [--size WxH] [--grid 100|50] [--static S] [--csv FILE] [--quick]
//                 [--methods zb,vfc,rgvc,rgvc+chc,chc,sw,ideal]   (default: all, in that order)
#include "BenchSupport.hpp"
#include "GlWalk.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

using namespace rgvc;
using namespace rgvc::bench;
namespace ref = rgvc::reference;

namespace {

struct Config {
    int frames = 150, width = 640, height = 480, gridRes = 100, statics = 4800, spheres = 5000;
    std::string csv;
    std::string methods = "zb,vfc,rgvc,rgvc+chc,chc,sw,ideal"; // --methods: a comma-separated subset
};

[[noreturn]] void usage(const char* why) {
    std::fprintf(stderr, "rgvc_bench_gl: %s\nusage: rgvc_bench_gl [--frames N] [--size WxH] [--grid 100|50] "
                         "[--static S] [--csv FILE] [--quick] [--methods zb,vfc,rgvc,rgvc+chc,chc,sw,ideal]\n", why);
    std::exit(2);
}

Config parse(int argc, char** argv) {
    Config c;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) usage(("missing value after " + a).c_str());
            return argv[++i];
        };
        if (a == "--frames") c.frames = std::atoi(next().c_str());
        else if (a == "--size") {
            const std::string v = next();
            if (std::sscanf(v.c_str(), "%dx%d", &c.width, &c.height) != 2) usage("--size: WxH");
        } else if (a == "--grid") c.gridRes = std::atoi(next().c_str());
        else if (a == "--static") c.statics = std::atoi(next().c_str());
        else if (a == "--csv") c.csv = next();
        else if (a == "--methods") c.methods = next();
        else if (a == "--quick") {
            c.frames = 4;
            c.width = 160;
            c.height = 90;
            c.spheres = 500;
            c.statics = 480;
        } else usage(("unknown option " + a).c_str());
    }
    if (c.frames < 1 || c.width < 1 || c.height < 1 || c.width > 16384 || c.height > 16384) usage("bad sizes");
    if (c.gridRes != 100 && c.gridRes != 50) usage("--grid: 100 or 50");
    c.statics = std::clamp(c.statics, 0, c.spheres);
    return c;
}

} // namespace

int main(int argc, char** argv) {
    const Config cfg = parse(argc, argv);
    try {
        ref::MovingSpheres3D scene = paperWalkScene(cfg.spheres, cfg.statics);
        const GridGeometry3 grid(scene.grid.origin(), scene.grid.voxelSize() * 100.0 / cfg.gridRes,
                                 IVec3{cfg.gridRes, cfg.gridRes * 6 / 10, cfg.gridRes});
        std::vector<GlMethodSpec> specs;
        try {
            specs = parseGlMethods(cfg.methods, grid);
        } catch (const std::invalid_argument& e) {
            usage((std::string("--methods: ") + e.what()).c_str());
        }
        GlWalk walk(scene.objects, std::move(specs), {.width = cfg.width, .height = cfg.height});
        std::printf("rgvc_bench_gl on %s, one thread; %s\n", machine().c_str(), walk.context().description().c_str());
        std::printf("scene: %d spheres (%d static, %d moving) of %zu triangles in 100x60x100 units, grid %s, "
                    "%dx%d pixels, %d frames of the walk\n", cfg.spheres, cfg.statics, cfg.spheres - cfg.statics,
                    walk.renderer().sphereMesh().triangleCount(), resolutionLabel(grid).c_str(), cfg.width, cfg.height,
                    cfg.frames);
        const std::span<const ObjectDesc<3>> moving(scene.objects.data() + cfg.statics, scene.objects.size() - std::size_t(cfg.statics));
        ProgressBar progress("  walk", cfg.frames);
        for (int f = 0; f < cfg.frames; ++f) {
            if (f > 0) {
                ref::stepMovingSpheres(scene);
                walk.moveObjects(moving);
            }
            walk.frame(ref::movingSpheresCamera(scene, f, cfg.frames));
            progress.update(f + 1);
        }
        progress.finish();
        std::printf("\n");
        walk.printSummary(stdout);
        if (!cfg.csv.empty()) {
            std::ofstream out(cfg.csv);
            out << "# rgvc_bench_gl spheres=" << cfg.spheres << " static=" << cfg.statics << " grid=" << cfg.gridRes
                << " size=" << cfg.width << "x" << cfg.height << " frames=" << cfg.frames << "\n";
            out << GlWalk::csvHeader() << "\n";
            walk.writeCsvRows(out, "");
        }
        const std::uint64_t misses = walk.totalMisses();
        std::printf("misses: %llu\n", (unsigned long long)misses);
        return misses == 0 ? 0 : 1;
    } catch (const GlError& e) {
        std::fprintf(stderr, "rgvc_bench_gl: %s\n", e.what());
        return 2;
    }
}
