// Occluder extension in 2D (seed 004 §4.3, after Schaufler et al.'s blocker extension).
//
// Starting from an opaque voxel met by the traversal, aggregate neighbouring voxels that are opaque or
// occluded into a larger *virtual occluder*. Using occluded voxels is sound: every point of an occluded
// voxel is already hidden from the whole camera voxel, so any ray that touches one is blocked before it.
//
// The paper's extension is an L: one straight run, then a perpendicular run from one of its ends, the
// directions chosen from where the camera is (its Figure 4). We use the same two kinds of step, chosen
// so that each step widens the occluder's angular extent as seen from the camera:
//   1. the primary run through the start voxel, across the line of sight: along y when the start voxel
//      lies on a side of its ring where |dx| >= |dy| (that side is a column), else along x;
//      if that run is a single voxel, the other axis is tried instead;
//   2. at each end E of the primary run, an arm along the other axis, in the direction that moves
//      angularly *away* from the run (the side of ray C->E opposite to the run's other end). An arm that
//      would turn back into the run's angular range adds no occlusion and is not taken.
// This is the L at both ends (a "U" or "Z" when both arms exist). Each run is straight and axis-aligned,
// which is what OcclusionShadow2D's from-region argument needs, so each run casts its own shadow. An arm
// shares its first voxel K with the primary run, and when the two lie on opposite sides of the ray from
// the camera through K their open shadows meet exactly on that ray; the traversal then adds the ray past
// K (OcclusionShadow2D::cornerRay, which derives why that is hidden from the whole camera voxel), so the
// extended occluder's shadow is one region. Arms on the same side of that ray overlap in angle instead.
#pragma once

#include "rgvc/grid/Math.hpp"

#include <cstdint>
#include <cstdlib>

namespace rgvc {

/// Axis-aligned run of voxels from a to b, inclusive.
struct VoxelRun2D {
    IVec2 a{0}, b{0};
    std::int32_t length() const { return std::abs(b.x - a.x) + std::abs(b.y - a.y) + 1; }
};

namespace extension_detail {
template <class IsBlocker>
IVec2 walk(const IVec2& from, const IVec2& step, std::int32_t maxSteps, IsBlocker& isBlocker) {
    IVec2 end = from;
    for (std::int32_t i = 0; i < maxSteps; ++i) {
        IVec2 next = end + step;
        if (!isBlocker(next)) break;
        end = next;
    }
    return end;
}
inline int sign(std::int64_t v) { return (v > 0) - (v < 0); }
} // namespace extension_detail

/// Extends the occluder that starts at voxel `start`, seen from the camera voxel `camera`.
/// @param isBlocker  bool(IVec2): voxel is in the grid and opaque (or occluded, when extension uses H).
/// @param withArms   false: the primary run only (no L arms).
/// @param maxRun     [Voxels] cap on each walk, bounding the cost of one extension.
/// @param out        receives up to 3 runs: the primary run first, then the arms.
/// @return the number of runs written (0 when no run longer than one voxel exists).
template <class IsBlocker>
int extendOccluder2D(const IVec2& camera, const IVec2& start, IsBlocker&& isBlocker, bool withArms,
                     std::int32_t maxRun, VoxelRun2D out[3]) {
    using namespace extension_detail;
    const IVec2 d = start - camera;
    IVec2 axis = std::abs(d.x) >= std::abs(d.y) ? IVec2{0, 1} : IVec2{1, 0};
    VoxelRun2D primary{walk(start, -axis, maxRun, isBlocker), walk(start, axis, maxRun, isBlocker)};
    if (primary.length() == 1) {
        axis = IVec2{axis.y, axis.x};
        primary = {walk(start, -axis, maxRun, isBlocker), walk(start, axis, maxRun, isBlocker)};
        if (primary.length() == 1) return 0;
    }
    int n = 0;
    out[n++] = primary;
    if (!withArms) return n;

    const IVec2 across{axis.y, axis.x};
    const IVec2 ends[2][2] = {{primary.a, primary.b}, {primary.b, primary.a}};
    for (const auto& e : ends) {
        const IVec2 end = e[0], other = e[1];
        const int runSide = sign(cross2(end - camera, other - camera));
        const int acrossSide = sign(cross2(end - camera, across));
        if (runSide == 0 || acrossSide == 0) continue;
        // Step s*across lands on the side of ray C->end opposite to the run: sign(s * acrossSide) = -runSide.
        const IVec2 step = (acrossSide == runSide) ? -across : across;
        IVec2 armEnd = walk(end, step, maxRun, isBlocker);
        if (armEnd != end) out[n++] = {end, armEnd};
    }
    return n;
}

} // namespace rgvc
