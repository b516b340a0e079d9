// rgvc_bench_classes: culling time, work and accuracy of the culler across classes of scenes.
//
// Speed is measured here, never asserted in tests. Each scene is built here from a fixed seed (the paper's
// scene comes from reference::movingSpheres3D, the same generator rgvc_bench3d uses), run for a number of
// frames with a moving camera, and culled by every variant of the culler:
//   3D: new  (default CullerOptions: hierarchical = true, the output-sensitive brick-tree core),
//       old  (hierarchical = false: the paper's per-voxel shell traversal),
//       vfc  (occlusion = false: grid view-frustum culling only; its |PVS| is the scene's |VFC|);
//   2D: new  (default CullerOptions: hierarchical = true, the brick quadtree with its angular image),
//       rings (hierarchical = false: the paper's chess-ring traversal with occluder extension and H), vfc.
// The variants run interleaved frame by frame in one process: one scene, moved once per frame, and one
// culler per variant, each culling the same camera with the same placement query (the pull interface,
// cull(camera, placementOf)); the order of the variants rotates from frame to frame so that none is always
// the first one after the motion and the reference (cold caches). The scenes and their motion are in
// ClassScenes.hpp.
//
// Accuracy: every K-th measured frame is checked against the reference (3D: reference::visible3D at 128
// grid and 8 target divisions with critical rays, as rgvc_bench3d's accuracy scenario; 2D:
// reference::exactVisible2D), given only the objects that touch the view region (exact: the view region
// is convex and holds the camera, so a segment from the camera to a point in it meets only objects that
// touch it; the eps is the whole scene's). K comes from --ref-every, or else from the first check's cost:
// the reference gets about kReferenceBudgetMs per scene. A miss (a visible object not in a PVS) is printed
// at once with the scene written to /tmp, counted in the table, and makes the run exit 1.
// |PVS|/|visible| is averaged over the checked frames where something is visible and the camera is not
// inside an object (from inside one the reference sees that object only).
//
//   rgvc_bench_classes [--scene NAME|all] [--frames N] [--warmup W] [--ref-every K] [--no-reference] [--quick]
//                      [--variant NAME[,NAME...]]   (only those variants: new, fullimg, adaptbuf, freshbuf, img128,
//                                       nobuf, lazy, old, rings, vfc; for profiling, or to set up fewer cullers)
//                      [--voxel-size V]   (every scene's grid re-made with voxels of V world units)
//                      [--repeats R]      (each scene run R times, fresh cullers each time: the tables give the
//                                          median over the runs of each run's median, the shared machine's
//                                          load moving whole runs)
//                      [--csv FILE] [--plot FILE.png]   (one CSV row per scene and variant; the plot, drawn
//                                          by scripts/plot_classes.gp from the CSV: time per class against
//                                          Masked Occlusion Culling's figures, where the time goes, |PVS|/|visible|)
//
// --quick: 3 measured frames after 1 warm-up, every frame checked, small object counts, room-1k only
// among the rooms and a 256^3 empty grid (a smoke test: a few seconds). Output: a header (machine,
// scenes), one markdown table on stdout, then the reference notes per scene; a progress line on stderr
// when it is a terminal. Exit 0, 1 on any miss (or error), 2 on a bad flag.
#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/grid/VoxelSize.hpp"

#include "BenchReference.hpp"
#include "BenchSupport.hpp"
#include "ClassScenes.hpp"

#include "ExactVisibility2D.hpp"
#include "ExactVisibility3D.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

using namespace rgvc;
namespace ref = rgvc::reference;
using namespace rgvc::bench;

namespace {

constexpr double kReferenceBudgetMs = 3000; // per scene, when --ref-every is not given

// ---------------------------------------------------------------------------------------------------
// Running

struct Config {
    int frames = 60, warmup = 5, refEvery = 0; // refEvery 0: chosen from the first check's cost
    bool noReference = false;                  // --no-reference: timing only (profiling), no accuracy columns
    bool quick = false;
    std::string variant; // --variant NAME[,NAME...]: only these (profiling, or fewer cullers); empty: all
    double voxelSize = 0; // --voxel-size V: every scene's grid re-made with voxels of V world units (0: the scene's)
    int repeats = 1;      // --repeats R
    std::string csv, plot; // --csv FILE, --plot FILE.png
};

/// One variant's counts per frame, summed over the measured frames and then divided into means.
struct FrameMeans {
    double voxels = 0, nodes = 0, empty = 0, hidden = 0, bricks = 0, pvs = 0;
    // The update's counts (the second table, where the time goes).
    double queries = 0, tracked = 0, hiddenObjects = 0, created = 0, renewed = 0, revealed = 0;

    void add(const CullResult& r) {
        const CullStats& s = r.stats;
        voxels += double(s.voxelsVisited);
        nodes += double(s.nodesVisited);
        empty += double(s.nodesEmpty);
        hidden += double(s.nodesHidden);
        bricks += double(s.bricksVisited);
        pvs += double(r.pvs.size());
        queries += double(s.placementQueries);
        tracked += double(s.trackedObjects);
        hiddenObjects += double(s.hiddenObjects);
        created += double(s.tbvsCreated);
        renewed += double(s.tbvsRenewed);
        revealed += double(s.tbvsRevealed);
    }
    static constexpr double FrameMeans::*kFields[] = {
        &FrameMeans::voxels,  &FrameMeans::nodes,   &FrameMeans::empty,         &FrameMeans::hidden,
        &FrameMeans::bricks,  &FrameMeans::pvs,     &FrameMeans::queries,       &FrameMeans::tracked,
        &FrameMeans::hiddenObjects, &FrameMeans::created, &FrameMeans::renewed, &FrameMeans::revealed};
    FrameMeans over(double n) const {
        FrameMeans m = *this;
        for (double FrameMeans::*f : kFields) m.*f /= n;
        return m;
    }
    FrameMeans& operator+=(const FrameMeans& o) {
        for (double FrameMeans::*f : kFields) this->*f += o.*f;
        return *this;
    }
};

/// One variant's times per frame: the whole cull and its parts (CullStats), for medians.
struct FrameTimes {
    std::vector<double> cull, update, buffer, walk;
    void add(const CullStats& s) {
        cull.push_back(s.cullMs);
        update.push_back(s.updateMs);
        buffer.push_back(s.bufferMs);
        walk.push_back(std::max(0.0, s.cullMs - s.updateMs - s.bufferMs));
    }
};

struct Row {
    std::string scene, variant;
    int dim = 3;
    bool hierarchical = true; // the brick walk ran (its node counts are printed)
    double medianMs = 0, p90Ms = 0;
    double updateMs = 0, bufferMs = 0, walkMs = 0; // medians of the parts (where the time goes)
    FrameMeans mean;
    double ratio = -1; // -1: no frame counted
    std::uint64_t misses = 0;
};

std::vector<Row> g_rows;
std::vector<std::string> g_notes;
std::uint64_t g_totalMisses = 0;
const bool g_progress = isatty(fileno(stderr)) != 0;

template <int D> std::string gridText(const GridGeometry<D>& g) {
    std::string s = std::to_string(g.resolution()[0]);
    for (int k = 1; k < D; ++k)
        s += "x" + std::to_string(g.resolution()[k]);
    return s;
}

template <int D> struct Variant {
    const char* name;
    CullerOptions options;
};

template <int D> std::vector<Variant<D>> variantsFor() {
    if constexpr (D == 3) return {{"new", {}}, {"fullimg", {.adaptiveImage = false}}, {"adaptbuf", {.adaptiveBuffer = true}}, {"freshbuf", {.bufferFromTraversalImage = false}}, {"img128", {.traversalImageRows = 128}}, {"nobuf", {.occlusionBufferRows = 0}}, {"lazy", {.lazyStorage = true}}, {"old", {.hierarchical = false}}, {"vfc", {.occlusion = false}}};
    else return {{"new", {}}, {"rings", {.hierarchical = false}}, {"vfc", {.occlusion = false}}};
}

template <int D> void runScene(World<D>& w, const Config& cfg) {
    {
        // recommendVoxelSize over the scene's frame-0 shapes, printed beside the size the run uses.
        std::vector<Shape<D>> shapes;
        shapes.reserve(w.objects.size());
        for (const ObjectDesc<D>& o : w.objects) shapes.push_back(o.shape);
        Box<D> world{w.grid.origin(), w.grid.origin()};
        for (int a = 0; a < D; ++a) world.max[a] += w.grid.voxelSize() * w.grid.resolution()[a];
        const double recommended = recommendVoxelSize<D>(shapes, world);
        if (cfg.voxelSize > 0) {
            IVec<D> res;
            for (int a = 0; a < D; ++a) res[a] = int(std::ceil((world.max[a] - world.min[a]) / cfg.voxelSize - 1e-9));
            w.grid = GridGeometry<D>(w.grid.origin(), cfg.voxelSize, res);
        }
        std::printf("- %s: voxel size %g (recommendVoxelSize: %.3g)\n", w.name.c_str(), w.grid.voxelSize(), recommended);
    }
    std::vector<Variant<D>> variants = variantsFor<D>();
    if (!cfg.variant.empty()) {
        // A comma-separated list; a name of the other dimension's variants (rings, old) just matches nothing here.
        const std::string list = "," + cfg.variant + ",";
        std::erase_if(variants, [&](const Variant<D>& v) { return list.find("," + std::string(v.name) + ",") == std::string::npos; });
        if (variants.empty()) return; // not a variant of this dimension
    }
    const std::size_t nv = variants.size();
    const int frames = w.maxFrames > 0 ? std::min(cfg.frames, w.maxFrames) : cfg.frames;
    std::printf("- %s: %dD grid %s, %zu objects: %s; %d frames after %d warm-up\n", w.name.c_str(), D,
                gridText(w.grid).c_str(), w.objects.size(), w.description.c_str(), frames, cfg.warmup);
    std::fflush(stdout);

    const auto tBuild = std::chrono::steady_clock::now();
    std::vector<Culler<D>> cullers;
    for (const Variant<D>& v : variants) {
        cullers.emplace_back(w.grid, v.options);
        for (const ObjectDesc<D>& o : w.objects)
            cullers.back().addObject(o);
    }
    const double buildMs = msSince(tBuild);
    const PlacementQuery<D> placementOf = [&w](ObjectId id) { return w.objects[std::size_t(id)].shape; };

    std::vector<FrameTimes> times(nv);
    std::vector<FrameMeans> sums(nv);
    std::vector<double> ratio(nv);
    std::vector<std::uint64_t> misses(nv);
    int refEvery = cfg.refEvery > 0 ? cfg.refEvery : 1, checked = 0, counted = 0;
    double refMs = 0, visibleSum = 0, firstRefMs = 0;
    for (int f = 0; f < cfg.warmup + frames; ++f) {
        if (f > 0) stepWorld(w);
        const Camera<D> cam = w.camera(f);
        const int m = f - cfg.warmup; // measured frame index, < 0 in the warm-up
        Reference truth;
        const bool check = !cfg.noReference && m >= 0 && m % refEvery == 0;
        if (check) {
            const auto t0 = std::chrono::steady_clock::now();
            truth = referenceOf(w.objects, cam);
            const double t = msSince(t0);
            refMs += t;
            if (checked++ == 0) {
                firstRefMs = t;
                if (cfg.refEvery <= 0) // keep the reference near the budget for the whole scene
                    refEvery = std::clamp(int(std::ceil(t * frames / (cfg.quick ? 1000.0 : kReferenceBudgetMs))), 1,
                                          std::max(frames, 1));
            }
            visibleSum += double(truth.count);
        }
        const bool count = check && truth.count > 0 && !truth.cameraInsideObject;
        counted += count;
        for (std::size_t j = 0; j < nv; ++j) {
            const std::size_t k = (j + std::size_t(f)) % nv; // rotate the order
            const CullResult& r = cullers[k].cull(cam, placementOf);
            if (m < 0) continue;
            times[k].add(r.stats);
            sums[k].add(r);
            if (!check) continue;
            if (count) ratio[k] += double(r.pvs.size()) / double(truth.count);
            for (std::size_t i = 0; i < w.objects.size(); ++i)
                if (truth.visible[i] && !std::binary_search(r.pvs.begin(), r.pvs.end(), w.objects[i].id)) {
                    if (misses[k]++ < 3) {
                        const std::string path = "/tmp/rgvc-bench-classes-miss-" + w.name + "-" + variants[k].name +
                                                 "-frame" + std::to_string(m) + ".json";
                        std::ofstream(path) << ref::toJson(w.grid, w.objects, cam);
                        std::fprintf(stderr, "%sMISS: scene %s, variant %s, frame %d, object %llu (scene: %s)\n",
                                     g_progress ? "\n" : "", w.name.c_str(), variants[k].name, m,
                                     (unsigned long long)w.objects[i].id, path.c_str());
                    }
                }
        }
        if (g_progress)
            std::fprintf(stderr, "\r  %-10s frame %d/%d%s   ", w.name.c_str(), f + 1, cfg.warmup + frames,
                         check ? " (reference)" : "");
    }
    if (g_progress) std::fprintf(stderr, "\r%70s\r", "");

    const double n = std::max(1, frames);
    for (std::size_t k = 0; k < nv; ++k) {
        Row row;
        row.scene = w.name;
        row.dim = D;
        row.variant = variants[k].name;
        row.hierarchical = variants[k].options.hierarchical;
        row.medianMs = percentile(times[k].cull, 0.5);
        row.p90Ms = percentile(times[k].cull, 0.9);
        row.updateMs = percentile(times[k].update, 0.5);
        row.bufferMs = percentile(times[k].buffer, 0.5);
        row.walkMs = percentile(times[k].walk, 0.5);
        row.mean = sums[k].over(n);
        row.ratio = counted > 0 ? ratio[k] / counted : -1;
        row.misses = misses[k];
        g_totalMisses += misses[k];
        g_rows.push_back(row);
    }
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "%s: reference checked %d of %d frames (every %d%s), %.0f ms per check (first %.0f ms); "
                  "mean |visible| %.1f; ratio over %d frames (%d with the camera inside an object or nothing "
                  "visible left out); setup (%zu cullers, addObject) %.0f ms, RSS %.0f MiB",
                  w.name.c_str(), checked, frames, refEvery, cfg.refEvery > 0 ? ", --ref-every" : ", auto",
                  refMs / std::max(1, checked), firstRefMs, visibleSum / std::max(1, checked), counted,
                  checked - counted, nv, buildMs, double(rssKiB()) / 1024.0);
    g_notes.emplace_back(buf);
}

/// Rows of the same scene and variant from --repeats runs merged into one, in the order they first
/// appear: times are the median over the runs of each run's median (p90, parts likewise), counts and
/// |PVS|/|visible| the mean over the runs, misses the sum.
std::vector<Row> mergeRepeats(const std::vector<Row>& rows) {
    std::vector<Row> out;
    for (const Row& r : rows) {
        const bool seen = std::any_of(out.begin(), out.end(), [&](const Row& o) { return o.scene == r.scene && o.variant == r.variant; });
        if (seen) continue;
        std::vector<double> med, p90, upd, buf, walk;
        FrameMeans sum;
        double ratioSum = 0;
        int ratioRuns = 0, runs = 0;
        Row m = r;
        m.misses = 0;
        for (const Row& x : rows) {
            if (x.scene != r.scene || x.variant != r.variant) continue;
            ++runs;
            med.push_back(x.medianMs);
            p90.push_back(x.p90Ms);
            upd.push_back(x.updateMs);
            buf.push_back(x.bufferMs);
            walk.push_back(x.walkMs);
            sum += x.mean;
            if (x.ratio >= 0) ratioSum += x.ratio, ++ratioRuns;
            m.misses += x.misses;
        }
        m.medianMs = percentile(med, 0.5);
        m.p90Ms = percentile(p90, 0.5);
        m.updateMs = percentile(upd, 0.5);
        m.bufferMs = percentile(buf, 0.5);
        m.walkMs = percentile(walk, 0.5);
        m.mean = sum.over(runs);
        m.ratio = ratioRuns > 0 ? ratioSum / ratioRuns : -1;
        out.push_back(m);
    }
    return out;
}

/// [ms] Masked Occlusion Culling's figure for the scene class, from issue #10's table (Hasselgren,
/// Andersson and Akenine-Möller 2016; AVX2, one thread, 640 x 384, occluders front to back, measured by
/// the author on the same kind of scene and machine; the 3D cities: the top of its 0.015-0.05
/// range); -1 where the issue gives none. The plot draws them beside the variants' times.
double mocMs(const std::string& scene) {
    if (scene == "room-1k") return 0.048;
    if (scene == "room-100k") return 3.2;
    if (scene == "clusters") return 0.56;
    if (scene == "game") return 0.20;
    if (scene == "large") return 0.45;
    if (scene == "city3d") return 0.05;
    return -1;
}

/// --csv: one row per scene and variant, the tables' columns, the scene's ordinal (for the plot's x axis),
/// Masked Occlusion Culling's figure (mocMs) and the scene's vfc median (the plot's unit for "never slower
/// than --no-occlusion"; -1 when vfc did not run). Returns false when the file cannot be written.
bool writeCsv(const std::string& path, const std::vector<Row>& rows, int repeats) {
    std::ofstream out(path);
    out << "scene,scene_no,dim,variant,median_ms,p90_ms,update_ms,walk_ms,buffer_ms,voxels,nodes,bricks,pvs,"
           "pvs_over_visible,misses,moc_ms,runs,vfc_ms\n";
    std::vector<std::string> scenes;
    for (const Row& r : rows) {
        if (std::find(scenes.begin(), scenes.end(), r.scene) == scenes.end()) scenes.push_back(r.scene);
        const std::size_t no = std::size_t(std::find(scenes.begin(), scenes.end(), r.scene) - scenes.begin());
        double vfcMs = -1;
        for (const Row& v : rows)
            if (v.scene == r.scene && v.variant == "vfc") vfcMs = v.medianMs;
        char buf[512];
        std::snprintf(buf, sizeof buf, "%s,%zu,%d,%s,%.4f,%.4f,%.4f,%.4f,%.4f,%.0f,%.0f,%.1f,%.2f,%.4f,%llu,%.3f,%d,%.4f\n",
                      r.scene.c_str(), no, r.dim, r.variant.c_str(), r.medianMs, r.p90Ms, r.updateMs, r.walkMs, r.bufferMs,
                      r.mean.voxels, r.mean.nodes, r.mean.bricks, r.mean.pvs, r.ratio, (unsigned long long)r.misses,
                      mocMs(r.scene), repeats, vfcMs);
        out << buf;
    }
    return bool(out);
}

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

void printTable() {
    std::printf("\n| scene | variant | median ms | p90 ms | voxels | nodes | empty | hidden | bricks | \\|PVS\\| | "
                "\\|PVS\\|/\\|visible\\| | misses |\n");
    std::printf("|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    for (const Row& r : g_rows) {
        auto three = [&](double v) { return r.hierarchical ? fmt("%.0f", v) : std::string("-"); };
        std::printf("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s%llu%s |\n", r.scene.c_str(),
                    r.variant.c_str(), fmt("%.3f", r.medianMs).c_str(), fmt("%.3f", r.p90Ms).c_str(),
                    fmt("%.0f", r.mean.voxels).c_str(), three(r.mean.nodes).c_str(), three(r.mean.empty).c_str(),
                    three(r.mean.hidden).c_str(), three(r.mean.bricks).c_str(), fmt("%.1f", r.mean.pvs).c_str(),
                    r.ratio < 0 ? "-" : fmt("%.3f", r.ratio).c_str(), r.misses ? "**" : "",
                    (unsigned long long)r.misses, r.misses ? "**" : "");
    }
}

/// The second table: each variant's frame cut into the scene update (placement queries, O, I and T
/// writes, TBV creation and renewal), the walk (the traversal or the brick walk with its image) and the
/// occlusion buffer's pass, with the update's counts: what a figure that misses its target is made of.
void printBreakdown() {
    std::printf("\nWhere the time goes (median ms of each part, so they need not add up to the median frame; "
                "counts are means per frame):\n\n");
    std::printf("| scene | variant | update ms | walk ms | buffer ms | placement queries | tracked | held by TBVs | "
                "TBVs created | renewed | revealed |\n");
    std::printf("|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    for (const Row& r : g_rows)
        std::printf("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", r.scene.c_str(), r.variant.c_str(),
                    fmt("%.3f", r.updateMs).c_str(), fmt("%.3f", r.walkMs).c_str(), fmt("%.3f", r.bufferMs).c_str(),
                    fmt("%.0f", r.mean.queries).c_str(), fmt("%.0f", r.mean.tracked).c_str(), fmt("%.0f", r.mean.hiddenObjects).c_str(),
                    fmt("%.1f", r.mean.created).c_str(), fmt("%.1f", r.mean.renewed).c_str(), fmt("%.1f", r.mean.revealed).c_str());
}

[[noreturn]] void usageError(const std::string& what) {
    std::fprintf(stderr,
                 "rgvc_bench_classes: %s (usage: rgvc_bench_classes [--scene NAME|all] [--frames N] "
                 "[--warmup W] [--ref-every K] [--quick] [--repeats R] [--csv FILE] [--plot FILE.png])\n",
                 what.c_str());
    std::exit(2);
}

int parseInt(const std::string& flag, const char* text, int minimum) {
    char* end = nullptr;
    const long v = std::strtol(text, &end, 10);
    if (end == text || *end != '\0' || v < minimum || v > 1000000)
        usageError(flag + " needs an integer >= " + std::to_string(minimum) + ", got '" + text + "'");
    return int(v);
}

const char* const kScenes[] = {"room-1k", "room-10k", "room-100k", "clusters", "game",    "large",
                               "empty",   "city3d",   "paper",     "city2d",   "random2d", "room2d",
                               "large2d", "empty2d"};

} // namespace

int main(int argc, char** argv) {
    Config cfg;
    std::string scene = "all";
    bool framesGiven = false, warmupGiven = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> const char* {
            if (i + 1 >= argc) usageError(a + " needs a value");
            return argv[++i];
        };
        if (a == "--scene") scene = value();
        else if (a == "--frames") cfg.frames = parseInt(a, value(), 1), framesGiven = true;
        else if (a == "--warmup") cfg.warmup = parseInt(a, value(), 0), warmupGiven = true;
        else if (a == "--ref-every") cfg.refEvery = parseInt(a, value(), 1);
        else if (a == "--no-reference") cfg.noReference = true;
        else if (a == "--quick") cfg.quick = true;
        else if (a == "--variant") cfg.variant = value();
        else if (a == "--repeats") cfg.repeats = parseInt(a, value(), 1);
        else if (a == "--csv") cfg.csv = value();
        else if (a == "--plot") cfg.plot = value();
        else if (a == "--voxel-size") {
            cfg.voxelSize = std::atof(value());
            if (!(cfg.voxelSize > 0) || !std::isfinite(cfg.voxelSize)) usageError("--voxel-size needs a positive number");
        }
        else if (a == "--help" || a == "-h") {
            std::printf("usage: rgvc_bench_classes [--scene NAME|all] [--frames N] [--warmup W] [--ref-every K] "
                        "[--no-reference] [--quick] [--variant NAME[,NAME...]] [--voxel-size V] [--repeats R] [--csv FILE] "
                        "[--plot FILE.png]\nscenes:");
            for (const char* s : kScenes)
                std::printf(" %s", s);
            std::printf("\n");
            return 0;
        } else usageError("unknown flag '" + a + "'");
    }
    if (scene != "all" && std::find_if(std::begin(kScenes), std::end(kScenes),
                                       [&](const char* s) { return scene == s; }) == std::end(kScenes))
        usageError("unknown scene '" + scene + "'");
    if (!cfg.plot.empty() && cfg.csv.empty()) usageError("--plot needs --csv (the plot is drawn from it)");
    if (cfg.quick) {
        if (!framesGiven) cfg.frames = 3;
        if (!warmupGiven) cfg.warmup = 1;
        if (cfg.refEvery == 0) cfg.refEvery = 1;
    }
    const bool q = cfg.quick;
    auto wanted = [&](const char* s) {
        if (scene == s) return true;
        return scene == "all" && !(q && (std::string(s) == "room-10k" || std::string(s) == "room-100k"));
    };

    std::printf("rgvc_bench_classes on %s, one thread; %d frames per scene (empty: at most 5) after %d warm-up%s; "
                "reference %s\n",
                machine().c_str(), cfg.frames, cfg.warmup, q ? "; --quick (small object counts)" : "",
                cfg.refEvery > 0 ? ("every " + std::to_string(cfg.refEvery) + " frames").c_str()
                                 : "on a subset of frames: ~3 s per scene, every K-th (K in the notes)");
    std::printf("variants (interleaved frame by frame on the same scene): 3D new = default options "
                "(hierarchical), old = hierarchical off, vfc = occlusion off (its |PVS| is |VFC|); 2D new (bricks), rings (hierarchical off), vfc\n");
    std::printf("times: CullStats::cullMs (wall, placement queries included); voxels/nodes/empty/hidden/bricks/|PVS|: "
                "means per frame\n\nscenes:\n");
    // Each scene is built only when wanted (the large ones take seconds and GiBs to set up), then run.
    auto run = [&](const char* name, auto&& make) {
        if (!wanted(name)) return;
        for (int r = 0; r < cfg.repeats; ++r) { // a fresh scene each run: the runs move it from frame 0
            if (cfg.repeats > 1 && g_progress) std::fprintf(stderr, "\r  %s: run %d of %d   ", name, r + 1, cfg.repeats);
            auto w = make();
            runScene(w, cfg);
        }
    };
    try {
        run("room-1k", [&] { return roomScene("room-1k", 1000); });
        run("room-10k", [&] { return roomScene("room-10k", 10000); });
        run("room-100k", [&] { return roomScene("room-100k", 100000); });
        run("clusters", [&] { return clustersScene(q ? 500 : 5000); });
        run("game", [&] { return gameScene(q ? 20 : 50, q ? 200 : 2000); });
        run("large", [&] { return largeScene(q ? 50 : 500); });
        run("empty", [&] {
            auto w = emptyScene(q ? 256 : 512); // 512^3: 13 s and 5 GiB to set up three cullers
            if (q) w.maxFrames = 2;
            return w;
        });
        run("city3d", [&] { return city3dScene(q ? 30 : 300); });
        run("paper", [&] { return paperScene(q ? 500 : 5000); });
        run("city2d", [&] { return city2dScene(q ? 30 : 200); });
        run("random2d", [&] { return random2dScene(q ? 100 : 300); });
        run("room2d", [&] { return room2dScene(q ? 100 : 1000); });
        run("large2d", [&] { return large2dScene(q ? 50 : 500); });
        run("empty2d", [&] { return large2dScene(0, "empty2d"); });
    } catch (const std::exception& e) {
        if (g_progress) std::fprintf(stderr, "\n");
        std::fprintf(stderr, "rgvc_bench_classes: %s\n", e.what());
        return 1;
    }
    if (cfg.repeats > 1) {
        g_rows = mergeRepeats(g_rows);
        std::printf("\n(each scene run %d times, fresh cullers each time: times are the median over the runs of each "
                    "run's median; counts and |PVS|/|visible| the mean over the runs)\n", cfg.repeats);
    }
    printTable();
    printBreakdown();
    if (!cfg.csv.empty()) {
        if (!writeCsv(cfg.csv, g_rows, cfg.repeats)) {
            std::fprintf(stderr, "rgvc_bench_classes: cannot write %s\n", cfg.csv.c_str());
            return 1;
        }
        std::printf("\nCSV: %s\n", cfg.csv.c_str());
    }
    if (!cfg.plot.empty()) {
        const PlotStatus ps = runGnuplot(RGVC_SOURCE_DIR "/scripts/plot_classes.gp", {{"csv", cfg.csv}, {"out", cfg.plot}});
        if (ps != PlotStatus::Drawn) {
            std::fprintf(stderr, "rgvc_bench_classes: no plot: %s\n", plotStatusText(ps));
            return 1;
        }
        std::printf("plot: %s\n", cfg.plot.c_str());
    }
    std::printf("\nreference notes:\n");
    for (const std::string& n : g_notes)
        std::printf("- %s\n", n.c_str());
    if (g_totalMisses > 0) {
        std::printf("\n*** %llu MISSES: some PVS lacks a visible object (must be 0) ***\n",
                    (unsigned long long)g_totalMisses);
        std::fprintf(stderr, "rgvc_bench_classes: *** %llu MISSES (must be 0); scenes written to /tmp ***\n",
                     (unsigned long long)g_totalMisses);
        return 1;
    }
    std::printf("\nmisses: 0\n");
    return 0;
}
