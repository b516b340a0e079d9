// rgvc_sweep's runner (SweepRunner.hpp).
#include "SweepRunner.hpp"

#include "BenchReference.hpp"
#include "BenchSupport.hpp"

#include "SceneFile.hpp"
#include "SceneMotion.hpp"

#include "rgvc/render/Chc.hpp"
#include "rgvc/render/ObjectBvh.hpp"
#include "rgvc/render/gl/GlContext.hpp"
#include "rgvc/render/gl/GlQueryDevice.hpp"
#include "rgvc/render/gl/ItemBuffer.hpp"
#include "rgvc/render/gl/SceneRenderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>

namespace rgvc::bench {

struct SweepGl::Impl {
    std::unique_ptr<GlContext> context;
    std::unique_ptr<SceneRenderer> renderer;
    std::unique_ptr<GlQueryDevice> device;
    int width = 0, height = 0;
};

SweepGl::SweepGl(int width, int height) : m_impl(std::make_unique<Impl>()) {
    m_impl->width = width;
    m_impl->height = height;
    m_impl->context = createOsMesaContext(width, height);
    m_impl->renderer = std::make_unique<SceneRenderer>(*m_impl->context);
    m_impl->device = std::make_unique<GlQueryDevice>(*m_impl->renderer, width, height);
}

SweepGl::~SweepGl() {
    // GL objects go before their context.
    m_impl->device.reset();
    m_impl->renderer.reset();
}

const std::string& SweepGl::description() const { return m_impl->context->description(); }

namespace {

// 2D scenes are drawn as prisms over world y in [0, kPrismHeight], seen from the camera's 2D position at
// half that height looking level (SceneRenderer.hpp: 2D x -> world x, 2D y -> world z): the horizontal
// fov is the 2D view's, the vertical kPrismViewFovDeg.
constexpr double kPrismHeight = 2, kPrismViewFovDeg = 30;
constexpr double kPi = 3.14159265358979323846;

void place(SceneRenderer& r, ObjectId id, const Shape<3>& s) { r.setObject(id, s); }
void place(SceneRenderer& r, ObjectId id, const Shape<2>& s) { r.setPrism(id, s, 0, kPrismHeight); }

Box<3> bounds3(const Shape<3>& s) { return boundsOf<3>(s); }
Box<3> bounds3(const Shape<2>& s) {
    const Box<2> b = boundsOf<2>(s);
    return {{b.min.x, 0, b.min.y}, {b.max.x, kPrismHeight, b.max.y}};
}

/// The 3D camera that draws a 2D view; nullopt when the 2D fov is too wide for a perspective image.
std::optional<Camera3> drawingCamera(const Camera2& c) {
    if (c.fovDeg >= 170) return std::nullopt;
    Camera3 k;
    k.position = {c.position.x, kPrismHeight / 2, c.position.y};
    k.direction = {c.direction.x, 0, c.direction.y};
    k.fovDeg = kPrismViewFovDeg;
    k.aspect = std::tan(c.fovDeg * kPi / 360) / std::tan(kPrismViewFovDeg * kPi / 360);
    k.far = c.far;
    return k;
}
std::optional<Camera3> drawingCamera(const Camera3& c) { return c; }

CullMethod methodOf(const std::string& m) {
    if (m == "vfc") return CullMethod::Vfc;
    if (m == "sw") return CullMethod::StopAndWait;
    if (m == "chc") return CullMethod::Chc;
    if (m == "chcpp") return CullMethod::ChcPlusPlus;
    return CullMethod::Zb;
}

template <int D> GridGeometry<D> scaledGrid(const GridGeometry<D>& g, double k) {
    if (k == 1) return g;
    const double d = g.voxelSize() * k;
    IVec<D> res;
    for (int a = 0; a < D; ++a)
        res[a] = std::max(1, int(std::ceil(g.voxelSize() * g.resolution()[a] / d - 1e-9)));
    return GridGeometry<D>(g.origin(), d, res);
}

template <int D> std::string gridText(const GridGeometry<D>& g) {
    std::string s = std::to_string(g.resolution()[0]);
    for (int k = 1; k < D; ++k) { // appended in two steps: "x" + to_string made GCC 12 warn (-Wrestrict, a false positive)
        s += 'x';
        s += std::to_string(g.resolution()[k]);
    }
    return s;
}

struct FrameReference {
    bool checked = false;
    std::vector<ObjectId> exact;  ///< sorted
    std::vector<ObjectId> pixels; ///< item buffer, sorted (3D with drawing)
    bool counted = false;         ///< something visible, camera outside every object
};

template <int D> std::vector<ObjectDesc<D>> currentObjects(const SceneSimulator<D>& sim) {
    std::vector<ObjectDesc<D>> out(sim.size());
    for (std::size_t i = 0; i < sim.size(); ++i) {
        out[i].id = sim.idAt(i);
        out[i].shape = sim.shapeAt(i);
    }
    return out;
}

std::uint64_t missesIn(const std::vector<ObjectId>& mustHave, const std::vector<ObjectId>& sortedAnswer) {
    std::uint64_t n = 0;
    for (ObjectId id : mustHave) n += !std::binary_search(sortedAnswer.begin(), sortedAnswer.end(), id);
    return n;
}

template <int D>
std::vector<SweepRow> runScene(const std::string& name, const SceneData<D>& data, const SweepConfig& cfg, SweepGl* gl,
                               const SweepProgress& progress, std::vector<std::string>& notes) {
    const std::size_t limit = data.frameLimit();
    const int warmup = int(std::min<std::size_t>(std::size_t(cfg.warmup), limit > 1 ? limit - 1 : 0));
    const int frames = int(std::min<std::size_t>(std::size_t(cfg.frames), limit - std::size_t(warmup)));
    const int total = warmup + frames;
    const int every = std::max(1, frames / std::max(1, cfg.refFrames));
    SweepGl::Impl* g = gl ? &gl->impl() : nullptr;
    const bool pixelReference = g && D == 3;
    const std::string pixelName =
        g ? "item buffer " + std::to_string(g->width) + "x" + std::to_string(g->height) : std::string();

    // The reference pass.
    std::vector<FrameReference> refs(static_cast<std::size_t>(total));
    double refMs = 0, visibleSum = 0;
    int checked = 0;
    {
        SceneSimulator<D> sim(data);
        if (pixelReference)
            for (std::size_t i = 0; i < sim.size(); ++i) place(*g->renderer, sim.idAt(i), sim.shapeAt(i));
        for (int f = 0; f < total; ++f) {
            if (f > 0) {
                sim.step();
                if (pixelReference)
                    for (std::size_t i = 0; i < sim.size(); ++i)
                        if (sim.movedAt(i)) place(*g->renderer, sim.idAt(i), sim.shapeAt(i));
            }
            const int m = f - warmup;
            if (m < 0 || m % every != 0) continue;
            FrameReference& fr = refs[std::size_t(f)];
            const Camera<D> cam = data.cameraAt(std::size_t(f));
            const auto t0 = std::chrono::steady_clock::now();
            const std::vector<ObjectDesc<D>> objects = currentObjects(sim);
            const Reference r = referenceOf(objects, cam);
            refMs += msSince(t0);
            fr.checked = true;
            for (std::size_t i = 0; i < objects.size(); ++i)
                if (r.visible[i]) fr.exact.push_back(objects[i].id);
            std::sort(fr.exact.begin(), fr.exact.end());
            fr.counted = r.count > 0 && !r.cameraInsideObject;
            visibleSum += double(r.count);
            ++checked;
            if constexpr (D == 3)
                if (pixelReference) fr.pixels = itemBuffer(*g->renderer, cam, g->width, g->height).visible;
            progress(0, 0, checked, (frames + every - 1) / every, "reference");
        }
    }
    {
        char buf[512];
        std::snprintf(buf, sizeof buf,
                      "%s: %dD grid %s (voxel %g), %zu objects, %d frames after %d warm-up; reference on %d frames "
                      "(every %d), %.0f ms per frame, mean |visible| %.1f",
                      name.c_str(), D, gridText(data.grid).c_str(), data.grid.voxelSize(), data.objects.size(), frames,
                      warmup, checked, every, refMs / std::max(1, checked), visibleSum / std::max(1, checked));
        notes.emplace_back(buf);
    }

    std::vector<SweepSetting> settings = sweepSettings(D, cfg.quick);
    if (!g) std::erase_if(settings, [](const SweepSetting& s) { return s.glMethod != "zb"; });
    std::vector<SweepRow> rows;
    const bool stays = motionStaysInGrid(data);
    for (std::size_t si = 0; si < settings.size(); ++si) {
        const SweepSetting& s = settings[si];
        CullerOptions options = s.options;
        options.objectsStayInGrid = stays;
        const GridGeometry<D> grid = scaledGrid(data.grid, s.voxelScale);
        Culler<D> culler(grid, options);
        const bool queries = s.queries() && D == 3 && g;
        for (const SceneObject<D>& o : data.objects) {
            ObjectDesc<D> desc = o.desc();
            // The GL stage's rule (GlStage.hpp): with queries, the culler's occluders lie inside what is drawn.
            if constexpr (D == 3)
                if (queries) desc.occluderInset = g->renderer->occluderInset(desc.shape);
            culler.addObject(desc);
        }
        SceneSimulator<D> sim(data);
        ObjectBvh bvh;
        std::unique_ptr<ChcRenderer> chc;
        if (g) {
            std::vector<BvhItem> items;
            for (std::size_t i = 0; i < sim.size(); ++i) {
                place(*g->renderer, sim.idAt(i), sim.shapeAt(i));
                items.push_back({sim.idAt(i), bounds3(sim.shapeAt(i))});
            }
            bvh.build(items);
            // A PVS of 32 objects or fewer is drawn without queries, as `rgvc cull --gl` does.
            chc = std::make_unique<ChcRenderer>(*g->device, bvh,
                                                ChcOptions{.visiblePixelThreshold = s.visiblePixels, .queryMinCandidates = 32});
        }
        const PlacementQuery<D> placementOf = [&sim](ObjectId id) { return sim.shape(id); };
        std::vector<double> cullMs, frameMs;
        std::vector<ObjectId> answer;
        SweepRow row;
        row.scene = name;
        row.dims = D;
        row.setting = s;
        row.voxelSize = grid.voxelSize();
        row.grid = gridText(grid);
        row.missReference = queries ? pixelName : "exact";
        double answerSum = 0, ratioSum = 0;
        for (int f = 0; f < total; ++f) {
            if (f > 0) {
                sim.step();
                if (g) {
                    for (std::size_t i = 0; i < sim.size(); ++i)
                        if (sim.movedAt(i)) {
                            place(*g->renderer, sim.idAt(i), sim.shapeAt(i));
                            bvh.update(sim.idAt(i), bounds3(sim.shapeAt(i)));
                        }
                    bvh.rebuildIfDegraded();
                }
            }
            const Camera<D> cam = data.cameraAt(std::size_t(f));
            const auto t0 = std::chrono::steady_clock::now();
            const CullResult& r = culler.cull(cam, placementOf);
            const double cull = r.stats.cullMs;
            if (g) {
                if (const std::optional<Camera3> c3 = drawingCamera(cam)) {
                    const ChcFrameStats& st = chc->render(*c3, methodOf(queries ? s.glMethod : "zb"), r.pvs);
                    if (queries) {
                        answer = st.drawn;
                        std::sort(answer.begin(), answer.end());
                        answer.erase(std::unique(answer.begin(), answer.end()), answer.end());
                    }
                }
            }
            const double frame = msSince(t0);
            if (!queries) answer = r.pvs;
            const int m = f - warmup;
            if (f % 5 == 0 || f + 1 == total) progress(int(si) + 1, int(settings.size()), f + 1, total, s.name);
            if (m < 0) continue;
            cullMs.push_back(cull);
            frameMs.push_back(frame);
            answerSum += double(answer.size());
            const FrameReference& fr = refs[std::size_t(f)];
            if (!fr.checked) continue;
            ++row.checkedFrames;
            row.misses += missesIn(queries ? fr.pixels : fr.exact, answer);
            if (fr.counted) {
                ++row.countedFrames;
                ratioSum += double(answer.size()) / double(fr.exact.size());
            }
        }
        row.medianCullMs = percentile(cullMs, 0.5);
        row.p90CullMs = percentile(cullMs, 0.9);
        row.medianFrameMs = g ? percentile(frameMs, 0.5) : -1;
        row.meanAnswer = answerSum / std::max<std::size_t>(1, cullMs.size());
        row.meanVisible = visibleSum / std::max(1, checked);
        row.ratio = row.countedFrames > 0 ? ratioSum / row.countedFrames : -1;
        rows.push_back(row);
    }
    return rows;
}

} // namespace

std::vector<SweepRow> runSweepScene(const std::string& path, const SweepConfig& cfg, SweepGl* gl,
                                    const SweepProgress& progress, std::vector<std::string>& notes) {
    const Scene scene = loadScene(path);
    const std::string name = std::filesystem::path(path).stem().string();
    if (const SceneData<2>* d = scene.as<2>()) return runScene<2>(name, *d, cfg, gl, progress, notes);
    return runScene<3>(name, *scene.as<3>(), cfg, gl, progress, notes);
}

} // namespace rgvc::bench
