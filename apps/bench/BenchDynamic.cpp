// rgvc_bench_dynamic: dynamic scenes with temporal bounding volumes (issue #4's benchmark, issue #5's soak).
//
// The application owns the motion, as in a game: every moving object is a ball whose centre is a closed
// formula of the frame number (p0 + v * t, folded back by reflection at the walls of its zone, so its
// speed never exceeds |v| = maxSpeed), and the placement query of Culler::cull(camera, placementOf)
// evaluates that formula only for the ids the culler asks for. Hidden objects are never moved by the
// application: their cost is whatever the culler spends on them.
//
// hidden2d / hidden3d: per-frame culling time as the number of hidden moving objects grows (--counts,
// default 1,000, 10,000, 100,000) at a fixed visible set. A camera drifting slowly (< 1 voxel per frame)
// and turning a little looks at 100 moving balls in front of a static wall (boxes, isStatic) that spans
// the whole grid, so every ball behind it (radius 0.5..1, speed 0.02..0.1 voxel/frame, reflecting inside
// its zone) is hidden from every camera position in front of it. 2D: 1024x1024 voxels, wall at
// y 400..408, hidden zone y >= 420. 3D: 256x128x256 voxels, wall at z 96..100, hidden zone z >= 108.
// Three cullers see the same frames, interleaved frame by frame: TBVs with boundary discretization (the
// defaults, plus objectsStayInGrid: the zones are inside the grid), the --second variant (TBVs filled,
// 3D shells, or boundary TBVs without objectsStayInGrid), and the baseline temporalBoundingVolumes = false
// (every moving object re-placed every frame through the same query). Per hidden count and variant: median and p90 of CullStats::cullMs
// (wall time, placement queries and T updates included) and of this thread's CPU time for the same call,
// mean |PVS|, placement queries, TBVs created / renewed / revealed and grid writes per frame, and the
// ratio median(largest count) / median(smallest count), the target being < 2x. The first
// --warmup frames (default 50) are left out: frame 0 tracks every object and hides them all at once.
// On --check-frames frames of the first repeat every PVS is compared with the exact reference
// (reference::exactVisible2D / visible3D at 128 grid and 8 target divisions, as in rgvc_bench3d); it gets
// the objects touching the view region (fov <= 180 makes the region convex, so no other object can
// block a segment inside it), with the hidden zone split into chunks: leaving blockers out can only make
// the reference see more, so a chunked check may report a false miss but never hide a real one.
//
// soak: 2,000 moving balls of mixed speeds (0.01..1.5 voxel/frame) and 30 static walls in a 256x256
// grid, a camera walking a Lissajous path (< 0.4 voxel/frame) while turning, teleported every 5,000 frames,
// and --churn objects (default 20) removed and as many added under fresh ids every 1,000 frames, for
// --soak-frames frames (default 100,000). Every frame: bookkeeping (tracked + hidden + static + parked =
// objectCount), no speed violation, the placement query asked at most once per object and never for a
// static one, the PVS sorted. Every 1,000 frames: the process RSS (after malloc_trim, so that memory
// the allocator merely caches does not count). Every 10,000 frames and on every teleport's frame:
// misses against reference::exactVisible2D (a miss writes the scene to /tmp as a scene file).
// The exit status is 1 on any miss, invariant failure or RSS growth over 4 MiB after frame 1,000.
//
//   rgvc_bench_dynamic [--scenario hidden2d|hidden3d|soak|all] [--frames N] [--repeats R] [--seed S]
//                      [--counts 1000,10000,100000] [--warmup N] [--check-frames K] [--tbv-max-growth G]
//                      [--second filled|shell|unconfined]   (the second TBV variant: filled regions, (3D) per-voxel
//                      shells, or boundary TBVs without CullerOptions::objectsStayInGrid)
//                      [--soak-frames N] [--churn C]
// --frames sets the frames of the hidden scenarios (default 300 in 2D, 150 in 3D), or of the soak when it
// runs alone.
#include "rgvc/dynamics/Culler.hpp"

#include "BenchSupport.hpp"

#include "ExactVisibility2D.hpp"
#include "ExactVisibility3D.hpp"
#include "RandomScenes2D.hpp"
#include "SeededRandom.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <malloc.h>
#include <time.h>

using namespace rgvc;
namespace ref = rgvc::reference;
using namespace rgvc::bench;
namespace sr = rgvc::reference::seeded;

namespace {

unsigned long long U(std::uint64_t v) { return v; } // for %llu

/// x folded into [lo, hi] by reflection at both ends (a triangle wave): moving p0 + v * t through it
/// keeps the speed |v| and needs no state, so any frame's position costs the same.
double fold(double x, double lo, double hi) {
    const double span = hi - lo;
    if (!(span > 0)) return lo;
    double m = std::fmod(x - lo, 2 * span);
    if (m < 0) m += 2 * span;
    return lo + (m <= span ? m : 2 * span - m);
}

/// A ball moving in closed form inside the box [lo, hi] of centres.
template <int D> struct Mover {
    Vec<D> p0{0.0}, v{0.0}, lo{0.0}, hi{0.0};
    double radius = 1;
};

template <int D> Vec<D> centreAt(const Mover<D>& m, int frame) {
    Vec<D> c;
    for (int a = 0; a < D; ++a) c[a] = fold(m.p0[a] + m.v[a] * double(frame), m.lo[a], m.hi[a]);
    return c;
}

/// Objects indexed by id. zone: 0 static, 1 visible zone, 2 hidden zone (or, in the soak, anywhere).
template <int D> struct DynScene {
    GridGeometry<D> grid;
    std::vector<ObjectDesc<D>> objects; ///< statics hold their shape; movers their placement at frame 0
    std::vector<Mover<D>> movers;
    std::vector<std::uint8_t> zone, alive;
    std::size_t statics = 0, live = 0;

    ObjectId add(const ObjectDesc<D>& o, const Mover<D>& m, std::uint8_t z) {
        objects.push_back(o);
        objects.back().id = objects.size() - 1;
        movers.push_back(m);
        zone.push_back(z);
        alive.push_back(1);
        statics += o.isStatic;
        ++live;
        return objects.back().id;
    }
    void addStatic(const Shape<D>& s) { add({.shape = s, .isStatic = true}, {}, 0); }
    Shape<D> shapeAt(ObjectId id, int frame) const {
        if (objects[id].isStatic) return objects[id].shape;
        return Ball<D>{centreAt(movers[id], frame), movers[id].radius};
    }
};

/// A mover with its centre zone [lo + r, hi - r], a random start, direction and speed. maxSpeed gets a
/// hair over |v|: fmod's rounding must not turn into speed violations.
template <int D> ObjectDesc<D> randomMover(std::mt19937_64& rng, Vec<D> lo, Vec<D> hi, double r0, double r1, double s0,
                                           double s1, Mover<D>& m) {
    m.radius = sr::uniform(rng, r0, r1);
    m.lo = lo + m.radius;
    m.hi = hi - m.radius;
    for (int a = 0; a < D; ++a) m.p0[a] = sr::uniform(rng, m.lo[a], m.hi[a]);
    const double speed = sr::uniform(rng, s0, s1), phi = sr::uniform(rng, 0, 2 * M_PI);
    if constexpr (D == 2) {
        m.v = Vec2{std::cos(phi), std::sin(phi)} * speed;
    } else {
        const double z = sr::uniform(rng, -1, 1), s = std::sqrt(1 - z * z);
        m.v = Vec3{s * std::cos(phi), s * std::sin(phi), z} * speed;
    }
    return {.shape = Ball<D>{m.p0, m.radius}, .maxSpeed = speed * (1 + 1e-9) + 1e-12};
}

constexpr int kVisibleMovers = 100;

DynScene<2> hiddenScene2D(int hidden, std::uint64_t seed) {
    DynScene<2> s{GridGeometry2({0, 0}, 1.0, {1024, 1024}), {}, {}, {}, {}, 0, 0};
    std::mt19937_64 rng(seed); // visible movers drawn first: the same visible set for every hidden count
    for (int i = 0; i < 16; ++i) s.addStatic(Box<2>{{64.0 * i, 400}, {64.0 * (i + 1), 408}});
    Mover<2> m;
    for (int i = 0; i < kVisibleMovers; ++i) s.add(randomMover<2>(rng, {400, 180}, {624, 380}, 1, 2, 0.1, 0.4, m), m, 1);
    for (int i = 0; i < hidden; ++i) s.add(randomMover<2>(rng, {1, 420}, {1023, 1023}, 0.5, 1, 0.02, 0.1, m), m, 2);
    return s;
}

/// Drifts around (512, 120) at < 0.2 voxel/frame, looking along +y, turning +-10 degrees.
Camera2 hiddenCamera2D(int f) {
    const double a = M_PI / 2 + 10 * M_PI / 180 * std::sin(2 * M_PI * f / 900);
    return {.position = {512 + 40 * std::sin(2 * M_PI * f / 2000), 120 + 15 * std::sin(2 * M_PI * f / 1300)},
            .direction = {std::cos(a), std::sin(a)},
            .fovDeg = 90};
}

DynScene<3> hiddenScene3D(int hidden, std::uint64_t seed) {
    DynScene<3> s{GridGeometry3({0, 0, 0}, 1.0, {256, 128, 256}), {}, {}, {}, {}, 0, 0};
    std::mt19937_64 rng(seed);
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 4; ++j) s.addStatic(Box<3>{{32.0 * i, 32.0 * j, 96}, {32.0 * (i + 1), 32.0 * (j + 1), 100}});
    Mover<3> m;
    for (int i = 0; i < kVisibleMovers; ++i)
        s.add(randomMover<3>(rng, {88, 40, 40}, {168, 88, 90}, 1, 2, 0.1, 0.4, m), m, 1);
    for (int i = 0; i < hidden; ++i)
        s.add(randomMover<3>(rng, {1, 1, 108}, {255, 127, 255}, 0.5, 1, 0.02, 0.1, m), m, 2);
    return s;
}

/// Drifts around (128, 64, 20) at < 0.1 voxel/frame, looking along +z, turning +-6 degrees (yaw), +-4 (pitch).
Camera3 hiddenCamera3D(int f) {
    const double yaw = 6 * M_PI / 180 * std::sin(2 * M_PI * f / 1100);
    const double pitch = 4 * M_PI / 180 * std::sin(2 * M_PI * f / 1500);
    return {.position = {128 + 20 * std::sin(2 * M_PI * f / 2400), 64 + 6 * std::sin(2 * M_PI * f / 1700),
                         20 + 8 * std::sin(2 * M_PI * f / 3000)},
            .direction = {std::sin(yaw) * std::cos(pitch), std::sin(pitch), std::cos(yaw) * std::cos(pitch)},
            .fovDeg = 60,
            .aspect = 16.0 / 9.0};
}

std::vector<bool> referenceVisible(const std::vector<Shape<2>>& s, const Camera2& c) { return ref::exactVisible2D(s, c); }
std::vector<bool> referenceVisible(const std::vector<Shape<3>>& s, const Camera3& c) {
    ref::Visibility3DOptions o;
    o.gridDivisions = 128; // as rgvc_bench3d: a third of the defaults' cost, the same sets there
    o.targetDivisions = 8;
    return ref::visible3D(s, c, o);
}
std::vector<bool> inView(const std::vector<Shape<2>>& s, const Camera2& c) { return ref::inViewRegion2D(s, c); }
std::vector<bool> inView(const std::vector<Shape<3>>& s, const Camera3& c) { return ref::inViewRegion3D(s, c); }

/// Per id (index), whether the reference sees it at `frame` (see the file comment for the chunking).
template <int D> std::vector<bool> referenceAt(const DynScene<D>& s, int frame, const Camera<D>& cam, std::size_t chunk,
                                               std::size_t& inViewCount) {
    std::vector<Shape<D>> shapes;
    std::vector<std::size_t> ids;
    for (std::size_t i = 0; i < s.objects.size(); ++i)
        if (s.alive[i]) {
            shapes.push_back(s.shapeAt(i, frame));
            ids.push_back(i);
        }
    const std::vector<bool> view = inView(shapes, cam);
    std::vector<std::size_t> core, rest; // indices into shapes
    for (std::size_t k = 0; k < shapes.size(); ++k)
        if (view[k]) (s.zone[ids[k]] == 2 ? rest : core).push_back(k);
    inViewCount = core.size() + rest.size();
    std::vector<bool> out(s.objects.size(), false);
    for (std::size_t start = 0; start == 0 || start < rest.size(); start += chunk) {
        std::vector<std::size_t> pick = core;
        for (std::size_t k = start; k < std::min(rest.size(), start + chunk); ++k) pick.push_back(rest[k]);
        std::vector<Shape<D>> sub;
        for (std::size_t k : pick) sub.push_back(shapes[k]);
        const std::vector<bool> vis = referenceVisible(sub, cam);
        for (std::size_t k = start == 0 ? 0 : core.size(); k < pick.size(); ++k) out[ids[pick[k]]] = vis[k];
    }
    return out;
}

/// Checks the placement query's contract (at most once per object per cull, never a static or unknown
/// object) and counts the calls, to compare with CullStats::placementQueries.
struct QueryLog {
    std::vector<std::int32_t> askedAt; // per id: the last frame it was asked
    std::uint32_t calls = 0;           // this frame
    std::uint64_t violations = 0;
};

template <int D> PlacementQuery<D> makeQuery(const DynScene<D>& s, const int& frame, QueryLog& log) {
    return [&s, &frame, &log](ObjectId id) -> Shape<D> {
        ++log.calls;
        if (id >= s.objects.size() || !s.alive[id] || s.objects[id].isStatic || log.askedAt[id] == frame) {
            if (log.violations++ < 5)
                std::printf("QUERY CONTRACT: object %llu asked at frame %d (static, unknown or asked twice)\n",
                            U(id), frame);
            if (id >= s.objects.size()) throw std::out_of_range("unknown id");
        }
        log.askedAt[id] = frame;
        return s.shapeAt(id, frame);
    };
}

/// Everything one culler's frames add up to.
struct Tally {
    std::vector<double> ms, cpu;
    double pvs = 0, queries = 0, created = 0, renewed = 0, revealed = 0, hidden = 0, writes = 0, refused = 0, visited = 0;
    std::uint64_t frames = 0, badFrames = 0, speedViolations = 0, misses = 0, jumps = 0, revealedByJump = 0;
    void add(const CullStats& s, double cpuMs) {
        if (frames < ms.size()) { // pre-sized (the soak: its pages must not count as RSS growth)
            ms[frames] = s.cullMs;
            cpu[frames] = cpuMs;
        } else {
            ms.push_back(s.cullMs);
            cpu.push_back(cpuMs);
        }
        pvs += s.pvsSize;
        queries += s.placementQueries;
        created += s.tbvsCreated;
        renewed += s.tbvsRenewed;
        revealed += s.tbvsRevealed;
        hidden += s.hiddenObjects;
        writes += double(s.gridWrites);
        visited += double(s.voxelsVisited);
        refused += s.tbvsRefused;
        jumps += s.cameraJump;
        revealedByJump += s.tbvsRevealedByJump;
        speedViolations += s.speedViolations;
        ++frames;
    }
};

/// cull(camera, query) with the query's frame log reset; an exception is reported and the frame's result kept.
template <int D> const CullResult& cullFrame(Culler<D>& c, const Camera<D>& cam, const PlacementQuery<D>& q, QueryLog& log,
                                             const char* what, int frame, std::uint64_t& failures) {
    log.calls = 0;
    try {
        return c.cull(cam, q);
    } catch (const std::exception& e) {
        if (failures++ < 10) std::printf("EXCEPTION (%s, frame %d): %s\n", what, frame, e.what());
        return c.lastResult();
    }
}

/// The per-frame invariants; prints the first failures. Returns false on a failure.
template <int D> bool checkFrame(const DynScene<D>& s, const CullResult& r, const QueryLog& log, bool tbvs,
                                 const char* what, int frame, std::uint64_t& failures) {
    const CullStats& st = r.stats;
    std::string why;
    using std::to_string;
    if (std::size_t(st.trackedObjects) + st.hiddenObjects + s.statics + st.parkedObjects != s.live || st.objectCount != s.live)
        why += " bookkeeping: tracked " + to_string(st.trackedObjects) + " + hidden " + to_string(st.hiddenObjects) +
               " + static " + to_string(s.statics) + " + parked " + to_string(st.parkedObjects) + " != objects " +
               to_string(s.live) + " (objectCount " + to_string(st.objectCount) + ");";
    if (st.speedViolations) why += " speedViolations " + to_string(st.speedViolations) + ";";
    if (st.placementQueries != log.calls)
        why += " placementQueries " + to_string(st.placementQueries) + " != calls " + to_string(log.calls) + " (revealed " +
               to_string(st.tbvsRevealed) + ", renewed " + to_string(st.tbvsRenewed) + ");";
    if (!tbvs && st.hiddenObjects) why += " hidden objects without TBVs;";
    if (st.pvsSize != r.pvs.size() || !std::is_sorted(r.pvs.begin(), r.pvs.end()) ||
        std::adjacent_find(r.pvs.begin(), r.pvs.end()) != r.pvs.end())
        why += " PVS not sorted/unique or pvsSize wrong;";
    if (why.empty()) return true;
    if (failures++ < 10) std::printf("INVARIANT (%s, frame %d):%s\n", what, frame, why.c_str());
    return false;
}

/// Counts the objects the reference sees that the PVS lacks; prints the first few.
template <int D> std::uint64_t countMisses(const DynScene<D>& s, const std::vector<bool>& vis,
                                           const std::vector<ObjectId>& pvs, const char* what, int frame,
                                           std::uint64_t printed) {
    std::uint64_t n = 0;
    for (std::size_t i = 0; i < vis.size(); ++i)
        if (vis[i] && !std::binary_search(pvs.begin(), pvs.end(), ObjectId(i))) {
            if (printed + n++ < 5) {
                const Vec<D> c = centreAt(s.movers[i], frame);
                std::printf("MISS: %s, frame %d, object %zu (zone %d) at (%.3f, %.3f%s)\n", what, frame, i, s.zone[i], c[0],
                            c[1], D == 3 ? (", " + std::to_string(c[D - 1])).c_str() : "");
            }
        }
    return n;
}

struct Variant {
    const char* name;
    CullerOptions options;
};

struct Settings {
    int frames = 300, repeats = 1, warmup = 50, checkFrames = 3, soakFrames = 100000, churn = 20;
    std::vector<int> counts{1000, 10000, 100000};
    double growth = CullerOptions{}.tbvMaxGrowth;
    std::uint64_t seed = 2004;
    std::string second = "filled";     ///< --second: filled, shell or unconfined (see the top of the file)
};

template <int D> std::uint64_t runHidden(const char* title, const Settings& cfg,
                                         const std::function<DynScene<D>(int)>& makeScene,
                                         const std::function<Camera<D>(int)>& cameraAt, std::size_t chunk) {
    CullerOptions boundary;
    boundary.tbvMaxGrowth = cfg.growth;
    // Every mover reflects inside its zone, and the zones are inside the grid: the promise holds.
    boundary.objectsStayInGrid = true;
    CullerOptions filled = boundary;
    if (cfg.second == "unconfined") filled.objectsStayInGrid = false;
    else filled.tbvDiscretization = cfg.second == "shell" ? TbvDiscretization::Shell : TbvDiscretization::Filled;
    CullerOptions baseline;
    baseline.temporalBoundingVolumes = false;
    const std::vector<Variant> variants{{"TBV boundary", boundary},
                                        {cfg.second == "shell"        ? "TBV shell"
                                         : cfg.second == "unconfined" ? "TBV unconfined"
                                                                      : "TBV filled",
                                         filled},
                                        {"re-insert all", baseline}};
    const std::size_t nv = variants.size();
    const int warmup = std::min(cfg.warmup, cfg.frames - 1);
    const DynScene<D> s0 = makeScene(0);
    std::string grid, counts;
    for (int a = 0; a < D; ++a) grid += (a ? " x " : "") + std::to_string(s0.grid.resolution()[a]);
    for (int n : cfg.counts) counts += (counts.empty() ? "" : "/") + std::to_string(n);
    std::printf("\n== %s: grid %s, %zu static wall boxes, %d visible movers, hidden movers %s; %d frames (first %d "
                "skipped) x %d repeats, tbvMaxGrowth %g ==\n",
                title, grid.c_str(), s0.statics, kVisibleMovers, counts.c_str(), cfg.frames, warmup, cfg.repeats,
                cfg.growth > 0 ? cfg.growth : (D == 2 ? 32.0 : 8.0));
    std::fflush(stdout);
    std::uint64_t failures = 0;
    std::vector<std::vector<Tally>> tallies(cfg.counts.size(), std::vector<Tally>(nv));
    for (std::size_t ci = 0; ci < cfg.counts.size(); ++ci) {
        const int n = cfg.counts[ci];
        std::vector<double> addMs(nv, 0), firstMs(nv, 0);
        double refMs = 0;
        std::size_t refInView = 0, checked = 0;
        long rss = 0;
        for (int rep = 0; rep < cfg.repeats; ++rep) {
            const DynScene<D> s = makeScene(n);
            std::vector<Culler<D>> cullers;
            std::vector<QueryLog> logs(nv);
            std::vector<PlacementQuery<D>> queries;
            int frame = 0;
            for (std::size_t k = 0; k < nv; ++k) {
                const auto t0 = std::chrono::steady_clock::now();
                cullers.emplace_back(s.grid, variants[k].options);
                for (const ObjectDesc<D>& o : s.objects) cullers.back().addObject(o);
                addMs[k] += msSince(t0) / cfg.repeats;
                logs[k].askedAt.assign(s.objects.size(), -1);
                queries.push_back(makeQuery(s, frame, logs[k]));
            }
            for (frame = 0; frame < cfg.frames; ++frame) {
                const Camera<D> cam = cameraAt(frame);
                bool check = false; // checkFrames frames spread evenly over the measured ones, the last included
                for (int i = 0; rep == 0 && i < cfg.checkFrames; ++i)
                    check = check ||
                            frame == cfg.frames - 1 - (cfg.frames - 1 - warmup) * i / std::max(1, cfg.checkFrames - 1);
                std::vector<std::vector<ObjectId>> pvs(nv);
                for (std::size_t k = 0; k < nv; ++k) {
                    const double c0 = threadCpuMs();
                    const CullResult& r = cullFrame(cullers[k], cam, queries[k], logs[k], variants[k].name, frame, failures);
                    const double cpu = threadCpuMs() - c0;
                    if (!checkFrame(s, r, logs[k], k != 2, variants[k].name, frame, failures)) ++tallies[ci][k].badFrames;
                    if (frame == 0) firstMs[k] += r.stats.cullMs / cfg.repeats;
                    if (frame >= warmup) tallies[ci][k].add(r.stats, cpu);
                    if (check) pvs[k] = r.pvs;
                }
                if (check) {
                    const auto t0 = std::chrono::steady_clock::now();
                    const std::vector<bool> vis = referenceAt(s, frame, cam, chunk, refInView);
                    refMs += msSince(t0);
                    ++checked;
                    for (std::size_t k = 0; k < nv; ++k)
                        tallies[ci][k].misses += countMisses(s, vis, pvs[k], variants[k].name, frame, tallies[ci][k].misses);
                }
                if ((frame + 1) % 10 == 0 || frame + 1 == cfg.frames)
                    std::fprintf(stderr, "\r  N=%d repeat %d/%d frame %d/%d", n, rep + 1, cfg.repeats, frame + 1,
                                 cfg.frames);
            }
            rss = std::max(rss, rssKiB());
            for (const QueryLog& l : logs) failures += l.violations;
        }
        std::fprintf(stderr, "\r%60s\r", "");
        const std::vector<Tally>& T = tallies[ci];
        std::printf("N=%d (boundary/filled/baseline): addObject %.0f/%.0f/%.0f ms, frame 0 (all tracked) %.1f/%.1f/%.1f ms, "
                    "RSS %.0f MiB\n  reference on %zu frames (%zu objects in view, %.0f ms each): misses %llu/%llu/%llu; "
                    "frames failing invariants %llu/%llu/%llu (speed violations %llu/%llu/%llu)\n",
                    n, addMs[0], addMs[1], addMs[2], firstMs[0], firstMs[1], firstMs[2], double(rss) / 1024, checked,
                    refInView, refMs / double(std::max<std::size_t>(1, checked)), U(T[0].misses), U(T[1].misses),
                    U(T[2].misses), U(T[0].badFrames), U(T[1].badFrames), U(T[2].badFrames), U(T[0].speedViolations),
                    U(T[1].speedViolations), U(T[2].speedViolations));
        std::fflush(stdout);
    }
    std::printf("%7s %-13s %9s %8s %8s %8s %6s %8s %7s %7s %7s %7s %7s %8s\n", "hidden", "variant", "median ms",
                "p90 ms", "cpu med", "cpu p90", "|PVS|", "queries", "created", "renewed", "reveal", "hidden", "writes",
                "voxels");
    for (std::size_t ci = 0; ci < cfg.counts.size(); ++ci)
        for (std::size_t k = 0; k < nv; ++k) {
            const Tally& t = tallies[ci][k];
            const double f = double(std::max<std::uint64_t>(1, t.frames));
            std::printf("%7d %-13s %9.3f %8.3f %8.3f %8.3f %6.1f %8.1f %7.2f %7.2f %7.2f %7.0f %7.0f %8.0f\n",
                        cfg.counts[ci], variants[k].name, percentile(t.ms, 0.5), percentile(t.ms, 0.9), percentile(t.cpu, 0.5),
                        percentile(t.cpu, 0.9), t.pvs / f, t.queries / f, t.created / f, t.renewed / f, t.revealed / f,
                        t.hidden / f, t.writes / f, t.visited / f);
            failures += t.misses;
        }
    std::printf("(means per measured frame; ms: CullStats::cullMs; cpu: thread CPU of the same call; writes: gridWrites; "
                "voxels: voxelsVisited)\n");
    const std::size_t last = cfg.counts.size() - 1;
    for (std::size_t k = 0; last > 0 && k < nv; ++k) {
        const double w = percentile(tallies[last][k].ms, 0.5) / percentile(tallies[0][k].ms, 0.5);
        const double c = percentile(tallies[last][k].cpu, 0.5) / percentile(tallies[0][k].cpu, 0.5);
        const char* verdict = std::max(w, c) < 2 ? "met" : std::min(w, c) < 2 ? "met on one clock only" : "NOT met";
        std::printf("time(%d)/time(%d), %-13s: wall %.2fx, cpu %.2fx%s%s%s\n", cfg.counts[last], cfg.counts[0],
                    variants[k].name, w, c, k == 2 ? "" : "  (target < 2x: ", k == 2 ? "" : verdict, k == 2 ? "" : ")");
    }
    std::fflush(stdout);
    return failures;
}

// ---- soak ----

/// Lissajous walk over the grid (< 0.4 voxel/frame), turning +-35 degrees about its tangent; every 5,000
/// frames the walk jumps a third of a loop ahead (a teleport).
Camera2 soakCamera(int f) {
    const double t = 2 * M_PI * (double(f) + 1333.0 * (f / 5000)) / 4000.0, R = 100, c = 128;
    const double turn = 35 * M_PI / 180 * std::sin(2 * M_PI * f / 700);
    const Vec2 tangent = safeNormalize<2>(Vec2{std::cos(t), 2 * std::cos(2 * t + 0.3)} + Vec2{1e-9, 0});
    return {.position = {c + R * std::sin(t), c + R * std::sin(2 * t + 0.3)},
            .direction = {tangent.x * std::cos(turn) - tangent.y * std::sin(turn),
                          tangent.x * std::sin(turn) + tangent.y * std::cos(turn)},
            .fovDeg = 90};
}

ObjectDesc<2> soakMover(std::mt19937_64& rng, Mover<2>& m) {
    const double p = sr::uniform01(rng); // 70% slow, 25% medium, 5% fast
    const double s0 = p < 0.7 ? 0.01 : p < 0.95 ? 0.1 : 0.5, s1 = p < 0.7 ? 0.1 : p < 0.95 ? 0.5 : 1.5;
    return randomMover<2>(rng, {0, 0}, {256, 256}, 0.5, 2.5, s0, s1, m);
}

std::uint64_t runSoak(const Settings& cfg) {
    const int frames = cfg.soakFrames, movers = 2000, walls = 30;
    std::mt19937_64 rng(cfg.seed);
    DynScene<2> s{GridGeometry2({0, 0}, 1.0, {256, 256}), {}, {}, {}, {}, 0, 0};
    const std::size_t capacity = std::size_t(walls + movers) + std::size_t(cfg.churn) * std::size_t(frames / 1000 + 1);
    // The application's arrays get their final size and touched pages now: they must not show up as RSS growth.
    auto pretouch = [capacity](auto& v) { v.resize(capacity); v.clear(); };
    pretouch(s.objects), pretouch(s.movers), pretouch(s.zone), pretouch(s.alive);
    for (int i = 0; i < walls; ++i) {
        const Vec2 c{sr::uniform(rng, 20, 236), sr::uniform(rng, 20, 236)};
        const Vec2 half = sr::chance(rng, 0.5) ? Vec2{1, sr::uniform(rng, 5, 15)} : Vec2{sr::uniform(rng, 5, 15), 1};
        s.addStatic(Box<2>{c - half, c + half});
    }
    Mover<2> m;
    for (int i = 0; i < movers; ++i) s.add(soakMover(rng, m), m, 2);
    std::printf("\n== soak: grid 256 x 256, %d static walls, %d moving balls (speeds 0.01..1.5), %d frames, camera walk "
                "(teleport every 5,000 frames), churn %d objects every 1,000 frames ==\n",
                walls, movers, frames, cfg.churn);
    std::fflush(stdout);
    Culler2D culler(s.grid);
    for (const ObjectDesc<2>& o : s.objects) culler.addObject(o);
    QueryLog log;
    log.askedAt.assign(capacity, -1);
    int frame = 0;
    const PlacementQuery<2> query = makeQuery(s, frame, log);
    Tally t;
    t.ms.assign(std::size_t(frames), 0);
    t.cpu.assign(std::size_t(frames), 0);
    std::vector<long> rss;
    rss.reserve(std::size_t(frames / 1000 + 1));
    std::uint64_t failures = 0, checks = 0, unexpectedJumps = 0, missedJumps = 0;
    double refMs = 0;
    for (frame = 0; frame < frames; ++frame) {
        if (frame % 1000 == 500 && cfg.churn > 0) { // churn: ids never come back; slots must be reused
            for (int i = 0; i < cfg.churn; ++i) {
                ObjectId id;
                do id = s.statics + rng() % (s.objects.size() - s.statics); while (!s.alive[id]);
                culler.removeObject(id);
                s.alive[id] = 0;
                --s.live;
            }
            for (int i = 0; i < cfg.churn; ++i) {
                ObjectDesc<2> o = soakMover(rng, m);
                m.p0 -= m.v * double(frame); // so that the walk starts at the drawn point now
                o.shape = Ball<2>{centreAt(m, frame), m.radius};
                o.id = s.add(o, m, 2);
                culler.addObject(o);
            }
        }
        const Camera2 cam = soakCamera(frame);
        const double c0 = threadCpuMs();
        const CullResult* r = &cullFrame(culler, cam, query, log, "soak", frame, failures);
        t.add(r->stats, threadCpuMs() - c0);
        if (!checkFrame(s, *r, log, true, "soak", frame, failures)) ++t.badFrames;
        const bool teleport = frame > 0 && frame % 5000 == 0;
        unexpectedJumps += r->stats.cameraJump && !teleport && frame > 0;
        missedJumps += teleport && !r->stats.cameraJump;
        if ((frame + 1) % 10000 == 0 || teleport || frame + 1 == frames) {
            const auto t0 = std::chrono::steady_clock::now();
            std::size_t inViewCount = 0;
            const std::vector<bool> vis = referenceAt(s, frame, cam, s.objects.size(), inViewCount);
            refMs += msSince(t0);
            ++checks;
            const std::uint64_t miss = countMisses(s, vis, r->pvs, "soak", frame, t.misses);
            if (miss > 0) {
                std::vector<ObjectDesc<2>> now;
                for (std::size_t i = 0; i < s.objects.size(); ++i)
                    if (s.alive[i]) now.push_back({i, s.shapeAt(i, frame), s.objects[i].isStatic, s.objects[i].maxSpeed});
                const std::string path = "/tmp/rgvc-bench-dynamic-soak-miss-frame" + std::to_string(frame) + ".json";
                std::ofstream(path) << ref::toJson(s.grid, now, cam);
                std::printf("  scene of frame %d written to %s\n", frame, path.c_str());
            }
            t.misses += miss;
        }
        if ((frame + 1) % 1000 == 0) {
            malloc_trim(0);
            rss.push_back(rssKiB());
            std::fprintf(stderr, "\r  soak frame %d/%d, RSS %ld KiB", frame + 1, frames, rss.back());
        }
        if ((frame + 1) % 10000 == 0 || frame + 1 == frames) {
            std::fprintf(stderr, "\r%60s\r", "");
            std::printf("frames %6d..%6d: RSS KiB", frame + 1 - std::min<int>(frame + 1, 10000) + 1, frame + 1);
            for (std::size_t i = std::size_t(std::max(0, (frame + 1) / 1000 - 10)); i < rss.size(); ++i)
                std::printf(" %ld", rss[i]);
            std::printf("; hidden %u tracked %u, median %.3f ms so far\n", r->stats.hiddenObjects, r->stats.trackedObjects,
                        percentile({t.ms.begin(), t.ms.begin() + frame + 1}, 0.5));
            std::fflush(stdout);
        }
    }
    const long growth = rss.size() > 1 ? rss.back() - rss.front() : 0;
    std::printf("RSS: frame 1,000 %ld KiB, final %ld KiB, growth %ld KiB, max %ld KiB%s\n", rss.empty() ? 0 : rss.front(),
                rss.empty() ? 0 : rss.back(), growth, rss.empty() ? 0 : *std::max_element(rss.begin(), rss.end()),
                growth > 4096 ? "  GROWTH OVER 4 MiB" : "");
    std::printf("TBVs: created %.0f, renewed %.0f, revealed %.0f, refused %.0f; revealed by camera jumps %llu; camera jumps "
                "%llu (%d teleports; unexpected %llu, teleports not flagged %llu)\n",
                t.created, t.renewed, t.revealed, t.refused, U(t.revealedByJump), U(t.jumps),
                (frames - 1) / 5000, U(unexpectedJumps), U(missedJumps));
    std::printf("per frame: median %.4f ms, p90 %.4f ms, max %.3f ms (cpu median %.4f ms); mean |PVS| %.1f, queries %.1f, "
                "hidden %.0f; reference on %llu frames (%.0f ms each): misses %llu\n",
                percentile(t.ms, 0.5), percentile(t.ms, 0.9), *std::max_element(t.ms.begin(), t.ms.end()),
                percentile(t.cpu, 0.5), t.pvs / double(frames), t.queries / double(frames), t.hidden / double(frames),
                U(checks), refMs / double(std::max<std::uint64_t>(1, checks)), U(t.misses));
    std::printf("bookkeeping: frames failing invariants %llu (speed violations %llu), query contract violations %llu\n",
                U(t.badFrames), U(t.speedViolations), U(log.violations));
    std::fflush(stdout);
    return failures + log.violations + t.misses + (growth > 4096);
}

} // namespace

int main(int argc, char** argv) {
    Settings cfg;
    std::string scenario = "all";
    bool framesGiven = false;
    const std::pair<const char*, int*> intFlags[] = {{"--frames", &cfg.frames},           {"--repeats", &cfg.repeats},
                                                     {"--warmup", &cfg.warmup},           {"--check-frames", &cfg.checkFrames},
                                                     {"--soak-frames", &cfg.soakFrames}, {"--churn", &cfg.churn}};
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a != "--help" && a != "-h" && i + 1 >= argc) {
            std::fprintf(stderr, "rgvc_bench_dynamic: %s needs a value\n", a.c_str());
            return 2;
        }
        const char* v = i + 1 < argc ? argv[i + 1] : "";
        bool known = true;
        if (a == "--scenario") scenario = v;
        else if (a == "--tbv-max-growth") cfg.growth = std::atof(v);
        else if (a == "--second") cfg.second = v;
        else if (a == "--seed") cfg.seed = std::strtoull(v, nullptr, 10);
        else if (a == "--counts") {
            cfg.counts.clear();
            for (const char* p = v; *p; p = std::strchr(p, ',') ? std::strchr(p, ',') + 1 : "")
                cfg.counts.push_back(std::max(0, std::atoi(p)));
        } else {
            known = false;
            for (const auto& [flag, value] : intFlags)
                if (a == flag) *value = std::max(0, std::atoi(v)), known = true;
            framesGiven = framesGiven || a == "--frames";
        }
        if (!known) {
            std::fprintf(stderr, "usage: rgvc_bench_dynamic [--scenario hidden2d|hidden3d|soak|all] [--frames N] [--repeats R] "
                                 "[--seed S] [--counts 1000,10000,100000] [--warmup N] [--check-frames K] "
                                 "[--tbv-max-growth G] [--second filled|shell|unconfined] [--soak-frames N] [--churn C]\n");
            return a == "--help" || a == "-h" ? 0 : 2;
        }
        ++i;
    }
    if (scenario != "hidden2d" && scenario != "hidden3d" && scenario != "soak" && scenario != "all") {
        std::fprintf(stderr, "rgvc_bench_dynamic: unknown scenario '%s'\n", scenario.c_str());
        return 2;
    }
    if (cfg.second != "filled" && cfg.second != "shell" && cfg.second != "unconfined") {
        std::fprintf(stderr, "rgvc_bench_dynamic: --second takes filled, shell or unconfined, got '%s'\n", cfg.second.c_str());
        return 2;
    }
    cfg.frames = std::max(2, cfg.frames), cfg.repeats = std::max(1, cfg.repeats);
    cfg.soakFrames = std::max(1, cfg.soakFrames);
    if (scenario == "soak" && framesGiven) cfg.soakFrames = cfg.frames;
    if (cfg.counts.empty() || !(cfg.growth >= 0)) {
        std::fprintf(stderr, "rgvc_bench_dynamic: --counts needs a number, --tbv-max-growth a non-negative one (0: default)\n");
        return 2;
    }
    std::printf("rgvc_bench_dynamic on %s, one thread, seed %llu\n", machine().c_str(), U(cfg.seed));
    std::uint64_t failures = 0;
    if (scenario == "hidden2d" || scenario == "all")
        failures += runHidden<2>("hidden2d", cfg, [&](int n) { return hiddenScene2D(n, cfg.seed); }, hiddenCamera2D, 300);
    Settings cfg3 = cfg; // 3D frames cost ~0.1-1 s at 100,000 objects: half the frames unless --frames says otherwise
    cfg3.frames = framesGiven ? cfg.frames : 150;
    if (scenario == "hidden3d" || scenario == "all")
        failures += runHidden<3>("hidden3d", cfg3, [&](int n) { return hiddenScene3D(n, cfg.seed); }, hiddenCamera3D, 300);
    if (scenario == "soak" || scenario == "all") failures += runSoak(cfg);
    std::printf("\n%s\n", failures ? "FAILED: misses or invariant failures above" : "all checks passed");
    return failures ? 1 : 0;
}
