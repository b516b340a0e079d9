// GlWalk: the GL stage's culling methods compared on one scene, frame by frame, in one OSMesa context
// (shared by rgvc_bench_gl and rgvc_bench3d --figure).
//
//   rgvc::bench::GlWalk walk(objects, parseGlMethods("zb,vfc,rgvc", grid), {.width = 640, .height = 480});
//   for (int f = 0; f < frames; ++f) { step the scene; walk.moveObjects(moved); walk.frame(camera); }
//   walk.printSummary(stdout);  walk.writeCsvRows(out, "5b,");
//
// A frame first renders the item buffer of every object (untimed: it is the reference, and it also sends
// the frame's moved instances to the GPU, so no method pays for the uploads), then runs every method, the
// order rotating frame by frame so that none always runs first (caches, the driver's state). A method's
// frame time is cull + draw + glFinish ([Milliseconds], wall time: steady_clock around the grid's cull and
// ChcRenderer::render, whose endFrame calls glFinish). Every method must draw every object the item buffer
// shows: the others are misses, counted per frame (they must be 0; the benchmarks exit 1 otherwise).
//
// Methods (seed 001 §6.2's comparison, with the grid stage of seed 004 in front):
//   zb        draw every object           vfc       hierarchical view-frustum culling (object BVH)
//   rgvc      the grid culler's PVS, drawn as is
//   rgvc+chc  the grid culler's PVS refined by CHC++ queries
//   chc       CHC++ over every object     sw        hierarchical stop-and-wait over every object
//   ideal     exactly the objects the item buffer shows (found untimed, then drawn and timed)
// The grid cullers get each ball's occluder inset to the drawn mesh (apps/rgvc/GlStage.hpp's reason).
#pragma once

#include "RandomScenes3D.hpp"

#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/render/Chc.hpp"
#include "rgvc/render/ObjectBvh.hpp"
#include "rgvc/render/gl/GlContext.hpp"
#include "rgvc/render/gl/GlQueryDevice.hpp"
#include "rgvc/render/gl/SceneRenderer.hpp"

#include <cstdint>
#include <cstdio>
#include <memory>
#include <ostream>
#include <span>
#include <string>
#include <vector>

namespace rgvc::bench {

/// One method of the comparison.
struct GlMethodSpec {
    std::string name;                 ///< label in tables and CSV rows ("rgvc", "rgvc-50x30x50", ...)
    CullMethod gl = CullMethod::Zb;   ///< what the GL stage does with the candidates
    bool grid = false;                ///< candidates: the grid culler's PVS (else every object)
    bool ideal = false;               ///< candidates: the item buffer's visible set
    GridGeometry3 geometry{};         ///< the grid culler's grid (grid methods only)
    CullerOptions culler{};           ///< its options (grid methods only)
};

/// The method called `name` (zb, vfc, rgvc, rgvc+chc, chc, sw, ideal); grid methods cull on `geometry`.
/// `label` replaces the name in tables and CSV rows when not empty.
/// @throws std::invalid_argument "unknown method 'x'".
GlMethodSpec glMethod(const std::string& name, const GridGeometry3& geometry, const std::string& label = {});
/// A comma-separated list of method names, each kept once in the order given.
/// @throws std::invalid_argument for an unknown name or an empty list.
std::vector<GlMethodSpec> parseGlMethods(const std::string& list, const GridGeometry3& geometry);

/// The paper's walkthrough scene (seed 004 §6, Figure 5 centre and right): reference::movingSpheres3D's
/// `spheres` clustered spheres (seed 7) in 100 x 60 x 100 units, the first `statics` of them made static
/// (velocity 0, isStatic), the others moving up to 0.5 unit per frame. Walk it with
/// reference::movingSpheresCamera and step it with reference::stepMovingSpheres.
reference::MovingSpheres3D paperWalkScene(int spheres, int statics);

/// "50x30x50".
std::string resolutionLabel(const GridGeometry3& g);

struct GlWalkOptions {
    int width = 640, height = 480;   ///< [Pixels] every method's target and the item buffer's. [Limit] 1..16384.
    SceneRendererOptions renderer{}; ///< the sphere mesh, among others
    /// The GL stage's options (CHC++'s batching, ...): the benchmark default skips queries for PVSs of
    /// at most 32 objects (ChcOptions::queryMinCandidates).
    ChcOptions chc{.queryMinCandidates = 32};
};

/// What one method recorded, one entry per frame.
struct GlMethodRecord {
    GlMethodSpec spec;
    std::unique_ptr<Culler3D> culler; ///< grid methods
    std::unique_ptr<ChcRenderer> chc;
    std::vector<double> ms, cullMs;   ///< [Milliseconds] frame time; of it, the grid's cull (CullStats::cullMs)
    std::vector<std::uint32_t> queries, drawn, candidates, misses;
    std::uint64_t totalMisses = 0;
};

class GlWalk {
public:
    /// Makes the OSMesa context (options.width x options.height), the renderer, the query device, the
    /// object BVH and one grid culler per grid method, and adds `objects` to all of them.
    /// @throws GlError (no GL 4.5 context), InvalidInput (a bad object or option).
    GlWalk(const std::vector<ObjectDesc<3>>& objects, std::vector<GlMethodSpec> methods, const GlWalkOptions& options = {});
    ~GlWalk();
    GlWalk(const GlWalk&) = delete;
    GlWalk& operator=(const GlWalk&) = delete;

    /// Moves (or reshapes) `moved`, already added, in the renderer, the BVH (refitted; rebuilt when it
    /// degraded) and every grid culler (updateObject: O(1) for a hidden object inside its TBV).
    void moveObjects(std::span<const ObjectDesc<3>> moved);
    /// One frame seen from `camera`: the item buffer, then every method (see the top of this file).
    void frame(const Camera3& camera);

    /// Forgets every frame recorded so far (warm-up frames), keeping the cullers' and CHC's state.
    void clearRecords();
    /// Frames recorded.
    int frames() const { return int(m_visible.size()); }
    const std::vector<GlMethodRecord>& methods() const { return m_methods; }
    /// The record of the method labelled `name`, nullptr if none.
    const GlMethodRecord* method(const std::string& name) const;
    /// The grid culler of the method labelled `name` (its state after the last frame), nullptr if none.
    const Culler3D* culler(const std::string& name) const;
    /// Per frame: how many objects the item buffer showed.
    const std::vector<std::uint32_t>& visibleCounts() const { return m_visible; }
    /// The last frame's item buffer (the exact visible set at the target's resolution).
    const std::vector<ObjectId>& lastVisible() const { return m_lastVisible; }
    /// Misses of every method over every frame (must be 0).
    std::uint64_t totalMisses() const;

    /// The summary table (Markdown): per method the median and 95th-percentile frame time, the
    /// speed-up over ZB (when ZB ran), the grid's median cull time, queries and objects drawn per frame,
    /// mean |PVS| / mean |visible| (candidates for the grid alone, drawn otherwise) and the misses.
    void printSummary(std::FILE* out) const;
    /// CSV rows, one per frame and method, method by method: `prefix` then
    /// frame,method,frame_ms,cull_ms,queries,drawn,candidates,visible,misses (see csvHeader()).
    void writeCsvRows(std::ostream& out, const std::string& prefix) const;
    static const char* csvHeader() { return "frame,method,frame_ms,cull_ms,queries,drawn,candidates,visible,misses"; }

    GlContext& context() { return *m_context; }
    SceneRenderer& renderer() { return *m_renderer; }
    const GlWalkOptions& options() const { return m_options; }

private:
    GlWalkOptions m_options;
    std::unique_ptr<GlContext> m_context;
    std::unique_ptr<SceneRenderer> m_renderer;
    std::unique_ptr<GlQueryDevice> m_device;
    ObjectBvh m_bvh;
    std::vector<GlMethodRecord> m_methods;
    std::vector<std::uint32_t> m_visible;
    std::vector<ObjectId> m_lastVisible, m_drawnScratch;
};

} // namespace rgvc::bench
