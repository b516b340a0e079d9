// rgvc_bench3d --figure 5a|5b|5c|6|all: seed 004 §6's Figure 5 with the GL stage (Figures3D.hpp).
//
// (a) The scene: a static wall 6 units thick (z 49-55) that spans the 100 x 60 x 100-unit world and 2
// units past its sides (so that it holds whole voxels of both grids up to the border), `visible5a`
// static spheres in front of it (z 6-46, what the camera sees) and N moving spheres behind it (z 58-98,
// radii 0.3-3, up to 0.5 unit per frame, reflected inside their box). The camera stands at (50, 30, 1)
// and turns +-12 degrees left and right over the frames, so every mover stays behind the wall: from a
// camera and a mover inside the world box, the segment between them crosses the wall's slab inside the
// world. The program checks that: the item buffer must show no mover (exit 1 otherwise). The paper's
// claim (§6, Figure 5 left): RGVC's time depends on what is visible, not on the hidden movers (their
// TBVs make a hidden mover's update O(1) and the traversal stops at the wall), ZB's grows linearly.
//
// (b), (c) The walkthrough (rgvc_bench_gl's scene, GlWalk.hpp's paperWalkScene): one run, every method
// interleaved frame by frame, RGVC and RGVC + CHC++ at both grid resolutions.
#include "Figures3D.hpp"

#include "BenchSupport.hpp"
#include "GlWalk.hpp"

#include "RandomScenes3D.hpp"
#include "rgvc/render/gl/Meshes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#ifndef RGVC_SOURCE_DIR
#define RGVC_SOURCE_DIR "."
#endif

namespace rgvc::bench {
namespace ref = rgvc::reference;

namespace {

[[noreturn]] void usage(const std::string& why, int status = 2) {
    std::fprintf(status == 0 ? stdout : stderr,
                 "rgvc_bench3d: %s\nusage: rgvc_bench3d --figure 5a|5b|5c|6|all[,...] [--quick] [--out DIR] [--size WxH]\n"
                 "       [--hidden N,N,...] [--frames-5a N] [--warmup-5a N] [--level-5a L] [--lod-level L] [--lod-above N]\n"
                 "       [--visible-5a N]"
                 " [--walk-frames N] [--spheres N] [--static S] [--fig6-grid 50|100] [--no-plots] [--gnuplot-script F]\n",
                 why.c_str());
    std::exit(status);
}

int toInt(const std::string& flag, const std::string& v, int lo, int hi) {
    char* end = nullptr;
    const long x = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || *end != 0 || x < lo || x > hi)
        usage(flag + " needs an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '" + v + "'");
    return int(x);
}

std::vector<std::string> splitCommas(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream in(s);
    for (std::string item; std::getline(in, item, ',');)
        if (!item.empty()) out.push_back(item);
    return out;
}

GridGeometry3 worldGrid(int res) { return GridGeometry3(Vec3(0.0), 100.0 / res, IVec3{res, res * 6 / 10, res}); }

bool writeFailed(const std::ofstream& out, const std::string& path) {
    if (out) return false;
    std::fprintf(stderr, "rgvc_bench3d: cannot write %s\n", path.c_str());
    return true;
}

// ---- (a) ----

struct HiddenMoversScene {
    std::vector<ObjectDesc<3>> objects; ///< the wall, the visible statics, the movers (ids in that order)
    ref::MovingSpheres3D movers;        ///< the movers' motion; their ids as in `objects`
    ObjectId firstMover = 0;
};

HiddenMoversScene hiddenMoversScene(int visible, int hidden) {
    HiddenMoversScene s;
    ObjectId next = 1;
    ObjectDesc<3> wall;
    wall.id = next++;
    wall.shape = Box<3>{{-2, -2, 49}, {102, 62, 55}};
    wall.isStatic = true;
    s.objects.push_back(wall);
    for (ObjectDesc<3> o : ref::movingSpheres3D(11, visible, {100, 60, 40}).objects) {
        o.id = next++;
        o.shape = translated<3>(o.shape, Vec3{0, 0, 6});
        o.isStatic = true;
        o.maxSpeed = 0;
        s.objects.push_back(o);
    }
    // The movers' box is the generator's grid moved behind the wall (stepMovingSpheres reflects at it).
    const Vec3 shift{0, 0, 58};
    s.movers = ref::movingSpheres3D(13, hidden, {100, 60, 40});
    s.movers.grid = GridGeometry3(shift, 1.0, {100, 60, 40});
    s.firstMover = next;
    for (std::size_t i = 0; i < s.movers.objects.size(); ++i) {
        s.movers.frame0[i] = translated<3>(s.movers.frame0[i], shift);
        ObjectDesc<3>& o = s.movers.objects[i];
        o.shape = translated<3>(o.shape, shift);
        o.id = next++;
        s.objects.push_back(o);
    }
    return s;
}

Camera3 hiddenMoversCamera(int frame, int frames, double aspect) {
    const double yaw = 0.21 * std::sin(6.283185307179586 * frame / std::max(frames, 1)); // +-12 degrees
    Camera3 cam;
    cam.position = {50, 30, 1};
    cam.direction = {std::sin(yaw), -0.03, std::cos(yaw)};
    cam.fovDeg = 60;
    cam.aspect = aspect;
    return cam;
}

struct Fig5aPoint {
    int hidden = 0;
    std::size_t triangles = 0;
    std::vector<std::string> names;
    std::vector<double> median, p95, drawn;
    double visible = 0;
};

/// Runs (a); appends rows to fig5a.csv; returns false on a miss or a visible mover.
bool runFigure5a(const FigureConfig& c, std::vector<Fig5aPoint>& points) {
    const std::string path = c.out + "/fig5a.csv";
    std::ofstream csv(path);
    csv << "# rgvc_bench3d --figure 5a: frame time against hidden moving spheres; wall z 49-55 spanning the "
           "100x60x100 world, "
        << c.visible5a << " visible static spheres, camera (50,30,1) turning +-12 deg, size " << c.width << "x" << c.height
        << ", " << c.frames5a << " frames per point after " << c.warmup5a << " warm-up frames (the first hides the movers, the second makes "
           "their TBVs), icospheres of "
        << icosphere(c.level5a).triangleCount() << " triangles (" << icosphere(c.lodLevel5a).triangleCount() << " above "
        << c.lodAbove5a << " movers); " << machine() << "\n";
    csv << "hidden,triangles_per_sphere," << GlWalk::csvHeader() << "\n";
    if (writeFailed(csv, path)) return false;
    bool ok = true;
    const int framesPerPoint = c.frames5a + c.warmup5a;
    ProgressBar progress("  figure 5a", long(c.hidden5a.size()) * framesPerPoint);
    long done = 0;
    for (int n : c.hidden5a) {
        HiddenMoversScene scene = hiddenMoversScene(c.visible5a, n);
        GlWalkOptions opt{.width = c.width, .height = c.height};
        opt.renderer.sphere = icosphere(n > c.lodAbove5a ? c.lodLevel5a : c.level5a);
        std::vector<GlMethodSpec> methods = {glMethod("zb", worldGrid(100)), glMethod("vfc", worldGrid(100)),
                                             glMethod("rgvc", worldGrid(50), "rgvc-50x30x50"),
                                             glMethod("rgvc", worldGrid(100), "rgvc-100x60x100")};
        GlWalk walk(scene.objects, std::move(methods), opt);
        std::uint64_t moversSeen = 0;
        for (int f = 0; f < framesPerPoint; ++f) {
            if (f > 0) {
                ref::stepMovingSpheres(scene.movers);
                walk.moveObjects(scene.movers.objects);
            }
            walk.frame(hiddenMoversCamera(f, framesPerPoint, double(c.width) / c.height));
            for (ObjectId id : walk.lastVisible()) moversSeen += id >= scene.firstMover;
            if (f + 1 == c.warmup5a) walk.clearRecords();
            progress.update(++done, "hidden " + std::to_string(n));
        }
        Fig5aPoint p;
        p.hidden = n;
        p.triangles = opt.renderer.sphere.triangleCount();
        double vis = 0;
        for (auto v : walk.visibleCounts()) vis += v;
        p.visible = vis / std::max(1, walk.frames());
        for (const GlMethodRecord& m : walk.methods()) {
            p.names.push_back(m.spec.name);
            p.median.push_back(percentile(m.ms, 0.5));
            p.p95.push_back(percentile(m.ms, 0.95));
            double d = 0;
            for (auto x : m.drawn) d += x;
            p.drawn.push_back(d / std::max<std::size_t>(1, m.drawn.size()));
        }
        points.push_back(p);
        walk.writeCsvRows(csv, std::to_string(n) + "," + std::to_string(p.triangles) + ",");
        if (walk.totalMisses() > 0 || moversSeen > 0) {
            progress.finish();
            std::printf("FAIL: %d hidden movers: %llu misses, %llu mover sightings in the item buffer (must be 0)\n", n,
                        (unsigned long long)walk.totalMisses(), (unsigned long long)moversSeen);
            ok = false;
        }
    }
    progress.finish();
    if (writeFailed(csv, path)) return false;

    // The per-point medians, what the plot draws.
    const std::string mpath = c.out + "/fig5a-median.csv";
    std::ofstream med(mpath);
    med << "# medians of fig5a.csv per point and method\nhidden,method,median_ms,p95_ms,triangles_per_sphere,mean_drawn,"
           "mean_visible\n";
    if (!points.empty())
        for (std::size_t k = 0; k < points[0].names.size(); ++k)
            for (const Fig5aPoint& p : points)
                med << p.hidden << ',' << p.names[k] << ',' << p.median[k] << ',' << p.p95[k] << ',' << p.triangles << ','
                    << p.drawn[k] << ',' << p.visible << '\n';
    if (writeFailed(med, mpath)) return false;

    std::printf("\nFigure 5a: median frame ms (cull + draw + glFinish) against hidden moving spheres\n\n"
                "| hidden movers | triangles / sphere |");
    for (const std::string& name : points.front().names) std::printf(" %s |", name.c_str());
    std::printf(" RGVC 100 FPS | ZB / RGVC 100 | mean visible |\n|--:|--:|");
    for (std::size_t k = 0; k < points.front().names.size(); ++k) std::printf("--:|");
    std::printf("--:|--:|--:|\n");
    for (const Fig5aPoint& p : points) {
        std::printf("| %d | %zu |", p.hidden, p.triangles);
        for (double m : p.median) std::printf(" %.2f |", m);
        std::printf(" %.0f | %.1f | %.1f |\n", 1000.0 / p.median[3], p.median[0] / p.median[3], p.visible);
    }
    return ok;
}

// ---- (b), (c) ----

std::vector<std::string> walkMethodNames() {
    return {"zb", "vfc", "rgvc-50x30x50", "rgvc-100x60x100", "rgvc+chc-50x30x50", "rgvc+chc-100x60x100", "chc", "ideal"};
}

bool runWalk(const FigureConfig& c) {
    ref::MovingSpheres3D scene = paperWalkScene(c.spheres, c.statics);
    std::vector<GlMethodSpec> methods = {glMethod("zb", worldGrid(100)), glMethod("vfc", worldGrid(100))};
    for (const char* name : {"rgvc", "rgvc+chc"})
        for (int res : {50, 100}) methods.push_back(glMethod(name, worldGrid(res), std::string(name) + "-" + resolutionLabel(worldGrid(res))));
    // zb, vfc, rgvc-50, rgvc-100, rgvc+chc-50, rgvc+chc-100, chc, ideal: walkMethodNames()'s order.
    methods.push_back(glMethod("chc", worldGrid(100)));
    methods.push_back(glMethod("ideal", worldGrid(100)));
    GlWalk walk(scene.objects, std::move(methods), {.width = c.width, .height = c.height});
    std::printf("\nFigures 5b, 5c: the walk, %d spheres (%d static, %d moving) of %zu triangles, %d frames, %dx%d; %s\n",
                c.spheres, c.statics, c.spheres - c.statics, walk.renderer().sphereMesh().triangleCount(), c.walkFrames,
                c.width, c.height, walk.context().description().c_str());
    const std::span<const ObjectDesc<3>> moving(scene.objects.data() + c.statics, scene.objects.size() - std::size_t(c.statics));
    ProgressBar progress("  walk", c.walkFrames);
    for (int f = 0; f < c.walkFrames; ++f) {
        if (f > 0) {
            ref::stepMovingSpheres(scene);
            walk.moveObjects(moving);
        }
        walk.frame(ref::movingSpheresCamera(scene, f, c.walkFrames));
        progress.update(f + 1);
    }
    progress.finish();
    const std::string path = c.out + "/fig5bc.csv";
    std::ofstream csv(path);
    csv << "# rgvc_bench3d --figure 5b,5c: the paper's walkthrough, " << c.spheres << " spheres (" << c.statics
        << " static) of " << walk.renderer().sphereMesh().triangleCount() << " triangles in 100x60x100 units, "
        << c.walkFrames << " frames, size " << c.width << "x" << c.height << ", methods interleaved; " << machine() << "\n";
    csv << "# |PVS| per frame: candidates for rgvc-*, drawn for rgvc+chc-* and vfc; visible: the item buffer's count\n";
    csv << GlWalk::csvHeader() << "\n";
    walk.writeCsvRows(csv, "");
    if (writeFailed(csv, path)) return false;
    std::printf("\nSummary of the walk (frame time = cull + draw + glFinish):\n\n");
    walk.printSummary(stdout);
    std::printf("misses: %llu\n", (unsigned long long)walk.totalMisses());
    return walk.totalMisses() == 0;
}

std::string joined(const std::vector<std::string>& v) {
    std::string s;
    for (const std::string& x : v) s += (s.empty() ? "" : " ") + x;
    return s;
}

/// Runs gnuplot on the CSVs; a missing gnuplot is a message, not a failure.
void runPlots(const FigureConfig& c) {
    if (!c.plots) return;
    const std::string script = c.gnuplotScript.empty() ? std::string(RGVC_SOURCE_DIR) + "/scripts/plot_fig5.gp" : c.gnuplotScript;
    const PlotStatus ps = runGnuplot(script, {{"dir", c.out}, {"m5a", "zb vfc rgvc-50x30x50 rgvc-100x60x100"}, {"mwalk", joined(walkMethodNames())}});
    if (ps != PlotStatus::Drawn) std::printf("plots skipped: %s; the CSVs are in %s\n", plotStatusText(ps), c.out.c_str());
    else std::printf("plots: %s/fig5a.png, fig5b.png, fig5c.png (where their CSVs exist)\n", c.out.c_str());
}

} // namespace

FigureConfig parseFigureConfig(int argc, char** argv) {
    FigureConfig c;
    for (int i = 1; i < argc; ++i)
        if (std::string(argv[i]) == "--quick") {
            c.quick = true;
            c.width = 160;
            c.height = 90;
            c.hidden5a = {0, 200, 1000};
            c.frames5a = 2;
            c.warmup5a = 2;
            c.visible5a = 60;
            c.walkFrames = 4;
            c.spheres = 500;
            c.statics = 480;
        }
    std::string figures = "all";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) usage("missing value after " + a);
            return argv[++i];
        };
        if (a == "--figure") figures = next();
        else if (a == "--quick") continue;
        else if (a == "--help" || a == "-h") usage("the paper's Figures 5 and 6 with the GL stage", 0);
        else if (a == "--out") c.out = next();
        else if (a == "--size") {
            const std::string v = next();
            if (std::sscanf(v.c_str(), "%dx%d", &c.width, &c.height) != 2 || c.width < 1 || c.height < 1 || c.width > 16384 ||
                c.height > 16384)
                usage("--size needs WxH, 1..16384 each");
        } else if (a == "--hidden") {
            c.hidden5a.clear();
            for (const std::string& v : splitCommas(next())) c.hidden5a.push_back(toInt("--hidden", v, 0, 2000000));
            if (c.hidden5a.empty()) usage("--hidden needs a list of counts");
        } else if (a == "--frames-5a") c.frames5a = toInt(a, next(), 1, 100000);
        else if (a == "--warmup-5a") c.warmup5a = toInt(a, next(), 0, 100000);
        else if (a == "--lod-above") c.lodAbove5a = toInt(a, next(), 0, 2000000);
        else if (a == "--level-5a") c.level5a = toInt(a, next(), 0, 5);
        else if (a == "--lod-level") c.lodLevel5a = toInt(a, next(), 0, 5);
        else if (a == "--visible-5a") c.visible5a = toInt(a, next(), 0, 100000);
        else if (a == "--walk-frames") c.walkFrames = toInt(a, next(), 1, 100000);
        else if (a == "--spheres") c.spheres = toInt(a, next(), 1, 2000000);
        else if (a == "--static") c.statics = toInt(a, next(), 0, 2000000);
        else if (a == "--fig6-grid") {
            c.fig6Grid = toInt(a, next(), 50, 100);
            if (c.fig6Grid != 50 && c.fig6Grid != 100) usage("--fig6-grid: 50 or 100");
        } else if (a == "--no-plots") c.plots = false;
        else if (a == "--gnuplot-script") c.gnuplotScript = next();
        else usage("unknown option " + a);
    }
    for (const std::string& f : splitCommas(figures)) {
        if (f == "all") c.fig5a = c.fig5b = c.fig5c = c.fig6 = true;
        else if (f == "5a") c.fig5a = true;
        else if (f == "5b") c.fig5b = true;
        else if (f == "5c") c.fig5c = true;
        else if (f == "6") c.fig6 = true;
        else usage("--figure: unknown figure '" + f + "' (5a, 5b, 5c, 6, all)");
    }
    if (!(c.fig5a || c.fig5b || c.fig5c || c.fig6)) usage("--figure: no figure given");
    c.statics = std::min(c.statics, c.spheres);
    return c;
}

int runFigures(const FigureConfig& c) {
    try {
        std::filesystem::create_directories(c.out);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rgvc_bench3d: cannot make %s: %s\n", c.out.c_str(), e.what());
        return 2;
    }
    std::printf("rgvc_bench3d --figure on %s, one thread (llvmpipe threads aside)%s; output in %s\n", machine().c_str(),
                c.quick ? ", quick" : "", c.out.c_str());
    bool ok = true;
    try {
        std::vector<Fig5aPoint> points;
        if (c.fig5a) ok = runFigure5a(c, points) && ok;
        if (c.fig5b || c.fig5c) ok = runWalk(c) && ok;
        if (c.fig6) {
            // The paper's per-voxel shell traversal with caps on every frame: it records H voxel by voxel,
            // where the default brick tree skips hidden bricks without marking their voxels.
            auto shellMethod = [](const GridGeometry3& g, const std::string& name) {
                GlMethodSpec spec = glMethod("rgvc", g, name);
                spec.culler.hierarchical = false;
                spec.culler.adaptiveCaps = false;
                return spec;
            };
            {
                // The paper's scene at the walk's first frame, culled once on the Figure 6 grid.
                ref::MovingSpheres3D scene = paperWalkScene(c.spheres, c.statics);
                const GridGeometry3 g = worldGrid(c.fig6Grid);
                const std::string name = "rgvc-" + resolutionLabel(g);
                GlWalk walk(scene.objects, {shellMethod(g, name)}, {.width = c.width, .height = c.height});
                const Camera3 cam = ref::movingSpheresCamera(scene, 0, c.walkFrames);
                walk.frame(cam);
                const std::string path = c.out + "/fig6.png";
                writeFigure6(walk, name, cam, "walk, " + std::to_string(c.spheres) + " spheres, grid " + resolutionLabel(g), path);
                std::printf("\nFigure 6: %s (misses %llu)\n", path.c_str(), (unsigned long long)walk.totalMisses());
                ok = ok && walk.totalMisses() == 0;
            }
            {
                // Figure 5a's scene, where the grid's occlusion shows: the wall's voxels and the hidden half.
                const int movers = c.quick ? 200 : 2000;
                HiddenMoversScene scene = hiddenMoversScene(c.visible5a, movers);
                const GridGeometry3 g = worldGrid(50);
                const std::string name = "rgvc-" + resolutionLabel(g);
                GlWalk walk(scene.objects, {shellMethod(g, name)}, {.width = c.width, .height = c.height});
                const Camera3 cam = hiddenMoversCamera(0, 1, double(c.width) / c.height);
                walk.frame(cam);
                const std::string path = c.out + "/fig6-wall.png";
                writeFigure6(walk, name, cam, "figure 5a's wall, " + std::to_string(movers) + " hidden movers, grid " +
                             resolutionLabel(g), path);
                std::printf("Figure 6, the wall scene: %s (misses %llu)\n", path.c_str(), (unsigned long long)walk.totalMisses());
                ok = ok && walk.totalMisses() == 0;
            }
        }
    } catch (const GlError& e) {
        std::fprintf(stderr, "rgvc_bench3d: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) { // bad input (InvalidInput), a PNG that cannot be written
        std::fprintf(stderr, "rgvc_bench3d: %s\n", e.what());
        return 2;
    }
    runPlots(c);
    std::printf("%s\n", ok ? "misses: 0" : "FAILED: misses or visible movers (see above)");
    return ok ? 0 : 1;
}

} // namespace rgvc::bench
