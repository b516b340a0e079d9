// `rgvc cull --gl`: the GL occlusion-query stage after the CPU pipeline (scene-format.md, `rgvc cull`).
//
// Headless (OSMesa). Every object of the scene is held by a SceneRenderer (balls as inscribed icospheres,
// boxes exactly) and by a persistent ObjectBvh (their boxes, refitted when they move); each frame the
// CPU culler's PVS is the candidate set of a ChcRenderer frame (CHC++ by default), and the objects it
// draws are the frame's `pvs`. Why that answer keeps the contract ("every object that shows a pixel in an
// image of all objects" at the --gl-size resolution): the CPU culler runs with each ball's occluder
// inset to the drawn mesh's inradius (ObjectDesc::occluderInset), so it hides nothing that the drawn
// meshes leave visible, and CHC with n_vp = 0 culls a node only when the depth of drawn objects hides its
// box, which contains what is drawn for it.
//
// Built only with RGVC_WITH_GL; without it `available()` is false and the CLI says so.
#pragma once

#include "rgvc/dynamics/Culler.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace rgvc::cli {

struct GlStageArgs {
    bool enabled = false;
    std::string method = "chcpp"; ///< chc, chcpp, sw, vfc, zb
    int width = 640, height = 480; ///< [Pixels]
    std::uint64_t visiblePixels = 0; ///< n_vp ([Samples]; > 0 is approximate: stats.gl_approximate)
    int assumedVisibleFrames = 0;    ///< t_av ([Frames])
};

class GlStage {
public:
    /// Whether this binary has the GL stage.
    static bool available();
    /// Validates the method name (throws std::invalid_argument with a one-line message).
    static void checkMethod(const std::string& method);
    /// Makes the context and the renderer. @throws GlError (no context, bad size) or std::runtime_error.
    explicit GlStage(const GlStageArgs& args);
    ~GlStage();
    GlStage(const GlStage&) = delete;
    GlStage& operator=(const GlStage&) = delete;

    /// [World units] the occluder inset that puts the shape's occluder inside what is drawn for it
    /// (SceneRenderer::occluderInset: a ball's mesh inradius, with float rounding).
    double occluderInset(const Shape<3>& shape) const;
    /// Adds or moves an object (before the first frame: all of them; then the moved ones).
    void setObject(ObjectId id, const Shape<3>& shape);
    /// Renders one frame over the CPU's PVS; returns the GL answer (sorted ids) and adds its figures
    /// to `stats` (gl_method, gl_ms, queries, ...).
    const std::vector<ObjectId>& frame(const Camera3& camera, std::span<const ObjectId> cpuPvs, nlohmann::ordered_json& stats);

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

} // namespace rgvc::cli
