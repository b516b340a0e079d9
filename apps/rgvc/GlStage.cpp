// `rgvc cull --gl` (GlStage.hpp). With RGVC_WITH_GL the stage is the library's: OSMesa context,
// SceneRenderer, GlQueryDevice, ObjectBvh and ChcRenderer; without it every entry point says so.
#include "GlStage.hpp"

#include <chrono>
#include <stdexcept>

#ifdef RGVC_HAS_GL
#include "rgvc/render/Chc.hpp"
#include "rgvc/render/ObjectBvh.hpp"
#include "rgvc/render/gl/GlContext.hpp"
#include "rgvc/render/gl/GlQueryDevice.hpp"
#include "rgvc/render/gl/SceneRenderer.hpp"

#include <algorithm>
#include <unordered_map>
#endif

namespace rgvc::cli {

void GlStage::checkMethod(const std::string& method) {
    for (const char* m : {"chc", "chcpp", "sw", "vfc", "zb"})
        if (method == m) return;
    throw std::invalid_argument("--gl-method: must be one of chc, chcpp, sw, vfc, zb, got '" + method + "'");
}

#ifdef RGVC_HAS_GL

namespace {
CullMethod methodOf(const std::string& m) {
    if (m == "chc") return CullMethod::Chc;
    if (m == "sw") return CullMethod::StopAndWait;
    if (m == "vfc") return CullMethod::Vfc;
    if (m == "zb") return CullMethod::Zb;
    return CullMethod::ChcPlusPlus;
}
} // namespace

struct GlStage::Impl {
    GlStageArgs args;
    std::unique_ptr<GlContext> context;
    std::unique_ptr<SceneRenderer> renderer;
    std::unique_ptr<GlQueryDevice> device;
    ObjectBvh bvh;
    std::unique_ptr<ChcRenderer> chc;
    std::unordered_map<ObjectId, Box<3>> bounds; // last bounds given to the hierarchy
    std::vector<BvhItem> pending;                // objects added before the hierarchy is built
    std::vector<ObjectId> pvs;
};

bool GlStage::available() { return true; }

GlStage::GlStage(const GlStageArgs& args) : m_impl(std::make_unique<Impl>()) {
    Impl& m = *m_impl;
    m.args = args;
    m.context = createOsMesaContext(args.width, args.height);
    m.renderer = std::make_unique<SceneRenderer>(*m.context);
    m.device = std::make_unique<GlQueryDevice>(*m.renderer, args.width, args.height);
}

GlStage::~GlStage() = default;

double GlStage::occluderInset(const Shape<3>& shape) const { return m_impl->renderer->occluderInset(shape); }

void GlStage::setObject(ObjectId id, const Shape<3>& shape) {
    Impl& m = *m_impl;
    m.renderer->setObject(id, shape);
    const Box<3> b = boundsOf<3>(shape);
    auto it = m.bounds.find(id);
    if (it == m.bounds.end()) {
        m.bounds.emplace(id, b);
        if (m.chc) m.bvh.insert(id, b);
        else m.pending.push_back({id, b});
    } else if (it->second.min != b.min || it->second.max != b.max) {
        it->second = b;
        if (m.chc) m.bvh.update(id, b);
        else
            for (BvhItem& p : m.pending)
                if (p.id == id) p.bounds = b;
    }
}

const std::vector<ObjectId>& GlStage::frame(const Camera3& camera, std::span<const ObjectId> cpuPvs,
                                            nlohmann::ordered_json& stats) {
    Impl& m = *m_impl;
    if (!m.chc) {
        m.bvh.build(m.pending);
        m.pending.clear();
        // A PVS of 32 objects or fewer is drawn without queries (ChcOptions::queryMinCandidates).
        m.chc = std::make_unique<ChcRenderer>(*m.device, m.bvh,
                                              ChcOptions{.visiblePixelThreshold = m.args.visiblePixels,
                                                         .assumedVisibleFrames = m.args.assumedVisibleFrames,
                                                         .queryMinCandidates = 32});
    } else {
        m.bvh.rebuildIfDegraded();
    }
    const GlQueryStats before = m.device->stats();
    const std::uint64_t trianglesBefore = m.renderer->stats().trianglesDrawn;
    const auto t0 = std::chrono::steady_clock::now();
    const ChcFrameStats& s = m.chc->render(camera, methodOf(m.args.method), cpuPvs);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const GlQueryStats& after = m.device->stats();
    m.pvs.assign(s.drawn.begin(), s.drawn.end());
    std::sort(m.pvs.begin(), m.pvs.end());
    m.pvs.erase(std::unique(m.pvs.begin(), m.pvs.end()), m.pvs.end());

    stats["cpu_pvs_size"] = cpuPvs.size();
    stats["pvs_size"] = m.pvs.size();
    stats["gl_method"] = cullMethodName(s.method);
    stats["gl_size"] = std::to_string(m.args.width) + "x" + std::to_string(m.args.height);
    stats["gl_ms"] = ms;
    stats["gl_wait_ms"] = after.waitMs - before.waitMs;
    stats["gl_finish_ms"] = after.finishMs - before.finishMs;
    stats["gl_queries"] = s.queries();
    stats["gl_single_queries"] = s.singleQueries;
    stats["gl_multi_queries"] = s.multiQueries;
    stats["gl_results_waited"] = after.resultsWaited - before.resultsWaited;
    stats["gl_nodes_traversed"] = s.nodesTraversed;
    stats["gl_objects_drawn"] = s.objectsDrawn;
    stats["gl_draw_calls"] = s.drawCalls;
    stats["gl_triangles_drawn"] = m.renderer->stats().trianglesDrawn - trianglesBefore;
    stats["gl_submit_ms"] = ms - (after.finishMs - before.finishMs); // traversal and submission, without glFinish
    stats["gl_approximate"] = s.approximate;
    stats["gl_queries_skipped"] = s.queriesSkipped;
    stats["gl_context"] = m.context->description();
    return m.pvs;
}

#else // no GL stage in this build

struct GlStage::Impl {};

bool GlStage::available() { return false; }
GlStage::GlStage(const GlStageArgs&) { throw std::runtime_error("--gl: this rgvc was built without RGVC_WITH_GL"); }
GlStage::~GlStage() = default;
double GlStage::occluderInset(const Shape<3>&) const { return 0; }
void GlStage::setObject(ObjectId, const Shape<3>&) {}
const std::vector<ObjectId>& GlStage::frame(const Camera3&, std::span<const ObjectId>, nlohmann::ordered_json&) {
    static const std::vector<ObjectId> none;
    return none;
}

#endif

} // namespace rgvc::cli
