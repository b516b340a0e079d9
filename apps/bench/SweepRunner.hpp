// rgvc_sweep's runner: one scene file, every setting (SweepSettings.hpp), the same frames for each.
//
// Per scene: a reference pass walks the scene's motion and camera path once and keeps, for every K-th
// measured frame, the exact visible set (BenchReference.hpp: tests/reference, 2D exact, 3D at 128 grid and
// 8 target divisions) and, in 3D with drawing on, the item buffer of all objects at the GL stage's
// resolution (the pixel-level set the GL stage's answer must contain, scene-format.md `--gl`). Then each
// setting runs the same frames from frame 0 with a fresh culler (the scene's voxel size times
// voxelScale, same world box) and, with drawing, a fresh ObjectBvh and ChcRenderer over one shared
// SceneRenderer and GlQueryDevice (OSMesa): frame time = cull() + the GL method over the CPU PVS + glFinish.
//
// What is counted on the checked frames: misses, against the exact set for a CPU answer and against the
// item buffer for the answer of a GL query method (a pixel-level answer; it may rightly leave out an
// object that covers no pixel centre); |answer| / |exact visible|, averaged over the frames where
// something is visible and the camera is not inside an object (the reference then sees that object only).
// Times: medians over the measured frames (after the warm-up), wall clock (CullStats::cullMs for the cull).
#pragma once

#include "SweepSettings.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace rgvc::bench {

struct SweepConfig {
    int frames = 40;    ///< [Frames] measured per setting (fewer when the camera path is shorter)
    int warmup = 5;     ///< [Frames] run first, not measured
    int refFrames = 8;  ///< [Frames] checked against the references per scene (every K-th measured frame)
    bool draw = true;   ///< GL drawing (OSMesa); false: cull times only, no GL settings
    int glWidth = 480, glHeight = 270; ///< [Pixels] the GL stage's image and the item buffer's
    bool quick = false;
};

struct SweepRow {
    std::string scene; ///< file stem
    int dims = 3;
    SweepSetting setting;
    double voxelSize = 1;
    std::string grid;                 ///< "96x24x96"
    double medianCullMs = 0, p90CullMs = 0;
    double medianFrameMs = -1;        ///< -1: not drawn
    double meanAnswer = 0;            ///< mean |answer| over the measured frames
    double meanVisible = 0;           ///< mean |exact visible| over the checked frames
    double ratio = -1;                ///< mean |answer| / |visible| (-1: no frame counted)
    std::uint64_t misses = 0;
    std::string missReference;        ///< "exact" or "item buffer WxH"
    int checkedFrames = 0, countedFrames = 0;
    bool pareto = false;              ///< on its scene's Pareto front (time against ratio, 0 misses, conservative)
};

/// The GL stage shared by all scenes: one OSMesa context, renderer and query device.
class SweepGl {
public:
    /// @throws GlError when no context can be made.
    SweepGl(int width, int height);
    ~SweepGl();
    const std::string& description() const;
    struct Impl;
    Impl& impl() { return *m_impl; }

private:
    std::unique_ptr<Impl> m_impl;
};

/// progress(setting index, settings, frame, frames, setting name)
using SweepProgress = std::function<void(int, int, int, int, const std::string&)>;

/// Runs every setting on the scene file. `gl` may be null (no drawing). Notes (one line each: the scene,
/// its frames, its reference cost) go to `notes`.
/// @throws SceneError for a bad file, InvalidInput / GlError from the library.
std::vector<SweepRow> runSweepScene(const std::string& path, const SweepConfig& cfg, SweepGl* gl,
                                    const SweepProgress& progress, std::vector<std::string>& notes);

} // namespace rgvc::bench
