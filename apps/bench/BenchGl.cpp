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
// must be 0). The grid culler gets each ball's occluder inset to the drawn mesh (GlStage.hpp's reason).
//
//   rgvc_bench_gl [--frames N] [--size WxH] [--grid 100|50] [--static S] [--csv FILE] [--quick]
//                 [--methods zb,vfc,rgvc,rgvc+chc,chc,sw,ideal]   (default: all, in that order)
#include "BenchSupport.hpp"

#include "RandomScenes3D.hpp"
#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/render/Chc.hpp"
#include "rgvc/render/ObjectBvh.hpp"
#include "rgvc/render/gl/GlContext.hpp"
#include "rgvc/render/gl/GlQueryDevice.hpp"
#include "rgvc/render/gl/ItemBuffer.hpp"
#include "rgvc/render/gl/SceneRenderer.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
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

struct Method {
    const char* name;
    CullMethod gl;  // what the GL stage does with the candidates
    bool grid;      // candidates: the grid culler's PVS (else every object)
    bool ideal;     // candidates: the item buffer's visible set
    std::unique_ptr<Culler3D> culler;
    std::unique_ptr<ChcRenderer> chc;
    std::vector<double> ms, cullMs;
    std::vector<std::uint32_t> queries, drawn, candidates;
    std::uint64_t misses = 0;
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

double median(std::vector<double> v) { return percentile(std::move(v), 0.5); }
double mean(const std::vector<std::uint32_t>& v) {
    double s = 0;
    for (auto x : v) s += x;
    return v.empty() ? 0 : s / double(v.size());
}

} // namespace

int main(int argc, char** argv) {
    const Config cfg = parse(argc, argv);
    try {
        ref::MovingSpheres3D scene = ref::movingSpheres3D(7, cfg.spheres);
        for (int i = 0; i < cfg.statics; ++i) {
            scene.velocity[std::size_t(i)] = Vec3(0.0);
            scene.objects[std::size_t(i)].isStatic = true;
            scene.objects[std::size_t(i)].maxSpeed = 0;
        }
        auto context = createOsMesaContext(cfg.width, cfg.height);
        SceneRenderer renderer(*context);
        GlQueryDevice device(renderer, cfg.width, cfg.height);
        ObjectBvh bvh;
        std::vector<BvhItem> items;
        for (const ObjectDesc<3>& o : scene.objects) {
            renderer.setObject(o.id, o.shape);
            items.push_back({o.id, boundsOf<3>(o.shape)});
        }
        bvh.build(items);
        const GridGeometry3 grid(scene.grid.origin(), scene.grid.voxelSize() * 100.0 / cfg.gridRes,
                                 IVec3{cfg.gridRes, cfg.gridRes * 6 / 10, cfg.gridRes});

        std::vector<Method> methods;
        {
            // The combinations, chosen by --methods (each name once, in the order given).
            std::string list = cfg.methods + ",";
            for (std::size_t start = 0, comma; (comma = list.find(',', start)) != std::string::npos; start = comma + 1) {
                const std::string name = list.substr(start, comma - start);
                bool dup = false;
                for (const Method& m : methods) dup = dup || name == m.name;
                if (name.empty() || dup) continue;
                if (name == "zb") methods.push_back({"zb", CullMethod::Zb, false, false, {}, {}, {}, {}, {}, {}, {}, 0});
                else if (name == "vfc") methods.push_back({"vfc", CullMethod::Vfc, false, false, {}, {}, {}, {}, {}, {}, {}, 0});
                else if (name == "rgvc") methods.push_back({"rgvc", CullMethod::Zb, true, false, {}, {}, {}, {}, {}, {}, {}, 0});
                else if (name == "rgvc+chc")
                    methods.push_back({"rgvc+chc", CullMethod::ChcPlusPlus, true, false, {}, {}, {}, {}, {}, {}, {}, 0});
                else if (name == "chc") methods.push_back({"chc", CullMethod::ChcPlusPlus, false, false, {}, {}, {}, {}, {}, {}, {}, 0});
                else if (name == "sw") methods.push_back({"sw", CullMethod::StopAndWait, false, false, {}, {}, {}, {}, {}, {}, {}, 0});
                else if (name == "ideal") methods.push_back({"ideal", CullMethod::Ideal, false, true, {}, {}, {}, {}, {}, {}, {}, 0});
                else usage(("--methods: unknown method '" + name + "'").c_str());
            }
            if (methods.empty()) usage("--methods: no method given");
        }
        for (Method& m : methods) {
            m.chc = std::make_unique<ChcRenderer>(device, bvh, ChcOptions{.queryMinCandidates = 32});
            if (m.grid) {
                m.culler = std::make_unique<Culler3D>(grid);
                for (ObjectDesc<3> o : scene.objects) {
                    o.occluderInset = renderer.occluderInset(o.shape);
                    m.culler->addObject(o);
                }
            }
        }
        std::printf("rgvc_bench_gl on %s, one thread; %s\n", machine().c_str(), context->description().c_str());
        std::printf("scene: %d spheres (%d static, %d moving) of %zu triangles in 100x60x100 units, grid %dx%dx%d, "
                    "%dx%d pixels, %d frames of the walk\n", cfg.spheres, cfg.statics, cfg.spheres - cfg.statics,
                    SceneRendererOptions{}.sphere.indices.size() / 3, grid.resolution().x, grid.resolution().y, grid.resolution().z,
                    cfg.width, cfg.height, cfg.frames);
        const bool tty = isatty(1) != 0;
        std::vector<std::uint32_t> visibleCounts;
        for (int f = 0; f < cfg.frames; ++f) {
            if (f > 0) {
                ref::stepMovingSpheres(scene);
                for (std::size_t i = std::size_t(cfg.statics); i < scene.objects.size(); ++i) {
                    const ObjectDesc<3>& o = scene.objects[i];
                    renderer.setObject(o.id, o.shape);
                    bvh.update(o.id, boundsOf<3>(o.shape));
                    for (Method& m : methods)
                        if (m.culler) m.culler->updateObject(o.id, o.shape);
                }
                bvh.rebuildIfDegraded();
            }
            const Camera3 cam = ref::movingSpheresCamera(scene, f, cfg.frames);
            const ItemBufferImage img = itemBuffer(renderer, cam, cfg.width, cfg.height);
            visibleCounts.push_back(std::uint32_t(img.visible.size()));
            for (std::size_t k = 0; k < methods.size(); ++k) {
                Method& m = methods[(k + std::size_t(f)) % methods.size()];
                const auto t0 = std::chrono::steady_clock::now();
                double cullMs = 0;
                const ChcFrameStats* s;
                if (m.grid) {
                    const CullResult& r = m.culler->cull(cam);
                    cullMs = r.stats.cullMs;
                    m.candidates.push_back(std::uint32_t(r.pvs.size()));
                    s = &m.chc->render(cam, m.gl, r.pvs);
                } else if (m.ideal) {
                    m.candidates.push_back(std::uint32_t(img.visible.size()));
                    s = &m.chc->render(cam, m.gl, img.visible);
                } else {
                    m.candidates.push_back(std::uint32_t(scene.objects.size()));
                    s = &m.chc->renderAll(cam, m.gl);
                }
                m.ms.push_back(msSince(t0));
                m.cullMs.push_back(cullMs);
                m.queries.push_back(s->queries());
                m.drawn.push_back(s->objectsDrawn);
                std::vector<ObjectId> drawn = s->drawn;
                std::sort(drawn.begin(), drawn.end());
                for (ObjectId id : img.visible)
                    if (!std::binary_search(drawn.begin(), drawn.end(), id)) ++m.misses;
            }
            if (tty) {
                std::printf("\r  frame %d/%d", f + 1, cfg.frames);
                std::fflush(stdout);
            }
        }
        if (tty) std::printf("\n");

        double zb = 0; // the "x ZB" column needs ZB in the run
        for (const Method& m : methods)
            if (std::strcmp(m.name, "zb") == 0) zb = median(m.ms);
        double visible = mean(visibleCounts);
        std::printf("\n| method | median frame ms | p95 ms | x ZB | grid cull ms | queries/frame | drawn/frame | "
                    "drawn / visible | misses |\n|---|--:|--:|--:|--:|--:|--:|--:|--:|\n");
        for (const Method& m : methods) {
            const double med = median(m.ms);
            std::printf("| %s | %.2f | %.2f | %.1f | %.3f | %.1f | %.1f | %.2f | %llu |\n", m.name, med,
                        percentile(m.ms, 0.95), zb > 0 ? zb / med : 0.0, median(m.cullMs), mean(m.queries), mean(m.drawn),
                        visible > 0 ? mean(m.drawn) / visible : 0.0, (unsigned long long)m.misses);
        }
        std::printf("mean |visible| (item buffer at %dx%d): %.1f\n", cfg.width, cfg.height, visible);
        if (!cfg.csv.empty()) {
            std::ofstream out(cfg.csv);
            out << "# rgvc_bench_gl spheres=" << cfg.spheres << " static=" << cfg.statics << " grid=" << cfg.gridRes
                << " size=" << cfg.width << "x" << cfg.height << " frames=" << cfg.frames << "\n";
            out << "frame,method,frame_ms,cull_ms,queries,drawn,candidates,visible\n";
            for (const Method& m : methods)
                for (int f = 0; f < cfg.frames; ++f)
                    out << f << ',' << m.name << ',' << m.ms[std::size_t(f)] << ',' << m.cullMs[std::size_t(f)] << ','
                        << m.queries[std::size_t(f)] << ',' << m.drawn[std::size_t(f)] << ','
                        << m.candidates[std::size_t(f)] << ',' << visibleCounts[std::size_t(f)] << '\n';
        }
        std::uint64_t misses = 0;
        for (const Method& m : methods) misses += m.misses;
        std::printf("misses: %llu\n", (unsigned long long)misses);
        return misses == 0 ? 0 : 1;
    } catch (const GlError& e) {
        std::fprintf(stderr, "rgvc_bench_gl: %s\n", e.what());
        return 2;
    }
}
